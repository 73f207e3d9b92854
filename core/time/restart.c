/* Restarts (checkpoint.h): a checkpoint folder's description and every rank's state file read back, checked against
 * the scene and mesh they were written for, and applied to a system on any number of ranks (the state is keyed by
 * mesh ids and the plugins' entity keys). The file layout is described in checkpoint.c. */
#define _GNU_SOURCE
#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "checkpoint.h"
#include "checkpoint_format.h"
#include "checkpoint_partition.h"
#include "../model/master_ghosts.h"
#include "stickslip/config.h"
#include "stickslip/files.h"

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
  if (!sk_is_directory(dir)) return sk_error_set(SK_ERR_INPUT, "--restart %s: no such folder", dir);
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
  if (status == SK_OK && format != SK_CHECKPOINT_FORMAT)
    status = sk_error_set(SK_ERR_INPUT, "%s: format %d, this stickslip reads %d", path, format, SK_CHECKPOINT_FORMAT);
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
  double factorisations = 0, krylov = 0; /* optional: checkpoints before these counts lack them */
  if (status == SK_OK) status = sk_cfg_double(cfg, "linear_factorisations", 0, 0, &factorisations);
  if (status == SK_OK) status = sk_cfg_double(cfg, "krylov_iterations", 0, 0, &krylov);
  if (status == SK_OK) status = sk_cfg_int(cfg, "linear_fallback", 1, 0, &fallback);
  if (status == SK_OK) status = sk_cfg_double(cfg, "dissipated", 1, 0, &r->dissipated);
  if (status == SK_OK) status = sk_cfg_double(cfg, "external_work", 1, 0, &r->external_work);
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
    r->linear_factorisations = (int64_t)factorisations;
    r->krylov_iterations = (int64_t)krylov;
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
  int64_t longs[9] = {r->progress.steps, r->progress.scheduled, r->progress.newton_iterations, r->progress.cuts,
                      r->last_vtu_step, r->linear_solves, r->active_set_loops, r->linear_factorisations,
                      r->krylov_iterations};
  MPI_Bcast(longs, 9, MPI_INT64_T, 0, comm);
  double doubles[4] = {r->time, r->progress.dt, r->dissipated, r->external_work};
  MPI_Bcast(doubles, 4, MPI_DOUBLE, 0, comm);
  if (rank != 0) {
    r->ranks = ints[0], r->n_nodes = ints[1], r->dim = ints[2], r->progress.substep = ints[3];
    r->progress.cuts_in_a_row = ints[4], r->progress.good_steps = ints[5], r->linear_fallback = ints[6];
    r->progress.steps = longs[0], r->progress.scheduled = longs[1], r->progress.newton_iterations = longs[2];
    r->progress.cuts = longs[3], r->last_vtu_step = longs[4], r->linear_solves = longs[5], r->active_set_loops = longs[6];
    r->linear_factorisations = longs[7], r->krylov_iterations = longs[8];
    r->time = doubles[0], r->progress.dt = doubles[1], r->dissipated = doubles[2];
    r->external_work = doubles[3];
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
static sk_status load_state_file(const sk_restart *r, int rank, sk_byte_buffer *b) {
  char path[4400];
  snprintf(path, sizeof path, "%s/state-%04d.bin", r->dir, rank);
  FILE *f = fopen(path, "rb");
  if (!f)
    return sk_error_set(SK_ERR_INPUT, "--restart: %s is missing (the checkpoint was written by %d ranks): %s", path,
                        r->ranks, strerror(errno));
  if (sk_checkpoint_slurp(f, b) != 0) return sk_error_set(SK_ERR_NOMEM, "--restart: out of memory reading %s", path);
  const int whole = sk_checkpoint_whole(b, sk_checkpoint_state_magic, 16);
  if (whole == 0)
    return sk_error_set(SK_ERR_INPUT, "--restart: %s is not a whole stickslip state file (truncated or damaged)", path);
  if (whole < 0) return sk_error_set(SK_ERR_INPUT, "--restart: %s is damaged (its checksum does not match)", path);
  int32_t head[4];
  memcpy(head, b->data + sizeof sk_checkpoint_state_magic, sizeof head);
  if (head[0] != rank || head[1] != r->ranks || head[2] != r->dim || head[3] != SK_CHECKPOINT_FORMAT)
    return sk_error_set(SK_ERR_INPUT, "--restart: %s belongs to another checkpoint (rank %d of %d, dim %d, format %d)",
                        path, head[0], head[1], head[2], head[3]);
  return SK_OK;
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
  sk_record_set *sets = calloc((size_t)n_plugins + 1, sizeof *sets);
  unsigned char *seen = calloc((size_t)m->n_nodes + 1, 1);
  if (!sets || !seen) status = sk_error_set(SK_ERR_NOMEM, "--restart: out of memory");
  /* every rank's file: the nodes this rank holds, every record */
  for (int file = 0; file < r->ranks && status == SK_OK; ++file) {
    sk_byte_buffer b = {0};
    sk_error_clear();
    status = load_state_file(r, file, &b);
    size_t at = sizeof sk_checkpoint_state_magic + 4 * sizeof(int32_t);
    const size_t end = b.size - sizeof(uint64_t) - sizeof sk_checkpoint_end_magic;
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
      if (status != SK_OK) break;
      at += (size_t)len;
      memcpy(&count, b.data + at, sizeof count);
      at += sizeof count;
      int no_memory = 0;
      const int64_t used = sk_record_set_parse(&sets[t], b.data + at, end - at, count, &no_memory);
      if (used < 0) {
        status = no_memory ? sk_error_set(SK_ERR_NOMEM, "--restart: out of memory for the plugins' records")
                           : SK_ERR_INPUT;
        break;
      }
      at += (size_t)used;
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
    sys->linear_factorisations = (int)r->linear_factorisations;
    sys->krylov_iterations = r->krylov_iterations;
    sys->active_set_loops = (int)r->active_set_loops;
    sys->linear_fallback = r->linear_fallback;
    if (r->linear_fallback) status = sk_linsys_set_solver(sys->linsys, SK_LINEAR_DIRECT);
    sys->x_version++;
  }
  /* the contact partition of the checkpointed step, then the master faces held from the restart's positions (its
   * bodies may have moved beyond the set-up's reach) */
  int repartitioned = 0;
  if (status == SK_OK) status = sk_restart_partition(r->dir, sys, &repartitioned);
  if (status == SK_OK) status = sk_master_ghosts_restart(sys);
  for (int t = 0, k = 0; t < n_plugins && status == SK_OK; ++t) {
    while (sk_term_plugin_checkpointable(sys->terms[k], NULL) < 0) ++k;
    sk_term *term = sys->terms[k++];
    if (!sk_record_set_sort(&sets[t])) status = sk_error_set(SK_ERR_NOMEM, "--restart: out of memory");
    const int pair = sk_term_plugin_pair(term);
    const int slave_too = repartitioned && pair >= 0 && m->pairs[pair].contact_node_owner;
    if (status == SK_OK)
      status = sk_master_ghosts_term(sys, term) || slave_too
                   ? sk_term_plugin_recreate(term, sys, &sets[t].abi, slave_too)
                   : sk_term_plugin_load(term, sys, &sets[t].abi);
    if (status != SK_OK) sk_error_prefix(status, "--restart: %s: ", term->name);
    status = sk_system_collective(sys, status);
  }
  for (int t = 0; t < n_plugins && sets; ++t) sk_record_set_free(&sets[t]);
  free(sets);
  if (status == SK_OK) *progress = r->progress;
  return status;
}
