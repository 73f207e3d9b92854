/* The figures behind the mesh generator's limits, each mesh made in a fresh child process:
 * - gmsh's peak resident memory per element (the memory limit, core/mesh/mesh_load.c): the peak resident size
 *   (VmHWM) after gmshInitialize and after meshing, the difference over the element count;
 * - the mesh size queries per curve node while gmsh meshes the curves (the 1D watchdog, core/mesh/mesh_guard.c):
 *   a global size callback that only counts, against the curve nodes made.
 *
 *   bench_mesh_limits          (run from the source tree: it reads the scripts in meshes/)
 *
 * gmsh 4.8.4 (Debian 12): 0.51 (hertz-2d quads), 0.62 (block hexes), 0.35 (torus hexes), 0.55 (1.34 million tets),
 * 0.85 kB per element (triangles; the smallest mesh, where gmsh's fixed cost weighs most); size queries per curve
 * node on hertz-2d.geo: 104 at refine 1, 6.1 at 100, 1.6 at 10^4. */
#define _DEFAULT_SOURCE /* mkstemps */
#include <gmshc.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

static long peak_kb(void) {
  FILE *f = fopen("/proc/self/status", "r");
  char line[256];
  long kb = 0;
  while (f && fgets(line, sizeof line, f))
    if (strncmp(line, "VmHWM:", 6) == 0) kb = atol(line + 6);
  if (f) fclose(f);
  return kb;
}

/* Meshes `script` (gmsh text) to dimension `dim` and prints the figures. */
static void measure(const char *label, const char *script, int dim) {
  char path[] = "/tmp/bench-mesh-memory-XXXXXX.geo";
  int fd = mkstemps(path, 4);
  if (fd < 0 || write(fd, script, strlen(script)) != (ssize_t)strlen(script)) {
    perror("temporary script");
    exit(1);
  }
  close(fd);
  fflush(stdout);
  pid_t pid = fork();
  if (pid == 0) {
    int ierr = 0;
    gmshInitialize(0, NULL, 0, &ierr);
    gmshOptionSetNumber("General.Terminal", 0, &ierr);
    long before = peak_kb();
    gmshOpen(path, &ierr);
    gmshModelMeshGenerate(dim, &ierr);
    long after = peak_kb();
    int *types = NULL;
    size_t n_types = 0, **tags = NULL, *tags_n = NULL, tags_nn = 0, **nodes = NULL, *nodes_n = NULL, nodes_nn = 0;
    gmshModelMeshGetElements(&types, &n_types, &tags, &tags_n, &tags_nn, &nodes, &nodes_n, &nodes_nn, dim, -1, &ierr);
    size_t elements = 0;
    for (size_t t = 0; t < tags_nn; ++t) elements += tags_n[t];
    printf("%-40s %9zu elements  %7ld kB -> %7ld kB  %.2f kB/element\n", label, elements, before, after,
           elements ? (double)(after - before) / (double)elements : 0.0);
    fflush(stdout);
    _exit(0);
  }
  waitpid(pid, NULL, 0);
  unlink(path);
}

static long asks;
static double count_asks(int dim, int tag, double x, double y, double z, void *data) {
  (void)dim, (void)tag, (void)x, (void)y, (void)z, (void)data;
  ++asks;
  return 1e22; /* never below gmsh's own size: the mesh is unchanged */
}

/* Meshes the curves of hertz-2d.geo at `refine` and prints size queries against curve nodes. */
static void measure_asks(const char *cwd, double refine) {
  fflush(stdout);
  pid_t pid = fork();
  if (pid == 0) {
    char path[] = "/tmp/bench-mesh-asks-XXXXXX.geo", script[4200];
    int fd = mkstemps(path, 4);
    snprintf(script, sizeof script, "refine = %g;\nInclude \"%s/meshes/hertz-2d.geo\";\n", refine, cwd);
    if (fd < 0 || write(fd, script, strlen(script)) != (ssize_t)strlen(script)) _exit(1);
    close(fd);
    int ierr = 0;
    gmshInitialize(0, NULL, 0, &ierr);
    gmshOptionSetNumber("General.Terminal", 0, &ierr);
    gmshOpen(path, &ierr);
    gmshModelMeshSetSizeCallback(count_asks, NULL, &ierr);
    gmshModelMeshGenerate(1, &ierr);
    size_t *tags = NULL, n_tags = 0, n_coords = 0, n_param = 0;
    double *coords = NULL, *param = NULL;
    gmshModelMeshGetNodes(&tags, &n_tags, &coords, &n_coords, &param, &n_param, 1, -1, 1, 0, &ierr);
    printf("hertz-2d.geo refine %-8g %9zu curve nodes  %10ld size queries  %.2f per node\n", refine, n_tags, asks,
           (double)asks / (double)n_tags);
    fflush(stdout);
    unlink(path);
    _exit(0);
  }
  waitpid(pid, NULL, 0);
}

int main(void) {
  char cwd[4096], script[8192];
  if (!getcwd(cwd, sizeof cwd)) return 1;
  snprintf(script, sizeof script, "refine = 8;\nInclude \"%s/meshes/hertz-2d.geo\";\n", cwd);
  measure("hertz-2d.geo refine 8 (quads)", script, 2);
  snprintf(script, sizeof script, "refine = 6;\nInclude \"%s/meshes/block.geo\";\n", cwd);
  measure("block.geo refine 6 (hexes)", script, 3);
  snprintf(script, sizeof script, "refine = 2;\nInclude \"%s/meshes/torus.geo\";\n", cwd);
  measure("torus.geo refine 2 (hexes)", script, 3);
  const char *cube = "Point(1) = {0, 0, 0, %g}; Point(2) = {1, 0, 0, %g}; Point(3) = {1, 1, 0, %g};\n"
                     "Point(4) = {0, 1, 0, %g}; Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4};\n"
                     "Line(4) = {4, 1}; Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};\n%s";
  const char *extrude = "Extrude {0, 0, 1} { Surface{1}; }\n";
  snprintf(script, sizeof script, cube, 0.015, 0.015, 0.015, 0.015, extrude);
  measure("unit cube, size 0.015 (tets)", script, 3);
  snprintf(script, sizeof script, cube, 0.01, 0.01, 0.01, 0.01, "");
  measure("unit square, size 0.01 (triangles)", script, 2);
  for (double refine = 1; refine <= 1e4; refine *= 100) measure_asks(cwd, refine);
  return 0;
}
