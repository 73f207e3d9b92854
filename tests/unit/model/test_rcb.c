/* The recursive coordinate bisection of the contact partition (core/model/contact_partition.c: sk_rcb): part sizes
 * within one point of each other for unit weights (any number of parts, fewer points than parts), cuts across the
 * longest side (the parts of a long strip are consecutive slabs), weights shared in proportion, and ties broken by
 * the points' order (the same split on every rank). */
#include <stdio.h>
#include <string.h>

#include "sk_test.h"
#include "contact_partition.h"

#define MAX_POINTS 64

/* points on an nx x ny grid of spacing (hx, hy) */
static int grid(int nx, int ny, double hx, double hy, double *pos) {
  int n = 0;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i, ++n) {
      pos[3 * n] = i * hx;
      pos[3 * n + 1] = j * hy;
      pos[3 * n + 2] = 0.0;
    }
  return n;
}

static void counts(const int *part, int n, int n_parts, int first, int *count) {
  memset(count, 0, sizeof(int) * (size_t)n_parts);
  for (int j = 0; j < n; ++j) {
    SK_CHECK(part[j] >= first && part[j] < first + n_parts);
    if (part[j] >= first && part[j] < first + n_parts) count[part[j] - first]++;
  }
}

int main(void) {
  double pos[3 * MAX_POINTS];
  int part[MAX_POINTS], again[MAX_POINTS], count[8];
  /* 25 points of a 5 x 5 grid over 4 parts (the pad of scenes/corner-contact.yaml on 4 ranks): 6 or 7 each */
  int n = grid(5, 5, 1.0, 1.0, pos);
  SK_CHECK(sk_rcb(n, pos, NULL, 4, 0, part) == 0);
  counts(part, n, 4, 0, count);
  for (int r = 0; r < 4; ++r) SK_CHECK(count[r] == 6 || count[r] == 7);
  /* 3 parts of a 10 x 3 strip: the cuts run across x, each part a slab of 10 points with its x range apart */
  n = grid(10, 3, 1.0, 1.0, pos);
  SK_CHECK(sk_rcb(n, pos, NULL, 3, 2, part) == 0);
  counts(part, n, 3, 2, count);
  for (int r = 0; r < 3; ++r) SK_CHECK(count[r] == 10);
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b)
      if (pos[3 * a] < pos[3 * b]) SK_CHECK(part[a] <= part[b]);
  /* weights: one point of weight 9 against nine of weight 1 on a line, 2 parts: the heavy one alone */
  double weight[10];
  n = grid(10, 1, 1.0, 1.0, pos);
  for (int j = 0; j < n; ++j) weight[j] = j == 0 ? 9.0 : 1.0;
  SK_CHECK(sk_rcb(n, pos, weight, 2, 0, part) == 0);
  SK_CHECK(part[0] == 0);
  for (int j = 1; j < n; ++j) SK_CHECK(part[j] == 1);
  /* ties: every point at one place, 3 parts: by the points' order, and the same split again */
  for (int j = 0; j < 3 * 7; ++j) pos[j] = 0.5;
  SK_CHECK(sk_rcb(7, pos, NULL, 3, 0, part) == 0);
  SK_CHECK(sk_rcb(7, pos, NULL, 3, 0, again) == 0);
  for (int j = 0; j < 7; ++j) SK_CHECK(part[j] == again[j]);
  for (int j = 1; j < 7; ++j) SK_CHECK(part[j - 1] <= part[j]);
  counts(part, 7, 3, 0, count);
  for (int r = 0; r < 3; ++r) SK_CHECK(count[r] == 2 || count[r] == 3);
  /* the halves' boxes are the parent's box cut at the cut, not their points' boxes: two clusters of 2 columns of 3
   * points at the ends of a 4 x 1 box, 4 parts. The first cut runs across x at 2; each half's box is then 2 x 1, so
   * the second cut runs across x again (the clusters' own boxes, 0.4 x 1, would have turned it across y). Both
   * bisections of a surface (its nodes, its faces' centroids) see nearly the same boxes this way, and their parts
   * coincide. */
  n = 0;
  for (int c = 0; c < 2; ++c)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 2; ++i, ++n) {
        pos[3 * n] = 3.6 * c + 0.4 * i;
        pos[3 * n + 1] = 0.5 * j;
        pos[3 * n + 2] = 0.0;
      }
  SK_CHECK(sk_rcb(n, pos, NULL, 4, 0, part) == 0);
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b)
      if (pos[3 * a] == pos[3 * b]) SK_CHECK(part[a] == part[b]); /* a column of a cluster: one part */
  /* fewer points than parts, and none */
  n = grid(3, 1, 1.0, 1.0, pos);
  SK_CHECK(sk_rcb(n, pos, NULL, 8, 0, part) == 0);
  counts(part, n, 8, 0, count);
  SK_CHECK(part[0] != part[1] && part[1] != part[2] && part[0] != part[2]);
  SK_CHECK(sk_rcb(0, pos, NULL, 4, 0, part) == 0);
  return sk_test_finish("test_rcb");
}
