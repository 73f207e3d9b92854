/* The system of a time step (system.h; created and destroyed in system_create.c): the unknowns, the terms' stages,
 * the declared sparsity pattern and the NOX callbacks. Every term — a body's bulk, the tractions, the Dirichlet conditions, a plugin instance — is called
 * through term.h; nothing here knows which term does what. No allocation happens inside Newton: the work arrays grow
 * at layout time, outside the loop. */
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
#include <time.h>
#include <unistd.h>

#include "stickslip/condense.h"

static double now_seconds(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

double sk_system_seconds(void) { return now_seconds(); }

sk_status sk_system_out_of_memory(const char *what, int64_t count) {
  return sk_error_set(SK_ERR_NOMEM, "out of memory for %s (%lld entries)", what, (long long)count);
}

sk_status sk_system_collective(const sk_system *sys, sk_status local) {
  int code = (int)local, worst = 0;
  MPI_Allreduce(&code, &worst, 1, MPI_INT, MPI_MAX, sys->comm);
  if (worst == SK_OK) return SK_OK;
  /* every rank reports the message of the lowest rank that failed with the worst status (rank 0 prints it) */
  int mine = local == (sk_status)worst ? sys->rank : sys->n_ranks, first = 0;
  MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, sys->comm);
  char message[2048]; /* the size of error.c's buffer */
  snprintf(message, sizeof message, "%s", sk_error_message());
  MPI_Bcast(message, (int)sizeof message, MPI_CHAR, first, sys->comm);
  if (first != sys->rank) sk_error_set((sk_status)worst, "%s", message);
  return (sk_status)worst;
}

static int is_plugin(const sk_term *term) { return strcmp(term->ops->kind, "plugin") == 0; }

/* ---- state from an iterate --------------------------------------------------------------------------------------- */

/* 1 when every rank's owned unknowns equal `owned` (collective: the ranks take the same branch). */
static int same_everywhere(const sk_system *sys, const double *reference, const double *owned) {
  int same = 1;
  for (int64_t k = 0; k < sys->n_owned && same; ++k) same = memcmp(&reference[sys->owned[k]], &owned[k], sizeof(double)) == 0;
  MPI_Allreduce(MPI_IN_PLACE, &same, 1, MPI_INT, MPI_MIN, sys->comm);
  return same;
}

void sk_system_update_ghost_dofs(sk_system *sys, double *dofs) { sk_exchange_forward(&sys->ghost_dofs, dofs); }

/* The ghosts from their owners and the positions, after the owned unknowns of x changed. */
static void refresh_iterate(sk_system *sys) {
  sk_model *m = sys->model;
  sk_exchange_forward(&sys->ghost_dofs, sys->x);
  sk_exchange_forward(&sys->ghost_extras, sys->x);
  for (int k = 0; k < m->n_dofs; ++k) sys->q[k] = m->X[k] + sys->x[k];
  sys->x_version++;
}

/* x from NOX's owned unknowns (collective). */
static void set_iterate(sk_system *sys, const double *owned) {
  if (same_everywhere(sys, sys->x, owned)) return;
  for (int64_t k = 0; k < sys->n_owned; ++k) sys->x[sys->owned[k]] = owned[k];
  refresh_iterate(sys);
}

/* update_active_set once at every new point, before the first residual or Jacobian evaluated there. */
static sk_status update_active_set(sk_system *sys) {
  for (int64_t k = 0; k < sys->n_owned; ++k) sys->owned_work[k] = sys->x[sys->owned[k]];
  if (sys->set_valid && same_everywhere(sys, sys->set_x, sys->owned_work)) return SK_OK;
  for (int64_t k = 0; k < sys->n_owned; ++k) sys->set_x[sys->owned[k]] = sys->owned_work[k];
  sys->set_valid = 1;
  sk_status status = SK_OK;
  int n_live;
  sk_term *const *live = sk_system_live_terms(sys, &n_live);
  for (int k = 0; k < n_live && status == SK_OK; ++k) {
    sk_term *term = live[k];
    if (!term->ops->update_active_set) continue;
    int changed = 0;
    const sk_clock t0 = sk_system_contact_clock(sys);
    status = term->ops->update_active_set(term, sys, &changed);
    if (is_plugin(term)) sk_system_charge_contact(sys, SK_CONTACT_ACTIVE_SET, t0);
    if (status != SK_OK) sk_error_prefix(status, "%s: update_active_set: ", term->name);
  }
  return status;
}

