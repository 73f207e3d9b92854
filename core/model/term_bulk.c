/* The bulk term of one body (internal, inertial and body-force terms of its elements on this rank, integrated by the
 * body's time integrator) and the traction term (the scene's surface loads). A body claimed by a body plugin
 * (stickslip.bulk claim) is left to the plugin: its bulk term then does nothing, and its tractions reach the plugin
 * through external_force instead. */
#include <stdlib.h>
#include <string.h>

#include "assemble.h"
#include "system.h"

typedef struct {
  sk_term base;
  int body;
  int64_t n_dofs;
  int64_t *dofs;    /* the body's displacement dofs (its nodes, sorted, dim each) */
  double *K;        /* one element Jacobian (too large for the stack of deep call chains) */
} bulk_term;

static sk_bulk_state bulk_state(const sk_system *sys, const sk_body *body) {
  const sk_time_integrator *integrator = body->integrator;
  sk_bulk_state state = {.integrator = integrator,
                         .t_n = sys->t_n,
                         .t = sys->t,
                         .dt = sys->dt,
                         .u_n = sys->u_n,
                         .v_n = integrator->dynamic ? sys->v_n : NULL,
                         .u = sys->x};
  return state;
}

static int active(const bulk_term *term, const sk_system *sys) { return !sys->claimed[term->body]; }

static void bulk_destroy(sk_term *base) {
  bulk_term *term = (bulk_term *)base;
  free(term->dofs);
  free(term->K);
  free(term);
}

static sk_status bulk_predict(sk_term *base, sk_system *sys) {
  bulk_term *term = (bulk_term *)base;
  if (!active(term, sys)) return SK_OK;
  const sk_body *body = &sys->model->bodies[term->body];
  /* quasi-static: the previous increment's rate when solver.newton.predictor asks for it (NULL: from u_n) */
  const double *rate = body->integrator->dynamic ? sys->v_n : sys->solver->predictor ? sys->rate_n : NULL;
  body->integrator->predict(term->n_dofs, term->dofs, sys->u_n, rate, sys->dt, sys->x);
  return SK_OK;
}

/* The rows of this rank's elements of the body (claimed ones too: a body plugin adds its mass and stiffness there). */
static sk_status bulk_pattern(sk_term *base, sk_system *sys, unsigned char *rows) {
  bulk_term *term = (bulk_term *)base;
  const sk_model *m = sys->model;
  const sk_body *body = &m->bodies[term->body];
  int dofs[SK_MAX_NEN * 3];
  for (int e = body->first_element; e < body->first_element + body->group->n_elems; ++e) {
    if (m->element_part[e] != m->rank) continue;
    const int nd = sk_element_dofs(m, e, dofs, NULL, NULL);
    for (int j = 0; j < nd; ++j) rows[dofs[j]] = 1;
  }
  return SK_OK;
}

static sk_status bulk_residual(sk_term *base, sk_system *sys) {
  bulk_term *term = (bulk_term *)base;
  if (!active(term, sys)) return SK_OK;
  const sk_model *m = sys->model;
  const sk_body *body = &m->bodies[term->body];
  const sk_bulk_state state = bulk_state(sys, body);
  int dofs[SK_MAX_NEN * 3], n = 0;
  double f[SK_MAX_NEN * 3];
  for (int e = body->first_element; e < body->first_element + body->group->n_elems; ++e) {
    if (m->element_part[e] != m->rank) continue;
    SK_TRY(sk_element_system(m, &state, e, dofs, &n, f, NULL));
    for (int k = 0; k < n; ++k) sys->F_local[dofs[k]] += f[k];
  }
  return SK_OK;
}

static sk_status bulk_jacobian(sk_term *base, sk_system *sys) {
  bulk_term *term = (bulk_term *)base;
  if (!active(term, sys)) return SK_OK;
  const sk_model *m = sys->model;
  const sk_body *body = &m->bodies[term->body];
  const sk_bulk_state state = bulk_state(sys, body);
  int dofs[SK_MAX_NEN * 3], n = 0;
  double f[SK_MAX_NEN * 3];
  for (int e = body->first_element; e < body->first_element + body->group->n_elems; ++e) {
    if (m->element_part[e] != m->rank) continue;
    const int nd = body->group->nen * m->dim;
    memset(term->K, 0, sizeof(double) * (size_t)(nd * nd));
    SK_TRY(sk_element_system(m, &state, e, dofs, &n, f, term->K));
    const int64_t *pos = sys->elem_pos + sys->elem_pos_offset[e];
    for (int i = 0; i < n * n; ++i) sys->values[pos[i]] += term->K[i];
  }
  return SK_OK;
}

/* The converged step's velocities of the body's dofs. */
static sk_status bulk_commit(sk_term *base, sk_system *sys) {
  bulk_term *term = (bulk_term *)base;
  if (!active(term, sys)) return SK_OK;
  const sk_body *body = &sys->model->bodies[term->body];
  body->integrator->velocity(term->n_dofs, term->dofs, sys->u_n, sys->v_n, sys->x, sys->dt, sys->v);
  return SK_OK;
}

