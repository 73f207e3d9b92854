/* The plugin test kit (plugin_kit.h): a mock host over small hand-built meshes and the finite-difference check of the
 * assembled operator through the plugin interface. */
#define _GNU_SOURCE
#include "plugin_kit.h"

#include <dlfcn.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../core/model/host.h"
#include "sk_test.h"
#include "stickslip/fe.h"
#include "stickslip/plugins.h"

struct kit_view {
  sk_view_data data;
};

/* The mock handle: the real struct first (unused), then the kit. */
typedef struct kit_host {
  struct sk_host real;
  kit *k;
} kit_host;

static kit *kit_of(sk_host *host) { return ((kit_host *)(void *)host)->k; }

/* ---- the mock api ----------------------------------------------------------------------------------------------- */

static void mock_ranks(const sk_host *host, int *rank, int *n_ranks) {
  (void)host;
  *rank = 0;
  *n_ranks = 1;
}

static int find_param(const kit *k, const char *key) {
  for (int i = 0; i < k->n_params; ++i)
    if (strcmp(k->key[i], key) == 0) return i;
  return -1;
}

static sk_status mock_param_double(sk_host *host, const char *key, int required, double dflt, double *out) {
  const kit *k = kit_of(host);
  const int i = find_param(k, key);
  if (i < 0 || k->text[i]) {
    if (required) return sk_error_set(SK_ERR_INPUT, "test scene: missing key '%s'", key);
    *out = dflt;
    return SK_OK;
  }
  *out = k->value[i];
  return SK_OK;
}

static sk_status mock_param_int(sk_host *host, const char *key, int required, int dflt, int *out) {
  double v = 0.0;
  SK_TRY(mock_param_double(host, key, required, dflt, &v));
  if (v != floor(v)) return sk_error_set(SK_ERR_INPUT, "test scene: key '%s' expects an integer, got %g", key, v);
  *out = (int)v;
  return SK_OK;
}

static sk_status mock_param_string(sk_host *host, const char *key, int required, const char *dflt, const char **out) {
  const kit *k = kit_of(host);
  const int i = find_param(k, key);
  if (i < 0 || !k->text[i]) {
    if (required) return sk_error_set(SK_ERR_INPUT, "test scene: missing key '%s'", key);
    *out = dflt;
    return SK_OK;
  }
  *out = k->text[i];
  return SK_OK;
}

static sk_status mock_error(sk_host *host, sk_status code, const char *fmt, ...) {
  (void)host;
  char message[1024];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(message, sizeof message, fmt, ap);
  va_end(ap);
  return sk_error_set(code, "%s", message);
}

static void mock_log(sk_host *host, int level, const char *fmt, ...) {
  (void)host, (void)level, (void)fmt;
}

static sk_status mock_reduce(sk_host *host, int op, double *values, int n) {
  (void)host, (void)values, (void)n;
  return op == 0 || op == 1 ? SK_OK : sk_error_set(SK_ERR_PLUGIN, "reduce: bad op %d", op);
}

static sk_instance *mock_body_instance(sk_host *host, int body) {
  (void)host, (void)body;
  return NULL;
}

static sk_status mock_condense_pair(sk_host *host, int64_t n_groups, int block, const int64_t *extra_index,
                                    const int64_t *rows) {
  kit *k = kit_of(host);
  const int64_t n = n_groups * block;
  free(k->pair_extra);
  free(k->pair_row);
  k->pair_extra = malloc(sizeof(int64_t) * (size_t)(n + 1));
  k->pair_row = malloc(sizeof(int64_t) * (size_t)(n + 1));
  if (n > 0) {
    memcpy(k->pair_extra, extra_index, sizeof(int64_t) * (size_t)n);
    memcpy(k->pair_row, rows, sizeof(int64_t) * (size_t)n);
  }
  k->n_pairs = n;
  k->pair_block = block;
  return SK_OK;
}

static const sk_condense_ext mock_condense = {SK_TABLE_HEADER(sk_condense_ext), .pair = mock_condense_pair};

/* stickslip.scene.v1: the description kit_create builds from the views and kit_material, and the defaults the
 * instance reports (kit.computed_*). */
static const sk_scene_info *mock_scene_info(sk_host *host) { return &kit_of(host)->scene; }

