/* The results folder (--out DIR). What stickslip guarantees (docs/user-guide.md, "The results folder"):
 * - results appear complete or not at all: they are written into a staging folder DIR.partial-PID next to DIR and
 *   put in place by renames only at the end;
 * - only files stickslip wrote are ever replaced: every results folder carries a manifest (SK_OUTDIR_MARKER) listing
 *   its files (those in subfolders as "folder/file"), and an existing DIR is replaced only when every entry in it
 *   is listed there (or it is empty); any other file is a refusal naming it — before the run, and again at the end.
 *   The project's tools that write into a results folder (scripts/plot-*.sh) add what they wrote to the manifest
 *   (scripts/claim-results-files.sh): their files are the run's and go with it;
 * - a run that did not finish (failed, interrupted) never replaces finished results: it goes to DIR.incomplete;
 * - a run that cannot write (a full disk) leaves DIR as it was and removes its staging folder;
 * - staging folders of runs that were killed (SIGKILL, a crash) are named on the next run into the same DIR, not
 *   deleted: they hold the rows written before the kill. */
#define _DEFAULT_SOURCE /* realpath, DT_* */

#include <dirent.h>
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

#include "stickslip/output.h"

enum { PATH_CAP = 4096 };

static const char manifest_header[] = "# stickslip results folder: the files below were written by stickslip (or "
                                      "its tools: scripts/plot-*.sh); the next run into this folder may replace it, "
                                      "but only if it holds nothing else\n";
static const char *const status_names[] = {"ok", "failed", "interrupted"};

/* dir without trailing slashes ("out/" → "out"); "/" and "" are refused. */
static sk_status clean_dir_name(const char *dir, char *out) {
  size_t n = dir ? strlen(dir) : 0;
  while (n > 1 && dir[n - 1] == '/') --n;
  if (n == 0 || (n == 1 && dir[0] == '/')) {
    return sk_error_set(SK_ERR_INPUT, "output directory '%s' is not usable", dir ? dir : "");
  }
  if (n >= PATH_CAP - 64) return sk_error_set(SK_ERR_INPUT, "output directory path '%s' is too long", dir);
  memcpy(out, dir, n);
  out[n] = '\0';
  return SK_OK;
}

static int path_exists(const char *path) {
  struct stat st;
  return lstat(path, &st) == 0;
}

/* mkdir -p of the parent directories of `path`. */
static sk_status make_parents(const char *path) {
  char buf[PATH_CAP];
  snprintf(buf, sizeof buf, "%s", path);
  for (char *c = buf + 1; *c; ++c) {
    if (*c != '/') continue;
    *c = '\0';
    if (mkdir(buf, 0777) != 0 && errno != EEXIST) {
      return sk_error_set(SK_ERR_IO, "cannot create directory '%s': %s", buf, strerror(errno));
    }
    *c = '/';
  }
  return SK_OK;
}

/* ---- the manifest ------------------------------------------------------------------------------------------- */

typedef struct {
  int found;       /* the folder has a manifest */
  int listed;      /* it lists files (older stickslip wrote a bare marker) */
  char status[16]; /* "ok", "failed", "interrupted", or "" */
  char *text;      /* the file names, one per line */
} manifest;

static void manifest_read(const char *dir, manifest *m) {
  memset(m, 0, sizeof *m);
  char path[PATH_CAP + 64];
  snprintf(path, sizeof path, "%s/%s", dir, SK_OUTDIR_MARKER);
  FILE *f = fopen(path, "r");
  if (!f) return;
  m->found = 1;
  size_t cap = 4096, used = 0;
  m->text = malloc(cap);
  char line[1024];
  while (m->text && fgets(line, sizeof line, f)) {
    if (line[0] == '#') {
      m->listed = 1; /* the header of a manifest (the bare marker has none) */
      continue;
    }
    if (strncmp(line, "status: ", 8) == 0) {
      sscanf(line + 8, "%15s", m->status);
      continue;
    }
    size_t n = strlen(line);
    if (used + n + 1 > cap) {
      char *grown = realloc(m->text, 2 * cap + n);
      if (!grown) break;
      m->text = grown;
      cap = 2 * cap + n;
    }
    memcpy(m->text + used, line, n);
    used += n;
  }
  if (m->text) m->text[used] = '\0';
  fclose(f);
}

