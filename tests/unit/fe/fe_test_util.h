/* Helpers shared by the fe unit tests: deterministic random numbers, distorted elements, element lists. */
#ifndef FE_TEST_UTIL_H
#define FE_TEST_UTIL_H

#include <math.h>
#include <string.h>

#include "stickslip/fe.h"

static unsigned long long fe_test_rng_state = 0x9E3779B97F4A7C15ull;

/* Uniform in [-1, 1) (xorshift64*, deterministic across runs). */
static inline double fe_rand(void) {
  fe_test_rng_state ^= fe_test_rng_state >> 12;
  fe_test_rng_state ^= fe_test_rng_state << 25;
  fe_test_rng_state ^= fe_test_rng_state >> 27;
  const unsigned long long r = fe_test_rng_state * 2685821657736338717ull;
  return (double)(r >> 11) / 4503599627370496.0 - 1.0;
}

/* Solid element types per dimension. */
static const sk_elem_type fe_solids_2d[] = {SK_TRI3, SK_QUAD4, SK_QUAD9};
static const sk_elem_type fe_solids_3d[] = {SK_TET4, SK_HEX8, SK_HEX27};

/* A distorted element of `type` in dimension dim == pdim: the reference nodes scaled, sheared, shifted, then
 * every node perturbed by up to `perturb` (mid-nodes too: curved edges for quadratic elements). */
static inline void fe_distorted_element(sk_elem_type type, int dim, double perturb, double *X) {
  const int nen = sk_elem_nen(type);
  const double *xi = sk_elem_node_coords(type);
  static const double affine[9] = {1.1, 0.2, 0.1, -0.15, 0.9, 0.05, 0.1, -0.1, 1.2};
  for (int a = 0; a < nen; ++a)
    for (int i = 0; i < dim; ++i) {
      double x = 0.3 * (i + 1);
      for (int k = 0; k < dim; ++k) x += affine[i * 3 + k] * xi[a * dim + k];
      X[a * dim + i] = x + perturb * fe_rand();
    }
}

/* A random deformation gradient F = I + scale * random (det F > 0 for scale <= 0.3), 3x3 (plane: F33 = 1,
 * no out-of-plane coupling). */
static inline void fe_random_gradient(int dim, double scale, double F[9]) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) F[i * 3 + j] = (i == j) + ((i < dim && j < dim) ? scale * fe_rand() : 0.0);
}

/* u_a = A X_a (A = F - I). */
static inline void fe_linear_displacement(int dim, int nen, const double F[9], const double *X, double *u) {
  for (int a = 0; a < nen; ++a)
    for (int i = 0; i < dim; ++i) {
      double s = 0.0;
      for (int k = 0; k < dim; ++k) s += (F[i * 3 + k] - (i == k)) * X[a * dim + k];
      u[a * dim + i] = s;
    }
}

static inline double fe_max_abs(const double *v, int n) {
  double m = 0.0;
  for (int i = 0; i < n; ++i) m = fmax(m, fabs(v[i]));
  return m;
}

/* C = F^T F (3x3 row-major). */
static inline void right_cauchy_green(const double F[9], double C[9]) {
  for (int I = 0; I < 3; ++I)
    for (int J = 0; J < 3; ++J) {
      double s = 0.0;
      for (int k = 0; k < 3; ++k) s += F[k * 3 + I] * F[k * 3 + J];
      C[I * 3 + J] = s;
    }
}

#endif
