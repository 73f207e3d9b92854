#define _DEFAULT_SOURCE /* mkdtemp */
/* Second-order meshes from sk_mesh_options (tet10, hex20, hex27, tri6, quad8, quad9 with line3/tri6/quad8/quad9
 * boundaries): element types and counts, positive volumes, mid-nodes where the corners put them (straight geometry)
 * or on the curved geometry (sphere), outward boundary normals; the orientation fix-up of every quadratic type on a
 * mirrored mesh; bad options. Element measures come from core/fe (tested on its own in tests/unit/fe). */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "mesh_internal.h"
#include "sk_test.h"
#include "stickslip/fe.h"

#define PI 3.14159265358979323846
/* gmsh places the new nodes of a straight edge through the curve's parametrisation: measured up to 1.2e-12 off the
 * midpoint on unit boxes. */
#define STRAIGHT_TOL 1e-11

static int load(const char *path, const sk_mesh_param *params, int n_params, int order, int serendipity,
                sk_mesh *mesh) {
  sk_mesh_options options;
  sk_mesh_options_default(&options);
  options.order = order, options.serendipity = serendipity;
  sk_status status = sk_mesh_load_with(path, params, n_params, &options, mesh);
  if (status != SK_OK) fprintf(stderr, "loading %s failed: %s\n", path, sk_error_message());
  SK_CHECK(status == SK_OK);
  return status == SK_OK;
}

static const sk_group *group_of(const sk_mesh *mesh, const char *name, sk_elem_type type) {
  const sk_group *group = sk_mesh_find_group(mesh, name);
  SK_CHECK(group != NULL);
  if (!group) return NULL;
  if (group->type != type)
    fprintf(stderr, "%s: group %s is %s, expected %s\n", mesh->source, name, sk_elem_name(group->type),
            sk_elem_name(type));
  SK_CHECK(group->type == type && group->nen == sk_elem_nen(type));
  return group->type == type ? group : NULL;
}

static void element_coords(const sk_mesh *mesh, const sk_group *group, int e, int dim, double *X) {
  for (int a = 0; a < group->nen; ++a)
    for (int i = 0; i < dim; ++i) X[a * dim + i] = mesh->x[3 * group->conn[(size_t)e * group->nen + a] + i];
}

/* Total volume (area) of a body group; *min_volume gets the smallest element volume. */
static double body_volume(const sk_mesh *mesh, const sk_group *body, double *min_volume) {
  static const sk_material material = {SK_MAT_SVK, 1, 0.3, 0.5, 0.4, 1};
  const sk_solid solid = {body->type, mesh->dim, &material};
  double total = 0.0, X[SK_MAX_NEN * 3];
  *min_volume = INFINITY;
  for (int e = 0; e < body->n_elems; ++e) {
    element_coords(mesh, body, e, mesh->dim, X);
    const double v = sk_solid_volume(&solid, X);
    total += v;
    *min_volume = fmin(*min_volume, v);
  }
  return total;
}

/* Largest distance of a node from where the element's corners put it (the linear map at the node's parametric
 * point): zero for straight-sided elements with their nodes in gmsh's order. */
static double straight_deviation(const sk_mesh *mesh, const sk_group *group) {
  const int pdim = sk_elem_pdim(group->type), corners = sk_elem_corners(group->type);
  const sk_elem_type linear = pdim == 1 ? SK_LINE2 : pdim == 2 ? (corners == 3 ? SK_TRI3 : SK_QUAD4)
                                                               : (corners == 4 ? SK_TET4 : SK_HEX8);
  const double *xi = sk_elem_node_coords(group->type);
  double worst = 0.0, X[SK_MAX_NEN * 3], N[8];
  for (int e = 0; e < group->n_elems; ++e) {
    element_coords(mesh, group, e, 3, X);
    for (int a = corners; a < group->nen; ++a) {
      sk_elem_shape(linear, xi + a * pdim, N, NULL);
      for (int i = 0; i < 3; ++i) {
        double x = 0.0;
        for (int c = 0; c < corners; ++c) x += N[c] * X[c * 3 + i];
        worst = fmax(worst, fabs(x - X[a * 3 + i]));
      }
    }
  }
  return worst;
}

/* Unit normal of a boundary element at its parametric centre from the quadratic map (a1 x a2; (t_y, -t_x) in 2D)
 * and the point there. */
