/* mortar-dual kernel: the mortar integrals of one face pair. Biorthogonality of the dual basis; patch-test-type
 * integrals (a flat non-matching interface: sum_l M_jl = D_jj, linear fields reproduced, constant gap) exact with
 * segment-based integration and only approximate with concentrated integration (deviation printed); invariance
 * under a rigid motion; and a finite-difference check of every derivative of D, M and the weighted gap for 2D
 * segments, 3D segments (tri3/quad4 in all combinations), concentrated points (normal variants A and M) and rigid
 * obstacles; the 3D segments' continuity where a clip-polygon vertex appears and their derivatives on slivers. */
#include "mortar_test_support.h"

#ifndef MORTAR_INTEGRALS_QUAD9
#define MORTAR_INTEGRALS_QUAD9 0
#endif
#ifndef MORTAR_INTEGRALS_TRI6
#define MORTAR_INTEGRALS_TRI6 0
#endif
#ifndef MORTAR_INTEGRALS_QUAD8
#define MORTAR_INTEGRALS_QUAD8 0
#endif

static const double FD_STEP = 1e-6;
static const double FD_TOL = 2e-7;
/* biorthogonality on a curved QUAD9 face (bulging by 8 % of its size; J not polynomial) with the kernel's 8 x 8 rule:
 * measured 1.70e-9 */
static const double QUAD9_CURVED_TOL = 2.5e-9;

/* ---- quadrature and bases -------------------------------------------------------------------------------------- */
static void check_quadrature(void) {
  for (int n = 1; n <= 8; ++n) {
    double x[MORTAR_MAX_RULE], w[MORTAR_MAX_RULE];
    mortar_gauss_legendre(n, x, w);
    double err = 0.0;
    for (int p = 0; p <= 2 * n - 1; ++p) {
      double s = 0.0;
      for (int i = 0; i < n; ++i) s += w[i] * pow(x[i], p);
      err = fmax(err, fabs(s - (p % 2 ? 0.0 : 2.0 / (p + 1))));
    }
    SK_CHECK(err < 1e-14);
  }
  static const int sizes[] = {1, 3, 6, 7, 12}, degrees[] = {1, 2, 4, 5, 6};
  for (int r = 0; r < 5; ++r) {
    const double *xi, *w;
    const int n = mortar_triangle_rule(sizes[r], &xi, &w);
    SK_CHECK(n == sizes[r]);
    double err = 0.0;
    for (int a = 0; a <= degrees[r]; ++a)
      for (int b = 0; a + b <= degrees[r]; ++b) {
        double s = 0.0, exact = tgamma(a + 1) * tgamma(b + 1) / tgamma(a + b + 3); /* int x^a y^b */
        for (int q = 0; q < n; ++q) s += w[q] * pow(xi[2 * q], a) * pow(xi[2 * q + 1], b);
        err = fmax(err, fabs(s - exact));
      }
    SK_CHECK(err < 1e-13);
  }
}

/* int_e Phi_j N_k = delta_jk int_e N_k on the current face, with a rule finer than the kernel's. Exact on planar
 * faces and on LINE3 faces, straight or curved (the kernel's 10 points there); on a warped QUAD4 only up to the error of the kernel's 3 x 3 rule for D_e, M_e (the Jacobian is not
 * polynomial there): `tol`. */
/* The slave face's integrals D, M over the whole face with the rule exact for its type (the weights D_jj). */
static void whole_face_integrals(const mortar_pair *p, const mortar_basis_coeffs *A, mortar_basis basis,
                                 mortar_integrals *I) {
  double xi[MORTAR_MAX_RULE * MORTAR_MAX_RULE * 2], w[MORTAR_MAX_RULE * MORTAR_MAX_RULE];
  mortar_integrals_zero(I, p);
  const sk_elem_type type = p->slave->type;
  const int nd = mortar_face_rule(type, mortar_face_exact_order(type), xi, w);
  mortar_slave_integrals(p, A, basis, nd, xi, w, I);
}

