/* nts-augmented — element kernel: constraints, derivatives, friction and the element system (kernel.h).
 *
 * Derivatives go through the nine intermediate quantities w = [r, a_1, a_2]: every constraint is a function
 * phi(w) and w is linear in the x_I, so
 *   grad Phi = g_w B,   d2 Phi = B^T H_w B + sum_j g_w,j d2 w_j / dz2,   B = dw/dz (9 x nz),
 * where d2 w / dz2 needs x,ab (r in f) and x,abc (a_a in f); the latter vanishes on TRI3, QUAD4, TRI6, LINE2 and
 * LINE3 (x(f) at most quadratic or bilinear) and is taken on QUAD8 and QUAD9 from the shape functions' Hessians.
 * Only d2 phi_n / dw2 is long; it follows from s(r, c) = r . c / |c| with c = a_1 x a_2 (bilinear in a). */
#include "kernel.h"

#include <math.h>
#include <string.h>

enum { NW = 9 }; /* w = [r (3), a_1 (3), a_2 (3)] */

int nts_facet_init(nts_facet *facet, sk_elem_type type, nts_shape_fn shape, nts_shape_hessian_fn shape_hessian) {
  switch (type) {
  case SK_LINE2: facet->nen = 2; break;
  case SK_LINE3: case SK_TRI3: facet->nen = 3; break;
  case SK_QUAD4: facet->nen = 4; break;
  case SK_TRI6: facet->nen = 6; break;
  case SK_QUAD8: facet->nen = 8; break;
  case SK_QUAD9: facet->nen = 9; break;
  default: return -1;
  }
  facet->type = type;
  facet->extruded = type == SK_LINE2 || type == SK_LINE3;
  facet->third = type == SK_QUAD8 || type == SK_QUAD9;
  facet->shape = shape;
  facet->shape_hessian = shape_hessian;
  return 0;
}

double nts_facet_outside(const nts_facet *facet, const double f[2]) {
  if (facet->type == SK_TRI3 || facet->type == SK_TRI6) return fmax(fmax(0.0, -f[0]), fmax(-f[1], f[0] + f[1] - 1.0));
  const double beyond = fabs(f[0]) - 1.0;
  return facet->extruded ? fmax(0.0, beyond) : fmax(fmax(0.0, beyond), fabs(f[1]) - 1.0);
}

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void cross3(const double *a, const double *b, double *c) {
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}

/* [v]x: the matrix with [v]x u = v x u. */
static void skew3(const double *v, double S[3][3]) {
  S[0][0] = 0.0;   S[0][1] = -v[2]; S[0][2] = v[1];
  S[1][0] = v[2];  S[1][1] = 0.0;   S[1][2] = -v[0];
  S[2][0] = -v[1]; S[2][1] = v[0];  S[2][2] = 0.0;
}

/* Gradients of each constraint with respect to w. */
static void constraint_w_gradients(const nts_geometry *geo, double gw[3][NW]) {
  memset(gw, 0, sizeof(double) * 3 * NW);
  for (int alpha = 0; alpha < 2; ++alpha)
    for (int i = 0; i < 3; ++i) {
      gw[alpha][i] = geo->a[alpha][i];
      gw[alpha][3 + 3 * alpha + i] = geo->r[i];
    }
  /* phi_n = r . n: d/dc = p = (r - s n)/|c|; dc = da_1 x a_2 + a_1 x da_2. */
  double p[3], g1[3], g2[3];
  for (int i = 0; i < 3; ++i) p[i] = (geo->r[i] - geo->phi[NTS_PHI_N] * geo->n[i]) / geo->c_norm;
  cross3(geo->a[1], p, g1);
  cross3(p, geo->a[0], g2);
  for (int i = 0; i < 3; ++i) {
    gw[NTS_PHI_N][i] = geo->n[i];
    gw[NTS_PHI_N][3 + i] = g1[i];
    gw[NTS_PHI_N][6 + i] = g2[i];
  }
}

