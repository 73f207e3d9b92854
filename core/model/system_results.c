/* The contact results of the system's plugin terms (system.h): the reports summed over ranks, the points. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "assemble.h"
#include "system.h"

/* ---- results ----------------------------------------------------------------------------------------------------- */

/* A report that history.csv would carry as if it were a result: non-finite numbers, negative counts (issue 15,
 * item 15). */
static sk_status check_report(const sk_contact_report *r) {
  const double values[] = {r->force[0],  r->force[1],  r->force[2],  r->moment[0],
                           r->moment[1], r->moment[2], r->dissipated, r->constraint_norm};
  static const char *const names[] = {"force[0]",  "force[1]",  "force[2]",   "moment[0]",
                                      "moment[1]", "moment[2]", "dissipated", "constraint_norm"};
  for (size_t k = 0; k < sizeof values / sizeof values[0]; ++k)
    if (!isfinite(values[k])) return sk_error_set(SK_ERR_PLUGIN, "%s = %g is not a number", names[k], values[k]);
  if (r->active < 0 || r->stick < 0 || r->slip < 0)
    return sk_error_set(SK_ERR_PLUGIN, "negative point counts (active %lld, stick %lld, slip %lld)",
                        (long long)r->active, (long long)r->stick, (long long)r->slip);
  return SK_OK;
}

sk_status sk_system_contact_totals(sk_system *sys, int initial, sk_contact_totals *totals) {
  double *obstacle_force = totals->obstacle_force;
  memset(totals, 0, sizeof *totals);
  totals->obstacle_force = obstacle_force;
  double sums[10] = {0};
  sk_status status = SK_OK;
  const int n_obstacles = sys->model->n_obstacle_columns;
  if (obstacle_force) memset(obstacle_force, 0, sizeof(double) * 3 * (size_t)n_obstacles);
  struct ratio_at {
    double ratio;
    int term;
  } deepest = {0.0, -1}; /* MPI_DOUBLE_INT */
  int n_live; /* after a step a sleeping pair reports nothing (zeros); at the start every term reports */
  sk_term *const *live = initial ? sys->terms : sk_system_live_terms(sys, &n_live);
  if (initial) n_live = sys->n_terms;
  for (int k = 0; k < n_live && status == SK_OK; ++k) {
    sk_term *term = live[k];
    if (!term->ops->report) continue;
    sk_contact_report r = {.struct_size = sizeof r};
    status = term->ops->report(term, sys, initial, &r);
    if (status == SK_OK) status = check_report(&r);
    if (status != SK_OK) {
      sk_error_prefix(status, "%s: report: ", term->name);
      break;
    }
    for (int i = 0; i < 3; ++i) {
      sums[i] += r.force[i];
      sums[3 + i] += r.moment[i];
    }
    sums[6] += (double)r.active;
    sums[7] += (double)r.stick;
    sums[8] += (double)r.slip;
    sums[9] += r.dissipated;
    totals->constraint = fmax(totals->constraint, r.constraint_norm);
    double h = 0.0;
    if (sk_term_plugin_penalty_pair(term, &h) && h > 0.0 && r.constraint_norm / h > deepest.ratio)
      for (int t = 0; t < sys->n_terms; ++t)
        if (sys->terms[t] == term) deepest = (struct ratio_at){r.constraint_norm / h, t};
    const int column = sk_term_plugin_obstacle_column(term);
    if (obstacle_force && column >= 0)
      for (int i = 0; i < 3; ++i) obstacle_force[3 * column + i] -= r.force[i];
  }
  SK_TRY(sk_system_collective(sys, status));
  totals->active_local = sums[6];
  MPI_Allreduce(MPI_IN_PLACE, sums, 10, MPI_DOUBLE, MPI_SUM, sys->comm);
  if (obstacle_force && n_obstacles > 0)
    MPI_Allreduce(MPI_IN_PLACE, obstacle_force, 3 * n_obstacles, MPI_DOUBLE, MPI_SUM, sys->comm);
  double constraint = totals->constraint;
  MPI_Allreduce(&constraint, &totals->constraint, 1, MPI_DOUBLE, MPI_MAX, sys->comm);
  MPI_Allreduce(MPI_IN_PLACE, &deepest, 1, MPI_DOUBLE_INT, MPI_MAXLOC, sys->comm);
  totals->penetration_ratio = deepest.ratio;
  totals->penetration_term = deepest.ratio > 0.0 ? deepest.term : -1;
  for (int i = 0; i < 3; ++i) {
    totals->force[i] = sums[i];
    totals->moment[i] = sums[3 + i];
  }
  totals->active = sums[6];
  totals->stick = sums[7];
  totals->slip = sums[8];
  totals->dissipated = sums[9];
  totals->n_obstacles = n_obstacles;
  return SK_OK;
}

sk_status sk_system_scheme_energy(sk_system *sys, const double *u, const double *v, int initial, double scheme[2],
                                  double host[2]) {
  scheme[0] = scheme[1] = host[0] = host[1] = 0.0;
  sk_status status = SK_OK;
  for (int k = 0; k < sys->n_terms && status == SK_OK; ++k) {
    int body;
    double energy[2];
    status = sk_term_plugin_scheme_energy(sys->terms[k], sys, initial, &body, energy);
    status = sk_system_collective(sys, status);
    if (status != SK_OK || body < 0) continue; /* the same on every rank: every rank creates every instance */
    sk_invariants own;
    status = sk_bulk_body_invariants(sys->model, body, u, v, &own);
    scheme[0] += energy[0];
    scheme[1] += energy[1];
    host[0] += own.kinetic;
    host[1] += own.strain;
  }
  SK_TRY(status);
  MPI_Allreduce(MPI_IN_PLACE, scheme, 2, MPI_DOUBLE, MPI_SUM, sys->comm);
  return SK_OK;
}

