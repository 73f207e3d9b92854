/* Plugin discovery and loading with dlopen. */
#define _GNU_SOURCE
#include "stickslip/plugins.h"

#include <dirent.h>
#include <stddef.h>
#include <dlfcn.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

enum { MAX_DIRS = 16, MAX_TABLES = 256 };

/* The tables of the libraries loaded, as this host reads them (libraries stay loaded for the process). */
static sk_plugin tables[MAX_TABLES];
static const sk_plugin *raw_tables[MAX_TABLES];
static int n_tables;

static int plugin_dirs(char dirs[MAX_DIRS][PATH_MAX]) {
  int n = 0;
  const char *env = getenv("STICKSLIP_PLUGIN_PATH");
  if (env && *env) {
    const char *p = env;
    while (*p && n < MAX_DIRS - 1) {
      const char *colon = strchr(p, ':');
      size_t len = colon ? (size_t)(colon - p) : strlen(p);
      if (len > 0 && len < PATH_MAX) {
        memcpy(dirs[n], p, len);
        dirs[n][len] = '\0';
        ++n;
      }
      if (!colon) break;
      p = colon + 1;
    }
  }
  char exe[PATH_MAX];
  ssize_t len = readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (len > 0) {
    exe[len] = '\0';
    char *slash = strrchr(exe, '/');
    if (slash) *slash = '\0';
    /* bin/stickslip and tests/<test> both sit one level below the build root */
    snprintf(dirs[n++], PATH_MAX, "%.3800s/../lib/stickslip/plugins", exe);
  }
  return n;
}

static const char *const capability_names[] = {"2d", "3d", "friction", "quasi-static", "dynamics", "energy-momentum",
                                               "rigid-obstacle", "deformable-master", "multipliers", "condensation",
                                               "needs-curvature", "needs-mass", "owns-kinematics", "self-contact"};

void sk_kinds_string(uint32_t kinds, char *out, int size) {
  snprintf(out, (size_t)size, "%s%s%s", kinds & SK_KIND_PAIR ? "pair" : "", (kinds & SK_KIND_PAIR) && (kinds & SK_KIND_BODY) ? ", " : "",
           kinds & SK_KIND_BODY ? "body" : "");
}

void sk_capabilities_string(uint64_t caps, char *out, int size) {
  int used = 0;
  out[0] = '\0';
  for (size_t i = 0; i < sizeof capability_names / sizeof capability_names[0]; ++i) {
    if ((caps >> i) & 1u) {
      int w = snprintf(out + used, (size_t)(size - used), "%s%s", used ? " " : "", capability_names[i]);
      if (w < 0 || used + w >= size) break;
      used += w;
    }
  }
}

sk_status sk_plugin_open_file(const char *path, const sk_plugin **plugin) {
  void *handle = dlopen(path, RTLD_NOW | RTLD_LOCAL);
  if (!handle) return sk_error_set(SK_ERR_PLUGIN, "cannot load plugin library %s: %s", path, dlerror());
  sk_plugin_entry_fn entry;
  *(void **)&entry = dlsym(handle, SK_PLUGIN_ENTRY_SYMBOL);
  if (!entry) {
    dlclose(handle);
    return sk_error_set(SK_ERR_PLUGIN, "plugin library %s does not export %s()", path, SK_PLUGIN_ENTRY_SYMBOL);
  }
  const sk_plugin *p = entry();
  if (!p) {
    dlclose(handle);
    return sk_error_set(SK_ERR_PLUGIN, "plugin library %s: %s() returned NULL", path, SK_PLUGIN_ENTRY_SYMBOL);
  }
  /* every table starts with abi_major, abi_minor, struct_size; a v1 table starts with abi_version = 1 */
  const uint32_t *head = (const uint32_t *)(const void *)p;
  if (head[0] != SK_ABI_MAJOR) {
    const unsigned major = head[0];
    dlclose(handle);
    return sk_error_set(SK_ERR_PLUGIN,
                        "plugin library %s has plugin ABI version %u; this stickslip has ABI %u.%u: %s", path, major,
                        SK_ABI_MAJOR, SK_ABI_MINOR,
                        major < SK_ABI_MAJOR ? "port it to ABI 2 (docs/plugin-abi.md §12) and rebuild it"
                                             : "it needs a newer stickslip");
  }
  if (head[2] < offsetof(sk_plugin, get_extension) + sizeof(void *)) { /* every 2.x table has all 2.0 members */
    const unsigned size = head[2];
    dlclose(handle);
    return sk_error_set(SK_ERR_PLUGIN, "plugin library %s: its sk_plugin table is %u bytes (struct_size), too small "
                        "for ABI 2", path, size);
  }
  /* the table as this host reads it: members beyond the plugin's struct_size (an older minor) are NULL */
  for (int k = 0; k < n_tables; ++k)
    if (raw_tables[k] == p) {
      *plugin = &tables[k];
      return SK_OK;
    }
  if (n_tables == MAX_TABLES) {
    dlclose(handle);
    return sk_error_set(SK_ERR_PLUGIN, "plugin library %s: more than %d plugin libraries loaded", path, MAX_TABLES);
  }
  sk_plugin *table = &tables[n_tables];
  memset(table, 0, sizeof *table);
  memcpy(table, p, head[2] < sizeof *table ? head[2] : sizeof *table);
  const char *missing = !table->name                ? "name"
                        : !table->kinds             ? "kinds"
                        : !table->create            ? "create"
                        : !table->destroy           ? "destroy"
                        : !table->begin_step        ? "begin_step"
                        : !table->layout            ? "layout"
                        : !table->residual          ? "residual"
                        : !table->jacobian          ? "jacobian"
                        : !table->commit_step       ? "commit_step"
                        : !table->reject_step       ? "reject_step"
                        : !table->report            ? "report"
                        : !table->strategies || !table->strategies[0] ? "strategies"
                                                                        : NULL;
  if (missing) {
    dlclose(handle);
    return sk_error_set(SK_ERR_PLUGIN, "plugin library %s lacks the required entry `%s` of its sk_plugin table", path,
                        missing);
  }
  raw_tables[n_tables++] = p;
  *plugin = table;
  return SK_OK;
}

