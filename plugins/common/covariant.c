/* Covariant contact kinematics and friction (covariant.h): the linearisation that penalty-nts used inline, shared
 * with the covariant-penalty plugin. */
#include "covariant.h"

#include <math.h>
#include <string.h>

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

int cov_invert2(int n, const double a[2][2], double inv[2][2]) {
  if (n == 1) {
    if (a[0][0] == 0.0) return 0;
    inv[0][0] = 1.0 / a[0][0];
    inv[0][1] = inv[1][0] = 0.0;
    inv[1][1] = 1.0;
    return 1;
  }
  double det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
  if (det == 0.0) return 0;
  inv[0][0] = a[1][1] / det;
  inv[1][1] = a[0][0] / det;
  inv[0][1] = -a[0][1] / det;
  inv[1][0] = -a[1][0] / det;
  return 1;
}

int cov_complete_metric(int pdim, sk_surface_point *pt) {
  double m[2][2] = {{1.0, 0.0}, {0.0, 1.0}};
  for (int a = 0; a < pdim; ++a)
    for (int b = 0; b < pdim; ++b) m[a][b] = dot3(pt->a[a], pt->a[b]);
  double inv[2][2];
  if (!cov_invert2(pdim, m, inv)) return 0;
  memcpy(pt->m, m, sizeof m);
  memcpy(pt->m_inv, inv, sizeof inv);
  for (int a = 0; a < pdim; ++a)
    for (int i = 0; i < 3; ++i) {
      pt->a_dual[a][i] = 0.0;
      for (int b = 0; b < pdim; ++b) pt->a_dual[a][i] += inv[a][b] * pt->a[b][i];
    }
  return 1;
}

int cov_kinematics_eval(const sk_surface_point *pt, int dim, int nen, double g, cov_kinematics *k) {
  const int pdim = dim - 1, nd = dim * (1 + nen);
  const double *n = pt->n;
  k->dim = dim;
  k->pdim = pdim;
  k->nen = nen;
  k->nd = nd;
  k->g = g;
  /* First derivatives, as rows over the local dofs: G = dg/dq, C_a = a_a . (du at fixed xi), E_a = n . da_a. */
  double C[2][COV_MAX_DOFS] = {{0}}, E[2][COV_MAX_DOFS] = {{0}};
  memset(k->G, 0, sizeof k->G);
  for (int i = 0; i < dim; ++i) {
    k->G[i] = n[i];
    for (int a = 0; a < pdim; ++a) C[a][i] = pt->a[a][i];
  }
  for (int I = 0; I < nen; ++I)
    for (int i = 0; i < dim; ++i) {
      int c = dim * (1 + I) + i;
      k->G[c] = -pt->N[I] * n[i];
      for (int a = 0; a < pdim; ++a) {
        C[a][c] = -pt->N[I] * pt->a[a][i];
        E[a][c] = pt->dN[I][a] * n[i];
      }
    }
  /* dxi = A^-1 (C + g E), A = m - g h */
  double A[2][2] = {{1.0, 0.0}, {0.0, 1.0}}, Ainv[2][2];
  for (int a = 0; a < pdim; ++a)
    for (int b = 0; b < pdim; ++b) A[a][b] = pt->m[a][b] - g * pt->h[a][b];
  if (!cov_invert2(pdim, A, Ainv)) return 0;
  memset(k->Dxi, 0, sizeof k->Dxi);
  memset(k->Dn, 0, sizeof k->Dn);
  memset(k->Dn_rot, 0, sizeof k->Dn_rot);
  memset(k->Dn_curv, 0, sizeof k->Dn_curv);
  for (int c = 0; c < nd; ++c) {
    for (int a = 0; a < pdim; ++a)
      for (int b = 0; b < pdim; ++b) k->Dxi[a][c] += Ainv[a][b] * (C[b][c] + g * E[b][c]);
    /* dn = -a^a (n . da_a + h_ab dxi^b): the nodal (rotational) and the xi (curvature) part */
    for (int a = 0; a < pdim; ++a) {
      double curv = 0.0;
      for (int b = 0; b < pdim; ++b) curv += pt->h[a][b] * k->Dxi[b][c];
      for (int i = 0; i < 3; ++i) {
        k->Dn_rot[i][c] -= pt->a_dual[a][i] * E[a][c];
        k->Dn_curv[i][c] -= pt->a_dual[a][i] * curv;
      }
    }
    for (int i = 0; i < 3; ++i) k->Dn[i][c] = k->Dn_rot[i][c] + k->Dn_curv[i][c];
  }
  return 1;
}

