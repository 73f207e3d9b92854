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

#include "candidates.h"
#include "records.h"
#include "covariant.h"
#include "defaults.h"
#include "self_contact.h"
#include "stickslip/plugin.h"

#define PNTS_EXPORT __attribute__((visibility("default")))

enum { MAX_FACE_NODES = 9, MAX_LOCAL_DOFS = 3 * (1 + MAX_FACE_NODES) };
enum { STATE_INACTIVE = 0, STATE_STICK = 1, STATE_SLIP = 2 };

/* Friction history of one slave node (one step's anchor, or the committed one). */
typedef struct {
  int valid;            /* 0: no anchor (no friction force this step) */
  int face;             /* deformable: master face and parameters of the anchor, covariant traction */
  double xi[2];
  double t[2];
  double anchor[3];     /* obstacle: anchor point minus the obstacle translation, spatial traction */
  double traction[3];
} friction_history;

/* The friction state of one slave node at the last point where the Jacobian was assembled (the last accepted Newton
 * iterate): its traction when it slipped there, the switch's memory (cov_return_map_held). */
typedef struct {
  int slip;             /* 0: stuck, inactive or frictionless there (the return map decides alone) */
  int face;             /* deformable master: the face whose covariant basis t is in */
  double t[3];          /* covariant (deformable master, pdim components) or spatial (obstacle) traction */
} held_friction;

/* Everything one evaluation of a slave node produces. */
typedef struct {
  int found;            /* a projection exists (gap and normal are meaningful) */
  int state;            /* STATE_* */
  int face;
  double xi[2];
  double gap, p;        /* p: normal force (penalty times the slave's area when area weighted) */
  double x[3], normal[3];
  double force[3];      /* total contact force on the slave node */
  double traction[3];   /* its tangential part */
  double t_cov[2];      /* covariant tangential traction (deformable master) */
  double slip[3];       /* tangential displacement of the slave relative to the master since the step's anchor */
  double dissipation;   /* slip increment . traction of the step so far */
  int nd;               /* local dofs: slave node, then the master face nodes */
  int64_t rows[MAX_LOCAL_DOFS];
  double R[MAX_LOCAL_DOFS];
  double K[MAX_LOCAL_DOFS * MAX_LOCAL_DOFS];
} point_eval;

struct sk_instance {
  const sk_host_api *api;
  sk_host *host;
  const sk_contact_services *cs;
  const sk_view *slave;         /* the slave surface as this rank sees it: the slave nodes are its view nodes */
  const sk_view *master;        /* deformable master (whole), or NULL */
  const sk_obstacle *obstacle;  /* rigid master, or NULL */
  const char *name;             /* the pair's name */
  int dim;
  double penalty, penalty_t, mu, margin;
  int self;                     /* self contact: slave and master are the same surface */
  double self_exclusion;        /* self contact: faces with a node this close to the slave node (reference) are not
                                   its candidates */
  double touch_tolerance;       /* points with g <= this are active (see evaluate_point) */
  double extension;             /* master_extension: band beyond the master's border, fraction of a face */
  int area_weighted;
  int n_slave;
  double *area;                 /* tributary reference area of each slave node (1 when not area weighted) */
  sk_search *search;
  int *cand_start, *cand_count; /* candidate master faces of each slave node in cand (find_candidates) */
  cand_list cand;
  friction_history *committed;  /* at the last accepted step */
  double (*slip_increment)[3];  /* of the last accepted step (points), and the accumulated slip length */
  double *slip;
  friction_history *anchor;     /* used during the current step */
  unsigned char *last_state;    /* for after_iteration's change detection */
  held_friction *held;          /* per slave node, the stick/slip switch's memory within the step */
  int return_map_only;          /* 1: evaluate without the memory (pnts_converged compares the two) */
  int *sel_face;                /* master face selected for each slave node (-1: none), see select_face */
  unsigned char *sel_beyond;    /* 1: the selection lies beyond the master's border (and its extension band) */
  unsigned char *escaped;       /* 1: the closest face at the last point is not a candidate (see select_face) */
  double (*sel_xi)[2];          /* start of the closest-point Newton on the selected face */
  int64_t *pattern_dofs;        /* the dofs of a slave node's neighbourhood (pattern) */
  int pattern_capacity;
  /* TRI6 slaves: the pressure reported at node k is (T^T f)_k / A_k (see tributary_weights), a combination of the
   * nodal forces of node k and its edge nodes: CSR rows rec_start[k] .. rec_start[k+1] of (rec_node, rec_coef) over
   * view nodes; rec_force holds every view node's normal and tangential force, whether it is in contact and its gap
   * (REC_STRIDE per node) while points() reports. */
  int *rec_start, *rec_node;
  double *rec_coef, *rec_force;
};
enum { REC_STRIDE = 6 };
/* An open TRI6 node within this many times its neighbours' penetration of the master reports the recovered traction
 * (pnts_points). */
