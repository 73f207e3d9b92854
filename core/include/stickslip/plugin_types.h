/* stickslip — the plain-data types of the plugin ABI (version 2). APPEND-ONLY.
 *
 * Every type a plugin and the host exchange lives in this one header, and nothing else of the core is part of the
 * ABI (plugin.h holds the function tables). The rules that keep it binary compatible across minor versions:
 *
 * - Append only. A new member goes at the end of its struct; a new enumerator at the end of its enum. Nothing is
 *   removed, reordered, resized or given a new meaning within a major version (that is a major version).
 * - struct_size. Every struct that crosses the boundary starts with `uint32_t struct_size`, set to sizeof(its type)
 *   by whoever ALLOCATES it (the host for sk_state, sk_attach, sk_view, sk_vectors, sk_layout, sk_contact_report;
 *   the plugin for sk_surface_point, sk_projection, sk_contact_point). The other side touches only members that lie
 *   within struct_size: test with SK_HAS(ptr, member) before using a member added in a later minor version. An
 *   older plugin on a newer host, and a newer plugin on an older host, both stay within the memory they share.
 * - Sizes that can grow are int64_t: global node, face and unknown indices, counts of unknowns. Per-entity sizes
 *   (nodes per face, local block sizes) are int.
 *
 * Only plain data and the two macros below: no functions, no core struct layouts (the mesh, the core's surfaces,
 * obstacles and search trees stay behind opaque handles). */
#ifndef STICKSLIP_PLUGIN_TYPES_H
#define STICKSLIP_PLUGIN_TYPES_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ---- versions ------------------------------------------------------------------------------------------------- */
/* The ABI a plugin is built against. The host accepts any plugin of the same major version and any minor (CLAP's
 * clap_version_is_compatible, Lua's luaL_checkversion): members a side does not know are found by struct_size. */
