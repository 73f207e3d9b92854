/* mortar-dual kernel: the mortar integrals of one face pair — 2D segments, concentrated points, rigid obstacles —,
 * projections of the integration points, and the pair's forces (see kernel.h; 3D segments: clip.c; the point
 * projections themselves: projection.c). */
#include <math.h>
#include <string.h>

#include "kernel.h"
#include "kernel_internal.h"

/* ---- small dense solves ---------------------------------------------------------------------------------------- */
int mortar_solve_small(int n, double *A, double *B, int nrhs) {
  for (int c = 0; c < n; ++c) {
    int piv = c;
    for (int r = c + 1; r < n; ++r)
      if (fabs(A[r * n + c]) > fabs(A[piv * n + c])) piv = r;
    if (!(fabs(A[piv * n + c]) > 0.0)) return -1;
    if (piv != c) {
      for (int k = 0; k < n; ++k) {
        const double t = A[c * n + k];
        A[c * n + k] = A[piv * n + k];
        A[piv * n + k] = t;
      }
      for (int k = 0; k < nrhs; ++k) {
        const double t = B[c * nrhs + k];
        B[c * nrhs + k] = B[piv * nrhs + k];
        B[piv * nrhs + k] = t;
      }
    }
    for (int r = c + 1; r < n; ++r) {
      const double f = A[r * n + c] / A[c * n + c];
      if (f == 0.0) continue;
      for (int k = c; k < n; ++k) A[r * n + k] -= f * A[c * n + k];
      for (int k = 0; k < nrhs; ++k) B[r * nrhs + k] -= f * B[c * nrhs + k];
    }
  }
  for (int c = n - 1; c >= 0; --c)
    for (int k = 0; k < nrhs; ++k) {
      double v = B[c * nrhs + k];
      for (int j = c + 1; j < n; ++j) v -= A[c * n + j] * B[j * nrhs + k];
      B[c * nrhs + k] = v / A[c * n + c];
    }
  return 0;
}

int mortar_implicit(int m, const double *J, const fwd *r, const double *y, fwd *out) {
  int n = 0;
  for (int i = 0; i < m; ++i) n = fwd_imax(n, r[i].n);
  double A[9], B[3 * FWD_MAX];
  memcpy(A, J, sizeof(double) * (size_t)(m * m));
  for (int i = 0; i < m; ++i)
    for (int k = 0; k < n; ++k) B[i * n + k] = k < r[i].n ? -r[i].d[k] : 0.0;
  if (n > 0 && mortar_solve_small(m, A, B, n) != 0) return -1;
  for (int i = 0; i < m; ++i) {
    out[i].v = y[i];
    out[i].n = n;
    for (int k = 0; k < n; ++k) out[i].d[k] = B[i * n + k];
  }
  return 0;
}

/* ---- integration ----------------------------------------------------------------------------------------------- */
void mortar_integrals_zero(mortar_integrals *I, const mortar_pair *p) {
  I->nen_s = p->nen_s;
  I->nen_m = p->nen_m;
  /* in place: an assignment of fwd_const copies the whole struct (FWD_MAX slots) */
  for (int j = 0; j < MORTAR_MAX_NEN; ++j) {
    fwd_set_const(&I->gap[j], 0.0);
    I->cover[j] = 0.0;
    for (int k = 0; k < MORTAR_MAX_NEN; ++k) {
      fwd_set_const(&I->D[j][k], 0.0);
      fwd_set_const(&I->M[j][k], 0.0);
    }
  }
  I->measure = 0.0;
  I->gap_min = INFINITY;
  I->n_cells = 0;
}

/* Phi_j at the slave shape functions N1. */
static void basis_values(const mortar_pair *p, const mortar_basis_coeffs *A, mortar_basis basis, const fwd *N1,
                         fwd *Phi) {
  const int ns = p->nen_s;
  for (int j = 0; j < ns; ++j) {
    if (basis == MORTAR_STANDARD) {
      Phi[j] = N1[j];
    } else {
      fwd_set_mul(&Phi[j], &A->coeff[j][0], &N1[0]);
      for (int k = 1; k < ns; ++k) fwd_acc_mul(&Phi[j], &A->coeff[j][k], &N1[k]);
    }
  }
}

