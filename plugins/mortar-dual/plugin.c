/* mortar-dual — plugin glue: parameters, topology, the step's candidates, the active-set loops, history, output.
 * The contact terms themselves are assembled by assemble.c from the kernel (kernel.h). Strategies:
 *   saddle-point  displacements and z (standard or dual basis): a direct solver
 *   condensed     dual basis; z eliminated by the host on the assembled operator (stickslip.condense.v1) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "defaults.h"
#include "mortar.h"
#include "records.h"
#include "stickslip/modified_basis.h"

static const char *const strategies[] = {"saddle-point", "condensed", NULL};
static const char *const parameters[] = {
    "basis: dual | standard multipliers (condensed needs dual) [dual]",
    "integration: segments (exact for straight edges / flat faces) | concentrated (Hammer's Gauss points) [segments]",
    "normal: A (averaged slave normal) | M (master normal; concentrated integration only) [A]",
    "active_set: semismooth (set updated with the iterate) | nested (Hammer: frozen in Newton, updated at "
    "convergence) [semismooth]",
    "mu: Coulomb friction coefficient [0]",
    "c_n: complementarity parameter of the normal condition, traction per length [computed from the scene: 10 E*/h "
    "(E*: contact modulus of the pair, h: mean edge of the slave surface)]",
    "c_t: complementarity parameter of the tangential condition, traction per length [computed from the scene: c_n]",
    "segment_gauss: Gauss points per 2D integration segment [3; 5 with line3 faces]",
    "cell_rule: points per 3D integration triangle: 3, 6, 7 or 12 (degree 2, 4, 5, 6) [3 on tri3/tri3 pairs, exact "
    "there; 12 with quad9 faces; else 6, exact on parallelograms and flat tri6 faces]",
    "face_gauss: Gauss points per direction on a slave face (concentrated integration, obstacles) [5]",
    "frozen_band: concentrated integration: how far beyond its edge, in face parameters, a Gauss point keeps the "
    "master face chosen at the step's start (0.1: 5 % of an edge); 0 chooses again whenever it leaves the face, "
    "path-independent to round-off at the cost of more Newton runs [0.1]",
    "max_flips: active-set changes of a node within a step before its branch is frozen (semismooth) [8]",
    "min_cover: share of a node's support the master must cover for it to enter contact [0.5]",
    "search_margin: inflation of the search boxes (length) [the mean master edge length]",
    "self_exclusion: self contact only: faces with nodes within this distance of each other in the reference "
    "configuration never meet [computed from the scene: the surface's largest face (diagonal of its reference box)]",
    NULL};

/* ---- helpers ----------------------------------------------------------------------------------------------------- */
static void *alloc_zero(size_t n, size_t size) { return calloc(n > 0 ? n : 1, size); }

static void destroy(sk_instance *inst) {
  if (!inst) return;
  if (inst->search) inst->api->contact->search_destroy(inst->search);
  void *ptrs[] = {inst->A_node, inst->A_current, inst->star_face_ptr, inst->star_face, inst->star_node_ptr, inst->star_node,
                  inst->face_star_index,
                  inst->face_needed, inst->normal, inst->dnormal, inst->cvec, inst->dc, inst->owned,
                  inst->owned_of_node, inst->cand_ptr, inst->cand, inst->cand_ptr_next, inst->cand_next, inst->hit_ptr,
                  inst->hits.faces, inst->ip_master, inst->col, inst->col_side,
                  inst->col_node, inst->col_comp, inst->acc_gap, inst->acc_W, inst->z_committed, inst->hist_side,
                  inst->hist_node, inst->hist_value, inst->pair_extra, inst->pair_row, inst->anchor, inst->chain.side,
                  inst->chain.node, inst->chain.entry, inst->block, inst->block_cols, inst->pos_map,
                  inst->commit_rows, inst->tmp_entries, inst->master_star_ptr, inst->master_star,
                  inst->master_border, inst->role, inst->role_committed, inst->role_preferred,
                  inst->on_master, inst->edge, inst->adj_ptr, inst->adj, inst->queue, inst->cache_values,
                  inst->cache_x, inst->cache_cells};
  for (size_t i = 0; i < sizeof ptrs / sizeof ptrs[0]; ++i) free(ptrs[i]);
  free(inst);
}

static sk_status nomem(sk_instance *inst) {
  return inst->api->error(inst->host, SK_ERR_NOMEM, "mortar-dual: out of memory");
}

static int choice(const char *value, const char *const *options) {
  for (int i = 0; options[i]; ++i)
    if (strcmp(value, options[i]) == 0) return i;
  return -1;
}

static sk_status read_choice(sk_instance *inst, const char *key, const char *const *options, int *out) {
  const char *value;
  SK_TRY(inst->api->param_string(inst->host, key, 0, options[0], &value));
  *out = choice(value, options);
  if (*out < 0)
    return inst->api->error(inst->host, SK_ERR_INPUT, "mortar-dual: %s must be %s or %s (got '%s')", key, options[0],
                            options[1], value);
  return SK_OK;
}

/* Node -> faces and node -> nodes of those faces (CSR), for a view. */
static sk_status build_stars(sk_instance *inst, const sk_view *v, int **face_ptr, int **faces, int **node_ptr,
                             int **nodes) {
  const int nn = v->n_nodes, nen = v->nen;
  int *fp = alloc_zero((size_t)nn + 1, sizeof(int)), *fl = alloc_zero((size_t)v->n_cells * nen, sizeof(int));
  if (!fp || !fl) {
    free(fp);
    free(fl);
    return nomem(inst);
  }
  for (int f = 0; f < v->n_cells; ++f)
    for (int a = 0; a < nen; ++a) ++fp[v->conn[(int64_t)f * nen + a] + 1];
  for (int k = 0; k < nn; ++k) fp[k + 1] += fp[k];
  int *fill = alloc_zero((size_t)nn, sizeof(int));
  if (!fill) {
    free(fp);
    free(fl);
    return nomem(inst);
  }
  for (int f = 0; f < v->n_cells; ++f)
    for (int a = 0; a < nen; ++a) {
      const int k = v->conn[(int64_t)f * nen + a];
      fl[fp[k] + fill[k]++] = f;
    }
  *face_ptr = fp;
  *faces = fl;
  if (!node_ptr) {
    free(fill);
    return SK_OK;
  }
  /* nodes of the faces around each node, unique, the node itself included */
  int *np = alloc_zero((size_t)nn + 1, sizeof(int)), *nl = alloc_zero((size_t)fp[nn] * nen, sizeof(int));
  if (!np || !nl) {
    free(fill);
    free(np);
    free(nl);
    return nomem(inst);
  }
  int n = 0;
  for (int k = 0; k < nn; ++k) {
    np[k] = n;
    for (int e = fp[k]; e < fp[k + 1]; ++e)
      for (int a = 0; a < nen; ++a) {
        const int b = v->conn[(int64_t)fl[e] * nen + a];
        int seen = 0;
        for (int s = np[k]; s < n && !seen; ++s) seen = nl[s] == b;
        if (!seen) nl[n++] = b;
      }
  }
  np[nn] = n;
  free(fill);
  *node_ptr = np;
  *nodes = nl;
  return SK_OK;
}

