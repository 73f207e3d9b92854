/* mortar-dual — forward-mode first derivatives ("directional derivatives") for the kernel.
 *
 * A `fwd` carries a value and its derivatives with respect to the local unknowns of one evaluation (e.g. the
 * coordinates of a slave/master face pair and the slave nodal normals: at most FWD_MAX). Every step of the mortar
 * algorithm — projections, segment bounds, clipping, the dual basis, Gauss points — is written once in fwd
 * arithmetic, so that D, M, the weighted gap and slip carry their exact directional derivatives (the linearisation
 * of Popp et al. 2009/2010, evaluated through the chain rule instead of written out term by term; MOOSE's mortar
 * constraints use the same idea with their AD types).
 *
 * `n` is the number of derivative slots in use: constants have n = 0 and cost a scalar operation; a value-only
 * evaluation (residual, active-set update) seeds nothing and runs at scalar cost. Slots k >= n are never read. */
#ifndef MORTAR_FWD_H
#define MORTAR_FWD_H

#include <math.h>

/* Derivative slots: a QUAD9 pair has (2 * 9 + 9) * 3 = 81, a pair of first-order faces at most (2 * 4 + 4) * 3 = 36.
 * Every fwd is FWD_MAX large, and first-order runs paid for 81 (docs/plugins/mortar-dual.md section 9.3): the kernel
 * and the evaluation are compiled a second time with MORTAR_NARROW (narrow.c), and a contact pair whose faces have at
 * most 4 nodes runs that copy. */
enum { FWD_MAX_WIDE = 81, FWD_MAX_NARROW = 36 };
#ifdef MORTAR_NARROW
enum { FWD_MAX = FWD_MAX_NARROW };
#else
enum { FWD_MAX = FWD_MAX_WIDE };
#endif

typedef struct {
  double v;
  int n;
  double d[FWD_MAX];
} fwd;

static inline fwd fwd_const(double v) {
  fwd r;
  r.v = v;
  r.n = 0;
  return r;
}

/* The independent variable number `index` of `n` (derivative 1 in that slot). */
static inline fwd fwd_var(double v, int index, int n) {
  fwd r;
  r.v = v;
  r.n = n;
  for (int k = 0; k < n; ++k) r.d[k] = 0.0;
  r.d[index] = 1.0;
  return r;
}

static inline int fwd_imax(int a, int b) { return a > b ? a : b; }
static inline int fwd_imin(int a, int b) { return a < b ? a : b; }

/* alpha a + beta b with derivatives (the common kernel of +, -, scaling). */
static inline fwd fwd_lin(double alpha, fwd a, double beta, fwd b) {
  fwd r;
  r.v = alpha * a.v + beta * b.v;
  r.n = fwd_imax(a.n, b.n);
  const int m = fwd_imin(a.n, b.n);
  for (int k = 0; k < m; ++k) r.d[k] = alpha * a.d[k] + beta * b.d[k];
  for (int k = m; k < a.n; ++k) r.d[k] = alpha * a.d[k];
  for (int k = m; k < b.n; ++k) r.d[k] = beta * b.d[k];
  return r;
}

static inline fwd fwd_add(fwd a, fwd b) { return fwd_lin(1.0, a, 1.0, b); }
static inline fwd fwd_sub(fwd a, fwd b) { return fwd_lin(1.0, a, -1.0, b); }

static inline fwd fwd_scale(double s, fwd a) {
  fwd r;
  r.v = s * a.v;
  r.n = a.n;
  for (int k = 0; k < a.n; ++k) r.d[k] = s * a.d[k];
  return r;
}

static inline fwd fwd_neg(fwd a) { return fwd_scale(-1.0, a); }

static inline fwd fwd_addc(fwd a, double c) {
  a.v += c;
  return a;
}

static inline fwd fwd_mul(fwd a, fwd b) {
  fwd r;
  r.v = a.v * b.v;
  r.n = fwd_imax(a.n, b.n);
  const int m = fwd_imin(a.n, b.n);
  for (int k = 0; k < m; ++k) r.d[k] = a.d[k] * b.v + a.v * b.d[k];
  for (int k = m; k < a.n; ++k) r.d[k] = a.d[k] * b.v;
  for (int k = m; k < b.n; ++k) r.d[k] = a.v * b.d[k];
  return r;
}

/* a += s * b, in place (accumulation in integration loops). */
static inline void fwd_axpy(fwd *a, fwd s, fwd b) { *a = fwd_add(*a, fwd_mul(s, b)); }

