/* nts-augmented — what the strategies do with the element system (kernel.h): exact condensation and recovery,
 * the paper's reduced scheme (55), (78)-(81), the projection P (54) and lambda_aug (52), the closest point (41) and
 * the direct method's local elimination. */
#include <float.h>
#include <math.h>
#include <string.h>

#include "kernel.h"

/* Gaussian elimination with partial pivoting. A pivot is tested against the largest entry of the row it came from:
 * the element's (f, lambda_aug) block is a saddle point whose rows differ by eps_t times the facet metric (1e7 against
 * 0.25 on the coarse ring), so a test against the largest entry of A called regular blocks singular. */
int nts_solve_dense(int n, double *A, double *b, int nrhs) {
  enum { MAX_N = 128 }; /* the plugin solves n = 4; the tests solve whole systems up to 68 */
  if (n > MAX_N) return -1;
  double row_scale[MAX_N];
  for (int i = 0; i < n; ++i) {
    row_scale[i] = 0.0;
    for (int j = 0; j < n; ++j) row_scale[i] = fmax(row_scale[i], fabs(A[i * n + j]));
    if (!(row_scale[i] > 0.0)) return -1; /* a zero row, or nan */
  }
  for (int col = 0; col < n; ++col) {
    int piv = col;
    for (int i = col + 1; i < n; ++i)
      if (fabs(A[i * n + col]) > fabs(A[piv * n + col])) piv = i;
    if (!(fabs(A[piv * n + col]) > 1e-14 * row_scale[piv])) return -1;
    if (piv != col) {
      for (int j = 0; j < n; ++j) {
        double t = A[col * n + j];
        A[col * n + j] = A[piv * n + j];
        A[piv * n + j] = t;
      }
      for (int j = 0; j < nrhs; ++j) {
        double t = b[col * nrhs + j];
        b[col * nrhs + j] = b[piv * nrhs + j];
        b[piv * nrhs + j] = t;
      }
      const double t = row_scale[col];
      row_scale[col] = row_scale[piv];
      row_scale[piv] = t;
    }
    for (int i = col + 1; i < n; ++i) {
      const double l = A[i * n + col] / A[col * n + col];
      if (l == 0.0) continue;
      for (int j = col; j < n; ++j) A[i * n + j] -= l * A[col * n + j];
      for (int j = 0; j < nrhs; ++j) b[i * nrhs + j] -= l * b[col * nrhs + j];
    }
  }
  for (int col = n - 1; col >= 0; --col)
    for (int j = 0; j < nrhs; ++j) {
      double v = b[col * nrhs + j];
      for (int k = col + 1; k < n; ++k) v -= A[col * n + k] * b[k * nrhs + j];
      b[col * nrhs + j] = v / A[col * n + col];
    }
  return 0;
}

int nts_condense(const nts_element_system *sys, double *Jc, double *rhs) {
  const int nu = sys->nu, nk = sys->nq + 1, ne = 4, nr = nk + 1;
  double Jee[16], X[4 * (NTS_MAX_NQ + 2)];
  for (int a = 0; a < ne; ++a) {
    for (int b = 0; b < ne; ++b) Jee[a * ne + b] = sys->J[(nk + a) * nu + nk + b];
    for (int j = 0; j < nk; ++j) X[a * nr + j] = sys->J[(nk + a) * nu + j];
    X[a * nr + nk] = sys->R[nk + a];
  }
  if (nts_solve_dense(ne, Jee, X, nr) != 0) return -1;
  for (int i = 0; i < nk; ++i) {
    for (int j = 0; j < nk; ++j) {
      double v = sys->J[i * nu + j];
      for (int a = 0; a < ne; ++a) v -= sys->J[i * nu + nk + a] * X[a * nr + j];
      Jc[i * nk + j] = v;
    }
    double v = 0.0;
    for (int a = 0; a < ne; ++a) v += sys->J[i * nu + nk + a] * X[a * nr + nk];
    rhs[i] = v;
  }
  return 0;
}

