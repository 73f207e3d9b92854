/* The host's broad phase over the pairs created by `bodies:` (broad_phase.h).
 *
 * Per body: the box of its boundary nodes at the start of the step and at the current iterate (a face moves
 * linearly between the two, so it stays inside), one pass over the nodes and one reduction over the ranks. Then a
 * sort and sweep along x: bodies sorted by their boxes' lower x; each one meets only the bodies after it whose lower
 * x lies below its upper x plus the largest margin, and those that overlap in y (and z) too make the sweep's overlap
 * list. Each overlap finds its created pairs by binary search in the pairs sorted by their two bodies, and a pair is
 * near when its own margin still makes the boxes overlap. Only the near pairs are in the system's live terms (the
 * terms a step attempt visits): a pair apart costs nothing per step, and nothing here is N x N (storage: the pairs
 * created, the bodies, the overlaps). */
#include <math.h>
#include <stdlib.h>

#include "broad_phase.h"
#include "term_plugin.h"

typedef struct {
  int body[2];      /* the smaller body first (the key) */
  double margin;    /* the inflation of this pair's boxes */
  sk_term *term;    /* its term, and the term's place among the system's terms (found at the first sweep) */
  int term_index;
  unsigned stamp;   /* the sweep that found it near */
  unsigned char awake;
} broad_pair;

typedef struct sk_broad_phase {
  int n_bodies;
  const sk_surface **boundary; /* per body: a surface over its whole boundary, or NULL (no created pair) */
  double *box;                 /* 6 per body: lo[3], then -hi[3] (one MIN reduction) */
  int *order;                  /* bodies by lower x */
  broad_pair *pairs;           /* the registered pairs, in the order of registration */
  int n_pairs, cap_pairs;
  int *by_key;                 /* pair ids sorted by their two bodies */
  int *overlap;                /* 2 per body pair whose boxes overlap at the last sweep (largest margin) */
  int n_overlap, cap_overlap;
  int *awake;                  /* the ids of the pairs awake (near at the attempt's start, or woken since) */
  int n_awake;
  int *fresh;                  /* scratch: the ids near at a sweep */
  int *others;                 /* the indices of the terms the broad phase does not drive */
  int n_others, ready;
  unsigned sweep;
  uint64_t version;            /* the system's x_version of the boxes */
  double margin_max;
} sk_broad_phase;

static sk_status no_memory(int n) {
  return sk_error_set(SK_ERR_NOMEM, "out of memory for the broad phase of %d bodies", n);
}

sk_status sk_broad_phase_add(sk_system *sys, const sk_contact_pair *pair, double margin, int *id) {
  const int n = sys->model->n_bodies;
  sk_broad_phase *bp = sys->broad;
  if (!bp) {
    bp = calloc(1, sizeof *bp);
    if (bp) {
      bp->n_bodies = n;
      bp->boundary = calloc((size_t)n, sizeof *bp->boundary);
      bp->box = malloc(sizeof(double) * 6 * (size_t)n);
      bp->order = malloc(sizeof(int) * (size_t)n);
      bp->version = UINT64_MAX;
    }
    sys->broad = bp;
    if (!bp || !bp->boundary || !bp->box || !bp->order) return no_memory(n);
  }
  if (bp->n_pairs == bp->cap_pairs) {
    const int cap = 2 * bp->cap_pairs + 16;
    broad_pair *grown = realloc(bp->pairs, sizeof *grown * (size_t)cap);
    if (!grown) return no_memory(n);
    bp->pairs = grown;
    bp->cap_pairs = cap;
  }
  const int a = pair->slave.body, b = pair->master.body;
  bp->pairs[bp->n_pairs] = (broad_pair){.body = {a < b ? a : b, a < b ? b : a}, .margin = margin, .term_index = -1,
                                        .awake = 1};
  bp->boundary[a] = &pair->slave;
  bp->boundary[b] = &pair->master;
  bp->margin_max = fmax(bp->margin_max, margin);
  *id = bp->n_pairs++;
  return SK_OK;
}

void sk_broad_phase_free(sk_system *sys) {
  sk_broad_phase *bp = sys->broad;
  if (!bp) return;
  free(bp->boundary);
  free(bp->box);
  free(bp->order);
  free(bp->pairs);
  free(bp->by_key);
  free(bp->overlap);
  free(bp->awake);
  free(bp->fresh);
  free(bp->others);
  free(sys->live);
  sys->live = NULL;
  free(bp);
  sys->broad = NULL;
}

static void body_box(const sk_model *m, const sk_surface *boundary, const double *u_start, const double *q_now,
                     double box[6]) {
  for (int i = 0; i < 6; ++i) box[i] = INFINITY;
  for (int j = 0; boundary && j < boundary->n_nodes; ++j) {
    const int64_t d = (int64_t)boundary->nodes[j] * m->dim;
    for (int i = 0; i < m->dim; ++i) {
      const double start = m->X[d + i] + (u_start ? u_start[d + i] : 0.0), now = q_now ? q_now[d + i] : start;
      box[i] = fmin(box[i], fmin(start, now));
      box[3 + i] = fmin(box[3 + i], -fmax(start, now));
    }
  }
}

