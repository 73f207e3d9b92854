/* covariant-penalty — the step: broad phase, the master face of each contact point, the local point handed to the
 * kernel, history, assembly and output (ABI v2 calls begin_step ... points). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "glue.h"

/* ---- small helpers ---------------------------------------------------------------------------------------------- */

sk_surface_point cp_new_surface_point(void) {
  sk_surface_point p;
  memset(&p, 0, sizeof p);
  p.struct_size = sizeof p;
  return p;
}

static void face_positions(const sk_view *v, const double *x, int face, double *xf) {
  for (int k = 0; k < v->nen; ++k) memcpy(xf + 3 * k, x + 3 * (size_t)v->conn[(size_t)face * v->nen + k], 3 * sizeof *xf);
}

static void slave_point(const entity *e, const double *xs, double r[3]) {
  r[0] = r[1] = r[2] = 0.0;
  for (int a = 0; a < e->n_slave; ++a)
    for (int i = 0; i < 3; ++i) r[i] += e->S[a] * xs[3 * (size_t)e->slave[a] + i];
}

/* Closest point of r on the extension of master face `face` from xi; 1 when it converged within `band`. */
static int closest_on_face(const sk_instance *in, const double *xm, int face, const double r[3], double xi[2],
                           double band) {
  double xf[3 * CP_MAX_FACE_NODES], guess[2] = {xi[0], xi[1]};
  face_positions(in->master, xm, face, xf);
  if (cp_closest_point(&in->face, xf, r, guess, CLOSEST_ITERATIONS) < 0 || !cand_within_band(in->face.type, guess, band))
    return 0;
  xi[0] = guess[0];
  xi[1] = guess[1];
  return 1;
}

static int obstacle_distance(void *ctx, const double y[3], double *distance, double normal[3]) {
  const distance_ctx *d = ctx;
  sk_surface_point p = cp_new_surface_point();
  if (d->cs->obstacle_project(d->obstacle, d->t, y, 3, &p, distance) != SK_OK) return 0;
  memcpy(normal, p.n, 3 * sizeof(double));
  return 1;
}

/* ---- master face selection (sts, nts) ---------------------------------------------------------------------------- */

/* The closest-point projection over the candidates with the master_extension treatment at the master's border. */
static sk_status project_global(const sk_instance *in, const entity *e, const double *xm, const double r[3],
                                int *face, double xi[2], int *beyond) {
  *face = -1;
  *beyond = 0;
  xi[0] = xi[1] = 0.0;
  if (e->cand_count == 0) return SK_OK;
  sk_projection proj;
  memset(&proj, 0, sizeof proj);
  proj.struct_size = sizeof proj;
  SK_TRY(in->cs->project(in->master, xm, r, in->cand.faces + e->cand_start, e->cand_count, &proj)); /* diverged: cut */
  if (proj.face < 0) return SK_OK;
  *face = proj.face;
  xi[0] = proj.xi[0];
  xi[1] = proj.xi[1];
  if (proj.kind != SK_PROJ_OUTSIDE) return SK_OK;
  *beyond = !(in->extension > 0.0 && closest_on_face(in, xm, proj.face, r, xi, in->extension));
  return SK_OK;
}

/* The face of entity e at master positions xm: the projection, except that a face selected earlier in the step is
 * kept while the point stays within SELECT_BAND beyond it. The projection walks across faces from the candidates,
 * so under large sliding it may end on a face whose couplings cp_pattern did not declare: such a point stays on its
 * last face's extension until Newton converges, and cp_converged searches again. */
