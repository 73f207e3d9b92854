/* mortar-dual — the glue's shared state (plugin.c: the ABI calls; parameters.c, surface.c, checkpoint.c: what they
 * read, build and save; assemble.c: the contact terms at a point x).
 * Views: attach->views = {slave, master} (or {slave} with an obstacle). Extra unknowns: z, dim per slave surface
 * node, at dim * node_index. Faces of the slave view are processed when owned (their forces) or when they touch an
 * owned node (that node's weighted gap and slip). */
#ifndef MORTAR_GLUE_H
#define MORTAR_GLUE_H

#include <stdlib.h>

#include "candidates.h"
#include "kernel.h"
#include "stickslip/modified_basis.h"
#include "stickslip/plugin.h"

enum { STRATEGY_SADDLE_POINT = 0, STRATEGY_CONDENSED = 1 };
enum { INTEGRATION_SEGMENTS = 0, INTEGRATION_CONCENTRATED = 1 };
enum { ACTIVE_SET_SEMISMOOTH = 0, ACTIVE_SET_NESTED = 1 };
enum { SIDE_SLAVE = 0, SIDE_MASTER = 1 };
enum { FACE_IDLE = 0, FACE_SLAVE = 1, FACE_MASTER = 2 };

/* One owned slave node: its constraint rows live on a column list fixed for the step attempt. */
typedef struct {
  int node;                 /* slave view node */
  int64_t extra;            /* index of z_j[0] among the instance's extras (dim * node_index) */
  double A_ref;             /* reference tributary measure int N_j over the slave surface ([C1], [U1]) */
  double ref[3];            /* tangent reference direction for the attempt (3D) */
  int state, c_state;       /* NCP branch (mortar_state) now / committed */
  int flips;                /* branch changes within the attempt (semismooth) */
  double slip_dir[3], c_slip_dir[3]; /* nested loop: the slip branch's direction (Cartesian unit vector, tangential)
                                        frozen for a Newton run, now / committed (mortar_ncp_eval_dir) */
  int cols, n_cols;         /* its columns: inst->col[cols .. cols + n_cols), sorted */
  int hist, n_hist;         /* committed D^n (+) and M^n (-) coefficients: inst->hist_* [hist .. hist + n_hist) */
  /* values at the last evaluation */
  double gap;               /* g~_j [I3] */
  double cover;             /* int_overlap N_j: the master's coverage of the node's support */
  double W[3];              /* deformable master: W_j [S1]; obstacle: the weighted jump D (x - x^n - dd) */
  double z[3];              /* z_j at the last evaluation (output) */
  double dissipation;       /* EVAL_COMMIT: z_t . u~_t, the friction work of the step */
  double slip_increment[3]; /* EVAL_COMMIT with friction: the weighted slip u~_t / A of the step, spatial */
  double slip_length;       /* the accumulated length of the slip increments */
} owned_node;

/* From a pair's local slots [x_s | x_m | n_s] to the global columns of the nodes involved. */
typedef struct {
  int pos;
  double coef;
} chain_entry;

typedef struct {
  int dim, n_nodes, cap_nodes;
  int *side, *node;
  int slot_ptr[FWD_MAX_WIDE + 1]; /* the same layout in both copies of the evaluation (fwd.h) */
  chain_entry *entry;
  int cap_entries;
} pair_chain;

struct sk_instance {
  const sk_host_api *api;
  sk_host *host;
  const sk_attach *attach;
  const sk_view *slave, *master;
  const sk_obstacle *obstacle;
  int dim;

  /* options (parameters) */
  int strategy, integration, active_set, friction;
  mortar_basis basis;
  mortar_normal normal_variant;
  mortar_ncp_params ncp;
  int segment_gauss, cell_rule, face_gauss, max_flips;
  double search_margin, min_cover;
  double frozen_band; /* concentrated integration: a Gauss point keeps its master face this far beyond its edge */
  double branch_tol;        /* a traction: 1e-8 c_n h (h the slave's mean edge), the round-off band of a branch at a
                               converged point (mortar_ncp_branch_holds) */

  mortar_face_type st, mt;
  sk_search *search;

