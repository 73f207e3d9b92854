#define _DEFAULT_SOURCE /* mkdtemp */
/* The meshes/ scripts load at coarse settings with the documented groups, element types, counts and measures. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "mesh_measure.h"

#define PI 3.14159265358979323846
#include "sk_test.h"
#include "stickslip/mesh.h"

static int load(const char *path, const sk_mesh_param *params, int n_params, sk_mesh *mesh) {
  sk_status status = sk_mesh_load(path, params, n_params, 0, mesh);
  if (status != SK_OK) fprintf(stderr, "loading %s failed: %s\n", path, sk_error_message());
  SK_CHECK(status == SK_OK);
  return status == SK_OK;
}

/* The group exists with that dimension, type and element count (count < 0: any). */
static const sk_group *expect_group(const sk_mesh *mesh, const char *name, int dim, sk_elem_type type, int count) {
  const sk_group *group = NULL;
  sk_status status = sk_mesh_require_group(mesh, name, dim, &group);
  if (status != SK_OK) fprintf(stderr, "%s\n", sk_error_message());
  SK_CHECK(status == SK_OK);
  if (!group) return NULL;
  SK_CHECK(group->type == type);
  if (count >= 0 && group->n_elems != count)
    fprintf(stderr, "%s: group %s has %d elements, expected %d\n", mesh->source, name, group->n_elems, count);
  SK_CHECK(count < 0 || group->n_elems == count);
  return group;
}

/* Largest |value(node) - target| over the nodes of a group, value = coordinate `axis` or, with axis < 0, the
 * distance from (cx, cy). */
static double group_deviation(const sk_mesh *mesh, const sk_group *group, int axis, double cx, double cy,
                              double target) {
  int *nodes = NULL, n = 0;
  SK_CHECK(sk_group_nodes(group, &nodes, &n) == SK_OK);
  double worst = 0;
  for (int k = 0; k < n; ++k) {
    const double *x = mesh->x + 3 * nodes[k];
    double value = axis >= 0 ? x[axis] : hypot(x[0] - cx, x[1] - cy);
    worst = fmax(worst, fabs(value - target));
  }
  free(nodes);
  return worst;
}

static void test_block(void) {
  sk_mesh mesh;
  if (!load("meshes/block.geo", NULL, 0, &mesh)) return;
  SK_CHECK(mesh.dim == 3);
  SK_CHECK(mesh.n_groups == 7);
  SK_CHECK(mesh.n_nodes == 125);
  double min_volume;
  const sk_group *body = expect_group(&mesh, "body", 3, SK_HEX8, 64);
  if (body) SK_CHECK_CLOSE(group_measure(&mesh, body, &min_volume), 1.0, 1e-12);
  const char *faces[6] = {"xmin", "xmax", "ymin", "ymax", "zmin", "zmax"};
  for (int f = 0; f < 6; ++f) {
    const sk_group *face = expect_group(&mesh, faces[f], 2, SK_QUAD4, 16);
    if (face) SK_CHECK(group_deviation(&mesh, face, f / 2, 0, 0, f % 2 ? 1.0 : 0.0) < 1e-12);
    double outward[3] = {0, 0, 0};
    outward[f / 2] = f % 2 ? 1 : -1;
    if (face) SK_CHECK(min_normal_alignment(&mesh, face, outward, NULL, 1) > 1 - 1e-12); /* faces point out */
  }
  sk_mesh_free(&mesh);

  const sk_mesh_param params[] = {{"refine", 2}, {"lx", 2}, {"nz", 1}, {"z0", -1}};
  if (!load("meshes/block.geo", params, 4, &mesh)) return;
  body = expect_group(&mesh, "body", 3, SK_HEX8, 8 * 8 * 2);
  if (body) {
    SK_CHECK_CLOSE(group_measure(&mesh, body, &min_volume), 2.0, 1e-12);
    SK_CHECK(min_volume > 0);
  }
  const sk_group *zmin = expect_group(&mesh, "zmin", 2, SK_QUAD4, 64);
  if (zmin) SK_CHECK(group_deviation(&mesh, zmin, 2, 0, 0, -1.0) < 1e-12);
  sk_mesh_free(&mesh);
}