typedef struct {
  void (*callback)(void *ctx, int pair, const sk_contact_point *point);
  void *ctx;
  int pair;
} points_relay;

static void relay_point(void *ctx, const sk_contact_point *point) {
  points_relay *relay = ctx;
  relay->callback(relay->ctx, relay->pair, point);
}

sk_status sk_system_points(sk_system *sys, int initial,
                           void (*callback)(void *ctx, int pair, const sk_contact_point *point), void *ctx) {
  sk_status status = SK_OK;
  int n_live; /* after a step a sleeping pair has no point near contact; at the start every term gives its points */
  sk_term *const *live = initial ? sys->terms : sk_system_live_terms(sys, &n_live);
  if (initial) n_live = sys->n_terms;
  for (int k = 0; k < n_live && status == SK_OK; ++k) {
    sk_term *term = live[k];
    if (!term->ops->points) continue;
    points_relay relay = {callback, ctx, sk_term_plugin_pair(term)};
    status = term->ops->points(term, sys, initial, relay_point, &relay);
    if (status != SK_OK) sk_error_prefix(status, "%s: points: ", term->name);
  }
  return status;
}

void sk_system_describe_worst(const sk_system *sys, char *text, size_t size) {
  text[0] = '\0';
  char mine[256] = "";
  const int64_t row = sys->worst_row;
  const sk_model *m = sys->model;
  if (sys->worst_rank == sys->rank && row >= 0) {
    const int64_t local = sk_system_local_of(sys, row);
    if (row < m->n_dofs_global && local >= 0) {
      const int node = (int)(local / m->dim), body = sk_model_body_of_node(m, node);
      snprintf(mine, sizeof mine, "largest residual at node %lld (%c) of body '%s': F = %.3g",
               (long long)m->node_gid[node], "xyz"[row % m->dim], body >= 0 ? m->bodies[body].name : "?",
               sys->worst_residual);
    } else {
      for (int k = 0; k < sys->n_terms; ++k) {
        const sk_term *term = sys->terms[k];
        if (row >= term->extra_offset && row < term->extra_offset + term->n_extra) {
          snprintf(mine, sizeof mine, "largest residual at extra unknown %lld of %s: F = %.3g",
                   (long long)(row - term->extra_offset), term->name, sys->worst_residual);
          break;
        }
      }
    }
  }
  /* the rank holding it says it to all (the message of the failed step is every rank's) */
  if (sys->worst_rank >= 0) MPI_Bcast(mine, (int)sizeof mine, MPI_CHAR, sys->worst_rank, sys->comm);
  snprintf(text, size, "%s", mine);
}

/* ---- the work of the loads ---------------------------------------------------------------------------------------- */

sk_status sk_system_load_work(sk_system *sys, double *scratch, double *work) {
  const sk_model *m = sys->model;
  const int dim = m->dim;
  const int64_t n_dofs = (int64_t)m->n_nodes * dim;
  double w = 0.0;
  /* the body force: b . M (u - u_n) over the owned nodes' mass rows (the load vector is M b for every scheme) */
  const double *b = m->body_force;
  if ((b[0] != 0 || b[1] != 0 || b[2] != 0) && m->mass_row_ptr) {
    for (int a = 0; a < m->n_nodes; ++a) {
      if (m->node_owner[a] != m->rank) continue;
      for (int64_t k = m->mass_row_ptr[a]; k < m->mass_row_ptr[a + 1]; ++k) {
        const int64_t col = (int64_t)m->mass_cols[k] * dim;
        for (int i = 0; i < dim; ++i) w += b[i] * m->mass_values[k] * (sys->x[col + i] - sys->u_n[col + i]);
      }
    }
  }
  /* tractions and resultants: the forces they add to the residual (with a minus sign), each written by one rank;
   * a scene without them costs no sweep over the dofs */
  int n_resultants = 0;
  for (int k = 0; k < sys->n_terms; ++k) n_resultants += strcmp(sys->terms[k]->ops->kind, "resultant") == 0;
  sk_status status = SK_OK;
  if (m->n_tractions > 0 || n_resultants > 0) {
    memset(scratch, 0, sizeof(double) * (size_t)n_dofs);
    for (int k = 0; k < m->n_tractions; ++k) {
      const sk_group *g = m->tractions[k].faces;
      const int body = g->n_elems > 0 ? sk_model_body_of_node(m, g->conn[0]) : -1;
      const sk_time_integrator *integrator = body >= 0 ? m->bodies[body].integrator : sys->integrator;
      sk_traction_add(m, k, integrator->force_time(sys->t_n, sys->t), scratch);
    }
    double *const residual = sys->F_local;
    sys->F_local = scratch;
    for (int k = 0; status == SK_OK && k < sys->n_terms; ++k)
      if (strcmp(sys->terms[k]->ops->kind, "resultant") == 0)
        status = sys->terms[k]->ops->residual(sys->terms[k], sys);
    sys->F_local = residual;
    for (int64_t k = 0; k < n_dofs; ++k) w -= scratch[k] * (sys->x[k] - sys->u_n[k]);
  }
  MPI_Allreduce(MPI_IN_PLACE, &w, 1, MPI_DOUBLE, MPI_SUM, m->comm);
  *work = w;
  return status;
}
