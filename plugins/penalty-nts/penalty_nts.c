/* stickslip plugin "penalty-nts": node-to-surface penalty contact, frictionless or with penalty-regularised Coulomb
 * friction, against a deformable master surface or a rigid analytical obstacle, in 2D and 3D.
 *
 * Normal part. For a slave node x_s and its closest point x_m = N_I(xi) x_I on the master, g = (x_s - x_m) . n and
 * the energy W = eps/2 <-g>^2 gives the residual dW/dq = -p dg/dq with p = eps <-g>: the slave gets the force p n,
 * master node I the force -N_I p n. The Jacobian is the exact derivative, including the variation of xi (from the
 * closest-point condition, A_ab dxi^b = a_a . du + g n . da_a with A_ab = m_ab - g h_ab) and of the normal
 * (dn = -a^a (n . da_a + h_ab dxi^b)).
 *
 * Friction (deformable master). The trial traction is convected in covariant components on the master:
 *   t_a^trial = t_a,n - eps_t m_ab (xi^b - xi_n^b),
 * with (xi_n, t_n) committed at the end of the previous step. xi and m_ab do not change under a superposed rigid
 * motion, so the trial (and the return map on |t| = sqrt(t_a m^ab t_b) <= mu p) is frame indifferent; an
 * incremental spatial slip vector would not be. The slave gets the force p n + t_a a^a, each master node -N_I times
 * that, so linear momentum is conserved exactly; angular momentum only for frictionless contact (the tangential
 * force acts at x_s on the slave and at x_m on the master, which differ by g n).
 * Friction (rigid obstacle). The obstacle only translates, so the history is an anchor point fixed in the
 * obstacle and a spatial traction: t^trial = P (t_n - eps_t (x_s - x_anchor(t))), P = I - n n.
 * The stick/slip switch of a Newton iteration remembers the traction of a node that slipped at the last Jacobian's
 * point (held_friction; cov_return_map_held): such a node sticks, rather than slipping the other way, once its trial
 * turns back, so that a stiff eps_t does not make Newton cycle between two slip directions (docs/stability.md,
 * finding 19). At a converged point the switch must agree with the return map (pnts_converged).
 *
 * Master face. begin_step and update_active_set select one master face per slave node (the closest-point projection,
 * keeping a face selected earlier in the step while the slave stays within 10 % of a face beyond it); residual and
 * Jacobian evaluate the closest point on that face's extension, so they are smooth in q between selections.
 *
 * Every scheme is evaluated at t_{n+1} (q, state->t): the plugin does not claim the energy-momentum capability. */
#include <math.h>
#include <stdio.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "penalty_nts.h"

/* ---- step -------------------------------------------------------------------------------------------------------- */

/* Self contact: the candidates of slave node k without the faces it cannot touch (self_contact.h). */
static sk_status exclude_own_faces(sk_instance *in, int k) {
  sk_status status;
  const int kept = self_contact_filter(in->cs, in->master, in->slave->X + (size_t)k * in->dim, in->self_exclusion,
                                       in->cand.faces + in->cand_start[k], in->cand_count[k], &status);
  if (kept < 0) return status;
  in->cand_count[k] = kept;
  in->cand.used = in->cand_start[k] + kept;
  return SK_OK;
}

/* Candidate faces of every slave node from boxes swept between x_n and x (the predictor at begin_step, the
 * converged point in pnts_converged), inflated by the search margin. */
static sk_status find_candidates(sk_instance *in, const double *const *x_n, const double *const *x) {
  in->cs->search_update(in->search, x_n[1], x[1], in->margin);
  in->cand.used = 0;
  for (int k = 0; k < in->n_slave; ++k) {
    in->cand_start[k] = in->cand.used;
    in->cand_count[k] = 0;
    if (!in->evaluated[k]) continue; /* another rank's node: no candidates here */
    double x0[3], x1[3];
    slave_position(in, x_n, k, x0);
    slave_position(in, x, k, x1);
    if (cand_query_swept(in->cs, in->search, x0, x1, in->dim, in->margin, &in->cand, &in->cand_start[k],
                         &in->cand_count[k]) != 0)
      return in->api->error(in->host, SK_ERR_NOMEM, "%s: penalty-nts: out of memory", in->name);
    if (in->self) SK_TRY(exclude_own_faces(in, k));
  }
  return SK_OK;
}

