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

/* ---- the plugins' sink ------------------------------------------------------------------------------------------ */

static void sink_fail(sk_system_sink *sink, const char *fmt, long long a, long long b) {
  if (sink->failed) return;
  sink->failed = 1;
  snprintf(sink->message, sizeof sink->message, fmt, a, b);
}

/* The unknowns over all ranks, in the ABI numbering. */
static int64_t abi_count(const sk_system *sys) { return sys->n - sys->extra_shift; }

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
    if (!grown) return out_of_memory("the declared pattern", cap);
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
  if (!count) return out_of_memory("the element graph", nn);
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
    return out_of_memory("the element graph", total);
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
    return out_of_memory("the element graph", nn);
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
    return out_of_memory("the rows of this rank", n_rows);
  }
  ptr[0] = 0;
  for (int64_t r = 0, i = 0; r < sys->n; ++r) {
    if (sys->solver_of[r] < 0 || sys->row_ptr[r + 1] == sys->row_ptr[r]) continue;
    rows[i] = sys->solver_of[r];
    ptr[i + 1] = sys->row_ptr[r + 1];
    ++i;
  }
  const sk_status status = sk_linsys_set_pattern(sys->linsys, (int)sys->n_owned_dofs, (int)(sys->n_kept - sys->n_nodal),
                                                 n_rows, rows, ptr, sys->cols);
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
  if (!sys->elem_pos) return out_of_memory("the element positions", total);
  for (int e = 0; e < m->n_elements; ++e) {
    if (m->element_part[e] != m->rank) continue;
    const int nd = sk_element_dofs(m, e, dofs, NULL, NULL);
    int64_t *pos = sys->elem_pos + sys->elem_pos_offset[e];
    for (int i = 0; i < nd; ++i)
      for (int j = 0; j < nd; ++j) pos[i * nd + j] = sk_system_position(sys, dofs[i], dofs[j]);
  }
  return SK_OK;
}

/* The rows from the element graph, the keys and the diagonal. `follow`: the columns' numbering is the one of the
 * current pattern, so each element position follows its entry (always kept) to where it moved — a merge per row
 * instead of a binary search of every element entry (6.6 % of a full two-tori contact step, where each new contact
 * coupling grew the pattern); else the positions are computed afresh. */
static sk_status build_rows(sk_system *sys, int follow) {
  const int64_t n = sys->n;
  const int64_t longest = longest_row(sys);
  int64_t bound = 0, k = 0;
  for (int a = 0; a < sys->model->n_nodes; ++a) bound += (int64_t)(sys->bulk_ptr[a + 1] - sys->bulk_ptr[a]) * sys->model->dim * sys->model->dim;
  bound += n + sys->n_extra_keys;
  int64_t *row_ptr = malloc(sizeof(int64_t) * (size_t)(n + 1));
  int *cols = malloc(sizeof(int) * (size_t)(bound > 0 ? bound : 1));
  int *row = malloc(sizeof(int) * (size_t)longest);
  const int64_t old_entries = follow && sys->row_ptr ? sys->row_ptr[n] : 0;
  int64_t *moved_to = follow ? malloc(sizeof(int64_t) * (size_t)(old_entries > 0 ? old_entries : 1)) : NULL;
  if (!row_ptr || !cols || !row || (follow && !moved_to)) {
    free(row_ptr), free(cols), free(row), free(moved_to);
    return out_of_memory("the sparsity pattern", bound);
  }
  int64_t used = 0;
  row_ptr[0] = 0;
  for (int64_t r = 0; r < n; ++r) {
    const int64_t len = row_columns(sys, r, &k, row);
    memcpy(cols + used, row, sizeof(int) * (size_t)len);
    if (follow) {
      int64_t q = used;
      for (int64_t p = sys->row_ptr[r]; p < sys->row_ptr[r + 1]; ++p) {
        while (q < used + len && cols[q] < sys->cols[p]) ++q;
        moved_to[p] = q < used + len && cols[q] == sys->cols[p] ? q : -1;
      }
    }
    used += len;
    row_ptr[r + 1] = used;
  }
  free(row);
  int *shrunk = realloc(cols, sizeof(int) * (size_t)(used > 0 ? used : 1));
  free(sys->row_ptr);
  free(sys->cols);
  sys->row_ptr = row_ptr;
  sys->cols = shrunk ? shrunk : cols;
  sk_status status = SK_OK;
  if (follow) {
    const sk_model *m = sys->model;
    const int64_t total = sys->elem_pos_offset[m->n_elements];
    for (int64_t j = 0; j < total; ++j) sys->elem_pos[j] = moved_to[sys->elem_pos[j]];
    free(moved_to);
  } else {
    status = place_elements(sys);
  }
  if (status == SK_OK) status = hand_to_solver(sys);
  return status;
}

