/* Element catalogue: shape functions (partition of unity, Kronecker property, linear and, for quadratic elements,
 * quadratic completeness), derivative
 * and Hessian finite-difference checks, quadrature exactness, face tables (on the boundary, outward, and the
 * divergence theorem reproducing the element volume). */
#include "fe_test_util.h"
#include "sk_test.h"

/* A random point inside the reference element. */
static void random_point(sk_elem_type type, double *xi) {
  const int pdim = sk_elem_pdim(type);
  if (sk_elem_is_simplex(type)) {
    double sum = 0.0;
    for (int k = 0; k < pdim; ++k) sum += (xi[k] = 0.5 * (fe_rand() + 1.0));
    for (int k = 0; k < pdim; ++k) xi[k] *= 0.9 / fmax(sum, 0.9); /* inside the simplex */
  } else {
    for (int k = 0; k < pdim; ++k) xi[k] = 0.95 * fe_rand();
  }
}

static void check_shapes(sk_elem_type type) {
  const int nen = sk_elem_nen(type), pdim = sk_elem_pdim(type);
  const double *node_xi = sk_elem_node_coords(type);
  double N[SK_MAX_NEN], dN[SK_MAX_NEN * 3], ddN[SK_MAX_NEN * 9];
  /* Kronecker property at the nodes. */
  for (int b = 0; b < nen; ++b) {
    sk_elem_shape(type, node_xi + b * pdim, N, NULL);
    for (int a = 0; a < nen; ++a) SK_CHECK_CLOSE(N[a], a == b ? 1.0 : 0.0, 1e-14);
  }
  for (int trial = 0; trial < 5; ++trial) {
    double xi[3] = {0, 0, 0};
    random_point(type, xi);
    sk_elem_shape(type, xi, N, dN);
    sk_elem_shape_hessian(type, xi, ddN);
    /* Partition of unity and linear completeness: sum N_a xi_a = xi, so sum dN_a/dxi_k xi_a,l = delta_kl. */
    double sum = 0.0, dsum[3] = {0, 0, 0}, ddsum[9] = {0};
    for (int a = 0; a < nen; ++a) {
      sum += N[a];
      for (int k = 0; k < pdim; ++k) dsum[k] += dN[a * pdim + k];
      for (int kl = 0; kl < pdim * pdim; ++kl) ddsum[kl] += ddN[a * pdim * pdim + kl];
    }
    SK_CHECK_CLOSE(sum, 1.0, 1e-14);
    for (int k = 0; k < pdim; ++k) SK_CHECK_CLOSE(dsum[k], 0.0, 1e-13);
    for (int kl = 0; kl < pdim * pdim; ++kl) SK_CHECK_CLOSE(ddsum[kl], 0.0, 1e-13);
    for (int l = 0; l < pdim; ++l) {
      double x = 0.0;
      for (int a = 0; a < nen; ++a) x += N[a] * node_xi[a * pdim + l];
      SK_CHECK_CLOSE(x, xi[l], 1e-14);
      for (int k = 0; k < pdim; ++k) {
        double g = 0.0;
        for (int a = 0; a < nen; ++a) g += dN[a * pdim + k] * node_xi[a * pdim + l];
        SK_CHECK_CLOSE(g, k == l ? 1.0 : 0.0, 1e-13);
      }
    }
    /* Central differences: dN from N, ddN from dN (polynomials: truncation ~h^2, so 1e-8 is tight). */
    const double h = 1e-5;
    double worst_d = 0.0, worst_dd = 0.0, hess_sym = 0.0;
    for (int k = 0; k < pdim; ++k) {
      double xp[3], xm[3], Np[SK_MAX_NEN], Nm[SK_MAX_NEN], dNp[SK_MAX_NEN * 3], dNm[SK_MAX_NEN * 3];
      memcpy(xp, xi, sizeof xp), memcpy(xm, xi, sizeof xm);
      xp[k] += h, xm[k] -= h;
      sk_elem_shape(type, xp, Np, dNp);
      sk_elem_shape(type, xm, Nm, dNm);
      for (int a = 0; a < nen; ++a) {
        worst_d = fmax(worst_d, fabs((Np[a] - Nm[a]) / (2 * h) - dN[a * pdim + k]));
        for (int l = 0; l < pdim; ++l) {
          const double fd = (dNp[a * pdim + l] - dNm[a * pdim + l]) / (2 * h);
          worst_dd = fmax(worst_dd, fabs(fd - ddN[(a * pdim + l) * pdim + k]));
          hess_sym = fmax(hess_sym, fabs(ddN[(a * pdim + l) * pdim + k] - ddN[(a * pdim + k) * pdim + l]));
        }
      }
    }
    SK_CHECK(worst_d < 1e-8);
    SK_CHECK(worst_dd < 1e-8);
    SK_CHECK(hess_sym < 1e-14);
    /* Quadratic elements reproduce every quadratic polynomial (serendipity ones too): sum N_a p(xi_a) = p(xi) for
     * the monomials xi_k xi_l, which catches a wrong edge function or a mid-node out of place. */
    if (sk_elem_order(type) == 2) {
      double worst_q = 0.0;
      for (int k = 0; k < pdim; ++k)
        for (int l = k; l < pdim; ++l) {
          double p = 0.0;
          for (int a = 0; a < nen; ++a) p += N[a] * node_xi[a * pdim + k] * node_xi[a * pdim + l];
          worst_q = fmax(worst_q, fabs(p - xi[k] * xi[l]));
        }
      SK_CHECK(worst_q < 1e-14);
    }
    if (trial == 0) printf("  %-6s FD error: dN %.2e  ddN %.2e\n", sk_elem_name(type), worst_d, worst_dd);
  }
}

