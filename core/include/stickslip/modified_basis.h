/* The modified basis of quadratic faces with non-positive nodal integrals (Popp, Wohlmuth, Gee & Wall, SIAM J. Sci.
 * Comput. 34, 2012): N~_corner = N_corner + alpha (N_m1 + N_m2) over the corner's two edge nodes, N~_edge =
 * (1 - 2 alpha) N_edge, alpha = 1/5, a partition of unity with positive integrals (flat TRI6: 2/15 and 1/5 of the
 * area, QUAD8: 1/20 and 1/5). Header-only, so that the core (surface.c, the host's tributary measures) and plugins
 * (which link only libc/libm) use the same weights. */
#ifndef STICKSLIP_MODIFIED_BASIS_H
#define STICKSLIP_MODIFIED_BASIS_H

#include "stickslip/plugin_types.h"

#define SK_MODIFIED_BASIS_ALPHA 0.2

/* The corners of a face type that takes the modified basis (TRI6: 3, QUAD8: 4), 0 for the others (their integrals
 * are positive and used as they are). */
static inline int sk_modified_basis_corners(sk_elem_type type) {
  return type == SK_TRI6 ? 3 : type == SK_QUAD8 ? 4 : 0;
}

/* A[] holds integral N_I per face node (corners first, then edge node e between corners e and e + 1); on return the
 * integrals of the modified basis. Other face types are left as they are. */
static inline void sk_modified_basis_weights(sk_elem_type type, double *A) {
  const int corners = sk_modified_basis_corners(type);
  double edge[4];
  for (int e = 0; e < corners; ++e) edge[e] = A[corners + e];
  for (int e = 0; e < corners; ++e) {
    A[e] += SK_MODIFIED_BASIS_ALPHA * edge[e];
    A[(e + 1) % corners] += SK_MODIFIED_BASIS_ALPHA * edge[e];
    A[corners + e] = (1.0 - 2.0 * SK_MODIFIED_BASIS_ALPHA) * edge[e];
  }
}

#endif
