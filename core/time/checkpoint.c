/* Checkpoints and restarts (checkpoint.h). A checkpoint folder (--checkpoint DIR) holds stickslip's marker, a file
 * `latest` naming the newest checkpoint, and the last two checkpoints as step-NNNNNNNN folders, each with
 *   checkpoint.yaml   the scene it was written for (file, --set values, --plugin, hashes of the scene file and the
 *                     mesh), the time, the stepper's and the recorder's counters (rank 0);
 *   history.csv       the rows written so far (rank 0, with --out);
 *   state-RRRR.bin    each rank's owned nodes (mesh id, u, v, rate) and its plugin instances' records, with a
 *                     checksum and an end mark, so that a truncated or damaged file is refused.
 * A checkpoint is written into a hidden folder and renamed into place once every rank has written its file, so a
 * checkpoint appears complete or not at all; older ones are removed only after the new one is in place, and only
 * the files stickslip wrote. Reading them back is restart.c. */
#define _GNU_SOURCE
#include "checkpoint.h"
#include "checkpoint_format.h"
#include "checkpoint_partition.h"

#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "stickslip/config.h"
#include "stickslip/files.h"

enum { KEEP = 2 };
static const char MARKER[] = ".stickslip-checkpoints";
const char sk_checkpoint_state_magic[8] = {'S', 'K', 'S', 'T', 'A', 'T', 'E', '1'};
const char sk_checkpoint_end_magic[8] = {'S', 'K', 'S', 'T', 'E', 'N', 'D', '1'};

uint64_t sk_checkpoint_file_hash(const char *path) {
  FILE *f = fopen(path, "rb");
  if (!f) return 0;
  uint64_t hash = SK_CHECKPOINT_FNV_SEED;
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
    uint64_t h = sk_fnv1a(SK_CHECKPOINT_FNV_SEED, &m->node_gid[a], sizeof(int64_t));
    h = sk_fnv1a(h, m->X + (size_t)a * m->dim, sizeof(double) * (size_t)m->dim);
    mine ^= h;
  }
  uint64_t all = 0;
  MPI_Allreduce(&mine, &all, 1, MPI_UINT64_T, MPI_BXOR, m->comm);
  return all;
}

int sk_checkpoint_slurp(FILE *f, sk_byte_buffer *b) {
  char chunk[65536];
  size_t got;
  while ((got = fread(chunk, 1, sizeof chunk, f)) > 0) sk_byte_buffer_put(b, chunk, got);
  fclose(f);
  return b->failed ? -1 : 0;
}

int sk_checkpoint_whole(const sk_byte_buffer *b, const char magic[8], size_t head) {
  const size_t tail = sizeof(uint64_t) + sizeof sk_checkpoint_end_magic;
  if (b->size < 8 + head + tail || memcmp(b->data, magic, 8) != 0 ||
      memcmp(b->data + b->size - sizeof sk_checkpoint_end_magic, sk_checkpoint_end_magic,
             sizeof sk_checkpoint_end_magic) != 0)
    return 0;
  uint64_t sum;
  memcpy(&sum, b->data + b->size - tail, sizeof sum);
  return sum == sk_fnv1a(SK_CHECKPOINT_FNV_SEED, b->data, b->size - tail) ? 1 : -1;
}

/* ---- paths ---------------------------------------------------------------------------------------------------- */

static void step_name(int64_t step, char *out, size_t n) { snprintf(out, n, "step-%08lld", (long long)step); }