static void face_normal(const sk_mesh *mesh, const sk_group *group, int e, double *n, double *x) {
  const int pdim = sk_elem_pdim(group->type);
  const double c = sk_elem_is_simplex(group->type) ? 1.0 / 3.0 : 0.0, xi[2] = {c, c};
  double X[SK_MAX_NEN * 3], N[SK_MAX_NEN], dN[SK_MAX_NEN * 2], a[2][3] = {{0}};
  element_coords(mesh, group, e, 3, X);
  sk_elem_shape(group->type, xi, N, dN);
  for (int i = 0; i < 3; ++i) {
    x[i] = 0.0;
    for (int b = 0; b < group->nen; ++b) {
      x[i] += N[b] * X[b * 3 + i];
      for (int k = 0; k < pdim; ++k) a[k][i] += dN[b * pdim + k] * X[b * 3 + i];
    }
  }
  if (pdim == 1) {
    n[0] = a[0][1], n[1] = -a[0][0], n[2] = 0.0;
  } else {
    n[0] = a[0][1] * a[1][2] - a[0][2] * a[1][1];
    n[1] = a[0][2] * a[1][0] - a[0][0] * a[1][2];
    n[2] = a[0][0] * a[1][1] - a[0][1] * a[1][0];
  }
  const double length = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (int i = 0; i < 3; ++i) n[i] /= length;
}

/* Smallest n . d over a boundary group: d a fixed direction, or (origin != NULL) the unit vector from origin to the
 * face point. */
static double min_alignment(const sk_mesh *mesh, const sk_group *group, const double *direction,
                            const double *origin) {
  double lowest = INFINITY;
  for (int e = 0; group && e < group->n_elems; ++e) {
    double n[3], x[3], d[3];
    face_normal(mesh, group, e, n, x);
    for (int i = 0; i < 3; ++i) d[i] = origin ? x[i] - origin[i] : direction[i];
    const double length = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    lowest = fmin(lowest, (n[0] * d[0] + n[1] * d[1] + n[2] * d[2]) / length);
  }
  return lowest;
}

/* Box [0,1]^3 (2 x 2 x 2 hexahedra): body and the six faces, with `sign` = -1 for the mirrored box (x -> -x). */
static void check_box(const sk_mesh *mesh, sk_elem_type body_type, sk_elem_type face_type, double sign) {
  const sk_group *body = group_of(mesh, "body", body_type);
  double min_volume;
  if (body) {
    SK_CHECK_CLOSE(body_volume(mesh, body, &min_volume), 1.0, 1e-13);
    SK_CHECK(min_volume > 0.0);
    SK_CHECK(straight_deviation(mesh, body) < STRAIGHT_TOL);
  }
  const char *faces[6] = {"xmin", "xmax", "ymin", "ymax", "zmin", "zmax"};
  for (int f = 0; f < 6; ++f) {
    const sk_group *face = group_of(mesh, faces[f], face_type);
    double outward[3] = {0, 0, 0};
    outward[f / 2] = (f % 2 ? 1.0 : -1.0) * (f / 2 == 0 ? sign : 1.0);
    if (face) SK_CHECK(min_alignment(mesh, face, outward, NULL) > 1 - 1e-12);
    if (face) SK_CHECK(straight_deviation(mesh, face) < STRAIGHT_TOL);
  }
}

/* Mirrors the mesh (x -> -x), which turns every element inside out, and runs the orientation fix-up again. */
static void mirror(sk_mesh *mesh) {
  for (int n = 0; n < mesh->n_nodes; ++n) mesh->x[3 * n] = -mesh->x[3 * n];
  SK_CHECK(sk_mesh_orient(mesh) == SK_OK);
}

