/* Hand-built contact surfaces for the contact tests: structured patches of LINE2/LINE3 (2D) and TRI3/TRI6/QUAD4/
 * QUAD8/QUAD9 (3D) faces on a mapped parameter grid, with adjacency found by brute force (independent of
 * sk_surface_build). */
#ifndef CONTACT_TEST_UTIL_H
#define CONTACT_TEST_UTIL_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "stickslip/contact.h"
#include "stickslip/fe.h"

/* Maps grid parameters (u, v) to a point x[3]. */
typedef void (*patch_map)(double u, double v, const void *ctx, double *x);

typedef struct {
  sk_surface surface;
  double *q;   /* positions, dim per node */
  int n_nodes; /* nodes of the grid (all on the surface, except the cell centres of a QUAD8 patch) */
} test_patch;

static inline void test_patch_neighbors(sk_surface *s) {
  s->face_neighbors = malloc((size_t)s->n_faces * s->n_edges * sizeof(int));
  for (int f = 0; f < s->n_faces; ++f)
    for (int e = 0; e < s->n_edges; ++e) {
      const int *c = s->conn + (size_t)f * s->nen;
      int a = c[e], b = s->dim == 2 ? c[e] : c[(e + 1) % s->n_edges];
      int found = -1;
      for (int g = 0; g < s->n_faces && found < 0; ++g) {
        if (g == f) continue;
        const int *d = s->conn + (size_t)g * s->nen;
        for (int k = 0; k < s->n_edges; ++k) {
          int x = d[k], y = s->dim == 2 ? d[k] : d[(k + 1) % s->n_edges];
          if ((x == a && y == b) || (x == b && y == a)) found = g;
        }
      }
      s->face_neighbors[(size_t)f * s->n_edges + e] = found;
    }
}

/* nu x nv cells of `type` over (u, v) in [u0, u1] x [v0, v1] (2D types ignore v); triangles split each cell along
 * its diagonal. Corners run counter-clockwise in (u, v), so a flat patch z = 0 mapped by identity has normal +z
 * (3D); a 2D line along +u has normal -y. Quadratic faces take their nodes from a grid of twice the density. */
static inline void test_patch_make(test_patch *p, sk_elem_type type, int nu, int nv, double u0, double u1, double v0,
                                   double v1, patch_map map, const void *ctx) {
  memset(p, 0, sizeof *p);
  sk_surface *s = &p->surface;
  snprintf(s->name, sizeof s->name, "patch");
  s->face_type = type;
  s->nen = sk_elem_nen(type);
  int quadratic = sk_elem_order(type) == 2, triangles = sk_elem_is_simplex(type);
  int step = quadratic ? 2 : 1;
  if (type == SK_LINE2 || type == SK_LINE3) {
    s->dim = 2;
    s->n_edges = 2;
    int n = nu * step + 1;
    p->n_nodes = n;
    p->q = malloc((size_t)n * 2 * sizeof(double));
    for (int i = 0; i < n; ++i) {
      double x[3];
      map(u0 + (u1 - u0) * i / (n - 1), 0.0, ctx, x);
      p->q[2 * i] = x[0];
      p->q[2 * i + 1] = x[1];
    }
    s->n_faces = nu;
    s->conn = malloc((size_t)nu * s->nen * sizeof(int));
    for (int f = 0; f < nu; ++f) {
      s->conn[f * s->nen] = f * step;
      s->conn[f * s->nen + 1] = f * step + step;
      if (quadratic) s->conn[f * s->nen + 2] = f * step + 1;
    }
  } else {
    s->dim = 3;
    s->n_edges = triangles ? 3 : 4;
    int mu = nu * step + 1, mv = nv * step + 1;
    p->n_nodes = mu * mv;
    p->q = malloc((size_t)p->n_nodes * 3 * sizeof(double));
    for (int j = 0; j < mv; ++j)
      for (int i = 0; i < mu; ++i)
        map(u0 + (u1 - u0) * i / (mu - 1), v0 + (v1 - v0) * j / (mv - 1), ctx, p->q + 3 * (j * mu + i));
#define NODE(i, j) ((j) * mu + (i))
    s->n_faces = nu * nv * (triangles ? 2 : 1);
    s->conn = malloc((size_t)s->n_faces * s->nen * sizeof(int));
    int f = 0;
    for (int j = 0; j < nv; ++j)
      for (int i = 0; i < nu; ++i) {
        int I = i * step, J = j * step;
        int *c = s->conn + (size_t)f * s->nen;
        if (triangles) {
          int a = NODE(I, J), b = NODE(I + step, J), cc = NODE(I + step, J + step), d = NODE(I, J + step);
          int *c2 = c + s->nen;
          c[0] = a, c[1] = b, c[2] = cc;
          c2[0] = a, c2[1] = cc, c2[2] = d;
          if (quadratic) { /* edge nodes (0-1) (1-2) (2-0) */
            c[3] = NODE(I + 1, J), c[4] = NODE(I + 2, J + 1), c[5] = NODE(I + 1, J + 1);
            c2[3] = NODE(I + 1, J + 1), c2[4] = NODE(I + 1, J + 2), c2[5] = NODE(I, J + 1);
          }
          f += 2;
        } else {
          c[0] = NODE(I, J), c[1] = NODE(I + step, J), c[2] = NODE(I + step, J + step), c[3] = NODE(I, J + step);
          if (quadratic) {
            c[4] = NODE(I + 1, J), c[5] = NODE(I + 2, J + 1), c[6] = NODE(I + 1, J + 2), c[7] = NODE(I, J + 1);
            if (type == SK_QUAD9) c[8] = NODE(I + 1, J + 1);
          }
          f += 1;
        }
      }
#undef NODE
  }
  /* The surface's nodes: the grid nodes its faces use, ascending. */
  char *used = calloc((size_t)p->n_nodes, 1);
  for (int k = 0; k < s->n_faces * s->nen; ++k) used[s->conn[k]] = 1;
  s->nodes = malloc((size_t)p->n_nodes * sizeof(int));
  s->n_nodes = 0;
  for (int i = 0; i < p->n_nodes; ++i)
    if (used[i]) s->nodes[s->n_nodes++] = i;
  free(used);
  test_patch_neighbors(s);
}

static inline void test_patch_free(test_patch *p) {
  free(p->surface.conn);
  free(p->surface.nodes);
  free(p->surface.face_neighbors);
  free(p->q);
  memset(p, 0, sizeof *p);
}

static inline void map_flat(double u, double v, const void *ctx, double *x) {
  (void)ctx;
  x[0] = u, x[1] = v, x[2] = 0.0;
}

/* Deterministic pseudo-random numbers in [0, 1) (tests must not depend on libc's rand). */
static inline double test_random(unsigned long long *state) {
  *state = *state * 6364136223846793005ULL + 1442695040888963407ULL;
  return (double)(*state >> 11) / 9007199254740992.0;
}

#endif
