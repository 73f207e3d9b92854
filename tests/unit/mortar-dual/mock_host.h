/* A small host of plugin ABI v2 for the mortar-dual tests: hand-made surface views, parameters from a key list, a
 * brute-force search, analytic obstacles (a line/plane y|z = c or a circle/sphere), the core's shape functions, an
 * identity reduce (one rank), a recording stickslip.condense.v1, and dense sinks over all unknowns. */
#ifndef MORTAR_MOCK_HOST_H
#define MORTAR_MOCK_HOST_H

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "stickslip/fe.h"
#include "stickslip/plugin.h"

const sk_plugin *stickslip_plugin_entry(void);

enum { MOCK_MAX_KEYS = 16, MOCK_MAX_UNKNOWNS = 256, MOCK_MAX_PAIRS = 64 };

struct sk_obstacle {
  int sphere;         /* 0: the plane x[dim-1] = level (outward normal +e_dim); 1: a circle/sphere */
  double level;
  double centre[3], radius;
  double velocity[3]; /* translation d(t) = velocity t */
};

struct sk_host {
  int n_keys;
  const char *keys[MOCK_MAX_KEYS];
  const char *values[MOCK_MAX_KEYS];
  char last_error[512];
  int64_t n_pairs, pair_extra[MOCK_MAX_PAIRS], pair_row[MOCK_MAX_PAIRS];
  int pair_block;
};

static const char *mock_value(sk_host *host, const char *key) {
  for (int i = 0; i < host->n_keys; ++i)
    if (strcmp(host->keys[i], key) == 0) return host->values[i];
  return NULL;
}

static sk_status mock_error(sk_host *host, sk_status code, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(host->last_error, sizeof host->last_error, fmt, ap);
  va_end(ap);
  return code;
}

static void mock_log(sk_host *host, int level, const char *fmt, ...) {
  (void)host;
  (void)level;
  (void)fmt;
}

static sk_status mock_param_double(sk_host *host, const char *key, int required, double dflt, double *out) {
  const char *v = mock_value(host, key);
  if (!v) {
    if (required) return mock_error(host, SK_ERR_INPUT, "missing %s", key);
    *out = dflt;
    return SK_OK;
  }
  *out = atof(v);
  return SK_OK;
}

static sk_status mock_param_int(sk_host *host, const char *key, int required, int dflt, int *out) {
  double v = dflt;
  const sk_status st = mock_param_double(host, key, required, dflt, &v);
  if (st == SK_OK) *out = (int)v;
  return st;
}

static sk_status mock_param_string(sk_host *host, const char *key, int required, const char *dflt, const char **out) {
  const char *v = mock_value(host, key);
  if (!v && required) return mock_error(host, SK_ERR_INPUT, "missing %s", key);
  *out = v ? v : dflt;
  return SK_OK;
}

static void mock_ranks(const sk_host *host, int *rank, int *n) {
  (void)host;
  *rank = 0;
  *n = 1;
}

static sk_status mock_reduce(sk_host *host, int op, double *values, int n) {
  (void)host;
  (void)op;
  (void)values;
  (void)n;
  return SK_OK;
}

static sk_status mock_pair(sk_host *host, int64_t n_groups, int block, const int64_t *extra, const int64_t *rows) {
  host->n_pairs = n_groups * block;
  host->pair_block = block;
  for (int64_t i = 0; i < host->n_pairs && i < MOCK_MAX_PAIRS; ++i) {
    host->pair_extra[i] = extra[i];
    host->pair_row[i] = rows[i];
  }
  return SK_OK;
}

static const sk_condense_ext mock_condense = {SK_TABLE_HEADER(sk_condense_ext), mock_pair};

static const void *mock_extension(sk_host *host, const char *id) {
  (void)host;
  return strcmp(id, SK_EXT_CONDENSE) == 0 ? &mock_condense : NULL;
}

/* search: every face (the plugin's kernel rejects pairs that do not overlap) */
struct sk_search {
  int n;
};
static struct sk_search mock_tree;
static sk_status mock_search_create(const sk_view *v, sk_search **s) {
  mock_tree.n = v->n_cells;
  *s = &mock_tree;
  return SK_OK;
}
static void mock_search_destroy(sk_search *s) { (void)s; }
static void mock_search_update(sk_search *s, const double *x0, const double *x1, double margin) {
  (void)s;
  (void)x0;
  (void)x1;
  (void)margin;
}
static int mock_search_query(const sk_search *s, const double lo[3], const double hi[3], int *faces, int max) {
  (void)lo;
  (void)hi;
  for (int f = 0; f < s->n && f < max; ++f) faces[f] = f;
  return s->n;
}

