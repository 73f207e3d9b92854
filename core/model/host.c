/* The host api of the plugin ABI (plugin.h: sk_host_api) and its extensions stickslip.bulk.v1,
 * stickslip.condense.v1, stickslip.linear.v1 and stickslip.scene.v1; and the one path for messages to the user
 * (sk_log_message). */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "assemble.h"
#include "stickslip/fe.h"
#include "term_plugin.h"

int sk_log_verbosity = 0;

static void log_va(int rank, int level, const char *fmt, va_list args) {
  /* warnings always; information unless --quiet (verbosity -1); debug with --verbose (1) */
  int shown = level == 1 || (level == 0 && sk_log_verbosity >= 0) || (level >= 2 && sk_log_verbosity > 0);
  if (rank != 0 || !shown) return;
  char message[2048];
  vsnprintf(message, sizeof message, fmt, args);
  fprintf(stderr, "%s%s\n", level == 1 ? "warning: " : "", message);
}

void sk_log_message(int rank, int level, const char *fmt, ...) {
  va_list args;
  va_start(args, fmt);
  log_va(rank, level, fmt, args);
  va_end(args);
}

/* ---- the api ---------------------------------------------------------------------------------------------------- */

static void host_ranks(const sk_host *host, int *rank, int *n_ranks) {
  *rank = host->sys->rank;
  *n_ranks = host->sys->n_ranks;
}

static sk_status host_param_double(sk_host *host, const char *key, int required, double dflt, double *out) {
  return sk_cfg_double(host->params, key, required, dflt, out);
}

static sk_status host_param_int(sk_host *host, const char *key, int required, int dflt, int *out) {
  return sk_cfg_int(host->params, key, required, dflt, out);
}

static sk_status host_param_string(sk_host *host, const char *key, int required, const char *dflt, const char **out) {
  return sk_cfg_string(host->params, key, required, dflt, out);
}

static sk_status host_error(sk_host *host, sk_status code, const char *fmt, ...) {
  (void)host;
  char message[1024];
  va_list args;
  va_start(args, fmt);
  vsnprintf(message, sizeof message, fmt, args);
  va_end(args);
  return sk_error_set(code, "%s", message);
}

static void host_log(sk_host *host, int level, const char *fmt, ...) {
  va_list args;
  va_start(args, fmt);
  log_va(host->sys->rank, level, fmt, args);
  va_end(args);
}

static sk_status host_reduce(sk_host *host, int op, double *values, int n) {
  if (op != 0 && op != 1) return sk_error_set(SK_ERR_PLUGIN, "%s: reduce: op %d is neither 0 (sum) nor 1 (max)",
                                              host->name, op);
  const sk_clock t0 = sk_system_clock();
  MPI_Allreduce(MPI_IN_PLACE, values, n, MPI_DOUBLE, op == 0 ? MPI_SUM : MPI_MAX, host->sys->comm);
  sk_system_charge_wait(host->sys, t0); /* not contact work (contact_wait) */
  return SK_OK;
}

static sk_instance *host_body_instance(sk_host *host, int body) {
  const sk_system *sys = host->sys;
  if (body < 0 || body >= sys->model->n_bodies || !sys->body_plugin[body]) return NULL;
  const plugin_term *owner = (const plugin_term *)sys->body_plugin[body];
  return owner->plugin == host->term->plugin ? owner->instance : NULL;
}

/* ---- stickslip.bulk.v1 ------------------------------------------------------------------------------------------ */

static sk_status need_body(sk_host *host, const char *call) {
  if (host->term->body < 0)
    return sk_error_set(SK_ERR_PLUGIN, "%s: stickslip.bulk %s: only a body instance has a body", host->name, call);
  return SK_OK;
}

static sk_status need_mass(sk_host *host, const char *call) {
  SK_TRY(need_body(host, call));
  if (!(host->term->plugin->caps & SK_CAP_NEEDS_MASS))
    return sk_error_set(SK_ERR_PLUGIN, "%s: stickslip.bulk %s needs the needs-mass capability", host->name, call);
  return SK_OK;
}

