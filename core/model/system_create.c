/* The system of a time step (system.h), its creation and destruction: the terms of the model (bodies' bulk, loads,
 * Dirichlet conditions, plugin instances for bodies and pairs), the node coordinates handed to the linear solver,
 * and the arrays over the unknowns. system.c runs the stages of an attempt. */
#define _GNU_SOURCE
#include "system.h"
#include "broad_phase.h"
#include "contact_partition.h"
#include "master_ghosts.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "stickslip/condense.h"

static sk_status add_term(sk_system *sys, sk_term *term) {
  sk_term **grown = realloc(sys->terms, sizeof *grown * (size_t)(sys->n_terms + 1));
  if (!grown) {
    term->ops->destroy(term);
    return sk_system_out_of_memory("the terms", sys->n_terms + 1);
  }
  sys->terms = grown;
  sys->terms[sys->n_terms++] = term;
  return SK_OK;
}

/* A plugin instance on every rank, or on none: a plugin may refuse its view on some ranks only (mortar-dual without
 * the second layer of slave faces there), and the ranks that created theirs would wait for it in their first
 * collective call. Every rank reports the failing rank's message (sk_system_collective). */
static sk_status create_plugin_term(sk_system *sys, int body, int pair, sk_term **term) {
  *term = NULL;
  const sk_status status = sk_system_collective(sys, sk_term_plugin_create(sys, body, pair, term));
  if (status != SK_OK && *term) {
    (*term)->ops->destroy(*term);
    *term = NULL;
  }
  return status;
}

static sk_status create_terms(sk_system *sys) {
  sk_model *m = sys->model;
  sk_term *term;
  for (int b = 0; b < m->n_bodies; ++b) {
    SK_TRY(sk_term_bulk_create(sys, b, &term));
    SK_TRY(add_term(sys, term));
  }
  SK_TRY(sk_term_traction_create(sys, &term));
  SK_TRY(add_term(sys, term));
  for (int k = 0; k < m->n_resultants; ++k) {
    SK_TRY(sk_term_resultant_create(sys, k, &term));
    SK_TRY(add_term(sys, term));
  }
  /* body plugins before pair plugins: a pair instance may reach its body's instance at create */
  for (int b = 0; b < m->n_bodies; ++b) {
    if (!m->bodies[b].plugin) continue;
    SK_TRY(create_plugin_term(sys, b, -1, &term));
    sys->body_plugin[b] = term;
    SK_TRY(add_term(sys, term));
  }
  for (int k = 0; k < m->n_pairs; ++k) {
    SK_TRY(create_plugin_term(sys, -1, k, &term));
    SK_TRY(add_term(sys, term));
  }
  /* last: its finishing stages act on what every other term assembled */
  SK_TRY(sk_term_dirichlet_create(sys, &term));
  return add_term(sys, term);
}

/* The displacements are the bridge's nodal block (whole-node aggregates, rigid-body-mode nullspace): the reference
 * positions of this rank's owned nodes, in the order of its nodal rows. */
static sk_status hand_coordinates(sk_system *sys) {
  const sk_model *m = sys->model;
  double *X = malloc(sizeof(double) * (size_t)(sys->n_owned_dofs > 0 ? sys->n_owned_dofs : 1));
  if (!X) return sk_system_out_of_memory("the owned coordinates", sys->n_owned_dofs);
  for (int64_t k = 0; k < sys->n_owned_dofs; ++k) X[k] = m->X[sys->owned_dofs[k]];
  sk_status status = sk_linsys_set_coordinates(sys->linsys, (int)(sys->n_owned_dofs / m->dim), m->dim, X);
  free(X);
  return status;
}

