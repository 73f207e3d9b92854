/* stickslip — error reporting shared by core, driver and plugins.
 *
 * Every fallible core call returns an sk_status. On failure the callee records one human-readable message
 * (naming the file, key, line, group or parameter at fault) with sk_error_set(); callers up the stack may prefix
 * context with sk_error_prefix(). The driver prints the final message once and exits non-zero. */
#ifndef STICKSLIP_ERROR_H
#define STICKSLIP_ERROR_H

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
  SK_OK = 0,
  SK_ERR_INPUT = 1,     /* bad scene, mesh, parameter or command line */
  SK_ERR_IO = 2,        /* a file could not be read or written */
  SK_ERR_INVERTED = 3,  /* an element has det F <= 0 (the step may be cut and retried) */
  SK_ERR_DIVERGED = 4,  /* Newton did not converge (the step may be cut and retried) */
  SK_ERR_PLUGIN = 5,    /* a plugin failed to load, has the wrong ABI or lacks a capability */
  SK_ERR_INTERNAL = 6,  /* a broken invariant: a bug */
  SK_ERR_NOMEM = 7,
  SK_ERR_LINEAR_SOLVER = 8 /* a linear solve failed (no Krylov convergence, singular matrix): a property of the
                              solver and the system, so cutting the step does not help (bridge.h says what does) */
} sk_status;

/* Records the message of the current failure (printf-style), replacing any earlier one. Returns `code`. */
sk_status sk_error_set(sk_status code, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* Prepends context ("scene.yaml: ") to the current message. Returns `code`. */
sk_status sk_error_prefix(sk_status code, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* The current message ("" when none). */
const char *sk_error_message(void);
void sk_error_clear(void);

/* Propagates a failing status to the caller. */
#define SK_TRY(call)                 \
  do {                               \
    sk_status sk_try_status_ = (call); \
    if (sk_try_status_ != SK_OK) return sk_try_status_; \
  } while (0)

#ifdef __cplusplus
}
#endif
#endif
