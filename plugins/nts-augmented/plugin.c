/* nts-augmented — the plugin table (glue.h): parameters, the unknowns' layout per strategy, the active set (the
 * history, results and checkpoints: history.c). The strategies (element.c has what each one assembles):
 *   condensed        f and lambda_aug condensed out exactly per element: n + n_s unknowns, iterates = augmented
 *   augmented        the whole augmented system (50)/(76) of the active nodes: n + 5 n_c (n + 3 n_c in 2D)
 *   paper-reduced    the paper's size reduction (55), (78)-(81) as published
 *   direct           the direct method: closest point by a local Newton (41); at the midpoint (74)/(75)
 *   direct-endpoint  the direct method with the closest point at t_{n+1}, forces at the mean of f (= the augmented
 *                    equations, f and lambda_aug eliminated nonlinearly)
 * `reduced` and `none`, the names before these, are kept as deprecated aliases of `condensed` and `augmented`. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "candidates.h"
#include "defaults.h"
#include "glue.h"
#include "self_contact.h"

static const char *const strategies[] = {"condensed", "augmented", "paper-reduced", "direct", "direct-endpoint",
                                         "reduced",   "none",      NULL};
enum { N_STRATEGIES = 5 }; /* the rest are aliases */
static const nts_strategy alias_of[] = {NTS_CONDENSED, NTS_AUGMENTED};

static const char *const parameters[] = {
    "mu: Coulomb friction coefficient [0]",
    "epsilon_t: tangential penalty of the regularised friction law, force per unit of f (a nodal stiffness) "
    "[computed from the scene: 10 E*/h A (E*: contact modulus of the pair, h: mean edge and A: mean tributary "
    "area per node of the slave surface)]",
    "c_n: weight of the gap in the active-set test -lambda_n - c_n g > 0, force per length [computed from the "
    "scene: E*/h A]",
    "search_margin: inflation of the search boxes (length) [computed from the scene: half the mean master edge length; "
    "of the slave surface against an obstacle]",
    MASTER_EXTENSION_HELP,
    "max_flips: active-set changes of one node per step before its state is frozen [4]",
    "slide_search: 1 moves a node that slid beyond its facet into the master onto that face at the converged point "
    "(large sliding per step; docs/plugins/nts-augmented.md) [0]",
    SELF_EXCLUSION_HELP,
    NULL};

/* A frozen node (max_flips) is set right at a converged point when it is in tension or penetrates beyond these
 * fractions of the pair's largest |lambda_n| and of the search margin (round-off of converged states is ~1e-13). */
static const double TENSION_FRACTION = 1e-9, PENETRATION_FRACTION = 1e-9;

/* ---- create / destroy --------------------------------------------------------------------------------------------- */
static void destroy(sk_instance *inst) {
  if (!inst) return;
  if (inst->search) inst->api->contact->search_destroy(inst->search);
  free(inst->points);
  free(inst->initial);
  free(inst->eliminated);
  free(inst->anchor);
  free(inst->node_flags);
  free(inst->candidates);
  free(inst->projections);
  nts_self_free(inst);
  free(inst);
}

static double mean_edge(const sk_view *view) {
  double sum = 0.0;
  int count = 0;
  const sk_elem_type type = view->cell_type;
  const int corners = type == SK_TRI3 || type == SK_TRI6 ? 3 : type == SK_LINE2 || type == SK_LINE3 ? 2 : 4;
  const int dim = view->dim;
  const double *X = view->X;
  for (int f = 0; f < view->n_cells; ++f)
    for (int e = 0; e < (corners == 2 ? 1 : corners); ++e) {
      const int a = view->conn[f * view->nen + e], b = view->conn[f * view->nen + (e + 1) % corners];
      double d2 = 0.0;
      for (int i = 0; i < dim; ++i) d2 += (X[dim * a + i] - X[dim * b + i]) * (X[dim * a + i] - X[dim * b + i]);
      sum += sqrt(d2);
      ++count;
    }
  return count ? sum / count : 1.0;
}