  /* slave view topology (static): faces around each node, nodes of those faces ("stars") */
  int *star_face_ptr, *star_face;
  int *star_node_ptr, *star_node;
  int *face_star_index;     /* [(f * nen + a) * nen + b]: entry of conn[f][b] in the node star of conn[f][a] */
  unsigned char *face_needed; /* owned, or with an owned node */
  int max_star;

  /* nodal normals at the current evaluation (per slave view node) */
  double *A_node;           /* per slave view node: reference tributary measure A_j = int N_j (complete at the nodes
                               of needed faces: check_stars) */
  double *A_current;        /* the same over the current surface, for the output's nominal pressure (points) */
  double *normal;           /* 3 per node */
  double *dnormal;          /* 9 per star entry: d n_j / d x_b (3 x 3 row-major, dim x dim used) */
  double *cvec, *dc;

  /* owned slave nodes */
  int n_owned;
  owned_node *owned;
  int *owned_of_node;       /* slave view node -> owned index, -1 */

  /* rules: whole slave face (D, dual coefficients, concentrated and obstacle points), 2D segments, 3D cells */
  int n_face_points;
  double face_xi[MORTAR_MAX_RULE * MORTAR_MAX_RULE * 2], face_w[MORTAR_MAX_RULE * MORTAR_MAX_RULE];
  int n_d_points;
  double d_xi[MORTAR_MAX_RULE * MORTAR_MAX_RULE * 2], d_w[MORTAR_MAX_RULE * MORTAR_MAX_RULE];
  double seg_eta[MORTAR_MAX_RULE], seg_w[MORTAR_MAX_RULE];

  /* the attempt's candidates: master faces per slave view face (segments: all that may overlap; concentrated: the
   * frozen face of each Gauss point, Hammer 7.2.3, ip_master[f * n_face_points + q], -1 when dropped) */
  int *cand_ptr, *cand;
  int cand_cap;
  int *cand_ptr_next, *cand_next;     /* the extended candidates being built at convergence (search.c) */
  int cand_next_cap;
  int *ip_master;
  cand_list hits;                     /* master faces whose boxes meet each slave face's box swept over the step */
  int *hit_ptr;                       /* face f's hits: hits.faces[hit_ptr[f] .. hit_ptr[f + 1]) */
  int *master_star_ptr, *master_star; /* master faces around each master view node (concentrated selection) */
  unsigned char *master_border;       /* master node on the border of the master surface (out-of-first/-last) */

  /* owned nodes' columns and derivative accumulators */
  int64_t *col;
  int *col_side, *col_node, *col_comp; /* which node's which component each column is */
  int col_cap, n_col;
  double *acc_gap, *acc_W; /* n_col; 3 * n_col */

  /* history */
  double *z_committed;      /* n_extra: the last converged z of OWNED nodes, zero elsewhere (the host sums the
                               ranks' initial values) */
  int64_t n_extra;
  int *hist_side, *hist_node;
  double *hist_value;
  int hist_cap, n_hist;
  int history_ready;        /* D^n, M^n recorded (after the first commit, or at the first step's start) */
  double obstacle_d[3], obstacle_d_n[3];
  const sk_condense_ext *condense;
  int narrow; /* slave and master faces of at most MORTAR_MAX_NEN_NARROW nodes: mortar_narrow_evaluate (fwd.h) */

  /* self contact (self.c, docs/plugins/mortar-dual.md section 3.6): the surface's faces split into the step's slave
   * and master sides; the views are two copies of the one surface (same numbering) */
  int self;
  double self_exclusion;    /* faces with nodes this close in the reference configuration never meet */
  unsigned char *role, *role_committed; /* per face: FACE_IDLE, FACE_SLAVE, FACE_MASTER (now / last committed step) */
  unsigned char *role_preferred;        /* per face: scratch of mortar_self_assign */
  unsigned char *on_master; /* per node: lies on a master-side face (its row then holds other nodes' z) */
  int *edge, n_edge, edge_cap; /* face pairs (f < m) that reach each other: 2 per pair */
  int *adj_ptr, *adj, *queue;  /* the pairs as a graph over faces (CSR) and the colouring's queue */
  int adj_cap;
  int dropped;              /* pairs left out of the colouring (both faces on one side: an odd cycle) */

