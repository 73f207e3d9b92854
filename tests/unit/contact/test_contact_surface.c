/* sk_surface_build on hand-made meshes: faces given with the wrong orientation come out outward (normal pointing
 * away from the body), node lists sorted, adjacency across edges / end points, and errors naming group and face; on
 * second-order gmsh meshes (hex27, hex20, tet10): outward quadratic faces, full adjacency, and the curvature of the
 * sphere's tri6 faces; the sizes the scene extension reports (sk_surface_sizes: corner-to-corner edges, area). */
#include <string.h>

#include "contact_test_util.h"
#include "sk_test.h"

/* Outward on a convex body: the normal at each face centre points away from the body's centroid. */
static void check_outward(const sk_surface *s, const double *q, const double *centroid) {
  const double c = sk_elem_is_simplex(s->face_type) ? 1.0 / 3.0 : 0.0;
  double xi[2] = {c, c};
  for (int f = 0; f < s->n_faces; ++f) {
    sk_surface_point p;
    sk_surface_geometry(s, f, xi, q, &p);
    double out = 0.0;
    for (int i = 0; i < 3; ++i) out += (p.x[i] - centroid[i]) * p.n[i];
    SK_CHECK(out > 0.0);
  }
}

static void build_2d(void) {
  /* Two quads side by side: 0 (0,0), 1 (1,0), 2 (2,0), 3 (0,1), 4 (1,1), 5 (2,1). */
  double x[18] = {0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0, 1, 1, 0, 2, 1, 0};
  double q[12];
  for (int k = 0; k < 6; ++k) q[2 * k] = x[3 * k], q[2 * k + 1] = x[3 * k + 1];
  int body_conn[8] = {0, 1, 4, 3, 1, 2, 5, 4};
  int bottom_conn[4] = {1, 0, 2, 1}; /* clockwise: the wrong way round */
  int top_conn[4] = {3, 4, 4, 5};    /* clockwise around the body too */
  sk_group groups[3] = {
      {.name = "body", .dim = 2, .type = SK_QUAD4, .nen = 4, .n_elems = 2, .conn = body_conn},
      {.name = "bottom", .dim = 1, .type = SK_LINE2, .nen = 2, .n_elems = 2, .conn = bottom_conn},
      {.name = "top", .dim = 1, .type = SK_LINE2, .nen = 2, .n_elems = 2, .conn = top_conn},
  };
  sk_mesh mesh = {.dim = 2, .n_nodes = 6, .x = x, .n_groups = 3, .groups = groups, .source = "hand-made"};
  sk_surface s;
  SK_CHECK(sk_surface_build(&mesh, &groups[1], &groups[0], 0, &s) == SK_OK);
  SK_CHECK(strcmp(s.name, "bottom") == 0 && s.dim == 2 && s.face_type == SK_LINE2 && s.n_edges == 2);
  SK_CHECK(s.n_faces == 2 && s.conn[0] == 0 && s.conn[1] == 1 && s.conn[2] == 1 && s.conn[3] == 2);
  SK_CHECK(s.n_nodes == 3 && s.nodes[0] == 0 && s.nodes[1] == 1 && s.nodes[2] == 2);
  /* end 0 of face 0 is node 0 (border), end 1 is node 1 shared with face 1 */
  SK_CHECK(s.face_neighbors[0] == -1 && s.face_neighbors[1] == 1 && s.face_neighbors[2] == 0 &&
           s.face_neighbors[3] == -1);
  double centroid[3] = {1, 0.5, 0};
  check_outward(&s, q, centroid);
  sk_surface_point p;
  double xi[1] = {0};
  sk_surface_geometry(&s, 0, xi, q, &p);
  SK_CHECK_CLOSE(p.n[1], -1.0, 1e-15);
  /* sizes (stickslip.scene.v1): two faces of length 1 */
  double h_min, h_mean, h_max, measure;
  sk_surface_sizes(&s, x, 3, &h_min, &h_mean, &h_max, &measure);
  SK_CHECK(h_min == 1.0 && h_mean == 1.0 && h_max == 1.0 && measure == 2.0);
  sk_surface_free(&s);

  SK_CHECK(sk_surface_build(&mesh, &groups[2], &groups[0], 0, &s) == SK_OK);
  SK_CHECK(s.conn[0] == 4 && s.conn[1] == 3 && s.conn[2] == 5 && s.conn[3] == 4);
  check_outward(&s, q, centroid);
  sk_surface_free(&s);

  /* A line that is not a boundary edge of any element (a diagonal). */
  int diagonal_conn[2] = {0, 4};
  sk_group diagonal = {.name = "diagonal", .dim = 1, .type = SK_LINE2, .nen = 2, .n_elems = 1, .conn = diagonal_conn};
  SK_CHECK(sk_surface_build(&mesh, &diagonal, &groups[0], 0, &s) == SK_ERR_INPUT);
  SK_CHECK(strstr(sk_error_message(), "diagonal") != NULL && strstr(sk_error_message(), "face 0") != NULL);
  SK_CHECK(s.conn == NULL && s.nodes == NULL && s.face_neighbors == NULL);
}

