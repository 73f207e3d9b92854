/* stickslip — contact services of the core: surfaces, surface geometry, search, projection, rigid obstacles.
 *
 * Plugins reach these through the host table (plugin.h: sk_host.contact); the structs below are plain data so a
 * plugin can read them without linking the core.
 *
 * Positions. Functions take the current nodal positions q as the global unknown layout: q[node*dim + i]. A surface
 * of a 3D body has 2D faces (TRI3, TRI6, QUAD4, QUAD8, QUAD9) with parameters xi[2]; in 2D faces are LINE2/LINE3 with
 * xi[1] and the second tangent is e_z (so a1 x e_z is the in-plane outward normal). Normals point out of the body. */
#ifndef STICKSLIP_CONTACT_H
#define STICKSLIP_CONTACT_H

#include "stickslip/error.h"
#include "stickslip/mesh.h"
#include "stickslip/plugin_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- surfaces ----------------------------------------------------------------------------------------------- */
typedef struct {
  char name[64];          /* physical group name */
  int dim;                /* spatial dimension (2 or 3) */
  sk_elem_type face_type; /* LINE2, LINE3, TRI3, TRI6, QUAD4, QUAD8, QUAD9 */
  int nen;                /* nodes per face */
  int n_faces;
  int *conn;              /* n_faces * nen global node ids, oriented so normals point out of the body */
  int n_nodes;            /* distinct nodes of the surface */
  int *nodes;             /* their global ids, sorted */
  int *face_neighbors;    /* n_faces * n_edges: face across each face edge (edge e joins corner e and e+1), -1 at a
                             border; in 2D the two "edges" are the end points */
  int n_edges;            /* edges per face (2 in 2D, 3 tri, 4 quad) */
  int body;               /* index of the body (volume group) the faces bound */
  /* After the mesh is distributed (core/model/model_distribute.c) a surface holds the faces this rank holds: */
  int n_faces_global, n_nodes_global; /* the whole surface's counts */
  int64_t *face_index;    /* per face: its index in the whole surface (NULL: the whole surface, the face itself) */
  int64_t *node_index;    /* per node: its index in the whole surface's sorted node list (NULL: the same) */
  int *face_owner;        /* per face: the rank owning the element it bounds (NULL: not known) */
  int whole_sizes;        /* 1 once distributed: the whole surface's edge lengths and measure below */
  double whole_h_min, whole_h_mean, whole_h_max, whole_measure;
} sk_surface;

/* Builds a surface from a face group, orienting each face outward with the volume elements of `body` that carry
 * it. Error if a face is not a face of that body (message names the group and the face). */
sk_status sk_surface_build(const sk_mesh *mesh, const sk_group *faces, const sk_group *body, int body_index,
                           sk_surface *surface);
/* The whole boundary of a body (the faces of its elements that no other element of it shares), named `name`. */
sk_status sk_surface_build_boundary(const sk_mesh *mesh, const sk_group *body, int body_index, const char *name,
                                    sk_surface *surface);
void sk_surface_free(sk_surface *surface);
/* Sizes of a surface at positions X_nodes (`stride` entries per node of the surface's numbering: 3 for the mesh's
 * coordinates): corner-to-corner edge lengths (min, mean and max over every face's edges; a 2D face is one edge,
 * mid-side nodes do not split it) and the total area (3D) or length (2D). The sizes stickslip.scene.v1 reports. */
void sk_surface_sizes(const sk_surface *surface, const double *X_nodes, int stride, double *h_min, double *h_mean,
                      double *h_max, double *measure);

/* ---- covariant geometry at a surface point ------------------------------------------------------------------ */
/* sk_surface_point (plugin_types.h, part of the plugin ABI): core functions fill every member and ignore
 * struct_size. */

/* Geometry of face `face` at parameters xi for positions q. 2D faces fill only index 0 of the parametric
 * quantities (and set a[1] = e_z, m[1][1] = 1 so that the 2D case reads as a 3D one). */
void sk_surface_geometry(const sk_surface *surface, int face, const double *xi, const double *q,
                         sk_surface_point *point);

/* Averaged nodal normals: for each surface node (in surface->nodes order) the normalised area-weighted mean of the
 * adjacent face normals. normals has 3 * n_nodes entries. */
void sk_surface_nodal_normals(const sk_surface *surface, const double *q, double *normals);

