/* covariant-penalty — kernel: geometry, closest point, normal ray, residual and the exact tangent split
 * (docs/plugins/covariant-penalty.md §2-§5; the paper's printed tangent is in kernel_paper.c).
 *
 * Derivatives are carried as rows over the local dofs c = 3 node + component: dg[c], dDelta_rho[i][c],
 * Dxi[j][c], dn[i][c]. Every matrix of the formulation is a node-weight vector times a 3 x 3 block (A, B_j, A_Delta),
 * so a part's K follows from ds_part[i][c] (the change of the traction s) as K[(a,i), c] = -w alpha_a ds_part[i][c],
 * plus the weight channel w beta_j,a s_i Dxi^j[c]. */
#include "kernel.h"

#include <math.h>
#include <string.h>

#include "kernel_internal.h"

int cp_face_init(cp_face *face, sk_elem_type type, cp_shape_fn shape, cp_shape_hessian_fn shape_hessian) {
  int nen = type == SK_QUAD4 ? 4 : type == SK_QUAD9 ? 9 : type == SK_TRI3 ? 3 : 0;
  if (!nen || !shape || !shape_hessian) return -1;
  face->type = type;
  face->nen = nen;
  face->shape = shape;
  face->shape_hessian = shape_hessian;
  return 0;
}

int cp_face_point(const cp_face *face, const double *xf, const double xi[2], sk_surface_point *pt) {
  memset(pt, 0, sizeof *pt);
  pt->struct_size = sizeof *pt;
  double dN[2 * CP_MAX_FACE_NODES], ddN[4 * CP_MAX_FACE_NODES];
  face->shape(face->type, xi, pt->N, dN);
  face->shape_hessian(face->type, xi, ddN);
  pt->nen = face->nen;
  pt->face = -1;
  pt->xi[0] = xi[0];
  pt->xi[1] = xi[1];
  for (int a = 0; a < face->nen; ++a) {
    const double *xa = xf + 3 * a;
    pt->dN[a][0] = dN[2 * a];
    pt->dN[a][1] = dN[2 * a + 1];
    for (int i = 0; i < 3; ++i) {
      pt->x[i] += pt->N[a] * xa[i];
      for (int k = 0; k < 2; ++k) {
        pt->a[k][i] += dN[2 * a + k] * xa[i];
        for (int l = 0; l < 2; ++l) pt->a_ab[k][l][i] += ddN[(2 * a + k) * 2 + l] * xa[i];
      }
    }
  }
  double c[3];
  cp_cross3(pt->a[0], pt->a[1], c);
  pt->jacobian = sqrt(cp_dot3(c, c));
  for (int k = 0; k < 2; ++k)
    for (int l = 0; l < 2; ++l) pt->m[k][l] = cp_dot3(pt->a[k], pt->a[l]);
  double det = pt->m[0][0] * pt->m[1][1] - pt->m[0][1] * pt->m[1][0];
  if (!(pt->jacobian > 0.0) || !(det > 0.0)) return -1;
  for (int i = 0; i < 3; ++i) pt->n[i] = c[i] / pt->jacobian;
  pt->m_inv[0][0] = pt->m[1][1] / det;
  pt->m_inv[1][1] = pt->m[0][0] / det;
  pt->m_inv[0][1] = pt->m_inv[1][0] = -pt->m[0][1] / det;
  for (int k = 0; k < 2; ++k)
    for (int i = 0; i < 3; ++i) pt->a_dual[k][i] = pt->m_inv[k][0] * pt->a[0][i] + pt->m_inv[k][1] * pt->a[1][i];
  for (int k = 0; k < 2; ++k)
    for (int l = 0; l < 2; ++l) {
      pt->h[k][l] = cp_dot3(pt->a_ab[k][l], pt->n);                                   /* (11) */
      for (int q = 0; q < 2; ++q) pt->christoffel[k][l][q] = cp_dot3(pt->a_ab[k][l], pt->a_dual[q]); /* (15) */
    }
  return 0;
}