static void mock_obstacle_displacement(const sk_obstacle *o, double t, double d[3]) {
  for (int i = 0; i < 3; ++i) d[i] = o->velocity[i] * t;
}

static sk_status mock_obstacle_project(const sk_obstacle *o, double t, const double *x, int dim, sk_surface_point *pt,
                                       double *gap) {
  double d[3];
  mock_obstacle_displacement(o, t, d);
  memset(pt->n, 0, sizeof pt->n);
  if (!o->sphere) {
    pt->n[dim - 1] = 1.0;
    *gap = x[dim - 1] - (o->level + d[dim - 1]);
    return SK_OK;
  }
  double r = 0.0;
  for (int i = 0; i < dim; ++i) r += (x[i] - o->centre[i] - d[i]) * (x[i] - o->centre[i] - d[i]);
  r = sqrt(r);
  for (int i = 0; i < dim; ++i) pt->n[i] = (x[i] - o->centre[i] - d[i]) / r;
  *gap = r - o->radius;
  return SK_OK;
}

static const sk_contact_services mock_services = {
    .abi_major = SK_ABI_MAJOR,
    .abi_minor = SK_ABI_MINOR,
    .struct_size = sizeof(sk_contact_services),
    .search_create = mock_search_create,
    .search_destroy = mock_search_destroy,
    .search_update = mock_search_update,
    .search_query = mock_search_query,
    .obstacle_project = mock_obstacle_project,
    .obstacle_displacement = mock_obstacle_displacement,
    .shape = sk_elem_shape,
    .shape_hessian = sk_elem_shape_hessian,
};

static const sk_host_api mock_api = {
    SK_TABLE_HEADER(sk_host_api),
    .contact = &mock_services,
    .ranks = mock_ranks,
    .param_double = mock_param_double,
    .param_int = mock_param_int,
    .param_string = mock_param_string,
    .error = mock_error,
    .log = mock_log,
    .reduce = mock_reduce,
    .get_extension = mock_extension,
};

/* ---- a view of a whole surface owned by this (only) rank: dofs node * dim + i of a global numbering -------------- */
typedef struct {
  sk_view view;
  int32_t conn[64];
  unsigned char cell_owned[32], owned[64];
  int64_t cell_index[32], node_index[64], node_id[64], dofs[192];
  int32_t neighbors[128];
  double X[192];
} mock_view;

/* Faces given by global node ids (gmsh order, oriented outward); nodes numbered in order of first appearance. */
static void mock_view_build(mock_view *m, const char *name, int dim, sk_elem_type type, int nen, int n_faces,
                            const int *face_nodes, const double *X_global) {
  memset(m, 0, sizeof *m);
  sk_view *v = &m->view;
  int ids[64], n = 0;
  for (int f = 0; f < n_faces; ++f)
    for (int a = 0; a < nen; ++a) {
      const int g = face_nodes[f * nen + a];
      int k = 0;
      while (k < n && ids[k] != g) ++k;
      if (k == n) ids[n++] = g;
      m->conn[f * nen + a] = k;
    }
  for (int k = 0; k < n; ++k) {
    m->node_index[k] = k;
    m->node_id[k] = ids[k];
    m->owned[k] = 1;
    for (int i = 0; i < dim; ++i) {
      m->dofs[k * dim + i] = (int64_t)ids[k] * dim + i;
      m->X[k * dim + i] = X_global[ids[k] * dim + i];
    }
  }
  const int n_edges = dim == 2 ? 2 : (type == SK_TRI3 ? 3 : 4);
  for (int f = 0; f < n_faces; ++f) {
    m->cell_owned[f] = 1;
    m->cell_index[f] = f;
    for (int e = 0; e < n_edges; ++e) {
      /* the face across edge e (2D: the face sharing end point e) */
      const int a = m->conn[f * nen + e], b = dim == 2 ? -1 : m->conn[f * nen + (e + 1) % n_edges];
      m->neighbors[f * n_edges + e] = -1;
      for (int g = 0; g < n_faces; ++g) {
        if (g == f) continue;
        int has_a = 0, has_b = b < 0;
        for (int c = 0; c < nen; ++c) {
          has_a |= m->conn[g * nen + c] == a;
          has_b |= m->conn[g * nen + c] == b;
        }
        if (has_a && has_b) m->neighbors[f * n_edges + e] = g;
      }
    }
  }
  v->struct_size = sizeof *v;
  v->name = name;
  v->dim = dim;
  v->cell_type = type;
  v->nen = nen;
  v->n_cells = n_faces;
  v->conn = m->conn;
  v->cell_owned = m->cell_owned;
  v->cell_index = m->cell_index;
  v->n_cells_global = n_faces;
  v->n_edges = n_edges;
  v->neighbors = m->neighbors;
  v->n_nodes = n;
  v->node_index = m->node_index;
  v->n_nodes_global = n;
  v->node_id = m->node_id;
  v->owned = m->owned;
  v->dofs = m->dofs;
  v->X = m->X;
}

