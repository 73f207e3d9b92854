/* mortar-dual kernel: face shape functions in fwd arithmetic, the multiplier bases, nodal normals and tangents,
 * quadrature rules (see kernel.h). */
#include <math.h>
#include <string.h>

#include "kernel.h"
#include "stickslip/modified_basis.h"

int mortar_face_type_init(mortar_face_type *ft, sk_elem_type type, mortar_shape_fn shape,
                          mortar_shape_hessian_fn shape_hessian) {
  switch (type) {
    case SK_LINE2: ft->nen = 2; ft->pdim = 1; break;
    case SK_LINE3: ft->nen = 3; ft->pdim = 1; break;
    case SK_TRI3: ft->nen = 3; ft->pdim = 2; break;
    case SK_TRI6: ft->nen = 6; ft->pdim = 2; break;
    case SK_QUAD4: ft->nen = 4; ft->pdim = 2; break;
    case SK_QUAD8: ft->nen = 8; ft->pdim = 2; break;
    case SK_QUAD9: ft->nen = 9; ft->pdim = 2; break;
    default: return -1;
  }
  ft->type = type;
  ft->shape = shape;
  ft->shape_hessian = shape_hessian;
  ft->alpha = SK_MODIFIED_BASIS_ALPHA;
  return 0;
}

void mortar_pair_set(mortar_pair *p, int dim, const mortar_face_type *slave, const mortar_face_type *master,
                     const double *xs, const double *xm, const double *ns, int derivatives) {
  p->dim = dim;
  p->slave = slave;
  p->master = master;
  p->nen_s = slave->nen;
  p->nen_m = master ? master->nen : 0;
  p->n_local = derivatives ? (2 * p->nen_s + p->nen_m) * dim : 0;
  for (int a = 0; a < p->nen_s; ++a)
    for (int i = 0; i < 3; ++i) {
      const int seeded = p->n_local > 0 && i < dim;
      p->xs[a][i] = seeded ? fwd_var(xs[3 * a + i], mortar_slot_xs(p, a, i), p->n_local) : fwd_const(xs[3 * a + i]);
      p->ns[a][i] = seeded ? fwd_var(ns[3 * a + i], mortar_slot_ns(p, a, i), p->n_local) : fwd_const(ns[3 * a + i]);
    }
  for (int b = 0; b < p->nen_m; ++b)
    for (int i = 0; i < 3; ++i) {
      const int seeded = p->n_local > 0 && i < dim;
      p->xm[b][i] = seeded ? fwd_var(xm[3 * b + i], mortar_slot_xm(p, b, i), p->n_local) : fwd_const(xm[3 * b + i]);
    }
}

/* ---- shape functions ------------------------------------------------------------------------------------------- */
void mortar_shape(const mortar_face_type *ft, const fwd *xi, fwd *N, fwd dN[][2]) {
  const int pd = ft->pdim;
  double x[2] = {xi[0].v, pd > 1 ? xi[1].v : 0.0};
  double Nv[MORTAR_MAX_NEN], dNv[2 * MORTAR_MAX_NEN], ddN[4 * MORTAR_MAX_NEN];
  ft->shape(ft->type, x, Nv, dNv);
  if (dN) ft->shape_hessian(ft->type, x, ddN);
  for (int a = 0; a < ft->nen; ++a) {
    fwd_set_chain(&N[a], Nv[a], pd, dNv + a * pd, xi);
    if (dN)
      for (int k = 0; k < pd; ++k) fwd_set_chain(&dN[a][k], dNv[a * pd + k], pd, ddN + (a * pd + k) * pd, xi);
  }
}

