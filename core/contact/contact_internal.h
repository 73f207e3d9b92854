/* stickslip — contact module internals shared by its source files (not installed, not part of the API).
 *
 * The parametric domain of a face is the polygon of its corners; each edge e (corner e to corner e+1, in 2D the
 * end point e) is the constraint g_e(xi) = offset + w . xi >= 0. Every face type is described by one table. */
#ifndef STICKSLIP_CONTACT_INTERNAL_H
#define STICKSLIP_CONTACT_INTERNAL_H

#include "stickslip/contact.h"

typedef struct {
  int pdim;                 /* parametric dimension: 1 (lines) or 2 */
  int n_corners;            /* = n_edges */
  double corner[4][2];      /* parametric coordinates of the corners */
  double edge_w[4][2];      /* inward constraint gradients */
  double edge_offset[4];    /* g_e(xi) = edge_offset[e] + edge_w[e] . xi */
  double centre[2];         /* a start point for Newton */
  double lebesgue;          /* max over the face of sum |N_a|: node boxes grown by this factor enclose the face */
} sk_face_domain;

/* NULL for a type that is not a face type. */
const sk_face_domain *sk_face_domain_of(sk_elem_type type);

/* Value of the edge constraint g_e at xi (>= 0 inside). */
static inline double sk_face_edge_value(const sk_face_domain *domain, int edge, const double *xi) {
  double g = domain->edge_offset[edge] + domain->edge_w[edge][0] * xi[0];
  if (domain->pdim == 2) g += domain->edge_w[edge][1] * xi[1];
  return g;
}

#endif
