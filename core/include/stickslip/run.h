/* stickslip — running a scene: the time-stepping loop over NOX, contact plugins and result files. */
#ifndef STICKSLIP_RUN_H
#define STICKSLIP_RUN_H

#include "stickslip/scene.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
  const char *out_dir;     /* results folder (replaced atomically at the end), or NULL for none */
  int progress;            /* progress line on stderr (rank 0) */
  int verbose;             /* Newton details per step */
  int max_steps;           /* stop after this many steps (0: run to the end) — for tests and quick looks */
} sk_run_options;

typedef struct {
  int steps;
  int newton_iterations;
  int linear_solves;
  int cuts;                /* step halvings */
  int64_t unknowns_max;    /* largest size of the nonlinear system over the run */
  int64_t linear_size_max; /* largest size of the linear system actually solved (after condensation) */
  int pattern_builds;      /* sparsity patterns built or grown (each rebuilds the solver's matrix; solver.pattern_margin) */
  int active_set_loops;    /* Newton restarts because a term rejected a converged point (plugin.h: converged) */
  int roundoff_floor_steps; /* steps accepted at the residual's round-off floor (bridge.h: SK_NEWTON_ROUNDOFF_FLOOR) */
  int backtrack_retries;   /* failed steps solved again with the backtracking line search before a cut
                              (line_search full-step-then-backtrack) */
  int backtrack_rescues;   /* of those, the ones that converged (no cut needed) */
  double final_time;
  double wall_seconds, assembly_seconds, contact_seconds, solve_seconds;
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

#ifdef __cplusplus
}
#endif
#endif