void mortar_face_point(const mortar_face_type *ft, fwd x[][3], const fwd *xi, fwd *pos, fwd a[2][3]) {
  fwd N[MORTAR_MAX_NEN], dN[MORTAR_MAX_NEN][2];
  mortar_shape(ft, xi, N, a ? dN : NULL);
  for (int i = 0; i < 3; ++i) {
    if (pos) {
      fwd_set_mul(&pos[i], &N[0], &x[0][i]);
      for (int b = 1; b < ft->nen; ++b) fwd_acc_mul(&pos[i], &N[b], &x[b][i]);
    }
    if (a)
      for (int k = 0; k < ft->pdim; ++k) {
        fwd_set_mul(&a[k][i], &dN[0][k], &x[0][i]);
        for (int b = 1; b < ft->nen; ++b) fwd_acc_mul(&a[k][i], &dN[b][k], &x[b][i]);
      }
  }
}

/* Jacobian of the slave face map at xi: |a_1| (lines) or |a_1 x a_2| (surfaces). */
static fwd face_jacobian(const mortar_face_type *ft, fwd a[2][3]) {
  if (ft->pdim == 1) return fwd_norm(3, a[0]);
  fwd c[3];
  fwd_cross3(a[0], a[1], c);
  return fwd_norm(3, c);
}

/* ---- multiplier bases ------------------------------------------------------------------------------------------ */
void mortar_basis_coefficients(const mortar_pair *p, mortar_basis basis, mortar_basis_coeffs *A) {
  const mortar_face_type *ft = p->slave;
  const int nen = ft->nen;
  A->nen = nen;
  for (int j = 0; j < nen; ++j)
    for (int k = 0; k < nen; ++k) A->coeff[j][k] = fwd_const(j == k ? 1.0 : 0.0);
  if (basis == MORTAR_STANDARD) return;
  /* D_e and M_e over the whole face with the rule of D (mortar_face_exact_order: exact on affine faces, to round-off
   * on curved LINE3 faces) */
  double xi[MORTAR_MAX_RULE * MORTAR_MAX_RULE * 2], w[MORTAR_MAX_RULE * MORTAR_MAX_RULE];
  const int nq = mortar_face_rule(ft->type, mortar_face_exact_order(ft->type), xi, w);
  fwd De[MORTAR_MAX_NEN], Me[MORTAR_MAX_NEN][MORTAR_MAX_NEN];
  for (int j = 0; j < nen; ++j) {
    De[j] = fwd_const(0.0);
    for (int k = 0; k < nen; ++k) Me[j][k] = fwd_const(0.0);
  }
  fwd xs[MORTAR_MAX_NEN][3];
  memcpy(xs, p->xs, sizeof xs);
  double T[MORTAR_MAX_NEN][MORTAR_MAX_NEN];
  const int transformed = basis == MORTAR_DUAL_TRANSFORMED && mortar_transform(ft, T);
  for (int q = 0; q < nq; ++q) {
    fwd x_q[2] = {fwd_const(xi[q * ft->pdim]), fwd_const(ft->pdim > 1 ? xi[q * ft->pdim + 1] : 0.0)};
    fwd N[MORTAR_MAX_NEN], a[2][3];
    mortar_shape(ft, x_q, N, NULL);
    if (transformed) { /* N <- N~ = T N (the shape values carry no derivative slots) */
      double Nv[MORTAR_MAX_NEN], Nt[MORTAR_MAX_NEN];
      for (int j = 0; j < nen; ++j) Nv[j] = N[j].v;
      mortar_transform_values(nen, T, Nv, Nt);
      for (int j = 0; j < nen; ++j) N[j] = fwd_const(Nt[j]);
    }
    mortar_face_point(ft, xs, x_q, NULL, a);
    const fwd wJ = fwd_scale(w[q], face_jacobian(ft, a));
    for (int j = 0; j < nen; ++j) {
      fwd wN;
      fwd_set_mul(&wN, &wJ, &N[j]);
      fwd_acc_scaled(&De[j], 1.0, &wN);
      for (int k = 0; k < nen; ++k) fwd_acc_mul(&Me[j][k], &wN, &N[k]);
    }
  }
  /* A_e = D_e M_e^-1: Gauss-Jordan on [M_e | I] (M_e is symmetric positive definite: no pivoting) */
  fwd inv[MORTAR_MAX_NEN][MORTAR_MAX_NEN];
  for (int j = 0; j < nen; ++j)
    for (int k = 0; k < nen; ++k) inv[j][k] = fwd_const(j == k ? 1.0 : 0.0);
  for (int c = 0; c < nen; ++c) {
    const fwd piv = Me[c][c];
    for (int k = 0; k < nen; ++k) {
      Me[c][k] = fwd_div(Me[c][k], piv);
      inv[c][k] = fwd_div(inv[c][k], piv);
    }
    for (int r = 0; r < nen; ++r) {
      if (r == c) continue;
      const fwd f = Me[r][c];
      for (int k = 0; k < nen; ++k) {
        Me[r][k] = fwd_sub(Me[r][k], fwd_mul(f, Me[c][k]));
        inv[r][k] = fwd_sub(inv[r][k], fwd_mul(f, inv[c][k]));
      }
    }
  }
  for (int j = 0; j < nen; ++j)
    for (int k = 0; k < nen; ++k) A->coeff[j][k] = fwd_mul(De[j], inv[j][k]);
  if (!transformed) return;
  /* Phi_j = sum_l A~_jl N~_l = sum_k (A~ T)_jk N_k */
  fwd At[MORTAR_MAX_NEN][MORTAR_MAX_NEN];
  for (int j = 0; j < nen; ++j)
    for (int k = 0; k < nen; ++k) {
      At[j][k] = fwd_const(0.0);
      for (int l = 0; l < nen; ++l)
        if (T[l][k] != 0.0) fwd_acc_scaled(&At[j][k], T[l][k], &A->coeff[j][l]);
    }
  for (int j = 0; j < nen; ++j)
    for (int k = 0; k < nen; ++k) A->coeff[j][k] = At[j][k];
}

