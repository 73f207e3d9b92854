/* The cache of generated meshes (mesh_internal.h): a .geo script meshed once with given parameters is read back
 * from a file instead of running gmsh again. The key hashes everything the generated mesh depends on — the script's
 * text (an untrusted script cannot Include or Merge other files, geo_scan.c, so the text is the whole input), the
 * parameters, the dimension asked for, mesh.max_elements, mesh.order and mesh.serendipity, the gmsh API version and this format — so an edited
 * script or another parameter is a different entry, never a stale one. Trusted scripts (--trust-scripts) may read
 * other files or act on the machine: they are never cached.
 *
 * Folder: $STICKSLIP_MESH_CACHE, else $XDG_CACHE_HOME/stickslip/meshes, else ~/.cache/stickslip/meshes;
 * STICKSLIP_MESH_CACHE=off turns the cache off. Concurrent runs are safe: an entry is written to a private
 * temporary file and renamed into place (atomic), so a reader sees a whole entry or none; a damaged entry (its
 * checksum or the mesh's own checks fail) is ignored and replaced. Entries are small (the serialized mesh, e.g.
 * 0.2 MB for 16 000 tetrahedra) and never expire: delete the folder to reclaim the space. */
#define _GNU_SOURCE
#include <errno.h>
#include <gmshc.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "mesh_internal.h"
#include "stickslip/files.h"

enum { CACHE_FORMAT = 1 };
static const char MAGIC[8] = {'s', 'k', 'm', 'e', 's', 'h', 'c', '1'};

static const uint64_t SEEDS[2] = {0xcbf29ce484222325ULL, 0x84222325cbf29ce4ULL};

static int make_folder(const char *path) {
  char partial[1024];
  snprintf(partial, sizeof partial, "%s", path);
  for (char *p = partial + 1; *p; ++p) {
    if (*p != '/') continue;
    *p = '\0';
    if (mkdir(partial, 0755) != 0 && errno != EEXIST) return 0;
    *p = '/';
  }
  return mkdir(partial, 0755) == 0 || errno == EEXIST;
}

static int cache_folder(char *out, size_t n, char *why, size_t why_n) {
  const char *env = getenv("STICKSLIP_MESH_CACHE"), *xdg = getenv("XDG_CACHE_HOME"), *home = getenv("HOME");
  if (env && strcmp(env, "off") == 0) {
    snprintf(why, why_n, "STICKSLIP_MESH_CACHE=off");
    return 0;
  }
  if (env && env[0]) snprintf(out, n, "%s", env);
  else if (xdg && xdg[0] == '/') snprintf(out, n, "%s/stickslip/meshes", xdg);
  else if (home && home[0] == '/') snprintf(out, n, "%s/.cache/stickslip/meshes", home);
  else {
    snprintf(why, why_n, "no cache folder (set STICKSLIP_MESH_CACHE, XDG_CACHE_HOME or HOME)");
    return 0;
  }
  if (!make_folder(out)) {
    snprintf(why, why_n, "cannot create the cache folder %.100s: %s", out, strerror(errno));
    return 0;
  }
  return 1;
}

static char *read_whole(const char *path, size_t *length) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  char *data = NULL;
  size_t used = 0, capacity = 0;
  for (;;) {
    if (used == capacity) {
      capacity = 2 * capacity + 65536;
      char *grown = realloc(data, capacity);
      if (!grown) break;
      data = grown;
    }
    size_t got = fread(data + used, 1, capacity - used, f);
    used += got;
    if (got == 0) break;
  }
  const int failed = ferror(f) || !feof(f);
  fclose(f);
  if (failed) {
    free(data);
    return NULL;
  }
  *length = used;
  return data;
}