static void mock_computed(sk_host *host, const char *key, double value, const char *fmt, ...) {
  kit *k = kit_of(host);
  (void)fmt;
  if (k->n_computed == KIT_MAX_PARAMS) return;
  snprintf(k->computed_key[k->n_computed], sizeof k->computed_key[0], "%s", key);
  k->computed_value[k->n_computed++] = value;
}

static const sk_scene_ext mock_scene = {SK_TABLE_HEADER(sk_scene_ext), .info = mock_scene_info,
                                        .computed = mock_computed};

static const void *mock_extension(sk_host *host, const char *id) {
  (void)host;
  if (strcmp(id, SK_EXT_SCENE) == 0) return &mock_scene;
  return strcmp(id, SK_EXT_CONDENSE) == 0 ? &mock_condense : NULL;
}

/* ---- meshes and views ------------------------------------------------------------------------------------------- */

void kit_init(kit *k, int dim, int n_nodes, const double *X) {
  memset(k, 0, sizeof *k);
  k->dim = dim;
  k->n_nodes = n_nodes;
  k->n_dofs = n_nodes * dim;
  k->X = malloc(sizeof(double) * (size_t)k->n_dofs);
  memcpy(k->X, X, sizeof(double) * (size_t)k->n_dofs);
  k->alpha = 1.0;
  for (int role = 0; role < 2; ++role) k->E[role] = 1.0; /* kit_material; nu 0 */
  k->api = (sk_host_api){SK_TABLE_HEADER(sk_host_api),
                         .contact = &sk_host_contact_table,
                         .ranks = mock_ranks,
                         .param_double = mock_param_double,
                         .param_int = mock_param_int,
                         .param_string = mock_param_string,
                         .error = mock_error,
                         .log = mock_log,
                         .reduce = mock_reduce,
                         .body_instance = mock_body_instance,
                         .get_extension = mock_extension};
  k->host = calloc(1, sizeof *k->host);
  k->host->k = k;
  k->attach.struct_size = sizeof k->attach;
  k->attach.kind = SK_KIND_PAIR;
  k->attach.name = "test pair";
}

void kit_param(kit *k, const char *key, double value) {
  k->key[k->n_params] = key;
  k->text[k->n_params] = NULL;
  k->value[k->n_params++] = value;
}

void kit_param_text(kit *k, const char *key, const char *value) {
  k->key[k->n_params] = key;
  k->text[k->n_params] = value;
  k->value[k->n_params++] = 0.0;
}

static int compare_int(const void *a, const void *b) { return *(const int *)a - *(const int *)b; }


/* The core surface of n_faces faces (mesh node ids): sorted node list, neighbours through shared corners (2D: the
 * end point itself). The caller frees conn, nodes and face_neighbors. */
static void make_surface(sk_surface *s, int dim, sk_elem_type type, int nen, int n_faces, const int *conn) {
  const int nc = sk_elem_corners(type);
  memset(s, 0, sizeof *s);
  snprintf(s->name, sizeof s->name, "surface");
  s->dim = dim;
  s->face_type = type;
  s->nen = nen;
  s->n_faces = n_faces;
  s->n_edges = nc;
  s->conn = malloc(sizeof(int) * (size_t)(n_faces * nen));
  s->nodes = malloc(sizeof(int) * (size_t)(n_faces * nen));
  s->face_neighbors = malloc(sizeof(int) * (size_t)(n_faces * nc));
  memcpy(s->conn, conn, sizeof(int) * (size_t)(n_faces * nen));
  for (int i = 0; i < n_faces * nen; ++i) {
    int seen = 0;
    for (int j = 0; j < s->n_nodes; ++j) seen |= s->nodes[j] == conn[i];
    if (!seen) s->nodes[s->n_nodes++] = conn[i];
  }
  qsort(s->nodes, (size_t)s->n_nodes, sizeof(int), compare_int);
  for (int f = 0; f < n_faces; ++f)
    for (int e = 0; e < nc; ++e) {
      s->face_neighbors[f * nc + e] = -1;
      const int a = conn[f * nen + e], b = conn[f * nen + (e + 1) % nc];
      for (int g = 0; g < n_faces; ++g) {
        if (g == f) continue;
        int has_a = 0, has_b = 0;
        for (int c = 0; c < nc; ++c) {
          has_a |= conn[g * nen + c] == a;
          has_b |= conn[g * nen + c] == b;
        }
        if (dim == 2 ? has_a : (has_a && has_b)) s->face_neighbors[f * nc + e] = g;
      }
    }
}