static double factorial(int n) { return n <= 1 ? 1.0 : n * factorial(n - 1); }

/* Exact integral of xi^p eta^q zeta^r over the reference element. */
static double exact_monomial(sk_elem_type type, const int *e) {
  const int pdim = sk_elem_pdim(type);
  if (sk_elem_is_simplex(type)) {
    double num = 1.0;
    int total = 0;
    for (int k = 0; k < pdim; ++k) num *= factorial(e[k]), total += e[k];
    return num / factorial(total + pdim);
  }
  double value = 1.0;
  for (int k = 0; k < pdim; ++k) value *= e[k] % 2 ? 0.0 : 2.0 / (e[k] + 1);
  return value;
}

static void check_quadrature(sk_elem_type type) {
  const int pdim = sk_elem_pdim(type);
  int n;
  const double *xi, *w;
  sk_elem_quadrature(type, &n, &xi, &w);
  SK_CHECK(n >= 1 && n <= SK_MAX_QP);
  const int simplex = sk_elem_is_simplex(type);
  const int quadratic = sk_elem_order(type) == 2;
  /* Gauss with 2 (3) points per direction: every monomial of degree <= 3 (5) per direction; simplices (tri6 and
   * tet10 too): total degree <= 2. One degree more must fail somewhere (the rule is no richer than documented). */
  const int max_deg = simplex ? 2 : quadratic ? 5 : 3;
  int e[3] = {0, 0, 0}, exact_all = 1, beyond_exact = 1;
  const int range = max_deg + 2;
  const int count = pdim == 1 ? range : pdim == 2 ? range * range : range * range * range;
  for (int m = 0; m < count; ++m) {
    int rest = m, total = 0, worst = 0;
    for (int k = 0; k < pdim; ++k) e[k] = rest % range, rest /= range, total += e[k], worst = e[k] > worst ? e[k] : worst;
    double sum = 0.0;
    for (int q = 0; q < n; ++q) {
      double v = w[q];
      for (int k = 0; k < pdim; ++k) v *= pow(xi[q * pdim + k], e[k]);
      sum += v;
    }
    const int in_range = simplex ? total <= max_deg : worst <= max_deg;
    const int exact = fabs(sum - exact_monomial(type, e)) < 1e-14;
    if (in_range) exact_all &= exact;
    if ((simplex ? total == max_deg + 1 : worst == max_deg + 1) && !exact) beyond_exact = 0;
  }
  SK_CHECK(exact_all);
  SK_CHECK(!beyond_exact);
  double volume = 0.0;
  for (int q = 0; q < n; ++q) volume += w[q];
  const double ref_volume = simplex ? (pdim == 2 ? 0.5 : 1.0 / 6.0) : pow(2.0, pdim);
  SK_CHECK_CLOSE(volume, ref_volume, 1e-15);
}