/* ---- the attempt ------------------------------------------------------------------------------------------------- */

static sk_status lay_out(sk_system *sys, int again);

sk_status sk_system_begin(sk_system *sys, double dt, int64_t step) {
  sys->step_solvers = 0;
  sk_model *m = sys->model;
  sys->dt = dt;
  sys->t = sys->t_n + dt;
  sys->step = step;
  sys->set_valid = 0;
  sys->worst_row = -1;
  if (!sys->x) SK_TRY(sk_system_ensure_capacity(sys, m->n_dofs));
  memcpy(sys->x, sys->u_n, sizeof(double) * (size_t)m->n_dofs);
  sk_status status = SK_OK;
  int n_live; /* the last attempt's: a created pair has no predictor */
  sk_term *const *live = sk_system_live_terms(sys, &n_live);
  for (int k = 0; k < n_live && status == SK_OK; ++k)
    if (live[k]->ops->predict) status = live[k]->ops->predict(live[k], sys);
  SK_TRY(sk_system_collective(sys, status));
  /* the predictors write the dofs of their bodies' elements; the ghosts outside them (master surface nodes held for
   * contact) get their owners' predicted values */
  sk_exchange_forward(&sys->ghost_dofs, sys->x);
  for (int k = 0; k < m->n_dofs; ++k) sys->q[k] = m->X[k] + sys->x[k];
  sys->x_version++;
  /* a new contact partition after an uneven step (contact_partition.h): its boxes enter the check below */
  int rebalanced = 0;
  if (sys->contact_rebalance_pending) SK_TRY(sk_contact_partition_rebalance(sys, &rebalanced));
  int64_t missing = 0; /* the ghosted master faces still reach every slave point, or are ghosted again (collective) */
  SK_TRY(sk_master_ghosts_check(sys, &missing));
  if (missing > 0 || rebalanced) {
    if (missing > 0 && sys->verbose && sys->rank == 0)
      fprintf(stderr, "step %lld: %lld master face(s) came within reach of a rank not holding them: ghosted again\n",
              (long long)step, (long long)missing);
    SK_TRY(sk_master_ghosts_renew(sys, rebalanced));
    sys->master_reghosts += missing > 0;
    sys->contact_rebalances += rebalanced;
  }
  SK_TRY(sk_system_collective(sys, sk_broad_phase_begin(sys))); /* the pairs near at the predictor: live terms */
  live = sk_system_live_terms(sys, &n_live);
  for (int k = 0; k < n_live; ++k) {
    sk_term *term = live[k];
    if (!term->ops->begin_step) continue;
    const sk_clock t0 = sk_system_contact_clock(sys); /* the contact search: contact work (contact_seconds) */
    status = term->ops->begin_step(term, sys);
    if (is_plugin(term)) sk_system_charge_contact(sys, SK_CONTACT_SEARCH, t0);
    status = sk_system_collective(sys, status);
    if (status != SK_OK) return sk_error_prefix(status, "%s: begin_step: ", term->name);
  }
  return lay_out(sys, 0);
}

/* A slave row that a Dirichlet condition fixes is the condition's row (term_dirichlet.c replaces it), no longer the
 * contact force's: the multiplier component paired with it has no D entry there and cannot be eliminated through it
 * (found: a roller on the slave surface's corner node made the D block singular in the patch test). Such pairs are
 * dropped and their groups shrink; the multiplier stays an unknown of the condensed system with its own row. */