void kit_surface(kit *k, int role, sk_elem_type type, int nen, int n_faces, const int *conn) {
  kit_view *kv = calloc(1, sizeof *kv);
  sk_surface s;
  make_surface(&s, k->dim, type, nen, n_faces, conn);
  /* the host's view of a whole surface on one rank: every face and node owned */
  SK_CHECK(sk_view_fill_surface(&kv->data, &s, role == 0 ? "slave" : "master", k->dim, k->X) == SK_OK);
  sk_surface_free(&s);
  k->views[role] = kv;
  k->view_list[role] = &kv->data.view;
  if (role + 1 > k->n_views) k->n_views = role + 1;
  if (role == 0) k->attach.slave = k->view_list[role];
  else k->attach.master = k->view_list[role];
}

void kit_obstacle(kit *k, const sk_obstacle *obstacle) {
  k->obstacle = *obstacle;
  k->attach.obstacle = &k->obstacle;
}

void kit_material(kit *k, int role, double E, double nu) {
  k->E[role] = E;
  k->nu[role] = nu;
}

double kit_computed(const kit *k, const char *key) {
  for (int i = 0; i < k->n_computed; ++i)
    if (strcmp(k->computed_key[i], key) == 0) return k->computed_value[i];
  return NAN;
}

/* The scene description of the kit's attachment (kit_create): sizes of the views, the materials of kit_material. */
static void describe(kit *k) {
  for (int role = 0; role < 2; ++role) {
    sk_scene_side *side = &k->sides[role];
    memset(side, 0, sizeof *side);
    side->struct_size = sizeof *side;
    if (role == 1 && k->attach.obstacle) {
      side->name = side->body_name = "obstacle";
      side->body = -1;
      side->rigid = 1;
      side->shape = (sk_obstacle_shape)(SK_SHAPE_PLANE + (int)k->obstacle.kind);
      side->E = INFINITY;
      continue;
    }
    if (role >= k->n_views) continue;
    const kit_view *kv = k->views[role];
    side->name = side->body_name = role == 0 ? "slave" : "master";
    side->body = role;
    side->E = k->E[role];
    side->nu = k->nu[role];
    side->cell_type = kv->data.view.cell_type;
    side->order = sk_elem_order(side->cell_type);
    sk_surface_sizes(&kv->data.local, kv->data.view.X, k->dim, &side->h_min, &side->h_mean, &side->h_max,
                     &side->measure);
    side->n_cells = kv->data.view.n_cells;
    side->n_nodes = kv->data.view.n_nodes;
  }
  k->scene = (sk_scene_info){.struct_size = sizeof k->scene, .kind = SK_KIND_PAIR, .name = k->attach.name,
                             .dim = k->dim, .scheme = k->alpha == 1.0 ? "quasi-static" : "midpoint",
                             .alpha = k->alpha, .dynamic = k->dynamic, .n_ranks = 1, .strategy = k->attach.strategy,
                             .self_contact = k->attach.self_contact, .slave = &k->sides[0],
                             .master = &k->sides[1]};
}

void kit_integrator(kit *k, double alpha, int dynamic) {
  k->alpha = alpha;
  k->dynamic = dynamic;
}

/* ---- the instance ----------------------------------------------------------------------------------------------- */

sk_status kit_create(kit *k, const sk_plugin *plugin, int strategy) {
  k->plugin = plugin;
  k->attach.strategy = strategy;
  k->attach.n_views = k->n_views;
  k->attach.views = k->view_list;
  for (int v = 0; v < k->n_views; ++v) {
    const int n = k->view_list[v]->n_nodes * k->dim;
    k->x[v] = calloc((size_t)n, sizeof(double));
    k->x_n[v] = calloc((size_t)n, sizeof(double));
    k->v_n[v] = calloc((size_t)n, sizeof(double));
    k->xl[v] = k->x[v];
    k->x_nl[v] = k->x_n[v];
    k->v_nl[v] = k->v_n[v];
  }
  k->state.struct_size = sizeof k->state;
  k->state.n_views = k->n_views;
  k->state.x = k->xl;
  k->state.x_n = k->x_nl;
  k->state.scheme = "test";
  k->n = k->n_dofs;
  describe(k);
  k->n_computed = 0;
  return plugin->create(&k->api, (sk_host *)(void *)k->host, &k->attach, &k->instance);
}

