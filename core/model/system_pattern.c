/* The sparsity pattern of a step attempt (system.h): the rows this rank writes — its elements' blocks, the couplings
 * its terms declare and the diagonal of its owned rows — grown once before Newton, and the sink plugins add through,
 * which refuses entries outside it. The bridge merges every rank's rows into the owned rows of the matrix. Rows and
 * columns are local unknowns here; the pattern stores the linear system's (global) column indices, sorted. */
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "assemble.h"
#include "system.h"


static int compare_int(const void *a, const void *b) {
  int x = *(const int *)a, y = *(const int *)b;
  return (x > y) - (x < y);
}

/* Adds the wall and CPU seconds since t0 to seconds[2]. */
static void charge(double seconds[2], sk_clock t0) {
  const sk_clock t = sk_system_clock();
  seconds[0] += t.wall - t0.wall;
  seconds[1] += t.cpu - t0.cpu;
}


/* ---- the plugins' sink ------------------------------------------------------------------------------------------ */

static void sink_fail(sk_system_sink *sink, const char *fmt, long long a, long long b) {
  if (sink->failed) return;
  sink->failed = 1;
  snprintf(sink->message, sizeof sink->message, fmt, a, b);
}

/* The unknowns over all ranks, in the ABI numbering. */
static int64_t abi_count(const sk_system *sys) { return sys->n_abi; }

/* The local row of an ABI index. A negative index means "no row" (skipped); one at or beyond the number of unknowns
 * is a plugin's error, never a contribution dropped without a word (issue 15, item 15); so is one this rank does not
 * hold (outside its views). */
static int64_t row_in_system(sk_system_sink *sink, int64_t row, const char *what) {
  if (row < 0) return -1;
  if (row >= abi_count(sink->sys)) {
    sink_fail(sink, what, (long long)row, (long long)abi_count(sink->sys));
    return -1;
  }
  const int64_t local = sk_system_local_of(sink->sys, row);
  if (local < 0) sink_fail(sink, "unknown %lld outside this rank's views (of %lld unknowns)", (long long)row,
                           (long long)abi_count(sink->sys));
  return local;
}

static void sink_add_vector(sk_sink *abi, int n, const int64_t *rows, const double *values) {
  sk_system_sink *sink = (sk_system_sink *)abi;
  for (int k = 0; k < n; ++k) {
    const int64_t r = row_in_system(sink, rows[k], "residual entry in row %lld, beyond the %lld unknowns");
    if (r >= 0) sink->sys->F_local[r] += values[k];
  }
}

static void sink_add_rhs(sk_sink *abi, int n, const int64_t *rows, const double *values) {
  sk_system_sink *sink = (sk_system_sink *)abi;
  for (int k = 0; k < n; ++k) {
    const int64_t r = row_in_system(sink, rows[k], "right-hand-side entry in row %lld, beyond the %lld unknowns");
    if (r >= 0) sink->sys->rhs_local[r] += values[k];
  }
}

int64_t sk_system_position(const sk_system *sys, int64_t row, int64_t col) {
  const int c = sys->solver_of[col];
  if (c < 0) return -1;
  const int *begin = sys->cols + sys->row_ptr[row];
  const size_t len = (size_t)(sys->row_ptr[row + 1] - sys->row_ptr[row]);
  const int *hit = bsearch(&c, begin, len, sizeof(int), compare_int);
  return hit ? sys->row_ptr[row] + (hit - begin) : -1;
}

