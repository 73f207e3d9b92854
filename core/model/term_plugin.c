/* A plugin instance as a term (term_plugin.h): keeps the state the instance sees (positions per view, refreshed when
 * the iterate changes) and runs the ABI calls at the system's stages (the views and the instance are created in
 * term_plugin_create.c). The capability checks that depend on what an instance does (extra unknowns, eliminations)
 * are made here. */
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "term_plugin.h"
#include "broad_phase.h"
#include "contact_partition.h"
#include "stickslip/fe.h"



/* A vector over the local dofs at the view's nodes. */
static void gather(const sk_view *view, const double *local, double *out) {
  const int64_t *dofs = sk_view_data_of(view)->local_dofs;
  const int n = sk_view_dof_count(view);
  for (int k = 0; k < n; ++k) out[k] = local[dofs[k]];
}

void sk_plugin_term_refresh(plugin_term *term, sk_system *sys, int initial) {
  sk_state *st = &term->state;
  const int dynamic = term->integrator ? term->integrator->dynamic : sys->integrator->dynamic;
  st->t_n = sys->t_n;
  st->t = initial ? sys->t_n : sys->t;
  st->dt = initial ? 0.0 : sys->dt;
  st->step = initial ? 0 : sys->step;
  for (int v = 0; v < term->n_views; ++v) {
    const sk_view *view = term->view_list[v];
    gather(view, sys->q_n, term->x_n[v]);
    if (dynamic) gather(view, sys->v_n, term->v_n[v]);
    if (initial) memcpy(term->x[v], term->x_n[v], sizeof(double) * (size_t)sk_view_dof_count(view));
    else if (term->x_version != sys->x_version) gather(view, sys->q, term->x[v]);
  }
  term->x_version = initial ? 0 : sys->x_version;
  st->extra = initial ? NULL : sk_system_extra_block(sys, &term->base);
  st->n_extra = initial ? 0 : term->base.n_extra;
  st->extra_offset = term->base.extra_offset;
}

/* Within Newton only the iterate changes: positions only. */
static void refresh_x(plugin_term *term, sk_system *sys) {
  term->state.extra = sk_system_extra_block(sys, &term->base);
  term->state.n_extra = term->base.n_extra;
  term->state.extra_offset = term->base.extra_offset;
  if (term->x_version == sys->x_version) return;
  for (int v = 0; v < term->n_views; ++v) gather(term->view_list[v], sys->q, term->x[v]);
  term->x_version = sys->x_version;
}

/* A plugin that fails without saying why (no api->error) would leave an empty or a stale reason: the host names the
 * call and the status instead (issue 15, item 11). */
sk_status sk_plugin_term_said(const plugin_term *term, const char *call, sk_status status) {
  static const char *const names[] = {"SK_OK", "SK_ERR_INPUT", "SK_ERR_IO", "SK_ERR_INVERTED", "SK_ERR_DIVERGED",
                                      "SK_ERR_PLUGIN", "SK_ERR_INTERNAL", "SK_ERR_NOMEM", "SK_ERR_INTERRUPTED"};
  if (status == SK_OK || sk_error_message()[0]) return status;
  const int known = status > 0 && (size_t)status < sizeof names / sizeof names[0];
  return sk_error_set(status, "plugin '%s' failed in %s() with status %d (%s) and gave no message", term->plugin->name,
                      call, (int)status, known ? names[status] : "unknown status");
}

/* ---- the stages ------------------------------------------------------------------------------------------------- */

static void plugin_destroy(sk_term *base) {
  plugin_term *term = (plugin_term *)base;
  if (term->instance) term->table.destroy(term->instance);
  for (int v = 0; v < PLUGIN_MAX_VIEWS; ++v) {
    sk_view_free(&term->views[v]);
    free(term->x[v]);
    free(term->x_n[v]);
    free(term->v_n[v]);
    free(term->F_view[v]);
    free(term->dx_view[v]);
    free(term->Jdx_view[v]);
  }
  free(term->pending_u);
  free(term->pending_v);
  free(term->scratch_K);
  free(term->anchor);
  free(term->extra_owner);
  free(term->in_view);
  free(term->again_b);
  free(term->again_y);
  free(term->recover_F);
  free(term->recover_dx);
  free(term->recover_Jdx);
  free(term);
}