void kit_destroy(kit *k) {
  if (k->instance) k->plugin->destroy(k->instance);
  k->instance = NULL;
}

void kit_free(kit *k) {
  kit_destroy(k);
  for (int v = 0; v < KIT_MAX_VIEWS; ++v) {
    if (k->views[v]) sk_view_free(&k->views[v]->data);
    free(k->views[v]);
    free(k->x[v]);
    free(k->x_n[v]);
    free(k->v_n[v]);
  }
  free(k->X);
  free(k->host);
  free(k->extra);
  free(k->declared);
  free(k->pair_extra);
  free(k->pair_row);
  memset(k, 0, sizeof *k);
}

static void gather(const sk_view *view, const double *global, double *local) {
  for (int i = 0; i < view->n_nodes * view->dim; ++i) local[i] = global[view->dofs[i]];
}

void kit_state(kit *k, const double *q_n, const double *q, double t_n, double t, const double *v_n) {
  sk_state *st = &k->state;
  st->t_n = t_n;
  st->t = t;
  st->dt = t - t_n;
  st->alpha = k->alpha;
  st->dynamic = k->dynamic;
  for (int v = 0; v < k->n_views; ++v) {
    gather(k->view_list[v], q_n, k->x_n[v]);
    gather(k->view_list[v], q, k->x[v]);
    if (v_n) gather(k->view_list[v], v_n, k->v_n[v]);
  }
  st->v_n = v_n ? k->v_nl : NULL;
  st->extra = k->extra;
  st->n_extra = k->layout.n_extra;
  st->extra_offset = k->n_dofs;
}

static void set_positions(kit *k, const double *q) {
  for (int v = 0; v < k->n_views; ++v) gather(k->view_list[v], q, k->x[v]);
}

/* ---- dense sinks ------------------------------------------------------------------------------------------------ */

typedef struct {
  sk_sink abi;
  kit *k;
  double *F, *J, *rhs;
} dense_sink;

typedef struct {
  sk_pattern abi;
  kit *k;
} dense_pattern;

static void dense_vector(sk_sink *sink, int n, const int64_t *rows, const double *values) {
  dense_sink *d = (dense_sink *)sink;
  for (int i = 0; i < n; ++i)
    if (rows[i] >= 0 && rows[i] < d->k->n) d->F[rows[i]] += values[i];
}

static void dense_rhs(sk_sink *sink, int n, const int64_t *rows, const double *values) {
  dense_sink *d = (dense_sink *)sink;
  for (int i = 0; i < n && d->rhs; ++i)
    if (rows[i] >= 0 && rows[i] < d->k->n) d->rhs[rows[i]] += values[i];
}

/* an entry the host would have without a declaration: the diagonal, or within one node's block */
static int implicit_entry(const kit *k, int64_t r, int64_t c) {
  return r == c || (r < k->n_dofs && c < k->n_dofs && r / k->dim == c / k->dim);
}

static void dense_matrix(sk_sink *sink, int nr, const int64_t *rows, int nc, const int64_t *cols,
                         const double *values) {
  dense_sink *d = (dense_sink *)sink;
  kit *k = d->k;
  for (int i = 0; i < nr; ++i)
    for (int j = 0; j < nc; ++j) {
      const double v = values[i * nc + j];
      if (rows[i] < 0 || rows[i] >= k->n || cols[j] < 0 || cols[j] >= k->n || v == 0.0) continue;
      d->J[rows[i] * k->n + cols[j]] += v;
      if (k->declared && !k->declared[rows[i] * k->n + cols[j]] && !implicit_entry(k, rows[i], cols[j]))
        k->outside_pattern++;
    }
}

static void dense_block(sk_pattern *pattern, int nr, const int64_t *rows, int nc, const int64_t *cols) {
  kit *k = ((dense_pattern *)pattern)->k;
  for (int i = 0; i < nr; ++i)
    for (int j = 0; j < nc; ++j)
      if (rows[i] >= 0 && rows[i] < k->n && cols[j] >= 0 && cols[j] < k->n) k->declared[rows[i] * k->n + cols[j]] = 1;
}