static void sink_add_matrix(sk_sink *abi, int nr, const int64_t *rows, int nc, const int64_t *cols,
                            const double *values) {
  sk_system_sink *sink = (sk_system_sink *)abi;
  sk_system *sys = sink->sys;
  enum { CHUNK = 128 }; /* the columns' local indices, a chunk at a time (no allocation inside Newton) */
  int64_t local[CHUNK];
  for (int j0 = 0; j0 < nc; j0 += CHUNK) {
    const int mc = nc - j0 < CHUNK ? nc - j0 : CHUNK;
    for (int j = 0; j < mc; ++j)
      local[j] = row_in_system(sink, cols[j0 + j], "Jacobian entry in column %lld, beyond the %lld unknowns");
    for (int i = 0; i < nr; ++i) {
      const int64_t r = row_in_system(sink, rows[i], "Jacobian entry in row %lld, beyond the %lld unknowns");
      if (r < 0 || sys->solver_of[r] < 0) continue;
      for (int j = 0; j < mc; ++j) {
        const double v = values[i * nc + j0 + j];
        const int64_t c = local[j];
        if (v == 0.0 || c < 0 || sys->solver_of[c] < 0) continue;
        if (!sys->row_local[r]) {
          sink_fail(sink, "Jacobian entry in row %lld (column %lld) outside this rank's views", (long long)rows[i],
                    (long long)cols[j0 + j]);
          continue;
        }
        const int64_t p = sk_system_position(sys, r, c);
        if (p < 0) {
          sink_fail(sink, "Jacobian entry (%lld, %lld) outside the pattern declared by pattern()", (long long)rows[i],
                    (long long)cols[j0 + j]);
          continue;
        }
        sys->values[p] += v;
      }
    }
  }
}

void sk_system_sink_init(sk_system *sys) {
  sys->sink.abi = (sk_sink){SK_TABLE_HEADER(sk_sink), .add_vector = sink_add_vector, .add_matrix = sink_add_matrix,
                            .add_rhs = sink_add_rhs};
  sys->sink.sys = sys;
}

/* ---- declarations ------------------------------------------------------------------------------------------------ */

/* A direct-mapped table of the keys declared this attempt: a key found in its slot is already in `declared`. Plugins
 * declare a coupling once per face and candidate, so most keys repeat (3D frictional mortar: 7.0 M declared, 226 k
 * distinct), and sorting the repeats at every pattern change cost 12 % of such a run. */
enum { DECLARED_RECENT_BITS = 18, DECLARED_RECENT = 1 << DECLARED_RECENT_BITS };

static int declared_before(sk_system *sys, int64_t key) {
  int64_t *slot = sys->declared_recent + (((uint64_t)key * 0x9E3779B97F4A7C15u) >> (64 - DECLARED_RECENT_BITS));
  if (*slot == key) return 1;
  *slot = key;
  return 0;
}

sk_status sk_system_declare_local(sk_system *sys, int nr, const int64_t *rows, int nc, const int64_t *cols) {
  const int64_t need = sys->n_declared + (int64_t)nr * nc;
  if (need > sys->cap_declared) {
    const int64_t cap = 2 * need + 1024;
    int64_t *grown = realloc(sys->declared, sizeof(int64_t) * (size_t)cap);
    if (!grown) return sk_system_out_of_memory("the declared pattern", cap);
    sys->declared = grown;
    sys->cap_declared = cap;
  }
  for (int i = 0; i < nr; ++i) {
    if (rows[i] < 0 || rows[i] >= sys->n || sys->solver_of[rows[i]] < 0) continue;
    for (int j = 0; j < nc; ++j) {
      if (cols[j] < 0 || cols[j] >= sys->n || sys->solver_of[cols[j]] < 0) continue;
      const int64_t key = rows[i] * sys->n + cols[j];
      if (!declared_before(sys, key)) sys->declared[sys->n_declared++] = key;
    }
  }
  return SK_OK;
}

sk_status sk_system_declare(sk_system *sys, int nr, const int64_t *rows, int nc, const int64_t *cols) {
  enum { CHUNK = 96 };
  int64_t r[CHUNK], c[CHUNK];
  for (int i0 = 0; i0 < nr; i0 += CHUNK) {
    const int mr = nr - i0 < CHUNK ? nr - i0 : CHUNK;
    for (int i = 0; i < mr; ++i) r[i] = sk_system_local_of(sys, rows[i0 + i]);
    for (int j0 = 0; j0 < nc; j0 += CHUNK) {
      const int mc = nc - j0 < CHUNK ? nc - j0 : CHUNK;
      for (int j = 0; j < mc; ++j) c[j] = sk_system_local_of(sys, cols[j0 + j]);
      SK_TRY(sk_system_declare_local(sys, mr, r, mc, c));
    }
  }
  return SK_OK;
}