#define RIM_GAP_FACTOR 4.0

static const char *const pnts_strategies[] = {"none", NULL};
static const char *const pnts_parameters[] = {
    "penalty: normal penalty eps_n > 0; pressure/length when area_weighted, force/length otherwise [computed from "
    "the scene: 10 E*/h on first-order slave faces, 300 E*/h on second-order ones (E*: contact modulus of the "
    "pair, h: mean edge of the slave surface); times the mean tributary area when area_weighted is 0]",
    "mu: Coulomb friction coefficient >= 0 [0]",
    "penalty_tangential: tangential penalty eps_t > 0, same units as penalty [computed from the scene: penalty]",
    "area_weighted: 1 scales the penalties by the slave node's tributary reference area, 0 uses them as nodal "
    "stiffnesses [1]",
    "search_margin: inflation of the search boxes (length); default half the mean master face size",
    "master_extension: a slave node up to this fraction of a face beyond the master's border stays in contact with "
    "the extrapolated face (0 switches it off) [0.1]",
    SELF_EXCLUSION_HELP,
    NULL};

/* ---- small dense helpers --------------------------------------------------------------------------------------- */
static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* Slave node k's position from the positions per view x (x[0]: the slave view, x[1]: the master view). */
static void slave_position(const sk_instance *in, const double *const *x, int k, double xs[3]) {
  xs[2] = 0.0;
  for (int i = 0; i < in->dim; ++i) xs[i] = x[0][k * in->dim + i];
}

/* Closest point on the polynomial extension of `face` (also beyond its border): Newton on (x_s - x(xi)) . a_a = 0
 * from pt->xi, *pt holding the geometry there. Returns 1 with *pt at the closest point when Newton converged and the
 * point lies within `band` of the face (|xi| <= 1 + 2 band on lines and quads, barycentrics >= -band on
 * triangles), 0 otherwise. Used beyond the master's border with band = master_extension (without it a slave node
 * level with the master's end, a patch test's corner, toggles in and out of contact between Newton iterations)
 * and for the face selected during a step (band SELECT_BAND, see select_face). */
static int extend_on_face(const sk_instance *in, int face, const double *xs, const double *xm, double band,
                          sk_surface_point *pt) {
  const sk_view *master = in->master;
  const int pdim = in->dim - 1;
  double xi[2] = {pt->xi[0], pt->xi[1]};
  int converged = 0;
  for (int it = 0; it < 30 && !converged; ++it) {
    double d[3] = {xs[0] - pt->x[0], xs[1] - pt->x[1], xs[2] - pt->x[2]}, r[2] = {0, 0};
    double J[2][2] = {{1.0, 0.0}, {0.0, 1.0}}, Jinv[2][2], step = 0.0;
    for (int a = 0; a < pdim; ++a) {
      r[a] = dot3(d, pt->a[a]);
      for (int b = 0; b < pdim; ++b) J[a][b] = dot3(pt->a[a], pt->a[b]) - dot3(d, pt->a_ab[a][b]);
    }
    if (!cov_invert2(pdim, J, Jinv)) return 0;
    for (int a = 0; a < pdim; ++a) {
      double dxi = 0.0;
      for (int b = 0; b < pdim; ++b) dxi += Jinv[a][b] * r[b];
      xi[a] += dxi;
      step = fmax(step, fabs(dxi));
    }
    in->cs->geometry(master, face, xi, xm, pt);
    converged = step <= 1e-13;
  }
  if (!converged) return 0;
  pt->face = face;
  pt->xi[0] = xi[0];
  pt->xi[1] = xi[1];
  if (master->cell_type == SK_TRI3 || master->cell_type == SK_TRI6)
    return xi[0] >= -band && xi[1] >= -band && 1.0 - xi[0] - xi[1] >= -band;
  for (int a = 0; a < pdim; ++a)
    if (fabs(xi[a]) > 1.0 + 2.0 * band) return 0;
  return 1;
}

