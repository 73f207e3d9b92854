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
  double *K_const;  /* linear material (no stiffness-update need): the stiffness of this rank's elements, in loop
                       order, nd x nd each, computed at set-up; NULL otherwise */
  double *geometry; /* the reference geometry (sk_solid_geometry) of this rank's elements, in loop order; NULL when
                       the stiffness is constant or the cache would exceed GEOMETRY_CACHE_LIMIT */
  int geometry_size; /* doubles per element */
  int nd;            /* dofs per element */
} bulk_term;

/* Bytes per rank up to which the reference geometry is cached: 26 MB for the paper-size tori (2 x 8024 hex8), where
 * recomputing it was 10 % of the run's CPU (docs/linear-solvers.md); a larger body recomputes it per evaluation. */
static const double GEOMETRY_CACHE_LIMIT = 512.0 * 1024 * 1024;

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
  free(term->K_const);
  free(term->geometry);
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

/* The cached reference geometry of the own-th element of this rank's loop, or NULL (computed from coordinates). */
static const double *element_geometry(const bulk_term *term, int64_t own) {
  return term->geometry ? term->geometry + own * term->geometry_size : NULL;
}

/* The internal force of a linear element from its constant stiffness: f = K u, or K (u_n + u)/2 for the midpoint
 * rule's discrete gradient (exact for a quadratic energy); then inertia and body force. */
static sk_status constant_element(const sk_system *sys, const sk_bulk_state *state, int e, const double *K, int *dofs,
                                  double *f) {
  const int nd = sk_element_dofs(sys->model, e, dofs, NULL, NULL);
  const int midpoint = state->integrator->discrete_gradient;
  double u[SK_MAX_NEN * 3];
  for (int j = 0; j < nd; ++j) u[j] = midpoint ? 0.5 * (state->u_n[dofs[j]] + state->u[dofs[j]]) : state->u[dofs[j]];
  for (int i = 0; i < nd; ++i) {
    double sum = 0.0;
    for (int j = 0; j < nd; ++j) sum += K[i * nd + j] * u[j];
    f[i] = sum;
  }
  return sk_element_inertia(sys->model, state, e, dofs, f, NULL);
}

