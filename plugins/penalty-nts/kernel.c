/* penalty-nts: the evaluation of one slave node (gap, forces, local Jacobian), the kernel of residual, Jacobian,
 * active set, report and points; the formulation is described at the top of penalty_nts.c. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "penalty_nts.h"

/* ---- evaluation of one slave node ------------------------------------------------------------------------------- */

/* The traction slave node k held while slipping at the last Jacobian's point, in the basis the evaluation on `face`
 * uses (-1: an obstacle), or NULL: the return map decides alone (a node that stuck there, or that has changed face
 * since, whose old covariant components would mean nothing on the new one). */
static const double *held_traction(const sk_instance *in, int k, int face) {
  const held_friction *h = &in->held[k];
  return !in->return_map_only && h->slip && h->face == face ? h->t : NULL;
}

/* Evaluates slave node k at state->x and state->t: gap, forces and, when want_jacobian, the local Jacobian. The
 * covariant kinematics and friction (dxi, dn, the metric derivatives, the return map) are the shared kernel's
 * (plugins/common/covariant.h). */
sk_status evaluate_point(sk_instance *in, const sk_state *st, int k, int want_jacobian, point_eval *e) {
  const sk_contact_services *cs = in->cs;
  const int dim = in->dim, pdim = dim - 1;
  const int64_t slave_node = in->slave->node_id[k];
  const sk_view *master = in->master;
  double xs[3];
  slave_position(in, st->x, k, xs);

  e->found = 0;
  e->state = STATE_INACTIVE;
  e->face = -1;
  e->gap = NAN;
  e->p = 0.0;
  e->dissipation = 0.0;
  e->nd = 0;
  memcpy(e->x, xs, sizeof xs);
  memset(e->normal, 0, sizeof e->normal);
  memset(e->force, 0, sizeof e->force);
  memset(e->traction, 0, sizeof e->traction);
  memset(e->t_cov, 0, sizeof e->t_cov);
  memset(e->slip, 0, sizeof e->slip);

  sk_surface_point pt = {.struct_size = sizeof pt};
  double g;
  int nen = 0;
  const int32_t *conn = NULL;
  if (master) {
    /* The face chosen by select_face (begin_step, update_active_set); the closest point on its polynomial
     * extension, so that the residual is smooth in q between selections. Beyond the master's border (and its band)
     * the clamped projection gives the reported gap. */
    sk_projection proj;
    proj.face = in->sel_face[k];
    if (proj.face < 0) return SK_OK;
    proj.xi[0] = in->sel_xi[k][0];
    proj.xi[1] = in->sel_xi[k][1];
    cs->geometry(master, proj.face, proj.xi, st->x[1], &pt);
    pt.xi[0] = proj.xi[0];
    pt.xi[1] = proj.xi[1];
    int beyond = in->sel_beyond[k];
    if (!beyond) {
      sk_surface_point extended = pt;
      extend_on_face(in, proj.face, xs, st->x[1], HUGE_VAL, &extended); /* band checked by select_face */
      pt = extended;
      proj.xi[0] = pt.xi[0];
      proj.xi[1] = pt.xi[1];
    }
    if (!cov_complete_metric(pdim, &pt)) return SK_OK; /* degenerate face: no contact there */
    nen = master->nen;
    conn = master->conn + proj.face * nen;
    for (int I = 0; I < nen; ++I)
      if (master->node_id[conn[I]] == slave_node) return SK_OK; /* a node never contacts a face it belongs to */
    double d[3] = {xs[0] - pt.x[0], xs[1] - pt.x[1], xs[2] - pt.x[2]};
    g = dot3(d, pt.n);
    e->found = 1;
    e->face = proj.face;
    e->xi[0] = proj.xi[0];
    e->xi[1] = proj.xi[1];
    e->gap = g;
    memcpy(e->normal, pt.n, sizeof pt.n);
    if (beyond) return SK_OK; /* beyond the master's border (and its extension band) */
  } else {
    SK_TRY(cs->obstacle_project(in->obstacle, st->t, xs, dim, &pt, &g));
    if (!cov_complete_metric(pdim, &pt))
      return in->api->error(in->host, SK_ERR_INTERNAL, "%s: degenerate obstacle tangents", in->name);
    e->found = 1;
    e->gap = g;
    memcpy(e->normal, pt.n, sizeof pt.n);
  }
  /* Active when penetrating, and also when just touching (g = 0 up to round-off): p is 0 there, but the Jacobian
   * then carries the penetrating side's stiffness, so bodies that start in contact without other support (a patch
   * test, stacked blocks) do not give a singular first Newton matrix. */
  if (!(g <= in->touch_tolerance)) return SK_OK;

  /* Local dofs: the slave node, then the master face nodes (none for an obstacle). */
  const int nd = dim * (1 + nen);
  e->nd = nd;
  for (int i = 0; i < dim; ++i) e->rows[i] = in->slave->dofs[k * dim + i];
  for (int I = 0; I < nen; ++I)
    for (int i = 0; i < dim; ++i) e->rows[dim * (1 + I) + i] = master->dofs[conn[I] * dim + i];

  const double eps_n = in->penalty * in->area[k], eps_t = in->penalty_t * in->area[k];
  const double *n = pt.n;
  const double p = g < 0.0 ? -eps_n * g : 0.0;
  e->p = p;

  /* dg/dq, dxi/dq, dn/dq over the local dofs */
  cov_kinematics kin;
  if (!cov_kinematics_eval(&pt, dim, nen, g, &kin))
    return in->api->error(in->host, SK_ERR_DIVERGED, "%s: slave node %lld sits at a focal point of the master (m - g "
                          "h singular)", in->name, (long long)slave_node);
  double Dp[MAX_LOCAL_DOFS]; /* the penetrating side's derivative, also at g = 0 */
  for (int c = 0; c < nd; ++c) Dp[c] = -eps_n * kin.G[c];

  /* Tangential force T and its derivative DT. */
  double T[3] = {0.0, 0.0, 0.0}, DT[3][MAX_LOCAL_DOFS] = {{0}};
  e->state = STATE_STICK; /* frictionless contact reports as stick (no slip state to speak of) */
  const friction_history *h = &in->anchor[k];
  if (in->mu > 0.0 && h->valid && master) {
    /* Increment of the master parameters since the anchor. A slave that moved onto another face gets the anchor
     * carried over through the current tangent plane (frozen within the iteration: inexact tangent there only). */
    double dxi[2] = {0.0, 0.0}, tn[2] = {0.0, 0.0};
    if (h->face == e->face) {
      for (int a = 0; a < pdim; ++a) {
        dxi[a] = e->xi[a] - h->xi[a];
        tn[a] = h->t[a];
      }
    } else {
      sk_surface_point old = {.struct_size = sizeof old};
      cs->geometry(master, h->face, h->xi, st->x[1], &old);
      cov_complete_metric(pdim, &old);
      double told[3] = {0.0, 0.0, 0.0}, rel[3];
      for (int i = 0; i < 3; ++i) {
        for (int a = 0; a < pdim; ++a) told[i] += h->t[a] * old.a_dual[a][i];
        rel[i] = pt.x[i] - old.x[i];
      }
      for (int a = 0; a < pdim; ++a) {
        dxi[a] = dot3(pt.a_dual[a], rel);
        tn[a] = dot3(told, pt.a[a]);
      }
    }
    for (int i = 0; i < 3; ++i)
      for (int a = 0; a < pdim; ++a) e->slip[i] += dxi[a] * pt.a[a][i];
    cov_metric_derivatives metric;
    cov_metric_derivatives_eval(&pt, &kin, &metric);
    e->state = cov_friction(&pt, &kin, &metric, tn, dxi, eps_t, in->mu, p, Dp, held_traction(in, k, e->face),
                            e->t_cov, T, DT, &e->dissipation);
  } else if (in->mu > 0.0 && h->valid) {
    /* Obstacle: trial = P w, w = t_n - eps_t (x_s - x_anchor(t)), P = I - n n; D(P w) = P Dw - Dn (n.w) - n (w.Dn). */
    double d[3], w[3], nw;
    cs->obstacle_displacement(in->obstacle, st->t, d);
    for (int i = 0; i < 3; ++i) w[i] = h->traction[i] - eps_t * (xs[i] - (h->anchor[i] + d[i]));
    nw = dot3(n, w);
    double rel[3], rel_n;
    for (int i = 0; i < 3; ++i) rel[i] = xs[i] - (h->anchor[i] + d[i]);
    rel_n = dot3(n, rel);
    for (int i = 0; i < 3; ++i) e->slip[i] = rel[i] - rel_n * n[i];
    double trial[3], Dtrial[3 * MAX_LOCAL_DOFS];
    for (int i = 0; i < 3; ++i) trial[i] = w[i] - n[i] * nw;
    for (int c = 0; c < nd; ++c) {
      double wDn = 0.0;
      for (int j = 0; j < 3; ++j) wDn += w[j] * kin.Dn[j][c];
      for (int i = 0; i < 3; ++i) {
        /* Dw = -eps_t I on the slave dofs (c < dim here: an obstacle has no other dofs). */
        double Pdw = -eps_t * ((i == c ? 1.0 : 0.0) - n[i] * n[c]);
        Dtrial[i * nd + c] = Pdw - kin.Dn[i][c] * nw - n[i] * wDn;
      }
    }
    const double identity[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    double Dt[3 * MAX_LOCAL_DOFS];
    e->state = cov_return_map_held(3, trial, Dtrial, identity, in->mu, p, Dp, nd, eps_t, held_traction(in, k, -1),
                                   T, Dt, &e->dissipation);
    for (int i = 0; i < 3; ++i)
      for (int c = 0; c < nd; ++c) DT[i][c] = Dt[i * nd + c];
  }

  /* Force on the slave f = p n + T; residual: -f on the slave, +N_I f on master node I. */
  double f[3], Df[3][MAX_LOCAL_DOFS];
  for (int i = 0; i < 3; ++i) {
    f[i] = p * n[i] + T[i];
    for (int c = 0; c < nd; ++c) Df[i][c] = Dp[c] * n[i] + p * kin.Dn[i][c] + DT[i][c];
  }
  memcpy(e->force, f, sizeof f);
  memcpy(e->traction, T, sizeof T);
  for (int i = 0; i < dim; ++i) e->R[i] = -f[i];
  for (int I = 0; I < nen; ++I)
    for (int i = 0; i < dim; ++i) e->R[dim * (1 + I) + i] = pt.N[I] * f[i];
  if (!want_jacobian) return SK_OK;
  for (int i = 0; i < dim; ++i)
    for (int c = 0; c < nd; ++c) e->K[i * nd + c] = -Df[i][c];
  for (int I = 0; I < nen; ++I) {
    double DN[MAX_LOCAL_DOFS];
    for (int c = 0; c < nd; ++c) {
      DN[c] = 0.0;
      for (int a = 0; a < pdim; ++a) DN[c] += pt.dN[I][a] * kin.Dxi[a][c];
    }
    for (int i = 0; i < dim; ++i)
      for (int c = 0; c < nd; ++c) e->K[(dim * (1 + I) + i) * nd + c] = pt.N[I] * Df[i][c] + f[i] * DN[c];
  }
  return SK_OK;
}