/* ---- the bulk graph of this rank's elements ------------------------------------------------------------------- */

/* Per node, the nodes this rank's elements couple it with (sorted; the node itself when it is owned, also when no
 * element holds it). Built once. */
static sk_status build_bulk_graph(sk_system *sys) {
  const sk_model *m = sys->model;
  const int nn = m->n_nodes;
  int *count = calloc((size_t)nn + 1, sizeof(int));
  if (!count) return sk_system_out_of_memory("the element graph", nn);
  int nodes[SK_MAX_NEN];
  for (int e = 0; e < m->n_elements; ++e) {
    if (m->element_part[e] != m->rank) continue;
    const sk_body *body;
    const int *conn;
    sk_element_dofs(m, e, NULL, &body, &conn);
    for (int a = 0; a < body->group->nen; ++a) count[conn[a] + 1] += body->group->nen;
  }
  for (int a = 0; a < nn; ++a) count[a + 1] += count[a] + (sys->node_role[a] == SK_NODE_OWNED);
  int *cols = malloc(sizeof(int) * (size_t)(count[nn] > 0 ? count[nn] : 1));
  int *fill = calloc((size_t)nn + 1, sizeof(int));
  if (!cols || !fill) {
    const int total = count[nn];
    free(count);
    free(cols);
    free(fill);
    return sk_system_out_of_memory("the element graph", total);
  }
  for (int a = 0; a < nn; ++a)
    if (sys->node_role[a] == SK_NODE_OWNED) cols[count[a] + fill[a]++] = a;
  for (int e = 0; e < m->n_elements; ++e) {
    if (m->element_part[e] != m->rank) continue;
    const sk_body *body;
    const int *conn;
    sk_element_dofs(m, e, NULL, &body, &conn);
    const int nen = body->group->nen;
    memcpy(nodes, conn, sizeof(int) * (size_t)nen);
    for (int a = 0; a < nen; ++a)
      for (int b = 0; b < nen; ++b) cols[count[conn[a]] + fill[conn[a]]++] = nodes[b];
  }
  free(fill);
  /* sorted, unique, compacted */
  int used = 0;
  int *ptr = malloc(sizeof(int) * ((size_t)nn + 1));
  if (!ptr) {
    free(count);
    free(cols);
    return sk_system_out_of_memory("the element graph", nn);
  }
  ptr[0] = 0;
  for (int a = 0; a < nn; ++a) {
    int *row = cols + count[a];
    const int len = count[a + 1] - count[a];
    qsort(row, (size_t)len, sizeof(int), compare_int);
    for (int k = 0; k < len; ++k)
      if (k == 0 || row[k] != row[k - 1]) cols[used++] = row[k];
    ptr[a + 1] = used;
  }
  free(count);
  int *shrunk = realloc(cols, sizeof(int) * (size_t)(used > 0 ? used : 1));
  sys->bulk_cols = shrunk ? shrunk : cols;
  sys->bulk_ptr = ptr;
  return SK_OK;
}

/* ---- the rows ----------------------------------------------------------------------------------------------------- */

/* The columns (linear system numbering) of the keys of local row r (extra_keys from *k on, advanced) and its diagonal
 * when owned, added to the `len` in out; all of them sorted and unique; returns how many. */
static int64_t key_columns(const sk_system *sys, int64_t r, int64_t *k, int *out, int64_t len) {
  if (sys->role[r] == SK_NODE_OWNED) out[len++] = sys->solver_of[r];
  for (; *k < sys->n_extra_keys && sys->extra_keys[*k] / sys->n == r; ++*k) {
    const int c = sys->solver_of[sys->extra_keys[*k] % sys->n];
    if (c >= 0) out[len++] = c;
  }
  qsort(out, (size_t)len, sizeof(int), compare_int);
  int64_t unique = 0;
  for (int64_t j = 0; j < len; ++j)
    if (j == 0 || out[j] != out[unique - 1]) out[unique++] = out[j];
  return unique;
}

