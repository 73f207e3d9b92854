/* Solid kernels: uniform-strain patch tests (single distorted element and multi-element patches), force vs
 * finite differences of the energy and stiffness vs finite differences of the force for every element type and
 * material, rigid rotations, inverted elements, bad input, consistent mass (total mass and inertia tensor),
 * Cauchy stress, face traction loads and areas. */
#include <stdlib.h>

#include "fe_test_util.h"
#include "sk_test.h"

static sk_material materials[SK_MAT_MODEL_COUNT];

/* Energy density of a uniform gradient F as the element sees it (Hooke: linearised strain). */
static double uniform_energy(const sk_material *mat, const double F[9]) {
  double C[9], W = 0.0;
  if (mat->model == SK_MAT_HOOKE)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) C[i * 3 + j] = F[i * 3 + j] + F[j * 3 + i] - (i == j);
  else
    right_cauchy_green(F, C);
  SK_CHECK(sk_material_energy(mat, C, &W) == SK_OK);
  return W;
}

/* Single distorted element under u = A X: W = volume * W(C); f vs dW/du and K vs df/du by central differences. */
static void check_element(sk_elem_type type, int dim, const sk_material *mat) {
  const int nen = sk_elem_nen(type), ndof = nen * dim;
  const sk_solid el = {type, dim, mat};
  double X[SK_MAX_NEN * 3], u[SK_MAX_NEN * 3], F[9], W;
  fe_distorted_element(type, dim, 0.08, X);
  fe_random_gradient(dim, 0.25, F);
  fe_linear_displacement(dim, nen, F, X, u);
  SK_CHECK(sk_solid_internal(&el, X, u, &W, NULL, NULL) == SK_OK);
  const double volume = sk_solid_volume(&el, X);
  SK_CHECK_CLOSE(W, volume * uniform_energy(mat, F), 1e-12 * fabs(W));

  /* A non-uniform finite deformation. */
  for (int i = 0; i < ndof; ++i) u[i] += 0.03 * fe_rand();
  static double K[SK_MAX_NEN * 3 * SK_MAX_NEN * 3], Kp[SK_MAX_NEN * 3 * SK_MAX_NEN * 3];
  double f[SK_MAX_NEN * 3], fp[SK_MAX_NEN * 3], fm[SK_MAX_NEN * 3];
  SK_CHECK(sk_solid_internal(&el, X, u, &W, f, K) == SK_OK);
  /* Partial outputs agree with the full call. */
  double W_only, f_only[SK_MAX_NEN * 3];
  SK_CHECK(sk_solid_internal(&el, X, u, &W_only, f_only, NULL) == SK_OK);
  SK_CHECK(sk_solid_internal(&el, X, u, NULL, NULL, Kp) == SK_OK);
  SK_CHECK(W_only == W && memcmp(f_only, f, ndof * sizeof *f) == 0 && memcmp(Kp, K, ndof * ndof * sizeof *K) == 0);
  const double h = 1e-6, fmax_abs = fe_max_abs(f, ndof), Kmax = fe_max_abs(K, ndof * ndof);
  double err_f = 0.0, err_K = 0.0, asym = 0.0;
  for (int j = 0; j < ndof; ++j) {
    double Wp, Wm;
    const double keep = u[j];
    u[j] = keep + h;
    sk_solid_internal(&el, X, u, &Wp, fp, NULL);
    u[j] = keep - h;
    sk_solid_internal(&el, X, u, &Wm, fm, NULL);
    u[j] = keep;
    err_f = fmax(err_f, fabs((Wp - Wm) / (2 * h) - f[j]) / fmax_abs);
    for (int i = 0; i < ndof; ++i) {
      err_K = fmax(err_K, fabs((fp[i] - fm[i]) / (2 * h) - K[i * ndof + j]) / Kmax);
      asym = fmax(asym, fabs(K[i * ndof + j] - K[j * ndof + i]));
    }
  }
  printf("  %dD %-6s %-9s relative FD error: f %.2e  K %.2e\n", dim, sk_elem_name(type),
         sk_material_model_names[mat->model], err_f, err_K);
  SK_CHECK(err_f < 1e-7);
  SK_CHECK(err_K < 1e-7);
  SK_CHECK(asym <= 1e-14 * Kmax);

  /* Rigid rotation (finite-strain models): no energy, no force. */
  if (mat->model != SK_MAT_HOOKE) {
    const double c = cos(0.7), s = sin(0.7);
    double R[9] = {c, -s, 0, s, c, 0, 0, 0, 1};
    if (dim == 3) { /* a rotation about a skew axis: R = Rz(0.7) Rx(0.4) */
      const double c2 = cos(0.4), s2 = sin(0.4);
      const double Rx[9] = {1, 0, 0, 0, c2, -s2, 0, s2, c2}, Rz[9] = {c, -s, 0, s, c, 0, 0, 0, 1};
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          R[i * 3 + j] = 0.0;
          for (int k = 0; k < 3; ++k) R[i * 3 + j] += Rz[i * 3 + k] * Rx[k * 3 + j];
        }
    }
    fe_linear_displacement(dim, nen, R, X, u);
    SK_CHECK(sk_solid_internal(&el, X, u, &W, f, NULL) == SK_OK);
    SK_CHECK(fabs(W) < 1e-13 * mat->mu * volume);
    SK_CHECK(fe_max_abs(f, ndof) < 1e-12 * mat->mu * volume);

    /* Inverted: a reflection. Outputs untouched. */
    double Fr[9] = {-1, 0, 0, 0, 1, 0, 0, 0, 1};
    fe_linear_displacement(dim, nen, Fr, X, u);
    for (int i = 0; i < ndof; ++i) f[i] = 42.0;
    W = 42.0;
    sk_error_clear();
    SK_CHECK(sk_solid_internal(&el, X, u, &W, f, K) == SK_ERR_INVERTED);
    SK_CHECK(strstr(sk_error_message(), "det F") != NULL);
    SK_CHECK(W == 42.0 && f[0] == 42.0 && f[ndof - 1] == 42.0);
  }
}