int mortar_transform(const mortar_face_type *ft, double T[MORTAR_MAX_NEN][MORTAR_MAX_NEN]) {
  /* the corners first, then edge node e between corners e and e + 1 (gmsh's TRI6 and QUAD8): the weights of
   * sk_modified_basis_weights, as a matrix */
  const int corners = sk_modified_basis_corners(ft->type);
  if (!corners) return 0;
  const double alpha = ft->alpha;
  memset(T, 0, sizeof(double) * MORTAR_MAX_NEN * MORTAR_MAX_NEN);
  for (int v = 0; v < corners; ++v) T[v][v] = 1.0;
  for (int e = 0; e < corners; ++e) {
    T[e][corners + e] = alpha;
    T[(e + 1) % corners][corners + e] = alpha;
    T[corners + e][corners + e] = 1.0 - 2.0 * alpha;
  }
  return 2 * corners;
}

void mortar_transform_values(int nen, double T[MORTAR_MAX_NEN][MORTAR_MAX_NEN], const double *N, double *Nt) {
  for (int j = 0; j < nen; ++j) {
    Nt[j] = 0.0;
    for (int k = 0; k < nen; ++k) Nt[j] += T[j][k] * N[k];
  }
}

/* ---- nodal normals and tangents -------------------------------------------------------------------------------- */
void mortar_face_normal_at_node(const mortar_face_type *ft, int dim, const double *x, int a, double c[3],
                                double dc[][3][3]) {
  static const double line2[] = {-1, 1};
  static const double line3[] = {-1, 1, 0}; /* gmsh order: the ends, then the middle */
  /* TRI3 and TRI6 (gmsh order: the corners, the middles of edges 01, 12, 20) */
  static const double tri6[] = {0, 0, 1, 0, 0, 1, 0.5, 0, 0.5, 0.5, 0, 0.5};
  /* QUAD4 and QUAD9 (gmsh order: the corners, the mid-side nodes, the centre) */
  static const double quad9[] = {-1, -1, 1, -1, 1, 1, -1, 1, 0, -1, 1, 0, 0, 1, -1, 0, 0, 0};
  const double *nodes = ft->type == SK_LINE2   ? line2
                        : ft->type == SK_LINE3 ? line3
                        : ft->type == SK_TRI3 || ft->type == SK_TRI6 ? tri6
                                               : quad9;
  const int pd = ft->pdim, nen = ft->nen;
  double N[MORTAR_MAX_NEN], dN[2 * MORTAR_MAX_NEN];
  ft->shape(ft->type, nodes + a * pd, N, dN);
  double t[2][3] = {{0, 0, 0}, {0, 0, 0}};
  for (int b = 0; b < nen; ++b)
    for (int k = 0; k < pd; ++k)
      for (int i = 0; i < 3; ++i) t[k][i] += dN[b * pd + k] * x[3 * b + i];
  memset(dc, 0, sizeof(double) * 9 * (size_t)nen);
  if (dim == 2) {
    /* c = a_1 x e_z = (a_y, -a_x) */
    c[0] = t[0][1];
    c[1] = -t[0][0];
    c[2] = 0.0;
    for (int b = 0; b < nen; ++b) {
      dc[b][0][1] = dN[b];
      dc[b][1][0] = -dN[b];
    }
    return;
  }
  /* c = a_1 x a_2;  dc = -[a_2]x da_1 + [a_1]x da_2,  da_k / dx_b = dN_b,k I */
  c[0] = t[0][1] * t[1][2] - t[0][2] * t[1][1];
  c[1] = t[0][2] * t[1][0] - t[0][0] * t[1][2];
  c[2] = t[0][0] * t[1][1] - t[0][1] * t[1][0];
  for (int b = 0; b < nen; ++b) {
    const double g1 = dN[b * 2], g2 = dN[b * 2 + 1];
    const double *a1 = t[0], *a2 = t[1];
    /* [v]x = [[0, -v2, v1], [v2, 0, -v0], [-v1, v0, 0]] */
    const double S1[3][3] = {{0, -a1[2], a1[1]}, {a1[2], 0, -a1[0]}, {-a1[1], a1[0], 0}};
    const double S2[3][3] = {{0, -a2[2], a2[1]}, {a2[2], 0, -a2[0]}, {-a2[1], a2[0], 0}};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) dc[b][i][j] = -g1 * S2[i][j] + g2 * S1[i][j];
  }
}