static const sk_view_data *body_view(const sk_host *host) { return &host->term->views[0]; }

static const double *element_mass(const sk_model *m, int element) {
  return m->element_mass + m->element_mass_offset[element];
}

static sk_status bulk_claim(sk_host *host) {
  SK_TRY(need_body(host, "claim"));
  if (!(host->term->plugin->caps & SK_CAP_OWNS_KINEMATICS))
    return sk_error_set(SK_ERR_PLUGIN, "%s: stickslip.bulk claim needs the owns-kinematics capability", host->name);
  host->term->claimed = 1;
  host->sys->claimed[host->term->body] = 1;
  return SK_OK;
}

static sk_status bulk_mass_properties(sk_host *host, double *mass, double center[3]) {
  SK_TRY(need_body(host, "mass_properties"));
  const sk_model *m = host->sys->model;
  const sk_body *body = &m->bodies[host->term->body];
  const sk_group *g = body->group;
  double sums[4] = {0, 0, 0, 0}; /* moment, total: this rank's elements, then summed over ranks */
  for (int e = 0; e < g->n_elems; ++e) {
    if (m->element_part[body->first_element + e] != m->rank) continue;
    const double *M = element_mass(m, body->first_element + e);
    const int *conn = g->conn + (size_t)e * g->nen;
    for (int a = 0; a < g->nen; ++a)
      for (int b = 0; b < g->nen; ++b) {
        sums[3] += M[a * g->nen + b];
        for (int i = 0; i < m->dim; ++i) sums[i] += M[a * g->nen + b] * m->X[(size_t)conn[a] * m->dim + i];
      }
  }
  MPI_Allreduce(MPI_IN_PLACE, sums, 4, MPI_DOUBLE, MPI_SUM, m->comm);
  *mass = sums[3];
  for (int i = 0; i < 3; ++i) center[i] = sums[3] > 0.0 ? sums[i] / sums[3] : 0.0;
  return SK_OK;
}

/* y += (M_scalar ⊗ I) u over this rank's elements of the body view; with u NULL, the same product with the constant
 * nodal vector `constant` (a body force per unit mass). */
static void add_mass_times(const sk_model *m, const sk_view_data *v, const double *u, const double *constant,
                           double *y) {
  const int dim = m->dim, nen = v->view.nen;
  for (int c = 0; c < v->view.n_cells; ++c) {
    if (!v->cell_owned[c]) continue;
    const double *M = element_mass(m, v->cell_element[c]);
    const int *conn = v->conn + (size_t)c * nen;
    for (int a = 0; a < nen; ++a)
      for (int b = 0; b < nen; ++b)
        for (int i = 0; i < dim; ++i) y[conn[a] * dim + i] += M[a * nen + b] * (u ? u[conn[b] * dim + i] : constant[i]);
  }
}

static sk_status bulk_apply_mass(sk_host *host, const double *u, double *y) {
  SK_TRY(need_mass(host, "apply_mass"));
  const sk_view_data *v = body_view(host);
  memset(y, 0, sizeof(double) * (size_t)v->view.n_nodes * (size_t)v->view.dim);
  add_mass_times(host->sys->model, v, u, NULL, y);
  return SK_OK;
}

static sk_status bulk_add_mass(sk_host *host, const double *block, sk_sink *sink) {
  SK_TRY(need_mass(host, "add_mass"));
  const sk_model *m = host->sys->model;
  const sk_view_data *v = body_view(host);
  const int dim = m->dim, nen = v->view.nen;
  double values[9];
  for (int c = 0; c < v->view.n_cells; ++c) {
    if (!v->cell_owned[c]) continue;
    const double *M = element_mass(m, v->cell_element[c]);
    const int *conn = v->conn + (size_t)c * nen;
    for (int a = 0; a < nen; ++a)
      for (int b = 0; b < nen; ++b) {
        for (int k = 0; k < dim * dim; ++k) values[k] = M[a * nen + b] * block[k];
        sink->add_matrix(sink, dim, v->dofs + (size_t)conn[a] * dim, dim, v->dofs + (size_t)conn[b] * dim, values);
      }
  }
  return SK_OK;
}

