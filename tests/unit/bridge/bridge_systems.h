/* Small sparse test systems for the bridge tests (unit and MPI): 2D five-point Laplacians on an m x m grid
 * (Dirichlet boundary eliminated), optionally with an upwind convection term that makes them nonsymmetric, and the
 * saddle-point systems of contact built on them. */
#ifndef STICKSLIP_TEST_BRIDGE_SYSTEMS_H
#define STICKSLIP_TEST_BRIDGE_SYSTEMS_H

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

typedef struct {
  int n;
  int64_t *row_ptr;
  int *cols;
  double *values;
} test_csr;

/* 4 on the diagonal, -1 to the four neighbours; `convection` > 0 adds an upwind x-derivative (nonsymmetric). */
static inline test_csr test_laplacian_2d(int m, double convection) {
  test_csr a;
  a.n = m * m;
  a.row_ptr = (int64_t *)malloc(sizeof(int64_t) * (size_t)(a.n + 1));
  a.cols = (int *)malloc(sizeof(int) * (size_t)a.n * 5);
  a.values = (double *)malloc(sizeof(double) * (size_t)a.n * 5);
  int64_t k = 0;
  for (int j = 0; j < m; ++j) {
    for (int i = 0; i < m; ++i) {
      const int row = j * m + i;
      a.row_ptr[row] = k;
      /* columns in increasing order: south, west, centre, east, north */
      if (j > 0) { a.cols[k] = row - m; a.values[k++] = -1.0; }
      if (i > 0) { a.cols[k] = row - 1; a.values[k++] = -1.0 - convection; }
      a.cols[k] = row; a.values[k++] = 4.0 + convection;
      if (i < m - 1) { a.cols[k] = row + 1; a.values[k++] = -1.0; }
      if (j < m - 1) { a.cols[k] = row + m; a.values[k++] = -1.0; }
    }
  }
  a.row_ptr[a.n] = k;
  return a;
}

static inline void test_csr_free(test_csr *a) {
  free(a->row_ptr);
  free(a->cols);
  free(a->values);
}

/* The saddle point of contact: [A B^T; B 0] with A the m x m Laplacian and `n_multipliers` multiplier rows, the
 * j-th tying unknown k_j = (2 j + 1) m^2 / (2 n_multipliers) (B = e_{k_j}^T); each multiplier row stores its zero
 * diagonal explicitly, as assembled contact rows do. Nonsingular, indefinite. */
static inline test_csr test_saddle_2d(int m, int n_multipliers) {
  test_csr lap = test_laplacian_2d(m, 0.0), a;
  const int nu = lap.n;
  a.n = nu + n_multipliers;
  a.row_ptr = (int64_t *)malloc(sizeof(int64_t) * (size_t)(a.n + 1));
  a.cols = (int *)malloc(sizeof(int) * ((size_t)lap.row_ptr[nu] + 3 * (size_t)n_multipliers));
  a.values = (double *)malloc(sizeof(double) * ((size_t)lap.row_ptr[nu] + 3 * (size_t)n_multipliers));
  int64_t k = 0;
  for (int row = 0; row < nu; ++row) {
    a.row_ptr[row] = k;
    for (int64_t q = lap.row_ptr[row]; q < lap.row_ptr[row + 1]; ++q) {
      a.cols[k] = lap.cols[q];
      a.values[k++] = lap.values[q];
    }
    for (int j = 0; j < n_multipliers; ++j) {
      if ((int)((2LL * j + 1) * nu / (2LL * n_multipliers)) == row) { a.cols[k] = nu + j; a.values[k++] = 1.0; }
    }
  }
  for (int j = 0; j < n_multipliers; ++j) {
    a.row_ptr[nu + j] = k;
    a.cols[k] = (int)((2LL * j + 1) * nu / (2LL * n_multipliers));
    a.values[k++] = 1.0;
    a.cols[k] = nu + j;
    a.values[k++] = 0.0;
  }
  a.row_ptr[a.n] = k;
  test_csr_free(&lap);
  return a;
}

static inline void test_csr_multiply(const test_csr *a, const double *x, double *y) {
  for (int i = 0; i < a->n; ++i) {
    double sum = 0;
    for (int64_t k = a->row_ptr[i]; k < a->row_ptr[i + 1]; ++k) sum += a->values[k] * x[a->cols[k]];
    y[i] = sum;
  }
}

/* A smooth, non-trivial reference solution. */
static inline void test_reference_solution(int n, double *x) {
  for (int i = 0; i < n; ++i) x[i] = sin(0.37 * i) + 0.01 * i;
}

static inline double test_max_difference(int n, const double *a, const double *b) {
  double worst = 0;
  for (int i = 0; i < n; ++i) worst = fmax(worst, fabs(a[i] - b[i]));
  return worst;
}

#endif
