/* nts-augmented — begin_step: the search, each slave node's facet for the step and its history on that facet
 * (glue.h). With a rigid plane obstacle every slave node has one fixed plane facet for the whole run. */
#include <math.h>
#include <string.h>

#include "candidates.h"
#include "glue.h"
#include "self_contact.h"

/* A committed closest point counts as on its facet up to this parametric distance beyond the border: nodes placed
 * on a master corner sit there to round-off (1e-16), closest points converge to LOCAL_NEWTON_TOL. */
#define FACET_BORDER_BAND 1e-12
/* A node beyond its facet is moved onto the face it is over when it penetrates that face by more than this fraction
 * of the search margin, at most MAX_SWITCHES times per step. A node at a shallow concave kink penetrates whichever
 * face it is not on by little: on the 3D stress slider (pressing, t = 0.49) by 2.5e-10 = 1e-9 of the margin, where
 * a band of 1e-9 made it alternate between the two faces until the step was cut 6 times. The force lost on a
 * facet extension is ~1e-3 of the margin (the slider at dt 0.1: 2 % of the normal force). */
#define RESEARCH_PENETRATION 1e-6
enum { MAX_SWITCHES = 2 };

/* The nodes of a node's plane facet at time t: x(f) = c + f^a t_a with c = origin + d(t) (a QUAD4 whose corners are
 * c -+ t_1 -+ t_2 in 3D; a LINE2 from c - t_1 to c + t_1 in 2D), so f is arc length along the orthonormal t_a. */