/* The columns (linear system numbering, sorted, unique) of local row r: its node's element graph, the keys of the row
 * (extra_keys from *k on, advanced), its diagonal when owned; into out, returns how many. */
static int64_t row_columns(const sk_system *sys, int64_t r, int64_t *k, int *out) {
  const sk_model *m = sys->model;
  int64_t len = 0;
  if (sys->solver_of[r] < 0) {
    while (*k < sys->n_extra_keys && sys->extra_keys[*k] / sys->n == r) ++*k;
    return 0;
  }
  if (r < m->n_dofs) {
    const int a = (int)(r / m->dim);
    for (int j = sys->bulk_ptr[a]; j < sys->bulk_ptr[a + 1]; ++j)
      for (int i = 0; i < m->dim; ++i) {
        const int c = sys->solver_of[(int64_t)sys->bulk_cols[j] * m->dim + i];
        if (c >= 0) out[len++] = c;
      }
  }
  return key_columns(sys, r, k, out, len);
}

/* An upper bound of any row's length. */
static int64_t longest_row(const sk_system *sys) {
  const sk_model *m = sys->model;
  int64_t longest = 1, run = 0, previous = -1;
  for (int a = 0; a < m->n_nodes; ++a)
    if ((sys->bulk_ptr[a + 1] - sys->bulk_ptr[a]) * m->dim > longest) longest = (sys->bulk_ptr[a + 1] - sys->bulk_ptr[a]) * m->dim;
  for (int64_t k = 0; k < sys->n_extra_keys; ++k) {
    const int64_t r = sys->extra_keys[k] / sys->n;
    run = r == previous ? run + 1 : 1;
    previous = r;
    if (run > longest) longest = run;
  }
  return 2 * longest + 2;
}

/* The rows this rank writes, to the bridge: every row with entries or owned (the values array is the CSR's). */
static sk_status hand_to_solver(sk_system *sys) {
  int n_rows = 0;
  for (int64_t r = 0; r < sys->n; ++r) n_rows += sys->solver_of[r] >= 0 && sys->row_ptr[r + 1] > sys->row_ptr[r];
  int *rows = malloc(sizeof(int) * (size_t)(n_rows + 1));
  int64_t *ptr = malloc(sizeof(int64_t) * (size_t)(n_rows + 1));
  if (!rows || !ptr) {
    free(rows);
    free(ptr);
    return sk_system_out_of_memory("the rows of this rank", n_rows);
  }
  ptr[0] = 0;
  for (int64_t r = 0, i = 0; r < sys->n; ++r) {
    if (sys->solver_of[r] < 0 || sys->row_ptr[r + 1] == sys->row_ptr[r]) continue;
    rows[i] = sys->solver_of[r];
    ptr[i + 1] = sys->row_ptr[r + 1];
    ++i;
  }
  const sk_clock t0 = sk_system_clock();
  const sk_status status = sk_linsys_set_pattern(sys->linsys, (int)sys->n_owned_dofs, (int)(sys->n_kept - sys->n_nodal),
                                                 n_rows, rows, ptr, sys->cols);
  charge(sys->t_pattern_bridge, t0);
  free(rows);
  free(ptr);
  SK_TRY(status);
  sys->values = sk_linsys_values(sys->linsys);
  sys->pattern_builds++;
  return SK_OK;
}