/* The element's linear (small-strain Hooke) stiffness in the reference configuration, applied to u_e or into K. */
static sk_status hooke_element(const sk_model *m, const sk_view_data *v, int c, const double *u_view, double *f,
                               double *K) {
  const int dim = m->dim, nen = v->view.nen;
  const sk_body *body = &m->bodies[v->view.body];
  sk_material hooke;
  SK_TRY(sk_material_init(&hooke, SK_MAT_HOOKE, body->material.E, body->material.nu, body->material.density));
  const sk_solid solid = {.type = body->solid.type, .dim = dim, .mat = &hooke};
  double X[SK_MAX_NEN * 3], u[SK_MAX_NEN * 3] = {0};
  const int *conn = v->conn + (size_t)c * nen;
  for (int a = 0; a < nen; ++a)
    for (int i = 0; i < dim; ++i) {
      X[a * dim + i] = v->X[conn[a] * dim + i];
      if (u_view) u[a * dim + i] = u_view[conn[a] * dim + i];
    }
  return sk_solid_internal(&solid, X, u, NULL, f, K);
}

static sk_status bulk_apply_stiffness(sk_host *host, const double *u, double *y) {
  SK_TRY(need_body(host, "apply_stiffness"));
  const sk_model *m = host->sys->model;
  const sk_view_data *v = body_view(host);
  const int dim = m->dim, nen = v->view.nen;
  memset(y, 0, sizeof(double) * (size_t)v->view.n_nodes * dim);
  double f[SK_MAX_NEN * 3];
  for (int c = 0; c < v->view.n_cells; ++c) {
    if (!v->cell_owned[c]) continue;
    SK_TRY(hooke_element(m, v, c, u, f, NULL)); /* Hooke: f = K u exactly */
    const int *conn = v->conn + (size_t)c * nen;
    for (int a = 0; a < nen; ++a)
      for (int i = 0; i < dim; ++i) y[conn[a] * dim + i] += f[a * dim + i];
  }
  return SK_OK;
}

static sk_status bulk_add_stiffness(sk_host *host, double scale, sk_sink *sink) {
  SK_TRY(need_body(host, "add_stiffness"));
  const sk_model *m = host->sys->model;
  const sk_view_data *v = body_view(host);
  const int dim = m->dim, nen = v->view.nen, nd = nen * dim;
  double *K = host->term->scratch_K;
  int64_t rows[SK_MAX_NEN * 3];
  for (int c = 0; c < v->view.n_cells; ++c) {
    if (!v->cell_owned[c]) continue;
    memset(K, 0, sizeof(double) * (size_t)nd * nd);
    SK_TRY(hooke_element(m, v, c, NULL, NULL, K));
    for (int k = 0; k < nd * nd; ++k) K[k] *= scale;
    const int *conn = v->conn + (size_t)c * nen;
    for (int a = 0; a < nen; ++a)
      for (int i = 0; i < dim; ++i) rows[a * dim + i] = v->dofs[(size_t)conn[a] * dim + i];
    sink->add_matrix(sink, nd, rows, nd, rows, K);
  }
  return SK_OK;
}

/* The view node of a model node (view nodes are sorted by model node), or -1. */
static int view_node_of(const sk_view_data *v, int node) {
  const int dim = v->view.dim;
  int lo = 0, hi = v->view.n_nodes;
  while (lo < hi) {
    const int mid = lo + (hi - lo) / 2;
    if (v->local_dofs[(int64_t)mid * dim] / dim < node) lo = mid + 1;
    else hi = mid;
  }
  return lo < v->view.n_nodes && v->local_dofs[(int64_t)lo * dim] / dim == node ? lo : -1;
}