void mortar_add_point(const mortar_pair *p, const mortar_basis_coeffs *A, mortar_basis basis, const fwd *xi1,
                      const fwd *xi2, fwd weight, fwd g, mortar_integrals *I) {
  fwd N1[MORTAR_MAX_NEN], N2[MORTAR_MAX_NEN];
  mortar_shape(p->slave, xi1, N1, NULL);
  if (xi2) mortar_shape(p->master, xi2, N2, NULL);
  mortar_add_point_shapes(p, A, basis, N1, xi2 ? N2 : NULL, &weight, &g, I);
}

void mortar_add_point_shapes(const mortar_pair *p, const mortar_basis_coeffs *A, mortar_basis basis, const fwd *N1,
                             const fwd *N2, const fwd *weight, const fwd *g, mortar_integrals *I) {
  const int ns = p->nen_s, nm = p->nen_m;
  fwd Phi[MORTAR_MAX_NEN];
  basis_values(p, A, basis, N1, Phi);
  /* coverage in the functions of the nodes' measures: N~ on TRI6 and QUAD8 (their vertex functions integrate to 0 and
   * to a negative value) */
  double Nc[MORTAR_MAX_NEN], T[MORTAR_MAX_NEN][MORTAR_MAX_NEN];
  for (int j = 0; j < ns; ++j) Nc[j] = N1[j].v;
  if (mortar_transform(p->slave, T)) {
    double Nv[MORTAR_MAX_NEN];
    memcpy(Nv, Nc, sizeof Nv);
    mortar_transform_values(ns, T, Nv, Nc);
  }
  for (int j = 0; j < ns; ++j) {
    fwd wPhi;
    fwd_set_mul(&wPhi, weight, &Phi[j]);
    fwd_acc_mul(&I->gap[j], &wPhi, g);
    I->cover[j] += weight->v * Nc[j];
    if (N2)
      for (int l = 0; l < nm; ++l) fwd_acc_mul(&I->M[j][l], &wPhi, &N2[l]);
  }
  I->measure += weight->v;
  I->gap_min = fmin(I->gap_min, g->v);
}

void mortar_slave_integrals(const mortar_pair *p, const mortar_basis_coeffs *A, mortar_basis basis, int n,
                            const double *xi, const double *w, mortar_integrals *I) {
  const int ns = p->nen_s, pd = p->slave->pdim;
  fwd xs[MORTAR_MAX_NEN][3];
  memcpy(xs, p->xs, sizeof(fwd) * 3 * (size_t)ns);
  for (int q = 0; q < n; ++q) {
    const fwd x_q[2] = {fwd_const(xi[q * pd]), fwd_const(pd > 1 ? xi[q * pd + 1] : 0.0)};
    fwd N[MORTAR_MAX_NEN], Phi[MORTAR_MAX_NEN], a[2][3], jac;
    mortar_shape(p->slave, x_q, N, NULL);
    mortar_face_point(p->slave, xs, x_q, NULL, a);
    if (pd == 1) {
      jac = fwd_norm(3, a[0]);
    } else {
      fwd c[3];
      fwd_cross3(a[0], a[1], c);
      jac = fwd_norm(3, c);
    }
    basis_values(p, A, basis, N, Phi);
    const fwd wj = fwd_scale(w[q], jac);
    for (int j = 0; j < ns; ++j) {
      fwd wPhi;
      fwd_set_mul(&wPhi, &wj, &Phi[j]);
      if (basis == MORTAR_DUAL) {
        fwd_acc_scaled(&I->D[j][j], 1.0, &wPhi); /* row sum: sum_k Phi_j N_k = Phi_j */
      } else {
        for (int k = 0; k < ns; ++k) fwd_acc_mul(&I->D[j][k], &wPhi, &N[k]);
      }
    }
  }
}

static int segments_2d_curved(const mortar_pair *p, const mortar_basis_coeffs *A, mortar_basis basis, int n_gauss,
                              mortar_integrals *I);

