/* The system of a time step (system.h): the unknowns, the terms' stages, the declared sparsity pattern and the NOX
 * callbacks. Every term — a body's bulk, the tractions, the Dirichlet conditions, a plugin instance — is called
 * through term.h; nothing here knows which term does what. No allocation happens inside Newton: the work arrays grow
 * at layout time, outside the loop. */
#define _GNU_SOURCE
#include "system.h"

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

static sk_status out_of_memory(const char *what, int64_t count) {
  return sk_error_set(SK_ERR_NOMEM, "out of memory for %s (%lld entries)", what, (long long)count);
}

sk_status sk_system_collective(const sk_system *sys, sk_status local) {
  int code = (int)local, worst = 0;
  MPI_Allreduce(&code, &worst, 1, MPI_INT, MPI_MAX, sys->comm);
  if (worst != SK_OK && local == SK_OK) sk_error_set((sk_status)worst, "failure on another rank");
  return (sk_status)worst;
}

static int is_plugin(const sk_term *term) { return strcmp(term->ops->kind, "plugin") == 0; }

/* ---- creation --------------------------------------------------------------------------------------------------- */

static sk_status add_term(sk_system *sys, sk_term *term) {
  sk_term **grown = realloc(sys->terms, sizeof *grown * (size_t)(sys->n_terms + 1));
  if (!grown) {
    term->ops->destroy(term);
    return out_of_memory("the terms", sys->n_terms + 1);
  }
  sys->terms = grown;
  sys->terms[sys->n_terms++] = term;
  return SK_OK;
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
    SK_TRY(sk_term_plugin_create(sys, b, -1, &term));
    sys->body_plugin[b] = term;
    SK_TRY(add_term(sys, term));
  }
  for (int k = 0; k < m->n_pairs; ++k) {
    SK_TRY(sk_term_plugin_create(sys, -1, k, &term));
    SK_TRY(add_term(sys, term));
  }
  /* last: its finishing stages act on what every other term assembled */
  SK_TRY(sk_term_dirichlet_create(sys, &term));
  return add_term(sys, term);
}

sk_status sk_system_create(sk_model *model, const sk_solver_settings *solver, sk_system **out) {
  *out = NULL;
  sk_system *sys = calloc(1, sizeof *sys);
  if (!sys) return out_of_memory("the system", 1);
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
    return out_of_memory("the state vectors", model->n_dofs);
  }
  for (int k = 0; k < model->n_dofs; ++k) sys->q_n[k] = sys->q[k] = model->X[k];
  sk_status status = sk_linsys_create(model->comm, &solver->linear, &sys->linsys);
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
  double **arrays[] = {&sys->F_local, &sys->rhs_local, &sys->rhs, &sys->b, &sys->y, &sys->dx_elim, &sys->Jdx,
                       &sys->set_x};
  for (size_t k = 0; k < sizeof arrays / sizeof arrays[0]; ++k) {
    free(*arrays[k]);
    *arrays[k] = NULL;
  }
  free(sys->kept);
  free(sys->full_of_kept);
  sys->kept = sys->full_of_kept = NULL;
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
  for (int k = sys->n_terms - 1; k >= 0; --k) sys->terms[k]->ops->destroy(sys->terms[k]);
  free(sys->terms);
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
  free(sys->extra_keys);
  free(sys->row_ptr);
  free(sys->cols);
  free(sys->row_local);
  free(sys->local_rows);
  free(sys->elem_pos_offset);
  free(sys->elem_pos);
  free(sys->pair_z);
  free(sys->pair_row);
  free(sys->pair_block);
  sk_condenser_destroy(sys->condenser);
  sk_linsys_destroy(sys->linsys);
  free(sys);
}

/* ---- the unknowns of an attempt ---------------------------------------------------------------------------------- */