/* Values over the body view (owned nodes) into `target` (a vector over the local unknowns) at their dofs; the ghosts
 * of every node from their owners (collective). */
static void scatter_body(plugin_term *term, sk_system *sys, const double *values, double *target) {
  const sk_view *view = term->view_list[0];
  const int64_t *dofs = term->views[0].local_dofs;
  const int dim = view->dim;
  for (int k = 0; k < view->n_nodes; ++k)
    if (view->owned[k])
      for (int i = 0; i < dim; ++i) target[dofs[k * dim + i]] = values[k * dim + i];
  sk_system_update_ghost_dofs(sys, target);
}

static sk_status plugin_predict(sk_term *base, sk_system *sys) {
  plugin_term *term = (plugin_term *)base;
  if (!term->claimed || !term->integrator) return SK_OK;
  sk_plugin_term_refresh(term, sys, 0);
  sk_status status = term->integrator->predict(term->instance, &term->state, term->x[0]);
  status = sk_system_collective(sys, status);
  if (status != SK_OK) return sk_error_prefix(status, "%s: predict: ", base->name);
  scatter_body(term, sys, term->x[0], sys->x);
  return SK_OK;
}

/* A created pair's term is visited only while the broad phase keeps it awake (broad_phase.c): it is near then. */
static sk_status plugin_begin_step(sk_term *base, sk_system *sys) {
  plugin_term *term = (plugin_term *)base;
  sk_plugin_term_refresh(term, sys, 0);
  return PLUGIN_CALL(term, begin_step, term->instance, &term->state);
}

int sk_term_plugin_broad_id(const sk_term *base) {
  const plugin_term *term = (const plugin_term *)base;
  return base->ops == sk_plugin_term_ops() && term->broad_phase ? term->broad_id : -1;
}

void sk_term_plugin_set_far(sk_term *base, sk_system *sys, int far) {
  plugin_term *term = (plugin_term *)base;
  if (far != term->far)
    sk_log_message(sys->rank, 2, "%s: %s at step %lld", base->name,
                   far ? "surfaces apart (broad phase): no plugin call" : "surfaces near (broad phase): called again",
                   (long long)sys->step);
  term->far = far;
  if (!far) return;
  sk_term_no_extras(base); /* the layout of an apart pair (the layout loop skips sleeping terms) */
  term->idle = 1;
}

/* The step's boxes were made with the predictor: a converged point that brought the surfaces near runs Newton again
 * with the plugin's search done from it. */
sk_status sk_term_plugin_wake(sk_term *base, sk_system *sys) {
  plugin_term *term = (plugin_term *)base;
  term->far = 0;
  sys->far_pair_attempts--;
  sk_log_message(sys->rank, 2, "%s: surfaces near at the converged point of step %lld (broad phase): Newton again",
                 base->name, (long long)sys->step);
  sk_plugin_term_refresh(term, sys, 0);
  return PLUGIN_CALL(term, begin_step, term->instance, &term->state);
}

/* An idle instance with extra unknowns (ABI 2.3) promised that each has the trivial equation `extra = 0` with 1 on
 * the diagonal; the host writes those rows itself. It checks what it can: the extras start at 0 (otherwise their
 * first Newton correction is not 0 and the plugin's row scaling would matter), and the instance paired none of them
 * with displacement rows for condensation (the condenser eliminates a multiplier through the plugin's D block,
 * which an idle call would not add). */
static int extras_trivial(const sk_layout *layout, int64_t condense_pairs) {
  if (condense_pairs != 0) return 0;
  for (int64_t j = 0; layout->initial && j < layout->n_extra; ++j)
    if (layout->initial[j] != 0.0) return 0;
  return 1;
}

/* The rows of an idle instance's extras: F = extra - 0, J = 1 on the diagonal (rows the sink skips, the eliminated
 * ones, need none: their correction stays 0 without recover). Added once, by each extra's owner. */