int mortar_segments_2d(const mortar_pair *p, const mortar_basis_coeffs *A, mortar_basis basis, int n_gauss,
                       mortar_integrals *I) {
  if (p->slave->type != SK_LINE2 || p->master->type != SK_LINE2) return segments_2d_curved(p, A, basis, n_gauss, I);
  /* slave x1(xi) = c + xi h, n(xi) = nm + xi nd; master x2(eta) = cm + eta hm (LINE2 faces) */
  fwd c[2], h[2], nm[2], nd[2], cm[2], hm[2];
  for (int i = 0; i < 2; ++i) {
    c[i] = fwd_scale(0.5, fwd_add(p->xs[0][i], p->xs[1][i]));
    h[i] = fwd_scale(0.5, fwd_sub(p->xs[1][i], p->xs[0][i]));
    nm[i] = fwd_scale(0.5, fwd_add(p->ns[0][i], p->ns[1][i]));
    nd[i] = fwd_scale(0.5, fwd_sub(p->ns[1][i], p->ns[0][i]));
    cm[i] = fwd_scale(0.5, fwd_add(p->xm[0][i], p->xm[1][i]));
    hm[i] = fwd_scale(0.5, fwd_sub(p->xm[1][i], p->xm[0][i]));
  }
  /* only faces that face each other: master outward normal (hm_y, -hm_x) against the slave normal */
  if (hm[1].v * nm[0].v - hm[0].v * nm[1].v >= 0.0) return 0;
  /* master node b on the slave line along the interpolated normal: (c + xi h - x_b) x (nm + xi nd) = 0 */
  fwd ends[2];
  for (int b = 0; b < 2; ++b) {
    fwd r[2] = {fwd_sub(c[0], p->xm[b][0]), fwd_sub(c[1], p->xm[b][1])};
    const double a2 = fwd_cross2(h, nd).v, a1 = fwd_cross2(r, nd).v + fwd_cross2(h, nm).v, a0 = fwd_cross2(r, nm).v;
    if (!(fabs(a1) > 0.0)) return 0;
    double xi = -a0 / a1;
    for (int it = 0; it < 30; ++it) {
      const double f = (a2 * xi + a1) * xi + a0, df = 2.0 * a2 * xi + a1;
      if (!(fabs(df) > 0.0)) return 0;
      const double step = f / df;
      xi -= step;
      if (fabs(step) < 1e-15) break;
    }
    fwd xl[2] = {fwd_add(r[0], fwd_scale(xi, h[0])), fwd_add(r[1], fwd_scale(xi, h[1]))};
    fwd nl[2] = {fwd_add(nm[0], fwd_scale(xi, nd[0])), fwd_add(nm[1], fwd_scale(xi, nd[1]))};
    ends[b] = fwd_implicit(xi, fwd_cross2(xl, nl), 2.0 * a2 * xi + a1);
  }
  fwd lo = ends[0].v < ends[1].v ? ends[0] : ends[1];
  fwd hi = ends[0].v < ends[1].v ? ends[1] : ends[0];
  if (lo.v < -1.0) lo = fwd_const(-1.0);
  if (hi.v > 1.0) hi = fwd_const(1.0);
  if (!(hi.v - lo.v > 1e-12)) return 0;
  /* A genuine segment's middle projects onto the master face. A master face far off the slave line can have its
   * nodes projected onto the slave face through a strongly turning normal field (n(xi) = nm + xi nd rotates for
   * large |xi|) and would claim it (measured: a block corner's node covered 3.4 times in Hammer's benchmark, Newton
   * diverged); its middle then projects far outside the face. The test is generous (0.5 beyond the face) so that it
   * never cuts a genuine segment near a crossing, where the segment's ends move continuously. */
  {
    const double xi_mid = 0.5 * (lo.v + hi.v), x_mid[2] = {c[0].v + xi_mid * h[0].v, c[1].v + xi_mid * h[1].v};
    const double n_mid[2] = {nm[0].v + xi_mid * nd[0].v, nm[1].v + xi_mid * nd[1].v};
    const double d[2] = {x_mid[0] - cm[0].v, x_mid[1] - cm[1].v};
    const double den = hm[0].v * n_mid[1] - hm[1].v * n_mid[0];
    if (!(fabs(den) > 0.0) || !(fabs((d[0] * n_mid[1] - d[1] * n_mid[0]) / den) <= 1.5)) return 0;
  }
  double eta[MORTAR_MAX_RULE], w[MORTAR_MAX_RULE];
  mortar_gauss_legendre(n_gauss, eta, w);
  const fwd jac = fwd_scale(0.5, fwd_mul(fwd_sub(hi, lo), fwd_norm(2, h)));
  for (int g = 0; g < n_gauss; ++g) {
    const fwd xi1 = fwd_lin(0.5 * (1.0 - eta[g]), lo, 0.5 * (1.0 + eta[g]), hi);
    fwd x1[2], n[2], d[2];
    for (int i = 0; i < 2; ++i) {
      x1[i] = fwd_add(c[i], fwd_mul(xi1, h[i]));
      n[i] = fwd_add(nm[i], fwd_mul(xi1, nd[i]));
      d[i] = fwd_sub(x1[i], cm[i]);
    }
    const fwd xi2 = fwd_div(fwd_cross2(d, n), fwd_cross2(hm, n));
    fwd gapv[2];
    for (int i = 0; i < 2; ++i) gapv[i] = fwd_sub(fwd_add(cm[i], fwd_mul(xi2, hm[i])), x1[i]);
    const fwd g_n = fwd_div(fwd_dot(2, gapv, n), fwd_norm(2, n));
    const fwd xi1v[2] = {xi1, fwd_const(0.0)}, xi2v[2] = {xi2, fwd_const(0.0)};
    mortar_add_point(p, A, basis, xi1v, xi2v, fwd_scale(w[g], jac), g_n, I);
  }
  I->n_cells += 1;
  return 1;
}