static dense_sink make_sink(kit *k, double *F, double *J, double *rhs) {
  dense_sink d = {.abi = {SK_TABLE_HEADER(sk_sink), .add_vector = dense_vector, .add_matrix = dense_matrix,
                          .add_rhs = dense_rhs},
                  .k = k, .F = F, .J = J, .rhs = rhs};
  return d;
}

static sk_status declare_pattern(kit *k) {
  free(k->declared);
  k->declared = NULL;
  k->outside_pattern = 0;
  if (!k->plugin->pattern) return SK_OK;
  k->declared = calloc((size_t)(k->n * k->n), 1);
  dense_pattern p = {.abi = {SK_TABLE_HEADER(sk_pattern), .add_block = dense_block}, .k = k};
  return k->plugin->pattern(k->instance, &k->state, &p.abi);
}

sk_status kit_begin(kit *k) {
  SK_TRY(k->plugin->begin_step(k->instance, &k->state));
  memset(&k->layout, 0, sizeof k->layout);
  k->layout.struct_size = sizeof k->layout;
  SK_TRY(k->plugin->layout(k->instance, &k->state, &k->layout));
  k->n = k->n_dofs + k->layout.n_extra;
  free(k->extra);
  k->extra = calloc((size_t)k->layout.n_extra + 1, sizeof(double));
  if (k->layout.initial) memcpy(k->extra, k->layout.initial, sizeof(double) * (size_t)k->layout.n_extra);
  k->state.extra = k->extra;
  k->state.n_extra = k->layout.n_extra;
  return declare_pattern(k);
}

sk_status kit_layout_again(kit *k) {
  const int64_t n_extra = k->layout.n_extra;
  memset(&k->layout, 0, sizeof k->layout);
  k->layout.struct_size = sizeof k->layout;
  SK_TRY(k->plugin->layout(k->instance, &k->state, &k->layout));
  if (k->layout.n_extra != n_extra)
    return sk_error_set(SK_ERR_PLUGIN, "layout again: %lld extra unknowns instead of %lld",
                        (long long)k->layout.n_extra, (long long)n_extra);
  return declare_pattern(k);
}

sk_status kit_converged(kit *k, const double *q, int *accept) {
  *accept = 1;
  set_positions(k, q);
  return k->plugin->converged ? k->plugin->converged(k->instance, &k->state, accept) : SK_OK;
}

sk_status kit_update_active_set(kit *k, const double *q, int *changed) {
  *changed = 0;
  set_positions(k, q);
  return k->plugin->update_active_set ? k->plugin->update_active_set(k->instance, &k->state, changed) : SK_OK;
}

sk_status kit_residual(kit *k, const double *q, double *F) {
  set_positions(k, q);
  memset(F, 0, sizeof(double) * (size_t)k->n);
  dense_sink d = make_sink(k, F, NULL, NULL);
  return k->plugin->residual(k->instance, &k->state, &d.abi);
}

sk_status kit_jacobian(kit *k, const double *q, double *J, double *rhs) {
  set_positions(k, q);
  memset(J, 0, sizeof(double) * (size_t)(k->n * k->n));
  if (rhs) memset(rhs, 0, sizeof(double) * (size_t)k->n);
  dense_sink d = make_sink(k, NULL, J, rhs);
  return k->plugin->jacobian(k->instance, &k->state, &d.abi);
}

void kit_fd_jacobian(kit *k, const double *q0, double h, double *J_fd) {
  const int64_t n = k->n;
  double *Fp = calloc((size_t)n, sizeof(double)), *Fm = calloc((size_t)n, sizeof(double));
  double *q = malloc(sizeof(double) * (size_t)k->n_dofs);
  memcpy(q, q0, sizeof(double) * (size_t)k->n_dofs);
  for (int64_t j = 0; j < n; ++j) {
    double *target = j < k->n_dofs ? &q[j] : &k->extra[j - k->n_dofs];
    const double saved = *target;
    *target = saved + h;
    SK_CHECK(kit_residual(k, q, Fp) == SK_OK);
    *target = saved - h;
    SK_CHECK(kit_residual(k, q, Fm) == SK_OK);
    *target = saved;
    for (int64_t i = 0; i < n; ++i) J_fd[i * n + j] = (Fp[i] - Fm[i]) / (2.0 * h);
  }
  set_positions(k, q0);
  free(Fp);
  free(Fm);
  free(q);
}

