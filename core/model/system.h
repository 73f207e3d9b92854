/* The system of a time step (internal to the simulation layer): the unknowns x = [displacement dofs | the terms'
 * extra unknowns], the list of terms (term.h) that pose F(x) = 0 and its Jacobian, the sparsity pattern (the bulk
 * element graph plus the couplings the terms declare), the linear solve with its condensation stages, and the NOX
 * callbacks. The stepper (core/time/run.c) drives it; the recorder (core/time/recorder.c) reads it.
 *
 * Parallel model (docs/design.md): each rank holds its local unknowns — the dofs of the nodes it owns, then of its
 * ghost nodes, then each term's block of extra unknowns — evaluates its own elements and entities into them, and
 * sums the ghost rows into their owners (exchange.h); NOX sees the owned unknowns; the matrix is assembled in the
 * bridge from the rows each rank writes. */
#ifndef STICKSLIP_SYSTEM_H
#define STICKSLIP_SYSTEM_H

#include <mpi.h>
#include <stdio.h>

#include "stickslip/bridge.h"
#include "stickslip/model.h"
#include "stickslip/scene.h"
#include "exchange.h"
#include "term.h"

typedef struct sk_condenser sk_condenser;

/* The contact phases timed apart (sk_system_charge_contact): the plugins' begin_step (search), update_active_set,
 * residual, jacobian, commit, and the host's broad phase over pairs. */
enum { SK_CONTACT_SEARCH, SK_CONTACT_ACTIVE_SET, SK_CONTACT_RESIDUAL, SK_CONTACT_JACOBIAN, SK_CONTACT_COMMIT,
       SK_CONTACT_BROAD_PHASE, SK_CONTACT_PHASES };
/* A reading of both clocks: wall (monotonic) and this thread's CPU time, in seconds; from sk_system_contact_clock
 * also the rank's waits so far (contact_wait), which the contact time leaves out. */
typedef struct {
  double wall, cpu, wait_wall, wait_cpu;
} sk_clock;

/* The sink plugins add through: the ABI table first, then the system. */
typedef struct {
  sk_sink abi;
  sk_system *sys;
  int failed;              /* an entry outside the pattern or this rank's rows: the message is recorded */
  char message[256];
} sk_system_sink;

struct sk_system {
  sk_model *model;
  MPI_Comm comm;
  int rank, n_ranks;
  const sk_solver_settings *solver;
  int backtracking; /* 1: this attempt's Newton uses the backtracking line search (run.c's retry of a failed step) */
  const sk_time_integrator *integrator; /* the scene's (pair plugins see its name and alpha) */
  int n_terms;
  sk_term **terms;
  sk_term **body_plugin;   /* per body: the plugin term attached to it, or NULL */
  unsigned char *claimed;  /* per body: 1 when a body plugin claimed it (no bulk term acts on it) */

  /* Local numbering (docs/design.md): the model's dofs (node * dim + i, owned and ghost nodes; the model holds this
   * rank's nodes), then each term's extra unknowns that this rank owns or ghosts, one block per term (extra_local,
   * n_held: term.h). The plugins' (ABI) numbering is the mesh node id * dim + i and, for extras,
   * term->extra_offset + j. */
  unsigned char *node_role;  /* per model node: SK_NODE_OWNED, SK_NODE_GHOST or 0 (not held by this rank) */
  int64_t n_owned_dofs;
  int *owned_dofs;           /* local dofs this rank owns, in the order of its nodal rows in the linear system */
  int64_t first_row;         /* the linear system's row of owned_dofs[0]; n_nodal rows over all ranks */
  int64_t n_nodal;

  /* time of the attempt and the committed state (the local dofs) */
  double t_n, t, dt;
  int64_t step;
  double *u_n, *v_n;       /* at t_n */
  double *rate_n;          /* (u_n - u_{n-1}) / dt of the last step: the quasi-static predictor's rate */
  double *v;               /* at t after commit */
  double *q_n;             /* positions X + u_n */

