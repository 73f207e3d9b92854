/* covariant-penalty — kernel internals shared by kernel.c and kernel_paper.c (not part of the plugin's API). */
#ifndef COVARIANT_PENALTY_KERNEL_INTERNAL_H
#define COVARIANT_PENALTY_KERNEL_INTERNAL_H

#include <math.h>

#include "kernel.h"

/* Everything one evaluation of a point produces besides the result. */
typedef struct {
  sk_surface_point frame;     /* geometry at xi_F from x_F: the normal */
  sk_surface_point kin;       /* geometry at xi_K from x_K: rho */
  int has_ray;                /* stas: the ray hit the obstacle at hit, with its normal nu */
  double hit[3], nu[3];
  double delta[3];            /* slip increment Delta rho (47), (48) */
  int friction;               /* a trial was formed (mu > 0 and a history) */
  double tau_hat[3];          /* t_n - eps_t Delta rho, before the projection */
  double tau_norm;            /* |tau| */
  int slip_branch;            /* the tangent differentiates the slip branch: slip, or on the cone to round-off */
  double e[3];                /* slip direction tau/|tau| (slip branch only) */
  double s[3];                /* traction on the slave p n + t */
  cp_result result;
} cp_eval;

static inline double cp_dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static inline void cp_cross3(const double *a, const double *b, double *c) {
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}

static inline int cp_normalise(const double *v, double *u) {
  double length = sqrt(cp_dot3(v, v));
  if (!(length > 0.0) || !isfinite(length)) return 0;
  for (int i = 0; i < 3; ++i) u[i] = v[i] / length;
  return 1;
}

/* Positions of the master face's nodes from the local positions x. */
void cp_gather_face(const cp_point *point, const double *x, double *xf);

/* Gap, pressure, trial and return map through the channels (NULL: the point's own). Returns 0 (state in
 * e->result.state, possibly inactive), or -1 for a degenerate face point. */
int cp_point_state(const cp_point *point, const cp_params *params, const cp_channels *channels, cp_eval *e);

/* R = -w A(xi_W)^T s into e->result.R (zero when inactive). */
void cp_assemble_residual(const cp_point *point, const cp_params *params, const double *xi_W, cp_eval *e);

/* The paper's printed tangent parts (kernel_paper.c), K[part] += ... for parts with want[part]. */
void cp_paper_tangent(const cp_point *point, const cp_params *params, const cp_eval *e, const int want[CP_N_PARTS],
                      double *K[CP_N_PARTS]);

#endif
