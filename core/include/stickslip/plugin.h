/* stickslip — THE plugin ABI, version 2: how a formulation (a shared library) poses its part of a time step.
 *
 * A plugin library exports one symbol, SK_PLUGIN_ENTRY_SYMBOL, returning a const sk_plugin table. The host
 * dlopen()s it, reads {abi_major, abi_minor, struct_size} (the first three members of every table), accepts any
 * plugin of its major version (a v1 plugin is refused with a message naming its version), checks the capabilities
 * the scene needs, and creates one INSTANCE per attachment: per contact pair (kind "pair") or per body (kind
 * "body") that names the plugin. Plugins link nothing but libc and libm (and static helpers of their own, such as
 * plugins/common): everything the core offers comes through the sk_host_api table handed to create(), always with
 * the instance's opaque sk_host handle, and optional abilities are found by string id through get_extension (CLAP).
 * The plain-data types are in plugin_types.h (append-only; the struct_size rules are written there).
 *
 * Threading and lifetime: all calls come from one thread per MPI rank. Every rank creates every instance and makes
 * every call (collective): a failing status on any rank fails the call everywhere. The api table, the sk_host
 * handle, the attach and its views live as long as the instance; sk_state, sk_vectors and sinks only for the call.
 *
 * Ownership and sums: a rank adds residual, Jacobian and report contributions only for the entities it owns
 * (sk_view: owned[] nodes, cell_owned[] cells); the host sums over ranks, so each term counts exactly once. A
 * global scalar row (a rotation, a Tisserand condition) may be added partially by every rank: the sum completes it.
 *
 * The unknowns: x = [displacement dofs | extra unknowns of instance 0 | instance 1 | ...]. Each instance declares
 * its extra unknowns (multipliers, augmented coordinates, rotation rates) in layout(), once per step attempt; their
 * number is fixed during the attempt so NOX sees one vector space, and inactive entities keep trivial equations
 * (lambda = 0). Sign convention: F(x) = 0 with F = internal - external forces; Newton solves J dx = -F, x += dx.
 * Rows and columns in sinks are global unknown indices: view->dofs[k*dim + i] and state->extra_offset + j.
 *
 * Order of calls in a step attempt (docs/plugin-abi.md §3 has the whole life cycle):
 *   begin_step → layout → pattern → Newton { at every new point x: update_active_set, then residual and/or jacobian
 *   there; after each linear solve: recover } → converged (may reject: Newton again) → commit_step → report, points.
 *   A failed attempt: reject_step, dt halved, begin_step again. */
#ifndef STICKSLIP_PLUGIN_H
#define STICKSLIP_PLUGIN_H

#include <stdint.h>

#include "stickslip/plugin_types.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SK_PLUGIN_ENTRY_SYMBOL "stickslip_plugin_entry"

/* The first members of every table of this header, in this order. Initialise them with SK_TABLE_HEADER(type). */
#define SK_TABLE_HEADER(type) .abi_major = SK_ABI_MAJOR, .abi_minor = SK_ABI_MINOR, .struct_size = sizeof(type)

typedef struct sk_host sk_host;         /* the core's handle for ONE instance (opaque; pass it to every api call) */
typedef struct sk_instance sk_instance; /* a plugin's per-attachment state (opaque to the core) */
typedef struct sk_search sk_search;     /* a broad-phase search tree over a surface view */

/* ---- sinks: how an instance adds to the global system ----------------------------------------------------------- */
/* Allocated by the host for one call; do not keep. A negative index means "no row" and is skipped; an index at or
 * beyond the number of unknowns is an error naming it (it ends the run); exact zeros of add_matrix are skipped. A matrix entry outside the pattern declared by pattern() (plus the bulk's element graph
 * and the diagonal) is an error naming the entry: declare every coupling first. */
typedef struct sk_sink {
  uint32_t abi_major, abi_minor, struct_size;
  /* F += values at rows */
  void (*add_vector)(struct sk_sink *sink, int n, const int64_t *rows, const double *values);
  /* J += a row-major nr x nc block */
  void (*add_matrix)(struct sk_sink *sink, int nr, const int64_t *rows, int nc, const int64_t *cols,
                     const double *values);
  /* plugin-local condensation: the kept system is J_c dx = -F + rhs (docs/plugin-abi.md §6) */
  void (*add_rhs)(struct sk_sink *sink, int n, const int64_t *rows, const double *values);
} sk_sink;