enum { IDLE_CHUNK = 256 };
static void idle_extra_rows(const plugin_term *term, sk_system *sys, int jacobian) {
  int64_t rows[IDLE_CHUNK];
  double values[IDLE_CHUNK];
  for (int64_t first = 0; first < term->base.n_held; first += IDLE_CHUNK) {
    const int64_t end = term->base.n_held - first < IDLE_CHUNK ? term->base.n_held : first + IDLE_CHUNK;
    int n = 0;
    for (int64_t k = first; k < end; ++k) {
      if (sys->role[term->base.extra_local + k] != SK_NODE_OWNED) continue;
      rows[n] = term->base.extra_offset + term->base.held[k];
      values[n++] = jacobian ? 1.0 : sys->x[term->base.extra_local + k];
    }
    if (!jacobian) sys->sink.abi.add_vector(&sys->sink.abi, n, rows, values);
    for (int k = 0; jacobian && k < n; ++k) sys->sink.abi.add_matrix(&sys->sink.abi, 1, rows + k, 1, rows + k, values);
  }
}

/* sk_layout.extra_anchor (ABI 2.4) of every rank combined (a rank gives -1 for nodes it does not see), and the
 * owner of each extra this rank holds: an extra belongs to its entity, so to the owner of its anchor node (with a
 * contact partition, a slave node's contact owner: contact_partition.h), and this
 * rank holds it when that node is in one of the instance's views; without anchors (global scalars) rank 0 owns every
 * extra and every rank holds them (docs/design.md, "Who owns what"). The combination runs when the anchors change. */
static sk_status combine_anchors(plugin_term *term, sk_system *sys) {
  const sk_layout *layout = &term->layout;
  const sk_model *m = sys->model;
  const int64_t n = layout->n_extra;
  const sk_contact_pair *pair = term->pair >= 0 ? &m->pairs[term->pair] : NULL;
  term->base.anchor = NULL;
  term->base.extra_owner = NULL;
  int given = SK_HAS(layout, extra_anchor) && layout->extra_anchor && n > 0, everywhere = 0;
  MPI_Allreduce(&given, &everywhere, 1, MPI_INT, MPI_MIN, sys->comm);
  if (!everywhere) return SK_OK;
  int changed = n != term->anchor_count;
  if (n > term->anchor_size) {
    int64_t *grown = realloc(term->anchor, sizeof(int64_t) * (size_t)n);
    if (grown) term->anchor = grown;
    int *owners = realloc(term->extra_owner, sizeof(int) * (size_t)n);
    if (owners) term->extra_owner = owners;
    if (!grown || !owners)
      return sk_error_set(SK_ERR_NOMEM, "out of memory for the anchors of %lld extra unknowns", (long long)n);
    term->anchor_size = n;
    changed = 1;
  }
  for (int64_t k = 0; k < n && !changed; ++k) {
    const int64_t a = layout->extra_anchor[k];
    changed = a >= 0 && a < m->n_dofs_global && term->anchor[k] != a;
  }
  MPI_Allreduce(MPI_IN_PLACE, &changed, 1, MPI_INT, MPI_MAX, sys->comm);
  if (changed) {
    for (int64_t k = 0; k < n; ++k) {
      const int64_t a = layout->extra_anchor[k];
      term->anchor[k] = a >= 0 && a < m->n_dofs_global ? a : -1;
    }
    for (int64_t first = 0; first < n; first += INT_MAX / 2) {
      const int chunk = (int)(n - first < INT_MAX / 2 ? n - first : INT_MAX / 2);
      MPI_Allreduce(MPI_IN_PLACE, term->anchor + first, chunk, MPI_INT64_T, MPI_MAX, sys->comm);
    }
    for (int64_t k = 0; k < n; ++k) {
      const int node = term->anchor[k] >= 0 ? sk_model_node_of(m, term->anchor[k] / m->dim) : -1;
      term->extra_owner[k] = term->anchor[k] < 0                      ? 0
                             : node >= 0 && term->in_view[node] ? sk_contact_owner_of_node(m, pair, node)
                                                                : -1;
    }
    term->anchor_count = n;
  }
  term->base.anchor = term->anchor;
  term->base.extra_owner = term->extra_owner;
  return SK_OK;
}

/* recover's blocks of the extras (F, dx, J dx: n_extra each), grown at layout (recover runs inside Newton). */
static sk_status recover_blocks(plugin_term *term, int64_t n) {
  if (!term->table.recover || (term->recover_F && n <= term->recover_size)) return SK_OK;
  double **blocks[] = {&term->recover_F, &term->recover_dx, &term->recover_Jdx};
  for (size_t k = 0; k < sizeof blocks / sizeof blocks[0]; ++k) {
    free(*blocks[k]);
    *blocks[k] = sk_plugin_zeros(n);
  }
  const int ok = term->recover_F && term->recover_dx && term->recover_Jdx;
  term->recover_size = ok ? n : 0;
  return ok ? SK_OK : sk_error_set(SK_ERR_NOMEM, "out of memory for recover (%lld extra unknowns)",
                                                   (long long)n);
}

