/* Master faces ghosted by swept boxes (master_ghosts.h; docs/design.md, "Master faces ghosted by swept boxes"). */
#include "master_ghosts.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "stickslip/config.h"
#include "stickslip/contact.h"
#include "contact_partition.h"
#include "records.h"
#include "term_plugin.h"

sk_status sk_master_ghosting_check_setting(void) {
  const char *env = getenv("STICKSLIP_MASTER_GHOSTING");
  if (env && strcmp(env, "boxes") != 0 && strcmp(env, "replicated") != 0)
    return sk_error_set(SK_ERR_INPUT, "environment variable STICKSLIP_MASTER_GHOSTING=%s: expected 'boxes' (the "
                        "default: master faces ghosted by swept boxes) or 'replicated' (every master face on every "
                        "rank with the pair)", env);
  return SK_OK;
}

int sk_master_ghosting_on(void) {
  const char *env = getenv("STICKSLIP_MASTER_GHOSTING");
  return !env || strcmp(env, "replicated") != 0;
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
static double capture_distance(const sk_contact_pair *pair, double h) {
  const sk_cfg *given = pair->params ? sk_cfg_peek(pair->params, "search_margin") : NULL;
  const char *text = given ? sk_cfg_scalar(given) : NULL;
  char *end = NULL;
  const double margin = text ? strtod(text, &end) : NAN;
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
  pair->ghost_capture = capture_distance(pair, pair->master.whole_h_max);
  pair->ghost_reach = 2.0 * pair->master.whole_h_max;
  double *box = pair->ghost_boxes;
  for (int r = 0; r < p; ++r) box_empty(box + 6 * r);
  const sk_surface *s = &pair->slave;
  /* the slave entities each rank evaluates: their owners', or their contact owners' (contact_partition.h) */
  for (int k = 0; k < s->n_nodes; ++k) box_add(box + 6 * sk_contact_node_owner(m, pair, k), m->X, dim, s->nodes[k]);
  for (int f = 0; f < s->n_faces; ++f) {
    const int owner = pair->contact_face_owner ? pair->contact_face_owner[f] : face_owner_of_slave[f];
    for (int a = 0; a < s->nen; ++a) box_add(box + 6 * owner, m->X, dim, s->conn[(size_t)f * s->nen + a]);
  }
  for (int r = 0; r < p; ++r) box_grow(box + 6 * r, pair->ghost_capture + pair->ghost_reach);
  return SK_OK;
}

void sk_master_ghosts_explain(const sk_model *m, FILE *out) {
  int any = 0;
  for (int k = 0; k < m->n_pairs; ++k) any |= !m->pairs[k].has_obstacle && !m->pairs[k].self_contact;
  if (!any) return;
  const int on = sk_master_ghosting_on();
  fprintf(out, "master faces on more than one rank (STICKSLIP_MASTER_GHOSTING=%s): %s\n", on ? "boxes" : "replicated",
          on ? "each rank holds the faces within its slave region's swept box grown by the capture distance and the "
               "reach, and they are ghosted again at a step whose swept boxes reach a face a rank does not hold"
             : "every rank with the pair holds the whole master surface");
  for (int k = 0; on && k < m->n_pairs; ++k) {
    const sk_contact_pair *pair = &m->pairs[k];
    if (pair->has_obstacle || pair->self_contact) continue;
    double h_min, h_mean, h_max = pair->master.whole_h_max, measure;
    if (!pair->master.whole_sizes) sk_surface_sizes(&pair->master, m->X, m->dim, &h_min, &h_mean, &h_max, &measure);
    const double capture = capture_distance(pair, h_max);
    fprintf(out, "  contact pair %s: capture distance %.6g (%s), reach %.6g (two of %s's largest edges, %.6g)\n",
            pair->name, capture, capture > h_max ? "its search_margin" : "the master's largest edge, above every "
            "plugin's default search_margin", 2.0 * h_max, pair->master.name, h_max);
  }
}

/* Whether rank `rank` holds master face f (its box at the last ghosting overlaps the rank's box of then): the holder
 * decides it from the same numbers the face's owner checks it with. */
static int face_ghosted(const sk_contact_pair *pair, int f, int rank) {
  return boxes_overlap(pair->master_face_box + 6 * (size_t)f, pair->ghost_boxes + 6 * (size_t)rank);
}

/* The faces this rank holds: those ghosted to it, and those whose nodes its element ghost layer holds anyway. */
static void hold_faces(const sk_model *m, sk_contact_pair *pair, const unsigned char *layer) {
  const sk_surface *s = &pair->master;
  for (int f = 0; f < s->n_faces; ++f) {
    int layer_holds = 1;
    for (int a = 0; a < s->nen; ++a) layer_holds = layer_holds && layer[s->conn[(size_t)f * s->nen + a]];
    pair->master_held[f] = (unsigned char)(layer_holds || face_ghosted(pair, f, m->rank));
  }
}

sk_status sk_master_ghosts_hold(sk_model *m) {
  unsigned char *layer = NULL;
  sk_status status = SK_OK;
  for (int k = 0; k < m->n_pairs && status == SK_OK; ++k) {
    sk_contact_pair *pair = &m->pairs[k];
    if (!pair->ghost_boxes) continue;
    const sk_surface *s = &pair->master;
    const size_t nf = (size_t)(s->n_faces > 0 ? s->n_faces : 1);
    if (!layer) {
      layer = malloc((size_t)(m->n_nodes > 0 ? m->n_nodes : 1));
      if (layer) sk_model_layer_roles(m, layer);
    }
    pair->master_held = malloc(nf);
    pair->master_face_box = malloc(sizeof(double) * 6 * nf);
    if (!layer || !pair->master_held || !pair->master_face_box) {
      status = sk_error_set(SK_ERR_NOMEM, "out of memory for the master faces of contact pair %s", pair->name);
      break;
    }
    for (int f = 0; f < s->n_faces; ++f) {
      double *box = pair->master_face_box + 6 * (size_t)f;
      box_empty(box);
      for (int a = 0; a < s->nen; ++a) box_add(box, m->X, m->dim, s->conn[(size_t)f * s->nen + a]);
    }
    hold_faces(m, pair, layer);
  }
  free(layer);
  return status;
}

/* Adds nodes' positions at the start and the end of the step (the swept box). */
static void swept_add(double *box, const sk_system *sys, int a) {
  box_add(box, sys->q_n, sys->model->dim, a);
  box_add(box, sys->q, sys->model->dim, a);
}

sk_status sk_master_ghosts_check(sk_system *sys, int64_t *missing_faces) {
  const sk_model *m = sys->model;
  *missing_faces = 0;
  for (int k = 0; k < m->n_pairs; ++k) {
    const sk_contact_pair *pair = &m->pairs[k];
    if (!pair->ghost_boxes) continue;
    /* this rank's slave entities swept over the step, grown by the capture distance and half the reach (the other
     * half is left for Newton to move past the predictor before the next step's check) */
    double mine[6], *now = pair->ghost_boxes + 6 * (size_t)m->n_ranks;
    box_empty(mine);
    const sk_surface *s = &pair->slave;
    for (int j = 0; j < s->n_nodes; ++j)
      if (sk_contact_node_owner(m, pair, j) == m->rank) swept_add(mine, sys, s->nodes[j]);
    for (int f = 0; f < s->n_faces; ++f)
      if (sk_contact_face_owner(m, pair, f) == m->rank)
        for (int a = 0; a < s->nen; ++a) swept_add(mine, sys, s->conn[(size_t)f * s->nen + a]);
    box_grow(mine, pair->ghost_capture + 0.5 * pair->ghost_reach);
    MPI_Allgather(mine, 6, MPI_DOUBLE, now, 6, MPI_DOUBLE, sys->comm);
    /* each master face's owner: every rank whose box the face's swept box overlaps must hold the face */
    const sk_surface *ms = &pair->master;
    long long missing = 0;
    for (int f = 0; f < ms->n_faces; ++f) {
      if (!ms->face_owner || ms->face_owner[f] != m->rank) continue;
      const int *conn = ms->conn + (size_t)f * ms->nen;
      double face[6];
      box_empty(face);
      for (int a = 0; a < ms->nen; ++a) swept_add(face, sys, conn[a]);
      for (int r = 0; r < m->n_ranks; ++r)
        if (r != m->rank && boxes_overlap(face, now + 6 * r) && !face_ghosted(pair, f, r)) missing++;
    }
    long long total = 0;
    MPI_Allreduce(&missing, &total, 1, MPI_LONG_LONG, MPI_SUM, sys->comm);
    *missing_faces += total;
  }
  return SK_OK;
}

/* The plugin terms of pairs whose master faces are ghosted, in the terms' order (the same on every rank). */
static int ghosted_term(const sk_system *sys, int k) { return sk_master_ghosts_term(sys, sys->terms[k]); }

/* Every rank's records of a term, gathered to every rank and sorted (the reader its re-created instance loads). */
static sk_status gather_records(sk_system *sys, sk_term *term, sk_record_set *set) {
  sk_byte_buffer mine = {0};
  sk_buffer_writer w;
  sk_buffer_writer_init(&w, &mine);
  sk_status status = sk_term_plugin_save(term, sys, &w.abi);
  if (status == SK_OK && mine.failed) status = sk_error_set(SK_ERR_NOMEM, "out of memory for the records of %s", term->name);
  status = sk_system_collective(sys, status);
  if (status != SK_OK) {
    free(mine.data);
    return status;
  }
  const int p = sys->n_ranks;
  int *sizes = malloc(sizeof(int) * (size_t)p), *displs = malloc(sizeof(int) * ((size_t)p + 1));
  long long *counts = malloc(sizeof(long long) * (size_t)p);
  int size = (int)mine.size;
  long long count = w.count;
  unsigned char *all = NULL;
  if (sizes && displs && counts) {
    MPI_Allgather(&size, 1, MPI_INT, sizes, 1, MPI_INT, sys->comm);
    MPI_Allgather(&count, 1, MPI_LONG_LONG, counts, 1, MPI_LONG_LONG, sys->comm);
    displs[0] = 0;
    for (int r = 0; r < p; ++r) displs[r + 1] = displs[r] + sizes[r];
    all = malloc((size_t)displs[p] + 1);
  }
  int ok = all != NULL;
  MPI_Allreduce(MPI_IN_PLACE, &ok, 1, MPI_INT, MPI_MIN, sys->comm);
  if (ok) MPI_Allgatherv(mine.data, size, MPI_BYTE, all, sizes, displs, MPI_BYTE, sys->comm);
  for (int r = 0; ok && r < p; ++r) {
    int no_memory = 0;
    ok = sk_record_set_parse(set, all + displs[r], (size_t)sizes[r], counts[r], &no_memory) == sizes[r];
  }
  ok = ok && sk_record_set_sort(set);
  free(mine.data), free(sizes), free(displs), free(counts), free(all);
  return sk_system_collective(
      sys, ok ? SK_OK : sk_error_set(SK_ERR_NOMEM, "out of memory gathering the records of %s", term->name));
}

/* The faces held from the step's boxes (ghost_boxes' second half, sk_master_ghosts_check): each rank's box grown by
 * the whole reach, each face's swept box; then the nodes' roles, their exchange and (at the layout) the ghosts' rows. */
static sk_status hold_again(sk_system *sys) {
  sk_model *m = sys->model;
  unsigned char *layer = malloc((size_t)(m->n_nodes > 0 ? m->n_nodes : 1));
  if (!layer) return sk_error_set(SK_ERR_NOMEM, "out of memory ghosting the master faces again");
  sk_model_layer_roles(m, layer);
  for (int k = 0; k < m->n_pairs; ++k) {
    sk_contact_pair *pair = &m->pairs[k];
    if (!pair->ghost_boxes) continue;
    memcpy(pair->ghost_boxes, pair->ghost_boxes + 6 * (size_t)m->n_ranks, sizeof(double) * 6 * (size_t)m->n_ranks);
    for (int r = 0; r < m->n_ranks; ++r) box_grow(pair->ghost_boxes + 6 * r, 0.5 * pair->ghost_reach);
    const sk_surface *s = &pair->master;
    for (int f = 0; f < s->n_faces; ++f) {
      double *box = pair->master_face_box + 6 * (size_t)f;
      box_empty(box);
      for (int a = 0; a < s->nen; ++a) swept_add(box, sys, s->conn[(size_t)f * s->nen + a]);
    }
    hold_faces(m, pair, layer);
  }
  free(layer);
  /* the nodes' roles, their exchange and (at the layout) the rows of the ghosts */
  SK_TRY(sk_model_node_roles(m, sys->node_role));
  SK_TRY(sk_system_plan_ghost_dofs(sys, &sys->ghost_dofs, 0));
  sys->owned_known = 0;
  return SK_OK;
}

/* The terms re-created: those of pairs with ghosted master faces, and with `rebalanced` those of pairs with a
 * contact partition. */
static int renewed_term(const sk_system *sys, int k, int rebalanced) {
  const int pair = sk_term_plugin_pair(sys->terms[k]);
  return ghosted_term(sys, k) || (rebalanced && pair >= 0 && sys->model->pairs[pair].contact_node_owner);
}

sk_status sk_master_ghosts_renew(sk_system *sys, int rebalanced) {
  sk_model *m = sys->model;
  /* the plugins are re-created over their new master views from their records (stickslip.checkpoint.v1) */
  sk_status status = SK_OK;
  for (int k = 0; k < sys->n_terms && status == SK_OK; ++k) {
    const char *plugin = NULL;
    if (ghosted_term(sys, k) && sk_term_plugin_checkpointable(sys->terms[k], &plugin) != 1)
      status = sk_error_set(SK_ERR_INPUT, "%s: at step %lld (t = %g) its master faces must be ghosted again, and "
                            "plugin '%s' keeps no records (stickslip.checkpoint.v1) to be re-created from: run with "
                            "STICKSLIP_MASTER_GHOSTING=replicated", sys->terms[k]->name, (long long)sys->step, sys->t,
                            plugin ? plugin : "?");
  }
  SK_TRY(sk_system_collective(sys, status));
  /* the current state of every master node this rank holds, from the owners (the faces it did not hold were not
   * kept up to date) */
  sk_exchange every = {0};
  SK_TRY(sk_system_plan_ghost_dofs(sys, &every, 1));
  double *const state[] = {sys->u_n, sys->v_n, sys->rate_n, sys->v, sys->x};
  for (size_t j = 0; j < sizeof state / sizeof state[0]; ++j) sk_exchange_forward(&every, state[j]);
  sys->ghost_dofs.bytes_sent += every.bytes_sent; /* counted with the ghost exchanges (STICKSLIP_RANK_STATS) */
  sk_exchange_free(&every);
  for (int64_t d = 0; d < m->n_dofs; ++d) {
    sys->q_n[d] = m->X[d] + sys->u_n[d];
    sys->q[d] = m->X[d] + sys->x[d];
  }
  sys->x_version++;
  SK_TRY(hold_again(sys));
  for (int k = 0; k < sys->n_terms && status == SK_OK; ++k) {
    if (!renewed_term(sys, k, rebalanced)) continue;
    const int pair = sk_term_plugin_pair(sys->terms[k]);
    sk_record_set records = {0};
    status = gather_records(sys, sys->terms[k], &records);
    if (status == SK_OK)
      status = sk_term_plugin_recreate(sys->terms[k], sys, &records.abi,
                                           rebalanced && m->pairs[pair].contact_node_owner != NULL);
    status = sk_system_collective(sys, status);
    sk_record_set_free(&records);
  }
  return status;
}

int sk_master_ghosts_term(const sk_system *sys, const sk_term *term) {
  const int pair = sk_term_plugin_pair(term);
  return pair >= 0 && sys->model->pairs[pair].ghost_boxes != NULL;
}

sk_status sk_master_ghosts_restart(sk_system *sys) {
  int64_t missing = 0;
  SK_TRY(sk_master_ghosts_check(sys, &missing)); /* the boxes at the restart's positions (q = q_n) */
  return hold_again(sys);
}