/* Checks that the faces around every node of a needed slave face are in the view on this rank (the averaged normal
 * of such a node and its derivative need them all): face counts per node, maximised over ranks. */
static sk_status check_stars(sk_instance *inst) {
  const sk_view *v = inst->slave;
  double *count = alloc_zero((size_t)v->n_nodes_global, sizeof(double));
  if (!count) return nomem(inst);
  for (int k = 0; k < v->n_nodes; ++k) count[v->node_index[k]] = inst->star_face_ptr[k + 1] - inst->star_face_ptr[k];
  double *local = alloc_zero((size_t)v->n_nodes_global, sizeof(double));
  if (!local) {
    free(count);
    return nomem(inst);
  }
  memcpy(local, count, sizeof(double) * (size_t)v->n_nodes_global);
  sk_status st = inst->api->reduce(inst->host, 1, count, (int)v->n_nodes_global);
  int64_t bad = -1;
  for (int f = 0; st == SK_OK && f < v->n_cells && bad < 0; ++f)
    if (inst->face_needed[f])
      for (int a = 0; a < v->nen; ++a) {
        const int k = v->conn[(int64_t)f * v->nen + a];
        if (local[v->node_index[k]] < count[v->node_index[k]]) bad = v->node_id[k];
      }
  free(count);
  free(local);
  SK_TRY(st);
  if (bad >= 0)
    return inst->api->error(inst->host, SK_ERR_INPUT,
                            "mortar-dual: the slave view of this rank lacks faces around node %lld, whose averaged "
                            "normal enters this rank's contact terms: the host must ghost two layers of slave faces",
                            (long long)bad);
  return SK_OK;
}

static double mean_edge(const sk_view *v) {
  double sum = 0.0;
  int count = 0;
  const int corners = v->cell_type == SK_QUAD4 || v->cell_type == SK_QUAD8 || v->cell_type == SK_QUAD9 ? 4
                      : v->cell_type == SK_TRI3 || v->cell_type == SK_TRI6 ? 3
                                                                           : 2;
  for (int f = 0; f < v->n_cells; ++f)
    for (int e = 0; e < (corners == 2 ? 1 : corners); ++e) {
      const int a = v->conn[(int64_t)f * v->nen + e], b = v->conn[(int64_t)f * v->nen + (e + 1) % corners];
      double d2 = 0.0;
      for (int i = 0; i < v->dim; ++i) {
        const double d = v->X[(int64_t)a * v->dim + i] - v->X[(int64_t)b * v->dim + i];
        d2 += d * d;
      }
      sum += sqrt(d2);
      ++count;
    }
  return count ? sum / count : 1.0;
}

/* c_n and c_t: the scene's values, or computed from it (docs/plugins/mortar-dual.md#defaults). A solution does not
 * depend on them, but the semismooth Newton does: with c_t s far below mu z_n the slip branch follows the sign of
 * the iterate z_t and the set cycles (slider-2d at dt 0.4: 5935 Newton iterations in 315 steps at c_n = 1, 336 in
 * 29 steps at c_n = 1000 = E). The rows are tractions (divided by the tributary measure A_j), so c_n is a modulus per
 * length: C_N_FACTOR E* / h with E* the pair's contact modulus and h the slave surface's mean edge; c_t = c_n. */
static const double C_N_FACTOR = 10.0;

static sk_status read_complementarity(sk_instance *inst) {
  const sk_scene_ext *scene = sk_defaults_scene(inst->api, inst->host);
  double computed = 0.0;
  char reason[700] = "";
  if (scene) computed = sk_defaults_stiffness(scene->info(inst->host), C_N_FACTOR, 0, reason, sizeof reason);
  SK_TRY(sk_defaults_param(inst->api, inst->host, scene, "c_n", computed, reason, &inst->ncp.c_n));
  /* frictionless: unused, so not reported */
  return sk_defaults_follow(inst->api, inst->host, scene, "c_t", inst->ncp.c_n, "c_n", inst->ncp.mu > 0.0,
                            &inst->ncp.c_t);
}

/* Slave faces whose multipliers are dual to the transformed functions (TRI6, QUAD8: section 3.5 of the plugin page). */
static int transformed_face(sk_elem_type type) { return sk_modified_basis_corners(type) > 0; }
static int quadratic_quad(sk_elem_type type) { return type == SK_QUAD8 || type == SK_QUAD9; }