static void test_box(void) {
  const sk_mesh_param params[] = {{"nx", 2}, {"ny", 2}, {"nz", 2}};
  sk_mesh mesh;
  if (load("meshes/block.geo", params, 3, 2, 0, &mesh)) {
    SK_CHECK(mesh.n_nodes == 5 * 5 * 5);
    check_box(&mesh, SK_HEX27, SK_QUAD9, 1.0);
    mirror(&mesh);
    check_box(&mesh, SK_HEX27, SK_QUAD9, -1.0);
    sk_mesh_free(&mesh);
  }
  if (load("meshes/block.geo", params, 3, 2, 1, &mesh)) {
    SK_CHECK(mesh.n_nodes == 27 + 3 * 2 * 9); /* corners and edge nodes only */
    check_box(&mesh, SK_HEX20, SK_QUAD8, 1.0);
    mirror(&mesh);
    check_box(&mesh, SK_HEX20, SK_QUAD8, -1.0);
    sk_mesh_free(&mesh);
  }
  /* A .msh file has no geometry: gmsh puts the new nodes on straight edges. */
  if (load("meshes/two-elements.msh", NULL, 0, 2, 0, &mesh)) {
    const sk_group *upper = group_of(&mesh, "upper", SK_HEX27);
    if (upper) SK_CHECK(straight_deviation(&mesh, upper) < STRAIGHT_TOL);
    group_of(&mesh, "upper-bottom", SK_QUAD9);
    sk_mesh_free(&mesh);
  }
}

/* 2D rectangle 1 x 2 (quads) and an unstructured triangulated rectangle, both mirrored too. */
static void check_rectangle(const sk_mesh *mesh, const char *body_name, sk_elem_type body_type, double area,
                            const char *top_name) {
  const sk_group *body = group_of(mesh, body_name, body_type);
  double min_area;
  if (body) {
    SK_CHECK_CLOSE(body_volume(mesh, body, &min_area), area, 1e-13);
    SK_CHECK(min_area > 0.0);
    SK_CHECK(straight_deviation(mesh, body) < STRAIGHT_TOL);
  }
  const sk_group *top = group_of(mesh, top_name, SK_LINE3);
  const double up[3] = {0, 1, 0};
  if (top) SK_CHECK(min_alignment(mesh, top, up, NULL) > 1 - 1e-12);
}

static void test_2d(void) {
  const sk_mesh_param params[] = {{"nx", 3}, {"ly", 2}};
  sk_mesh mesh;
  if (load("meshes/block-2d.geo", params, 2, 2, 0, &mesh)) {
    SK_CHECK(mesh.n_nodes == 7 * 9);
    check_rectangle(&mesh, "body", SK_QUAD9, 2.0, "top");
    mirror(&mesh);
    check_rectangle(&mesh, "body", SK_QUAD9, 2.0, "top");
    sk_mesh_free(&mesh);
  }
  if (load("meshes/block-2d.geo", params, 2, 2, 1, &mesh)) { /* the script asks for quad9; the options win */
    SK_CHECK(mesh.n_nodes == 7 * 9 - 12);
    check_rectangle(&mesh, "body", SK_QUAD8, 2.0, "top");
    mirror(&mesh);
    check_rectangle(&mesh, "body", SK_QUAD8, 2.0, "top");
    sk_mesh_free(&mesh);
  }
  char dir[64] = "/tmp/stickslip-mesh-order-XXXXXX", path[128];
  SK_CHECK(mkdtemp(dir) != NULL);
  snprintf(path, sizeof path, "%s/triangles.geo", dir);
  FILE *file = fopen(path, "w");
  SK_CHECK(file != NULL);
  if (!file) return;
  fputs("Point(1) = {0, 0, 0, 0.3}; Point(2) = {0, 1, 0, 0.3}; Point(3) = {2, 1, 0, 0.3}; Point(4) = {2, 0, 0, 0.3};\n"
        "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};\n"
        "Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};\n" /* clockwise: gmsh's triangles are too */
        "Physical Surface(\"plate\") = {1}; Physical Curve(\"top\") = {2};\n",
        file);
  fclose(file);
  if (load(path, NULL, 0, 2, 0, &mesh)) {
    check_rectangle(&mesh, "plate", SK_TRI6, 2.0, "top");
    mirror(&mesh);
    check_rectangle(&mesh, "plate", SK_TRI6, 2.0, "top");
    sk_mesh_free(&mesh);
  }
  unlink(path);
  rmdir(dir);
}

/* Curved geometry: the sphere of hertz-3d.geo as tet10 with tri6 faces whose nodes all lie on the sphere. The
 * volume error of the eighth ball (pi/6) drops from the inscribed polyhedron's to that of the quadratic surface. */
