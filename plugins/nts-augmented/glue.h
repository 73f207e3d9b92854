/* nts-augmented — the plugin glue around the kernel (private to the plugin):
 *   plugin.c   the ABI table: parameters, layout, pattern, the active set, commit, results
 *   step.c     begin_step: the search, the step's facet of each slave node, the history on it, the plane facets
 *              of a rigid obstacle
 *   element.c  one slave node's element under each strategy: residual rows, Jacobian blocks, recovery
 *
 * One NTS element per slave node and step (the slave node and the facet chosen at begin_step). Extra unknowns per
 * slave node, at extra_offset + stride * node_index (its index in the whole slave surface, the same on every
 * rank): [lambda_n, f1, f2, lambda_aug1, lambda_aug2] in 3D (stride 5), [lambda_n, f1, lambda_aug1] in 2D (stride
 * 3: the kernel's f2 and lambda_aug2 of the extruded segment are identically zero and have no unknowns). */
#ifndef NTS_AUGMENTED_GLUE_H
#define NTS_AUGMENTED_GLUE_H

#include "kernel.h"
#include "stickslip/plugin.h"

/* The strategies, in the order of the plugin's strategy names (plugin.c). */
typedef enum {
  NTS_CONDENSED = 0,  /* (50)/(76) with f, lambda_aug condensed out exactly per element: n + n_s unknowns */
  NTS_AUGMENTED,      /* (50)/(76) itself: the extras of the active nodes only, n + 5 n_c */
  NTS_PAPER,          /* the paper's reduced scheme (55), (78)-(81) */
  NTS_DIRECT,         /* the direct method (41)-(46), at the midpoint (74)/(75) */
  NTS_DIRECT_ENDPOINT /* the direct method with the closest point at t_{n+1} and forces at the mean of f */
} nts_strategy;

enum { LOCAL_NEWTON_MAX = 30, NTS_MAX_STRIDE = 5 };
#define LOCAL_NEWTON_TOL 1e-13

typedef struct {
  int k;                       /* the node in the slave view */
  int64_t node;                /* its mesh id (messages, output) */
  int64_t index;               /* its index in the whole slave surface (extra unknowns at stride * index) */
  /* committed at the end of the last accepted step */
  int c_facet, c_active, c_slip;
  double c_f[2];               /* f at t_n */
  double c_t[2];               /* tangential traction t_n, covariant on c_facet */
  double c_t_vector[3];        /* the same traction as a spatial vector, to map it onto a new facet */
  double c_extra[NTS_MAX_STRIDE];
  /* this step */
  int facet, active, flips;
  int corrections;             /* converged() set this frozen node's contact state right (this attempt) */
  int switches;                /* converged() moved the node onto another face (this attempt) */
  int left_facet;              /* the face converged() moved it off (-1: none); it does not return to it */
  double tension, penetration; /* the violations that made it do so last (lambda_n > 0 in contact, -gap released) */
  int slip;                    /* stick/slip branch of the return map used in this iteration (friction only) */
  int return_map;              /* after max_flips: the return map itself picks the branch at every evaluation */
  int in_system;               /* `augmented`: the node's extras are unknowns of the linear system this loop */
  int wants_in;                /* `augmented`: the node wants to become active, its extras are eliminated */
  int facet_nodes[NTS_MAX_NEN]; /* the facet's nodes in the master view */
  double f_start[2], t_start[2], f_frozen[2];
  double f_gap[2];             /* `direct`: the last closest point of q_{n+1} (the next local Newton's start) */
  double plane_origin[3];      /* rigid obstacle: a point of the plane near the node, without its displacement */
  double gap_estimate;         /* gap seen at begin_step (for output of inactive points) */
  double slip_increment[3];    /* a_a (f - f_start)^a of the last accepted step (friction) */
  double slip_length;          /* the accumulated length of the slip increments */
} slave_point;

struct sk_instance {
  const sk_host_api *api;
  sk_host *host;
  const sk_view *slave, *master; /* master NULL with a rigid obstacle */
  const sk_obstacle *obstacle;
  const char *name;
  nts_facet facet;
  int dim, pdim, stride;       /* 3, 2, 5 in 3D; 2, 1, 3 in 2D */
  nts_strategy strategy;
  nts_friction_params friction;
  double c_n, search_margin;
  double master_extension;     /* band beyond the master's border kept in contact, fraction of a face (find_facet) */
  int max_flips;
  int slide_search;            /* converged() moves nodes that slid beyond their facet (nts_research_facet) */
  int self;                    /* self contact: slave and master are the same surface */
  double self_exclusion;       /* self contact: the reach of the faces a node cannot touch (self_contact.h) */
  double *self_table;          /* self contact (self.c): per node of the surface its facet's nodes and state */
  int *self_colour;            /* self contact: the side of each node in its zone */
  int64_t *self_queue;         /* self contact: the breadth-first sweep's nodes */
  unsigned char *self_master_only; /* self contact: 1 for a node on the master side of its zone this step */
  sk_projection *projections;  /* begin_step: each point's projection on its facet */
  sk_search *search;
  int n_points;
  slave_point *points;
  int64_t n_extra;             /* stride per node of the whole slave surface */
  double *initial;             /* for the owned points (zero elsewhere: the host sums over ranks) */
  unsigned char *eliminated;
  int64_t *anchor; /* n_extra: a dof of each extra's slave node (sk_layout.extra_anchor), -1 for nodes not viewed */
  double *node_flags;          /* per node of the whole slave surface: the augmented layout's set, summed over ranks */
  int *candidates;
  double alpha;                /* 1: backward Euler / quasi-static, 1/2: midpoint */
  double plane_normal[3], plane_tangent[2][3]; /* rigid obstacle: the plane's frame (a_1 x a_2 = n) */
};