/* Slave point x1(xi), unnormalised normal n(xi) and surface Jacobian at fixed parameters. */
static void slave_point(const mortar_pair *p, const fwd *xi, fwd x1[3], fwd n[3], fwd *jac) {
  fwd N[MORTAR_MAX_NEN], a[2][3];
  fwd xs[MORTAR_MAX_NEN][3];
  memcpy(xs, p->xs, sizeof(fwd) * 3 * (size_t)p->nen_s);
  mortar_shape(p->slave, xi, N, NULL);
  mortar_face_point(p->slave, xs, xi, x1, a);
  mortar_slave_normal(p, N, n);
  if (p->slave->pdim == 1) {
    *jac = fwd_norm(3, a[0]);
  } else {
    fwd c[3];
    fwd_cross3(a[0], a[1], c);
    *jac = fwd_norm(3, c);
  }
}

/* Projection of x1 (normal n1, unnormalised) onto the pair's master face with variant A or M: xi2 and g_n (fwd).
 * xi0 is the start and returns the converged parameters. */
static int project_fwd(const mortar_pair *p, mortar_normal normal, const fwd *x1, const fwd *n1, double xi0[2],
                       fwd xi2[2], fwd *g) {
  fwd xm[MORTAR_MAX_NEN][3];
  memcpy(xm, p->xm, sizeof(fwd) * 3 * (size_t)p->nen_m);
  const int dim = p->dim;
  if (normal == MORTAR_NORMAL_A) {
    fwd t;
    if (mortar_along_fwd(p->master, xm, dim, x1, n1, xi0, xi2, &t) != 0) return -1;
    *g = fwd_mul(t, fwd_norm(dim, n1));
    return 0;
  }
  if (mortar_closest_fwd(p->master, xm, dim, x1, xi0, xi2) != 0) return -1;
  fwd x2[3], a[2][3], nbar[3], diff[3];
  mortar_face_point(p->master, xm, xi2, x2, a);
  mortar_face_normal(dim, p->master->pdim, a, nbar);
  for (int i = 0; i < 3; ++i) diff[i] = fwd_sub(x1[i], x2[i]);
  *g = fwd_dot(dim, diff, nbar);
  return 0;
}

/* ---- 2D segments on curved (LINE3) faces ------------------------------------------------------------------------
 * The LINE2 construction with the closed forms replaced by local Newton iterations: x1(xi) and n(xi) = sum N_k n_k are
 * quadratic, the master's end nodes are placed on the slave line by f(xi) = (x1(xi) - x_b) x n(xi) = 0 (a quartic),
 * and every Gauss point is projected onto the quadratic master along n(xi) (project_fwd, variant A). The Jacobian of
 * the slave face varies along the segment and is evaluated at each point. */