/* ---- multi-element patches ---------------------------------------------------------------------------------- */
enum { PATCH_CELLS = 2, LATTICE = 2 * PATCH_CELLS + 1, MAX_PATCH_NODES = LATTICE * LATTICE * LATTICE,
       MAX_PATCH_ELEMS = 6 * PATCH_CELLS * PATCH_CELLS * PATCH_CELLS };

typedef struct {
  int n_elems, nen;
  int conn[MAX_PATCH_ELEMS * SK_MAX_NEN];
  double X[MAX_PATCH_NODES * 3];
} patch;

static int lattice_id(int dim, const int *l) { return dim == 2 ? l[0] + LATTICE * l[1] : l[0] + LATTICE * (l[1] + LATTICE * l[2]); }

static double signed_volume(int dim, const double *X, const int *nodes) {
  double a[3][3];
  for (int k = 0; k < dim; ++k)
    for (int i = 0; i < dim; ++i) a[k][i] = X[nodes[k + 1] * dim + i] - X[nodes[0] * dim + i];
  if (dim == 2) return a[0][0] * a[1][1] - a[0][1] * a[1][0];
  return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
         a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
}

/* PATCH_CELLS^dim unit cells on a lattice of half-unit spacing; simplices split each cell (2 triangles, 6 Kuhn
 * tetrahedra). Every node is perturbed, so elements are distorted and quadratic edges curved. */