int mortar_normalize(const double c[3], double n[3], double dn_dc[3][3]) {
  const double len = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
  if (!(len > 0.0)) return -1;
  for (int i = 0; i < 3; ++i) n[i] = c[i] / len;
  if (dn_dc)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) dn_dc[i][j] = ((i == j ? 1.0 : 0.0) - n[i] * n[j]) / len;
  return 0;
}

int mortar_tangents(int dim, const double n[3], const double ref[3], double tau[2][3], double dtau_dn[2][3][3]) {
  memset(tau, 0, sizeof(double) * 6);
  memset(dtau_dn, 0, sizeof(double) * 18);
  if (dim == 2) {
    /* tau = e_z x n = (-n_y, n_x) */
    tau[0][0] = -n[1];
    tau[0][1] = n[0];
    dtau_dn[0][0][1] = -1.0;
    dtau_dn[0][1][0] = 1.0;
    return 0;
  }
  const double rn = ref[0] * n[0] + ref[1] * n[1] + ref[2] * n[2];
  double p[3], dp_dn[3][3], dt1_dp[3][3];
  for (int i = 0; i < 3; ++i) p[i] = ref[i] - rn * n[i];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) dp_dn[i][j] = -rn * (i == j ? 1.0 : 0.0) - n[i] * ref[j];
  const double plen = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
  if (plen < 1e-8 * sqrt(ref[0] * ref[0] + ref[1] * ref[1] + ref[2] * ref[2])) return -1;
  if (mortar_normalize(p, tau[0], dt1_dp) != 0) return -1;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double v = 0.0;
      for (int k = 0; k < 3; ++k) v += dt1_dp[i][k] * dp_dn[k][j];
      dtau_dn[0][i][j] = v;
    }
  const double *t1 = tau[0];
  tau[1][0] = n[1] * t1[2] - n[2] * t1[1];
  tau[1][1] = n[2] * t1[0] - n[0] * t1[2];
  tau[1][2] = n[0] * t1[1] - n[1] * t1[0];
  /* d(n x t1) = dn x t1 + n x dt1 = -[t1]x dn + [n]x dt1 */
  const double St[3][3] = {{0, -t1[2], t1[1]}, {t1[2], 0, -t1[0]}, {-t1[1], t1[0], 0}};
  const double Sn[3][3] = {{0, -n[2], n[1]}, {n[2], 0, -n[0]}, {-n[1], n[0], 0}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double v = -St[i][j];
      for (int k = 0; k < 3; ++k) v += Sn[i][k] * dtau_dn[0][k][j];
      dtau_dn[1][i][j] = v;
    }
  return 0;
}

