/* A plugin instance as a term of the system (internal): the instance, its host handle, attachment, views and the
 * state it sees. term_plugin_create.c creates it, term_plugin.c runs the ABI calls; host.c serves the api and the
 * extensions. */
#ifndef STICKSLIP_TERM_PLUGIN_H
#define STICKSLIP_TERM_PLUGIN_H

#include <stdlib.h>

#include "host.h"
#include "scene_info.h"

enum { PLUGIN_MAX_VIEWS = 2, PLUGIN_MAX_COMPUTED = 16 };

/* A parameter default the instance computed from the scene (stickslip.scene.v1 computed()), for --explain. */
typedef struct {
  char key[64];
  double value;
  char reason[400];
} plugin_computed;

typedef struct plugin_term {
  sk_term base;
  sk_plugin table;                 /* the plugin's table, members beyond its struct_size NULL */
  const sk_plugin *plugin;         /* as loaded (its name, strategies) */
  sk_instance *instance;
  sk_host host;
  sk_attach attach;
  int body, pair;                  /* what it is attached to (-1: not that kind) */
  int n_views;
  sk_view_data views[PLUGIN_MAX_VIEWS];
  const sk_view *view_list[PLUGIN_MAX_VIEWS];
  /* the state it sees: positions per view, refreshed when the system's iterate changes */
  sk_state state;
  double *x[PLUGIN_MAX_VIEWS], *x_n[PLUGIN_MAX_VIEWS], *v_n[PLUGIN_MAX_VIEWS];
  const double *x_list[PLUGIN_MAX_VIEWS], *x_n_list[PLUGIN_MAX_VIEWS], *v_n_list[PLUGIN_MAX_VIEWS];
  uint64_t x_version;
  sk_layout layout;
  int idle; /* this attempt: the plugin said sk_layout.idle on every rank, so its calls are skipped */
  /* the host's broad phase (pairs created by `bodies:`, plugins without extra unknowns; broad_phase.c): far = the
   * two surfaces' boxes, swept over the step and inflated by broad_margin, do not overlap, so the term is not among
   * the attempt's live terms and its plugin is not called; broad_id: its number in the broad phase */
  int broad_phase, broad_id, far, apart_at_start;
  double broad_margin;
  int64_t *anchor;                 /* sk_layout.extra_anchor combined over ranks (n_extra), or NULL */
  int *extra_owner;                /* the owner of each extra this rank holds, else -1 (n_extra) */
  int64_t anchor_size, anchor_count;
  unsigned char *in_view;          /* per model node: 1 when it is a node of one of the views */
  /* recover: the solve's vectors in the instance's layout */
  double *F_view[PLUGIN_MAX_VIEWS], *dx_view[PLUGIN_MAX_VIEWS], *Jdx_view[PLUGIN_MAX_VIEWS];
  const double *F_list[PLUGIN_MAX_VIEWS], *dx_list[PLUGIN_MAX_VIEWS], *Jdx_list[PLUGIN_MAX_VIEWS];
  double *recover_F, *recover_dx, *recover_Jdx; /* and of the extras, as the instance's block (n_extra by j) */
  int64_t recover_size;
  /* body plugins */
  int claimed;                     /* stickslip.bulk claim() */
  const sk_integrator *integrator; /* its own integrator when claimed */
  double *pending_u, *pending_v;   /* set_state() of this commit (view layout), applied by the host */
  int has_pending_state;
  double *scratch_K;               /* one element stiffness (stickslip.bulk add_stiffness, inside Newton) */
  /* stickslip.linear: solve_again's full vectors (allocated at layout, used inside Newton) */
  int wants_linear;
  double *again_b, *again_y;
  int64_t again_size;
  /* stickslip.scene.v1: the attachment as the scene describes it, and the defaults computed from it */
  sk_scene_description scene;
  plugin_computed computed[PLUGIN_MAX_COMPUTED];
  int n_computed;
} plugin_term;

/* n doubles set to zero (at least one, so that an empty view's arrays are not NULL), and a view's dof count. */
static inline double *sk_plugin_zeros(int64_t n) { return calloc((size_t)(n > 0 ? n : 1), sizeof(double)); }
static inline int sk_view_dof_count(const sk_view *view) { return view->n_nodes * view->dim; }
/* A plugin call's status, with a message naming the call and the status where the plugin returned an error without
 * one; PLUGIN_CALL(term, call, args...) makes the call through it. */
sk_status sk_plugin_term_said(const plugin_term *term, const char *call, sk_status status);
#define PLUGIN_CALL(term, call, ...) \
  (sk_error_clear(), sk_plugin_term_said((term), #call, (term)->table.call(__VA_ARGS__)))
/* Positions, x_n and v_n of the views from the system (refresh_state: only when the iterate changed). */
void sk_plugin_term_refresh(plugin_term *term, sk_system *sys, int initial);
/* The ops of plugin terms (to tell them apart from core terms). */
const sk_term_ops *sk_plugin_term_ops(void);
/* The broad phase's side of a created pair's term (broad_phase.c): its number there, or -1 when the broad phase does
 * not drive it; far = 1 puts it to sleep (idle, no extra unknowns) and 0 wakes it for the attempt about to start;
 * wake brings it near at a converged point (its plugin's begin_step from there). */
int sk_term_plugin_broad_id(const sk_term *term);
void sk_term_plugin_set_far(sk_term *term, sk_system *sys, int far);
sk_status sk_term_plugin_wake(sk_term *term, sk_system *sys);

#endif
