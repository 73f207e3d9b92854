/* A term of a step's nonlinear system (internal to the simulation layer): a body's bulk, the Dirichlet conditions,
 * the tractions, a plugin instance (pair or body). The system (system.c) holds a list of terms and calls them in
 * order; no term is special-cased in the stepper. Every entry may be NULL. The plugin ABI (plugin.h) mirrors this
 * table: term_plugin.c adapts one instance to it.
 *
 * Stages of an attempt: predict → begin_step → layout → pattern (+ rows) → Newton { update_active_set at each new
 * point; residual → (sum over ranks) → finish_residual; jacobian → finish_jacobian → (sum, condensation, solve) →
 * recover } → converged → commit (or reject) → report / points. */
#ifndef STICKSLIP_TERM_H
#define STICKSLIP_TERM_H

#include <stdio.h>

#include "stickslip/plugin.h"
#include "stickslip/model.h"

typedef struct sk_system sk_system;
typedef struct sk_term sk_term;

/* What a term needs evaluated, declared once when it is created (system_needs.c collects them): the system computes
 * a need only when some term declares it, and `stickslip run|check --explain` prints the declarations with their
 * reasons. `applies` says the question makes sense for the term (a bulk term has no friction to skip). */
typedef enum {
  SK_NEED_MASS,            /* consistent element mass: inertia, body force, a plugin's stickslip.bulk mass calls */
  SK_NEED_FRICTION,        /* tangential terms, slip history and friction output of a contact pair */
  SK_NEED_MASTER_UNKNOWNS, /* a deformable master surface: its dofs coupled into the pair's rows */
  SK_NEED_STIFFNESS_UPDATE,/* element stiffness re-evaluated at every iterate (else: assembled once, f = K u) */
  SK_NEED_IDLE_CALLS,      /* a pair's active-set, residual and Jacobian calls on steps it has no candidate */
  SK_NEED_COUNT
} sk_need;

typedef struct {
  unsigned char applies[SK_NEED_COUNT];
  unsigned char needed[SK_NEED_COUNT];
  char why[SK_NEED_COUNT][160]; /* the reason, for --explain: "time.scheme backward-euler (inertia)" */
} sk_needs;