static int boxes_apart(int dim, const double *a, const double *b, double margin) {
  int apart = 0;
  for (int i = 0; i < dim; ++i) apart |= a[i] > margin - b[3 + i] || b[i] > margin - a[3 + i];
  return apart;
}

/* qsort has no context argument; the broad phase runs on one thread */
static const double *sort_boxes;
static const broad_pair *sort_pairs;

static int by_lower_x(const void *a, const void *b) {
  const double x = sort_boxes[6 * *(const int *)a], y = sort_boxes[6 * *(const int *)b];
  return (x > y) - (x < y);
}

static int compare_keys(const int *p, const int *q) {
  return p[0] != q[0] ? (p[0] > q[0]) - (p[0] < q[0]) : (p[1] > q[1]) - (p[1] < q[1]);
}

static int by_bodies(const void *a, const void *b) {
  const int i = *(const int *)a, j = *(const int *)b;
  const int c = compare_keys(sort_pairs[i].body, sort_pairs[j].body);
  return c ? c : (i > j) - (i < j);
}

static int by_value(const void *a, const void *b) {
  const int x = *(const int *)a, y = *(const int *)b;
  return (x > y) - (x < y);
}

/* Once, at the first attempt: the pairs sorted by their bodies, each pair's place among the system's terms, the
 * terms the broad phase does not drive, and every pair awake (as before any step: the first sweep puts the far ones
 * to sleep). O(terms + pairs log pairs). */
static sk_status get_ready(sk_system *sys, sk_broad_phase *bp) {
  const int n = bp->n_pairs;
  bp->by_key = malloc(sizeof(int) * ((size_t)n + 1));
  bp->awake = malloc(sizeof(int) * ((size_t)n + 1));
  bp->fresh = malloc(sizeof(int) * ((size_t)n + 1));
  bp->others = malloc(sizeof(int) * ((size_t)sys->n_terms + 1));
  sys->live = malloc(sizeof *sys->live * ((size_t)sys->n_terms + 1));
  if (!bp->by_key || !bp->awake || !bp->fresh || !bp->others || !sys->live) return no_memory(bp->n_bodies);
  for (int k = 0; k < sys->n_terms; ++k) {
    const int id = sk_term_plugin_broad_id(sys->terms[k]);
    if (id < 0) {
      bp->others[bp->n_others++] = k;
      continue;
    }
    bp->pairs[id].term = sys->terms[k];
    bp->pairs[id].term_index = k;
  }
  for (int id = 0; id < n; ++id) {
    if (bp->pairs[id].term_index < 0)
      return sk_error_set(SK_ERR_INTERNAL, "broad phase: created pair %d has no term", id);
    bp->by_key[id] = bp->awake[id] = id;
  }
  bp->n_awake = n;
  sort_pairs = bp->pairs;
  qsort(bp->by_key, (size_t)n, sizeof *bp->by_key, by_bodies);
  bp->ready = 1;
  return SK_OK;
}

static sk_status sweep(sk_system *sys) {
  sk_broad_phase *bp = sys->broad;
  const sk_model *m = sys->model;
  int n = 0;
  for (int b = 0; b < bp->n_bodies; ++b) body_box(m, bp->boundary[b], sys->u_n, sys->q, bp->box + 6 * b);
  const sk_clock t0 = sk_system_clock();
  MPI_Allreduce(MPI_IN_PLACE, bp->box, 6 * bp->n_bodies, MPI_DOUBLE, MPI_MIN, sys->comm);
  sk_system_charge_wait(sys, t0);
  for (int b = 0; b < bp->n_bodies; ++b)
    if (bp->boundary[b]) bp->order[n++] = b;
  sort_boxes = bp->box;
  qsort(bp->order, (size_t)n, sizeof *bp->order, by_lower_x);
  if (++bp->sweep == 0) ++bp->sweep; /* 0 is the pairs' initial stamp: never current */
  bp->n_overlap = 0;
  for (int i = 0; i < n; ++i) {
    const int a = bp->order[i];
    const double *box_a = bp->box + 6 * a;
    for (int j = i + 1; j < n && bp->box[6 * bp->order[j]] <= bp->margin_max - box_a[3]; ++j) {
      const int b = bp->order[j];
      if (boxes_apart(m->dim, box_a, bp->box + 6 * b, bp->margin_max)) continue;
      if (bp->n_overlap == bp->cap_overlap) {
        const int cap = 2 * bp->cap_overlap + 16;
        int *grown = realloc(bp->overlap, sizeof(int) * 2 * (size_t)cap);
        if (!grown) return no_memory(bp->n_bodies);
        bp->overlap = grown;
        bp->cap_overlap = cap;
      }
      bp->overlap[2 * bp->n_overlap] = a < b ? a : b;
      bp->overlap[2 * bp->n_overlap++ + 1] = a < b ? b : a;
    }
  }
  bp->version = sys->x_version;
  sys->broad_phase_sweeps++;
  return SK_OK;
}