static int manifest_lists(const manifest *m, const char *name) {
  size_t n = strlen(name);
  for (const char *at = m->text; at && *at;) {
    const char *end = strchr(at, '\n');
    size_t len = end ? (size_t)(end - at) : strlen(at);
    if (len == n && strncmp(at, name, n) == 0) return 1;
    at = end ? end + 1 : at + len;
  }
  return 0;
}

/* Names stickslip has always written, for folders of older versions whose marker lists nothing. */
static int is_output_name(const char *name) {
  static const char *const names[] = {"history.csv", "contact.csv", "summary.json", "scene.yaml", "results.pvd", NULL};
  for (int k = 0; names[k]; ++k)
    if (strcmp(name, names[k]) == 0) return 1;
  size_t n = strlen(name);
  return strncmp(name, "step-", 5) == 0 && n > 9 && strcmp(name + n - 4, ".vtu") == 0;
}

static int is_directory(const char *path) {
  struct stat st;
  return lstat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

/* Calls visit(ctx, name, path) for every entry below `dir` but the manifest, `name` relative to the results folder
 * ("snapshots/step-000010.png"; `prefix` is "" at the top) and `path` NULL when it is too long to form. The visitor
 * returns 1 to enter a folder, 0 not to, -1 to stop (with the error it set). */
typedef int (*entry_visitor)(void *ctx, const char *name, const char *path);

static sk_status walk(const char *dir, const char *prefix, entry_visitor visit, void *ctx) {
  DIR *d = opendir(dir);
  if (!d) return sk_error_set(SK_ERR_IO, "cannot open directory '%s': %s", dir, strerror(errno));
  sk_status status = SK_OK;
  struct dirent *e;
  while (status == SK_OK && (e = readdir(d)) != NULL) {
    if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..") || (!prefix[0] && !strcmp(e->d_name, SK_OUTDIR_MARKER)))
      continue;
    char name[PATH_CAP], path[PATH_CAP];
    int fits = (size_t)snprintf(name, sizeof name, "%s%s", prefix, e->d_name) < sizeof name &&
               (size_t)snprintf(path, sizeof path, "%s/%s", dir, e->d_name) < sizeof path;
    int enter = visit(ctx, name, fits ? path : NULL);
    if (enter < 0) {
      status = SK_ERR_IO;
    } else if (enter && fits && is_directory(path)) {
      char sub[PATH_CAP + 1];
      snprintf(sub, sizeof sub, "%s/", name);
      status = walk(path, sub, visit, ctx);
    }
  }
  closedir(d);
  return status;
}

/* The manifest lists every entry, those in folders too. */
static int list_entry(void *ctx, const char *name, const char *path) {
  if (!path) {
    sk_error_set(SK_ERR_IO, "path too long: '%s'", name);
    return -1;
  }
  fprintf((FILE *)ctx, "%s\n", name);
  return 1;
}

/* Writes the manifest of `dir`: every entry in it now, and the status. */
static sk_status manifest_write(const char *dir, sk_results_status status) {
  char path[PATH_CAP + 64];
  snprintf(path, sizeof path, "%s/%s", dir, SK_OUTDIR_MARKER);
  FILE *f = fopen(path, "w");
  if (!f) return sk_error_set(SK_ERR_IO, "cannot write '%s': %s", path, strerror(errno));
  fputs(manifest_header, f);
  fprintf(f, "status: %s\n", status_names[status]);
  sk_status listed = walk(dir, "", list_entry, f);
  if (listed != SK_OK) {
    fclose(f);
    return listed;
  }
  int failed = ferror(f);
  if (fclose(f) != 0 || failed) return sk_error_set(SK_ERR_IO, "cannot write '%s': %s", path, strerror(errno));
  return SK_OK;
}

/* ---- what may be replaced ------------------------------------------------------------------------------------ */

/* rm -r without following symbolic links. */
static sk_status remove_tree(const char *path) {
  struct stat st;
  if (lstat(path, &st) != 0) {
    if (errno == ENOENT) return SK_OK;
    return sk_error_set(SK_ERR_IO, "cannot inspect '%s': %s", path, strerror(errno));
  }
  if (S_ISDIR(st.st_mode)) {
    DIR *d = opendir(path);
    if (!d) return sk_error_set(SK_ERR_IO, "cannot open directory '%s': %s", path, strerror(errno));
    struct dirent *e;
    sk_status status = SK_OK;
    while (status == SK_OK && (e = readdir(d)) != NULL) {
      if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0) continue;
      char child[PATH_CAP];
      if ((size_t)snprintf(child, sizeof child, "%s/%s", path, e->d_name) >= sizeof child) {
        status = sk_error_set(SK_ERR_IO, "path too long below '%s'", path);
      } else {
        status = remove_tree(child);
      }
    }
    closedir(d);
    if (status != SK_OK) return status;
    if (rmdir(path) != 0) return sk_error_set(SK_ERR_IO, "cannot remove directory '%s': %s", path, strerror(errno));
    return SK_OK;
  }
  if (unlink(path) != 0) return sk_error_set(SK_ERR_IO, "cannot remove '%s': %s", path, strerror(errno));
  return SK_OK;
}