  /* the attempt's unknowns: n local ones (dofs, then the extras blocks) */
  int64_t n, capacity;
  int64_t n_abi;           /* the unknowns over all ranks (ABI numbering: every dof, every term's n_extra) */
  int *solver_of;          /* n: the unknown's row / column in the linear system, or -1 (eliminated, not held) */
  unsigned char *role;     /* n: SK_NODE_OWNED, SK_NODE_GHOST (kept up to date from its owner) or 0 (not held) */
  int64_t n_owned;         /* NOX's unknowns: the owned ones */
  int *owned;              /* n_owned local indices: the owned dofs, then the owned extras */
  int64_t n_kept;          /* the linear system's size (all ranks) */
  sk_exchange ghost_dofs;  /* the ghost nodes' dofs (planned again when master faces are ghosted again) */
  sk_exchange ghost_extras;/* the ghost extra unknowns (planned when their owners change) */
  int owned_known;         /* the extras' plan and the ghost dofs' rows are made */
  /* the kept extras are the linear system's constraint rows, all on the last rank: each rank's owned kept extras go
   * there (b) and come back (x) */
  int n_constraint_out;    /* this rank's owned kept extras */
  int *constraint_out;     /* their local indices */
  int *constraint_counts, *constraint_displs; /* per rank (the last rank's gather) */
  int *constraint_row;     /* last rank: the row (minus n_nodal) of each gathered value */
  double *constraint_buffer;
  int n_rows_owned;        /* rows of the linear system this rank owns */
  double *x;               /* the current iterate (capacity) */
  double *q;               /* positions X + x of the displacement dofs */
  uint64_t x_version;      /* bumped whenever x changes: terms refresh their views lazily */
  double *set_x;           /* the point of the last update_active_set */
  int set_valid;

  /* assembly: F_local, rhs_local over the local unknowns; b, y over the owned rows of the linear system */
  double *F_local, *rhs_local, *b, *y, *dx_local, *Jdx, *owned_work, *q_work;
  sk_system_sink sink;

  /* sparsity: the rows this rank writes (local unknowns), CSR with the linear system's global column indices */
  int64_t *declared;       /* (local row, global column) pairs declared by this rank this attempt, as row * n_cols + col */
  int64_t n_declared, cap_declared;
  int64_t *declared_recent; /* DECLARED_RECENT slots: keys declared this attempt, by hash (repeats are skipped) */
  int64_t *extra_keys;     /* sorted keys beyond the bulk graph in the current pattern (this rank's declarations) */
  int64_t n_extra_keys;
  int64_t key_columns;     /* the column count the keys are encoded with (n_kept of the numbering they belong to) */
  int64_t *row_ptr;        /* n + 1: the local rows' entries (empty rows for unknowns this rank does not write) */
  int *cols;
  unsigned char *row_local; /* n: rows this rank may write matrix entries into */
  int64_t pattern_n;       /* n_kept of the current pattern, -1 before the first */
  int *bulk_ptr, *bulk_cols; /* per local node: the local nodes its owned elements couple it with (sorted) */
  int *pattern_dof_solver;  /* n_dofs: solver_of and role of the dofs when the current pattern was built (a new one */
  unsigned char *pattern_dof_role; /* keeps the bulk entries of its dof rows while these hold) */
  int64_t *elem_pos_offset;/* per element: its entries' positions in elem_pos (own elements only) */
  int64_t *elem_pos;
  sk_linear_system *linsys;
  double *values;          /* this rank's contributions over its local rows */

  /* condensation on the assembled operator (stickslip.condense): pairs of the attempt */
  int64_t n_pairs, cap_pairs;
  int64_t *pair_z, *pair_row; /* multiplier unknown and paired row (full numbering), grouped by pair_block */
  int *pair_block;            /* group size of each pair's group (the same for its members) */
  sk_condenser *condenser;    /* NULL until pairs appear */
  int condensing;             /* this attempt solves through the condenser */

