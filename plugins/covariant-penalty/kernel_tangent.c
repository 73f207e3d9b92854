/* covariant-penalty — kernel: the exact tangent of one contact point, split by channel into the main, rotational
 * and curvature parts (docs/plugins/covariant-penalty.md §5), on top of the shared covariant kernel
 * (plugins/common/covariant.h): its closest-point kinematics give dg, Dxi and the normal's change split into
 * Dn_rot (the face's nodes move at fixed xi) and Dn_curv (the point moves on the curved face); its return map
 * differentiates the Coulomb law for each channel's change of the trial and the pressure.
 *
 * Channel by channel, with tau = P (t_n - eps_t Delta rho), P = I - n n and the node weights
 *   alpha (A = d(r_s - rho)/dz: S_a on slave nodes, -N_k on master nodes), beta_j (B_j: N_k,j),
 *   gamma (A_Delta = d Delta rho/dz at fixed xi: N_k on the current face, -N_old on the last step's face):
 *   main        dp = -eps_n dg,                      dtau = -eps_t P (A_Delta + rho_i Dxi^i) dz
 *   rotational  dn = Dn_rot [stas: dp = eps_n g nu . dn / (nu . n)],   dtau = dP tau_hat
 *   curvature   dn = Dn_curv,                        dtau = dP tau_hat
 * then ds = dp n + p dn + dt (dt from the return map) and K_part[(a,i), c] = -w alpha_a ds[i][c]; the weight
 * channel adds w beta_j,a s_i Dxi^j[c] to the rotational part. */
#include <string.h>

#include "covariant.h"
#include "kernel.h"
#include "kernel_internal.h"

/* The shared kernel's rows are over [r_s | the master face's nodes]; spread them onto the point's local dofs. */
static void spread_row(const cp_point *point, const double *row, double *out) {
  for (int a = 0; a < point->n_slave; ++a)
    for (int i = 0; i < 3; ++i) out[3 * point->slave[a] + i] += point->S[a] * row[i];
  for (int k = 0; k < point->master.nen; ++k)
    for (int i = 0; i < 3; ++i) out[3 * point->master_nodes[k] + i] += row[3 * (1 + k) + i];
}

/* dP tau_hat for a change dn of the normal, P = I - n n. */
static void projector_change(const double *n, const double *tau_hat, const double *dn, double *out) {
  double n_tau = cp_dot3(n, tau_hat), dn_tau = cp_dot3(dn, tau_hat);
  for (int i = 0; i < 3; ++i) out[i] = -dn[i] * n_tau - n[i] * dn_tau;
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
  const double *n = f->n, g = out->g, p = out->p, w = params->weight;
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

  /* Closest-point kinematics (stas: only the nodal turn of the normal is used; xi is a fixed Gauss point). */
  cov_kinematics kin;
  if (!cov_kinematics_eval(f, 3, point->master.nen, stas ? 0.0 : g, &kin))
    return -1; /* a focal point of the master: a_ij - g h_ij singular */
  double dg[CP_MAX_DOFS] = {0}, Dxi[2][CP_MAX_DOFS] = {{0}}, Dn[2][3][CP_MAX_DOFS] = {{{0}}};
  for (int i = 0; i < 3; ++i) {
    spread_row(point, kin.Dn_rot[i], Dn[0][i]);
    if (!stas) spread_row(point, kin.Dn_curv[i], Dn[1][i]);
  }
  const double nu_n = stas ? cp_dot3(e.nu, n) : 1.0;
  if (stas) { /* (dg-stas): the ray moves with rho, dg = nu^T A dz / (nu . n) */
    for (int c = 0; c < nd; ++c) dg[c] = alpha[c / 3] * e.nu[c % 3] / nu_n;
  } else {
    spread_row(point, kin.G, dg);
    for (int j = 0; j < 2; ++j) spread_row(point, kin.Dxi[j], Dxi[j]);
  }

  /* Each channel's change of the pressure, the trial and the normal; the return map turns them into ds. */
  static const double identity[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  double ds[3][CP_MAX_DOFS];
  for (int part = 0; part < CP_N_PARTS; ++part) {
    if (!want[part] || (part == CP_CURVATURE && stas)) continue;
    double Dp[CP_MAX_DOFS], Dtau[3 * CP_MAX_DOFS], Dt[3 * CP_MAX_DOFS] = {0};
    for (int c = 0; c < nd; ++c) {
      double dn[3] = {0.0, 0.0, 0.0}, dtau[3] = {0.0, 0.0, 0.0};
      if (part == CP_MAIN) {
        Dp[c] = -params->eps_n * dg[c];
        double dDelta[3];
        for (int i = 0; i < 3; ++i)
          dDelta[i] = (i == c % 3 ? gamma[c / 3] : 0.0) + f->a[0][i] * Dxi[0][c] + f->a[1][i] * Dxi[1][c];
        double n_dDelta = cp_dot3(n, dDelta);
        for (int i = 0; i < 3; ++i) dtau[i] = -params->eps_t * (dDelta[i] - n[i] * n_dDelta);
      } else {
        for (int i = 0; i < 3; ++i) dn[i] = Dn[part - 1][i][c];
        Dp[c] = stas && part == CP_ROTATIONAL ? params->eps_n * g * cp_dot3(e.nu, dn) / nu_n : 0.0;
        if (e.friction) projector_change(n, e.tau_hat, dn, dtau);
      }
      for (int i = 0; i < 3; ++i) {
        Dtau[i * nd + c] = dtau[i];
        ds[i][c] = Dp[c] * n[i] + p * dn[i];
      }
    }
    if (e.friction) {
      double t[3], dissipation;
      cov_return_map_branch(e.slip_branch ? COV_SLIP : COV_STICK, 3, out->tau, Dtau, identity, params->mu, p,
                            Dp, nd, params->eps_t, t, Dt, &dissipation);
      for (int i = 0; i < 3; ++i)
        for (int c = 0; c < nd; ++c) ds[i][c] += Dt[i * nd + c];
    }
    double *Kp = K[part];
    for (int a = 0; a < point->n_local; ++a) {
      if (alpha[a] == 0.0) continue;
      for (int i = 0; i < 3; ++i) {
        double *row = Kp + (size_t)(3 * a + i) * nd;
        for (int c = 0; c < nd; ++c) row[c] -= w * alpha[a] * ds[i][c];
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
