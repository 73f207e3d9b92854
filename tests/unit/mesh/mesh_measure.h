/* Independent element measures for the mesh tests (deliberately not core/fe, so the mesh tests stand alone):
 * hex8 volume and corner Jacobians, tet4 volume, quad4/quad9/tri3 area in the plane z = 0. gmsh node ordering. */
#ifndef MESH_MEASURE_H
#define MESH_MEASURE_H

#include <math.h>

#include "stickslip/mesh.h"

/* det of the trilinear hex8 map at parametric point xi (gmsh ordering: corners (-1,-1,-1), (1,-1,-1), (1,1,-1),
 * (-1,1,-1), then the same at zeta = +1). */
static inline double hex8_det(const double *X, const double *xi) {
  static const double corner[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                      {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  double J[3][3] = {{0}};
  for (int a = 0; a < 8; ++a) {
    double f[3];
    for (int k = 0; k < 3; ++k) f[k] = 1 + corner[a][k] * xi[k];
    double dN[3] = {corner[a][0] * f[1] * f[2] / 8, corner[a][1] * f[0] * f[2] / 8, corner[a][2] * f[0] * f[1] / 8};
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) J[i][k] += X[3 * a + i] * dN[k];
  }
  return J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) - J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
         J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
}

static inline double hex8_volume(const double *X) {
  const double g = 1 / sqrt(3.0);
  double volume = 0;
  for (int q = 0; q < 8; ++q) {
    double xi[3] = {(q & 1) ? g : -g, (q & 2) ? g : -g, (q & 4) ? g : -g};
    volume += hex8_det(X, xi);
  }
  return volume;
}

/* Smallest Jacobian determinant over the eight corners (positive for a valid, positively oriented hex). */
static inline double hex8_min_corner_det(const double *X) {
  double lowest = INFINITY;
  for (int c = 0; c < 8; ++c) {
    double xi[3] = {(c == 1 || c == 2 || c == 5 || c == 6) ? 1 : -1, (c == 2 || c == 3 || c == 6 || c == 7) ? 1 : -1,
                    c >= 4 ? 1 : -1};
    lowest = fmin(lowest, hex8_det(X, xi));
  }
  return lowest;
}

static inline double tet4_volume(const double *X) {
  double a[3], b[3], c[3];
  for (int i = 0; i < 3; ++i) a[i] = X[3 + i] - X[i], b[i] = X[6 + i] - X[i], c[i] = X[9 + i] - X[i];
  return (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0])) /
         6;
}

/* Signed area of the polygon through the first n nodes (the corners of a straight-sided tri3/quad4/quad9). */
static inline double polygon_area(const double *X, int n) {
  double twice = 0;
  for (int a = 0; a < n; ++a) {
    int b = (a + 1) % n;
    twice += X[3 * a] * X[3 * b + 1] - X[3 * b] * X[3 * a + 1];
  }
  return twice / 2;
}

/* Element coordinates packed 3 per node. */
static inline void element_coords(const sk_mesh *mesh, const sk_group *group, int e, double *X) {
  for (int a = 0; a < group->nen; ++a)
    for (int i = 0; i < 3; ++i) X[3 * a + i] = mesh->x[3 * group->conn[e * group->nen + a] + i];
}

/* Total volume (3D bodies) or area (2D bodies); *min_measure gets the smallest element measure. */
static inline double group_measure(const sk_mesh *mesh, const sk_group *group, double *min_measure) {
  double X[27 * 3], total = 0, lowest = INFINITY;
  for (int e = 0; e < group->n_elems; ++e) {
    element_coords(mesh, group, e, X);
    double m = 0;
    switch (group->type) {
      case SK_HEX8: m = hex8_volume(X); break;
      case SK_TET4: m = tet4_volume(X); break;
      case SK_TRI3: m = polygon_area(X, 3); break;
      case SK_QUAD4: case SK_QUAD9: m = polygon_area(X, 4); break;
      default: m = NAN; break;
    }
    total += m;
    lowest = fmin(lowest, m);
  }
  if (min_measure) *min_measure = lowest;
  return total;
}

/* Unit normal of a boundary element from its corners: (t_y, -t_x) for lines in the plane z = 0, the right-hand
 * normal of the corner loop for triangles and quads. Also its centroid (corners). */
static inline void boundary_normal(const sk_mesh *mesh, const sk_group *group, int e, double *n, double *centre) {
  const int *c = group->conn + e * group->nen;
  const double *x0 = mesh->x + 3 * c[0], *x1 = mesh->x + 3 * c[1];
  int corners = group->type == SK_TRI3 ? 3 : (group->type == SK_QUAD4 || group->type == SK_QUAD9) ? 4 : 2;
  if (corners == 2) {
    n[0] = x1[1] - x0[1], n[1] = x0[0] - x1[0], n[2] = 0;
  } else {
    const double *p = mesh->x + 3 * c[corners == 3 ? 0 : 0], *q = mesh->x + 3 * c[corners == 3 ? 1 : 1];
    const double *r = mesh->x + 3 * c[2], *s = mesh->x + 3 * c[corners == 3 ? 0 : 3];
    /* triangle: (x1 - x0) x (x2 - x0); quad: diagonals (x2 - x0) x (x3 - x1) */
    double a[3], b[3];
    for (int i = 0; i < 3; ++i) {
      a[i] = corners == 3 ? q[i] - p[i] : r[i] - p[i];
      b[i] = corners == 3 ? r[i] - p[i] : s[i] - q[i];
    }
    n[0] = a[1] * b[2] - a[2] * b[1], n[1] = a[2] * b[0] - a[0] * b[2], n[2] = a[0] * b[1] - a[1] * b[0];
  }
  double length = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (int i = 0; i < 3; ++i) n[i] /= length;
  for (int i = 0; i < 3; ++i) {
    centre[i] = 0;
    for (int a = 0; a < corners; ++a) centre[i] += mesh->x[3 * c[a] + i] / corners;
  }
}

/* Smallest n . d over the group's elements, d = the unit vector `direction`, or, when `origin` is given, the unit
 * vector from origin to the element's centroid (sign -1 flips it, for normals that point at the origin). */
static inline double min_normal_alignment(const sk_mesh *mesh, const sk_group *group, const double *direction,
                                          const double *origin, double sign) {
  double lowest = INFINITY;
  for (int e = 0; e < group->n_elems; ++e) {
    double n[3], c[3], d[3];
    boundary_normal(mesh, group, e, n, c);
    for (int i = 0; i < 3; ++i) d[i] = origin ? sign * (c[i] - origin[i]) : direction[i];
    double length = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    lowest = fmin(lowest, (n[0] * d[0] + n[1] * d[1] + n[2] * d[2]) / length);
  }
  return lowest;
}

#endif
