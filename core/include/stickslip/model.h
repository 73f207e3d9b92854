/* stickslip — the model: the scene's description of bodies, boundary conditions, loads, contact pairs and time
 * stepping, with the finite-element data derived from it once (consistent mass, METIS partition, node owners).
 * Built from a scene by sk_scene_load (scene.h); the nonlinear system of a step is core/model/system.c's. It does
 * not change during a run, but for the master faces a rank holds (sk_contact_pair.master_held: ghosted again when
 * the contact moves, core/model/master_ghosts.h). */
#ifndef STICKSLIP_MODEL_H
#define STICKSLIP_MODEL_H

#include <mpi.h>
#include <stdint.h>

#include "stickslip/contact.h"
#include "stickslip/error.h"
#include "stickslip/fe.h"
#include "stickslip/integrator.h"
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
  const sk_time_integrator *integrator; /* the scene's time.scheme (a body plugin may replace it) */
  const sk_plugin *plugin; /* a body plugin (kind "body"), or NULL */
  int strategy;            /* index into plugin->strategies */
  const void *params;      /* the scene node of its `parameters` (sk_cfg), or NULL */
  const void *plugin_node; /* the scene node of its `plugin` key (sk_cfg), or NULL: where messages point without
                              `parameters` */
  /* the whole body's counts, and each node's index in its sorted node list (per model node, -1: not of the body;
   * NULL before the mesh is distributed, when the group is whole) */
  int n_elems_global, n_nodes_global;
  int64_t *node_index;
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

/* A prescribed total force on a face group (boundary `resultant:`): the uniform traction R / A over the group's
 * faceted area A, reference or current, so that the nodal forces w_a R / A sum to R exactly on any faces (curved,
 * quadratic: w_a = integral N_a dA, negative at QUAD8 corners). Assembled by term_resultant.c. */
typedef struct {
  char name[SK_NAME_MAX];
  const sk_group *faces;
  double resultant[3];     /* total force, multiplied by `history` */
  int current_area;        /* 0: over the reference area (a dead load), 1: over the current area (follows x) */
  sk_history history;
} sk_resultant;

typedef struct {
  char name[SK_NAME_MAX];
  const sk_plugin *plugin;
  sk_surface slave;
  sk_surface master;       /* unused with an obstacle */
  sk_obstacle obstacle;
  int has_obstacle;
  int self_contact;        /* slave and master are the same surface (master then copies slave) */
  int strategy;            /* index into plugin->strategies */
  const void *params;      /* the scene node of the pair's `parameters` (sk_cfg), or NULL */
  const void *plugin_node; /* the scene node of the entry's `plugin` key (sk_cfg), or NULL: where messages point
                              without `parameters` */
  int entry;               /* index of the scene's `contact` entry that gives it */
  int obstacle_column;     /* with an obstacle: its reaction's columns in history.csv (the pairs an entry with
                              `bodies:` creates against one obstacle share them), else -1 */
  int generated;           /* created by an entry with `bodies:` (between two bodies' whole boundaries, or a body's
                              boundary and an obstacle); the host's broad phase may keep it idle (term_plugin.c) */
  /* master faces ghosted by swept boxes (core/model/master_ghosts.h; NULL: the master surface is whole on every rank
   * with the pair): per rank its grown slave box of the set-up, then (second half) the step's swept boxes */
  double *ghost_boxes;
  double ghost_capture, ghost_reach; /* the capture distance and the reach the set-up's boxes were grown by */
  /* after the model is distributed (every master node is held, its faces too): per master face, 1 when this rank
   * holds it now (its nodes exchanged, in the plugins' master view), and its box when the faces were last ghosted */
  unsigned char *master_held;
  double *master_face_box;
  /* the contact partition (core/model/contact_partition.h; NULL: the bulk partition): the rank evaluating each slave
   * node and each slave face, by its index in the whole slave surface (surface-sized, on every rank) */
  int *contact_node_owner;
  int *contact_face_owner;
  /* with a contact partition: the measured work of each slave node, then each slave face (whole-surface indices), at
   * the last step that asked for a rebalance (the bisection's weights; all 0 before) */
  double *contact_weight;
} sk_contact_pair;

typedef struct {
  const sk_time_integrator *integrator; /* time.scheme */
  double dt, t_end, t_start;
  int max_cuts;            /* successive halvings of dt before giving up */
} sk_time_options;