  /* bookkeeping */
  sk_newton_report newton;  /* the last solve of a step (iterations summed over active-set loops) */
  int linear_solves;
  int linear_factorisations; /* numeric LU factorisations of the system matrix (sk_linear_report.factorisations) */
  int64_t krylov_iterations; /* Krylov iterations of all linear solves */
  unsigned step_solvers;    /* bit k: the linear solver of kind k produced a solution in this attempt (auto resolved) */
  int active_set_loops;
  double t_assembly, t_contact, t_solve;
  /* t_contact as this thread's CPU seconds (CLOCK_THREAD_CPUTIME_ID): a rank descheduled on a shared or
   * oversubscribed machine does not accrue it, a rank busy-polling in a collective inside a contact call does */
  double t_contact_cpu;
  double contact_phase[SK_CONTACT_PHASES][2]; /* t_contact and t_contact_cpu by phase: wall, CPU */
  /* wall and CPU seconds this rank spent in collectives and exchanges inside the contact calls (a plugin's reduce,
   * the commit's status checks, the broad phase's boxes): waiting for the slowest rank, not contact work, so
   * t_contact and t_contact_cpu leave them out (with busy polling a wait costs CPU time as well) */
  double contact_wait[2];
  double t_broad_phase;       /* the host's broad phase over pairs (broad_phase.c), part of t_contact */
  struct sk_broad_phase *broad; /* its boxes and sweep (broad_phase.c), NULL without created pairs */
  sk_term **live;             /* with a broad phase: the terms an attempt visits (sk_system_live_terms) */
  int n_live;
  int64_t pair_attempts, far_pair_attempts; /* pairs' step attempts, and those the broad phase kept idle */
  int64_t broad_phase_sweeps;  /* the broad phase's passes (at each attempt's start, and at converged points while a
                                  created pair sleeps) */
  int64_t unknowns_max, linear_size_max;
  int pattern_builds; /* sparsity patterns handed to the solver (each rebuilds its matrix): built or grown */
  /* settling the pattern at an attempt's start (sk_system_settle_pattern), as [wall, CPU] seconds: all of it (the
   * terms' declarations and the check included), the builds (keys sorted and widened, rows, positions, the bridge),
   * and the bridge's part of the builds (sk_linsys_set_pattern); the keys sorted by the builds (declared ones and the
   * pattern's keys after widening) */
  double t_pattern[2], t_pattern_build[2], t_pattern_bridge[2];
  int64_t pattern_keys_declared, pattern_keys_kept;
  int master_reghosts; /* steps at which the master faces were ghosted again (master_ghosts.c) */
  /* the contact partition rebalanced between steps (contact_partition.h): set after a step whose contact work is
   * uneven (core/time/contact_balance.c), done at the next step's predictor */
  int contact_rebalance_pending;
  double contact_step_cpu;     /* this rank's contact CPU seconds in the last recorded step (the rebalance's weights) */
  int contact_rebalances;      /* rebalances done */
  int verbose;
  double newton_energy;     /* |dx . F| of the last Newton direction (FEAP's energy norm), printed with --verbose */
  int linear_fallback; /* 1 once a failed Krylov solver was replaced by the direct one (linear_solve) */
  int forget_setup;    /* test switch STICKSLIP_NO_SKIP=symbolic-setup: every solve sets up as on a new pattern */
  /* the largest residual entry of the attempt's last evaluation (-1: none yet), for the message of a failed step */
  int64_t worst_row;       /* ABI index of the largest residual, on the rank holding it (worst_rank); else -1 */
  int worst_rank;
  double worst_residual;
  /* a plugin, internal or memory error inside Newton ends the run (NOX reports every failure as divergence) */
  sk_status fatal;
  char fatal_message[1024];
};

sk_status sk_system_create(sk_model *model, const sk_solver_settings *solver, sk_system **sys);
/* Adds a term before the Dirichlet term (which stays last); the system owns it (tests add mock terms). */
sk_status sk_system_add_term(sk_system *sys, sk_term *term);
void sk_system_destroy(sk_system *sys);

/* The stages of a step attempt from t_n = sys->t_n: predictor, begin_step, layout, pattern. */
sk_status sk_system_begin(sk_system *sys, double dt, int64_t step);
/* Newton (NOX) until every term accepts the converged point (converged()); SK_ERR_DIVERGED to cut the step. */
sk_status sk_system_solve(sk_system *sys);
/* The attempt converged: velocities, the terms' commits. The state still spans the step. */
sk_status sk_system_commit(sk_system *sys);
/* The attempt failed: the terms roll back. */
void sk_system_reject(sk_system *sys);
/* After output: the committed state becomes the start of the next step. */
void sk_system_advance(sk_system *sys);