enum { FOREIGN_NAMED = 3 };
typedef struct {
  char names[FOREIGN_NAMED][PATH_CAP / 4]; /* the first few in name order */
  int n;
} foreign_files;

static void add_foreign(foreign_files *foreign, const char *name) {
  int at = foreign->n < FOREIGN_NAMED ? foreign->n : FOREIGN_NAMED;
  while (at > 0 && strcmp(name, foreign->names[at - 1]) < 0) {
    if (at < FOREIGN_NAMED) memcpy(foreign->names[at], foreign->names[at - 1], sizeof foreign->names[at]);
    --at;
  }
  if (at < FOREIGN_NAMED) snprintf(foreign->names[at], sizeof foreign->names[at], "%s", name);
  ++foreign->n;
}

/* The entries of a results folder that its manifest does not list. A listed folder is the run's only with everything
 * in it listed too ("sub/file"): a file of the user's put into a folder a tool wrote (snapshots/) is not lost with
 * it. A path too long to form is not ours to remove. */
typedef struct {
  const manifest *m;
  foreign_files *foreign;
} foreign_search;

static int find_foreign(void *ctx, const char *name, const char *path) {
  const foreign_search *search = ctx;
  const manifest *m = search->m;
  int top = strchr(name, '/') == NULL;
  int ours = path && m->found && (m->listed ? manifest_lists(m, name) : top && is_output_name(name));
  if (!ours) add_foreign(search->foreign, name);
  return ours && m->listed; /* enter the run's folders to look at what is in them */
}

/* May `dir` be replaced? Yes if it does not exist, is empty, or holds only files its manifest lists (files of the
 * known output names for a bare marker of an older version). Otherwise an error naming the first foreign file;
 * `where` (may be NULL) says where the new results are waiting. */