static sk_status select_face(const sk_instance *in, entity *e, const double *xs, const double *xm) {
  double r[3], xi[2];
  int face, beyond;
  slave_point(e, xs, r);
  SK_TRY(project_global(in, e, xm, r, &face, xi, &beyond));
  e->escaped = face >= 0 && !cand_contains(&in->cand, e->cand_start, e->cand_count, face);
  if (e->escaped) {
    face = e->sel_face;
    beyond = face >= 0 ? e->sel_beyond : 0;
    xi[0] = e->sel_xi[0];
    xi[1] = e->sel_xi[1];
  }
  if (e->sel_face >= 0 && e->sel_face != face && face >= 0 && !beyond) {
    double keep[2] = {e->sel_xi[0], e->sel_xi[1]};
    if (closest_on_face(in, xm, e->sel_face, r, keep, SELECT_BAND)) {
      e->sel_xi[0] = keep[0];
      e->sel_xi[1] = keep[1];
      e->sel_beyond = 0;
      return SK_OK;
    }
  }
  e->sel_face = face;
  e->sel_xi[0] = xi[0];
  e->sel_xi[1] = xi[1];
  e->sel_beyond = beyond;
  return SK_OK;
}

/* ---- one contact point made local -------------------------------------------------------------------------------- */
static int add_node(local_point *L, int view, int node, const sk_view *v, const double *x) {
  for (int k = 0; k < L->pt.n_local; ++k)
    if (L->view[k] == view && L->node[k] == node) return k;
  int k = L->pt.n_local++;
  L->view[k] = view;
  L->node[k] = node;
  memcpy(L->x + 3 * k, x + 3 * (size_t)node, 3 * sizeof(double));
  for (int i = 0; i < 3; ++i) L->rows[3 * k + i] = v->dofs[3 * (size_t)node + i];
  return k;
}

int cp_local_point(sk_instance *in, const entity *e, const sk_state *st, local_point *L) {
  memset(&L->pt, 0, sizeof L->pt);
  cp_point *pt = &L->pt;
  const double *xs = st->x[0];
  pt->x = L->x;
  pt->master = in->face;
  if (in->variant == CP_STAS) {
    pt->variant = CP_STAS;
    for (int k = 0; k < in->slave->nen; ++k)
      pt->master_nodes[k] = add_node(L, 0, in->slave->conn[(size_t)e->cell * in->slave->nen + k], in->slave, xs);
    pt->xi[0] = e->eta[0];
    pt->xi[1] = e->eta[1];
    in->distance.t = st->t;
    in->cs->obstacle_displacement(in->obstacle, st->t, pt->obstacle_d);
    pt->distance = obstacle_distance;
    pt->distance_ctx = &in->distance;
    pt->max_depth = in->max_depth;
    pt->history = e->anchor.valid;
    memcpy(pt->t_n, e->anchor.t, sizeof pt->t_n);
    memcpy(pt->anchor, e->anchor.anchor, sizeof pt->anchor);
    return 1;
  }
  if (e->sel_face < 0 || e->sel_beyond) return 0;
  const double *xm = st->x[1];
  pt->variant = in->variant;
  double r[3];
  slave_point(e, xs, r);
  pt->xi[0] = e->sel_xi[0];
  pt->xi[1] = e->sel_xi[1];
  if (!closest_on_face(in, xm, e->sel_face, r, pt->xi, HUGE_VAL)) return 0; /* the band was checked at selection */
  pt->n_slave = e->n_slave;
  for (int a = 0; a < e->n_slave; ++a) {
    pt->slave[a] = add_node(L, 0, e->slave[a], in->slave, xs);
    pt->S[a] = e->S[a];
  }
  for (int k = 0; k < in->master->nen; ++k) {
    int node = in->master->conn[(size_t)e->sel_face * in->master->nen + k];
    pt->master_nodes[k] = add_node(L, 1, node, in->master, xm);
  }
  if (e->anchor.valid) {
    pt->history = 1;
    memcpy(pt->t_n, e->anchor.t, sizeof pt->t_n);
    double dN[2 * CP_MAX_FACE_NODES];
    in->face.shape(in->face.type, e->anchor.xi, pt->N_old, dN);
    pt->n_old = in->master->nen;
    for (int k = 0; k < in->master->nen; ++k)
      pt->old_nodes[k] = add_node(L, 1, in->master->conn[(size_t)e->anchor.face * in->master->nen + k], in->master, xm);
  }
  return 1;
}

cp_params cp_point_params(const sk_instance *in, const entity *e) {
  return (cp_params){.eps_n = in->eps_n, .eps_t = in->eps_t, .mu = in->mu, .weight = e->weight,
                     .touch_tol = in->touch_tol};
}

