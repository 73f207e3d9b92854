/* stickslip — a growing piece of text (messages, listings, the header of the results' scene.yaml). */
#ifndef STICKSLIP_TEXT_H
#define STICKSLIP_TEXT_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
  char *text; /* NULL until something is added; free() it when done */
  size_t used, cap;
} sk_text;

/* Appends `s`. Out of memory, the text stays as it was: it is for people to read, so a shorter text is the worst
 * case. */
void sk_text_add(sk_text *t, const char *s);

#ifdef __cplusplus
}
#endif
#endif