static sk_status read_parameters(sk_instance *inst) {
  const sk_host_api *api = inst->api;
  sk_host *host = inst->host;
  static const char *const bases[] = {"dual", "standard", NULL};
  static const char *const integrations[] = {"segments", "concentrated", NULL};
  static const char *const normals[] = {"A", "M", NULL};
  static const char *const sets[] = {"semismooth", "nested", NULL};
  int basis, normal;
  SK_TRY(read_choice(inst, "basis", bases, &basis));
  inst->basis = basis == 0 ? MORTAR_DUAL : MORTAR_STANDARD;
  /* TRI6 and QUAD8 slave faces: the dual basis of the transformed functions (section 3.5 of the plugin page) */
  if (inst->basis == MORTAR_DUAL && transformed_face(inst->slave->cell_type)) inst->basis = MORTAR_DUAL_TRANSFORMED;
  SK_TRY(read_choice(inst, "integration", integrations, &inst->integration));
  SK_TRY(read_choice(inst, "normal", normals, &normal));
  inst->normal_variant = normal == 0 ? MORTAR_NORMAL_A : MORTAR_NORMAL_M;
  SK_TRY(read_choice(inst, "active_set", sets, &inst->active_set));
  SK_TRY(api->param_double(host, "mu", 0, 0.0, &inst->ncp.mu));
  SK_TRY(read_complementarity(inst));
  /* straight faces: Phi_j N_l of degree 2 (line2) or 4 (line3) on a segment; curved LINE3 faces are not polynomial */
  const int curved = inst->slave->cell_type == SK_LINE3 || (inst->master && inst->master->cell_type == SK_LINE3);
  SK_TRY(api->param_int(host, "segment_gauss", 0, curved ? 5 : 3, &inst->segment_gauss));
  /* flat faces make the integrands polynomials in the plane: Phi_j N_l of degree 2 (tri3/tri3) or 4 (quad4) */
  const int tri_only = inst->slave->cell_type == SK_TRI3 && (!inst->master || inst->master->cell_type == SK_TRI3);
  /* quad9: Phi_j (degree 4 in the plane of a flat quarter) times the gap of a second-order face (degree 2); quad8:
   * Phi_j times N_l, both of degree 3 */
  const int quad9 = quadratic_quad(inst->slave->cell_type) || (inst->master && quadratic_quad(inst->master->cell_type));
  SK_TRY(api->param_int(host, "cell_rule", 0, tri_only ? 3 : quad9 ? 12 : 6, &inst->cell_rule));
  SK_TRY(api->param_int(host, "face_gauss", 0, 5, &inst->face_gauss));
  SK_TRY(api->param_double(host, "frozen_band", 0, 0.1, &inst->frozen_band));
  SK_TRY(api->param_int(host, "max_flips", 0, 8, &inst->max_flips));
  SK_TRY(api->param_double(host, "min_cover", 0, 0.5, &inst->min_cover));
  const double edge = inst->master ? mean_edge(inst->master) : mean_edge(inst->slave);
  SK_TRY(api->param_double(host, "search_margin", 0, edge, &inst->search_margin));
  const double *dummy_xi, *dummy_w;
  if (inst->ncp.mu < 0.0 || !(inst->ncp.c_n > 0.0) || !(inst->ncp.c_t > 0.0) || inst->search_margin < 0.0 ||
      inst->segment_gauss < 1 || inst->segment_gauss > MORTAR_MAX_RULE || inst->face_gauss < 1 ||
      inst->face_gauss > MORTAR_MAX_RULE || mortar_triangle_rule(inst->cell_rule, &dummy_xi, &dummy_w) == 0 ||
      inst->max_flips < 1 || inst->min_cover < 0.0 || inst->min_cover > 1.0 || !(inst->frozen_band >= 0.0) ||
      !(inst->frozen_band <= 1.0))
    return api->error(host, SK_ERR_INPUT,
                      "mortar-dual: need mu >= 0, c_n > 0, c_t > 0, search_margin >= 0, 1 <= segment_gauss, face_gauss "
                      "<= %d, cell_rule in {1, 3, 6, 7, 12}, max_flips >= 1, 0 <= min_cover <= 1, 0 <= frozen_band "
                      "<= 1 (got mu %g, c_n %g, c_t %g, search_margin %g, segment_gauss %d, face_gauss %d, cell_rule "
                      "%d, max_flips %d, min_cover %g, frozen_band %g)",
                      MORTAR_MAX_RULE, inst->ncp.mu, inst->ncp.c_n, inst->ncp.c_t, inst->search_margin,
                      inst->segment_gauss, inst->face_gauss, inst->cell_rule, inst->max_flips, inst->min_cover,
                      inst->frozen_band);
  inst->friction = inst->ncp.mu > 0.0;
  /* c_n h is about the modulus (c_n ~ E / h): 1e-8 of it lies far below any pressure the run resolves and above the
   * round-off of z_n and c_n g at a converged point */
  inst->branch_tol = 1e-8 * inst->ncp.c_n * mean_edge(inst->slave);
  if (inst->strategy == STRATEGY_CONDENSED && inst->basis == MORTAR_DUAL_TRANSFORMED)
    return api->error(host, SK_ERR_INPUT, "mortar-dual: strategy 'condensed' eliminates z with a diagonal D, which TRI6 "
                      "and QUAD8 slave faces do not have (D = diag(int Phi_j) T^-T): use strategy: saddle-point");
  if (inst->strategy == STRATEGY_CONDENSED && inst->basis != MORTAR_DUAL)
    return api->error(host, SK_ERR_INPUT,
                      "mortar-dual: strategy 'condensed' eliminates z with a diagonal D: it needs basis: dual");
  if (inst->integration == INTEGRATION_SEGMENTS && inst->normal_variant == MORTAR_NORMAL_M)
    return api->error(host, SK_ERR_INPUT,
                      "mortar-dual: normal: M (the master normal) has no unique normal at master nodes to segment "
                      "with: use integration: concentrated, or normal: A");
  if (inst->obstacle && inst->normal_variant == MORTAR_NORMAL_M)
    return api->error(host, SK_ERR_INPUT,
                      "mortar-dual: a rigid obstacle measures the gap along its own normal; normal: M is for "
                      "deformable masters");
  return SK_OK;
}

/* The slave surface's tributary measures int N_j at positions x (dim per view node), complete at the nodes of needed
 * faces (check_stars makes sure): at X, A_j of [C1], [U1]; at x, the current ones of the output. */
static void tributary_measures(const sk_instance *inst, const double *x, double *measure) {
  const sk_view *v = inst->slave;
  memset(measure, 0, sizeof(double) * (size_t)v->n_nodes);
  for (int f = 0; f < v->n_cells; ++f) {
    double X[3 * MORTAR_MAX_NEN] = {0}, n[3 * MORTAR_MAX_NEN] = {0};
    for (int a = 0; a < v->nen; ++a)
      for (int i = 0; i < v->dim; ++i) X[3 * a + i] = x[(int64_t)v->conn[(int64_t)f * v->nen + a] * v->dim + i];
    mortar_pair p;
    mortar_basis_coeffs A;
    mortar_integrals I;
    mortar_pair_set(&p, inst->dim, &inst->st, NULL, X, NULL, n, 0);
    /* TRI6's and QUAD8's vertex functions integrate to 0 and a negative value: their measures are those of the
     * transformed functions, int N~_j = int Phi_j = sum_k D_jk of their dual basis (with either multiplier basis) */
    const mortar_basis b = transformed_face(v->cell_type) ? MORTAR_DUAL_TRANSFORMED : MORTAR_STANDARD;
    mortar_basis_coefficients(&p, b, &A);
    mortar_integrals_zero(&I, &p);
    mortar_slave_integrals(&p, &A, b, inst->n_d_points, inst->d_xi, inst->d_w, &I);
    for (int a = 0; a < v->nen; ++a)
      for (int k = 0; k < v->nen; ++k) measure[v->conn[(int64_t)f * v->nen + a]] += I.D[a][k].v;
  }
}

static void reference_measures(sk_instance *inst) {
  tributary_measures(inst, inst->slave->X, inst->A_node);
  for (int oi = 0; oi < inst->n_owned; ++oi) inst->owned[oi].A_ref = inst->A_node[inst->owned[oi].node];
}

/* ---- what the plugin cannot run (sk_plugin.check, ABI 2.7) ----------------------------------------------------- */

/* Contact is enforced at t_(n+1): a scheme balancing forces elsewhere (the midpoint rule) is refused. */
static int scheme_refused(const char *scheme, double alpha, char *reason, int size) {
  if (alpha == 1.0) return 0;
  snprintf(reason, (size_t)size, "the scheme '%s' balances forces at t_n + %g dt, and mortar-dual enforces contact at "
           "t_(n+1): it supports quasi-static and backward-euler", scheme, alpha);
  return 1;
}

/* Faces the kernel integrates: first-order ones, LINE3 in 2D and QUAD9 in 3D (their standard dual bases are
 * admissible: the shape functions integrate to the positive weights 1/6, 2/3, 1/6 and 1/36, 1/9, 4/9 of the face),
 * and TRI6 and QUAD8 with the dual basis of the transformed functions (Popp, Wohlmuth, Gee & Wall 2012; their vertex
 * functions integrate to 0 and -1/12 of the face). Every face type of the ABI. */
static int face_supported(sk_elem_type type) {
  return type == SK_LINE2 || type == SK_LINE3 || type == SK_TRI3 || type == SK_QUAD4 || type == SK_QUAD9 ||
         type == SK_TRI6 || type == SK_QUAD8;
}

static const char *face_name(sk_elem_type type) {
  switch (type) {
    case SK_TRI6: return "TRI6";
    case SK_QUAD8: return "QUAD8";
    case SK_QUAD9: return "QUAD9";
    default: return "second-order";
  }
}