static sk_status drop_fixed_pairs(sk_system *sys) {
  const sk_model *m = sys->model;
  if (m->n_dirichlet == 0 || sys->n_pairs == 0) return SK_OK;
  unsigned char *fixed = calloc((size_t)m->n_dofs, 1);
  if (!fixed) return sk_system_out_of_memory("the fixed rows of the condensation pairs", m->n_dofs);
  for (int k = 0; k < m->n_dirichlet; ++k)
    for (int j = 0; j < m->dirichlet[k].n_nodes; ++j)
      for (int i = 0; i < m->dim; ++i)
        if (m->dirichlet[k].fixed[i]) fixed[(int64_t)m->dirichlet[k].nodes[j] * m->dim + i] = 1;
  int64_t kept = 0;
  for (int64_t first = 0; first < sys->n_pairs;) {
    const int block = sys->pair_block[first];
    int free_rows = 0;
    for (int b = 0; b < block; ++b) free_rows += !fixed[sys->pair_row[first + b]];
    for (int b = 0; b < block; ++b)
      if (!fixed[sys->pair_row[first + b]]) {
        sys->pair_z[kept] = sys->pair_z[first + b];
        sys->pair_row[kept] = sys->pair_row[first + b];
        sys->pair_block[kept++] = free_rows;
      }
    first += block;
  }
  sys->n_pairs = kept;
  free(fixed);
  return SK_OK;
}

/* The attempt's unknowns, pattern and condensation pairs from the terms' layouts (again: see
 * sk_system_layout_unknowns). */
static sk_status lay_out(sk_system *sys, int again) {
  sk_model *m = sys->model;
  int changed = 0;
  sk_status status = sk_system_collective(sys, sk_system_layout_unknowns(sys, again, &changed));
  if (status != SK_OK) return status;
  sys->x_version++; /* the extras got their starting values */
  /* the condensation pairs (ABI indices from the plugins) as local unknowns of this rank */
  for (int64_t k = 0; k < sys->n_pairs && status == SK_OK; ++k) {
    const int64_t z = sk_system_local_of(sys, sys->pair_z[k]), row = sk_system_local_of(sys, sys->pair_row[k]);
    if (z < 0 || row < 0 || row >= m->n_dofs)
      status = sk_error_set(SK_ERR_PLUGIN, "stickslip.condense: pair (unknown %lld, row %lld) outside this rank's "
                            "unknowns, or the row not a displacement row", (long long)sys->pair_z[k],
                            (long long)sys->pair_row[k]);
    sys->pair_z[k] = z;
    sys->pair_row[k] = row;
  }
  SK_TRY(sk_system_collective(sys, status));
  SK_TRY(sk_system_settle_pattern(sys, changed));
  sys->condensing = 0;
  SK_TRY(sk_system_collective(sys, drop_fixed_pairs(sys)));
  int64_t pairs_anywhere = 0;
  MPI_Allreduce(&sys->n_pairs, &pairs_anywhere, 1, MPI_INT64_T, MPI_SUM, sys->comm);
  if (pairs_anywhere > 0) {
    /* the pairs in the linear system's numbering */
    for (int64_t k = 0; k < sys->n_pairs; ++k) {
      const int z = sys->solver_of[sys->pair_z[k]], row = sys->solver_of[sys->pair_row[k]];
      if (z < 0 || row < 0 || sys->pair_row[k] >= m->n_dofs)
        status = sk_error_set(SK_ERR_PLUGIN, "stickslip.condense: pair %lld (unknown %lld, row %lld): the multiplier "
                              "is eliminated by the plugin or the row is not a displacement row", (long long)k,
                              (long long)sk_system_abi_of(sys, sys->pair_z[k]),
                              (long long)sk_system_abi_of(sys, sys->pair_row[k]));
      sys->pair_z[k] = z;
      sys->pair_row[k] = row;
    }
    SK_TRY(sk_system_collective(sys, status));
    if (!sys->condenser) {
      SK_TRY(sk_condenser_create(sys->comm, &sys->solver->linear, &sys->condenser));
      if (sys->linear_fallback) SK_TRY(sk_linsys_set_solver(sk_condenser_reduced(sys->condenser), SK_LINEAR_DIRECT));
    }
    SK_TRY(sk_condenser_set_pairs(sys->condenser, sys->linsys, sys->n_pairs, sys->pair_z, sys->pair_row,
                                  sys->pair_block));
    sys->condensing = 1;
  }
  const int64_t solved = sys->condensing ? sk_condenser_size(sys->condenser) : sys->n_kept;
  if (sys->linear_size_max < solved) sys->linear_size_max = solved;
  return SK_OK;
}

/* Keeps a failure that must end the run rather than cut the step (NOX turns every callback failure into
 * divergence). */
static sk_status note_fatal(sk_system *sys, sk_status status) {
  if ((status == SK_ERR_PLUGIN || status == SK_ERR_INTERNAL || status == SK_ERR_NOMEM) && sys->fatal == SK_OK) {
    sys->fatal = status;
    snprintf(sys->fatal_message, sizeof sys->fatal_message, "%s", sk_error_message());
  }
  return status;
}