/* A rigid obstacle: the plane's frame and each node's origin on it. The augmented coordinates need a
 * parametrisation x(f) of the master, which the contact services give for a plane only (curved obstacles come
 * with their closest point and curvature, not a chart). */
static sk_status plane_setup(sk_instance *inst) {
  const sk_view *slave = inst->slave;
  const int dim = inst->dim;
  double d0[3] = {0, 0, 0};
  inst->api->contact->obstacle_displacement(inst->obstacle, 0.0, d0);
  for (int k = 0; k < slave->n_nodes; ++k) {
    sk_surface_point pt = {.struct_size = sizeof pt};
    double gap = 0.0;
    SK_TRY(inst->api->contact->obstacle_project(inst->obstacle, 0.0, slave->X + dim * k, dim, &pt, &gap));
    const double h = fabs(pt.h[0][0]) + fabs(pt.h[0][1]) + fabs(pt.h[1][0]) + fabs(pt.h[1][1]);
    if (h != 0.0)
      return inst->api->error(inst->host, SK_ERR_INPUT,
                              "%s: nts-augmented takes plane obstacles only: this obstacle is curved (curvature %g "
                              "at slave node %lld), and the augmented coordinates need a parametrisation of the "
                              "master surface that the contact services give for planes only",
                              inst->name, h, (long long)slave->node_id[k]);
    for (int i = 0; i < 3; ++i) inst->points[k].plane_origin[i] = pt.x[i] - (i < dim ? d0[i] : 0.0);
    if (k == 0) memcpy(inst->plane_normal, pt.n, sizeof pt.n);
  }
  const double *n = inst->plane_normal;
  if (dim == 2) { /* a_1 x e_z = n */
    const double t1[3] = {-n[1], n[0], 0.0};
    memcpy(inst->plane_tangent[0], t1, sizeof t1);
  } else { /* a_1 from the services' frame, a_2 = n x a_1 so that a_1 x a_2 = n */
    sk_surface_point pt = {.struct_size = sizeof pt};
    double gap = 0.0;
    SK_TRY(inst->api->contact->obstacle_project(inst->obstacle, 0.0, slave->X, dim, &pt, &gap));
    memcpy(inst->plane_tangent[0], pt.a[0], sizeof pt.a[0]);
    const double *t1 = pt.a[0];
    double *t2 = inst->plane_tangent[1];
    t2[0] = n[1] * t1[2] - n[2] * t1[1];
    t2[1] = n[2] * t1[0] - n[0] * t1[2];
    t2[2] = n[0] * t1[1] - n[1] * t1[0];
  }
  return SK_OK;
}

/* ---- what the plugin cannot run (sk_plugin.check, ABI 2.7; create() asks the same on older hosts) ---------------- */

/* Every node of a slave face is a slave point with its own multiplier, a nodal force, which takes the consistent
 * nodal loads of the face's standard shape functions: under a uniform pressure those are positive on line2, line3,
 * tri3, quad4 and quad9 faces (line3: 1/6, 2/3, 1/6 of the length; quad9: 1/36, 1/9, 4/9 of the area at a corner,
 * an edge, the centre), zero at TRI6 corners and negative at QUAD8 corners (-1/12), which would have to pull
 * (docs/plugins/nts-augmented.md#quadratic-faces). Master faces are geometry only: every face type of the kernel. */
static int slave_face_taken(sk_elem_type type) {
  return type == SK_LINE2 || type == SK_LINE3 || type == SK_TRI3 || type == SK_QUAD4 || type == SK_QUAD9;
}

static int master_face_taken(sk_elem_type type) {
  return slave_face_taken(type) || type == SK_TRI6 || type == SK_QUAD8;
}

static const char *face_name(sk_elem_type type) {
  return type == SK_TRI6 ? "TRI6" : type == SK_QUAD8 ? "QUAD8" : "unsupported";
}