/* x1, its tangent, n and dn/dxi of the slave face at a plain parameter (values). */
static void slave_line_values(const mortar_pair *p, double xi, double x[2], double a[2], double n[2], double dn[2]) {
  double N[MORTAR_MAX_NEN], dN[MORTAR_MAX_NEN];
  const double xq[2] = {xi, 0.0};
  p->slave->shape(p->slave->type, xq, N, dN);
  for (int i = 0; i < 2; ++i) {
    x[i] = a[i] = n[i] = dn[i] = 0.0;
    for (int k = 0; k < p->nen_s; ++k) {
      x[i] += N[k] * p->xs[k][i].v;
      a[i] += dN[k] * p->xs[k][i].v;
      n[i] += N[k] * p->ns[k][i].v;
      dn[i] += dN[k] * p->ns[k][i].v;
    }
  }
}

/* The slave parameter whose interpolated normal passes through xb, with its derivatives. Returns 0; -1 when Newton
 * fails (no such point near the face), with *guess the start: the projection onto the chord of the face's ends. */
static int point_on_slave_line(const mortar_pair *p, const fwd *xb, fwd *out, double *guess) {
  double h[2], c[2];
  for (int i = 0; i < 2; ++i) {
    c[i] = 0.5 * (p->xs[0][i].v + p->xs[1][i].v);
    h[i] = 0.5 * (p->xs[1][i].v - p->xs[0][i].v);
  }
  double xi = ((xb[0].v - c[0]) * h[0] + (xb[1].v - c[1]) * h[1]) / (h[0] * h[0] + h[1] * h[1]);
  *guess = xi;
  double previous = INFINITY, df = 0.0;
  int done = 0;
  for (int it = 0; it < 40 && !done; ++it) {
    double x[2], a[2], n[2], dn[2];
    slave_line_values(p, xi, x, a, n, dn);
    const double d[2] = {x[0] - xb[0].v, x[1] - xb[1].v};
    const double f = d[0] * n[1] - d[1] * n[0];
    df = a[0] * n[1] - a[1] * n[0] + d[0] * dn[1] - d[1] * dn[0];
    if (!(fabs(df) > 0.0)) return -1;
    const double step = f / df;
    xi -= step;
    if (!isfinite(xi) || fabs(xi) > 10.0) return -1;
    done = mortar_newton_done(fabs(step), previous, fabs(xi));
    previous = fabs(step);
  }
  if (!done) return -1;
  const fwd xc[2] = {fwd_const(xi), fwd_const(0.0)};
  fwd N[MORTAR_MAX_NEN], x1[3], n1[3], d[2];
  fwd xs[MORTAR_MAX_NEN][3];
  memcpy(xs, p->xs, sizeof(fwd) * 3 * (size_t)p->nen_s);
  mortar_shape(p->slave, xc, N, NULL);
  mortar_face_point(p->slave, xs, xc, x1, NULL);
  mortar_slave_normal(p, N, n1);
  for (int i = 0; i < 2; ++i) d[i] = fwd_sub(x1[i], xb[i]);
  /* df at the root: the last iterate's, one step of round-off away */
  *out = fwd_implicit(xi, fwd_cross2(d, n1), df);
  return 0;
}