static void build_patch(sk_elem_type type, int dim, patch *p) {
  const int nen = sk_elem_nen(type), simplex = type == SK_TRI3 || type == SK_TET4;
  const int n_lattice = dim == 2 ? LATTICE * LATTICE : LATTICE * LATTICE * LATTICE;
  for (int n = 0; n < n_lattice; ++n) {
    int rest = n;
    for (int i = 0; i < dim; ++i) {
      p->X[n * dim + i] = 0.5 * (rest % LATTICE) + 0.06 * fe_rand();
      rest /= LATTICE;
    }
  }
  p->nen = nen;
  p->n_elems = 0;
  const int n_cells = dim == 2 ? PATCH_CELLS * PATCH_CELLS : PATCH_CELLS * PATCH_CELLS * PATCH_CELLS;
  for (int cell = 0; cell < n_cells; ++cell) {
    int origin[3] = {0, 0, 0}, rest = cell;
    for (int i = 0; i < dim; ++i) origin[i] = 2 * (rest % PATCH_CELLS), rest /= PATCH_CELLS;
    if (!simplex) {
      const double *xi = sk_elem_node_coords(type);
      int *conn = p->conn + p->n_elems++ * nen;
      for (int a = 0; a < nen; ++a) {
        int l[3];
        for (int i = 0; i < dim; ++i) l[i] = origin[i] + (int)xi[a * dim + i] + 1;
        conn[a] = lattice_id(dim, l);
      }
      continue;
    }
    if (dim == 2) {
      int c[4], l[3];
      static const int corner[4][2] = {{0, 0}, {2, 0}, {2, 2}, {0, 2}};
      for (int k = 0; k < 4; ++k) l[0] = origin[0] + corner[k][0], l[1] = origin[1] + corner[k][1], c[k] = lattice_id(2, l);
      const int tris[2][3] = {{c[0], c[1], c[2]}, {c[0], c[2], c[3]}};
      for (int t = 0; t < 2; ++t) memcpy(p->conn + p->n_elems++ * 3, tris[t], sizeof tris[t]);
      continue;
    }
    static const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    for (int t = 0; t < 6; ++t) {
      int l[3] = {origin[0], origin[1], origin[2]};
      int *conn = p->conn + p->n_elems++ * 4;
      conn[0] = lattice_id(3, l);
      for (int k = 0; k < 3; ++k) {
        l[perms[t][k]] += 2;
        conn[k + 1] = lattice_id(3, l);
      }
      if (signed_volume(3, p->X, conn) < 0.0) {
        const int swap = conn[1];
        conn[1] = conn[2], conn[2] = swap;
      }
    }
  }
}

static int patch_interior(int dim, int node) {
  for (int i = 0; i < dim; ++i, node /= LATTICE)
    if (node % LATTICE == 0 || node % LATTICE == LATTICE - 1) return 0;
  return 1;
}

/* u = A X on all nodes: interior nodal forces vanish (uniform stress is in equilibrium), the total force
 * vanishes, and the energy is volume * W(C). */