static void test_block_2d(void) {
  sk_mesh mesh;
  if (!load("meshes/block-2d.geo", NULL, 0, &mesh)) return;
  SK_CHECK(mesh.dim == 2);
  SK_CHECK(mesh.n_nodes == 25);
  const sk_group *body = expect_group(&mesh, "body", 2, SK_QUAD4, 16);
  double min_area;
  if (body) {
    SK_CHECK_CLOSE(group_measure(&mesh, body, &min_area), 1.0, 1e-12);
    SK_CHECK(min_area > 0); /* counter-clockwise quads */
  }
  const char *edges[4] = {"left", "right", "bottom", "top"};
  for (int e = 0; e < 4; ++e) {
    const sk_group *edge = expect_group(&mesh, edges[e], 1, SK_LINE2, 4);
    if (edge) SK_CHECK(group_deviation(&mesh, edge, e / 2, 0, 0, e % 2 ? 1.0 : 0.0) < 1e-12);
    double outward[3] = {0, 0, 0};
    outward[e / 2] = e % 2 ? 1 : -1;
    if (edge) SK_CHECK(min_normal_alignment(&mesh, edge, outward, NULL, 1) > 1 - 1e-12);
  }
  sk_mesh_free(&mesh);

  const sk_mesh_param quadratic[] = {{"order", 2}, {"nx", 3}, {"ly", 2}};
  if (!load("meshes/block-2d.geo", quadratic, 3, &mesh)) return;
  SK_CHECK(mesh.n_nodes == 7 * 9);
  body = expect_group(&mesh, "body", 2, SK_QUAD9, 12);
  if (body) SK_CHECK_CLOSE(group_measure(&mesh, body, NULL), 2.0, 1e-12);
  expect_group(&mesh, "top", 1, SK_LINE3, 3);
  expect_group(&mesh, "left", 1, SK_LINE3, 4);
  sk_mesh_free(&mesh);
}

static void test_disk_and_ring(void) {
  sk_mesh mesh;
  const sk_mesh_param disk[] = {{"radius", 2}, {"cx", 1}};
  if (load("meshes/disk.geo", disk, 2, &mesh)) {
    double min_area;
    const sk_group *body = expect_group(&mesh, "body", 2, SK_QUAD4, 192);
    /* straight-sided quads: the area of the inscribed 32-gon, 0.64 % below the circle's */
    if (body) {
      SK_CHECK_CLOSE(group_measure(&mesh, body, &min_area), 16 * 4.0 * sin(2 * PI / 32), 1e-9);
      SK_CHECK(min_area > 0);
    }
    const sk_group *rim = expect_group(&mesh, "boundary", 1, SK_LINE2, 32);
    if (rim) SK_CHECK(group_deviation(&mesh, rim, -1, 1, 0, 2.0) < 1e-9);
    const double centre[3] = {1, 0, 0};
    if (rim) SK_CHECK(min_normal_alignment(&mesh, rim, NULL, centre, 1) > 0.99);
    sk_mesh_free(&mesh);
  }
  if (load("meshes/ring.geo", NULL, 0, &mesh)) {
    double min_area;
    const sk_group *body = expect_group(&mesh, "body", 2, SK_QUAD4, 32 * 4);
    if (body) {
      SK_CHECK_CLOSE(group_measure(&mesh, body, &min_area), 16 * (1 - 0.25) * sin(2 * PI / 32), 1e-9);
      SK_CHECK(min_area > 0);
    }
    const sk_group *inner = expect_group(&mesh, "inner", 1, SK_LINE2, 32);
    const sk_group *outer = expect_group(&mesh, "outer", 1, SK_LINE2, 32);
    if (inner) SK_CHECK(group_deviation(&mesh, inner, -1, 0, 0, 0.5) < 1e-9);
    if (outer) SK_CHECK(group_deviation(&mesh, outer, -1, 0, 0, 1.0) < 1e-9);
    const double centre[3] = {0, 0, 0};
    if (outer) SK_CHECK(min_normal_alignment(&mesh, outer, NULL, centre, 1) > 0.99);
    if (inner) SK_CHECK(min_normal_alignment(&mesh, inner, NULL, centre, -1) > 0.99); /* out of the ring: inwards */
    SK_CHECK(mesh.n_nodes == 32 * 5); /* the quarter patches share their seam nodes */
    sk_mesh_free(&mesh);
  }
}