static int faces_refused(const char *slave_name, sk_elem_type slave, const char *master_name, sk_elem_type master,
                         char *reason, int size) {
  if (!slave_face_taken(slave))
    snprintf(reason, (size_t)size, "nts-augmented takes line2, line3, tri3, quad4 and quad9 slave faces: slave "
             "surface '%s' has %s faces, whose corner nodes' consistent loads under a uniform pressure are %s, which "
             "nodal multipliers cannot carry (docs/plugins/nts-augmented.md#quadratic-faces; mesh.order: 2 with "
             "hexahedra gives quad9 faces)", slave_name, face_name(slave),
             slave == SK_TRI6 ? "zero" : slave == SK_QUAD8 ? "negative" : "unknown");
  else if (master_name && !master_face_taken(master))
    snprintf(reason, (size_t)size, "nts-augmented: master surface '%s' has faces of a type it does not take",
             master_name);
  else
    return 0;
  return 1;
}

static sk_status check(const sk_scene_info *scene, char *reason, int size) {
  const sk_scene_side *slave = scene->slave, *master = scene->master;
  if (faces_refused(slave->name, slave->cell_type, master->rigid ? NULL : master->name, master->cell_type, reason,
                    size))
    return SK_ERR_PLUGIN;
  if (master->rigid && master->shape != SK_SHAPE_PLANE) {
    snprintf(reason, (size_t)size, "nts-augmented takes plane obstacles only: obstacle '%s' is curved, and the "
             "augmented coordinates need a parametrisation of the master surface, which the contact services give "
             "for planes only", master->name);
    return SK_ERR_PLUGIN;
  }
  return SK_OK;
}

/* epsilon_t and c_n: the scene's values, or computed from it (docs/plugins/nts-augmented.md#defaults). Both are
 * nodal stiffnesses (force per length: lambda_n is a nodal force, epsilon_t m (f - f_n) a nodal tangential force):
 * c E* / h times the slave surface's mean tributary area (length in 2D) per node, with E* the pair's contact modulus
 * and h the slave surface's mean edge; c = EPSILON_T_FACTOR and C_N_FACTOR. */
static const double EPSILON_T_FACTOR = 10.0, C_N_FACTOR = 1.0;

static sk_status read_stiffnesses(sk_instance *inst) {
  const sk_scene_ext *scene = sk_defaults_scene(inst->api, inst->host);
  const sk_scene_info *info = scene ? scene->info(inst->host) : NULL;
  char reason[900] = "";
  if (inst->friction.mu > 0.0) {
    const double computed = info ? sk_defaults_stiffness(info, EPSILON_T_FACTOR, 1, reason, sizeof reason) : 0.0;
    SK_TRY(sk_defaults_param(inst->api, inst->host, scene, "epsilon_t", computed, reason, &inst->friction.epsilon_t));
  } else { /* frictionless: unused, so not required; reported as unused */
    SK_TRY(inst->api->param_double(inst->host, "epsilon_t", 0, NAN, &inst->friction.epsilon_t));
    if (isnan(inst->friction.epsilon_t)) {
      inst->friction.epsilon_t = 0.0;
      sk_defaults_unused(inst->api, inst->host, "epsilon_t", "unused: the pair is frictionless (mu 0)");
    }
  }
  const double computed = info ? sk_defaults_stiffness(info, C_N_FACTOR, 1, reason, sizeof reason) : 0.0;
  return sk_defaults_param(inst->api, inst->host, scene, "c_n", computed, reason, &inst->c_n);
}

