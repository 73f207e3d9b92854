/* penalty-nts: parameters and their defaults, what check refuses, creation (tributary areas, TRI6 recovery) and
 * destruction of an instance. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "penalty_nts.h"
#include "stickslip/modified_basis.h"

const char *const pnts_strategies[] = {"none", NULL};
const char *const pnts_parameters[] = {
    "penalty: normal penalty eps_n > 0; pressure/length when area_weighted, force/length otherwise [computed from "
    "the scene: 10 E*/h on first-order slave faces, 300 E*/h on second-order ones (E*: contact modulus of the "
    "pair, h: mean edge of the slave surface); times the mean tributary area when area_weighted is 0]",
    "mu: Coulomb friction coefficient >= 0 [0]",
    "penalty_tangential: tangential penalty eps_t > 0, same units as penalty [computed from the scene: penalty]",
    "area_weighted: 1 scales the penalties by the slave node's tributary reference area, 0 uses them as nodal "
    "stiffnesses [1]",
    "search_margin: inflation of the search boxes (length) [computed from the scene: half the mean master face "
    "size; 0 against an obstacle]",
    MASTER_EXTENSION_HELP,
    SELF_EXCLUSION_HELP,
    NULL};

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

sk_status pnts_check(const sk_scene_info *scene, char *reason, int size) {
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
 * The weights: sk_modified_basis_weights (stickslip/modified_basis.h, shared with the host's tributary measures). */

/* The rows of T^T for the pressure recovery of TRI6 slaves: a corner takes its own force and alpha times the force of
 * each edge node next to it (each edge once, however many faces share it), an edge node (1 - 2 alpha) times its own.
 * For a uniform pressure p the nodal forces are p integral N_I, and the recovery returns p at every node; the raw
 * force / weight gives 0 at TRI6 corners and 5/3 p at edge nodes. Over view nodes: the view holds every face around
 * an owned node, so an owned node's row is complete. */
static sk_status build_recovery(sk_instance *in) {
  const sk_view *slave = in->slave;
  const int corners = sk_modified_basis_corners(slave->cell_type);
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
    in->rec_coef[fill[pair_corner[k]]++] = SK_MODIFIED_BASIS_ALPHA;
  }
  for (int k = 0; k < n; ++k) in->rec_coef[in->rec_start[pair_edge[k]]] = 1.0 - 2.0 * SK_MODIFIED_BASIS_ALPHA;
done:
  free(pair_corner);
  free(pair_edge);
  free(fill);
  free(edge_done);
  return status;
}

/* The slave nodes this rank evaluates (sk_instance.evaluated): a node's residual, Jacobian and history depend on
 * its own candidates, selection and anchor only, so a rank needs them for the nodes whose rows it writes (its owned
 * nodes) and, with the TRI6 recovery, for the nodes their reported pressure combines. Under a contact partition the
 * view holds two layers of faces around the owned nodes; evaluating every view node made each rank repeat most of
 * its neighbours' work (corner-contact on 4 ranks: 20 to 25 view nodes for 6 or 7 owned, docs/scaling.md). */
static sk_status mark_evaluated(sk_instance *in) {
  in->evaluated = calloc((size_t)(in->n_slave > 0 ? in->n_slave : 1), 1);
  if (!in->evaluated) return in->api->error(in->host, SK_ERR_NOMEM, "%s: penalty-nts: out of memory", in->name);
  for (int k = 0; k < in->n_slave; ++k) {
    if (!in->slave->owned[k]) continue;
    in->evaluated[k] = 1;
    for (int r = in->rec_start ? in->rec_start[k] : 0; in->rec_start && r < in->rec_start[k + 1]; ++r)
      in->evaluated[in->rec_node[r]] = 1;
  }
  return SK_OK;
}

void pnts_destroy(sk_instance *in) {
  if (!in) return;
  if (in->search) in->cs->search_destroy(in->search);
  free(in->area);
  free(in->evaluated);
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
  if (in->self)
    SK_TRY(self_contact_exclusion(api, host, master, &in->self_exclusion));
  else
    self_contact_exclusion_unused(api, host);
  char why[200];
  if (master)
    snprintf(why, sizeof why, "half the mean face size (diagonal of the reference box) of master surface '%s'",
             master->name);
  else
    snprintf(why, sizeof why, "0: a rigid obstacle has no master faces to search");
  SK_TRY(sk_defaults_length(api, host, "search_margin", 0.5 * mean_size, why, &in->margin));
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
   * nodes: the view holds every face around them); on TRI6 faces of the modified basis (sk_modified_basis_weights). */
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
      sk_modified_basis_weights(slave->cell_type, A);
      for (int I = 0; I < slave->nen; ++I) in->area[slave->conn[f * slave->nen + I]] += A[I];
    }
  } else {
    for (int k = 0; k < in->n_slave; ++k) in->area[k] = 1.0;
  }
  SK_TRY(build_recovery(in));
  SK_TRY(mark_evaluated(in));
  if (master) SK_TRY(in->cs->search_create(master, &in->search));
  return SK_OK;
}

sk_status pnts_create(const sk_host_api *api, sk_host *host, const sk_attach *attach, sk_instance **instance) {
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