int nts_recover(const nts_element_system *sys, const double *dk, double de[4]) {
  const int nu = sys->nu, nk = sys->nq + 1, ne = 4;
  double Jee[16], b[4];
  for (int a = 0; a < ne; ++a) {
    for (int c = 0; c < ne; ++c) Jee[a * ne + c] = sys->J[(nk + a) * nu + nk + c];
    double v = sys->R[nk + a];
    for (int j = 0; j < nk; ++j) v += sys->J[(nk + a) * nu + j] * dk[j];
    b[a] = -v;
  }
  if (nts_solve_dense(ne, Jee, b, 1) != 0) return -1;
  for (int a = 0; a < ne; ++a) de[a] = b[a];
  return 0;
}

static int gf_inverse_transpose(const nts_geometry *geo, double Git[2][2]) {
  double Gft[2][2];
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b) Gft[a][b] = geo->grad[b][geo->nq + a]; /* (Gf^T)_ab = dPhi_b / df_a */
  return nts_inverse2(Gft, Git);
}

int nts_projection_matrix(const nts_geometry *geo, double *P) {
  double Git[2][2];
  if (gf_inverse_transpose(geo, Git) != 0) return -1;
  for (int i = 0; i < geo->nq; ++i)
    for (int b = 0; b < 2; ++b) P[i * 2 + b] = -(geo->grad[0][i] * Git[0][b] + geo->grad[1][i] * Git[1][b]);
  return 0;
}

int nts_lambda_aug(const nts_geometry *geo, double lambda_n, const double t[2], double lambda_aug[2]) {
  double Git[2][2];
  if (gf_inverse_transpose(geo, Git) != 0) return -1;
  double rhs[2];
  for (int a = 0; a < 2; ++a) rhs[a] = geo->grad[NTS_PHI_N][geo->nq + a] * lambda_n + t[a];
  for (int a = 0; a < 2; ++a) lambda_aug[a] = -(Git[a][0] * rhs[0] + Git[a][1] * rhs[1]);
  return 0;
}

/* Phi_a = (x - x(f)) . a_a carries round-off eps |x| |a_a|, so the step in f_a is noise below eps |x| / |a_a|: on a
 * face 3e-4 long at x = 1 that is ~1e-12, above LOCAL_NEWTON_TOL (the graded patch test's slave node at the end of
 * the interface never converged; the core's projection has the same floor, core/contact/project.c). The strict
 * tolerance still decides wherever it can be met: the floor ends the iteration only after NOISE_STEPS steps under it,
 * so every closest point that converged before is the same to the last bit. */
static const double ROUNDOFF_STEPS = 16.0;
enum { NOISE_STEPS = 3 };

int nts_closest_point(const nts_facet *facet, const double *q_A, double f[2], double tol, int max_iterations) {
  nts_geometry geo;
  double coordinate_scale = 0.0;
  for (int i = 0; i < 3 + 3 * facet->nen; ++i) coordinate_scale = fmax(coordinate_scale, fabs(q_A[i]));
  const double noise = ROUNDOFF_STEPS * DBL_EPSILON * coordinate_scale;
  int steps_in_noise = 0;
  for (int it = 0; it < max_iterations; ++it) {
    nts_geometry_eval(facet, q_A, f, &geo);
    double Gf[2][2], Gi[2][2];
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) Gf[a][b] = geo.grad[a][geo.nq + b];
    if (nts_inverse2(Gf, Gi) != 0) return -1;
    const double d0 = -(Gi[0][0] * geo.phi[0] + Gi[0][1] * geo.phi[1]);
    const double d1 = -(Gi[1][0] * geo.phi[0] + Gi[1][1] * geo.phi[1]);
    f[0] += d0;
    f[1] += d1;
    if (!isfinite(f[0]) || !isfinite(f[1]) || fabs(f[0]) > 1e3 || fabs(f[1]) > 1e3) return -1;
    if (fabs(d0) <= tol && fabs(d1) <= tol) return it + 1;
    const double floor0 = geo.m[0][0] > 0.0 ? noise / sqrt(geo.m[0][0]) : 0.0;
    const double floor1 = geo.m[1][1] > 0.0 ? noise / sqrt(geo.m[1][1]) : 0.0;
    steps_in_noise = fabs(d0) <= fmax(tol, floor0) && fabs(d1) <= fmax(tol, floor1) ? steps_in_noise + 1 : 0;
    if (steps_in_noise == NOISE_STEPS) return it + 1;
  }
  return -1;
}