static sk_status create_checked(sk_instance *inst, const sk_attach *attach) {
  const sk_host_api *api = inst->api;
  sk_host *host = inst->host;
  const sk_view *slave = attach->slave, *master = attach->master;
  inst->dim = slave->dim;
  inst->pdim = slave->dim - 1;
  inst->stride = 1 + 2 * inst->pdim;
  if (!master && !attach->obstacle)
    return api->error(host, SK_ERR_INPUT, "%s: nts-augmented needs a master surface or a plane obstacle", inst->name);
  char reason[400];
  if (faces_refused(slave->name, slave->cell_type, master ? master->name : NULL,
                    master ? master->cell_type : SK_POINT1, reason, sizeof reason))
    return api->error(host, SK_ERR_INPUT, "%s: %s", inst->name, reason);
  const sk_elem_type facet_type = master ? master->cell_type : inst->dim == 3 ? SK_QUAD4 : SK_LINE2;
  if (nts_facet_init(&inst->facet, facet_type, api->contact->shape, api->contact->shape_hessian) != 0)
    return api->error(host, SK_ERR_INTERNAL, "%s: nts-augmented: no facet for %d-node faces", inst->name,
                      master ? master->nen : 0);
  inst->strategy = attach->strategy < N_STRATEGIES ? (nts_strategy)attach->strategy
                                                   : alias_of[attach->strategy - N_STRATEGIES];
  if (attach->strategy >= N_STRATEGIES)
    api->log(host, 1, "%s: nts-augmented: strategy '%s' is deprecated; it is '%s' (docs/plugins/nts-augmented.md)",
             inst->name, strategies[attach->strategy], strategies[inst->strategy]);
  SK_TRY(api->param_double(host, "mu", 0, 0.0, &inst->friction.mu));
  SK_TRY(read_stiffnesses(inst));
  char why[200];
  snprintf(why, sizeof why, "half the mean edge of %s surface '%s'", master ? "master" : "slave",
           (master ? master : slave)->name);
  SK_TRY(sk_defaults_length(api, host, "search_margin", 0.5 * mean_edge(master ? master : slave), why,
                            &inst->search_margin));
  SK_TRY(api->param_double(host, "master_extension", 0, 0.1, &inst->master_extension));
  SK_TRY(api->param_int(host, "max_flips", 0, 4, &inst->max_flips));
  SK_TRY(api->param_int(host, "slide_search", 0, 0, &inst->slide_search));
  inst->self = attach->self_contact;
  if (inst->self) {
    SK_TRY(self_contact_exclusion(api, host, master, &inst->self_exclusion));
    SK_TRY(nts_self_setup(inst));
  } else {
    self_contact_exclusion_unused(api, host);
  }
  if (inst->friction.mu < 0.0 || (inst->friction.mu > 0.0 && inst->friction.epsilon_t <= 0.0) || inst->c_n <= 0.0 ||
      inst->search_margin < 0.0 || !(inst->master_extension >= 0.0 && inst->master_extension <= 0.5))
    return api->error(host, SK_ERR_INPUT,
                      "%s: nts-augmented needs mu >= 0, epsilon_t > 0 when mu > 0, c_n > 0, search_margin >= 0 and "
                      "master_extension in [0, 0.5] (got mu %g, epsilon_t %g, c_n %g, search_margin %g, "
                      "master_extension %g)",
                      inst->name, inst->friction.mu, inst->friction.epsilon_t, inst->c_n, inst->search_margin,
                      inst->master_extension);
  inst->n_points = slave->n_nodes;
  inst->n_extra = inst->stride * slave->n_nodes_global;
  inst->points = calloc((size_t)(slave->n_nodes > 0 ? slave->n_nodes : 1), sizeof *inst->points);
  inst->initial = calloc((size_t)inst->n_extra + 1, sizeof *inst->initial);
  inst->eliminated = calloc((size_t)inst->n_extra + 1, 1);
  inst->anchor = malloc(sizeof(int64_t) * ((size_t)inst->n_extra + 1));
  inst->node_flags = calloc((size_t)slave->n_nodes_global + 1, sizeof *inst->node_flags);
  inst->projections = calloc((size_t)(slave->n_nodes > 0 ? slave->n_nodes : 1), sizeof *inst->projections);
  inst->candidates = malloc(sizeof(int) * (size_t)(master && master->n_cells > 0 ? master->n_cells : 1));
  if (!inst->points || !inst->initial || !inst->eliminated || !inst->anchor || !inst->node_flags || !inst->candidates ||
      !inst->projections)
    return api->error(host, SK_ERR_NOMEM, "%s: out of memory", inst->name);
  for (int k = 0; k < slave->n_nodes; ++k) {
    slave_point *p = &inst->points[k];
    p->k = k;
    p->node = slave->node_id[k];
    p->index = slave->node_index[k];
    p->c_facet = p->facet = -1;
  }
  /* the layout is the same on every rank: every node of the whole surface; `augmented` chooses per attempt */
  for (int64_t i = 0; i < inst->n_extra; ++i) inst->eliminated[i] = i % inst->stride != 0;
  for (int64_t i = 0; i < inst->n_extra; ++i) inst->anchor[i] = -1;
  for (int k = 0; k < slave->n_nodes; ++k)
    for (int j = 0; j < inst->stride; ++j) inst->anchor[inst->stride * slave->node_index[k] + j] = slave->dofs[inst->dim * k];
  if (attach->obstacle) {
    inst->obstacle = attach->obstacle;
    return plane_setup(inst);
  }
  return api->contact->search_create(master, &inst->search);
}