/* ---- master face selection --------------------------------------------------------------------------------------- */

/* Hysteresis of the face selection: a selected face is kept while the slave's closest point on its polynomial
 * extension stays within this fraction of the face beyond its edge. */
#define SELECT_BAND 0.1

/* The closest-point projection over the candidates with the master_extension treatment at the master's border:
 * face (-1: none), parameters, and whether the point lies beyond the border and its band. */
static sk_status project_global(const sk_instance *in, const double *xm, const double *xs, int k, int *face,
                                double xi[2], int *beyond) {
  const sk_view *master = in->master;
  *face = -1;
  *beyond = 0;
  xi[0] = xi[1] = 0.0;
  if (in->cand_count[k] == 0) return SK_OK;
  sk_projection proj = {.struct_size = sizeof proj};
  SK_TRY(in->cs->project(master, xm, xs, in->cand.faces + in->cand_start[k], in->cand_count[k], &proj));
  if (proj.face < 0) return SK_OK;
  *face = proj.face;
  xi[0] = proj.xi[0];
  xi[1] = proj.xi[1];
  if (proj.kind != SK_PROJ_OUTSIDE) return SK_OK;
  *beyond = 1;
  if (in->extension > 0.0) {
    sk_surface_point pt = {.struct_size = sizeof pt};
    in->cs->geometry(master, proj.face, proj.xi, xm, &pt);
    pt.xi[0] = proj.xi[0];
    pt.xi[1] = proj.xi[1];
    if (extend_on_face(in, proj.face, xs, xm, in->extension, &pt)) {
      xi[0] = pt.xi[0];
      xi[1] = pt.xi[1];
      *beyond = 0;
    }
  }
  return SK_OK;
}

/* Selects the master face of slave node k at positions q: the closest-point projection, except that a face selected
 * earlier in the step is kept while the slave's closest point on that face's extension stays within SELECT_BAND of
 * it (and the slave has not slid off the master). Called by begin_step (at the predictor, with no earlier face) and
 * by after_iteration at every new iterate; residual and Jacobian only evaluate the selection, so they are smooth
 * functions of q. Without the hysteresis a slave node at a shared master node where the master has a kink jumps
 * between the two faces: the closest point's normal turns from one face's normal to the other's within a fan of
 * width ~ |g| x kink angle (1e-10 in the patch test), where the slave is held by the full penalty stiffness, while
 * outside it only the bodies' stiffness acts, so Newton steps over the fan and back forever. */
