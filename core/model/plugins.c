/* Plugin discovery and loading with dlopen. */
#define _GNU_SOURCE
#include "stickslip/plugins.h"

#include <dirent.h>
#include <stddef.h>
#include <dlfcn.h>
#include <elf.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
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
                                               "needs-curvature", "needs-mass", "owns-kinematics", "self-contact",
                                               "says-idle"};

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

/* ---- checking a library before dlopen ---------------------------------------------------------------------- */

/* dlopen maps a library's segments straight from the file: a truncated copy (an interrupted build or download)
 * maps pages past the end of the file, and the first touch of such a page in the dynamic loader raises SIGBUS —
 * an uncatchable crash of `stickslip plugins` or of any scene. So every library is checked first: a regular file,
 * an ELF shared object for this machine, and every segment and the section table inside the file. */

/* e_machine of the running executable: the machine every plugin must be built for. */
static int host_machine(void) {
  static int machine = -1;
  if (machine >= 0) return machine;
  machine = EM_NONE;
  int fd = open("/proc/self/exe", O_RDONLY | O_CLOEXEC);
  Elf64_Ehdr header;
  if (fd >= 0 && read(fd, &header, sizeof header) == (ssize_t)sizeof header &&
      memcmp(header.e_ident, ELFMAG, SELFMAG) == 0)
    machine = header.e_machine;
  if (fd >= 0) close(fd);
  return machine;
}

static sk_status check_library_file(const char *path) {
  int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return sk_error_set(SK_ERR_PLUGIN, "cannot open plugin library %s: %s", path, strerror(errno));
  struct stat st;
  Elf64_Ehdr h;
  sk_status status = SK_OK;
  if (fstat(fd, &st) != 0) {
    status = sk_error_set(SK_ERR_PLUGIN, "cannot inspect plugin library %s: %s", path, strerror(errno));
  } else if (!S_ISREG(st.st_mode)) {
    status = sk_error_set(SK_ERR_PLUGIN, "plugin library %s is not a regular file", path);
  } else if (pread(fd, &h, sizeof h, 0) != (ssize_t)sizeof h || memcmp(h.e_ident, ELFMAG, SELFMAG) != 0) {
    status = sk_error_set(SK_ERR_PLUGIN, "plugin library %s is not an ELF shared library (%lld bytes)", path,
                          (long long)st.st_size);
  } else if (h.e_ident[EI_CLASS] != ELFCLASS64 || h.e_ident[EI_DATA] != ELFDATA2LSB || h.e_type != ET_DYN ||
             h.e_machine != host_machine()) {
    status = sk_error_set(SK_ERR_PLUGIN, "plugin library %s is not a 64-bit shared library for this machine "
                          "(ELF class %d, type %d, machine %d)", path, h.e_ident[EI_CLASS], h.e_type, h.e_machine);
  } else if (h.e_phentsize != sizeof(Elf64_Phdr) || h.e_phnum == 0 ||
             h.e_phoff + (uint64_t)h.e_phnum * sizeof(Elf64_Phdr) > (uint64_t)st.st_size) {
    status = sk_error_set(SK_ERR_PLUGIN, "plugin library %s is truncated or damaged (%lld bytes; its program "
                          "headers end beyond the file)", path, (long long)st.st_size);
  } else if (h.e_shoff != 0 && h.e_shoff + (uint64_t)h.e_shnum * h.e_shentsize > (uint64_t)st.st_size) {
    status = sk_error_set(SK_ERR_PLUGIN, "plugin library %s is truncated (%lld bytes, the ELF header promises %llu): "
                          "an interrupted copy or build? Rebuild or reinstall it", path, (long long)st.st_size,
                          (unsigned long long)(h.e_shoff + (uint64_t)h.e_shnum * h.e_shentsize));
  }
  for (int k = 0; status == SK_OK && k < h.e_phnum; ++k) {
    Elf64_Phdr ph;
    if (pread(fd, &ph, sizeof ph, (off_t)(h.e_phoff + (uint64_t)k * sizeof ph)) != (ssize_t)sizeof ph ||
        (ph.p_type == PT_LOAD && ph.p_offset + ph.p_filesz > (uint64_t)st.st_size))
      status = sk_error_set(SK_ERR_PLUGIN, "plugin library %s is truncated (%lld bytes; segment %d ends at byte %llu): "
                            "an interrupted copy or build? Rebuild or reinstall it", path, (long long)st.st_size, k,
                            (unsigned long long)(ph.p_offset + ph.p_filesz));
  }
  close(fd);
  return status;
}

