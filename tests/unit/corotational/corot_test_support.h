/* Helpers for the corotational kernel tests: a body (M, S, contact nodes and D_pp) from a gmsh mesh through the
 * core's element kernels, and a dense LU that implements the kernel's solver interface (factorise once, solve many). */
#ifndef COROT_TEST_SUPPORT_H
#define COROT_TEST_SUPPORT_H

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "kernel.h"
#include "stickslip/fe.h"
#include "stickslip/mesh.h"

/* ---- dense LU with partial pivoting --------------------------------------------------------------------------- */
typedef struct {
  int N;
  double *A; /* N x N, row-major, factorised in place */
  int *piv;
  int factorisations, solves;
} dense_lu;

static inline int dense_factor(void *ctx, const corot_system *sys) {
  dense_lu *lu = ctx;
  const int n = sys->n, N = n + sys->n_border, dim = sys->dim, dd = dim * dim;
  if (lu->N != N) {
    free(lu->A);
    free(lu->piv);
    lu->N = N;
    lu->A = malloc(sizeof(double) * (size_t)N * (size_t)N);
    lu->piv = malloc(sizeof(int) * (size_t)N);
    if (!lu->A || !lu->piv) return -1;
  }
  double *A = lu->A;
  memset(A, 0, sizeof(double) * (size_t)N * (size_t)N);
  for (int a = 0; a < sys->n_nodes; ++a)
    for (int64_t k = sys->row_ptr[a]; k < sys->row_ptr[a + 1]; ++k)
      for (int i = 0; i < dim; ++i)
        for (int j = 0; j < dim; ++j)
          A[(size_t)(a * dim + i) * N + sys->cols[k] * dim + j] = sys->blocks[k * dd + i * dim + j];
  for (int b = 0; b < sys->n_border; ++b)
    for (int i = 0; i < n; ++i) {
      A[(size_t)i * N + n + b] = sys->border_col[b][i];
      A[(size_t)(n + b) * N + i] = sys->border_row[b][i];
    }
  for (int k = 0; k < N; ++k) {
    int p = k;
    for (int i = k + 1; i < N; ++i)
      if (fabs(A[(size_t)i * N + k]) > fabs(A[(size_t)p * N + k])) p = i;
    if (A[(size_t)p * N + k] == 0.0) return -1;
    lu->piv[k] = p;
    if (p != k)
      for (int j = 0; j < N; ++j) {
        double t = A[(size_t)k * N + j];
        A[(size_t)k * N + j] = A[(size_t)p * N + j];
        A[(size_t)p * N + j] = t;
      }
    const double inv = 1.0 / A[(size_t)k * N + k];
    for (int i = k + 1; i < N; ++i) {
      double l = A[(size_t)i * N + k] *= inv;
      if (l == 0.0) continue;
      for (int j = k + 1; j < N; ++j) A[(size_t)i * N + j] -= l * A[(size_t)k * N + j];
    }
  }
  lu->factorisations++;
  return 0;
}

static inline int dense_solve(void *ctx, const double *rhs, double *x) {
  dense_lu *lu = ctx;
  const int N = lu->N;
  if (x != rhs) memcpy(x, rhs, sizeof(double) * (size_t)N);
  /* the row swaps first (L is stored in the final row order), then L and U */
  for (int k = 0; k < N; ++k) {
    const int p = lu->piv[k];
    const double t = x[k];
    x[k] = x[p];
    x[p] = t;
  }
  for (int k = 0; k < N; ++k)
    for (int i = k + 1; i < N; ++i) x[i] -= lu->A[(size_t)i * N + k] * x[k];
  for (int i = N - 1; i >= 0; --i) {
    double sum = x[i];
    for (int j = i + 1; j < N; ++j) sum -= lu->A[(size_t)i * N + j] * x[j];
    x[i] = sum / lu->A[(size_t)i * N + i];
  }
  lu->solves++;
  return 0;
}

static inline void dense_free(dense_lu *lu) {
  free(lu->A);
  free(lu->piv);
  memset(lu, 0, sizeof *lu);
}