/* The n-sized work arrays; x keeps its values when it grows. Called at layout time only. */
static sk_status ensure_capacity(sk_system *sys, int64_t n) {
  if (n <= sys->capacity && sys->kept) return SK_OK;
  const int64_t cap = n + n / 4 + 16;
  /* calloc of many GB succeeds lazily on Linux and the first touch gets the process killed by the OOM killer: refuse
   * work vectors (x, two numberings, eight vectors: 80 bytes per unknown) larger than the machine's memory */
  const double need = 80.0 * (double)cap, memory = (double)sysconf(_SC_PHYS_PAGES) * (double)sysconf(_SC_PAGESIZE);
  if (memory > 0 && need > memory) {
    const sk_term *largest = sys->terms[0];
    for (int k = 1; k < sys->n_terms; ++k)
      if (sys->terms[k]->n_extra > largest->n_extra) largest = sys->terms[k];
    return sk_error_set(SK_ERR_NOMEM, "%lld unknowns (%lld displacement dofs, %lld extra unknowns of %s) need %.3g GB "
                        "for the work vectors alone, more than this machine's %.3g GB of memory", (long long)n,
                        (long long)sys->model->n_dofs, (long long)largest->n_extra, largest->name, need / 1e9,
                        memory / 1e9);
  }
  free_unknown_arrays(sys);
  double *x = calloc((size_t)cap, sizeof(double));
  if (!x) return out_of_memory("the unknowns", cap);
  if (sys->x) memcpy(x, sys->x, sizeof(double) * (size_t)sys->capacity);
  free(sys->x);
  sys->x = x;
  sys->capacity = cap;
  sys->kept = calloc((size_t)cap, sizeof(int));
  sys->full_of_kept = calloc((size_t)cap, sizeof(int));
  double **arrays[] = {&sys->F_local, &sys->rhs_local, &sys->rhs, &sys->b, &sys->y, &sys->dx_elim, &sys->Jdx,
                       &sys->set_x};
  int ok = sys->kept && sys->full_of_kept;
  for (size_t k = 0; k < sizeof arrays / sizeof arrays[0]; ++k) {
    *arrays[k] = calloc((size_t)cap, sizeof(double));
    ok = ok && *arrays[k];
  }
  if (!ok) {
    free_unknown_arrays(sys);
    return out_of_memory("the work vectors", cap);
  }
  return SK_OK;
}

/* Numbers the attempt's unknowns from the terms' layouts; *changed when the kept numbering differs from before.
 * again: a layout after a rejected converged point (docs/plugin-abi.md, converged): the extras keep their values at
 * x and their number must not change; only what the plugins eliminate may. */
