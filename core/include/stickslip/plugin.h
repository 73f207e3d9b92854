/* stickslip — THE plugin ABI: how a contact formulation (a shared library) poses its part of a time step.
 *
 * A plugin library exports one symbol, SK_PLUGIN_ENTRY_SYMBOL, returning a const sk_plugin table. The driver
 * dlopen()s the library, checks abi_version == SK_PLUGIN_ABI_VERSION and the capabilities a scene needs, then
 * creates one instance per contact pair. Plugins link nothing but libc and libm: everything the core offers comes
 * through the sk_host table handed to create(). Optional, later abilities are found by string id through
 * get_extension (on either side), so this table stays small and stable while features grow (the CLAP model).
 *
 * Threading and lifetime: all calls come from one thread per MPI rank. Pointers in sk_host, sk_pair and sk_state
 * stay valid for the call (sk_host and sk_pair for the instance's lifetime). Every rank creates every instance and
 * calls every function (collective), but a plugin adds residual/Jacobian entries only for the contact entities its
 * rank owns (sk_host.owns_node on the slave node), so each entry is assembled exactly once over the ranks.
 *
 * The unknowns. The driver's vector of unknowns is [displacement dofs (n_nodes*dim, node-major) | the extra unknowns
 * of instance 0 | of instance 1 | ...]. A plugin declares its extra unknowns (multipliers, augmented coordinates,
 * angles, ...) in layout(), once per step: their number is fixed during the step, so NOX sees one vector space;
 * unknowns of inactive points carry trivial equations (e.g. lambda = 0). Sign convention: residual F(x) = 0,
 * Newton solves J dx = -F, x <- x + dx.
 *
 * Condensation. A plugin may offer strategies (names in `strategies`, the first is the default). Under a strategy
 * that eliminates some extra unknowns, layout() flags them; jacobian() then adds the condensed blocks among the
 * kept unknowns plus a right-hand-side correction (sink->add_rhs), the driver solves the smaller system, and
 * recover() fills the eliminated entries of dx. The linear solve changes, the nonlinear problem does not. */
#ifndef STICKSLIP_PLUGIN_H
#define STICKSLIP_PLUGIN_H

#include <stdint.h>

#include "stickslip/contact.h"
#include "stickslip/error.h"
#include "stickslip/mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SK_PLUGIN_ABI_VERSION 1u
#define SK_PLUGIN_ENTRY_SYMBOL "stickslip_plugin_entry"

/* ---- capabilities ----------------------------------------------------------------------------------------------- */
typedef enum {
  SK_CAP_2D = 1u << 0,
  SK_CAP_3D = 1u << 1,
  SK_CAP_FRICTION = 1u << 2,          /* Coulomb friction */
  SK_CAP_QUASISTATIC = 1u << 3,
  SK_CAP_DYNAMICS = 1u << 4,          /* backward Euler */
  SK_CAP_ENERGY_MOMENTUM = 1u << 5,   /* consistent with the midpoint (discrete-gradient) scheme */
  SK_CAP_RIGID_OBSTACLE = 1u << 6,    /* master may be a rigid analytical obstacle */
  SK_CAP_DEFORMABLE_MASTER = 1u << 7, /* master may be a deformable surface */
  SK_CAP_MULTIPLIERS = 1u << 8,       /* adds extra unknowns */
  SK_CAP_CONDENSATION = 1u << 9,      /* offers strategies that eliminate extra unknowns */
  SK_CAP_NEEDS_CURVATURE = 1u << 10,  /* uses h_ab / Christoffel symbols (quadratic faces recommended) */
  SK_CAP_NEEDS_MASS = 1u << 11,       /* reads the mass matrix through the host */
  SK_CAP_OWNS_KINEMATICS = 1u << 12,  /* replaces the bulk time discretisation of its bodies (co-rotational) */
  SK_CAP_SELF_CONTACT = 1u << 13
} sk_capability;

/* ---- what the core offers plugins ------------------------------------------------------------------------------- */
typedef struct sk_params sk_params;   /* a pair's plugin parameters (opaque; read through sk_host) */