static int segments_2d_curved(const mortar_pair *p, const mortar_basis_coeffs *A, mortar_basis basis, int n_gauss,
                              mortar_integrals *I) {
  /* only faces that face each other: the master's outward normal a_m x e_z at its middle against the slave normal */
  double x0[2], a0[2], n0[2], dn0[2], xmid[3], am[2][3], aam[2][2][3];
  slave_line_values(p, 0.0, x0, a0, n0, dn0);
  fwd xm[MORTAR_MAX_NEN][3];
  memcpy(xm, p->xm, sizeof(fwd) * 3 * (size_t)p->nen_m);
  const double zero[2] = {0.0, 0.0};
  mortar_face_values(p->master, xm, zero, xmid, am, aam);
  if (am[0][1] * n0[0] - am[0][0] * n0[1] >= 0.0) return 0;
  /* the master's end nodes (local 0 and 1 on LINE2 and LINE3) on the slave line */
  fwd ends[2];
  for (int b = 0; b < 2; ++b) {
    double guess;
    if (point_on_slave_line(p, p->xm[b], &ends[b], &guess) != 0) {
      /* far beyond the face: the chord says on which side; near it, no segment can be built */
      if (fabs(guess) <= 1.5) return 0;
      ends[b] = fwd_const(guess < 0.0 ? -1.0 : 1.0);
    }
  }
  fwd lo = ends[0].v < ends[1].v ? ends[0] : ends[1];
  fwd hi = ends[0].v < ends[1].v ? ends[1] : ends[0];
  if (lo.v < -1.0) lo = fwd_const(-1.0);
  if (hi.v > 1.0) hi = fwd_const(1.0);
  if (!(hi.v - lo.v > 1e-12)) return 0;
  /* a genuine segment's middle projects onto the master face (mortar_segments_2d) */
  {
    double x[2], a[2], n[2], dn[2], eta[2] = {0.0, 0.0}, t = 0.0;
    slave_line_values(p, 0.5 * (lo.v + hi.v), x, a, n, dn);
    const fwd xf[3] = {fwd_const(x[0]), fwd_const(x[1]), fwd_const(0.0)};
    const fwd nf[3] = {fwd_const(n[0]), fwd_const(n[1]), fwd_const(0.0)};
    if (mortar_along(p->master, xm, 2, xf, nf, eta, &t) != 0 || !(fabs(eta[0]) <= 1.5)) return 0;
  }
  double eta[MORTAR_MAX_RULE], w[MORTAR_MAX_RULE];
  mortar_gauss_legendre(n_gauss, eta, w);
  const fwd half = fwd_scale(0.5, fwd_sub(hi, lo));
  double start[2] = {0.0, 0.0};
  for (int g = 0; g < n_gauss; ++g) {
    const fwd xi1[2] = {fwd_lin(0.5 * (1.0 - eta[g]), lo, 0.5 * (1.0 + eta[g]), hi), fwd_const(0.0)};
    fwd x1[3], n1[3], jac, xi2[2], g_n;
    slave_point(p, xi1, x1, n1, &jac);
    if (project_fwd(p, MORTAR_NORMAL_A, x1, n1, start, xi2, &g_n) != 0) continue;
    mortar_add_point(p, A, basis, xi1, xi2, fwd_scale(w[g], fwd_mul(half, jac)), g_n, I);
  }
  I->n_cells += 1;
  return 1;
}

void mortar_points(const mortar_pair *p, const mortar_basis_coeffs *A, mortar_basis basis, mortar_normal normal,
                   int n, const double *xi, const double *w, mortar_integrals *I) {
  const int pd = p->slave->pdim;
  for (int q = 0; q < n; ++q) {
    const fwd xi1[2] = {fwd_const(xi[q * pd]), fwd_const(pd > 1 ? xi[q * pd + 1] : 0.0)};
    fwd x1[3], n1[3], jac, xi2[2], g;
    slave_point(p, xi1, x1, n1, &jac);
    double start[2] = {0.0, 0.0};
    if (p->master->type == SK_TRI3 || p->master->type == SK_TRI6) start[0] = start[1] = 1.0 / 3.0;
    if (project_fwd(p, normal, x1, n1, start, xi2, &g) != 0) continue;
    mortar_add_point(p, A, basis, xi1, xi2, fwd_scale(w[q], jac), g, I);
    I->n_cells += 1;
  }
}

void mortar_obstacle_points(const mortar_pair *p, const mortar_basis_coeffs *A, mortar_basis basis, int n,
                            const double *xi, const double *w, mortar_obstacle_fn obstacle, void *ctx,
                            mortar_integrals *I) {
  const int pd = p->slave->pdim, dim = p->dim;
  for (int q = 0; q < n; ++q) {
    const fwd xi1[2] = {fwd_const(xi[q * pd]), fwd_const(pd > 1 ? xi[q * pd + 1] : 0.0)};
    fwd x1[3], n1[3], jac;
    slave_point(p, xi1, x1, n1, &jac);
    double xv[3], g0, nrm[3] = {0, 0, 0};
    mortar_values(dim, x1, xv);
    if (obstacle(ctx, xv, &g0, nrm) != 0) continue;
    /* the distance function's gradient is the unit normal at the closest point */
    const fwd g = fwd_chain(g0, dim, nrm, x1);
    mortar_add_point(p, A, basis, xi1, NULL, fwd_scale(w[q], jac), g, I);
    I->n_cells += 1;
  }
}

