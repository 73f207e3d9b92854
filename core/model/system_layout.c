/* The layout of an attempt's unknowns (system.h; docs/design.md, "Numbering"): the terms' extra unknowns after the
 * dofs, who owns and who holds each unknown, the linear system's numbering (each rank's owned dofs a block of nodal
 * rows, the kept extras constraint rows on the last rank), the ghost exchanges and the gather of the constraint
 * rows' right-hand side. */
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "system.h"


/* The live term whose block of extras holds `index` (by_local: a local unknown, else an ABI index), or NULL: the
 * last term whose block starts at or before it (the blocks follow the terms' order; empty ones are passed over). */
static const sk_term *term_of_extra(const sk_system *sys, int64_t index, int by_local) {
  int n_live;
  sk_term *const *live = sk_system_live_terms(sys, &n_live);
  int lo = 0, hi = n_live - 1, found = -1;
  while (lo <= hi) {
    const int mid = lo + (hi - lo) / 2;
    if ((by_local ? live[mid]->extra_local : live[mid]->extra_offset) <= index) {
      found = mid;
      lo = mid + 1;
    } else {
      hi = mid - 1;
    }
  }
  if (found < 0) return NULL;
  const sk_term *term = live[found];
  return by_local ? (index - term->extra_local < term->n_held ? term : NULL)
                  : (index - term->extra_offset < term->n_extra ? term : NULL);
}

int64_t sk_system_local_of(const sk_system *sys, int64_t abi) {
  const sk_model *m = sys->model;
  if (abi < 0) return -1;
  if (abi < m->n_dofs_global) {
    const int node = sk_model_node_of(m, abi / m->dim);
    return node >= 0 && sys->node_role[node] ? (int64_t)node * m->dim + abi % m->dim : -1;
  }
  const sk_term *term = abi < sys->n_abi ? term_of_extra(sys, abi, 0) : NULL;
  if (!term) return -1;
  const int64_t j = abi - term->extra_offset;
  if (term->n_held == term->n_extra) return term->extra_local + j; /* every extra held: held[k] = k, no search */
  const int64_t *at = bsearch(&j, term->held, (size_t)term->n_held, sizeof(int64_t), sk_compare_i64);
  return at ? term->extra_local + (at - term->held) : -1;
}

int64_t sk_system_abi_of(const sk_system *sys, int64_t local) {
  const sk_model *m = sys->model;
  if (local < m->n_dofs) return m->node_gid[local / m->dim] * m->dim + local % m->dim;
  const sk_term *term = term_of_extra(sys, local, 1);
  return term ? term->extra_offset + term->held[local - term->extra_local] : -1;
}

double *sk_system_extra_block(const sk_system *sys, sk_term *term) {
  if (!term->extra_values) return NULL;
  for (int64_t k = 0; k < term->n_held; ++k) term->extra_values[term->held[k]] = sys->x[term->extra_local + k];
  return term->extra_values;
}

void sk_system_extras_to_block(const sk_term *term, const double *local, double *block) {
  for (int64_t j = 0; j < term->n_extra; ++j) block[j] = 0.0;
  for (int64_t k = 0; k < term->n_held; ++k) block[term->held[k]] = local[term->extra_local + k];
}

void sk_system_extras_from_block(const sk_term *term, const double *block, double *local) {
  for (int64_t k = 0; k < term->n_held; ++k) local[term->extra_local + k] = block[term->held[k]];
}

/* The extras of a term this rank holds (held, n_held: those with an owner; all without extra_owner) and room for
 * the plugins' block; *moved when they differ from the last layout's. */
static sk_status hold_extras(sk_term *term, int *moved) {
  const int64_t n = term->n_extra;
  if (n > term->held_size || n > term->values_size) {
    int64_t *held = realloc(term->held, sizeof(int64_t) * (size_t)(n > 0 ? n : 1));
    if (held) {
      term->held = held;
      term->held_size = n;
    }
    double *values = realloc(term->extra_values, sizeof(double) * (size_t)(n > 0 ? n : 1));
    if (values) {
      term->extra_values = values;
      term->values_size = n;
    }
    if (!held || !values) return sk_system_out_of_memory("the extra unknowns held", n);
  }
  int64_t count = 0;
  for (int64_t j = 0; j < n; ++j) {
    if (term->extra_owner && term->extra_owner[j] < 0) continue;
    *moved |= count >= term->n_held || term->held[count] != j;
    term->held[count++] = j;
  }
  *moved |= count != term->n_held || term->held_offset != term->extra_offset;
  term->n_held = count;
  term->held_offset = term->extra_offset;
  return SK_OK;
}

