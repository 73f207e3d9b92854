/* covariant-penalty — kernel: the paper's printed tangent (Konyukhov & Schweizerhof 2005, Tables 1 and 2), written
 * in the plugin's one sign convention (docs/plugins/covariant-penalty.md §1, §5): p = -N >= 0, t the traction on the
 * slave, K = dR/dz. The normal terms keep the paper's signs, the tangential ones change sign.
 *
 *   main        w eps_n A^T n n^T A                                                          (83)
 *               stick: + w eps_t A^T P A                                                      (100)
 *               slip:  + w eps_n mu A^T e n^T A + w eps_t mu p/|T^tr| A^T (P - e e^T) A       (107), (107a), (107b)
 *   rotational  w (B_j^T s rho^j^T A + A^T rho^j s^T B_j),  s = p n + t                      (83a), (100a), (107c)
 *   curvature   w p A^T h^ij rho_i rho_j^T A - w A^T (tau_h n^T + n tau_h^T) A,  tau_h = T_i h^ij rho_j
 *                                                                                             (83b), (100b), (107d)
 *               slip: - w mu p/|T^tr|^3 A^T T^tr (-T^j T_m Gamma^m_jn rho^n + T^j h_jk T^k n)^T A   (107e)
 * Each part is symmetric in stick; (107), (107e) are not. */
#include <string.h>

#include "kernel.h"
#include "kernel_internal.h"

/* K[(a,i),(b,k)] += coef u_a v_b M[i][k] over the local nodes. */
static void add_block(double *K, int n_local, const double *u, const double *v, const double M[3][3], double coef) {
  const int nd = 3 * n_local;
  for (int a = 0; a < n_local; ++a) {
    if (u[a] == 0.0) continue;
    for (int b = 0; b < n_local; ++b) {
      double uv = coef * u[a] * v[b];
      if (uv == 0.0) continue;
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) K[(size_t)(3 * a + i) * nd + 3 * b + k] += uv * M[i][k];
    }
  }
}

static void outer(const double *x, const double *y, double M[3][3]) {
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) M[i][k] = x[i] * y[k];
}

void cp_paper_tangent(const cp_point *point, const cp_params *params, const cp_eval *e, const int want[CP_N_PARTS],
                      double *K[CP_N_PARTS]) {
  const sk_surface_point *f = &e->frame;
  const cp_result *r = &e->result;
  const double *n = f->n, w = params->weight, p = r->p;
  const int nl = point->n_local, slip = e->slip_branch;
  double alpha[CP_MAX_NODES] = {0}, beta[2][CP_MAX_NODES] = {{0}}, M[3][3];
  for (int a = 0; a < point->n_slave; ++a) alpha[point->slave[a]] += point->S[a];
  for (int k = 0; k < point->master.nen; ++k) {
    alpha[point->master_nodes[k]] -= f->N[k];
    for (int j = 0; j < 2; ++j) beta[j][point->master_nodes[k]] += f->dN[k][j];
  }

  if (want[CP_MAIN]) {
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) {
        double P = (i == k ? 1.0 : 0.0) - n[i] * n[k];
        M[i][k] = params->eps_n * n[i] * n[k];
        if (e->friction && !slip) M[i][k] += params->eps_t * P;
        if (slip)
          M[i][k] += params->eps_n * params->mu * e->e[i] * n[k] +
                     params->eps_t * params->mu * p / e->tau_norm * (P - e->e[i] * e->e[k]);
      }
    add_block(K[CP_MAIN], nl, alpha, alpha, M, w);
  }
  if (want[CP_ROTATIONAL])
    for (int j = 0; j < 2; ++j) {
      outer(e->s, f->a_dual[j], M);
      add_block(K[CP_ROTATIONAL], nl, beta[j], alpha, M, w);
      outer(f->a_dual[j], e->s, M);
      add_block(K[CP_ROTATIONAL], nl, alpha, beta[j], M, w);
    }
  if (want[CP_CURVATURE]) {
    /* h^ij rho_i rho_j = h_ij rho^i rho^j; tau_h = T_i h^ij rho_j = (t . rho^i) h_ij rho^j */
    double T_up[2], tau_h[3] = {0.0, 0.0, 0.0};
    for (int i = 0; i < 2; ++i) T_up[i] = cp_dot3(r->t, f->a_dual[i]);
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j)
        for (int c = 0; c < 3; ++c) tau_h[c] += T_up[i] * f->h[i][j] * f->a_dual[j][c];
    for (int c = 0; c < 3; ++c)
      for (int d = 0; d < 3; ++d) {
        M[c][d] = -(tau_h[c] * n[d] + n[c] * tau_h[d]);
        for (int i = 0; i < 2; ++i)
          for (int j = 0; j < 2; ++j) M[c][d] += p * f->h[i][j] * f->a_dual[i][c] * f->a_dual[j][d];
      }
    add_block(K[CP_CURVATURE], nl, alpha, alpha, M, w);
    if (slip) { /* (107e) with the trial components T_m = tau . rho_m, T^j = tau . rho^j */
      double Tc[2], Tu[2], v[3] = {0.0, 0.0, 0.0};
      for (int i = 0; i < 2; ++i) {
        Tc[i] = cp_dot3(r->tau, f->a[i]);
        Tu[i] = cp_dot3(r->tau, f->a_dual[i]);
      }
      for (int j = 0; j < 2; ++j)
        for (int q = 0; q < 2; ++q) {
          double gamma_term = 0.0; /* T_m Gamma^m_jq, christoffel[j][q][m] = Gamma^m_jq */
          for (int m = 0; m < 2; ++m) gamma_term += Tc[m] * f->christoffel[j][q][m];
          for (int c = 0; c < 3; ++c) v[c] -= Tu[j] * gamma_term * f->a_dual[q][c];
        }
      double hTT = 0.0;
      for (int j = 0; j < 2; ++j)
        for (int k = 0; k < 2; ++k) hTT += Tu[j] * f->h[j][k] * Tu[k];
      for (int c = 0; c < 3; ++c) v[c] += hTT * n[c];
      outer(r->tau, v, M);
      double norm3 = e->tau_norm * e->tau_norm * e->tau_norm;
      add_block(K[CP_CURVATURE], nl, alpha, alpha, M, -w * params->mu * p / norm3);
    }
  }
}