static sk_status create(const sk_host_api *api, sk_host *host, const sk_attach *attach, sk_instance **out) {
  *out = NULL;
  sk_instance *inst = calloc(1, sizeof *inst);
  if (!inst) return api->error(host, SK_ERR_NOMEM, "%s: out of memory", attach->name);
  inst->api = api;
  inst->host = host;
  inst->slave = attach->slave;
  inst->master = attach->master;
  inst->name = attach->name;
  const sk_status st = create_checked(inst, attach);
  if (st != SK_OK) {
    destroy(inst);
    return st;
  }
  *out = inst;
  return SK_OK;
}

/* ---- the unknowns ---------------------------------------------------------------------------------------------- */
static sk_status begin_step(sk_instance *inst, const sk_state *state) { return nts_begin_step(inst, state); }

/* Under `augmented` the linear system holds the extras of the active nodes only (the set at begin_step, or at the
 * converged point of the last outer loop); every other node's extras are eliminated with their identity rows. */
static sk_status layout(sk_instance *inst, const sk_state *state, sk_layout *out) {
  (void)state;
  out->n_extra = inst->n_extra;
  out->initial = inst->initial;
  out->eliminated = inst->eliminated;
  if (SK_HAS(out, extra_anchor)) out->extra_anchor = inst->anchor;
  /* ABI 2.3: no point reached a facet at begin_step, so every extra has its trivial row and starts at 0 */
  if (SK_HAS(out, idle)) {
    out->idle = 1;
    for (int k = 0; k < inst->n_points && out->idle; ++k) out->idle = inst->points[k].facet < 0;
  }
  if (inst->strategy != NTS_AUGMENTED) return SK_OK;
  const int64_t n_nodes = inst->slave->n_nodes_global;
  memset(inst->node_flags, 0, sizeof(double) * (size_t)n_nodes);
  for (int k = 0; k < inst->n_points; ++k) {
    const slave_point *p = &inst->points[k];
    if (nts_owned(inst, p) && p->facet >= 0 && p->active) inst->node_flags[p->index] = 1.0;
  }
  SK_TRY(inst->api->reduce(inst->host, 0, inst->node_flags, (int)n_nodes));
  for (int64_t i = 0; i < n_nodes; ++i)
    memset(inst->eliminated + inst->stride * i, inst->node_flags[i] < 0.5, (size_t)inst->stride);
  for (int k = 0; k < inst->n_points; ++k) inst->points[k].in_system = inst->node_flags[inst->points[k].index] > 0.5;
  return SK_OK;
}

static void extra_rows(const sk_instance *inst, const slave_point *p, int64_t *rows) {
  const int64_t base = inst->stride * p->index;
  for (int j = 0; j < inst->stride; ++j) rows[j] = base + j;
}

