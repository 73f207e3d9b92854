/* The sparsity pattern of a step attempt (system.h): the bulk element graph, the couplings the terms declare and
 * the diagonal, grown once before Newton; and the sink plugins add through, which refuses entries outside it. */
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

/* A negative index means "no row" (skipped); one at or beyond the number of unknowns is a plugin's error, never a
 * contribution dropped without a word (issue 15, item 15). */
static int row_in_system(sk_system_sink *sink, int64_t row, const char *what) {
  if (row < sink->sys->n) return row >= 0;
  sink_fail(sink, what, (long long)row, (long long)sink->sys->n);
  return 0;
}

static void sink_add_vector(sk_sink *abi, int n, const int64_t *rows, const double *values) {
  sk_system_sink *sink = (sk_system_sink *)abi;
  for (int k = 0; k < n; ++k)
    if (row_in_system(sink, rows[k], "residual entry in row %lld, beyond the %lld unknowns"))
      sink->sys->F_local[rows[k]] += values[k];
}

static void sink_add_rhs(sk_sink *abi, int n, const int64_t *rows, const double *values) {
  sk_system_sink *sink = (sk_system_sink *)abi;
  for (int k = 0; k < n; ++k)
    if (row_in_system(sink, rows[k], "right-hand-side entry in row %lld, beyond the %lld unknowns"))
      sink->sys->rhs_local[rows[k]] += values[k];
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
    if (!row_in_system(sink, rows[i], "Jacobian entry in row %lld, beyond the %lld unknowns")) continue;
    const int r = sys->kept[rows[i]];
    if (r < 0) continue;
    for (int j = 0; j < nc; ++j) {
      if (!row_in_system(sink, cols[j], "Jacobian entry in column %lld, beyond the %lld unknowns")) continue;
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

void sk_system_sink_init(sk_system *sys) {
  sys->sink.abi = (sk_sink){SK_TABLE_HEADER(sk_sink), .add_vector = sink_add_vector, .add_matrix = sink_add_matrix,
                            .add_rhs = sink_add_rhs};
  sys->sink.sys = sys;
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

/* The displacements are the bridge's nodal block (whole-node aggregates, rigid-body-mode nullspace); plugin
 * unknowns after them are constraint rows, which its iterative solvers take through their Schur complement. */
static sk_status hand_to_solver(sk_system *sys) {
  const sk_model *m = sys->model;
  SK_TRY(sk_linsys_set_coordinates(sys->linsys, m->n_nodes, m->dim, m->X));
  SK_TRY(sk_linsys_set_pattern(sys->linsys, (int)sys->n_kept, sys->row_ptr, sys->cols, sys->n_local_rows,
                               sys->local_rows));
  sys->values = sk_linsys_values(sys->linsys);
  sys->pattern_builds++;
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
  SK_TRY(hand_to_solver(sys));

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

/* The bulk columns of row r, the diagonal among them, sorted (the node graph expanded per dof); returns how many. */
static int64_t bulk_row(const sk_system *sys, int64_t r, int *out) {
  const sk_model *m = sys->model;
  int64_t len = 0;
  int diagonal_done = 0;
  if (r < m->n_dofs) {
    const int64_t a = r / m->dim;
    for (int64_t j = m->mass_row_ptr[a]; j < m->mass_row_ptr[a + 1]; ++j)
      for (int i = 0; i < m->dim; ++i) {
        const int c = m->mass_cols[j] * m->dim + i;
        if (!diagonal_done && c >= r) {
          if (c > r) out[len++] = (int)r;
          diagonal_done = 1;
        }
        out[len++] = c;
      }
  }
  if (!diagonal_done) out[len++] = (int)r;
  return len;
}

/* The rows rebuilt from the bulk graph, the diagonal and extra_keys within the same unknowns (a pattern grown, or
 * with pattern_margin re-widened around the current couplings): each row is a merge of sorted lists, and every
 * element position follows its bulk entry (always kept) to where it moved, instead of build_pattern's sort of every
 * row and binary search of every element entry (6.6 % of a full two-tori contact step, where each new contact
 * coupling grew the pattern). */
static sk_status rebuild_rows(sk_system *sys) {
  const sk_model *m = sys->model;
  const int64_t nk = sys->n_kept, old_entries = sys->row_ptr[nk];
  const int64_t *key = sys->extra_keys, n_keys = sys->n_extra_keys;
  int64_t bound = nk + n_keys, longest = 1;
  for (int64_t a = 0; a < m->n_nodes; ++a) {
    const int64_t len = (m->mass_row_ptr[a + 1] - m->mass_row_ptr[a]) * m->dim;
    bound += len * m->dim;
    if (len + 1 > longest) longest = len + 1;
  }
  int64_t *row_ptr = malloc(sizeof(int64_t) * (size_t)(nk + 1));
  int *cols = malloc(sizeof(int) * (size_t)bound);
  int *bulk = malloc(sizeof(int) * (size_t)longest);
  int64_t *moved_to = malloc(sizeof(int64_t) * (size_t)(old_entries > 0 ? old_entries : 1));
  if (!row_ptr || !cols || !bulk || !moved_to) {
    free(row_ptr);
    free(cols);
    free(bulk);
    free(moved_to);
    return out_of_memory("the rebuilt sparsity pattern", bound);
  }
  int64_t used = 0, k = 0;
  row_ptr[0] = 0;
  for (int64_t r = 0; r < nk; ++r) {
    const int64_t n_bulk = bulk_row(sys, r, bulk);
    int64_t b = 0;
    while (b < n_bulk || (k < n_keys && key[k] / nk == r)) {
      const int from_key = b >= n_bulk || (k < n_keys && key[k] / nk == r && key[k] % nk < bulk[b]);
      const int c = from_key ? (int)(key[k++] % nk) : bulk[b++];
      if (used == row_ptr[r] || cols[used - 1] != c) cols[used++] = c;
    }
    row_ptr[r + 1] = used;
    int64_t q = row_ptr[r];
    for (int64_t p = sys->row_ptr[r]; p < sys->row_ptr[r + 1]; ++p) {
      while (q < used && cols[q] < sys->cols[p]) ++q;
      moved_to[p] = q < used && cols[q] == sys->cols[p] ? q : -1;
    }
  }
  free(bulk);
  free(sys->row_ptr);
  free(sys->cols);
  sys->row_ptr = row_ptr;
  sys->cols = cols;
  int dofs[SK_MAX_NEN * 3];
  for (int e = 0; e < m->n_elements; ++e) {
    if (m->element_part[e] != m->rank) continue;
    const int nd = sk_element_dofs(m, e, dofs, NULL, NULL);
    int64_t *pos = sys->elem_pos + sys->elem_pos_offset[e];
    for (int j = 0; j < nd * nd; ++j) pos[j] = moved_to[pos[j]];
  }
  free(moved_to);
  return hand_to_solver(sys);
}

static void sort_unique(int64_t *keys, int64_t *n) {
  if (*n < 2) return; /* also keys == NULL with none */
  qsort(keys, (size_t)*n, sizeof(int64_t), compare_i64);
  int64_t unique = 0;
  for (int64_t k = 0; k < *n; ++k)
    if (k == 0 || keys[k] != keys[unique - 1]) keys[unique++] = keys[k];
  *n = unique;
}

/* The neighbourhoods the pattern widens over. Unknowns are grouped by "points": the mesh nodes (0 .. n_nodes-1,
 * dim unknowns each), then one point per kept plugin unknown. A mesh node's neighbours are itself and the nodes of
 * contact surfaces among its element graph's (the mass graph: interior nodes never enter a contact coupling, and
 * widening through them filled the condensed operator for nothing); a plugin unknown's are the plugin unknowns
 * anchored at the neighbours of its anchor node (sk_layout.extra_anchor), or itself without an anchor. */
typedef struct {
  const sk_model *m;
  int64_t n_points;
  int64_t *anchor_node;   /* per plugin unknown (kept numbering - n_dofs): its anchor node, or -1 */
  int64_t *anchored_ptr;  /* n_nodes + 1: CSR of the plugin unknowns anchored at each node */
  int64_t *anchored;
  unsigned char *on_surface; /* n_nodes: 1 on a contact pair's slave or master surface */
} widening;

static void widening_free(widening *w) {
  free(w->anchor_node);
  free(w->anchored_ptr);
  free(w->anchored);
  free(w->on_surface);
}

static int widening_init(widening *w, const sk_system *sys) {
  const sk_model *m = sys->model;
  const int64_t n_plugin = sys->n_kept - m->n_dofs;
  memset(w, 0, sizeof *w);
  w->m = m;
  w->n_points = m->n_nodes + n_plugin;
  w->anchor_node = malloc(sizeof(int64_t) * (size_t)(n_plugin > 0 ? n_plugin : 1));
  w->anchored_ptr = calloc((size_t)m->n_nodes + 1, sizeof(int64_t));
  w->anchored = malloc(sizeof(int64_t) * (size_t)(n_plugin > 0 ? n_plugin : 1));
  w->on_surface = calloc((size_t)m->n_nodes + 1, 1);
  if (!w->anchor_node || !w->anchored_ptr || !w->anchored || !w->on_surface) {
    widening_free(w);
    return 0;
  }
  for (int k = 0; k < m->n_pairs; ++k) {
    const sk_contact_pair *pair = &m->pairs[k];
    for (int j = 0; j < pair->slave.n_nodes; ++j) w->on_surface[pair->slave.nodes[j]] = 1;
    for (int j = 0; !pair->has_obstacle && j < pair->master.n_nodes; ++j) w->on_surface[pair->master.nodes[j]] = 1;
  }
  for (int64_t e = 0; e < n_plugin; ++e) {
    const int64_t full = sys->full_of_kept[m->n_dofs + e];
    w->anchor_node[e] = -1;
    for (int k = 0; k < sys->n_terms; ++k) {
      const sk_term *term = sys->terms[k];
      if (full < term->extra_offset || full >= term->extra_offset + term->n_extra) continue;
      if (term->anchor && term->anchor[full - term->extra_offset] >= 0)
        w->anchor_node[e] = term->anchor[full - term->extra_offset] / m->dim;
      break;
    }
    if (w->anchor_node[e] >= 0) w->anchored_ptr[w->anchor_node[e] + 1]++;
  }
  for (int64_t a = 0; a < m->n_nodes; ++a) w->anchored_ptr[a + 1] += w->anchored_ptr[a];
  int64_t *fill = calloc((size_t)m->n_nodes + 1, sizeof(int64_t));
  if (!fill) {
    widening_free(w);
    return 0;
  }
  for (int64_t e = 0; e < n_plugin; ++e)
    if (w->anchor_node[e] >= 0) {
      const int64_t a = w->anchor_node[e];
      w->anchored[w->anchored_ptr[a] + fill[a]++] = m->n_nodes + e;
    }
  free(fill);
  return 1;
}

/* The neighbour points of `point` into out (when not NULL); returns how many. */
static int64_t neighbours(const widening *w, int64_t point, int64_t *out) {
  const sk_model *m = w->m;
  int64_t n = 0;
  if (point < m->n_nodes) {
    if (out) out[n] = point; /* itself, also when no element holds it */
    ++n;
    for (int64_t j = m->mass_row_ptr[point]; j < m->mass_row_ptr[point + 1]; ++j) {
      if (m->mass_cols[j] == point || !w->on_surface[m->mass_cols[j]]) continue;
      if (out) out[n] = m->mass_cols[j];
      ++n;
    }
    return n;
  }
  const int64_t a = w->anchor_node[point - m->n_nodes];
  if (a < 0) {
    if (out) out[0] = point;
    return 1;
  }
  for (int64_t j = m->mass_row_ptr[a]; j < m->mass_row_ptr[a + 1]; ++j) {
    const int64_t b = m->mass_cols[j];
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
 * keys). The added entries stay zero. On failure (memory) the keys stay as they are: widening only saves work. */
static void widen_keys(const sk_system *sys, int rings, int64_t **keys, int64_t *n_keys) {
  const sk_model *m = sys->model;
  const int64_t nk = sys->n_kept;
  widening w;
  if (rings <= 0 || *n_keys == 0 || !m->mass_row_ptr || !widening_init(&w, sys)) return;
  const int64_t np = w.n_points;
  int64_t n = *n_keys;
  int64_t *pairs = malloc(sizeof(int64_t) * (size_t)n);
  if (!pairs) {
    widening_free(&w);
    return;
  }
  for (int64_t k = 0; k < n; ++k) {
    const int64_t r = (*keys)[k] / nk, c = (*keys)[k] % nk;
    pairs[k] = (r < m->n_dofs ? r / m->dim : m->n_nodes + (r - m->n_dofs)) * np +
               (c < m->n_dofs ? c / m->dim : m->n_nodes + (c - m->n_dofs));
  }
  sort_unique(pairs, &n);
  /* plugin unknowns are coupled among themselves only as declared: a multiplier's block with its neighbours' would
   * break the block-diagonal D that condensation eliminates through (and fill the condensed operator) */
  const int64_t n_declared_pairs = n;
  int64_t *declared_pairs = malloc(sizeof(int64_t) * (size_t)n);
  if (!declared_pairs) {
    free(pairs);
    widening_free(&w);
    return;
  }
  memcpy(declared_pairs, pairs, sizeof(int64_t) * (size_t)n);
  for (int ring = 0; ring < 2 * rings && pairs; ++ring) {
    int64_t *wider = widen_pairs(&w, pairs, n, ring % 2, &n);
    free(pairs);
    pairs = wider;
  }
  widening_free(&w);
  if (pairs) {
    int64_t kept = 0;
    for (int64_t k = 0; k < n; ++k) {
      const int both_plugin = pairs[k] / np >= m->n_nodes && pairs[k] % np >= m->n_nodes;
      if (!both_plugin ||
          bsearch(&pairs[k], declared_pairs, (size_t)n_declared_pairs, sizeof(int64_t), compare_i64))
        pairs[kept++] = pairs[k];
    }
    n = kept;
  }
  free(declared_pairs);
  if (!pairs) return;
  /* the unknowns of each point pair (dim x dim, or fewer for plugin unknowns) */
  int64_t count = 0;
  for (int64_t k = 0; k < n; ++k)
    count += (int64_t)(pairs[k] / np < m->n_nodes ? m->dim : 1) * (pairs[k] % np < m->n_nodes ? m->dim : 1);
  int64_t *wide = malloc(sizeof(int64_t) * (size_t)(count > 0 ? count : 1));
  if (!wide) {
    free(pairs);
    return;
  }
  int64_t used = 0;
  for (int64_t k = 0; k < n; ++k) {
    const int64_t a = pairs[k] / np, b = pairs[k] % np;
    const int64_t r0 = a < m->n_nodes ? a * m->dim : m->n_dofs + (a - m->n_nodes), nr = a < m->n_nodes ? m->dim : 1;
    const int64_t c0 = b < m->n_nodes ? b * m->dim : m->n_dofs + (b - m->n_nodes), nc = b < m->n_nodes ? m->dim : 1;
    for (int64_t r = r0; r < r0 + nr; ++r)
      for (int64_t c = c0; c < c0 + nc; ++c)
        wide[used++] = r * nk + c;
  }
  free(pairs);
  sort_unique(wide, &used);
  free(*keys);
  *keys = wide;
  *n_keys = used;
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
  int64_t n = sys->n_extra_keys + total;
  sort_unique(merged, &n);
  sys->n_extra_keys = n;
  return SK_OK;
}

/* The attempt's pattern: every term declares its couplings and rows; declared entries the current pattern lacks
 * (on any rank) grow it once, before Newton. */
sk_status sk_system_settle_pattern(sk_system *sys, int layout_changed) {
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

  /* declared keys the pattern lacks; with pattern_margin all declarations go on, since the widened pattern is
   * rebuilt around all of them (entries the contact has left behind are dropped, not accumulated) */
  const int renumbered = layout_changed || sys->pattern_n != nk;
  const int rings = sys->solver ? sys->solver->pattern_margin : 0;
  int64_t n_send = 0;
  int flags[2] = {renumbered, rows_changed || renumbered}, anywhere[2]; /* {keys missing, rows changed} */
  for (int64_t k = 0; k < sys->n_declared; ++k) {
    const int64_t key = sys->declared[k];
    const int missing = renumbered || sk_system_position(sys, (int)(key / nk), (int)(key % nk)) < 0;
    flags[0] |= missing;
    if (missing || rings > 0) sys->declared[n_send++] = key;
  }
  MPI_Allreduce(flags, anywhere, 2, MPI_INT, MPI_MAX, sys->comm);
  if (!anywhere[0] && !anywhere[1]) return SK_OK;
  if (!anywhere[0]) return hand_to_solver(sys); /* only the rows of this rank changed */
  sort_unique(sys->declared, &n_send); /* only now: with a margin, n_send is every declaration of the step */
  if (renumbered || rings > 0) sys->n_extra_keys = 0; /* renumbered: the keys were in the old numbering */
  SK_TRY(merge_keys(sys, sys->declared, n_send));
  widen_keys(sys, rings, &sys->extra_keys, &sys->n_extra_keys); /* all ranks' keys, widened alike on every rank */
  return renumbered ? build_pattern(sys) : rebuild_rows(sys);
}