static int faces_refused(const char *slave_name, sk_elem_type slave, const char *master_name, int has_master,
                         sk_elem_type master, char *reason, int size) {
  const int slave_ok = face_supported(slave);
  if (slave_ok && (!has_master || face_supported(master))) return 0;
  snprintf(reason, (size_t)size, "mortar-dual handles line2 and line3 faces in 2D, tri3, tri6, quad4, quad8 and quad9 "
           "in 3D; %s surface '%s' has %s faces", slave_ok ? "master" : "slave",
           slave_ok ? master_name : slave_name, face_name(slave_ok ? master : slave));
  return 1;
}

/* Self contact (section 3.6 of the plugin page): 2D and 3D first-order faces (and LINE3), one rank. */
static int self_refused(int self, int n_ranks, sk_elem_type type, char *reason, int size) {
  if (self && (type == SK_QUAD9 || type == SK_TRI6 || type == SK_QUAD8)) {
    snprintf(reason, (size_t)size, "mortar-dual's self contact runs on first-order faces in 3D (its face pairing is "
             "not tested on %s faces)", face_name(type));
    return 1;
  }
  if (!self || n_ranks <= 1) return 0;
  snprintf(reason, (size_t)size, "mortar-dual's self contact runs on one rank (the slave/master assignment colours "
           "the whole surface's face pairs on one rank; this run has %d)", n_ranks);
  return 1;
}

/* TRI6 and QUAD8 slave faces: D = diag(int Phi_j) T^-T is not diagonal in the slave unknowns, and strategy
 * 'condensed' eliminates z node by node with a diagonal D (section 3.5 of the plugin page). */
static int condensed_refused(int strategy, sk_elem_type slave, char *reason, int size) {
  if (strategy != STRATEGY_CONDENSED || !transformed_face(slave)) return 0;
  snprintf(reason, (size_t)size, "mortar-dual's strategy 'condensed' eliminates the multipliers with a diagonal D; on "
           "the slave surface's %s faces D = diag(int Phi_j) T^-T is not diagonal (the dual basis of the transformed "
           "functions): use strategy: saddle-point", face_name(slave));
  return 1;
}

static sk_status check(const sk_scene_info *scene, char *reason, int size) {
  const sk_scene_side *slave = scene->slave, *master = scene->master;
  if (scheme_refused(scene->scheme, scene->alpha, reason, size) ||
      self_refused(scene->self_contact, scene->n_ranks, slave->cell_type, reason, size) ||
      condensed_refused(scene->strategy, slave->cell_type, reason, size) ||
      faces_refused(slave->name, slave->cell_type, master->name, !master->rigid, master->cell_type, reason, size))
    return SK_ERR_PLUGIN;
  return SK_OK;
}

