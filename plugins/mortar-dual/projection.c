/* mortar-dual kernel: point projections onto a face — along a direction, closest point — with their implicit
 * derivatives, and the faces' normals (see kernel_internal.h). */
#include <math.h>
#include <string.h>

#include "kernel.h"
#include "kernel_internal.h"

/* ---- projections ----------------------------------------------------------------------------------------------- */
void mortar_values(int dim, const fwd *x, double *v) {
  for (int i = 0; i < 3; ++i) v[i] = i < dim ? x[i].v : 0.0;
}

void mortar_face_values(const mortar_face_type *ft, fwd x[][3], const double *xi, double pos[3], double a[2][3],
                        double aa[2][2][3]) {
  double N[MORTAR_MAX_NEN], dN[2 * MORTAR_MAX_NEN], ddN[4 * MORTAR_MAX_NEN];
  const double xq[2] = {xi[0], ft->pdim > 1 ? xi[1] : 0.0};
  const int pd = ft->pdim;
  ft->shape(ft->type, xq, N, dN);
  ft->shape_hessian(ft->type, xq, ddN);
  memset(pos, 0, sizeof(double) * 3);
  memset(a, 0, sizeof(double) * 6);
  memset(aa, 0, sizeof(double) * 12);
  for (int b = 0; b < ft->nen; ++b)
    for (int i = 0; i < 3; ++i) {
      pos[i] += N[b] * x[b][i].v;
      for (int k = 0; k < pd; ++k) {
        a[k][i] += dN[b * pd + k] * x[b][i].v;
        for (int l = 0; l < pd; ++l) aa[k][l][i] += ddN[(b * pd + k) * pd + l] * x[b][i].v;
      }
    }
}

int mortar_along(const mortar_face_type *mt, fwd xm[][3], int dim, const fwd *x1, const fwd *d, double xi[2],
                 double *t) {
  const int pd = mt->pdim, m = pd + 1;
  double x1v[3], dv[3];
  mortar_values(dim, x1, x1v);
  mortar_values(dim, d, dv);
  double previous = INFINITY;
  for (int it = 0; it < 40; ++it) {
    double pos[3], a[2][3], aa[2][2][3], J[9], r[3];
    mortar_face_values(mt, xm, xi, pos, a, aa);
    for (int i = 0; i < dim; ++i) {
      r[i] = -(pos[i] - x1v[i] - *t * dv[i]);
      for (int k = 0; k < pd; ++k) J[i * m + k] = a[k][i];
      J[i * m + pd] = -dv[i];
    }
    if (mortar_solve_small(m, J, r, 1) != 0) return -1;
    for (int k = 0; k < pd; ++k) xi[k] += r[k];
    *t += r[pd];
    if (!isfinite(xi[0]) || fabs(xi[0]) > 1e3 || (pd > 1 && fabs(xi[1]) > 1e3)) return -1;
    double step = 0.0, size = fabs(*t);
    for (int k = 0; k < m; ++k) step = fmax(step, fabs(r[k]));
    for (int k = 0; k < pd; ++k) size = fmax(size, fabs(xi[k]));
    if (mortar_newton_done(step, previous, size)) return 0;
    previous = step;
  }
  return -1;
}

int mortar_along_fwd(const mortar_face_type *mt, fwd xm[][3], int dim, const fwd *x1, const fwd *d, double xi0[2],
                     fwd xi[2], fwd *t) {
  double xv[2] = {xi0[0], xi0[1]}, tv = 0.0;
  if (mortar_along(mt, xm, dim, x1, d, xv, &tv) != 0) return -1;
  const int pd = mt->pdim, m = pd + 1;
  fwd xc[2] = {fwd_const(xv[0]), fwd_const(xv[1])}, pos[3], a[2][3], r[3];
  mortar_face_point(mt, xm, xc, pos, a);
  double J[9], y[3] = {xv[0], pd > 1 ? xv[1] : tv, tv};
  for (int i = 0; i < dim; ++i) {
    r[i] = fwd_sub(fwd_sub(pos[i], x1[i]), fwd_scale(tv, d[i]));
    for (int k = 0; k < pd; ++k) J[i * m + k] = a[k][i].v;
    J[i * m + pd] = -d[i].v;
  }
  fwd out[3];
  if (mortar_implicit(m, J, r, y, out) != 0) return -1;
  xi[0] = out[0];
  xi[1] = pd > 1 ? out[1] : fwd_const(0.0);
  *t = out[pd];
  xi0[0] = xv[0];
  xi0[1] = xv[1];
  return 0;
}