static sk_status plugin_layout(sk_term *base, sk_system *sys) {
  plugin_term *term = (plugin_term *)base;
  sk_layout *layout = &term->layout;
  memset(layout, 0, sizeof *layout);
  layout->struct_size = sizeof *layout;
  term->state.extra_offset = base->extra_offset;
  term->state.extra = NULL;
  term->state.n_extra = 0;
  if (term->far) { /* no extra unknowns (broad_phase is only on without multipliers) and no call */
    base->n_extra = 0;
    base->initial = NULL;
    base->eliminated = NULL;
    base->recover_needs_jdx = 0;
    SK_TRY(combine_anchors(term, sys));
    term->idle = 1;
    return SK_OK;
  }
  const int64_t pairs_before = sys->n_pairs;
  SK_TRY(PLUGIN_CALL(term, layout, term->instance, &term->state, layout));
  const uint64_t caps = term->plugin->caps;
  if (layout->n_extra > 0 && !(caps & SK_CAP_MULTIPLIERS))
    return sk_error_set(SK_ERR_PLUGIN, "plugin '%s' declares %lld extra unknowns without the multipliers capability",
                        term->plugin->name, (long long)layout->n_extra);
  if (layout->eliminated && !(caps & SK_CAP_CONDENSATION))
    return sk_error_set(SK_ERR_PLUGIN, "plugin '%s' eliminates unknowns without the condensation capability",
                        term->plugin->name);
  base->n_extra = layout->n_extra;
  base->initial = layout->initial;
  base->eliminated = layout->eliminated;
  base->recover_needs_jdx = layout->recover_needs_jdx;
  SK_TRY(combine_anchors(term, sys));
  SK_TRY(recover_blocks(term, layout->n_extra));
  /* One answer on every rank: a skipped call must not leave a collective call of the plugin (reduce) unmatched. */
  int idle = (caps & SK_CAP_SAYS_IDLE) && SK_HAS(layout, idle) && layout->idle &&
             (layout->n_extra == 0 || extras_trivial(layout, sys->n_pairs - pairs_before)) &&
             !base->needs.needed[SK_NEED_IDLE_CALLS] && !sk_need_forced(SK_NEED_IDLE_CALLS);
  MPI_Allreduce(MPI_IN_PLACE, &idle, 1, MPI_INT, MPI_MIN, sys->comm);
  if (idle != term->idle)
    sk_log_message(sys->rank, 2, "%s: %s at step %lld", base->name,
                   idle ? "no candidate: active-set, residual and Jacobian calls skipped" : "candidates: called again",
                   (long long)sys->step);
  term->idle = idle;
  return SK_OK;
}

typedef struct {
  sk_pattern abi;
  sk_system *sys;
  sk_status status;
} pattern_relay;

static void relay_block(sk_pattern *abi, int nr, const int64_t *rows, int nc, const int64_t *cols) {
  pattern_relay *relay = (pattern_relay *)abi;
  if (relay->status == SK_OK) relay->status = sk_system_declare(relay->sys, nr, rows, nc, cols);
}

static sk_status plugin_pattern(sk_term *base, sk_system *sys, unsigned char *rows) {
  plugin_term *term = (plugin_term *)base;
  for (int v = 0; v < term->n_views; ++v) {
    const sk_view *view = term->view_list[v];
    for (int k = 0; k < sk_view_dof_count(view); ++k) rows[term->views[v].local_dofs[k]] = 1;
  }
  if (term->wants_linear && term->again_size < sys->n) {
    free(term->again_b);
    free(term->again_y);
    term->again_b = sk_plugin_zeros(sys->capacity);
    term->again_y = sk_plugin_zeros(sys->capacity);
    if (!term->again_b || !term->again_y)
      return sk_error_set(SK_ERR_NOMEM, "out of memory for solve_again (%lld unknowns)", (long long)sys->capacity);
    term->again_size = sys->capacity;
  }
  if (!term->table.pattern || term->far) return SK_OK;
  pattern_relay relay = {.abi = {SK_TABLE_HEADER(sk_pattern), .add_block = relay_block}, .sys = sys, .status = SK_OK};
  SK_TRY(PLUGIN_CALL(term, pattern, term->instance, &term->state, &relay.abi));
  return relay.status;
}