typedef struct sk_contact_services {
  /* see contact.h for the meaning of each call */
  void (*geometry)(const sk_surface *surface, int face, const double *xi, const double *q, sk_surface_point *point);
  void (*nodal_normals)(const sk_surface *surface, const double *q, double *normals);
  sk_status (*project)(const sk_surface *surface, const double *q, const double *x, const int *candidates,
                       int n_candidates, sk_projection *projection);
  sk_status (*search_create)(const sk_surface *surface, sk_search **search);
  void (*search_destroy)(sk_search *search);
  void (*search_update)(sk_search *search, const double *q0, const double *q1, double margin);
  int (*search_query)(const sk_search *search, const double lo[3], const double hi[3], int *faces, int max_faces);
  sk_status (*obstacle_project)(const sk_obstacle *obstacle, double t, const double *x, int dim,
                                sk_surface_point *point, double *gap);
  void (*shape)(sk_elem_type type, const double *xi, double *N, double *dN);
  void (*shape_hessian)(sk_elem_type type, const double *xi, double *ddN);
  /* appended within ABI 1 (before its first release): */
  void (*obstacle_displacement)(const sk_obstacle *obstacle, double t, double d[3]);
  void (*search_rebuild)(sk_search *search);
} sk_contact_services;

/* The core's implementation of the table (for the host and for tests' mock hosts; plugins get it via sk_host). */
const sk_contact_services *sk_core_contact_services(void);

