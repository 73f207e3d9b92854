/* Checkpoints and restarts (checkpoint.h). A checkpoint folder (--checkpoint DIR) holds stickslip's marker, a file
 * `latest` naming the newest checkpoint, and the last two checkpoints as step-NNNNNNNN folders, each with
 *   checkpoint.yaml   the scene it was written for (file, --set values, --plugin, hashes of the scene file and the
 *                     mesh), the time, the stepper's and the recorder's counters (rank 0);
 *   history.csv       the rows written so far (rank 0, with --out);
 *   state-RRRR.bin    each rank's owned nodes (mesh id, u, v, rate) and its plugin instances' records, with a
 *                     checksum and an end mark, so that a truncated or damaged file is refused.
 * A checkpoint is written into a hidden folder and renamed into place once every rank has written its file, so a
 * checkpoint appears complete or not at all; older ones are removed only after the new one is in place, and only
 * the files stickslip wrote. A restart reads every rank's file on every rank and keeps what each rank holds (the
 * state is keyed by mesh ids and the plugins' entity keys), so it runs on any number of ranks. */
#define _GNU_SOURCE
#include "checkpoint.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "stickslip/config.h"
#include "stickslip/files.h"

enum { FORMAT = 1, KEEP = 2 };
static const char MARKER[] = ".stickslip-checkpoints";
static const char STATE_MAGIC[8] = {'S', 'K', 'S', 'T', 'A', 'T', 'E', '1'};
static const char END_MAGIC[8] = {'S', 'K', 'S', 'T', 'E', 'N', 'D', '1'};

static const uint64_t FNV_SEED = 0xcbf29ce484222325ULL;

uint64_t sk_checkpoint_file_hash(const char *path) {
  FILE *f = fopen(path, "rb");
  if (!f) return 0;
  uint64_t hash = FNV_SEED;
  char buffer[65536];
  size_t got;
  while ((got = fread(buffer, 1, sizeof buffer, f)) > 0) hash = sk_fnv1a(hash, buffer, got);
  fclose(f);
  return hash;
}

uint64_t sk_checkpoint_mesh_hash(const sk_model *m) {
  uint64_t mine = 0;
  for (int a = 0; a < m->n_nodes; ++a) {
    if (m->node_owner[a] != m->rank) continue;
    uint64_t h = sk_fnv1a(FNV_SEED, &m->node_gid[a], sizeof(int64_t));
    h = sk_fnv1a(h, m->X + (size_t)a * m->dim, sizeof(double) * (size_t)m->dim);
    mine ^= h;
  }
  uint64_t all = 0;
  MPI_Allreduce(&mine, &all, 1, MPI_UINT64_T, MPI_BXOR, m->comm);
  return all;
}

/* ---- a growing byte buffer ----------------------------------------------------------------------------------- */

typedef struct {
  unsigned char *data;
  size_t size, cap;
  int failed;
} buffer;

static void put(buffer *b, const void *data, size_t n) {
  if (b->failed) return;
  if (b->size + n > b->cap) {
    size_t cap = 2 * (b->size + n) + 4096;
    unsigned char *grown = realloc(b->data, cap);
    if (!grown) {
      b->failed = 1;
      return;
    }
    b->data = grown;
    b->cap = cap;
  }
  memcpy(b->data + b->size, data, n);
  b->size += n;
}

typedef struct {
  sk_record_writer abi;
  buffer *out;
  int64_t count;
} record_writer;

static void writer_put(sk_record_writer *abi, int64_t key, const void *data, uint32_t bytes) {
  record_writer *w = (record_writer *)abi;
  put(w->out, &key, sizeof key);
  put(w->out, &bytes, sizeof bytes);
  put(w->out, data, bytes);
  w->count++;
}

/* ---- paths ---------------------------------------------------------------------------------------------------- */

static void step_name(int64_t step, char *out, size_t n) { snprintf(out, n, "step-%08lld", (long long)step); }

