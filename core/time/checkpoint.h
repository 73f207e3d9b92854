/* Checkpoints and restarts (internal to the simulation layer; docs/user-guide.md, "Checkpoints and restart"): the
 * state of a run after a converged step — the dofs' displacements, velocities and last rates by mesh id, the
 * plugins' history as keyed records (plugin.h: stickslip.checkpoint.v1), the stepper's and the recorder's counters —
 * written by every rank into a folder that appears complete or not at all, and read back on any number of ranks. */
#ifndef STICKSLIP_CHECKPOINT_H
#define STICKSLIP_CHECKPOINT_H

#include "../model/system.h"
#include "stickslip/run.h"

/* Where the stepper stands after a converged step (run.c), what a restart continues from. */
typedef struct {
  int64_t steps;          /* converged steps */
  int64_t scheduled;      /* scheduled times reached */
  int substep;            /* sub-steps since the last scheduled time */
  double dt;              /* the step size the next step starts with */
  int cuts_in_a_row, good_steps;
  int64_t newton_iterations, cuts;
} sk_progress;

/* The recorder's part of a checkpoint (recorder.c). */
typedef struct sk_recorder_state_s {
  double dissipated;      /* accumulated dissipated energy */
  double external_work;   /* accumulated work of the loads */
  int64_t last_vtu_step;
  const char *history_path; /* rank 0: the history.csv written so far (NULL: none) */
  const char *contact_path; /* rank 0: the contact.csv written so far (NULL: none) */
} sk_recorder_state;

/* Refuses a run with checkpoints whose plugins cannot write their history (collective). */
sk_status sk_checkpoint_check(sk_system *sys, const sk_run_options *options);
/* Writes the checkpoint of the step just committed (before the system advances; collective). */
sk_status sk_checkpoint_write(const sk_run_options *options, sk_system *sys, const sk_progress *progress,
                              const sk_recorder_state *recorder);

/* A checkpoint read for a restart (sk_restart_open, in the driver, before the scene is loaded). */
struct sk_restart {
  char dir[4096];          /* the checkpoint's step folder */
  char scene[4096];        /* the scene file it was written for */
  char plugin[256];        /* its --plugin, or "" */
  int n_sets;
  char **sets;             /* its --set and --replace values, in their order */
  sk_cfg_override_mode *set_modes; /* per value: SK_CFG_MERGE (--set) or SK_CFG_REPLACE (--replace) */
  uint64_t scene_hash, mesh_hash;
  int ranks;               /* the number of ranks that wrote it */
  int n_nodes, dim;
  double time;
  sk_progress progress;
  double dissipated, external_work;
  int64_t last_vtu_step;
  int64_t linear_solves, active_set_loops;
  int64_t linear_factorisations, krylov_iterations; /* 0 from checkpoints written before they were counted */
  int linear_fallback;
};

/* The restart's state into the system and its plugins, the stepper's counters into *progress (collective). */
sk_status sk_restart_apply(const sk_restart *restart, sk_system *sys, sk_progress *progress);
/* A 64-bit FNV-1a hash of a file's bytes (0 when it cannot be read). */
uint64_t sk_checkpoint_file_hash(const char *path);
/* An order-independent hash of the mesh (each node's id and reference position; collective). */
uint64_t sk_checkpoint_mesh_hash(const sk_model *model);

#endif