/* Evaluates entity e (residual only when K is NULL). */
static sk_status evaluate(sk_instance *in, const entity *e, const sk_state *st, local_point *L, cp_result *r,
                          int jacobian) {
  if (!cp_local_point(in, e, st, L)) {
    memset(r, 0, sizeof *r);
    r->state = CP_INACTIVE;
    r->g = NAN;
    return SK_OK;
  }
  cp_params par = cp_point_params(in, e);
  if (!jacobian) {
    cp_point_residual(&L->pt, &par, NULL, r);
    return SK_OK;
  }
  if (cp_point_eval(&L->pt, &par, in->form, in->want, r, in->K) != 0)
    return in->api->error(in->host, SK_ERR_DIVERGED, "covariant-penalty: a contact point sits at a focal point of "
                          "master face %d (a_ij - g h_ij singular)", e->sel_face);
  return SK_OK;
}


/* ---- the step ---------------------------------------------------------------------------------------------------- */

/* Candidate master faces of every point from boxes swept between x_n and x (the predictor at begin_step, the
 * converged point in cp_converged), inflated by the search margin. */
static sk_status find_candidates(sk_instance *in, const sk_state *st, const double *xs) {
  in->cs->search_update(in->search, st->x_n[1], st->x[1], in->margin);
  in->cand.used = 0;
  for (int k = 0; k < in->n_entities; ++k) {
    entity *e = &in->entities[k];
    double r0[3], r1[3];
    slave_point(e, st->x_n[0], r0);
    slave_point(e, xs, r1);
    if (cand_query_swept(in->cs, in->search, r0, r1, 3, in->margin, &in->cand, &e->cand_start, &e->cand_count) != 0)
      return in->api->error(in->host, SK_ERR_NOMEM, "covariant-penalty: out of memory");
  }
  return SK_OK;
}

/* The step's candidate faces (find_candidates) and friction anchors: the committed history, or for a point without
 * one its projection at x_n with t = 0 (the zero-load projection of the paper's Table 1). The master face of every
 * point is selected at the predictor. */
sk_status cp_begin_step(sk_instance *in, const sk_state *st) {
  const double *xs = st->x[0], *xs_n = st->x_n[0];
  if (in->master) SK_TRY(find_candidates(in, st, xs));
  for (int k = 0; k < in->n_entities; ++k) {
    entity *e = &in->entities[k];
    e->anchor = e->committed;
    e->last_state = CP_INACTIVE;
    /* The contact point of the last step starts the selection, so that its face's hysteresis (select_face) carries
     * over: a point held on a face's extension stays there, and the step starts where the last one ended, at
     * Delta rho = 0 (47) up to round-off, instead of on a neighbouring face's polynomial, a different point. */
    e->sel_face = in->master && e->committed.valid ? e->committed.face : -1;
    e->sel_xi[0] = e->committed.xi[0];
    e->sel_xi[1] = e->committed.xi[1];
    e->sel_beyond = 0;
    if (in->mu == 0.0 || e->anchor.valid) continue;
    history *a = &e->anchor;
    memset(a, 0, sizeof *a);
    if (in->master) {
      /* A point that enters contact during the step from beyond the master's border (the leading edge of a sliding
       * body) is anchored on the face's extension, up to a whole face away: without an anchor it would carry
       * pressure but no friction in its first step (measured: F_x/F_y of 6.1 run B fell from 0.3 to 0.296). */
      double r0[3];
      int face, beyond;
      slave_point(e, xs_n, r0);
      SK_TRY(project_global(in, e, st->x_n[1], r0, &face, a->xi, &beyond));
      if (face >= 0 && beyond) beyond = !closest_on_face(in, st->x_n[1], face, r0, a->xi, 0.5);
      a->face = face;
      a->valid = face >= 0 && !beyond;
    } else {
      double xf[3 * CP_MAX_FACE_NODES], d[3];
      sk_surface_point p;
      face_positions(in->slave, xs_n, e->cell, xf);
      if (cp_face_point(&in->face, xf, e->eta, &p) != 0) continue;
      in->cs->obstacle_displacement(in->obstacle, st->t_n, d);
      for (int i = 0; i < 3; ++i) a->anchor[i] = p.x[i] - d[i];
      a->valid = 1;
    }
  }
  if (in->master)
    for (int k = 0; k < in->n_entities; ++k) SK_TRY(select_face(in, &in->entities[k], xs, st->x[1]));
  return SK_OK;
}

