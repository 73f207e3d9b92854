/* Minimal test helpers shared by the C test programs: each check prints what failed and where; a test program
 * returns sk_test_finish() (0 when every check passed). */
#ifndef SK_TEST_H
#define SK_TEST_H

#include <math.h>
#include <stdio.h>
#include <string.h>

static int sk_test_failures = 0;
static int sk_test_checks = 0;

#define SK_CHECK(cond)                                                                  \
  do {                                                                                  \
    ++sk_test_checks;                                                                   \
    if (!(cond)) {                                                                      \
      ++sk_test_failures;                                                               \
      fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond);          \
    }                                                                                   \
  } while (0)

/* |a - b| <= tol * max(1, |b|) */
#define SK_CHECK_CLOSE(a, b, tol)                                                       \
  do {                                                                                  \
    double sk_a_ = (a), sk_b_ = (b), sk_t_ = (tol);                                     \
    ++sk_test_checks;                                                                   \
    if (!(fabs(sk_a_ - sk_b_) <= sk_t_ * fmax(1.0, fabs(sk_b_)))) {                     \
      ++sk_test_failures;                                                               \
      fprintf(stderr, "%s:%d: %s = %.17g, expected %s = %.17g (tol %g)\n", __FILE__, __LINE__, #a, sk_a_, #b, \
              sk_b_, sk_t_);                                                            \
    }                                                                                   \
  } while (0)

/* Whether `text` contains `part`; prints both when it does not (for messages checked by fragments). */
static inline int sk_test_contains(const char *text, const char *part) {
  int found = text && strstr(text, part) != NULL;
  if (!found) fprintf(stderr, "  expected '%s' in: %s\n", part, text ? text : "(null)");
  return found;
}

static inline int sk_test_finish(const char *name) {
  printf("%s: %d checks, %d failed\n", name, sk_test_checks, sk_test_failures);
  return sk_test_failures == 0 ? 0 : 1;
}

#endif
