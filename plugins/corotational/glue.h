/* corotational — the ABI glue's shared state (plugin.c: tables and pairs; glue_setup.c: the body's setup; glue.c:
 * its calls in a step). */
#ifndef COROT_GLUE_H
#define COROT_GLUE_H

#include "kernel.h"
#include "stickslip/plugin.h"

typedef struct {
  int64_t dof;                   /* global unknown index */
  int slot;                      /* view node * dim + component */
} glue_dof;

typedef struct {
  sk_instance *instance;
  const sk_view *slave;
  const sk_obstacle *obstacle;
  double mu;
  int *body_node;                /* per slave view node: its body view node */
  corot_plane plane;             /* the obstacle as a plane (checked at create) */
} glue_pair;

typedef struct {
  const sk_view *view;
  const sk_bulk_ext *bulk;
  const sk_linear_ext *linear;
  const sk_condense_ext *condense; /* strategy dual */
  int monolithic;                /* strategy monolithic: w kept, its row and column in the host's matrix */
  int dual;                      /* strategy dual: lambda condensed by the host (stickslip.condense) */
  /* parameters */
  corot_model model;
  double axis[3], c_n, c_t, tolerance;
  int steady;
  /* M and S captured over the body view's node graph */
  int64_t *row_ptr;
  int *cols;
  double *mass, *stiffness;
  glue_dof *dofs;                /* the view's global dofs, sorted */
  corot_body body;
  /* contact */
  int n_pairs;
  glue_pair pairs[COROT_MAX_PLANES];
  int contact_ready;
  corot_contact contact;
  int *contact_of_node;          /* body view node -> contact index, or -1 */
  /* the scheme */
  int started;                   /* the initial state is set */
  corot_state state, next;
  corot_world world;
  corot_world_jacobian J;
  double step_t_n, step_dt;      /* the attempt corot_world_begin was called for */
  double *y, *F, *dF, *dgy, *y2_view, *y2_extra, *rhs_extra, *f_world, *q, *v; /* world.N, n or n_extra */
  int64_t n_extra;
  double *initial;               /* layout: [w, border, lambda] */
  unsigned char *eliminated;
  int64_t *index;                /* index buffer for sinks (max(n, n_extra) + 64 entries) */
  double *block;                 /* value buffer for sinks (as many) */
  double g_scale;                /* g's row scale in F */
  double l_scale;                /* the body's length L = sqrt(I_e / m) */
  /* the committed step, for report() and points() */
  double Rm[9];                  /* R at the last step's midpoint */
  double *work_node;             /* per contact node: dt D_pp s_T . lambda_T of the last step (friction work) */
  double *slip_increment;        /* per contact node (3 each): dt R_m s_p,T of the last step, world (friction) */
  double *slip_length;           /* per contact node: the accumulated length of the slip increments */
  int rotation_updates;          /* Newton updates of w in the last step */
  int rejections;                /* converged() rejections in this attempt */
  double energy[2];              /* kinetic and strain energy of the scheme (Lemma 2.1) at the published state */
} glue_body;

struct sk_instance {
  sk_kind kind;
  const sk_host_api *api;
  sk_host *host;
  const sk_attach *attach;
  glue_body *body;               /* kind body: its own; kind pair: the body instance's */
  sk_instance *owner;            /* kind pair: the body instance */
  int pair_index;                /* kind pair: its plane among the body's */
};

/* glue_setup.c */
sk_status glue_create_body(sk_instance *inst);
sk_status glue_build_contact(sk_instance *inst);
sk_status glue_ensure_started(sk_instance *inst, const sk_state *state);
sk_status glue_publish_state(sk_instance *inst);
sk_status glue_nomem(sk_instance *inst);
void glue_destroy_body(sk_instance *inst);
sk_status glue_register_pair(sk_instance *owner, sk_instance *pair, const sk_view *slave, const sk_obstacle *obstacle,
                             double mu, int *index);
/* glue.c */
sk_status glue_begin_step(sk_instance *inst, const sk_state *state);
sk_status glue_layout(sk_instance *inst, const sk_state *state, sk_layout *layout);
sk_status glue_pattern(sk_instance *inst, const sk_state *state, sk_pattern *pattern);
sk_status glue_update_active_set(sk_instance *inst, const sk_state *state, int *changed);
sk_status glue_residual(sk_instance *inst, const sk_state *state, sk_sink *sink);
sk_status glue_jacobian(sk_instance *inst, const sk_state *state, sk_sink *sink);
sk_status glue_recover(sk_instance *inst, const sk_state *state, sk_vectors *vectors);
sk_status glue_converged(sk_instance *inst, const sk_state *state, int *accept);
sk_status glue_commit_step(sk_instance *inst, const sk_state *state);
sk_status glue_report(sk_instance *inst, const sk_state *state, sk_contact_report *report);
sk_status glue_points(sk_instance *inst, const sk_state *state, sk_point_callback callback, void *ctx);
sk_status glue_predict(sk_instance *inst, const sk_state *state, double *u);
sk_status glue_velocity(sk_instance *inst, const sk_state *state, double *v);
sk_status glue_energy(sk_instance *inst, const sk_state *state, double *kinetic, double *strain);

#endif
