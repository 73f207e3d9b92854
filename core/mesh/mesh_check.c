/* Element checks after loading: what gmsh accepts but a finite element run cannot use, found here with the file,
 * group and element named, instead of deep in a kernel ("hex8 element: reference Jacobian det J = nan") or not at
 * all (a collapsed hex runs, with a wrong energy; two bodies on one group double the stiffness) — issue 15, items 9,
 * 13, 14. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_internal.h"

/* "element 3 of physical group 'block' (first node at (0, 1, 0))" */
static void describe(const sk_mesh *mesh, const sk_group *group, int e, char *out, size_t n) {
  const double *x = mesh->x + 3 * (size_t)group->conn[(size_t)e * (size_t)group->nen];
  snprintf(out, n, "mesh %s: physical group '%s', element %d (of %d; first node at (%g, %g, %g))", mesh->source,
           group->name, e, group->n_elems, x[0], x[1], x[2]);
}

static double det3(const double *a, const double *b, const double *c) {
  return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
}

/* Corners of a body element and, per corner, its neighbours in the order that makes the corner's Jacobian
 * positive for a well-shaped element in gmsh's node ordering. The corners come first in every gmsh element, so
 * second-order elements share the pattern of their first-order one. */
typedef struct {
  int corners, dim;
  int next[8][3];
} corner_pattern;

static const corner_pattern triangle = {3, 2, {{1, 2}, {2, 0}, {0, 1}}};
static const corner_pattern quadrangle = {4, 2, {{1, 3}, {2, 0}, {3, 1}, {0, 2}}};
static const corner_pattern tetrahedron = {4, 3, {{1, 2, 3}, {2, 0, 3}, {0, 1, 3}, {0, 2, 1}}};
static const corner_pattern hexahedron = {
    8, 3, {{1, 3, 4}, {2, 0, 5}, {3, 1, 6}, {0, 2, 7}, {7, 5, 0}, {4, 6, 1}, {5, 7, 2}, {6, 4, 3}}};

static const corner_pattern *pattern_of(const sk_group *group) {
  if (group->dim == 2) return group->nen == 3 || group->nen == 6 ? &triangle : &quadrangle;
  if (group->dim == 3) return group->nen == 4 || group->nen == 10 ? &tetrahedron : &hexahedron;
  return NULL;
}

/* The Jacobian at each corner, relative to the cube (square) of the element's longest corner edge: 1 for a cube,
 * 0 for a flat corner, negative for an inverted one. Returns the worst corner. */
static int worst_corner(const sk_mesh *mesh, const corner_pattern *p, const int *conn, double *worst) {
  int at = 0;
  *worst = INFINITY;
  for (int a = 0; a < p->corners; ++a) {
    const double *x0 = mesh->x + 3 * (size_t)conn[a];
    double e[3][3] = {{0}}, longest = 0;
    for (int k = 0; k < p->dim; ++k) {
      const double *xk = mesh->x + 3 * (size_t)conn[p->next[a][k]];
      for (int i = 0; i < 3; ++i) e[k][i] = xk[i] - x0[i];
      longest = fmax(longest, sqrt(e[k][0] * e[k][0] + e[k][1] * e[k][1] + e[k][2] * e[k][2]));
    }
    double J = p->dim == 2 ? e[0][0] * e[1][1] - e[0][1] * e[1][0] : det3(e[0], e[1], e[2]);
    double relative = J / pow(longest, p->dim);
    if (!(relative >= *worst)) { /* also catches nan */
      *worst = relative;
      at = a;
    }
  }
  return at;
}

/* A well-shaped corner has a relative Jacobian of order 1 (a cube: 1), a flat one 0 up to round-off (~1e-16):
 * 1e-10 separates them and still admits stretched elements up to an aspect ratio of ~1e5 (2D) or ~1e3 (3D, two
 * short edges). */
static const double flat_corner = 1e-10;

