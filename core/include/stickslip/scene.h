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
  char source[4096];        /* the scene file's absolute path */
  char *provenance;         /* comment lines for the results' scene.yaml: where the scene came from, the overrides */
  char description[512];
  sk_cfg *cfg;
  sk_model model;
  sk_solver_settings solver;
  sk_output_settings output;
  struct sk_system *system; /* the step's system of terms, with the plugin instances (core/model/system.h) */
} sk_scene;

/* The command line's changes to a scene, applied to its tree in this order: the assignments (command-line order),
 * then the plugin. */
typedef struct {
  int n;
  const char *const *assignments;    /* "key.path=value" */
  const sk_cfg_override_mode *modes; /* per assignment: SK_CFG_MERGE (--set) or SK_CFG_REPLACE (--replace); NULL:
                                        all --set */
  const char *plugin;                /* --plugin NAME: every pair's plugin, keeping of each pair's parameters (and
                                        strategy) what NAME takes; NULL: none */
} sk_scene_overrides;

/* Reads and validates a scene: YAML, the overrides, meshes, bodies, boundary conditions, contact pairs and the
 * plugins of pairs and bodies (their instances created, so plugin parameters are checked), time, solver and output
 * settings; unknown keys are errors. Afterwards scene->cfg is the effective scene (overrides applied, mesh paths
 * absolute). `overrides` may be NULL. Collective. */
sk_status sk_scene_load_with(const char *path, const sk_scene_overrides *overrides, MPI_Comm comm, sk_scene *scene);
/* The same with `--set` assignments only. */
sk_status sk_scene_load(const char *path, int n_sets, const char *const *sets, const char *plugin_override,
                        MPI_Comm comm, sk_scene *scene);
/* Applies the overrides to scene->cfg and records them in scene->provenance (scene_effective.c): a --plugin that
 * changes a pair's plugin drops the parameters and the strategy of the file that the new plugin does not take (one
 * warning names them; keys set on the command line stay, so a misspelt one is still an error). */
sk_status sk_scene_apply_overrides(sk_scene *scene, const sk_scene_overrides *overrides);
/* Adds `line` (without its "# " and newline) to the header of the results' scene.yaml: what the command line did to
 * the run that the scene does not say (`--steps N`). */
void sk_scene_note(sk_scene *scene, const char *line);
/* Rewrites every mesh `file` of scene->cfg as an absolute path, so the effective scene reads from any folder. */
sk_status sk_scene_absolute_mesh_paths(sk_scene *scene);
/* The effective scene as YAML into `path`, after a comment header saying where it came from and what the command
 * line changed: `stickslip run path` reruns it from any folder. */
sk_status sk_scene_write(const sk_scene *scene, const char *path);
/* Every key of the loaded scene with its value or default, unit and origin (file:line:column, --set, default), and
 * for each pair and body plugin every parameter of its table (`stickslip keys`). Rank 0 calls it. */
void sk_scene_keys(const sk_scene *scene, FILE *out);
/* The same for a plugin alone: its parameters with their declared defaults (`stickslip keys --plugin NAME`). */
sk_status sk_plugin_keys(const sk_plugin *plugin, FILE *out);
void sk_scene_free(sk_scene *scene);
/* What the scene computes and skips, with the reasons: every term's declared needs and the outputs of a run into
 * `out_dir` (NULL: no result files). For `stickslip run|check --explain`; rank 0 calls it. */
void sk_scene_explain(const sk_scene *scene, const char *out_dir, int progress, FILE *out);

/* A message to the user on rank 0 (rank == 0): level 0 info (not shown with sk_log_verbosity < 0, i.e. --quiet),
 * 1 warning ("warning: " prefix, always shown), 2 debug (shown only with sk_log_verbosity > 0, i.e. --verbose). The
 * one path for the core's and the plugins' messages (host.c). */
void sk_log_message(int rank, int level, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
extern int sk_log_verbosity;

#ifdef __cplusplus
}
#endif
#endif