/* The element positions from scratch (binary search of every entry of every own element). */
static sk_status place_elements(sk_system *sys) {
  const sk_model *m = sys->model;
  int64_t total = 0;
  int dofs[SK_MAX_NEN * 3];
  for (int e = 0; e < m->n_elements; ++e) {
    sys->elem_pos_offset[e] = total;
    if (m->element_part[e] == m->rank) {
      const int nd = sk_element_dofs(m, e, NULL, NULL, NULL);
      total += (int64_t)nd * nd;
    }
  }
  sys->elem_pos_offset[m->n_elements] = total;
  free(sys->elem_pos);
  sys->elem_pos = malloc(sizeof(int64_t) * (size_t)(total > 0 ? total : 1));
  if (!sys->elem_pos) return sk_system_out_of_memory("the element positions", total);
  for (int e = 0; e < m->n_elements; ++e) {
    if (m->element_part[e] != m->rank) continue;
    const int nd = sk_element_dofs(m, e, dofs, NULL, NULL);
    int64_t *pos = sys->elem_pos + sys->elem_pos_offset[e];
    for (int i = 0; i < nd; ++i)
      for (int j = 0; j < nd; ++j) pos[i * nd + j] = sk_system_position(sys, dofs[i], dofs[j]);
  }
  return SK_OK;
}

/* Marks the entries of the current pattern that belong to the bulk graph (row_columns: its node's element graph):
 * the element entries (elem_pos) and, for a node in its own graph, the columns of its own dofs. */
static void mark_bulk(const sk_system *sys, unsigned char *bulk) {
  const sk_model *m = sys->model;
  const int64_t total = sys->elem_pos_offset[m->n_elements];
  memset(bulk, 0, (size_t)sys->row_ptr[m->n_dofs]);
  for (int64_t j = 0; j < total; ++j)
    if (sys->elem_pos[j] >= 0) bulk[sys->elem_pos[j]] = 1;
  for (int a = 0; a < m->n_nodes; ++a) {
    const int *own = sys->bulk_cols + sys->bulk_ptr[a];
    if (!bsearch(&a, own, (size_t)(sys->bulk_ptr[a + 1] - sys->bulk_ptr[a]), sizeof(int), compare_int)) continue;
    for (int i = 0; i < m->dim; ++i)
      for (int k = 0; k < m->dim; ++k) {
        const int64_t p = sk_system_position(sys, (int64_t)a * m->dim + i, (int64_t)a * m->dim + k);
        if (p >= 0) bulk[p] = 1;
      }
  }
}

/* 1 when the dofs' rows and columns (solver_of, role) are those the current pattern was built with: the bulk
 * entries of its dof rows are still right. */
static int same_dof_numbering(const sk_system *sys) {
  const int64_t n_dofs = sys->model->n_dofs;
  return sys->row_ptr && sys->pattern_dof_solver &&
         memcmp(sys->pattern_dof_solver, sys->solver_of, sizeof(int) * (size_t)n_dofs) == 0 &&
         memcmp(sys->pattern_dof_role, sys->role, (size_t)n_dofs) == 0;
}

/* Keeps the dofs' numbering of the pattern just built (same_dof_numbering). */
static sk_status note_dof_numbering(sk_system *sys) {
  const int64_t n_dofs = sys->model->n_dofs;
  if (!sys->pattern_dof_solver) sys->pattern_dof_solver = malloc(sizeof(int) * (size_t)(n_dofs > 0 ? n_dofs : 1));
  if (!sys->pattern_dof_role) sys->pattern_dof_role = malloc((size_t)(n_dofs > 0 ? n_dofs : 1));
  if (!sys->pattern_dof_solver || !sys->pattern_dof_role) return sk_system_out_of_memory("the dofs' rows", n_dofs);
  memcpy(sys->pattern_dof_solver, sys->solver_of, sizeof(int) * (size_t)n_dofs);
  memcpy(sys->pattern_dof_role, sys->role, (size_t)n_dofs);
  return SK_OK;
}

/* The rows from the element graph, the keys and the diagonal. `follow`: the dofs keep the current pattern's numbering
 * (solver_of, role), so the bulk entries of each dof row are those of its current row: they are merged with the
 * row's keys (no sort of the whole row) and each element position follows its entry to where it moved (no binary
 * search of every element entry); else the rows and the positions are computed afresh. */