double kit_fd_check(kit *k, const double *q0, double h, double *scale) {
  const int64_t n = k->n;
  double *J = calloc((size_t)(n * n), sizeof(double)), *J_fd = calloc((size_t)(n * n), sizeof(double));
  SK_CHECK(kit_jacobian(k, q0, J, NULL) == SK_OK);
  kit_fd_jacobian(k, q0, h, J_fd);
  double worst = 0.0, big = 0.0;
  for (int64_t i = 0; i < n * n; ++i) {
    big = fmax(big, fabs(J[i]));
    worst = fmax(worst, fabs(J_fd[i] - J[i]));
  }
  free(J);
  free(J_fd);
  if (scale) *scale = big;
  return worst;
}

/* A (m x m, row-major) overwritten; B (m x nb) <- A^-1 B. Partial pivoting. Returns -1 when singular. */
static int dense_solve(int m, double *A, double *B, int nb) {
  for (int c = 0; c < m; ++c) {
    int piv = c;
    for (int i = c + 1; i < m; ++i)
      if (fabs(A[i * m + c]) > fabs(A[piv * m + c])) piv = i;
    if (A[piv * m + c] == 0.0) return -1;
    for (int j = 0; j < m && piv != c; ++j) {
      const double t = A[c * m + j];
      A[c * m + j] = A[piv * m + j];
      A[piv * m + j] = t;
    }
    for (int j = 0; j < nb && piv != c; ++j) {
      const double t = B[c * nb + j];
      B[c * nb + j] = B[piv * nb + j];
      B[piv * nb + j] = t;
    }
    for (int i = c + 1; i < m; ++i) {
      const double l = A[i * m + c] / A[c * m + c];
      for (int j = c; j < m; ++j) A[i * m + j] -= l * A[c * m + j];
      for (int j = 0; j < nb; ++j) B[i * nb + j] -= l * B[c * nb + j];
    }
  }
  for (int c = m - 1; c >= 0; --c)
    for (int j = 0; j < nb; ++j) {
      double v = B[c * nb + j];
      for (int l = c + 1; l < m; ++l) v -= A[c * m + l] * B[l * nb + j];
      B[c * nb + j] = v / A[c * m + c];
    }
  return 0;
}

double kit_fd_check_condensed(kit *k, const double *q0, double h, double *scale, double *rhs_error) {
  const int64_t n = k->n;
  double *J = calloc((size_t)(n * n), sizeof(double)), *rhs = calloc((size_t)n, sizeof(double));
  double *J_fd = calloc((size_t)(n * n), sizeof(double)), *F = calloc((size_t)n, sizeof(double));
  SK_CHECK(kit_jacobian(k, q0, J, rhs) == SK_OK);
  SK_CHECK(kit_residual(k, q0, F) == SK_OK);
  kit_fd_jacobian(k, q0, h, J_fd);
  int *e = malloc(sizeof(int) * (size_t)n);
  int ne = 0;
  for (int64_t j = k->n_dofs; j < n; ++j)
    if (k->layout.eliminated && k->layout.eliminated[j - k->n_dofs]) e[ne++] = (int)j;
  /* X = J_ee^-1 [J_ek | F_e] over all columns (the kept ones are read) */
  double *Jee = calloc((size_t)(ne * ne) + 1, sizeof(double)), *X = calloc((size_t)(ne * (n + 1)) + 1, sizeof(double));
  for (int a = 0; a < ne; ++a) {
    for (int b = 0; b < ne; ++b) Jee[a * ne + b] = J_fd[e[a] * n + e[b]];
    for (int64_t j = 0; j < n; ++j) X[a * (n + 1) + j] = J_fd[e[a] * n + j];
    X[a * (n + 1) + n] = F[e[a]];
  }
  SK_CHECK(ne == 0 || dense_solve(ne, Jee, X, (int)n + 1) == 0);
  unsigned char *is_e = calloc((size_t)n, 1);
  for (int a = 0; a < ne; ++a) is_e[e[a]] = 1;
  double worst = 0.0, big = 0.0, worst_rhs = 0.0;
  for (int64_t i = 0; i < n; ++i) {
    double r = 0.0;
    for (int a = 0; a < ne; ++a) r += J_fd[i * n + e[a]] * X[a * (n + 1) + n];
    if (!is_e[i]) worst_rhs = fmax(worst_rhs, fabs(rhs[i] - r));
    for (int64_t j = 0; j < n; ++j) {
      big = fmax(big, fabs(J[i * n + j]));
      if (is_e[i] || is_e[j]) {
        worst = fmax(worst, fabs(J[i * n + j])); /* the plugin must not touch eliminated rows or columns */
        continue;
      }
      double s = J_fd[i * n + j];
      for (int a = 0; a < ne; ++a) s -= J_fd[i * n + e[a]] * X[a * (n + 1) + j];
      worst = fmax(worst, fabs(J[i * n + j] - s));
    }
  }
  free(J);
  free(rhs);
  free(J_fd);
  free(F);
  free(e);
  free(Jee);
  free(X);
  free(is_e);
  if (scale) *scale = big;
  if (rhs_error) *rhs_error = worst_rhs;
  return worst;
}