/* The owner's local index of an unknown it owns (sk_exchange_lookup). */
static int64_t lookup_owned(void *ctx, int64_t abi) {
  const sk_system *sys = ctx;
  const int64_t local = sk_system_local_of(sys, abi);
  return local >= 0 && sys->role[local] == SK_NODE_OWNED ? local : -1;
}

/* The room the work arrays of n unknowns get (some to spare, so that small changes do not reallocate). */
static int64_t room_for(int64_t n) { return n + n / 4 + 16; }

/* calloc of many GB succeeds lazily on Linux and the first touch gets the process killed by the OOM killer: refuses
 * work vectors (x, numberings, nine vectors: about 90 bytes per unknown) for n unknowns larger than the machine's
 * memory. */
static sk_status refuse_beyond_memory(const sk_system *sys, int64_t n) {
  const double need = 90.0 * (double)room_for(n);
  const double memory = (double)sysconf(_SC_PHYS_PAGES) * (double)sysconf(_SC_PAGESIZE);
  if (memory <= 0 || need <= memory) return SK_OK;
  const sk_term *largest = sys->terms[0];
  for (int k = 1; k < sys->n_terms; ++k)
    if (sys->terms[k]->n_extra > largest->n_extra) largest = sys->terms[k];
  return sk_error_set(SK_ERR_NOMEM, "%lld unknowns (%lld displacement dofs, %lld extra unknowns of %s) need %.3g GB "
                      "for the work vectors alone, more than this machine's %.3g GB of memory", (long long)n,
                      (long long)sys->model->n_dofs, (long long)largest->n_extra, largest->name, need / 1e9,
                      memory / 1e9);
}

/* The n-sized work arrays; x keeps its values when it grows. Called at layout time only. */
sk_status sk_system_ensure_capacity(sk_system *sys, int64_t n) {
  if (n <= sys->capacity && sys->solver_of) return SK_OK;
  const int64_t cap = room_for(n);
  SK_TRY(refuse_beyond_memory(sys, n));
  double *x = calloc((size_t)cap, sizeof(double));
  if (!x) return sk_system_out_of_memory("the unknowns", cap);
  if (sys->x) memcpy(x, sys->x, sizeof(double) * (size_t)sys->capacity);
  free(sys->x);
  sys->x = x;
  sys->capacity = cap;
  double **arrays[] = {&sys->F_local, &sys->rhs_local, &sys->b, &sys->y, &sys->dx_local, &sys->Jdx, &sys->set_x,
                       &sys->owned_work, &sys->q_work};
  int ok = 1;
  for (size_t k = 0; k < sizeof arrays / sizeof arrays[0]; ++k) {
    free(*arrays[k]);
    *arrays[k] = calloc((size_t)cap, sizeof(double));
    ok = ok && *arrays[k];
  }
  free(sys->solver_of);
  free(sys->role);
  free(sys->owned);
  free(sys->constraint_out);
  sys->solver_of = malloc(sizeof(int) * (size_t)cap);
  sys->role = calloc((size_t)cap, 1);
  sys->owned = malloc(sizeof(int) * (size_t)cap);
  sys->constraint_out = malloc(sizeof(int) * (size_t)cap);
  if (!ok || !sys->solver_of || !sys->role || !sys->owned || !sys->constraint_out)
    return sk_system_out_of_memory("the work vectors", cap);
  return SK_OK;
}

/* The dofs' owned list, the first nodal row of this rank (once: the owners of the nodes do not change during a run)
 * and the dofs' ghost exchange (planned again when master faces are ghosted again, master_ghosts.c). */