static sk_status bulk_external_force(sk_host *host, double t, double *f) {
  SK_TRY(need_body(host, "external_force"));
  const sk_system *sys = host->sys;
  const sk_model *m = sys->model;
  const sk_view_data *v = body_view(host);
  const int dim = m->dim;
  memset(f, 0, sizeof(double) * (size_t)v->view.n_nodes * dim);
  add_mass_times(m, v, NULL, m->body_force, f); /* body force: M b over owned elements */
  /* tractions on the body's faces: each face once, by the owner of its first node (a node of this view) */
  for (int k = 0; k < m->n_tractions; ++k) {
    const sk_traction *load = &m->tractions[k];
    const sk_group *g = load->faces;
    if (g->n_elems == 0 || sk_model_body_of_node(m, g->conn[0]) != v->view.body) continue;
    const double scale = sk_history_value(&load->history, t);
    double traction[3], X[SK_MAX_NEN * 3], fe[SK_MAX_NEN * 3];
    for (int i = 0; i < 3; ++i) traction[i] = scale * load->traction[i];
    for (int e = 0; e < g->n_elems; ++e) {
      const int *conn = g->conn + (size_t)e * g->nen;
      if (m->node_owner[conn[0]] != m->rank) continue;
      for (int a = 0; a < g->nen; ++a)
        for (int i = 0; i < dim; ++i) X[a * dim + i] = m->X[(size_t)conn[a] * dim + i];
      sk_face_traction(g->type, dim, X, traction, fe);
      for (int a = 0; a < g->nen; ++a) {
        const int node = view_node_of(v, conn[a]);
        if (node < 0) return sk_error_set(SK_ERR_INTERNAL, "%s: traction node %lld outside the body view", host->name,
                                       (long long)m->node_gid[conn[a]]);
        for (int i = 0; i < dim; ++i) f[node * dim + i] += fe[a * dim + i];
      }
    }
  }
  return SK_OK;
}

static sk_status bulk_set_state(sk_host *host, const double *u, const double *v) {
  SK_TRY(need_body(host, "set_state"));
  plugin_term *term = host->term;
  const size_t n = sizeof(double) * (size_t)term->view_list[0]->n_nodes * term->view_list[0]->dim;
  memcpy(term->pending_u, u, n);
  memcpy(term->pending_v, v, n);
  term->has_pending_state = 1;
  return SK_OK;
}

static const sk_bulk_ext bulk_ext = {SK_TABLE_HEADER(sk_bulk_ext),
                                     .claim = bulk_claim,
                                     .mass_properties = bulk_mass_properties,
                                     .apply_mass = bulk_apply_mass,
                                     .add_mass = bulk_add_mass,
                                     .apply_stiffness = bulk_apply_stiffness,
                                     .add_stiffness = bulk_add_stiffness,
                                     .external_force = bulk_external_force,
                                     .set_state = bulk_set_state};

/* ---- stickslip.condense.v1 and stickslip.linear.v1 --------------------------------------------------------------- */

static sk_status condense_pair(sk_host *host, int64_t n_groups, int block, const int64_t *extra_index,
                               const int64_t *rows) {
  const plugin_term *term = host->term;
  if (!(term->plugin->caps & SK_CAP_CONDENSATION))
    return sk_error_set(SK_ERR_PLUGIN, "%s: stickslip.condense needs the condensation capability", host->name);
  if (block < 1 || block > 3 || n_groups < 0)
    return sk_error_set(SK_ERR_PLUGIN, "%s: stickslip.condense pair: block %d must be 1..3", host->name, block);
  const int64_t n = n_groups * block;
  int64_t *z = malloc(sizeof(int64_t) * (size_t)(n > 0 ? n : 1));
  if (!z) return sk_error_set(SK_ERR_NOMEM, "%s: out of memory for %lld pairs", host->name, (long long)n);
  for (int64_t k = 0; k < n; ++k) {
    if (extra_index[k] < 0 || extra_index[k] >= term->layout.n_extra) {
      free(z);
      return sk_error_set(SK_ERR_PLUGIN, "%s: stickslip.condense pair: extra unknown %lld outside [0, %lld)",
                          host->name, (long long)extra_index[k], (long long)term->layout.n_extra);
    }
    z[k] = term->base.extra_offset + extra_index[k];
  }
  sk_status status = sk_system_condense_pairs(host->sys, n_groups, block, z, rows);
  free(z);
  return status;
}