static sk_status layout_unknowns(sk_system *sys, int again, int *changed) {
  sk_model *m = sys->model;
  int64_t n = m->n_dofs;
  sys->n_pairs = 0;
  for (int k = 0; k < sys->n_terms; ++k) {
    sk_term *term = sys->terms[k];
    term->extra_offset = n;
    term->n_extra = 0;
    term->initial = NULL;
    term->eliminated = NULL;
    term->anchor = NULL;
    term->recover_needs_jdx = 0;
    if (!term->ops->layout) continue;
    sk_status status = term->ops->layout(term, sys);
    if (status != SK_OK) return sk_error_prefix(status, "%s: layout: ", term->name);
    if (term->n_extra < 0) return sk_error_set(SK_ERR_PLUGIN, "%s: negative layout", term->name);
    n += term->n_extra;
  }
  if (again && n != sys->n)
    return sk_error_set(SK_ERR_PLUGIN, "the number of extra unknowns changed from %lld to %lld within a step "
                        "attempt (a layout after converged() may change only what is eliminated)",
                        (long long)(sys->n - m->n_dofs), (long long)(n - m->n_dofs));
  /* the bridge and NOX count unknowns in int */
  if (n > INT_MAX - 16)
    return sk_error_set(SK_ERR_INPUT, "%lld unknowns exceed the %d the linear solvers can number", (long long)n,
                        INT_MAX - 16);
  const int64_t old_n = sys->n, old_kept = sys->n_kept;
  int *old = NULL;
  if (old_n > 0) {
    old = malloc(sizeof(int) * (size_t)old_n);
    if (!old) return out_of_memory("the unknowns' numbering", old_n);
    memcpy(old, sys->kept, sizeof(int) * (size_t)old_n);
  }
  sk_status status = ensure_capacity(sys, n);
  if (status != SK_OK) {
    free(old);
    return status;
  }
  sys->n = n;
  int kept = 0;
  for (int64_t i = 0; i < m->n_dofs; ++i) {
    sys->kept[i] = kept;
    sys->full_of_kept[kept++] = (int)i;
  }
  for (int k = 0; k < sys->n_terms; ++k) {
    const sk_term *term = sys->terms[k];
    for (int64_t j = 0; j < term->n_extra; ++j) {
      const int64_t i = term->extra_offset + j;
      if (term->eliminated && term->eliminated[j]) {
        sys->kept[i] = -1;
      } else {
        sys->kept[i] = kept;
        sys->full_of_kept[kept++] = (int)i;
      }
      if (!again) sys->x[i] = term->initial ? term->initial[j] : 0.0;
    }
  }
  sys->n_kept = kept;
  if (sys->n_ranks > 1 && n > m->n_dofs) {
    /* each rank gives the starting values of its owned entities (zero elsewhere): the sum is the whole layout */
    if (!again)
      MPI_Allreduce(MPI_IN_PLACE, sys->x + m->n_dofs, (int)(n - m->n_dofs), MPI_DOUBLE, MPI_SUM, sys->comm);
    int64_t counts[2] = {kept, -kept};
    MPI_Allreduce(MPI_IN_PLACE, counts, 2, MPI_INT64_T, MPI_MAX, sys->comm);
    if (counts[0] != -counts[1]) {
      free(old);
      return sk_error_set(SK_ERR_PLUGIN, "the eliminated unknowns differ between ranks (layout().eliminated must "
                          "describe the whole layout on every rank)");
    }
  }
  *changed = old_n != n || old_kept != kept || (old && memcmp(old, sys->kept, sizeof(int) * (size_t)n) != 0);
  free(old);
  if (sys->unknowns_max < n) sys->unknowns_max = n;
  return SK_OK;
}

/* ---- state from an iterate --------------------------------------------------------------------------------------- */

static void set_iterate(sk_system *sys, const double *x) {
  sk_model *m = sys->model;
  if (x != sys->x) {
    if (memcmp(x, sys->x, sizeof(double) * (size_t)sys->n) == 0) return;
    memcpy(sys->x, x, sizeof(double) * (size_t)sys->n);
  }
  for (int k = 0; k < m->n_dofs; ++k) sys->q[k] = m->X[k] + sys->x[k];
  sys->x_version++;
}

