/* The mortar integrals of one face pair as a function of its local unknowns u = [x_s | x_m | n_s], shared by the
 * kernel's tests (test_mortar_integrals.c: first-order faces and LINE3; test_mortar_integrals_quadratic.c: QUAD9,
 * TRI6, QUAD8): the whole-face integrals and the biorthogonality of the dual basis, pair cases (segments, concentrated
 * points, obstacles) with a generic curved configuration, and the finite-difference check of their derivatives. */
#ifndef MORTAR_PAIR_CASES_H
#define MORTAR_PAIR_CASES_H

#include "mortar_test_support.h"

static const double FD_STEP = 1e-6;
static const double FD_TOL = 2e-7;

/* The slave face's integrals D, M over the whole face with the rule exact for its type (the weights D_jj). */
static inline void whole_face_integrals(const mortar_pair *p, const mortar_basis_coeffs *A, mortar_basis basis,
                                        mortar_integrals *I) {
  double xi[MORTAR_MAX_RULE * MORTAR_MAX_RULE * 2], w[MORTAR_MAX_RULE * MORTAR_MAX_RULE];
  mortar_integrals_zero(I, p);
  const sk_elem_type type = p->slave->type;
  const int nd = mortar_face_rule(type, mortar_face_exact_order(type), xi, w);
  mortar_slave_integrals(p, A, basis, nd, xi, w, I);
}

/* int_e Phi_j N_k = delta_jk int_e N_k on the current face, with a rule finer than the kernel's. Exact on planar
 * faces and on LINE3 faces, straight or curved (the kernel's 10 points there); on a warped QUAD4 only up to the error
 * of the kernel's 3 x 3 rule for D_e, M_e (the Jacobian is not polynomial there): `tol`. */
static inline void check_biorthogonality(const mortar_face_type *ft, const double *x, double tol) {
  mortar_pair p;
  double ns[3 * MORTAR_MAX_NEN] = {0};
  mortar_pair_set(&p, ft->pdim + 1, ft, NULL, x, NULL, ns, 0);
  mortar_basis_coeffs A;
  mortar_basis_coefficients(&p, MORTAR_DUAL, &A);
  double xi[MORTAR_MAX_RULE * MORTAR_MAX_RULE * 2], w[MORTAR_MAX_RULE * MORTAR_MAX_RULE];
  const int nq = mortar_face_rule(ft->type, ft->pdim == 1 || ft->type == SK_QUAD9 ? MORTAR_MAX_RULE : 8, xi, w);
  double PN[MORTAR_MAX_NEN][MORTAR_MAX_NEN] = {{0}}, intN[MORTAR_MAX_NEN] = {0};
  for (int q = 0; q < nq; ++q) {
    fwd xq[2] = {fwd_const(xi[q * ft->pdim]), fwd_const(ft->pdim > 1 ? xi[q * ft->pdim + 1] : 0.0)};
    fwd N[MORTAR_MAX_NEN], a[2][3], pos[3];
    mortar_shape(ft, xq, N, NULL);
    mortar_face_point(ft, p.xs, xq, pos, a);
    double J;
    if (ft->pdim == 1) {
      J = fwd_norm(3, a[0]).v;
    } else {
      fwd c[3];
      fwd_cross3(a[0], a[1], c);
      J = fwd_norm(3, c).v;
    }
    for (int j = 0; j < ft->nen; ++j) {
      double phi = 0.0;
      for (int k = 0; k < ft->nen; ++k) phi += A.coeff[j][k].v * N[k].v;
      intN[j] += w[q] * J * N[j].v;
      for (int k = 0; k < ft->nen; ++k) PN[j][k] += w[q] * J * phi * N[k].v;
    }
  }
  double err = 0.0;
  for (int j = 0; j < ft->nen; ++j)
    for (int k = 0; k < ft->nen; ++k) err = fmax(err, fabs(PN[j][k] - (j == k ? intN[k] : 0.0)));
  printf("  biorthogonality %s: max |int Phi_j N_k - delta_jk int N_k| = %.2e\n", sk_elem_name(ft->type), err);
  SK_CHECK(err < tol);
  /* LINE3: D_jj = int Phi_j = int N_j > 0 (the standard dual basis is admissible); on a straight face with its middle
   * node in the middle, L (1/6, 1/6, 2/3) */
  if (ft->type == SK_LINE3) {
    mortar_integrals I;
    whole_face_integrals(&p, &A, MORTAR_DUAL, &I);
    double length = 0.0;
    for (int j = 0; j < 3; ++j) length += I.D[j][j].v;
    printf("  line3 weights D_jj / L: %.15f %.15f %.15f\n", I.D[0][0].v / length, I.D[1][1].v / length,
           I.D[2][2].v / length);
    for (int j = 0; j < 3; ++j) SK_CHECK(I.D[j][j].v > 0.0);
    const double chord = hypot(x[3] - x[0], x[4] - x[1]);
    const double off = fabs((x[6] - x[0]) * (x[4] - x[1]) - (x[7] - x[1]) * (x[3] - x[0])) / chord;
    const double mid = hypot(x[6] - 0.5 * (x[0] + x[3]), x[7] - 0.5 * (x[1] + x[4]));
    if (off < 1e-15 * chord && mid < 1e-15 * chord) {
      SK_CHECK_CLOSE(I.D[0][0].v / length, 1.0 / 6.0, 1e-14);
      SK_CHECK_CLOSE(I.D[2][2].v / length, 2.0 / 3.0, 1e-14);
    }
  }
  /* the affine faces give the textbook constants */
  if (ft->type == SK_LINE2) {
    SK_CHECK_CLOSE(A.coeff[0][0].v, 2.0, 1e-13);
    SK_CHECK_CLOSE(A.coeff[0][1].v, -1.0, 1e-13);
  }
  if (ft->type == SK_TRI3) {
    SK_CHECK_CLOSE(A.coeff[1][1].v, 3.0, 1e-13);
    SK_CHECK_CLOSE(A.coeff[1][2].v, -1.0, 1e-13);
  }
}