int sk_is_directory(const char *path) {
  struct stat st;
  return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

/* The checkpoint folder is stickslip's: empty or new (then marked), or carrying the marker (rank 0). */
static sk_status claim_folder(const char *dir) {
  char path[4200];
  if (!sk_is_directory(dir)) {
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
                     strcmp(n, "contact.csv") == 0 || strcmp(n, sk_checkpoint_partition_file()) == 0 ||
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
static sk_status state_bytes(sk_system *sys, sk_byte_buffer *b) {
  const sk_model *m = sys->model;
  const int dim = m->dim;
  sk_byte_buffer_put(b, sk_checkpoint_state_magic, sizeof sk_checkpoint_state_magic);
  const int32_t head[4] = {sys->rank, sys->n_ranks, dim, SK_CHECKPOINT_FORMAT};
  sk_byte_buffer_put(b, head, sizeof head);
  int64_t n_owned = 0;
  for (int a = 0; a < m->n_nodes; ++a) n_owned += m->node_owner[a] == m->rank;
  sk_byte_buffer_put(b, &n_owned, sizeof n_owned);
  for (int a = 0; a < m->n_nodes; ++a) {
    if (m->node_owner[a] != m->rank) continue;
    sk_byte_buffer_put(b, &m->node_gid[a], sizeof(int64_t));
    double values[9];
    for (int i = 0; i < dim; ++i) {
      const int64_t d = (int64_t)a * dim + i;
      values[i] = sys->x[d];
      values[dim + i] = sys->v[d];
      values[2 * dim + i] = (sys->x[d] - sys->u_n[d]) / sys->dt;
    }
    sk_byte_buffer_put(b, values, sizeof(double) * 3 * (size_t)dim);
  }
  int32_t n_plugins = 0;
  for (int k = 0; k < sys->n_terms; ++k) n_plugins += sk_term_plugin_checkpointable(sys->terms[k], NULL) >= 0;
  sk_byte_buffer_put(b, &n_plugins, sizeof n_plugins);
  sk_status status = SK_OK;
  for (int k = 0; k < sys->n_terms && status == SK_OK; ++k) {
    sk_term *term = sys->terms[k];
    if (sk_term_plugin_checkpointable(term, NULL) < 0) continue;
    const int32_t len = (int32_t)strlen(term->name);
    sk_byte_buffer_put(b, &len, sizeof len);
    sk_byte_buffer_put(b, term->name, (size_t)len);
    const size_t count_at = b->size;
    int64_t count = 0;
    sk_byte_buffer_put(b, &count, sizeof count);
    sk_buffer_writer w;
    sk_buffer_writer_init(&w, b);
    status = sk_term_plugin_save(term, sys, &w.abi);
    if (status != SK_OK) sk_error_prefix(status, "%s: ", term->name);
    if (!b->failed) memcpy(b->data + count_at, &w.count, sizeof w.count);
  }
  const uint64_t sum = b->failed ? 0 : sk_fnv1a(SK_CHECKPOINT_FNV_SEED, b->data, b->size);
  sk_byte_buffer_put(b, &sum, sizeof sum);
  sk_byte_buffer_put(b, sk_checkpoint_end_magic, sizeof sk_checkpoint_end_magic);
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
  sk_byte_buffer b = {0};
  sk_status status = sk_checkpoint_slurp(in, &b) != 0 ? sk_error_set(SK_ERR_NOMEM, "checkpoint: out of memory copying '%s'", from)
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
  fprintf(f, "format: %d\n", SK_CHECKPOINT_FORMAT);
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
  fprintf(f, "linear_factorisations: %d\nkrylov_iterations: %lld\n", sys->linear_factorisations,
          (long long)sys->krylov_iterations);
  fprintf(f, "dissipated: %.17g\nexternal_work: %.17g\nlast_vtu_step: %lld\n", rec->dissipated, rec->external_work,
          (long long)rec->last_vtu_step);
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
  sk_byte_buffer b = {0};
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
    sk_byte_buffer part = {0};
    if (status == SK_OK) status = sk_checkpoint_partition_bytes(sys, &part);
    if (status == SK_OK && part.size > 0) {
      snprintf(path, sizeof path, "%s/%s", partial, sk_checkpoint_partition_file());
      status = write_file(path, part.data, part.size);
    }
    free(part.data);
    /* in place: a checkpoint of the same step from an earlier run is replaced */
    if (status == SK_OK && sk_is_directory(final)) remove_step(final);
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