/* ---- widening (solver.pattern_margin) ------------------------------------------------------------------------- */

static void sort_unique(int64_t *keys, int64_t *n) {
  if (*n < 2) return; /* also keys == NULL with none */
  qsort(keys, (size_t)*n, sizeof(int64_t), compare_i64);
  int64_t unique = 0;
  for (int64_t k = 0; k < *n; ++k)
    if (k == 0 || keys[k] != keys[unique - 1]) keys[unique++] = keys[k];
  *n = unique;
}

/* The neighbourhoods the pattern widens over. Unknowns are grouped by "points": the nodes (0 .. n_nodes-1, dim
 * unknowns each), then one point per extra unknown. A node's neighbours are itself and the contact-surface nodes that
 * share an element with it (model.h: surface_ptr; interior nodes never enter a contact coupling, and widening
 * through them filled the condensed operator for nothing) that this rank holds; an extra unknown's are the extras
 * anchored at the neighbours of its anchor node (sk_layout.extra_anchor), or itself without an anchor. */
typedef struct {
  const sk_system *sys;
  int64_t n_points;
  int64_t *anchor_node;   /* per extra (local index - n_dofs): its anchor node, or -1 */
  int64_t *anchored_ptr;  /* n_nodes + 1: CSR of the extras anchored at each node */
  int64_t *anchored;
} widening;

static void widening_free(widening *w) {
  free(w->anchor_node);
  free(w->anchored_ptr);
  free(w->anchored);
}

static int widening_init(widening *w, const sk_system *sys) {
  const sk_model *m = sys->model;
  const int64_t n_extras = sys->n - m->n_dofs;
  memset(w, 0, sizeof *w);
  w->sys = sys;
  w->n_points = m->n_nodes + n_extras;
  w->anchor_node = malloc(sizeof(int64_t) * (size_t)(n_extras > 0 ? n_extras : 1));
  w->anchored_ptr = calloc((size_t)m->n_nodes + 1, sizeof(int64_t));
  w->anchored = malloc(sizeof(int64_t) * (size_t)(n_extras > 0 ? n_extras : 1));
  if (!w->anchor_node || !w->anchored_ptr || !w->anchored) {
    widening_free(w);
    return 0;
  }
  for (int64_t e = 0; e < n_extras; ++e) w->anchor_node[e] = -1;
  for (int k = 0; k < sys->n_terms; ++k) {
    const sk_term *term = sys->terms[k];
    for (int64_t j = 0; term->anchor && j < term->n_extra; ++j) {
      const int64_t local = term->anchor[j] >= 0 ? sk_system_local_of(sys, term->anchor[j]) : -1;
      if (local >= 0 && local < m->n_dofs) w->anchor_node[term->extra_local + j - m->n_dofs] = local / m->dim;
    }
  }
  for (int64_t e = 0; e < n_extras; ++e)
    if (w->anchor_node[e] >= 0) w->anchored_ptr[w->anchor_node[e] + 1]++;
  for (int64_t a = 0; a < m->n_nodes; ++a) w->anchored_ptr[a + 1] += w->anchored_ptr[a];
  int64_t *fill = calloc((size_t)m->n_nodes + 1, sizeof(int64_t));
  if (!fill) {
    widening_free(w);
    return 0;
  }
  for (int64_t e = 0; e < n_extras; ++e)
    if (w->anchor_node[e] >= 0) {
      const int64_t a = w->anchor_node[e];
      w->anchored[w->anchored_ptr[a] + fill[a]++] = m->n_nodes + e;
    }
  free(fill);
  return 1;
}