/* The ids of the pairs near at the current iterate (sweeping first if it moved), in bp->fresh, ascending. */
static sk_status near_pairs(sk_system *sys, int *n_near) {
  sk_broad_phase *bp = sys->broad;
  const sk_clock t0 = sk_system_contact_clock(sys);
  *n_near = 0;
  if (bp->version != sys->x_version) SK_TRY(sweep(sys));
  for (int k = 0; k < bp->n_overlap; ++k) {
    const int *key = bp->overlap + 2 * k;
    int lo = 0, hi = bp->n_pairs; /* the first pair whose bodies are not below the key */
    while (lo < hi) {
      const int mid = lo + (hi - lo) / 2;
      if (compare_keys(bp->pairs[bp->by_key[mid]].body, key) < 0) lo = mid + 1;
      else hi = mid;
    }
    for (; lo < bp->n_pairs && compare_keys(bp->pairs[bp->by_key[lo]].body, key) == 0; ++lo) {
      broad_pair *p = &bp->pairs[bp->by_key[lo]];
      if (boxes_apart(sys->model->dim, bp->box + 6 * key[0], bp->box + 6 * key[1], p->margin)) continue;
      p->stamp = bp->sweep;
      bp->fresh[(*n_near)++] = bp->by_key[lo];
    }
  }
  qsort(bp->fresh, (size_t)*n_near, sizeof *bp->fresh, by_value);
  sys->t_broad_phase += sk_system_seconds() - t0.wall;
  sk_system_charge_contact(sys, SK_CONTACT_BROAD_PHASE, t0); /* contact work (contact_seconds), as the pairs' own */
  return SK_OK;
}

/* The live terms: the others and the awake pairs' terms, merged in the terms' order. */
static void make_live(sk_system *sys, sk_broad_phase *bp) {
  int *index = bp->fresh; /* free again: the awake pairs' term indices, sorted */
  for (int k = 0; k < bp->n_awake; ++k) index[k] = bp->pairs[bp->awake[k]].term_index;
  qsort(index, (size_t)bp->n_awake, sizeof *index, by_value);
  int i = 0, j = 0, n = 0;
  while (i < bp->n_others || j < bp->n_awake)
    sys->live[n++] = sys->terms[j >= bp->n_awake || (i < bp->n_others && bp->others[i] < index[j]) ? bp->others[i++]
                                                                                                   : index[j++]];
  sys->n_live = n;
}

sk_status sk_broad_phase_begin(sk_system *sys) {
  sk_broad_phase *bp = sys->broad;
  if (!bp) return SK_OK;
  if (!bp->ready) SK_TRY(get_ready(sys, bp));
  int n_near = 0;
  SK_TRY(near_pairs(sys, &n_near));
  /* the awake pairs not near any more fall asleep; the near ones are the new awake set */
  for (int k = 0, j = 0; k < bp->n_awake; ++k) {
    while (j < n_near && bp->fresh[j] < bp->awake[k]) ++j;
    if (j < n_near && bp->fresh[j] == bp->awake[k]) continue;
    bp->pairs[bp->awake[k]].awake = 0;
    sk_term_plugin_set_far(bp->pairs[bp->awake[k]].term, sys, 1);
  }
  for (int k = 0; k < n_near; ++k) {
    broad_pair *p = &bp->pairs[bp->fresh[k]];
    if (!p->awake) sk_term_plugin_set_far(p->term, sys, 0);
    p->awake = 1;
    bp->awake[k] = bp->fresh[k];
  }
  bp->n_awake = n_near;
  sys->pair_attempts += bp->n_pairs;
  sys->far_pair_attempts += bp->n_pairs - n_near;
  make_live(sys, bp);
  return SK_OK;
}

sk_status sk_broad_phase_converged(sk_system *sys, int *accept) {
  sk_broad_phase *bp = sys->broad;
  if (!bp || bp->n_awake == bp->n_pairs) return SK_OK;
  int n_near = 0;
  SK_TRY(near_pairs(sys, &n_near));
  sk_status status = SK_OK;
  int woken = 0;
  for (int k = 0; k < n_near && status == SK_OK; ++k) {
    broad_pair *p = &bp->pairs[bp->fresh[k]];
    if (p->awake) continue;
    p->awake = 1;
    bp->awake[bp->n_awake + woken++] = bp->fresh[k];
    status = sk_term_plugin_wake(p->term, sys);
    *accept = 0;
  }
  if (!woken) return status;
  bp->n_awake += woken;
  qsort(bp->awake, (size_t)bp->n_awake, sizeof *bp->awake, by_value);
  make_live(sys, bp);
  return status;
}

int sk_broad_phase_apart_at_start(const sk_system *sys, const sk_contact_pair *pair, double margin) {
  const sk_model *m = sys->model;
  double boxes[12];
  body_box(m, &pair->slave, NULL, NULL, boxes);
  body_box(m, &pair->master, NULL, NULL, boxes + 6);
  MPI_Allreduce(MPI_IN_PLACE, boxes, 12, MPI_DOUBLE, MPI_MIN, sys->comm);
  return boxes_apart(m->dim, boxes, boxes + 6, margin);
}