static inline corot_solver dense_solver(dense_lu *lu) {
  corot_solver s = {.ctx = lu, .factor = dense_factor, .solve = dense_solve};
  return s;
}

/* ---- a body from a mesh ---------------------------------------------------------------------------------------- */
typedef struct {
  sk_mesh mesh;
  int dim, n_nodes;
  int64_t *row_ptr;
  int *cols;
  double *mass, *stiffness, *X;
  int n_contact;
  int *contact_nodes;
  double *contact_weight; /* D_pp = sum over faces of integral N_p ds (reference) */
  corot_body body;
} test_body;

static inline int cmp_int(const void *a, const void *b) { return (*(const int *)a > *(const int *)b) - (*(const int *)a < *(const int *)b); }

static inline int64_t graph_find(const test_body *tb, int a, int b) {
  for (int64_t k = tb->row_ptr[a]; k < tb->row_ptr[a + 1]; ++k)
    if (tb->cols[k] == b) return k;
  return -1;
}

/* Loads `path` with the given parameters, assembles M and the Hooke S of group `body` (E, nu, rho) and the contact
 * weights of the face group `surface` (may be NULL). Returns 0 on success. */
static inline int test_body_load(test_body *tb, const char *path, const sk_mesh_param *params, int n_params, const char *body,
                          const char *surface, double E, double nu, double rho, const double axis[3]) {
  memset(tb, 0, sizeof *tb);
  if (sk_mesh_load(path, params, n_params, 0, &tb->mesh) != SK_OK) {
    fprintf(stderr, "%s\n", sk_error_message());
    return -1;
  }
  const sk_group *g = sk_mesh_find_group(&tb->mesh, body);
  if (!g) return -1;
  const int dim = tb->dim = tb->mesh.dim, nn = tb->n_nodes = tb->mesh.n_nodes, nen = g->nen, dd = dim * dim;
  /* node graph: every pair of nodes sharing an element */
  int *count = calloc((size_t)nn, sizeof(int));
  for (int e = 0; e < g->n_elems; ++e)
    for (int i = 0; i < nen; ++i) count[g->conn[e * nen + i]] += nen;
  int64_t *start = calloc((size_t)nn + 1, sizeof(int64_t));
  for (int a = 0; a < nn; ++a) start[a + 1] = start[a] + count[a] + 1;
  int *raw = malloc(sizeof(int) * (size_t)start[nn]);
  int *fill = calloc((size_t)nn, sizeof(int));
  for (int a = 0; a < nn; ++a) raw[start[a] + fill[a]++] = a;
  for (int e = 0; e < g->n_elems; ++e)
    for (int i = 0; i < nen; ++i) {
      const int a = g->conn[e * nen + i];
      for (int j = 0; j < nen; ++j) raw[start[a] + fill[a]++] = g->conn[e * nen + j];
    }
  tb->row_ptr = calloc((size_t)nn + 1, sizeof(int64_t));
  tb->cols = malloc(sizeof(int) * (size_t)start[nn]);
  int64_t used = 0;
  for (int a = 0; a < nn; ++a) {
    int *row = raw + start[a];
    qsort(row, (size_t)fill[a], sizeof(int), cmp_int);
    for (int j = 0; j < fill[a]; ++j)
      if (j == 0 || row[j] != row[j - 1]) tb->cols[used++] = row[j];
    tb->row_ptr[a + 1] = used;
  }
  free(count);
  free(start);
  free(raw);
  free(fill);
  tb->mass = calloc((size_t)used, sizeof(double));
  tb->stiffness = calloc((size_t)used * dd, sizeof(double));
  tb->X = malloc(sizeof(double) * (size_t)nn * dim);
  for (int a = 0; a < nn; ++a)
    for (int i = 0; i < dim; ++i) tb->X[a * dim + i] = tb->mesh.x[3 * a + i];
  sk_material mat;
  if (sk_material_init(&mat, SK_MAT_HOOKE, E, nu, rho) != SK_OK) return -1;
  sk_solid solid = {.type = g->type, .dim = dim, .mat = &mat};
  double Xe[SK_MAX_NEN * 3], ue[SK_MAX_NEN * 3] = {0}, Me[SK_MAX_NEN * SK_MAX_NEN];
  double *Ke = malloc(sizeof(double) * SK_MAX_NEN * 3 * SK_MAX_NEN * 3);
  for (int e = 0; e < g->n_elems; ++e) {
    const int *conn = g->conn + e * nen;
    for (int i = 0; i < nen; ++i)
      for (int k = 0; k < dim; ++k) Xe[i * dim + k] = tb->X[conn[i] * dim + k];
    if (sk_solid_mass(&solid, Xe, Me) != SK_OK || sk_solid_internal(&solid, Xe, ue, NULL, NULL, Ke) != SK_OK) {
      free(Ke);
      return -1;
    }
    for (int i = 0; i < nen; ++i)
      for (int j = 0; j < nen; ++j) {
        const int64_t k = graph_find(tb, conn[i], conn[j]);
        tb->mass[k] += Me[i * nen + j];
        for (int r = 0; r < dim; ++r)
          for (int c = 0; c < dim; ++c) tb->stiffness[k * dd + r * dim + c] += Ke[(i * dim + r) * nen * dim + j * dim + c];
      }
  }
  free(Ke);
  if (surface) {
    const sk_group *f = sk_mesh_find_group(&tb->mesh, surface);
    if (!f || sk_group_nodes(f, &tb->contact_nodes, &tb->n_contact) != SK_OK) return -1;
    tb->contact_weight = calloc((size_t)tb->n_contact, sizeof(double));
    for (int e = 0; e < f->n_elems; ++e) {
      double Xf[SK_MAX_NEN * 3], one[3] = {1, 1, 1}, load[SK_MAX_NEN * 3];
      for (int i = 0; i < f->nen; ++i)
        for (int k = 0; k < dim; ++k) Xf[i * dim + k] = tb->X[f->conn[e * f->nen + i] * dim + k];
      sk_face_traction(f->type, dim, Xf, one, load); /* integral N_p ds per component */
      for (int i = 0; i < f->nen; ++i) {
        int *hit = bsearch(&f->conn[e * f->nen + i], tb->contact_nodes, (size_t)tb->n_contact, sizeof(int), cmp_int);
        tb->contact_weight[hit - tb->contact_nodes] += load[i * dim];
      }
    }
  }
  return corot_body_init(&tb->body, dim, nn, tb->row_ptr, tb->cols, tb->mass, tb->stiffness, tb->X, axis);
}