static void check_patch(sk_elem_type type, int dim, const sk_material *mat) {
  static patch p;
  build_patch(type, dim, &p);
  const int n_nodes = dim == 2 ? LATTICE * LATTICE : LATTICE * LATTICE * LATTICE;
  const sk_solid el = {type, dim, mat};
  double F[9], u_all[MAX_PATCH_NODES * 3], f_all[MAX_PATCH_NODES * 3] = {0}, W_total = 0.0, volume = 0.0;
  fe_random_gradient(dim, 0.25, F);
  fe_linear_displacement(dim, n_nodes, F, p.X, u_all);
  for (int e = 0; e < p.n_elems; ++e) {
    double Xe[SK_MAX_NEN * 3], ue[SK_MAX_NEN * 3], fe[SK_MAX_NEN * 3], We;
    for (int a = 0; a < p.nen; ++a)
      for (int i = 0; i < dim; ++i) {
        Xe[a * dim + i] = p.X[p.conn[e * p.nen + a] * dim + i];
        ue[a * dim + i] = u_all[p.conn[e * p.nen + a] * dim + i];
      }
    SK_CHECK(sk_solid_internal(&el, Xe, ue, &We, fe, NULL) == SK_OK);
    W_total += We;
    volume += sk_solid_volume(&el, Xe);
    for (int a = 0; a < p.nen; ++a)
      for (int i = 0; i < dim; ++i) f_all[p.conn[e * p.nen + a] * dim + i] += fe[a * dim + i];
  }
  const double fscale = fe_max_abs(f_all, n_nodes * dim);
  double interior = 0.0, total[3] = {0, 0, 0};
  int n_interior = 0, used[MAX_PATCH_NODES] = {0};
  for (int k = 0; k < p.n_elems * p.nen; ++k) used[p.conn[k]] = 1;
  for (int n = 0; n < n_nodes; ++n) {
    for (int i = 0; i < dim; ++i) total[i] += f_all[n * dim + i];
    if (!used[n] || !patch_interior(dim, n)) continue;
    ++n_interior;
    for (int i = 0; i < dim; ++i) interior = fmax(interior, fabs(f_all[n * dim + i]));
  }
  printf("  patch %dD %-6s %-9s %2d elements, %2d interior nodes: max interior |f| / max |f| = %.1e\n", dim,
         sk_elem_name(type), sk_material_model_names[mat->model], p.n_elems, n_interior, interior / fscale);
  SK_CHECK(n_interior >= 1);
  SK_CHECK(fscale > 1e-3);
  SK_CHECK(interior < 1e-12 * fscale);
  for (int i = 0; i < dim; ++i) SK_CHECK(fabs(total[i]) < 1e-12 * fscale);
  SK_CHECK_CLOSE(W_total, volume * uniform_energy(mat, F), 1e-12 * fabs(W_total));
}

/* ---- mass ----------------------------------------------------------------------------------------------------- */
static const double gl5_x[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831, 0.9061798459386640};
static const double gl5_w[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889, 0.4786286704993665,
                                0.2369268850561891};

/* integral X X^T and volume over a tensor-product element by 5-point Gauss (exact for the test elements). */
static void tensor_inertia(sk_elem_type type, int dim, const double *X, double *inertia, double *volume) {
  const int nen = sk_elem_nen(type), n = dim == 2 ? 25 : 125;
  memset(inertia, 0, 9 * sizeof *inertia);
  *volume = 0.0;
  for (int q = 0; q < n; ++q) {
    double xi[3], w = 1.0, N[SK_MAX_NEN], dN[SK_MAX_NEN * 3], J[9] = {0}, x[3] = {0, 0, 0};
    for (int k = 0, rest = q; k < dim; ++k, rest /= 5) xi[k] = gl5_x[rest % 5], w *= gl5_w[rest % 5];
    sk_elem_shape(type, xi, N, dN);
    for (int a = 0; a < nen; ++a)
      for (int i = 0; i < dim; ++i) {
        x[i] += N[a] * X[a * dim + i];
        for (int k = 0; k < dim; ++k) J[i * 3 + k] += X[a * dim + i] * dN[a * dim + k];
      }
    const double det = dim == 2 ? J[0] * J[4] - J[1] * J[3]
                                : J[0] * (J[4] * J[8] - J[5] * J[7]) - J[1] * (J[3] * J[8] - J[5] * J[6]) +
                                      J[2] * (J[3] * J[7] - J[4] * J[6]);
    *volume += w * det;
    for (int i = 0; i < dim; ++i)
      for (int j = 0; j < dim; ++j) inertia[i * 3 + j] += w * det * x[i] * x[j];
  }
}