typedef struct sk_model {
  MPI_Comm comm;
  int rank, n_ranks;
  sk_mesh mesh;
  int dim, n_nodes, n_dofs; /* the nodes this rank holds (docs/design.md) and their dofs */
  double *X;               /* reference positions in dof layout (n_dofs) */
  int n_nodes_global;      /* over all ranks: the mesh's */
  int64_t n_dofs_global;
  int64_t *node_gid;       /* per node: its mesh id (the numbering of the scene's mesh, of output and of plugins) */
  int64_t *gid_sorted;     /* (mesh id, node) pairs sorted by id, for sk_model_node_of */

  int n_bodies;
  sk_body *bodies;
  int n_elements;          /* over all bodies (this rank's, after sk_model_distribute) */
  int *element_part;       /* METIS part per element */
  int *element_index;      /* per element: its index in its body's whole group */
  int *node_owner;         /* rank owning each node: the lowest part among the elements holding it */
  int n_dirichlet;
  sk_dirichlet *dirichlet;
  int n_tractions;
  sk_traction *tractions;
  int n_resultants;
  sk_resultant *resultants;
  double body_force[3];    /* per unit mass */
  int n_pairs;
  sk_contact_pair *pairs;
  int n_obstacle_columns;  /* distinct obstacles (contact_pair.obstacle_column) */
  sk_time_options time;
  int contact_rebalance;   /* contact_balance.rebalance: 1 gives the contact pairs their own partition */
  double rebalance_time_ratio;       /* contact_balance.time_ratio: rebalance after a step whose max/mean contact
                                        time over the ranks exceeds it */
  double rebalance_entity_imbalance; /* contact_balance.entity_imbalance: or whose (max - min) / max active slave
                                        points per rank exceeds it */

  /* consistent mass: nodal scalar CSR (n_nodes x n_nodes; its graph is the bulk's node graph). The graph is built
   * always; the values (zero until then) and the element matrices (NULL until then) by sk_model_build_mass. */
  int64_t *mass_row_ptr;
  int *mass_cols;
  double *mass_values;
  int64_t *element_mass_offset; /* per element: offset of its scalar mass matrix (nen x nen) in element_mass */
  double *element_mass;
  /* the contact neighbourhoods the sparsity pattern widens over (solver.pattern_margin): per node, itself and the
   * nodes of contact surfaces that share an element with it in the whole mesh, those this rank holds (CSR) */
  int64_t *surface_ptr;
  int *surface_cols;
} sk_model;

/* The finite-element data of a model whose bodies are read: the METIS partition of the elements over the model's
 * ranks and the node owners (the lowest part among the elements holding a node); the mesh ids. */
sk_status sk_model_build(sk_model *model);
/* Distributes a built model (docs/design.md, "What each rank holds"): this rank keeps its elements and their ghost
 * layer, the nodes it holds (sk_model_node_roles) in a local numbering — its owned nodes first, then its ghosts, each
 * by mesh id — the faces of its surfaces and loads on those nodes, and the node graph of its elements; the whole
 * sizes and indices that plugins and output need are kept beside them. Collective. */
sk_status sk_model_distribute(sk_model *model);
/* The node graph of the model's elements (the mass matrix's pattern; called by sk_model_distribute), and the lookup
 * table of the nodes' mesh ids (sk_model_node_of). */
sk_status sk_model_build_graph(sk_model *model);
sk_status sk_model_index_nodes(sk_model *model);
/* The consistent mass (CSR values and per element), once; only when a term of the system needs it. */
sk_status sk_model_build_mass(sk_model *model);
void sk_model_free(sk_model *model);
/* What a rank holds of each node (docs/design.md, "What each rank holds"): the nodes it owns, and as ghosts the
 * other nodes of its elements' ghost layer (every element it owns or that holds a node it owns), of the master
 * surfaces of its contact pairs (with ghost boxes, of the master faces ghosted to it), and on rank 0 of the
 * current-area resultant loads' groups. */
enum { SK_NODE_OWNED = 1, SK_NODE_GHOST = 2 };
/* role[node] = SK_NODE_OWNED, SK_NODE_GHOST or 0 for every node of the model, for this rank. */
sk_status sk_model_node_roles(const sk_model *model, unsigned char *role);
/* The same without the contact pairs' master surfaces: the owned nodes, the element ghost layer and the resultant
 * loads' groups. */
void sk_model_layer_roles(const sk_model *model, unsigned char *role);
/* The node with mesh id `gid`, or -1 when this rank does not hold it. */
int sk_model_node_of(const sk_model *model, int64_t gid);
/* The body whose elements hold mesh node `node` first (in body order), or -1. */
int sk_model_body_of_node(const sk_model *model, int node);

#ifdef __cplusplus
}
#endif
#endif