sk_status cp_layout(sk_instance *in, const sk_state *st, sk_layout *layout) {
  (void)st;
  layout->n_extra = 0;
  layout->initial = NULL;
  layout->eliminated = NULL;
  /* no point has a candidate face: every selection stays -1 (project_global), so no point is evaluated */
  if (SK_HAS(layout, idle)) layout->idle = in->master && in->cand.used == 0;
  return SK_OK;
}

/* Every point couples its slave nodes with each candidate master face and the face of its anchor. */
sk_status cp_pattern(sk_instance *in, const sk_state *st, sk_pattern *pattern) {
  local_point L;
  for (int k = 0; k < in->n_entities; ++k) {
    const entity *e = &in->entities[k];
    int n_faces = in->master ? e->cand_count : 1;
    for (int c = 0; c < n_faces; ++c) {
      L.pt.n_local = 0;
      if (!in->master) {
        for (int j = 0; j < in->slave->nen; ++j)
          add_node(&L, 0, in->slave->conn[(size_t)e->cell * in->slave->nen + j], in->slave, st->x[0]);
      } else {
        int face = in->cand.faces[e->cand_start + c];
        for (int a = 0; a < e->n_slave; ++a) add_node(&L, 0, e->slave[a], in->slave, st->x[0]);
        for (int j = 0; j < in->master->nen; ++j)
          add_node(&L, 1, in->master->conn[(size_t)face * in->master->nen + j], in->master, st->x[1]);
        if (e->anchor.valid)
          for (int j = 0; j < in->master->nen; ++j)
            add_node(&L, 1, in->master->conn[(size_t)e->anchor.face * in->master->nen + j], in->master, st->x[1]);
      }
      int nd = 3 * L.pt.n_local;
      pattern->add_block(pattern, nd, L.rows, nd, L.rows);
    }
  }
  return SK_OK;
}

/* At a new point x: the master face of every point (with hysteresis) and its state. */
sk_status cp_update_active_set(sk_instance *in, const sk_state *st, int *changed) {
  local_point L;
  cp_result r;
  int faces = 0, states[3][3] = {{0}};
  *changed = 0;
  for (int k = 0; k < in->n_entities; ++k) {
    entity *e = &in->entities[k];
    if (in->master) {
      int face = e->sel_face;
      SK_TRY(select_face(in, e, st->x[0], st->x[1]));
      faces += e->sel_face != face;
    }
    SK_TRY(evaluate(in, e, st, &L, &r, 0));
    states[e->last_state][r.state]++;
    e->last_state = r.state;
  }
  int flips = faces;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      if (a != b) flips += states[a][b];
  *changed = flips > 0;
  in->api->log(in->host, 2, "covariant-penalty: %d face changes; inactive->stick %d, ->slip %d; stick->inactive %d, "
               "->slip %d; slip->inactive %d, ->stick %d", faces, states[0][1], states[0][2], states[1][0],
               states[1][2], states[2][0], states[2][1]);
  return SK_OK;
}

/* A point whose closest face at the converged point is not among its candidates (it slid further within the step
 * than the predictor and the search margin reach) was held on its last face's extension: the candidates are searched
 * again over the box swept from x_n to the converged point, the faces selected there, and the point is rejected, so
 * that the host declares the new couplings (layout and pattern again) and Newton runs again from it. */