sk_status sk_system_layout_dofs(sk_system *sys) {
  sk_model *m = sys->model;
  sys->node_role = calloc((size_t)(m->n_nodes > 0 ? m->n_nodes : 1), 1);
  sys->owned_dofs = malloc(sizeof(int) * (size_t)(m->n_dofs > 0 ? m->n_dofs : 1));
  if (!sys->node_role || !sys->owned_dofs) return sk_system_out_of_memory("the owned dofs", m->n_dofs);
  SK_TRY(sk_model_node_roles(m, sys->node_role));
  int64_t n_owned = 0;
  for (int a = 0; a < m->n_nodes; ++a)
    if (sys->node_role[a] == SK_NODE_OWNED)
      for (int i = 0; i < m->dim; ++i) sys->owned_dofs[n_owned++] = a * m->dim + i;
  sys->n_owned_dofs = n_owned;
  MPI_Exscan(&n_owned, &sys->first_row, 1, MPI_INT64_T, MPI_SUM, sys->comm);
  if (sys->rank == 0) sys->first_row = 0;
  MPI_Allreduce(&n_owned, &sys->n_nodal, 1, MPI_INT64_T, MPI_SUM, sys->comm);
  if (sys->n_nodal > INT_MAX - 16)
    return sk_error_set(SK_ERR_INPUT, "%lld displacement dofs exceed the %d the linear solvers can number",
                        (long long)sys->n_nodal, INT_MAX - 16);
  return sk_system_plan_ghost_dofs(sys, &sys->ghost_dofs, 0);
}

sk_status sk_system_plan_ghost_dofs(sk_system *sys, sk_exchange *x, int every_node) {
  const sk_model *m = sys->model;
  int64_t n_ghosts = 0;
  for (int a = 0; a < m->n_nodes; ++a)
    n_ghosts += every_node ? sys->node_role[a] != SK_NODE_OWNED : sys->node_role[a] == SK_NODE_GHOST;
  /* the role array over the dofs is all the lookup needs */
  int64_t *local = malloc(sizeof(int64_t) * (size_t)(n_ghosts * m->dim + 1));
  int64_t *gid = malloc(sizeof(int64_t) * (size_t)(n_ghosts * m->dim + 1));
  int *owner = malloc(sizeof(int) * (size_t)(n_ghosts * m->dim + 1));
  unsigned char *role = calloc((size_t)(m->n_dofs > 0 ? m->n_dofs : 1), 1);
  sk_status status = local && gid && owner && role ? SK_OK : sk_system_out_of_memory("the ghost dofs", n_ghosts);
  int64_t g = 0;
  for (int a = 0; a < m->n_nodes && status == SK_OK; ++a) {
    for (int i = 0; i < m->dim; ++i) role[a * m->dim + i] = sys->node_role[a];
    if (every_node ? sys->node_role[a] == SK_NODE_OWNED : sys->node_role[a] != SK_NODE_GHOST) continue;
    for (int i = 0; i < m->dim; ++i, ++g) {
      local[g] = a * m->dim + i;
      gid[g] = m->node_gid[a] * m->dim + i;
      owner[g] = m->node_owner[a];
    }
  }
  /* the lookup reads sys->role over the dofs (the extras come later) */
  unsigned char *saved = sys->role;
  int64_t saved_n = sys->n;
  sys->role = role;
  sys->n = m->n_dofs;
  status = sk_system_collective(sys, status);
  if (status == SK_OK) status = sk_exchange_plan(x, sys->comm, g, local, gid, owner, lookup_owned, sys);
  sys->role = saved;
  sys->n = saved_n;
  free(local);
  free(gid);
  free(owner);
  free(role);
  return status;
}

/* The extras' owners (each term's, or rank 0 for all), their ghost exchange, the owned list for NOX and the
 * constraint rows' gather (after the terms' layouts). */
