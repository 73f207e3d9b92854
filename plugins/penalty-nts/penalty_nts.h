/* penalty-nts, internal: the instance and its per-node state, shared by the plugin's files: penalty_nts.c (the
 * plugin table, candidates and self contact, the step), kernel.c (evaluation of one slave node), face_select.c (the
 * master face of each slave node), setup.c (parameters, check, creation). */
#ifndef PENALTY_NTS_H
#define PENALTY_NTS_H

#include <math.h>
#include <stdio.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "candidates.h"
#include "records.h"
#include "covariant.h"
#include "defaults.h"
#include "self_contact.h"
#include "stickslip/plugin.h"

#define PNTS_EXPORT __attribute__((visibility("default")))

enum { MAX_FACE_NODES = 9, MAX_LOCAL_DOFS = 3 * (1 + MAX_FACE_NODES) };
enum { STATE_INACTIVE = 0, STATE_STICK = 1, STATE_SLIP = 2 };

/* Friction history of one slave node (one step's anchor, or the committed one). */
typedef struct {
  int valid;            /* 0: no anchor (no friction force this step) */
  int face;             /* deformable: master face and parameters of the anchor, covariant traction */
  double xi[2];
  double t[2];
  double anchor[3];     /* obstacle: anchor point minus the obstacle translation, spatial traction */
  double traction[3];
} friction_history;

/* The friction state of one slave node at the last point where the Jacobian was assembled (the last accepted Newton
 * iterate): its traction when it slipped there, the switch's memory (cov_return_map_held). */
typedef struct {
  int slip;             /* 0: stuck, inactive or frictionless there (the return map decides alone) */
  int face;             /* deformable master: the face whose covariant basis t is in */
  double t[3];          /* covariant (deformable master, pdim components) or spatial (obstacle) traction */
} held_friction;

/* Everything one evaluation of a slave node produces. */
typedef struct {
  int found;            /* a projection exists (gap and normal are meaningful) */
  int state;            /* STATE_* */
  int face;
  double xi[2];
  double gap, p;        /* p: normal force (penalty times the slave's area when area weighted) */
  double x[3], normal[3];
  double force[3];      /* total contact force on the slave node */
  double traction[3];   /* its tangential part */
  double t_cov[2];      /* covariant tangential traction (deformable master) */
  double slip[3];       /* tangential displacement of the slave relative to the master since the step's anchor */
  double dissipation;   /* slip increment . traction of the step so far */
  int nd;               /* local dofs: slave node, then the master face nodes */
  int64_t rows[MAX_LOCAL_DOFS];
  double R[MAX_LOCAL_DOFS];
  double K[MAX_LOCAL_DOFS * MAX_LOCAL_DOFS];
} point_eval;

struct sk_instance {
  const sk_host_api *api;
  sk_host *host;
  const sk_contact_services *cs;
  const sk_view *slave;         /* the slave surface as this rank sees it: the slave nodes are its view nodes */
  const sk_view *master;        /* deformable master (whole), or NULL */
  const sk_obstacle *obstacle;  /* rigid master, or NULL */
  const char *name;             /* the pair's name */
  int dim;
  double penalty, penalty_t, mu, margin;
  int self;                     /* self contact: slave and master are the same surface */
  double self_exclusion;        /* self contact: faces with a node this close to the slave node (reference) are not
                                   its candidates */
  double touch_tolerance;       /* points with g <= this are active (see evaluate_point) */
  double extension;             /* master_extension: band beyond the master's border, fraction of a face */
  int area_weighted;
  int n_slave;
  /* 1 for the slave nodes this rank evaluates: its owned nodes and, for the TRI6 recovery, the edge nodes their
   * reported pressure combines (rec_node). The others (ghost nodes of the view, whose rows are other ranks') get no
   * candidates, selection or history here: their owners compute them (mark_evaluated). */
  unsigned char *evaluated;
  double *area;                 /* tributary reference area of each slave node (1 when not area weighted) */
  sk_search *search;
  int *cand_start, *cand_count; /* candidate master faces of each slave node in cand (find_candidates) */
  cand_list cand;
  friction_history *committed;  /* at the last accepted step */
  double (*slip_increment)[3];  /* of the last accepted step (points), and the accumulated slip length */
  double *slip;
  friction_history *anchor;     /* used during the current step */
  unsigned char *last_state;    /* for after_iteration's change detection */
  held_friction *held;          /* per slave node, the stick/slip switch's memory within the step */
  int return_map_only;          /* 1: evaluate without the memory (pnts_converged compares the two) */
  int *sel_face;                /* master face selected for each slave node (-1: none), see select_face */
  unsigned char *sel_beyond;    /* 1: the selection lies beyond the master's border (and its extension band) */
  unsigned char *escaped;       /* 1: the closest face at the last point is not a candidate (see select_face) */
  double (*sel_xi)[2];          /* start of the closest-point Newton on the selected face */
  int64_t *pattern_dofs;        /* the dofs of a slave node's neighbourhood (pattern) */
  int pattern_capacity;
  /* TRI6 slaves: the pressure reported at node k is (T^T f)_k / A_k (see sk_modified_basis_weights), a combination
   * of the nodal forces of node k and its edge nodes: CSR rows rec_start[k] .. rec_start[k+1] of (rec_node,
   * rec_coef) over view nodes; rec_force holds every view node's normal and tangential force, whether it is in
   * contact and its gap (REC_STRIDE per node) while points() reports. */
  int *rec_start, *rec_node;
  double *rec_coef, *rec_force;
};
enum { REC_STRIDE = 6 };
/* An open TRI6 node within this many times its neighbours' penetration of the master reports the recovered traction
 * (pnts_points). */
#define RIM_GAP_FACTOR 4.0

/* ---- small dense helpers --------------------------------------------------------------------------------------- */
static inline double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* Slave node k's position from the positions per view x (x[0]: the slave view, x[1]: the master view). */
static inline void slave_position(const sk_instance *in, const double *const *x, int k, double xs[3]) {
  xs[2] = 0.0;
  for (int i = 0; i < in->dim; ++i) xs[i] = x[0][k * in->dim + i];
}

/* parameters and strategies (setup.c) */
extern const char *const pnts_strategies[];
extern const char *const pnts_parameters[];
sk_status pnts_check(const sk_scene_info *scene, char *reason, int size);
sk_status pnts_create(const sk_host_api *api, sk_host *host, const sk_attach *attach, sk_instance **instance);
void pnts_destroy(sk_instance *in);
/* master face selection (face_select.c) */
int extend_on_face(const sk_instance *in, int face, const double *xs, const double *xm, double band,
                   sk_surface_point *pt);
sk_status select_face(sk_instance *in, const double *const *x, int k);
/* evaluation of one slave node (kernel.c) */
sk_status evaluate_point(sk_instance *in, const sk_state *st, int k, int want_jacobian, point_eval *e);

#endif