/* ---- one pair as a function of its local unknowns u = [x_s | x_m | n_s] ---------------------------------------- */
typedef enum { MODE_SEGMENTS, MODE_POINTS_A, MODE_POINTS_M, MODE_OBSTACLE_PLANE, MODE_OBSTACLE_SPHERE } pair_mode;

typedef struct {
  int dim;
  const mortar_face_type *st, *mt;
  mortar_basis basis;
  pair_mode mode;
  int order;
} pair_case;

static inline int obstacle_plane(void *ctx, const double *x, double *gap, double *normal) {
  const int dim = *(const int *)ctx; /* y (2D) or z (3D) = -0.1, outward normal up */
  normal[0] = normal[1] = normal[2] = 0.0;
  normal[dim - 1] = 1.0;
  *gap = x[dim - 1] + 0.1;
  return 0;
}

static inline int obstacle_sphere(void *ctx, const double *x, double *gap, double *normal) {
  const int dim = *(const int *)ctx; /* radius 2 centred 2.1 below the origin */
  double c[3] = {0.3, 0.0, 0.0};
  c[dim - 1] = -2.1;
  double d = 0.0;
  for (int i = 0; i < dim; ++i) d += (x[i] - c[i]) * (x[i] - c[i]);
  d = sqrt(d);
  for (int i = 0; i < 3; ++i) normal[i] = i < dim ? (x[i] - c[i]) / d : 0.0;
  *gap = d - 2.0;
  return 0;
}

static inline int n_local(const pair_case *c) {
  return (2 * c->st->nen + (c->mt ? c->mt->nen : 0)) * c->dim;
}

static inline int n_outputs(const pair_case *c) {
  const int ns = c->st->nen, nm = c->mt ? c->mt->nen : 0;
  return ns * ns + ns * nm + ns;
}

static inline void unpack(const pair_case *c, const double *u, double *xs, double *xm, double *ns) {
  const int d = c->dim, es = c->st->nen, em = c->mt ? c->mt->nen : 0;
  memset(xs, 0, sizeof(double) * 3 * MORTAR_MAX_NEN);
  memset(xm, 0, sizeof(double) * 3 * MORTAR_MAX_NEN);
  memset(ns, 0, sizeof(double) * 3 * MORTAR_MAX_NEN);
  for (int a = 0; a < es; ++a)
    for (int i = 0; i < d; ++i) {
      xs[3 * a + i] = u[a * d + i];
      ns[3 * a + i] = u[(es + em + a) * d + i];
    }
  for (int b = 0; b < em; ++b)
    for (int i = 0; i < d; ++i) xm[3 * b + i] = u[(es + b) * d + i];
}

