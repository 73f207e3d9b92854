/* Shared helpers of the nts-augmented tests: facet shape functions (gmsh node order, the same layout as
 * sk_elem_shape: dN[a*2 + k], ddN[(a*2 + k)*2 + l]) so the kernel can be tested without the core, a small
 * deterministic random generator and finite-difference helpers. */
#ifndef NTS_TEST_SUPPORT_H
#define NTS_TEST_SUPPORT_H

#include <math.h>
#include <string.h>

#include "kernel.h"

static inline void test_shape(sk_elem_type type, const double *xi, double *N, double *dN) {
  const double s = xi[0], t = xi[1];
  if (type == SK_LINE2) { /* xi in [-1, 1]; one parametric direction */
    if (N) N[0] = 0.5 * (1 - s), N[1] = 0.5 * (1 + s);
    if (dN) dN[0] = -0.5, dN[1] = 0.5;
  } else if (type == SK_QUAD4) {
    static const double c[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    for (int a = 0; a < 4; ++a) {
      if (N) N[a] = 0.25 * (1 + c[a][0] * s) * (1 + c[a][1] * t);
      if (dN) {
        dN[a * 2 + 0] = 0.25 * c[a][0] * (1 + c[a][1] * t);
        dN[a * 2 + 1] = 0.25 * c[a][1] * (1 + c[a][0] * s);
      }
    }
  } else {
    if (N) {
      N[0] = 1 - s - t;
      N[1] = s;
      N[2] = t;
    }
    if (dN) {
      const double d[6] = {-1, -1, 1, 0, 0, 1};
      memcpy(dN, d, sizeof d);
    }
  }
}

static inline void test_shape_hessian(sk_elem_type type, const double *xi, double *ddN) {
  (void)xi;
  if (type == SK_LINE2) {
    ddN[0] = ddN[1] = 0.0;
  } else if (type == SK_QUAD4) {
    static const double c[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    for (int a = 0; a < 4; ++a) {
      ddN[(a * 2 + 0) * 2 + 0] = 0.0;
      ddN[(a * 2 + 1) * 2 + 1] = 0.0;
      ddN[(a * 2 + 0) * 2 + 1] = ddN[(a * 2 + 1) * 2 + 0] = 0.25 * c[a][0] * c[a][1];
    }
  } else {
    memset(ddN, 0, sizeof(double) * 12);
  }
}

static unsigned long long test_rng_state = 88172645463325252ull;
static inline double test_rand(void) { /* uniform in [-1, 1] */
  test_rng_state ^= test_rng_state << 13;
  test_rng_state ^= test_rng_state >> 7;
  test_rng_state ^= test_rng_state << 17;
  return 2.0 * (double)(test_rng_state >> 11) / 9007199254740992.0 - 1.0;
}

/* A distorted, non-planar facet near z = 0 (normal +z) with a slave node above or below it. q_A = [q_s | x_I]. */
static inline void test_element(sk_elem_type type, double slave_height, double *q_A) {
  static const double quad[4][3] = {{-1, -1, 0}, {1.2, -0.9, 0}, {1.1, 1.3, 0}, {-0.8, 1.0, 0}};
  static const double tri[3][3] = {{-1, -1, 0}, {1.3, -0.8, 0}, {-0.7, 1.2, 0}};
  const int nen = type == SK_QUAD4 ? 4 : 3;
  for (int I = 0; I < nen; ++I)
    for (int i = 0; i < 3; ++i)
      q_A[3 + 3 * I + i] = (type == SK_QUAD4 ? quad[I][i] : tri[I][i]) + 0.15 * test_rand();
  q_A[0] = 0.1 + 0.1 * test_rand();
  q_A[1] = -0.05 + 0.1 * test_rand();
  q_A[2] = slave_height;
}

static inline double max_abs(const double *v, int n) {
  double m = 0.0;
  for (int i = 0; i < n; ++i) m = fmax(m, fabs(v[i]));
  return m;
}

#endif