sk_status kit_recover(kit *k, const double *q, const double *F, double *dx) {
  if (!k->plugin->recover) return SK_OK;
  set_positions(k, q);
  double *F_view[KIT_MAX_VIEWS] = {NULL}, *dx_view[KIT_MAX_VIEWS] = {NULL};
  const double *F_list[KIT_MAX_VIEWS] = {NULL}, *dx_list[KIT_MAX_VIEWS] = {NULL};
  for (int v = 0; v < k->n_views; ++v) {
    const int n = k->view_list[v]->n_nodes * k->dim;
    F_view[v] = malloc(sizeof(double) * (size_t)n);
    dx_view[v] = malloc(sizeof(double) * (size_t)n);
    gather(k->view_list[v], F, F_view[v]);
    gather(k->view_list[v], dx, dx_view[v]);
    F_list[v] = F_view[v];
    dx_list[v] = dx_view[v];
  }
  sk_vectors vectors = {.struct_size = sizeof vectors, .F_view = F_list, .F_extra = F + k->n_dofs,
                        .dx_view = dx_list, .dx_extra = dx + k->n_dofs};
  const sk_status status = k->plugin->recover(k->instance, &k->state, &vectors);
  for (int v = 0; v < k->n_views; ++v) {
    free(F_view[v]);
    free(dx_view[v]);
  }
  return status;
}

sk_status kit_commit(kit *k) { return k->plugin->commit_step(k->instance, &k->state); }

sk_status kit_report(kit *k, sk_contact_report *report) {
  memset(report, 0, sizeof *report);
  report->struct_size = sizeof *report;
  return k->plugin->report(k->instance, &k->state, report);
}

static void collect_point(void *ctx, const sk_contact_point *point) {
  kit_points *list = ctx;
  if (list->n < (int)(sizeof list->p / sizeof list->p[0])) list->p[list->n++] = *point;
}

sk_status kit_points_at(kit *k, kit_points *points) {
  points->n = 0;
  return k->plugin->points ? k->plugin->points(k->instance, &k->state, collect_point, points) : SK_OK;
}

const sk_contact_point *kit_point_of(const kit_points *points, int64_t node) {
  for (int i = 0; i < points->n; ++i)
    if (points->p[i].slave_node == node) return &points->p[i];
  return NULL;
}

const sk_plugin *kit_load_module(const char *path, const char *name, const char *internal_symbol) {
  const sk_plugin *plugin = NULL;
  if (sk_plugin_open_file(path, &plugin) != SK_OK) {
    fprintf(stderr, "%s: %s\n", path, sk_error_message());
    SK_CHECK(plugin != NULL);
    return NULL;
  }
  SK_CHECK(plugin->abi_major == SK_ABI_MAJOR && plugin->struct_size >= sizeof(sk_plugin));
  SK_CHECK(strcmp(plugin->name, name) == 0);
  SK_CHECK(plugin->kinds != 0 && plugin->summary && plugin->parameters);
  void *module = dlopen(path, RTLD_NOW | RTLD_LOCAL);
  SK_CHECK(module != NULL);
  if (module) {
    /* hidden visibility: only the entry symbol is exported */
    SK_CHECK(dlsym(module, SK_PLUGIN_ENTRY_SYMBOL) != NULL);
    if (internal_symbol) SK_CHECK(dlsym(module, internal_symbol) == NULL);
    dlclose(module);
  }
  return plugin;
}