void cov_metric_derivatives_eval(const sk_surface_point *pt, const cov_kinematics *k, cov_metric_derivatives *d) {
  const int dim = k->dim, pdim = k->pdim, nen = k->nen, nd = k->nd;
  memset(d, 0, sizeof *d);
  for (int a = 0; a < pdim; ++a)
    for (int i = 0; i < 3; ++i)
      for (int c = 0; c < nd; ++c) {
        double s = 0.0;
        for (int b = 0; b < pdim; ++b) s += pt->a_ab[a][b][i] * k->Dxi[b][c];
        d->Da[a][i][c] = s;
      }
  for (int a = 0; a < pdim; ++a)
    for (int I = 0; I < nen; ++I)
      for (int i = 0; i < dim; ++i) d->Da[a][i][dim * (1 + I) + i] += pt->dN[I][a];
  for (int a = 0; a < pdim; ++a)
    for (int b = 0; b < pdim; ++b)
      for (int c = 0; c < nd; ++c)
        for (int i = 0; i < 3; ++i) d->Dm[a][b][c] += pt->a[b][i] * d->Da[a][i][c] + pt->a[a][i] * d->Da[b][i][c];
  for (int a = 0; a < pdim; ++a)
    for (int b = 0; b < pdim; ++b)
      for (int c = 0; c < nd; ++c) {
        double s = 0.0;
        for (int x = 0; x < pdim; ++x)
          for (int y = 0; y < pdim; ++y) s -= pt->m_inv[a][x] * d->Dm[x][y][c] * pt->m_inv[y][b];
        d->Dminv[a][b][c] = s;
      }
  for (int a = 0; a < pdim; ++a)
    for (int i = 0; i < 3; ++i)
      for (int c = 0; c < nd; ++c) {
        double s = 0.0;
        for (int b = 0; b < pdim; ++b) s += d->Dminv[a][b][c] * pt->a[b][i] + pt->m_inv[a][b] * d->Da[b][i][c];
        d->Da_dual[a][i][c] = s;
      }
}

int cov_return_map(int n, const double *trial, const double *Dtrial, const double metric_inv[3][3], double mu,
                   double p, const double *Dp, int nd, double eps_t, double *t, double *Dt, double *dissipation) {
  return cov_return_map_held(n, trial, Dtrial, metric_inv, mu, p, Dp, nd, eps_t, NULL, t, Dt, dissipation);
}

int cov_slip_turned_back(int n, const double *trial, const double metric_inv[3][3], double limit,
                         const double *held) {
  if (!held) return 0;
  /* held . trial / |held| <= mu p, in the metric of the trial */
  double along = 0.0, held2 = 0.0;
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) {
      along += held[a] * metric_inv[a][b] * trial[b];
      held2 += held[a] * metric_inv[a][b] * held[b];
    }
  return held2 > 0.0 && along <= limit * sqrt(held2);
}

int cov_return_map_held(int n, const double *trial, const double *Dtrial, const double metric_inv[3][3], double mu,
                        double p, const double *Dp, int nd, double eps_t, const double *held, double *t, double *Dt,
                        double *dissipation) {
  double norm2 = 0.0;
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) norm2 += trial[a] * metric_inv[a][b] * trial[b];
  const double limit = mu * p;
  const int state =
      sqrt(norm2) <= limit || cov_slip_turned_back(n, trial, metric_inv, limit, held) ? COV_STICK : COV_SLIP;
  cov_return_map_branch(state, n, trial, Dtrial, metric_inv, mu, p, Dp, nd, eps_t, t, Dt, dissipation);
  return state;
}