static inline int integrate_case(const pair_case *c, const double *xs, const double *xm, const double *ns,
                                 int derivatives, mortar_pair *p, mortar_integrals *I) {
  mortar_pair_set(p, c->dim, c->st, c->mt, xs, xm, ns, derivatives);
  mortar_basis_coeffs A;
  mortar_basis_coefficients(p, c->basis, &A);
  mortar_integrals_zero(I, p);
  double xi[MORTAR_MAX_RULE * MORTAR_MAX_RULE * 2], w[MORTAR_MAX_RULE * MORTAR_MAX_RULE];
  int nq = mortar_face_rule(c->st->type, mortar_face_exact_order(c->st->type), xi, w);
  mortar_slave_integrals(p, &A, c->basis, nq, xi, w, I);
  nq = mortar_face_rule(c->st->type, c->order, xi, w);
  int dim = c->dim;
  switch (c->mode) {
    case MODE_SEGMENTS:
      return c->dim == 2 ? mortar_segments_2d(p, &A, c->basis, c->order, I) - 1
                         : mortar_segments_3d(p, &A, c->basis, c->order, I) - 1;
    case MODE_POINTS_A:
    case MODE_POINTS_M:
      mortar_points(p, &A, c->basis, c->mode == MODE_POINTS_A ? MORTAR_NORMAL_A : MORTAR_NORMAL_M, nq, xi, w, I);
      return I->n_cells == nq ? 0 : -1;
    case MODE_OBSTACLE_PLANE:
      mortar_obstacle_points(p, &A, c->basis, nq, xi, w, obstacle_plane, &dim, I);
      return 0;
    case MODE_OBSTACLE_SPHERE:
      mortar_obstacle_points(p, &A, c->basis, nq, xi, w, obstacle_sphere, &dim, I);
      return 0;
  }
  return -1;
}

static inline int eval_pair(void *ctx, const double *u, int derivatives, fwd *out) {
  const pair_case *c = ctx;
  double xs[3 * MORTAR_MAX_NEN], xm[3 * MORTAR_MAX_NEN], ns[3 * MORTAR_MAX_NEN];
  unpack(c, u, xs, xm, ns);
  mortar_pair p;
  mortar_integrals I;
  if (integrate_case(c, xs, xm, ns, derivatives, &p, &I) != 0) return -1;
  int m = 0;
  for (int j = 0; j < p.nen_s; ++j) {
    for (int k = 0; k < p.nen_s; ++k) out[m++] = I.D[j][k];
    for (int l = 0; l < p.nen_m; ++l) out[m++] = I.M[j][l];
    out[m++] = I.gap[j];
  }
  return 0;
}

/* QUAD9 node positions (gmsh order) of the bilinear map of corners P plus a bulge b (1 - xi^2)(1 - eta^2) along z. */
static inline void quad9_nodes(const double P[4][3], double bulge, double out[9][3]) {
  static const double nodes[9][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}, {0, -1}, {1, 0}, {0, 1}, {-1, 0}, {0, 0}};
  for (int a = 0; a < 9; ++a) {
    const double s = nodes[a][0], t = nodes[a][1];
    const double w[4] = {(1 - s) * (1 - t) / 4, (1 + s) * (1 - t) / 4, (1 + s) * (1 + t) / 4, (1 - s) * (1 + t) / 4};
    for (int i = 0; i < 3; ++i) out[a][i] = w[0] * P[0][i] + w[1] * P[1][i] + w[2] * P[2][i] + w[3] * P[3][i];
    out[a][2] += bulge * (1 - s * s) * (1 - t * t);
  }
}

/* TRI6 node positions (gmsh order: corners, middles of edges 01, 12, 20) of the affine map of corners P plus a bulge
 * b along z at the mid-side nodes. */
