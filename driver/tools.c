/* Commands written in Python (`stickslip compare`: runs variants of a scene, tabulates and plots them) live in
 * share/stickslip/tools beside the driver's own tree — in the build tree as in an install — and are found relative to
 * the driver's path like the plugins, so an installed tree stays relocatable. */
#define _GNU_SOURCE
#include "tools.h"

#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

int sk_driver_exec_tool(const char *script, int argc, char **argv) {
  char exe[PATH_MAX];
  ssize_t len = readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (len <= 0) {
    fprintf(stderr, "stickslip %s: cannot find the driver's own path (/proc/self/exe): %s\n", argv[1], strerror(errno));
    return 1;
  }
  exe[len] = '\0';
  char dir[PATH_MAX];
  snprintf(dir, sizeof dir, "%s", exe);
  char *slash = strrchr(dir, '/');
  if (slash) *slash = '\0';
  char path[PATH_MAX + 64];
  snprintf(path, sizeof path, "%.3800s/../share/stickslip/tools/%s", dir, script);
  if (access(path, R_OK) != 0) {
    fprintf(stderr, "stickslip %s: %s is missing (the driver's tree is incomplete: rebuild or reinstall)\n", argv[1],
            path);
    return 1;
  }
  setenv("STICKSLIP_BIN", exe, 1);
  char **args = calloc((size_t)argc + 2, sizeof(char *));
  if (!args) return 1;
  args[0] = "python3";
  args[1] = path;
  for (int i = 2; i < argc; ++i) args[i] = argv[i];
  execvp("python3", args);
  fprintf(stderr, "stickslip %s: cannot start python3 (%s); `stickslip %s` needs python3 and gnuplot "
          "(scripts/install-deps.sh)\n", argv[1], strerror(errno), argv[1]);
  free(args);
  return 1;
}