static sk_status create(const sk_host_api *api, sk_host *host, const sk_attach *attach, sk_instance **out) {
  *out = NULL;
  sk_instance *inst = calloc(1, sizeof *inst);
  if (!inst) return api->error(host, SK_ERR_NOMEM, "mortar-dual: out of memory");
  inst->api = api;
  inst->host = host;
  inst->attach = attach;
  inst->slave = attach->slave;
  inst->master = attach->master;
  inst->obstacle = attach->obstacle;
  inst->dim = attach->slave->dim;
  inst->strategy = attach->strategy;
  const sk_view *sv = inst->slave;
  sk_status st = SK_OK;
  char reason[300];
  if (faces_refused(sv->name, sv->cell_type, inst->master ? inst->master->name : "", inst->master != NULL,
                    inst->master ? inst->master->cell_type : SK_POINT1, reason, sizeof reason))
    st = api->error(host, SK_ERR_INPUT, "%s: %s", attach->name, reason);
  else if (mortar_face_type_init(&inst->st, sv->cell_type, api->contact->shape, api->contact->shape_hessian) != 0 ||
           (inst->master && mortar_face_type_init(&inst->mt, inst->master->cell_type, api->contact->shape,
                                                  api->contact->shape_hessian) != 0))
    st = api->error(host, SK_ERR_INTERNAL, "%s: mortar-dual: no face type for a supported face", attach->name);
  if (st == SK_OK) st = read_parameters(inst);
  /* the narrow copy of the evaluation (36 derivative slots, narrow.c) where both faces are first-order (or LINE3) */
  inst->narrow = sv->nen <= MORTAR_MAX_NEN_NARROW && (!inst->master || inst->master->nen <= MORTAR_MAX_NEN_NARROW) &&
                 (2 * sv->nen + (inst->master ? inst->master->nen : 0)) * inst->dim <= FWD_MAX_NARROW;
  inst->self = attach->self_contact;
  if (st == SK_OK && inst->self) st = mortar_self_create(inst);
  if (st == SK_OK && inst->strategy == STRATEGY_CONDENSED) {
    inst->condense = api->get_extension(host, SK_EXT_CONDENSE);
    if (!inst->condense)
      st = api->error(host, SK_ERR_PLUGIN,
                      "mortar-dual: strategy 'condensed' needs the host extension %s, which this stickslip lacks",
                      SK_EXT_CONDENSE);
  }
  if (st != SK_OK) {
    destroy(inst);
    return st;
  }
  /* rules: D and the dual coefficients (degree 2 per direction suffices on affine faces; 3 points per direction),
   * the whole face (concentrated points, obstacles), the 2D segments */
  inst->n_d_points = mortar_face_rule(sv->cell_type, mortar_face_exact_order(sv->cell_type), inst->d_xi, inst->d_w);
  inst->n_face_points = mortar_face_rule(sv->cell_type, inst->face_gauss, inst->face_xi, inst->face_w);
  mortar_gauss_legendre(inst->segment_gauss, inst->seg_eta, inst->seg_w);
  /* topology */
  const int nn = sv->n_nodes, nen = sv->nen, dim = inst->dim;
  st = build_stars(inst, sv, &inst->star_face_ptr, &inst->star_face, &inst->star_node_ptr, &inst->star_node);
  if (st == SK_OK && inst->master)
    st = build_stars(inst, inst->master, &inst->master_star_ptr, &inst->master_star, NULL, NULL);
  if (st != SK_OK) {
    destroy(inst);
    return st;
  }
  const int n_star = inst->star_node_ptr[nn];
  inst->face_star_index = alloc_zero((size_t)sv->n_cells * nen * nen, sizeof(int));
  inst->face_needed = alloc_zero((size_t)sv->n_cells, 1);
  inst->normal = alloc_zero(3 * (size_t)nn, sizeof(double));
  inst->A_node = alloc_zero((size_t)nn, sizeof(double));
  inst->A_current = alloc_zero((size_t)nn, sizeof(double));
  inst->cvec = alloc_zero(3 * (size_t)nn, sizeof(double));
  inst->dnormal = alloc_zero(9 * (size_t)n_star, sizeof(double));
  inst->dc = alloc_zero(9 * (size_t)n_star, sizeof(double));
  inst->owned_of_node = alloc_zero((size_t)nn, sizeof(int));
  inst->owned = alloc_zero((size_t)nn, sizeof(owned_node));
  inst->cand_ptr = alloc_zero((size_t)sv->n_cells + 1, sizeof(int));
  inst->cand_ptr_next = alloc_zero((size_t)sv->n_cells + 1, sizeof(int));
  inst->hit_ptr = alloc_zero((size_t)sv->n_cells + 1, sizeof(int));
  inst->ip_master = alloc_zero((size_t)sv->n_cells * inst->n_face_points, sizeof(int));
  inst->n_extra = (int64_t)dim * sv->n_nodes_global;
  inst->z_committed = alloc_zero((size_t)inst->n_extra, sizeof(double));
  inst->pair_extra = alloc_zero((size_t)nn * dim, sizeof(int64_t));
  inst->pair_row = alloc_zero((size_t)nn * dim, sizeof(int64_t));
  inst->anchor = alloc_zero((size_t)inst->n_extra, sizeof(int64_t));
  if (inst->master) {
    inst->master_border = alloc_zero((size_t)inst->master->n_nodes, 1);
    if (!inst->master_border) {
      destroy(inst);
      return nomem(inst);
    }
  }
  if (!inst->face_star_index || !inst->face_needed || !inst->normal || !inst->A_node || !inst->A_current ||
      !inst->cvec ||
      !inst->dnormal || !inst->dc ||
      !inst->owned_of_node || !inst->owned || !inst->cand_ptr || !inst->cand_ptr_next || !inst->hit_ptr || !inst->ip_master || !inst->z_committed ||
      !inst->pair_extra || !inst->pair_row || !inst->anchor) {
    st = nomem(inst);
    destroy(inst);
    return st;
  }
  for (int f = 0; f < sv->n_cells; ++f)
    for (int a = 0; a < nen; ++a) {
      const int j = sv->conn[(int64_t)f * nen + a];
      if (sv->owned[j] || sv->cell_owned[f]) inst->face_needed[f] = 1;
      for (int b = 0; b < nen; ++b) {
        const int k = sv->conn[(int64_t)f * nen + b];
        for (int s = inst->star_node_ptr[j]; s < inst->star_node_ptr[j + 1]; ++s)
          if (inst->star_node[s] == k) inst->face_star_index[(f * nen + a) * nen + b] = s;
      }
      inst->max_star = fwd_imax(inst->max_star, inst->star_node_ptr[j + 1] - inst->star_node_ptr[j]);
    }
  for (int64_t e = 0; e < inst->n_extra; ++e) inst->anchor[e] = -1;
  for (int k = 0; k < nn; ++k)
    for (int i = 0; i < dim; ++i) inst->anchor[(int64_t)dim * sv->node_index[k] + i] = sv->dofs[(int64_t)dim * k];
  for (int k = 0; k < nn; ++k) {
    inst->owned_of_node[k] = -1;
    if (!sv->owned[k]) continue;
    owned_node *o = &inst->owned[inst->n_owned];
    o->node = k;
    o->extra = (int64_t)dim * sv->node_index[k];
    inst->owned_of_node[k] = inst->n_owned++;
  }
  if (inst->master) { /* border nodes: a 2D end point without neighbour, a 3D edge without neighbour */
    const sk_view *mv = inst->master;
    for (int f = 0; f < mv->n_cells; ++f)
      for (int e = 0; e < mv->n_edges; ++e)
        if (mv->neighbors[(int64_t)f * mv->n_edges + e] < 0) {
          inst->master_border[mv->conn[(int64_t)f * mv->nen + e]] = 1;
          if (dim == 3) inst->master_border[mv->conn[(int64_t)f * mv->nen + (e + 1) % mv->n_edges]] = 1;
        }
  }
  reference_measures(inst);
  /* scratch for a pair's chain of columns */
  pair_chain *pc = &inst->chain;
  const int nen_m = inst->master ? inst->master->nen : 0;
  pc->dim = dim;
  pc->cap_nodes = nen + nen_m + nen * inst->max_star;
  pc->cap_entries = (nen + nen_m) * dim + nen * dim * inst->max_star * dim;
  pc->side = alloc_zero((size_t)pc->cap_nodes, sizeof(int));
  pc->node = alloc_zero((size_t)pc->cap_nodes, sizeof(int));
  pc->entry = alloc_zero((size_t)pc->cap_entries, sizeof(chain_entry));
  inst->block_cap = 2 * MORTAR_MAX_NEN * 3 * pc->cap_nodes * dim;
  inst->block = alloc_zero((size_t)inst->block_cap, sizeof(double));
  inst->block_cols = alloc_zero((size_t)pc->cap_nodes * dim, sizeof(int64_t));
  inst->pos_map = alloc_zero((size_t)pc->cap_nodes * dim, sizeof(int));
  if (!pc->side || !pc->node || !pc->entry || !inst->block || !inst->block_cols || !inst->pos_map) {
    st = nomem(inst);
    destroy(inst);
    return st;
  }
  st = check_stars(inst);
  if (st == SK_OK && inst->master) st = api->contact->search_create(inst->master, &inst->search);
  if (st != SK_OK) {
    destroy(inst);
    return st;
  }
  *out = inst;
  return SK_OK;
}

/* D^n (+) and M^n (-) of every owned node from the last EVAL_COMMIT, for the objective slip [S1]. */
static sk_status store_history(sk_instance *inst) {
  int need = 0;
  for (int k = 0; k < inst->n_col; ++k) need += inst->col_comp[k] == 0 && inst->commit_rows[k] != 0.0;
  if (need > inst->hist_cap) {
    const int cap = 2 * need + 64;
    int *hs = realloc(inst->hist_side, sizeof(int) * (size_t)cap);
    if (hs) inst->hist_side = hs;
    int *hn = realloc(inst->hist_node, sizeof(int) * (size_t)cap);
    if (hn) inst->hist_node = hn;
    double *hv = realloc(inst->hist_value, sizeof(double) * (size_t)cap);
    if (hv) inst->hist_value = hv;
    if (!hs || !hn || !hv) return nomem(inst);
    inst->hist_cap = cap;
  }
  inst->n_hist = 0;
  for (int oi = 0; oi < inst->n_owned; ++oi) {
    owned_node *o = &inst->owned[oi];
    o->hist = inst->n_hist;
    for (int k = o->cols; k < o->cols + o->n_cols; ++k)
      if (inst->col_comp[k] == 0 && inst->commit_rows[k] != 0.0) {
        inst->hist_side[inst->n_hist] = inst->col_side[k];
        inst->hist_node[inst->n_hist] = inst->col_node[k];
        inst->hist_value[inst->n_hist++] = inst->commit_rows[k];
      }
    o->n_hist = inst->n_hist - o->hist;
  }
  inst->history_ready = 1;
  return SK_OK;
}

/* mortar_evaluate with the copy for the pair's faces (mortar.h: the results are the same to the bit) */
static sk_status evaluate(sk_instance *inst, const sk_state *state, eval_mode mode, sk_sink *sink, int *changed) {
  return inst->narrow ? mortar_narrow_evaluate(inst, state, mode, sink, changed)
                      : mortar_evaluate(inst, state, mode, sink, changed);
}