/* B = dw/dz, 9 x nz (row-major, row stride NTS_MAX_NZ). */
static void w_jacobian(const nts_geometry *geo, double B[NW][NTS_MAX_NZ]) {
  memset(B, 0, sizeof(double) * NW * NTS_MAX_NZ);
  const int nq = geo->nq;
  for (int i = 0; i < 3; ++i) {
    B[i][i] = 1.0;
    for (int I = 0; I < geo->nen; ++I) {
      B[i][3 + 3 * I + i] = -geo->N[I];
      B[3 + i][3 + 3 * I + i] = geo->dN[I][0];
      B[6 + i][3 + 3 * I + i] = geo->dN[I][1];
    }
    for (int b = 0; b < 2; ++b) {
      B[i][nq + b] = -geo->a[b][i];
      B[3 + i][nq + b] = geo->a_ab[0][b][i];
      B[6 + i][nq + b] = geo->a_ab[1][b][i];
    }
  }
}

/* x,abc of a QUAD8/QUAD9 facet: the shape functions' second derivatives are at most quadratic in each parametric
 * coordinate, so their central difference with any step is their exact derivative (to round-off). */
static void third_derivatives(const nts_facet *facet, const double *q_A, const double f[2], nts_geometry *geo) {
  static const double STEP = 0.5;
  for (int c = 0; c < 2; ++c) {
    double plus[2] = {f[0], f[1]}, minus[2] = {f[0], f[1]}, dd_plus[36], dd_minus[36];
    plus[c] += STEP;
    minus[c] -= STEP;
    facet->shape_hessian(facet->type, plus, dd_plus);
    facet->shape_hessian(facet->type, minus, dd_minus);
    for (int I = 0; I < facet->nen; ++I) {
      const double *xI = q_A + 3 + 3 * I;
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b) {
          const double d = (dd_plus[(I * 2 + a) * 2 + b] - dd_minus[(I * 2 + a) * 2 + b]) / (2.0 * STEP);
          for (int i = 0; i < 3; ++i) geo->a_abc[a][b][c][i] += d * xI[i];
        }
    }
  }
}

void nts_geometry_eval(const nts_facet *facet, const double *q_A, const double f[2], nts_geometry *geo) {
  memset(geo, 0, sizeof *geo);
  const int nen = facet->nen;
  geo->nen = nen;
  geo->nq = 3 + 3 * nen;
  geo->nz = geo->nq + 2;
  double N[9], dN[18], ddN[36];
  facet->shape(facet->type, f, N, dN);
  facet->shape_hessian(facet->type, f, ddN);
  const int pdim = facet->extruded ? 1 : 2; /* the segment's shape functions depend on f1 only */
  for (int I = 0; I < nen; ++I) {
    geo->N[I] = N[I];
    for (int a = 0; a < pdim; ++a) {
      geo->dN[I][a] = dN[I * pdim + a];
      for (int b = 0; b < pdim; ++b) geo->ddN[I][a][b] = ddN[(I * pdim + a) * pdim + b];
    }
    const double *xI = q_A + 3 + 3 * I;
    for (int i = 0; i < 3; ++i) {
      geo->x[i] += geo->N[I] * xI[i];
      for (int a = 0; a < 2; ++a) {
        geo->a[a][i] += geo->dN[I][a] * xI[i];
        for (int b = 0; b < 2; ++b) geo->a_ab[a][b][i] += geo->ddN[I][a][b] * xI[i];
      }
    }
  }
  if (facet->third) third_derivatives(facet, q_A, f, geo);
  if (facet->extruded) { /* x(f) = sum N_I(f1) x_I + f2 e_z */
    geo->x[2] += f[1];
    geo->a[1][2] = 1.0;
  }
  for (int i = 0; i < 3; ++i) geo->r[i] = q_A[i] - geo->x[i];
  cross3(geo->a[0], geo->a[1], geo->c);
  geo->c_norm = sqrt(dot3(geo->c, geo->c));
  for (int i = 0; i < 3; ++i) geo->n[i] = geo->c[i] / geo->c_norm;
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b) geo->m[a][b] = dot3(geo->a[a], geo->a[b]);
  geo->phi[NTS_PHI_AUG1] = dot3(geo->r, geo->a[0]);
  geo->phi[NTS_PHI_AUG2] = dot3(geo->r, geo->a[1]);
  geo->phi[NTS_PHI_N] = dot3(geo->r, geo->n);

  double gw[3][NW], B[NW][NTS_MAX_NZ];
  constraint_w_gradients(geo, gw);
  w_jacobian(geo, B);
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < geo->nz; ++j) {
      double s = 0.0;
      for (int w = 0; w < NW; ++w) s += gw[k][w] * B[w][j];
      geo->grad[k][j] = s;
    }
}

