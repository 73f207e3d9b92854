/* torus.geo: the structured hollow torus. Counts, no duplicate nodes at the seams of the four quarter sweeps,
 * positive Jacobians, volume, and skins on the right radii; the default mesh has 8024 hexahedra. */
#include <math.h>
#include <stdlib.h>

#include "mesh_measure.h"
#include "sk_test.h"
#include "stickslip/mesh.h"

#define PI 3.14159265358979323846

/* Distance of x from the tube's centre circle (radius R about the axis through c parallel to z). */
static double tube_distance(const double *x, const double *c, double R) {
  double rho = hypot(x[0] - c[0], x[1] - c[1]);
  return hypot(rho - R, x[2] - c[2]);
}

/* Number of node pairs closer than tol: sort by x, compare neighbours within tol in x. */
static const double *sort_coords;
static int compare_index_by_x(const void *a, const void *b) {
  double xa = sort_coords[3 * *(const int *)a], xb = sort_coords[3 * *(const int *)b];
  return (xa > xb) - (xa < xb);
}

static int count_coincident_nodes(const sk_mesh *mesh, double tol) {
  int *order = malloc((size_t)mesh->n_nodes * sizeof *order);
  for (int i = 0; i < mesh->n_nodes; ++i) order[i] = i;
  sort_coords = mesh->x;
  qsort(order, (size_t)mesh->n_nodes, sizeof *order, compare_index_by_x);
  int pairs = 0;
  for (int i = 0; i < mesh->n_nodes; ++i) {
    const double *a = mesh->x + 3 * order[i];
    for (int j = i + 1; j < mesh->n_nodes; ++j) {
      const double *b = mesh->x + 3 * order[j];
      if (b[0] - a[0] > tol) break;
      pairs += hypot(hypot(a[0] - b[0], a[1] - b[1]), a[2] - b[2]) <= tol;
    }
  }
  free(order);
  return pairs;
}

static void check_torus(const sk_mesh_param *params, int n_params, int n_around, int n_tube, int n_wall, double R,
                        double r_outer, double r_inner, const double *centre, double volume_tol) {
  sk_mesh mesh;
  sk_status status = sk_mesh_load("meshes/torus.geo", params, n_params, 0, &mesh);
  if (status != SK_OK) fprintf(stderr, "%s\n", sk_error_message());
  SK_CHECK(status == SK_OK);
  if (status != SK_OK) return;
  const int n_elems = n_around * n_tube * n_wall;
  SK_CHECK(mesh.dim == 3);
  SK_CHECK(mesh.n_groups == 3);
  SK_CHECK(mesh.n_nodes == n_around * n_tube * (n_wall + 1)); /* a closed structured grid: seams shared */
  SK_CHECK(count_coincident_nodes(&mesh, 1e-6 * R) == 0);

  const sk_group *body = sk_mesh_find_group(&mesh, "body");
  const sk_group *outer = sk_mesh_find_group(&mesh, "outer");
  const sk_group *inner = sk_mesh_find_group(&mesh, "inner");
  SK_CHECK(body && outer && inner);
  if (body && outer && inner) {
    SK_CHECK(body->type == SK_HEX8 && body->n_elems == n_elems && body->dim == 3);
    SK_CHECK(outer->type == SK_QUAD4 && outer->n_elems == n_around * n_tube && outer->dim == 2);
    SK_CHECK(inner->type == SK_QUAD4 && inner->n_elems == n_around * n_tube);

    double X[24], lowest = INFINITY;
    for (int e = 0; e < body->n_elems; ++e) {
      element_coords(&mesh, body, e, X);
      lowest = fmin(lowest, hex8_min_corner_det(X));
    }
    SK_CHECK(lowest > 0);
    /* exact 2 pi^2 R (ro^2 - ri^2); the faceted mesh is slightly smaller */
    double exact = 2 * PI * PI * R * (r_outer * r_outer - r_inner * r_inner);
    double volume = group_measure(&mesh, body, NULL);
    SK_CHECK(volume < exact);
    SK_CHECK_CLOSE(volume, exact, volume_tol);

    int *nodes = NULL, n = 0;
    double worst_outer = 0, worst_inner = 0;
    SK_CHECK(sk_group_nodes(outer, &nodes, &n) == SK_OK);
    SK_CHECK(n == n_around * n_tube);
    for (int k = 0; k < n; ++k) worst_outer = fmax(worst_outer, fabs(tube_distance(mesh.x + 3 * nodes[k], centre, R) - r_outer));
    free(nodes);
    SK_CHECK(sk_group_nodes(inner, &nodes, &n) == SK_OK);
    for (int k = 0; k < n; ++k) worst_inner = fmax(worst_inner, fabs(tube_distance(mesh.x + 3 * nodes[k], centre, R) - r_inner));
    free(nodes);
    SK_CHECK(worst_outer < 1e-9 * R);
    /* skins face out of the wall: outer away from the tube's centre circle, inner towards it */
    double worst_alignment[2] = {INFINITY, INFINITY};
    for (int s = 0; s < 2; ++s) {
      const sk_group *skin = s == 0 ? outer : inner;
      for (int e = 0; e < skin->n_elems; ++e) {
        double nrm[3], c[3], foot[3], d[3];
        boundary_normal(&mesh, skin, e, nrm, c);
        double rho = hypot(c[0] - centre[0], c[1] - centre[1]);
        foot[0] = centre[0] + R * (c[0] - centre[0]) / rho, foot[1] = centre[1] + R * (c[1] - centre[1]) / rho;
        foot[2] = centre[2];
        for (int i = 0; i < 3; ++i) d[i] = (s == 0 ? 1 : -1) * (c[i] - foot[i]);
        double alignment = (nrm[0] * d[0] + nrm[1] * d[1] + nrm[2] * d[2]) / hypot(hypot(d[0], d[1]), d[2]);
        worst_alignment[s] = fmin(worst_alignment[s], alignment);
      }
    }
    SK_CHECK(worst_alignment[0] > 0.8);
    SK_CHECK(worst_alignment[1] > 0.8);
    SK_CHECK(worst_inner < 1e-9 * R);
  }
  sk_mesh_free(&mesh);
}

int main(void) {
  /* CI setting: refine 0.25 gives 30 x 9 x 1 = 270 hexahedra, moved off the origin. */
  const double centre[3] = {10, -5, 3};
  const sk_mesh_param coarse[] = {{"refine", 0.25}, {"cx", 10}, {"cy", -5}, {"cz", 3}};
  check_torus(coarse, 4, 30, 9, 1, 76, 24, 19.5, centre, 0.1);
  /* other radii, counts not multiples of 4 */
  const double origin[3] = {0, 0, 0};
  const sk_mesh_param custom[] = {{"R", 3}, {"r_outer", 1}, {"r_inner", 0.5}, {"n_around", 13}, {"n_tube", 7},
                                  {"n_wall", 2}};
  check_torus(custom, 6, 13, 7, 2, 3, 1, 0.5, origin, 0.25); /* 1 or 2 divisions per quarter: coarse facets */
  /* the default: 118 x 34 x 2 = 8024 hexahedra */
  check_torus(NULL, 0, 118, 34, 2, 76, 24, 19.5, origin, 0.01);
  return sk_test_finish("test_mesh_torus");
}
