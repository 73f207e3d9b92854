/* Orientation fix-up after loading. gmsh orients elements after their geometric entity (a clockwise-defined surface
 * gives clockwise quads, a boundary surface may face into its volume), so the loader normalises:
 * - body elements (dimension = mesh dimension) have positive Jacobian: counter-clockwise in 2D, positive volume in 3D;
 * - boundary elements (one dimension lower) that lie on a body element's face have their normal pointing out of that
 *   body (a 2D edge then runs counter-clockwise around its body, with outward normal (t_y, -t_x)). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_internal.h"
#include "stickslip/fe.h"

/* Node permutations that reverse an element's orientation within gmsh's node-ordering rules: new node a = old node
 * perm[a]. Lines and tri3/tet4 swap two corners, quads run the other way round, hexes swap bottom and top; edge,
 * face and body nodes follow their corners. */
static const int reverse_line[3] = {1, 0, 2}; /* a line3's middle node is node 2 in both directions */
static const int reverse_tri[6] = {0, 2, 1, 5, 4, 3};
static const int reverse_quad[9] = {0, 3, 2, 1, 7, 6, 5, 4, 8};
static const int reverse_tet[10] = {0, 2, 1, 3, 6, 5, 4, 7, 9, 8};
static const int reverse_hex[27] = {4,  5,  6,  7,  0,  1,  2,  3,  16, 17, 10, 18, 12, 19,
                                    14, 15, 8,  9,  11, 13, 25, 21, 22, 23, 24, 20, 26};

static void reverse_element(sk_elem_type type, int *conn) {
  const int *perm = NULL;
  switch (type) {
    case SK_LINE2: case SK_LINE3: perm = reverse_line; break;
    case SK_TRI3: case SK_TRI6: perm = reverse_tri; break;
    case SK_QUAD4: case SK_QUAD8: case SK_QUAD9: perm = reverse_quad; break;
    case SK_TET4: case SK_TET10: perm = reverse_tet; break;
    case SK_HEX8: case SK_HEX20: case SK_HEX27: perm = reverse_hex; break;
    default: return; /* points */
  }
  const int nen = sk_elem_nen(type);
  int copy[SK_MAX_NEN];
  memcpy(copy, conn, (size_t)nen * sizeof *conn);
  for (int a = 0; a < nen; ++a) conn[a] = copy[perm[a]];
}

static void sub(const double *a, const double *b, double *d) {
  for (int i = 0; i < 3; ++i) d[i] = a[i] - b[i];
}
static void cross(const double *a, const double *b, double *c) {
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}
static double dot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* Sign of the element's orientation measured from its corners (0 when not handled). */
static double body_orientation(const sk_mesh *mesh, const sk_group *group, const int *conn) {
  const double *x[8];
  const int corners = sk_elem_corners(group->type);
  for (int a = 0; a < corners && a < 8; ++a) x[a] = mesh->x + 3 * conn[a];
  double d1[3], d2[3], d3[3], n[3];
  switch (group->type) {
    case SK_TRI3: case SK_TRI6: case SK_QUAD4: case SK_QUAD8: case SK_QUAD9: {
      double twice = 0; /* shoelace over the corners */
      for (int a = 0; a < corners; ++a) {
        int b = (a + 1) % corners;
        twice += x[a][0] * x[b][1] - x[b][0] * x[a][1];
      }
      return twice;
    }
    case SK_TET4: case SK_TET10:
      sub(x[1], x[0], d1), sub(x[2], x[0], d2), sub(x[3], x[0], d3);
      cross(d1, d2, n);
      return dot(n, d3);
    case SK_HEX8: case SK_HEX20: case SK_HEX27: {
      /* bottom face normal (by its diagonals) against the direction to the top face */
      double up[3] = {0, 0, 0};
      sub(x[2], x[0], d1), sub(x[3], x[1], d2);
      cross(d1, d2, n);
      for (int a = 0; a < 4; ++a)
        for (int i = 0; i < 3; ++i) up[i] += (x[a + 4][i] - x[a][i]) / 4;
      return dot(n, up);
    }
    default: return 0;
  }
}

/* Normal of a boundary element from its corners (not normalised); 2D edges in the plane z = 0 use (t_y, -t_x). */
static void face_normal(const sk_mesh *mesh, sk_elem_type type, const int *conn, double *n) {
  const double *x0 = mesh->x + 3 * conn[0], *x1 = mesh->x + 3 * conn[1];
  double d1[3], d2[3];
  n[0] = n[1] = n[2] = 0;
  switch (type) {
    case SK_LINE2: case SK_LINE3:
      n[0] = x1[1] - x0[1];
      n[1] = -(x1[0] - x0[0]);
      break;
    case SK_TRI3: case SK_TRI6:
      sub(x1, x0, d1), sub(mesh->x + 3 * conn[2], x0, d2);
      cross(d1, d2, n);
      break;
    case SK_QUAD4: case SK_QUAD8: case SK_QUAD9:
      sub(mesh->x + 3 * conn[2], x0, d1), sub(mesh->x + 3 * conn[3], x1, d2);
      cross(d1, d2, n);
      break;
    default: break;
  }
}

