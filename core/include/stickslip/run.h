/* stickslip — running a scene: the time-stepping loop over NOX, contact plugins and result files. */
#ifndef STICKSLIP_RUN_H
#define STICKSLIP_RUN_H

#include "stickslip/scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A checkpoint read for a restart (core/time/restart.c). */
typedef struct sk_restart sk_restart;

typedef struct {
  const char *out_dir;     /* results folder (replaced atomically at the end), or NULL for none */
  int progress;            /* progress line on stderr (rank 0) */
  int verbose;             /* Newton details per step */
  int max_steps;           /* stop after this many steps (0: run to the end) — for tests and quick looks */
  int checkpoint_every;    /* write a checkpoint every this many converged steps (0: none) */
  const char *checkpoint_dir; /* the folder of the checkpoints (docs/user-guide.md, "Checkpoints and restart") */
  /* the scene as loaded (its file, --set values, --plugin), recorded in checkpoints to load it again */
  const char *scene_path;
  const char *const *sets;
  const sk_cfg_override_mode *set_modes; /* per entry of sets: --set or --replace (NULL: all --set) */
  int n_sets;
  const char *plugin;
  const sk_restart *restart; /* continue from this checkpoint (sk_restart_open), or NULL */
} sk_run_options;

typedef struct {
  int steps;
  int newton_iterations;
  int linear_solves;
  int linear_factorisations; /* numeric LU factorisations of the system matrix (direct solvers, gmres-lu) */
  int64_t krylov_iterations; /* Krylov iterations over all linear solves */
  int cuts;                /* step halvings */
  int64_t unknowns_max;    /* largest size of the nonlinear system over the run */
  int64_t linear_size_max; /* largest size of the linear system actually solved (after condensation) */
  int pattern_builds;      /* sparsity patterns built or grown (each rebuilds the solver's matrix; solver.pattern_margin) */
  int master_reghosts;     /* steps at which master faces ghosted by swept boxes were ghosted again */
  int contact_rebalances;  /* steps that started from a new contact partition (contact_balance.rebalance) */
  int active_set_loops;    /* Newton restarts because a term rejected a converged point (plugin.h: converged) */
  int roundoff_floor_steps; /* steps accepted at the residual's round-off floor (bridge.h: SK_NEWTON_ROUNDOFF_FLOOR) */
  int backtrack_retries;   /* failed steps solved again with the backtracking line search before a cut
                              (line_search full-step-then-backtrack) */
  int backtrack_rescues;   /* of those, the ones that converged (no cut needed) */
  int newton_backtrack_switches; /* Newton solves that made no progress under the full step and went on with the
                                    backtracking line search (newton.cpp: NoProgressTest) */
  double final_time;
  double wall_seconds, assembly_seconds, contact_seconds, solve_seconds; /* rank 0's */
  double contact_seconds_largest; /* the largest rank's contact seconds (0 when no results were written) */
  int failed;
  int interrupted;         /* with failed: stopped by SIGINT/SIGTERM between two steps (stickslip/interrupt.h) */
  char message[1024];
  char results_dir[4096];  /* where the result files are (out_dir, out_dir.incomplete, the staging folder when it
                              could not be put in place), "" when none were written (no --out, or a write error) */
} sk_run_summary;

/* Runs the scene to its end time (collective). On a failure after the run started (a step that cannot be solved
 * even after max_cuts halvings), the results up to the last converged step are still written, complete, with
 * status "failed" in summary.json, and the failure status is returned. A SIGINT/SIGTERM recorded by
 * sk_interrupt_install() is polled before each step: the run stops there, its results are written the same way with
 * status "interrupted", and SK_ERR_INTERRUPTED is returned. */
sk_status sk_run(sk_scene *scene, const sk_run_options *options, sk_run_summary *summary);

/* Reads the checkpoint in `dir` — a checkpoint folder (its latest checkpoint) or one of its step-NNNNNNNN folders —
 * on every rank: the scene, --set values and --plugin it was written for (the accessors below), and the state that
 * sk_run continues from (sk_run_options.restart). Errors name the folder and the file: no checkpoint, a partial one,
 * a damaged or truncated file. Collective. */
sk_status sk_restart_open(const char *dir, MPI_Comm comm, sk_restart **restart);
void sk_restart_free(sk_restart *restart);
const char *sk_restart_scene(const sk_restart *restart);
const char *sk_restart_plugin(const sk_restart *restart); /* NULL when it had none */
int sk_restart_sets(const sk_restart *restart, const char *const **sets, const sk_cfg_override_mode **modes);
/* The step folder it reads from, and the time and step it continues from. */
const char *sk_restart_folder(const sk_restart *restart);
double sk_restart_time(const sk_restart *restart);
int64_t sk_restart_step(const sk_restart *restart);

#ifdef __cplusplus
}
#endif
#endif