  /* results of the committed step (EVAL_COMMIT), for report() */
  double force[3], moment[3], dissipated;

  /* condensation pairs (owned nodes) */
  int64_t *pair_extra, *pair_row;
  int64_t *anchor; /* n_extra: a dof of each multiplier's slave node (sk_layout.extra_anchor), -1 if not viewed */

  /* scratch (sized in create): the pair chain, a block of rows x chain columns, column indices, a position map */
  pair_chain chain;
  double *block;
  int64_t *block_cols;
  int *pos_map;
  int block_cap;
  double *commit_rows;      /* EVAL_COMMIT: D_jk (+) and -M_jl on the owned nodes' columns (component 0) */
  int deciding;             /* EVAL_SET of the nested loop's outer update (converged): decide the branches */
  int recording_start;      /* EVAL_COMMIT at x_n for D^n, M^n only: the committed step's results stay */
  struct column_entry *tmp_entries;
  int tmp_cap;

  /* the values of the integrals at the last value-only pass (cache.c): entries f (face part: D), n_cells + f (the
   * obstacle's points), 2 n_cells + c (candidate c's pair); positions of both views and t they were computed at */
  double *cache_values, *cache_x, cache_t;
  int *cache_cells;
  int cache_cap, cache_valid, cache_use;
};

/* What an evaluation does: decide the active set, add F, add J, or record D^n, M^n for the committed step. */
typedef enum { EVAL_SET = 0, EVAL_RESIDUAL = 1, EVAL_JACOBIAN = 2, EVAL_COMMIT = 3 } eval_mode;

/* The contact terms at state->x (mortar.h header comment). EVAL_SET decides the NCP branches (semismooth, or
 * `decide` for the nested loop's outer update) and sets *changed. Returns SK_ERR_DIVERGED when a projection fails. */
sk_status mortar_evaluate(sk_instance *inst, const sk_state *state, eval_mode mode, sk_sink *sink, int *changed);
/* The same compiled with 36 derivative slots and faces of at most 4 nodes (narrow.c): the same arithmetic on smaller
 * structs, so the same results to the bit, for inst->narrow pairs. */
sk_status mortar_narrow_evaluate(sk_instance *inst, const sk_state *state, eval_mode mode, sk_sink *sink,
                                 int *changed);

/* Averaged nodal normals [N1] and their derivatives [N3] at every slave view node, at positions xs. */
void mortar_compute_normals(sk_instance *inst, const double *xs);

/* 1 when slave face f and master face m have a mortar segment at positions xs, xm (the nodal normals at xs must be
 * current) with a normal gap <= reach at one of its integration points at least. */
int mortar_pair_reaches(sk_instance *inst, int f, int m, const double *xs, const double *xm, double reach);

/* The step's candidates (begin_step), from the slave faces' boxes swept from x_n to the predictor (search.c). */
sk_status mortar_step_candidates(sk_instance *inst, const sk_state *state);

/* At a converged point: *added > 0 when the slave surface slid onto master faces that are not candidates (or, with
 * concentrated integration, a Gauss point left its frozen face): the candidates and columns are extended and the
 * point must be rejected (search.c). */
sk_status mortar_extend_candidates(sk_instance *inst, const sk_state *state, int *added);

/* Self contact: the step's face pairs (the hits of search_faces at xs, less the excluded pairs and those that do not
 * reach each other, united with the pairs found so far when `keep`), the faces' sides and the slave faces'
 * candidates (self.c). *added: the pairs new to the list. */
sk_status mortar_self_assign(sk_instance *inst, const double *xs, int keep, int *added);

/* An int array grown to hold `need` entries (search.c). */
sk_status mortar_grow(sk_instance *inst, int **array, int *cap, int need);

/* Self contact: checks what it needs (2D, frictionless, segments, the whole surface on this rank), reads
 * self_exclusion and allocates its arrays (self.c). */
sk_status mortar_self_create(sk_instance *inst);