static void check_mass(sk_elem_type type, int dim) {
  const int nen = sk_elem_nen(type);
  sk_material mat = materials[SK_MAT_SVK];
  mat.density = 2.5;
  const sk_solid el = {type, dim, &mat};
  double X[SK_MAX_NEN * 3], M[SK_MAX_NEN * SK_MAX_NEN], exact[9] = {0}, volume;
  fe_distorted_element(type, dim, 0.1, X);
  SK_CHECK(sk_solid_mass(&el, X, M) == SK_OK);
  if (type == SK_TET4 || type == SK_TRI3) {
    /* integral X X^T over a simplex = |T| / ((d+1)(d+2)) (sum X_a X_a^T + (sum X_a)(sum X_a)^T). */
    volume = sk_solid_volume(&el, X);
    double sum[3] = {0, 0, 0};
    for (int a = 0; a < nen; ++a)
      for (int i = 0; i < dim; ++i) sum[i] += X[a * dim + i];
    for (int i = 0; i < dim; ++i)
      for (int j = 0; j < dim; ++j) {
        double s = sum[i] * sum[j];
        for (int a = 0; a < nen; ++a) s += X[a * dim + i] * X[a * dim + j];
        exact[i * 3 + j] = volume * s / ((dim + 1) * (dim + 2));
      }
  } else {
    tensor_inertia(type, dim, X, exact, &volume);
  }
  double total = 0.0, inertia[9] = {0}, asym = 0.0;
  for (int a = 0; a < nen; ++a)
    for (int b = 0; b < nen; ++b) {
      total += M[a * nen + b];
      asym = fmax(asym, fabs(M[a * nen + b] - M[b * nen + a]));
      for (int i = 0; i < dim; ++i)
        for (int j = 0; j < dim; ++j) inertia[i * 3 + j] += M[a * nen + b] * X[a * dim + i] * X[b * dim + j];
    }
  SK_CHECK_CLOSE(total, mat.density * volume, 1e-13 * mat.density * volume);
  SK_CHECK_CLOSE(sk_solid_volume(&el, X), volume, 1e-13 * volume);
  SK_CHECK(asym == 0.0);
  double err = 0.0;
  for (int i = 0; i < 9; ++i) err = fmax(err, fabs(inertia[i] - mat.density * exact[i]));
  const double scale = mat.density * fe_max_abs(exact, 9);
  printf("  mass %-6s total %.12f (rho V %.12f), inertia relative error %.1e\n", sk_elem_name(type), total,
         mat.density * volume, err / scale);
  SK_CHECK(err < 1e-13 * scale);
}

/* ---- Cauchy stress ---------------------------------------------------------------------------------------------- */
static void check_cauchy(void) {
  /* Neo-Hooke under a uniform F on a distorted hex27: sigma = (mu (b - I) + p(J) I) / J with the volumetric
   * p = lambda ln J (Bonet) or lambda/2 (J^2 - 1) (Ciarlet). */
  for (int m = SK_MAT_NEOHOOKE_BONET; m <= SK_MAT_NEOHOOKE_CIARLET; ++m) {
    const sk_material *nh = &materials[m];
    const sk_solid el = {SK_HEX27, 3, nh};
    double X[27 * 3], u[27 * 3], F[9], sigma[9];
    fe_distorted_element(SK_HEX27, 3, 0.05, X);
    fe_random_gradient(3, 0.25, F);
    fe_linear_displacement(3, 27, F, X, u);
    SK_CHECK(sk_solid_cauchy(&el, X, u, sigma) == SK_OK);
    const double J = F[0] * (F[4] * F[8] - F[5] * F[7]) - F[1] * (F[3] * F[8] - F[5] * F[6]) +
                     F[2] * (F[3] * F[7] - F[4] * F[6]);
    const double p = m == SK_MAT_NEOHOOKE_BONET ? nh->lambda * log(J) : 0.5 * nh->lambda * (J * J - 1.0);
    double err = 0.0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        double b = 0.0;
        for (int k = 0; k < 3; ++k) b += F[i * 3 + k] * F[j * 3 + k];
        const double expected = (nh->mu * (b - (i == j)) + p * (i == j)) / J;
        err = fmax(err, fabs(sigma[i * 3 + j] - expected));
      }
    SK_CHECK(err < 1e-12 * nh->mu);
  }
  /* Plane-strain Hooke on a quad4: sigma = lambda tr(eps) I + 2 mu eps, sigma_zz = lambda tr(eps). */
  const sk_material *hooke = &materials[SK_MAT_HOOKE];
  const sk_solid el2 = {SK_QUAD4, 2, hooke};
  double X2[8], u2[8], F2[9], sigma[9];
  fe_distorted_element(SK_QUAD4, 2, 0.1, X2);
  fe_random_gradient(2, 0.01, F2);
  fe_linear_displacement(2, 4, F2, X2, u2);
  SK_CHECK(sk_solid_cauchy(&el2, X2, u2, sigma) == SK_OK);
  const double tr = F2[0] + F2[4] - 2.0;
  SK_CHECK_CLOSE(sigma[0], hooke->lambda * tr + 2 * hooke->mu * (F2[0] - 1.0), 1e-12 * hooke->mu);
  SK_CHECK_CLOSE(sigma[1], hooke->mu * (F2[1] + F2[3]), 1e-12 * hooke->mu);
  SK_CHECK_CLOSE(sigma[3], sigma[1], 1e-15);
  SK_CHECK_CLOSE(sigma[8], hooke->lambda * tr, 1e-12 * hooke->mu);
  SK_CHECK(sigma[2] == 0.0 && sigma[5] == 0.0);
}