/* Remembers where |F| is largest over the owned unknowns of all ranks (the first non-finite one wins): where a step
 * that cannot be solved fails. sys->worst_row is the ABI index of that unknown on the rank holding it, else -1. */
static void note_worst(sk_system *sys, const double *F_owned) {
  int64_t worst = -1;
  double largest = -1.0;
  for (int64_t k = 0; k < sys->n_owned; ++k) {
    const double a = fabs(F_owned[k]);
    if (!isfinite(a)) {
      worst = k;
      largest = INFINITY;
      break;
    }
    if (a > largest) {
      worst = k;
      largest = a;
    }
  }
  struct {
    double value;
    int rank;
  } mine = {largest, sys->rank}, best;
  MPI_Allreduce(&mine, &best, 1, MPI_DOUBLE_INT, MPI_MAXLOC, sys->comm);
  sys->worst_rank = best.rank;
  sys->worst_row = best.rank == sys->rank && worst >= 0 ? sk_system_abi_of(sys, sys->owned[worst]) : -1;
  sys->worst_residual = best.rank == sys->rank && worst >= 0 ? F_owned[worst] : 0.0;
}

static sk_status cb_residual(void *ctx, const double *x, double *F) {
  sk_system *sys = ctx;
  set_iterate(sys, x);
  sk_status status = update_active_set(sys);
  memset(sys->F_local, 0, sizeof(double) * (size_t)sys->n);
  sys->sink.failed = 0;
  int n_live;
  sk_term *const *live = sk_system_live_terms(sys, &n_live);
  for (int k = 0; k < n_live && status == SK_OK; ++k) {
    sk_term *term = live[k];
    if (!term->ops->residual) continue;
    const sk_clock t0 = sk_system_contact_clock(sys);
    status = term->ops->residual(term, sys);
    if (status == SK_OK && sys->sink.failed) status = sk_error_set(SK_ERR_PLUGIN, "%s", sys->sink.message);
    if (status != SK_OK && strncmp(sk_error_message(), term->name, strlen(term->name)) != 0) /* named once */
      sk_error_prefix(status, "%s: ", term->name);
    if (is_plugin(term)) sk_system_charge_contact(sys, SK_CONTACT_RESIDUAL, t0);
    else sys->t_assembly += now_seconds() - t0.wall;
  }
  status = note_fatal(sys, sk_system_collective(sys, status));
  sys->worst_row = -1; /* a residual that cannot be evaluated names its own culprit (an element, a plugin) */
  sys->worst_rank = -1;
  if (status != SK_OK) return status;
  /* the ghosts' rows summed into their owners */
  sk_exchange_reverse(&sys->ghost_dofs, sys->F_local);
  sk_exchange_reverse(&sys->ghost_extras, sys->F_local);
  for (int k = 0; k < n_live && status == SK_OK; ++k)
    if (live[k]->ops->finish_residual) status = live[k]->ops->finish_residual(live[k], sys, sys->F_local);
  for (int64_t k = 0; k < sys->n_owned; ++k) F[k] = sys->F_local[sys->owned[k]];
  note_worst(sys, F);
  return status;
}

static sk_status cb_jacobian(void *ctx, const double *x) {
  sk_system *sys = ctx;
  set_iterate(sys, x);
  sk_status status = update_active_set(sys);
  sk_linsys_zero(sys->linsys);
  memset(sys->rhs_local, 0, sizeof(double) * (size_t)sys->n);
  sys->sink.failed = 0;
  int n_live;
  sk_term *const *live = sk_system_live_terms(sys, &n_live);
  for (int k = 0; k < n_live && status == SK_OK; ++k) {
    sk_term *term = live[k];
    if (!term->ops->jacobian) continue;
    const sk_clock t0 = sk_system_contact_clock(sys);
    status = term->ops->jacobian(term, sys);
    if (status == SK_OK && sys->sink.failed) status = sk_error_set(SK_ERR_PLUGIN, "%s", sys->sink.message);
    if (status != SK_OK) sk_error_prefix(status, "%s: jacobian: ", term->name);
    if (is_plugin(term)) sk_system_charge_contact(sys, SK_CONTACT_JACOBIAN, t0);
    else sys->t_assembly += now_seconds() - t0.wall;
  }
  for (int k = 0; k < n_live && status == SK_OK; ++k)
    if (live[k]->ops->finish_jacobian) status = live[k]->ops->finish_jacobian(live[k], sys);
  status = note_fatal(sys, sk_system_collective(sys, status));
  if (status != SK_OK) return status;
  sk_exchange_reverse(&sys->ghost_dofs, sys->rhs_local);
  sk_exchange_reverse(&sys->ghost_extras, sys->rhs_local);
  for (int k = 0; k < n_live; ++k)
    if (live[k]->ops->finish_rhs) live[k]->ops->finish_rhs(live[k], sys, sys->rhs_local);
  const double t0 = now_seconds();
  status = sys->condensing ? sk_condenser_assemble(sys->condenser, sys->linsys) : sk_linsys_assemble(sys->linsys);
  sys->t_assembly += now_seconds() - t0;
  return status;
}