int cp_closest_point(const cp_face *face, const double *xf, const double r[3], double xi[2], int max_iterations) {
  sk_surface_point pt;
  for (int it = 1; it <= max_iterations; ++it) {
    if (cp_face_point(face, xf, xi, &pt) != 0) return -1;
    double d[3] = {r[0] - pt.x[0], r[1] - pt.x[1], r[2] - pt.x[2]}, R[2], H[2][2];
    for (int k = 0; k < 2; ++k) {
      R[k] = cp_dot3(d, pt.a[k]);                                                    /* (24) */
      for (int l = 0; l < 2; ++l) H[k][l] = pt.m[k][l] - cp_dot3(d, pt.a_ab[k][l]); /* (25) */
    }
    double det = H[0][0] * H[1][1] - H[0][1] * H[1][0];
    if (det == 0.0 || !isfinite(det)) return -1;
    double dxi0 = (H[1][1] * R[0] - H[0][1] * R[1]) / det, dxi1 = (H[0][0] * R[1] - H[1][0] * R[0]) / det;
    xi[0] += dxi0;
    xi[1] += dxi1;
    if (fmax(fabs(dxi0), fabs(dxi1)) <= 1e-13) return it;
  }
  return -1;
}

/* ---- the normal ray against a rigid surface (117)-(124) ------------------------------------------------------- */
int cp_ray(cp_distance_fn distance, void *ctx, const double rho[3], const double n[3], double max_depth, double *g,
           double hit[3], double nu[3]) {
  /* Newton on phi(g) = distance(rho + g n): phi' = nu . n. The paper's closed form (122) for the parabolic cylinder is
   * this iteration's root; here the host's closest-point projection gives phi for any obstacle. */
  double gk = 0.0, y[3], phi, v[3];
  int converged = 0;
  for (int it = 0; it < 40 && converged < 2; ++it) {
    for (int i = 0; i < 3; ++i) y[i] = rho[i] + gk * n[i];
    if (!distance(ctx, y, &phi, v)) return 0;
    double rate = cp_dot3(v, n);
    if (!(rate < -1e-3)) return 0; /* not facing, or grazing: no usable intersection */
    double step = -phi / rate;
    gk += step;
    if (!(fabs(gk) <= max_depth)) return 0;
    /* quadratic convergence: one more step after 1e-9 leaves round-off, so that differences of g stay exact */
    if (converged || fabs(step) <= 1e-9 * fmax(1.0, fabs(gk))) ++converged;
  }
  if (converged < 2) return 0;
  for (int i = 0; i < 3; ++i) y[i] = rho[i] + gk * n[i];
  if (!distance(ctx, y, &phi, v) || !(cp_dot3(v, n) < 0.0)) return 0;
  *g = gk;
  memcpy(hit, y, 3 * sizeof *hit);
  memcpy(nu, v, 3 * sizeof *nu);
  return 1;
}

/* ---- residual ------------------------------------------------------------------------------------------------- */

void cp_gather_face(const cp_point *point, const double *x, double *xf) {
  for (int k = 0; k < point->master.nen; ++k)
    memcpy(xf + 3 * k, x + 3 * point->master_nodes[k], 3 * sizeof *xf);
}