static const sk_condense_ext condense_ext = {SK_TABLE_HEADER(sk_condense_ext), .pair = condense_pair};

static sk_status linear_solve_again(sk_host *host, const double *const *b_view, const double *b_extra,
                                    double *const *y_view, double *y_extra) {
  plugin_term *term = host->term;
  sk_system *sys = host->sys;
  if (!term->again_b || term->again_size < sys->n)
    return sk_error_set(SK_ERR_INTERNAL, "%s: solve_again without its buffers", host->name);
  /* this rank's part of b (its owned nodes, the extras it holds); the system sums the parts into the owners */
  memset(term->again_b, 0, sizeof(double) * (size_t)sys->n);
  for (int v = 0; v < term->n_views; ++v) {
    const sk_view *view = term->view_list[v];
    const int64_t *dofs = term->views[v].local_dofs;
    for (int k = 0; k < view->n_nodes; ++k)
      if (view->owned[k])
        for (int i = 0; i < view->dim; ++i) term->again_b[dofs[k * view->dim + i]] += b_view[v][k * view->dim + i];
  }
  for (int64_t k = 0; k < term->base.n_held; ++k)
    term->again_b[term->base.extra_local + k] += b_extra[term->base.held[k]];
  SK_TRY(sk_system_solve_again(sys, term->again_b, term->again_y));
  for (int v = 0; v < term->n_views; ++v) {
    const sk_view *view = term->view_list[v];
    const int64_t *dofs = term->views[v].local_dofs;
    for (int k = 0; k < view->n_nodes * view->dim; ++k) y_view[v][k] = term->again_y[dofs[k]];
  }
  sk_system_extras_to_block(&term->base, term->again_y, y_extra);
  return SK_OK;
}

static const sk_linear_ext linear_ext = {SK_TABLE_HEADER(sk_linear_ext), .solve_again = linear_solve_again};

/* ---- stickslip.scene.v1 ------------------------------------------------------------------------------------------ */

static const sk_scene_info *scene_info(sk_host *host) { return &host->term->scene.info; }

static void scene_computed(sk_host *host, const char *key, double value, const char *fmt, ...) {
  plugin_term *term = host->term;
  plugin_computed *entry = NULL;
  for (int k = 0; k < term->n_computed && !entry; ++k)
    if (strcmp(term->computed[k].key, key) == 0) entry = &term->computed[k]; /* a second report replaces the first */
  if (!entry && term->n_computed < PLUGIN_MAX_COMPUTED) entry = &term->computed[term->n_computed++];
  if (!entry) return;
  snprintf(entry->key, sizeof entry->key, "%s", key);
  entry->value = value;
  va_list args;
  va_start(args, fmt);
  vsnprintf(entry->reason, sizeof entry->reason, fmt, args);
  va_end(args);
  sk_log_message(host->sys->rank, 2, "%s: parameter %s = %g (computed: %s)", host->name, key, value, entry->reason);
}

static const sk_scene_ext scene_ext = {SK_TABLE_HEADER(sk_scene_ext), .info = scene_info, .computed = scene_computed};

static const void *host_get_extension(sk_host *host, const char *id) {
  if (!id) return NULL;
  if (strcmp(id, SK_EXT_BULK) == 0) return host->term->body >= 0 ? &bulk_ext : NULL;
  if (strcmp(id, SK_EXT_CONDENSE) == 0) return &condense_ext;
  if (strcmp(id, SK_EXT_SCENE) == 0) return &scene_ext;
  if (strcmp(id, SK_EXT_LINEAR) == 0) {
    host->term->wants_linear = 1;
    return &linear_ext;
  }
  return NULL;
}

static const sk_host_api api = {SK_TABLE_HEADER(sk_host_api),
                                .contact = &sk_host_contact_table,
                                .ranks = host_ranks,
                                .param_double = host_param_double,
                                .param_int = host_param_int,
                                .param_string = host_param_string,
                                .error = host_error,
                                .log = host_log,
                                .reduce = host_reduce,
                                .body_instance = host_body_instance,
                                .get_extension = host_get_extension};

const sk_host_api *sk_host_api_table(void) { return &api; }