sk_status sk_mesh_check_elements(const sk_mesh *mesh) {
  for (int n = 0; n < mesh->n_nodes; ++n)
    for (int i = 0; i < 3; ++i)
      if (!isfinite(mesh->x[3 * n + i]))
        return sk_error_set(SK_ERR_INPUT, "mesh %s: node %d has a non-finite coordinate (%g, %g, %g)", mesh->source,
                            n, mesh->x[3 * n], mesh->x[3 * n + 1], mesh->x[3 * n + 2]);
  char where[1024];
  for (int g = 0; g < mesh->n_groups; ++g) {
    const sk_group *group = &mesh->groups[g];
    const corner_pattern *pattern = group->dim == mesh->dim ? pattern_of(group) : NULL;
    for (int e = 0; e < group->n_elems; ++e) {
      const int *conn = group->conn + (size_t)e * (size_t)group->nen;
      for (int a = 0; a < group->nen; ++a)
        for (int b = a + 1; b < group->nen; ++b)
          if (conn[a] == conn[b]) {
            describe(mesh, group, e, where, sizeof where);
            return sk_error_set(SK_ERR_INPUT, "%s: its nodes %d and %d are the same node (a collapsed element)",
                                where, a, b);
          }
      if (!pattern) continue;
      double worst;
      int corner = worst_corner(mesh, pattern, conn, &worst);
      if (!(worst > flat_corner)) {
        describe(mesh, group, e, where, sizeof where);
        const double *x = mesh->x + 3 * (size_t)conn[corner];
        return sk_error_set(SK_ERR_INPUT, "%s: %s at corner %d (%g, %g, %g): its Jacobian there is %.3g times the "
                            "cube of its longest edge", where, worst < 0 ? "inverted (twisted)" : "degenerate (flat)",
                            corner, x[0], x[1], x[2], worst);
      }
    }
  }
  return SK_OK;
}

/* ---- elements used twice -------------------------------------------------------------------------------------- */

typedef struct {
  int *nodes; /* sorted, padded with -1 to `width` */
  int group, element;
} element_key;

static int key_width;

static int compare_ints(const void *a, const void *b) {
  int x = *(const int *)a, y = *(const int *)b;
  return (x > y) - (x < y);
}

static int compare_keys(const void *a, const void *b) {
  const element_key *x = a, *y = b;
  int c = memcmp(x->nodes, y->nodes, sizeof(int) * (size_t)key_width); /* any total order will do */
  return c ? c : (x->group > y->group) - (x->group < y->group);
}

sk_status sk_mesh_check_disjoint(const sk_mesh *mesh, const sk_group *const *groups, const char *const *names, int n) {
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      if (groups[i] == groups[j])
        return sk_error_set(SK_ERR_INPUT, "%s and %s both use physical group '%s' of mesh %s: its elements would "
                            "count twice (give each body its own group)", names[i], names[j], groups[i]->name,
                            mesh->source);
  size_t total = 0;
  int width = 1;
  for (int i = 0; i < n; ++i) {
    total += (size_t)groups[i]->n_elems;
    if (groups[i]->nen > width) width = groups[i]->nen;
  }
  element_key *keys = malloc((total + 1) * sizeof *keys);
  int *storage = malloc((total + 1) * (size_t)width * sizeof *storage);
  if (!keys || !storage) {
    free(keys);
    free(storage);
    return sk_error_set(SK_ERR_NOMEM, "out of memory checking the bodies of mesh %s", mesh->source);
  }
  size_t k = 0;
  for (int i = 0; i < n; ++i)
    for (int e = 0; e < groups[i]->n_elems; ++e, ++k) {
      int *nodes = storage + k * (size_t)width;
      for (int a = 0; a < width; ++a) nodes[a] = a < groups[i]->nen ? groups[i]->conn[(size_t)e * groups[i]->nen + a] : -1;
      qsort(nodes, (size_t)groups[i]->nen, sizeof *nodes, compare_ints);
      keys[k] = (element_key){nodes, i, e};
    }
  key_width = width;
  qsort(keys, total, sizeof *keys, compare_keys);
  sk_status status = SK_OK;
  for (size_t m = 1; m < total && status == SK_OK; ++m) {
    if (memcmp(keys[m - 1].nodes, keys[m].nodes, sizeof(int) * (size_t)width) != 0) continue;
    const element_key *a = &keys[m - 1], *b = &keys[m];
    char where[1024];
    describe(mesh, groups[b->group], b->element, where, sizeof where);
    if (a->group == b->group)
      status = sk_error_set(SK_ERR_INPUT, "%s (used by %s) is listed twice in the group (also as element %d): it "
                            "would count twice", where, names[a->group], a->element);
    else
      status = sk_error_set(SK_ERR_INPUT, "%s is also element %d of physical group '%s': %s and %s overlap, so these "
                            "elements would count twice", where, a->element, groups[a->group]->name,
                            names[a->group], names[b->group]);
  }
  free(keys);
  free(storage);
  return status;
}