static sk_status plugin_update_active_set(sk_term *base, sk_system *sys, int *changed) {
  plugin_term *term = (plugin_term *)base;
  if (!term->table.update_active_set || term->idle) return SK_OK;
  refresh_x(term, sys);
  return PLUGIN_CALL(term, update_active_set, term->instance, &term->state, changed);
}

static sk_status plugin_residual(sk_term *base, sk_system *sys) {
  plugin_term *term = (plugin_term *)base;
  if (term->idle) {
    idle_extra_rows(term, sys, 0);
    return SK_OK;
  }
  refresh_x(term, sys);
  return PLUGIN_CALL(term, residual, term->instance, &term->state, &sys->sink.abi);
}

static sk_status plugin_jacobian(sk_term *base, sk_system *sys) {
  plugin_term *term = (plugin_term *)base;
  if (term->idle) {
    idle_extra_rows(term, sys, 1);
    return SK_OK;
  }
  refresh_x(term, sys);
  return PLUGIN_CALL(term, jacobian, term->instance, &term->state, &sys->sink.abi);
}

static sk_status plugin_recover(sk_term *base, sk_system *sys, const double *F, double *dx) {
  plugin_term *term = (plugin_term *)base;
  if (!term->table.recover || term->idle) return SK_OK;
  refresh_x(term, sys);
  for (int v = 0; v < term->n_views; ++v) {
    const sk_view *view = term->view_list[v];
    gather(view, F, term->F_view[v]);
    gather(view, dx, term->dx_view[v]);
    if (base->recover_needs_jdx) gather(view, sys->Jdx, term->Jdx_view[v]);
  }
  /* the extras in the instance's block (n_extra by j; 0 at those this rank does not hold) */
  sk_system_extras_to_block(base, F, term->recover_F);
  sk_system_extras_to_block(base, dx, term->recover_dx);
  if (base->recover_needs_jdx) sk_system_extras_to_block(base, sys->Jdx, term->recover_Jdx);
  sk_vectors vectors = {.struct_size = sizeof vectors,
                        .F_view = term->F_list,
                        .F_extra = term->recover_F,
                        .dx_view = term->dx_list,
                        .dx_extra = term->recover_dx,
                        .Jdx_view = base->recover_needs_jdx ? term->Jdx_list : NULL,
                        .Jdx_extra = base->recover_needs_jdx ? term->recover_Jdx : NULL};
  const sk_status status = PLUGIN_CALL(term, recover, term->instance, &term->state, &vectors);
  sk_system_extras_from_block(base, term->recover_dx, dx);
  return status;
}

static sk_status plugin_converged(sk_term *base, sk_system *sys, int *accept) {
  plugin_term *term = (plugin_term *)base;
  if (!term->table.converged) return SK_OK;
  refresh_x(term, sys);
  return PLUGIN_CALL(term, converged, term->instance, &term->state, accept);
}

static sk_status plugin_commit(sk_term *base, sk_system *sys) {
  plugin_term *term = (plugin_term *)base;
  refresh_x(term, sys);
  sk_status status = SK_OK;
  if (term->claimed && term->integrator) {
    memset(term->pending_v, 0, sizeof(double) * (size_t)sk_view_dof_count(term->view_list[0]));
    status = term->integrator->velocity(term->instance, &term->state, term->pending_v);
    const sk_clock t0 = sk_system_clock(); /* the status check and the exchange: waits (contact_wait) */
    status = sk_system_collective(sys, status);
    if (status == SK_OK) scatter_body(term, sys, term->pending_v, sys->v);
    sk_system_charge_wait(sys, t0);
    if (status != SK_OK) return sk_error_prefix(status, "%s: velocity: ", base->name);
  }
  term->has_pending_state = 0;
  if (term->far) return SK_OK; /* nothing happened to the pair: its history stays */
  status = PLUGIN_CALL(term, commit_step, term->instance, &term->state);
  const sk_clock t0 = sk_system_clock();
  status = sk_system_collective(sys, status);
  int pending = term->has_pending_state, anywhere = 0;
  if (status == SK_OK) MPI_Allreduce(&pending, &anywhere, 1, MPI_INT, MPI_MAX, sys->comm);
  sk_system_charge_wait(sys, t0);
  if (status != SK_OK) return status;
  if (anywhere) {
    /* set_state: the body's displacement and velocity for output, invariants and the next step */
    scatter_body(term, sys, term->pending_u, sys->x);
    scatter_body(term, sys, term->pending_v, sys->v);
    for (int k = 0; k < sys->model->n_dofs; ++k) sys->q[k] = sys->model->X[k] + sys->x[k];
    sys->x_version++;
  }
  return SK_OK;
}