void mortar_ncp_places(int dim, const double n[3], const double tau[2][3], int place[3]) {
  int axis = 0;
  for (int i = 1; i < dim; ++i)
    if (fabs(n[i]) > fabs(n[axis])) axis = i;
  place[0] = axis;
  const int p = (axis + 1) % dim, q = (axis + 2) % dim; /* the other axes (dim 3; dim 2: p only) */
  if (dim == 2) {
    place[1] = p;
    return;
  }
  const int keep = fabs(tau[0][p]) * fabs(tau[1][q]) >= fabs(tau[0][q]) * fabs(tau[1][p]);
  place[1] = keep ? p : q;
  place[2] = keep ? q : p;
}

/* ---- quadrature ------------------------------------------------------------------------------------------------ */
void mortar_gauss_legendre(int n, double *x, double *w) {
  /* Newton on the Legendre polynomial P_n from the Chebyshev-like initial guesses (Golub-Welsch would need an
   * eigensolver); converges to round-off in a few iterations for n <= 16. */
  for (int i = 0; i < (n + 1) / 2; ++i) {
    double z = cos(3.14159265358979323846 * (i + 0.75) / (n + 0.5)), dp = 1.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = z;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      if (n == 1) p0 = 1.0;
      dp = n * (z * p1 - p0) / (z * z - 1.0);
      const double dz = p1 / dp;
      z -= dz;
      if (fabs(dz) < 1e-16) break;
    }
    x[i] = -z;
    x[n - 1 - i] = z;
    w[i] = w[n - 1 - i] = 2.0 / ((1.0 - z * z) * dp * dp);
  }
  if (n % 2 == 1) x[n / 2] = 0.0;
}

/* Dunavant (1985) symmetric rules on the unit triangle; weights normalised to sum 1/2. */
static const double tri1_xi[] = {1.0 / 3, 1.0 / 3};
static const double tri1_w[] = {0.5};
static const double tri3_xi[] = {1.0 / 6, 1.0 / 6, 2.0 / 3, 1.0 / 6, 1.0 / 6, 2.0 / 3};
static const double tri3_w[] = {1.0 / 6, 1.0 / 6, 1.0 / 6};
#define T6A 0.445948490915965
#define T6B 0.091576213509771
#define T6WA (0.223381589678011 / 2)
#define T6WB (0.109951743655322 / 2)
static const double tri6_xi[] = {T6A, T6A, 1 - 2 * T6A, T6A, T6A, 1 - 2 * T6A,
                                 T6B, T6B, 1 - 2 * T6B, T6B, T6B, 1 - 2 * T6B};
static const double tri6_w[] = {T6WA, T6WA, T6WA, T6WB, T6WB, T6WB};
#define T7A 0.470142064105115
#define T7B 0.101286507323456
#define T7WA (0.132394152788506 / 2)
#define T7WB (0.125939180544827 / 2)
static const double tri7_xi[] = {1.0 / 3,     1.0 / 3,     T7A, T7A, T7A, 1 - 2 * T7A, 1 - 2 * T7A, T7A,
                                 T7B,         T7B,         T7B, 1 - 2 * T7B, 1 - 2 * T7B, T7B};