int mortar_project_point(const mortar_pair *p, mortar_normal normal, const double *xi, double tol,
                         mortar_point_projection *out) {
  const int pd = p->slave->pdim;
  mortar_pair v = *p; /* values only */
  v.n_local = 0;
  for (int a = 0; a < p->nen_s; ++a)
    for (int i = 0; i < 3; ++i) {
      v.xs[a][i] = fwd_const(p->xs[a][i].v);
      v.ns[a][i] = fwd_const(p->ns[a][i].v);
    }
  for (int b = 0; b < p->nen_m; ++b)
    for (int i = 0; i < 3; ++i) v.xm[b][i] = fwd_const(p->xm[b][i].v);
  const fwd xi1[2] = {fwd_const(xi[0]), fwd_const(pd > 1 ? xi[1] : 0.0)};
  fwd x1[3], n1[3], jac, xi2[2], g;
  slave_point(&v, xi1, x1, n1, &jac);
  double start[2] = {0.0, 0.0};
  if (p->master->type == SK_TRI3 || p->master->type == SK_TRI6) start[0] = start[1] = 1.0 / 3.0;
  if (project_fwd(&v, normal, x1, n1, start, xi2, &g) != 0) return -1;
  out->xi[0] = xi2[0].v;
  out->xi[1] = xi2[1].v;
  out->gap = g.v;
  const double s = out->xi[0], t = out->xi[1];
  if (p->master->type == SK_TRI3 || p->master->type == SK_TRI6)
    out->inside = s >= -tol && t >= -tol && s + t <= 1.0 + tol;
  else if (p->master->type == SK_QUAD4 || p->master->type == SK_QUAD8 || p->master->type == SK_QUAD9)
    out->inside = fabs(s) <= 1.0 + tol && fabs(t) <= 1.0 + tol;
  else
    out->inside = fabs(s) <= 1.0 + tol;
  return 0;
}

/* ---- what the pair contributes --------------------------------------------------------------------------------- */
void mortar_pair_forces(const mortar_pair *p, const mortar_integrals *I, mortar_basis basis, const double z[][3],
                        fwd f[][3]) {
  const int ns = p->nen_s, nm = p->nen_m;
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < ns; ++k) {
      if (basis == MORTAR_DUAL) {
        f[k][i] = fwd_scale(z[k][i], I->D[k][k]);
      } else {
        f[k][i] = fwd_scale(z[0][i], I->D[0][k]);
        for (int j = 1; j < ns; ++j) f[k][i] = fwd_lin(1.0, f[k][i], z[j][i], I->D[j][k]);
      }
    }
    for (int l = 0; l < nm; ++l) {
      f[ns + l][i] = fwd_scale(-z[0][i], I->M[0][l]);
      for (int j = 1; j < ns; ++j) f[ns + l][i] = fwd_lin(1.0, f[ns + l][i], -z[j][i], I->M[j][l]);
    }
  }
}

void mortar_pair_weighted_positions(const mortar_pair *p, const mortar_integrals *I, mortar_basis basis,
                                    fwd W[][3]) {
  const int ns = p->nen_s, nm = p->nen_m;
  for (int j = 0; j < ns; ++j)
    for (int i = 0; i < 3; ++i) {
      fwd w = fwd_const(0.0);
      for (int k = 0; k < ns; ++k) {
        if (basis == MORTAR_DUAL && k != j) continue;
        w = fwd_add(w, fwd_mul(I->D[j][k], p->xs[k][i]));
      }
      for (int l = 0; l < nm; ++l) w = fwd_sub(w, fwd_mul(I->M[j][l], p->xm[l][i]));
      W[j][i] = w;
    }
}