/* positions of a view from a global vector (node * dim + i) */
static void mock_view_positions(const mock_view *m, const double *x_global, double *x) {
  const sk_view *v = &m->view;
  for (int k = 0; k < v->n_nodes; ++k)
    for (int i = 0; i < v->dim; ++i) x[k * v->dim + i] = x_global[v->node_id[k] * v->dim + i];
}

/* ---- dense sinks over all unknowns ---------------------------------------------------------------------------- */
typedef struct {
  int n;
  double F[MOCK_MAX_UNKNOWNS];
  double J[MOCK_MAX_UNKNOWNS * MOCK_MAX_UNKNOWNS];
  int64_t bad_row;
} mock_system;

typedef struct {
  sk_sink sink;
  mock_system *sys;
} mock_sink;

static void mock_add_vector(sk_sink *s, int n, const int64_t *rows, const double *values) {
  mock_system *sys = ((mock_sink *)s)->sys;
  for (int i = 0; i < n; ++i) {
    if (rows[i] < 0 || rows[i] >= sys->n) sys->bad_row = rows[i];
    else sys->F[rows[i]] += values[i];
  }
}

static void mock_add_matrix(sk_sink *s, int nr, const int64_t *rows, int nc, const int64_t *cols,
                            const double *values) {
  mock_system *sys = ((mock_sink *)s)->sys;
  for (int i = 0; i < nr; ++i)
    for (int j = 0; j < nc; ++j) {
      if (rows[i] < 0 || rows[i] >= sys->n || cols[j] < 0 || cols[j] >= sys->n) sys->bad_row = rows[i];
      else sys->J[rows[i] * sys->n + cols[j]] += values[i * nc + j];
    }
}

static inline void mock_sink_init(mock_sink *s, mock_system *sys) {
  memset(s, 0, sizeof *s);
  s->sink.abi_major = SK_ABI_MAJOR;
  s->sink.abi_minor = SK_ABI_MINOR;
  s->sink.struct_size = sizeof(sk_sink);
  s->sink.add_vector = mock_add_vector;
  s->sink.add_matrix = mock_add_matrix;
  s->sys = sys;
}

/* pattern: records every declared entry */
typedef struct {
  sk_pattern pattern;
  int n;
  unsigned char declared[MOCK_MAX_UNKNOWNS * MOCK_MAX_UNKNOWNS];
} mock_pattern;

static void mock_add_block(sk_pattern *p, int nr, const int64_t *rows, int nc, const int64_t *cols) {
  mock_pattern *m = (mock_pattern *)p;
  for (int i = 0; i < nr; ++i)
    for (int j = 0; j < nc; ++j)
      if (rows[i] >= 0 && rows[i] < m->n && cols[j] >= 0 && cols[j] < m->n) m->declared[rows[i] * m->n + cols[j]] = 1;
}

static inline void mock_pattern_init(mock_pattern *p, int n) {
  memset(p, 0, sizeof *p);
  p->pattern.abi_major = SK_ABI_MAJOR;
  p->pattern.abi_minor = SK_ABI_MINOR;
  p->pattern.struct_size = sizeof(sk_pattern);
  p->pattern.add_block = mock_add_block;
  p->n = n;
}

#endif