static const double tri7_w[] = {0.225 / 2, T7WA, T7WA, T7WA, T7WB, T7WB, T7WB};
#define T12A 0.249286745170910
#define T12B 0.063089014491502
#define T12C 0.310352451033784
#define T12D 0.053145049844817
#define T12WA (0.116786275726379 / 2)
#define T12WB (0.050844906370207 / 2)
#define T12WC (0.082851075618374 / 2)
static const double tri12_xi[] = {
    T12A, T12A, 1 - 2 * T12A, T12A, T12A, 1 - 2 * T12A,
    T12B, T12B, 1 - 2 * T12B, T12B, T12B, 1 - 2 * T12B,
    T12C, T12D, T12D, T12C, 1 - T12C - T12D, T12C, T12C, 1 - T12C - T12D, T12D, 1 - T12C - T12D, 1 - T12C - T12D,
    T12D};
static const double tri12_w[] = {T12WA, T12WA, T12WA, T12WB, T12WB, T12WB,
                                 T12WC, T12WC, T12WC, T12WC, T12WC, T12WC};

int mortar_triangle_rule(int n, const double **xi, const double **w) {
  switch (n) {
    case 1: *xi = tri1_xi; *w = tri1_w; return 1;
    case 3: *xi = tri3_xi; *w = tri3_w; return 3;
    case 6: *xi = tri6_xi; *w = tri6_w; return 6;
    case 7: *xi = tri7_xi; *w = tri7_w; return 7;
    case 12: *xi = tri12_xi; *w = tri12_w; return 12;
    default: return 0;
  }
}

/* QUAD9: N_j N_k J of degree 4 per direction on a parallelogram with its mid-side nodes in the middles (3 points
 * suffice), 5 on any flat quadrilateral (QUAD8 the same: its functions are of degree 2 per direction); a curved
 * face's J is not polynomial: on a face bulging by 8 % of its size,
 * int Phi_j N_k = delta_jk int N_k to 4.0e-6 with 5 x 5 points, 1.7e-9 with 8 x 8, 1.4e-11 with 10 x 10
 * (test_mortar_integrals) */
enum { QUAD9_EXACT_ORDER = 8 };

int mortar_face_exact_order(sk_elem_type type) {
  /* LINE3: N_j N_k J of degree 4 on a straight face with the middle node in the middle, 5 with it moved along the
   * chord (3 points suffice); a curved face's J is not polynomial: 10 points give int Phi_j N_k = delta_jk int N_k
   * to 1.5e-16 on a 30-degree arc (5 points: 7.4e-8; test_mortar_integrals) */
  /* TRI6: N~_j N~_k J of degree 4 on a flat face with its mid-side nodes in the middles: order 5 takes the 12-point
   * rule (degree 6) */
  return type == SK_LINE3 ? 10 : type == SK_QUAD9 || type == SK_QUAD8 ? QUAD9_EXACT_ORDER : type == SK_TRI6 ? 5 : 3;
}

int mortar_face_rule(sk_elem_type type, int order, double *xi, double *w) {
  if (order < 1) order = 1;
  if (order > MORTAR_MAX_RULE) order = MORTAR_MAX_RULE;
  double g[MORTAR_MAX_RULE], gw[MORTAR_MAX_RULE];
  if (type == SK_TRI3 || type == SK_TRI6) {
    static const int sizes[] = {1, 3, 7, 7, 12};
    const double *txi = tri1_xi, *tw = tri1_w;
    const int n = mortar_triangle_rule(sizes[order > 5 ? 4 : order - 1], &txi, &tw);
    memcpy(xi, txi, sizeof(double) * 2 * (size_t)n);
    memcpy(w, tw, sizeof(double) * (size_t)n);
    return n;
  }
  mortar_gauss_legendre(order, g, gw);
  if (type == SK_LINE2 || type == SK_LINE3) {
    memcpy(xi, g, sizeof(double) * (size_t)order);
    memcpy(w, gw, sizeof(double) * (size_t)order);
    return order;
  }
  int q = 0;
  for (int j = 0; j < order; ++j)
    for (int i = 0; i < order; ++i, ++q) {
      xi[2 * q] = g[i];
      xi[2 * q + 1] = g[j];
      w[q] = gw[i] * gw[j];
    }
  return q;
}