/* Closest point of x1 on the master face: F_alpha = (x2(xi) - x1) . a_alpha = 0. */
static int closest(const mortar_face_type *mt, fwd xm[][3], int dim, const fwd *x1, double xi[2]) {
  const int pd = mt->pdim;
  double x1v[3];
  mortar_values(dim, x1, x1v);
  double previous = INFINITY;
  for (int it = 0; it < 40; ++it) {
    double pos[3], a[2][3], aa[2][2][3], J[4], F[2];
    mortar_face_values(mt, xm, xi, pos, a, aa);
    for (int k = 0; k < pd; ++k) {
      F[k] = 0.0;
      for (int i = 0; i < 3; ++i) F[k] -= (pos[i] - x1v[i]) * a[k][i];
      for (int l = 0; l < pd; ++l) {
        double v = 0.0;
        for (int i = 0; i < 3; ++i) v += a[k][i] * a[l][i] + (pos[i] - x1v[i]) * aa[k][l][i];
        J[k * pd + l] = v;
      }
    }
    if (mortar_solve_small(pd, J, F, 1) != 0) return -1;
    for (int k = 0; k < pd; ++k) xi[k] += F[k];
    if (!isfinite(xi[0]) || fabs(xi[0]) > 1e3 || (pd > 1 && fabs(xi[1]) > 1e3)) return -1;
    const double step = pd > 1 ? fmax(fabs(F[0]), fabs(F[1])) : fabs(F[0]);
    const double size = pd > 1 ? fmax(fabs(xi[0]), fabs(xi[1])) : fabs(xi[0]);
    if (mortar_newton_done(step, previous, size)) return 0;
    previous = step;
  }
  return -1;
}

int mortar_closest_fwd(const mortar_face_type *mt, fwd xm[][3], int dim, const fwd *x1, double xi0[2], fwd xi[2]) {
  double xv[2] = {xi0[0], xi0[1]};
  if (closest(mt, xm, dim, x1, xv) != 0) return -1;
  const int pd = mt->pdim;
  double pos[3], a[2][3], aa[2][2][3], J[4], x1v[3];
  mortar_face_values(mt, xm, xv, pos, a, aa);
  mortar_values(dim, x1, x1v);
  for (int k = 0; k < pd; ++k)
    for (int l = 0; l < pd; ++l) {
      double v = 0.0;
      for (int i = 0; i < 3; ++i) v += a[k][i] * a[l][i] + (pos[i] - x1v[i]) * aa[k][l][i];
      J[k * pd + l] = v;
    }
  fwd xc[2] = {fwd_const(xv[0]), fwd_const(xv[1])}, posf[3], af[2][3], F[2], diff[3];
  mortar_face_point(mt, xm, xc, posf, af);
  for (int i = 0; i < 3; ++i) diff[i] = fwd_sub(posf[i], x1[i]);
  for (int k = 0; k < pd; ++k) F[k] = fwd_dot(dim, diff, af[k]);
  fwd out[2];
  if (mortar_implicit(pd, J, F, xv, out) != 0) return -1;
  xi[0] = out[0];
  xi[1] = pd > 1 ? out[1] : fwd_const(0.0);
  xi0[0] = xv[0];
  xi0[1] = xv[1];
  return 0;
}

/* Outward unit normal of a face from its tangents (2D: a_1 x e_z). */
void mortar_face_normal(int dim, int pdim, fwd a[2][3], fwd n[3]) {
  fwd c[3];
  if (pdim == 1) {
    c[0] = a[0][1];
    c[1] = fwd_neg(a[0][0]);
    c[2] = fwd_const(0.0);
  } else {
    fwd_cross3(a[0], a[1], c);
  }
  const fwd len = fwd_norm(dim, c);
  for (int i = 0; i < 3; ++i) n[i] = i < dim ? fwd_div(c[i], len) : fwd_const(0.0);
}

/* n(xi) = sum_k N_k n_k, not normalised. */
void mortar_slave_normal(const mortar_pair *p, const fwd *N, fwd n[3]) {
  for (int i = 0; i < 3; ++i) {
    fwd_set_mul(&n[i], &N[0], &p->ns[0][i]);
    for (int k = 1; k < p->nen_s; ++k) fwd_acc_mul(&n[i], &N[k], &p->ns[k][i]);
  }
}