static sk_status bulk_residual(sk_term *base, sk_system *sys) {
  bulk_term *term = (bulk_term *)base;
  if (!active(term, sys)) return SK_OK;
  const sk_model *m = sys->model;
  const sk_body *body = &m->bodies[term->body];
  const sk_bulk_state state = bulk_state(sys, body);
  int dofs[SK_MAX_NEN * 3], n = 0;
  double f[SK_MAX_NEN * 3];
  const int64_t nd2 = (int64_t)term->nd * term->nd;
  int64_t own = 0;
  for (int e = body->first_element; e < body->first_element + body->group->n_elems; ++e) {
    if (m->element_part[e] != m->rank) continue;
    if (term->K_const) {
      SK_TRY(constant_element(sys, &state, e, term->K_const + nd2 * own++, dofs, f));
      n = term->nd;
    } else {
      SK_TRY(sk_element_system(m, &state, e, element_geometry(term, own++), dofs, &n, f, NULL));
    }
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
  const int64_t nd2 = (int64_t)term->nd * term->nd;
  const double scale = state.integrator->discrete_gradient ? 0.5 : 1.0; /* d(u_n + u)/2 / du */
  int64_t own = 0;
  for (int e = body->first_element; e < body->first_element + body->group->n_elems; ++e) {
    if (m->element_part[e] != m->rank) continue;
    if (term->K_const) {
      const double *Kc = term->K_const + nd2 * own++;
      for (int64_t i = 0; i < nd2; ++i) term->K[i] = scale * Kc[i];
      n = sk_element_dofs(m, e, dofs, NULL, NULL);
      memset(f, 0, sizeof(double) * (size_t)n); /* the inertia adds its force too; only K is used here */
      SK_TRY(sk_element_inertia(m, &state, e, dofs, f, term->K));
    } else { /* the solid kernel zeroes K itself */
      SK_TRY(sk_element_system(m, &state, e, element_geometry(term, own++), dofs, &n, f, term->K));
    }
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

/* The mass: for inertia (a dynamic scheme), a body force (M b), or an initial velocity (the kinetic energy and
 * momenta of the history rows; a quasi-static scheme sets every later velocity to zero). */
static void declare_needs(const sk_model *m, const sk_body *body, sk_needs *needs) {
  const char *material = sk_material_model_names[body->material.model];
  if (body->material.model == SK_MAT_HOOKE)
    sk_needs_declare(needs, SK_NEED_STIFFNESS_UPDATE, 0, "material %s: linear, its stiffness is assembled once",
                     material);
  else
    sk_needs_declare(needs, SK_NEED_STIFFNESS_UPDATE, 1, "material %s: the tangent depends on the displacement",
                     material);
  const double *b = m->body_force, *v = body->velocity, *w = body->angular_velocity;
  if (body->integrator->dynamic)
    sk_needs_declare(needs, SK_NEED_MASS, 1, "time.scheme %s: inertia", body->integrator->name);
  else if (b[0] != 0.0 || b[1] != 0.0 || b[2] != 0.0)
    sk_needs_declare(needs, SK_NEED_MASS, 1, "body force (%g, %g, %g) per unit mass", b[0], b[1], b[2]);
  else if (v[0] != 0.0 || v[1] != 0.0 || v[2] != 0.0 || w[0] != 0.0 || w[1] != 0.0 || w[2] != 0.0)
    sk_needs_declare(needs, SK_NEED_MASS, 1, "initial velocity: kinetic energy and momenta of the initial row");
  else
    sk_needs_declare(needs, SK_NEED_MASS, 0, "time.scheme %s, no body force, starts at rest",
                     body->integrator->name);
}

static int64_t owned_elements(const sk_model *m, const sk_body *body) {
  int64_t own = 0;
  for (int e = body->first_element; e < body->first_element + body->group->n_elems; ++e) own += m->element_part[e] == m->rank;
  return own;
}

/* Element e's dofs and their reference coordinates. */
static void reference_coordinates(const sk_model *m, int e, int *dofs, double *X) {
  const int nd = sk_element_dofs(m, e, dofs, NULL, NULL);
  for (int j = 0; j < nd; ++j) X[j] = m->X[dofs[j]];
}

/* The stiffness of this rank's elements at u = 0 (a linear material's stiffness at every u). */
static sk_status constant_stiffness(bulk_term *term, const sk_model *m, const sk_body *body) {
  int64_t own = owned_elements(m, body);
  const int64_t nd2 = (int64_t)term->nd * term->nd;
  term->K_const = calloc((size_t)(own * nd2 > 0 ? own * nd2 : 1), sizeof(double));
  if (!term->K_const)
    return sk_error_set(SK_ERR_NOMEM, "body '%s': out of memory for the constant stiffness of %lld elements (%lld "
                        "values)", body->name, (long long)own, (long long)(own * nd2));
  const double zero[SK_MAX_NEN * 3] = {0};
  double X[SK_MAX_NEN * 3];
  int dofs[SK_MAX_NEN * 3];
  own = 0;
  for (int e = body->first_element; e < body->first_element + body->group->n_elems; ++e) {
    if (m->element_part[e] != m->rank) continue;
    reference_coordinates(m, e, dofs, X);
    if (sk_solid_internal(&body->solid, X, zero, NULL, NULL, term->K_const + nd2 * own++) != SK_OK)
      return sk_error_prefix(SK_ERR_INVERTED, "body '%s', element %d: ", body->name, m->element_index[e]);
  }
  return SK_OK;
}

/* The reference geometry of this rank's elements, when it fits GEOMETRY_CACHE_LIMIT. Without it (no memory, or a
 * degenerate element, which the first evaluation then reports by name) the elements compute it themselves. */
static void cache_geometry(bulk_term *term, const sk_model *m, const sk_body *body) {
  int64_t own = owned_elements(m, body);
  term->geometry_size = sk_solid_geometry_size(&body->solid);
  const double bytes = (double)own * term->geometry_size * sizeof(double);
  if (own == 0 || bytes > GEOMETRY_CACHE_LIMIT) return;
  term->geometry = malloc((size_t)bytes);
  if (!term->geometry) return;
  double X[SK_MAX_NEN * 3];
  int dofs[SK_MAX_NEN * 3];
  own = 0;
  for (int e = body->first_element; e < body->first_element + body->group->n_elems; ++e) {
    if (m->element_part[e] != m->rank) continue;
    reference_coordinates(m, e, dofs, X);
    if (sk_solid_geometry(&body->solid, X, term->geometry + own++ * term->geometry_size) != SK_OK) {
      sk_error_clear();
      free(term->geometry);
      term->geometry = NULL;
      return;
    }
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
  qsort(nodes, (size_t)n_conn, sizeof(int64_t), sk_compare_i64);
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
  declare_needs(m, body, &term->base.needs);
  term->nd = g->nen * m->dim;
  sk_status status = SK_OK;
  if (!term->base.needs.needed[SK_NEED_STIFFNESS_UPDATE] && !sk_need_forced(SK_NEED_STIFFNESS_UPDATE))
    status = constant_stiffness(term, m, body);
  else
    cache_geometry(term, m, body);
  if (status != SK_OK) {
    bulk_destroy(&term->base);
    return status;
  }
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

/* Dead loads at the time where the bodies' integrator balances forces; each face by the owner of its first node. */
static sk_status traction_residual(sk_term *base, sk_system *sys) {
  traction_term *term = (traction_term *)base;
  const sk_model *m = sys->model;
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