static sk_status select_face(sk_instance *in, const double *const *x, int k) {
  double xs[3], xi[2];
  int face, beyond;
  slave_position(in, x, k, xs);
  SK_TRY(project_global(in, x[1], xs, k, &face, xi, &beyond));
  int old = in->sel_face[k];
  /* The projection walks across faces from the candidates, so under large sliding it may end on a face whose
   * couplings pattern() did not declare. Such a point stays on its last face's extension until Newton converges;
   * pnts_converged then searches again around the converged point and has the host lay out the pattern again. */
  in->escaped[k] = face >= 0 && !cand_contains(&in->cand, in->cand_start[k], in->cand_count[k], face);
  if (in->escaped[k]) {
    face = old;
    beyond = 0;
    if (old >= 0) {
      xi[0] = in->sel_xi[k][0];
      xi[1] = in->sel_xi[k][1];
      beyond = in->sel_beyond[k];
    }
  }
  if (old >= 0 && old != face && face >= 0 && !beyond) {
    sk_surface_point pt = {.struct_size = sizeof pt};
    in->cs->geometry(in->master, old, in->sel_xi[k], x[1], &pt);
    pt.xi[0] = in->sel_xi[k][0];
    pt.xi[1] = in->sel_xi[k][1];
    if (extend_on_face(in, old, xs, x[1], SELECT_BAND, &pt)) {
      in->sel_xi[k][0] = pt.xi[0];
      in->sel_xi[k][1] = pt.xi[1];
      in->sel_beyond[k] = 0;
      return SK_OK;
    }
  }
  in->sel_face[k] = face;
  in->sel_xi[k][0] = xi[0];
  in->sel_xi[k][1] = xi[1];
  in->sel_beyond[k] = (unsigned char)beyond;
  return SK_OK;
}

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
static sk_status evaluate_point(sk_instance *in, const sk_state *st, int k, int want_jacobian, point_eval *e) {
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

/* ---- creation ---------------------------------------------------------------------------------------------------- */

static int face_type_fits(sk_elem_type type, int dim) {
  if (dim == 2) return type == SK_LINE2 || type == SK_LINE3;
  return type == SK_TRI3 || type == SK_TRI6 || type == SK_QUAD4 || type == SK_QUAD8 || type == SK_QUAD9;
}

/* ---- what the plugin cannot run (sk_plugin.check, ABI 2.7; create() asks the same on older hosts) ---------------- */

/* A uniform pressure puts tensile consistent loads (-1/12 of the face area) on QUAD8 corners, which a penalty node
 * cannot carry: measured on the 3D patch test with hex20, every corner opened by 4e-4 while the edge nodes
 * penetrated 1e-6, and the pressures ranged over 6 ... 21 for p = 10. */
static int faces_refused(const char *slave_name, sk_elem_type slave, int has_master, sk_elem_type master, int dim,
                         char *reason, int size) {
  if (!face_type_fits(slave, dim) || (has_master && !face_type_fits(master, dim)))
    snprintf(reason, (size_t)size, "penalty-nts supports LINE2/LINE3 faces in 2D and TRI3/TRI6/QUAD4/QUAD8/QUAD9 in "
             "3D");
  else if (slave == SK_QUAD8)
    snprintf(reason, (size_t)size, "penalty-nts cannot use QUAD8 (hex20) slave faces (surface '%s'): their corner "
             "nodes would need tensile contact forces under a uniform pressure. Use hex27 (QUAD9 faces: "
             "mesh.serendipity false), or make the QUAD8 surface the master", slave_name);
  else
    return 0;
  return 1;
}

static sk_status pnts_check(const sk_scene_info *scene, char *reason, int size) {
  const sk_scene_side *master = scene->master;
  return faces_refused(scene->slave->name, scene->slave->cell_type, !master->rigid, master->cell_type, scene->dim,
                       reason, size)
             ? SK_ERR_PLUGIN
             : SK_OK;
}

/* The trap of node-to-surface on quadratic faces: integral N_I over a flat TRI6 is 0 at the corners (1/3 of the area
 * at each edge node), over a QUAD8 -1/12 at the corners, so area-weighted penalties would leave the corners
 * unconstrained (TRI6: measured on hertz-3d with mesh.order 2, corner nodes penetrate up to 37 times as deep as edge
 * nodes) or pull them into the master (QUAD8). The weights are taken instead from the modified basis of Popp,
 * Wohlmuth, Gee & Wall (SIAM J. Sci. Comput. 34, 2012): N~_corner = N_corner + alpha (N_m1 + N_m2) over the corner's
 * two edge nodes, N~_edge = (1 - 2 alpha) N_edge, alpha = 1/5, a partition of unity with positive integrals (flat
 * TRI6: 2/15 and 1/5 of the area; QUAD8: 1/20 and 1/5). The consistent nodal loads of a uniform pressure remain the
 * integrals of N_I, so collocating at the nodes with these weights does not pass the patch test
 * (docs/plugins/penalty-nts.md has the measured error). QUAD9 and LINE3 integrals are positive and used as they are.
 * A[] holds integral N_I per face node on entry; edge node e joins corners e and e + 1. */
#define MODIFIED_BASIS_ALPHA 0.2
static int modified_corners(sk_elem_type type) { return type == SK_TRI6 ? 3 : type == SK_QUAD8 ? 4 : 0; }

static void tributary_weights(sk_elem_type type, double *A) {
  const int corners = modified_corners(type);
  double edge[4];
  for (int e = 0; e < corners; ++e) edge[e] = A[corners + e];
  for (int e = 0; e < corners; ++e) {
    A[e] += MODIFIED_BASIS_ALPHA * edge[e];
    A[(e + 1) % corners] += MODIFIED_BASIS_ALPHA * edge[e];
    A[corners + e] = (1.0 - 2.0 * MODIFIED_BASIS_ALPHA) * edge[e];
  }
}

/* The rows of T^T for the pressure recovery of TRI6 slaves: a corner takes its own force and alpha times the force of
 * each edge node next to it (each edge once, however many faces share it), an edge node (1 - 2 alpha) times its own.
 * For a uniform pressure p the nodal forces are p integral N_I, and the recovery returns p at every node; the raw
 * force / weight gives 0 at TRI6 corners and 5/3 p at edge nodes. Over view nodes: the view holds every face around
 * an owned node, so an owned node's row is complete. */
static sk_status build_recovery(sk_instance *in) {
  const sk_view *slave = in->slave;
  const int corners = modified_corners(slave->cell_type);
  if (corners == 0 || !in->area_weighted) return SK_OK;
  const int ns = in->n_slave, n_pairs = slave->n_cells * corners * 2;
  int *pair_corner = malloc(((size_t)n_pairs + 1) * sizeof(int));
  int *pair_edge = malloc(((size_t)n_pairs + 1) * sizeof(int));
  int *fill = malloc(((size_t)ns + 1) * sizeof(int));
  char *edge_done = calloc((size_t)ns + 1, 1);
  in->rec_start = calloc((size_t)ns + 1, sizeof(int));
  in->rec_force = calloc(REC_STRIDE * (size_t)ns + 1, sizeof(double));
  sk_status status = SK_OK;
  if (!pair_corner || !pair_edge || !fill || !edge_done || !in->rec_start || !in->rec_force) {
    status = in->api->error(in->host, SK_ERR_NOMEM, "%s: penalty-nts: out of memory", in->name);
    goto done;
  }
  /* (corner, edge node) pairs, each edge once (an edge node has the same two corners in every face sharing it). */
  int n = 0;
  for (int f = 0; f < slave->n_cells; ++f)
    for (int e = 0; e < corners; ++e) {
      const int32_t *c = slave->conn + (size_t)f * slave->nen;
      const int m = c[corners + e];
      if (edge_done[m]) continue;
      edge_done[m] = 1;
      pair_corner[n] = c[e], pair_edge[n++] = m;
      pair_corner[n] = c[(e + 1) % corners], pair_edge[n++] = m;
    }
  for (int k = 0; k < n; ++k) ++in->rec_start[pair_corner[k] + 1];
  for (int k = 0; k < ns; ++k) in->rec_start[k + 1] += in->rec_start[k] + 1; /* + the node itself */
  in->rec_node = malloc(((size_t)in->rec_start[ns] + 1) * sizeof(int));
  in->rec_coef = malloc(((size_t)in->rec_start[ns] + 1) * sizeof(double));
  if (!in->rec_node || !in->rec_coef) {
    status = in->api->error(in->host, SK_ERR_NOMEM, "%s: penalty-nts: out of memory", in->name);
    goto done;
  }
  for (int k = 0; k < ns; ++k) {
    fill[k] = in->rec_start[k] + 1;
    in->rec_node[in->rec_start[k]] = k;
    in->rec_coef[in->rec_start[k]] = 1.0; /* corners; edge nodes are scaled below */
  }
  for (int k = 0; k < n; ++k) {
    in->rec_node[fill[pair_corner[k]]] = pair_edge[k];
    in->rec_coef[fill[pair_corner[k]]++] = MODIFIED_BASIS_ALPHA;
  }
  for (int k = 0; k < n; ++k) in->rec_coef[in->rec_start[pair_edge[k]]] = 1.0 - 2.0 * MODIFIED_BASIS_ALPHA;
done:
  free(pair_corner);
  free(pair_edge);
  free(fill);
  free(edge_done);
  return status;
}

static void pnts_destroy(sk_instance *in) {
  if (!in) return;
  if (in->search) in->cs->search_destroy(in->search);
  free(in->area);
  free(in->cand_start);
  free(in->cand_count);
  free(in->cand.faces);
  free(in->committed);
  free(in->slip_increment);
  free(in->slip);
  free(in->anchor);
  free(in->last_state);
  free(in->held);
  free(in->sel_face);
  free(in->escaped);
  free(in->sel_beyond);
  free(in->sel_xi);
  free(in->pattern_dofs);
  free(in->rec_start);
  free(in->rec_node);
  free(in->rec_coef);
  free(in->rec_force);
  free(in);
}

/* The penalties: the scene's values, or computed from it (docs/plugins/penalty-nts.md#defaults): eps_N = c E* / h
 * with c = PENALTY_FACTOR[order of the slave faces], E* the pair's contact modulus and h the slave surface's mean
 * edge; times the mean tributary area per slave node when the penalty is a nodal stiffness (area_weighted 0);
 * eps_T = eps_N. */
/* Second-order faces: 300 (docs/plugins/penalty-nts.md#defaults: on tet10 Hertz 100 left the profile error at 0.079
 * where 300 gives 0.039, on quad9 Hertz 300 is as good as 100 for the same iterations). */
static const double PENALTY_FACTOR[3] = {0.0, 10.0, 300.0};

static sk_status read_penalties(sk_instance *in) {
  return sk_defaults_penalties(in->api, in->host, PENALTY_FACTOR, !in->area_weighted, in->mu > 0.0, &in->penalty, &in->penalty_t);
}

/* Gauss rule for the tributary areas: degree 5 on lines and quads (3 points, 3x3), degree 2 on triangles (3 points):
 * exact for N_I times the area element of straight faces. */
enum { AREA_POINTS_MAX = 16 };

static sk_status pnts_create_checked(sk_instance *in, const sk_attach *attach) {
  const sk_host_api *api = in->api;
  sk_host *host = in->host;
  const sk_view *slave = attach->slave, *master = attach->master;
  in->slave = slave;
  in->master = master;
  in->obstacle = attach->obstacle;
  in->name = attach->name;
  in->dim = slave ? slave->dim : 0;
  if (!slave || (!master) == (!attach->obstacle))
    return api->error(host, SK_ERR_INPUT, "%s: penalty-nts needs a slave surface and either a master surface or an "
                      "obstacle", in->name);
  if (in->dim != 2 && in->dim != 3)
    return api->error(host, SK_ERR_INPUT, "%s: penalty-nts works in 2D or 3D, not %dD", in->name, in->dim);
  char reason[300];
  if (faces_refused(slave->name, slave->cell_type, master != NULL, master ? master->cell_type : SK_POINT1, in->dim,
                    reason, sizeof reason))
    return api->error(host, SK_ERR_INPUT, "%s: %s", in->name, reason);

  SK_TRY(api->param_int(host, "area_weighted", 0, 1, &in->area_weighted));
  if (in->area_weighted != 0 && in->area_weighted != 1)
    return api->error(host, SK_ERR_INPUT, "%s: penalty-nts parameter 'area_weighted' must be 0 or 1, got %d",
                      in->name, in->area_weighted);
  SK_TRY(api->param_double(host, "mu", 0, 0.0, &in->mu));
  if (!(in->mu >= 0.0) || !isfinite(in->mu))
    return api->error(host, SK_ERR_INPUT, "%s: penalty-nts parameter 'mu' must be a finite number >= 0, got %g",
                      in->name, in->mu);
  SK_TRY(read_penalties(in));
  SK_TRY(api->param_double(host, "master_extension", 0, 0.1, &in->extension));
  if (!(in->extension >= 0.0 && in->extension <= 0.5))
    return api->error(host, SK_ERR_INPUT, "%s: penalty-nts parameter 'master_extension' must be in [0, 0.5], got %g",
                      in->name, in->extension);

  /* Default margin: half the mean master face size (reference), enough for Newton to move past the predictor. */
  double mean_size = 0.0;
  if (master && master->n_cells > 0) {
    for (int f = 0; f < master->n_cells; ++f) {
      const int32_t *c = master->conn + f * master->nen;
      double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL}, diag2 = 0.0;
      for (int I = 0; I < master->nen; ++I)
        for (int i = 0; i < in->dim; ++i) {
          lo[i] = fmin(lo[i], master->X[c[I] * in->dim + i]);
          hi[i] = fmax(hi[i], master->X[c[I] * in->dim + i]);
        }
      for (int i = 0; i < in->dim; ++i) diag2 += (hi[i] - lo[i]) * (hi[i] - lo[i]);
      mean_size += sqrt(diag2);
    }
    mean_size /= master->n_cells;
  }
  in->self = attach->self_contact;
  if (in->self) SK_TRY(self_contact_exclusion(api, host, master, &in->self_exclusion));
  SK_TRY(api->param_double(host, "search_margin", 0, 0.5 * mean_size, &in->margin));
  /* Round-off scale of gaps: 1e-10 of the mean slave face size (of the faces this rank sees). */
  double slave_size = 0.0;
  for (int f = 0; f < slave->n_cells; ++f) {
    const int32_t *c = slave->conn + f * slave->nen;
    double diag2 = 0.0;
    for (int i = 0; i < in->dim; ++i) {
      double d = slave->X[c[1] * in->dim + i] - slave->X[c[0] * in->dim + i];
      diag2 += d * d;
    }
    slave_size += sqrt(diag2);
  }
  in->touch_tolerance = slave->n_cells > 0 ? 1e-10 * slave_size / slave->n_cells : 0.0;
  if (!(in->margin >= 0.0) || !isfinite(in->margin))
    return api->error(host, SK_ERR_INPUT, "%s: penalty-nts parameter 'search_margin' must be a finite number >= 0, "
                      "got %g", in->name, in->margin);

  in->n_slave = slave->n_nodes;
  size_t ns = (size_t)in->n_slave > 0 ? (size_t)in->n_slave : 1;
  in->area = calloc(ns, sizeof *in->area);
  in->cand_start = calloc(ns, sizeof(int));
  in->cand_count = calloc(ns, sizeof(int));
  in->committed = calloc(ns, sizeof *in->committed);
  in->slip_increment = calloc(ns, sizeof *in->slip_increment);
  in->slip = calloc(ns, sizeof *in->slip);
  in->anchor = calloc(ns, sizeof *in->anchor);
  in->last_state = calloc(ns, 1);
  in->held = calloc(ns, sizeof *in->held);
  in->sel_face = malloc(ns * sizeof(int));
  in->sel_beyond = calloc(ns, 1);
  in->escaped = calloc(ns, 1);
  in->sel_xi = calloc(ns, sizeof *in->sel_xi);
  if (!in->area || !in->cand_start || !in->cand_count || !in->committed || !in->slip_increment || !in->slip ||
      !in->anchor || !in->last_state || !in->held ||
      !in->sel_face || !in->sel_beyond || !in->escaped || !in->sel_xi)
    return api->error(host, SK_ERR_NOMEM, "%s: penalty-nts: out of memory", in->name);
  for (int k = 0; k < in->n_slave; ++k) in->sel_face[k] = -1;

  /* Tributary areas A_I = integral of N_I over the slave faces in the reference configuration (exact for the owned
   * nodes: the view holds every face around them); on TRI6 faces of the modified basis (tributary_weights). */
  if (in->area_weighted) {
    double qxi[AREA_POINTS_MAX][2], qw[AREA_POINTS_MAX];
    const int order = slave->cell_type == SK_TRI3 ? 2 : slave->cell_type == SK_TRI6 ? 4 : 5;
    const int nq = in->cs->quadrature(slave->cell_type, order, AREA_POINTS_MAX, qxi, qw);
    if (nq <= 0) return api->error(host, SK_ERR_INTERNAL, "%s: no face quadrature of degree %d", in->name, order);
    for (int f = 0; f < slave->n_cells; ++f) {
      double A[MAX_FACE_NODES] = {0};
      for (int g = 0; g < nq; ++g) {
        sk_surface_point pt = {.struct_size = sizeof pt};
        in->cs->geometry(slave, f, qxi[g], slave->X, &pt);
        for (int I = 0; I < slave->nen; ++I) A[I] += pt.N[I] * pt.jacobian * qw[g];
      }
      tributary_weights(slave->cell_type, A);
      for (int I = 0; I < slave->nen; ++I) in->area[slave->conn[f * slave->nen + I]] += A[I];
    }
  } else {
    for (int k = 0; k < in->n_slave; ++k) in->area[k] = 1.0;
  }
  SK_TRY(build_recovery(in));
  if (master) SK_TRY(in->cs->search_create(master, &in->search));
  return SK_OK;
}