/* The system that the linear solves go to: the reduced one when pairs are condensed. */
static sk_linear_system *solving_system(sk_system *sys) {
  return sys->condensing ? sk_condenser_reduced(sys->condenser) : sys->linsys;
}

static sk_status solve_once(sk_system *sys, const double *b, double *y, sk_linear_report *report) {
  if (sys->forget_setup) {
    sk_linsys_forget_setup(sys->linsys);
    if (sys->condenser) sk_linsys_forget_setup(sk_condenser_reduced(sys->condenser));
  }
  return sys->condensing ? sk_condenser_solve(sys->condenser, sys->linsys, b, y, report)
                         : sk_linsys_solve(sys->linsys, b, y, report);
}

/* The kept system J_c dy = b over the linear system's owned rows; with stickslip.condense pairs through the
 * condenser (reduced solve + recovery). A Krylov solver the scene chose that misses its tolerance is replaced by the
 * direct solver for the rest of the run and the system solved again: a shorter step would not change its behaviour
 * on this system (bridge.h, sk_linear_failure). `auto` falls back by itself; a singular matrix fails for every
 * solver and is reported. */
static sk_status linear_solve(sk_system *sys, const double *b, double *y) {
  sk_linear_report report = {0};
  const double t0 = now_seconds();
  sk_status status = solve_once(sys, b, y, &report);
  const sk_linear_solver_kind chosen = sys->solver->linear.kind;
  if (status == SK_ERR_LINEAR_SOLVER && report.failure == SK_LINEAR_FAILURE_NOT_CONVERGED &&
      chosen != SK_LINEAR_AUTO && !sys->linear_fallback) {
    if (sys->rank == 0)
      fprintf(stderr, "stickslip: step %lld: %s; solver.linear.solver %s replaced by direct (MUMPS) for the rest "
              "of the run\n", (long long)sys->step, sk_error_message(), sk_linear_solver_name(chosen));
    sys->linear_fallback = 1;
    SK_TRY(sk_linsys_set_solver(sys->linsys, SK_LINEAR_DIRECT));
    if (sys->condenser) SK_TRY(sk_linsys_set_solver(sk_condenser_reduced(sys->condenser), SK_LINEAR_DIRECT));
    status = solve_once(sys, b, y, &report);
  }
  sys->t_solve += now_seconds() - t0;
  sys->linear_solves++;
  sys->linear_factorisations += report.factorisations;
  sys->krylov_iterations += report.iterations;
  if (report.solved) sys->step_solvers |= 1u << report.solver;
  return status;
}

/* A vector over the owned unknowns (NOX's) into the local unknowns, ghosts from their owners. */
static void owned_to_local(sk_system *sys, const double *owned, double *local) {
  for (int64_t k = 0; k < sys->n_owned; ++k) local[sys->owned[k]] = owned[k];
  sk_exchange_forward(&sys->ghost_dofs, local);
  sk_exchange_forward(&sys->ghost_extras, local);
}