static void check_biorthogonality(const mortar_face_type *ft, const double *x, double tol) {
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

/* QUAD9: D_jj = int Phi_j = int N_j > 0 at every node (the standard dual basis is admissible); on a parallelogram with
 * its mid-side and centre nodes in the middles, the area times 1/36 (corners), 1/9 (mid-sides), 4/9 (centre). */
static void check_quad9_weights(const double *x, int parallelogram) {
  mortar_pair p;
  double ns[3 * MORTAR_MAX_NEN] = {0};
  mortar_pair_set(&p, 3, &ft_quad9, NULL, x, NULL, ns, 0);
  mortar_basis_coeffs A;
  mortar_basis_coefficients(&p, MORTAR_DUAL, &A);
  mortar_integrals I;
  whole_face_integrals(&p, &A, MORTAR_DUAL, &I);
  double area = 0.0;
  for (int j = 0; j < 9; ++j) area += I.D[j][j].v;
  printf("  quad9 weights D_jj / area:");
  for (int j = 0; j < 9; ++j) printf(" %.15f", I.D[j][j].v / area);
  printf("\n");
  for (int j = 0; j < 9; ++j) SK_CHECK(I.D[j][j].v > 0.0);
  if (parallelogram)
    for (int j = 0; j < 9; ++j)
      SK_CHECK_CLOSE(I.D[j][j].v / area, j < 4 ? 1.0 / 36.0 : j < 8 ? 1.0 / 9.0 : 4.0 / 9.0, 1e-14);
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

static int obstacle_plane(void *ctx, const double *x, double *gap, double *normal) {
  const int dim = *(const int *)ctx; /* y (2D) or z (3D) = -0.1, outward normal up */
  normal[0] = normal[1] = normal[2] = 0.0;
  normal[dim - 1] = 1.0;
  *gap = x[dim - 1] + 0.1;
  return 0;
}

static int obstacle_sphere(void *ctx, const double *x, double *gap, double *normal) {
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

static int n_local(const pair_case *c) {
  return (2 * c->st->nen + (c->mt ? c->mt->nen : 0)) * c->dim;
}

static int n_outputs(const pair_case *c) {
  const int ns = c->st->nen, nm = c->mt ? c->mt->nen : 0;
  return ns * ns + ns * nm + ns;
}

static void unpack(const pair_case *c, const double *u, double *xs, double *xm, double *ns) {
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

static int integrate_case(const pair_case *c, const double *xs, const double *xm, const double *ns, int derivatives,
                          mortar_pair *p, mortar_integrals *I) {
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

static int eval_pair(void *ctx, const double *u, int derivatives, fwd *out) {
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
static void quad9_nodes(const double P[4][3], double bulge, double out[9][3]) {
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
static void tri6_nodes(const double P[3][3], double bulge, double out[6][3]) {
  static const int ends[3][2] = {{0, 1}, {1, 2}, {2, 0}};
  for (int a = 0; a < 3; ++a) memcpy(out[a], P[a], sizeof(double) * 3);
  for (int e = 0; e < 3; ++e) {
    for (int i = 0; i < 3; ++i) out[3 + e][i] = 0.5 * (P[ends[e][0]][i] + P[ends[e][1]][i]);
    out[3 + e][2] += bulge;
  }
}

/* QUAD8 node positions (gmsh order: corners, middles of edges 01, 12, 23, 30) of the bilinear map of corners P plus a
 * bulge b along z at the mid-side nodes. */
static void quad8_nodes(const double P[4][3], double bulge, double out[8][3]) {
  double q9[9][3];
  quad9_nodes(P, 0.0, q9);
  memcpy(out, q9, sizeof(double) * 24);
  for (int e = 4; e < 8; ++e) out[e][2] += bulge;
}

/* A generic (curved, partly overlapping) configuration: slave above with outward normal down, master below facing
 * up, perturbed nodal normals. QUAD9 and QUAD8 faces: the QUAD4 corners' bilinear maps, curved (bulges 0.03 and
 * -0.02); TRI6 faces: the TRI3 corners', curved (bulges 0.03 and -0.02). */
static void generic_configuration(const pair_case *c, double *u) {
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

static void check_derivatives(const char *label, pair_case c) {
  double u[FWD_MAX];
  generic_configuration(&c, u);
  const double err = test_fd_check(label, eval_pair, &c, u, n_local(&c), n_outputs(&c), FD_STEP);
  SK_CHECK(err < FD_TOL);
}

/* ---- patch-test-type integrals: a flat slave face over several master faces, summed --------------------------- */
enum { MAX_PATCH_MASTERS = 32 };
typedef struct {
  double D[4], Msum[4], Mx[4][3], Dx[4][3], gap[4];
  double M[MAX_PATCH_MASTERS][4][4]; /* per master face */
} patch_sums;

typedef struct {
  int n;
  double xm[MAX_PATCH_MASTERS][12];
} patch_masters;

/* M and gap of a pair (D, of the slave face alone, is added once by integrate_patch). */
static void add_integrals(const mortar_pair *p, const mortar_integrals *I, const double *xm, int face,
                          patch_sums *s) {
  for (int j = 0; j < p->nen_s; ++j) {
    for (int l = 0; l < p->nen_m; ++l) {
      s->Msum[j] += I->M[j][l].v;
      s->M[face][j][l] += I->M[j][l].v;
      for (int i = 0; i < 3; ++i) s->Mx[j][i] += I->M[j][l].v * xm[3 * l + i];
    }
    s->gap[j] += I->gap[j].v;
  }
}

/* Segments: every pair. Concentrated: each slave point goes to the first master face it projects into. */
static void integrate_patch(const pair_case *c, const double *xs, const double *ns, const patch_masters *pm,
                            patch_sums *s) {
  mortar_pair p;
  mortar_integrals I;
  integrate_case(c, xs, pm->xm[0], ns, 0, &p, &I); /* D of the slave face */
  for (int j = 0; j < p.nen_s; ++j)
    for (int k = 0; k < p.nen_s; ++k) {
      s->D[j] += I.D[j][k].v;
      for (int i = 0; i < 3; ++i) s->Dx[j][i] += I.D[j][k].v * xs[3 * k + i];
    }
  if (c->mode == MODE_SEGMENTS) {
    for (int f = 0; f < pm->n; ++f)
      if (integrate_case(c, xs, pm->xm[f], ns, 0, &p, &I) == 0) add_integrals(&p, &I, pm->xm[f], f, s);
    return;
  }
  double xi[MORTAR_MAX_RULE * MORTAR_MAX_RULE * 2], w[MORTAR_MAX_RULE * MORTAR_MAX_RULE];
  const int nq = mortar_face_rule(c->st->type, c->order, xi, w), pd = c->st->pdim;
  for (int q = 0; q < nq; ++q)
    for (int f = 0; f < pm->n; ++f) {
      mortar_pair_set(&p, c->dim, c->st, c->mt, xs, pm->xm[f], ns, 0);
      mortar_point_projection proj;
      if (mortar_project_point(&p, MORTAR_NORMAL_A, xi + q * pd, 1e-12, &proj) != 0 || !proj.inside) continue;
      mortar_basis_coeffs A;
      mortar_basis_coefficients(&p, c->basis, &A);
      mortar_integrals_zero(&I, &p);
      mortar_points(&p, &A, c->basis, MORTAR_NORMAL_A, 1, xi + q * pd, w + q, &I);
      add_integrals(&p, &I, pm->xm[f], f, s);
      break;
    }
}

/* Returns the largest deviation of sum_l M_jl = sum_k D_jk, sum_l M_jl x_l = sum_k D_jk x_k (in-plane
 * components) and gap_j = delta sum_k D_jk, relative to the face measure. */
static double patch_deviation(const pair_case *c, double delta, patch_sums *sums) {
  const int d = c->dim;
  patch_sums s;
  memset(&s, 0, sizeof s);
  double xs[12] = {0}, ns[12] = {0}, xm[12] = {0};
  double measure;
  patch_masters pm = {0};
  if (d == 2) {
    xs[3] = 1.0; /* slave (0,0)-(1,0), outward normal down */
    ns[1] = ns[4] = -1.0;
    static const double xn[] = {1.25, 0.6, 0.15, -0.3};
    for (int e = 0; e < 3; ++e) {
      xm[0] = xn[e];
      xm[3] = xn[e + 1];
      xm[1] = xm[4] = -delta;
      memcpy(pm.xm[pm.n++], xm, sizeof xm);
    }
    measure = 1.0;
  } else {
    static const double quad[4][2] = {{0, 0}, {0, 1}, {1, 1}, {1, 0}}, tri[3][2] = {{0, 0}, {0, 1}, {1, 0}};
    const int es = c->st->nen;
    for (int a = 0; a < es; ++a) {
      xs[3 * a] = es == 4 ? quad[a][0] : tri[a][0];
      xs[3 * a + 1] = es == 4 ? quad[a][1] : tri[a][1];
      ns[3 * a + 2] = -1.0;
    }
    measure = es == 4 ? 1.0 : 0.5;
    /* master grid over [-0.2, 1.3]^2, irregular lines, facing up (counter-clockwise from above) */
    static const double gx[] = {-0.2, 0.37, 0.81, 1.3}, gy[] = {-0.2, 0.29, 0.74, 1.3};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const double P[4][2] = {{gx[i], gy[j]}, {gx[i + 1], gy[j]}, {gx[i + 1], gy[j + 1]}, {gx[i], gy[j + 1]}};
        if (c->mt->nen == 4) {
          for (int b = 0; b < 4; ++b) {
            xm[3 * b] = P[b][0];
            xm[3 * b + 1] = P[b][1];
            xm[3 * b + 2] = -delta;
          }
          memcpy(pm.xm[pm.n++], xm, sizeof xm);
        } else {
          static const int split[2][3] = {{0, 1, 2}, {0, 2, 3}};
          for (int t = 0; t < 2; ++t) {
            for (int b = 0; b < 3; ++b) {
              xm[3 * b] = P[split[t][b]][0];
              xm[3 * b + 1] = P[split[t][b]][1];
              xm[3 * b + 2] = -delta;
            }
            memcpy(pm.xm[pm.n++], xm, sizeof xm);
          }
        }
      }
  }
  integrate_patch(c, xs, ns, &pm, &s);
  double dev = 0.0, total = 0.0;
  for (int j = 0; j < c->st->nen; ++j) {
    total += s.D[j];
    dev = fmax(dev, fabs(s.Msum[j] - s.D[j]));
    for (int i = 0; i < d - 1; ++i) dev = fmax(dev, fabs(s.Mx[j][i] - s.Dx[j][i]));
    dev = fmax(dev, fabs(s.gap[j] - delta * s.D[j]));
  }
  SK_CHECK(fabs(total - measure) < 1e-13);
  *sums = s;
  return dev / measure;
}

/* The sums hold for any rule (partition of unity, linear fields); the entries M_jl show the integration error:
 * segment-based entries do not change with the rule (exact), concentrated ones do. */
static double max_entry_difference(const patch_sums *a, const patch_sums *b) {
  double e = 0.0;
  for (int f = 0; f < MAX_PATCH_MASTERS; ++f)
    for (int j = 0; j < 4; ++j)
      for (int l = 0; l < 4; ++l) e = fmax(e, fabs(a->M[f][j][l] - b->M[f][j][l]));
  return e;
}

static void check_patch(void) {
  const mortar_face_type *slaves[] = {&ft_line2, &ft_tri3, &ft_quad4, &ft_quad4, &ft_tri3};
  const mortar_face_type *masters[] = {&ft_line2, &ft_tri3, &ft_quad4, &ft_tri3, &ft_quad4};
  static patch_sums s1, s2, c1;
  for (int t = 0; t < 5; ++t)
    for (int basis = 0; basis < 2; ++basis) {
      const int dim = t == 0 ? 2 : 3;
      pair_case seg = {dim, slaves[t], masters[t], (mortar_basis)basis, MODE_SEGMENTS, dim == 2 ? 2 : 7};
      const double e1 = patch_deviation(&seg, 0.01, &s1);
      seg.order = dim == 2 ? 6 : 12;
      const double e2 = patch_deviation(&seg, 0.01, &s2);
      pair_case con = {dim, slaves[t], masters[t], (mortar_basis)basis, MODE_POINTS_A, dim == 2 ? 5 : 4};
      const double e3 = patch_deviation(&con, 0.01, &c1);
      const double d_seg = max_entry_difference(&s1, &s2), d_con = max_entry_difference(&s2, &c1);
      printf("  patch %s/%s %s: sums %.1e %.1e %.1e; entries: segments rule a vs b %.1e, concentrated %.2e\n",
             sk_elem_name(slaves[t]->type), sk_elem_name(masters[t]->type), basis ? "dual" : "standard", e1, e2, e3,
             d_seg, d_con);
      SK_CHECK(e1 < 1e-14 && e2 < 1e-14 && e3 < 1e-14);
      SK_CHECK(d_seg < 1e-15);
      SK_CHECK(d_con > 1e-4); /* concentrated integration does not see the master kinks */
    }
}

/* ---- a rigid motion leaves D, M and the gap unchanged (the objectivity of the weighted slip rests on it) -------- */
static void check_rigid_motion(pair_case c) {
  double u[FWD_MAX], v[FWD_MAX];
  generic_configuration(&c, u);
  const double ang = 0.7, R[3][3] = {{cos(ang), -sin(ang), 0}, {sin(ang), cos(ang), 0}, {0, 0, 1}};
  const double R3[3][3] = {{1, 0, 0}, {0, cos(0.4), -sin(0.4)}, {0, sin(0.4), cos(0.4)}};
  const int d = c.dim, nodes = n_local(&c) / d, es = c.st->nen, em = c.mt ? c.mt->nen : 0;
  for (int a = 0; a < nodes; ++a) {
    double x[3] = {0, 0, 0}, y[3] = {0, 0, 0};
    for (int i = 0; i < d; ++i) x[i] = u[a * d + i];
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) {
        double Q = 0.0; /* Q = R3 R in 3D, R in 2D */
        for (int m = 0; m < 3; ++m) Q += (d == 3 ? R3[i][m] : (i == m ? 1.0 : 0.0)) * R[m][k];
        y[i] += Q * x[k];
      }
    const int is_normal = a >= es + em;
    for (int i = 0; i < d; ++i) v[a * d + i] = y[i] + (is_normal ? 0.0 : 1.5 + i);
  }
  fwd y0[TEST_MAX_OUT], y1[TEST_MAX_OUT];
  SK_CHECK(eval_pair(&c, u, 0, y0) == 0 && eval_pair(&c, v, 0, y1) == 0);
  double err = 0.0;
  for (int i = 0; i < n_outputs(&c); ++i) err = fmax(err, fabs(y0[i].v - y1[i].v));
  SK_CHECK(err < 1e-13);
}

/* ---- continuity where a clip-polygon vertex appears: a master edge crossing a slave corner ---------------------
 * The slave face (a planar trapezoid, so the inverse map and the integrand are not polynomial) has its corner
 * Q = (1, 1, 0) at the end of the edge from P = (1.2, 0, 0); the master quad's right edge crosses the line of PQ at
 * Q + s nu (nu: the edge's outward normal) at 0.2 rad to it. For s < 0 the edge runs inside the slave face and the
 * clip polygon has 4 vertices, for s > 0 it cuts PQ near Q and the polygon has a 5th vertex next to Q. Exact
 * integrals are continuous in s; the rule's over a fan about the mean of the vertices jumped by the quadrature
 * error, which stalled Newton on conforming 3D meshes (docs/plugins/mortar-dual.md, section 10). */
static void vertex_event_outputs(double s, int rule, mortar_basis basis, double *out) {
  const pair_case c = {3, &ft_quad4, &ft_quad4, basis, MODE_SEGMENTS, rule};
  const double xs[12] = {0, 0, 0, 0, 1, 0, 1, 1, 0, 1.2, 0, 0};
  double ns[12] = {0};
  for (int a = 0; a < 4; ++a) ns[3 * a + 2] = -1.0;
  const double P[2] = {1.2, 0.0}, Q[2] = {1.0, 1.0}, theta = 0.2;
  const double len = hypot(Q[0] - P[0], Q[1] - P[1]), d[2] = {(Q[0] - P[0]) / len, (Q[1] - P[1]) / len};
  const double nu[2] = {d[1], -d[0]}; /* outward: to the right of P -> Q */
  const double e[2] = {cos(theta) * d[0] - sin(theta) * d[1], sin(theta) * d[0] + cos(theta) * d[1]};
  const double X[2] = {Q[0] + s * nu[0], Q[1] + s * nu[1]};
  /* the master's right edge X - 1.5 e ... X + 0.5 e, its left edge at x = -0.4; counter-clockwise from above */
  const double xm[12] = {-0.4, X[1] - 1.5 * e[1], -0.05, X[0] - 1.5 * e[0], X[1] - 1.5 * e[1], -0.04,
                         X[0] + 0.5 * e[0], X[1] + 0.5 * e[1], -0.07, -0.4, X[1] + 0.5 * e[1], -0.05};
  mortar_pair p;
  mortar_integrals I;
  SK_CHECK(integrate_case(&c, xs, xm, ns, 0, &p, &I) == 0);
  int m = 0;
  for (int j = 0; j < 4; ++j) {
    for (int l = 0; l < 4; ++l) out[m++] = I.M[j][l].v;
    out[m++] = I.gap[j].v;
  }
}

static void check_vertex_event_continuity(void) {
  for (int basis = 0; basis < 2; ++basis)
    for (int r = 0; r < 2; ++r) {
      const int rule = r ? 6 : 3;
      double lo[20], hi[20], lo2[20], hi2[20];
      const double delta = 1e-10;
      vertex_event_outputs(-delta, rule, (mortar_basis)basis, lo);
      vertex_event_outputs(delta, rule, (mortar_basis)basis, hi);
      vertex_event_outputs(-1e-3, rule, (mortar_basis)basis, lo2);
      vertex_event_outputs(1e-3, rule, (mortar_basis)basis, hi2);
      double jump = 0.0, slope = 0.0;
      for (int i = 0; i < 20; ++i) {
        jump = fmax(jump, fabs(hi[i] - lo[i]));
        slope = fmax(slope, fabs(hi2[i] - lo2[i]) / 2e-3);
      }
      printf("  vertex event, %s basis, cell rule %d: |change| over s = +-1e-10: %.2e (slope %.2e)\n",
             basis ? "dual" : "standard", rule, jump, slope);
      SK_CHECK(jump < 1.5 * 2.0 * delta * slope + 1e-15); /* measured: 1.01 ... 1.03 times 2 delta slope */
    }
}

/* ---- sliver overlaps: the master face beside the slave face, over its edge by 1e-10 or less ----------------------
 * Faces that share an edge (a block on a base with matching nodes) overlap in slivers while Newton moves them. The
 * sliver's integrals are of the order of its area, and their derivatives of the order of its edges. A fan centre
 * that divides by the area (the area centroid) had derivatives of 1/area on the triangular slivers (measured: 8e2
 * and 6e4), and slider-3d's Newton turned linear. Checked: every derivative of M and the gap is bounded by the
 * faces' size (measured 0.83), the values by the sliver's area. */
static void check_sliver_derivatives(void) {
  const pair_case c = {3, &ft_quad4, &ft_quad4, MORTAR_DUAL, MODE_SEGMENTS, 6};
  const double xs[12] = {0, 0, 0, 0, 1, 0, 1, 1, 0, 1, 0, 0};
  double ns[12] = {0};
  for (int a = 0; a < 4; ++a) ns[3 * a + 2] = -1.0;
  /* the master's left edge from (1 - w0, 0) to (1 - w1, 1), beside the slave's right edge x = 1 */
  static const double w[3][2] = {{1e-11, 1e-11}, {1e-10, -1e-12}, {-1e-13, 1e-11}};
  for (int k = 0; k < 3; ++k) {
    const double xm[12] = {1 - w[k][0], 0, -0.01, 2, 0, -0.01, 2, 1, -0.01, 1 - w[k][1], 1, -0.01};
    mortar_pair p;
    mortar_integrals I;
    SK_CHECK(integrate_case(&c, xs, xm, ns, 1, &p, &I) == 0);
    double largest = 0.0, value = 0.0;
    for (int j = 0; j < 4; ++j) {
      for (int l = 0; l < 4; ++l) {
        value = fmax(value, fabs(I.M[j][l].v));
        for (int i = 0; i < I.M[j][l].n; ++i) largest = fmax(largest, fabs(I.M[j][l].d[i]));
      }
      for (int i = 0; i < I.gap[j].n; ++i) largest = fmax(largest, fabs(I.gap[j].d[i]));
    }
    printf("  sliver %g .. %g wide: |M| <= %.2e, largest derivative of M and the gap %.2e\n", w[k][0], w[k][1],
           value, largest);
    SK_CHECK(value > 0.0 && value <= 1.01 * fmax(fabs(w[k][0]), fabs(w[k][1]))); /* measured 1.0, 0.83, 0.83 times */
    SK_CHECK(largest < 1.0);
  }
}

/* QUAD9 faces (hex27), their own test (test_mortar_integrals_quad9: this file with MORTAR_INTEGRALS_QUAD9 = 1, about
 * 3 s of CPU): the dual basis's biorthogonality and weights; the derivatives of segments on the faces' quarters
 * (curved QUAD9 against QUAD9 and QUAD4, the plugin's rule 12) and of concentrated points, both bases. Measured
 * |derivative - FD| <= 5.0e-10. */
static void check_quad9(void) {
  /* QUAD9: a flat parallelogram with its mid-side and centre nodes in the middles, a flat trapezoid (bilinear map:
   * N_j N_k J of degree 5 per direction), the trapezoid curved by a bulge of 0.1 (J not polynomial) */
  {
    const double parallelogram[4][3] = {{0, 0, 0}, {1.3, 0.2, 0}, {1.5, 1.2, 0}, {0.2, 1.0, 0}};
    const double trapezoid[4][3] = {{0, 0, 0}, {1.3, -0.1, 0}, {1.1, 1.2, 0}, {-0.2, 0.8, 0}};
    double q9[3][9][3];
    quad9_nodes(parallelogram, 0.0, q9[0]);
    quad9_nodes(trapezoid, 0.0, q9[1]);
    quad9_nodes(trapezoid, 0.1, q9[2]);
    check_biorthogonality(&ft_quad9, &q9[0][0][0], 1e-15); /* measured 4.1e-16 */
    check_biorthogonality(&ft_quad9, &q9[1][0][0], 1e-15); /* measured 3.8e-16 */
    check_biorthogonality(&ft_quad9, &q9[2][0][0], QUAD9_CURVED_TOL);
    check_quad9_weights(&q9[0][0][0], 1);
    check_quad9_weights(&q9[2][0][0], 0);
  }
  for (int basis = 0; basis < 2; ++basis) {
    char label[96];
    const mortar_basis b = (mortar_basis)basis;
    /* QUAD9 (curved) against QUAD9 and QUAD4: segments on the quarters, the plugin's rule 12 */
    const mortar_face_type *st9[] = {&ft_quad9, &ft_quad9, &ft_quad4}, *mt9[] = {&ft_quad9, &ft_quad4, &ft_quad9};
    for (int t = 0; t < 3; ++t) {
      snprintf(label, sizeof label, "3D segments %s/%s (%s)", sk_elem_name(st9[t]->type), sk_elem_name(mt9[t]->type),
               basis ? "dual" : "standard");
      check_derivatives(label, (pair_case){3, st9[t], mt9[t], b, MODE_SEGMENTS, 12});
    }
    check_derivatives("3D points A quad9/quad9", (pair_case){3, &ft_quad9, &ft_quad9, b, MODE_POINTS_A, 3});
  }
}

/* TRI6 (tet10) and QUAD8 (hex20): the dual basis of the transformed functions N~ = T N (alpha = 1/5). int Phi_j N~_k
 * = delta_jk int N~_k against a reference rule (TRI6: the 12-point rule on 16 sub-triangles, exact to degree 6 on
 * each; QUAD8: 16 x 16 Gauss points), int N~_j / area = 2/15, 1/5 (TRI6) and 1/20, 1/5 (QUAD8: -1/12 + 2/15 and
 * (1 - 2/5) / 3) at the vertices and edges of a flat face with its mid-side nodes in the middles (a parallelogram for
 * QUAD8), and the sum of a row of D = int Phi_j N_k equal to int N~_j. */
static void check_transformed_basis(const mortar_face_type *ft, const double *x, double tol, int affine) {
  mortar_pair p;
  double ns[3 * MORTAR_MAX_NEN] = {0};
  const int nen = ft->nen, corners = nen / 2, tri = ft->type == SK_TRI6;
  mortar_pair_set(&p, 3, ft, NULL, x, NULL, ns, 0);
  mortar_basis_coeffs A;
  mortar_basis_coefficients(&p, MORTAR_DUAL_TRANSFORMED, &A);
  double T[MORTAR_MAX_NEN][MORTAR_MAX_NEN];
  SK_CHECK(mortar_transform(ft->type, T) == nen);
  /* the reference rule: points (s, t) and weights on the parameter domain */
  enum { SPLIT = 4, QUAD_POINTS = 16 };
  double rs[2 * QUAD_POINTS * QUAD_POINTS], rwt[QUAD_POINTS * QUAD_POINTS]; /* >= TRI6's 16 x 12 points */
  int nr = 0;
  if (tri) {
    const double *rxi, *rw;
    const int n12 = mortar_triangle_rule(12, &rxi, &rw);
    for (int i = 0; i < SPLIT; ++i)
      for (int j = 0; i + j < SPLIT; ++j)
        for (int up = 0; up < (i + j < SPLIT - 1 ? 2 : 1); ++up)
          for (int q = 0; q < n12; ++q, ++nr) {
            /* sub-triangle (i, j): lower with corner (i, j) / SPLIT, upper (turned) with corner (i + 1, j + 1) /
             * SPLIT */
            const double h = (up ? -1.0 : 1.0) / SPLIT;
            rs[2 * nr] = (i + up) / (double)SPLIT + h * rxi[2 * q];
            rs[2 * nr + 1] = (j + up) / (double)SPLIT + h * rxi[2 * q + 1];
            rwt[nr] = rw[q] / (SPLIT * SPLIT);
          }
  } else {
    nr = mortar_face_rule(SK_QUAD4, QUAD_POINTS, rs, rwt);
  }
  double PN[MORTAR_MAX_NEN][MORTAR_MAX_NEN] = {{0}}, intNt[MORTAR_MAX_NEN] = {0}, area = 0.0;
  for (int q = 0; q < nr; ++q) {
    fwd xq[2] = {fwd_const(rs[2 * q]), fwd_const(rs[2 * q + 1])}, N[MORTAR_MAX_NEN], a[2][3], c[3];
    mortar_shape(ft, xq, N, NULL);
    mortar_face_point(ft, p.xs, xq, NULL, a);
    fwd_cross3(a[0], a[1], c);
    const double wJ = rwt[q] * fwd_norm(3, c).v;
    double Nv[MORTAR_MAX_NEN], Nt[MORTAR_MAX_NEN], phi[MORTAR_MAX_NEN] = {0};
    for (int k = 0; k < nen; ++k) Nv[k] = N[k].v;
    mortar_transform_values(nen, T, Nv, Nt);
    for (int r = 0; r < nen; ++r)
      for (int k = 0; k < nen; ++k) phi[r] += A.coeff[r][k].v * N[k].v;
    for (int r = 0; r < nen; ++r) {
      intNt[r] += wJ * Nt[r];
      for (int k = 0; k < nen; ++k) PN[r][k] += wJ * phi[r] * Nt[k];
    }
    area += wJ;
  }
  const char *name = sk_elem_name(ft->type);
  double err = 0.0;
  for (int j = 0; j < nen; ++j)
    for (int k = 0; k < nen; ++k) err = fmax(err, fabs(PN[j][k] - (j == k ? intNt[k] : 0.0)));
  printf("  biorthogonality %s (transformed): max |int Phi_j N~_k - delta_jk int N~_k| = %.2e (area %.3f)\n", name,
         err, area);
  SK_CHECK(err < tol);
  printf("  %s weights int N~_j / area:", name);
  for (int j = 0; j < nen; ++j) printf(" %.15f", intNt[j] / area);
  printf("\n");
  for (int j = 0; j < nen; ++j) SK_CHECK(intNt[j] > 0.0);
  if (affine)
    for (int j = 0; j < nen; ++j)
      SK_CHECK_CLOSE(intNt[j] / area, j >= corners ? 1.0 / 5.0 : tri ? 2.0 / 15.0 : 1.0 / 20.0, 1e-14);
  /* the kernel's D: rows sum to int Phi_j = int N~_j */
  mortar_integrals I;
  whole_face_integrals(&p, &A, MORTAR_DUAL_TRANSFORMED, &I);
  double row_err = 0.0;
  for (int j = 0; j < nen; ++j) {
    double row = 0.0;
    for (int k = 0; k < nen; ++k) row += I.D[j][k].v;
    row_err = fmax(row_err, fabs(row - intNt[j]));
  }
  printf("  %s: max |sum_k D_jk - int N~_j| = %.2e\n", name, row_err);
  SK_CHECK(row_err < tol);
}

/* The derivatives of segments (slave st[t] against master mt[t], the triangle rule `rule`) and of concentrated points
 * on ft/ft, with the standard basis and the dual one (of the transformed functions where the slave face is ft). */
static void check_transformed_derivatives(const mortar_face_type *ft, const mortar_face_type *const *st,
                                          const mortar_face_type *const *mt, int n, int rule) {
  for (int basis = 0; basis < 2; ++basis) {
    char label[96];
    for (int t = 0; t < n; ++t) {
      const mortar_basis b = !basis ? MORTAR_STANDARD : st[t] == ft ? MORTAR_DUAL_TRANSFORMED : MORTAR_DUAL;
      snprintf(label, sizeof label, "3D segments %s/%s (%s)", sk_elem_name(st[t]->type), sk_elem_name(mt[t]->type),
               basis ? "dual" : "standard");
      check_derivatives(label, (pair_case){3, st[t], mt[t], b, MODE_SEGMENTS, rule});
    }
    snprintf(label, sizeof label, "3D points A %s/%s", sk_elem_name(ft->type), sk_elem_name(ft->type));
    check_derivatives(label, (pair_case){3, ft, ft, basis ? MORTAR_DUAL_TRANSFORMED : MORTAR_STANDARD, MODE_POINTS_A,
                                         3});
  }
}

/* TRI6 faces (tet10), their own test (test_mortar_integrals_tri6: this file with MORTAR_INTEGRALS_TRI6 = 1): the
 * transformed dual basis; the derivatives of segments on the faces' sub-triangles (curved TRI6 against TRI6 and TRI3,
 * the plugin's rule 6) and of concentrated points, both bases. Measured |derivative - FD| <= 1.7e-10; 0.7 s of CPU. */
static void check_tri6(void) {
  const double tri[3][3] = {{0, 0, 0}, {1.2, 0.1, 0.2}, {0.3, 0.9, -0.1}};
  double t6[3][6][3];
  tri6_nodes(tri, 0.0, t6[0]);
  /* flat, mid-side nodes moved within the plane (J of degree 2: the kernel's 12 points are exact) */
  memcpy(t6[1], t6[0], sizeof t6[0]);
  for (int i = 0; i < 3; ++i) {
    t6[1][3][i] += 0.08 * (tri[2][i] - t6[0][3][i]);
    t6[1][4][i] += 0.05 * (tri[0][i] - t6[0][4][i]);
  }
  tri6_nodes(tri, 0.08, t6[2]); /* curved: J not polynomial */
  check_transformed_basis(&ft_tri6, &t6[0][0][0], 1e-15, 1); /* measured 4.3e-16 */
  check_transformed_basis(&ft_tri6, &t6[1][0][0], 1e-15, 0); /* measured 4.3e-16 */
  /* the mid-side nodes 0.08 off the plane (about 8 % of an edge): the kernel's 12 points leave 2.5e-6 (sum of D's rows
   * against int N~_j: 1.1e-8) */
  check_transformed_basis(&ft_tri6, &t6[2][0][0], 3e-6, 0);
  const mortar_face_type *st6[] = {&ft_tri6, &ft_tri6, &ft_tri3}, *mt6[] = {&ft_tri6, &ft_tri3, &ft_tri6};
  check_transformed_derivatives(&ft_tri6, st6, mt6, 3, 6);
}

/* QUAD8 (hex20), its own test (test_mortar_integrals_quad8: this file with MORTAR_INTEGRALS_QUAD8 = 1): the
 * transformed dual basis; a flat slave parallelogram over a flat master larger than it (its quarters meet at the
 * serendipity map's centre: the cells tile the face, so the measure is its area and the rows of M sum to those of D);
 * the derivatives of segments on the faces' quarters (curved QUAD8 against QUAD8, QUAD4 and QUAD9, the plugin's rule
 * 12) and of concentrated points, both bases. Measured |derivative - FD| <= 9.7e-10; 3.0 s of CPU. */
static void check_quad8(void) {
  const double parallelogram[4][3] = {{0, 0, 0}, {1.3, 0.2, 0}, {1.5, 1.2, 0}, {0.2, 1.0, 0}};
  const double trapezoid[4][3] = {{0, 0, 0}, {1.3, -0.1, 0}, {1.1, 1.2, 0}, {-0.2, 0.8, 0}};
  double q8[3][8][3];
  quad8_nodes(parallelogram, 0.0, q8[0]);
  quad8_nodes(trapezoid, 0.0, q8[1]);  /* flat, bilinear map: N~_j N~_k J of degree 5 per direction */
  quad8_nodes(trapezoid, 0.08, q8[2]); /* mid-side nodes off the plane: J not polynomial */
  /* measured 1.3e-15 and 6.1e-16 (8 x 8 entries of order 0.1 summed over 64 points: round-off), 8.7e-13 with the
   * kernel's 8 x 8 points on the curved face */
  check_transformed_basis(&ft_quad8, &q8[0][0][0], 2e-15, 1);
  check_transformed_basis(&ft_quad8, &q8[1][0][0], 2e-15, 0);
  check_transformed_basis(&ft_quad8, &q8[2][0][0], 1.5e-12, 0);
  {
    /* the slave facing down (the parallelogram's corners turned round: an affine map, so the rule 12 integrates
     * Phi_j, of degree 3 in the plane, exactly; on the trapezoid's bilinear map it does not: 7.7e-10), the master 0.1
     * below it facing up */
    const double down[4][3] = {{0, 0, 0}, {0.2, 1.0, 0}, {1.5, 1.2, 0}, {1.3, 0.2, 0}};
    const double big[4][3] = {{-0.4, -0.3, -0.1}, {1.9, -0.5, -0.1}, {2.0, 1.6, -0.1}, {-0.3, 1.5, -0.1}};
    double xs[8][3], ns[3 * MORTAR_MAX_NEN] = {0};
    quad8_nodes(down, 0.0, xs);
    for (int a = 0; a < 8; ++a) ns[3 * a + 2] = -1.0;
    mortar_pair p;
    mortar_basis_coeffs A;
    mortar_integrals I;
    mortar_pair_set(&p, 3, &ft_quad8, &ft_quad4, &xs[0][0], &big[0][0], ns, 0);
    mortar_basis_coefficients(&p, MORTAR_DUAL_TRANSFORMED, &A);
    whole_face_integrals(&p, &A, MORTAR_DUAL_TRANSFORMED, &I);
    SK_CHECK(mortar_segments_3d(&p, &A, MORTAR_DUAL_TRANSFORMED, 12, &I) == 1);
    double area = 0.0, row_err = 0.0, gap_err = 0.0;
    for (int j = 0; j < 8; ++j) {
      double d = 0.0, m = 0.0;
      for (int k = 0; k < 8; ++k) d += I.D[j][k].v;
      for (int l = 0; l < 4; ++l) m += I.M[j][l].v;
      area += d;
      row_err = fmax(row_err, fabs(d - m));
      gap_err = fmax(gap_err, fabs(I.gap[j].v - 0.1 * d));
    }
    printf("  quad8 over a flat quad4: measure %.15f (area %.15f, %d cells), max |sum_l M_jl - sum_k D_jk| = %.2e, "
           "max |gap_j - 0.1 int Phi_j| = %.2e\n", I.measure, area, I.n_cells, row_err, gap_err);
    /* measured: measure 2.5e-15 of the area (16 cells summed), rows 1.0e-15, gaps 1.1e-16 */
    SK_CHECK_CLOSE(I.measure, area, 5e-15 * area);
    SK_CHECK(row_err < 2e-15);
    SK_CHECK(gap_err < 1e-15);
  }
  const mortar_face_type *st8[] = {&ft_quad8, &ft_quad8, &ft_quad4, &ft_quad8};
  const mortar_face_type *mt8[] = {&ft_quad8, &ft_quad4, &ft_quad8, &ft_quad9};
  check_transformed_derivatives(&ft_quad8, st8, mt8, 4, 12);
}

int main(void) {
  test_face_types();
  if (MORTAR_INTEGRALS_TRI6) {
    check_tri6();
    return sk_test_finish("test_mortar_integrals_tri6");
  }
  if (MORTAR_INTEGRALS_QUAD8) {
    check_quad8();
    return sk_test_finish("test_mortar_integrals_quad8");
  }
  if (MORTAR_INTEGRALS_QUAD9) {
    check_quad9();
    return sk_test_finish("test_mortar_integrals_quad9");
  }
  check_quadrature();
  const double line[] = {0.1, 0.2, 0, 1.3, 0.7, 0};
  const double tri[] = {0, 0, 0, 1.2, 0.1, 0.2, 0.3, 0.9, -0.1};
  const double quad[] = {0, 0, 0, 1.3, -0.1, 0.0, 1.1, 1.2, 0.0, -0.2, 0.8, 0};
  const double warped[] = {0, 0, 0, 1.3, -0.1, 0.1, 1.1, 1.2, 0.3, -0.2, 0.8, 0};
  check_biorthogonality(&ft_line2, line, 1e-15);
  check_biorthogonality(&ft_tri3, tri, 1e-15);
  check_biorthogonality(&ft_quad4, quad, 1e-15);
  check_biorthogonality(&ft_quad4, warped, 3e-6); /* measured 2.1e-6 (face area 1.4) */
  /* LINE3 (gmsh order: ends, middle): straight with the middle node in the middle, straight with it moved by 10 % of
   * the length (a distorted parametrisation: N_j N_k J is not polynomial), a curved arc (30 degrees) */
  const double line3_straight[] = {0.1, 0.2, 0, 1.3, 0.7, 0, 0.7, 0.45, 0};
  const double line3_distorted[] = {0.1, 0.2, 0, 1.3, 0.7, 0, 0.82, 0.5, 0};
  double line3_arc[9];
  for (int a = 0; a < 3; ++a) {
    const double angle = (a == 2 ? 0.0 : a == 0 ? -1.0 : 1.0) * 3.14159265358979323846 / 12.0;
    line3_arc[3 * a] = 2.0 * sin(angle);
    line3_arc[3 * a + 1] = 2.0 * cos(angle);
    line3_arc[3 * a + 2] = 0.0;
  }
  check_biorthogonality(&ft_line3, line3_straight, 1e-15);
  check_biorthogonality(&ft_line3, line3_distorted, 1e-15); /* measured 3.9e-16 */
  check_biorthogonality(&ft_line3, line3_arc, 1e-15);       /* measured 1.5e-16 with the kernel's 10 points */
  check_patch();
  check_vertex_event_continuity();
  check_sliver_derivatives();

  const mortar_face_type *st3[] = {&ft_tri3, &ft_quad4, &ft_quad4, &ft_tri3};
  const mortar_face_type *mt3[] = {&ft_tri3, &ft_quad4, &ft_tri3, &ft_quad4};
  for (int basis = 0; basis < 2; ++basis) {
    char label[96];
    const mortar_basis b = (mortar_basis)basis;
    /* 2D pairs: slave, master, segment rule (LINE3: the plugin's default 5); points on LINE2 and LINE3 pairs */
    const struct { const mortar_face_type *s, *m; int segment_rule, points; } pairs2d[] = {
        {&ft_line2, &ft_line2, 3, 1}, {&ft_line3, &ft_line3, 5, 1}, {&ft_line3, &ft_line2, 5, 0}};
    for (int t = 0; t < 3; ++t) {
      const char *s_name = sk_elem_name(pairs2d[t].s->type), *m_name = sk_elem_name(pairs2d[t].m->type);
      snprintf(label, sizeof label, "2D segments %s/%s (%s)", s_name, m_name, basis ? "dual" : "standard");
      check_derivatives(label, (pair_case){2, pairs2d[t].s, pairs2d[t].m, b, MODE_SEGMENTS, pairs2d[t].segment_rule});
      for (int mode = MODE_POINTS_A; pairs2d[t].points && mode <= MODE_POINTS_M; ++mode) {
        snprintf(label, sizeof label, "2D points %s %s/%s (%s)", mode == MODE_POINTS_A ? "A" : "M", s_name, m_name,
                 basis ? "dual" : "standard");
        check_derivatives(label, (pair_case){2, pairs2d[t].s, pairs2d[t].m, b, (pair_mode)mode, 4});
      }
    }
    check_derivatives("2D obstacle plane", (pair_case){2, &ft_line2, NULL, b, MODE_OBSTACLE_PLANE, 3});
    check_derivatives("2D obstacle circle", (pair_case){2, &ft_line2, NULL, b, MODE_OBSTACLE_SPHERE, 3});
    for (int t = 0; t < 4; ++t) {
      snprintf(label, sizeof label, "3D segments %s/%s (%s)", sk_elem_name(st3[t]->type), sk_elem_name(mt3[t]->type),
               basis ? "dual" : "standard");
      check_derivatives(label, (pair_case){3, st3[t], mt3[t], (mortar_basis)basis, MODE_SEGMENTS, 7});
      snprintf(label, sizeof label, "3D points A %s/%s", sk_elem_name(st3[t]->type), sk_elem_name(mt3[t]->type));
      check_derivatives(label, (pair_case){3, st3[t], mt3[t], (mortar_basis)basis, MODE_POINTS_A, 3});
      snprintf(label, sizeof label, "3D points M %s/%s", sk_elem_name(st3[t]->type), sk_elem_name(mt3[t]->type));
      check_derivatives(label, (pair_case){3, st3[t], mt3[t], (mortar_basis)basis, MODE_POINTS_M, 3});
    }
    check_derivatives("3D obstacle sphere quad4", (pair_case){3, &ft_quad4, NULL, b, MODE_OBSTACLE_SPHERE, 3});
    check_derivatives("3D obstacle sphere tri3", (pair_case){3, &ft_tri3, NULL, b, MODE_OBSTACLE_SPHERE, 3});
    check_rigid_motion((pair_case){2, &ft_line2, &ft_line2, (mortar_basis)basis, MODE_SEGMENTS, 3});
    check_rigid_motion((pair_case){2, &ft_line3, &ft_line3, (mortar_basis)basis, MODE_SEGMENTS, 5});
    check_rigid_motion((pair_case){3, &ft_quad4, &ft_tri3, (mortar_basis)basis, MODE_SEGMENTS, 7});
    check_rigid_motion((pair_case){3, &ft_tri3, &ft_quad4, (mortar_basis)basis, MODE_POINTS_A, 3});
  }
  return sk_test_finish("test_mortar_integrals");
}