/* Declared couplings of one step attempt (pattern()). */
typedef struct sk_pattern {
  uint32_t abi_major, abi_minor, struct_size;
  /* every (rows[i], cols[j]) may receive Jacobian entries during this attempt */
  void (*add_block)(struct sk_pattern *pattern, int nr, const int64_t *rows, int nc, const int64_t *cols);
} sk_pattern;

typedef void (*sk_point_callback)(void *ctx, const sk_contact_point *point);

/* ---- contact services: geometry, projection, search, obstacles, quadrature ------------------------------------- */
/* Pure functions of the core over views. Positions `x` are in the view's numbering (dim per view node), as
 * sk_state.x[v] gives them; faces are view faces. docs/contact-services.md has the algorithms. */
typedef struct sk_contact_services {
  uint32_t abi_major, abi_minor, struct_size;
  /* Geometry of a face at parameters xi for positions x. */
  void (*geometry)(const sk_view *surface, int face, const double xi[2], const double *x, sk_surface_point *point);
  /* Averaged nodal normals (3 per view node; exact at nodes all of whose faces are in the view, e.g. owned nodes). */
  void (*nodal_normals)(const sk_view *surface, const double *x, double *normals);
  /* Closest point of `point` (dim entries) on the surface, trying the candidate faces (all when NULL); picks the
   * smallest distance, ties to the lowest face. SK_ERR_DIVERGED (result filled) when the local Newton failed. */
  sk_status (*project)(const sk_view *surface, const double *x, const double *point, const int *candidates,
                       int n_candidates, sk_projection *projection);
  /* Bounding-volume tree over the faces of a view. */
  sk_status (*search_create)(const sk_view *surface, sk_search **search);
  void (*search_destroy)(sk_search *search);
  /* Refits each face's box to enclose the face at x0 (start of step) and x1 (predictor), inflated by margin. */
  void (*search_update)(sk_search *search, const double *x0, const double *x1, double margin);
  /* Faces whose boxes overlap [lo, hi]: writes at most max_faces, returns how many overlap. */
  int (*search_query)(const sk_search *search, const double lo[3], const double hi[3], int *faces, int max_faces);
  /* Asks the next update for a new split of the tree (a surface that deformed a lot). */
  void (*search_rebuild)(sk_search *search);
  /* Closest point on a rigid obstacle at time t, and the gap (sk_surface_point says what is filled). */
  sk_status (*obstacle_project)(const sk_obstacle *obstacle, double t, const double *point, int dim,
                                sk_surface_point *closest, double *gap);
  /* The obstacle's prescribed translation at time t (piecewise linear in the scene's motion table). */
  void (*obstacle_displacement)(const sk_obstacle *obstacle, double t, double d[3]);
  /* Shape functions N[a] and parametric derivatives dN[a*pdim + k] of any element type; ddN[(a*pdim+k)*pdim+l]. */
  void (*shape)(sk_elem_type type, const double *xi, double *N, double *dN);
  void (*shape_hessian)(sk_elem_type type, const double *xi, double *ddN);
  /* Gauss rule on a face type exact for polynomials of degree `order` in the face parameters: writes up to
   * max_points points xi[q][0..pdim) and weights w[q] (summing to the reference face's measure), returns their
   * number, or -(the number needed) when max_points is too small, 0 for a type that is not a face. */
  int (*quadrature)(sk_elem_type face_type, int order, int max_points, double (*xi)[2], double *w);
} sk_contact_services;