static sk_status build_rows(sk_system *sys) {
  const sk_model *m = sys->model;
  const int follow = same_dof_numbering(sys);
  const int64_t n = sys->n;
  const int64_t longest = longest_row(sys);
  int64_t bound = 0, k = 0;
  for (int a = 0; a < m->n_nodes; ++a) bound += (int64_t)(sys->bulk_ptr[a + 1] - sys->bulk_ptr[a]) * m->dim * m->dim;
  bound += n + sys->n_extra_keys;
  int64_t *row_ptr = malloc(sizeof(int64_t) * (size_t)(n + 1));
  int *cols = malloc(sizeof(int) * (size_t)(bound > 0 ? bound : 1));
  int *row = malloc(sizeof(int) * (size_t)longest);
  const int64_t old_entries = follow ? sys->row_ptr[m->n_dofs] : 0; /* the dof rows' entries: all element entries */
  int64_t *moved_to = follow ? malloc(sizeof(int64_t) * (size_t)(old_entries > 0 ? old_entries : 1)) : NULL;
  unsigned char *bulk = follow ? malloc((size_t)(old_entries > 0 ? old_entries : 1)) : NULL;
  if (!row_ptr || !cols || !row || (follow && (!moved_to || !bulk))) {
    free(row_ptr), free(cols), free(row), free(moved_to), free(bulk);
    return sk_system_out_of_memory("the sparsity pattern", bound);
  }
  if (follow) mark_bulk(sys, bulk);
  int64_t used = 0;
  row_ptr[0] = 0;
  for (int64_t r = 0; r < n; ++r) {
    int64_t len;
    if (sys->solver_of[r] < 0) {
      len = row_columns(sys, r, &k, row); /* none; skips the row's keys */
    } else if (follow && r < m->n_dofs) {
      /* the current row's bulk entries merged with the row's keys (both sorted) */
      const int64_t nk = key_columns(sys, r, &k, row, 0);
      int64_t q = used, j = 0;
      for (int64_t p = sys->row_ptr[r]; p < sys->row_ptr[r + 1]; ++p) {
        if (!bulk[p]) continue;
        const int c = sys->cols[p];
        while (j < nk && row[j] < c) cols[q++] = row[j++];
        if (j < nk && row[j] == c) ++j;
        moved_to[p] = q;
        cols[q++] = c;
      }
      while (j < nk) cols[q++] = row[j++];
      used = q;
      row_ptr[r + 1] = used;
      continue;
    } else {
      len = r < m->n_dofs ? row_columns(sys, r, &k, row) : key_columns(sys, r, &k, row, 0);
    }
    memcpy(cols + used, row, sizeof(int) * (size_t)len);
    used += len;
    row_ptr[r + 1] = used;
  }
  free(row);
  free(bulk);
  int *shrunk = realloc(cols, sizeof(int) * (size_t)(used > 0 ? used : 1));
  free(sys->row_ptr);
  free(sys->cols);
  sys->row_ptr = row_ptr;
  sys->cols = shrunk ? shrunk : cols;
  sk_status status = SK_OK;
  if (follow) {
    const int64_t total = sys->elem_pos_offset[m->n_elements];
    for (int64_t j = 0; j < total; ++j) sys->elem_pos[j] = sys->elem_pos[j] >= 0 ? moved_to[sys->elem_pos[j]] : -1;
    free(moved_to);
  } else {
    status = place_elements(sys);
  }
  if (status == SK_OK) status = note_dof_numbering(sys);
  if (status == SK_OK) status = hand_to_solver(sys);
  return status;
}

/* ---- settling the pattern of an attempt ------------------------------------------------------------------------ */

/* Adds keys (sorted, unique) to extra_keys (sorted, unique): a merge. */
static sk_status merge_keys(sk_system *sys, const int64_t *keys, int64_t n_keys) {
  if (n_keys == 0) return SK_OK; /* keys may be NULL then (an attempt that declares nothing new) */
  const int64_t *old = sys->extra_keys, n_old = sys->n_extra_keys;
  int64_t *merged = malloc(sizeof(int64_t) * (size_t)(n_old + n_keys + 1));
  if (!merged) return sk_system_out_of_memory("the pattern keys", n_old + n_keys);
  int64_t i = 0, j = 0, n = 0;
  while (i < n_old || j < n_keys) {
    const int64_t next = j == n_keys || (i < n_old && old[i] < keys[j]) ? old[i++] : keys[j++];
    if (n == 0 || merged[n - 1] != next) merged[n++] = next;
  }
  free(sys->extra_keys);
  sys->extra_keys = merged;
  sys->n_extra_keys = n;
  return SK_OK;
}

