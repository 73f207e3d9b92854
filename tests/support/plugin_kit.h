/* The plugin test kit: one mock host for every plugin's unit tests, and one finite-difference checker of the
 * assembled operator through the plugin interface (tests/support/plugin_kit.c).
 *
 * A kit holds a small mesh (node positions, dim per node), the views of a pair built from face lists (whole
 * surfaces, every node and face owned, local numbering = sorted mesh ids, as the host builds them on one rank), a
 * mock api (parameters from a key/value list, errors recorded through sk_error_set, the core's contact services over
 * the views) and dense sinks over all unknowns [positions (dim per mesh node) | the instance's extra unknowns]. The
 * plugin is driven through its ABI table exactly as the host drives it; kit_fd_check compares the Jacobian the plugin
 * assembles with central differences of the residual it assembles, over every unknown, and counts Jacobian entries
 * outside the pattern the plugin declared. The mock api offers stickslip.condense.v1 and records the pairs (the
 * elimination itself is the host's, core/solver/condense.cpp), and stickslip.scene.v1 (the views' sizes, the
 * materials of kit_material, and the defaults the instance reports). */
#ifndef STICKSLIP_PLUGIN_KIT_H
#define STICKSLIP_PLUGIN_KIT_H

#include "stickslip/contact.h"
#include "stickslip/plugin.h"

enum { KIT_MAX_PARAMS = 16, KIT_MAX_VIEWS = 2 };

typedef struct kit_view kit_view; /* a view and what backs it */

typedef struct kit {
  /* the mesh */
  int dim, n_nodes, n_dofs;
  double *X;                       /* reference positions, dim per node */
  /* the attachment */
  kit_view *views[KIT_MAX_VIEWS];
  const sk_view *view_list[KIT_MAX_VIEWS];
  int n_views;
  sk_obstacle obstacle;
  sk_attach attach;
  /* parameters */
  int n_params;
  const char *key[KIT_MAX_PARAMS];
  double value[KIT_MAX_PARAMS];
  const char *text[KIT_MAX_PARAMS];
  /* the plugin and its instance */
  const sk_plugin *plugin;
  sk_instance *instance;
  sk_host_api api;
  struct kit_host *host;
  /* the state the instance sees */
  sk_state state;
  double *x[KIT_MAX_VIEWS], *x_n[KIT_MAX_VIEWS], *v_n[KIT_MAX_VIEWS];
  const double *xl[KIT_MAX_VIEWS], *x_nl[KIT_MAX_VIEWS], *v_nl[KIT_MAX_VIEWS];
  double alpha;                    /* the integrator's (default 1: quasi-static) */
  int dynamic;
  /* the layout of the current attempt */
  sk_layout layout;
  int64_t n;                       /* n_dofs + n_extra */
  double *extra;                   /* the extra unknowns (n_extra) */
  unsigned char *declared;         /* n x n: entries declared by pattern() (NULL when the plugin has none) */
  int64_t outside_pattern;         /* Jacobian entries outside the declared pattern (and outside node blocks) */
  /* what the instance declared through stickslip.condense.v1 in its last layout(): groups of `pair_block` pairs,
   * extra index pair_extra[i] with displacement row pair_row[i] */
  int64_t n_pairs;
  int pair_block;
  int64_t *pair_extra, *pair_row;
  /* stickslip.scene.v1: the description of the attachment (built by kit_create) and the defaults the instance
   * computed from it */
  double E[2], nu[2];
  sk_scene_side sides[2];
  sk_scene_info scene;
  int n_computed;
  char computed_key[KIT_MAX_PARAMS][32];
  double computed_value[KIT_MAX_PARAMS];
} kit;

void kit_init(kit *k, int dim, int n_nodes, const double *X);
void kit_free(kit *k);
void kit_param(kit *k, const char *key, double value);
void kit_param_text(kit *k, const char *key, const char *value);
/* Slave (role 0) or master (role 1) surface from n_faces faces of `nen` mesh node ids each. */
void kit_surface(kit *k, int role, sk_elem_type type, int nen, int n_faces, const int *conn);
/* A rigid obstacle as the master. */
void kit_obstacle(kit *k, const sk_obstacle *obstacle);
/* The material of the slave (role 0) or master (role 1) body, for the scene description the mock host offers
 * through stickslip.scene.v1 (default E 1, nu 0). */
void kit_material(kit *k, int role, double E, double nu);
/* The default the instance computed for `key` and reported (stickslip.scene.v1 computed()), or NaN. */
double kit_computed(const kit *k, const char *key);
/* The time integrator the instance sees (alpha, dynamic). */
void kit_integrator(kit *k, double alpha, int dynamic);

/* create() with the strategy; the instance lives until kit_destroy. */
sk_status kit_create(kit *k, const sk_plugin *plugin, int strategy);
void kit_destroy(kit *k);

/* The state for positions q (dim per mesh node), q_n, times, velocities v_n (may be NULL); extra: the instance's extra
 * unknowns (NULL: the kit's own). */
void kit_state(kit *k, const double *q_n, const double *q, double t_n, double t, const double *v_n);
/* begin_step, layout (initial values into the kit's extras) and pattern at the current state. */
sk_status kit_begin(kit *k);
/* update_active_set at positions q (and the kit's extras). */
sk_status kit_update_active_set(kit *k, const double *q, int *changed);
/* Dense residual F (n) and Jacobian J (n x n, row-major) at positions q and the kit's extras (rhs: the add_rhs
 * correction, may be NULL). */
sk_status kit_residual(kit *k, const double *q, double *F);
sk_status kit_jacobian(kit *k, const double *q, double *J, double *rhs);
/* J against central differences of F over every unknown (positions and extras), at q and the kit's extras, with step
 * h. Returns the largest absolute error; *scale gets max |J|. The active set stays as it is (no update). */
double kit_fd_check(kit *k, const double *q, double h, double *scale);
/* Under plugin-local condensation (layout.eliminated): the assembled kept block against the Schur complement of
 * central differences over the eliminated unknowns, J_kk - J_ke J_ee^-1 J_ek, and add_rhs against J_ke J_ee^-1 F_e
 * (docs/plugin-abi.md §6). Returns the largest absolute error of the block; *rhs_error that of the right-hand side,
 * *scale max |J|. Entries the plugin adds in eliminated rows or columns count as errors. */
double kit_fd_check_condensed(kit *k, const double *q, double h, double *scale, double *rhs_error);
/* Central differences of F over every unknown, J_fd (n x n, row-major), at q and the kit's extras. */
void kit_fd_jacobian(kit *k, const double *q, double h, double *J_fd);
/* converged() at positions q (accept = 1 when the plugin has none). */
sk_status kit_converged(kit *k, const double *q, int *accept);
/* After a rejected converged point: layout and pattern again, as the host does; the extras keep their values. */
sk_status kit_layout_again(kit *k);
/* recover() after a solve: F and dx over all n unknowns (dx's eliminated extras are written). */
sk_status kit_recover(kit *k, const double *q, const double *F, double *dx);
sk_status kit_commit(kit *k);
sk_status kit_report(kit *k, sk_contact_report *report);

typedef struct {
  int n;
  sk_contact_point p[256];
} kit_points;
sk_status kit_points_at(kit *k, kit_points *points);
const sk_contact_point *kit_point_of(const kit_points *points, int64_t node);

/* A built plugin module loaded as the host loads it: the entry, ABI 2, its name, the required entries, hidden
 * internals (`internal_symbol` must not be exported). Returns the table or NULL (after failed checks). */
const sk_plugin *kit_load_module(const char *path, const char *name, const char *internal_symbol);

#endif