static sk_status check_replaceable(const char *dir, const char *where) {
  struct stat st;
  if (lstat(dir, &st) != 0) {
    if (errno == ENOENT) return SK_OK;
    return sk_error_set(SK_ERR_IO, "cannot inspect '%s': %s", dir, strerror(errno));
  }
  const char *kept = where ? "; the new results are in " : "";
  if (!S_ISDIR(st.st_mode))
    return sk_error_set(SK_ERR_IO, "refusing to replace '%s': it exists and is not a directory%s%s", dir, kept,
                        where ? where : "");
  manifest m;
  manifest_read(dir, &m);
  foreign_files foreign = {.n = 0};
  foreign_search search = {&m, &foreign};
  sk_status status = walk(dir, "", find_foreign, &search);
  int found = m.found;
  free(m.text);
  if (status != SK_OK) return status;
  const int n_foreign = foreign.n;
  if (n_foreign == 0) return SK_OK;
  char list[900] = "";
  for (int k = 0; k < n_foreign && k < FOREIGN_NAMED; ++k)
    snprintf(list + strlen(list), sizeof list - strlen(list), "%s'%s'", k ? ", " : "", foreign.names[k]);
  if (n_foreign > FOREIGN_NAMED)
    snprintf(list + strlen(list), sizeof list - strlen(list), " and %d more", n_foreign - FOREIGN_NAMED);
  return sk_error_set(SK_ERR_IO,
                      "refusing to replace '%s': it holds %s, which stickslip did not write%s; move %s away or "
                      "choose another --out%s%s",
                      dir, list, found ? "" : " (it is not a stickslip results folder)",
                      n_foreign > 1 ? "them" : "it", kept, where ? where : "");
}

/* The results folder must not be the current directory or one that contains it: replacing it would pull the
 * folder out from under the user's shell (and "--out ." would stage into "..partial-PID"). */
static sk_status check_not_cwd(const char *dir) {
  char *real = realpath(dir, NULL), *cwd = realpath(".", NULL);
  int contains_cwd = 0;
  if (real && cwd) {
    size_t n = strlen(real);
    contains_cwd = strncmp(cwd, real, n) == 0 && (cwd[n] == '\0' || cwd[n] == '/' || n == 1);
  }
  free(real);
  free(cwd);
  if (contains_cwd)
    return sk_error_set(SK_ERR_INPUT, "--out '%s' is the current directory or contains it: stickslip replaces the "
                        "results folder as a whole, so give it a folder of its own (e.g. --out results)", dir);
  return SK_OK;
}

/* Staging folders "BASE.partial-PID" (or "BASE.partial-PID.N") of processes that no longer exist: killed runs. */
static void name_stale_staging(const char *clean) {
  char parent[PATH_CAP];
  snprintf(parent, sizeof parent, "%s", clean);
  char *slash = strrchr(parent, '/');
  const char *base = slash ? slash + 1 : clean;
  if (slash) *slash = '\0';
  DIR *d = opendir(slash ? (parent[0] ? parent : "/") : ".");
  if (!d) return;
  size_t n = strlen(base);
  struct dirent *e;
  while ((e = readdir(d)) != NULL) {
    if (strncmp(e->d_name, base, n) != 0) continue;
    const char *tail = e->d_name + n;
    int partial = strncmp(tail, ".partial-", 9) == 0, old = strncmp(tail, ".old-", 5) == 0;
    if (!partial && !old) continue;
    const char *digits = tail + (partial ? 9 : 5);
    char *end;
    long pid = strtol(digits, &end, 10);
    if (end == digits || (*end && *end != '.') || pid <= 0) continue;
    if (kill((pid_t)pid, 0) == 0 || errno != ESRCH) continue; /* still running (another run into the same DIR) */
    fprintf(stderr, "note: %s%s%s holds %s of process %ld, which ended without finishing (killed?); stickslip "
            "leaves it for you to inspect or delete\n", slash ? parent : "", slash ? "/" : "", e->d_name,
            partial ? "the unfinished results" : "earlier results it was replacing", pid);
  }
  closedir(d);
}

/* ---- the public steps ----------------------------------------------------------------------------------------- */

