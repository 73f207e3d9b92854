/* The mesh size guard and the mesh generator's child process (issue 15, items 1, 2, 17):
 * - every bundled script loads with mesh.max_elements at twice its element count (the estimates never refuse a mesh
 *   within the limit by more than that), and is refused, naming the limit, at half its count;
 * - the estimate made before meshing (printed beside the exact count) for the record in mesh_guard.c;
 * - gmsh's memory per element, the basis of the child's memory limit (printed);
 * - a runaway mesh is refused in seconds, a script that loops forever ends at the time limit, a gmsh exception
 *   (mesh size 0) is a message, not an abort. */
#define _DEFAULT_SOURCE /* mkdtemp */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include "sk_test.h"
#include "stickslip/mesh.h"

static double seconds(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* CPU seconds of the waited-for children so far (the mesh generator runs in one) */
static double children_cpu_seconds(void) {
  struct rusage usage;
  getrusage(RUSAGE_CHILDREN, &usage);
  return (double)usage.ru_utime.tv_sec + 1e-6 * (double)usage.ru_utime.tv_usec + (double)usage.ru_stime.tv_sec +
         1e-6 * (double)usage.ru_stime.tv_usec;
}

static long body_elements(const sk_mesh *mesh) {
  long n = 0;
  for (int g = 0; g < mesh->n_groups; ++g) n += mesh->groups[g].dim == mesh->dim ? mesh->groups[g].n_elems : 0;
  return n;
}

/* Loads with the given limit; returns the status and leaves the message in sk_error_message(). */
static sk_status load_limited(const char *path, const sk_mesh_param *params, int n_params, long max_elements,
                              double time_limit, sk_mesh *mesh) {
  sk_mesh_options options;
  sk_mesh_options_default(&options);
  options.max_elements = max_elements;
  if (time_limit > 0) options.time_limit = time_limit;
  return sk_mesh_load_with(path, params, n_params, &options, mesh);
}

/* The estimate is what the refusal at max_elements = 1 reports ("about N elements") before any surface is meshed. */
static void check_script(const char *path, const sk_mesh_param *params, int n_params) {
  sk_mesh mesh;
  sk_status status = load_limited(path, params, n_params, SK_MESH_DEFAULT_MAX_ELEMENTS, 0, &mesh);
  SK_CHECK(status == SK_OK);
  if (status != SK_OK) {
    fprintf(stderr, "%s: %s\n", path, sk_error_message());
    return;
  }
  long count = body_elements(&mesh);
  int dim = mesh.dim;
  sk_mesh_free(&mesh);
  status = load_limited(path, params, n_params, 1, 0, &mesh);
  const char *about = strstr(sk_error_message(), "about ");
  double estimate = about ? atof(about + 6) : -1;
  printf("%-26s %8ld elements, estimated before meshing the %s: %8.0f (ratio %.2f)\n", path, count,
         dim == 3 ? "volumes" : "surfaces", estimate, estimate / (double)count);
  SK_CHECK(status == SK_ERR_INPUT && sk_test_contains(sk_error_message(), "mesh.max_elements = 1"));
  /* within the limit at twice the count, refused at half of it */
  status = load_limited(path, params, n_params, 2 * count, 0, &mesh);
  if (status != SK_OK) fprintf(stderr, "%s at 2x its count: %s\n", path, sk_error_message());
  SK_CHECK(status == SK_OK);
  if (status == SK_OK) sk_mesh_free(&mesh);
  status = load_limited(path, params, n_params, count / 2, 0, &mesh);
  SK_CHECK(status == SK_ERR_INPUT);
  char limit[64];
  snprintf(limit, sizeof limit, "mesh.max_elements = %ld", count / 2);
  SK_CHECK(sk_test_contains(sk_error_message(), limit));
}

static void write_file(const char *path, const char *text) {
  FILE *f = fopen(path, "w");
  SK_CHECK(f != NULL);
  if (!f) return;
  fputs(text, f);
  fclose(f);
}

int main(void) {
  const sk_mesh_param fine2d[] = {{"refine", 4}};
  const sk_mesh_param coarse[] = {{"refine", 0.5}};
  check_script("meshes/block.geo", NULL, 0);
  check_script("meshes/block-2d.geo", NULL, 0);
  check_script("meshes/disk.geo", NULL, 0);
  check_script("meshes/ring.geo", NULL, 0);
  check_script("meshes/patch-test-2d.geo", NULL, 0);
  check_script("meshes/hertz-2d.geo", NULL, 0);
  check_script("meshes/hertz-2d.geo", fine2d, 1);
  check_script("meshes/hertz-3d.geo", coarse, 1);
  check_script("meshes/torus.geo", coarse, 1);

  char dir[] = "/tmp/stickslip-guard-test-XXXXXX", path[256];
  SK_CHECK(mkdtemp(dir) != NULL);
  sk_mesh mesh;

  /* a runaway refinement of sizes: refused while meshing the curves, long before the memory is gone (a limit of
   * 10^4 keeps the test light: the memory limit is then 275 MB) */
  const sk_mesh_param runaway[] = {{"refine", 1e6}};
  double t0 = seconds();
  sk_status status = load_limited("meshes/hertz-2d.geo", runaway, 1, 10000, 0, &mesh);
  double spent = seconds() - t0;
  printf("hertz-2d refine 1e6: refused after %.2f s: %s\n", spent, sk_error_message());
  SK_CHECK(status == SK_ERR_INPUT && sk_test_contains(sk_error_message(), "meshing the curves alone asked for the mesh size at"));
  SK_CHECK(sk_test_contains(sk_error_message(), "mesh.max_elements = 10000") && sk_test_contains(sk_error_message(), "refine = 1e+06"));
  /* a runaway transfinite count (no size is asked for): the child's memory limit */
  t0 = seconds();
  status = load_limited("meshes/block.geo", runaway, 1, 10000, 0, &mesh);
  spent = seconds() - t0;
  printf("block refine 1e6: refused after %.2f s: %s\n", spent, sk_error_message());
  SK_CHECK(status == SK_ERR_INPUT && sk_test_contains(sk_error_message(), "gmsh used more than 275 MB while meshing the curves"));

  /* a mesh size of zero: gmsh throws inside an OpenMP region, which used to abort stickslip */
  const sk_mesh_param zero[] = {{"h_contact", 0}};
  status = sk_mesh_load("meshes/hertz-2d.geo", zero, 1, 0, &mesh);
  SK_CHECK(status == SK_ERR_INPUT && sk_test_contains(sk_error_message(), "Wrong mesh element size"));
  SK_CHECK(sk_test_contains(sk_error_message(), "h_contact = 0") && sk_test_contains(sk_error_message(), "meshes/hertz-2d.geo"));

  /* a script that never ends: stopped at the time limit, naming what gmsh was doing */
  snprintf(path, sizeof path, "%s/loop.geo", dir);
  write_file(path, "For i In {1:1e15}\n  x = i;\nEndFor\n");
  /* The child's own CPU time, not the wall: the limit counts from gmsh loaded in the child, and on a loaded machine
   * the fork and gmsh's loading alone took seconds of wall (the loop spins for the limit: about 1 s of CPU, plus
   * gmsh's loading, 0.3 s, measured on an idle machine). */
  const double cpu_before = children_cpu_seconds();
  status = load_limited(path, NULL, 0, SK_MESH_DEFAULT_MAX_ELEMENTS, 1.0, &mesh);
  const double child_cpu = children_cpu_seconds() - cpu_before;
  printf("loop.geo at mesh.time_limit 1: the child used %.2f s of CPU\n", child_cpu);
  SK_CHECK(status == SK_ERR_INPUT && sk_test_contains(sk_error_message(), "did not finish within 1 s while evaluating"));
  SK_CHECK(sk_test_contains(sk_error_message(), "mesh.time_limit"));
  SK_CHECK(child_cpu < 2.0);
  unlink(path);

  /* a .msh over the limit is refused after reading (it has no estimate) */
  status = load_limited("meshes/two-elements.msh", NULL, 0, 1, 0, &mesh);
  SK_CHECK(status == SK_ERR_INPUT && sk_test_contains(sk_error_message(), "has 2 elements of dimension 3"));

  /* bad limits */
  status = load_limited("meshes/block.geo", NULL, 0, 0, 0, &mesh);
  SK_CHECK(status == SK_ERR_INPUT && sk_test_contains(sk_error_message(), "max_elements must be at least 1"));
  rmdir(dir);
  return sk_test_finish("test_mesh_guard");
}