sk_status sk_system_create(sk_model *model, const sk_solver_settings *solver, sk_system **out) {
  *out = NULL;
  sk_system *sys = calloc(1, sizeof *sys);
  if (!sys) return sk_system_out_of_memory("the system", 1);
  sys->model = model;
  sys->comm = model->comm;
  sys->rank = model->rank;
  sys->n_ranks = model->n_ranks;
  sys->solver = solver;
  sys->integrator = model->time.integrator;
  sys->pattern_n = -1;
  sys->forget_setup = sk_skip_forced("symbolic-setup");
  sys->t_n = model->time.t_start;
  sk_system_sink_init(sys);
  const size_t nd = (size_t)(model->n_dofs > 0 ? model->n_dofs : 1);
  const size_t nb = (size_t)(model->n_bodies > 0 ? model->n_bodies : 1);
  sys->u_n = calloc(nd, sizeof(double));
  sys->v_n = calloc(nd, sizeof(double));
  sys->rate_n = calloc(nd, sizeof(double));
  sys->v = calloc(nd, sizeof(double));
  sys->q_n = calloc(nd, sizeof(double));
  sys->q = calloc(nd, sizeof(double));
  sys->body_plugin = calloc(nb, sizeof *sys->body_plugin);
  sys->claimed = calloc(nb, 1);
  sys->elem_pos_offset = calloc((size_t)model->n_elements + 1, sizeof(int64_t));
  if (!sys->u_n || !sys->v_n || !sys->rate_n || !sys->v || !sys->q_n || !sys->q || !sys->body_plugin || !sys->claimed ||
      !sys->elem_pos_offset) {
    sk_system_destroy(sys);
    return sk_system_out_of_memory("the state vectors", model->n_dofs);
  }
  for (int k = 0; k < model->n_dofs; ++k) sys->q_n[k] = sys->q[k] = model->X[k];
  sk_status status = sk_linsys_create(model->comm, &solver->linear, &sys->linsys);
  if (status == SK_OK) status = sk_system_layout_dofs(sys);
  if (status == SK_OK) status = hand_coordinates(sys);
  if (status == SK_OK) status = create_terms(sys);
  if (status == SK_OK) status = sk_system_settle_needs(sys);
  if (status != SK_OK) {
    sk_system_destroy(sys);
    return status;
  }
  *out = sys;
  return SK_OK;
}

static void free_unknown_arrays(sk_system *sys) {
  double **arrays[] = {&sys->F_local, &sys->rhs_local, &sys->b, &sys->y, &sys->dx_local, &sys->Jdx, &sys->set_x,
                       &sys->owned_work, &sys->q_work};
  for (size_t k = 0; k < sizeof arrays / sizeof arrays[0]; ++k) {
    free(*arrays[k]);
    *arrays[k] = NULL;
  }
  free(sys->solver_of);
  free(sys->role);
  free(sys->owned);
  free(sys->constraint_out);
  free(sys->constraint_counts);
  free(sys->constraint_displs);
  free(sys->constraint_row);
  free(sys->constraint_buffer);
  sys->solver_of = sys->owned = sys->constraint_out = sys->constraint_counts = sys->constraint_displs = NULL;
  sys->constraint_row = NULL;
  sys->constraint_buffer = NULL;
  sys->role = NULL;
}

sk_status sk_system_add_term(sk_system *sys, sk_term *term) {
  SK_TRY(add_term(sys, term));
  /* keep the Dirichlet term last: its finishing stages act on what every other term assembled */
  sk_term **t = sys->terms;
  const int n = sys->n_terms;
  if (n >= 2 && strcmp(t[n - 2]->ops->kind, "dirichlet") == 0) {
    sk_term *dirichlet = t[n - 2];
    t[n - 2] = t[n - 1];
    t[n - 1] = dirichlet;
  }
  return SK_OK;
}

void sk_system_destroy(sk_system *sys) {
  if (!sys) return;
  for (int k = sys->n_terms - 1; k >= 0; --k) {
    free(sys->terms[k]->held);
    free(sys->terms[k]->extra_values);
    sys->terms[k]->ops->destroy(sys->terms[k]);
  }
  free(sys->terms);
  sk_broad_phase_free(sys);
  free_unknown_arrays(sys);
  free(sys->x);
  free(sys->u_n);
  free(sys->v_n);
  free(sys->rate_n);
  free(sys->v);
  free(sys->q_n);
  free(sys->q);
  free(sys->body_plugin);
  free(sys->claimed);
  free(sys->declared);
  free(sys->declared_recent);
  free(sys->extra_keys);
  free(sys->row_ptr);
  free(sys->cols);
  free(sys->row_local);
  free(sys->bulk_ptr);
  free(sys->bulk_cols);
  free(sys->pattern_dof_solver);
  free(sys->pattern_dof_role);
  free(sys->node_role);
  free(sys->owned_dofs);
  sk_exchange_free(&sys->ghost_dofs);
  sk_exchange_free(&sys->ghost_extras);
  free(sys->elem_pos_offset);
  free(sys->elem_pos);
  free(sys->pair_z);
  free(sys->pair_row);
  free(sys->pair_block);
  sk_condenser_destroy(sys->condenser);
  sk_linsys_destroy(sys->linsys);
  free(sys);
}