static sk_status settle_pattern(sk_system *sys, int layout_changed);

/* The attempt's pattern: every term declares its couplings and rows; declared entries the current pattern lacks
 * (on any rank) grow it once, before Newton. */
sk_status sk_system_settle_pattern(sk_system *sys, int layout_changed) {
  const sk_clock t0 = sk_system_clock();
  const sk_status status = settle_pattern(sys, layout_changed);
  charge(sys->t_pattern, t0);
  return status;
}

static sk_status settle_pattern(sk_system *sys, int layout_changed) {
  const int64_t n = sys->n;
  if (!sys->bulk_ptr) SK_TRY(build_bulk_graph(sys));
  sys->n_declared = 0;
  if (!sys->declared_recent) sys->declared_recent = malloc(sizeof(int64_t) * DECLARED_RECENT);
  if (!sys->declared_recent) return sk_system_out_of_memory("the declared pattern", DECLARED_RECENT);
  for (int k = 0; k < DECLARED_RECENT; ++k) sys->declared_recent[k] = -1;
  free(sys->row_local);
  sys->row_local = calloc((size_t)n + 1, 1);
  if (!sys->row_local) return sk_system_out_of_memory("the rows of this rank", n);
  /* extras this rank holds: it may add to an entity's rows (its owner sums) */
  for (int64_t r = sys->model->n_dofs; r < n; ++r) sys->row_local[r] = sys->role[r] != 0;
  sk_status status = SK_OK;
  int n_live; /* a sleeping pair declares nothing */
  sk_term *const *live = sk_system_live_terms(sys, &n_live);
  for (int k = 0; k < n_live && status == SK_OK; ++k) {
    sk_term *term = live[k];
    if (!term->ops->pattern) continue;
    status = term->ops->pattern(term, sys, sys->row_local);
    if (status != SK_OK) sk_error_prefix(status, "%s: pattern: ", term->name);
  }
  SK_TRY(sk_system_collective(sys, status));

  /* declared keys the pattern lacks; with pattern_margin all declarations go on, since the widened pattern is
   * rebuilt around all of them (entries the contact has left behind are dropped, not accumulated) */
  const int renumbered = layout_changed || sys->pattern_n != sys->n_kept || sys->key_columns != n;
  const int rings = sys->solver ? sys->solver->pattern_margin : 0;
  int missing = renumbered;
  for (int64_t k = 0; k < sys->n_declared && !missing; ++k) {
    const int64_t key = sys->declared[k];
    missing = sk_system_position(sys, key / n, key % n) < 0;
  }
  int anywhere = missing;
  MPI_Allreduce(MPI_IN_PLACE, &anywhere, 1, MPI_INT, MPI_MAX, sys->comm);
  if (!anywhere) return SK_OK;
  const sk_clock t0 = sk_system_clock();
  sys->pattern_keys_declared += sys->n_declared;
  int64_t n_send = sys->n_declared;
  sk_sort_unique_i64(sys->declared, &n_send);
  if (renumbered || rings > 0) sys->n_extra_keys = 0; /* renumbered: the keys were in the old numbering */
  SK_TRY(merge_keys(sys, sys->declared, n_send));
  sk_system_widen_keys(sys, rings, &sys->extra_keys, &sys->n_extra_keys);
  sys->key_columns = n;
  sys->pattern_n = sys->n_kept;
  sys->pattern_keys_kept += sys->n_extra_keys;
  status = build_rows(sys);
  charge(sys->t_pattern_build, t0);
  return status;
}