/* Tributary measure of each surface node (surface->nodes order; area in 3D, length in 2D) at positions q: the
 * integral of its shape function over the faces, which a uniform traction turns into the node's force. TRI6 and QUAD8
 * corners, where that integral is 0 or negative, take the positive weights of the modified basis of Popp, Wohlmuth,
 * Gee & Wall (alpha = 1/5, as penalty-nts does; docs/plugins/penalty-nts.md). */
void sk_surface_tributary_measures(const sk_surface *surface, const double *q, double *measure);

/* ---- closest-point projection (narrow phase) ---------------------------------------------------------------- */
/* sk_projection and sk_projection_kind: plugin_types.h. */

/* Projects point x (dim entries) onto the surface, trying the candidate faces (from the broad phase; all faces
 * when candidates == NULL), using Newton with the full second-derivative term, clamping to the face and switching
 * to the neighbouring face when the iterate leaves it. Picks the candidate with the smallest distance; ties on a
 * shared edge pick the lowest face id (deterministic). Classification tolerance 1e-10 in xi; a result reported on
 * an edge lies exactly on it. SK_ERR_INPUT for a candidate id out of range, SK_ERR_DIVERGED (result still filled)
 * when Newton did not converge. docs/contact-services.md has the details. */
sk_status sk_surface_project(const sk_surface *surface, const double *q, const double *x, const int *candidates,
                             int n_candidates, sk_projection *projection);

/* ---- broad phase -------------------------------------------------------------------------------------------- */
typedef struct sk_search sk_search;

/* A bounding-volume tree over the faces of `surface`. */
sk_status sk_search_create(const sk_surface *surface, sk_search **search);
void sk_search_destroy(sk_search *search);
/* Refits the face boxes to enclose each face at both q0 (start of step) and q1 (current predictor), inflated by
 * `margin`: a face that cannot be reached during the step is never returned. Either q may be NULL. */
void sk_search_update(sk_search *search, const double *q0, const double *q1, double margin);
/* Faces whose boxes overlap the box [lo, hi]; writes at most max_faces ids, returns how many overlap in total.
 * Before the first sk_search_update nothing is returned. */
int sk_search_query(const sk_search *search, const double lo[3], const double hi[3], int *faces, int max_faces);
/* The tree's split is made by the first update (create has no positions) and later updates only refit its boxes;
 * this asks the next update for a new split, for a surface that has deformed a lot. Allocates nothing. */
void sk_search_rebuild(sk_search *search);
/* The same answer as sk_search_query by testing every face box (order: increasing face id): the reference for
 * tests and benchmarks. */
int sk_search_brute_force(const sk_search *search, const double lo[3], const double hi[3], int *faces,
                          int max_faces);

/* ---- rigid analytical obstacles ----------------------------------------------------------------------------- */
typedef enum {
  SK_OBSTACLE_PLANE = 0,            /* through `point` with outward unit `normal` */
  SK_OBSTACLE_SPHERE,               /* centre `point`, `radius` (2D: a circle) */
  SK_OBSTACLE_CYLINDER,             /* axis through `point` along `axis`, `radius` */
  SK_OBSTACLE_PARABOLIC_CYLINDER    /* z = c x^2 in the frame (point; axis = e_y direction of the generators;
                                       normal = e_z): material on the side z < c x^2, outward normal up */
} sk_obstacle_kind;

enum { SK_OBSTACLE_MOTION_MAX = 64 };

typedef struct sk_obstacle { /* opaque to plugins (plugin_types.h declares the tag) */
  sk_obstacle_kind kind;
  char name[64];
  double point[3];
  double normal[3];       /* plane normal / parabolic cylinder "up" */
  double axis[3];         /* cylinder axis / parabolic cylinder generator direction */
  double radius;
  double c;               /* parabolic coefficient */
  int n_motion;           /* prescribed translation: piecewise linear in time through (t_k, d_k) */
  double motion_t[SK_OBSTACLE_MOTION_MAX];
  double motion_d[SK_OBSTACLE_MOTION_MAX][3];
} sk_obstacle;

/* Closest point on the obstacle at time t for point x: fills position, unit normal (out of the obstacle),
 * tangents (orthonormal, a[0] x a[1] = n), metric (identity for these tangents), curvature h_ab and gap. */
sk_status sk_obstacle_project(const sk_obstacle *obstacle, double t, const double *x, int dim,
                              sk_surface_point *point, double *gap);
/* Translation of the obstacle at time t. */
void sk_obstacle_displacement(const sk_obstacle *obstacle, double t, double d[3]);

#ifdef __cplusplus
}
#endif
#endif