void cov_return_map_branch(int state, int n, const double *trial, const double *Dtrial, const double metric_inv[3][3],
                           double mu, double p, const double *Dp, int nd, double eps_t, double *t, double *Dt,
                           double *dissipation) {
  if (state == COV_STICK) {
    for (int a = 0; a < n; ++a) t[a] = trial[a];
    memcpy(Dt, Dtrial, (size_t)(n * nd) * sizeof(double));
    *dissipation = 0.0;
    return;
  }
  double norm2 = 0.0;
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) norm2 += trial[a] * metric_inv[a][b] * trial[b];
  const double norm = sqrt(norm2), limit = mu * p;
  /* Slip: t = mu p trial/|trial|. dissipation = slip increment . t = mu p (|trial| - mu p) / eps_t >= 0. */
  for (int a = 0; a < n; ++a) t[a] = limit * trial[a] / norm;
  for (int c = 0; c < nd; ++c) {
    double dnorm2 = 0.0; /* metric derivative terms are added by the caller (covariant case) */
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b) dnorm2 += 2.0 * trial[a] * metric_inv[a][b] * Dtrial[b * nd + c];
    for (int a = 0; a < n; ++a)
      Dt[a * nd + c] = mu * Dp[c] * trial[a] / norm + limit * Dtrial[a * nd + c] / norm -
                       limit * trial[a] * dnorm2 / (2.0 * norm2 * norm);
  }
  *dissipation = fmax(limit * (norm - limit) / eps_t, 0.0);
}

int cov_friction(const sk_surface_point *pt, const cov_kinematics *k, const cov_metric_derivatives *d,
                 const double t_n[2], const double dxi[2], double eps_t, double mu, double p, const double *Dp,
                 const double *held, double t_cov[2], double T[3], double DT[3][COV_MAX_DOFS], double *dissipation) {
  const int pdim = k->pdim, nd = k->nd;
  /* Trial t_a = t_n,a - eps_t m_ab dxi^b. */
  double trial[2] = {0.0, 0.0}, Dtrial[2 * COV_MAX_DOFS] = {0};
  for (int a = 0; a < pdim; ++a) {
    trial[a] = t_n[a];
    for (int b = 0; b < pdim; ++b) trial[a] -= eps_t * pt->m[a][b] * dxi[b];
    for (int c = 0; c < nd; ++c) {
      double s = 0.0;
      for (int b = 0; b < pdim; ++b) s += d->Dm[a][b][c] * dxi[b] + pt->m[a][b] * k->Dxi[b][c];
      Dtrial[a * nd + c] = -eps_t * s;
    }
  }
  double minv[3][3] = {{0}};
  for (int a = 0; a < pdim; ++a)
    for (int b = 0; b < pdim; ++b) minv[a][b] = pt->m_inv[a][b];
  double t[2] = {0.0, 0.0}, Dt[2 * COV_MAX_DOFS] = {0};
  int state = cov_return_map_held(pdim, trial, Dtrial, minv, mu, p, Dp, nd, eps_t, held, t, Dt, dissipation);
  if (state == COV_SLIP) {
    /* The norm also depends on q through m^ab: add -mu p trial_a/|trial|^3 * (1/2) trial . Dm^-1 . trial. */
    double norm2 = 0.0;
    for (int a = 0; a < pdim; ++a)
      for (int b = 0; b < pdim; ++b) norm2 += trial[a] * minv[a][b] * trial[b];
    double norm = sqrt(norm2), limit = mu * p;
    for (int c = 0; c < nd; ++c) {
      double s = 0.0;
      for (int a = 0; a < pdim; ++a)
        for (int b = 0; b < pdim; ++b) s += trial[a] * d->Dminv[a][b][c] * trial[b];
      for (int a = 0; a < pdim; ++a) Dt[a * nd + c] -= limit * trial[a] * s / (2.0 * norm2 * norm);
    }
  }
  t_cov[0] = t_cov[1] = 0.0;
  for (int a = 0; a < pdim; ++a) t_cov[a] = t[a];
  for (int i = 0; i < 3; ++i) {
    T[i] = 0.0;
    for (int c = 0; c < nd; ++c) DT[i][c] = 0.0;
  }
  for (int i = 0; i < 3; ++i)
    for (int a = 0; a < pdim; ++a) {
      T[i] += t[a] * pt->a_dual[a][i];
      for (int c = 0; c < nd; ++c) DT[i][c] += Dt[a * nd + c] * pt->a_dual[a][i] + t[a] * d->Da_dual[a][i][c];
    }
  return state;
}
