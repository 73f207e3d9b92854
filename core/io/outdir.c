/* Output directories that appear complete or not at all: results go to "DIR.partial-PID" and replace DIR by
 * renames only at the end. Only directories stickslip made (or empty ones) are ever deleted. */
#define _POSIX_C_SOURCE 200809L

#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

#include "stickslip/output.h"

enum { PATH_CAP = 4096 };

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

/* 1 if the directory has no entries, 0 if it has, -1 if it cannot be read. */
static int dir_is_empty(const char *path) {
  DIR *d = opendir(path);
  if (!d) return -1;
  int empty = 1;
  struct dirent *e;
  while ((e = readdir(d)) != NULL) {
    if (strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0) {
      empty = 0;
      break;
    }
  }
  closedir(d);
  return empty;
}

/* Made by stickslip: the marker file, or a summary.json that names stickslip. */
static int is_stickslip_dir(const char *path) {
  char file[PATH_CAP];
  snprintf(file, sizeof file, "%s/%s", path, SK_OUTDIR_MARKER);
  if (path_exists(file)) return 1;
  snprintf(file, sizeof file, "%s/summary.json", path);
  FILE *f = fopen(file, "r");
  if (!f) return 0;
  char text[65536];
  size_t n = fread(text, 1, sizeof text - 1, f);
  fclose(f);
  text[n] = '\0';
  return strstr(text, "stickslip") != NULL;
}

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

/* An existing `dir` may be replaced only if it is empty or made by stickslip; `staging` names where the new
 * results wait (NULL before the run). */
static sk_status check_replaceable(const char *dir, const char *staging) {
  struct stat st;
  if (lstat(dir, &st) != 0) {
    if (errno == ENOENT) return SK_OK;
    return sk_error_set(SK_ERR_IO, "cannot inspect '%s': %s", dir, strerror(errno));
  }
  const char *kept = staging ? "; results are in " : "";
  if (!S_ISDIR(st.st_mode)) {
    return sk_error_set(SK_ERR_IO, "refusing to replace '%s': it exists and is not a directory%s%s", dir, kept,
                        staging ? staging : "");
  }
  if (dir_is_empty(dir) != 1 && !is_stickslip_dir(dir)) {
    return sk_error_set(SK_ERR_IO,
                        "refusing to replace '%s': it is not empty and is not a stickslip output directory (no %s "
                        "or stickslip summary.json); move it away or choose another output%s%s",
                        dir, SK_OUTDIR_MARKER, kept, staging ? staging : "");
  }
  return SK_OK;
}

sk_status sk_outdir_begin(const char *dir, char *staging, size_t staging_size) {
  char clean[PATH_CAP];
  SK_TRY(clean_dir_name(dir, clean));
  SK_TRY(check_replaceable(clean, NULL)); /* refuse before the run rather than after it */
  int n = snprintf(staging, staging_size, "%s.partial-%ld", clean, (long)getpid());
  if (n < 0 || (size_t)n >= staging_size) {
    return sk_error_set(SK_ERR_INTERNAL, "staging path for '%s' does not fit in %zu bytes", dir, staging_size);
  }
  SK_TRY(make_parents(clean));
  if (path_exists(staging)) {
    /* Left over by an earlier process with the same id: ours to remove, but only if it is one of ours. */
    if (!is_stickslip_dir(staging) && dir_is_empty(staging) != 1) {
      return sk_error_set(SK_ERR_IO, "'%s' exists and was not made by stickslip; remove it by hand", staging);
    }
    SK_TRY(remove_tree(staging));
  }
  if (mkdir(staging, 0777) != 0) {
    return sk_error_set(SK_ERR_IO, "cannot create output directory '%s': %s", staging, strerror(errno));
  }
  char marker[PATH_CAP];
  snprintf(marker, sizeof marker, "%s/%s", staging, SK_OUTDIR_MARKER);
  FILE *f = fopen(marker, "w");
  if (!f || fputs("stickslip output directory: may be replaced by the next run\n", f) < 0 || fclose(f) != 0) {
    return sk_error_set(SK_ERR_IO, "cannot write '%s': %s", marker, strerror(errno));
  }
  return SK_OK;
}

sk_status sk_outdir_commit(const char *staging, const char *dir) {
  char clean[PATH_CAP];
  SK_TRY(clean_dir_name(dir, clean));
  struct stat st;
  if (lstat(clean, &st) != 0) {
    if (errno != ENOENT) return sk_error_set(SK_ERR_IO, "cannot inspect '%s': %s", clean, strerror(errno));
    if (rename(staging, clean) != 0) {
      return sk_error_set(SK_ERR_IO, "cannot rename '%s' to '%s': %s", staging, clean, strerror(errno));
    }
    return SK_OK;
  }
  SK_TRY(check_replaceable(clean, staging));
  /* Move the old results aside first, so `dir` is never half old, half new. */
  char old[PATH_CAP + 32];
  snprintf(old, sizeof old, "%s.old-%ld", clean, (long)getpid());
  SK_TRY(check_replaceable(old, staging)); /* a leftover of ours at worst; never someone else's */
  SK_TRY(remove_tree(old));
  if (rename(clean, old) != 0) {
    return sk_error_set(SK_ERR_IO, "cannot move '%s' aside to '%s': %s", clean, old, strerror(errno));
  }
  if (rename(staging, clean) != 0) {
    sk_status status = sk_error_set(SK_ERR_IO, "cannot rename '%s' to '%s': %s", staging, clean, strerror(errno));
    rename(old, clean); /* put the previous results back */
    return status;
  }
  return remove_tree(old);
}

sk_status sk_outdir_abort(const char *staging) {
  if (!staging || !staging[0] || !path_exists(staging)) return SK_OK;
  if (!is_stickslip_dir(staging) && dir_is_empty(staging) != 1) {
    return sk_error_set(SK_ERR_IO, "not removing '%s': it is not a stickslip staging directory", staging);
  }
  return remove_tree(staging);
}