static void plugin_reject(sk_term *base, sk_system *sys) {
  plugin_term *term = (plugin_term *)base;
  (void)sys;
  term->table.reject_step(term->instance);
}

static sk_status plugin_report(sk_term *base, sk_system *sys, int initial, sk_contact_report *report) {
  plugin_term *term = (plugin_term *)base;
  if (term->far && !initial) return SK_OK; /* no contact point: the report stays zero */
  sk_plugin_term_refresh(term, sys, initial);
  return PLUGIN_CALL(term, report, term->instance, &term->state, report);
}

static sk_status plugin_points(sk_term *base, sk_system *sys, int initial, sk_point_callback callback, void *ctx) {
  plugin_term *term = (plugin_term *)base;
  if (!term->table.points || (term->far && !initial)) return SK_OK; /* apart: no point near contact */
  sk_plugin_term_refresh(term, sys, initial);
  return PLUGIN_CALL(term, points, term->instance, &term->state, callback, ctx);
}

static const sk_term_ops plugin_ops = {.kind = "plugin",
                                       .destroy = plugin_destroy,
                                       .predict = plugin_predict,
                                       .begin_step = plugin_begin_step,
                                       .layout = plugin_layout,
                                       .pattern = plugin_pattern,
                                       .update_active_set = plugin_update_active_set,
                                       .residual = plugin_residual,
                                       .jacobian = plugin_jacobian,
                                       .recover = plugin_recover,
                                       .converged = plugin_converged,
                                       .commit = plugin_commit,
                                       .reject = plugin_reject,
                                       .report = plugin_report,
                                       .points = plugin_points};

int sk_term_plugin_obstacle_column(const sk_term *base) {
  if (base->ops != &plugin_ops) return -1;
  const plugin_term *term = (const plugin_term *)base;
  return term->pair >= 0 ? term->host.sys->model->pairs[term->pair].obstacle_column : -1;
}

static const sk_checkpoint_ext *checkpoint_ext(const plugin_term *term) {
  if (!term->table.get_extension) return NULL;
  const sk_checkpoint_ext *ext = term->table.get_extension(SK_EXT_CHECKPOINT);
  return ext && ext->abi_major == SK_ABI_MAJOR ? ext : NULL;
}

int sk_term_plugin_checkpointable(const sk_term *base, const char **plugin) {
  if (base->ops != &plugin_ops) return -1;
  const plugin_term *term = (const plugin_term *)base;
  if (plugin) *plugin = term->plugin->name;
  return checkpoint_ext(term) != NULL;
}

sk_status sk_term_plugin_save(sk_term *base, sk_system *sys, sk_record_writer *writer) {
  plugin_term *term = (plugin_term *)base;
  const sk_checkpoint_ext *ext = checkpoint_ext(term);
  if (!ext || !SK_HAS(ext, save) || !ext->save) return SK_OK;
  sk_plugin_term_refresh(term, sys, 0);
  sk_error_clear();
  return sk_plugin_term_said(term, "checkpoint save", ext->save(term->instance, &term->state, writer));
}

sk_status sk_term_plugin_load(sk_term *base, sk_system *sys, const sk_record_reader *reader) {
  plugin_term *term = (plugin_term *)base;
  const sk_checkpoint_ext *ext = checkpoint_ext(term);
  if (!ext || !SK_HAS(ext, load) || !ext->load) return SK_OK;
  sk_plugin_term_refresh(term, sys, 1);
  sk_error_clear();
  return sk_plugin_term_said(term, "checkpoint load", ext->load(term->instance, &term->state, reader));
}

int sk_term_plugin_pair(const sk_term *base) {
  if (base->ops != &plugin_ops) return -1;
  return ((const plugin_term *)base)->pair;
}

