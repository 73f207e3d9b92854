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
  int32_t *conn32 = malloc(sizeof(int32_t) * (size_t)(g->n_elems * nen));
  for (int k = 0; k < g->n_elems * nen; ++k) conn32[k] = g->conn[k];
  const int graph = corot_node_graph(nn, g->n_elems, nen, conn32, &tb->row_ptr, &tb->cols);
  free(conn32);
  if (graph != 0) return -1;
  const int64_t used = tb->row_ptr[nn];
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

/* The two bodies of the kernel tests: the unit disk (disk.geo refine 0.5: 48 quad4, E 1000, nu 0.3, rho 2, contact
 * surface the rim) and a unit cube of 8 hex8 (E 500, nu 0.25, rho 1) spinning about a tilted axis, with its ymin face
 * as contact surface. */
static inline int load_unit_disk(test_body *tb) {
  static const double axis_z[3] = {0, 0, 1};
  const sk_mesh_param params[] = {{"radius", 1.0}, {"refine", 0.5}};
  return test_body_load(tb, "meshes/disk.geo", params, 2, "body", "boundary", 1000.0, 0.3, 2.0, axis_z);
}
static inline int load_tilted_cube(test_body *tb) {
  static const double axis_tilted[3] = {0.2, 0.1, 1.0};
  const sk_mesh_param params[] = {{"nx", 2}, {"ny", 2}, {"nz", 2}, {"x0", -0.5}, {"y0", -0.5}, {"z0", -0.4}};
  return test_body_load(tb, "meshes/block.geo", params, 6, "body", "ymin", 500.0, 0.25, 1.0, axis_tilted);
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

/* A random mid-flight state (u ~ 0.01 L, s ~ 3 L, theta 0.4, w 7) and world loads f ~ 50, for derivative tests. */
static inline void random_state(const corot_body *b, corot_state *state, double *f_world) {
  const double L = sqrt(b->inertia / b->mass_total);
  for (int i = 0; i < b->n; ++i) {
    state->u[i] = 0.01 * L * corot_rand();
    state->s[i] = 3.0 * L * corot_rand();
    f_world[i] = 50.0 * corot_rand();
  }
  state->theta = 0.4;
  state->w = 7.0;
}

static inline double vec_norm(int n, const double *v) {
  double s = 0.0;
  for (int i = 0; i < n; ++i) s += v[i] * v[i];
  return sqrt(s);
}

#endif
