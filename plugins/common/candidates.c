/* The broad phase of the node- and point-to-surface plugins (candidates.h). */
#include "candidates.h"

#include <math.h>
#include <stdlib.h>

int cand_query_swept(const sk_contact_services *cs, sk_search *search, const double *r0, const double *r1, int dim,
                     double margin, cand_list *list, int *start, int *count) {
  const double big = 1e300; /* a 2D box spans every z */
  double lo[3] = {-big, -big, -big}, hi[3] = {big, big, big};
  for (int i = 0; i < dim; ++i) {
    lo[i] = fmin(r0[i], r1[i]) - margin;
    hi[i] = fmax(r0[i], r1[i]) + margin;
  }
  int room = list->capacity - list->used;
  int n = cs->search_query(search, lo, hi, list->faces ? list->faces + list->used : NULL, room > 0 ? room : 0);
  if (n > room) {
    const int capacity = 2 * (list->used + n) + 64;
    int *grown = realloc(list->faces, (size_t)capacity * sizeof *grown);
    if (!grown) return -1;
    list->faces = grown;
    list->capacity = capacity;
    n = cs->search_query(search, lo, hi, list->faces + list->used, list->capacity - list->used);
  }
  *start = list->used;
  *count = n;
  list->used += n;
  return 0;
}

int cand_within_band(sk_elem_type type, const double xi[2], double band) {
  if (type == SK_TRI3 || type == SK_TRI6) return xi[0] >= -band && xi[1] >= -band && 1.0 - xi[0] - xi[1] >= -band;
  const int pdim = type == SK_LINE2 || type == SK_LINE3 ? 1 : 2;
  for (int a = 0; a < pdim; ++a)
    if (fabs(xi[a]) > 1.0 + 2.0 * band) return 0;
  return 1;
}

int cand_contains(const cand_list *list, int start, int count, int face) {
  for (int c = 0; c < count; ++c)
    if (list->faces[start + c] == face) return 1;
  return 0;
}