/* Everything of one slave node's element at an iterate. */
typedef struct {
  nts_element_input in;
  nts_element_system sys;      /* every strategy but `paper-reduced` (and its inactive rows) */
  nts_paper_system paper;      /* `paper-reduced`, active */
  int paper_active;
  double q_A[NTS_MAX_NQ], q_A_start[NTS_MAX_NQ];
  double x_e[4];               /* the global f1 f2 lambda_aug1 lambda_aug2 (differ from in.f under `direct`) */
  double f_gap[2];
  int64_t idx[NTS_MAX_NU];     /* the global unknown of each kernel unknown (u order), -1 for none */
} nts_element;

static inline int nts_owned(const sk_instance *inst, const slave_point *p) { return inst->slave->owned[p->k]; }

/* The primal-dual active-set test -lambda_n - c_n g > 0, with a node just touching (g = 0 to round-off, lambda_n =
 * 0: bodies that start in contact) counted in: otherwise a body held by the contact alone is unsupported in the
 * first solve (the quasi-static patch test: a singular system). The gaps of nodes placed on the master are
 * round-off, ~1e-17 of an edge; the band is 1e-12 of the search margin (half an edge by default). */
static inline int nts_wants_contact(const sk_instance *inst, double lambda_n, double gap) {
  return -lambda_n - inst->c_n * gap > -1e-12 * inst->c_n * inst->search_margin;
}

/* The extra slot (0 .. stride-1) of kernel unknown nq + 1 + e, e in [f1 f2 lambda_aug1 lambda_aug2]; -1 for the
 * zero f2, lambda_aug2 of a 2D element. */
static inline int nts_slot_of_e(const sk_instance *inst, int e) {
  if (inst->pdim == 2) return 1 + e;
  return e == 0 ? 1 : e == 2 ? 2 : -1;
}

/* element.c */
/* The global unknown of each kernel unknown (u order): positions (none for the z of a 2D node and the nodes of a
 * rigid facet), then the extras at extra_base. */
void nts_element_indices(const sk_instance *inst, const slave_point *p, int64_t extra_base, int64_t *idx);
/* Builds point k's element at the state's iterate for the instance's strategy (under `direct*` after the local
 * elimination). The point must have a facet. */
sk_status nts_element_eval(sk_instance *inst, int k, const sk_state *state, nts_element *e);
/* The element's residual rows in kernel u order (assembled through e->idx). */
void nts_element_residual(const sk_instance *inst, const slave_point *p, const nts_element *e, double *R);
sk_status nts_element_jacobian(sk_instance *inst, const slave_point *p, nts_element *e, sk_sink *sink);
sk_status nts_element_recover(sk_instance *inst, const slave_point *p, nts_element *e, const sk_state *state,
                              sk_vectors *v);
/* The contact force on the slave node (3), and the constraint values the element enforces (3). */
void nts_element_slave_force(const sk_instance *inst, const nts_element *e, double force[3]);
/* The tangential force on the slave node at t_{n+1}: from the friction traction t_{n+1}, which the return map bounds
 * by mu |lambda_n|. The step's force (above) carries t_used = (1 - alpha) t_n + alpha t_{n+1} instead: the same
 * but under the midpoint scheme, where it is the mean of the tractions at t_n and t_{n+1}. */
void nts_element_traction(const sk_instance *inst, const nts_element *e, double traction[3]);
const double *nts_element_constraints(const nts_element *e);
const nts_friction *nts_element_friction(const nts_element *e);
const nts_geometry *nts_element_geometry(const nts_element *e, int at_hat);

/* self.c */
sk_status nts_self_setup(sk_instance *inst);
void nts_self_free(sk_instance *inst);
/* Self contact, at begin_step after the search: per zone of facing nodes one side is slave; the other side's
 * projections get face -1 (those nodes are master nodes only this step). */
sk_status nts_self_sides(sk_instance *inst, sk_projection *proj);

/* history.c: the sk_plugin calls of a step's end and of the results, and the checkpoint extension. */
sk_status nts_commit_step(sk_instance *inst, const sk_state *state);
void nts_reject_step(sk_instance *inst);
sk_status nts_report(sk_instance *inst, const sk_state *state, sk_contact_report *rep);
sk_status nts_points(sk_instance *inst, const sk_state *state, sk_point_callback callback, void *ctx);
extern const sk_checkpoint_ext nts_checkpoint;

/* step.c */
sk_status nts_begin_step(sk_instance *inst, const sk_state *state);
/* The element's positions q_A = [slave node | facet nodes] (3 per node; z = 0 in 2D) from the positions per view
 * at time t (a rigid facet moves with the obstacle). */
void nts_gather(const sk_instance *inst, const slave_point *p, const double *const *x, double t, double *q_A);
/* The closest-point gap of the slave node on its step facet (f: start, then the closest point); HUGE_VAL when the
 * local Newton fails. */
double nts_gap_on_facet(const sk_instance *inst, const slave_point *p, const double *const *x, double t,
                        double f[2]);
/* At a converged point: an active node beyond its facet that penetrates the master face it is over changes to that
 * face (*switched; Newton must run again). */
sk_status nts_research_facet(sk_instance *inst, slave_point *p, const sk_state *state, int *switched);

#endif
