/* stickslip — the model: bodies, boundary conditions, contact pairs and the time-stepping state, plus the bulk
 * (non-contact) parts of each step's nonlinear system. Built from a scene by sk_scene_build (scene.h). */
#ifndef STICKSLIP_MODEL_H
#define STICKSLIP_MODEL_H

#include <mpi.h>
#include <stdint.h>

#include "stickslip/contact.h"
#include "stickslip/error.h"
#include "stickslip/fe.h"
#include "stickslip/mesh.h"
#include "stickslip/plugin.h"

#ifdef __cplusplus
extern "C" {
#endif

enum { SK_HISTORY_MAX = 64, SK_NAME_MAX = 64 };

/* A piecewise-linear function of time through (t_k, v_k), constant beyond its ends; n == 0 means the constant 1. */
typedef struct {
  int n;
  double t[SK_HISTORY_MAX];
  double v[SK_HISTORY_MAX];
} sk_history;

double sk_history_value(const sk_history *history, double t);

typedef struct {
  char name[SK_NAME_MAX];
  const sk_group *group;   /* volume elements */
  sk_solid solid;          /* element type, dim, material pointer (-> material below) */
  sk_material material;
  double velocity[3];      /* initial translational velocity */
  double angular_velocity[3]; /* initial spin about `center` */
  double center[3];
  int first_element;       /* index of its first element in the global element numbering */
} sk_body;

typedef struct {
  char name[SK_NAME_MAX];
  int n_nodes;
  int *nodes;
  int fixed[3];            /* which components are prescribed */
  double value[3];         /* prescribed displacement components, multiplied by `history` */
  sk_history history;
} sk_dirichlet;

typedef struct {
  char name[SK_NAME_MAX];
  const sk_group *faces;
  double traction[3];      /* reference traction, multiplied by `history` */
  sk_history history;
} sk_traction;

typedef struct {
  char name[SK_NAME_MAX];
  const sk_plugin *plugin;
  sk_pair pair;
  sk_surface slave;
  sk_surface master;       /* unused with an obstacle */
  sk_obstacle obstacle;
  int has_obstacle;
  int strategy;
  sk_instance *instance;
  sk_layout layout;        /* of the current step */
  int extra_offset;        /* global index of its first extra unknown */
  void *params;            /* the scene node of the pair's parameters (sk_params) */
} sk_contact_pair;

typedef struct {
  sk_scheme scheme;
  double dt, t_end, t_start;
  int max_cuts;            /* successive halvings of dt before giving up */
  double dt_min;
} sk_time_options;

typedef struct sk_model {
  MPI_Comm comm;
  int rank, n_ranks;
  sk_mesh mesh;
  int dim, n_nodes, n_dofs;
  double *X;               /* reference positions in dof layout (n_dofs) */

  int n_bodies;
  sk_body *bodies;
  int n_elements;          /* over all bodies */
  int *element_part;       /* METIS part per element */
  int *node_owner;         /* rank owning each node: the lowest part among the elements holding it */
  int n_dirichlet;
  sk_dirichlet *dirichlet;
  int n_tractions;
  sk_traction *tractions;
  double body_force[3];    /* per unit mass */
  int n_pairs;
  sk_contact_pair *pairs;
  sk_time_options time;

  /* mass: consistent, nodal scalar CSR (n_nodes x n_nodes), and lumped (row sums) for plugins */
  int64_t *mass_row_ptr;
  int *mass_cols;
  double *mass_values;
  double *lumped_mass;
  double total_mass;
  int64_t *element_mass_offset; /* per element: offset of its scalar mass matrix (nen x nen) in element_mass */
  double *element_mass;
} sk_model;

void sk_model_free(sk_model *model);

#ifdef __cplusplus
}
#endif
#endif
