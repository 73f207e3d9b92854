/* A growing piece of text (stickslip/text.h). */
#include "stickslip/text.h"

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