static void test_patch_test_2d(void) {
  sk_mesh mesh;
  if (!load("meshes/patch-test-2d.geo", NULL, 0, &mesh)) return;
  const sk_group *lower = expect_group(&mesh, "lower", 2, SK_QUAD4, 8);
  const sk_group *upper = expect_group(&mesh, "upper", 2, SK_QUAD4, 10);
  expect_group(&mesh, "lower-top", 1, SK_LINE2, 4);
  expect_group(&mesh, "upper-bottom", 1, SK_LINE2, 5);
  expect_group(&mesh, "lower-bottom", 1, SK_LINE2, 4);
  expect_group(&mesh, "upper-top", 1, SK_LINE2, 5);
  const char *sides[] = {"lower-left", "lower-right", "upper-left", "upper-right"};
  for (int s = 0; s < 4; ++s) expect_group(&mesh, sides[s], 1, SK_LINE2, 2);
  if (lower && upper) {
    SK_CHECK_CLOSE(group_measure(&mesh, lower, NULL), 0.5, 1e-12);
    SK_CHECK_CLOSE(group_measure(&mesh, upper, NULL), 0.5, 1e-12);
    /* two bodies: no node may be shared across the interface */
    int *a = NULL, *b = NULL, na = 0, nb = 0, shared = 0;
    SK_CHECK(sk_group_nodes(lower, &a, &na) == SK_OK);
    SK_CHECK(sk_group_nodes(upper, &b, &nb) == SK_OK);
    for (int i = 0; i < na; ++i)
      for (int j = 0; j < nb; ++j) shared += a[i] == b[j];
    SK_CHECK(shared == 0);
    SK_CHECK(na == 15 && nb == 18 && mesh.n_nodes == 33);
    free(a);
    free(b);
  }
  sk_mesh_free(&mesh);
}

static void test_hertz(void) {
  sk_mesh mesh;
  const sk_mesh_param coarse2d[] = {{"refine", 0.5}};
  if (load("meshes/hertz-2d.geo", coarse2d, 1, &mesh)) {
    double min_area;
    const sk_group *cylinder = expect_group(&mesh, "cylinder", 2, SK_QUAD4, -1);
    const sk_group *block = expect_group(&mesh, "block", 2, SK_QUAD4, -1);
    if (cylinder) {
      SK_CHECK_CLOSE(group_measure(&mesh, cylinder, &min_area), PI / 4, 0.01);
      SK_CHECK(min_area > 0);
    }
    if (block) {
      SK_CHECK_CLOSE(group_measure(&mesh, block, &min_area), 2.0, 1e-9);
      SK_CHECK(min_area > 0);
    }
    const sk_group *arc = expect_group(&mesh, "cylinder-contact", 1, SK_LINE2, -1);
    if (arc) SK_CHECK(group_deviation(&mesh, arc, -1, 0, 1, 1.0) < 1e-9);
    const double centre[3] = {0, 1, 0}, up[3] = {0, 1, 0};
    if (arc) SK_CHECK(min_normal_alignment(&mesh, arc, NULL, centre, 1) > 0.99);
    const sk_group *top = expect_group(&mesh, "block-contact", 1, SK_LINE2, -1);
    if (top) SK_CHECK(group_deviation(&mesh, top, 1, 0, 0, 0.0) < 1e-12);
    if (top) SK_CHECK(min_normal_alignment(&mesh, top, up, NULL, 1) > 1 - 1e-12);
    expect_group(&mesh, "cylinder-top", 1, SK_LINE2, -1);
    expect_group(&mesh, "block-bottom", 1, SK_LINE2, -1);
    const sk_group *symmetry = expect_group(&mesh, "symmetry", 1, SK_LINE2, -1);
    if (symmetry) SK_CHECK(group_deviation(&mesh, symmetry, 0, 0, 0, 0.0) < 1e-12);
    sk_mesh_free(&mesh);
  }
  const sk_mesh_param coarse3d[] = {{"refine", 0.5}};
  if (load("meshes/hertz-3d.geo", coarse3d, 1, &mesh)) {
    double min_volume;
    const sk_group *sphere = expect_group(&mesh, "sphere", 3, SK_TET4, -1);
    const sk_group *block = expect_group(&mesh, "block", 3, SK_TET4, -1);
    if (sphere) {
      SK_CHECK_CLOSE(group_measure(&mesh, sphere, &min_volume), PI / 6, 0.05);
      SK_CHECK(min_volume > 0);
    }
    if (block) {
      SK_CHECK_CLOSE(group_measure(&mesh, block, &min_volume), 1.5 * 1.5 * 1.0, 1e-9);
      SK_CHECK(min_volume > 0);
    }
    const char *faces[] = {"sphere-contact", "sphere-top", "block-contact", "block-bottom", "sym-x", "sym-y"};
    for (int f = 0; f < 6; ++f) expect_group(&mesh, faces[f], 2, SK_TRI3, -1);
    const sk_group *symx = sk_mesh_find_group(&mesh, "sym-x");
    if (symx) SK_CHECK(group_deviation(&mesh, symx, 0, 0, 0, 0.0) < 1e-9);
    const sk_group *top = sk_mesh_find_group(&mesh, "sphere-top");
    if (top) SK_CHECK(group_deviation(&mesh, top, 2, 0, 0, 1.0) < 1e-9);
    const double up[3] = {0, 0, 1}, down[3] = {0, 0, -1}, centre[3] = {0, 0, 1};
    if (top) SK_CHECK(min_normal_alignment(&mesh, top, up, NULL, 1) > 1 - 1e-9);
    const sk_group *block_top = sk_mesh_find_group(&mesh, "block-contact");
    if (block_top) SK_CHECK(min_normal_alignment(&mesh, block_top, up, NULL, 1) > 1 - 1e-9);
    const sk_group *bottom = sk_mesh_find_group(&mesh, "block-bottom");
    if (bottom) SK_CHECK(min_normal_alignment(&mesh, bottom, down, NULL, 1) > 1 - 1e-9);
    const sk_group *ball = sk_mesh_find_group(&mesh, "sphere-contact");
    if (ball) SK_CHECK(min_normal_alignment(&mesh, ball, NULL, centre, 1) > 0.9);
    sk_mesh_free(&mesh);
  }
}