/* The neighbour points of `point` into out (when not NULL); returns how many. */
static int64_t neighbours(const widening *w, int64_t point, int64_t *out) {
  const sk_model *m = w->sys->model;
  int64_t n = 0;
  if (point < m->n_nodes) {
    for (int64_t j = m->surface_ptr[point]; j < m->surface_ptr[point + 1]; ++j) {
      if (out) out[n] = m->surface_cols[j];
      ++n;
    }
    if (n == 0) { /* itself, also when it is on no contact surface */
      if (out) out[0] = point;
      n = 1;
    }
    return n;
  }
  const int64_t a = w->anchor_node[point - m->n_nodes];
  if (a < 0) {
    if (out) out[0] = point;
    return 1;
  }
  for (int64_t j = m->surface_ptr[a]; j < m->surface_ptr[a + 1]; ++j) {
    const int64_t b = m->surface_cols[j];
    for (int64_t k = w->anchored_ptr[b]; k < w->anchored_ptr[b + 1]; ++k) {
      if (out) out[n] = w->anchored[k];
      ++n;
    }
  }
  return n;
}

/* Point pairs (a, b) -> (a', b) for every neighbour a' of a (side 0), or (a, b') (side 1); sorted, unique. */
static int64_t *widen_pairs(const widening *w, const int64_t *pairs, int64_t n, int side, int64_t *n_out) {
  const int64_t np = w->n_points;
  int64_t count = 0;
  for (int64_t k = 0; k < n; ++k) count += neighbours(w, side == 0 ? pairs[k] / np : pairs[k] % np, NULL);
  int64_t *out = malloc(sizeof(int64_t) * (size_t)(count > 0 ? count : 1));
  if (!out) return NULL;
  int64_t used = 0;
  for (int64_t k = 0; k < n; ++k) {
    const int64_t a = pairs[k] / np, b = pairs[k] % np;
    const int64_t first = used;
    used += neighbours(w, side == 0 ? a : b, out + used);
    for (int64_t j = first; j < used; ++j) out[j] = side == 0 ? out[j] * np + b : a * np + out[j];
  }
  sort_unique(out, &used);
  *n_out = used;
  return out;
}

/* The keys widened by `rings` rings of neighbours on both sides (see widening): the couplings a contact declares
 * move with sliding to the neighbouring faces' nodes, and each growth of the pattern rebuilds the solver's matrix
 * and the condensed operator (0.3 s per step on the full two-tori, where every contact step grew it by a few hundred
 * keys). The added entries stay zero. Each rank widens its own keys: the owned rows of the matrix, the union over
 * ranks, are the widened union. On failure (memory) the keys stay as they are: widening only saves work. */
