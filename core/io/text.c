/* A growing piece of text (stickslip/text.h). */
#include "stickslip/text.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>

void sk_text_add(sk_text *t, const char *s) {
  size_t n = strlen(s);
  if (t->used + n + 1 > t->cap) {
    size_t cap = 2 * (t->used + n + 1);
    char *grown = realloc(t->text, cap);
    if (!grown) return;
    t->text = grown;
    t->cap = cap;
  }
  memcpy(t->text + t->used, s, n + 1);
  t->used += n;
}

/* Optimal string alignment distance (a transposition counts as one edit). Long words: no suggestion. */
static int edit_distance(const char *a, const char *b) {
  enum { MAXLEN = 64 };
  size_t la = strlen(a), lb = strlen(b);
  if (la >= MAXLEN || lb >= MAXLEN) return INT_MAX;
  int d[MAXLEN + 1][MAXLEN + 1];
  for (size_t i = 0; i <= la; ++i) d[i][0] = (int)i;
  for (size_t j = 0; j <= lb; ++j) d[0][j] = (int)j;
  for (size_t i = 1; i <= la; ++i) {
    for (size_t j = 1; j <= lb; ++j) {
      int cost = a[i - 1] != b[j - 1];
      int best = d[i - 1][j] + 1;
      if (d[i][j - 1] + 1 < best) best = d[i][j - 1] + 1;
      if (d[i - 1][j - 1] + cost < best) best = d[i - 1][j - 1] + cost;
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] && d[i - 2][j - 2] + 1 < best) {
        best = d[i - 2][j - 2] + 1;
      }
      d[i][j] = best;
    }
  }
  return d[la][lb];
}

void sk_closest_offer(sk_closest *c, const char *word, const char *candidate) {
  if (strcmp(candidate, word) == 0) return;
  int d = edit_distance(word, candidate);
  if (d < c->distance && (size_t)d < strlen(candidate)) {
    c->best = candidate;
    c->distance = d;
  }
}