/* D^n, M^n at the step's start x_n with the step's pairs, for the objective slip: the first step of any pair, and
 * every side assignment of a self pair (a node slave now may have been master or idle at the last commit, without
 * D^n of its own; a node that keeps its side and partners gets the committed values again, the same integrals at
 * the same x_n). The committed step's results (forces, slip, dissipation for report()) stay. */
static sk_status record_start_history(sk_instance *inst, const sk_state *state) {
  sk_state start = *state;
  start.x = state->x_n;
  start.extra = NULL;
  double force[3], moment[3];
  memcpy(force, inst->force, sizeof force);
  memcpy(moment, inst->moment, sizeof moment);
  inst->recording_start = 1;
  const sk_status st = evaluate(inst, &start, EVAL_COMMIT, NULL, NULL);
  inst->recording_start = 0;
  memcpy(inst->force, force, sizeof force);
  memcpy(inst->moment, moment, sizeof moment);
  SK_TRY(st);
  SK_TRY(store_history(inst));
  return mortar_build_columns(inst);
}

/* ---- the step ---------------------------------------------------------------------------------------------------- */
static sk_status begin_step(sk_instance *inst, const sk_state *state) {
  char reason[300];
  if (scheme_refused(state->scheme, state->alpha, reason, sizeof reason)) /* a host before ABI 2.7 skips check() */
    return inst->api->error(inst->host, SK_ERR_INPUT, "mortar-dual: %s", reason);
  /* the attempt starts from the committed set; tangent references from the normals at t_n */
  mortar_compute_normals(inst, state->x_n[0]);
  for (int oi = 0; oi < inst->n_owned; ++oi) {
    owned_node *o = &inst->owned[oi];
    o->state = o->c_state;
    memcpy(o->slip_dir, o->c_slip_dir, sizeof o->slip_dir);
    o->flips = 0;
    const double *n = inst->normal + 3 * o->node;
    int axis = 0;
    for (int i = 1; i < 3; ++i)
      if (fabs(n[i]) < fabs(n[axis])) axis = i;
    o->ref[0] = o->ref[1] = o->ref[2] = 0.0;
    o->ref[axis] = 1.0;
  }
  SK_TRY(mortar_step_candidates(inst, state));
  SK_TRY(mortar_build_columns(inst));
  /* the first step: the slip is measured from the start configuration, whose D and M it needs */
  if (inst->friction && (!inst->history_ready || inst->self)) SK_TRY(record_start_history(inst, state));
  return SK_OK;
}

static sk_status layout(sk_instance *inst, const sk_state *state, sk_layout *layout) {
  (void)state;
  layout->n_extra = inst->n_extra;
  layout->initial = inst->z_committed;
  layout->eliminated = NULL;
  layout->recover_needs_jdx = 0;
  if (SK_HAS(layout, extra_anchor)) layout->extra_anchor = inst->anchor;
  /* ABI 2.3: no slave face has a candidate this step, so every z row is the inactive C = z (ncp.c) */
  if (SK_HAS(layout, idle)) layout->idle = inst->master && inst->cand_ptr[inst->slave->n_cells] == 0;
  if (inst->strategy != STRATEGY_CONDENSED) return SK_OK;
  /* z_j paired with the slave rows of node j: their D block is D_jj I (dual basis) */
  const int dim = inst->dim;
  int n_pairs = 0;
  for (int oi = 0; oi < inst->n_owned; ++oi) {
    /* self contact: a node on a master-side face has other nodes' z in its rows; its z stays in the system */
    if (inst->self && inst->on_master[inst->owned[oi].node]) continue;
    for (int i = 0; i < dim; ++i) {
      inst->pair_extra[n_pairs * dim + i] = inst->owned[oi].extra + i;
      inst->pair_row[n_pairs * dim + i] = inst->slave->dofs[(int64_t)inst->owned[oi].node * dim + i];
    }
    ++n_pairs;
  }
  return inst->condense->pair(inst->host, n_pairs, dim, inst->pair_extra, inst->pair_row);
}

static sk_status pattern(sk_instance *inst, const sk_state *state, sk_pattern *pat) {
  const sk_view *sv = inst->slave;
  const int dim = inst->dim, nen = sv->nen, nen_m = inst->master ? inst->master->nen : 0;
  /* an owned face: its nodes' rows against their stars and z (the face part); each pair with a candidate: the
   * face's and the candidate's rows against the stars, the candidate's nodes and z */
  const size_t cap = (size_t)((nen + nen_m) * dim + nen * inst->max_star * dim + nen * dim);
  int64_t *rows = malloc(sizeof(int64_t) * cap), *cols = malloc(sizeof(int64_t) * cap);
  if (!rows || !cols) {
    free(rows);
    free(cols);
    return nomem(inst);
  }
  for (int f = 0; f < sv->n_cells; ++f) {
    if (!sv->cell_owned[f]) continue;
    int nr = 0, nc = 0;
    for (int a = 0; a < nen; ++a) {
      const int j = sv->conn[(int64_t)f * nen + a];
      for (int i = 0; i < dim; ++i) {
        rows[nr++] = sv->dofs[(int64_t)j * dim + i];
        cols[nc++] = state->extra_offset + dim * sv->node_index[j] + i;
      }
      for (int s = inst->star_node_ptr[j]; s < inst->star_node_ptr[j + 1]; ++s)
        for (int i = 0; i < dim; ++i) cols[nc++] = sv->dofs[(int64_t)inst->star_node[s] * dim + i];
    }
    pat->add_block(pat, nr, rows, nc, cols);
    const int nr_face = nr, nc_face = nc;
    for (int c = inst->cand_ptr[f]; c < inst->cand_ptr[f + 1]; ++c) {
      nr = nr_face;
      nc = nc_face;
      for (int b = 0; b < nen_m; ++b)
        for (int i = 0; i < dim; ++i) {
          const int32_t node = inst->master->conn[(int64_t)inst->cand[c] * nen_m + b];
          rows[nr++] = cols[nc++] = inst->master->dofs[(int64_t)node * dim + i];
        }
      pat->add_block(pat, nr, rows, nc, cols);
    }
  }
  free(rows);
  free(cols);
  /* an owned node's constraint rows against its columns and its z */
  for (int oi = 0; oi < inst->n_owned; ++oi) {
    const owned_node *o = &inst->owned[oi];
    int64_t zr[3];
    for (int i = 0; i < dim; ++i) zr[i] = state->extra_offset + o->extra + i;
    pat->add_block(pat, dim, zr, o->n_cols, inst->col + o->cols);
    pat->add_block(pat, dim, zr, dim, zr);
  }
  return SK_OK;
}

static sk_status update_active_set(sk_instance *inst, const sk_state *state, int *changed) {
  *changed = 0;
  if (inst->active_set == ACTIVE_SET_NESTED) return SK_OK; /* the set changes only at convergence */
  return evaluate(inst, state, EVAL_SET, NULL, changed);
}

static sk_status residual(sk_instance *inst, const sk_state *state, sk_sink *sink) {
  return evaluate(inst, state, EVAL_RESIDUAL, sink, NULL);
}