int nts_direct_eliminate(const nts_facet *facet, nts_element_input *in, const nts_friction_params *params,
                         int at_midpoint, double f_gap[2], double tol, int max_iterations) {
  const double alpha = in->alpha;
  in->aug_at_hat = 0;
  in->f_gap = NULL;
  if (!at_midpoint || alpha == 1.0) {
    if (nts_closest_point(facet, in->q_A, in->f, tol, max_iterations) < 0) return -1;
  } else {
    /* (75): xi_{n+1/2} is the closest point of the midpoint configuration; f_hat takes it */
    const int nq = 3 + 3 * facet->nen;
    double q_hat[NTS_MAX_NQ], f_hat[2];
    for (int i = 0; i < nq; ++i) q_hat[i] = alpha * in->q_A[i] + (1.0 - alpha) * in->q_A_start[i];
    for (int a = 0; a < 2; ++a) f_hat[a] = alpha * in->f[a] + (1.0 - alpha) * in->f_start[a];
    if (nts_closest_point(facet, q_hat, f_hat, tol, max_iterations) < 0) return -1;
    for (int a = 0; a < 2; ++a) in->f[a] = (f_hat[a] - (1.0 - alpha) * in->f_start[a]) / alpha;
    /* (74)_3: the normal constraint at t_{n+1} with the closest point of q_{n+1} */
    if (nts_closest_point(facet, in->q_A, f_gap, tol, max_iterations) < 0) return -1;
    in->aug_at_hat = 1;
    in->f_gap = f_gap;
  }
  nts_geometry geo_hat;
  if (alpha == 1.0)
    nts_geometry_eval(facet, in->q_A, in->f, &geo_hat);
  else
    nts_geometry_hat(facet, in, &geo_hat);
  nts_friction fr;
  nts_friction_eval(&geo_hat, alpha, in->f, in->f_start, in->t_start, in->lambda_n, params, in->friction_mode,
                    &fr);
  return nts_lambda_aug(&geo_hat, in->lambda_n, fr.t_used, in->lambda_aug);
}

/* ---- the paper's reduced scheme ----------------------------------------------------------------------------------- */

/* Gf^{-1} Phi_aug at geo (Gf_ab = d Phi_aug,a / d f_b). */
static int gf_inverse_phi(const nts_geometry *geo, double out[2]) {
  double Gf[2][2], Gi[2][2];
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b) Gf[a][b] = geo->grad[a][geo->nq + b];
  if (nts_inverse2(Gf, Gi) != 0) return -1;
  for (int a = 0; a < 2; ++a) out[a] = Gi[a][0] * geo->phi[0] + Gi[a][1] * geo->phi[1];
  return 0;
}