static inline void tri6_nodes(const double P[3][3], double bulge, double out[6][3]) {
  static const int ends[3][2] = {{0, 1}, {1, 2}, {2, 0}};
  for (int a = 0; a < 3; ++a) memcpy(out[a], P[a], sizeof(double) * 3);
  for (int e = 0; e < 3; ++e) {
    for (int i = 0; i < 3; ++i) out[3 + e][i] = 0.5 * (P[ends[e][0]][i] + P[ends[e][1]][i]);
    out[3 + e][2] += bulge;
  }
}

/* QUAD8 node positions (gmsh order: corners, middles of edges 01, 12, 23, 30) of the bilinear map of corners P plus a
 * bulge b along z at the mid-side nodes. */
static inline void quad8_nodes(const double P[4][3], double bulge, double out[8][3]) {
  double q9[9][3];
  quad9_nodes(P, 0.0, q9);
  memcpy(out, q9, sizeof(double) * 24);
  for (int e = 4; e < 8; ++e) out[e][2] += bulge;
}

/* A generic (curved, partly overlapping) configuration: slave above with outward normal down, master below facing
 * up, perturbed nodal normals. QUAD9 and QUAD8 faces: the QUAD4 corners' bilinear maps, curved (bulges 0.03 and
 * -0.02); TRI6 faces: the TRI3 corners', curved (bulges 0.03 and -0.02). */
static inline void generic_configuration(const pair_case *c, double *u) {
  const int d = c->dim, es = c->st->nen, em = c->mt ? c->mt->nen : 0;
  static const double line_s[3][2] = {{0, 0}, {1, 0.1}, {0.58, 0.09}}, line_m[3][2] = {{0.7, -0.05}, {-0.4, 0.02},
                                                                                      {0.2, -0.07}};
  static const double tri_s[3][3] = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}};
  static const double quad_s[4][3] = {{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}};
  static const double tri_m[3][3] = {{-0.2, -0.1, -0.05}, {0.9, -0.2, -0.04}, {0.1, 0.8, -0.06}};
  static const double quad_m[4][3] = {{-0.3, -0.2, -0.05}, {0.8, -0.3, -0.04}, {0.9, 0.7, -0.06}, {-0.2, 0.8, -0.05}};
  double quad9_s[9][3], quad9_m[9][3], tri6_s[6][3], tri6_m[6][3], quad8_s[8][3], quad8_m[8][3];
  quad9_nodes(quad_s, 0.03, quad9_s);
  quad9_nodes(quad_m, -0.02, quad9_m);
  quad8_nodes(quad_s, 0.03, quad8_s);
  quad8_nodes(quad_m, -0.02, quad8_m);
  tri6_nodes(tri_s, 0.03, tri6_s);
  tri6_nodes(tri_m, -0.02, tri6_m);
  for (int a = 0; a < es; ++a) {
    double nrm[3] = {0.05 * test_rand(), 0.05 * test_rand(), 0.05 * test_rand()};
    nrm[d - 1] = -1.0;
    const double len = sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + (d == 3 ? nrm[2] * nrm[2] : 0.0));
    for (int i = 0; i < d; ++i) {
      const double base = d == 2    ? line_s[a][i]
                          : es == 3 ? tri_s[a][i]
                          : es == 6 ? tri6_s[a][i]
                          : es == 9 ? quad9_s[a][i]
                          : es == 8 ? quad8_s[a][i]
                                    : quad_s[a][i];
      u[a * d + i] = base + (i < d - 1 ? 0.03 : 0.02) * test_rand();
      u[(es + em + a) * d + i] = nrm[i] / len;
    }
  }
  for (int b = 0; b < em; ++b)
    for (int i = 0; i < d; ++i) {
      const double base = d == 2    ? line_m[b][i]
                          : em == 3 ? tri_m[b][i]
                          : em == 6 ? tri6_m[b][i]
                          : em == 9 ? quad9_m[b][i]
                          : em == 8 ? quad8_m[b][i]
                                    : quad_m[b][i];
      u[(es + b) * d + i] = base + 0.02 * test_rand();
    }
}

static inline void check_derivatives(const char *label, pair_case c) {
  double u[FWD_MAX];
  generic_configuration(&c, u);
  const double err = test_fd_check(label, eval_pair, &c, u, n_local(&c), n_outputs(&c), FD_STEP);
  SK_CHECK(err < FD_TOL);
}

#endif