/* Records one declaration of a term (printf-style reason). */
void sk_needs_declare(sk_needs *needs, sk_need need, int needed, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
const char *sk_need_name(sk_need need);
/* 1 when the test switch STICKSLIP_NO_SKIP (a comma list of need names, or "all") forces `need` to be computed
 * even where no term declares it: tests/bench/skip compares the results with and without the skip. Only the needs
 * the host skips itself (mass, stiffness-update, idle-calls) can be forced; the others are skipped inside the plugins. */
int sk_need_forced(sk_need need);
/* The same switch for a skip that is not a term's need (the recorder's "invariants"). */
int sk_skip_forced(const char *name);

typedef struct sk_term_ops {
  const char *kind; /* "bulk", "dirichlet", "traction", "resultant", "plugin" */
  void (*destroy)(sk_term *term);
  /* Start of an attempt, before the plugins see the step: the predictor of the term's unknowns in sys->x. */
  sk_status (*predict)(sk_term *term, sk_system *sys);
  sk_status (*begin_step)(sk_term *term, sk_system *sys);
  /* Sets term->n_extra, initial, eliminated (and pairs for condensation through sys) for the attempt. */
  sk_status (*layout)(sk_term *term, sk_system *sys);
  /* Declares couplings beyond the bulk graph (sk_system_declare) and marks the rows this rank writes matrix
   * entries into (rows[r] = 1). */
  sk_status (*pattern)(sk_term *term, sk_system *sys, unsigned char *rows);
  sk_status (*update_active_set)(sk_term *term, sk_system *sys, int *changed);
  /* Adds to sys->F_local (this rank's part). */
  sk_status (*residual)(sk_term *term, sk_system *sys);
  /* Adds to the operator's local contributions (sys->values) and sys->rhs_local. */
  sk_status (*jacobian)(sk_term *term, sk_system *sys);
  /* On the residual summed over ranks (Dirichlet: reactions, then rows replaced). */
  sk_status (*finish_residual)(sk_term *term, sk_system *sys, double *F);
  /* On the local contributions after every term's jacobian (Dirichlet: rows zeroed, unit diagonal on rank 0). */
  sk_status (*finish_jacobian)(sk_term *term, sk_system *sys);
  /* On the summed right-hand side correction of plugin-local condensation (Dirichlet: zero at fixed rows). */
  void (*finish_rhs)(sk_term *term, sk_system *sys, double *rhs);
  /* After a linear solve: fill dx of the term's eliminated extras (owned entities; summed over ranks). */
  sk_status (*recover)(sk_term *term, sk_system *sys, const double *F, double *dx);
  sk_status (*converged)(sk_term *term, sk_system *sys, int *accept);
  sk_status (*commit)(sk_term *term, sk_system *sys);
  void (*reject)(sk_term *term, sk_system *sys);
  /* Contact results of the committed step (initial: the initial row); this rank's part. */
  sk_status (*report)(sk_term *term, sk_system *sys, int initial, sk_contact_report *report);
  sk_status (*points)(sk_term *term, sk_system *sys, int initial, sk_point_callback callback, void *ctx);
} sk_term_ops;

struct sk_term {
  const sk_term_ops *ops;
  char name[96];                   /* for messages: "body 'disk'", "contact pair 'floor'" */
  /* the extra unknowns of the current attempt (layout): ABI indices extra_offset + j (j < n_extra); this rank holds
   * (owns or ghosts) n_held of them, held[k] ascending, at the local unknowns extra_local + k (system_layout.c) */
  int64_t extra_offset, n_extra, extra_local;
  int64_t *held, n_held, held_size;
  int64_t held_offset;             /* extra_offset when held was made (a moved block is a changed layout) */
  /* the block the plugins read (sk_state.extra, n_extra values by j): the held ones copied from x
   * (sk_system_extra_block), the others the layout's starting values */
  double *extra_values;
  int64_t values_size;
  const double *initial;
  const unsigned char *eliminated;
  /* n_extra: the rank owning each extra (that of its entity) when this rank holds it, -1 when it does not; NULL:
   * every rank holds every extra and rank 0 owns them (global scalars, or a plugin that gives no extra_anchor) */
  const int *extra_owner;
  const int64_t *anchor;           /* n_extra: an unknown of the mesh node each extra belongs to, or -1; NULL: none
                                      (the same on every rank; widens the pattern's growth, system_pattern.c) */
  int recover_needs_jdx;
  double seconds;                  /* time spent in residual/jacobian (summary.json) */
  sk_needs needs;                  /* declared at create (see sk_need) */
};

/* A term without extra unknowns for the attempt: what each layout starts from, and the layout of a created pair the
 * broad phase puts to sleep. */
static inline void sk_term_no_extras(sk_term *term) {
  term->n_extra = 0;
  term->initial = NULL;
  term->eliminated = NULL;
  term->anchor = NULL;
  term->extra_owner = NULL;
  term->recover_needs_jdx = 0;
}

/* The terms of core/model (each returns a new term or an error). */
sk_status sk_term_bulk_create(sk_system *sys, int body, sk_term **term);      /* term_bulk.c */
sk_status sk_term_traction_create(sk_system *sys, sk_term **term);            /* term_bulk.c */
sk_status sk_term_resultant_create(sk_system *sys, int k, sk_term **term);    /* term_resultant.c */
sk_status sk_term_dirichlet_create(sk_system *sys, sk_term **term);           /* term_dirichlet.c */
/* A plugin instance attached to body `body` (>= 0) or contact pair `pair` (>= 0); term_plugin.c. */
sk_status sk_term_plugin_create(sk_system *sys, int body, int pair, sk_term **term);
/* The obstacle's reaction column of a plugin term of a pair with a rigid obstacle (sk_contact_pair.obstacle_column,
 * -1 otherwise); the pair index of a plugin term (-1 for a body). */
int sk_term_plugin_obstacle_column(const sk_term *term);
int sk_term_plugin_pair(const sk_term *term);
/* Checkpoints (plugin.h: stickslip.checkpoint.v1): for a plugin term, 1 when its plugin offers the extension and
 * *plugin its name, 0 when it does not; -1 for other terms. save: the history after a commit (the state of report);
 * load: before the first step of a restarted run (the state at t_n). */
int sk_term_plugin_checkpointable(const sk_term *term, const char **plugin);
sk_status sk_term_plugin_save(sk_term *term, sk_system *sys, sk_record_writer *writer);
/* A pair's instance re-created over its master view built again from the faces held now (master_ghosts.c) — with
 * slave_too also its slave view, from the slave entities its rank contact-owns now (contact_partition.h), and its
 * extras' owners recomputed — its history loaded from `records` (every rank's, as at a restart). */
sk_status sk_term_plugin_recreate(sk_term *term, sk_system *sys, const sk_record_reader *records, int slave_too);
sk_status sk_term_plugin_load(sk_term *term, sk_system *sys, const sk_record_reader *reader);
/* A plugin term that claimed its body and whose integrator reports the energy its scheme conserves (ABI 2.5): *body
 * is that body and energy[0], energy[1] its kinetic and strain energy, this rank's part (initial: of the initial
 * state); *body = -1 and zeros for any other term. */
sk_status sk_term_plugin_scheme_energy(sk_term *term, sk_system *sys, int initial, int *body, double energy[2]);
/* The parameters a plugin term computed from the scene (stickslip.scene.v1), one line each into `out` (--explain;
 * NULL: none); returns how many. */
int sk_term_plugin_explain_defaults(const sk_term *term, FILE *out);
/* The k-th parameter a plugin term computed from the scene: its key path in the scene ("contact[0].parameters.penalty",
 * the pair's entry for a pair created by `bodies:`), value and reason; 0 past the last (or for another term). */
int sk_term_plugin_computed(const sk_term *term, int k, char *path, size_t size, double *value, const char **reason);
/* A contact pair created by `bodies:`: one line with its surfaces and what the broad phase does with it (1), or 0
 * for other terms (nothing printed; out NULL only counts). */
int sk_term_plugin_explain_pair(const sk_term *term, FILE *out);
/* A contact pair whose plugin regularises the constraint by a penalty (no multipliers, SK_CAP_MULTIPLIERS unset), so
 * that its report's constraint_norm is a penetration: the pair, with *h the mean corner-to-corner edge of its slave
 * surface (the whole surface's); NULL for other terms. */
const sk_contact_pair *sk_term_plugin_penalty_pair(const sk_term *term, double *h);

#endif
