/* covariant-penalty — the ABI glue's internals shared by plugin.c (creation, the table) and step.c (the step). */
#ifndef COVARIANT_PENALTY_GLUE_H
#define COVARIANT_PENALTY_GLUE_H

#include "candidates.h"
#include "kernel.h"
#include "stickslip/plugin.h"

/* A face selected earlier in the step is kept while the point's closest point on its polynomial extension stays
 * within this fraction of the face beyond its edge (penalty-nts: a slave at a kinked master node otherwise jumps
 * between the two faces every iteration). */
#define SELECT_BAND 0.1

enum { MAX_GAUSS = 25, CLOSEST_ITERATIONS = 30 };

typedef struct {
  int valid;
  int face;          /* sts/nts: master view face of the contact point at the last commit */
  double xi[2];
  double t[3];       /* traction on the slave, Cartesian (51) */
  double anchor[3];  /* stas: the Gauss point at the last commit minus the obstacle's translation (48) */
} history;

typedef struct {
  int cell;                       /* sts, stas: slave view face */
  double eta[2];                  /* its Gauss point */
  int n_slave;                    /* sts, nts: r_s = S_a x(slave[a]) on the slave view */
  int slave[CP_MAX_FACE_NODES];
  double S[CP_MAX_FACE_NODES];
  double weight;                  /* reference area */
  int cand_start, cand_count;     /* candidate master faces for the step */
  int sel_face;                   /* selected master face (-1: none) */
  double sel_xi[2];
  int sel_beyond;                 /* the point lies beyond the master's border (and its band) */
  int escaped;                    /* the closest face at the last point is not a candidate (select_face) */
  int last_state;
  history committed, anchor;      /* at the last commit / used during the step */
  double slip_increment[3], slip; /* of the last commit on the scene's slave, and the accumulated slip length */
} entity;

typedef struct { /* the obstacle's signed distance at the current time, for the kernel's ray (stas) */
  const sk_contact_services *cs;
  const sk_obstacle *obstacle;
  double t;
} distance_ctx;

struct sk_instance {
  const sk_host_api *api;
  sk_host *host;
  const sk_attach *attach;
  const sk_contact_services *cs;
  const sk_view *slave, *master;
  const sk_obstacle *obstacle;
  cp_variant variant;
  cp_form form;
  int want[CP_N_PARTS];
  double eps_n, eps_t, mu, margin, extension, touch_tol, max_depth;
  int gauss, area_weighted;
  cp_face face;                   /* master face type (stas: the slave's own faces) */
  int n_entities;
  entity *entities;
  sk_search *search;
  cand_list cand;                 /* candidate master faces of all points (find_candidates) */
  distance_ctx distance;
  double *K[CP_N_PARTS], *K_sum;  /* CP_MAX_DOFS^2 each */
};

/* One contact point made local: the kernel's point, positions and the global rows of its dofs. */
typedef struct {
  cp_point pt;
  double x[3 * CP_MAX_NODES];
  int64_t rows[CP_MAX_DOFS];
  int view[CP_MAX_NODES], node[CP_MAX_NODES];
} local_point;

/* A surface point to fill (struct_size set). */
sk_surface_point cp_new_surface_point(void);

/* The kernel's point of entity e at state->x: positions, global rows, history (step.c; the tests use it too).
 * Returns 0 when the point has no master face at this iteration. */
int cp_local_point(sk_instance *in, const entity *e, const sk_state *st, local_point *L);
/* The kernel's parameters of entity e (its weight). */
cp_params cp_point_params(const sk_instance *in, const entity *e);

/* The step (step.c): the calls of the plugin table. */
sk_status cp_begin_step(sk_instance *in, const sk_state *st);
sk_status cp_layout(sk_instance *in, const sk_state *st, sk_layout *layout);
sk_status cp_pattern(sk_instance *in, const sk_state *st, sk_pattern *pattern);
sk_status cp_update_active_set(sk_instance *in, const sk_state *st, int *changed);
sk_status cp_converged(sk_instance *in, const sk_state *st, int *accept);
sk_status cp_residual(sk_instance *in, const sk_state *st, sk_sink *sink);
sk_status cp_jacobian(sk_instance *in, const sk_state *st, sk_sink *sink);
sk_status cp_commit_step(sk_instance *in, const sk_state *st);
void cp_reject_step(sk_instance *in);
sk_status cp_report(sk_instance *in, const sk_state *st, sk_contact_report *report);
sk_status cp_points(sk_instance *in, const sk_state *st, sk_point_callback callback, void *ctx);

#endif