/* ---- the host api ----------------------------------------------------------------------------------------------- */
typedef struct sk_host_api {
  uint32_t abi_major, abi_minor, struct_size;
  const sk_contact_services *contact;
  /* This rank and the number of ranks (for messages and partial global scalars; ownership is in the views). */
  void (*ranks)(const sk_host *host, int *rank, int *n_ranks);
  /* Typed parameters of this instance (`parameters:` of its pair or body). An absent key gives `dflt` unless
   * `required`; errors name the scene file, line and key. Reading a key marks it used: keys no plugin reads are
   * reported to the user as unknown. Strings live as long as the instance. */
  sk_status (*param_double)(sk_host *host, const char *key, int required, double dflt, double *out);
  sk_status (*param_int)(sk_host *host, const char *key, int required, int dflt, int *out);
  sk_status (*param_string)(sk_host *host, const char *key, int required, const char *dflt, const char **out);
  /* Records an error message and returns `code`; the host prefixes "contact pair 'NAME': " or "body 'NAME': ". */
  sk_status (*error)(sk_host *host, sk_status code, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
  /* Messages to the user on rank 0: level 0 = info, 1 = warning, 2 = debug (shown with --verbose). */
  void (*log)(sk_host *host, int level, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
  /* Sums (op 0) or maxima (op 1) of n values over ranks, in place (collective). */
  sk_status (*reduce)(sk_host *host, int op, double *values, int n);
  /* The instance of THIS plugin attached to body `body` (kind "body"), or NULL: lets a pair instance of a body
   * plugin reach the body's instance (e.g. the contact of a co-rotational body). */
  sk_instance *(*body_instance)(sk_host *host, int body);
  /* Optional core abilities by id ("stickslip.bulk.v1", "stickslip.condense.v1", "stickslip.linear.v1",
   * "stickslip.scene.v1"); NULL if absent. Ask in create() and fail there with a clear message if an extension you
   * need is missing. */
  const void *(*get_extension)(sk_host *host, const char *id);
} sk_host_api;

/* ---- extension "stickslip.bulk.v1": a body's operators, for body plugins ----------------------------------------- */
/* Vectors are over the instance's body view (dim per view node). apply_* and external_force return THIS RANK's
 * element contributions (partial at nodes shared with other ranks): add them through a sink as they are, or form
 * partial dot products, and the host's sum over ranks completes them. */
#define SK_EXT_BULK "stickslip.bulk.v1"
typedef struct sk_bulk_ext {
  uint32_t abi_major, abi_minor, struct_size;
  /* From create() of a body instance (needs SK_CAP_OWNS_KINEMATICS): the host then adds no bulk residual or
   * Jacobian (internal, inertial, body-force terms), no tractions, no predictor and no velocity update for this
   * body's dofs; the instance owns those rows and the body's time integration (sk_plugin.integrator), and gets the
   * body's loads from external_force. Dirichlet conditions and contact pairs still act on the rows. */
  sk_status (*claim)(sk_host *host);
  /* Total mass and centre of mass in the reference configuration. */
  sk_status (*mass_properties)(sk_host *host, double *mass, double center[3]);
  /* y = M u with the consistent mass matrix (M = M_scalar ⊗ I_dim). Needs SK_CAP_NEEDS_MASS. */
  sk_status (*apply_mass)(sk_host *host, const double *u, double *y);
  /* J += M_scalar ⊗ B for a dim x dim row-major block B (e.g. B = (2/dt) I + w Pi). Needs SK_CAP_NEEDS_MASS. */
  sk_status (*add_mass)(sk_host *host, const double *block, sk_sink *sink);
  /* y = S u and J += scale S, with S the linear (small-strain Hooke) stiffness of the body's material in the
   * reference configuration. */
  sk_status (*apply_stiffness)(sk_host *host, const double *u, double *y);
  sk_status (*add_stiffness)(sk_host *host, double scale, sk_sink *sink);
  /* External forces at time t: the scene's tractions on the body's faces and its body force. */
  sk_status (*external_force)(sk_host *host, double t, double *f);
  /* From commit_step: the body's displacement and velocity at t (owned nodes) for history.csv's energies and
   * momenta, the VTU files and the next step's v_n. Without it the host uses x - X and the integrator's velocity. */
  sk_status (*set_state)(sk_host *host, const double *u, const double *v);
} sk_bulk_ext;

/* ---- extension "stickslip.condense.v1": elimination of paired multipliers on the assembled operator ------------- */
/* Dual-mortar condensation (Popp et al.; 4C's run_pre_apply_jacobian_inverse, MOOSE's
 * VariableCondensationPreconditioner). An instance pairs blocks of `block` of its extra unknowns z_g with `block`
 * displacement rows s_g whose z-columns form an invertible block D_g (dual basis: D diagonal per node). After the
 * host has assembled and summed J (owned rows), it eliminates, for every pair g,
 *     dz_g = D_g^-1 (-F_s - J_s,u du)
 * from the paired rows: every other row r (bulk, master, Dirichlet, and the multipliers' own constraint rows)
 * becomes r - J_r,z D^-1 [J_s | F_s], and the constraint rows of z_g take the places of the rows s_g, so the solver
 * sees a displacement-only system. After the solve the host recovers dz from J_s,u du (recover() then sees the full
 * dx and, if asked, J dx). The nonlinear problem does not change. Requirements (checked, with a message): within the
 * rows s_g, the paired z appear only in their own block; a paired unknown is neither `eliminated` nor paired twice.
 * Results equal the saddle-point solve to round-off on any number of ranks. */
#define SK_EXT_CONDENSE "stickslip.condense.v1"
typedef struct sk_condense_ext {
  uint32_t abi_major, abi_minor, struct_size;
  /* From layout() of every attempt (the pairs hold for the attempt), for this rank's owned entities: n_groups
   * groups of `block` pairs (extra[j] <-> row): extra_index[g*block + b] (index into this instance's extras) pairs
   * with rows[g*block + b] (global displacement row). Needs SK_CAP_CONDENSATION. */
  sk_status (*pair)(sk_host *host, int64_t n_groups, int block, const int64_t *extra_index, const int64_t *rows);
} sk_condense_ext;

/* ---- extension "stickslip.linear.v1": more solves with the current operator -------------------------------------- */
#define SK_EXT_LINEAR "stickslip.linear.v1"
typedef struct sk_linear_ext {
  uint32_t abi_major, abi_minor, struct_size;
  /* From recover() only: solves J y = b with the operator of the solve just made, reusing its factorisation (or
   * preconditioner) and its condensation. b and y in the instance's layout (sk_vectors): b_view[v] (dim per node)
   * and b_extra; entries of owned nodes/entities are summed over ranks, put zeros elsewhere; y is filled at owned
   * and ghosted nodes and all extras. Collective. For a bordered system (a scalar unknown eliminated by the
   * plugin: the outer Newton on a rotation rate) this is the second solve with the same matrix. */
  sk_status (*solve_again)(sk_host *host, const double *const *b_view, const double *b_extra, double *const *y_view,
                           double *y_extra);
} sk_linear_ext;

/* ---- extension "stickslip.scene.v1" (ABI 2.7): the scene around an instance, and defaults computed from it ------ */
/* A parameter whose good value depends on the scene (a penalty ~ E/h, a complementarity constant) gets its default
 * from the scene: the plugin reads the key with param_*(..., required 0, dflt NAN, ...), and when it is absent
 * computes the value from info() by the rule its page states, then tells the host with computed(), which
 * `stickslip check|run --explain` prints as `contact[0].parameters.penalty = 2.3e+06 (computed: REASON)`. A value
 * the scene gives always wins. Ask in create(); a host without the extension returns NULL (then fail there, naming
 * the key the user has to give). */
#define SK_EXT_SCENE "stickslip.scene.v1"
typedef struct sk_scene_ext {
  uint32_t abi_major, abi_minor, struct_size;
  /* The instance's attachment as the scene describes it: materials, obstacle, face types and orders, sizes of the
   * whole surfaces. The same on every rank; valid for the instance's lifetime. */
  const sk_scene_info *(*info)(sk_host *host);
  /* Records the default computed for parameter `key` and why: the rule and its numbers, e.g. "10 E* / h; E* = 1.1e+03
   * (slave body 'block' E 1e+03 nu 0.3, rigid obstacle), h = 0.25 mean edge of slave surface 'zmin'". */
  void (*computed)(sk_host *host, const char *key, double value, const char *fmt, ...)
      __attribute__((format(printf, 4, 5)));
} sk_scene_ext;

/* ---- plugin-side extension "stickslip.checkpoint.v1": the instances' history in a checkpoint (ABI 2.8) --------- */
/* A plugin whose instances keep history from step to step (active sets, stick anchors, committed multipliers and
 * projections, a body's rotation and co-rotated velocities) returns this table from sk_plugin.get_extension, so that
 * `stickslip run --checkpoint-every N` writes the history and `stickslip run --restart DIR` gives it back, on the same
 * or another number of ranks (docs/plugin-abi.md §5.1). The history is a set of records, each under a key the plugin
 * chooses from its entity's whole index (a view's node_index or cell_index; -1 and below for the instance's own
 * scalars), so that a restart on other ranks can hand each rank the records of the entities it holds. A plugin that
 * keeps no history returns the table with both functions NULL; one without the table cannot be checkpointed (the
 * host refuses `--checkpoint-every` for it, naming it). */
#define SK_EXT_CHECKPOINT "stickslip.checkpoint.v1"
typedef struct sk_record_writer {
  uint32_t abi_major, abi_minor, struct_size;
  /* One record of `bytes` bytes (copied). Each key once per instance over all ranks: the entity's owner writes it. */
  void (*put)(struct sk_record_writer *writer, int64_t key, const void *data, uint32_t bytes);
} sk_record_writer;
typedef struct sk_record_reader {
  uint32_t abi_major, abi_minor, struct_size;
  /* Copies record `key` into data (at most `capacity` bytes) and returns its size, or -1 when there is none. Every
   * record the instance's ranks wrote can be read on every rank. */
  int64_t (*get)(const struct sk_record_reader *reader, int64_t key, void *data, uint32_t capacity);
} sk_record_reader;
typedef struct sk_checkpoint_ext {
  uint32_t abi_major, abi_minor, struct_size;
  /* After a committed step, with the state of report(): the history of the entities this rank owns. NULL: none. */
  sk_status (*save)(sk_instance *instance, const sk_state *state, sk_record_writer *writer);
  /* Once, after create and before the first begin_step of a restarted run, with the state of the step the
   * checkpoint was written at (x = x_n, the positions then; t = t_n; extra = NULL): the history of the entities this
   * rank holds, from the records. Collective with the instance's other ranks. NULL: none. */
  sk_status (*load)(sk_instance *instance, const sk_state *state, const sk_record_reader *reader);
} sk_checkpoint_ext;

/* ---- a body's time integrator, supplied by a body plugin -------------------------------------------------------- */
/* The core integrates its bodies with the scene's scheme (quasi-static, backward Euler, energy-momentum midpoint:
 * core/time/integrator.c). A body plugin that claims its body supplies its own here (needs
 * SK_CAP_OWNS_KINEMATICS); other terms then see its name and alpha in sk_state when they act on that body. */
typedef struct sk_integrator {
  uint32_t abi_major, abi_minor, struct_size;
  const char *name;            /* e.g. "corotational-midpoint": summary.json, messages */
  double alpha;                /* other terms' forces on the body balance at t_n + alpha dt */
  int dynamic;                 /* 1 when the body has inertia */
  /* Start of an attempt: the predictor DISPLACEMENTS u of the body view's nodes at t (from state->x_n, v_n, dt),
   * from which the host starts Newton and the search sweeps its boxes. */
  sk_status (*predict)(sk_instance *instance, const sk_state *state, double *u);
  /* Converged step: the body's velocities at t (view numbering), for output and the next v_n (set_state of
   * stickslip.bulk overrides them). */
  sk_status (*velocity)(sk_instance *instance, const sk_state *state, double *v);
  /* ABI 2.5 (the host reads it only when SK_HAS(integrator, energy); NULL: none): the kinetic and strain energy that
   * the integrator's scheme conserves, or balances against its contact work, for the body at the state's time (the
   * last committed step; for the initial output, state->step == 0, the initial state), this rank's part (the host
   * sums over ranks). history.csv's kinetic_energy, strain_energy and total_energy carry these for the body instead
   * of the host's (from the world state and the body's material, which stay in material_total_energy): a scheme whose
   * energy is not the material's (a co-rotational linear energy) reports the one it conserves. */
  sk_status (*energy)(sk_instance *instance, const sk_state *state, double *kinetic, double *strain);
} sk_integrator;

/* ---- the plugin table ------------------------------------------------------------------------------------------- */
typedef struct sk_plugin {
  uint32_t abi_major, abi_minor, struct_size; /* SK_TABLE_HEADER(sk_plugin) */
  const char *name;               /* the name scenes use, e.g. "penalty-nts" */
  const char *summary;            /* one line, shown by `stickslip plugins` */
  uint32_t kinds;                 /* sk_kind bits: what instances attach to */
  uint64_t caps;                  /* sk_capability bits (each checked as plugin_types.h says) */
  const char *const *strategies;  /* NULL-terminated; the first is the default ("none" if nothing is condensed) */
  const char *const *parameters;  /* NULL-terminated "key: meaning [default]" lines, shown by `stickslip plugins` */

  /* Once, at scene load, before the unknown-key check: read and check every parameter, allocate everything sized
   * by the views, ask for extensions. `api`, `host` and `attach` stay valid until destroy. */
  sk_status (*create)(const sk_host_api *api, sk_host *host, const sk_attach *attach, sk_instance **instance);
  void (*destroy)(sk_instance *instance);

  /* Start of every step attempt (also after a cut): state->x is the predictor, x_n the last converged step.
   * Broad phase, candidate pairs, data frozen for the step, starting values of the extra unknowns. */
  sk_status (*begin_step)(sk_instance *instance, const sk_state *state);
  /* The attempt's extra unknowns (fixed during the attempt). Pointers stay valid until the next begin_step. */
  sk_status (*layout)(sk_instance *instance, const sk_state *state, sk_layout *layout);
  /* Every coupling jacobian() may add during the attempt (beyond the bulk element graph and the diagonal), for
   * owned entities: e.g. a slave node with every node of its candidate master faces. NULL: none. */
  sk_status (*pattern)(sk_instance *instance, const sk_state *state, sk_pattern *pattern);
  /* The active set and stick/slip states at a NEW point x: called once at every point where the host is about to
   * evaluate the residual or the Jacobian (Newton iterates and line-search trials), before them, so that F and J
   * at one point always belong to one set (semismooth Newton). *changed = 1 if the set changed. NULL: no set. */
  sk_status (*update_active_set)(sk_instance *instance, const sk_state *state, int *changed);
  /* Adds this instance's part of F(x); must not change the state J depends on (that is update_active_set's). */
  sk_status (*residual)(sk_instance *instance, const sk_state *state, sk_sink *sink);
  /* Adds dF/dx at the same point and set (under plugin-local condensation: the condensed blocks and add_rhs). */
  sk_status (*jacobian)(sk_instance *instance, const sk_state *state, sk_sink *sink);
  /* After every linear solve: fills dx of eliminated extras of owned entities (plugin-local condensation), and may
   * use stickslip.linear's solve_again. NULL when the plugin eliminates nothing. */
  sk_status (*recover)(sk_instance *instance, const sk_state *state, sk_vectors *vectors);
  /* Newton converged at state->x. Set *accept = 0 to reject the converged point once the plugin has changed its
   * active set (an outer active-set loop, Hammer's nested Newton, PDASS): the host runs Newton again from x within
   * the same attempt (at most solver.newton.max_active_set_loops times, then the step is cut). NULL: accept. */
  sk_status (*converged)(sk_instance *instance, const sk_state *state, int *accept);
  /* The attempt is accepted: commit history (friction, projections, multipliers for the next `initial`). */
  sk_status (*commit_step)(sk_instance *instance, const sk_state *state);
  /* The attempt failed and will be retried with a smaller dt: roll back to the last commit. */
  void (*reject_step)(sk_instance *instance);
  /* Results for history.csv, right after commit_step with the state spanning the step (x_n, t_n at its start; x,
   * t, extra at its end); never for the initial row (its contact columns are zero). This rank's entities;
   * `dissipated` is the step's increment. */
  sk_status (*report)(sk_instance *instance, const sk_state *state, sk_contact_report *report);
  /* Each owned contact point (contact.csv, VTU), with the state of report(); for the initial output with step = 0,
   * t_n = t, x_n = x and extra = NULL; at the end of a run possibly with x_n == x: compute nothing from x - x_n
   * here. NULL: no points. */
  sk_status (*points)(sk_instance *instance, const sk_state *state, sk_point_callback callback, void *ctx);
  /* Body plugins that integrate their body themselves (SK_CAP_OWNS_KINEMATICS), else NULL. */
  const sk_integrator *integrator;
  /* Optional plugin-side interfaces by id; may be NULL. */
  const void *(*get_extension)(const char *id);
  /* ABI 2.7, may be NULL: can the plugin run the attachment `scene` describes? Called before any instance exists, by
   * `stickslip check` and `run` for the plugin a pair or body names, and for every plugin on the search path when
   * the host looks for the ones that can (the error lists them). SK_OK, or SK_ERR_PLUGIN with one sentence in
   * `reason` (e.g. "the midpoint scheme balances forces at t_n + dt/2, and mortar-dual enforces contact at
   * t_(n+1)"). A pure function of `scene`: the capability bits are checked before it, and parameter values are
   * create()'s to check. Everything a plugin cannot run that the scene alone decides (scheme, dimension, obstacle
   * shape or motion, face types and orders, strategy, ranks) belongs here, not in begin_step. */
  sk_status (*check)(const sk_scene_info *scene, char *reason, int reason_size);
} sk_plugin;

typedef const sk_plugin *(*sk_plugin_entry_fn)(void);

#ifdef __cplusplus
}
#endif
#endif