static void test_sphere(void) {
  const sk_mesh_param params[] = {{"refine", 0.5}};
  sk_mesh linear, quadratic;
  if (!load("meshes/hertz-3d.geo", params, 1, 0, 0, &linear)) return;
  if (!load("meshes/hertz-3d.geo", params, 1, 2, 0, &quadratic)) {
    sk_mesh_free(&linear);
    return;
  }
  double min_volume;
  const sk_group *ball1 = group_of(&linear, "sphere", SK_TET4), *ball2 = group_of(&quadratic, "sphere", SK_TET10);
  if (ball1 && ball2) {
    SK_CHECK(ball1->n_elems == ball2->n_elems);
    const double error1 = fabs(body_volume(&linear, ball1, &min_volume) - PI / 6) / (PI / 6);
    const double error2 = fabs(body_volume(&quadratic, ball2, &min_volume) - PI / 6) / (PI / 6);
    printf("  eighth ball, %d elements: volume error tet4 %.2e, tet10 %.2e\n", ball2->n_elems, error1, error2);
    SK_CHECK(min_volume > 0.0);
    SK_CHECK(error2 < 0.01 * error1);
  }
  const sk_group *skin = group_of(&quadratic, "sphere-contact", SK_TRI6);
  const double centre[3] = {0, 0, 1}, up[3] = {0, 0, 1}, down[3] = {0, 0, -1};
  if (skin) {
    int *nodes = NULL, n = 0;
    SK_CHECK(sk_group_nodes(skin, &nodes, &n) == SK_OK);
    double worst = 0.0;
    for (int k = 0; k < n; ++k) {
      const double *x = quadratic.x + 3 * nodes[k];
      worst = fmax(worst, fabs(sqrt(x[0] * x[0] + x[1] * x[1] + (x[2] - 1) * (x[2] - 1)) - 1.0));
    }
    free(nodes);
    SK_CHECK(worst < 1e-9);
    SK_CHECK(min_alignment(&quadratic, skin, NULL, centre) > 0.95);
  }
  const sk_group *block = group_of(&quadratic, "block", SK_TET10);
  if (block) {
    SK_CHECK_CLOSE(body_volume(&quadratic, block, &min_volume), 1.5 * 1.5, 1e-12);
    SK_CHECK(straight_deviation(&quadratic, block) < STRAIGHT_TOL);
  }
  SK_CHECK(min_alignment(&quadratic, group_of(&quadratic, "block-contact", SK_TRI6), up, NULL) > 1 - 1e-12);
  SK_CHECK(min_alignment(&quadratic, group_of(&quadratic, "block-bottom", SK_TRI6), down, NULL) > 1 - 1e-12);
  SK_CHECK(min_alignment(&quadratic, group_of(&quadratic, "sphere-top", SK_TRI6), up, NULL) > 1 - 1e-12);
  mirror(&quadratic);
  if (ball2) {
    SK_CHECK(body_volume(&quadratic, ball2, &min_volume) > 0.0);
    SK_CHECK(min_volume > 0.0);
  }
  SK_CHECK(min_alignment(&quadratic, skin, NULL, centre) > 0.95); /* the mirror keeps the centre */
  SK_CHECK(min_alignment(&quadratic, group_of(&quadratic, "block-contact", SK_TRI6), up, NULL) > 1 - 1e-12);
  sk_mesh_free(&linear);
  sk_mesh_free(&quadratic);
}

static void test_bad_options(void) {
  sk_mesh mesh;
  sk_mesh_options options;
  sk_mesh_options_default(&options);
  options.order = 3;
  SK_CHECK(sk_mesh_load_with("meshes/block.geo", NULL, 0, &options, &mesh) == SK_ERR_INPUT);
  SK_CHECK(strstr(sk_error_message(), "order 3") != NULL && strstr(sk_error_message(), "block.geo") != NULL);
  options.order = 1, options.serendipity = 1;
  SK_CHECK(sk_mesh_load_with("meshes/block.geo", NULL, 0, &options, &mesh) == SK_ERR_INPUT);
  SK_CHECK(strstr(sk_error_message(), "serendipity") != NULL);
  SK_CHECK(sk_mesh_load_with("meshes/block.geo", NULL, 0, NULL, &mesh) == SK_ERR_INTERNAL);
}

int main(void) {
  test_box();
  test_2d();
  test_sphere();
  test_bad_options();
  return sk_test_finish("test_mesh_order");
}