int nts_paper_build(const nts_facet *facet, const nts_element_input *in, const nts_friction_params *params,
                    nts_paper_system *sys) {
  const int nq = 3 + 3 * facet->nen, nz = nq + 2;
  const double alpha = in->alpha;
  memset(sys, 0, sizeof *sys);
  sys->nq = nq;
  nts_geometry_eval(facet, in->q_A, in->f, &sys->geo_end);
  if (alpha == 1.0)
    sys->geo_hat = sys->geo_end;
  else
    nts_geometry_hat(facet, in, &sys->geo_hat);
  const nts_geometry *gh = &sys->geo_hat, *ge = &sys->geo_end;
  nts_friction_eval(gh, alpha, in->f, in->f_start, in->t_start, in->lambda_n, params, in->friction_mode,
                    &sys->friction);
  const nts_friction *fr = &sys->friction;
  /* mu = -Gf^{-T} t: the multiplier P t stands for (52 without its h_f lambda_n term) */
  double mu[2], P_hat[NTS_MAX_NQ * 2];
  if (nts_lambda_aug(gh, 0.0, fr->t_used, mu) != 0 || nts_lambda_aug(gh, in->lambda_n, fr->t_used, sys->lambda_aug) ||
      nts_projection_matrix(gh, P_hat) != 0 || nts_projection_matrix(ge, sys->P_end) != 0 ||
      gf_inverse_phi(ge, sys->Gf_inv_phi) != 0)
    return -1;
  for (int i = 0; i < nq; ++i) {
    sys->h_hat[i] = gh->grad[NTS_PHI_N][i];
    sys->h_end[i] = ge->grad[NTS_PHI_N][i];
    sys->R_q[i] = sys->h_hat[i] * in->lambda_n + P_hat[2 * i] * fr->t_used[0] + P_hat[2 * i + 1] * fr->t_used[1];
  }
  for (int k = 0; k < 3; ++k) sys->phi_end[k] = ge->phi[k];
  /* dR_q/dz = alpha H_qz(mu, lambda_n) + P (alpha H_fz(mu) + dt/dz), every geometric quantity at y_hat:
   * d(Gq^T mu) = dGq^T mu + Gq^T dmu and Gf^T dmu = -(dGf^T mu + dt) */
  double Hq[NTS_MAX_NZ * NTS_MAX_NZ], Hf[NTS_MAX_NZ * NTS_MAX_NZ];
  const double lq[3] = {mu[0], mu[1], in->lambda_n}, lf[3] = {mu[0], mu[1], 0.0};
  nts_constraint_hessian(gh, lq, Hq);
  nts_constraint_hessian(gh, lf, Hf);
  for (int j = 0; j < nz; ++j) {
    double v[2];
    for (int b = 0; b < 2; ++b) v[b] = alpha * Hf[(nq + b) * nz + j] + fr->dt_dz[b][j];
    for (int i = 0; i < nq; ++i) {
      const double d = alpha * Hq[i * nz + j] + P_hat[2 * i] * v[0] + P_hat[2 * i + 1] * v[1];
      if (j < nq)
        sys->K_qq[i * nq + j] = d;
      else
        sys->K_qf[i * 2 + (j - nq)] = d;
    }
  }
  return 0;
}

void nts_paper_condensed(const nts_paper_system *sys, double *Jc, double *rhs) {
  const int nq = sys->nq, nk = nq + 1;
  for (int i = 0; i < nq; ++i) {
    for (int j = 0; j < nq; ++j)
      Jc[i * nk + j] = sys->K_qq[i * nq + j] + sys->K_qf[2 * i] * sys->P_end[2 * j] +
                       sys->K_qf[2 * i + 1] * sys->P_end[2 * j + 1];
    Jc[i * nk + nq] = sys->h_hat[i];
    Jc[nq * nk + i] = sys->h_end[i];
    rhs[i] = sys->K_qf[2 * i] * sys->Gf_inv_phi[0] + sys->K_qf[2 * i + 1] * sys->Gf_inv_phi[1];
  }
  Jc[nq * nk + nq] = 0.0;
  rhs[nq] = 0.0;
}

void nts_paper_recover(const nts_paper_system *sys, const double *dq, const double phi_aug[2], double df[2]) {
  double Gf[2][2], Gi[2][2];
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b) Gf[a][b] = sys->geo_end.grad[a][sys->nq + b];
  nts_inverse2(Gf, Gi); /* invertible: nts_paper_build checked it */
  for (int a = 0; a < 2; ++a) {
    df[a] = -(Gi[a][0] * phi_aug[0] + Gi[a][1] * phi_aug[1]);
    for (int i = 0; i < sys->nq; ++i) df[a] += sys->P_end[2 * i + a] * dq[i];
  }
}