static int node3(int i, int j, int k) { return i + 3 * j + 6 * k; }

static void build_3d(void) {
  /* Two hex8 side by side along x on a 3 x 2 x 2 node grid. */
  double x[36];
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 3; ++i) {
        double *p = x + 3 * node3(i, j, k);
        p[0] = i, p[1] = j, p[2] = k;
      }
  int body_conn[16];
  for (int e = 0; e < 2; ++e) {
    int *c = body_conn + 8 * e;
    for (int k = 0; k < 2; ++k) {
      c[4 * k + 0] = node3(e, 0, k), c[4 * k + 1] = node3(e + 1, 0, k);
      c[4 * k + 2] = node3(e + 1, 1, k), c[4 * k + 3] = node3(e, 1, k);
    }
  }
  /* Top faces listed clockwise seen from above (inward) and rotated; the side face x = 0 given outward already. */
  int top_conn[8] = {node3(0, 1, 1), node3(1, 1, 1), node3(1, 0, 1), node3(0, 0, 1),
                     node3(2, 0, 1), node3(1, 0, 1), node3(1, 1, 1), node3(2, 1, 1)};
  int side_conn[4] = {node3(0, 0, 0), node3(0, 0, 1), node3(0, 1, 1), node3(0, 1, 0)};
  sk_group body = {.name = "blocks", .dim = 3, .type = SK_HEX8, .nen = 8, .n_elems = 2, .conn = body_conn};
  sk_group top = {.name = "top", .dim = 2, .type = SK_QUAD4, .nen = 4, .n_elems = 2, .conn = top_conn};
  sk_group side = {.name = "side", .dim = 2, .type = SK_QUAD4, .nen = 4, .n_elems = 1, .conn = side_conn};
  sk_mesh mesh = {.dim = 3, .n_nodes = 12, .x = x, .n_groups = 0, .groups = NULL, .source = "hand-made"};
  sk_surface s;
  double centroid[3] = {1, 0.5, 0.5};
  SK_CHECK(sk_surface_build(&mesh, &top, &body, 3, &s) == SK_OK);
  SK_CHECK(s.body == 3 && s.n_faces == 2 && s.n_nodes == 6 && s.n_edges == 4 && s.face_type == SK_QUAD4);
  for (int k = 1; k < s.n_nodes; ++k) SK_CHECK(s.nodes[k - 1] < s.nodes[k]);
  check_outward(&s, x, centroid);
  double xi[2] = {0.3, -0.2};
  sk_surface_point p;
  sk_surface_geometry(&s, 0, xi, x, &p);
  SK_CHECK_CLOSE(p.n[2], 1.0, 1e-15);
  /* Exactly one edge of each face is shared with the other face. */
  int shared0 = 0, shared1 = 0;
  for (int e = 0; e < 4; ++e) {
    shared0 += s.face_neighbors[e] == 1;
    shared1 += s.face_neighbors[4 + e] == 0;
    SK_CHECK(s.face_neighbors[e] == 1 || s.face_neighbors[e] == -1);
  }
  SK_CHECK(shared0 == 1 && shared1 == 1);
  sk_surface_free(&s);
  SK_CHECK(s.conn == NULL);

  SK_CHECK(sk_surface_build(&mesh, &side, &body, 0, &s) == SK_OK);
  check_outward(&s, x, centroid);
  sk_surface_free(&s);

  /* Wrong face type for the body, and a face that is not on the body. */
  sk_group lines = {.name = "edges", .dim = 1, .type = SK_LINE2, .nen = 2, .n_elems = 1, .conn = side_conn};
  SK_CHECK(sk_surface_build(&mesh, &lines, &body, 0, &s) == SK_ERR_INPUT);
  SK_CHECK(strstr(sk_error_message(), "edges") != NULL);
  int skew_conn[8] = {node3(0, 0, 1), node3(1, 0, 1), node3(1, 1, 1), node3(0, 1, 1),
                      node3(0, 0, 0), node3(1, 0, 1), node3(2, 1, 1), node3(0, 1, 0)};
  sk_group skew = {.name = "skew", .dim = 2, .type = SK_QUAD4, .nen = 4, .n_elems = 2, .conn = skew_conn};
  SK_CHECK(sk_surface_build(&mesh, &skew, &body, 0, &s) == SK_ERR_INPUT);
  SK_CHECK(strstr(sk_error_message(), "skew") != NULL && strstr(sk_error_message(), "face 1") != NULL &&
           strstr(sk_error_message(), "blocks") != NULL);
}