/* The step's candidate faces (find_candidates) and friction anchors: the committed history, or for a node without
 * one the projection of its start-of-step position. */
static sk_status pnts_begin_step(sk_instance *in, const sk_state *st) {
  const sk_contact_services *cs = in->cs;
  const sk_view *master = in->master;
  if (master) SK_TRY(find_candidates(in, st->x_n, st->x));
  for (int k = 0; k < in->n_slave; ++k) {
    friction_history *a = &in->anchor[k];
    *a = in->committed[k];
    if (in->mu == 0.0 || a->valid || !in->evaluated[k]) continue;
    double x0[3];
    slave_position(in, st->x_n, k, x0);
    if (master) {
      if (in->cand_count[k] == 0) continue;
      sk_projection proj = {.struct_size = sizeof proj};
      SK_TRY(cs->project(master, st->x_n[1], x0, in->cand.faces + in->cand_start[k], in->cand_count[k], &proj));
      if (proj.face < 0) continue;
      if (proj.kind == SK_PROJ_OUTSIDE) {
        sk_surface_point pt = {.struct_size = sizeof pt};
        cs->geometry(master, proj.face, proj.xi, st->x_n[1], &pt);
        pt.xi[0] = proj.xi[0];
        pt.xi[1] = proj.xi[1];
        if (in->extension == 0.0 || !extend_on_face(in, proj.face, x0, st->x_n[1], in->extension, &pt)) continue;
        proj.xi[0] = pt.xi[0];
        proj.xi[1] = pt.xi[1];
      }
      a->valid = 1;
      a->face = proj.face;
      a->xi[0] = proj.xi[0];
      a->xi[1] = proj.xi[1];
    } else {
      sk_surface_point pt = {.struct_size = sizeof pt};
      double g, d[3];
      SK_TRY(cs->obstacle_project(in->obstacle, st->t_n, x0, in->dim, &pt, &g));
      cs->obstacle_displacement(in->obstacle, st->t_n, d);
      a->valid = 1;
      for (int i = 0; i < 3; ++i) a->anchor[i] = pt.x[i] - d[i];
    }
  }
  memset(in->last_state, 0, (size_t)in->n_slave);
  memset(in->held, 0, sizeof *in->held * (size_t)in->n_slave);
  for (int k = 0; k < in->n_slave; ++k) in->sel_face[k] = -1;
  if (master)
    for (int k = 0; k < in->n_slave; ++k)
      if (in->evaluated[k]) SK_TRY(select_face(in, st->x, k));
  return SK_OK;
}

static sk_status pnts_layout(sk_instance *in, const sk_state *st, sk_layout *layout) {
  (void)st;
  layout->n_extra = 0;
  layout->initial = NULL;
  layout->eliminated = NULL;
  /* no slave node has a candidate face: every selection stays -1 (project_global), so no point is evaluated */
  if (SK_HAS(layout, idle)) layout->idle = in->master && in->cand.used == 0;
  return SK_OK;
}

/* Every owned slave node with the nodes of each of its candidate master faces, face by face (the face selected
 * during the step is one of them; a point's Jacobian couples it with that one face only, so nodes of two candidate
 * faces are never coupled by it); against an obstacle only the node's own block. */
static sk_status pnts_pattern(sk_instance *in, const sk_state *st, sk_pattern *pattern) {
  (void)st;
  const sk_view *slave = in->slave, *master = in->master;
  const int dim = in->dim;
  const int need = dim * (1 + (master ? master->nen : 0));
  if (need > in->pattern_capacity) {
    int64_t *grown = realloc(in->pattern_dofs, sizeof(int64_t) * (size_t)need);
    if (!grown) return in->api->error(in->host, SK_ERR_NOMEM, "%s: penalty-nts: out of memory", in->name);
    in->pattern_dofs = grown;
    in->pattern_capacity = need;
  }
  int64_t *dofs = in->pattern_dofs;
  for (int k = 0; k < in->n_slave; ++k) {
    if (!slave->owned[k]) continue;
    for (int i = 0; i < dim; ++i) dofs[i] = slave->dofs[k * dim + i];
    if (!master || in->cand_count[k] == 0) {
      pattern->add_block(pattern, dim, dofs, dim, dofs);
      continue;
    }
    for (int c = 0; c < in->cand_count[k]; ++c) {
      const int32_t *conn = master->conn + in->cand.faces[in->cand_start[k] + c] * master->nen;
      int n = dim;
      for (int I = 0; I < master->nen; ++I)
        for (int i = 0; i < dim; ++i) dofs[n++] = master->dofs[conn[I] * dim + i];
      pattern->add_block(pattern, n, dofs, n, dofs);
    }
  }
  return SK_OK;
}