static sk_status pnts_create(const sk_host_api *api, sk_host *host, const sk_attach *attach, sk_instance **instance) {
  *instance = NULL;
  sk_instance *in = calloc(1, sizeof *in);
  if (!in) return api->error(host, SK_ERR_NOMEM, "%s: penalty-nts: out of memory", attach->name);
  in->api = api;
  in->host = host;
  in->cs = api->contact;
  sk_status status = pnts_create_checked(in, attach);
  if (status != SK_OK) {
    pnts_destroy(in);
    return status;
  }
  *instance = in;
  return SK_OK;
}

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
    if (in->mu == 0.0 || a->valid) continue;
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
    for (int k = 0; k < in->n_slave; ++k) SK_TRY(select_face(in, st->x, k));
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

/* Every owned slave node with every node of its candidate master faces (the face selected during the step is one
 * of them); against an obstacle only the node's own block. */
static sk_status pnts_pattern(sk_instance *in, const sk_state *st, sk_pattern *pattern) {
  (void)st;
  const sk_view *slave = in->slave, *master = in->master;
  const int dim = in->dim;
  for (int k = 0; k < in->n_slave; ++k) {
    if (!slave->owned[k]) continue;
    const int need = dim * (1 + (master ? in->cand_count[k] * master->nen : 0));
    if (need > in->pattern_capacity) {
      int64_t *grown = realloc(in->pattern_dofs, sizeof(int64_t) * (size_t)need);
      if (!grown) return in->api->error(in->host, SK_ERR_NOMEM, "%s: penalty-nts: out of memory", in->name);
      in->pattern_dofs = grown;
      in->pattern_capacity = need;
    }
    int64_t *dofs = in->pattern_dofs;
    int n = 0;
    for (int i = 0; i < dim; ++i) dofs[n++] = slave->dofs[k * dim + i];
    for (int c = 0; master && c < in->cand_count[k]; ++c) {
      const int32_t *conn = master->conn + in->cand.faces[in->cand_start[k] + c] * master->nen;
      for (int I = 0; I < master->nen; ++I) {
        const int64_t first = master->dofs[conn[I] * dim];
        int seen = 0;
        for (int j = 0; j < n && !seen; j += dim) seen = dofs[j] == first;
        if (seen) continue;
        for (int i = 0; i < dim; ++i) dofs[n++] = master->dofs[conn[I] * dim + i];
      }
    }
    pattern->add_block(pattern, n, dofs, n, dofs);
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
 * its face or state since the previous point. */
static sk_status pnts_update_active_set(sk_instance *in, const sk_state *st, int *changed) {
  point_eval e;
  *changed = 0;
  for (int k = 0; k < in->n_slave; ++k) {
    if (in->master) { /* every slave node of the view: commit_step evaluates them all */
      int face = in->sel_face[k];
      SK_TRY(select_face(in, st->x, k));
      if (in->sel_face[k] != face && in->slave->owned[k]) *changed = 1;
    }
    if (!in->slave->owned[k]) continue;
    SK_TRY(evaluate_point(in, st, k, 0, &e));
    if (e.state != in->last_state[k]) *changed = 1;
    in->last_state[k] = (unsigned char)e.state;
  }
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
  /* The recovery combines neighbouring nodes' forces: evaluate every node of the view first (ghosts too). */
  for (int k = 0; in->rec_start && k < in->n_slave; ++k) {
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

/* The history of every slave node this rank holds (owned and ghost: commit_step keeps both). */
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