int cp_point_state(const cp_point *point, const cp_params *params, const cp_channels *channels, cp_eval *e) {
  const double *x_K = channels && channels->x_K ? channels->x_K : point->x;
  const double *x_F = channels && channels->x_F ? channels->x_F : point->x;
  const double *xi_K = channels && channels->xi_K ? channels->xi_K : point->xi;
  const double *xi_F = channels && channels->xi_F ? channels->xi_F : point->xi;
  double xf[3 * CP_MAX_FACE_NODES];
  cp_result *out = &e->result;
  memset(out, 0, sizeof *out);
  out->nd = 3 * point->n_local;
  out->state = CP_INACTIVE;
  out->g = NAN;
  e->has_ray = 0;

  /* Frame: the normal at xi_F from x_F. */
  cp_gather_face(point, x_F, xf);
  if (cp_face_point(&point->master, xf, xi_F, &e->frame) != 0) return -1;
  /* Kinematics: rho at xi_K from x_K. */
  const double *xk = x_K;
  cp_gather_face(point, xk, xf);
  if (cp_face_point(&point->master, xf, xi_K, &e->kin) != 0) return -1;
  const double *n = e->frame.n;
  memcpy(out->n, n, sizeof out->n);
  memcpy(out->x_master, e->kin.x, sizeof out->x_master);
  double g, delta[3] = {0.0, 0.0, 0.0};
  if (point->variant == CP_STAS) {
    if (!cp_ray(point->distance, point->distance_ctx, e->kin.x, n, point->max_depth, &g, e->hit, e->nu)) return 0;
    e->has_ray = 1;
    for (int i = 0; i < 3; ++i) delta[i] = -(e->kin.x[i] - point->anchor[i] - point->obstacle_d[i]); /* (48) */
  } else {
    double rs[3] = {0.0, 0.0, 0.0};
    for (int a = 0; a < point->n_slave; ++a)
      for (int i = 0; i < 3; ++i) rs[i] += point->S[a] * xk[3 * point->slave[a] + i];
    g = (rs[0] - e->kin.x[0]) * n[0] + (rs[1] - e->kin.x[1]) * n[1] + (rs[2] - e->kin.x[2]) * n[2]; /* (27) */
    for (int i = 0; i < 3; ++i) { /* (47): the current point minus the old material point, both at current x */
      delta[i] = e->kin.x[i];
      for (int l = 0; l < point->n_old; ++l) delta[i] -= point->N_old[l] * xk[3 * point->old_nodes[l] + i];
    }
  }
  out->g = g;
  if (!(g <= params->touch_tol)) return 0;

  const double p = g < 0.0 ? -params->eps_n * g : 0.0; /* (62) */
  out->p = p;
  out->state = CP_STICK; /* frictionless points report stick: in contact, no slip to speak of */
  memcpy(e->delta, delta, sizeof e->delta);
  e->friction = params->mu > 0.0 && point->history;
  e->slip_branch = 0;
  if (e->friction) {
    const double dn = cp_dot3(n, delta);
    for (int i = 0; i < 3; ++i) out->slip[i] = delta[i] - dn * n[i];
    /* Trial by parallel transport (51), (77): tau = P (t_n - eps_t Delta rho). */
    for (int i = 0; i < 3; ++i) e->tau_hat[i] = point->t_n[i] - params->eps_t * delta[i];
    double nt = cp_dot3(n, e->tau_hat);
    for (int i = 0; i < 3; ++i) out->tau[i] = e->tau_hat[i] - nt * n[i];
    e->tau_norm = sqrt(cp_dot3(out->tau, out->tau));
    const double limit = params->mu * p;
    if (e->tau_norm <= limit) { /* (79) stick */
      memcpy(out->t, out->tau, sizeof out->t);
    } else {                    /* (79) slip */
      out->state = CP_SLIP;
      for (int i = 0; i < 3; ++i) out->t[i] = limit * out->tau[i] / e->tau_norm;
      out->dissipation = params->weight * limit * (e->tau_norm - limit) / params->eps_t;
    }
    /* The tangent differentiates the slip branch also on the cone to round-off: a point that slipped in the last step
     * starts the next one there (Delta rho = 0 up to the round-off of positions, its traction transported unchanged),
     * and the stick branch's tangent would hold it for a whole Newton iteration. Both branches give the same
     * traction on the cone; the band is eps_t times the gaps' round-off scale. */
    e->slip_branch = e->tau_norm > 0.0 && e->tau_norm > limit - params->eps_t * params->touch_tol;
    if (e->slip_branch)
      for (int i = 0; i < 3; ++i) e->e[i] = out->tau[i] / e->tau_norm;
  }
  for (int i = 0; i < 3; ++i) e->s[i] = p * n[i] + out->t[i];
  return 0;
}

void cp_assemble_residual(const cp_point *point, const cp_params *params, const double *xi_W, cp_eval *e) {
  cp_result *out = &e->result;
  memset(out->R, 0, sizeof out->R);
  if (out->state == CP_INACTIVE) return;
  const double w = params->weight;
  double N[CP_MAX_FACE_NODES], dN[2 * CP_MAX_FACE_NODES];
  point->master.shape(point->master.type, xi_W, N, dN);
  for (int a = 0; a < point->n_slave; ++a)
    for (int i = 0; i < 3; ++i) out->R[3 * point->slave[a] + i] -= w * point->S[a] * e->s[i];
  for (int k = 0; k < point->master.nen; ++k)
    for (int i = 0; i < 3; ++i) out->R[3 * point->master_nodes[k] + i] += w * N[k] * e->s[i];
}

void cp_point_residual(const cp_point *point, const cp_params *params, const cp_channels *channels, cp_result *out) {
  cp_eval e;
  cp_channels ch = channels ? *channels : (cp_channels){0};
  if (cp_point_state(point, params, &ch, &e) != 0) {
    memset(out, 0, sizeof *out);
    out->nd = 3 * point->n_local;
    out->g = NAN;
    return;
  }
  cp_assemble_residual(point, params, ch.xi_W ? ch.xi_W : point->xi, &e);
  *out = e.result;
}