/* Each owned point's slave node and extras with its facet's nodes (the facet is fixed for the step). */
static sk_status pattern(sk_instance *inst, const sk_state *state, sk_pattern *out) {
  for (int k = 0; k < inst->n_points; ++k) {
    const slave_point *p = &inst->points[k];
    if (!nts_owned(inst, p)) continue;
    int64_t idx[NTS_MAX_NU];
    if (p->facet < 0) {
      extra_rows(inst, p, idx);
      for (int j = 0; j < inst->stride; ++j) idx[j] += state->extra_offset;
      out->add_block(out, inst->stride, idx, inst->stride, idx);
      continue;
    }
    nts_element_indices(inst, p, state->extra_offset + inst->stride * p->index, idx);
    const int nu = 3 + 3 * inst->facet.nen + 5;
    out->add_block(out, nu, idx, nu, idx);
  }
  return SK_OK;
}

/* ---- the active set ------------------------------------------------------------------------------------------- */
static sk_status update_active_set(sk_instance *inst, const sk_state *state, int *changed) {
  *changed = 0;
  for (int k = 0; k < inst->n_points; ++k) {
    slave_point *p = &inst->points[k];
    if (p->facet < 0) continue;
    const double *x = state->extra + inst->stride * p->index;
    double gap;
    int want_slip = p->slip;
    if (p->active) {
      nts_element e;
      SK_TRY(nts_element_eval(inst, k, state, &e));
      gap = nts_element_constraints(&e)[NTS_PHI_N];
      /* the stick/slip set follows the return map's trial at this iterate */
      const nts_friction *fr = nts_element_friction(&e);
      if (inst->friction.mu > 0.0) want_slip = fr->trial_norm > fr->cone;
    } else {
      double f[2] = {p->f_frozen[0], p->f_frozen[1]};
      gap = nts_gap_on_facet(inst, p, state->x, state->t, f);
    }
    const double lambda_n = p->active ? x[0] : 0.0;
    const int want_active = nts_wants_contact(inst, lambda_n, gap);
    /* `augmented`: a node whose extras are not in this loop's system waits for the converged point */
    p->wants_in = inst->strategy == NTS_AUGMENTED && want_active && !p->active && !p->in_system &&
                  p->flips < inst->max_flips;
    if (p->wants_in || (want_active == p->active && want_slip == p->slip)) continue;
    /* chattering: after max_flips the contact state is kept for the rest of the step and the stick/slip branch
     * is left to the return map (so Coulomb's law still holds exactly at convergence) */
    if (p->flips >= inst->max_flips) continue;
    if (++p->flips == inst->max_flips) {
      p->return_map = 1;
      inst->api->log(inst->host, 2, "%s: nts-augmented: slave node %lld changed its contact state %d times; frozen "
                     "for this step", inst->name, (long long)p->node, p->flips);
    }
    if (want_active != p->active) {
      p->active = want_active;
      p->slip = 0; /* a new contact starts sticking */
      if (!p->active) {
        /* keep f where it is: its trivial equation f = f_frozen is then already satisfied */
        p->f_frozen[0] = x[1];
        p->f_frozen[1] = inst->pdim == 2 ? x[2] : 0.0;
      }
    } else {
      p->slip = want_slip;
    }
    *changed = 1;
  }
  return SK_OK;
}

/* The converged point is rejected (Newton again from it) when `augmented` must take in a new contact, or when a
 * node frozen by max_flips is in tension or penetrates: no step ends with such a node.
 * A frozen node can be in a state that is consistent neither in contact nor out of it at this dt: in contact it
 * pulls (lambda_n > 0), released it penetrates (the coarse two tori, step 129: node 532, lambda_n 6.0 against
 * |lambda_n| up to 2e4, gap -9.5e-6). The discrete problem then has no complementary solution for that node with the
 * rest of the set; the midpoint force at y_hat, the gap at t_{n+1} and the non-associated friction make its normal
 * response non-monotone. Accepting the smaller violation would end the step penetrating (the next step's
 * activation then does the work |lambda_n| |g_n| on the bodies, the energy increase the facet-switch rule removed)
 * or pulling (Signorini violated), so the step is cut instead, which restores a consistent state (measured: the
 * half steps converge). The cut comes as soon as the set cycles, when the node needs a third correction (both
 * states rejected, one twice), rather than after solver.newton.max_active_set_loops outer loops. */