static sk_status pnts_residual(sk_instance *in, const sk_state *st, sk_sink *sink) {
  point_eval e;
  for (int k = 0; k < in->n_slave; ++k) {
    if (!in->slave->owned[k]) continue;
    SK_TRY(evaluate_point(in, st, k, 0, &e));
    if (e.nd > 0) sink->add_vector(sink, e.nd, e.rows, e.R);
  }
  return SK_OK;
}

/* The Jacobian is assembled at the accepted Newton iterates only: its point is the memory of the stick/slip switch
 * for the points that follow (held_friction). */
static sk_status pnts_jacobian(sk_instance *in, const sk_state *st, sk_sink *sink) {
  point_eval e;
  for (int k = 0; k < in->n_slave; ++k) {
    if (!in->slave->owned[k]) continue;
    SK_TRY(evaluate_point(in, st, k, 1, &e));
    if (e.nd > 0) sink->add_matrix(sink, e.nd, e.rows, e.nd, e.rows, e.K);
    held_friction *h = &in->held[k];
    h->slip = e.state == STATE_SLIP;
    h->face = in->master ? e.face : -1;
    for (int i = 0; i < 3; ++i) h->t[i] = in->master ? (i < 2 ? e.t_cov[i] : 0.0) : e.traction[i];
  }
  return SK_OK;
}

/* The master faces follow the iterate (select_face, with hysteresis); the penalty problem is smooth in q apart from
 * the kinks at g = 0 and |t| = mu p, so there is no active-set loop: `changed` only reports whether a point changed
 * its face or state since the previous point. With --verbose each point's set is printed (this rank's owned nodes:
 * in contact, entered and left since the previous point, changed master face), where the Newton iterations of a
 * step go (docs/hertz.md, "Newton iterations and linear solvers"); at the first point of a step every node in
 * contact counts as entered. */
static sk_status pnts_update_active_set(sk_instance *in, const sk_state *st, int *changed) {
  point_eval e;
  int active = 0, entered = 0, left = 0, moved = 0;
  *changed = 0;
  for (int k = 0; k < in->n_slave; ++k) {
    if (in->master && in->evaluated[k]) { /* every node commit_step evaluates */
      int face = in->sel_face[k];
      SK_TRY(select_face(in, st->x, k));
      if (in->sel_face[k] != face && in->slave->owned[k]) {
        *changed = 1;
        moved += face >= 0;
      }
    }
    if (!in->slave->owned[k]) continue;
    SK_TRY(evaluate_point(in, st, k, 0, &e));
    if (e.state != in->last_state[k]) *changed = 1;
    active += e.state != STATE_INACTIVE;
    entered += e.state != STATE_INACTIVE && in->last_state[k] == STATE_INACTIVE;
    left += e.state == STATE_INACTIVE && in->last_state[k] != STATE_INACTIVE;
    in->last_state[k] = (unsigned char)e.state;
  }
  in->api->log(in->host, 2, "%s: penalty-nts: active set: %d slave nodes in contact, %d entered, %d left, %d changed "
               "master face", in->name, active, entered, left, moved);
  return SK_OK;
}

/* At a converged point the switch's memory must not have kept a node stuck whose trial lies outside the cone: the
 * return map alone decides each node again, a node where it differs forgets its memory, and the point is rejected
 * (Newton again from it, with the return map's state there). */
static sk_status agree_with_return_map(sk_instance *in, const sk_state *st, int *accept) {
  if (in->mu == 0.0) return SK_OK;
  point_eval with, without;
  int differ = 0;
  for (int k = 0; k < in->n_slave; ++k) {
    if (!in->slave->owned[k] || !in->held[k].slip) continue;
    SK_TRY(evaluate_point(in, st, k, 0, &with));
    in->return_map_only = 1;
    const sk_status status = evaluate_point(in, st, k, 0, &without);
    in->return_map_only = 0;
    SK_TRY(status);
    if (with.state == without.state) continue;
    in->held[k].slip = 0;
    ++differ;
  }
  if (differ == 0) return SK_OK;
  in->api->log(in->host, 2, "%s: penalty-nts: %d slave node(s) held in stick at the converged point slip by the return "
               "map; Newton again from it", in->name, differ);
  *accept = 0;
  return SK_OK;
}

