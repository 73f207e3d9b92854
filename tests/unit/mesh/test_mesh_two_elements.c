/* meshes/two-elements.msh: the two hexahedra of Franke, Hesch & Betsch (Table I), read from a .msh file. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_measure.h"
#include "sk_test.h"
#include "stickslip/mesh.h"

/* Paper node coordinates, nodes 1..16 (1-8 upper block, 9-16 lower block). */
static const double paper[16][3] = {
    {-0.5, -1, 2.1}, {-0.5, 0, 2.1}, {-0.5, -1, 1.1}, {-0.5, 0, 1.1}, {0.5, -1, 2.1}, {0.5, 0, 2.1},
    {0.5, -1, 1.1},  {0.5, 0, 1.1},  {-1, -1, 1},     {-1.5, 1.5, 1}, {-1, -1, 0},    {-1.5, 1.5, 0},
    {1, -1, 1},      {1.2, 1, 1},    {1, -1, 0},      {1.2, 1, 0}};

/* Outward unit-free normal of a quad4 face from its first three corners. */
static double face_normal_z(const sk_mesh *mesh, const sk_group *face) {
  const double *a = mesh->x + 3 * face->conn[0], *b = mesh->x + 3 * face->conn[1], *c = mesh->x + 3 * face->conn[3];
  return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/* Whether this process maps a library whose path contains `name` (/proc/self/maps). */
static int maps_library(const char *name) {
  FILE *maps = fopen("/proc/self/maps", "r");
  if (!maps) return -1;
  char line[4096];
  int found = 0;
  while (!found && fgets(line, sizeof line, maps)) found = strstr(line, name) != NULL;
  fclose(maps);
  return found;
}

int main(void) {
  /* gmsh is loaded only by the mesh generator's child (core/mesh/mesh_load.c): not before a load, not after it */
  SK_CHECK(maps_library("libgmsh") == 0);
  sk_mesh mesh;
  sk_status status = sk_mesh_load("meshes/two-elements.msh", NULL, 0, 0, &mesh);
  if (status != SK_OK) fprintf(stderr, "%s\n", sk_error_message());
  SK_CHECK(status == SK_OK);
  if (status != SK_OK) return sk_test_finish("test_mesh_two_elements");
  SK_CHECK(maps_library("libgmsh") == 0);
  SK_CHECK(maps_library("libTKernel") == 0); /* OpenCASCADE, which gmsh links */

  SK_CHECK(mesh.dim == 3);
  SK_CHECK(mesh.n_nodes == 16);
  SK_CHECK(mesh.n_groups == 4);
  /* compact ids follow the file's node tags, which are the paper's numbers: id = paper number - 1 */
  for (int n = 0; n < 16 && mesh.n_nodes == 16; ++n)
    for (int i = 0; i < 3; ++i) SK_CHECK_CLOSE(mesh.x[3 * n + i], paper[n][i], 1e-15);

  const sk_group *upper = sk_mesh_find_group(&mesh, "upper");
  const sk_group *lower = sk_mesh_find_group(&mesh, "lower");
  const sk_group *slave = sk_mesh_find_group(&mesh, "upper-bottom");
  const sk_group *master = sk_mesh_find_group(&mesh, "lower-top");
  SK_CHECK(upper && lower && slave && master);
  if (upper && lower && slave && master) {
    SK_CHECK(upper->type == SK_HEX8 && upper->n_elems == 1 && upper->dim == 3);
    SK_CHECK(lower->type == SK_HEX8 && lower->n_elems == 1);
    SK_CHECK(slave->type == SK_QUAD4 && slave->n_elems == 1 && slave->dim == 2);
    SK_CHECK(master->type == SK_QUAD4 && master->n_elems == 1);
    double X[24];
    element_coords(&mesh, upper, 0, X);
    SK_CHECK_CLOSE(hex8_volume(X), 1.0, 1e-12);
    SK_CHECK(hex8_min_corner_det(X) > 0);
    element_coords(&mesh, lower, 0, X);
    SK_CHECK_CLOSE(hex8_volume(X), 5.25, 1e-12);
    SK_CHECK(hex8_min_corner_det(X) > 0);
    /* the slave face is paper nodes 3, 4, 8, 7 at z = 1.1 with normal -z; the master face 9, 13, 14, 10, +z */
    const int slave_paper[4] = {3, 4, 8, 7}, master_paper[4] = {9, 13, 14, 10};
    for (int a = 0; a < 4; ++a) {
      SK_CHECK(slave->conn[a] == slave_paper[a] - 1);
      SK_CHECK(master->conn[a] == master_paper[a] - 1);
    }
    SK_CHECK(face_normal_z(&mesh, slave) < 0);
    SK_CHECK(face_normal_z(&mesh, master) > 0);
  }
  sk_mesh_free(&mesh);
  return sk_test_finish("test_mesh_two_elements");
}