static sk_status correct_frozen(sk_instance *inst, slave_point *p, int to_active, double violation) {
  if (p->corrections >= 2)
    return inst->api->error(inst->host, SK_ERR_DIVERGED,
                            "%s: nts-augmented: frozen slave node %lld has no consistent contact state at this dt: "
                            "in contact it pulls (lambda_n %g), released it penetrates (gap %g); the step is cut",
                            inst->name, (long long)p->node, to_active ? p->tension : violation,
                            -(to_active ? violation : p->penetration));
  ++p->corrections;
  if (to_active) {
    p->penetration = violation;
    inst->api->log(inst->host, 2, "%s: nts-augmented: frozen slave node %lld penetrates (gap %g): in contact",
                   inst->name, (long long)p->node, -violation);
  } else {
    p->tension = violation;
    inst->api->log(inst->host, 2, "%s: nts-augmented: frozen slave node %lld in tension (lambda_n %g): released",
                   inst->name, (long long)p->node, violation);
  }
  return SK_OK;
}

static sk_status converged(sk_instance *inst, const sk_state *state, int *accept) {
  *accept = 1;
  double lambda_max = 0.0;
  for (int k = 0; k < inst->n_points; ++k) {
    const slave_point *p = &inst->points[k];
    if (nts_owned(inst, p) && p->facet >= 0 && p->active)
      lambda_max = fmax(lambda_max, fabs(state->extra[inst->stride * p->index]));
  }
  SK_TRY(inst->api->reduce(inst->host, 1, &lambda_max, 1));
  for (int k = 0; k < inst->n_points; ++k) {
    slave_point *p = &inst->points[k];
    if (p->facet < 0) continue;
    const double *x = state->extra + inst->stride * p->index;
    if (p->wants_in) {
      p->active = 1;
      p->slip = 0;
      p->wants_in = 0;
      *accept = 0;
      continue;
    }
    int switched = 0;
    if (inst->slide_search) SK_TRY(nts_research_facet(inst, p, state, &switched));
    if (switched) {
      *accept = 0;
      continue;
    }
    if (p->flips < inst->max_flips) continue;
    if (p->active && x[0] > TENSION_FRACTION * lambda_max) {
      SK_TRY(correct_frozen(inst, p, 0, x[0]));
      p->active = 0;
      p->f_frozen[0] = x[1];
      p->f_frozen[1] = inst->pdim == 2 ? x[2] : 0.0;
      *accept = 0;
    } else if (!p->active) {
      double f[2] = {p->f_frozen[0], p->f_frozen[1]};
      const double gap = nts_gap_on_facet(inst, p, state->x, state->t, f);
      if (gap < -PENETRATION_FRACTION * inst->search_margin) {
        SK_TRY(correct_frozen(inst, p, 1, -gap));
        p->active = 1;
        p->slip = 0;
        *accept = 0;
      }
    }
  }
  return SK_OK;
}

/* ---- residual, Jacobian, recovery ------------------------------------------------------------------------------ */
static sk_status residual(sk_instance *inst, const sk_state *state, sk_sink *sink) {
  for (int k = 0; k < inst->n_points; ++k) {
    const slave_point *p = &inst->points[k];
    if (!nts_owned(inst, p)) continue;
    if (p->facet < 0) {
      const double *x = state->extra + inst->stride * p->index;
      int64_t rows[NTS_MAX_STRIDE];
      double R[NTS_MAX_STRIDE];
      extra_rows(inst, p, rows);
      for (int j = 0; j < inst->stride; ++j) {
        rows[j] += state->extra_offset;
        R[j] = x[j];
      }
      R[1] -= p->f_frozen[0];
      if (inst->pdim == 2) R[2] -= p->f_frozen[1];
      sink->add_vector(sink, inst->stride, rows, R);
      continue;
    }
    nts_element e;
    SK_TRY(nts_element_eval(inst, k, state, &e));
    double R[NTS_MAX_NU];
    nts_element_residual(inst, p, &e, R);
    sink->add_vector(sink, 3 + 3 * inst->facet.nen + 5, e.idx, R);
  }
  return SK_OK;
}