static sk_status cb_solve(void *ctx, const double *x, const double *F, double *dx) {
  sk_system *sys = ctx;
  (void)x;
  /* b = -F + rhs over the local unknowns (owned entries), then on the linear system's rows */
  double *local = sys->dx_local;
  for (int64_t k = 0; k < sys->n_owned; ++k) local[sys->owned[k]] = -F[k] + sys->rhs_local[sys->owned[k]];
  SK_TRY(sk_system_to_rows(sys, local, sys->b));
  SK_TRY(linear_solve(sys, sys->b, sys->y));
  int any_jdx = 0, any_recover = 0, n_live;
  sk_term *const *live = sk_system_live_terms(sys, &n_live);
  for (int k = 0; k < n_live; ++k) {
    any_jdx |= live[k]->recover_needs_jdx;
    any_recover |= live[k]->ops->recover != NULL && live[k]->n_extra > 0;
  }
  MPI_Allreduce(MPI_IN_PLACE, &any_recover, 1, MPI_INT, MPI_MAX, sys->comm);
  memset(local, 0, sizeof(double) * (size_t)sys->n);
  SK_TRY(sk_system_from_rows(sys, sys->y, local));
  /* |dx . F| over the kept unknowns (FEAP's energy norm, --verbose), each owned entry once */
  double energy = 0.0;
  for (int64_t k = 0; k < sys->n_owned; ++k) energy += local[sys->owned[k]] * F[k];
  MPI_Allreduce(MPI_IN_PLACE, &energy, 1, MPI_DOUBLE, MPI_SUM, sys->comm);
  sys->newton_energy = fabs(energy);
  sk_exchange_forward(&sys->ghost_dofs, local);
  sk_exchange_forward(&sys->ghost_extras, local);
  if (any_recover) {
    if (any_jdx) {
      /* J dx with the assembled (uncondensed) operator, on the kept unknowns */
      SK_TRY(sk_linsys_apply(sys->linsys, sys->y, sys->b));
      memset(sys->Jdx, 0, sizeof(double) * (size_t)sys->n);
      SK_TRY(sk_system_from_rows(sys, sys->b, sys->Jdx));
      sk_exchange_forward(&sys->ghost_dofs, sys->Jdx);
      sk_exchange_forward(&sys->ghost_extras, sys->Jdx);
    }
    /* F over the local unknowns (the recover hooks read it at their views' nodes and extras) */
    double *F_local = sys->q_work;
    owned_to_local(sys, F, F_local);
    sk_status status = SK_OK;
    for (int k = 0; k < n_live && status == SK_OK; ++k) {
      sk_term *term = live[k];
      if (!term->ops->recover) continue;
      status = term->ops->recover(term, sys, F_local, local);
      if (status != SK_OK) sk_error_prefix(status, "%s: recover: ", term->name);
    }
    SK_TRY(note_fatal(sys, sk_system_collective(sys, status)));
    /* each rank recovered its own entities' eliminated unknowns; the sum over the ranks holding them completes dx */
    double *eliminated = sys->q_work;
    for (int64_t i = 0; i < sys->n; ++i) eliminated[i] = i >= sys->model->n_dofs && sys->solver_of[i] < 0 ? local[i] : 0.0;
    sk_exchange_reverse(&sys->ghost_extras, eliminated);
    for (int64_t i = sys->model->n_dofs; i < sys->n; ++i)
      if (sys->solver_of[i] < 0 && sys->role[i] == SK_NODE_OWNED) local[i] = eliminated[i];
  }
  for (int64_t k = 0; k < sys->n_owned; ++k) dx[k] = local[sys->owned[k]];
  return SK_OK;
}

sk_status sk_system_solve_again(sk_system *sys, const double *b, double *y) {
  /* b over the local unknowns: each rank's part, summed into the owners; the kept part is solved, eliminated entries
   * stay 0 */
  double *local = sys->q_work;
  memcpy(local, b, sizeof(double) * (size_t)sys->n);
  sk_exchange_reverse(&sys->ghost_dofs, local);
  sk_exchange_reverse(&sys->ghost_extras, local);
  SK_TRY(sk_system_to_rows(sys, local, sys->b));
  sk_linear_report report = {0};
  const double t0 = now_seconds();
  sk_status status = sys->condensing ? sk_condenser_solve_again(sys->condenser, sys->linsys, sys->b, sys->y, &report)
                                     : sk_linsys_solve_again(sys->linsys, sys->b, sys->y, &report);
  sys->t_solve += now_seconds() - t0;
  sys->linear_solves++;
  sys->linear_factorisations += report.factorisations;
  sys->krylov_iterations += report.iterations;
  if (report.solved) sys->step_solvers |= 1u << report.solver;
  SK_TRY(status);
  memset(y, 0, sizeof(double) * (size_t)sys->n);
  SK_TRY(sk_system_from_rows(sys, sys->y, y));
  for (int64_t i = 0; i < sys->n; ++i)
    if (sys->solver_of[i] < 0) y[i] = 0.0;
  sk_exchange_forward(&sys->ghost_dofs, y);
  sk_exchange_forward(&sys->ghost_extras, y);
  return SK_OK;
}

