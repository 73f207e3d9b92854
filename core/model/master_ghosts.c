/* Master faces ghosted by swept boxes (master_ghosts.h; docs/design.md, "Master faces ghosted by swept boxes"). */
#include "master_ghosts.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "stickslip/config.h"
#include "stickslip/contact.h"

int sk_master_ghosting_on(void) {
  const char *env = getenv("STICKSLIP_MASTER_GHOSTING");
  return env && strcmp(env, "boxes") == 0;
}

static void box_empty(double *box) {
  for (int i = 0; i < 3; ++i) box[i] = INFINITY, box[3 + i] = -INFINITY;
}

/* Adds node a at positions pos (dof layout, dim per node; z = 0 in 2D) to box. */
static void box_add(double *box, const double *pos, int dim, int a) {
  for (int i = 0; i < 3; ++i) {
    const double c = i < dim ? pos[(size_t)a * dim + i] : 0.0;
    box[i] = fmin(box[i], c);
    box[3 + i] = fmax(box[3 + i], c);
  }
}

static void box_grow(double *box, double by) {
  if (!(box[0] <= box[3])) return; /* empty stays empty */
  for (int i = 0; i < 3; ++i) box[i] -= by, box[3 + i] += by;
}

static int boxes_overlap(const double *a, const double *b) {
  for (int i = 0; i < 3; ++i)
    if (a[i] > b[3 + i] || b[i] > a[3 + i]) return 0;
  return 1;
}

/* The capture distance of the pair: the plugins' search margin when the scene gives one, else the master surface's
 * largest edge (every plugin's default margin is below it: penalty-nts takes half the mean face size). Read without
 * marking the key used: the plugin reads and validates it. */
static double capture_distance(const sk_contact_pair *pair) {
  const sk_cfg *given = pair->params ? sk_cfg_peek(pair->params, "search_margin") : NULL;
  const char *text = given ? sk_cfg_scalar(given) : NULL;
  char *end = NULL;
  const double margin = text ? strtod(text, &end) : NAN;
  const double h = pair->master.whole_h_max;
  return text && end && *end == '\0' && isfinite(margin) && margin > h ? margin : h;
}

sk_status sk_master_ghosts_plan(sk_model *m, sk_contact_pair *pair, const int *face_owner_of_slave) {
  const int p = m->n_ranks, dim = m->dim;
  pair->ghost_boxes = malloc(sizeof(double) * 12 * (size_t)p); /* the set-up's boxes, then the step's */
  if (!pair->ghost_boxes)
    return sk_error_set(SK_ERR_NOMEM, "out of memory for the master ghost boxes of contact pair %s", pair->name);
  if (!pair->master.whole_sizes) {
    sk_surface_sizes(&pair->master, m->mesh.x, 3, &pair->master.whole_h_min, &pair->master.whole_h_mean,
                     &pair->master.whole_h_max, &pair->master.whole_measure);
    pair->master.whole_sizes = 1;
  }
  /* capture distance, and a reach of two master faces: the motion a step's predictor and Newton may add before the
   * next step's check, and the neighbours of every face a slave point can reach (averaged nodal normals) */
  pair->ghost_capture = capture_distance(pair);
  pair->ghost_reach = 2.0 * pair->master.whole_h_max;
  double *box = pair->ghost_boxes;
  for (int r = 0; r < p; ++r) box_empty(box + 6 * r);
  const sk_surface *s = &pair->slave;
  for (int k = 0; k < s->n_nodes; ++k) box_add(box + 6 * m->node_owner[s->nodes[k]], m->X, dim, s->nodes[k]);
  for (int f = 0; f < s->n_faces; ++f)
    for (int a = 0; a < s->nen; ++a) box_add(box + 6 * face_owner_of_slave[f], m->X, dim, s->conn[(size_t)f * s->nen + a]);
  for (int r = 0; r < p; ++r) box_grow(box + 6 * r, pair->ghost_capture + pair->ghost_reach);
  return SK_OK;
}

int sk_master_face_ghosted(const sk_model *m, const sk_contact_pair *pair, const int *conn, int rank) {
  double face[6];
  box_empty(face);
  for (int a = 0; a < pair->master.nen; ++a) box_add(face, m->X, m->dim, conn[a]);
  return boxes_overlap(face, pair->ghost_boxes + 6 * rank);
}

/* Adds nodes' positions at the start and the end of the step (the swept box). */
static void swept_add(double *box, const sk_system *sys, int a) {
  box_add(box, sys->q_n, sys->model->dim, a);
  box_add(box, sys->q, sys->model->dim, a);
}

sk_status sk_master_ghosts_check(sk_system *sys) {
  const sk_model *m = sys->model;
  for (int k = 0; k < m->n_pairs; ++k) {
    const sk_contact_pair *pair = &m->pairs[k];
    if (!pair->ghost_boxes) continue;
    /* this rank's slave entities swept over the step, grown by the capture distance and half the reach (the other
     * half is left for Newton to move past the predictor before the next step's check) */
    double mine[6], *now = pair->ghost_boxes + 6 * (size_t)m->n_ranks;
    box_empty(mine);
    const sk_surface *s = &pair->slave;
    for (int j = 0; j < s->n_nodes; ++j)
      if (m->node_owner[s->nodes[j]] == m->rank) swept_add(mine, sys, s->nodes[j]);
    for (int f = 0; f < s->n_faces; ++f)
      if (s->face_owner && s->face_owner[f] == m->rank)
        for (int a = 0; a < s->nen; ++a) swept_add(mine, sys, s->conn[(size_t)f * s->nen + a]);
    box_grow(mine, pair->ghost_capture + 0.5 * pair->ghost_reach);
    MPI_Allgather(mine, 6, MPI_DOUBLE, now, 6, MPI_DOUBLE, sys->comm);
    /* each master face's owner: every rank whose box the face's swept box overlaps must hold the face */
    const sk_surface *ms = &pair->master;
    long long missing = 0;
    int first_rank = -1;
    for (int f = 0; f < ms->n_faces; ++f) {
      if (!ms->face_owner || ms->face_owner[f] != m->rank) continue;
      const int *conn = ms->conn + (size_t)f * ms->nen;
      double face[6];
      box_empty(face);
      for (int a = 0; a < ms->nen; ++a) swept_add(face, sys, conn[a]);
      for (int r = 0; r < m->n_ranks; ++r)
        if (r != m->rank && boxes_overlap(face, now + 6 * r) && !sk_master_face_ghosted(m, pair, conn, r)) {
          missing++;
          if (first_rank < 0) first_rank = r;
        }
    }
    long long total = 0;
    MPI_Allreduce(&missing, &total, 1, MPI_LONG_LONG, MPI_SUM, sys->comm);
    if (total > 0) {
      int where[2] = {missing > 0 ? m->rank : m->n_ranks, first_rank}, lowest[2];
      MPI_Allreduce(where, lowest, 1, MPI_2INT, MPI_MINLOC, sys->comm);
      return sk_error_set(SK_ERR_INPUT,
                          "contact pair %s: at step %lld (t = %g) %lld master face(s) of %s came within reach of the "
                          "slave region of a rank they are not ghosted to (first: faces owned by rank %d, reaching "
                          "rank %d); master ghosting by swept boxes (STICKSLIP_MASTER_GHOSTING=boxes) sets its ghosts "
                          "up once and does not re-ghost during a run yet: run without STICKSLIP_MASTER_GHOSTING",
                          pair->name, (long long)sys->step, sys->t, total, ms->name, lowest[0], lowest[1]);
    }
  }
  return SK_OK;
}