static inline fwd fwd_div(fwd a, fwd b) {
  fwd r;
  const double inv = 1.0 / b.v, q = a.v * inv;
  r.v = q;
  r.n = fwd_imax(a.n, b.n);
  const int m = fwd_imin(a.n, b.n);
  for (int k = 0; k < m; ++k) r.d[k] = (a.d[k] - q * b.d[k]) * inv;
  for (int k = m; k < a.n; ++k) r.d[k] = a.d[k] * inv;
  for (int k = m; k < b.n; ++k) r.d[k] = -q * b.d[k] * inv;
  return r;
}

static inline fwd fwd_sqrt(fwd a) {
  fwd r;
  r.v = sqrt(a.v);
  r.n = a.n;
  const double h = r.v > 0.0 ? 0.5 / r.v : 0.0;
  for (int k = 0; k < a.n; ++k) r.d[k] = h * a.d[k];
  return r;
}

/* A root of f(xi, u) = 0 found by the caller (value xi); f_u = f evaluated with the derivative seeds at the
 * constant xi, f_xi its partial derivative in xi. Implicit function theorem: d xi = -d f_u / f_xi. */
static inline fwd fwd_implicit(double xi, fwd f_u, double f_xi) {
  fwd r = fwd_scale(-1.0 / f_xi, f_u);
  r.v = xi;
  return r;
}

/* r = a function value v whose derivative is sum_i g[i] d x[i] (the chain rule through m arguments). */
static inline void fwd_set_chain(fwd *r, double v, int m, const double *g, const fwd *x) {
  r->v = v;
  r->n = 0;
  for (int i = 0; i < m; ++i) r->n = fwd_imax(r->n, x[i].n);
  for (int k = 0; k < r->n; ++k) r->d[k] = 0.0;
  for (int i = 0; i < m; ++i)
    for (int k = 0; k < x[i].n; ++k) r->d[k] += g[i] * x[i].d[k];
}

static inline fwd fwd_chain(double v, int m, const double *g, const fwd *x) {
  fwd r;
  fwd_set_chain(&r, v, m, g, x);
  return r;
}

/* ---- in place, through pointers: the hot loops (shape functions, face points, integrands) avoid copying whole
 * structs, which dominates when few slots are in use ------------------------------------------------------------ */
static inline void fwd_set_const(fwd *r, double v) {
  r->v = v;
  r->n = 0;
}

/* r += s * a */
static inline void fwd_acc_scaled(fwd *r, double s, const fwd *a) {
  r->v += s * a->v;
  const int m = fwd_imin(r->n, a->n);
  for (int k = 0; k < m; ++k) r->d[k] += s * a->d[k];
  for (int k = m; k < a->n; ++k) r->d[k] = s * a->d[k];
  if (a->n > r->n) r->n = a->n;
}

/* r += a * b */
static inline void fwd_acc_mul(fwd *r, const fwd *a, const fwd *b) {
  r->v += a->v * b->v;
  const int na = a->n, nb = b->n, nm = fwd_imax(na, nb);
  for (int k = r->n; k < nm; ++k) r->d[k] = 0.0;
  if (nm > r->n) r->n = nm;
  for (int k = 0; k < na; ++k) r->d[k] += a->d[k] * b->v;
  for (int k = 0; k < nb; ++k) r->d[k] += a->v * b->d[k];
}

/* r = a * b */
static inline void fwd_set_mul(fwd *r, const fwd *a, const fwd *b) {
  fwd_set_const(r, 0.0);
  fwd_acc_mul(r, a, b);
}

/* ---- small vectors (dim 2 or 3 entries; the third is unused in 2D) --------------------------------------------- */
static inline fwd fwd_dot(int dim, const fwd *a, const fwd *b) {
  fwd s;
  fwd_set_mul(&s, &a[0], &b[0]);
  for (int i = 1; i < dim; ++i) fwd_acc_mul(&s, &a[i], &b[i]);
  return s;
}

static inline void fwd_cross3(const fwd *a, const fwd *b, fwd *c) {
  c[0] = fwd_sub(fwd_mul(a[1], b[2]), fwd_mul(a[2], b[1]));
  c[1] = fwd_sub(fwd_mul(a[2], b[0]), fwd_mul(a[0], b[2]));
  c[2] = fwd_sub(fwd_mul(a[0], b[1]), fwd_mul(a[1], b[0]));
}

/* 2D cross product a x b = a_x b_y - a_y b_x. */
static inline fwd fwd_cross2(const fwd *a, const fwd *b) {
  return fwd_sub(fwd_mul(a[0], b[1]), fwd_mul(a[1], b[0]));
}

static inline fwd fwd_norm(int dim, const fwd *a) { return fwd_sqrt(fwd_dot(dim, a, a)); }

#endif