/* An inexact Newton step (newton.cpp's forcing term): iterative solvers stop at `tolerance`. */
static sk_status cb_solve_to_tolerance(void *ctx, const double *x, const double *F, double tolerance, double *dx) {
  sk_system *sys = ctx;
  SK_TRY(sk_linsys_set_tolerance(solving_system(sys), tolerance));
  return cb_solve(ctx, x, F, dx);
}

static sk_status cb_after_iteration(void *ctx, int iteration, const double *x, double residual_norm) {
  sk_system *sys = ctx;
  (void)x;
  if (sys->verbose && sys->rank == 0)
    fprintf(stderr, "  step %lld newton %d |F| = %.3e |dx.F| = %.3e\n", (long long)sys->step, iteration, residual_norm,
            sys->newton_energy);
  return SK_OK;
}

sk_status sk_system_solve(sk_system *sys) {
  const sk_newton_callbacks callbacks = {.ctx = sys,
                                         .residual = cb_residual,
                                         .jacobian = cb_jacobian,
                                         .solve = cb_solve,
                                         .solve_to_tolerance = cb_solve_to_tolerance,
                                         .after_iteration = cb_after_iteration};
  memset(&sys->newton, 0, sizeof sys->newton);
  const int max_loops = sys->solver->max_active_set_loops;
  /* the positions q = X + x carry the rounding that reaches the residual: the round-off floor of a correction */
  sk_newton_options options = sys->solver->newton;
  if (sys->backtracking) options.line_search = SK_LINE_SEARCH_BACKTRACK;
  double xx = 0.0;
  for (int64_t k = 0; k < sys->model->n_dofs; ++k)
    if (sys->role[k] == SK_NODE_OWNED) xx += sys->model->X[k] * sys->model->X[k];
  MPI_Allreduce(MPI_IN_PLACE, &xx, 1, MPI_DOUBLE, MPI_SUM, sys->comm);
  options.roundoff_scale = sqrt(xx);
  for (int loop = 0;; ++loop) {
    sk_newton_report report;
    sys->fatal = SK_OK;
    double *owned = sys->owned_work;
    for (int64_t k = 0; k < sys->n_owned; ++k) owned[k] = sys->x[sys->owned[k]];
    sk_status status = sk_newton_solve(sys->comm, &options, &callbacks, (int)sys->n_owned, owned, &report);
    if (status != SK_OK && sys->fatal != SK_OK) status = sk_error_set(sys->fatal, "%s", sys->fatal_message);
    const int iterations = sys->newton.iterations + report.iterations;
    const int solves = sys->newton.linear_solves + report.linear_solves;
    /* the attempt's solves that went on with backtracking (a count over the loops, where the report has a flag) */
    const int switches = sys->newton.switched_to_backtrack + report.switched_to_backtrack;
    if (report.switched_to_backtrack && sys->verbose && sys->rank == 0)
      fprintf(stderr, "  step %lld: no progress under the full step: Newton went on with backtracking\n",
              (long long)sys->step);
    sys->newton = report;
    sys->newton.iterations = iterations;
    sys->newton.linear_solves = solves;
    sys->newton.switched_to_backtrack = switches;
    for (int64_t k = 0; k < sys->n_owned; ++k) sys->x[sys->owned[k]] = owned[k];
    refresh_iterate(sys);
    if (status != SK_OK) return status;
    /* every term accepts the converged point, or Newton runs again from it (outer active-set loop) */
    int accept = 1, n_live;
    status = SK_OK;
    sk_term *const *live = sk_system_live_terms(sys, &n_live);
    for (int k = 0; k < n_live && status == SK_OK; ++k) {
      sk_term *term = live[k];
      if (!term->ops->converged) continue;
      int mine = 1;
      status = term->ops->converged(term, sys, &mine);
      if (status != SK_OK) sk_error_prefix(status, "%s: converged: ", term->name);
      accept = accept && mine;
    }
    if (status == SK_OK) status = sk_broad_phase_converged(sys, &accept); /* sleeping pairs brought near: woken */
    SK_TRY(sk_system_collective(sys, status));
    int all = 0;
    MPI_Allreduce(&accept, &all, 1, MPI_INT, MPI_MIN, sys->comm);
    if (all) return SK_OK;
    sys->active_set_loops++;
    sys->set_valid = 0; /* the set changed at this point: update_active_set runs again there */
    if (loop + 1 >= max_loops)
      return sk_error_set(SK_ERR_DIVERGED, "the active set did not settle after %d outer loops "
                          "(solver.newton.max_active_set_loops)", max_loops);
    /* the terms may eliminate other unknowns for the new set (nts-augmented: the augmented system of the active
     * nodes only); the pattern changes only if they do */
    SK_TRY(lay_out(sys, 1));
    if (sys->verbose && sys->rank == 0)
      fprintf(stderr, "  step %lld: a term rejected the converged point; Newton again (loop %d)\n",
              (long long)sys->step, loop + 2);
  }
}