static void build_tet(void) {
  double x[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  int body_conn[4] = {0, 1, 2, 3};
  /* All four faces, each listed in some order. */
  int faces_conn[12] = {0, 1, 2, 0, 1, 3, 1, 2, 3, 0, 3, 2};
  sk_group body = {.name = "tet", .dim = 3, .type = SK_TET4, .nen = 4, .n_elems = 1, .conn = body_conn};
  sk_group faces = {.name = "skin", .dim = 2, .type = SK_TRI3, .nen = 3, .n_elems = 4, .conn = faces_conn};
  sk_mesh mesh = {.dim = 3, .n_nodes = 4, .x = x, .source = "hand-made"};
  sk_surface s;
  SK_CHECK(sk_surface_build(&mesh, &faces, &body, 0, &s) == SK_OK);
  double centroid[3] = {0.25, 0.25, 0.25};
  check_outward(&s, x, centroid);
  /* a closed surface: every edge has a neighbour */
  for (int k = 0; k < 12; ++k) SK_CHECK(s.face_neighbors[k] >= 0 && s.face_neighbors[k] != k / 3);
  /* sizes: each face has its three edges counted (three of length 1, three of sqrt 2, each in two faces); area of
   * three right triangles and the equilateral one of side sqrt 2 */
  double h_min, h_mean, h_max, measure;
  sk_surface_sizes(&s, x, 3, &h_min, &h_mean, &h_max, &measure);
  SK_CHECK_CLOSE(h_min, 1.0, 1e-15);
  SK_CHECK_CLOSE(h_max, sqrt(2.0), 1e-15);
  SK_CHECK_CLOSE(h_mean, 0.5 + 0.5 * sqrt(2.0), 1e-15);
  SK_CHECK_CLOSE(measure, 1.5 + sqrt(3.0) / 2.0, 1e-14);
  sk_surface_free(&s);
}

/* Positions of a mesh in the dof layout (dim per node). */
static double *mesh_positions(const sk_mesh *mesh) {
  double *q = malloc((size_t)mesh->n_nodes * mesh->dim * sizeof *q);
  for (int n = 0; n < mesh->n_nodes; ++n)
    for (int i = 0; i < mesh->dim; ++i) q[n * mesh->dim + i] = mesh->x[3 * n + i];
  return q;
}

/* Edges of a surface without a neighbour. */
static int border_edges(const sk_surface *s) {
  int count = 0;
  for (int k = 0; k < s->n_faces * s->n_edges; ++k) count += s->face_neighbors[k] < 0;
  return count;
}

static void build_quadratic_box(int serendipity) {
  const sk_mesh_param params[] = {{"nx", 2}, {"ny", 3}, {"nz", 2}};
  sk_mesh_options options;
  sk_mesh_options_default(&options);
  options.order = 2, options.serendipity = serendipity;
  sk_mesh mesh;
  SK_CHECK(sk_mesh_load_with("meshes/block.geo", params, 3, &options, &mesh) == SK_OK);
  if (!mesh.n_groups) return;
  double *q = mesh_positions(&mesh);
  const sk_group *body = sk_mesh_find_group(&mesh, "body");
  const double centroid[3] = {0.5, 0.5, 0.5};
  sk_surface s;
  SK_CHECK(sk_surface_build(&mesh, sk_mesh_find_group(&mesh, "zmax"), body, 0, &s) == SK_OK);
  SK_CHECK(s.face_type == (serendipity ? SK_QUAD8 : SK_QUAD9) && s.n_faces == 6 && s.n_edges == 4);
  SK_CHECK(s.n_nodes == 5 * 7 - (serendipity ? 6 : 0)); /* a 5 x 7 grid of nodes; quad8 has no face centres */
  SK_CHECK(border_edges(&s) == 2 * (2 + 3));
  check_outward(&s, q, centroid);
  /* sizes between corner nodes: the quadratic faces have the edges of the 2 x 3 hex8 mesh, 1/2 and 1/3 (gmsh's
   * coordinates are exact to about 2e-12) */
  double h_min, h_mean, h_max, measure;
  sk_surface_sizes(&s, mesh.x, 3, &h_min, &h_mean, &h_max, &measure);
  SK_CHECK_CLOSE(h_min, 1.0 / 3.0, 1e-11);
  SK_CHECK_CLOSE(h_max, 0.5, 1e-11);
  SK_CHECK_CLOSE(h_mean, 5.0 / 12.0, 1e-11);
  SK_CHECK_CLOSE(measure, 1.0, 1e-11);
  sk_surface_free(&s);
  const char *sides[] = {"xmin", "xmax", "ymin", "ymax", "zmin"};
  for (int k = 0; k < 5; ++k) {
    SK_CHECK(sk_surface_build(&mesh, sk_mesh_find_group(&mesh, sides[k]), body, 0, &s) == SK_OK);
    check_outward(&s, q, centroid);
    sk_surface_free(&s);
  }
  free(q);
  sk_mesh_free(&mesh);
}

/* The eighth sphere of hertz-3d.geo as tet10: its tri6 skin faces outward, is one connected sheet (border edges only
 * on the three cut planes) and carries the sphere's curvature, m^ab h_ab = -2/R at every face centre (to the
 * interpolation error of the coarse mesh; flat tri3 faces have h = 0). */
static void build_quadratic_sphere(void) {
  const sk_mesh_param params[] = {{"refine", 0.5}};
  sk_mesh_options options;
  sk_mesh_options_default(&options);
  options.order = 2;
  sk_mesh mesh;
  SK_CHECK(sk_mesh_load_with("meshes/hertz-3d.geo", params, 1, &options, &mesh) == SK_OK);
  if (!mesh.n_groups) return;
  double *q = mesh_positions(&mesh);
  sk_surface s;
  SK_CHECK(sk_surface_build(&mesh, sk_mesh_find_group(&mesh, "sphere-contact"), sk_mesh_find_group(&mesh, "sphere"),
                            0, &s) == SK_OK);
  SK_CHECK(s.face_type == SK_TRI6 && s.nen == 6 && s.n_edges == 3);
  const double centre[3] = {0, 0, 1};
  double worst = 0.0, xi[2] = {1.0 / 3.0, 1.0 / 3.0};
  for (int f = 0; f < s.n_faces; ++f) {
    sk_surface_point p;
    sk_surface_geometry(&s, f, xi, q, &p);
    double out = 0.0, trace = 0.0;
    for (int i = 0; i < 3; ++i) out += (p.x[i] - centre[i]) * p.n[i];
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) trace += p.m_inv[a][b] * p.h[a][b];
    SK_CHECK(out > 0.9);
    worst = fmax(worst, fabs(trace / 2.0 + 1.0));
  }
  printf("tet10 eighth sphere, %d tri6 faces: |m^ab h_ab / 2 + 1/R| <= %.3f\n", s.n_faces, worst);
  SK_CHECK(worst < 0.05); /* measured 0.033 */
  int border = 0;
  for (int f = 0; f < s.n_faces; ++f)
    for (int e = 0; e < 3; ++e) {
      if (s.face_neighbors[f * 3 + e] >= 0) continue;
      const double *a = mesh.x + 3 * s.conn[f * 6 + e], *b = mesh.x + 3 * s.conn[f * 6 + (e + 1) % 3];
      /* a border edge lies in one of the cut planes x = 0, y = 0, z = 1 */
      border += (fabs(a[0]) < 1e-9 && fabs(b[0]) < 1e-9) || (fabs(a[1]) < 1e-9 && fabs(b[1]) < 1e-9) ||
                (fabs(a[2] - 1) < 1e-9 && fabs(b[2] - 1) < 1e-9);
    }
  SK_CHECK(border == border_edges(&s) && border > 0);
  sk_surface_free(&s);
  free(q);
  sk_mesh_free(&mesh);
}

int main(void) {
  build_quadratic_box(0);
  build_quadratic_box(1);
  build_quadratic_sphere();
  build_2d();
  build_3d();
  build_tet();
  return sk_test_finish("test_contact_surface");
}
