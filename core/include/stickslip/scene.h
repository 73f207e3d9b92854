/* stickslip — a scene: the YAML file (docs/scene-reference.md) turned into a model, solver and output settings. */
#ifndef STICKSLIP_SCENE_H
#define STICKSLIP_SCENE_H

#include <mpi.h>
#include <stdio.h>

#include "stickslip/bridge.h"
#include "stickslip/config.h"
#include "stickslip/model.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
  sk_newton_options newton;
  sk_linear_options linear;
  int predictor;            /* solver.newton.predictor: 1 (previous-increment) quasi-static steps start from u_n
                               plus the previous increment scaled to dt; 0 (last-state, default) from u_n */
  int max_active_set_loops; /* solver.newton.max_active_set_loops: Newton runs per attempt when terms reject a
                               converged point (plugin.h: converged) */
  int pattern_margin;       /* solver.pattern_margin: rings of mesh neighbours by which couplings the terms declare
                               widen the sparsity pattern when it grows (system_pattern.c) */
} sk_solver_settings;

typedef struct {
  int vtu_every;          /* write a .vtu every this many steps (0: only the last) */
  int write_vtu;
  int write_contact_csv;
} sk_output_settings;

typedef struct {
  char path[1024];
  char description[512];
  sk_cfg *cfg;
  sk_model model;
  sk_solver_settings solver;
  sk_output_settings output;
  struct sk_system *system; /* the step's system of terms, with the plugin instances (core/model/system.h) */
} sk_scene;

/* Reads and validates a scene: YAML, `--set` overrides, meshes, bodies, boundary conditions, contact pairs and the
 * plugins of pairs and bodies (their instances created, so plugin parameters are checked), time, solver and output
 * settings; unknown keys are errors. `plugin_override` (may be NULL) replaces every pair's plugin. Collective. */
sk_status sk_scene_load(const char *path, int n_sets, const char *const *sets, const char *plugin_override,
                        MPI_Comm comm, sk_scene *scene);
void sk_scene_free(sk_scene *scene);
/* What the scene computes and skips, with the reasons: every term's declared needs and the outputs of a run into
 * `out_dir` (NULL: no result files). For `stickslip run|check --explain`; rank 0 calls it. */
void sk_scene_explain(const sk_scene *scene, const char *out_dir, int progress, FILE *out);

/* A message to the user on rank 0 (rank == 0): level 0 info, 1 warning ("warning: " prefix), 2 debug (shown only
 * with sk_log_verbosity > 0, i.e. --verbose). The one path for the core's and the plugins' messages (host.c). */
void sk_log_message(int rank, int level, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
extern int sk_log_verbosity;

#ifdef __cplusplus
}
#endif
#endif
