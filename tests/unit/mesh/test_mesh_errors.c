/* Bad input gives a clear message naming the file, parameter or group, never a crash. */
#define _DEFAULT_SOURCE /* mkdtemp */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "sk_test.h"
#include "stickslip/mesh.h"

static char tmpdir[64];

static void write_file(const char *path, const char *text) {
  FILE *file = fopen(path, "w");
  SK_CHECK(file != NULL);
  if (!file) return;
  fputs(text, file);
  fclose(file);
}

/* Loading fails with `code` and a message containing each of the given fragments. */
static void expect_failure(const char *path, const sk_mesh_param *params, int n_params, sk_status code,
                           const char *fragment1, const char *fragment2) {
  sk_mesh mesh;
  sk_error_clear();
  sk_status status = sk_mesh_load(path, params, n_params, 0, &mesh);
  const char *message = sk_error_message();
  if (status != code || !strstr(message, fragment1) || (fragment2 && !strstr(message, fragment2)))
    fprintf(stderr, "loading %s: status %d, message '%s'\n", path, status, message);
  SK_CHECK(status == code);
  SK_CHECK(strstr(message, fragment1) != NULL);
  SK_CHECK(!fragment2 || strstr(message, fragment2) != NULL);
  SK_CHECK(mesh.n_groups == 0 && mesh.groups == NULL && mesh.x == NULL); /* nothing to free after a failure */
  sk_mesh_free(&mesh);
}