/* A clockwise-defined surface and an inward boundary: the loader makes the quads counter-clockwise and the
 * edges face out of the body. */
static void test_orientation(void) {
  char dir[64] = "/tmp/stickslip-mesh-orient-XXXXXX", path[128];
  SK_CHECK(mkdtemp(dir) != NULL);
  snprintf(path, sizeof path, "%s/clockwise.geo", dir);
  FILE *file = fopen(path, "w");
  SK_CHECK(file != NULL);
  if (!file) return;
  fputs("Point(1) = {0, 0, 0}; Point(2) = {0, 1, 0}; Point(3) = {2, 1, 0}; Point(4) = {2, 0, 0};\n"
        "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};\n"
        "Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};\n"
        "Transfinite Curve{1 : 4} = 3; Transfinite Surface{1}; Recombine Surface{1};\n"
        "Physical Surface(\"body\") = {1}; Physical Curve(\"left\") = {1}; Physical Curve(\"top\") = {2};\n",
        file);
  fclose(file);
  sk_mesh mesh;
  if (load(path, NULL, 0, &mesh)) {
    double min_area;
    const sk_group *body = expect_group(&mesh, "body", 2, SK_QUAD4, 4);
    if (body) SK_CHECK_CLOSE(group_measure(&mesh, body, &min_area), 2.0, 1e-12);
    if (body) SK_CHECK(min_area > 0);
    const double left[3] = {-1, 0, 0}, up[3] = {0, 1, 0};
    const sk_group *edge = expect_group(&mesh, "left", 1, SK_LINE2, 2);
    if (edge) SK_CHECK(min_normal_alignment(&mesh, edge, left, NULL, 1) > 1 - 1e-12);
    edge = expect_group(&mesh, "top", 1, SK_LINE2, 2);
    if (edge) SK_CHECK(min_normal_alignment(&mesh, edge, up, NULL, 1) > 1 - 1e-12);
    sk_mesh_free(&mesh);
  }
  unlink(path);
  rmdir(dir);
}

int main(void) {
  test_orientation();
  test_block();
  test_block_2d();
  test_disk_and_ring();
  test_patch_test_2d();
  test_hertz();
  return sk_test_finish("test_mesh_scripts");
}