static void widen_keys(const sk_system *sys, int rings, int64_t **keys, int64_t *n_keys) {
  const sk_model *m = sys->model;
  const int64_t n = sys->n;
  widening w;
  if (rings <= 0 || *n_keys == 0 || !m->surface_ptr || !widening_init(&w, sys)) return;
  const int64_t np = w.n_points;
  int64_t count = *n_keys;
  int64_t *pairs = malloc(sizeof(int64_t) * (size_t)count);
  if (!pairs) {
    widening_free(&w);
    return;
  }
  for (int64_t k = 0; k < count; ++k) {
    const int64_t r = (*keys)[k] / n, c = (*keys)[k] % n;
    pairs[k] = (r < m->n_dofs ? r / m->dim : m->n_nodes + (r - m->n_dofs)) * np +
               (c < m->n_dofs ? c / m->dim : m->n_nodes + (c - m->n_dofs));
  }
  sort_unique(pairs, &count);
  /* extra unknowns are coupled among themselves only as declared: a multiplier's block with its neighbours' would
   * break the block-diagonal D that condensation eliminates through (and fill the condensed operator) */
  const int64_t n_declared_pairs = count;
  int64_t *declared_pairs = malloc(sizeof(int64_t) * (size_t)count);
  if (!declared_pairs) {
    free(pairs);
    widening_free(&w);
    return;
  }
  memcpy(declared_pairs, pairs, sizeof(int64_t) * (size_t)count);
  for (int ring = 0; ring < 2 * rings && pairs; ++ring) {
    int64_t *wider = widen_pairs(&w, pairs, count, ring % 2, &count);
    free(pairs);
    pairs = wider;
  }
  widening_free(&w);
  if (pairs) {
    int64_t kept = 0;
    for (int64_t k = 0; k < count; ++k) {
      const int both_extras = pairs[k] / np >= m->n_nodes && pairs[k] % np >= m->n_nodes;
      if (!both_extras || bsearch(&pairs[k], declared_pairs, (size_t)n_declared_pairs, sizeof(int64_t), compare_i64))
        pairs[kept++] = pairs[k];
    }
    count = kept;
  }
  free(declared_pairs);
  if (!pairs) return;
  /* the unknowns of each point pair (dim x dim, or fewer for extras) */
  int64_t total = 0;
  for (int64_t k = 0; k < count; ++k)
    total += (int64_t)(pairs[k] / np < m->n_nodes ? m->dim : 1) * (pairs[k] % np < m->n_nodes ? m->dim : 1);
  int64_t *wide = malloc(sizeof(int64_t) * (size_t)(total > 0 ? total : 1));
  if (!wide) {
    free(pairs);
    return;
  }
  int64_t used = 0;
  for (int64_t k = 0; k < count; ++k) {
    const int64_t a = pairs[k] / np, b = pairs[k] % np;
    const int64_t r0 = a < m->n_nodes ? a * m->dim : m->n_dofs + (a - m->n_nodes), nr = a < m->n_nodes ? m->dim : 1;
    const int64_t c0 = b < m->n_nodes ? b * m->dim : m->n_dofs + (b - m->n_nodes), nc = b < m->n_nodes ? m->dim : 1;
    for (int64_t r = r0; r < r0 + nr; ++r)
      for (int64_t c = c0; c < c0 + nc; ++c)
        if (sys->solver_of[r] >= 0 && sys->solver_of[c] >= 0) wide[used++] = r * n + c;
  }
  free(pairs);
  sort_unique(wide, &used);
  free(*keys);
  *keys = wide;
  *n_keys = used;
}

/* ---- settling the pattern of an attempt ------------------------------------------------------------------------ */

/* Adds keys to extra_keys (sorted, unique). */
static sk_status merge_keys(sk_system *sys, const int64_t *keys, int64_t n_keys) {
  if (n_keys == 0) return SK_OK; /* keys may be NULL then (an attempt that declares nothing new) */
  int64_t *merged = realloc(sys->extra_keys, sizeof(int64_t) * (size_t)(sys->n_extra_keys + n_keys + 1));
  if (!merged) return out_of_memory("the pattern keys", sys->n_extra_keys + n_keys);
  sys->extra_keys = merged;
  memcpy(merged + sys->n_extra_keys, keys, sizeof(int64_t) * (size_t)n_keys);
  int64_t n = sys->n_extra_keys + n_keys;
  sort_unique(merged, &n);
  sys->n_extra_keys = n;
  return SK_OK;
}

/* The attempt's pattern: every term declares its couplings and rows; declared entries the current pattern lacks
 * (on any rank) grow it once, before Newton. */
sk_status sk_system_settle_pattern(sk_system *sys, int layout_changed) {
  const int64_t n = sys->n;
  if (!sys->bulk_ptr) SK_TRY(build_bulk_graph(sys));
  sys->n_declared = 0;
  if (!sys->declared_recent) sys->declared_recent = malloc(sizeof(int64_t) * DECLARED_RECENT);
  if (!sys->declared_recent) return out_of_memory("the declared pattern", DECLARED_RECENT);
  for (int k = 0; k < DECLARED_RECENT; ++k) sys->declared_recent[k] = -1;
  free(sys->row_local);
  sys->row_local = calloc((size_t)n + 1, 1);
  if (!sys->row_local) return out_of_memory("the rows of this rank", n);
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
  int64_t n_send = sys->n_declared;
  sort_unique(sys->declared, &n_send);
  if (renumbered || rings > 0) sys->n_extra_keys = 0; /* renumbered: the keys were in the old numbering */
  SK_TRY(merge_keys(sys, sys->declared, n_send));
  widen_keys(sys, rings, &sys->extra_keys, &sys->n_extra_keys);
  sys->key_columns = n;
  const int follow = !renumbered && sys->row_ptr != NULL;
  sys->pattern_n = sys->n_kept;
  return build_rows(sys, follow);
}
