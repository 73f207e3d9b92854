/* The host's broad phase over the pairs created by `bodies:` (broad_phase.h).
 *
 * Per body: the box of its boundary nodes at the start of the step and at the current iterate (a face moves
 * linearly between the two, so it stays inside), one pass over the nodes and one reduction over the ranks. Then a
 * sort and sweep along x: bodies sorted by their boxes' lower x; each one meets only the bodies after it whose lower
 * x lies below its upper x plus the largest margin, and those that overlap in y (and z) too are stamped with the
 * sweep's number in an N x N table (never cleared: a stale stamp is an older number). A pair is then apart unless
 * its stamp is current and its own margin still makes the boxes overlap. */
#include <math.h>
#include <stdlib.h>

#include "broad_phase.h"

typedef struct sk_broad_phase {
  int n_bodies;
  const sk_surface **boundary; /* per body: a surface over its whole boundary, or NULL (no created pair) */
  double *box;                 /* 6 per body: lo[3], then -hi[3] (one MIN reduction) */
  int *order;                  /* bodies by lower x */
  unsigned *stamp;             /* n_bodies^2: the sweep that found the two bodies' boxes overlapping */
  unsigned sweep;
  uint64_t version;            /* the system's x_version of the boxes */
  double margin_max;
} sk_broad_phase;

sk_status sk_broad_phase_add(sk_system *sys, const sk_contact_pair *pair, double margin) {
  const int n = sys->model->n_bodies;
  sk_broad_phase *bp = sys->broad;
  if (!bp) {
    bp = calloc(1, sizeof *bp);
    if (bp) {
      bp->n_bodies = n;
      bp->boundary = calloc((size_t)n, sizeof *bp->boundary);
      bp->box = malloc(sizeof(double) * 6 * (size_t)n);
      bp->order = malloc(sizeof(int) * (size_t)n);
      bp->stamp = calloc((size_t)n * (size_t)n, sizeof *bp->stamp);
      bp->version = UINT64_MAX;
    }
    sys->broad = bp;
    if (!bp || !bp->boundary || !bp->box || !bp->order || !bp->stamp)
      return sk_error_set(SK_ERR_NOMEM, "out of memory for the broad phase of %d bodies", n);
  }
  bp->boundary[pair->slave.body] = &pair->slave;
  bp->boundary[pair->master.body] = &pair->master;
  bp->margin_max = fmax(bp->margin_max, margin);
  return SK_OK;
}

void sk_broad_phase_free(sk_system *sys) {
  sk_broad_phase *bp = sys->broad;
  if (!bp) return;
  free(bp->boundary);
  free(bp->box);
  free(bp->order);
  free(bp->stamp);
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

static const double *sort_boxes; /* qsort has no context argument; the sweep runs on one thread */

static int by_lower_x(const void *a, const void *b) {
  const double x = sort_boxes[6 * *(const int *)a], y = sort_boxes[6 * *(const int *)b];
  return (x > y) - (x < y);
}

static void sweep(sk_system *sys) {
  sk_broad_phase *bp = sys->broad;
  const sk_model *m = sys->model;
  const double t0 = sk_system_seconds();
  int n = 0;
  for (int b = 0; b < bp->n_bodies; ++b) body_box(m, bp->boundary[b], sys->u_n, sys->q, bp->box + 6 * b);
  MPI_Allreduce(MPI_IN_PLACE, bp->box, 6 * bp->n_bodies, MPI_DOUBLE, MPI_MIN, sys->comm);
  for (int b = 0; b < bp->n_bodies; ++b)
    if (bp->boundary[b]) bp->order[n++] = b;
  sort_boxes = bp->box;
  qsort(bp->order, (size_t)n, sizeof *bp->order, by_lower_x);
  if (++bp->sweep == 0) ++bp->sweep; /* 0 is the table's initial value: never current */
  for (int i = 0; i < n; ++i) {
    const int a = bp->order[i];
    const double *box_a = bp->box + 6 * a;
    for (int j = i + 1; j < n && bp->box[6 * bp->order[j]] <= bp->margin_max - box_a[3]; ++j) {
      const int b = bp->order[j];
      if (boxes_apart(m->dim, box_a, bp->box + 6 * b, bp->margin_max)) continue;
      bp->stamp[(size_t)a * bp->n_bodies + b] = bp->stamp[(size_t)b * bp->n_bodies + a] = bp->sweep;
    }
  }
  bp->version = sys->x_version;
  sys->broad_phase_sweeps++;
  sys->t_broad_phase += sk_system_seconds() - t0;
}

int sk_broad_phase_apart(sk_system *sys, int body_a, int body_b, double margin) {
  sk_broad_phase *bp = sys->broad;
  if (bp->version != sys->x_version) sweep(sys);
  if (bp->stamp[(size_t)body_a * bp->n_bodies + body_b] != bp->sweep) return 1;
  return boxes_apart(sys->model->dim, bp->box + 6 * body_a, bp->box + 6 * body_b, margin);
}

int sk_broad_phase_apart_at_start(const sk_system *sys, const sk_contact_pair *pair, double margin) {
  const sk_model *m = sys->model;
  double boxes[12];
  body_box(m, &pair->slave, NULL, NULL, boxes);
  body_box(m, &pair->master, NULL, NULL, boxes + 6);
  MPI_Allreduce(MPI_IN_PLACE, boxes, 12, MPI_DOUBLE, MPI_MIN, sys->comm);
  return boxes_apart(m->dim, boxes, boxes + 6, margin);
}