static inline void test_body_free(test_body *tb) {
  corot_body_free(&tb->body);
  sk_mesh_free(&tb->mesh);
  free(tb->row_ptr);
  free(tb->cols);
  free(tb->mass);
  free(tb->stiffness);
  free(tb->X);
  free(tb->contact_nodes);
  free(tb->contact_weight);
  memset(tb, 0, sizeof *tb);
}

/* Deterministic numbers in [-1, 1). */
static unsigned long long corot_rng = 0x9E3779B97F4A7C15ull;
static inline double corot_rand(void) {
  corot_rng ^= corot_rng >> 12;
  corot_rng ^= corot_rng << 25;
  corot_rng ^= corot_rng >> 27;
  return (double)((corot_rng * 2685821657736338717ull) >> 11) / 4503599627370496.0 - 1.0;
}

/* The steady initial state to round-off (projected CG to 1e-13). */
static inline int initial_state(const corot_body *b, corot_model model, double omega, const double V0[3],
                                corot_state *state) {
  int iterations;
  return corot_initial_state(b, model, omega, V0, 1e-13, state->u, state->s, &iterations);
}

static inline double vec_norm(int n, const double *v) {
  double s = 0.0;
  for (int i = 0; i < n; ++i) s += v[i] * v[i];
  return sqrt(s);
}

#endif