/* Face tables: face nodes on one boundary facet of the reference element, normal a1 x a2 (2D: (t_y, -t_x))
 * pointing away from the element centre, and on a distorted element (1/dim) sum_faces integral X.n dA equals
 * the element volume (divergence theorem; wrong mid-node order or orientation breaks it). */
static void face_normal(sk_elem_type face_type, int dim, const double *Xf, const double *s, double *n) {
  const int fnen = sk_elem_nen(face_type), fp = sk_elem_pdim(face_type);
  double dN[SK_MAX_NEN * 2], a[2][3] = {{0}};
  sk_elem_shape(face_type, s, NULL, dN);
  for (int b = 0; b < fnen; ++b)
    for (int k = 0; k < fp; ++k)
      for (int i = 0; i < dim; ++i) a[k][i] += dN[b * fp + k] * Xf[b * dim + i];
  if (dim == 2) {
    n[0] = a[0][1], n[1] = -a[0][0];
  } else {
    n[0] = a[0][1] * a[1][2] - a[0][2] * a[1][1];
    n[1] = a[0][2] * a[1][0] - a[0][0] * a[1][2];
    n[2] = a[0][0] * a[1][1] - a[0][1] * a[1][0];
  }
}

static void check_faces(sk_elem_type type) {
  const int dim = sk_elem_pdim(type), nen = sk_elem_nen(type);
  sk_elem_type face_type;
  const int *faces;
  int fnen;
  const int nf = sk_elem_faces(type, &face_type, &faces, &fnen);
  SK_CHECK(nf == (dim == 2 ? sk_elem_corners(type) : sk_elem_is_simplex(type) ? 4 : 6));
  SK_CHECK(fnen == sk_elem_nen(face_type));
  SK_CHECK(sk_elem_pdim(face_type) == dim - 1);
  const double *node_xi = sk_elem_node_coords(type);
  double centre[3] = {0, 0, 0};
  for (int a = 0; a < nen; ++a)
    for (int k = 0; k < dim; ++k) centre[k] += node_xi[a * dim + k] / nen;
  for (int f = 0; f < nf; ++f) {
    const int *fn = faces + f * fnen;
    double Xf[SK_MAX_NEN * 3], fc[3] = {0, 0, 0}, n[3];
    for (int b = 0; b < fnen; ++b)
      for (int k = 0; k < dim; ++k) {
        Xf[b * dim + k] = node_xi[fn[b] * dim + k];
        fc[k] += Xf[b * dim + k] / fnen;
      }
    /* Every face node reproduces the face map at its own face coordinate (catches permuted mid-nodes). */
    const double *fxi = sk_elem_node_coords(face_type);
    double worst = 0.0;
    for (int b = 0; b < fnen; ++b) {
      double N[SK_MAX_NEN];
      sk_elem_shape(face_type, fxi + b * (dim - 1), N, NULL);
      /* Map through the face's corner nodes only (linear part), compare with the node's coordinates. */
      const int ncorner = sk_elem_corners(face_type);
      sk_elem_type corner_type = dim == 2 ? SK_LINE2 : (sk_elem_is_simplex(face_type) ? SK_TRI3 : SK_QUAD4);
      double Nc[4];
      sk_elem_shape(corner_type, fxi + b * (dim - 1), Nc, NULL);
      for (int k = 0; k < dim; ++k) {
        double x = 0.0;
        for (int c = 0; c < ncorner; ++c) x += Nc[c] * Xf[c * dim + k];
        worst = fmax(worst, fabs(x - Xf[b * dim + k]));
      }
    }
    SK_CHECK(worst < 1e-14);
    const double centre_xi = sk_elem_is_simplex(face_type) ? 1.0 / 3.0 : 0.0;
    double mid[2] = {centre_xi, centre_xi};
    face_normal(face_type, dim, Xf, mid, n);
    double outward = 0.0;
    for (int k = 0; k < dim; ++k) outward += n[k] * (fc[k] - centre[k]);
    SK_CHECK(outward > 0.0);
  }
  /* Divergence theorem on a distorted element. */
  double X[SK_MAX_NEN * 3];
  fe_distorted_element(type, dim, 0.08, X);
  double flux = 0.0, s[2], w;
  for (int f = 0; f < nf; ++f) {
    double Xf[SK_MAX_NEN * 3];
    for (int b = 0; b < fnen; ++b)
      for (int k = 0; k < dim; ++k) Xf[b * dim + k] = X[faces[f * fnen + b] * dim + k];
    for (int q = 0; fe_reference_point(face_type, q, s, &w); ++q) { /* X.n is of degree 4 on a curved tri6 */
      double N[SK_MAX_NEN], n[3], x[3] = {0, 0, 0};
      sk_elem_shape(face_type, s, N, NULL);
      face_normal(face_type, dim, Xf, s, n);
      for (int b = 0; b < fnen; ++b)
        for (int k = 0; k < dim; ++k) x[k] += N[b] * Xf[b * dim + k];
      for (int k = 0; k < dim; ++k) flux += w * x[k] * n[k] / dim;
    }
  }
  static const sk_material dummy = {SK_MAT_SVK, 1, 0, 0, 0.5, 1};
  const sk_solid el = {type, dim, &dummy};
  const double volume = sk_solid_volume(&el, X);
  printf("  %-6s volume %.15f, divergence-theorem volume %.15f\n", sk_elem_name(type), volume, flux);
  SK_CHECK(volume > 0.0);
  SK_CHECK_CLOSE(flux, volume, 1e-13);
}

