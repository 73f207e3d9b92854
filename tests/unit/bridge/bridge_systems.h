/* Small sparse test systems for the bridge tests (unit and MPI): 2D five-point Laplacians on an m x m grid
 * (Dirichlet boundary eliminated), optionally with an upwind convection term that makes them nonsymmetric, and the
 * saddle-point systems of contact built on them. */
#ifndef STICKSLIP_TEST_BRIDGE_SYSTEMS_H
#define STICKSLIP_TEST_BRIDGE_SYSTEMS_H

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "stickslip/bridge.h"

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

/* A contact-like system with a nodal block: an m x m x m grid of nodes with 3 unknowns each (node-major), the
 * coupled vector Laplacian K = L (x) M + shift I (L the 7-point graph Laplacian with its boundary tied to zero,
 * M = [1 .3 .3; .3 1 .3; .3 .3 1]), then multiplier rows: `n_active` gap rows tying u_z of a node to the mean
 * u_z of its two x-neighbours (C), with B = C^T scaled by 0.9 on the neighbours (nonsymmetric, as friction makes
 * it) and a diagonal of `diagonal` (0: stored zero; 1e-24: the round-off of a condensed row); each active
 * multiplier optionally carries a friction-like unknown f (`with_friction`): row f = 0.5 lambda + f + 0.2 u_x,
 * column entries 0.2 in its node's x row; then `n_inactive` identity rows. `coordinates` (3 per node) are filled
 * when not NULL (m^3 * 3 values). */
static inline test_csr test_contact_3d(int m, int n_active, int n_inactive, double diagonal, int with_friction,
                                       double shift, double *coordinates) {
  const int n_nodes = m * m * m, n_nodal = 3 * n_nodes, per_active = with_friction ? 2 : 1;
  const int n = n_nodal + per_active * n_active + n_inactive;
  /* the active points: nodes in the interior of the z = m/2 plane, spread along x */
  int *node = (int *)malloc(sizeof(int) * (size_t)(n_active > 0 ? n_active : 1));
  for (int j = 0; j < n_active; ++j) {
    const int i = 1 + (j % (m - 2)), jj = 1 + (j / (m - 2)) % (m - 2), k = m / 2;
    node[j] = i + m * (jj + m * k);
  }
  test_csr a;
  a.n = n;
  a.row_ptr = (int64_t *)malloc(sizeof(int64_t) * (size_t)(n + 1));
  const size_t cap = (size_t)n_nodal * 21 + (size_t)n_active * 16 + (size_t)n_inactive + 16;
  a.cols = (int *)malloc(sizeof(int) * cap);
  a.values = (double *)malloc(sizeof(double) * cap);
  const double mix[3][3] = {{1, .3, .3}, {.3, 1, .3}, {.3, .3, 1}};
  int64_t k = 0;
  int *row_cols = (int *)malloc(sizeof(int) * 64);
  double *row_vals = (double *)malloc(sizeof(double) * 64);
  for (int row = 0; row < n; ++row) {
    a.row_ptr[row] = k;
    int len = 0;
    if (row < n_nodal) {
      const int p = row / 3, c = row % 3, x = p % m, y = (p / m) % m, z = p / (m * m);
      const int neighbours[6] = {x > 0 ? p - 1 : -1, x < m - 1 ? p + 1 : -1, y > 0 ? p - m : -1,
                                 y < m - 1 ? p + m : -1, z > 0 ? p - m * m : -1, z < m - 1 ? p + m * m : -1};
      for (int d = 0; d < 3; ++d) { row_cols[len] = 3 * p + d; row_vals[len++] = 6.0 * mix[c][d] + (d == c ? shift : 0.0); }
      for (int q = 0; q < 6; ++q)
        if (neighbours[q] >= 0)
          for (int d = 0; d < 3; ++d) { row_cols[len] = 3 * neighbours[q] + d; row_vals[len++] = -mix[c][d]; }
      /* B: multiplier columns of the active points touching this dof */
      for (int j = 0; j < n_active; ++j) {
        const int lambda = n_nodal + per_active * j;
        if (c == 2 && p == node[j]) { row_cols[len] = lambda; row_vals[len++] = 1.0; }
        if (c == 2 && (p == node[j] - 1 || p == node[j] + 1)) { row_cols[len] = lambda; row_vals[len++] = -0.45; }
        if (with_friction && c == 0 && p == node[j]) { row_cols[len] = lambda + 1; row_vals[len++] = 0.2; }
      }
    } else if (row < n_nodal + per_active * n_active) {
      const int j = (row - n_nodal) / per_active, lambda = n_nodal + per_active * j;
      if (row == lambda) { /* gap row: u_z(node) - (u_z(left) + u_z(right)) / 2 */
        row_cols[len] = 3 * node[j] + 2; row_vals[len++] = 1.0;
        row_cols[len] = 3 * (node[j] - 1) + 2; row_vals[len++] = -0.5;
        row_cols[len] = 3 * (node[j] + 1) + 2; row_vals[len++] = -0.5;
        row_cols[len] = row; row_vals[len++] = diagonal;
      } else { /* friction-like row */
        row_cols[len] = 3 * node[j]; row_vals[len++] = 0.2;
        row_cols[len] = lambda; row_vals[len++] = 0.5;
        row_cols[len] = row; row_vals[len++] = 1.0;
      }
    } else {
      row_cols[len] = row; row_vals[len++] = 1.0;
    }
    /* sort the row by column (insertion sort: rows are short) */
    for (int i = 1; i < len; ++i)
      for (int j = i; j > 0 && row_cols[j - 1] > row_cols[j]; --j) {
        const int tc = row_cols[j]; row_cols[j] = row_cols[j - 1]; row_cols[j - 1] = tc;
        const double tv = row_vals[j]; row_vals[j] = row_vals[j - 1]; row_vals[j - 1] = tv;
      }
    for (int i = 0; i < len; ++i) { a.cols[k] = row_cols[i]; a.values[k++] = row_vals[i]; }
  }
  a.row_ptr[n] = k;
  if (coordinates)
    for (int p = 0; p < n_nodes; ++p) {
      coordinates[3 * p] = p % m;
      coordinates[3 * p + 1] = (p / m) % m;
      coordinates[3 * p + 2] = p / (m * m);
    }
  free(node);
  free(row_cols);
  free(row_vals);
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

/* A linear system of `kind` on `comm` solved to 1e-12 (the bridge tests' tolerance); NULL when creation fails. */
static inline sk_linear_system *test_linear_system(MPI_Comm comm, sk_linear_solver_kind kind) {
  sk_linear_options options;
  sk_linear_options_default(&options);
  options.kind = kind;
  options.tolerance = 1e-12;
  sk_linear_system *sys = NULL;
  if (sk_linsys_create(comm, &options, &sys) != SK_OK) return NULL;
  return sys;
}

#endif