sk_status cp_converged(sk_instance *in, const sk_state *st, int *accept) {
  *accept = 1;
  if (!in->master) return SK_OK;
  int escaped = 0, reached = 0;
  for (int k = 0; k < in->n_entities; ++k) escaped += in->entities[k].escaped;
  if (escaped == 0) return SK_OK;
  SK_TRY(find_candidates(in, st, st->x[0]));
  for (int k = 0; k < in->n_entities; ++k) {
    entity *e = &in->entities[k];
    if (!e->escaped) continue;
    const int held = e->sel_face;
    e->sel_face = -1;
    SK_TRY(select_face(in, e, st->x[0], st->x[1]));
    /* still outside: its closest face lies beyond the search margin of its whole path, so it is not in contact */
    if (e->escaped) {
      e->escaped = 0;
      e->sel_face = held;
    } else {
      reached++;
    }
  }
  if (reached == 0) return SK_OK;
  in->api->log(in->host, 2, "covariant-penalty: %d contact point(s) slid beyond their candidate faces; searching "
               "again and repeating Newton with the new faces", reached);
  *accept = 0;
  return SK_OK;
}

sk_status cp_residual(sk_instance *in, const sk_state *st, sk_sink *sink) {
  local_point L;
  cp_result r;
  for (int k = 0; k < in->n_entities; ++k) {
    SK_TRY(evaluate(in, &in->entities[k], st, &L, &r, 0));
    if (r.state != CP_INACTIVE) sink->add_vector(sink, r.nd, L.rows, r.R);
  }
  return SK_OK;
}

sk_status cp_jacobian(sk_instance *in, const sk_state *st, sk_sink *sink) {
  local_point L;
  cp_result r;
  for (int k = 0; k < in->n_entities; ++k) {
    SK_TRY(evaluate(in, &in->entities[k], st, &L, &r, 1));
    if (r.state == CP_INACTIVE) continue;
    const int nd = r.nd;
    for (int i = 0; i < nd * nd; ++i) {
      double v = 0.0;
      for (int part = 0; part < CP_N_PARTS; ++part)
        if (in->want[part]) v += in->K[part][i];
      in->K_sum[i] = v;
    }
    sink->add_matrix(sink, nd, L.rows, nd, L.rows, in->K_sum);
  }
  return SK_OK;
}

/* The converged point's contact point and traction become the history (47), (51); inactive points lose theirs. */
sk_status cp_commit_step(sk_instance *in, const sk_state *st) {
  local_point L;
  cp_result r;
  for (int k = 0; k < in->n_entities; ++k) {
    entity *e = &in->entities[k];
    history *c = &e->committed;
    SK_TRY(evaluate(in, e, st, &L, &r, 0));
    memset(c, 0, sizeof *c);
    memset(e->slip_increment, 0, sizeof e->slip_increment);
    if (r.state == CP_INACTIVE || in->mu == 0.0) continue;
    const double sign = in->variant == CP_STAS ? -1.0 : 1.0; /* on the scene's slave (stas: the deformable side) */
    for (int i = 0; i < 3; ++i) e->slip_increment[i] = sign * r.slip[i];
    e->slip += sqrt(e->slip_increment[0] * e->slip_increment[0] + e->slip_increment[1] * e->slip_increment[1] +
                    e->slip_increment[2] * e->slip_increment[2]);
    c->valid = 1;
    memcpy(c->t, r.t, sizeof c->t);
    if (in->master) {
      c->face = e->sel_face;
      c->xi[0] = L.pt.xi[0];
      c->xi[1] = L.pt.xi[1];
    } else {
      double d[3];
      in->cs->obstacle_displacement(in->obstacle, st->t, d);
      for (int i = 0; i < 3; ++i) c->anchor[i] = r.x_master[i] - d[i];
    }
  }
  return SK_OK;
}

/* History changes only in commit_step and begin_step rebuilds the anchors from it: nothing to undo. */
void cp_reject_step(sk_instance *in) { (void)in; }

/* The force on the scene's slave surface of one point: w s on the slave (sts, nts); stas: the slave is the
 * deformable surface, which carries -w s (s acts on the rigid surface, the paper's "slave"). */