typedef struct sk_host {
  uint32_t abi_version;
  int dim;                       /* 2 or 3 */
  int n_nodes;
  int n_dofs;                    /* n_nodes * dim */
  const double *X;               /* reference positions, dim per node (dof layout) */
  const double *lumped_mass;     /* nodal mass (n_nodes), or NULL when the scene is quasi-static */
  int rank, n_ranks;
  const sk_contact_services *contact;
  void *core;                    /* the core's own state behind these calls */
  int (*owns_node)(const struct sk_host *host, int node);
  /* Typed plugin parameters of a pair. An absent key gives `dflt` unless `required`; errors name the scene file,
   * line and key. Keys a plugin never reads are reported to the user as unknown. */
  sk_status (*param_double)(const struct sk_host *host, const sk_params *params, const char *key, int required,
                            double dflt, double *out);
  sk_status (*param_int)(const struct sk_host *host, const sk_params *params, const char *key, int required,
                         int dflt, int *out);
  sk_status (*param_string)(const struct sk_host *host, const sk_params *params, const char *key, int required,
                            const char *dflt, const char **out);
  /* Records an error message (as sk_error_set) and returns `code`. */
  sk_status (*error)(const struct sk_host *host, sk_status code, const char *fmt, ...)
      __attribute__((format(printf, 3, 4)));
  /* Messages to the user on rank 0: level 0 = info, 1 = warning, 2 = debug (shown with --verbose). */
  void (*log)(const struct sk_host *host, int level, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
  /* Optional core abilities by id (e.g. "stickslip.bulk.v1" for formulations that own kinematics); NULL if absent. */
  const void *(*get_extension)(const struct sk_host *host, const char *id);
} sk_host;

/* One contact pair as the scene defines it. */
typedef struct {
  const char *name;               /* "pair 0" or the scene's name for it */
  const sk_surface *slave;        /* never NULL */
  const sk_surface *master;       /* deformable master, or NULL for an obstacle */
  const sk_obstacle *obstacle;    /* rigid master, or NULL */
  const sk_params *params;        /* plugin parameters from the scene */
  int strategy;                   /* index into sk_plugin.strategies */
} sk_pair;

/* ---- the state of a step, as plugins see it --------------------------------------------------------------------- */
typedef enum {
  SK_SCHEME_QUASISTATIC = 0,
  SK_SCHEME_BACKWARD_EULER,
  SK_SCHEME_MIDPOINT              /* energy-momentum: forces with gradients at t_{n+1/2}, constraints at t_{n+1} */
} sk_scheme;

typedef struct {
  sk_scheme scheme;
  double t_n, t, dt;              /* step from t_n to t = t_n + dt */
  int step;
  const double *q_n;              /* positions at t_n (n_dofs) */
  const double *q;                /* positions of the current iterate at t */
  const double *v_n;              /* velocities at t_n (NULL when quasi-static) */
  const double *extra;            /* this instance's extra unknowns, current iterate (layout n_extra entries) */
  int extra_offset;               /* global index of this instance's first extra unknown */
} sk_state;

/* Sinks through which a plugin adds to the global system (indices are global unknown indices). */
typedef struct sk_sink {
  void *ctx;
  void (*add_vector)(struct sk_sink *sink, int n, const int *rows, const double *values);
  /* Row-major nr x nc block. */
  void (*add_matrix)(struct sk_sink *sink, int nr, const int *rows, int nc, const int *cols, const double *values);
  /* Right-hand-side correction of a condensing strategy: the kept system is J_c dx = -F + rhs. */
  void (*add_rhs)(struct sk_sink *sink, int n, const int *rows, const double *values);
} sk_sink;

typedef struct {
  int n_extra;                    /* extra unknowns this step */
  const double *initial;          /* their initial values for the step (n_extra), e.g. last step's multipliers */
  const unsigned char *eliminated;/* 1 for unknowns the current strategy condenses out, or NULL */
} sk_layout;

typedef struct {
  double force[3];                /* resultant contact force on the slave side */
  double moment[3];               /* its moment about the origin */
  int active, stick, slip;        /* counts of contact points */
  double dissipated;              /* frictional dissipation of the step */
  double constraint_norm;         /* largest constraint violation among active points (e.g. |Phi|) */
} sk_contact_report;

typedef struct {
  double x[3];                    /* slave point position */
  double normal[3];
  double pressure;                /* normal contact pressure (>= 0 in compression) or nodal force when no area */
  double traction[3];             /* tangential traction (or force) */
  double gap;
  int state;                      /* 0 inactive, 1 stick, 2 slip */
  int slave_node;                 /* global node id, or -1 */
} sk_contact_point;

typedef void (*sk_point_callback)(void *ctx, const sk_contact_point *point);

/* ---- the plugin table ------------------------------------------------------------------------------------------- */
typedef struct sk_instance sk_instance; /* a plugin's per-pair state (opaque to the core) */

typedef struct sk_plugin {
  uint32_t abi_version;           /* SK_PLUGIN_ABI_VERSION */
  const char *name;               /* the name scenes use, e.g. "penalty-nts" */
  const char *summary;            /* one line */
  uint64_t caps;                  /* sk_capability bits */
  const char *const *strategies;  /* NULL-terminated; first = default ("none" if the plugin does not condense) */
  const char *const *parameters;  /* NULL-terminated "key: meaning [default]" lines, shown by `stickslip plugins` */

  sk_status (*create)(const sk_host *host, const sk_pair *pair, sk_instance **instance);
  void (*destroy)(sk_instance *instance);

  /* Start of a step (and of each retry after a step cut): search, candidate pairs, frozen data. */
  sk_status (*begin_step)(sk_instance *instance, const sk_state *state);
  /* The step's extra unknowns; pointers stay valid until the next begin_step. */
  sk_status (*layout)(sk_instance *instance, const sk_state *state, sk_layout *layout);
  /* Adds the contact part of F(x). */
  sk_status (*residual)(sk_instance *instance, const sk_state *state, sk_sink *sink);
  /* Adds the contact part of J (condensed under the strategy, with add_rhs corrections). */
  sk_status (*jacobian)(sk_instance *instance, const sk_state *state, sk_sink *sink);
  /* Fills dx for eliminated extra unknowns (this rank's entities) from the kept part of dx and F; NULL if the
   * plugin never eliminates. dx and F are global vectors. */
  sk_status (*recover)(sk_instance *instance, const sk_state *state, const double *F, double *dx);
  /* Active-set / stick-slip update at a new iterate: the driver calls it at every point where it is about to
   * evaluate the residual (each Newton iterate and line-search trial), so that F and the following J always belong
   * to one set (semismooth-Newton style). *changed = 1 if the set changed. May be NULL. */
  sk_status (*after_iteration)(sk_instance *instance, const sk_state *state, int *changed);
  /* Converged step accepted: commit history (friction, projections). */
  sk_status (*commit_step)(sk_instance *instance, const sk_state *state);
  /* Step rejected (it will be retried with a smaller dt): roll history back to the last commit. */
  void (*reject_step)(sk_instance *instance);
  /* Results of the step just committed, for history.csv: called right after commit_step with the state still
   * spanning the step (q_n, t_n at its start; q, t, extra at its end); never for the initial state (whose contact
   * columns are zero). This rank's entities — the driver sums over ranks. `dissipated` is the step's increment;
   * the driver accumulates it. */
  sk_status (*report)(sk_instance *instance, const sk_state *state, sk_contact_report *report);
  /* Calls `callback` for each contact point this rank owns (contact.csv, VTU). */
  sk_status (*points)(sk_instance *instance, const sk_state *state, sk_point_callback callback, void *ctx);
  /* Optional abilities by id; may be NULL. */
  const void *(*get_extension)(const char *id);
} sk_plugin;

typedef const sk_plugin *(*sk_plugin_entry_fn)(void);

#ifdef __cplusplus
}
#endif
#endif