#define SK_ABI_MAJOR 2u
#define SK_ABI_MINOR 9u /* 1: the element types TRI6, QUAD8, TET10, HEX20; sk_contact_point X, has_multiplier, multiplier
                          2: sk_layout.idle and SK_CAP_SAYS_IDLE (a pair with no candidate skips its calls)
                          3: sk_layout.idle also with extra unknowns (their trivial rows written by the host)
                          4: sk_layout.extra_anchor (the mesh node of each extra unknown, for the pattern margin)
                          5: sk_integrator.energy (the energy a body plugin's scheme conserves, for history.csv)
                          6: sk_contact_point forces, area, has_slip, slip_increment, slip, slave_face (one meaning
                             of pressure for every plugin, slip over time)
                          7: sk_scene_info / sk_scene_side, sk_plugin.check and the extension stickslip.scene.v1 (what
                             an attachment is, for refusals at `check` and defaults computed from the scene)
                          8: the plugin-side extension stickslip.checkpoint.v1 (history in checkpoints)
                          9: no new member: stickslip.checkpoint.v1's load also follows a re-creation of a pair's
                             instance during a run, when its master faces are ghosted again (docs/plugin-abi.md) */

/* 1 when `member` lies within the struct_size the struct was allocated with (and may be read or written). */
#define SK_HAS(ptr, member) \
  ((ptr) != NULL && offsetof(__typeof__(*(ptr)), member) + sizeof((ptr)->member) <= (size_t)(ptr)->struct_size)

/* ---- status codes (the core's error.h takes them from here) ---------------------------------------------------- */
typedef enum {
  SK_OK = 0,
  SK_ERR_INPUT = 1,     /* bad scene, mesh, parameter or command line */
  SK_ERR_IO = 2,        /* a file could not be read or written */
  SK_ERR_INVERTED = 3,  /* an element has det F <= 0 (the step may be cut and retried) */
  SK_ERR_DIVERGED = 4,  /* Newton or a local Newton did not converge (the step is cut and retried) */
  SK_ERR_PLUGIN = 5,    /* a plugin failed to load, has the wrong ABI or lacks a capability */
  SK_ERR_INTERNAL = 6,  /* a broken invariant: a bug */
  SK_ERR_NOMEM = 7,     /* out of memory: returned with a message, never an abort */
  SK_ERR_INTERRUPTED = 8, /* SIGINT/SIGTERM: stopped on the user's request (stickslip/interrupt.h) */
  SK_ERR_LINEAR_SOLVER = 9 /* a linear solve failed (no Krylov convergence, singular matrix): a property of the
                              solver and the system, so cutting the step does not help (bridge.h says what does) */
} sk_status;

/* Propagates a failing status to the caller. */
#define SK_TRY(call)                                      \
  do {                                                    \
    sk_status sk_try_status_ = (call);                    \
    if (sk_try_status_ != SK_OK) return sk_try_status_;   \
  } while (0)

/* ---- element types (gmsh node ordering, docs/theory/elements.md; the core's mesh.h takes them from here) -------- */
typedef enum {
  SK_POINT1 = 0,
  SK_LINE2,
  SK_LINE3,
  SK_TRI3,
  SK_QUAD4,
  SK_QUAD9,
  SK_TET4,
  SK_HEX8,
  SK_HEX27,
  SK_TRI6,           /* minor 1: second-order elements (the scene key mesh.order: 2) */
  SK_QUAD8,          /* minor 1: serendipity, quad9 without the centre node */
  SK_TET10,          /* minor 1 */
  SK_HEX20,          /* minor 1: serendipity, hex27 without face and body centres */
  SK_ELEM_TYPE_COUNT /* the count of THIS header's version; new types are appended before it (a minor version) */
} sk_elem_type;

/* ---- plugin kinds and capabilities ------------------------------------------------------------------------------ */
/* What a plugin instance attaches to (sk_plugin.kinds is a bit set of these). */
typedef enum {
  SK_KIND_PAIR = 1u << 0, /* one instance per contact pair of the scene (`contact:` entries naming the plugin) */
  SK_KIND_BODY = 1u << 1  /* one instance per body of the scene whose entry names the plugin (`bodies[i].plugin`) */
} sk_kind;

/* sk_plugin.caps. "checked" says what the host does with the bit (docs/plugin-abi.md §4 has the table). */
typedef enum {
  SK_CAP_2D = 1u << 0,                /* checked: a 2D scene needs it */
  SK_CAP_3D = 1u << 1,                /* checked: a 3D scene needs it */
  SK_CAP_FRICTION = 1u << 2,          /* informational (`stickslip plugins`); friction parameters are the plugin's
                                         own keys, so a frictionless plugin rejects them as unknown keys */
  SK_CAP_QUASISTATIC = 1u << 3,       /* checked: time.scheme quasi-static needs it */
  SK_CAP_DYNAMICS = 1u << 4,          /* checked: a dynamic scheme (backward Euler, midpoint) needs it */
  SK_CAP_ENERGY_MOMENTUM = 1u << 5,   /* checked: without it the midpoint scheme warns (energy not kept through
                                         contact) */
  SK_CAP_RIGID_OBSTACLE = 1u << 6,    /* checked: a pair with `obstacle:` needs it */
  SK_CAP_DEFORMABLE_MASTER = 1u << 7, /* checked: a pair with `master:` needs it */
  SK_CAP_MULTIPLIERS = 1u << 8,       /* checked: layout() may declare n_extra > 0 only with it */
  SK_CAP_CONDENSATION = 1u << 9,      /* checked: layout.eliminated, a second strategy and stickslip.condense need it */
  SK_CAP_NEEDS_CURVATURE = 1u << 10,  /* checked: a warning when a surface has straight (LINE2/TRI3) faces, whose
                                         curvature terms vanish */
  SK_CAP_NEEDS_MASS = 1u << 11,       /* checked: the mass calls of stickslip.bulk need it */
  SK_CAP_OWNS_KINEMATICS = 1u << 12,  /* checked: stickslip.bulk claim() and sk_plugin.integrator need it */
  SK_CAP_SELF_CONTACT = 1u << 13,     /* checked: a pair with slave == master needs it */
  SK_CAP_SAYS_IDLE = 1u << 14         /* ABI 2.2, informational: layout() may set sk_layout.idle (--explain says the
                                         pair's calls are skipped on such steps) */
} sk_capability;

/* ---- views: the part of a surface or body this rank sees ------------------------------------------------------- */
/* A view is a surface (its cells are faces) or a body (its cells are volume elements) as one rank sees it: the
 * cells and nodes this rank OWNS plus GHOSTS around them, in a local numbering 0..n-1. Plugins never see the mesh,
 * the replicated vector of unknowns or all reference coordinates; positions arrive per view in sk_state.
 *
 * What a view holds (the contract; today's host may hold more, never less):
 * - a slave surface view: every face with an owned node, every face this rank owns, and their nodes;
 * - a master surface view: every master face a slave point of this rank can reach in the step (today: the whole
 *   master surface, which docs/design.md measures);
 * - a body view: every element of the body with an owned node or owned by this rank, and their nodes.
 * Ownership rule (each contribution is assembled by exactly one rank, the host sums over ranks):
 * - a node-based entity (a slave node of NTS, a node's multipliers) belongs to the owner of the node: owned[k];
 * - a cell-based entity (the Gauss points of a slave face in STS or mortar, an element's terms) belongs to the owner
 *   of the cell: cell_owned[c]. A face is owned by the rank that owns the body element it bounds.
 * All pointers stay valid for the instance's lifetime; the view does not change during a run. */
typedef struct sk_view {
  uint32_t struct_size;
  const char *name;            /* the surface's or body's name in the scene */
  int dim;                     /* spatial dimension, 2 or 3 (positions and dofs have dim entries per node) */
  int body;                    /* index of the body (the one the surface bounds) */
  sk_elem_type cell_type;      /* faces: LINE2, LINE3, TRI3, QUAD4, QUAD9, TRI6, QUAD8; bodies: the element type
                                  (a plugin refuses a type it does not handle, naming it) */
  int nen;                     /* nodes per cell */
  int32_t n_cells;             /* cells of this view on this rank (owned + ghosted) */
  const int32_t *conn;         /* n_cells * nen view node indices (faces: oriented so normals point out of the body) */
  const unsigned char *cell_owned; /* n_cells: 1 when this rank owns the cell */
  const int64_t *cell_index;   /* n_cells: the cell's index in the whole surface/body, 0 .. n_cells_global-1 */
  int64_t n_cells_global;
  int n_edges;                 /* faces: edges per face (2 in 2D, i.e. the end points; 3 tri; 4 quad); bodies: 0 */
  const int32_t *neighbors;    /* faces: n_cells * n_edges view face across each edge (edge e joins corner e and
                                  e+1), -1 at the surface's border or beyond the view; bodies: NULL */
  int32_t n_nodes;             /* nodes of this view on this rank (owned + ghosted) */
  const int64_t *node_index;   /* n_nodes: the node's index in the whole surface/body (sorted by mesh id), 0 ..
                                  n_nodes_global-1: lay out extra unknowns per node with it, so that every rank
                                  agrees on their numbering */
  int64_t n_nodes_global;
  const int64_t *node_id;      /* n_nodes: mesh node id (for output, sk_contact_point.slave_node, and messages) */
  const unsigned char *owned;  /* n_nodes: 1 when this rank owns the node */
  const int64_t *dofs;         /* n_nodes * dim: global unknown index of each displacement component (for sinks) */
  const double *X;             /* n_nodes * dim: reference positions */
} sk_view;

/* ---- what an instance is attached to --------------------------------------------------------------------------- */
typedef struct sk_obstacle sk_obstacle; /* a rigid analytical obstacle (opaque: contact services read it) */

typedef struct sk_attach {
  uint32_t struct_size;
  sk_kind kind;                /* SK_KIND_PAIR or SK_KIND_BODY */
  const char *name;            /* "pair 0" / the scene's name of the pair, or the body's name */
  int strategy;                /* index into sk_plugin.strategies chosen by the scene (`strategy:`) */
  /* the views whose positions sk_state carries, in this order: pair {slave, master} (master absent with an
   * obstacle), body {body} */
  int n_views;
  const sk_view *const *views;
  /* a pair: */
  const sk_view *slave;        /* never NULL for a pair */
  const sk_view *master;       /* deformable master, or NULL */
  const sk_obstacle *obstacle; /* rigid master, or NULL */
  int self_contact;            /* 1 when slave and master are the same surface (views are still two) */
  /* a body: */
  const sk_view *body;         /* the body's view, or NULL for a pair */
} sk_attach;

/* ---- the state of a step, as an instance sees it --------------------------------------------------------------- */
/* Positions per view of sk_attach.views (dim per view node, view numbering): x = X + u. Positions, not
 * displacements: dF/du = dF/dx, so a plugin differentiates with respect to x and adds to the rows view->dofs. */
typedef struct sk_state {
  uint32_t struct_size;
  double t_n, t, dt;           /* the step from t_n to t = t_n + dt */
  int64_t step;                /* 1 for the first step; 0 for the initial output */
  /* The time integrator of the bodies (the scene's `time.scheme`, or the claimed body's own). Forces balance at
   * t_n + alpha dt: alpha = 1 for quasi-static and backward Euler, 1/2 for the energy-momentum midpoint scheme
   * (whose constraint gradients are taken at x_n + alpha (x - x_n) and constraints enforced at t). */
  const char *scheme;          /* "quasi-static", "backward-euler", "midpoint" or a body plugin's integrator name */
  double alpha;
  int dynamic;                 /* 1 when there is inertia (v_n meaningful) */
  int n_views;
  const double *const *x;      /* [view]: positions of the current iterate at t */
  const double *const *x_n;    /* [view]: positions at t_n (the last converged step) */
  const double *const *v_n;    /* [view]: velocities at t_n; NULL entries when quasi-static */
  const double *extra;         /* this instance's extra unknowns at the current iterate (n_extra), NULL before the
                                  first layout (the initial output) */
  int64_t n_extra;
  int64_t extra_offset;        /* global unknown index of extra[0] (for sinks) */
} sk_state;

/* ---- the step's extra unknowns ----------------------------------------------------------------------------------- */
typedef struct sk_layout {
  uint32_t struct_size;        /* set by the host */
  int64_t n_extra;             /* extra unknowns of this attempt (>= 0; > 0 needs SK_CAP_MULTIPLIERS) */
  const double *initial;       /* their starting values (n_extra) for this rank's OWNED entities, zero elsewhere
                                  (the host sums them over ranks), or NULL for zeros; the host copies them */
  const unsigned char *eliminated; /* 1 for unknowns the plugin condenses itself (plugin-local condensation), or
                                      NULL; the same on every rank (checked); needs SK_CAP_CONDENSATION */
  int recover_needs_jdx;       /* 1: recover() wants J dx (sk_vectors.Jdx_*), which costs one operator apply */
  /* ABI 2.2 (write it only when SK_HAS(layout, idle)): 1 promises that during this attempt (until the next layout)
   * update_active_set, residual and jacobian would add nothing and change nothing the instance reports or commits,
   * at every x: e.g. no slave point has a candidate face. With n_extra = 0 and the same answer on every rank, the
   * host then skips those three calls; begin_step, pattern, converged, commit_step, report and points still come.
   * Needs SK_CAP_SAYS_IDLE (else ignored).
   * ABI 2.3: also with n_extra > 0, when the extras' own equations have the solution 0 whatever the other unknowns
   * (trivial rows such as lambda - 0 of inactive multipliers) and `initial` is 0: the host then writes extra = 0
   * (1 on the diagonal) itself and skips recover too. Not with stickslip.condense pairs declared in this layout. */
  int idle;
  /* ABI 2.4 (write it only when SK_HAS(layout, extra_anchor)): per extra unknown (n_extra), the global unknown index
   * of one displacement component of the mesh node the unknown belongs to (a slave node's multiplier or augmented
   * coordinates), or -1 (none, or a node this rank does not see: the host combines the ranks' answers); NULL for
   * none. A hint: when a coupling the plugin declares is missing from the sparsity pattern, the host grows the
   * pattern by the couplings of the mesh neighbours too (solver.pattern_margin), the extras' side included through
   * their nodes, so that contact moving on to the next nodes does not rebuild the solver's matrix every step. The
   * array stays valid until the next layout call. */
  const int64_t *extra_anchor;
} sk_layout;

/* ---- vectors of one linear solve, in the instance's own layout (recover) ---------------------------------------- */
/* Per view of sk_attach.views (dim per view node) and for the instance's extra unknowns. Valid at owned and
 * ghosted nodes; the extras of owned entities. */
typedef struct sk_vectors {
  uint32_t struct_size;
  const double *const *F_view;   /* [view] the residual F at the point of the solve (Dirichlet rows replaced) */
  const double *F_extra;
  const double *const *dx_view;  /* [view] the solved displacement update */
  double *dx_extra;              /* the update of the extra unknowns: kept ones solved (and multipliers paired
                                    through stickslip.condense recovered by the host), eliminated ones 0 on entry:
                                    write those of owned entities (the host sums over ranks) */
  const double *const *Jdx_view; /* [view] (J dx) with the assembled operator J and the full dx, or NULL unless
                                    layout.recover_needs_jdx */
  const double *Jdx_extra;
} sk_vectors;

/* ---- geometry returned by the contact services ------------------------------------------------------------------ */
enum { SK_FACE_NEN_MAX = 9 }; /* nodes of the largest face type (QUAD9); a larger face type is a major version */

/* Covariant geometry at a surface point. 2D faces fill index 0 of the parametric quantities and set a[1] = e_z,
 * m[1][1] = 1, so the 2D case reads as a 3D one. Obstacles fill position, normal, orthonormal tangents (metric =
 * identity, m_inv = identity, a_dual = a) and h_ab; their Christoffel symbols are zero (orthonormal tangents of a
 * plane, sphere, cylinder or parabolic cylinder at the closest point, not derived from a parametrisation). */
typedef struct sk_surface_point {
  uint32_t struct_size;        /* set by the caller: sizeof(sk_surface_point) */
  int face;
  double xi[2];
  double x[3];                 /* position */
  double a[2][3];              /* covariant tangents a_alpha = dx/dxi^alpha */
  double n[3];                 /* unit normal a1 x a2 / |a1 x a2|, out of the body */
  double m[2][2];              /* metric m_ab = a_a . a_b */
  double m_inv[2][2];          /* m^ab */
  double a_dual[2][3];         /* contravariant tangents a^a = m^ab a_b */
  double a_ab[2][2][3];        /* second derivatives x,ab */
  double h[2][2];              /* curvature h_ab = x,ab . n */
  double christoffel[2][2][2]; /* Gamma^c_ab = x,ab . a^c, index [a][b][c] */
  double jacobian;             /* |a1 x a2|: area element (length element in 2D) */
  int nen;
  double N[SK_FACE_NEN_MAX];   /* face shape functions at xi */
  double dN[SK_FACE_NEN_MAX][2];
} sk_surface_point;

typedef enum {
  SK_PROJ_INTERIOR = 0, /* inside the face */
  SK_PROJ_EDGE,         /* on a face edge (2D: an end point), including exactly on a shared edge */
  SK_PROJ_VERTEX,       /* at a face corner */
  SK_PROJ_OUTSIDE       /* the closest point is on the border of the surface: the point lies beyond it */
} sk_projection_kind;

typedef struct sk_projection {
  uint32_t struct_size;        /* set by the caller */
  int face;                    /* view face, -1 when nothing was found */
  double xi[2];
  double gap;                  /* (x - x_closest) . n: positive outside, negative penetrating */
  double distance;             /* |x - x_closest| */
  sk_projection_kind kind;
  int iterations;              /* Newton iterations of the local projection */
} sk_projection;

/* ---- results ---------------------------------------------------------------------------------------------------- */
typedef struct sk_contact_report {
  uint32_t struct_size;        /* set by the host */
  double force[3];             /* resultant contact force on the slave side (this rank's entities) */
  double moment[3];            /* its moment about the origin (history.csv contact_moment_*) */
  int64_t active, stick, slip; /* counts of contact points */
  double dissipated;           /* frictional dissipation of this step (the host accumulates it) */
  double constraint_norm;      /* largest constraint violation among active points (e.g. |Phi|); max over ranks */
} sk_contact_report;

/* One contact point as contact.csv and the VTU files show it (docs/plugin-abi.md §8 has the conventions). Tractions
 * are per REFERENCE measure (area in 3D, length in 2D): the normal force a point transmits is pressure x area. */
typedef struct sk_contact_point {
  uint32_t struct_size;        /* set by the plugin */
  double x[3];                 /* point position */
  double normal[3];            /* unit normal of the master surface (obstacle) pointing towards the slave: the normal
                                  traction on the slave is pressure x normal */
  double pressure;             /* normal traction, >= 0 in compression (a force with `forces`) */
  double traction[3];          /* tangential traction on the slave (a force with `forces`) */
  double gap;                  /* signed normal gap: > 0 apart, < 0 penetrating; NaN when nothing is within reach */
  int state;                   /* 0 inactive, 1 stick (or in contact without friction), 2 slip */
  int64_t slave_node;          /* mesh node id (sk_view.node_id), or -1 for a Gauss point */
  /* ABI 2.1 (contact.csv, docs/plugin-abi.md §8): */
  double X[3];                 /* reference position of a Gauss point (a node's comes from the mesh; not read) */
  int has_multiplier;          /* 1 when `multiplier` holds the point's normal Lagrange multiplier */
  double multiplier;           /* the formulation's multiplier of the normal constraint (its own sign convention) */
  /* ABI 2.6. Zero (as a plugin that does not know them leaves them) keeps the meaning of 2.4: */
  int forces;                  /* 1: pressure and traction hold the node's normal and tangential FORCES (a formulation
                                  without areas: nodal multipliers, nodal penalty stiffnesses); the host divides them
                                  by the node's tributary reference measure of the slave surface. 0: tractions */
  double area;                 /* the reference measure (area in 3D, length in 2D) the tractions act on: the tributary
                                  measure of a node, weight x area element of a Gauss point; the normal force is
                                  pressure x area. 0: unknown (the host takes a node's tributary measure) */
  int has_slip;                /* 1 when slip_increment and slip hold the point's friction kinematics */
  double slip_increment[3];    /* tangential displacement of the slave point relative to the master surface in the
                                  last step (spatial, in the tangent plane; a penalty law's elastic stick included) */
  double slip;                 /* accumulated length of the slip increments since the start */
  int64_t slave_face;          /* read when slave_node < 0: the Gauss point's face, its index in the whole slave
                                  surface (sk_view.cell_index) */
} sk_contact_point;

/* ---- the scene around an attachment (ABI 2.7): sk_plugin.check and the extension stickslip.scene.v1 ------------ */
/* Plain data the host fills from the scene alone (no instance needed), the same on every rank: what sk_plugin.check
 * decides on, and what a plugin computes its default parameters from (docs/plugin-abi.md §9.4). */
typedef enum {
  SK_SHAPE_NONE = 0,          /* not an obstacle: a deformable surface, or a body */
  SK_SHAPE_PLANE,
  SK_SHAPE_SPHERE,            /* a circle in 2D */
  SK_SHAPE_CYLINDER,
  SK_SHAPE_PARABOLIC_CYLINDER
} sk_obstacle_shape;

/* One side of a pair (its slave or master surface, or its rigid obstacle), or a body. */
typedef struct sk_scene_side {
  uint32_t struct_size;        /* set by the host */
  const char *name;            /* the surface's, obstacle's or body's name in the scene */
  int body;                    /* index of the body the surface bounds (or the body); -1 for a rigid obstacle */
  const char *body_name;       /* that body's name; the obstacle's name for an obstacle */
  int rigid;                   /* 1 for a rigid obstacle: infinitely stiff (E = INFINITY, nu = 0) */
  sk_obstacle_shape shape;     /* the obstacle's shape; SK_SHAPE_NONE otherwise */
  int moving;                  /* an obstacle whose `motion` moves it at some time; 0 otherwise */
  double E, nu;                /* the body's Young's modulus and Poisson ratio (`material`) */
  sk_elem_type cell_type;      /* faces of a surface, elements of a body; SK_POINT1 for an obstacle */
  int order;                   /* polynomial order of the cells: 1 or 2; 0 for an obstacle */
  /* Sizes in the reference configuration over the WHOLE surface (every rank the same values): lengths of the edges
   * between the corner nodes of its faces (a 2D face is one edge; mid-side nodes do not split an edge, so a tet10
   * mesh has the h of the tet4 mesh it was made from). 0 for an obstacle and for a body. */
  double h_min, h_mean, h_max;
  double measure;              /* total reference area of a 3D surface, length of a 2D one; 0 for an obstacle/body */
  int64_t n_cells, n_nodes;    /* faces and nodes of the whole surface (elements and nodes of a body) */
  double velocity[3];          /* the body's initial motion (`velocity`, `angular_velocity`, `center`): v(X) =
                                  velocity + angular_velocity x (X - center); zero for an obstacle */
  double angular_velocity[3];
  double center[3];
} sk_scene_side;

/* An attachment as the scene describes it. */
typedef struct sk_scene_info {
  uint32_t struct_size;        /* set by the host */
  sk_kind kind;                /* SK_KIND_PAIR or SK_KIND_BODY */
  const char *name;            /* the pair's or body's name */
  int dim;                     /* 2 or 3 */
  const char *scheme;          /* the integrator of the (slave) body: "quasi-static", "backward-euler", "midpoint",
                                  or a body plugin's own integrator name */
  double alpha;                /* forces balance at t_n + alpha dt (sk_state.alpha) */
  int dynamic;                 /* 1 with inertia */
  int n_ranks;                 /* MPI ranks of the run */
  int strategy;                /* index into sk_plugin.strategies: the scene's `strategy`; when the host looks for
                                  alternatives (probe = 1), each of the plugin's strategies in turn */
  int friction;                /* 1 when the parameters give mu > 0 */
  int self_contact;            /* 1 when slave and master are the same surface */
  const sk_scene_side *slave;  /* a pair's slave surface; a body: the body */
  const sk_scene_side *master; /* a pair's master surface or rigid obstacle; NULL for a body */
  int probe;                   /* 1 when the host asks a plugin (or the named one with another strategy) in its
                                  search for the plugins that can run what the named one cannot: a plugin that is no
                                  contact formulation (a teaching example) declines then */
} sk_scene_info;

#ifdef __cplusplus
}
#endif
#endif