/* Self contact: the search hits of every face over the step x_n -> xs (search.c). */
sk_status mortar_search_faces(sk_instance *inst, const sk_state *state, const double *xs, const double *xm);

/* The attempt's columns of every owned node's rows (after the candidates; begin_step; columns.c). */
sk_status mortar_build_columns(sk_instance *inst);

/* The integral cache (cache.c). mortar_cache_size: sized for the candidates and dropped (after every change of the
 * candidates, outside Newton). mortar_cache_begin: at the start of an evaluation; returns 1 when a value-only pass
 * may read the integrals at these positions (then mortar_cache_get), else a value-only pass records them
 * (mortar_cache_put, no-op otherwise). mortar_cache_end: the record counts only if the pass completed. */
enum { CACHE_OFF = 0, CACHE_READ = 1, CACHE_WRITE = 2 };
sk_status mortar_cache_size(sk_instance *inst);
int mortar_cache_begin(sk_instance *inst, const sk_state *state, int value_only);
void mortar_cache_end(sk_instance *inst, sk_status status);
void mortar_cache_put(sk_instance *inst, int entry, const mortar_integrals *I);
/* I zeroed for the pair (mortar_integrals_zero) on entry. */
void mortar_cache_get(const sk_instance *inst, int entry, mortar_integrals *I);

/* Out of memory, as every glue file reports it (`what`: the arrays being grown, or ""). */
static inline sk_status mortar_nomem(sk_instance *inst, const char *what) {
  return inst->api->error(inst->host, SK_ERR_NOMEM, "mortar-dual: out of memory%s%s%s", what[0] ? " (" : "", what,
                          what[0] ? ")" : "");
}

/* calloc that returns a pointer for zero entries too (a NULL then means out of memory). */
static inline void *mortar_alloc_zero(size_t n, size_t size) { return calloc(n > 0 ? n : 1, size); }

/* Slave faces whose multipliers are dual to the transformed functions (TRI6, QUAD8: section 3.5 of the plugin page). */
static inline int mortar_transformed_face(sk_elem_type type) { return sk_modified_basis_corners(type) > 0; }

/* The parameters of sk_plugin.parameters, read and checked into inst (parameters.c). */
sk_status mortar_read_parameters(sk_instance *inst);
/* sk_plugin.check: what the plugin cannot run (parameters.c); the scheme and face checks again at creation and at a
 * step, for hosts before ABI 2.7 (no check()): 1 and the reason when refused. */
sk_status mortar_check(const sk_scene_info *scene, char *reason, int size);
int mortar_scheme_refused(const char *scheme, double alpha, char *reason, int size);
int mortar_faces_refused(const char *slave_name, sk_elem_type slave, const char *master_name, int has_master,
                         sk_elem_type master, char *reason, int size);

/* Node -> faces and node -> nodes of those faces (CSR) of view v; node_ptr may be NULL (surface.c). */
sk_status mortar_build_stars(sk_instance *inst, const sk_view *v, int **face_ptr, int **faces, int **node_ptr,
                             int **nodes);
/* Every node of a needed slave face has all its faces in this rank's view (surface.c). */
sk_status mortar_check_stars(sk_instance *inst);
/* The slave surface's tributary measures int N_j at positions x (dim per view node) (surface.c). */
void mortar_tributary_measures(const sk_instance *inst, const double *x, double *measure);
/* A_j at the reference positions, into inst->A_node and the owned nodes' A_ref (surface.c). */
void mortar_reference_measures(sk_instance *inst);

/* The stickslip.checkpoint.v1 extension (checkpoint.c). */
extern const sk_checkpoint_ext mortar_checkpoint;

/* Global unknown index of component i of a node of the slave (side SIDE_SLAVE) or master view. */
static inline int64_t mortar_node_dof(const sk_instance *inst, int side, int node, int i) {
  const sk_view *v = side == SIDE_SLAVE ? inst->slave : inst->master;
  return v->dofs[(int64_t)node * v->dim + i];
}

/* Global unknown index of z_j component i for owned node o. */
static inline int64_t mortar_z_index(const sk_instance *inst, const sk_state *state, int64_t extra, int i) {
  (void)inst;
  return state->extra_offset + extra + i;
}

#endif
