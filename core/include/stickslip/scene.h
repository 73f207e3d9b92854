/* stickslip — a scene: the YAML file (docs/scene-reference.md) turned into a model, solver and output settings. */
#ifndef STICKSLIP_SCENE_H
#define STICKSLIP_SCENE_H

#include <mpi.h>

#include "stickslip/bridge.h"
#include "stickslip/config.h"
#include "stickslip/model.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
  sk_newton_options newton;
  sk_linear_options linear;
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
  sk_host host;           /* the table plugins reach the core through */
} sk_scene;

/* Reads and validates a scene: YAML, `--set` overrides, meshes, bodies, boundary conditions, contact pairs and their
 * plugins (created, so plugin parameters are checked), time, solver and output settings; unknown keys are errors.
 * `plugin_override` (may be NULL) replaces every pair's plugin. Collective over `comm`. */
sk_status sk_scene_load(const char *path, int n_sets, const char *const *sets, const char *plugin_override,
                        MPI_Comm comm, sk_scene *scene);
void sk_scene_free(sk_scene *scene);

/* The host table for a model (host.c). */
void sk_host_init(sk_host *host, sk_model *model);

#ifdef __cplusplus
}
#endif
#endif