int main(void) {
  static const char *const names[SK_ELEM_TYPE_COUNT] = {"point1", "line2", "line3", "tri3",  "quad4", "quad9", "tet4",
                                                       "hex8",   "hex27", "tri6",  "quad8", "tet10", "hex20"};
  static const int nens[SK_ELEM_TYPE_COUNT] = {1, 2, 3, 3, 4, 9, 4, 8, 27, 6, 8, 10, 20};
  static const int pdims[SK_ELEM_TYPE_COUNT] = {0, 1, 1, 2, 2, 2, 3, 3, 3, 2, 2, 3, 3};
  static const int orders[SK_ELEM_TYPE_COUNT] = {0, 1, 2, 1, 1, 2, 1, 1, 2, 2, 2, 2, 2};
  for (int t = 0; t < SK_ELEM_TYPE_COUNT; ++t) {
    SK_CHECK(strcmp(sk_elem_name((sk_elem_type)t), names[t]) == 0);
    SK_CHECK(sk_elem_nen((sk_elem_type)t) == nens[t]);
    SK_CHECK(sk_elem_pdim((sk_elem_type)t) == pdims[t]);
    SK_CHECK(sk_elem_order((sk_elem_type)t) == orders[t]);
  }
  /* Out-of-range types are rejected, not dereferenced. */
  SK_CHECK(sk_elem_nen(SK_ELEM_TYPE_COUNT) == 0);
  SK_CHECK(sk_elem_node_coords((sk_elem_type)-1) == NULL);
  SK_CHECK(strcmp(sk_elem_name(SK_ELEM_TYPE_COUNT), "unknown") == 0);
  {
    double N[1] = {-7.0};
    sk_elem_shape(SK_POINT1, NULL, N, NULL);
    SK_CHECK(N[0] == 1.0);
  }
  for (int t = SK_LINE2; t < SK_ELEM_TYPE_COUNT; ++t) {
    check_shapes((sk_elem_type)t);
    check_quadrature((sk_elem_type)t);
  }
  for (int t = SK_TRI3; t < SK_ELEM_TYPE_COUNT; ++t) check_faces((sk_elem_type)t);
  return sk_test_finish("fe_elements");
}
