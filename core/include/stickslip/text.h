/* stickslip — a growing piece of text (messages, listings, the header of the results' scene.yaml), and the closest
 * of a few words to a misspelt one (the "did you mean" of keys, options and commands). */
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

/* The candidate closest to a misspelt word, within 2 edits (a transposition is one): start with SK_CLOSEST_NONE,
 * offer every candidate, then `best` is the suggestion or NULL. A candidate equal to the word is skipped. */
typedef struct {
  const char *best;
  int distance;
} sk_closest;
#define SK_CLOSEST_NONE ((sk_closest){NULL, 3})
void sk_closest_offer(sk_closest *c, const char *word, const char *candidate);

#ifdef __cplusplus
}
#endif
#endif