static void plane_facet(const sk_instance *inst, const slave_point *p, double t, double *x) {
  static const double corner[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  double d[3] = {0, 0, 0};
  inst->api->contact->obstacle_displacement(inst->obstacle, t, d);
  for (int I = 0; I < inst->facet.nen; ++I)
    for (int i = 0; i < 3; ++i) {
      double v = p->plane_origin[i] + (i < inst->dim ? d[i] : 0.0) + corner[I][0] * inst->plane_tangent[0][i];
      if (inst->pdim == 2) v += corner[I][1] * inst->plane_tangent[1][i];
      x[3 * I + i] = v;
    }
}

void nts_gather(const sk_instance *inst, const slave_point *p, const double *const *x, double t, double *q_A) {
  const int dim = inst->dim, nen = inst->facet.nen;
  memset(q_A, 0, sizeof(double) * (size_t)(3 + 3 * nen));
  for (int i = 0; i < dim; ++i) q_A[i] = x[0][dim * p->k + i];
  if (inst->obstacle) {
    plane_facet(inst, p, t, q_A + 3);
    return;
  }
  for (int I = 0; I < nen; ++I)
    for (int i = 0; i < dim; ++i) q_A[3 * (1 + I) + i] = x[1][dim * p->facet_nodes[I] + i];
}

double nts_gap_on_facet(const sk_instance *inst, const slave_point *p, const double *const *x, double t,
                        double f[2]) {
  double q_A[NTS_MAX_NQ];
  nts_gather(inst, p, x, t, q_A);
  if (nts_closest_point(&inst->facet, q_A, f, LOCAL_NEWTON_TOL, LOCAL_NEWTON_MAX) < 0) return HUGE_VAL;
  nts_geometry geo;
  nts_geometry_eval(&inst->facet, q_A, f, &geo);
  return geo.phi[NTS_PHI_N];
}

static void set_facet(sk_instance *inst, slave_point *p, int facet) {
  p->facet = facet;
  if (inst->obstacle) return;
  for (int I = 0; I < inst->facet.nen; ++I) p->facet_nodes[I] = inst->master->conn[facet * inst->master->nen + I];
}

/* The candidate master faces of slave node p in the box lo..hi, into inst->candidates; a self-contact node's without
 * the faces it cannot touch (self_contact.h). Returns their number, or -1 with *status set. */
static int query_candidates(sk_instance *inst, const slave_point *p, const double *lo, const double *hi,
                            sk_status *status) {
  const sk_contact_services *cs = inst->api->contact;
  const sk_view *master = inst->master;
  *status = SK_OK;
  int n = cs->search_query(inst->search, lo, hi, inst->candidates, master->n_cells);
  if (n > master->n_cells) n = master->n_cells;
  if (n <= 0 || !inst->self) return n;
  return self_contact_filter(cs, master, inst->slave->X + inst->dim * p->k, inst->self_exclusion, inst->candidates,
                             n, status);
}

/* The closest point of q (slave node p at positions x) on the n candidates. The projection walks across the faces'
 * edges, so from a candidate face of a self-contact node it may end on a face the node cannot touch (its own face,
 * at gap 0): there each candidate is projected alone and a result on such a face is not taken. */
static sk_status project_candidates(sk_instance *inst, const slave_point *p, const double *x, const double *q, int n,
                                    sk_projection *proj) {
  const sk_contact_services *cs = inst->api->contact;
  const sk_view *master = inst->master;
  if (!inst->self) return cs->project(master, x, q, inst->candidates, n, proj);
  const double *X = inst->slave->X + inst->dim * p->k;
  for (int c = 0; c < n; ++c) {
    sk_projection one = {.struct_size = sizeof one, .face = -1};
    sk_status status = cs->project(master, x, q, inst->candidates + c, 1, &one);
    if (status == SK_ERR_DIVERGED) continue;
    if (status != SK_OK) return status;
    int face = one.face;
    if (face < 0 || self_contact_filter(cs, master, X, inst->self_exclusion, &face, 1, &status) != 1) continue;
    if (proj->face < 0 || one.distance < proj->distance || (one.distance == proj->distance && face < proj->face))
      *proj = one;
  }
  return SK_OK;
}

/* The step's facet of a node, its projection (xi, gap) and whether anything is reachable. */
static sk_status find_facet(sk_instance *inst, slave_point *p, const sk_state *state, sk_projection *proj) {
  const int dim = inst->dim;
  *proj = (sk_projection){.struct_size = sizeof *proj, .face = -1};
  const double *x_n = state->x_n[0] + dim * p->k, *x_p = state->x[0] + dim * p->k;
  if (inst->obstacle) {
    /* one plane facet for the run: the projection on it is exact */
    p->facet = 0;
    proj->face = 0;
    proj->xi[0] = proj->xi[1] = 0.0;
    proj->gap = nts_gap_on_facet(inst, p, state->x, state->t, proj->xi);
    proj->kind = SK_PROJ_INTERIOR;
    return SK_OK;
  }
  double lo[3] = {-inst->search_margin, -inst->search_margin, -inst->search_margin};
  double hi[3] = {inst->search_margin, inst->search_margin, inst->search_margin};
  for (int i = 0; i < dim; ++i) {
    lo[i] = fmin(x_n[i], x_p[i]) - inst->search_margin;
    hi[i] = fmax(x_n[i], x_p[i]) + inst->search_margin;
  }
  sk_status status;
  const int n_cand = query_candidates(inst, p, lo, hi, &status);
  if (n_cand < 0) return status;
  if (n_cand > 0) SK_TRY(project_candidates(inst, p, state->x[1], x_p, n_cand, proj));
  if (proj->face >= 0 && proj->kind == SK_PROJ_OUTSIDE && inst->master_extension > 0.0) {
    /* Beyond the master's border (the core clamps the closest point to it) but within master_extension of the
     * face: the node keeps that face, its closest point on the face's extension. Without the band a node level
     * with the master's end is dropped whenever round-off puts it a hair beyond: on the free ends of a crushed
     * tube (tube-crush-3d, one layer along) half of the end nodes of the fold lost their facet at random and the
     * walls passed through each other by 2.4e-2 (docs/plugins/nts-augmented.md, "Self contact"). */
    set_facet(inst, p, proj->face);
    double f[2] = {proj->xi[0], proj->xi[1]};
    const double gap = nts_gap_on_facet(inst, p, state->x, state->t, f);
    if (gap != HUGE_VAL && cand_within_band(inst->facet.type, f, inst->master_extension)) {
      proj->xi[0] = f[0];
      proj->xi[1] = f[1];
      proj->gap = gap;
      proj->kind = SK_PROJ_EDGE; /* on the face's extension: not dropped */
    }
  }
  return SK_OK;
}

/* The history of a node on a facet it was not on at t_n (a new contact, or a contact that changes facet): f_n (the
 * friction reference and midpoint start) is the closest point of q_n on the facet (f_guess if that fails); a
 * committed traction is carried over as a spatial vector (t_a = t . a_a on the new facet). */
static void start_on_new_facet(const sk_instance *inst, slave_point *p, const sk_state *state,
                               const double f_guess[2]) {
  double f_n[2] = {f_guess[0], f_guess[1]};
  if (nts_gap_on_facet(inst, p, state->x_n, state->t_n, f_n) == HUGE_VAL) {
    f_n[0] = f_guess[0];
    f_n[1] = f_guess[1];
  }
  p->f_start[0] = f_n[0];
  p->f_start[1] = f_n[1];
  p->t_start[0] = p->t_start[1] = 0.0;
  if (!p->c_active) return;
  double q_A[NTS_MAX_NQ];
  nts_geometry geo;
  nts_gather(inst, p, state->x_n, state->t_n, q_A);
  nts_geometry_eval(&inst->facet, q_A, f_n, &geo);
  for (int a = 0; a < inst->pdim; ++a)
    p->t_start[a] = geo.a[a][0] * p->c_t_vector[0] + geo.a[a][1] * p->c_t_vector[1] + geo.a[a][2] * p->c_t_vector[2];
}

sk_status nts_begin_step(sk_instance *inst, const sk_state *state) {
  inst->alpha = state->alpha;
  if (inst->search) inst->api->contact->search_update(inst->search, state->x_n[1], state->x[1], inst->search_margin);
  for (int k = 0; k < inst->n_points; ++k) SK_TRY(find_facet(inst, &inst->points[k], state, &inst->projections[k]));
  if (inst->self) SK_TRY(nts_self_sides(inst, inst->projections));
  for (int k = 0; k < inst->n_points; ++k) {
    slave_point *p = &inst->points[k];
    double *init = inst->initial + inst->stride * p->index;
    sk_projection proj = inst->projections[k];
    p->flips = 0;
    p->corrections = 0;
    p->switches = 0;
    p->left_facet = -1;
    p->tension = p->penetration = 0.0;
    p->slip = 0;
    p->return_map = 0;
    p->wants_in = 0;
    memset(init, 0, sizeof(double) * (size_t)inst->stride);
    if (proj.face < 0 || proj.kind == SK_PROJ_OUTSIDE || proj.gap == HUGE_VAL) {
      /* nothing reachable this step (or beyond the master's border): trivial equations */
      p->facet = -1;
      p->active = 0;
      p->f_frozen[0] = p->f_frozen[1] = 0.0;
      p->f_start[0] = p->f_start[1] = p->t_start[0] = p->t_start[1] = 0.0;
      p->gap_estimate = inst->search_margin;
      continue;
    }
    set_facet(inst, p, proj.face);
    p->gap_estimate = proj.gap;
    if (p->c_active && p->c_facet >= 0 && p->c_facet != p->facet &&
        nts_facet_outside(&inst->facet, p->c_f) <= FACET_BORDER_BAND) {
      /* A contact about to move onto another facet. The step enforces Phi_n = 0 at its end on the new facet, so
       * its normal force does the work -lambda_n (0 - g_n), g_n = the gap of q_n on the new facet. Across a convex
       * kink the slave, still on its old facet at t_n, lies below the new facet's plane (g_n < 0): the switch
       * would put lambda_n g_n > 0 into the bodies (up to 1e-4 of the energy per switch on the coarse tori). Such a
       * contact stays on its old facet (extended beyond its edge) for this step; once it has passed the edge, g_n
       * on the new facet is >= 0 and the switch only loses energy.
       * Only a contact that is on its old facet at t_n stays (for one step at most): one that ended the last step
       * beyond the edge switches whatever g_n. Kept on the extension step after step, a node slid along the plane
       * of a facet it had long left; where that plane dips below the master (a facet tilted by the load behind a
       * dragged block), the block sank into the master at zero gap and its normal force faded (the stress
       * slider, mu 0.3, dt 0.1: 21.3 -> 0.5 over the drag, the slave 0.0096 under the master surface). */
      double f_n[2] = {proj.xi[0], proj.xi[1]};
      const double g_n = nts_gap_on_facet(inst, p, state->x_n, state->t_n, f_n);
      if (g_n < 0.0) {
        double f[2] = {p->c_f[0], p->c_f[1]};
        set_facet(inst, p, p->c_facet);
        const double g = nts_gap_on_facet(inst, p, state->x, state->t, f);
        if (g != HUGE_VAL) proj.gap = p->gap_estimate = g;
      }
    }
    double f_init[2] = {proj.xi[0], inst->pdim == 2 ? proj.xi[1] : 0.0}, lambda_n = 0.0;
    double lambda_aug[2] = {0.0, 0.0};
    if (p->c_active && p->c_facet == p->facet) {
      /* persisting contact on the same facet: keep f and the history as committed */
      for (int a = 0; a < 2; ++a) {
        p->f_start[a] = f_init[a] = p->c_f[a];
        p->t_start[a] = p->c_t[a];
      }
      lambda_aug[0] = p->c_extra[nts_slot_of_e(inst, 2)];
      if (inst->pdim == 2) lambda_aug[1] = p->c_extra[4];
      lambda_n = p->c_extra[0];
      p->slip = p->c_slip;
    } else {
      start_on_new_facet(inst, p, state, f_init);
      if (p->c_active) lambda_n = p->c_extra[0];
    }
    p->f_frozen[0] = p->f_gap[0] = f_init[0];
    p->f_frozen[1] = p->f_gap[1] = f_init[1];
    p->active = nts_wants_contact(inst, lambda_n, proj.gap);
    if (p->active) {
      init[0] = lambda_n;
      init[nts_slot_of_e(inst, 2)] = lambda_aug[0];
      if (inst->pdim == 2) init[4] = lambda_aug[1];
    }
    init[1] = f_init[0];
    if (inst->pdim == 2) init[2] = f_init[1];
  }
  /* the starting values of the owned points only: the host sums them over ranks */
  for (int k = 0; k < inst->n_points; ++k)
    if (!nts_owned(inst, &inst->points[k]))
      memset(inst->initial + inst->stride * inst->points[k].index, 0, sizeof(double) * (size_t)inst->stride);
  return SK_OK;
}

/* A contact that slid beyond its step's facet within the step holds Phi_n = 0 on the facet's extension. Where that
 * plane lies below the master surface (a facet tilted by the load, or a concave kink) the node ends the step inside
 * the master at zero gap: on the stress slider at dt 0.4 (1.6 faces per step) F_n fell 10 % below the pressing
 * force, the residual converged. So at a converged point such a node is projected on the master again; if it
 * penetrates the face it is over, it changes to that face (its history as at a facet change) and Newton runs again.
 * A node above the face it is over (the extension across a convex kink) stays: that is the energy-safe switch. */
sk_status nts_research_facet(sk_instance *inst, slave_point *p, const sk_state *state, int *switched) {
  *switched = 0;
  if (inst->obstacle || p->facet < 0 || !p->active) return SK_OK;
  const double *x = state->extra + inst->stride * p->index;
  double f[2] = {x[nts_slot_of_e(inst, 0)], inst->pdim == 2 ? x[nts_slot_of_e(inst, 1)] : 0.0};
  if (nts_gap_on_facet(inst, p, state->x, state->t, f) == HUGE_VAL ||
      nts_facet_outside(&inst->facet, f) <= FACET_BORDER_BAND)
    return SK_OK;
  const int dim = inst->dim;
  const double *q = state->x[0] + dim * p->k;
  double lo[3] = {-inst->search_margin, -inst->search_margin, -inst->search_margin};
  double hi[3] = {inst->search_margin, inst->search_margin, inst->search_margin};
  for (int i = 0; i < dim; ++i) {
    lo[i] = q[i] - inst->search_margin;
    hi[i] = q[i] + inst->search_margin;
  }
  sk_status status;
  const int n_cand = query_candidates(inst, p, lo, hi, &status);
  if (n_cand < 0) return status;
  if (n_cand == 0) return SK_OK;
  sk_projection proj = {.struct_size = sizeof proj, .face = -1};
  SK_TRY(project_candidates(inst, p, state->x[1], q, n_cand, &proj));
  if (proj.face < 0 || proj.face == p->facet || proj.kind == SK_PROJ_OUTSIDE || proj.gap == HUGE_VAL ||
      proj.gap >= -RESEARCH_PENETRATION * inst->search_margin)
    return SK_OK;
  if (proj.face == p->left_facet) {
    /* A node in the valley of a concave kink penetrates whichever of the two faces it is not on (the stress
     * edge-to-edge case, n = 4: node 134 by 2e-6 between faces 1 and 2, moved back and forth until the step was cut
     * 6 times). Node-to-surface has one face per node; it stays on the one it moved to. */
    inst->api->log(inst->host, 2, "%s: nts-augmented: slave node %lld in a concave kink penetrates master face %d "
                   "(gap %g) it left in this step; it stays on face %d", inst->name, (long long)p->node, proj.face,
                   proj.gap, p->facet);
    return SK_OK;
  }
  if (p->switches >= MAX_SWITCHES)
    return inst->api->error(inst->host, SK_ERR_DIVERGED,
                            "%s: nts-augmented: slave node %lld slid beyond master face %d into face %d (gap %g) "
                            "for the %d. time in this step; the step is cut", inst->name, (long long)p->node,
                            p->facet, proj.face, proj.gap, p->switches + 1);
  ++p->switches;
  inst->api->log(inst->host, 2, "%s: nts-augmented: slave node %lld slid beyond master face %d into face %d (gap %g): "
                 "Newton again on that face", inst->name, (long long)p->node, p->facet, proj.face, proj.gap);
  p->left_facet = p->facet;
  set_facet(inst, p, proj.face);
  const double f_new[2] = {proj.xi[0], inst->pdim == 2 ? proj.xi[1] : 0.0};
  start_on_new_facet(inst, p, state, f_new);
  p->f_frozen[0] = p->f_gap[0] = f_new[0];
  p->f_frozen[1] = p->f_gap[1] = f_new[1];
  p->slip = 0;
  *switched = 1;
  return SK_OK;
}