static sk_status jacobian(sk_instance *inst, const sk_state *state, sk_sink *sink) {
  return evaluate(inst, state, EVAL_JACOBIAN, sink, NULL);
}

/* Newton converged. First the candidates: the slave surface may have slid beyond them (mortar_extend_candidates).
 * Then the set decided at the converged point. The nested loop (Hammer, Algorithm 1) updates it here
 * and asks for Newton again when it changed; the semismooth loop changes nothing here unless a node's branch was
 * frozen by max_flips (it gets another Newton with a fresh count). */
static sk_status converged(sk_instance *inst, const sk_state *state, int *accept) {
  int added = 0, changed = 0;
  inst->cache_valid = 0; /* the candidates may change below */
  SK_TRY(mortar_extend_candidates(inst, state, &added));
  if (added > 0 && inst->self && inst->friction) SK_TRY(record_start_history(inst, state)); /* new sides */
  double pairs = added;
  SK_TRY(inst->api->reduce(inst->host, 0, &pairs, 1));
  if (pairs > 0.0) {
    /* new couplings on some rank: Newton again with them (the set is decided at the next converged point) */
    for (int oi = 0; oi < inst->n_owned; ++oi) inst->owned[oi].flips = 0;
    if (added > 0)
      inst->api->log(inst->host, 2, "mortar-dual: the slave surface slid onto %d master face(s) beyond its "
                     "candidates within the step: searching again and repeating Newton with them", added);
    *accept = 0;
    return SK_OK;
  }
  inst->deciding = 1;
  const sk_status st = evaluate(inst, state, EVAL_SET, NULL, &changed);
  inst->deciding = 0;
  SK_TRY(st);
  if (changed > 0) {
    for (int oi = 0; oi < inst->n_owned; ++oi) inst->owned[oi].flips = 0;
    inst->api->log(inst->host, 2, "mortar-dual: %d nodes changed their contact state at convergence: Newton again",
                   changed);
  }
  double c = changed;
  SK_TRY(inst->api->reduce(inst->host, 0, &c, 1));
  *accept = c == 0.0;
  return SK_OK;
}

static sk_status commit_step(sk_instance *inst, const sk_state *state) {
  SK_TRY(evaluate(inst, state, EVAL_COMMIT, NULL, NULL));
  if (inst->self) memcpy(inst->role_committed, inst->role, (size_t)inst->slave->n_cells);
  if (inst->master && inst->friction) SK_TRY(store_history(inst));
  for (int oi = 0; oi < inst->n_owned; ++oi) {
    owned_node *o = &inst->owned[oi];
    o->c_state = o->state;
    memcpy(o->c_slip_dir, o->slip_dir, sizeof o->slip_dir);
  }
  if (state->extra)
    for (int oi = 0; oi < inst->n_owned; ++oi)
      for (int i = 0; i < inst->dim; ++i)
        inst->z_committed[inst->owned[oi].extra + i] = state->extra[inst->owned[oi].extra + i];
  return SK_OK;
}

static void reject_step(sk_instance *inst) {
  inst->cache_valid = 0;
  for (int oi = 0; oi < inst->n_owned; ++oi) {
    owned_node *o = &inst->owned[oi];
    o->state = o->c_state;
    memcpy(o->slip_dir, o->c_slip_dir, sizeof o->slip_dir);
  }
}

/* ---- results ---------------------------------------------------------------------------------------------------- */
static sk_status report(sk_instance *inst, const sk_state *state, sk_contact_report *rep) {
  if (!state->extra) return SK_OK; /* the initial row: no contact yet */
  for (int i = 0; i < 3; ++i) {
    rep->force[i] = inst->force[i];
    rep->moment[i] = inst->moment[i];
  }
  for (int oi = 0; oi < inst->n_owned; ++oi) {
    const owned_node *o = &inst->owned[oi];
    if (o->state == MORTAR_INACTIVE) continue;
    ++rep->active;
    if (inst->friction) { /* frictionless nodes are neither stuck nor slipping */
      if (o->state == MORTAR_STICK) ++rep->stick;
      else ++rep->slip;
    }
    rep->dissipated += o->dissipation;
    rep->constraint_norm = fmax(rep->constraint_norm, fabs(o->gap) / o->A_ref);
  }
  return SK_OK;
}

/* Output: z_j is a traction per current measure (the force on the slave is -D_jj z_j, D over the current surface, as
 * report() sums it); pressure and traction are written per reference measure, z_j A_j(x) / A_j(X) (the nodal force
 * over the reference tributary measure A_j(X), the point's `area`): in the patch test that is p itself, where
 * z_j = p L_0 / L. */
static sk_status points(sk_instance *inst, const sk_state *state, sk_point_callback callback, void *ctx) {
  if (!state->extra) mortar_compute_normals(inst, state->x[0]);
  const int dim = inst->dim;
  tributary_measures(inst, state->x[0], inst->A_current);
  for (int oi = 0; oi < inst->n_owned; ++oi) {
    const owned_node *o = &inst->owned[oi];
    const double *n = inst->normal + 3 * o->node;
    const double nominal = inst->A_current[o->node] / o->A_ref;
    sk_contact_point pt = {.struct_size = sizeof pt};
    double zn = 0.0;
    for (int i = 0; i < dim; ++i) zn += n[i] * o->z[i];
    /* n is the slave's outward normal and -z the traction on the slave: sk_contact_point's normal (the master's,
     * towards the slave) and traction (on the slave) are their opposites */
    for (int i = 0; i < 3; ++i) {
      pt.x[i] = i < dim ? state->x[0][(int64_t)o->node * dim + i] : 0.0;
      pt.normal[i] = -n[i];
      pt.traction[i] = -(o->z[i] - zn * n[i]) * nominal;
    }
    pt.pressure = state->extra ? zn * nominal : 0.0;
    pt.area = o->A_ref;
    pt.has_slip = inst->friction;
    memcpy(pt.slip_increment, o->slip_increment, sizeof pt.slip_increment);
    pt.slip = o->slip_length;
    pt.has_multiplier = state->extra != NULL; /* z_n, the normal part of the node's dual multiplier */
    pt.multiplier = state->extra ? zn : 0.0;
    pt.gap = o->cover > 0.0 ? o->gap / o->A_ref : NAN; /* NaN: no master face (or obstacle) over the node */
    pt.state = o->state == MORTAR_INACTIVE ? 0 : (o->state == MORTAR_SLIP && inst->friction ? 2 : 1);
    pt.slave_node = inst->slave->node_id[o->node];
    callback(ctx, &pt);
  }
  return SK_OK;
}

/* ---- checkpoints (stickslip.checkpoint.v1): each owned node's committed state, multiplier and friction history ---- */

/* A node's record: its NCP branch, z_j, and the committed D^n / M^n coefficients of its slip (side, whole node index
 * on that side's surface, value). */
typedef struct {
  int32_t state, n_hist;
  double z[3];
  double slip_length; /* the slip accumulated (contact.csv's `slip`) */
} saved_node;
typedef struct {
  int32_t side, node;
  double value;
} saved_coefficient;