static sk_status plan_extras(sk_system *sys) {
  const sk_model *m = sys->model;
  int64_t n_ghosts = 0;
  for (int64_t i = m->n_dofs; i < sys->n; ++i) n_ghosts += sys->role[i] == SK_NODE_GHOST;
  int64_t *local = malloc(sizeof(int64_t) * (size_t)(n_ghosts + 1));
  int64_t *gid = malloc(sizeof(int64_t) * (size_t)(n_ghosts + 1));
  int *owner = malloc(sizeof(int) * (size_t)(n_ghosts + 1));
  sk_status status = local && gid && owner ? SK_OK : sk_system_out_of_memory("the ghost extras", n_ghosts);
  int64_t g = 0;
  int n_live; /* a sleeping pair has no extra unknowns (sk_term_plugin_set_far) */
  sk_term *const *live = sk_system_live_terms(sys, &n_live);
  for (int k = 0; k < n_live && status == SK_OK; ++k) {
    const sk_term *term = live[k];
    for (int64_t h = 0; h < term->n_held; ++h) {
      const int64_t i = term->extra_local + h, j = term->held[h];
      if (sys->role[i] != SK_NODE_GHOST) continue;
      local[g] = i;
      gid[g] = term->extra_offset + j;
      owner[g++] = term->extra_owner ? term->extra_owner[j] : 0;
    }
  }
  status = sk_system_collective(sys, status);
  if (status == SK_OK) status = sk_exchange_plan(&sys->ghost_extras, sys->comm, g, local, gid, owner, lookup_owned, sys);
  free(local);
  free(gid);
  free(owner);
  return status;
}

/* The last rank's gather plan of the constraint rows (this rank's owned kept extras). */
static sk_status plan_constraints(sk_system *sys) {
  const int last = sys->n_ranks - 1;
  sys->n_constraint_out = 0;
  for (int64_t k = sys->n_owned_dofs; k < sys->n_owned; ++k)
    if (sys->solver_of[sys->owned[k]] >= 0) sys->constraint_out[sys->n_constraint_out++] = sys->owned[k];
  free(sys->constraint_counts);
  free(sys->constraint_displs);
  free(sys->constraint_row);
  free(sys->constraint_buffer);
  const int64_t n_constraints = sys->n_kept - sys->n_nodal;
  sys->constraint_counts = calloc((size_t)sys->n_ranks, sizeof(int));
  sys->constraint_displs = calloc((size_t)sys->n_ranks + 1, sizeof(int));
  sys->constraint_row = malloc(sizeof(int) * (size_t)(n_constraints + 1));
  sys->constraint_buffer = malloc(sizeof(double) * (size_t)(n_constraints + sys->n_constraint_out + 1));
  int *mine = malloc(sizeof(int) * (size_t)(sys->n_constraint_out + 1));
  if (!sys->constraint_counts || !sys->constraint_displs || !sys->constraint_row || !sys->constraint_buffer || !mine) {
    free(mine);
    return sk_system_out_of_memory("the constraint rows", n_constraints);
  }
  for (int k = 0; k < sys->n_constraint_out; ++k) mine[k] = sys->solver_of[sys->constraint_out[k]] - (int)sys->n_nodal;
  MPI_Gather(&sys->n_constraint_out, 1, MPI_INT, sys->constraint_counts, 1, MPI_INT, last, sys->comm);
  int total = 0;
  for (int r = 0; r < sys->n_ranks; ++r) {
    sys->constraint_displs[r] = total;
    total += sys->constraint_counts[r];
  }
  sys->constraint_displs[sys->n_ranks] = total;
  MPI_Gatherv(mine, sys->n_constraint_out, MPI_INT, sys->constraint_row, sys->constraint_counts,
              sys->constraint_displs, MPI_INT, last, sys->comm);
  free(mine);
  if (sys->rank == last && total != n_constraints)
    return sk_error_set(SK_ERR_INTERNAL, "the owners of the %lld kept extra unknowns hold %d of them",
                        (long long)n_constraints, total);
  return SK_OK;
}

sk_status sk_system_to_rows(sk_system *sys, const double *local, double *rows) {
  for (int64_t k = 0; k < sys->n_owned_dofs; ++k) rows[k] = local[sys->owned_dofs[k]];
  const int last = sys->n_ranks - 1;
  for (int k = 0; k < sys->n_constraint_out; ++k) sys->constraint_buffer[k] = local[sys->constraint_out[k]];
  double *gathered = sys->constraint_buffer + sys->n_constraint_out;
  MPI_Gatherv(sys->constraint_buffer, sys->n_constraint_out, MPI_DOUBLE, gathered, sys->constraint_counts,
              sys->constraint_displs, MPI_DOUBLE, last, sys->comm);
  if (sys->rank == last)
    for (int k = 0; k < sys->constraint_displs[sys->n_ranks]; ++k) rows[sys->n_owned_dofs + sys->constraint_row[k]] = gathered[k];
  return SK_OK;
}