sk_status sk_plugin_open_file(const char *path, const sk_plugin **plugin) {
  SK_TRY(check_library_file(path));
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

/* ---- finding libraries ------------------------------------------------------------------------------------ */

static const char file_prefix[] = "libstickslip-", file_suffix[] = ".so";

/* A plugin name becomes part of a file name: letters, digits, '-', '_' only (no '/', no ".."). */
static int is_plugin_name(const char *name) {
  if (!name || !name[0] || strlen(name) > 100) return 0;
  for (const char *c = name; *c; ++c)
    if (!((*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') || (*c >= '0' && *c <= '9') || *c == '-' || *c == '_'))
      return 0;
  return 1;
}

static int is_plugin_file(const char *file) {
  size_t n = strlen(file), np = sizeof file_prefix - 1, ns = sizeof file_suffix - 1;
  return n > np + ns && strncmp(file, file_prefix, np) == 0 && strcmp(file + n - ns, file_suffix) == 0;
}

static int compare_names(const void *a, const void *b) { return strcmp(*(char *const *)a, *(char *const *)b); }

enum { MAX_FILES = 256 };

/* The plugin library file names of one folder, sorted (a stable listing order); caller frees each name. */
static int list_plugin_files(const char *folder, char *names[MAX_FILES]) {
  DIR *dir = opendir(folder);
  if (!dir) return 0;
  int n = 0;
  struct dirent *entry;
  while ((entry = readdir(dir)) != NULL && n < MAX_FILES)
    if (is_plugin_file(entry->d_name) && (names[n] = strdup(entry->d_name)) != NULL) ++n;
  closedir(dir);
  qsort(names, (size_t)n, sizeof names[0], compare_names);
  return n;
}

int sk_plugin_each(void (*callback)(void *ctx, const sk_plugin *plugin, const char *path),
                   void (*broken)(void *ctx, const char *path, const char *message), void *ctx) {
  char dirs[MAX_DIRS][PATH_MAX];
  int n_dirs = plugin_dirs(dirs);
  int found = 0;
  for (int d = 0; d < n_dirs; ++d) {
    char *names[MAX_FILES];
    int n_names = list_plugin_files(dirs[d], names);
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

/* "a, b, c": the plugin names of every library file in the search path, from the file names alone (nothing is
 * loaded, so a broken library elsewhere in the path cannot get in the way). */
static void installed_names(char *list, size_t size) {
  char dirs[MAX_DIRS][PATH_MAX];
  int n_dirs = plugin_dirs(dirs);
  list[0] = '\0';
  for (int d = 0; d < n_dirs; ++d) {
    char *files[MAX_FILES];
    int n_files = list_plugin_files(dirs[d], files);
    for (int i = 0; i < n_files; ++i) {
      size_t length = strlen(files[i]) - (sizeof file_prefix - 1) - (sizeof file_suffix - 1);
      const char *name = files[i] + sizeof file_prefix - 1;
      int listed = 0; /* a name shadowed by an earlier folder is listed once */
      for (const char *at = list; *at && !listed; at += strcspn(at, ",") + (at[strcspn(at, ",")] ? 2 : 0))
        listed = strncmp(at, name, length) == 0 && (at[length] == ',' || at[length] == '\0');
      size_t used = strlen(list);
      if (!listed) snprintf(list + used, size - used, "%s%.*s", used ? ", " : "", (int)length, name);
      free(files[i]);
    }
  }
}

/* Only the library of the plugin asked for is opened: libstickslip-<name>.so, first in the search path wins. */
sk_status sk_plugin_load(const char *name, const sk_plugin **plugin) {
  if (!is_plugin_name(name))
    return sk_error_set(SK_ERR_PLUGIN, "'%s' is not a plugin name (letters, digits, '-' and '_' only)",
                        name ? name : "");
  char dirs[MAX_DIRS][PATH_MAX];
  int n_dirs = plugin_dirs(dirs);
  for (int d = 0; d < n_dirs; ++d) {
    char path[PATH_MAX + 300];
    snprintf(path, sizeof path, "%s/%s%s%s", dirs[d], file_prefix, name, file_suffix);
    if (access(path, F_OK) != 0) continue;
    const sk_plugin *p;
    sk_status status = sk_plugin_open_file(path, &p);
    if (status != SK_OK) return sk_error_prefix(status, "plugin '%s' cannot be used: ", name);
    if (strcmp(p->name, name) != 0)
      return sk_error_set(SK_ERR_PLUGIN, "plugin library %s calls itself '%s'; a plugin's library must be named "
                          "%s<name>%s after it", path, p->name, file_prefix, file_suffix);
    *plugin = p;
    return SK_OK;
  }
  char available[1024];
  installed_names(available, sizeof available);
  return sk_error_set(SK_ERR_PLUGIN, "unknown plugin '%s' (available: %s; extra folders: STICKSLIP_PLUGIN_PATH)",
                      name, available[0] ? available : "none found");
}