/* A slave node whose closest face at the converged point is not among its candidates (it slid further within the
 * step than the predictor and the search margin reach) was held on its last face's extension: the candidates are
 * searched again over the box swept from x_n to the converged point, the faces selected there, and the point is
 * rejected, so that the host declares the new couplings (layout and pattern again) and Newton runs again from it.
 * Never an entry outside the declared pattern, never a converged step on a face that is not the closest (within
 * the search margin). */
static sk_status pnts_converged(sk_instance *in, const sk_state *st, int *accept) {
  *accept = 1;
  SK_TRY(agree_with_return_map(in, st, accept));
  if (!in->master) return SK_OK;
  int escaped = 0, reached = 0;
  for (int k = 0; k < in->n_slave; ++k) escaped += in->escaped[k];
  if (escaped == 0) return SK_OK;
  SK_TRY(find_candidates(in, st->x_n, st->x));
  for (int k = 0; k < in->n_slave; ++k) {
    if (!in->escaped[k]) continue;
    const int held = in->sel_face[k];
    in->sel_face[k] = -1;
    SK_TRY(select_face(in, st->x, k));
    /* still outside: its closest face lies beyond the search margin of its whole path, so it is not in contact
     * (a node far from the master, whose projection walked far): as without candidates */
    if (in->escaped[k]) {
      in->escaped[k] = 0;
      in->sel_face[k] = held;
    } else {
      reached++;
    }
  }
  if (reached == 0) return SK_OK;
  in->api->log(in->host, 2, "%s: penalty-nts: %d slave node(s) slid beyond their candidate faces; searching again "
               "and repeating Newton with the new faces", in->name, reached);
  *accept = 0;
  return SK_OK;
}

static sk_status pnts_commit_step(sk_instance *in, const sk_state *st) {
  point_eval e;
  for (int k = 0; k < in->n_slave; ++k) {
    if (!in->evaluated[k]) continue; /* another rank's node: its owner keeps its history */
    friction_history *c = &in->committed[k];
    memset(c, 0, sizeof *c);
    memset(in->slip_increment[k], 0, sizeof in->slip_increment[k]);
    if (in->mu == 0.0) continue;
    SK_TRY(evaluate_point(in, st, k, 0, &e));
    if (e.state == STATE_INACTIVE) continue;
    memcpy(in->slip_increment[k], e.slip, sizeof e.slip);
    in->slip[k] += sqrt(dot3(e.slip, e.slip));
    c->valid = 1;
    if (in->master) {
      c->face = e.face;
      c->xi[0] = e.xi[0];
      c->xi[1] = e.xi[1];
      c->t[0] = e.t_cov[0];
      c->t[1] = e.t_cov[1];
    } else {
      double d[3];
      in->cs->obstacle_displacement(in->obstacle, st->t, d);
      for (int i = 0; i < 3; ++i) {
        c->anchor[i] = e.x[i] - e.gap * e.normal[i] - d[i]; /* the closest point, in the obstacle's frame */
        c->traction[i] = e.traction[i];
      }
    }
  }
  return SK_OK;
}

/* History only changes in commit_step, and begin_step rebuilds the step's anchors from it: nothing to undo. */
static void pnts_reject_step(sk_instance *in) { (void)in; }

static sk_status pnts_report(sk_instance *in, const sk_state *st, sk_contact_report *r) {
  point_eval e;
  for (int k = 0; k < in->n_slave; ++k) {
    if (!in->slave->owned[k]) continue;
    SK_TRY(evaluate_point(in, st, k, 0, &e));
    if (e.state == STATE_INACTIVE) continue;
    ++r->active;
    if (e.state == STATE_STICK) ++r->stick;
    else ++r->slip;
    for (int i = 0; i < 3; ++i) r->force[i] += e.force[i];
    r->moment[0] += e.x[1] * e.force[2] - e.x[2] * e.force[1];
    r->moment[1] += e.x[2] * e.force[0] - e.x[0] * e.force[2];
    r->moment[2] += e.x[0] * e.force[1] - e.x[1] * e.force[0];
    r->dissipated += e.dissipation;
    r->constraint_norm = fmax(r->constraint_norm, fmax(-e.gap, 0.0));
  }
  if (in->mu == 0.0) r->stick = 0; /* frictionless points are neither stuck nor slipping */
  return SK_OK;
}