static const sk_term_ops bulk_ops = {.kind = "bulk",
                                     .destroy = bulk_destroy,
                                     .predict = bulk_predict,
                                     .pattern = bulk_pattern,
                                     .residual = bulk_residual,
                                     .jacobian = bulk_jacobian,
                                     .commit = bulk_commit};

static int compare_i64(const void *a, const void *b) {
  int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
  return (x > y) - (x < y);
}

/* The initial velocity of the body's nodes: translation plus spin about its centre. */
static void initial_velocity(const sk_model *m, const sk_body *body, double *v) {
  const int dim = m->dim;
  const sk_group *g = body->group;
  for (int64_t k = 0; k < (int64_t)g->n_elems * g->nen; ++k) {
    const int a = g->conn[k];
    double r[3] = {0, 0, 0};
    for (int i = 0; i < dim; ++i) r[i] = m->X[a * dim + i] - body->center[i];
    const double *w = body->angular_velocity;
    const double spin[3] = {w[1] * r[2] - w[2] * r[1], w[2] * r[0] - w[0] * r[2], w[0] * r[1] - w[1] * r[0]};
    for (int i = 0; i < dim; ++i) v[a * dim + i] = body->velocity[i] + spin[i];
  }
}

sk_status sk_term_bulk_create(sk_system *sys, int body_index, sk_term **out) {
  const sk_model *m = sys->model;
  const sk_body *body = &m->bodies[body_index];
  const sk_group *g = body->group;
  bulk_term *term = calloc(1, sizeof *term);
  const int64_t n_conn = (int64_t)g->n_elems * g->nen;
  int64_t *nodes = malloc(sizeof(int64_t) * (size_t)(n_conn > 0 ? n_conn : 1));
  if (term) term->K = malloc(sizeof(double) * (size_t)(g->nen * m->dim) * (size_t)(g->nen * m->dim));
  if (!term || !nodes || !term->K) {
    free(nodes);
    if (term) free(term->K);
    free(term);
    return sk_error_set(SK_ERR_NOMEM, "body '%s': out of memory for its bulk term", body->name);
  }
  term->base.ops = &bulk_ops;
  snprintf(term->base.name, sizeof term->base.name, "body '%s'", body->name);
  term->body = body_index;
  for (int64_t k = 0; k < n_conn; ++k) nodes[k] = g->conn[k];
  qsort(nodes, (size_t)n_conn, sizeof(int64_t), compare_i64);
  int64_t unique = 0;
  for (int64_t k = 0; k < n_conn; ++k)
    if (k == 0 || nodes[k] != nodes[unique - 1]) nodes[unique++] = nodes[k];
  term->dofs = malloc(sizeof(int64_t) * (size_t)(unique * m->dim > 0 ? unique * m->dim : 1));
  if (!term->dofs) {
    free(nodes);
    bulk_destroy(&term->base);
    return sk_error_set(SK_ERR_NOMEM, "body '%s': out of memory for its dofs", body->name);
  }
  for (int64_t k = 0; k < unique; ++k)
    for (int i = 0; i < m->dim; ++i) term->dofs[k * m->dim + i] = nodes[k] * m->dim + i;
  term->n_dofs = unique * m->dim;
  free(nodes);
  initial_velocity(m, body, sys->v_n);
  *out = &term->base;
  return SK_OK;
}

/* ---- tractions --------------------------------------------------------------------------------------------------- */

typedef struct {
  sk_term base;
  int *body;        /* per traction: the body its faces lie on */
} traction_term;

static void traction_destroy(sk_term *base) {
  traction_term *term = (traction_term *)base;
  free(term->body);
  free(term);
}

/* Dead loads at the time where the bodies' integrator balances forces; added once (rank 0). */
static sk_status traction_residual(sk_term *base, sk_system *sys) {
  traction_term *term = (traction_term *)base;
  const sk_model *m = sys->model;
  if (m->rank != 0) return SK_OK;
  for (int k = 0; k < m->n_tractions; ++k) {
    const int b = term->body[k];
    if (b >= 0 && sys->claimed[b]) continue;
    const sk_time_integrator *integrator = b >= 0 ? m->bodies[b].integrator : sys->integrator;
    sk_traction_add(m, k, integrator->force_time(sys->t_n, sys->t), sys->F_local);
  }
  return SK_OK;
}

static const sk_term_ops traction_ops = {
    .kind = "traction", .destroy = traction_destroy, .residual = traction_residual};

sk_status sk_term_traction_create(sk_system *sys, sk_term **out) {
  const sk_model *m = sys->model;
  traction_term *term = calloc(1, sizeof *term);
  if (term) term->body = calloc((size_t)(m->n_tractions > 0 ? m->n_tractions : 1), sizeof(int));
  if (!term || !term->body) {
    free(term);
    return sk_error_set(SK_ERR_NOMEM, "out of memory for the traction term");
  }
  term->base.ops = &traction_ops;
  snprintf(term->base.name, sizeof term->base.name, "tractions");
  for (int k = 0; k < m->n_tractions; ++k) {
    const sk_group *g = m->tractions[k].faces;
    term->body[k] = g->n_elems > 0 ? sk_model_body_of_node(m, g->conn[0]) : -1;
  }
  *out = &term->base;
  return SK_OK;
}