void sk_mesh_cache_key_make(const char *path, const char *parameters, int dim, const sk_mesh_options *options,
                            sk_mesh_cache_key *key) {
  memset(key, 0, sizeof *key);
  if (sk_mesh_scripts_trusted()) {
    snprintf(key->why, sizeof key->why, "trusted scripts (--trust-scripts) may read other files: not cached");
    return;
  }
  char folder[900];
  if (!cache_folder(folder, sizeof folder, key->why, sizeof key->why)) return;
  size_t length = 0;
  char *text = read_whole(path, &length);
  if (!text) {
    snprintf(key->why, sizeof key->why, "cannot read the script");
    return;
  }
  char header[256];
  const int n = snprintf(header, sizeof header,
                         "format %d gmsh %s dim %d max_elements %ld order %d serendipity %d parameters ", CACHE_FORMAT,
                         GMSH_API_VERSION, dim, options->max_elements, options->order, options->serendipity);
  for (int h = 0; h < 2; ++h) {
    uint64_t hash = sk_fnv1a(SEEDS[h], header, (size_t)n);
    hash = sk_fnv1a(hash, parameters, strlen(parameters) + 1);
    key->hash[h] = sk_fnv1a(hash, text, length);
  }
  free(text);
  snprintf(key->file, sizeof key->file, "%s/%016llx%016llx.mesh", folder, (unsigned long long)key->hash[0],
           (unsigned long long)key->hash[1]);
}

/* entry: magic, the key's two hashes, the payload's length and checksum, the payload (sk_mesh_serialize) */
enum { HEADER = 8 + 4 * 8 };

int sk_mesh_cache_load(const sk_mesh_cache_key *key, sk_mesh *mesh) {
  if (!key->file[0]) return 0;
  size_t length = 0;
  char *data = read_whole(key->file, &length);
  if (!data) return 0;
  uint64_t head[4];
  int ok = length >= HEADER && memcmp(data, MAGIC, sizeof MAGIC) == 0;
  if (ok) {
    memcpy(head, data + 8, sizeof head);
    ok = head[0] == key->hash[0] && head[1] == key->hash[1] && head[2] == length - HEADER &&
         head[3] == sk_fnv1a(SEEDS[0], data + HEADER, length - HEADER);
  }
  char source[sizeof mesh->source];
  memcpy(source, mesh->source, sizeof source);
  if (ok && sk_mesh_deserialize(data + HEADER, length - HEADER, mesh) != SK_OK) ok = 0;
  free(data);
  if (!ok) {
    sk_mesh_free(mesh);
    memcpy(mesh->source, source, sizeof source);
  }
  return ok;
}

void sk_mesh_cache_store(const sk_mesh_cache_key *key, const sk_mesh *mesh) {
  if (!key->file[0]) return;
  uint64_t length = 0;
  char *payload = sk_mesh_serialize(mesh, &length);
  if (!payload) return;
  char temporary[1200];
  snprintf(temporary, sizeof temporary, "%s.XXXXXX", key->file);
  const int fd = mkstemp(temporary);
  if (fd < 0) {
    free(payload);
    return;
  }
  const uint64_t head[4] = {key->hash[0], key->hash[1], length, sk_fnv1a(SEEDS[0], payload, length)};
  FILE *f = fdopen(fd, "wb");
  int ok = f && fwrite(MAGIC, 1, sizeof MAGIC, f) == sizeof MAGIC && fwrite(head, 1, sizeof head, f) == sizeof head &&
           fwrite(payload, 1, length, f) == length;
  if (f) ok = fclose(f) == 0 && ok;
  else close(fd);
  free(payload);
  if (!ok || rename(temporary, key->file) != 0) unlink(temporary);
}

/* One line per .geo loaded by this process (a scene loads a handful; later ones beyond the table are counted). */
enum { MAX_NOTES = 16 };
static char notes[MAX_NOTES][1400];
static int n_notes;

void sk_mesh_cache_note(const char *path, const sk_mesh_cache_key *key, int hit) {
  if (n_notes >= MAX_NOTES) {
    ++n_notes;
    return;
  }
  char *line = notes[n_notes++];
  if (!key->file[0])
    snprintf(line, sizeof notes[0], "%s: not cached (%s): meshed by gmsh", path, key->why);
  else
    snprintf(line, sizeof notes[0], "%s: %s, key %016llx%016llx\n    entry %s", path,
             hit ? "hit: read from the cache, gmsh skipped" : "miss: meshed by gmsh, stored for the next run",
             (unsigned long long)key->hash[0], (unsigned long long)key->hash[1], key->file);
}

void sk_mesh_cache_explain(FILE *out) {
  if (n_notes == 0) return;
  fprintf(out, "mesh cache (generated meshes; docs/performance.md):\n");
  for (int k = 0; k < n_notes && k < MAX_NOTES; ++k) fprintf(out, "  %s\n", notes[k]);
  if (n_notes > MAX_NOTES) fprintf(out, "  ... and %d more .geo meshes\n", n_notes - MAX_NOTES);
}
