/* stickslip — meshes: nodes plus named element groups (gmsh physical groups).
 *
 * A group of the mesh dimension is a body; a group of one dimension lower is a boundary or a contact surface;
 * a group of dimension 0 is a node set. Node ids are 0-based and shared by all groups. */
#ifndef STICKSLIP_MESH_H
#define STICKSLIP_MESH_H

#include <stddef.h>
#include <stdio.h>

#include "stickslip/error.h"
#include "stickslip/plugin_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/* sk_elem_type (SK_LINE2, ..., SK_HEX27) is part of the plugin ABI: plugin_types.h defines it. */

typedef struct {
  char name[64];       /* physical group name */
  int dim;             /* topological dimension of its elements */
  sk_elem_type type;   /* one element type per group */
  int nen;             /* nodes per element */
  int n_elems;
  int *conn;           /* n_elems * nen node ids, gmsh node ordering converted to stickslip ordering (see fe.h) */
} sk_group;

typedef struct {
  int dim;             /* 2 (plane strain, z = 0) or 3 */
  int n_nodes;
  double *x;           /* reference coordinates, 3 per node (z = 0 in 2D) */
  int n_groups;
  sk_group *groups;
  char source[512];    /* file the mesh came from, for messages */
} sk_mesh;

typedef struct {
  const char *name;
  double value;
} sk_mesh_param;

/* Loads a mesh. A `.geo` script is meshed through the gmsh C API after its parameters (DefineConstant names, e.g.
 * `refine`, `radius`) are set from `params`; a `.msh` file is read directly. `dim` 0 means: the highest dimension
 * that carries a physical group. Errors name the file. Only DefineConstant names of the script are accepted as
 * parameters (others are an error naming them). Node ids are compact, in gmsh tag order; body elements are positively
 * oriented (counter-clockwise in 2D) and boundary elements face out of the body element they lie on. On failure
 * *mesh holds nothing to free. */
sk_status sk_mesh_load(const char *path, const sk_mesh_param *params, int n_params, int dim, sk_mesh *mesh);

/* gmsh runs in a child process (a crash, an endless script or a runaway mesh cannot take stickslip down), within
 * these limits (scene keys mesh.max_elements, mesh.time_limit). */
#define SK_MESH_DEFAULT_MAX_ELEMENTS 1000000L
#define SK_MESH_DEFAULT_TIME_LIMIT 600.0

typedef struct {
  int dim;            /* as sk_mesh_load's `dim` (0: the highest dimension with a physical group) */
  long max_elements;  /* refuse a mesh with more elements of dimension `dim`, estimated before each meshing stage
                         (.geo) and counted after; > 0 */
  double time_limit;  /* seconds gmsh may take for the whole load (script, meshing); > 0 */
  int order;          /* 0: the elements as meshed or stored; 1 or 2: gmsh makes them first or second order (a
                         second-order .geo mesh puts the new nodes on the geometry, a .msh one on straight edges) */
  int serendipity;    /* with order 2: quad8/hex20 instead of quad9/hex27 (tri6/tet10 either way) */
} sk_mesh_options;

void sk_mesh_options_default(sk_mesh_options *options); /* dim 0, the default limits, order 0 */
/* sk_mesh_load with options (sk_mesh_load is this with the defaults and `dim`). Besides sk_mesh_load's errors:
 * "mesh X: the mesh would have about 2.4e+09 elements, more than mesh.max_elements = 1000000 (parameters: ...)",
 * gmsh crashes and time or memory limits ("... while meshing the surfaces (2D)"), SK_ERR_INTERRUPTED on SIGINT/
 * SIGTERM (stickslip/interrupt.h), and invalid elements (sk_mesh_check_elements). */
sk_status sk_mesh_load_with(const char *path, const sk_mesh_param *params, int n_params,
                            const sk_mesh_options *options, sk_mesh *mesh);
void sk_mesh_free(sk_mesh *mesh);

/* Process-wide: whether .geo scripts may act outside the mesh (shell commands, file writes; see geo_scan.c). Off by
 * default; the driver turns it on for --trust-scripts. Never read from a scene: the scene is what is not trusted. */
void sk_mesh_trust_scripts(int trust);
/* What the cache of generated meshes did for each .geo this process loaded (hit or miss, its key and entry file,
 * or why it was not cached), for --explain. */
void sk_mesh_cache_explain(FILE *out);

/* Checks every element of every group: node coordinates finite, no node repeated within an element, and for body
 * elements (dimension = mesh dimension) a positive Jacobian at every corner. Errors name the file (mesh->source),
 * the group, the element (0-based within the group) and its nodes: "mesh m.msh: physical group 'block', element 3
 * (nodes 4, 5, 5, 9, ...): node 5 appears twice (a collapsed element)". sk_mesh_load calls it; call it again after
 * moving nodes (a scene's translate/rotate). */
sk_status sk_mesh_check_elements(const sk_mesh *mesh);
/* Refuses elements that belong to two of the given groups (or a group given twice): two bodies on one physical
 * group, or on overlapping ones, would count the same material twice. `names[i]` names what uses groups[i] in
 * messages ("body 'block'"). */
sk_status sk_mesh_check_disjoint(const sk_mesh *mesh, const sk_group *const *groups, const char *const *names, int n);

/* The group of that name, or NULL. */
const sk_group *sk_mesh_find_group(const sk_mesh *mesh, const char *name);
/* Like sk_mesh_find_group but records "mesh FILE has no physical group NAME (it has: a, b, c)" when missing. */
sk_status sk_mesh_require_group(const sk_mesh *mesh, const char *name, int dim, const sk_group **group);

/* Sorted unique node ids used by a group; caller frees *nodes. */
sk_status sk_group_nodes(const sk_group *group, int **nodes, int *n_nodes);

/* METIS partition of the elements of `n_bodies` groups into `n_parts` parts (k-way on the dual graph).
 * part[e] is the part of the e-th element counted through the groups in order. Deterministic. n_parts == 1 puts
 * everything in part 0 without calling METIS. */
sk_status sk_mesh_partition(const sk_mesh *mesh, const sk_group *const *bodies, int n_bodies, int n_parts, int *part);

#ifdef __cplusplus
}
#endif
#endif
