/* The widening of the pattern by solver.pattern_margin (system.h): the declared couplings grown by rings of
 * neighbouring contact-surface nodes, so that a contact zone that moves on keeps its entries in the pattern and the
 * matrix is not rebuilt at every step. */
#include <stdlib.h>
#include <string.h>

#include "system.h"

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
  int n_live;
  sk_term *const *live = sk_system_live_terms(sys, &n_live);
  for (int k = 0; k < n_live; ++k) {
    const sk_term *term = live[k];
    for (int64_t h = 0; term->anchor && h < term->n_held; ++h) {
      const int64_t anchor = term->anchor[term->held[h]];
      const int64_t local = anchor >= 0 ? sk_system_local_of(sys, anchor) : -1;
      if (local >= 0 && local < m->n_dofs) w->anchor_node[term->extra_local + h - m->n_dofs] = local / m->dim;
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

/* Point pairs (a, b) -> (a', b) for every neighbour a' of a (side 0), or (a, b') (side 1); sorted, unique. The pairs
 * are widened on their second point run by run of equal first points, each run's widened pairs sorted and made
 * unique at once: neighbouring points share most neighbours, so the repeats never pile up (they were three to four
 * times the result and, with qsort's buffer, a contact rank's peak heap: docs/scaling.md). Side 0 is side 1 of the
 * transposed pairs. `pairs` (sorted, unique) is reordered; NULL when out of memory. */
static void transpose_pairs(int64_t *pairs, int64_t n, int64_t np) {
  for (int64_t k = 0; k < n; ++k) pairs[k] = (pairs[k] % np) * np + pairs[k] / np;
  sk_sort_i64(pairs, n);
}

static int64_t *widen_pairs(const widening *w, int64_t *pairs, int64_t n, int side, int64_t *n_out) {
  const int64_t np = w->n_points;
  if (side == 0) transpose_pairs(pairs, n, np);
  int64_t capacity = 4 * n + 64, used = 0;
  int64_t *out = malloc(sizeof(int64_t) * (size_t)capacity);
  for (int64_t k = 0; out && k < n;) {
    const int64_t a = pairs[k] / np, first = used;
    for (; k < n && pairs[k] / np == a; ++k) {
      const int64_t count = neighbours(w, pairs[k] % np, NULL);
      if (used + count > capacity) {
        capacity = capacity + capacity / 2 + count;
        int64_t *grown = realloc(out, sizeof(int64_t) * (size_t)capacity);
        if (!grown) {
          free(out);
          out = NULL;
          break;
        }
        out = grown;
      }
      const int64_t at = used;
      used += neighbours(w, pairs[k] % np, out + used);
      for (int64_t j = at; j < used; ++j) out[j] += a * np;
    }
    if (!out) break;
    int64_t run = used - first;
    sk_sort_unique_i64(out + first, &run);
    used = first + run;
  }
  if (!out) return NULL;
  if (side == 0) transpose_pairs(out, used, np);
  *n_out = used;
  return out;
}

/* The keys widened by `rings` rings of neighbours on both sides (see widening): the couplings a contact declares
 * move with sliding to the neighbouring faces' nodes, and each growth of the pattern rebuilds the solver's matrix
 * and the condensed operator (0.3 s per step on the full two-tori, where every contact step grew it by a few hundred
 * keys). The added entries stay zero. Each rank widens its own keys: the owned rows of the matrix, the union over
 * ranks, are the widened union. On failure (memory) the keys stay as they are: widening only saves work. */
void sk_system_widen_keys(const sk_system *sys, int rings, int64_t **keys, int64_t *n_keys) {
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
  sk_sort_unique_i64(pairs, &count);
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
      if (!both_extras || bsearch(&pairs[k], declared_pairs, (size_t)n_declared_pairs, sizeof(int64_t), sk_compare_i64))
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
  sk_sort_unique_i64(wide, &used);
  free(*keys);
  *keys = wide;
  *n_keys = used;
}
