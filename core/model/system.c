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

#include "assemble.h"
#include "stickslip/condense.h"

static double now_seconds(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static sk_status out_of_memory(const char *what, int64_t count) {
  return sk_error_set(SK_ERR_NOMEM, "out of memory for %s (%lld entries)", what, (long long)count);
}

static int compare_int(const void *a, const void *b) {
  int x = *(const int *)a, y = *(const int *)b;
  return (x > y) - (x < y);
}

static int compare_i64(const void *a, const void *b) {
  int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
  return (x > y) - (x < y);
}

sk_status sk_system_collective(const sk_system *sys, sk_status local) {
  int code = (int)local, worst = 0;
  MPI_Allreduce(&code, &worst, 1, MPI_INT, MPI_MAX, sys->comm);
  if (worst != SK_OK && local == SK_OK) sk_error_set((sk_status)worst, "failure on another rank");
  return (sk_status)worst;
}

static int is_plugin(const sk_term *term) { return strcmp(term->ops->kind, "plugin") == 0; }

/* ---- the plugins' sink ------------------------------------------------------------------------------------------ */

static void sink_fail(sk_system_sink *sink, const char *fmt, long long a, long long b) {
  if (sink->failed) return;
  sink->failed = 1;
  snprintf(sink->message, sizeof sink->message, fmt, a, b);
}

static void sink_add_vector(sk_sink *abi, int n, const int64_t *rows, const double *values) {
  sk_system *sys = ((sk_system_sink *)abi)->sys;
  for (int k = 0; k < n; ++k)
    if (rows[k] >= 0 && rows[k] < sys->n) sys->F_local[rows[k]] += values[k];
}

static void sink_add_rhs(sk_sink *abi, int n, const int64_t *rows, const double *values) {
  sk_system *sys = ((sk_system_sink *)abi)->sys;
  for (int k = 0; k < n; ++k)
    if (rows[k] >= 0 && rows[k] < sys->n) sys->rhs_local[rows[k]] += values[k];
}

int64_t sk_system_position(const sk_system *sys, int row, int col) {
  const int *begin = sys->cols + sys->row_ptr[row];
  const size_t len = (size_t)(sys->row_ptr[row + 1] - sys->row_ptr[row]);
  const int *hit = bsearch(&col, begin, len, sizeof(int), compare_int);
  return hit ? sys->row_ptr[row] + (hit - begin) : -1;
}

static void sink_add_matrix(sk_sink *abi, int nr, const int64_t *rows, int nc, const int64_t *cols,
                            const double *values) {
  sk_system_sink *sink = (sk_system_sink *)abi;
  sk_system *sys = sink->sys;
  for (int i = 0; i < nr; ++i) {
    if (rows[i] < 0 || rows[i] >= sys->n) continue;
    const int r = sys->kept[rows[i]];
    if (r < 0) continue;
    for (int j = 0; j < nc; ++j) {
      if (cols[j] < 0 || cols[j] >= sys->n) continue;
      const int c = sys->kept[cols[j]];
      const double v = values[i * nc + j];
      if (c < 0 || v == 0.0) continue;
      if (!sys->row_local[r]) {
        sink_fail(sink, "Jacobian entry in row %lld (column %lld) outside this rank's views", (long long)rows[i],
                  (long long)cols[j]);
        continue;
      }
      const int64_t p = sk_system_position(sys, r, c);
      if (p < 0) {
        sink_fail(sink, "Jacobian entry (%lld, %lld) outside the pattern declared by pattern()", (long long)rows[i],
                  (long long)cols[j]);
        continue;
      }
      sys->values[p] += v;
    }
  }
}

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
  sys->t_n = model->time.t_start;
  sys->sink.abi = (sk_sink){SK_TABLE_HEADER(sk_sink), .add_vector = sink_add_vector, .add_matrix = sink_add_matrix,
                            .add_rhs = sink_add_rhs};
  sys->sink.sys = sys;
  const size_t nd = (size_t)(model->n_dofs > 0 ? model->n_dofs : 1);
  const size_t nb = (size_t)(model->n_bodies > 0 ? model->n_bodies : 1);
  sys->u_n = calloc(nd, sizeof(double));
  sys->v_n = calloc(nd, sizeof(double));
  sys->v = calloc(nd, sizeof(double));
  sys->q_n = calloc(nd, sizeof(double));
  sys->q = calloc(nd, sizeof(double));
  sys->body_plugin = calloc(nb, sizeof *sys->body_plugin);
  sys->claimed = calloc(nb, 1);
  sys->elem_pos_offset = calloc((size_t)model->n_elements + 1, sizeof(int64_t));
  if (!sys->u_n || !sys->v_n || !sys->v || !sys->q_n || !sys->q || !sys->body_plugin || !sys->claimed ||
      !sys->elem_pos_offset) {
    sk_system_destroy(sys);
    return out_of_memory("the state vectors", model->n_dofs);
  }
  for (int k = 0; k < model->n_dofs; ++k) sys->q_n[k] = sys->q[k] = model->X[k];
  sk_status status = sk_linsys_create(model->comm, &solver->linear, &sys->linsys);
  if (status == SK_OK) status = create_terms(sys);
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

/* Numbers the attempt's unknowns from the terms' layouts; *changed when the kept numbering differs from before. */
static sk_status layout_unknowns(sk_system *sys, int *changed) {
  sk_model *m = sys->model;
  int64_t n = m->n_dofs;
  sys->n_pairs = 0;
  for (int k = 0; k < sys->n_terms; ++k) {
    sk_term *term = sys->terms[k];
    term->extra_offset = n;
    term->n_extra = 0;
    term->initial = NULL;
    term->eliminated = NULL;
    term->recover_needs_jdx = 0;
    if (!term->ops->layout) continue;
    sk_status status = term->ops->layout(term, sys);
    if (status != SK_OK) return sk_error_prefix(status, "%s: layout: ", term->name);
    if (term->n_extra < 0) return sk_error_set(SK_ERR_PLUGIN, "%s: negative layout", term->name);
    n += term->n_extra;
  }
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
      sys->x[i] = term->initial ? term->initial[j] : 0.0;
    }
  }
  sys->n_kept = kept;
  if (sys->n_ranks > 1 && n > m->n_dofs) {
    /* each rank gives the starting values of its owned entities (zero elsewhere): the sum is the whole layout */
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

/* ---- the sparsity pattern ---------------------------------------------------------------------------------------- */

sk_status sk_system_declare(sk_system *sys, int nr, const int64_t *rows, int nc, const int64_t *cols) {
  const int64_t need = sys->n_declared + (int64_t)nr * nc;
  if (need > sys->cap_declared) {
    const int64_t cap = 2 * need + 1024;
    int64_t *grown = realloc(sys->declared, sizeof(int64_t) * (size_t)cap);
    if (!grown) return out_of_memory("the declared pattern", cap);
    sys->declared = grown;
    sys->cap_declared = cap;
  }
  for (int i = 0; i < nr; ++i) {
    if (rows[i] < 0 || rows[i] >= sys->n || sys->kept[rows[i]] < 0) continue;
    for (int j = 0; j < nc; ++j) {
      if (cols[j] < 0 || cols[j] >= sys->n || sys->kept[cols[j]] < 0) continue;
      sys->declared[sys->n_declared++] = (int64_t)sys->kept[rows[i]] * sys->n_kept + sys->kept[cols[j]];
    }
  }
  return SK_OK;
}

/* The CSR pattern: the node graph of the bulk elements expanded per dof, the extra keys, the diagonal. */
static sk_status build_pattern(sk_system *sys) {
  sk_model *m = sys->model;
  const int dim = m->dim;
  const int64_t nk = sys->n_kept;
  free(sys->row_ptr);
  free(sys->cols);
  sys->cols = NULL;
  sys->row_ptr = calloc((size_t)nk + 1, sizeof(int64_t));
  int64_t *count = calloc((size_t)nk + 1, sizeof(int64_t));
  if (!sys->row_ptr || !count) {
    free(count);
    return out_of_memory("the sparsity pattern", nk);
  }
  const int64_t *key = sys->extra_keys;
  const int64_t n_keys = sys->n_extra_keys;
  int64_t longest = 1;
  for (int64_t r = 0; r < nk; ++r) count[r] = 1;
  for (int64_t r = 0; r < m->n_dofs; ++r) {
    const int64_t a = r / dim;
    count[r] += (m->mass_row_ptr[a + 1] - m->mass_row_ptr[a]) * dim;
  }
  for (int64_t k = 0; k < n_keys; ++k) count[key[k] / nk]++;
  for (int64_t r = 0; r < nk; ++r) {
    sys->row_ptr[r + 1] = sys->row_ptr[r] + count[r];
    if (count[r] > longest) longest = count[r];
  }
  sys->cols = malloc(sizeof(int) * (size_t)(sys->row_ptr[nk] > 0 ? sys->row_ptr[nk] : 1));
  int *row_cols = malloc(sizeof(int) * (size_t)longest);
  if (!sys->cols || !row_cols) {
    free(count);
    free(row_cols);
    return out_of_memory("the sparsity pattern", sys->row_ptr[nk]);
  }
  int64_t used = 0, k = 0;
  for (int64_t r = 0; r < nk; ++r) {
    int64_t len = 0;
    if (r < m->n_dofs) {
      const int64_t a = r / dim;
      for (int64_t j = m->mass_row_ptr[a]; j < m->mass_row_ptr[a + 1]; ++j)
        for (int i = 0; i < dim; ++i) row_cols[len++] = m->mass_cols[j] * dim + i;
    }
    row_cols[len++] = (int)r;
    while (k < n_keys && key[k] / nk == r) row_cols[len++] = (int)(key[k++] % nk);
    qsort(row_cols, (size_t)len, sizeof(int), compare_int);
    for (int64_t j = 0; j < len; ++j)
      if (j == 0 || row_cols[j] != row_cols[j - 1]) sys->cols[used++] = row_cols[j];
    sys->row_ptr[r + 1] = used;
  }
  free(row_cols);
  free(count);

  /* Pure displacement systems get MueLu's elasticity setup (whole-node aggregates, rigid-body-mode nullspace);
   * systems with plugin unknowns are saddle points, for which the direct solver is the measured choice. */
  const int displacement_only = nk == m->n_dofs;
  SK_TRY(sk_linsys_set_block_size(sys->linsys, displacement_only ? dim : 1));
  if (displacement_only) SK_TRY(sk_linsys_set_coordinates(sys->linsys, m->n_nodes, dim, m->X));
  SK_TRY(sk_linsys_set_pattern(sys->linsys, (int)nk, sys->row_ptr, sys->cols, sys->n_local_rows, sys->local_rows));
  sys->values = sk_linsys_values(sys->linsys);

  /* positions of each own element's entries */
  int64_t total = 0;
  int dofs[SK_MAX_NEN * 3];
  for (int e = 0; e < m->n_elements; ++e) {
    sys->elem_pos_offset[e] = total;
    if (m->element_part[e] == m->rank) {
      const int nd = sk_element_dofs(m, e, dofs, NULL, NULL);
      total += (int64_t)nd * nd;
    }
  }
  free(sys->elem_pos);
  sys->elem_pos = malloc(sizeof(int64_t) * (size_t)(total > 0 ? total : 1));
  if (!sys->elem_pos) return out_of_memory("the element positions", total);
  for (int e = 0; e < m->n_elements; ++e) {
    if (m->element_part[e] != m->rank) continue;
    const int nd = sk_element_dofs(m, e, dofs, NULL, NULL);
    int64_t *pos = sys->elem_pos + sys->elem_pos_offset[e];
    for (int i = 0; i < nd; ++i)
      for (int j = 0; j < nd; ++j) pos[i * nd + j] = sk_system_position(sys, dofs[i], dofs[j]);
  }
  sys->pattern_n = nk;
  return SK_OK;
}

/* Merges keys of all ranks into extra_keys (collective; sorted, unique). */
static sk_status merge_keys(sk_system *sys, const int64_t *mine, int64_t n_mine) {
  if (n_mine > INT_MAX) return sk_error_set(SK_ERR_INPUT, "%lld declared pattern entries on one rank", (long long)n_mine);
  int count = (int)n_mine;
  int *counts = calloc((size_t)sys->n_ranks, sizeof(int)), *displs = calloc((size_t)sys->n_ranks, sizeof(int));
  if (!counts || !displs) {
    free(counts);
    free(displs);
    return out_of_memory("the pattern exchange", sys->n_ranks);
  }
  MPI_Allgather(&count, 1, MPI_INT, counts, 1, MPI_INT, sys->comm);
  int64_t total = 0;
  for (int r = 0; r < sys->n_ranks; ++r) {
    displs[r] = (int)total;
    total += counts[r];
  }
  int64_t *merged = realloc(sys->extra_keys, sizeof(int64_t) * (size_t)(sys->n_extra_keys + total + 1));
  if (!merged || total > INT_MAX) {
    free(counts);
    free(displs);
    return out_of_memory("the pattern exchange", total);
  }
  sys->extra_keys = merged;
  MPI_Allgatherv(mine, count, MPI_INT64_T, merged + sys->n_extra_keys, counts, displs, MPI_INT64_T, sys->comm);
  free(counts);
  free(displs);
  const int64_t n = sys->n_extra_keys + total;
  qsort(merged, (size_t)n, sizeof(int64_t), compare_i64);
  int64_t unique = 0;
  for (int64_t k = 0; k < n; ++k)
    if (k == 0 || merged[k] != merged[unique - 1]) merged[unique++] = merged[k];
  sys->n_extra_keys = unique;
  return SK_OK;
}

/* The attempt's pattern: every term declares its couplings and rows; declared entries the current pattern lacks
 * (on any rank) grow it once, before Newton. */
static sk_status settle_pattern(sk_system *sys, int layout_changed) {
  const int64_t nk = sys->n_kept;
  sys->n_declared = 0;
  free(sys->row_local);
  sys->row_local = calloc((size_t)nk + 1, 1);
  if (!sys->row_local) return out_of_memory("the rows of this rank", nk);
  for (int64_t r = sys->model->n_dofs; r < nk; ++r) sys->row_local[r] = 1; /* extras: any rank may own an entity */
  sk_status status = SK_OK;
  for (int k = 0; k < sys->n_terms && status == SK_OK; ++k) {
    sk_term *term = sys->terms[k];
    if (!term->ops->pattern) continue;
    status = term->ops->pattern(term, sys, sys->row_local);
    if (status != SK_OK) sk_error_prefix(status, "%s: pattern: ", term->name);
  }
  SK_TRY(sk_system_collective(sys, status));
  int n_rows = 0;
  for (int64_t r = 0; r < nk; ++r) n_rows += sys->row_local[r];
  int *rows = malloc(sizeof(int) * (size_t)(n_rows > 0 ? n_rows : 1));
  if (!rows) return out_of_memory("the rows of this rank", n_rows);
  for (int64_t r = 0, i = 0; r < nk; ++r)
    if (sys->row_local[r]) rows[i++] = (int)r;
  const int rows_changed = n_rows != sys->n_local_rows || !sys->local_rows ||
                           memcmp(rows, sys->local_rows, sizeof(int) * (size_t)n_rows) != 0;
  free(sys->local_rows);
  sys->local_rows = rows;
  sys->n_local_rows = n_rows;

  /* declared keys the pattern lacks */
  int64_t n_missing = 0;
  if (layout_changed || sys->pattern_n != nk) {
    sys->n_extra_keys = 0; /* the keys were in the old numbering */
    n_missing = sys->n_declared;
  } else {
    for (int64_t k = 0; k < sys->n_declared; ++k) {
      const int64_t key = sys->declared[k];
      if (sk_system_position(sys, (int)(key / nk), (int)(key % nk)) < 0) sys->declared[n_missing++] = key;
    }
  }
  qsort(sys->declared, (size_t)n_missing, sizeof(int64_t), compare_i64);
  int64_t unique = 0;
  for (int64_t k = 0; k < n_missing; ++k)
    if (k == 0 || sys->declared[k] != sys->declared[unique - 1]) sys->declared[unique++] = sys->declared[k];
  int any = unique > 0 || rows_changed || layout_changed || sys->pattern_n != nk, anywhere = 0;
  MPI_Allreduce(&any, &anywhere, 1, MPI_INT, MPI_MAX, sys->comm);
  if (!anywhere) return SK_OK;
  SK_TRY(merge_keys(sys, sys->declared, unique));
  return build_pattern(sys);
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

sk_status sk_system_begin(sk_system *sys, double dt, int64_t step) {
  sk_model *m = sys->model;
  sys->dt = dt;
  sys->t = sys->t_n + dt;
  sys->step = step;
  sys->set_valid = 0;
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
  int changed = 0;
  status = sk_system_collective(sys, layout_unknowns(sys, &changed));
  if (status != SK_OK) return status;
  sys->x_version++; /* the extras got their starting values */
  SK_TRY(settle_pattern(sys, changed));
  sys->condensing = 0;
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
    if (!sys->condenser) SK_TRY(sk_condenser_create(sys->comm, &sys->solver->linear, &sys->condenser));
    SK_TRY(sk_condenser_set_pairs(sys->condenser, sys->linsys, sys->n_pairs, sys->pair_z, sys->pair_row,
                                  sys->pair_block));
    sys->condensing = 1;
  }
  const int64_t solved = sys->condensing ? sk_condenser_size(sys->condenser) : sys->n_kept;
  if (sys->linear_size_max < solved) sys->linear_size_max = solved;
  return SK_OK;
}

static sk_status cb_residual(void *ctx, const double *x, double *F) {
  sk_system *sys = ctx;
  set_iterate(sys, x);
  sk_status status = update_active_set(sys);
  memset(sys->F_local, 0, sizeof(double) * (size_t)sys->n);
  for (int k = 0; k < sys->n_terms && status == SK_OK; ++k) {
    sk_term *term = sys->terms[k];
    if (!term->ops->residual) continue;
    const double t0 = now_seconds();
    status = term->ops->residual(term, sys);
    if (status != SK_OK) sk_error_prefix(status, "%s: ", term->name);
    *(is_plugin(term) ? &sys->t_contact : &sys->t_assembly) += now_seconds() - t0;
  }
  status = sk_system_collective(sys, status);
  if (status != SK_OK) return status;
  MPI_Allreduce(sys->F_local, F, (int)sys->n, MPI_DOUBLE, MPI_SUM, sys->comm);
  for (int k = 0; k < sys->n_terms && status == SK_OK; ++k)
    if (sys->terms[k]->ops->finish_residual) status = sys->terms[k]->ops->finish_residual(sys->terms[k], sys, F);
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
  status = sk_system_collective(sys, status);
  if (status != SK_OK) return status;
  MPI_Allreduce(sys->rhs_local, sys->rhs, (int)sys->n, MPI_DOUBLE, MPI_SUM, sys->comm);
  for (int k = 0; k < sys->n_terms; ++k)
    if (sys->terms[k]->ops->finish_rhs) sys->terms[k]->ops->finish_rhs(sys->terms[k], sys, sys->rhs);
  const double t0 = now_seconds();
  status = sys->condensing ? sk_condenser_assemble(sys->condenser, sys->linsys) : sk_linsys_assemble(sys->linsys);
  sys->t_assembly += now_seconds() - t0;
  return status;
}

/* The kept system J_c dy = b; with stickslip.condense pairs through the condenser (reduced solve + recovery). */
static sk_status linear_solve(sk_system *sys, const double *b, double *y) {
  sk_linear_report report;
  const double t0 = now_seconds();
  sk_status status = sys->condensing ? sk_condenser_solve(sys->condenser, sys->linsys, b, y, &report)
                                     : sk_linsys_solve(sys->linsys, b, y, &report);
  sys->t_solve += now_seconds() - t0;
  sys->linear_solves++;
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
  status = sk_system_collective(sys, status);
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
  sk_linear_report report;
  const double t0 = now_seconds();
  sk_status status = sys->condensing ? sk_condenser_solve_again(sys->condenser, sys->linsys, sys->b, sys->y, &report)
                                     : sk_linsys_solve_again(sys->linsys, sys->b, sys->y, &report);
  sys->t_solve += now_seconds() - t0;
  sys->linear_solves++;
  SK_TRY(status);
  for (int64_t i = 0; i < sys->n; ++i) y[i] = sys->kept[i] >= 0 ? sys->y[sys->kept[i]] : 0.0;
  return SK_OK;
}

static sk_status cb_after_iteration(void *ctx, int iteration, const double *x, double residual_norm) {
  sk_system *sys = ctx;
  (void)x;
  if (sys->verbose && sys->rank == 0)
    fprintf(stderr, "  step %lld newton %d |F| = %.3e\n", (long long)sys->step, iteration, residual_norm);
  return SK_OK;
}

sk_status sk_system_solve(sk_system *sys) {
  const sk_newton_callbacks callbacks = {.ctx = sys,
                                         .residual = cb_residual,
                                         .jacobian = cb_jacobian,
                                         .solve = cb_solve,
                                         .after_iteration = cb_after_iteration};
  memset(&sys->newton, 0, sizeof sys->newton);
  const int max_loops = sys->solver->max_active_set_loops;
  for (int loop = 0;; ++loop) {
    sk_newton_report report;
    sk_status status = sk_newton_solve(sys->comm, &sys->solver->newton, &callbacks, (int)sys->n, sys->x, &report);
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

/* ---- results ----------------------------------------------------------------------------------------------------- */

sk_status sk_system_contact_totals(sk_system *sys, int initial, sk_contact_totals *totals) {
  double *obstacle_force = totals->obstacle_force;
  memset(totals, 0, sizeof *totals);
  totals->obstacle_force = obstacle_force;
  double sums[10] = {0};
  sk_status status = SK_OK;
  int n_obstacles = 0;
  for (int k = 0; k < sys->n_terms && status == SK_OK; ++k) {
    sk_term *term = sys->terms[k];
    if (!term->ops->report) continue;
    sk_contact_report r = {.struct_size = sizeof r};
    status = term->ops->report(term, sys, initial, &r);
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
    if (obstacle_force && sk_term_plugin_has_obstacle(term)) {
      for (int i = 0; i < 3; ++i) obstacle_force[3 * n_obstacles + i] = -r.force[i];
      ++n_obstacles;
    }
  }
  SK_TRY(sk_system_collective(sys, status));
  MPI_Allreduce(MPI_IN_PLACE, sums, 10, MPI_DOUBLE, MPI_SUM, sys->comm);
  if (obstacle_force && n_obstacles > 0)
    MPI_Allreduce(MPI_IN_PLACE, obstacle_force, 3 * n_obstacles, MPI_DOUBLE, MPI_SUM, sys->comm);
  double constraint = totals->constraint;
  MPI_Allreduce(&constraint, &totals->constraint, 1, MPI_DOUBLE, MPI_MAX, sys->comm);
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
  for (int k = 0; k < sys->n_terms && status == SK_OK; ++k) {
    sk_term *term = sys->terms[k];
    if (!term->ops->points) continue;
    points_relay relay = {callback, ctx, sk_term_plugin_pair(term)};
    status = term->ops->points(term, sys, initial, relay_point, &relay);
    if (status != SK_OK) sk_error_prefix(status, "%s: points: ", term->name);
  }
  return status;
}