void nts_traction_vector(const nts_geometry *geo, const double t[2], double vector[3]) {
  const double det = geo->m[0][0] * geo->m[1][1] - geo->m[0][1] * geo->m[1][0];
  const double tau[2] = {(geo->m[1][1] * t[0] - geo->m[0][1] * t[1]) / det,
                         (-geo->m[1][0] * t[0] + geo->m[0][0] * t[1]) / det};
  for (int i = 0; i < 3; ++i) vector[i] = tau[0] * geo->a[0][i] + tau[1] * geo->a[1][i];
}

void nts_constraint_hessian(const nts_geometry *geo, const double lambda[3], double *H) {
  const int nz = geo->nz, nq = geo->nq;
  double gw3[3][NW], gw[NW] = {0}, Hw[NW][NW];
  constraint_w_gradients(geo, gw3);
  for (int k = 0; k < 3; ++k)
    for (int w = 0; w < NW; ++w) gw[w] += lambda[k] * gw3[k][w];
  memset(Hw, 0, sizeof Hw);
  /* Phi_aug,a = r . a_a */
  for (int a = 0; a < 2; ++a)
    for (int i = 0; i < 3; ++i) {
      Hw[i][3 + 3 * a + i] += lambda[a];
      Hw[3 + 3 * a + i][i] += lambda[a];
    }
  /* Phi_n = s(r, c(a_1, a_2)) */
  const double ln = lambda[NTS_PHI_N];
  if (ln != 0.0) {
    const double rho = geo->c_norm, s = geo->phi[NTS_PHI_N];
    const double *n = geo->n, *r = geo->r;
    double S[3][3], P[3][3], C[2][3][3], p[3];
    for (int i = 0; i < 3; ++i) {
      p[i] = (r[i] - s * n[i]) / rho;
      for (int j = 0; j < 3; ++j) {
        S[i][j] = (-r[i] * n[j] - n[i] * r[j] - (i == j ? s : 0.0) + 3.0 * s * n[i] * n[j]) / (rho * rho);
        P[i][j] = ((i == j ? 1.0 : 0.0) - n[i] * n[j]) / rho;
      }
    }
    skew3(geo->a[1], C[0]); /* dc/da_1 = -[a_2]x */
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) C[0][i][j] = -C[0][i][j];
    skew3(geo->a[0], C[1]); /* dc/da_2 = [a_1]x */
    for (int a = 0; a < 2; ++a) {
      /* (r, a_a) = (dn/dc) (dc/da_a) */
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          double v = 0.0;
          for (int l = 0; l < 3; ++l) v += P[i][l] * C[a][l][j];
          Hw[i][3 + 3 * a + j] += ln * v;
          Hw[3 + 3 * a + j][i] += ln * v;
        }
      for (int b = 0; b < 2; ++b)
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) {
            double v = 0.0;
            for (int l = 0; l < 3; ++l)
              for (int m = 0; m < 3; ++m) v += C[a][l][i] * S[l][m] * C[b][m][j];
            Hw[3 + 3 * a + i][3 + 3 * b + j] += ln * v;
          }
    }
    /* d2 c_i / da_1,j da_2,k = eps_ijk, contracted with p: -[p]x */
    double Sp[3][3];
    skew3(p, Sp);
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) {
        Hw[3 + j][6 + k] -= ln * Sp[j][k];
        Hw[6 + k][3 + j] -= ln * Sp[j][k];
      }
  }

  double B[NW][NTS_MAX_NZ], HB[NW][NTS_MAX_NZ];
  w_jacobian(geo, B);
  for (int w = 0; w < NW; ++w)
    for (int j = 0; j < nz; ++j) {
      double v = 0.0;
      for (int u = 0; u < NW; ++u) v += Hw[w][u] * B[u][j];
      HB[w][j] = v;
    }
  for (int i = 0; i < nz; ++i)
    for (int j = 0; j < nz; ++j) {
      double v = 0.0;
      for (int w = 0; w < NW; ++w) v += B[w][i] * HB[w][j];
      H[i * nz + j] = v;
    }
  /* second derivatives of w itself: r and a_a are bilinear in (x_I, f) but for d2 r / df2 = -x,ab and
   * d2 a_c / df2 = x,cab */
  for (int I = 0; I < geo->nen; ++I)
    for (int b = 0; b < 2; ++b)
      for (int i = 0; i < 3; ++i) {
        double v = -geo->dN[I][b] * gw[i];
        for (int a = 0; a < 2; ++a) v += geo->ddN[I][a][b] * gw[3 + 3 * a + i];
        H[(3 + 3 * I + i) * nz + nq + b] += v;
        H[(nq + b) * nz + 3 + 3 * I + i] += v;
      }
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b) {
      double v = -dot3(gw, geo->a_ab[a][b]);
      for (int c = 0; c < 2; ++c) v += dot3(gw + 3 + 3 * c, geo->a_abc[c][a][b]);
      H[(nq + a) * nz + nq + b] += v;
    }
}