sk_status sk_system_commit(sk_system *sys) {
  memset(sys->v, 0, sizeof(double) * (size_t)sys->model->n_dofs);
  sk_status status = SK_OK;
  int n_live;
  sk_term *const *live = sk_system_live_terms(sys, &n_live);
  for (int k = 0; k < n_live && status == SK_OK; ++k) {
    sk_term *term = live[k];
    if (!term->ops->commit) continue;
    const sk_clock t0 = sk_system_contact_clock(sys);
    status = term->ops->commit(term, sys);
    if (is_plugin(term)) sk_system_charge_contact(sys, SK_CONTACT_COMMIT, t0);
    if (status != SK_OK) sk_error_prefix(status, "%s: commit: ", term->name);
  }
  status = sk_system_collective(sys, status);
  /* the velocities of ghosts outside this rank's elements (which no term computes here) from their owners */
  if (status == SK_OK) sk_exchange_forward(&sys->ghost_dofs, sys->v);
  return status;
}

void sk_system_reject(sk_system *sys) {
  int n_live; /* the attempt's: a sleeping pair did nothing in it */
  sk_term *const *live = sk_system_live_terms(sys, &n_live);
  for (int k = 0; k < n_live; ++k)
    if (live[k]->ops->reject) live[k]->ops->reject(live[k], sys);
}

void sk_system_advance(sk_system *sys) {
  const size_t n = sizeof(double) * (size_t)sys->model->n_dofs;
  for (int64_t k = 0; k < sys->model->n_dofs; ++k) sys->rate_n[k] = (sys->x[k] - sys->u_n[k]) / sys->dt;
  memcpy(sys->u_n, sys->x, n);
  memcpy(sys->v_n, sys->v, n);
  memcpy(sys->q_n, sys->q, n);
  sys->t_n = sys->t;
}

sk_status sk_system_condense_pairs(sk_system *sys, int64_t n_groups, int block, const int64_t *z,
                                   const int64_t *rows) {
  const int64_t need = sys->n_pairs + n_groups * block;
  if (need > sys->cap_pairs) {
    const int64_t cap = 2 * need + 64;
    int64_t *pz = realloc(sys->pair_z, sizeof(int64_t) * (size_t)cap);
    if (pz) sys->pair_z = pz;
    int64_t *pr = realloc(sys->pair_row, sizeof(int64_t) * (size_t)cap);
    if (pr) sys->pair_row = pr;
    int *pb = realloc(sys->pair_block, sizeof(int) * (size_t)cap);
    if (pb) sys->pair_block = pb;
    if (!pz || !pr || !pb) return sk_system_out_of_memory("the condensation pairs", cap);
    sys->cap_pairs = cap;
  }
  for (int64_t k = 0; k < n_groups * block; ++k) {
    sys->pair_z[sys->n_pairs] = z[k]; /* ABI indices until the layout is known (lay_out) */
    sys->pair_row[sys->n_pairs] = rows[k];
    sys->pair_block[sys->n_pairs] = block;
    sys->n_pairs++;
  }
  return SK_OK;
}
