/* Gauss rules of any order on faces (fe.h: sk_face_quadrature): Gauss-Legendre on lines and quads, the collapsed
 * (Duffy) product of Gauss-Legendre rules on triangles. The Legendre nodes are computed (Newton on P_n from the
 * Chebyshev guess), not tabulated. */
#define _GNU_SOURCE
#include <math.h>

#include "stickslip/fe.h"

enum { GAUSS_MAX = 32 };

/* n-point Gauss-Legendre rule on [-1, 1], ascending; closed forms up to 3 points. */
static void gauss_legendre(int n, double *x, double *w) {
  if (n <= 3) {
    static const double x1[] = {0.0}, w1[] = {2.0}, w2[] = {1.0, 1.0}, w3[] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
    const double x2[] = {-1.0 / sqrt(3.0), 1.0 / sqrt(3.0)}, x3[] = {-sqrt(0.6), 0.0, sqrt(0.6)};
    const double *xs = n == 1 ? x1 : n == 2 ? x2 : x3, *ws = n == 1 ? w1 : n == 2 ? w2 : w3;
    for (int i = 0; i < n; ++i) {
      x[i] = xs[i];
      w[i] = ws[i];
    }
    return;
  }
  for (int i = 0; i < n; ++i) {
    double z = cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 1.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = z;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (z * p1 - p0) / (z * z - 1.0);
      const double dz = p1 / dp;
      z -= dz;
      if (fabs(dz) < 1e-16) break;
    }
    x[i] = -z;
    w[i] = 2.0 / ((1.0 - z * z) * dp * dp);
  }
}

int sk_face_quadrature(sk_elem_type type, int order, int max_points, double (*xi)[2], double *w) {
  if (order < 0) order = 0;
  double gx[GAUSS_MAX], gw[GAUSS_MAX], hx[GAUSS_MAX], hw[GAUSS_MAX];
  switch (type) {
    case SK_LINE2:
    case SK_LINE3: {
      const int n = (order + 2) / 2;
      if (n > GAUSS_MAX) return 0;
      if (n > max_points) return -n;
      gauss_legendre(n, gx, gw);
      for (int i = 0; i < n; ++i) {
        xi[i][0] = gx[i];
        xi[i][1] = 0.0;
        w[i] = gw[i];
      }
      return n;
    }
    case SK_QUAD4:
    case SK_QUAD9: {
      const int n = (order + 2) / 2;
      if (n > GAUSS_MAX) return 0;
      if (n * n > max_points) return -n * n;
      gauss_legendre(n, gx, gw);
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          xi[i * n + j][0] = gx[i];
          xi[i * n + j][1] = gx[j];
          w[i * n + j] = gw[i] * gw[j];
        }
      return n * n;
    }
    case SK_TRI3: {
      if (order <= 2) { /* the symmetric 3-point rule (Strang & Fix), degree 2 */
        if (max_points < 3) return -3;
        const double pts[3][2] = {{1.0 / 6.0, 1.0 / 6.0}, {2.0 / 3.0, 1.0 / 6.0}, {1.0 / 6.0, 2.0 / 3.0}};
        for (int i = 0; i < 3; ++i) {
          xi[i][0] = pts[i][0];
          xi[i][1] = pts[i][1];
          w[i] = 1.0 / 6.0;
        }
        return 3;
      }
      /* xi1 = u, xi2 = v (1 - u) on (u, v) in [0, 1]^2, Jacobian 1 - u: degree order + 1 in u, order in v */
      const int nu = (order + 3) / 2, nv = (order + 2) / 2;
      if (nu > GAUSS_MAX) return 0;
      if (nu * nv > max_points) return -nu * nv;
      gauss_legendre(nu, gx, gw);
      gauss_legendre(nv, hx, hw);
      for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
          const double u = 0.5 * (gx[i] + 1.0), v = 0.5 * (hx[j] + 1.0);
          xi[i * nv + j][0] = u;
          xi[i * nv + j][1] = v * (1.0 - u);
          w[i * nv + j] = 0.25 * gw[i] * hw[j] * (1.0 - u);
        }
      return nu * nv;
    }
    default:
      return 0;
  }
}
