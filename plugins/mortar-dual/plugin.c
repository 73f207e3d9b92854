/* mortar-dual — plugin glue: creation, the step's candidates, the active-set loops, history, output (the parameters,
 * the surface's topology and checkpoints have their files). The contact terms are assembled by assemble.c from the
 * kernel (kernel.h). Strategies:
 *   saddle-point  displacements and z (standard or dual basis): a direct solver
 *   condensed     dual basis; z eliminated by the host on the assembled operator (stickslip.condense.v1) */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "defaults.h"
#include "mortar.h"

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
    "segment_gauss: Gauss points per 2D integration segment [computed from the scene: 3; 5 with line3 faces]",
    "cell_rule: points per 3D integration triangle: 3, 6, 7 or 12 (degree 2, 4, 5, 6) [computed from the scene: 3 on "
    "tri3/tri3 pairs, exact there; 12 with quad9 faces; else 6, exact on parallelograms and flat tri6 faces]",
    "face_gauss: Gauss points per direction on a slave face (concentrated integration, obstacles) [5]",
    "frozen_band: concentrated integration: how far beyond its edge, in face parameters, a Gauss point keeps the "
    "master face chosen at the step's start (0.1: 5 % of an edge); 0 chooses again whenever it leaves the face, "
    "path-independent to round-off at the cost of more Newton runs [0.1]",
    "max_flips: active-set changes of a node within a step before its branch is frozen (semismooth) [8]",
    "transform_alpha: TRI6 and QUAD8 slave faces: alpha of the transformed functions the dual basis is built on, "
    "N~_vertex = N_vertex + alpha (N_edge1 + N_edge2), N~_edge = (1 - 2 alpha) N_edge [computed from the scene: "
    "0.1 on TRI6, 0.2 on QUAD8]",
    "min_cover: share of a node's support the master must cover for it to enter contact [0.5]",
    "search_margin: inflation of the search boxes (length) [computed from the scene: the mean master edge length; "
    "the slave's against an obstacle]",
    "self_exclusion: self contact only: faces with nodes within this distance of each other in the reference "
    "configuration never meet [computed from the scene: the surface's largest face (diagonal of its reference box)]",
    NULL};

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
  if (mortar_faces_refused(sv->name, sv->cell_type, inst->master ? inst->master->name : "", inst->master != NULL,
                    inst->master ? inst->master->cell_type : SK_POINT1, reason, sizeof reason))
    st = api->error(host, SK_ERR_INPUT, "%s: %s", attach->name, reason);
  else if (mortar_face_type_init(&inst->st, sv->cell_type, api->contact->shape, api->contact->shape_hessian) != 0 ||
           (inst->master && mortar_face_type_init(&inst->mt, inst->master->cell_type, api->contact->shape,
                                                  api->contact->shape_hessian) != 0))
    st = api->error(host, SK_ERR_INTERNAL, "%s: mortar-dual: no face type for a supported face", attach->name);
  if (st == SK_OK) st = mortar_read_parameters(inst);
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
  st = mortar_build_stars(inst, sv, &inst->star_face_ptr, &inst->star_face, &inst->star_node_ptr, &inst->star_node);
  if (st == SK_OK && inst->master)
    st = mortar_build_stars(inst, inst->master, &inst->master_star_ptr, &inst->master_star, NULL, NULL);
  if (st != SK_OK) {
    destroy(inst);
    return st;
  }
  const int n_star = inst->star_node_ptr[nn];
  inst->face_star_index = mortar_alloc_zero((size_t)sv->n_cells * nen * nen, sizeof(int));
  inst->face_needed = mortar_alloc_zero((size_t)sv->n_cells, 1);
  inst->normal = mortar_alloc_zero(3 * (size_t)nn, sizeof(double));
  inst->A_node = mortar_alloc_zero((size_t)nn, sizeof(double));
  inst->A_current = mortar_alloc_zero((size_t)nn, sizeof(double));
  inst->cvec = mortar_alloc_zero(3 * (size_t)nn, sizeof(double));
  inst->dnormal = mortar_alloc_zero(9 * (size_t)n_star, sizeof(double));
  inst->dc = mortar_alloc_zero(9 * (size_t)n_star, sizeof(double));
  inst->owned_of_node = mortar_alloc_zero((size_t)nn, sizeof(int));
  inst->owned = mortar_alloc_zero((size_t)nn, sizeof(owned_node));
  inst->cand_ptr = mortar_alloc_zero((size_t)sv->n_cells + 1, sizeof(int));
  inst->cand_ptr_next = mortar_alloc_zero((size_t)sv->n_cells + 1, sizeof(int));
  inst->hit_ptr = mortar_alloc_zero((size_t)sv->n_cells + 1, sizeof(int));
  inst->ip_master = mortar_alloc_zero((size_t)sv->n_cells * inst->n_face_points, sizeof(int));
  inst->n_extra = (int64_t)dim * sv->n_nodes_global;
  inst->z_committed = mortar_alloc_zero((size_t)inst->n_extra, sizeof(double));
  inst->pair_extra = mortar_alloc_zero((size_t)nn * dim, sizeof(int64_t));
  inst->pair_row = mortar_alloc_zero((size_t)nn * dim, sizeof(int64_t));
  inst->anchor = mortar_alloc_zero((size_t)inst->n_extra, sizeof(int64_t));
  if (inst->master) {
    inst->master_border = mortar_alloc_zero((size_t)inst->master->n_nodes, 1);
    if (!inst->master_border) {
      destroy(inst);
      return mortar_nomem(inst, "");
    }
  }
  if (!inst->face_star_index || !inst->face_needed || !inst->normal || !inst->A_node || !inst->A_current ||
      !inst->cvec ||
      !inst->dnormal || !inst->dc ||
      !inst->owned_of_node || !inst->owned || !inst->cand_ptr || !inst->cand_ptr_next || !inst->hit_ptr || !inst->ip_master || !inst->z_committed ||
      !inst->pair_extra || !inst->pair_row || !inst->anchor) {
    st = mortar_nomem(inst, "");
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
  mortar_reference_measures(inst);
  /* scratch for a pair's chain of columns */
  pair_chain *pc = &inst->chain;
  const int nen_m = inst->master ? inst->master->nen : 0;
  pc->dim = dim;
  pc->cap_nodes = nen + nen_m + nen * inst->max_star;
  pc->cap_entries = (nen + nen_m) * dim + nen * dim * inst->max_star * dim;
  pc->side = mortar_alloc_zero((size_t)pc->cap_nodes, sizeof(int));
  pc->node = mortar_alloc_zero((size_t)pc->cap_nodes, sizeof(int));
  pc->entry = mortar_alloc_zero((size_t)pc->cap_entries, sizeof(chain_entry));
  inst->block_cap = 2 * MORTAR_MAX_NEN * 3 * pc->cap_nodes * dim;
  inst->block = mortar_alloc_zero((size_t)inst->block_cap, sizeof(double));
  inst->block_cols = mortar_alloc_zero((size_t)pc->cap_nodes * dim, sizeof(int64_t));
  inst->pos_map = mortar_alloc_zero((size_t)pc->cap_nodes * dim, sizeof(int));
  if (!pc->side || !pc->node || !pc->entry || !inst->block || !inst->block_cols || !inst->pos_map) {
    st = mortar_nomem(inst, "");
    destroy(inst);
    return st;
  }
  st = mortar_check_stars(inst);
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
    if (!hs || !hn || !hv) return mortar_nomem(inst, "");
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
  if (mortar_scheme_refused(state->scheme, state->alpha, reason, sizeof reason)) /* a host before ABI 2.7 skips check() */
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
    return mortar_nomem(inst, "");
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
  mortar_tributary_measures(inst, state->x[0], inst->A_current);
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


static const void *extension(const char *id) {
  return id && strcmp(id, SK_EXT_CHECKPOINT) == 0 ? &mortar_checkpoint : NULL;
}

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
    .check = mortar_check,
};

__attribute__((visibility("default"))) const sk_plugin *stickslip_plugin_entry(void);
__attribute__((visibility("default"))) const sk_plugin *stickslip_plugin_entry(void) { return &plugin; }