static int is_plugin_file(const char *file) {
  size_t n = strlen(file);
  return strncmp(file, "libstickslip-", 13) == 0 && n > 16 && strcmp(file + n - 3, ".so") == 0;
}

static int compare_names(const void *a, const void *b) { return strcmp(*(char *const *)a, *(char *const *)b); }

int sk_plugin_each(void (*callback)(void *ctx, const sk_plugin *plugin, const char *path),
                   void (*broken)(void *ctx, const char *path, const char *message), void *ctx) {
  char dirs[MAX_DIRS][PATH_MAX];
  int n_dirs = plugin_dirs(dirs);
  int found = 0;
  for (int d = 0; d < n_dirs; ++d) {
    DIR *dir = opendir(dirs[d]);
    if (!dir) continue;
    char *names[256];
    int n_names = 0;
    struct dirent *entry;
    while ((entry = readdir(dir)) != NULL && n_names < 256)
      if (is_plugin_file(entry->d_name)) names[n_names++] = strdup(entry->d_name);
    closedir(dir);
    qsort(names, (size_t)n_names, sizeof names[0], compare_names); /* stable listing order */
    for (int i = 0; i < n_names; ++i) {
      char path[PATH_MAX + 300];
      snprintf(path, sizeof path, "%s/%s", dirs[d], names[i]);
      const sk_plugin *plugin;
      if (sk_plugin_open_file(path, &plugin) == SK_OK) {
        ++found;
        if (callback) callback(ctx, plugin, path);
      } else if (broken) {
        broken(ctx, path, sk_error_message());
      }
      free(names[i]);
    }
  }
  return found;
}

typedef struct {
  const char *wanted;
  const sk_plugin *match;
  char available[1024];
} find_ctx;

static void find_callback(void *ctx, const sk_plugin *plugin, const char *path) {
  (void)path;
  find_ctx *f = ctx;
  if (!f->match && strcmp(plugin->name, f->wanted) == 0) f->match = plugin;
  size_t used = strlen(f->available);
  if (used + strlen(plugin->name) + 3 < sizeof f->available)
    snprintf(f->available + used, sizeof f->available - used, "%s%s", used ? ", " : "", plugin->name);
}

sk_status sk_plugin_load(const char *name, const sk_plugin **plugin) {
  find_ctx f = {.wanted = name, .match = NULL, .available = ""};
  sk_plugin_each(find_callback, NULL, &f);
  if (!f.match)
    return sk_error_set(SK_ERR_PLUGIN, "unknown plugin '%s' (available: %s; extra folders: STICKSLIP_PLUGIN_PATH)",
                        name, f.available[0] ? f.available : "none found");
  *plugin = f.match;
  return SK_OK;
}