sk_status sk_outdir_begin(const char *dir, char *staging, size_t staging_size) {
  char clean[PATH_CAP];
  SK_TRY(clean_dir_name(dir, clean));
  if (path_exists(clean)) SK_TRY(check_not_cwd(clean));
  SK_TRY(check_replaceable(clean, NULL)); /* refuse before the run rather than after it */
  SK_TRY(make_parents(clean));
  name_stale_staging(clean);
  /* DIR.partial-PID, or DIR.partial-PID.N when a killed process with our PID left one */
  for (int k = 1;; ++k) {
    int n = k == 1 ? snprintf(staging, staging_size, "%s.partial-%ld", clean, (long)getpid())
                   : snprintf(staging, staging_size, "%s.partial-%ld.%d", clean, (long)getpid(), k);
    if (n < 0 || (size_t)n >= staging_size)
      return sk_error_set(SK_ERR_INTERNAL, "staging path for '%s' does not fit in %zu bytes", dir, staging_size);
    if (mkdir(staging, 0777) == 0) break;
    if (errno != EEXIST || k == 100)
      return sk_error_set(SK_ERR_IO, "cannot create output directory '%s': %s", staging, strerror(errno));
  }
  char marker[PATH_CAP + 64];
  snprintf(marker, sizeof marker, "%s/%s", staging, SK_OUTDIR_MARKER);
  FILE *f = fopen(marker, "w");
  if (!f || fputs(manifest_header, f) < 0 || fputs("status: running\n", f) < 0 || fclose(f) != 0) {
    return sk_error_set(SK_ERR_IO, "cannot write '%s': %s", marker, strerror(errno));
  }
  return SK_OK;
}

/* Puts `staging` in place of `target` (which check_replaceable accepted): the old folder is moved aside first, so
 * `target` is never half old, half new, and comes back if the second rename fails. */
static sk_status replace(const char *staging, const char *target) {
  if (!path_exists(target)) {
    if (rename(staging, target) != 0)
      return sk_error_set(SK_ERR_IO, "cannot rename '%s' to '%s': %s; the results are in %s", staging, target,
                          strerror(errno), staging);
    return SK_OK;
  }
  char old[PATH_CAP + 32];
  snprintf(old, sizeof old, "%s.old-%ld", target, (long)getpid());
  SK_TRY(check_replaceable(old, staging)); /* a leftover of ours at worst; never someone else's */
  SK_TRY(remove_tree(old));
  if (rename(target, old) != 0)
    return sk_error_set(SK_ERR_IO, "cannot move '%s' aside to '%s': %s; the results are in %s", target, old,
                        strerror(errno), staging);
  if (rename(staging, target) != 0) {
    sk_status status = sk_error_set(SK_ERR_IO, "cannot rename '%s' to '%s': %s; the results are in %s", staging,
                                    target, strerror(errno), staging);
    rename(old, target); /* put the previous results back */
    return status;
  }
  return remove_tree(old);
}

sk_status sk_outdir_commit(const char *staging, const char *dir, sk_results_status status, char *final_dir,
                           size_t final_size) {
  if (final_dir && final_size) snprintf(final_dir, final_size, "%s", staging);
  char clean[PATH_CAP];
  SK_TRY(clean_dir_name(dir, clean));
  SK_TRY(manifest_write(staging, status));
  /* unfinished results never replace finished ones */
  char target[PATH_CAP + 16];
  snprintf(target, sizeof target, "%s", clean);
  if (status != SK_RESULTS_OK) {
    manifest m;
    manifest_read(clean, &m);
    free(m.text);
    int finished = m.found && (m.status[0] ? strcmp(m.status, "ok") == 0 : m.listed == 0);
    if (finished) snprintf(target, sizeof target, "%s.incomplete", clean);
  }
  SK_TRY(check_replaceable(target, staging));
  SK_TRY(replace(staging, target));
  if (final_dir && final_size) snprintf(final_dir, final_size, "%s", target);
  return SK_OK;
}

sk_status sk_outdir_abort(const char *staging) {
  if (!staging || !staging[0] || !path_exists(staging)) return SK_OK;
  manifest m;
  manifest_read(staging, &m);
  free(m.text);
  if (!m.found || strcmp(m.status, "running") != 0)
    return sk_error_set(SK_ERR_IO, "not removing '%s': it is not a stickslip staging directory", staging);
  return remove_tree(staging);
}