sk_status sk_term_plugin_scheme_energy(sk_term *base, sk_system *sys, int initial, int *body, double energy[2]) {
  *body = -1;
  energy[0] = energy[1] = 0.0;
  if (base->ops != &plugin_ops) return SK_OK;
  plugin_term *term = (plugin_term *)base;
  if (!term->integrator || !SK_HAS(term->integrator, energy) || !term->integrator->energy) return SK_OK;
  sk_plugin_term_refresh(term, sys, initial);
  sk_error_clear();
  sk_status status = sk_plugin_term_said(
      term, "energy", term->integrator->energy(term->instance, &term->state, &energy[0], &energy[1]));
  if (status == SK_OK && !(isfinite(energy[0]) && isfinite(energy[1])))
    status = sk_error_set(SK_ERR_PLUGIN, "its integrator's energy is not a number (kinetic %g, strain %g)",
                          energy[0], energy[1]);
  if (status != SK_OK) return sk_error_prefix(status, "%s: energy: ", base->name);
  *body = term->body;
  return SK_OK;
}

const sk_term_ops *sk_plugin_term_ops(void) { return &plugin_ops; }

int sk_term_plugin_explain_defaults(const sk_term *base, FILE *out) {
  if (base->ops != &plugin_ops) return 0;
  const plugin_term *term = (const plugin_term *)base;
  const sk_contact_pair *pair = term->pair >= 0 ? &term->host.sys->model->pairs[term->pair] : NULL;
  for (int k = 0; out && k < term->n_computed; ++k)
    fprintf(out, "  %s[%d].parameters.%s = %.6g (%s%s%scomputed: %s)\n", pair ? "contact" : "bodies",
            pair ? pair->entry : term->body, term->computed[k].key, term->computed[k].value,
            pair && pair->generated ? "pair '" : "", pair && pair->generated ? pair->name : "",
            pair && pair->generated ? "'; " : "", term->computed[k].reason);
  return term->n_computed;
}

int sk_term_plugin_computed(const sk_term *base, int k, char *path, size_t size, double *value, const char **reason) {
  if (base->ops != &plugin_ops) return 0;
  const plugin_term *term = (const plugin_term *)base;
  if (k < 0 || k >= term->n_computed) return 0;
  const sk_contact_pair *pair = term->pair >= 0 ? &term->host.sys->model->pairs[term->pair] : NULL;
  snprintf(path, size, "%s[%d].parameters.%s", pair ? "contact" : "bodies", pair ? pair->entry : term->body,
           term->computed[k].key);
  *value = term->computed[k].value;
  *reason = term->computed[k].reason;
  return 1;
}

const sk_contact_pair *sk_term_plugin_penalty_pair(const sk_term *base, double *h) {
  if (base->ops != &plugin_ops) return NULL;
  const plugin_term *term = (const plugin_term *)base;
  if (term->pair < 0 || (term->table.caps & SK_CAP_MULTIPLIERS)) return NULL;
  *h = term->scene.slave.h_mean;
  return &term->host.sys->model->pairs[term->pair];
}

int sk_term_plugin_explain_pair(const sk_term *base, FILE *out) {
  if (base->ops != &plugin_ops) return 0;
  const plugin_term *term = (const plugin_term *)base;
  if (term->pair < 0 || !term->host.sys->model->pairs[term->pair].generated) return 0;
  const sk_contact_pair *pair = &term->host.sys->model->pairs[term->pair];
  if (!out) return 1;
  fprintf(out, "  contact[%d] '%s': slave %s (%d faces), master %s", pair->entry, pair->name, pair->slave.name,
          pair->slave.n_faces_global, pair->has_obstacle ? pair->obstacle.name : pair->master.name);
  if (term->broad_phase)
    fprintf(out, " (%d faces): %s\n", pair->master.n_faces_global,
            term->apart_at_start ? "apart at the start: idle (no plugin call) until their boxes come within the margin"
                                 : "near at the start: active");
  else
    fprintf(out, ": %s\n", pair->has_obstacle ? "an obstacle: no broad phase (the plugin's own idle test)"
                            : pair->self_contact ? "self contact: no broad phase (the plugin's own search and exclusion)"
                                                 : "the plugin has extra unknowns: no broad phase (the plugin's own idle test)");
  return 1;
}