int main(void) {
  snprintf(tmpdir, sizeof tmpdir, "/tmp/stickslip-mesh-test-XXXXXX");
  SK_CHECK(mkdtemp(tmpdir) != NULL);
  char path[256];

  expect_failure("meshes/no-such-mesh.geo", NULL, 0, SK_ERR_IO, "meshes/no-such-mesh.geo", "cannot open");
  expect_failure("meshes/no-such-mesh.msh", NULL, 0, SK_ERR_IO, "no-such-mesh.msh", NULL);
  expect_failure("meshes/README.md", NULL, 0, SK_ERR_INPUT, "meshes/README.md", "unknown mesh format");

  /* a typo in a parameter name is caught, naming the parameter and the file, listing the real ones */
  const sk_mesh_param typo[] = {{"refine", 1}, {"refin", 2}};
  expect_failure("meshes/block.geo", typo, 2, SK_ERR_INPUT, "unknown parameter 'refin'", "meshes/block.geo");
  expect_failure("meshes/block.geo", typo + 1, 1, SK_ERR_INPUT, "refine", NULL);
  const sk_mesh_param not_a_name[] = {{"lx; Abort", 1}};
  expect_failure("meshes/block.geo", not_a_name, 1, SK_ERR_INPUT, "not a valid identifier", NULL);
  const sk_mesh_param to_msh[] = {{"refine", 2}};
  expect_failure("meshes/two-elements.msh", to_msh, 1, SK_ERR_INPUT, "two-elements.msh", "'refine'");
  /* the script's own checks surface as gmsh errors */
  const sk_mesh_param inside_out[] = {{"r_inner", 30}};
  expect_failure("meshes/torus.geo", inside_out, 1, SK_ERR_INPUT, "meshes/torus.geo", "r_inner < r_outer");

  snprintf(path, sizeof path, "%s/syntax.geo", tmpdir);
  write_file(path, "Point(1) = {0, 0, 0;\n");
  expect_failure(path, NULL, 0, SK_ERR_INPUT, "syntax.geo", "syntax error");

  snprintf(path, sizeof path, "%s/no-groups.geo", tmpdir);
  write_file(path, "Point(1) = {0, 0, 0}; Point(2) = {1, 0, 0}; Point(3) = {0, 1, 0};\n"
                   "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 1};\n"
                   "Curve Loop(1) = {1, 2, 3}; Plane Surface(1) = {1};\n");
  expect_failure(path, NULL, 0, SK_ERR_INPUT, "no-groups.geo", "no physical groups");

  /* triangles and quads in one group; loading hertz-2d.geo first checks that its mesh options (recombine all)
   * do not outlive its load */
  sk_mesh previous;
  const sk_mesh_param coarse[] = {{"refine", 0.5}};
  SK_CHECK(sk_mesh_load("meshes/hertz-2d.geo", coarse, 1, 0, &previous) == SK_OK);
  sk_mesh_free(&previous);
  snprintf(path, sizeof path, "%s/mixed.geo", tmpdir);
  write_file(path, "DefineConstant[ h = 0.5 ];\n"
                   "Point(1) = {0, 0, 0, h}; Point(2) = {1, 0, 0, h}; Point(3) = {1, 1, 0, h}; Point(4) = {0, 1, 0, h};\n"
                   "Point(5) = {2, 0, 0, h};\n"
                   "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1}; Line(5) = {2, 5};\n"
                   "Line(6) = {5, 3};\n"
                   "Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};\n"
                   "Curve Loop(2) = {5, 6, -2}; Plane Surface(2) = {2};\n"
                   "Transfinite Surface{1}; Recombine Surface{1};\n"
                   "Physical Surface(\"plate\") = {1, 2};\n");
  expect_failure(path, NULL, 0, SK_ERR_INPUT, "mixes element types", "'plate'");

  /* a 2D mesh outside the plane z = 0 */
  snprintf(path, sizeof path, "%s/tilted.geo", tmpdir);
  write_file(path, "Point(1) = {0, 0, 0}; Point(2) = {1, 0, 0}; Point(3) = {0, 1, 1};\n"
                   "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 1};\n"
                   "Curve Loop(1) = {1, 2, 3}; Plane Surface(1) = {1}; Physical Surface(\"s\") = {1};\n");
  expect_failure(path, NULL, 0, SK_ERR_INPUT, "tilted.geo", "z = 0");

  /* a corrupt .msh */
  snprintf(path, sizeof path, "%s/corrupt.msh", tmpdir);
  write_file(path, "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0 0\n2 1 0\n");
  expect_failure(path, NULL, 0, SK_ERR_INPUT, "corrupt.msh", NULL);

  /* missing group: the message lists what the mesh has */
  sk_mesh mesh;
  sk_status status = sk_mesh_load("meshes/block-2d.geo", NULL, 0, 0, &mesh);
  SK_CHECK(status == SK_OK);
  if (status == SK_OK) {
    const sk_group *group = (const sk_group *)&mesh; /* must be reset to NULL */
    SK_CHECK(sk_mesh_require_group(&mesh, "contact", 1, &group) == SK_ERR_INPUT);
    SK_CHECK(group == NULL);
    const char *message = sk_error_message();
    SK_CHECK(strstr(message, "meshes/block-2d.geo") && strstr(message, "'contact'"));
    SK_CHECK(strstr(message, "body") && strstr(message, "left") && strstr(message, "top"));
    SK_CHECK(sk_mesh_require_group(&mesh, "body", 1, &group) == SK_ERR_INPUT); /* wrong dimension */
    SK_CHECK(strstr(sk_error_message(), "dimension") != NULL);
    SK_CHECK(sk_mesh_require_group(&mesh, "top", 1, &group) == SK_OK && group && group->dim == 1);
    SK_CHECK(sk_mesh_find_group(&mesh, "Top") == NULL);
    sk_mesh_free(&mesh);
  }
  /* a failed load leaves gmsh usable: the next load works */
  status = sk_mesh_load("meshes/block.geo", NULL, 0, 0, &mesh);
  SK_CHECK(status == SK_OK && mesh.n_nodes == 125);
  if (status == SK_OK) sk_mesh_free(&mesh);
  /* a parameter set for one load does not leak into the next */
  const sk_mesh_param longer[] = {{"lx", 3}};
  SK_CHECK(sk_mesh_load("meshes/block.geo", longer, 1, 0, &mesh) == SK_OK);
  double xmax = 0;
  for (int n = 0; n < mesh.n_nodes; ++n) xmax = xmax > mesh.x[3 * n] ? xmax : mesh.x[3 * n];
  SK_CHECK_CLOSE(xmax, 3.0, 1e-12);
  sk_mesh_free(&mesh);
  SK_CHECK(sk_mesh_load("meshes/block.geo", NULL, 0, 0, &mesh) == SK_OK);
  xmax = 0;
  for (int n = 0; n < mesh.n_nodes; ++n) xmax = xmax > mesh.x[3 * n] ? xmax : mesh.x[3 * n];
  SK_CHECK_CLOSE(xmax, 1.0, 1e-12);
  sk_mesh_free(&mesh);

  const char *names[] = {"syntax.geo", "no-groups.geo", "mixed.geo", "tilted.geo", "corrupt.msh"};
  for (int i = 0; i < 5; ++i) {
    snprintf(path, sizeof path, "%s/%s", tmpdir, names[i]);
    unlink(path);
  }
  rmdir(tmpdir);
  return sk_test_finish("test_mesh_errors");
}