sk_status sk_system_from_rows(sk_system *sys, const double *rows, double *local) {
  for (int64_t k = 0; k < sys->n_owned_dofs; ++k) local[sys->owned_dofs[k]] = rows[k];
  const int last = sys->n_ranks - 1;
  double *gathered = sys->constraint_buffer + sys->n_constraint_out;
  if (sys->rank == last)
    for (int k = 0; k < sys->constraint_displs[sys->n_ranks]; ++k) gathered[k] = rows[sys->n_owned_dofs + sys->constraint_row[k]];
  MPI_Scatterv(gathered, sys->constraint_counts, sys->constraint_displs, MPI_DOUBLE, sys->constraint_buffer,
               sys->n_constraint_out, MPI_DOUBLE, last, sys->comm);
  for (int k = 0; k < sys->n_constraint_out; ++k) local[sys->constraint_out[k]] = sys->constraint_buffer[k];
  return SK_OK;
}

sk_status sk_system_layout_unknowns(sk_system *sys, int again, int *changed) {
  sk_model *m = sys->model;
  int64_t n = m->n_dofs, abi = m->n_dofs_global;
  sys->n_pairs = 0;
  int n_live; /* a sleeping pair keeps the layout of an apart pair: no extra unknowns (sk_term_plugin_set_far) */
  sk_term *const *live = sk_system_live_terms(sys, &n_live);
  /* again: the extras keep their values, kept by j while the held ones are laid out anew */
  for (int k = 0; again && k < n_live; ++k) sk_system_extra_block(sys, live[k]);
  int moved = 0;
  for (int k = 0; k < n_live; ++k) {
    sk_term *term = live[k];
    term->extra_offset = abi;
    term->extra_local = n;
    sk_term_no_extras(term);
    if (term->ops->layout) {
      sk_status status = term->ops->layout(term, sys);
      if (status != SK_OK) return sk_error_prefix(status, "%s: layout: ", term->name);
      if (term->n_extra < 0) return sk_error_set(SK_ERR_PLUGIN, "%s: negative layout", term->name);
    }
    SK_TRY(refuse_beyond_memory(sys, n + term->n_extra)); /* before the held list: at most n_extra */
    SK_TRY(hold_extras(term, &moved));
    n += term->n_held;
    abi += term->n_extra;
  }
  if (again && abi != sys->n_abi)
    return sk_error_set(SK_ERR_PLUGIN, "the number of extra unknowns changed from %lld to %lld within a step "
                        "attempt (a layout after converged() may change only what is eliminated)",
                        (long long)(sys->n_abi - m->n_dofs_global), (long long)(abi - m->n_dofs_global));
  /* the bridge and NOX count unknowns in int */
  if (abi > INT_MAX - 16)
    return sk_error_set(SK_ERR_INPUT, "%lld unknowns exceed the %d the linear solvers can number", (long long)abi,
                        INT_MAX - 16);
  /* what the numbering was, to tell whether it changed */
  const int64_t old_n = sys->n, old_kept = sys->n_kept;
  int *old_solver = NULL;
  unsigned char *old_role = NULL;
  if (old_n > 0) {
    old_solver = malloc(sizeof(int) * (size_t)old_n);
    old_role = malloc((size_t)old_n);
    if (!old_solver || !old_role) {
      free(old_solver);
      free(old_role);
      return sk_system_out_of_memory("the unknowns' numbering", old_n);
    }
    memcpy(old_solver, sys->solver_of, sizeof(int) * (size_t)old_n);
    memcpy(old_role, sys->role, (size_t)old_n);
  }
  sk_status status = sk_system_ensure_capacity(sys, n);
  if (status != SK_OK) {
    free(old_solver);
    free(old_role);
    return status;
  }
  sys->n = n;
  sys->n_abi = abi;
  for (int64_t i = 0; i < m->n_dofs; ++i) sys->role[i] = sys->node_role[i / m->dim];
  int64_t kept = sys->n_nodal;
  for (int k = 0; k < n_live; ++k) {
    sk_term *term = live[k];
    /* the rows of the kept extras count over all of them (every rank numbers them alike), held or not */
    for (int64_t j = 0, h = 0; j < term->n_extra; ++j) {
      const int eliminated = term->eliminated && term->eliminated[j];
      if (!again) term->extra_values[j] = term->initial ? term->initial[j] : 0.0;
      if (h == term->n_held || term->held[h] != j) {
        kept += !eliminated;
        continue;
      }
      const int64_t i = term->extra_local + h++;
      const int owner = term->extra_owner ? term->extra_owner[j] : 0;
      sys->role[i] = owner == sys->rank ? SK_NODE_OWNED : SK_NODE_GHOST;
      sys->solver_of[i] = eliminated ? -1 : (int)kept++;
      sys->x[i] = term->extra_values[j];
    }
  }
  sys->n_kept = kept;
  /* layout().eliminated must describe the whole layout on every rank */
  int64_t counts[2] = {kept, -kept};
  MPI_Allreduce(MPI_IN_PLACE, counts, 2, MPI_INT64_T, MPI_MAX, sys->comm);
  if (counts[0] != -counts[1]) {
    free(old_solver);
    free(old_role);
    return sk_error_set(SK_ERR_PLUGIN, "the eliminated unknowns differ between ranks (layout().eliminated must "
                        "describe the whole layout on every rank)");
  }
  /* the dofs' rows: this rank's owned ones in order, the ghosts' from their owners */
  for (int64_t i = 0; i < m->n_dofs; ++i) sys->solver_of[i] = -1;
  for (int64_t k = 0; k < sys->n_owned_dofs; ++k) sys->solver_of[sys->owned_dofs[k]] = (int)(sys->first_row + k);
  int roles_changed = moved || old_n != n || (old_role && memcmp(old_role, sys->role, (size_t)n) != 0);
  MPI_Allreduce(MPI_IN_PLACE, &roles_changed, 1, MPI_INT, MPI_MAX, sys->comm);
  if (roles_changed || !sys->owned_known) {
    double *rows = sys->q_work;
    for (int64_t i = 0; i < m->n_dofs; ++i) rows[i] = sys->solver_of[i];
    sk_exchange_forward(&sys->ghost_dofs, rows);
    for (int64_t i = 0; i < m->n_dofs; ++i)
      if (sys->role[i] == SK_NODE_GHOST) sys->solver_of[i] = (int)rows[i];
    SK_TRY(plan_extras(sys));
    sys->owned_known = 1;
  } else {
    for (int64_t i = 0; i < m->n_dofs; ++i)
      if (sys->role[i] == SK_NODE_GHOST) sys->solver_of[i] = old_solver[i];
  }
  sys->n_owned = 0;
  for (int64_t k = 0; k < sys->n_owned_dofs; ++k) sys->owned[sys->n_owned++] = sys->owned_dofs[k];
  for (int64_t i = m->n_dofs; i < n; ++i)
    if (sys->role[i] == SK_NODE_OWNED) sys->owned[sys->n_owned++] = (int)i;
  status = plan_constraints(sys);
  sys->n_rows_owned = (int)(sys->n_owned_dofs + (sys->rank == sys->n_ranks - 1 ? sys->n_kept - sys->n_nodal : 0));
  if (status == SK_OK && !again && n > m->n_dofs) {
    /* each rank gives the starting values of its owned entities (zero elsewhere): the sum is the whole layout */
    sk_exchange_reverse(&sys->ghost_extras, sys->x);
    sk_exchange_forward(&sys->ghost_extras, sys->x);
  }
  *changed = roles_changed || old_kept != kept || /* roles_changed includes held extras that moved */
             (old_solver && memcmp(old_solver + m->n_dofs, sys->solver_of + m->n_dofs,
                                   sizeof(int) * (size_t)(n - m->n_dofs)) != 0);
  MPI_Allreduce(MPI_IN_PLACE, changed, 1, MPI_INT, MPI_MAX, sys->comm);
  free(old_solver);
  free(old_role);
  if (sys->unknowns_max < abi) sys->unknowns_max = abi;
  return status;
}