/* update_active_set once at every new point, before the first residual or Jacobian evaluated there. */
static sk_status update_active_set(sk_system *sys) {
  if (sys->set_valid && memcmp(sys->set_x, sys->x, sizeof(double) * (size_t)sys->n) == 0) return SK_OK;
  memcpy(sys->set_x, sys->x, sizeof(double) * (size_t)sys->n);
  sys->set_valid = 1;
  sk_status status = SK_OK;
  for (int k = 0; k < sys->n_terms && status == SK_OK; ++k) {
    sk_term *term = sys->terms[k];
    if (!term->ops->update_active_set) continue;
    int changed = 0;
    status = term->ops->update_active_set(term, sys, &changed);
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
  if (!sys->x) SK_TRY(ensure_capacity(sys, m->n_dofs));
  memcpy(sys->x, sys->u_n, sizeof(double) * (size_t)m->n_dofs);
  sk_status status = SK_OK;
  for (int k = 0; k < sys->n_terms && status == SK_OK; ++k)
    if (sys->terms[k]->ops->predict) status = sys->terms[k]->ops->predict(sys->terms[k], sys);
  SK_TRY(sk_system_collective(sys, status));
  for (int k = 0; k < m->n_dofs; ++k) sys->q[k] = m->X[k] + sys->x[k];
  sys->x_version++;
  for (int k = 0; k < sys->n_terms; ++k) {
    sk_term *term = sys->terms[k];
    if (!term->ops->begin_step) continue;
    status = sk_system_collective(sys, term->ops->begin_step(term, sys));
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
  if (!fixed) return out_of_memory("the fixed rows of the condensation pairs", m->n_dofs);
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

/* The attempt's unknowns, pattern and condensation pairs from the terms' layouts (again: see layout_unknowns). */
static sk_status lay_out(sk_system *sys, int again) {
  sk_model *m = sys->model;
  int changed = 0;
  sk_status status = sk_system_collective(sys, layout_unknowns(sys, again, &changed));
  if (status != SK_OK) return status;
  sys->x_version++; /* the extras got their starting values */
  SK_TRY(sk_system_settle_pattern(sys, changed));
  sys->condensing = 0;
  SK_TRY(sk_system_collective(sys, drop_fixed_pairs(sys)));
  int64_t pairs_anywhere = 0;
  MPI_Allreduce(&sys->n_pairs, &pairs_anywhere, 1, MPI_INT64_T, MPI_SUM, sys->comm);
  if (pairs_anywhere > 0) {
    /* the pairs in the linear system's (kept) numbering */
    for (int64_t k = 0; k < sys->n_pairs; ++k) {
      const int z = sys->kept[sys->pair_z[k]], row = sys->kept[sys->pair_row[k]];
      if (z < 0 || row < 0 || sys->pair_row[k] >= m->n_dofs)
        status = sk_error_set(SK_ERR_PLUGIN, "stickslip.condense: pair %lld (unknown %lld, row %lld): the multiplier "
                              "is eliminated by the plugin or the row is not a displacement row", (long long)k,
                              (long long)sys->pair_z[k], (long long)sys->pair_row[k]);
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

/* Remembers the largest |F| entry (the first non-finite one wins): where a step that cannot be solved fails. */
static void note_worst(sk_system *sys, const double *F) {
  int64_t worst = -1;
  double largest = -1.0;
  for (int64_t i = 0; i < sys->n; ++i) {
    const double a = fabs(F[i]);
    if (!isfinite(a)) {
      worst = i;
      largest = a;
      break;
    }
    if (a > largest) {
      worst = i;
      largest = a;
    }
  }
  sys->worst_row = worst;
  sys->worst_residual = F && worst >= 0 ? F[worst] : 0.0;
}

static sk_status cb_residual(void *ctx, const double *x, double *F) {
  sk_system *sys = ctx;
  set_iterate(sys, x);
  sk_status status = update_active_set(sys);
  memset(sys->F_local, 0, sizeof(double) * (size_t)sys->n);
  sys->sink.failed = 0;
  for (int k = 0; k < sys->n_terms && status == SK_OK; ++k) {
    sk_term *term = sys->terms[k];
    if (!term->ops->residual) continue;
    const double t0 = now_seconds();
    status = term->ops->residual(term, sys);
    if (status == SK_OK && sys->sink.failed) status = sk_error_set(SK_ERR_PLUGIN, "%s", sys->sink.message);
    if (status != SK_OK) sk_error_prefix(status, "%s: ", term->name);
    *(is_plugin(term) ? &sys->t_contact : &sys->t_assembly) += now_seconds() - t0;
  }
  status = note_fatal(sys, sk_system_collective(sys, status));
  sys->worst_row = -1; /* a residual that cannot be evaluated names its own culprit (an element, a plugin) */
  if (status != SK_OK) return status;
  MPI_Allreduce(sys->F_local, F, (int)sys->n, MPI_DOUBLE, MPI_SUM, sys->comm);
  for (int k = 0; k < sys->n_terms && status == SK_OK; ++k)
    if (sys->terms[k]->ops->finish_residual) status = sys->terms[k]->ops->finish_residual(sys->terms[k], sys, F);
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
  for (int k = 0; k < sys->n_terms && status == SK_OK; ++k) {
    sk_term *term = sys->terms[k];
    if (!term->ops->jacobian) continue;
    const double t0 = now_seconds();
    status = term->ops->jacobian(term, sys);
    if (status == SK_OK && sys->sink.failed) status = sk_error_set(SK_ERR_PLUGIN, "%s", sys->sink.message);
    if (status != SK_OK) sk_error_prefix(status, "%s: jacobian: ", term->name);
    *(is_plugin(term) ? &sys->t_contact : &sys->t_assembly) += now_seconds() - t0;
  }
  for (int k = 0; k < sys->n_terms && status == SK_OK; ++k)
    if (sys->terms[k]->ops->finish_jacobian) status = sys->terms[k]->ops->finish_jacobian(sys->terms[k], sys);
  status = note_fatal(sys, sk_system_collective(sys, status));
  if (status != SK_OK) return status;
  MPI_Allreduce(sys->rhs_local, sys->rhs, (int)sys->n, MPI_DOUBLE, MPI_SUM, sys->comm);
  for (int k = 0; k < sys->n_terms; ++k)
    if (sys->terms[k]->ops->finish_rhs) sys->terms[k]->ops->finish_rhs(sys->terms[k], sys, sys->rhs);
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

/* The kept system J_c dy = b; with stickslip.condense pairs through the condenser (reduced solve + recovery).
 * A Krylov solver the scene chose that misses its tolerance is replaced by the direct solver for the rest of the run
 * and the system solved again: a shorter step would not change its behaviour on this system (bridge.h,
 * sk_linear_failure). `auto` falls back by itself; a singular matrix fails for every solver and is reported. */
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
  if (report.solved) sys->step_solvers |= 1u << report.solver;
  return status;
}

static sk_status cb_solve(void *ctx, const double *x, const double *F, double *dx) {
  sk_system *sys = ctx;
  (void)x;
  for (int64_t k = 0; k < sys->n_kept; ++k) {
    const int i = sys->full_of_kept[k];
    sys->b[k] = -F[i] + sys->rhs[i];
  }
  SK_TRY(linear_solve(sys, sys->b, sys->y));
  int any_eliminated = sys->n_kept < sys->n, any_jdx = 0;
  for (int64_t i = 0; i < sys->n; ++i) dx[i] = sys->kept[i] >= 0 ? sys->y[sys->kept[i]] : 0.0;
  double energy = 0.0;
  for (int64_t i = 0; i < sys->n; ++i) energy += dx[i] * F[i];
  sys->newton_energy = fabs(energy);
  for (int k = 0; k < sys->n_terms; ++k) any_jdx |= sys->terms[k]->recover_needs_jdx;
  if (any_jdx) {
    /* J dx with the assembled (uncondensed) operator, on the kept unknowns */
    SK_TRY(sk_linsys_apply(sys->linsys, sys->y, sys->b));
    memset(sys->Jdx, 0, sizeof(double) * (size_t)sys->n);
    for (int64_t k = 0; k < sys->n_kept; ++k) sys->Jdx[sys->full_of_kept[k]] = sys->b[k];
  }
  sk_status status = SK_OK;
  for (int k = 0; k < sys->n_terms && status == SK_OK; ++k) {
    sk_term *term = sys->terms[k];
    if (!term->ops->recover) continue;
    status = term->ops->recover(term, sys, F, dx);
    if (status != SK_OK) sk_error_prefix(status, "%s: recover: ", term->name);
  }
  status = note_fatal(sys, sk_system_collective(sys, status));
  if (status != SK_OK || !any_eliminated || sys->n_ranks == 1) return status;
  /* each rank recovered its own entities' eliminated unknowns; the sum over ranks completes dx */
  int n_elim = 0;
  for (int64_t i = 0; i < sys->n; ++i)
    if (sys->kept[i] < 0) sys->dx_elim[n_elim++] = dx[i];
  MPI_Allreduce(MPI_IN_PLACE, sys->dx_elim, n_elim, MPI_DOUBLE, MPI_SUM, sys->comm);
  n_elim = 0;
  for (int64_t i = 0; i < sys->n; ++i)
    if (sys->kept[i] < 0) dx[i] = sys->dx_elim[n_elim++];
  return SK_OK;
}

sk_status sk_system_solve_again(sk_system *sys, const double *b, double *y) {
  /* b, y in the full numbering; the kept part is solved, eliminated entries stay 0 */
  for (int64_t k = 0; k < sys->n_kept; ++k) sys->b[k] = b[sys->full_of_kept[k]];
  sk_linear_report report = {0};
  const double t0 = now_seconds();
  sk_status status = sys->condensing ? sk_condenser_solve_again(sys->condenser, sys->linsys, sys->b, sys->y, &report)
                                     : sk_linsys_solve_again(sys->linsys, sys->b, sys->y, &report);
  sys->t_solve += now_seconds() - t0;
  sys->linear_solves++;
  if (report.solved) sys->step_solvers |= 1u << report.solver;
  SK_TRY(status);
  for (int64_t i = 0; i < sys->n; ++i) y[i] = sys->kept[i] >= 0 ? sys->y[sys->kept[i]] : 0.0;
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
  for (int64_t k = 0; k < sys->model->n_dofs; ++k) xx += sys->model->X[k] * sys->model->X[k];
  options.roundoff_scale = sqrt(xx);
  for (int loop = 0;; ++loop) {
    sk_newton_report report;
    sys->fatal = SK_OK;
    sk_status status = sk_newton_solve(sys->comm, &options, &callbacks, (int)sys->n, sys->x, &report);
    if (status != SK_OK && sys->fatal != SK_OK) status = sk_error_set(sys->fatal, "%s", sys->fatal_message);
    const int iterations = sys->newton.iterations + report.iterations;
    const int solves = sys->newton.linear_solves + report.linear_solves;
    sys->newton = report;
    sys->newton.iterations = iterations;
    sys->newton.linear_solves = solves;
    set_iterate(sys, sys->x);
    if (status != SK_OK) return status;
    /* every term accepts the converged point, or Newton runs again from it (outer active-set loop) */
    int accept = 1;
    status = SK_OK;
    for (int k = 0; k < sys->n_terms && status == SK_OK; ++k) {
      sk_term *term = sys->terms[k];
      if (!term->ops->converged) continue;
      int mine = 1;
      status = term->ops->converged(term, sys, &mine);
      if (status != SK_OK) sk_error_prefix(status, "%s: converged: ", term->name);
      accept = accept && mine;
    }
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
  for (int k = 0; k < sys->n_terms && status == SK_OK; ++k) {
    sk_term *term = sys->terms[k];
    if (!term->ops->commit) continue;
    status = term->ops->commit(term, sys);
    if (status != SK_OK) sk_error_prefix(status, "%s: commit: ", term->name);
  }
  return sk_system_collective(sys, status);
}

void sk_system_reject(sk_system *sys) {
  for (int k = 0; k < sys->n_terms; ++k)
    if (sys->terms[k]->ops->reject) sys->terms[k]->ops->reject(sys->terms[k], sys);
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
    if (!pz || !pr || !pb) return out_of_memory("the condensation pairs", cap);
    sys->cap_pairs = cap;
  }
  for (int64_t k = 0; k < n_groups * block; ++k) {
    sys->pair_z[sys->n_pairs] = z[k];
    sys->pair_row[sys->n_pairs] = rows[k];
    sys->pair_block[sys->n_pairs] = block;
    sys->n_pairs++;
  }
  return SK_OK;
}

