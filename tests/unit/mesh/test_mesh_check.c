/* Element checks after loading (issue 15, items 9, 13, 14): a collapsed element (a node repeated), non-finite
 * coordinates, an inverted or flat element, an element listed twice, and two bodies on the same or overlapping groups
 * are refused with the file, group and element named; every bundled mesh passes. */
#define _DEFAULT_SOURCE /* mkdtemp */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "sk_test.h"
#include "stickslip/mesh.h"

static char dir[] = "/tmp/stickslip-check-test-XXXXXX";

/* A .msh 2.2 file with the nodes of a unit cube (1..8; the top at z = 1, or 0 when `flat`), one more node (9) and the
 * given elements section. */
static const char *write_msh_top(const char *name, const char *node9, const char *elements, int flat) {
  static char path[256];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  FILE *f = fopen(path, "w");
  SK_CHECK(f != NULL);
  if (!f) return path;
  fprintf(f, "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n3 1 \"block\"\n3 2 \"other\"\n"
             "$EndPhysicalNames\n$Nodes\n9\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 0 0 %d\n6 1 0 %d\n7 1 1 %d\n"
             "8 0 1 %d\n9 %s\n$EndNodes\n$Elements\n%s$EndElements\n",
          !flat, !flat, !flat, !flat, node9, elements);
  fclose(f);
  return path;
}

static const char *write_msh(const char *name, const char *node9, const char *elements) {
  return write_msh_top(name, node9, elements, 0);
}

static void expect_refused(const char *path, const char *part1, const char *part2) {
  sk_mesh mesh;
  sk_status status = sk_mesh_load(path, NULL, 0, 0, &mesh);
  SK_CHECK(status == SK_ERR_INPUT);
  SK_CHECK(sk_test_contains(sk_error_message(), part1) && sk_test_contains(sk_error_message(), part2));
  SK_CHECK(mesh.groups == NULL && mesh.x == NULL);
  if (status == SK_OK) sk_mesh_free(&mesh);
}

int main(void) {
  SK_CHECK(mkdtemp(dir) != NULL);
  /* the reference: a good hex */
  sk_mesh mesh;
  const char *good = write_msh("good.msh", "2 2 2", "1\n1 5 2 1 1 1 2 3 4 5 6 7 8\n");
  SK_CHECK(sk_mesh_load(good, NULL, 0, 0, &mesh) == SK_OK);
  if (mesh.x) sk_mesh_free(&mesh);

  /* item 14: a hex with node 3 twice used to run with a wrong energy */
  expect_refused(write_msh("collapsed.msh", "2 2 2", "1\n1 5 2 1 1 1 2 3 3 5 6 7 8\n"),
                 "physical group 'block', element 0", "its nodes 2 and 3 are the same node (a collapsed element)");
  /* two corners swapped: a twisted hex */
  expect_refused(write_msh("twisted.msh", "2 2 2", "1\n1 5 2 1 1 1 2 4 3 5 6 7 8\n"),
                 "twisted.msh: physical group 'block', element 0", "inverted (twisted) at corner");
  /* a flat hex: the top face on the bottom one (distinct nodes at the same places) */
  expect_refused(write_msh_top("flat.msh", "2 2 2", "1\n1 5 2 1 1 1 2 3 4 5 6 7 8\n", 1), "flat.msh",
                 "degenerate (flat)");
  /* item 9: a non-finite coordinate is named as such, with the file */
  expect_refused(write_msh("nan.msh", "nan 0 0", "2\n1 5 2 1 1 1 2 3 4 5 6 7 8\n2 15 2 2 9 9\n"), "nan.msh",
                 "node 8 has a non-finite coordinate");
  /* an element listed twice in one group, and one element in two groups */
  SK_CHECK(sk_mesh_load(write_msh("twice.msh", "2 2 2", "2\n1 5 2 1 1 1 2 3 4 5 6 7 8\n2 5 2 1 1 5 6 7 8 1 2 3 4\n"),
                        NULL, 0, 0, &mesh) == SK_OK); /* loads: the check is on the groups a scene uses */
  if (mesh.x) {
    const sk_group *block = sk_mesh_find_group(&mesh, "block");
    const sk_group *one[1] = {block};
    const char *names[2] = {"body 'a'", "body 'b'"};
    SK_CHECK(sk_mesh_check_disjoint(&mesh, one, names, 1) == SK_ERR_INPUT);
    SK_CHECK(sk_test_contains(sk_error_message(), "twice.msh: physical group 'block', element 1") &&
             sk_test_contains(sk_error_message(), "is listed twice in the group (also as element 0)"));
    const sk_group *same[2] = {block, block};
    SK_CHECK(sk_mesh_check_disjoint(&mesh, same, names, 2) == SK_ERR_INPUT);
    SK_CHECK(sk_test_contains(sk_error_message(), "body 'a' and body 'b' both use physical group 'block'"));
    sk_mesh_free(&mesh);
  }
  SK_CHECK(sk_mesh_load(write_msh("overlap.msh", "2 2 2", "2\n1 5 2 1 1 1 2 3 4 5 6 7 8\n2 5 2 2 2 2 3 4 1 6 7 8 5\n"),
                        NULL, 0, 0, &mesh) == SK_OK);
  if (mesh.x) {
    const sk_group *both[2] = {sk_mesh_find_group(&mesh, "block"), sk_mesh_find_group(&mesh, "other")};
    const char *names[2] = {"body 'a'", "body 'b'"};
    SK_CHECK(both[0] && both[1] && sk_mesh_check_disjoint(&mesh, both, names, 2) == SK_ERR_INPUT);
    SK_CHECK(sk_test_contains(sk_error_message(), "body 'a' and body 'b' overlap"));
    sk_mesh_free(&mesh);
  }
  /* every bundled mesh passes the element checks (sk_mesh_load runs them) */
  const char *scripts[] = {"meshes/block.geo", "meshes/block-2d.geo", "meshes/disk.geo", "meshes/ring.geo",
                           "meshes/patch-test-2d.geo", "meshes/hertz-2d.geo", "meshes/two-elements.msh"};
  for (size_t k = 0; k < sizeof scripts / sizeof scripts[0]; ++k) {
    sk_status status = sk_mesh_load(scripts[k], NULL, 0, 0, &mesh);
    if (status != SK_OK) fprintf(stderr, "%s: %s\n", scripts[k], sk_error_message());
    SK_CHECK(status == SK_OK);
    if (status == SK_OK) sk_mesh_free(&mesh);
  }
  const char *files[] = {"good.msh", "collapsed.msh", "twisted.msh", "flat.msh", "nan.msh", "twice.msh", "overlap.msh"};
  char path[300];
  for (size_t k = 0; k < sizeof files / sizeof files[0]; ++k) {
    snprintf(path, sizeof path, "%s/%s", dir, files[k]);
    unlink(path);
  }
  rmdir(dir);
  return sk_test_finish("test_mesh_check");
}