void nts_metric_gradient(const nts_geometry *geo, double dm[3][NTS_MAX_NZ]) {
  double B[NW][NTS_MAX_NZ];
  w_jacobian(geo, B);
  static const int comp[3][2] = {{0, 0}, {0, 1}, {1, 1}};
  for (int c = 0; c < 3; ++c) {
    const int a = comp[c][0], b = comp[c][1];
    for (int j = 0; j < geo->nz; ++j) {
      double v = 0.0;
      for (int i = 0; i < 3; ++i) v += geo->a[b][i] * B[3 + 3 * a + i][j] + geo->a[a][i] * B[3 + 3 * b + i][j];
      dm[c][j] = v;
    }
  }
}

int nts_inverse2(const double A[2][2], double Ai[2][2]) {
  const double det = A[0][0] * A[1][1] - A[0][1] * A[1][0];
  const double scale = fabs(A[0][0] * A[1][1]) + fabs(A[0][1] * A[1][0]);
  if (det == 0.0 || fabs(det) <= 1e-14 * scale) return -1;
  Ai[0][0] = A[1][1] / det;
  Ai[1][1] = A[0][0] / det;
  Ai[0][1] = -A[0][1] / det;
  Ai[1][0] = -A[1][0] / det;
  return 0;
}

void nts_friction_eval(const nts_geometry *geo_hat, double alpha, const double f[2], const double f_start[2],
                       const double t_start[2], double lambda_n, const nts_friction_params *params,
                       nts_friction_mode mode, nts_friction *out) {
  memset(out, 0, sizeof *out);
  const int nz = geo_hat->nz, nq = geo_hat->nq;
  const double theta = alpha;
  if (params->mu <= 0.0 || params->epsilon_t <= 0.0) {
    /* frictionless: the traction stays at its (zero) start value */
    for (int a = 0; a < 2; ++a) out->t_used[a] = (1.0 - theta) * t_start[a];
    out->slip = 1;
    return;
  }
  const double eps = params->epsilon_t;
  double dm[3][NTS_MAX_NZ];
  nts_metric_gradient(geo_hat, dm);
  const double df[2] = {f[0] - f_start[0], f[1] - f_start[1]};
  double t_tr[2], dt_tr[2][NTS_MAX_NZ];
  /* d m_ab / d z_{n+1} = alpha d m_ab / d z_hat; component index of m_ab among (11, 12, 22) */
  static const int idx[2][2] = {{0, 1}, {1, 2}};
  for (int a = 0; a < 2; ++a) {
    t_tr[a] = t_start[a] + eps * (geo_hat->m[a][0] * df[0] + geo_hat->m[a][1] * df[1]);
    for (int j = 0; j < nz; ++j)
      dt_tr[a][j] = eps * alpha * (dm[idx[a][0]][j] * df[0] + dm[idx[a][1]][j] * df[1]);
    for (int b = 0; b < 2; ++b) dt_tr[a][nq + b] += eps * geo_hat->m[a][b];
  }
  double m_inv[2][2];
  if (nts_inverse2(geo_hat->m, m_inv) != 0) {
    memset(out, 0, sizeof *out);
    return;
  }
  double tau[2];
  for (int a = 0; a < 2; ++a) tau[a] = m_inv[a][0] * t_tr[0] + m_inv[a][1] * t_tr[1];
  const double nu = sqrt(fmax(0.0, tau[0] * t_tr[0] + tau[1] * t_tr[1]));
  const double cone = params->mu * fabs(lambda_n);
  out->trial_norm = nu;
  out->cone = cone;
  double dt_next[2][NTS_MAX_NZ];
  const int stick = mode == NTS_FRICTION_STICK || (mode == NTS_FRICTION_RETURN_MAP && nu <= cone) ||
                    (mode == NTS_FRICTION_SLIP && !(nu > 1e-300));
  if (stick) {
    for (int a = 0; a < 2; ++a) {
      out->t_next[a] = t_tr[a];
      for (int j = 0; j < nz; ++j) dt_next[a][j] = dt_tr[a][j];
    }
  } else {
    out->slip = 1;
    const double sign = lambda_n > 0.0 ? 1.0 : (lambda_n < 0.0 ? -1.0 : 0.0);
    for (int j = 0; j < nz; ++j) {
      /* d nu = (tau . dt_tr - 1/2 tau . dm tau) / nu */
      const double dmj[2][2] = {{alpha * dm[0][j], alpha * dm[1][j]}, {alpha * dm[1][j], alpha * dm[2][j]}};
      double dnu = tau[0] * dt_tr[0][j] + tau[1] * dt_tr[1][j];
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b) dnu -= 0.5 * tau[a] * dmj[a][b] * tau[b];
      dnu /= nu;
      for (int a = 0; a < 2; ++a) dt_next[a][j] = cone * (dt_tr[a][j] / nu - t_tr[a] * dnu / (nu * nu));
    }
    for (int a = 0; a < 2; ++a) {
      out->t_next[a] = cone * t_tr[a] / nu;
      out->dt_dlambda_n[a] = theta * params->mu * sign * t_tr[a] / nu;
    }
  }
  for (int a = 0; a < 2; ++a) {
    out->t_used[a] = (1.0 - theta) * t_start[a] + theta * out->t_next[a];
    for (int j = 0; j < nz; ++j) out->dt_dz[a][j] = theta * dt_next[a][j];
  }
}

