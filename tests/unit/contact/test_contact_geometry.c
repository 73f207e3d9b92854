/* Covariant surface geometry: every derivative against finite differences on curved and distorted faces of each
 * face type, frame identities, the 2D convention, and averaged nodal normals. */
#include "contact_test_util.h"
#include "sk_test.h"

static double dot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* A curved, sheared map: every second derivative of x(u, v) is non-zero. */
static void map_warped(double u, double v, const void *ctx, double *x) {
  (void)ctx;
  x[0] = u + 0.15 * v * v + 0.1 * u * v;
  x[1] = 0.8 * v + 0.2 * u * u;
  x[2] = 0.3 * sin(1.3 * u) * cos(0.7 * v) + 0.2 * u * v;
}

static void map_curve(double u, double v, const void *ctx, double *x) {
  (void)ctx;
  (void)v;
  x[0] = u + 0.2 * u * u;
  x[1] = 0.4 * sin(1.7 * u);
  x[2] = 0.0;
}

static void check_point(const sk_surface *s, int face, const double *xi, const double *q) {
  const int pdim = s->dim - 1;
  const double h = 1e-6;
  sk_surface_point p, pp, pm;
  sk_surface_geometry(s, face, xi, q, &p);
  SK_CHECK(p.face == face && p.nen == s->nen);

  double sumN = 0.0, sumdN[2] = {0, 0};
  for (int a = 0; a < p.nen; ++a) {
    sumN += p.N[a];
    for (int k = 0; k < pdim; ++k) sumdN[k] += p.dN[a][k];
  }
  SK_CHECK_CLOSE(sumN, 1.0, 1e-13);
  SK_CHECK_CLOSE(sumdN[0], 0.0, 1e-13);

  /* First and second derivatives, metric derivative (Christoffel symbols) and normal derivative (curvature). */
  for (int l = 0; l < pdim; ++l) {
    double xp[2] = {xi[0], xi[1]}, xm[2] = {xi[0], xi[1]};
    xp[l] += h;
    xm[l] -= h;
    sk_surface_geometry(s, face, xp, q, &pp);
    sk_surface_geometry(s, face, xm, q, &pm);
    for (int i = 0; i < 3; ++i) SK_CHECK_CLOSE(p.a[l][i], (pp.x[i] - pm.x[i]) / (2 * h), 1e-7);
    for (int k = 0; k < pdim; ++k)
      for (int i = 0; i < 3; ++i) SK_CHECK_CLOSE(p.a_ab[k][l][i], (pp.a[k][i] - pm.a[k][i]) / (2 * h), 1e-7);
    double dn[3];
    for (int i = 0; i < 3; ++i) dn[i] = (pp.n[i] - pm.n[i]) / (2 * h);
    for (int k = 0; k < pdim; ++k) {
      /* Weingarten: h_kl = -a_k . n,l */
      SK_CHECK_CLOSE(p.h[k][l], -dot(p.a[k], dn), 1e-7);
      /* m_ab,c = Gamma_{b,ac} + Gamma_{a,bc}, with Gamma_{d,ab} = m_dc Gamma^c_ab */
      for (int b = 0; b < pdim; ++b) {
        double dm = (pp.m[k][b] - pm.m[k][b]) / (2 * h);
        double expected = 0.0;
        for (int c = 0; c < 2; ++c)
          expected += p.m[b][c] * p.christoffel[k][l][c] + p.m[k][c] * p.christoffel[b][l][c];
        SK_CHECK_CLOSE(expected, dm, 1e-7);
      }
    }
  }
  /* Frame identities. */
  SK_CHECK_CLOSE(dot(p.n, p.n), 1.0, 1e-14);
  SK_CHECK_CLOSE(dot(p.n, p.a[0]), 0.0, 1e-13);
  SK_CHECK_CLOSE(dot(p.n, p.a[1]), 0.0, 1e-13);
  double cross[3] = {p.a[0][1] * p.a[1][2] - p.a[0][2] * p.a[1][1], p.a[0][2] * p.a[1][0] - p.a[0][0] * p.a[1][2],
                     p.a[0][0] * p.a[1][1] - p.a[0][1] * p.a[1][0]};
  SK_CHECK_CLOSE(dot(cross, p.n), p.jacobian, 1e-13);
  for (int k = 0; k < 2; ++k)
    for (int l = 0; l < 2; ++l) {
      SK_CHECK_CLOSE(p.m[k][l], dot(p.a[k], p.a[l]), 1e-14);
      SK_CHECK_CLOSE(p.m[k][0] * p.m_inv[0][l] + p.m[k][1] * p.m_inv[1][l], k == l ? 1.0 : 0.0, 1e-13);
      SK_CHECK_CLOSE(dot(p.a_dual[k], p.a[l]), k == l ? 1.0 : 0.0, 1e-13);
      SK_CHECK_CLOSE(p.h[k][l], dot(p.a_ab[k][l], p.n), 1e-14);
      SK_CHECK_CLOSE(p.h[k][l], p.h[l][k], 1e-13);
      for (int c = 0; c < 2; ++c) SK_CHECK_CLOSE(p.christoffel[k][l][c], dot(p.a_ab[k][l], p.a_dual[c]), 1e-13);
    }
  if (s->dim == 2) {
    /* a[1] = e_z and n = a1 x e_z = (a_y, -a_x)/|a|: outward for a boundary run counter-clockwise. */
    SK_CHECK(p.a[1][0] == 0.0 && p.a[1][1] == 0.0 && p.a[1][2] == 1.0);
    double length = sqrt(p.a[0][0] * p.a[0][0] + p.a[0][1] * p.a[0][1]);
    SK_CHECK_CLOSE(p.n[0], p.a[0][1] / length, 1e-14);
    SK_CHECK_CLOSE(p.n[1], -p.a[0][0] / length, 1e-14);
    SK_CHECK_CLOSE(p.jacobian, length, 1e-14);
    SK_CHECK_CLOSE(p.m[1][1], 1.0, 0);
  }
}