/* ---- faces -------------------------------------------------------------------------------------------------------- */
static void check_faces(void) {
  /* A flat quad9 (side 2, in-plane perturbation of mid/centre nodes keeps the square) rotated into 3D. */
  const double c = cos(0.5), s = sin(0.5);
  const double R[9] = {c, 0, s, 0, 1, 0, -s, 0, c};
  const double *xi = sk_elem_node_coords(SK_QUAD9);
  double X[9 * 3], t[3] = {1.0, -2.0, 0.5}, f[9 * 3];
  for (int a = 0; a < 9; ++a) {
    double p[3] = {xi[a * 2], xi[a * 2 + 1], 0.0};
    if (a == 4 || a == 6) p[0] += 0.2 * fe_rand(); /* mid-nodes slide along their (straight) edges */
    if (a == 5 || a == 7) p[1] += 0.2 * fe_rand();
    if (a == 8) p[0] += 0.2 * fe_rand(), p[1] += 0.2 * fe_rand();
    for (int i = 0; i < 3; ++i) X[a * 3 + i] = R[i * 3] * p[0] + R[i * 3 + 1] * p[1] + R[i * 3 + 2] * p[2];
  }
  SK_CHECK_CLOSE(sk_face_area(SK_QUAD9, 3, X), 4.0, 1e-14);
  sk_face_traction(SK_QUAD9, 3, X, t, f);
  for (int i = 0; i < 3; ++i) {
    double sum = 0.0;
    for (int a = 0; a < 9; ++a) sum += f[a * 3 + i];
    SK_CHECK_CLOSE(sum, 4.0 * t[i], 1e-14);
  }
  /* Flat unit square quad4: a quarter of the load per node. Triangle: area from the cross product. */
  const double Xq[12] = {0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
  sk_face_traction(SK_QUAD4, 3, Xq, t, f);
  for (int a = 0; a < 4; ++a)
    for (int i = 0; i < 3; ++i) SK_CHECK_CLOSE(f[a * 3 + i], 0.25 * t[i], 1e-15);
  const double Xt[9] = {0, 0, 0, 2, 0, 0, 0, 0, 3};
  SK_CHECK_CLOSE(sk_face_area(SK_TRI3, 3, Xt), 3.0, 1e-15);
  sk_face_traction(SK_TRI3, 3, Xt, t, f);
  for (int a = 0; a < 3; ++a) SK_CHECK_CLOSE(f[a * 3], 1.0, 1e-15);
  /* 2D lines: a straight line3 with a shifted mid-node still has length 5; line2 splits the load evenly. */
  const double Xl3[6] = {0, 0, 3, 4, 0.3 * 3, 0.3 * 4};
  SK_CHECK_CLOSE(sk_face_area(SK_LINE3, 2, Xl3), 5.0, 1e-14);
  sk_face_traction(SK_LINE3, 2, Xl3, t, f);
  SK_CHECK_CLOSE(f[0] + f[2] + f[4], 5.0 * t[0], 1e-14);
  const double Xl2[4] = {0, 0, 3, 4};
  sk_face_traction(SK_LINE2, 2, Xl2, t, f);
  SK_CHECK_CLOSE(f[1], 2.5 * t[1], 1e-15);
  SK_CHECK_CLOSE(f[3], 2.5 * t[1], 1e-15);
  /* Bad input: zero load and zero area rather than a crash. */
  f[0] = 42.0;
  sk_face_traction(SK_HEX8, 3, Xq, t, f);
  SK_CHECK(f[0] == 0.0);
  SK_CHECK(sk_face_area(SK_QUAD4, 5, Xq) == 0.0);
  SK_CHECK(sk_face_area(SK_QUAD4, 3, NULL) == 0.0);
}

static void check_bad_input(void) {
  double X[8 * 3], u[8 * 3] = {0}, f[8 * 3], M[64];
  fe_distorted_element(SK_HEX8, 3, 0.05, X);
  sk_solid el = {SK_HEX8, 4, &materials[SK_MAT_SVK]};
  SK_CHECK(sk_solid_internal(&el, X, u, NULL, f, NULL) == SK_ERR_INPUT);
  el.dim = 2;
  SK_CHECK(sk_solid_internal(&el, X, u, NULL, f, NULL) == SK_ERR_INPUT);
  SK_CHECK(strstr(sk_error_message(), "hex8") != NULL);
  el.dim = 3, el.mat = NULL;
  SK_CHECK(sk_solid_internal(&el, X, u, NULL, f, NULL) == SK_ERR_INPUT);
  SK_CHECK(sk_solid_mass(&el, X, M) == SK_ERR_INPUT);
  el.mat = &materials[SK_MAT_SVK], el.type = SK_LINE2;
  SK_CHECK(sk_solid_internal(&el, X, u, NULL, f, NULL) == SK_ERR_INPUT);
  SK_CHECK(sk_solid_volume(&el, X) == 0.0);
  el.type = (sk_elem_type)99;
  SK_CHECK(sk_solid_internal_midpoint(&el, X, u, u, f, NULL) == SK_ERR_INPUT);
  el.type = SK_HEX8;
  SK_CHECK(sk_solid_internal(&el, X, NULL, NULL, f, NULL) == SK_ERR_INPUT);
  /* Inside-out reference element (mirrored, so every Jacobian is negative): a mesh error, not an inverted step. */
  double Xm[8 * 3];
  for (int a = 0; a < 8; ++a)
    for (int i = 0; i < 3; ++i) Xm[a * 3 + i] = (i == 0 ? -1.0 : 1.0) * X[a * 3 + i];
  SK_CHECK(sk_solid_internal(&el, Xm, u, NULL, f, NULL) == SK_ERR_INPUT);
  SK_CHECK(strstr(sk_error_message(), "det J") != NULL);
  SK_CHECK(sk_solid_mass(&el, Xm, M) == SK_ERR_INPUT);
}

int main(void) {
  for (int m = SK_MAT_HOOKE; m < SK_MAT_MODEL_COUNT; ++m)
    if (sk_material_init(&materials[m], (sk_material_model)m, 100.0, 0.3, 1.0) != SK_OK) return 1;
  for (int dim = 2; dim <= 3; ++dim)
    for (int t = 0; t < 3; ++t)
      for (int m = 0; m < SK_MAT_MODEL_COUNT; ++m) {
        const sk_elem_type type = dim == 2 ? fe_solids_2d[t] : fe_solids_3d[t];
        check_element(type, dim, &materials[m]);
        check_patch(type, dim, &materials[m]);
      }
  for (int t = 0; t < 3; ++t) {
    check_mass(fe_solids_2d[t], 2);
    check_mass(fe_solids_3d[t], 3);
  }
  check_cauchy();
  check_faces();
  check_bad_input();
  return sk_test_finish("fe_solid");
}
