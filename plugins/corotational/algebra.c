/* corotational — kernel: node-wise algebra (the projection Pi, rotations, small matrix products), the node graph of
 * the body's operators, vector products. Equations in kernel.h and docs/plugins/corotational.md. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "kernel.h"

void corot_pi(int dim, const double e[3], const double *v, double *out) {
  if (dim == 2) {
    const double v0 = v[0];
    out[0] = -v[1];
    out[1] = v0;
    return;
  }
  const double t[3] = {e[1] * v[2] - e[2] * v[1], e[2] * v[0] - e[0] * v[2], e[0] * v[1] - e[1] * v[0]};
  memcpy(out, t, sizeof t);
}

void corot_pi_matrix(int dim, const double e[3], double P[9]) {
  memset(P, 0, 9 * sizeof *P);
  if (dim == 2) {
    P[1] = -1.0;
    P[2] = 1.0;
    return;
  }
  P[1] = -e[2], P[2] = e[1];
  P[3] = e[2], P[5] = -e[0];
  P[6] = -e[1], P[7] = e[0];
}

void corot_matmul(int dim, const double *A, const double *B, double *C) {
  for (int i = 0; i < dim; ++i)
    for (int j = 0; j < dim; ++j) {
      double sum = 0.0;
      for (int k = 0; k < dim; ++k) sum += A[i * dim + k] * B[k * dim + j];
      C[i * dim + j] = sum;
    }
}

void corot_rotation(int dim, const double e[3], double theta, double R[9]) {
  double P[9], P2[9];
  corot_pi_matrix(dim, e, P);
  corot_matmul(dim, P, P, P2);
  const double sn = sin(theta), cs1 = 1.0 - cos(theta);
  for (int i = 0; i < dim; ++i)
    for (int j = 0; j < dim; ++j) R[i * dim + j] = (i == j) + sn * P[i * dim + j] + cs1 * P2[i * dim + j];
}

void corot_cn(int dim, const double e[3], double a, double w, double C[9]) {
  double P[9], P2[9];
  corot_pi_matrix(dim, e, P);
  corot_matmul(dim, P, P, P2);
  const double d = a * a + w * w;
  for (int i = 0; i < dim; ++i)
    for (int j = 0; j < dim; ++j) {
      const double axial = dim == 3 ? e[i] * e[j] / a : 0.0; /* Pi e = 0: the axis sees only aI */
      C[i * dim + j] = axial - (a * P2[i * dim + j] + w * P[i * dim + j]) / d;
    }
}

void corot_mul(int dim, const double *B, const double *v, double *out) {
  for (int i = 0; i < dim; ++i) {
    double sum = 0.0;
    for (int j = 0; j < dim; ++j) sum += B[i * dim + j] * v[j];
    out[i] = sum;
  }
}

void corot_mul_t(int dim, const double *B, const double *v, double *out) {
  for (int i = 0; i < dim; ++i) {
    double sum = 0.0;
    for (int j = 0; j < dim; ++j) sum += B[j * dim + i] * v[j];
    out[i] = sum;
  }
}

static int compare_int(const void *a, const void *b) {
  const int x = *(const int *)a, y = *(const int *)b;
  return (x > y) - (x < y);
}

int corot_node_graph(int n_nodes, int64_t n_cells, int nen, const int32_t *conn, int64_t **row_ptr, int **cols) {
  int64_t *start = calloc((size_t)n_nodes + 1, sizeof(int64_t));
  int *fill = calloc((size_t)n_nodes + 1, sizeof(int));
  *row_ptr = calloc((size_t)n_nodes + 1, sizeof(int64_t));
  *cols = NULL;
  int *raw = NULL;
  if (!start || !fill || !*row_ptr) goto fail;
  for (int64_t c = 0; c < n_cells; ++c)
    for (int i = 0; i < nen; ++i) start[conn[c * nen + i] + 1] += nen;
  for (int a = 0; a < n_nodes; ++a) start[a + 1] += start[a] + 1; /* + the diagonal */
  raw = malloc(sizeof(int) * (size_t)(start[n_nodes] + 1));
  *cols = malloc(sizeof(int) * (size_t)(start[n_nodes] + 1));
  if (!raw || !*cols) goto fail;
  for (int a = 0; a < n_nodes; ++a) raw[start[a] + fill[a]++] = a;
  for (int64_t c = 0; c < n_cells; ++c)
    for (int i = 0; i < nen; ++i) {
      const int a = conn[c * nen + i];
      for (int j = 0; j < nen; ++j) raw[start[a] + fill[a]++] = conn[c * nen + j];
    }
  int64_t used = 0;
  for (int a = 0; a < n_nodes; ++a) {
    int *row = raw + start[a];
    qsort(row, (size_t)fill[a], sizeof(int), compare_int);
    for (int j = 0; j < fill[a]; ++j)
      if (j == 0 || row[j] != row[j - 1]) (*cols)[used++] = row[j];
    (*row_ptr)[a + 1] = used;
  }
  free(raw);
  free(start);
  free(fill);
  return 0;
fail:
  free(raw);
  free(start);
  free(fill);
  free(*row_ptr);
  free(*cols);
  *row_ptr = NULL;
  *cols = NULL;
  return -1;
}

double corot_dot(int n, const double *a, const double *b) {
  double sum = 0.0;
  for (int i = 0; i < n; ++i) sum += a[i] * b[i];
  return sum;
}