static sk_status pnts_points(sk_instance *in, const sk_state *st, sk_point_callback callback, void *ctx) {
  point_eval e;
  /* The recovery combines neighbouring nodes' forces: evaluate them first (ghosts too: mark_evaluated). */
  for (int k = 0; in->rec_start && k < in->n_slave; ++k) {
    if (!in->evaluated[k]) continue;
    SK_TRY(evaluate_point(in, st, k, 0, &e));
    double *stored = in->rec_force + REC_STRIDE * k;
    stored[0] = e.p;
    for (int i = 0; i < 3; ++i) stored[1 + i] = e.traction[i];
    stored[4] = e.state != STATE_INACTIVE;
    stored[5] = e.gap;
  }
  for (int k = 0; k < in->n_slave; ++k) {
    if (!in->slave->owned[k]) continue;
    SK_TRY(evaluate_point(in, st, k, 0, &e));
    sk_contact_point cp = {.struct_size = sizeof cp};
    memcpy(cp.x, e.x, sizeof cp.x);
    memcpy(cp.normal, e.normal, sizeof cp.normal);
    /* Pressure eps_n <-g> (force / reference area) when area weighted, the nodal force otherwise. */
    double scale = in->area_weighted && in->area[k] > 0.0 ? 1.0 / in->area[k] : 1.0;
    if (in->rec_start) {
      /* The recovered traction. A TRI6 corner opens where its consistent load would be tensile, inside the contact
       * zone and at its rim, by about the penetration of the edge nodes around it (hertz-3d tet10, refine 1.25: a
       * corner at r = 0.7 a opens by 1.5e-5 where they penetrate 7e-6); a node beyond the zone opens by the
       * geometry's gap (refine 1: 3.1e-4 at r = 1.01 a, 70x its neighbours' penetration). So an open node reports
       * the recovered traction when every edge node next to it is in contact (inside the zone), or when one is and
       * the node opens by at most RIM_GAP_FACTOR times the deepest one's penetration (at the rim: requiring every
       * neighbour there zeroed the corners at 0.95 <= r/a <= 1, most of the tet10 profile error at 71k unknowns;
       * docs/hertz.md). */
      int surrounded = 1;
      double deepest = 0.0;
      e.p = 0.0;
      memset(e.traction, 0, sizeof e.traction);
      for (int r = in->rec_start[k]; r < in->rec_start[k + 1]; ++r) {
        const double *stored = in->rec_force + REC_STRIDE * in->rec_node[r];
        e.p += in->rec_coef[r] * stored[0];
        for (int i = 0; i < 3; ++i) e.traction[i] += in->rec_coef[r] * stored[1 + i];
        if (in->rec_node[r] == k) continue;
        surrounded &= stored[4] != 0.0;
        if (stored[4] != 0.0) deepest = fmax(deepest, -stored[5]);
      }
      const int interior = surrounded && in->rec_start[k + 1] - in->rec_start[k] > 1;
      if (e.state == STATE_INACTIVE && !interior && !(deepest > 0.0 && e.gap <= RIM_GAP_FACTOR * deepest)) {
        e.p = 0.0;
        memset(e.traction, 0, sizeof e.traction);
      }
    }
    cp.pressure = e.p * scale;
    for (int i = 0; i < 3; ++i) cp.traction[i] = e.traction[i] * scale;
    cp.area = in->area_weighted ? in->area[k] : 0.0;
    cp.forces = !in->area_weighted; /* nodal stiffnesses give nodal forces: the host divides by its own areas */
    cp.gap = e.gap; /* NaN when no master face is within the search margin */
    cp.state = e.state; /* frictionless contact points report 1 (in contact) */
    cp.slave_node = in->slave->node_id[k];
    cp.has_slip = in->mu > 0.0;
    memcpy(cp.slip_increment, in->slip_increment[k], sizeof cp.slip_increment);
    cp.slip = in->slip[k];
    callback(ctx, &cp);
  }
  return SK_OK;
}

