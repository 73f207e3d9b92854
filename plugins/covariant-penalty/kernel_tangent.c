/* covariant-penalty — kernel: the exact tangent of one contact point, split by channel into the main, rotational
 * and curvature parts (docs/plugins/covariant-penalty.md §5).
 *
 * With z the local dofs (c = 3 node + component) and the node weights
 *   alpha (A = d(r_s - rho)/dz: S_a on slave nodes, -N_k on master nodes), beta_j (B_j = d rho_j/dz: N_k,j),
 *   gamma (A_Delta = d Delta rho/dz at fixed xi: N_k on the current face, -N_old on the last step's face),
 * the rows below are the derivatives of the primitive quantities; s = p n + t changes by
 *   main:        ds/dg dg + ds/dDelta dDelta              (the kinematic channel x_K, xi_K)
 *   rotational:  ds/dn dn_x  [+ ds/dg dg_F for stas]      (the frame channel x_F at fixed xi)
 *   curvature:   ds/dn dn_xi                               (the frame channel xi_F)
 * and K_part[(a,i), c] = -w alpha_a ds_part[i][c]; the weight channel adds w beta_j,a s_i Dxi^j[c] to the
 * rotational part. */
#include <string.h>

#include "kernel.h"
#include "kernel_internal.h"

/* ds = (ds/dn) . v for a change v of the normal: p v plus the change of t through P (docs §5). */
static void traction_normal_derivative(const cp_eval *e, const cp_params *params, const double *v, double *ds) {
  const double *n = e->frame.n;
  const cp_result *r = &e->result;
  for (int i = 0; i < 3; ++i) ds[i] = r->p * v[i];
  if (!e->friction) return;
  double n_tau = cp_dot3(n, e->tau_hat), v_tau = cp_dot3(v, e->tau_hat), dtau[3];
  for (int i = 0; i < 3; ++i) dtau[i] = -v[i] * n_tau - n[i] * v_tau; /* dP tau_hat, P = I - n n */
  if (r->state == CP_STICK) {
    for (int i = 0; i < 3; ++i) ds[i] += dtau[i];
    return;
  }
  double scale = params->mu * r->p / e->tau_norm, e_dtau = cp_dot3(e->e, dtau);
  for (int i = 0; i < 3; ++i) ds[i] += scale * (dtau[i] - e->e[i] * e_dtau); /* mu p (I - e e) dtau / |tau| */
}