static sk_status jacobian(sk_instance *inst, const sk_state *state, sk_sink *sink) {
  for (int k = 0; k < inst->n_points; ++k) {
    const slave_point *p = &inst->points[k];
    if (!nts_owned(inst, p)) continue;
    if (p->facet < 0) { /* identity rows of the kept extras */
      const double one = 1.0;
      int64_t rows[NTS_MAX_STRIDE];
      extra_rows(inst, p, rows);
      for (int j = 0; j < inst->stride; ++j) {
        rows[j] += state->extra_offset;
        if (!inst->eliminated[rows[j] - state->extra_offset]) sink->add_matrix(sink, 1, rows + j, 1, rows + j, &one);
      }
      continue;
    }
    nts_element e;
    SK_TRY(nts_element_eval(inst, k, state, &e));
    SK_TRY(nts_element_jacobian(inst, p, &e, sink));
  }
  return SK_OK;
}

static sk_status recover(sk_instance *inst, const sk_state *state, sk_vectors *v) {
  for (int k = 0; k < inst->n_points; ++k) {
    const slave_point *p = &inst->points[k];
    if (!nts_owned(inst, p)) continue;
    const double *F = v->F_extra + inst->stride * p->index;
    double *dx = v->dx_extra + inst->stride * p->index;
    if (inst->strategy == NTS_AUGMENTED) {
      if (!p->in_system) /* identity rows, all eliminated */
        for (int j = 0; j < inst->stride; ++j) dx[j] = -F[j];
      continue;
    }
    if (p->facet < 0 || !p->active) {
      for (int j = 1; j < inst->stride; ++j) dx[j] = -F[j];
      continue;
    }
    nts_element e;
    SK_TRY(nts_element_eval(inst, k, state, &e));
    SK_TRY(nts_element_recover(inst, p, &e, state, v));
  }
  return SK_OK;
}

static const void *extension(const char *id) {
  return id && strcmp(id, SK_EXT_CHECKPOINT) == 0 ? &nts_checkpoint : NULL;
}

static const sk_plugin plugin = {
    SK_TABLE_HEADER(sk_plugin),
    .name = "nts-augmented",
    .summary = "node-to-surface (2D: node-to-segment) contact with coordinate augmentation and size reduction "
               "(Franke, Hesch, Betsch 2013)",
    .kinds = SK_KIND_PAIR,
    .caps = SK_CAP_2D | SK_CAP_3D | SK_CAP_FRICTION | SK_CAP_QUASISTATIC | SK_CAP_DYNAMICS |
            SK_CAP_ENERGY_MOMENTUM | SK_CAP_RIGID_OBSTACLE | SK_CAP_DEFORMABLE_MASTER | SK_CAP_MULTIPLIERS |
            SK_CAP_CONDENSATION | SK_CAP_SAYS_IDLE | SK_CAP_SELF_CONTACT,
    .strategies = strategies,
    .parameters = parameters,
    .create = create,
    .destroy = destroy,
    .begin_step = begin_step,
    .layout = layout,
    .pattern = pattern,
    .update_active_set = update_active_set,
    .residual = residual,
    .jacobian = jacobian,
    .recover = recover,
    .converged = converged,
    .commit_step = nts_commit_step,
    .reject_step = nts_reject_step,
    .report = nts_report,
    .points = nts_points,
    .get_extension = extension,
    .check = check,
};

__attribute__((visibility("default"))) const sk_plugin *stickslip_plugin_entry(void);
__attribute__((visibility("default"))) const sk_plugin *stickslip_plugin_entry(void) { return &plugin; }