/* ---- checkpoints (stickslip.checkpoint.v1): the committed friction history, by slave node ------------------------- */

/* A slave node's record: its friction anchor and the slip it has accumulated (contact.csv's `slip`). */
typedef struct {
  friction_history anchor;
  double slip;
} saved_node;

/* One record per slave node with history, under its node_index, the master face as its whole cell index. */
static sk_status pnts_save(sk_instance *in, const sk_state *st, sk_record_writer *writer) {
  (void)st;
  for (int k = 0; k < in->n_slave; ++k) {
    if (!in->slave->owned[k] || (!in->committed[k].valid && in->slip[k] == 0.0)) continue;
    saved_node r = {.anchor = in->committed[k], .slip = in->slip[k]};
    if (in->master && r.anchor.valid) r.anchor.face = (int)in->master->cell_index[r.anchor.face];
    writer->put(writer, in->slave->node_index[k], &r, (uint32_t)sizeof r);
  }
  return SK_OK;
}

/* The history of every slave node this rank holds (owned and ghost; commit_step keeps the evaluated ones'). */
static sk_status pnts_load(sk_instance *in, const sk_state *st, const sk_record_reader *reader) {
  (void)st;
  int *cells = in->master ? records_cells_of_view(in->master) : NULL;
  if (in->master && !cells) return in->api->error(in->host, SK_ERR_NOMEM, "penalty-nts: out of memory");
  sk_status status = SK_OK;
  for (int k = 0; k < in->n_slave && status == SK_OK; ++k) {
    saved_node r;
    memset(&in->committed[k], 0, sizeof in->committed[k]);
    in->slip[k] = 0.0;
    const int64_t got = reader->get(reader, in->slave->node_index[k], &r, (uint32_t)sizeof r);
    if (got < 0) continue;
    if (got != (int64_t)sizeof r)
      status = in->api->error(in->host, SK_ERR_INPUT, "penalty-nts: slave node %lld: a history record of %lld bytes, "
                              "expected %zu", (long long)in->slave->node_id[k], (long long)got, sizeof r);
    else if (in->master && r.anchor.valid && (r.anchor.face = records_view_cell(cells, in->master, r.anchor.face)) < 0)
      status = in->api->error(in->host, SK_ERR_INPUT, "penalty-nts: slave node %lld: its friction anchor lies on a "
                              "master face this rank does not hold", (long long)in->slave->node_id[k]);
    else {
      in->committed[k] = r.anchor;
      in->slip[k] = r.slip;
    }
  }
  free(cells);
  return status;
}

static const sk_checkpoint_ext pnts_checkpoint = {SK_TABLE_HEADER(sk_checkpoint_ext), .save = pnts_save,
                                                  .load = pnts_load};

static const void *pnts_extension(const char *id) {
  return id && strcmp(id, SK_EXT_CHECKPOINT) == 0 ? &pnts_checkpoint : NULL;
}

static const sk_plugin pnts_plugin = {
    SK_TABLE_HEADER(sk_plugin),
    .name = "penalty-nts",
    .summary = "node-to-surface penalty contact with penalty-regularised Coulomb friction (baseline)",
    .kinds = SK_KIND_PAIR,
    .caps = SK_CAP_2D | SK_CAP_3D | SK_CAP_FRICTION | SK_CAP_QUASISTATIC | SK_CAP_DYNAMICS | SK_CAP_RIGID_OBSTACLE |
            SK_CAP_DEFORMABLE_MASTER | SK_CAP_SAYS_IDLE | SK_CAP_SELF_CONTACT,
    .strategies = pnts_strategies,
    .parameters = pnts_parameters,
    .create = pnts_create,
    .destroy = pnts_destroy,
    .begin_step = pnts_begin_step,
    .layout = pnts_layout,
    .pattern = pnts_pattern,
    .update_active_set = pnts_update_active_set,
    .residual = pnts_residual,
    .jacobian = pnts_jacobian,
    .converged = pnts_converged,
    .commit_step = pnts_commit_step,
    .reject_step = pnts_reject_step,
    .report = pnts_report,
    .points = pnts_points,
    .get_extension = pnts_extension,
    .check = pnts_check,
};

PNTS_EXPORT const sk_plugin *stickslip_plugin_entry(void);
PNTS_EXPORT const sk_plugin *stickslip_plugin_entry(void) { return &pnts_plugin; }