int cp_point_eval(const cp_point *point, const cp_params *params, cp_form form, const int want[CP_N_PARTS],
                  cp_result *out, double *K[CP_N_PARTS]) {
  cp_eval e;
  const int nd = 3 * point->n_local;
  for (int part = 0; part < CP_N_PARTS; ++part)
    if (want[part]) memset(K[part], 0, (size_t)nd * nd * sizeof(double));
  if (cp_point_state(point, params, NULL, &e) != 0) { /* degenerate master face: no contact there */
    memset(out, 0, sizeof *out);
    out->nd = nd;
    out->g = NAN;
    return 0;
  }
  cp_assemble_residual(point, params, point->xi, &e);
  *out = e.result;
  if (out->state == CP_INACTIVE) return 0;
  if (form == CP_FORM_PAPER) {
    cp_paper_tangent(point, params, &e, want, K);
    return 0;
  }

  const sk_surface_point *f = &e.frame;
  const double *n = f->n, g = out->g, w = params->weight;
  const int stas = point->variant == CP_STAS;
  double alpha[CP_MAX_NODES] = {0}, beta[2][CP_MAX_NODES] = {{0}}, gamma[CP_MAX_NODES] = {0};
  for (int a = 0; a < point->n_slave; ++a) alpha[point->slave[a]] += point->S[a];
  for (int k = 0; k < point->master.nen; ++k) {
    int node = point->master_nodes[k];
    alpha[node] -= f->N[k];
    gamma[node] += stas ? -f->N[k] : f->N[k];
    for (int j = 0; j < 2; ++j) beta[j][node] += f->dN[k][j];
  }
  if (!stas)
    for (int l = 0; l < point->n_old; ++l) gamma[point->old_nodes[l]] -= point->N_old[l];

  /* Dxi from the closest-point condition: (a_ij - g h_ij) Dxi^j = rho_i^T A + g n^T B_i. */
  double Dxi[2][CP_MAX_DOFS] = {{0}};
  if (!stas) {
    double M[2][2], Minv[2][2];
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) M[i][j] = f->m[i][j] - g * f->h[i][j];
    double det = M[0][0] * M[1][1] - M[0][1] * M[1][0];
    if (!(det > 0.0)) return -1; /* a focal point of the master: the closest point is not a minimum */
    Minv[0][0] = M[1][1] / det;
    Minv[1][1] = M[0][0] / det;
    Minv[0][1] = -M[0][1] / det;
    Minv[1][0] = -M[1][0] / det;
    for (int c = 0; c < nd; ++c) {
      int node = c / 3, comp = c % 3;
      double rhs[2];
      for (int k = 0; k < 2; ++k) rhs[k] = alpha[node] * f->a[k][comp] + g * beta[k][node] * n[comp];
      for (int j = 0; j < 2; ++j) Dxi[j][c] = Minv[j][0] * rhs[0] + Minv[j][1] * rhs[1];
    }
  }

  /* ds/dg and ds/dDelta (the kinematic channel). */
  double sg[3], SD[3][3] = {{0}};
  for (int i = 0; i < 3; ++i) sg[i] = -params->eps_n * (n[i] + (out->state == CP_SLIP ? params->mu * e.e[i] : 0.0));
  if (e.friction) {
    double scale = out->state == CP_SLIP ? params->mu * out->p / e.tau_norm : 1.0;
    for (int i = 0; i < 3; ++i)
      for (int l = 0; l < 3; ++l) {
        double P = (i == l ? 1.0 : 0.0) - n[i] * n[l];
        SD[i][l] = -params->eps_t * scale * (P - (out->state == CP_SLIP ? e.e[i] * e.e[l] : 0.0));
      }
  }
  const double nu_n = stas ? cp_dot3(e.nu, n) : 1.0;

  double ds[CP_N_PARTS][3][CP_MAX_DOFS];
  memset(ds, 0, sizeof ds);
  for (int c = 0; c < nd; ++c) {
    int node = c / 3, comp = c % 3;
    /* main: dg = n^T A dz (stas: nu^T A dz / (nu . n)), dDelta = A_Delta dz + rho_i Dxi^i */
    double dg = alpha[node] * (stas ? e.nu[comp] / nu_n : n[comp]), dDelta[3];
    for (int i = 0; i < 3; ++i) dDelta[i] = (i == comp ? gamma[node] : 0.0) + f->a[0][i] * Dxi[0][c] + f->a[1][i] * Dxi[1][c];
    for (int i = 0; i < 3; ++i)
      ds[CP_MAIN][i][c] = sg[i] * dg + SD[i][0] * dDelta[0] + SD[i][1] * dDelta[1] + SD[i][2] * dDelta[2];
    /* rotational: the normal turns with the nodes at fixed xi, dn_x = -rho^k (n . B_k dz) (13) */
    double dn_x[3], d[3];
    for (int i = 0; i < 3; ++i) dn_x[i] = -(f->a_dual[0][i] * beta[0][node] + f->a_dual[1][i] * beta[1][node]) * n[comp];
    traction_normal_derivative(&e, params, dn_x, d);
    double dg_F = stas ? -g * cp_dot3(e.nu, dn_x) / nu_n : 0.0; /* (dg-stas): the ray turns with n */
    for (int i = 0; i < 3; ++i) ds[CP_ROTATIONAL][i][c] = d[i] + sg[i] * dg_F;
    /* curvature: the normal turns because the point moves on a curved face, dn_xi = -rho^k h_kj Dxi^j */
    if (!stas) {
      double dn_xi[3];
      for (int i = 0; i < 3; ++i) {
        dn_xi[i] = 0.0;
        for (int k = 0; k < 2; ++k)
          dn_xi[i] -= f->a_dual[k][i] * (f->h[k][0] * Dxi[0][c] + f->h[k][1] * Dxi[1][c]);
      }
      traction_normal_derivative(&e, params, dn_xi, d);
      for (int i = 0; i < 3; ++i) ds[CP_CURVATURE][i][c] = d[i];
    }
  }

  for (int part = 0; part < CP_N_PARTS; ++part) {
    if (!want[part]) continue;
    double *Kp = K[part];
    for (int a = 0; a < point->n_local; ++a) {
      if (alpha[a] == 0.0) continue;
      for (int i = 0; i < 3; ++i) {
        double *row = Kp + (size_t)(3 * a + i) * nd;
        for (int c = 0; c < nd; ++c) row[c] -= w * alpha[a] * ds[part][i][c];
      }
    }
  }
  if (want[CP_ROTATIONAL] && !stas) { /* the weight channel: d(A^T)/dxi = -B_j^T */
    double *Kp = K[CP_ROTATIONAL];
    for (int a = 0; a < point->n_local; ++a) {
      if (beta[0][a] == 0.0 && beta[1][a] == 0.0) continue;
      for (int i = 0; i < 3; ++i) {
        double *row = Kp + (size_t)(3 * a + i) * nd;
        double c0 = w * beta[0][a] * e.s[i], c1 = w * beta[1][a] * e.s[i];
        for (int c = 0; c < nd; ++c) row[c] += c0 * Dxi[0][c] + c1 * Dxi[1][c];
      }
    }
  }
  return 0;
}