static sk_status save_state(sk_instance *inst, const sk_state *state, sk_record_writer *writer) {
  (void)state;
  size_t cap = 0;
  unsigned char *buffer = NULL;
  for (int oi = 0; oi < inst->n_owned; ++oi) {
    const owned_node *o = &inst->owned[oi];
    const int n_hist = inst->history_ready ? o->n_hist : 0;
    const size_t bytes = sizeof(saved_node) + sizeof(saved_coefficient) * (size_t)n_hist;
    if (bytes > cap) {
      unsigned char *grown = realloc(buffer, bytes);
      if (!grown) {
        free(buffer);
        return nomem(inst);
      }
      buffer = grown;
      cap = bytes;
    }
    saved_node head = {.state = o->c_state, .n_hist = n_hist, .slip_length = o->slip_length};
    for (int i = 0; i < inst->dim; ++i) head.z[i] = inst->z_committed[o->extra + i];
    memcpy(buffer, &head, sizeof head);
    for (int h = 0; h < n_hist; ++h) {
      const int side = inst->hist_side[o->hist + h];
      const sk_view *view = side == SIDE_SLAVE ? inst->slave : inst->master;
      const saved_coefficient c = {.side = side, .node = (int32_t)view->node_index[inst->hist_node[o->hist + h]],
                                   .value = inst->hist_value[o->hist + h]};
      memcpy(buffer + sizeof head + sizeof c * (size_t)h, &c, sizeof c);
    }
    writer->put(writer, inst->slave->node_index[o->node], buffer, (uint32_t)bytes);
  }
  free(buffer);
  return SK_OK;
}

static sk_status load_state(sk_instance *inst, const sk_state *state, const sk_record_reader *reader) {
  (void)state;
  inst->cache_valid = 0;
  int *slave_nodes = records_nodes_of_view(inst->slave);
  int *master_nodes = inst->master ? records_nodes_of_view(inst->master) : NULL;
  size_t cap = sizeof(saved_node) + 64 * sizeof(saved_coefficient);
  unsigned char *buffer = malloc(cap);
  sk_status status = slave_nodes && buffer && (!inst->master || master_nodes) ? SK_OK : nomem(inst);
  int total = 0;
  for (int oi = 0; oi < inst->n_owned && status == SK_OK; ++oi) {
    const owned_node *o = &inst->owned[oi];
    int64_t got = reader->get(reader, inst->slave->node_index[o->node], buffer, (uint32_t)cap);
    if (got > (int64_t)cap) {
      unsigned char *grown = realloc(buffer, (size_t)got);
      if (!grown) {
        status = nomem(inst);
        break;
      }
      buffer = grown;
      cap = (size_t)got;
      got = reader->get(reader, inst->slave->node_index[o->node], buffer, (uint32_t)cap);
    }
    saved_node head;
    if (got >= (int64_t)sizeof head) memcpy(&head, buffer, sizeof head);
    if (got < (int64_t)sizeof head || got != (int64_t)(sizeof head + sizeof(saved_coefficient) * (size_t)head.n_hist))
      status = inst->api->error(inst->host, SK_ERR_INPUT, "mortar-dual: slave node %lld: %s",
                                (long long)inst->slave->node_id[o->node],
                                got < 0 ? "no state in the checkpoint" : "a state record of another size");
    else
      total += head.n_hist;
  }
  /* the friction history's arrays, sized for all nodes' coefficients */
  if (status == SK_OK && total > inst->hist_cap) {
    int *hs = realloc(inst->hist_side, sizeof(int) * (size_t)total);
    if (hs) inst->hist_side = hs;
    int *hn = realloc(inst->hist_node, sizeof(int) * (size_t)total);
    if (hn) inst->hist_node = hn;
    double *hv = realloc(inst->hist_value, sizeof(double) * (size_t)total);
    if (hv) inst->hist_value = hv;
    if (!hs || !hn || !hv) status = nomem(inst);
    else inst->hist_cap = total;
  }
  memset(inst->z_committed, 0, sizeof(double) * (size_t)inst->n_extra);
  inst->n_hist = 0;
  for (int oi = 0; oi < inst->n_owned && status == SK_OK; ++oi) {
    owned_node *o = &inst->owned[oi];
    const int64_t got = reader->get(reader, inst->slave->node_index[o->node], buffer, (uint32_t)cap);
    saved_node head;
    memcpy(&head, buffer, sizeof head);
    (void)got;
    o->c_state = o->state = head.state;
    o->slip_length = head.slip_length;
    for (int i = 0; i < inst->dim; ++i) inst->z_committed[o->extra + i] = head.z[i];
    o->hist = inst->n_hist;
    for (int h = 0; h < head.n_hist && status == SK_OK; ++h) {
      saved_coefficient c;
      memcpy(&c, buffer + sizeof head + sizeof c * (size_t)h, sizeof c);
      const sk_view *view = c.side == SIDE_SLAVE ? inst->slave : inst->master;
      const int *nodes = c.side == SIDE_SLAVE ? slave_nodes : master_nodes;
      const int node = view && c.node >= 0 && c.node < view->n_nodes_global ? nodes[c.node] : -1;
      if (node < 0)
        status = inst->api->error(inst->host, SK_ERR_INPUT, "mortar-dual: slave node %lld: its slip history names a "
                                  "node this rank does not hold", (long long)inst->slave->node_id[o->node]);
      inst->hist_side[inst->n_hist] = c.side;
      inst->hist_node[inst->n_hist] = node;
      inst->hist_value[inst->n_hist++] = c.value;
    }
    o->n_hist = inst->n_hist - o->hist;
  }
  if (status == SK_OK && inst->master && inst->friction) inst->history_ready = 1;
  free(buffer);
  free(slave_nodes);
  free(master_nodes);
  return status;
}

static const sk_checkpoint_ext checkpoint = {SK_TABLE_HEADER(sk_checkpoint_ext), .save = save_state,
                                             .load = load_state};

static const void *extension(const char *id) { return id && strcmp(id, SK_EXT_CHECKPOINT) == 0 ? &checkpoint : NULL; }

static const sk_plugin plugin = {
    SK_TABLE_HEADER(sk_plugin),
    .name = "mortar-dual",
    .summary = "segment-to-segment mortar contact, standard or dual multipliers, semismooth Newton, condensation "
               "(Hammer 2012; Popp et al.)",
    .kinds = SK_KIND_PAIR,
    .caps = SK_CAP_2D | SK_CAP_3D | SK_CAP_FRICTION | SK_CAP_QUASISTATIC | SK_CAP_DYNAMICS | SK_CAP_RIGID_OBSTACLE |
            SK_CAP_DEFORMABLE_MASTER | SK_CAP_MULTIPLIERS | SK_CAP_CONDENSATION | SK_CAP_SAYS_IDLE |
            SK_CAP_SELF_CONTACT,
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
    .recover = NULL,
    .converged = converged,
    .commit_step = commit_step,
    .reject_step = reject_step,
    .report = report,
    .points = points,
    .integrator = NULL,
    .get_extension = extension,
    .check = check,
};

__attribute__((visibility("default"))) const sk_plugin *stickslip_plugin_entry(void);
__attribute__((visibility("default"))) const sk_plugin *stickslip_plugin_entry(void) { return &plugin; }