/* 1 when some term declared `need` (or the test switch forces it); system_needs.c. */
int sk_system_needs(const sk_system *sys, sk_need need);
/* After the terms are created: builds what they declared (the mass) and nothing else. */
sk_status sk_system_settle_needs(sk_system *sys);
/* Prints every term's declared needs and what the scene computes or skips, with the reasons (--explain). */
void sk_system_explain(const sk_system *sys, FILE *out);

/* Internal to system*.c: the layout of the unknowns (system_layout.c). */
sk_status sk_system_layout_dofs(sk_system *sys);
/* Plans an exchange over the dofs of this rank's ghost nodes (node_role), or with every_node of every node it holds
 * but does not own: the master nodes outside the faces it holds now too (master_ghosts.c) (collective). */
sk_status sk_system_plan_ghost_dofs(sk_system *sys, sk_exchange *x, int every_node);
sk_status sk_system_ensure_capacity(sk_system *sys, int64_t n);
sk_status sk_system_layout_unknowns(sk_system *sys, int again, int *changed);
/* A vector over the local unknowns to the linear system's owned rows (the owned dofs, and on the last rank the
 * constraint rows gathered from their owners), and back (collective). */
sk_status sk_system_to_rows(sk_system *sys, const double *local, double *rows);
sk_status sk_system_from_rows(sk_system *sys, const double *rows, double *local);
/* Declares couplings for the attempt (from a term's pattern stage); indices in the ABI numbering. */
sk_status sk_system_declare(sk_system *sys, int nr, const int64_t *rows, int nc, const int64_t *cols);
/* The same with local unknowns (core terms). */
sk_status sk_system_declare_local(sk_system *sys, int nr, const int64_t *rows, int nc, const int64_t *cols);
/* A status agreed by all ranks: the worst, with a message on every rank. */
sk_status sk_system_collective(const sk_system *sys, sk_status local);
/* The terms a step attempt visits, in the terms' order: every term but the created pairs the broad phase keeps
 * apart (broad_phase.c), which cost nothing per step; all terms without a broad phase. */
static inline sk_term *const *sk_system_live_terms(const sk_system *sys, int *n) {
  *n = sys->live ? sys->n_live : sys->n_terms;
  return sys->live ? sys->live : sys->terms;
}
/* Internal to system*.c: the plugins' sink; the attempt's pattern from the terms' declarations (system_pattern.c). */
void sk_system_sink_init(sk_system *sys);
sk_status sk_system_settle_pattern(sk_system *sys, int layout_changed);
/* The pattern keys *keys (row * n + col, local unknowns) widened by `rings` rings of neighbouring contact-surface
 * nodes (solver.pattern_margin), sorted and unique; *keys is replaced (left as it is when out of memory: widening
 * only saves work) (system_widening.c). */
void sk_system_widen_keys(const sk_system *sys, int rings, int64_t **keys, int64_t *n_keys);
/* The error of a failed allocation of `count` entries for `what` (SK_ERR_NOMEM). */
sk_status sk_system_out_of_memory(const char *what, int64_t count);
/* qsort/bsearch order of int64_t; sorts keys[*n] and drops repeats (sort_keys.c). */
int sk_compare_i64(const void *a, const void *b);
void sk_sort_unique_i64(int64_t *keys, int64_t *n);
/* Sorts keys in place, ascending, without allocating (sort_keys.c). */
void sk_sort_i64(int64_t *keys, int64_t n);
/* Position of (row, col) (local unknowns) in this rank's contributions (sys->values), or -1. */
int64_t sk_system_position(const sk_system *sys, int64_t row, int64_t col);
/* The local index of an unknown in the plugins' (ABI) numbering, or -1 when this rank does not hold it. */
int64_t sk_system_local_of(const sk_system *sys, int64_t abi);
/* The ABI index of a local unknown. */
int64_t sk_system_abi_of(const sk_system *sys, int64_t local);
/* A term's block of extra unknowns as the plugins read it (sk_state.extra: n_extra values by j): the held ones
 * copied from x, the others the layout's starting values (no allocation: sized at layout). */
double *sk_system_extra_block(const sk_system *sys, sk_term *term);
/* A vector over the local unknowns to a term's block (n_extra values by j, 0 at the extras this rank does not hold),
 * and the held entries of such a block back into the vector. */
