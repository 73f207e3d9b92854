/* .geo scripts that act outside the mesh are refused before gmsh runs them (issue 15, item 16): shell commands, file
 * writes and Exit, also in Included scripts and wherever they sit (inside If, Macro); the same words in strings,
 * comments or option names are fine; --trust-scripts (sk_mesh_trust_scripts) lets them through. */
#define _DEFAULT_SOURCE /* mkdtemp */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "sk_test.h"
#include "stickslip/mesh.h"

static char dir[] = "/tmp/stickslip-geo-scan-XXXXXX";

/* A unit square with a physical surface, after `prelude`. */
static const char *script(const char *name, const char *prelude) {
  static char path[256];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  FILE *f = fopen(path, "w");
  SK_CHECK(f != NULL);
  if (!f) return path;
  fprintf(f, "%s\nPoint(1) = {0, 0, 0, 0.5}; Point(2) = {1, 0, 0, 0.5}; Point(3) = {1, 1, 0, 0.5};\n"
             "Point(4) = {0, 1, 0, 0.5}; Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};\n"
             "Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1}; Physical Surface(\"s\") = {1};\n",
          prelude);
  fclose(f);
  return path;
}

static void expect(const char *path, sk_status code, const char *part1, const char *part2) {
  sk_mesh mesh;
  sk_status status = sk_mesh_load(path, NULL, 0, 0, &mesh);
  if (status != code) fprintf(stderr, "%s: status %d: %s\n", path, status, sk_error_message());
  SK_CHECK(status == code);
  if (status == SK_OK) sk_mesh_free(&mesh);
  if (part1) SK_CHECK(sk_test_contains(sk_error_message(), part1));
  if (part2) SK_CHECK(sk_test_contains(sk_error_message(), part2));
}

static int exists(const char *name) {
  char path[300];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  return access(path, F_OK) == 0;
}

int main(void) {
  SK_CHECK(mkdtemp(dir) != NULL);
  char text[1024];
  snprintf(text, sizeof text, "SystemCall \"touch %s/pwned\";", dir);
  expect(script("system.geo", text), SK_ERR_INPUT, "system.geo:1: 'SystemCall' runs a shell command", "--trust-scripts");
  SK_CHECK(!exists("pwned"));
  expect(script("if.geo", "If (0)\n  System \"true\";\nEndIf"), SK_ERR_INPUT, "if.geo:2: 'System'", NULL);
  expect(script("save.geo", "Save \"out.msh\";"), SK_ERR_INPUT, "'Save' writes a file", NULL);
  expect(script("print.geo", "Print Sprintf(\"x%g.png\", 1);"), SK_ERR_INPUT, "'Print' writes a file", NULL);
  expect(script("dir.geo", "CreateDir \"d\";"), SK_ERR_INPUT, "'CreateDir' creates a directory", NULL);
  expect(script("printf.geo", "Printf(\"%g\", 1) > \"log.txt\";"), SK_ERR_INPUT, "'Printf > file' writes a file", NULL);
  expect(script("exit.geo", "Exit;"), SK_ERR_INPUT, "'Exit' would end stickslip itself", NULL);
  expect(script("onelab.geo", "OnelabRun(\"x\", \"y\");"), SK_ERR_INPUT, "'OnelabRun' runs a program", NULL);
  /* an Included script is checked too, and the message says where it was included */
  script("inner.geo", "NonBlockingSystemCall \"true\";");
  snprintf(text, sizeof text, "Include \"inner.geo\";");
  expect(script("outer.geo", text), SK_ERR_INPUT, "(Include at ", "inner.geo:1: 'NonBlockingSystemCall'");
  expect(script("computed.geo", "f = \"inner\"; Include StrCat(f, \".geo\");"), SK_ERR_INPUT,
         "'Include' reads a file whose name is computed", NULL);
  /* harmless look-alikes: words in strings and comments, option names, Printf to the log, a data Merge */
  expect(script("fine.geo", "// SystemCall \"rm -rf /\";\n/* Save \"x\"; */\nPrintf(\"SystemCall %g\", 1);\n"
                            "Mesh.SaveAll = 0; General.Verbosity = 2; s = \"Exit\";"),
         SK_OK, NULL, NULL);
  script("cycle.geo", "Include \"cycle.geo\";"); /* an Include cycle ends the scan (gmsh itself would loop) */
  sk_mesh mesh;
  SK_CHECK(sk_mesh_load_with(script("a.geo", "Include \"cycle.geo\";"), NULL, 0,
                             &(sk_mesh_options){.max_elements = 100, .time_limit = 2}, &mesh) != SK_OK);
  /* trusted: the command runs */
  sk_mesh_trust_scripts(1);
  snprintf(text, sizeof text, "SystemCall \"touch %s/trusted\";", dir);
  expect(script("trusted.geo", text), SK_OK, NULL, NULL);
  SK_CHECK(exists("trusted"));
  sk_mesh_trust_scripts(0);
  const char *files[] = {"system.geo", "if.geo", "save.geo", "print.geo", "dir.geo", "printf.geo", "exit.geo",
                         "onelab.geo", "inner.geo", "outer.geo", "computed.geo", "fine.geo", "cycle.geo", "a.geo",
                         "trusted.geo", "trusted"};
  char path[300];
  for (size_t k = 0; k < sizeof files / sizeof files[0]; ++k) {
    snprintf(path, sizeof path, "%s/%s", dir, files[k]);
    unlink(path);
  }
  rmdir(dir);
  return sk_test_finish("test_geo_scan");
}
