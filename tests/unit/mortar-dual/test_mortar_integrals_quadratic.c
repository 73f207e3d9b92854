/* mortar-dual kernel on second-order 3D faces, one test per face type (this file with MORTAR_INTEGRALS_QUAD9,
 * MORTAR_INTEGRALS_TRI6 or MORTAR_INTEGRALS_QUAD8 = 1): QUAD9's standard dual basis and TRI6's and QUAD8's dual bases
 * of the transformed functions (biorthogonality, weights), and the derivatives of segments on the faces' flat
 * sub-facets and of concentrated points. */
#include "mortar_pair_cases.h"

#ifndef MORTAR_INTEGRALS_QUAD9
#define MORTAR_INTEGRALS_QUAD9 0
#endif
#ifndef MORTAR_INTEGRALS_TRI6
#define MORTAR_INTEGRALS_TRI6 0
#endif
#ifndef MORTAR_INTEGRALS_QUAD8
#define MORTAR_INTEGRALS_QUAD8 0
#endif

/* biorthogonality on a curved QUAD9 face (bulging by 8 % of its size; J not polynomial) with the kernel's 8 x 8 rule:
 * measured 1.70e-9 */
static const double QUAD9_CURVED_TOL = 2.5e-9;

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
  SK_CHECK(mortar_transform(ft, T) == nen);
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
  if (MORTAR_INTEGRALS_TRI6) check_tri6();
  if (MORTAR_INTEGRALS_QUAD8) check_quad8();
  if (MORTAR_INTEGRALS_QUAD9) check_quad9();
  return sk_test_finish(MORTAR_INTEGRALS_TRI6    ? "test_mortar_integrals_tri6"
                        : MORTAR_INTEGRALS_QUAD8 ? "test_mortar_integrals_quad8"
                                                 : "test_mortar_integrals_quad9");
}