/* Corners of the boundary elements the orientation handles (lines, triangles, quads); 0 for others. */
static int face_corner_count(sk_elem_type type) {
  return sk_elem_pdim(type) == 1 || sk_elem_pdim(type) == 2 ? sk_elem_corners(type) : 0;
}

sk_status sk_mesh_orient(sk_mesh *mesh) {
  int body_elems = 0;
  for (int g = 0; g < mesh->n_groups; ++g) {
    sk_group *group = &mesh->groups[g];
    if (group->dim != mesh->dim) continue;
    body_elems += group->n_elems;
    for (int e = 0; e < group->n_elems; ++e) {
      int *conn = group->conn + (size_t)e * (size_t)group->nen;
      if (body_orientation(mesh, group, conn) < 0) reverse_element(group->type, conn);
    }
  }
  if (body_elems == 0) return SK_OK;

  /* node -> body elements (CSR over corner nodes), to find the body element under each boundary element */
  int *start = calloc((size_t)mesh->n_nodes + 1, sizeof *start);
  if (!start) return sk_error_set(SK_ERR_NOMEM, "mesh %s: out of memory orienting faces", mesh->source);
  for (int g = 0; g < mesh->n_groups; ++g) {
    const sk_group *group = &mesh->groups[g];
    if (group->dim != mesh->dim) continue;
    for (int e = 0; e < group->n_elems; ++e)
      for (int a = 0; a < sk_elem_corners(group->type); ++a) ++start[group->conn[(size_t)e * group->nen + a] + 1];
  }
  for (int n = 0; n < mesh->n_nodes; ++n) start[n + 1] += start[n];
  int *fill = malloc(((size_t)mesh->n_nodes + 1) * sizeof *fill);
  int *entry = malloc(((size_t)start[mesh->n_nodes] + 1) * 2 * sizeof *entry); /* (group, element) pairs */
  if (!fill || !entry) {
    free(start), free(fill), free(entry);
    return sk_error_set(SK_ERR_NOMEM, "mesh %s: out of memory orienting faces", mesh->source);
  }
  memcpy(fill, start, (size_t)mesh->n_nodes * sizeof *fill);
  for (int g = 0; g < mesh->n_groups; ++g) {
    const sk_group *group = &mesh->groups[g];
    if (group->dim != mesh->dim) continue;
    for (int e = 0; e < group->n_elems; ++e)
      for (int a = 0; a < sk_elem_corners(group->type); ++a) {
        int k = fill[group->conn[(size_t)e * group->nen + a]]++;
        entry[2 * k] = g, entry[2 * k + 1] = e;
      }
  }

  for (int f = 0; f < mesh->n_groups; ++f) {
    sk_group *faces = &mesh->groups[f];
    int corners = face_corner_count(faces->type);
    if (faces->dim != mesh->dim - 1 || corners == 0) continue;
    for (int e = 0; e < faces->n_elems; ++e) {
      int *conn = faces->conn + (size_t)e * faces->nen;
      for (int k = start[conn[0]]; k < start[conn[0] + 1]; ++k) {
        const sk_group *body = &mesh->groups[entry[2 * k]];
        const int *body_conn = body->conn + (size_t)entry[2 * k + 1] * body->nen;
        int body_corners = sk_elem_corners(body->type), shared = 0;
        for (int a = 0; a < corners; ++a)
          for (int b = 0; b < body_corners; ++b) shared += conn[a] == body_conn[b];
        if (shared < corners) continue;
        /* outward: the normal points from the body element's centroid towards the face */
        double face_centre[3] = {0, 0, 0}, body_centre[3] = {0, 0, 0}, n[3], out[3];
        for (int a = 0; a < corners; ++a)
          for (int i = 0; i < 3; ++i) face_centre[i] += mesh->x[3 * conn[a] + i] / corners;
        for (int b = 0; b < body_corners; ++b)
          for (int i = 0; i < 3; ++i) body_centre[i] += mesh->x[3 * body_conn[b] + i] / body_corners;
        sub(face_centre, body_centre, out);
        face_normal(mesh, faces->type, conn, n);
        if (dot(n, out) < 0) reverse_element(faces->type, conn);
        break;
      }
    }
  }
  free(start);
  free(fill);
  free(entry);
  return SK_OK;
}