void nts_element_build(const nts_facet *facet, const nts_element_input *in, const nts_friction_params *params,
                       nts_element_system *sys) {
  const int nq = 3 + 3 * facet->nen, nz = nq + 2, nu = nq + 5;
  const int iln = nq, i_f = nq + 1, i_la = nq + 3;
  sys->nq = nq;
  sys->nu = nu;
  memset(sys->R, 0, sizeof sys->R);
  memset(sys->J, 0, sizeof(double) * (size_t)nu * (size_t)nu);
  memset(&sys->friction, 0, sizeof sys->friction);
  memset(sys->phi, 0, sizeof sys->phi);
  nts_geometry_eval(facet, in->q_A, in->f, &sys->geo_end);
  if (!in->active) {
    sys->geo_hat = sys->geo_end;
    sys->R[iln] = in->lambda_n;
    for (int a = 0; a < 2; ++a) {
      sys->R[i_f + a] = in->f[a] - in->f_frozen[a];
      sys->R[i_la + a] = in->lambda_aug[a];
    }
    for (int i = nq; i < nu; ++i) sys->J[i * nu + i] = 1.0;
    return;
  }
  const double alpha = in->alpha;
  if (alpha == 1.0)
    sys->geo_hat = sys->geo_end;
  else
    nts_geometry_hat(facet, in, &sys->geo_hat);
  const nts_geometry *gh = &sys->geo_hat, *ge = &sys->geo_end;
  const double lambda[3] = {in->lambda_aug[0], in->lambda_aug[1], in->lambda_n};
  double H[NTS_MAX_NZ * NTS_MAX_NZ];
  nts_constraint_hessian(gh, lambda, H);
  nts_friction_eval(gh, alpha, in->f, in->f_start, in->t_start, in->lambda_n, params, in->friction_mode,
                    &sys->friction);
  const nts_friction *fr = &sys->friction;

  /* z index -> u index */
  int zu[NTS_MAX_NZ];
  for (int j = 0; j < nq; ++j) zu[j] = j;
  zu[nq] = i_f;
  zu[nq + 1] = i_f + 1;

  for (int jz = 0; jz < nz; ++jz) {
    const int row = zu[jz];
    double force = 0.0;
    for (int k = 0; k < 3; ++k) force += lambda[k] * gh->grad[k][jz];
    sys->R[row] = force;
    for (int kz = 0; kz < nz; ++kz) sys->J[row * nu + zu[kz]] = alpha * H[jz * nz + kz];
    sys->J[row * nu + iln] = gh->grad[NTS_PHI_N][jz];
    for (int a = 0; a < 2; ++a) sys->J[row * nu + i_la + a] = gh->grad[a][jz];
  }
  for (int b = 0; b < 2; ++b) {
    const int row = i_f + b;
    sys->R[row] += fr->t_used[b];
    for (int kz = 0; kz < nz; ++kz) sys->J[row * nu + zu[kz]] += fr->dt_dz[b][kz];
    sys->J[row * nu + iln] += fr->dt_dlambda_n[b];
  }
  /* lambda_n row: Phi_n(y_{n+1}) (76)_4, or the closest-point gap of q_{n+1} (74)_3 */
  if (in->f_gap) {
    nts_geometry gg;
    nts_geometry_eval(facet, in->q_A, in->f_gap, &gg);
    sys->R[iln] = sys->phi[NTS_PHI_N] = gg.phi[NTS_PHI_N];
    for (int j = 0; j < nq; ++j) sys->J[iln * nu + j] = gg.grad[NTS_PHI_N][j];
  } else {
    sys->R[iln] = sys->phi[NTS_PHI_N] = ge->phi[NTS_PHI_N];
    for (int kz = 0; kz < nz; ++kz) sys->J[iln * nu + zu[kz]] = ge->grad[NTS_PHI_N][kz];
  }
  /* lambda_aug rows: Phi_aug(y_{n+1}) (76)_4, or Phi_aug(y_hat) (75) */
  const nts_geometry *ga = in->aug_at_hat ? gh : ge;
  const double scale = in->aug_at_hat ? alpha : 1.0;
  for (int a = 0; a < 2; ++a) {
    sys->R[i_la + a] = sys->phi[a] = ga->phi[a];
    for (int kz = 0; kz < nz; ++kz) sys->J[(i_la + a) * nu + zu[kz]] = scale * ga->grad[a][kz];
  }
}

void nts_geometry_hat(const nts_facet *facet, const nts_element_input *in, nts_geometry *geo_hat) {
  const int nq = 3 + 3 * facet->nen;
  const double alpha = in->alpha;
  double q_hat[NTS_MAX_NQ], f_hat[2];
  for (int i = 0; i < nq; ++i) q_hat[i] = alpha * in->q_A[i] + (1.0 - alpha) * in->q_A_start[i];
  for (int a = 0; a < 2; ++a) f_hat[a] = alpha * in->f[a] + (1.0 - alpha) * in->f_start[a];
  nts_geometry_eval(facet, q_hat, f_hat, geo_hat);
}