static int is_dir(const char *path) {
  struct stat st;
  return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

/* The checkpoint folder is stickslip's: empty or new (then marked), or carrying the marker (rank 0). */
static sk_status claim_folder(const char *dir) {
  char path[4200];
  if (!is_dir(dir)) {
    char partial[4200];
    snprintf(partial, sizeof partial, "%s", dir);
    for (char *c = partial + 1; *c; ++c) {
      if (*c != '/') continue;
      *c = '\0';
      if (mkdir(partial, 0777) != 0 && errno != EEXIST)
        return sk_error_set(SK_ERR_IO, "checkpoints: cannot create folder '%s': %s", partial, strerror(errno));
      *c = '/';
    }
    if (mkdir(dir, 0777) != 0 && errno != EEXIST)
      return sk_error_set(SK_ERR_IO, "checkpoints: cannot create folder '%s': %s", dir, strerror(errno));
  }
  snprintf(path, sizeof path, "%s/%s", dir, MARKER);
  if (access(path, F_OK) != 0) {
    DIR *d = opendir(dir);
    if (!d) return sk_error_set(SK_ERR_IO, "checkpoints: cannot read folder '%s': %s", dir, strerror(errno));
    struct dirent *e;
    const char *other = NULL;
    while ((e = readdir(d)))
      if (strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0) {
        other = e->d_name;
        break;
      }
    sk_status status = other ? sk_error_set(SK_ERR_INPUT, "checkpoints: folder '%s' holds '%s', which stickslip did not "
                                            "write: give --checkpoint an empty or new folder", dir, other)
                             : SK_OK;
    closedir(d);
    if (status != SK_OK) return status;
    FILE *f = fopen(path, "w");
    if (!f || fprintf(f, "stickslip checkpoints: the step-* folders and `latest` here were written by stickslip\n") < 0 ||
        fclose(f) != 0)
      return sk_error_set(SK_ERR_IO, "checkpoints: cannot write '%s': %s", path, strerror(errno));
  }
  return SK_OK;
}

/* Removes a step folder stickslip wrote (only its own files; a folder with anything else stays). */
static void remove_step(const char *folder) {
  DIR *d = opendir(folder);
  if (!d) return;
  struct dirent *e;
  char path[4400];
  while ((e = readdir(d))) {
    const char *n = e->d_name;
    const int ours = strcmp(n, "checkpoint.yaml") == 0 || strcmp(n, "history.csv") == 0 ||
                     strcmp(n, "contact.csv") == 0 ||
                     (strncmp(n, "state-", 6) == 0 && strstr(n, ".bin"));
    if (!ours) continue;
    snprintf(path, sizeof path, "%s/%s", folder, n);
    unlink(path);
  }
  closedir(d);
  rmdir(folder);
}

/* Keeps the KEEP newest step folders (rank 0, after a new one is in place). */
static void prune(const char *dir) {
  DIR *d = opendir(dir);
  if (!d) return;
  char names[64][32];
  int n = 0;
  struct dirent *e;
  while ((e = readdir(d)) && n < 64)
    if (strncmp(e->d_name, "step-", 5) == 0 && strlen(e->d_name) < sizeof names[0]) snprintf(names[n++], sizeof names[0], "%s", e->d_name);
  closedir(d);
  qsort(names, (size_t)n, sizeof names[0], (int (*)(const void *, const void *))strcmp);
  char path[4200];
  for (int k = 0; k + KEEP < n; ++k) {
    snprintf(path, sizeof path, "%s/%s", dir, names[k]);
    remove_step(path);
  }
}

/* ---- writing ------------------------------------------------------------------------------------------------- */

sk_status sk_checkpoint_check(sk_system *sys, const sk_run_options *options) {
  if (options->checkpoint_every <= 0) return SK_OK;
  sk_status status = SK_OK;
  for (int k = 0; k < sys->n_terms && status == SK_OK; ++k) {
    const char *plugin = NULL;
    if (sk_term_plugin_checkpointable(sys->terms[k], &plugin) == 0)
      status = sk_error_set(SK_ERR_INPUT, "--checkpoint-every: %s: plugin '%s' does not say how to save its history "
                            "(it offers no stickslip.checkpoint.v1, docs/plugin-abi.md), so a restart could not "
                            "continue it", sys->terms[k]->name, plugin);
  }
  if (status == SK_OK && !options->checkpoint_dir)
    status = sk_error_set(SK_ERR_INPUT, "--checkpoint-every needs a folder: --checkpoint DIR, or --out DIR (then "
                          "DIR.checkpoint)");
  if (status == SK_OK && sys->rank == 0) status = claim_folder(options->checkpoint_dir);
  return sk_system_collective(sys, status);
}

/* This rank's state file: owned nodes and the plugin terms' records. */
static sk_status state_bytes(sk_system *sys, buffer *b) {
  const sk_model *m = sys->model;
  const int dim = m->dim;
  put(b, STATE_MAGIC, sizeof STATE_MAGIC);
  const int32_t head[4] = {sys->rank, sys->n_ranks, dim, FORMAT};
  put(b, head, sizeof head);
  int64_t n_owned = 0;
  for (int a = 0; a < m->n_nodes; ++a) n_owned += m->node_owner[a] == m->rank;
  put(b, &n_owned, sizeof n_owned);
  for (int a = 0; a < m->n_nodes; ++a) {
    if (m->node_owner[a] != m->rank) continue;
    put(b, &m->node_gid[a], sizeof(int64_t));
    double values[9];
    for (int i = 0; i < dim; ++i) {
      const int64_t d = (int64_t)a * dim + i;
      values[i] = sys->x[d];
      values[dim + i] = sys->v[d];
      values[2 * dim + i] = (sys->x[d] - sys->u_n[d]) / sys->dt;
    }
    put(b, values, sizeof(double) * 3 * (size_t)dim);
  }
  int32_t n_plugins = 0;
  for (int k = 0; k < sys->n_terms; ++k) n_plugins += sk_term_plugin_checkpointable(sys->terms[k], NULL) >= 0;
  put(b, &n_plugins, sizeof n_plugins);
  sk_status status = SK_OK;
  for (int k = 0; k < sys->n_terms && status == SK_OK; ++k) {
    sk_term *term = sys->terms[k];
    if (sk_term_plugin_checkpointable(term, NULL) < 0) continue;
    const int32_t len = (int32_t)strlen(term->name);
    put(b, &len, sizeof len);
    put(b, term->name, (size_t)len);
    const size_t count_at = b->size;
    int64_t count = 0;
    put(b, &count, sizeof count);
    record_writer w = {.abi = {SK_TABLE_HEADER(sk_record_writer), .put = writer_put}, .out = b};
    status = sk_term_plugin_save(term, sys, &w.abi);
    if (status != SK_OK) sk_error_prefix(status, "%s: ", term->name);
    if (!b->failed) memcpy(b->data + count_at, &w.count, sizeof w.count);
  }
  const uint64_t sum = b->failed ? 0 : sk_fnv1a(FNV_SEED, b->data, b->size);
  put(b, &sum, sizeof sum);
  put(b, END_MAGIC, sizeof END_MAGIC);
  if (status == SK_OK && b->failed) status = sk_error_set(SK_ERR_NOMEM, "checkpoint: out of memory for the state");
  return status;
}

static sk_status write_file(const char *path, const void *data, size_t n) {
  FILE *f = fopen(path, "wb");
  if (!f) return sk_error_set(SK_ERR_IO, "checkpoint: cannot write '%s': %s", path, strerror(errno));
  const size_t written = fwrite(data, 1, n, f);
  const int flushed = fflush(f) == 0 && fsync(fileno(f)) == 0;
  if (fclose(f) != 0 || written != n || !flushed)
    return sk_error_set(SK_ERR_IO, "checkpoint: writing '%s' failed: %s", path, strerror(errno));
  return SK_OK;
}

static sk_status copy_file(const char *from, const char *to) {
  FILE *in = fopen(from, "rb");
  if (!in) return sk_error_set(SK_ERR_IO, "checkpoint: cannot read '%s': %s", from, strerror(errno));
  buffer b = {0};
  char chunk[65536];
  size_t got;
  while ((got = fread(chunk, 1, sizeof chunk, in)) > 0) put(&b, chunk, got);
  fclose(in);
  sk_status status = b.failed ? sk_error_set(SK_ERR_NOMEM, "checkpoint: out of memory copying '%s'", from)
                              : write_file(to, b.data, b.size);
  free(b.data);
  return status;
}

/* checkpoint.yaml: a YAML map the restart reads with the scene reader (sk_cfg). */
static sk_status write_description(const char *path, const sk_run_options *options, sk_system *sys,
                                   const sk_progress *p, const sk_recorder_state *rec, uint64_t mesh_hash) {
  FILE *f = fopen(path, "w");
  if (!f) return sk_error_set(SK_ERR_IO, "checkpoint: cannot write '%s': %s", path, strerror(errno));
  char scene[4096];
  if (!options->scene_path || !realpath(options->scene_path, scene))
    snprintf(scene, sizeof scene, "%s", options->scene_path ? options->scene_path : "");
  fprintf(f, "# stickslip checkpoint: `stickslip run --restart %s` continues from here\n", "FOLDER");
  fprintf(f, "format: %d\n", FORMAT);
  fprintf(f, "scene: \"%s\"\n", scene);
  fprintf(f, "scene_hash: \"%016llx\"\n", (unsigned long long)sk_checkpoint_file_hash(scene));
  fprintf(f, "mesh_hash: \"%016llx\"\n", (unsigned long long)mesh_hash);
  fprintf(f, "plugin: \"%s\"\n", options->plugin ? options->plugin : "");
  fprintf(f, "sets:\n");
  for (int k = 0; k < options->n_sets; ++k) {
    fputs("  - \"", f);
    for (const char *c = options->sets[k]; *c; ++c) {
      if (*c == '"' || *c == '\\') fputc('\\', f);
      fputc(*c, f);
    }
    fputs("\"\n", f);
  }
  if (options->n_sets == 0) fprintf(f, "  []\n");
  fprintf(f, "set_modes: [");
  for (int k = 0; k < options->n_sets; ++k)
    fprintf(f, "%s%s", k ? ", " : "",
            options->set_modes && options->set_modes[k] == SK_CFG_REPLACE ? "replace" : "merge");
  fprintf(f, "]\n");
  fprintf(f, "ranks: %d\ndim: %d\nnodes: %d\n", sys->n_ranks, sys->model->dim, sys->model->n_nodes_global);
  fprintf(f, "time: %.17g\nstep: %lld\nscheduled: %lld\nsubstep: %d\ndt: %.17g\n", sys->t, (long long)p->steps,
          (long long)p->scheduled, p->substep, p->dt);
  fprintf(f, "cuts_in_a_row: %d\ngood_steps: %d\nnewton_iterations: %lld\ncuts: %lld\n", p->cuts_in_a_row,
          p->good_steps, (long long)p->newton_iterations, (long long)p->cuts);
  fprintf(f, "linear_solves: %d\nactive_set_loops: %d\nlinear_fallback: %d\n", sys->linear_solves,
          sys->active_set_loops, sys->linear_fallback);
  fprintf(f, "dissipated: %.17g\nlast_vtu_step: %lld\n", rec->dissipated, (long long)rec->last_vtu_step);
  const int ok = fflush(f) == 0 && fsync(fileno(f)) == 0;
  if (fclose(f) != 0 || !ok) return sk_error_set(SK_ERR_IO, "checkpoint: writing '%s' failed: %s", path, strerror(errno));
  return SK_OK;
}

sk_status sk_checkpoint_write(const sk_run_options *options, sk_system *sys, const sk_progress *progress,
                              const sk_recorder_state *rec) {
  const char *dir = options->checkpoint_dir;
  char name[32], partial[4200], final[4200], path[4400];
  step_name(progress->steps, name, sizeof name);
  snprintf(final, sizeof final, "%s/%s", dir, name);
  /* the hidden folder every rank writes into (rank 0's pid names it) */
  int pid = (int)getpid();
  MPI_Bcast(&pid, 1, MPI_INT, 0, sys->comm);
  snprintf(partial, sizeof partial, "%s/.partial-%s-%d", dir, name, pid);
  sk_status status = SK_OK;
  if (sys->rank == 0 && mkdir(partial, 0777) != 0 && errno != EEXIST)
    status = sk_error_set(SK_ERR_IO, "checkpoint: cannot create '%s': %s", partial, strerror(errno));
  SK_TRY(sk_system_collective(sys, status));
  const uint64_t mesh_hash = sk_checkpoint_mesh_hash(sys->model);
  buffer b = {0};
  status = state_bytes(sys, &b);
  if (status == SK_OK) {
    snprintf(path, sizeof path, "%s/state-%04d.bin", partial, sys->rank);
    status = write_file(path, b.data, b.size);
  }
  free(b.data);
  status = sk_system_collective(sys, status);
  if (status == SK_OK && sys->rank == 0) {
    snprintf(path, sizeof path, "%s/checkpoint.yaml", partial);
    status = write_description(path, options, sys, progress, rec, mesh_hash);
    if (status == SK_OK && rec->history_path) {
      snprintf(path, sizeof path, "%s/history.csv", partial);
      status = copy_file(rec->history_path, path);
    }
    if (status == SK_OK && rec->contact_path) {
      snprintf(path, sizeof path, "%s/contact.csv", partial);
      status = copy_file(rec->contact_path, path);
    }
    /* in place: a checkpoint of the same step from an earlier run is replaced */
    if (status == SK_OK && is_dir(final)) remove_step(final);
    if (status == SK_OK && rename(partial, final) != 0)
      status = sk_error_set(SK_ERR_IO, "checkpoint: cannot rename '%s' to '%s': %s", partial, final, strerror(errno));
    if (status == SK_OK) {
      char latest[4200], tmp[4300];
      snprintf(latest, sizeof latest, "%s/latest", dir);
      snprintf(tmp, sizeof tmp, "%s/.latest-%d", dir, pid);
      FILE *f = fopen(tmp, "w");
      const int ok = f && fprintf(f, "%s\n", name) > 0;
      if (f && fclose(f) != 0) status = SK_ERR_IO;
      if (!ok || status != SK_OK || rename(tmp, latest) != 0)
        status = sk_error_set(SK_ERR_IO, "checkpoint: cannot write '%s': %s", latest, strerror(errno));
    }
    if (status == SK_OK) prune(dir);
    else remove_step(partial);
  }
  return sk_system_collective(sys, status);
}

/* ---- reading ------------------------------------------------------------------------------------------------- */

void sk_restart_free(sk_restart *r) {
  if (!r) return;
  for (int k = 0; k < r->n_sets; ++k) free(r->sets[k]);
  free(r->sets);
  free(r->set_modes);
  free(r);
}

const char *sk_restart_scene(const sk_restart *r) { return r->scene; }
const char *sk_restart_plugin(const sk_restart *r) { return r->plugin[0] ? r->plugin : NULL; }
int sk_restart_sets(const sk_restart *r, const char *const **sets, const sk_cfg_override_mode **modes) {
  *sets = (const char *const *)r->sets;
  *modes = r->set_modes;
  return r->n_sets;
}
const char *sk_restart_folder(const sk_restart *r) { return r->dir; }
double sk_restart_time(const sk_restart *r) { return r->time; }
int64_t sk_restart_step(const sk_restart *r) { return r->progress.steps; }

/* The step folder of `dir`: itself when it holds checkpoint.yaml, else the one its `latest` names (rank 0). */
static sk_status find_step(const char *dir, char *out, size_t n) {
  char path[4400];
  snprintf(path, sizeof path, "%s/checkpoint.yaml", dir);
  if (access(path, R_OK) == 0) {
    snprintf(out, n, "%s", dir);
    return SK_OK;
  }
  if (!is_dir(dir)) return sk_error_set(SK_ERR_INPUT, "--restart %s: no such folder", dir);
  snprintf(path, sizeof path, "%s/latest", dir);
  FILE *f = fopen(path, "r");
  char name[64] = "";
  if (f) {
    if (!fgets(name, sizeof name, f)) name[0] = '\0';
    fclose(f);
  }
  name[strcspn(name, "\r\n")] = '\0';
  if (!name[0]) {
    DIR *d = opendir(dir);
    const char *partial = NULL;
    struct dirent *e;
    char found[256] = "";
    while (d && (e = readdir(d)))
      if (strncmp(e->d_name, ".partial-", 9) == 0) snprintf(found, sizeof found, "%s", e->d_name), partial = found;
    if (d) closedir(d);
    if (partial)
      return sk_error_set(SK_ERR_INPUT, "--restart %s: no complete checkpoint (only the partial %s, whose writing was "
                          "interrupted)", dir, partial);
    return sk_error_set(SK_ERR_INPUT, "--restart %s: not a checkpoint (no checkpoint.yaml, no `latest`)", dir);
  }
  snprintf(out, n, "%s/%s", dir, name);
  snprintf(path, sizeof path, "%s/checkpoint.yaml", out);
  if (access(path, R_OK) != 0)
    return sk_error_set(SK_ERR_INPUT, "--restart %s: `latest` names %s, which has no checkpoint.yaml", dir, name);
  return SK_OK;
}

static sk_status read_int64(const sk_cfg *root, const char *key, int64_t *out) {
  double v = 0;
  SK_TRY(sk_cfg_double(root, key, 1, 0, &v));
  *out = (int64_t)v;
  return SK_OK;
}

static sk_status read_hash(const sk_cfg *root, const char *key, uint64_t *out) {
  const char *text;
  SK_TRY(sk_cfg_string(root, key, 1, NULL, &text));
  *out = strtoull(text, NULL, 16);
  return SK_OK;
}

/* Rank 0: checkpoint.yaml into r. */
static sk_status read_description(sk_restart *r) {
  char path[4400];
  snprintf(path, sizeof path, "%s/checkpoint.yaml", r->dir);
  sk_cfg *cfg = NULL;
  sk_status status = sk_cfg_load(path, &cfg);
  if (status != SK_OK) return sk_error_prefix(status, "--restart: ");
  int format = 0, substep = 0, cuts_in_a_row = 0, good_steps = 0, fallback = 0;
  const char *scene = "", *plugin = "";
  int64_t steps = 0, scheduled = 0, newton = 0, cuts = 0, vtu = 0, solves = 0, loops = 0;
  status = sk_cfg_int(cfg, "format", 1, 0, &format);
  if (status == SK_OK && format != FORMAT)
    status = sk_error_set(SK_ERR_INPUT, "%s: format %d, this stickslip reads %d", path, format, FORMAT);
  if (status == SK_OK) status = sk_cfg_string(cfg, "scene", 1, NULL, &scene);
  if (status == SK_OK) status = sk_cfg_string(cfg, "plugin", 0, "", &plugin);
  if (status == SK_OK) status = read_hash(cfg, "scene_hash", &r->scene_hash);
  if (status == SK_OK) status = read_hash(cfg, "mesh_hash", &r->mesh_hash);
  if (status == SK_OK) status = sk_cfg_int(cfg, "ranks", 1, 0, &r->ranks);
  if (status == SK_OK) status = sk_cfg_int(cfg, "dim", 1, 0, &r->dim);
  if (status == SK_OK) status = sk_cfg_int(cfg, "nodes", 1, 0, &r->n_nodes);
  if (status == SK_OK) status = sk_cfg_double(cfg, "time", 1, 0, &r->time);
  if (status == SK_OK) status = read_int64(cfg, "step", &steps);
  if (status == SK_OK) status = read_int64(cfg, "scheduled", &scheduled);
  if (status == SK_OK) status = sk_cfg_int(cfg, "substep", 1, 0, &substep);
  if (status == SK_OK) status = sk_cfg_double(cfg, "dt", 1, 0, &r->progress.dt);
  if (status == SK_OK) status = sk_cfg_int(cfg, "cuts_in_a_row", 1, 0, &cuts_in_a_row);
  if (status == SK_OK) status = sk_cfg_int(cfg, "good_steps", 1, 0, &good_steps);
  if (status == SK_OK) status = read_int64(cfg, "newton_iterations", &newton);
  if (status == SK_OK) status = read_int64(cfg, "cuts", &cuts);
  if (status == SK_OK) status = read_int64(cfg, "linear_solves", &solves);
  if (status == SK_OK) status = read_int64(cfg, "active_set_loops", &loops);
  if (status == SK_OK) status = sk_cfg_int(cfg, "linear_fallback", 1, 0, &fallback);
  if (status == SK_OK) status = sk_cfg_double(cfg, "dissipated", 1, 0, &r->dissipated);
  if (status == SK_OK) status = read_int64(cfg, "last_vtu_step", &vtu);
  const sk_cfg *sets = sk_cfg_get(cfg, "sets");
  const int n_sets = sets && sk_cfg_kind_of(sets) == SK_CFG_SEQ ? sk_cfg_size(sets) : 0;
  if (status == SK_OK) {
    r->sets = calloc((size_t)n_sets + 1, sizeof(char *));
    r->set_modes = calloc((size_t)n_sets + 1, sizeof *r->set_modes);
    if (!r->sets || !r->set_modes) status = sk_error_set(SK_ERR_NOMEM, "--restart: out of memory");
  }
  const sk_cfg *modes = sk_cfg_get(cfg, "set_modes"); /* absent: every value was a --set */
  for (int k = 0; k < n_sets && status == SK_OK; ++k) {
    const char *mode = modes && k < sk_cfg_size(modes) ? sk_cfg_scalar(sk_cfg_at(modes, k)) : NULL;
    r->set_modes[k] = mode && strcmp(mode, "replace") == 0 ? SK_CFG_REPLACE : SK_CFG_MERGE;
    const char *text = sk_cfg_scalar(sk_cfg_at(sets, k));
    r->sets[k] = strdup(text ? text : "");
    if (!r->sets[k]) status = sk_error_set(SK_ERR_NOMEM, "--restart: out of memory");
    r->n_sets = k + 1;
  }
  if (status == SK_OK) {
    snprintf(r->scene, sizeof r->scene, "%s", scene);
    snprintf(r->plugin, sizeof r->plugin, "%s", plugin);
    r->progress.steps = steps;
    r->progress.scheduled = scheduled;
    r->progress.substep = substep;
    r->progress.cuts_in_a_row = cuts_in_a_row;
    r->progress.good_steps = good_steps;
    r->progress.newton_iterations = newton;
    r->progress.cuts = cuts;
    r->last_vtu_step = vtu;
    r->linear_solves = solves;
    r->active_set_loops = loops;
    r->linear_fallback = fallback;
    if (r->ranks < 1 || r->dim < 2 || r->dim > 3 || r->n_nodes < 1 || !(r->progress.dt > 0) || !isfinite(r->time))
      status = sk_error_set(SK_ERR_INPUT, "%s: implausible values (ranks %d, dim %d, nodes %d, dt %g)", path, r->ranks,
                            r->dim, r->n_nodes, r->progress.dt);
  }
  sk_cfg_free(cfg);
  return status;
}

/* The description from rank 0 to every rank (its plain fields and strings). */
static sk_status share(sk_restart *r, MPI_Comm comm, int rank) {
  MPI_Bcast(r->dir, sizeof r->dir, MPI_CHAR, 0, comm);
  MPI_Bcast(r->scene, sizeof r->scene, MPI_CHAR, 0, comm);
  MPI_Bcast(r->plugin, sizeof r->plugin, MPI_CHAR, 0, comm);
  uint64_t hashes[2] = {r->scene_hash, r->mesh_hash};
  MPI_Bcast(hashes, 2, MPI_UINT64_T, 0, comm);
  r->scene_hash = hashes[0];
  r->mesh_hash = hashes[1];
  int ints[9] = {r->ranks, r->n_nodes, r->dim, r->progress.substep, r->progress.cuts_in_a_row, r->progress.good_steps,
                 r->linear_fallback, r->n_sets, 0};
  MPI_Bcast(ints, 9, MPI_INT, 0, comm);
  int64_t longs[7] = {r->progress.steps, r->progress.scheduled, r->progress.newton_iterations, r->progress.cuts,
                      r->last_vtu_step, r->linear_solves, r->active_set_loops};
  MPI_Bcast(longs, 7, MPI_INT64_T, 0, comm);
  double doubles[3] = {r->time, r->progress.dt, r->dissipated};
  MPI_Bcast(doubles, 3, MPI_DOUBLE, 0, comm);
  if (rank != 0) {
    r->ranks = ints[0], r->n_nodes = ints[1], r->dim = ints[2], r->progress.substep = ints[3];
    r->progress.cuts_in_a_row = ints[4], r->progress.good_steps = ints[5], r->linear_fallback = ints[6];
    r->progress.steps = longs[0], r->progress.scheduled = longs[1], r->progress.newton_iterations = longs[2];
    r->progress.cuts = longs[3], r->last_vtu_step = longs[4], r->linear_solves = longs[5], r->active_set_loops = longs[6];
    r->time = doubles[0], r->progress.dt = doubles[1], r->dissipated = doubles[2];
    r->sets = calloc((size_t)ints[7] + 1, sizeof(char *));
    r->set_modes = calloc((size_t)ints[7] + 1, sizeof *r->set_modes);
    if (!r->sets || !r->set_modes) return sk_error_set(SK_ERR_NOMEM, "--restart: out of memory");
    r->n_sets = ints[7];
  }
  if (r->n_sets > 0) MPI_Bcast(r->set_modes, (int)(sizeof *r->set_modes) * r->n_sets, MPI_BYTE, 0, comm);
  for (int k = 0; k < r->n_sets; ++k) {
    int len = rank == 0 ? (int)strlen(r->sets[k]) + 1 : 0;
    MPI_Bcast(&len, 1, MPI_INT, 0, comm);
    if (rank != 0 && !(r->sets[k] = malloc((size_t)len))) return sk_error_set(SK_ERR_NOMEM, "--restart: out of memory");
    MPI_Bcast(r->sets[k], len, MPI_CHAR, 0, comm);
  }
  return SK_OK;
}

sk_status sk_restart_open(const char *dir, MPI_Comm comm, sk_restart **out) {
  *out = NULL;
  int rank;
  MPI_Comm_rank(comm, &rank);
  sk_restart *r = calloc(1, sizeof *r);
  sk_status status = r ? SK_OK : sk_error_set(SK_ERR_NOMEM, "--restart: out of memory");
  if (status == SK_OK && rank == 0) status = find_step(dir, r->dir, sizeof r->dir);
  if (status == SK_OK && rank == 0) status = read_description(r);
  int code = (int)status;
  MPI_Bcast(&code, 1, MPI_INT, 0, comm);
  if (code != SK_OK) {
    char message[2048];
    snprintf(message, sizeof message, "%s", sk_error_message());
    MPI_Bcast(message, sizeof message, MPI_CHAR, 0, comm);
    sk_restart_free(r);
    return sk_error_set((sk_status)code, "%s", message);
  }
  status = share(r, comm, rank);
  if (status != SK_OK) {
    sk_restart_free(r);
    return status;
  }
  *out = r;
  return SK_OK;
}

/* One rank's state file, read whole and checked (magic, end mark, checksum). */
static sk_status load_state_file(const sk_restart *r, int rank, buffer *b) {
  char path[4400];
  snprintf(path, sizeof path, "%s/state-%04d.bin", r->dir, rank);
  FILE *f = fopen(path, "rb");
  if (!f)
    return sk_error_set(SK_ERR_INPUT, "--restart: %s is missing (the checkpoint was written by %d ranks): %s", path,
                        r->ranks, strerror(errno));
  char chunk[65536];
  size_t got;
  while ((got = fread(chunk, 1, sizeof chunk, f)) > 0) put(b, chunk, got);
  fclose(f);
  if (b->failed) return sk_error_set(SK_ERR_NOMEM, "--restart: out of memory reading %s", path);
  const size_t tail = sizeof(uint64_t) + sizeof END_MAGIC;
  if (b->size < sizeof STATE_MAGIC + 16 + tail || memcmp(b->data, STATE_MAGIC, sizeof STATE_MAGIC) != 0 ||
      memcmp(b->data + b->size - sizeof END_MAGIC, END_MAGIC, sizeof END_MAGIC) != 0)
    return sk_error_set(SK_ERR_INPUT, "--restart: %s is not a whole stickslip state file (truncated or damaged)", path);
  uint64_t sum;
  memcpy(&sum, b->data + b->size - tail, sizeof sum);
  if (sum != sk_fnv1a(FNV_SEED, b->data, b->size - tail))
    return sk_error_set(SK_ERR_INPUT, "--restart: %s is damaged (its checksum does not match)", path);
  int32_t head[4];
  memcpy(head, b->data + sizeof STATE_MAGIC, sizeof head);
  if (head[0] != rank || head[1] != r->ranks || head[2] != r->dim || head[3] != FORMAT)
    return sk_error_set(SK_ERR_INPUT, "--restart: %s belongs to another checkpoint (rank %d of %d, dim %d, format %d)",
                        path, head[0], head[1], head[2], head[3]);
  return SK_OK;
}

/* The records of one plugin term from every rank's file, sorted by key (the reader of stickslip.checkpoint.v1). */
typedef struct {
  sk_record_reader abi;
  buffer data;
  int64_t n, cap;
  int64_t *key, *offset;
  uint32_t *bytes;
} record_set;

static int64_t reader_get(const sk_record_reader *abi, int64_t key, void *data, uint32_t capacity) {
  const record_set *s = (const record_set *)abi;
  int64_t lo = 0, hi = s->n;
  while (lo < hi) {
    const int64_t mid = lo + (hi - lo) / 2;
    if (s->key[mid] < key) lo = mid + 1;
    else hi = mid;
  }
  if (lo >= s->n || s->key[lo] != key) return -1;
  memcpy(data, s->data.data + s->offset[lo], s->bytes[lo] < capacity ? s->bytes[lo] : capacity);
  return s->bytes[lo];
}

static int add_record(record_set *s, int64_t key, const unsigned char *data, uint32_t bytes) {
  if (s->n == s->cap) {
    const int64_t cap = 2 * s->cap + 256;
    int64_t *k = realloc(s->key, sizeof(int64_t) * (size_t)cap), *o = realloc(s->offset, sizeof(int64_t) * (size_t)cap);
    if (k) s->key = k;
    if (o) s->offset = o;
    uint32_t *b = realloc(s->bytes, sizeof(uint32_t) * (size_t)cap);
    if (b) s->bytes = b;
    if (!k || !o || !b) return 0;
    s->cap = cap;
  }
  s->key[s->n] = key;
  s->offset[s->n] = (int64_t)s->data.size;
  s->bytes[s->n] = bytes;
  put(&s->data, data, bytes);
  s->n++;
  return !s->data.failed;
}

static void record_set_free(record_set *s) {
  free(s->data.data);
  free(s->key);
  free(s->offset);
  free(s->bytes);
}

/* Sorts a record set by key (an index sort, then the arrays permuted). */
static const record_set *sort_target;
static int compare_records(const void *a, const void *b) {
  const int64_t x = sort_target->key[*(const int64_t *)a], y = sort_target->key[*(const int64_t *)b];
  return (x > y) - (x < y);
}

static int sort_records(record_set *s) {
  int64_t *order = malloc(sizeof(int64_t) * (size_t)(s->n + 1));
  int64_t *key = malloc(sizeof(int64_t) * (size_t)(s->n + 1)), *offset = malloc(sizeof(int64_t) * (size_t)(s->n + 1));
  uint32_t *bytes = malloc(sizeof(uint32_t) * (size_t)(s->n + 1));
  if (!order || !key || !offset || !bytes) {
    free(order), free(key), free(offset), free(bytes);
    return 0;
  }
  for (int64_t k = 0; k < s->n; ++k) order[k] = k;
  sort_target = s;
  qsort(order, (size_t)s->n, sizeof(int64_t), compare_records);
  for (int64_t k = 0; k < s->n; ++k) {
    key[k] = s->key[order[k]];
    offset[k] = s->offset[order[k]];
    bytes[k] = s->bytes[order[k]];
  }
  free(s->key), free(s->offset), free(s->bytes), free(order);
  s->key = key, s->offset = offset, s->bytes = bytes;
  return 1;
}

sk_status sk_restart_apply(const sk_restart *r, sk_system *sys, sk_progress *progress) {
  sk_model *m = sys->model;
  const int dim = m->dim;
  /* the scene must be the one the checkpoint was written for */
  sk_status status = SK_OK;
  if (r->dim != dim || r->n_nodes != m->n_nodes_global)
    status = sk_error_set(SK_ERR_INPUT, "--restart %s: the checkpoint has %d nodes in %dD, the scene %d in %dD",
                          r->dir, r->n_nodes, r->dim, m->n_nodes_global, dim);
  const uint64_t mesh_hash = sk_checkpoint_mesh_hash(m);
  if (status == SK_OK && mesh_hash != r->mesh_hash)
    status = sk_error_set(SK_ERR_INPUT, "--restart %s: the mesh of %s is not the one the checkpoint was written with "
                          "(its nodes moved)", r->dir, r->scene);
  if (status == SK_OK && sk_checkpoint_file_hash(r->scene) != r->scene_hash)
    status = sk_error_set(SK_ERR_INPUT, "--restart %s: %s changed since the checkpoint was written: restart with the "
                          "scene as it was", r->dir, r->scene);
  SK_TRY(sk_system_collective(sys, status));
  /* the plugin terms, in order */
  int n_plugins = 0;
  for (int k = 0; k < sys->n_terms; ++k) n_plugins += sk_term_plugin_checkpointable(sys->terms[k], NULL) >= 0;
  record_set *sets = calloc((size_t)n_plugins + 1, sizeof *sets);
  unsigned char *seen = calloc((size_t)m->n_nodes + 1, 1);
  if (!sets || !seen) status = sk_error_set(SK_ERR_NOMEM, "--restart: out of memory");
  /* every rank's file: the nodes this rank holds, every record */
  for (int file = 0; file < r->ranks && status == SK_OK; ++file) {
    buffer b = {0};
    sk_error_clear();
    status = load_state_file(r, file, &b);
    size_t at = sizeof STATE_MAGIC + 4 * sizeof(int32_t);
    const size_t end = b.size - sizeof(uint64_t) - sizeof END_MAGIC;
    int64_t n_nodes = 0;
    if (status == SK_OK) {
      memcpy(&n_nodes, b.data + at, sizeof n_nodes);
      at += sizeof n_nodes;
    }
    const size_t record = sizeof(int64_t) + 3 * (size_t)dim * sizeof(double);
    if (status == SK_OK && (n_nodes < 0 || at + (size_t)n_nodes * record > end))
      status = sk_error_set(SK_ERR_INPUT, "--restart: %s/state-%04d.bin: %lld nodes do not fit the file", r->dir, file,
                            (long long)n_nodes);
    for (int64_t k = 0; k < n_nodes && status == SK_OK; ++k, at += record) {
      int64_t gid;
      memcpy(&gid, b.data + at, sizeof gid);
      const int a = sk_model_node_of(m, gid);
      if (a < 0) continue;
      double values[9];
      memcpy(values, b.data + at + sizeof gid, 3 * (size_t)dim * sizeof(double));
      for (int i = 0; i < dim; ++i) {
        const int64_t d = (int64_t)a * dim + i;
        sys->u_n[d] = values[i];
        sys->v_n[d] = values[dim + i];
        sys->rate_n[d] = values[2 * dim + i];
        sys->q_n[d] = sys->q[d] = m->X[d] + values[i];
      }
      seen[a] = 1;
    }
    int32_t n_terms = 0;
    if (status == SK_OK && at + sizeof n_terms <= end) {
      memcpy(&n_terms, b.data + at, sizeof n_terms);
      at += sizeof n_terms;
    }
    if (status == SK_OK && n_terms != n_plugins)
      status = sk_error_set(SK_ERR_INPUT, "--restart: %s/state-%04d.bin holds %d plugin instances, the scene has %d",
                            r->dir, file, n_terms, n_plugins);
    for (int t = 0, k = 0; t < n_terms && status == SK_OK; ++t) {
      while (sk_term_plugin_checkpointable(sys->terms[k], NULL) < 0) ++k;
      const sk_term *term = sys->terms[k++];
      int32_t len = 0;
      int64_t count = 0;
      if (at + sizeof len > end) break;
      memcpy(&len, b.data + at, sizeof len);
      at += sizeof len;
      if (len < 0 || at + (size_t)len + sizeof count > end) {
        status = SK_ERR_INPUT;
        break;
      }
      if ((size_t)len != strlen(term->name) || memcmp(b.data + at, term->name, (size_t)len) != 0)
        status = sk_error_set(SK_ERR_INPUT, "--restart: %s/state-%04d.bin: instance %d is '%.*s', the scene's %s", r->dir,
                              file, t, (int)len, (const char *)b.data + at, term->name);
      at += (size_t)len;
      memcpy(&count, b.data + at, sizeof count);
      at += sizeof count;
      for (int64_t j = 0; j < count && status == SK_OK; ++j) {
        int64_t key;
        uint32_t bytes;
        if (at + sizeof key + sizeof bytes > end) {
          status = SK_ERR_INPUT;
          break;
        }
        memcpy(&key, b.data + at, sizeof key);
        memcpy(&bytes, b.data + at + sizeof key, sizeof bytes);
        at += sizeof key + sizeof bytes;
        if (at + bytes > end) {
          status = SK_ERR_INPUT;
          break;
        }
        if (!add_record(&sets[t], key, b.data + at, bytes))
          status = sk_error_set(SK_ERR_NOMEM, "--restart: out of memory for the plugins' records");
        at += bytes;
      }
    }
    if (status == SK_ERR_INPUT && !sk_error_message()[0])
      sk_error_set(SK_ERR_INPUT, "--restart: %s/state-%04d.bin: records run past the end of the file", r->dir, file);
    free(b.data);
  }
  /* every node this rank holds got its state */
  for (int a = 0; a < m->n_nodes && status == SK_OK; ++a)
    if (sys->node_role[a] && !seen[a])
      status = sk_error_set(SK_ERR_INPUT, "--restart: no state for node %lld in %s", (long long)m->node_gid[a], r->dir);
  free(seen);
  status = sk_system_collective(sys, status);
  /* the time and the plugins' history */
  if (status == SK_OK) {
    sys->t_n = sys->t = r->time;
    sys->dt = r->progress.dt;
    sys->step = r->progress.steps;
    sys->linear_solves = (int)r->linear_solves;
    sys->active_set_loops = (int)r->active_set_loops;
    sys->linear_fallback = r->linear_fallback;
    if (r->linear_fallback) status = sk_linsys_set_solver(sys->linsys, SK_LINEAR_DIRECT);
    sys->x_version++;
  }
  for (int t = 0, k = 0; t < n_plugins && status == SK_OK; ++t) {
    while (sk_term_plugin_checkpointable(sys->terms[k], NULL) < 0) ++k;
    sk_term *term = sys->terms[k++];
    if (!sort_records(&sets[t])) status = sk_error_set(SK_ERR_NOMEM, "--restart: out of memory");
    sets[t].abi = (sk_record_reader){SK_TABLE_HEADER(sk_record_reader), .get = reader_get};
    if (status == SK_OK) status = sk_term_plugin_load(term, sys, &sets[t].abi);
    if (status != SK_OK) sk_error_prefix(status, "--restart: %s: ", term->name);
    status = sk_system_collective(sys, status);
  }
  for (int t = 0; t < n_plugins && sets; ++t) record_set_free(&sets[t]);
  free(sets);
  if (status == SK_OK) *progress = r->progress;
  return status;
}