static void check_type(sk_elem_type type) {
  test_patch patch;
  unsigned long long seed = 12345u + (unsigned)type;
  int pdim = (type == SK_LINE2 || type == SK_LINE3) ? 1 : 2;
  test_patch_make(&patch, type, 3, 2, -0.7, 1.1, -0.5, 0.9, pdim == 1 ? map_curve : map_warped, NULL);
  /* Distort the nodes a little too, so no face is a clean image of the grid. */
  int dim = patch.surface.dim;
  for (int i = 0; i < patch.n_nodes * dim; ++i) patch.q[i] += 0.03 * (test_random(&seed) - 0.5);
  for (int f = 0; f < patch.surface.n_faces; ++f)
    for (int trial = 0; trial < 3; ++trial) {
      double xi[2];
      if (sk_elem_is_simplex(type)) {
        xi[0] = 0.05 + 0.6 * test_random(&seed);
        xi[1] = 0.05 + 0.3 * test_random(&seed);
      } else {
        xi[0] = -0.9 + 1.8 * test_random(&seed);
        xi[1] = pdim == 2 ? -0.9 + 1.8 * test_random(&seed) : 0.0;
      }
      check_point(&patch.surface, f, xi, patch.q);
    }
  test_patch_free(&patch);
}

/* Flat patch in a tilted plane: every nodal normal is the plane normal. */
static void tilted_plane(double u, double v, const void *ctx, double *x) {
  (void)ctx;
  x[0] = u;
  x[1] = 0.6 * v;
  x[2] = 0.8 * v + 0.3 * u + 2.0;
}

static void sphere_map(double u, double v, const void *ctx, double *x) {
  const double R = *(const double *)ctx;
  /* (u, v) are angles around the north pole; counter-clockwise in (u, v) gives the outward (radial) normal. */
  x[0] = R * sin(u) * cos(v);
  x[1] = R * sin(v);
  x[2] = R * cos(u) * cos(v);
}

static void check_nodal_normals(void) {
  sk_elem_type types[] = {SK_TRI3, SK_QUAD4, SK_TRI6, SK_QUAD8, SK_QUAD9};
  for (int t = 0; t < 5; ++t) {
    test_patch patch;
    test_patch_make(&patch, types[t], 4, 3, -1, 1, -1, 1, tilted_plane, NULL);
    double *normals = malloc(3 * (size_t)patch.surface.n_nodes * sizeof(double));
    sk_surface_nodal_normals(&patch.surface, patch.q, normals);
    double expected[3] = {-0.3 * 0.6, -0.8, 0.6}; /* (1, 0, 0.3) x (0, 0.6, 0.8) */
    double length = sqrt(dot(expected, expected));
    for (int k = 0; k < patch.surface.n_nodes; ++k)
      for (int i = 0; i < 3; ++i) SK_CHECK_CLOSE(normals[3 * k + i], expected[i] / length, 1e-13);
    free(normals);
    test_patch_free(&patch);

    double R = 2.0;
    test_patch_make(&patch, types[t], 8, 8, -0.6, 0.6, -0.6, 0.6, sphere_map, &R);
    normals = malloc(3 * (size_t)patch.surface.n_nodes * sizeof(double));
    sk_surface_nodal_normals(&patch.surface, patch.q, normals);
    double worst = 0.0;
    const int quadratic = sk_elem_order(types[t]) == 2;
    int mu = quadratic ? 17 : 9; /* nodes per grid row; border nodes see one side only: skip them */
    for (int k = 0; k < patch.surface.n_nodes; ++k) {
      const int g = patch.surface.nodes[k];
      if (g % mu == 0 || g % mu == mu - 1 || g / mu == 0 || g / mu == mu - 1) continue;
      const double *x = patch.q + 3 * g;
      double c = dot(normals + 3 * k, x) / sqrt(dot(x, x));
      worst = fmax(worst, 1.0 - c);
    }
    /* Radial to within a small angle at interior nodes: (1 - cos) < 1e-4 is under 1 degree; quadratic faces take the
     * normal of the curved face at the node itself (measured: tri6 9.9e-7, quad8 1.3e-10, quad9 7.3e-12). */
    SK_CHECK(worst < (!quadratic ? 1e-4 : sk_elem_is_simplex(types[t]) ? 2e-6 : 1e-9));
    printf("sphere patch %s: max 1 - cos(nodal normal, radial) = %.3g\n", sk_elem_name(types[t]), worst);
    free(normals);
    test_patch_free(&patch);
  }
}

int main(void) {
  sk_elem_type types[] = {SK_LINE2, SK_LINE3, SK_TRI3, SK_QUAD4, SK_TRI6, SK_QUAD8, SK_QUAD9};
  for (int t = 0; t < 7; ++t) check_type(types[t]);
  check_nodal_normals();
  return sk_test_finish("test_contact_geometry");
}