void sk_system_extras_to_block(const sk_term *term, const double *local, double *block);
void sk_system_extras_from_block(const sk_term *term, const double *block, double *local);
/* Copies the owners' values of the local dofs into their ghosts (collective). */
void sk_system_update_ghost_dofs(sk_system *sys, double *dofs);
/* Sets up a plugin term's view of a surface or body (term_plugin.c) — see views.h. */

/* Pairs of stickslip.condense for the attempt (from a term's layout): n_groups groups of `block`. */
sk_status sk_system_condense_pairs(sk_system *sys, int64_t n_groups, int block, const int64_t *z, const int64_t *rows);
/* Solves J y = b again with the operator of the last solve (stickslip.linear); b, y over the local unknowns, b
 * summed into the owners (each rank gives its part), y on owned and ghost unknowns. */
sk_status sk_system_solve_again(sk_system *sys, const double *b, double *y);

/* Sum of this rank's contact reports of the plugin terms (initial: the initial row): force, counts, dissipation,
 * and per obstacle pair the reaction on the obstacle (collective). */
typedef struct {
  double force[3], moment[3];
  double active, stick, slip;
  double active_local;     /* this rank's active points (not summed) */
  double dissipated;       /* this step's increment */
  double constraint;       /* max over ranks */
  /* the deepest penetration of a penalty pair (sk_term_plugin_penalty_pair) against its slave surface's mean edge:
   * penetration / h, the same on every rank, and the index in sys->terms of that pair's term (-1: none) */
  double penetration_ratio;
  int penetration_term;
  int n_obstacles;
  double *obstacle_force;  /* 3 per obstacle pair (caller's array) */
} sk_contact_totals;
sk_status sk_system_contact_totals(sk_system *sys, int initial, sk_contact_totals *totals);
/* The bodies whose plugin integrator reports the energy its scheme conserves (ABI 2.5): the sum of those energies
 * (scheme[0] kinetic, scheme[1] strain) and the host's own for the same bodies at (u, v) (host[0], host[1]: from the
 * world state and the body's material), both summed over ranks; zeros when no body reports (collective). */
sk_status sk_system_scheme_energy(sk_system *sys, const double *u, const double *v, int initial, double scheme[2],
                                  double host[2]);
/* Calls every plugin term's points() (initial: the initial state); the pair index is passed along. */
sk_status sk_system_points(sk_system *sys, int initial, void (*callback)(void *ctx, int pair, const sk_contact_point *),
                           void *ctx);
/* Where the last residual of the attempt was largest ("node 12 (y) of body 'block': |F| = 3.1e+02", or an extra
 * unknown of a term), for the message of a step that cannot be solved; "" before any residual. */
void sk_system_describe_worst(const sk_system *sys, char *text, size_t size);
/* The support reactions of every Dirichlet condition, 3 per condition (summed over ranks), from the last residual
 * (collective). */
void sk_system_reactions(const sk_system *sys, double *sums);
/* The work the prescribed loads (body force, tractions, resultants) did over the step from u_n to x, with each load
 * taken where the body's integrator balances forces (the time force_time, and for a current-area resultant the
 * configuration): the discrete external work of the scheme, so that an energy-consistent scheme keeps
 * E_{n+1} - E_n = W on a step without contact, friction or supports doing work. Not counted: supports, moving
 * obstacles, contact. scratch: room for the local dofs (model nodes times dim). Collective. */
sk_status sk_system_load_work(sk_system *sys, double *scratch, double *work);

/* Wall-clock seconds (monotonic) for the phases' timings. */
double sk_system_seconds(void);
/* Both clocks now (no waits); the same with the rank's contact waits so far, to start a contact phase; the contact
 * work since such a t0, its waits left out, charged to a phase (t_contact, t_contact_cpu, contact_phase); and a wait
 * inside a contact call since t0 (sk_system_clock) charged to contact_wait. */
sk_clock sk_system_clock(void);
sk_clock sk_system_contact_clock(const sk_system *sys);
void sk_system_charge_contact(sk_system *sys, int phase, sk_clock t0);
void sk_system_charge_wait(sk_system *sys, sk_clock t0);

#endif