static void slave_force(const sk_instance *in, const entity *e, const cp_result *r, double f[3], double x[3]) {
  const double sign = in->variant == CP_STAS ? -1.0 : 1.0;
  for (int i = 0; i < 3; ++i) {
    f[i] = sign * e->weight * (r->p * r->n[i] + r->t[i]);
    x[i] = in->variant == CP_STAS ? r->x_master[i] : r->x_master[i] + r->g * r->n[i]; /* rho, or r_s */
  }
}

sk_status cp_report(sk_instance *in, const sk_state *st, sk_contact_report *rep) {
  local_point L;
  cp_result r;
  for (int k = 0; k < in->n_entities; ++k) {
    const entity *e = &in->entities[k];
    SK_TRY(evaluate(in, e, st, &L, &r, 0));
    if (r.state == CP_INACTIVE) continue;
    double f[3], x[3];
    slave_force(in, e, &r, f, x);
    ++rep->active;
    if (in->mu > 0.0) {
      if (r.state == CP_STICK) ++rep->stick;
      else ++rep->slip;
    }
    for (int i = 0; i < 3; ++i) rep->force[i] += f[i];
    rep->moment[0] += x[1] * f[2] - x[2] * f[1];
    rep->moment[1] += x[2] * f[0] - x[0] * f[2];
    rep->moment[2] += x[0] * f[1] - x[1] * f[0];
    rep->dissipated += r.dissipation;
    rep->constraint_norm = fmax(rep->constraint_norm, fmax(-r.g, 0.0));
  }
  return SK_OK;
}

sk_status cp_points(sk_instance *in, const sk_state *st, sk_point_callback callback, void *ctx) {
  local_point L;
  cp_result r;
  for (int k = 0; k < in->n_entities; ++k) {
    const entity *e = &in->entities[k];
    SK_TRY(evaluate(in, e, st, &L, &r, 0));
    sk_contact_point cp;
    memset(&cp, 0, sizeof cp);
    cp.struct_size = sizeof cp;
    double f[3];
    slave_force(in, e, &r, f, cp.x);
    if (r.state == CP_INACTIVE) { /* no master point: report the slave point at rest with a NaN gap */
      double xf[3 * CP_MAX_FACE_NODES], rs[3];
      sk_surface_point p;
      if (in->variant == CP_STAS) {
        face_positions(in->slave, st->x[0], e->cell, xf);
        cp_face_point(&in->face, xf, e->eta, &p);
        memcpy(cp.x, p.x, sizeof cp.x);
      } else {
        slave_point(e, st->x[0], rs);
        memcpy(cp.x, rs, sizeof cp.x);
      }
    }
    const double sign = in->variant == CP_STAS ? -1.0 : 1.0; /* quantities on the scene's slave */
    for (int i = 0; i < 3; ++i) {
      cp.normal[i] = sign * r.n[i];
      cp.traction[i] = sign * r.t[i];
    }
    cp.pressure = r.p;
    /* p = eps_n <-g> is a traction on the point's reference area, or a force when nodal stiffnesses have no area */
    cp.forces = in->variant == CP_NTS && !in->area_weighted;
    cp.area = cp.forces ? 0.0 : e->weight;
    cp.gap = r.g;
    cp.state = r.state;
    cp.slave_node = in->variant == CP_NTS ? in->slave->node_id[e->slave[0]] : -1;
    cp.slave_face = in->variant == CP_NTS ? -1 : in->slave->cell_index[e->cell];
    cp.has_slip = in->mu > 0.0;
    memcpy(cp.slip_increment, e->slip_increment, sizeof cp.slip_increment);
    cp.slip = e->slip;
    if (in->variant == CP_STS) { /* a Gauss point's reference position, as cp.x on the reference positions */
      slave_point(e, in->slave->X, cp.X);
    } else if (in->variant == CP_STAS) {
      double xf[3 * CP_MAX_FACE_NODES];
      sk_surface_point p = {.struct_size = sizeof p};
      face_positions(in->slave, in->slave->X, e->cell, xf);
      cp_face_point(&in->face, xf, e->eta, &p);
      memcpy(cp.X, p.x, sizeof cp.X);
    }
    callback(ctx, &cp);
  }
  return SK_OK;
}
