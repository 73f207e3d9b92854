/* The time-stepping loop: each step is one nonlinear system F(x) = 0 over x = [displacements | plugin unknowns],
 * solved by NOX through the bridge; the driver-side callbacks assemble bulk and contact parts, apply Dirichlet
 * conditions and run the pair's condensation strategy inside the linear solve. Steps that fail are cut in half. */
#define _GNU_SOURCE
#include "stickslip/run.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "../model/assemble.h"
#include "stickslip/output.h"
#include "stickslip/plugins.h"

static double now_seconds(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void *xcalloc(size_t n, size_t size) {
  void *p = calloc(n ? n : 1, size);
  if (!p) {
    fprintf(stderr, "stickslip: out of memory (%zu bytes)\n", n * size);
    abort();
  }
  return p;
}

static int compare_i64(const void *a, const void *b) {
  int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
  return (x > y) - (x < y);
}

static int compare_int(const void *a, const void *b) {
  int x = *(const int *)a, y = *(const int *)b;
  return (x > y) - (x < y);
}

/* ---- the stepper ------------------------------------------------------------------------------------------------ */

typedef struct {
  int row, col;
  double value;
} coo_entry;

typedef struct {
  sk_scene *scene;
  sk_model *model;
  const sk_run_options *options;
  sk_run_summary *summary;

  /* unknowns of the current step */
  int n;                  /* n_dofs + extra unknowns */
  int n_kept;             /* unknowns of the linear system */
  int *kept;              /* n entries: kept index or -1 (eliminated) */
  int *full_of_kept;      /* n_kept entries */
  int capacity;           /* allocated length of the n-sized arrays */

  /* state */
  double t_n, t, dt;
  int step;
  double *u_n, *v_n, *v;  /* n_dofs */
  double *q_n, *q;        /* positions X + u */
  double *x;              /* current iterate (n) */
  double *extra_committed;/* plugin unknowns at the last converged step (n - n_dofs), for reporting */
  double *F_local, *rhs_local, *rhs, *b, *y, *dx_elim;
  double *reactions;      /* residual at Dirichlet dofs before replacement: the support reactions */

  /* Dirichlet */
  unsigned char *is_fixed;/* n_dofs */
  double *fixed_value;    /* n_dofs, at t */

  /* sparsity */
  int *node_adj_ptr, *node_adj;  /* node graph of the bulk elements */
  int64_t *extra_keys;    /* sorted unique (row * n_kept + col) of plugin entries outside the bulk graph */
  int n_extra_keys, cap_extra_keys;
  int64_t *row_ptr;
  int *cols;
  int *local_rows, n_local_rows;
  int pattern_n;          /* n_kept the pattern was built for (-1: none) */
  int *elem_pos_offset;   /* per element offset into elem_pos (own elements only) */
  int *elem_pos;
  int elements_own;
  sk_linear_system *sys;
  double *values;

  /* contact sink */
  coo_entry *coo;
  int n_coo, cap_coo;
  int64_t *missing;
  int n_missing, cap_missing;

  /* last Newton report of a step */
  sk_newton_report newton;
  double t_assembly, t_contact, t_solve;
  int linear_solves;
} stepper;

/* ---- unknown layout --------------------------------------------------------------------------------------------- */

/* The n-sized work arrays (n = all unknowns of a step); x keeps its values when it grows. */
static void free_unknown_arrays(stepper *s) {
  double **arrays[] = {&s->F_local, &s->rhs_local, &s->rhs, &s->b, &s->y, &s->dx_elim};
  for (size_t k = 0; k < sizeof arrays / sizeof arrays[0]; ++k) {
    free(*arrays[k]);
    *arrays[k] = NULL;
  }
  free(s->kept);
  free(s->full_of_kept);
}

static void ensure_capacity(stepper *s, int n) {
  if (n <= s->capacity) return;
  int cap = n + n / 4 + 16;
  free_unknown_arrays(s);
  double *x = xcalloc((size_t)cap, sizeof(double));
  if (s->x) memcpy(x, s->x, sizeof(double) * (size_t)s->capacity);
  free(s->x);
  s->x = x;
  s->kept = xcalloc((size_t)cap, sizeof(int));
  s->full_of_kept = xcalloc((size_t)cap, sizeof(int));
  s->F_local = xcalloc((size_t)cap, sizeof(double));
  s->rhs_local = xcalloc((size_t)cap, sizeof(double));
  s->rhs = xcalloc((size_t)cap, sizeof(double));
  s->b = xcalloc((size_t)cap, sizeof(double));
  s->y = xcalloc((size_t)cap, sizeof(double));
  s->dx_elim = xcalloc((size_t)cap, sizeof(double));
  s->capacity = cap;
}

static sk_state pair_state(const stepper *s, const sk_contact_pair *pair) {
  sk_state state = {
      .scheme = s->model->time.scheme,
      .t_n = s->t_n,
      .t = s->t,
      .dt = s->dt,
      .step = s->step,
      .q_n = s->q_n,
      .q = s->q,
      .v_n = s->model->time.scheme == SK_SCHEME_QUASISTATIC ? NULL : s->v_n,
      .extra = s->x + pair->extra_offset,
      .extra_offset = pair->extra_offset,
  };
  return state;
}

/* Lays out the step's unknowns from the plugins' layouts; returns 1 if the kept numbering changed. */
static sk_status layout_unknowns(stepper *s, int *changed) {
  sk_model *m = s->model;
  int n = m->n_dofs;
  for (int k = 0; k < m->n_pairs; ++k) {
    sk_contact_pair *pair = &m->pairs[k];
    pair->extra_offset = n;
    sk_state state = pair_state(s, pair);
    sk_status status = pair->plugin->layout(pair->instance, &state, &pair->layout);
    if (status != SK_OK) return sk_error_prefix(status, "contact pair '%s': layout: ", pair->name);
    if (pair->layout.n_extra < 0) return sk_error_set(SK_ERR_PLUGIN, "pair '%s': negative layout", pair->name);
    n += pair->layout.n_extra;
  }
  int old_n = s->n, old_kept = s->n_kept;
  int *old = NULL;
  if (old_n > 0) {
    old = xcalloc((size_t)old_n, sizeof(int));
    memcpy(old, s->kept, sizeof(int) * (size_t)old_n);
  }
  ensure_capacity(s, n);
  s->n = n;
  int kept = 0;
  for (int i = 0; i < m->n_dofs; ++i) {
    s->kept[i] = kept;
    s->full_of_kept[kept++] = i;
  }
  for (int k = 0; k < m->n_pairs; ++k) {
    sk_contact_pair *pair = &m->pairs[k];
    for (int j = 0; j < pair->layout.n_extra; ++j) {
      int i = pair->extra_offset + j;
      if (pair->layout.eliminated && pair->layout.eliminated[j]) {
        s->kept[i] = -1;
      } else {
        s->kept[i] = kept;
        s->full_of_kept[kept++] = i;
      }
      s->x[i] = pair->layout.initial ? pair->layout.initial[j] : 0.0;
    }
  }
  s->n_kept = kept;
  *changed = old_n != n || old_kept != kept || (old && memcmp(old, s->kept, sizeof(int) * (size_t)n) != 0);
  free(old);
  if (s->summary->unknowns_max < n) s->summary->unknowns_max = n;
  if (s->summary->linear_size_max < kept) s->summary->linear_size_max = kept;
  return SK_OK;
}

/* ---- sparsity pattern ------------------------------------------------------------------------------------------- */

static void build_node_graph(stepper *s) {
  sk_model *m = s->model;
  int nn = m->n_nodes;
  /* the mass matrix already holds the node graph of the bulk elements */
  s->node_adj_ptr = xcalloc((size_t)nn + 1, sizeof(int));
  for (int a = 0; a <= nn; ++a) s->node_adj_ptr[a] = (int)m->mass_row_ptr[a];
  s->node_adj = xcalloc((size_t)m->mass_row_ptr[nn], sizeof(int));
  memcpy(s->node_adj, m->mass_cols, sizeof(int) * (size_t)m->mass_row_ptr[nn]);
}

static int64_t find_position(const stepper *s, int row, int col) {
  const int *begin = s->cols + s->row_ptr[row];
  size_t len = (size_t)(s->row_ptr[row + 1] - s->row_ptr[row]);
  const int *hit = bsearch(&col, begin, len, sizeof(int), compare_int);
  return hit ? s->row_ptr[row] + (hit - begin) : -1;
}

static sk_status build_pattern(stepper *s) {
  sk_model *m = s->model;
  int dim = m->dim, nk = s->n_kept;
  free(s->row_ptr);
  free(s->cols);
  s->row_ptr = xcalloc((size_t)nk + 1, sizeof(int64_t));
  /* count: bulk columns + extra keys of the row + the diagonal */
  int64_t *key = s->extra_keys;
  int n_keys = s->n_extra_keys;
  int *count = xcalloc((size_t)nk, sizeof(int));
  for (int r = 0; r < nk; ++r) count[r] = 1;
  for (int r = 0; r < m->n_dofs; ++r) {
    int a = r / dim;
    count[r] += (s->node_adj_ptr[a + 1] - s->node_adj_ptr[a]) * dim;
  }
  for (int k = 0; k < n_keys; ++k) count[key[k] / nk]++;
  for (int r = 0; r < nk; ++r) s->row_ptr[r + 1] = s->row_ptr[r] + count[r];
  s->cols = xcalloc((size_t)s->row_ptr[nk], sizeof(int));
  int64_t used = 0;
  int k = 0;
  int *row_cols = xcalloc((size_t)nk > 0 ? 1 : 1, sizeof(int));
  int row_cap = 0;
  for (int r = 0; r < nk; ++r) {
    int len = 0;
    if (count[r] > row_cap) {
      free(row_cols);
      row_cap = count[r];
      row_cols = xcalloc((size_t)row_cap, sizeof(int));
    }
    if (r < m->n_dofs) {
      int a = r / dim;
      for (int j = s->node_adj_ptr[a]; j < s->node_adj_ptr[a + 1]; ++j)
        for (int i = 0; i < dim; ++i) row_cols[len++] = s->node_adj[j] * dim + i;
    }
    row_cols[len++] = r;
    while (k < n_keys && key[k] / nk == r) row_cols[len++] = (int)(key[k++] % nk);
    qsort(row_cols, (size_t)len, sizeof(int), compare_int);
    int64_t start = used;
    for (int j = 0; j < len; ++j)
      if (j == 0 || row_cols[j] != row_cols[j - 1]) s->cols[used++] = row_cols[j];
    s->row_ptr[r + 1] = used;
    (void)start;
  }
  free(row_cols);
  free(count);

  /* rows this rank writes: dofs of its elements, dofs of contact surface nodes, all plugin rows; Dirichlet rows
   * (written by rank 0 only) */
  unsigned char *touched = xcalloc((size_t)nk, 1);
  int dofs[SK_MAX_NEN * 3];
  for (int e = 0; e < m->n_elements; ++e) {
    if (m->element_part[e] != m->rank) continue;
    int nd = sk_element_dofs(m, e, dofs, NULL, NULL);
    for (int j = 0; j < nd; ++j) touched[dofs[j]] = 1;
  }
  for (int p = 0; p < m->n_pairs; ++p) {
    const sk_contact_pair *pair = &m->pairs[p];
    const sk_surface *surfaces[2] = {&pair->slave, pair->has_obstacle ? NULL : &pair->master};
    for (int sidx = 0; sidx < 2; ++sidx)
      if (surfaces[sidx])
        for (int j = 0; j < surfaces[sidx]->n_nodes; ++j)
          for (int i = 0; i < dim; ++i) touched[surfaces[sidx]->nodes[j] * dim + i] = 1;
  }
  for (int r = m->n_dofs; r < nk; ++r) touched[r] = 1;
  if (m->rank == 0)
    for (int r = 0; r < m->n_dofs; ++r)
      if (s->is_fixed[r]) touched[r] = 1;
  free(s->local_rows);
  s->local_rows = xcalloc((size_t)nk, sizeof(int));
  s->n_local_rows = 0;
  for (int r = 0; r < nk; ++r)
    if (touched[r]) s->local_rows[s->n_local_rows++] = r;
  free(touched);

  /* The displacements are the bridge's nodal block (whole-node aggregates, rigid-body-mode nullspace); plugin
   * unknowns after them are constraint rows, which its iterative solvers take through their Schur complement. */
  SK_TRY(sk_linsys_set_coordinates(s->sys, m->n_nodes, dim, m->X));
  SK_TRY(sk_linsys_set_pattern(s->sys, nk, s->row_ptr, s->cols, s->n_local_rows, s->local_rows));
  s->values = sk_linsys_values(s->sys);

  /* positions of each own element's entries */
  int64_t total = 0;
  for (int e = 0; e < m->n_elements; ++e) {
    s->elem_pos_offset[e] = (int)total;
    if (m->element_part[e] == m->rank) {
      int nd = sk_element_dofs(m, e, dofs, NULL, NULL);
      total += (int64_t)nd * nd;
    }
  }
  free(s->elem_pos);
  s->elem_pos = xcalloc((size_t)total, sizeof(int));
  for (int e = 0; e < m->n_elements; ++e) {
    if (m->element_part[e] != m->rank) continue;
    int nd = sk_element_dofs(m, e, dofs, NULL, NULL);
    int *pos = s->elem_pos + s->elem_pos_offset[e];
    for (int i = 0; i < nd; ++i)
      for (int j = 0; j < nd; ++j) pos[i * nd + j] = (int)find_position(s, dofs[i], dofs[j]);
  }
  s->pattern_n = nk;
  return SK_OK;
}

/* ---- sinks for plugins ------------------------------------------------------------------------------------------ */

static void sink_add_vector(sk_sink *sink, int n, const int *rows, const double *values) {
  stepper *s = sink->ctx;
  for (int k = 0; k < n; ++k)
    if (rows[k] >= 0 && rows[k] < s->n) s->F_local[rows[k]] += values[k];
}

static void sink_add_rhs(sk_sink *sink, int n, const int *rows, const double *values) {
  stepper *s = sink->ctx;
  for (int k = 0; k < n; ++k)
    if (rows[k] >= 0 && rows[k] < s->n) s->rhs_local[rows[k]] += values[k];
}

static void sink_add_matrix(sk_sink *sink, int nr, const int *rows, int nc, const int *cols, const double *values) {
  stepper *s = sink->ctx;
  for (int i = 0; i < nr; ++i) {
    if (rows[i] < 0 || rows[i] >= s->n) continue;
    int r = s->kept[rows[i]];
    if (r < 0 || (rows[i] < s->model->n_dofs && s->is_fixed[rows[i]])) continue;
    for (int j = 0; j < nc; ++j) {
      if (cols[j] < 0 || cols[j] >= s->n) continue;
      int c = s->kept[cols[j]];
      double v = values[i * nc + j];
      if (c < 0 || v == 0.0) continue;
      if (s->n_coo == s->cap_coo) {
        s->cap_coo = 2 * s->cap_coo + 1024;
        coo_entry *grown = realloc(s->coo, sizeof(coo_entry) * (size_t)s->cap_coo);
        if (!grown) abort();
        s->coo = grown;
      }
      s->coo[s->n_coo++] = (coo_entry){r, c, v};
    }
  }
}

/* ---- state from an iterate -------------------------------------------------------------------------------------- */

static void set_iterate(stepper *s, const double *x) {
  sk_model *m = s->model;
  if (x != s->x) memcpy(s->x, x, sizeof(double) * (size_t)s->n);
  for (int k = 0; k < m->n_dofs; ++k) s->q[k] = m->X[k] + s->x[k];
}

static sk_bulk_state bulk_state(const stepper *s) {
  sk_bulk_state b = {.scheme = s->model->time.scheme,
                     .t_n = s->t_n,
                     .t = s->t,
                     .dt = s->dt,
                     .u_n = s->u_n,
                     .v_n = s->model->time.scheme == SK_SCHEME_QUASISTATIC ? NULL : s->v_n,
                     .u = s->x};
  return b;
}

static void update_fixed_values(stepper *s) {
  sk_model *m = s->model;
  for (int k = 0; k < m->n_dirichlet; ++k) {
    const sk_dirichlet *bc = &m->dirichlet[k];
    double scale = sk_history_value(&bc->history, s->t);
    for (int j = 0; j < bc->n_nodes; ++j)
      for (int i = 0; i < m->dim; ++i)
        if (bc->fixed[i]) s->fixed_value[bc->nodes[j] * m->dim + i] = scale * bc->value[i];
  }
}

/* A collective status: the worst over ranks, with rank 0 holding a message if any rank failed. */
static sk_status collective_status(const stepper *s, sk_status local) {
  int code = (int)local, worst = 0;
  MPI_Allreduce(&code, &worst, 1, MPI_INT, MPI_MAX, s->model->comm);
  if (worst != SK_OK && local == SK_OK) sk_error_set((sk_status)worst, "failure on another rank");
  return (sk_status)worst;
}

/* ---- NOX callbacks ---------------------------------------------------------------------------------------------- */

static sk_status cb_residual(void *ctx, const double *x, double *F) {
  stepper *s = ctx;
  sk_model *m = s->model;
  double t0 = now_seconds();
  set_iterate(s, x);
  memset(s->F_local, 0, sizeof(double) * (size_t)s->n);
  sk_bulk_state bulk = bulk_state(s);
  sk_status status = sk_bulk_residual(m, &bulk, s->F_local);
  double t1 = now_seconds();
  sk_sink sink = {.ctx = s, .add_vector = sink_add_vector, .add_matrix = sink_add_matrix, .add_rhs = sink_add_rhs};
  for (int k = 0; k < m->n_pairs && status == SK_OK; ++k) {
    sk_contact_pair *pair = &m->pairs[k];
    sk_state state = pair_state(s, pair);
    int changed = 0;
    /* The active set follows the iterate: it is updated at every new point before F is evaluated there, so F and J
     * always belong to one set (semismooth-Newton style). */
    if (pair->plugin->after_iteration) status = pair->plugin->after_iteration(pair->instance, &state, &changed);
    if (status == SK_OK) status = pair->plugin->residual(pair->instance, &state, &sink);
    if (status != SK_OK) sk_error_prefix(status, "contact pair '%s': ", pair->name);
  }
  status = collective_status(s, status);
  double t2 = now_seconds();
  s->t_assembly += t1 - t0;
  s->t_contact += t2 - t1;
  if (status != SK_OK) return status;
  MPI_Allreduce(s->F_local, F, s->n, MPI_DOUBLE, MPI_SUM, m->comm);
  for (int k = 0; k < m->n_dofs; ++k)
    if (s->is_fixed[k]) {
      s->reactions[k] = F[k];
      F[k] = s->x[k] - s->fixed_value[k];
    }
  return SK_OK;
}

typedef struct {
  stepper *s;
} scatter_ctx;

static void scatter_element(void *ctx, int element, int n, const int *dofs, const double *K) {
  stepper *s = ctx;
  const int *pos = s->elem_pos + s->elem_pos_offset[element];
  for (int i = 0; i < n; ++i) {
    if (s->is_fixed[dofs[i]]) continue;
    for (int j = 0; j < n; ++j) s->values[pos[i * n + j]] += K[i * n + j];
  }
}

/* Adds the contact COO entries; records the ones the pattern lacks. */
static void scatter_contact(stepper *s) {
  s->n_missing = 0;
  for (int k = 0; k < s->n_coo; ++k) {
    int64_t p = find_position(s, s->coo[k].row, s->coo[k].col);
    if (p >= 0) {
      s->values[p] += s->coo[k].value;
    } else {
      if (s->n_missing == s->cap_missing) {
        s->cap_missing = 2 * s->cap_missing + 256;
        int64_t *grown = realloc(s->missing, sizeof(int64_t) * (size_t)s->cap_missing);
        if (!grown) abort();
        s->missing = grown;
      }
      s->missing[s->n_missing++] = (int64_t)s->coo[k].row * s->n_kept + s->coo[k].col;
    }
  }
}

/* Merges every rank's missing entries into the pattern's extra keys (collective). */
static void merge_missing(stepper *s) {
  sk_model *m = s->model;
  int *counts = xcalloc((size_t)m->n_ranks, sizeof(int)), *displs = xcalloc((size_t)m->n_ranks, sizeof(int));
  MPI_Allgather(&s->n_missing, 1, MPI_INT, counts, 1, MPI_INT, m->comm);
  int total = 0;
  for (int r = 0; r < m->n_ranks; ++r) {
    displs[r] = total;
    total += counts[r];
  }
  int64_t *all = xcalloc((size_t)total, sizeof(int64_t));
  MPI_Allgatherv(s->missing, s->n_missing, MPI_INT64_T, all, counts, displs, MPI_INT64_T, m->comm);
  int n_old = s->n_extra_keys;
  if (n_old + total > s->cap_extra_keys) {
    s->cap_extra_keys = 2 * (n_old + total) + 1024;
    int64_t *grown = realloc(s->extra_keys, sizeof(int64_t) * (size_t)s->cap_extra_keys);
    if (!grown) abort();
    s->extra_keys = grown;
  }
  memcpy(s->extra_keys + n_old, all, sizeof(int64_t) * (size_t)total);
  int n = n_old + total;
  qsort(s->extra_keys, (size_t)n, sizeof(int64_t), compare_i64);
  int unique = 0;
  for (int k = 0; k < n; ++k)
    if (k == 0 || s->extra_keys[k] != s->extra_keys[unique - 1]) s->extra_keys[unique++] = s->extra_keys[k];
  s->n_extra_keys = unique;
  free(all);
  free(counts);
  free(displs);
}

static sk_status cb_jacobian(void *ctx, const double *x) {
  stepper *s = ctx;
  sk_model *m = s->model;
  set_iterate(s, x);
  for (int attempt = 0; attempt < 3; ++attempt) {
    double t0 = now_seconds();
    sk_linsys_zero(s->sys);
    memset(s->rhs_local, 0, sizeof(double) * (size_t)s->n);
    sk_bulk_state bulk = bulk_state(s);
    sk_status status = sk_bulk_jacobian(m, &bulk, scatter_element, s);
    if (m->rank == 0)
      for (int k = 0; k < m->n_dofs; ++k)
        if (s->is_fixed[k]) s->values[find_position(s, k, k)] += 1.0;
    double t1 = now_seconds();
    s->n_coo = 0;
    sk_sink sink = {.ctx = s, .add_vector = sink_add_vector, .add_matrix = sink_add_matrix, .add_rhs = sink_add_rhs};
    for (int k = 0; k < m->n_pairs && status == SK_OK; ++k) {
      sk_contact_pair *pair = &m->pairs[k];
      sk_state state = pair_state(s, pair);
      status = pair->plugin->jacobian(pair->instance, &state, &sink);
      if (status != SK_OK) sk_error_prefix(status, "contact pair '%s': jacobian: ", pair->name);
    }
    status = collective_status(s, status);
    if (status != SK_OK) return status;
    scatter_contact(s);
    s->t_assembly += t1 - t0;
    s->t_contact += now_seconds() - t1;
    int missing = 0;
    MPI_Allreduce(&s->n_missing, &missing, 1, MPI_INT, MPI_SUM, m->comm);
    if (missing == 0) {
      MPI_Allreduce(s->rhs_local, s->rhs, s->n, MPI_DOUBLE, MPI_SUM, m->comm);
      double t2 = now_seconds();
      status = sk_linsys_assemble(s->sys);
      s->t_assembly += now_seconds() - t2;
      return status;
    }
    /* the contact structure grew: extend the pattern once and assemble again */
    merge_missing(s);
    SK_TRY(build_pattern(s));
  }
  return sk_error_set(SK_ERR_INTERNAL, "the Jacobian pattern did not settle after growing it");
}

static sk_status cb_solve(void *ctx, const double *x, const double *F, double *dx) {
  stepper *s = ctx;
  sk_model *m = s->model;
  (void)x;
  for (int k = 0; k < s->n_kept; ++k) {
    int i = s->full_of_kept[k];
    s->b[k] = -F[i] + ((i < m->n_dofs && s->is_fixed[i]) ? 0.0 : s->rhs[i]);
  }
  sk_linear_report report;
  double t0 = now_seconds();
  sk_status status = sk_linsys_solve(s->sys, s->b, s->y, &report);
  s->t_solve += now_seconds() - t0;
  s->linear_solves++;
  if (status != SK_OK) return status;
  int any_eliminated = s->n_kept < s->n;
  for (int i = 0; i < s->n; ++i) dx[i] = s->kept[i] >= 0 ? s->y[s->kept[i]] : 0.0;
  if (!any_eliminated) return SK_OK;
  /* each rank recovers its own entities' eliminated unknowns; the sum over ranks completes dx */
  status = SK_OK;
  for (int k = 0; k < m->n_pairs && status == SK_OK; ++k) {
    sk_contact_pair *pair = &m->pairs[k];
    if (!pair->plugin->recover) continue;
    sk_state state = pair_state(s, pair);
    status = pair->plugin->recover(pair->instance, &state, F, dx);
    if (status != SK_OK) sk_error_prefix(status, "contact pair '%s': recover: ", pair->name);
  }
  status = collective_status(s, status);
  if (status != SK_OK) return status;
  if (m->n_ranks > 1) {
    int n_elim = 0;
    for (int i = 0; i < s->n; ++i)
      if (s->kept[i] < 0) s->dx_elim[n_elim++] = dx[i];
    MPI_Allreduce(MPI_IN_PLACE, s->dx_elim, n_elim, MPI_DOUBLE, MPI_SUM, m->comm);
    n_elim = 0;
    for (int i = 0; i < s->n; ++i)
      if (s->kept[i] < 0) dx[i] = s->dx_elim[n_elim++];
  }
  return SK_OK;
}

static sk_status cb_after_iteration(void *ctx, int iteration, const double *x, double residual_norm) {
  stepper *s = ctx;
  (void)x;
  if (s->options->verbose && s->model->rank == 0)
    fprintf(stderr, "  step %d newton %d |F| = %.3e\n", s->step, iteration, residual_norm);
  return SK_OK;
}

/* ---- output ----------------------------------------------------------------------------------------------------- */

typedef struct {
  sk_csv *history;
  sk_pvd *pvd;
  char dir[1100];          /* staging folder */
  int n_columns;
  const char **names;
  char (*name_storage)[96];
  double *row;
  int vtu_count;
} outputs;

static const char *const fixed_columns[] = {
    "time", "step", "dt", "newton_iterations", "kinetic_energy", "strain_energy", "total_energy",
    "momentum_x", "momentum_y", "momentum_z", "angular_momentum_x", "angular_momentum_y", "angular_momentum_z",
    "contact_force_x", "contact_force_y", "contact_force_z", "active_points", "stick_points", "slip_points",
    "dissipated_energy", "constraint_violation"};
enum { N_FIXED_COLUMNS = sizeof fixed_columns / sizeof fixed_columns[0] };

static sk_status open_outputs(stepper *s, outputs *out) {
  sk_model *m = s->model;
  int n_obstacles = 0;
  for (int k = 0; k < m->n_pairs; ++k) n_obstacles += m->pairs[k].has_obstacle;
  out->n_columns = N_FIXED_COLUMNS + 3 * (m->n_dirichlet + n_obstacles) + 1;
  out->names = xcalloc((size_t)out->n_columns, sizeof(char *));
  out->name_storage = xcalloc((size_t)out->n_columns, sizeof *out->name_storage);
  out->row = xcalloc((size_t)out->n_columns, sizeof(double));
  int c = 0;
  for (; c < N_FIXED_COLUMNS; ++c) out->names[c] = fixed_columns[c];
  for (int k = 0; k < m->n_dirichlet; ++k)
    for (int i = 0; i < 3; ++i) {
      snprintf(out->name_storage[c], sizeof out->name_storage[c], "reaction_%s_%c", m->dirichlet[k].name, "xyz"[i]);
      out->names[c] = out->name_storage[c];
      ++c;
    }
  /* the force each rigid obstacle receives (minus the contact force on its slave surface) */
  for (int k = 0; k < m->n_pairs; ++k)
    if (m->pairs[k].has_obstacle)
      for (int i = 0; i < 3; ++i) {
        snprintf(out->name_storage[c], sizeof out->name_storage[c], "reaction_%s_%c", m->pairs[k].obstacle.name,
                 "xyz"[i]);
        out->names[c] = out->name_storage[c];
        ++c;
      }
  out->names[c] = "wall_seconds";
  if (!s->options->out_dir || m->rank != 0) return SK_OK;
  SK_TRY(sk_outdir_begin(s->options->out_dir, out->dir, sizeof out->dir));
  char path[1300];
  snprintf(path, sizeof path, "%s/history.csv", out->dir);
  SK_TRY(sk_csv_open(path, out->n_columns, out->names, &out->history));
  snprintf(path, sizeof path, "%s/scene.yaml", out->dir);
  SK_TRY(sk_cfg_write_file(s->scene->cfg, path));
  if (s->scene->output.write_vtu) {
    snprintf(path, sizeof path, "%s/results.pvd", out->dir);
    SK_TRY(sk_pvd_open(path, &out->pvd));
  }
  return SK_OK;
}

typedef struct {
  double *buffer;
  int n, cap;
  double *pressure, *gap, *state; /* per node, for the VTU */
} point_collector;

enum { POINT_FIELDS = 14 };

static void collect_point(void *ctx, const sk_contact_point *p) {
  point_collector *c = ctx;
  if (c->n == c->cap) {
    c->cap = 2 * c->cap + 256;
    double *grown = realloc(c->buffer, sizeof(double) * POINT_FIELDS * (size_t)c->cap);
    if (!grown) abort();
    c->buffer = grown;
  }
  double *r = c->buffer + POINT_FIELDS * (size_t)c->n++;
  double values[POINT_FIELDS] = {p->x[0], p->x[1], p->x[2], p->normal[0], p->normal[1], p->normal[2], p->pressure,
                                 p->traction[0], p->traction[1], p->traction[2], p->gap, (double)p->state,
                                 (double)p->slave_node, 0.0};
  memcpy(r, values, sizeof values);
  if (p->slave_node >= 0 && c->pressure) {
    c->pressure[p->slave_node] = p->pressure;
    c->gap[p->slave_node] = p->gap;
    c->state[p->slave_node] = p->state;
  }
}

/* Gathers contact points of every pair to rank 0 (pair index in the last field). Caller frees *all. */
static sk_status gather_points(stepper *s, double *node_fields, double **all, int *n_all) {
  sk_model *m = s->model;
  point_collector c = {0};
  if (node_fields) {
    c.pressure = node_fields;
    c.gap = node_fields + m->n_nodes;
    c.state = node_fields + 2 * m->n_nodes;
  }
  for (int k = 0; k < m->n_pairs; ++k) {
    sk_contact_pair *pair = &m->pairs[k];
    if (!pair->plugin->points) continue;
    int before = c.n;
    sk_state state = pair_state(s, pair);
    SK_TRY(pair->plugin->points(pair->instance, &state, collect_point, &c));
    for (int j = before; j < c.n; ++j) c.buffer[POINT_FIELDS * (size_t)j + POINT_FIELDS - 1] = k;
  }
  int count = c.n * POINT_FIELDS;
  int *counts = xcalloc((size_t)m->n_ranks, sizeof(int)), *displs = xcalloc((size_t)m->n_ranks, sizeof(int));
  MPI_Gather(&count, 1, MPI_INT, counts, 1, MPI_INT, 0, m->comm);
  int total = 0;
  for (int r = 0; r < m->n_ranks; ++r) {
    displs[r] = total;
    total += counts[r];
  }
  *all = xcalloc((size_t)total + 1, sizeof(double));
  MPI_Gatherv(c.buffer, count, MPI_DOUBLE, *all, counts, displs, MPI_DOUBLE, 0, m->comm);
  *n_all = total / POINT_FIELDS;
  free(counts);
  free(displs);
  free(c.buffer);
  return SK_OK;
}

static sk_status write_contact_csv(stepper *s, outputs *out, const double *points, int n_points) {
  static const char *const names[] = {"x", "y", "z", "normal_x", "normal_y", "normal_z", "pressure", "traction_x",
                                      "traction_y", "traction_z", "gap", "state", "node", "pair"};
  char path[1300];
  snprintf(path, sizeof path, "%s/contact.csv", out->dir);
  sk_csv *csv;
  SK_TRY(sk_csv_open(path, POINT_FIELDS, names, &csv));
  for (int k = 0; k < n_points; ++k) SK_TRY(sk_csv_row(csv, points + POINT_FIELDS * (size_t)k));
  (void)s;
  return sk_csv_close(csv);
}

static sk_status write_vtu(stepper *s, outputs *out) {
  sk_model *m = s->model;
  int dim = m->dim, nn = m->n_nodes;
  double *points = xcalloc(3 * (size_t)nn, sizeof(double));
  double *displacement = xcalloc(3 * (size_t)nn, sizeof(double));
  double *velocity = xcalloc(3 * (size_t)nn, sizeof(double));
  double *node_fields = xcalloc(3 * (size_t)nn, sizeof(double));
  double *node_fields_sum = xcalloc(3 * (size_t)nn, sizeof(double));
  double *stress = xcalloc(9 * (size_t)m->n_elements, sizeof(double));
  double *stress_sum = xcalloc(9 * (size_t)m->n_elements, sizeof(double));
  sk_status status = sk_bulk_stress(m, s->u_n, stress);
  status = collective_status(s, status);
  double *all_points = NULL;
  int n_points = 0;
  if (status == SK_OK) status = gather_points(s, node_fields, &all_points, &n_points);
  MPI_Reduce(stress, stress_sum, 9 * m->n_elements, MPI_DOUBLE, MPI_SUM, 0, m->comm);
  MPI_Reduce(node_fields, node_fields_sum, 3 * nn, MPI_DOUBLE, MPI_SUM, 0, m->comm);
  if (status == SK_OK && m->rank == 0) {
    for (int a = 0; a < nn; ++a)
      for (int i = 0; i < dim; ++i) {
        displacement[3 * a + i] = s->u_n[a * dim + i];
        velocity[3 * a + i] = s->v_n[a * dim + i];
        points[3 * a + i] = m->X[a * dim + i] + s->u_n[a * dim + i];
      }
    int n_cells = m->n_elements;
    sk_elem_type *types = xcalloc((size_t)n_cells, sizeof(sk_elem_type));
    int *offsets = xcalloc((size_t)n_cells + 1, sizeof(int));
    int *conn = xcalloc((size_t)n_cells * SK_MAX_NEN, sizeof(int));
    double *body_id = xcalloc((size_t)n_cells, sizeof(double));
    double *rank_id = xcalloc((size_t)n_cells, sizeof(double));
    for (int e = 0; e < n_cells; ++e) {
      const sk_body *body;
      const int *ec;
      int dofs[SK_MAX_NEN * 3];
      sk_element_dofs(m, e, dofs, &body, &ec);
      types[e] = body->group->type;
      offsets[e + 1] = offsets[e] + body->group->nen;
      memcpy(conn + offsets[e], ec, sizeof(int) * (size_t)body->group->nen);
      body_id[e] = (double)(body - m->bodies);
      rank_id[e] = m->element_part[e];
    }
    sk_vtu_field point_fields[] = {{"displacement", 3, displacement},
                                   {"velocity", 3, velocity},
                                   {"contact_pressure", 1, node_fields_sum},
                                   {"contact_gap", 1, node_fields_sum + nn},
                                   {"contact_state", 1, node_fields_sum + 2 * nn}};
    sk_vtu_field cell_fields[] = {{"cauchy_stress", 9, stress_sum}, {"body", 1, body_id}, {"rank", 1, rank_id}};
    int n_point_fields = m->n_pairs > 0 ? 5 : 2;
    char file[64], path[1400];
    snprintf(file, sizeof file, "step-%06d.vtu", s->step);
    snprintf(path, sizeof path, "%s/%s", out->dir, file);
    status = sk_vtu_write(path, nn, points, n_cells, types, offsets, conn, n_point_fields, point_fields, 3,
                          cell_fields);
    if (status == SK_OK) status = sk_pvd_add(out->pvd, s->t_n, file);
    out->vtu_count++;
    free(types);
    free(offsets);
    free(conn);
    free(body_id);
    free(rank_id);
  }
  free(all_points);
  free(points);
  free(displacement);
  free(velocity);
  free(node_fields);
  free(node_fields_sum);
  free(stress);
  free(stress_sum);
  return status;
}

/* Contact totals of the step just committed, summed over ranks, called while the state still spans the step
 * (q_n, t_n at its start; q, t at its end): totals = [force xyz, active, stick, slip, dissipated (step),
 * constraint violation, then the force on each rigid obstacle (xyz)]; 8 + 3 * obstacles entries. */
static sk_status contact_totals(stepper *s, double *totals) {
  sk_model *m = s->model;
  int n_obstacles = 0;
  memset(totals, 0, sizeof(double) * (size_t)(8 + 3 * m->n_pairs));
  sk_status status = SK_OK;
  for (int k = 0; k < m->n_pairs && status == SK_OK; ++k) {
    sk_contact_pair *pair = &m->pairs[k];
    sk_contact_report r = {0};
    sk_state state = pair_state(s, pair);
    status = pair->plugin->report(pair->instance, &state, &r);
    for (int i = 0; i < 3; ++i) totals[i] += r.force[i];
    totals[3] += r.active;
    totals[4] += r.stick;
    totals[5] += r.slip;
    totals[6] += r.dissipated;
    totals[7] = fmax(totals[7], r.constraint_norm);
    if (pair->has_obstacle) {
      for (int i = 0; i < 3; ++i) totals[8 + 3 * n_obstacles + i] = -r.force[i];
      ++n_obstacles;
    }
  }
  status = collective_status(s, status);
  if (status != SK_OK) return status;
  double constraint = totals[7];
  MPI_Allreduce(MPI_IN_PLACE, totals, 8 + 3 * n_obstacles, MPI_DOUBLE, MPI_SUM, m->comm);
  MPI_Allreduce(&constraint, &totals[7], 1, MPI_DOUBLE, MPI_MAX, m->comm);
  return SK_OK;
}

/* One history row for the converged state at t_n (after the state moved on), with the step's contact totals. */
static sk_status write_history_row(stepper *s, outputs *out, int newton_iterations, const double *contact,
                                   double dissipated_total, double wall_start) {
  sk_model *m = s->model;
  sk_invariants inv;
  SK_TRY(sk_bulk_invariants(m, s->u_n, s->v_n, &inv));
  int n_obstacles = 0;
  for (int k = 0; k < m->n_pairs; ++k) n_obstacles += m->pairs[k].has_obstacle;
  double *reaction_sum = xcalloc(3 * (size_t)(m->n_dirichlet + 1), sizeof(double));
  for (int k = 0; k < m->n_dirichlet; ++k) {
    const sk_dirichlet *bc = &m->dirichlet[k];
    for (int j = 0; j < bc->n_nodes; ++j)
      for (int i = 0; i < m->dim; ++i)
        if (bc->fixed[i]) reaction_sum[3 * k + i] += s->reactions[bc->nodes[j] * m->dim + i];
  }
  double *row = out->row;
  int c = 0;
  row[c++] = s->t_n;
  row[c++] = s->step;
  row[c++] = s->dt;
  row[c++] = newton_iterations;
  row[c++] = inv.kinetic;
  row[c++] = inv.strain;
  row[c++] = inv.kinetic + inv.strain;
  for (int i = 0; i < 3; ++i) row[c++] = inv.momentum[i];
  for (int i = 0; i < 3; ++i) row[c++] = inv.angular_momentum[i];
  for (int i = 0; i < 6; ++i) row[c++] = contact[i];
  row[c++] = dissipated_total + contact[6];
  row[c++] = contact[7];
  for (int k = 0; k < m->n_dirichlet; ++k)
    for (int i = 0; i < 3; ++i) row[c++] = reaction_sum[3 * k + i];
  for (int k = 0; k < 3 * n_obstacles; ++k) row[c++] = contact[8 + k];
  row[c++] = now_seconds() - wall_start;
  free(reaction_sum);
  if (out->history) SK_TRY(sk_csv_row(out->history, row));
  return SK_OK;
}

/* ---- the loop --------------------------------------------------------------------------------------------------- */

static sk_status solve_step(stepper *s, const sk_newton_callbacks *callbacks) {
  sk_model *m = s->model;
  /* predictor: constant velocity (dynamics) or the last state (quasi-static), Dirichlet values at t */
  for (int k = 0; k < m->n_dofs; ++k) {
    s->x[k] = s->u_n[k] + (m->time.scheme == SK_SCHEME_QUASISTATIC ? 0.0 : s->dt * s->v_n[k]);
  }
  update_fixed_values(s);
  for (int k = 0; k < m->n_dofs; ++k)
    if (s->is_fixed[k]) s->x[k] = s->fixed_value[k];
  for (int k = 0; k < m->n_dofs; ++k) s->q[k] = m->X[k] + s->x[k];
  for (int k = 0; k < m->n_pairs; ++k) {
    sk_contact_pair *pair = &m->pairs[k];
    sk_state state = pair_state(s, pair);
    sk_status status = pair->plugin->begin_step(pair->instance, &state);
    status = collective_status(s, status);
    if (status != SK_OK) return sk_error_prefix(status, "contact pair '%s': begin_step: ", pair->name);
  }
  int changed = 0;
  SK_TRY(layout_unknowns(s, &changed));
  if (changed || s->pattern_n != s->n_kept) {
    s->n_extra_keys = 0; /* keys are in the old numbering */
    SK_TRY(build_pattern(s));
  }
  return sk_newton_solve(m->comm, &s->scene->solver.newton, callbacks, s->n, s->x, &s->newton);
}

static void stepper_free(stepper *s) {
  free_unknown_arrays(s);
  free(s->u_n);
  free(s->v_n);
  free(s->v);
  free(s->q_n);
  free(s->q);
  free(s->x);
  free(s->reactions);
  free(s->is_fixed);
  free(s->fixed_value);
  free(s->node_adj_ptr);
  free(s->node_adj);
  free(s->extra_keys);
  free(s->row_ptr);
  free(s->cols);
  free(s->local_rows);
  free(s->elem_pos_offset);
  free(s->elem_pos);
  free(s->coo);
  free(s->missing);
  sk_linsys_destroy(s->sys);
}

static void initial_state(stepper *s) {
  sk_model *m = s->model;
  int dim = m->dim;
  for (int b = 0; b < m->n_bodies; ++b) {
    const sk_body *body = &m->bodies[b];
    const sk_group *g = body->group;
    for (long k = 0; k < (long)g->n_elems * g->nen; ++k) {
      int a = g->conn[k];
      double r[3] = {0, 0, 0};
      for (int i = 0; i < dim; ++i) r[i] = m->X[a * dim + i] - body->center[i];
      const double *w = body->angular_velocity;
      double spin[3] = {w[1] * r[2] - w[2] * r[1], w[2] * r[0] - w[0] * r[2], w[0] * r[1] - w[1] * r[0]};
      for (int i = 0; i < dim; ++i) s->v_n[a * dim + i] = body->velocity[i] + spin[i];
    }
  }
  for (int k = 0; k < m->n_dirichlet; ++k) {
    const sk_dirichlet *bc = &m->dirichlet[k];
    for (int j = 0; j < bc->n_nodes; ++j)
      for (int i = 0; i < dim; ++i)
        if (bc->fixed[i]) s->is_fixed[bc->nodes[j] * dim + i] = 1;
  }
  for (int k = 0; k < m->n_dofs; ++k) {
    s->q_n[k] = m->X[k];
    s->q[k] = m->X[k];
  }
}

static sk_status write_summary(stepper *s, outputs *out, const char *status_text) {
  sk_model *m = s->model;
  sk_run_summary *sum = s->summary;
  char path[1300];
  snprintf(path, sizeof path, "%s/summary.json", out->dir);
  sk_json *json;
  SK_TRY(sk_json_open(path, &json));
  sk_json_string(json, "status", status_text);
  if (sum->failed) sk_json_string(json, "message", sum->message);
  sk_json_string(json, "scene", s->scene->path);
  sk_json_int(json, "steps", sum->steps);
  sk_json_number(json, "final_time", sum->final_time);
  sk_json_int(json, "newton_iterations", sum->newton_iterations);
  sk_json_int(json, "linear_solves", sum->linear_solves);
  sk_json_int(json, "step_cuts", sum->cuts);
  sk_json_int(json, "dofs", m->n_dofs);
  sk_json_int(json, "unknowns", sum->unknowns_max);
  sk_json_int(json, "linear_system_size", sum->linear_size_max);
  sk_json_int(json, "ranks", m->n_ranks);
  char plugins[512] = "", strategies[512] = "";
  for (int k = 0; k < m->n_pairs; ++k) {
    const sk_contact_pair *pair = &m->pairs[k];
    snprintf(plugins + strlen(plugins), sizeof plugins - strlen(plugins), "%s%s", k ? "," : "", pair->plugin->name);
    snprintf(strategies + strlen(strategies), sizeof strategies - strlen(strategies), "%s%s", k ? "," : "",
             pair->plugin->strategies[pair->strategy]);
  }
  sk_json_string(json, "plugin", m->n_pairs ? plugins : "none");
  sk_json_string(json, "strategy", m->n_pairs ? strategies : "none");
  sk_json_string(json, "linear_solver", sk_linear_solver_name(s->scene->solver.linear.kind));
  sk_json_number(json, "wall_seconds", sum->wall_seconds);
  sk_json_number(json, "assembly_seconds", sum->assembly_seconds);
  sk_json_number(json, "contact_seconds", sum->contact_seconds);
  sk_json_number(json, "solve_seconds", sum->solve_seconds);
  return sk_json_close(json);
}

sk_status sk_run(sk_scene *scene, const sk_run_options *options, sk_run_summary *summary) {
  double wall_start = now_seconds();
  memset(summary, 0, sizeof *summary);
  sk_model *m = &scene->model;
  stepper s = {0};
  s.scene = scene;
  s.model = m;
  s.options = options;
  s.summary = summary;
  s.pattern_n = -1;
  s.u_n = xcalloc((size_t)m->n_dofs, sizeof(double));
  s.v_n = xcalloc((size_t)m->n_dofs, sizeof(double));
  s.v = xcalloc((size_t)m->n_dofs, sizeof(double));
  s.q_n = xcalloc((size_t)m->n_dofs, sizeof(double));
  s.q = xcalloc((size_t)m->n_dofs, sizeof(double));
  s.is_fixed = xcalloc((size_t)m->n_dofs, 1);
  s.fixed_value = xcalloc((size_t)m->n_dofs, sizeof(double));
  s.reactions = xcalloc((size_t)m->n_dofs, sizeof(double));
  s.elem_pos_offset = xcalloc((size_t)m->n_elements, sizeof(int));
  initial_state(&s);
  build_node_graph(&s);
  sk_status status = sk_linsys_create(m->comm, &scene->solver.linear, &s.sys);
  if (status != SK_OK) {
    stepper_free(&s);
    return status;
  }
  ensure_capacity(&s, m->n_dofs);
  s.n = m->n_dofs;

  outputs out = {0};
  status = open_outputs(&s, &out);
  status = collective_status(&s, status);
  sk_newton_callbacks callbacks = {.ctx = &s,
                                   .residual = cb_residual,
                                   .jacobian = cb_jacobian,
                                   .solve = cb_solve,
                                   .after_iteration = cb_after_iteration};
  s.t_n = m->time.t_start;
  double dt_nominal = m->time.dt, dt = dt_nominal, dissipated = 0.0;
  int cuts_in_a_row = 0, good_steps = 0;
  /* the initial state as row 0 */
  double *contact = xcalloc(8 + 3 * (size_t)m->n_pairs, sizeof(double)); /* zero at the initial state */
  if (status == SK_OK) status = write_history_row(&s, &out, 0, contact, 0.0, wall_start);
  if (status == SK_OK && scene->output.write_vtu && options->out_dir) status = write_vtu(&s, &out);
  if (options->progress && m->rank == 0) sk_progress_begin(scene->path, m->time.t_end);

  const double t_eps = 1e-12 * fmax(1.0, fabs(m->time.t_end));
  while (status == SK_OK && s.t_n < m->time.t_end - t_eps) {
    if (options->max_steps > 0 && summary->steps >= options->max_steps) break;
    s.dt = fmin(dt, m->time.t_end - s.t_n);
    s.t = s.t_n + s.dt;
    s.step = summary->steps + 1;
    status = solve_step(&s, &callbacks);
    summary->newton_iterations += s.newton.iterations;
    if (status == SK_OK) {
      /* accept: velocities, commit plugin history, output */
      sk_bulk_state bulk = bulk_state(&s);
      sk_bulk_velocity(m, &bulk, s.v);
      for (int k = 0; k < m->n_pairs && status == SK_OK; ++k) {
        sk_contact_pair *pair = &m->pairs[k];
        sk_state state = pair_state(&s, pair);
        status = pair->plugin->commit_step(pair->instance, &state);
      }
      status = collective_status(&s, status);
      if (status == SK_OK) status = contact_totals(&s, contact); /* while the state still spans the step */
      if (status != SK_OK) break;
      memcpy(s.u_n, s.x, sizeof(double) * (size_t)m->n_dofs);
      memcpy(s.v_n, s.v, sizeof(double) * (size_t)m->n_dofs);
      memcpy(s.q_n, s.q, sizeof(double) * (size_t)m->n_dofs);
      s.t_n = s.t;
      summary->steps++;
      status = write_history_row(&s, &out, s.newton.iterations, contact, dissipated, wall_start);
      dissipated = out.row[19];
      int last = !(s.t_n < m->time.t_end - t_eps) ||
                 (options->max_steps > 0 && summary->steps >= options->max_steps);
      if (status == SK_OK && scene->output.write_vtu && options->out_dir &&
          ((scene->output.vtu_every > 0 && summary->steps % scene->output.vtu_every == 0) || last))
        status = write_vtu(&s, &out);
      if (options->progress && m->rank == 0) {
        char extra[128];
        snprintf(extra, sizeof extra, "dt %.3g  E %.6g", s.dt, out.row[6]);
        sk_progress_update(summary->steps, s.t_n, s.newton.iterations, extra);
      }
      cuts_in_a_row = 0;
      if (dt < dt_nominal && ++good_steps >= 3) {
        dt = fmin(dt_nominal, 2.0 * dt);
        good_steps = 0;
      }
    } else if (status == SK_ERR_DIVERGED || status == SK_ERR_INVERTED) {
      /* cut the step and retry */
      for (int k = 0; k < m->n_pairs; ++k) m->pairs[k].plugin->reject_step(m->pairs[k].instance);
      summary->cuts++;
      if (++cuts_in_a_row > m->time.max_cuts) {
        char reason[600];
        snprintf(reason, sizeof reason, "%s", sk_error_message());
        status = sk_error_set(SK_ERR_DIVERGED,
                              "step %d from t = %.6g: no convergence after %d step cuts (dt = %.3g): %s", s.step,
                              s.t_n, m->time.max_cuts, s.dt, reason);
        break;
      }
      if (m->rank == 0 && options->verbose)
        fprintf(stderr, "step %d at t = %.6g: %s — cutting dt to %.3g\n", s.step, s.t_n, sk_error_message(),
                0.5 * s.dt);
      dt = 0.5 * s.dt;
      good_steps = 0;
      status = SK_OK;
    }
  }
  if (options->progress && m->rank == 0) sk_progress_end();

  summary->final_time = s.t_n;
  summary->linear_solves = s.linear_solves;
  summary->assembly_seconds = s.t_assembly;
  summary->contact_seconds = s.t_contact;
  summary->solve_seconds = s.t_solve;
  summary->wall_seconds = now_seconds() - wall_start;
  if (status != SK_OK) {
    summary->failed = 1;
    snprintf(summary->message, sizeof summary->message, "%s", sk_error_message());
  }
  /* results: complete files up to the last converged step, then the folder is swapped in atomically */
  double *points = NULL;
  int n_points = 0;
  sk_status points_status = SK_OK;
  if (options->out_dir && m->n_pairs > 0 && scene->output.write_contact_csv && summary->steps > 0) {
    char message[1100];
    snprintf(message, sizeof message, "%s", sk_error_message());
    points_status = collective_status(&s, gather_points(&s, NULL, &points, &n_points));
    sk_error_set(status, "%s", message);
  }
  if (options->out_dir && m->rank == 0 && out.dir[0]) {
    char message[1100];
    snprintf(message, sizeof message, "%s", sk_error_message());
    sk_status out_status = points_status;
    if (out_status == SK_OK && points) out_status = write_contact_csv(&s, &out, points, n_points);
    sk_csv_close(out.history);
    out.history = NULL;
    sk_pvd_close(out.pvd);
    out.pvd = NULL;
    if (out_status == SK_OK) out_status = write_summary(&s, &out, summary->failed ? "failed" : "ok");
    if (out_status == SK_OK) out_status = sk_outdir_commit(out.dir, options->out_dir);
    else sk_outdir_abort(out.dir);
    if (status == SK_OK) status = out_status;
    else sk_error_set(status, "%s", message);
  }
  free(points);
  free(contact);
  free(out.names);
  free(out.name_storage);
  free(out.row);
  stepper_free(&s);
  return status;
}
