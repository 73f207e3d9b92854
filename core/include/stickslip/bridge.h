/* stickslip — the Trilinos bridge: the only C++ in the tree lives behind this C header.
 *
 * Parallel model (docs/design.md). Each rank owns a contiguous block of the rows: its nodal rows (the unknowns of
 * the mesh nodes it owns, as many as it says) and, on the last rank, the constraint rows (a plugin's multipliers)
 * after every nodal row. Vectors cross this header as the owned rows' parts; nobody holds a whole vector or the
 * whole pattern. A matrix is assembled by every rank writing its contributions into a values array over the rows it
 * writes (its local rows, owned or not); sk_linsys_assemble sums them into the owned rows (the non-owned rows' values
 * go to their owners point to point, planned once per pattern; values replaced in place in the static-graph
 * matrix). Newton (NOX) runs on distributed vectors: norms and inner products are reduced over ranks. */
#ifndef STICKSLIP_BRIDGE_H
#define STICKSLIP_BRIDGE_H

#include <mpi.h>
#include <stdint.h>

#include "stickslip/error.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- linear systems ----------------------------------------------------------------------------------------- */
typedef enum {
  SK_LINEAR_DIRECT = 0,   /* the fastest direct backend measured on these systems (docs/linear-solvers.md): MUMPS */
  SK_LINEAR_GMRES_MUELU,  /* Belos GMRES preconditioned by MueLu smoothed-aggregation AMG on the nodal block, the
                             constraint rows (if any) through their Schur complement (docs/linear-solvers.md) */
  SK_LINEAR_GMRES_ILU,    /* the same with Ifpack2 ILU(k) in place of AMG */
  SK_LINEAR_AUTO,         /* the default: MUMPS, the lagged LU, GMRES + MueLu, + SGS or + Jacobi from measurements
                             (docs/linear-solvers.md) */
  SK_LINEAR_DIRECT_MUMPS, /* MUMPS (dmumps_c): multifrontal LU, factorised in parallel on the distributed matrix */
  SK_LINEAR_DIRECT_KLU2,  /* Amesos2 KLU2; on more than one rank the matrix is gathered and factorised on rank 0
                             (Debian's Trilinos 13.2 KLU2 gives wrong answers on distributed matrices) */
  SK_LINEAR_DIRECT_KLU,   /* Amesos (v1, Epetra) KLU (gathers to rank 0 itself) */
  SK_LINEAR_GMRES_SGS,    /* the same with one symmetric Gauss-Seidel sweep in place of AMG: no set-up, cheap per
                             iteration; its iterations grow under refinement unless inertia dominates */
  SK_LINEAR_GMRES_JACOBI, /* the same with point Jacobi (diagonal scaling): the cheapest per iteration, for systems
                             whose mass term dominates (explicit-like time steps) */
  SK_LINEAR_GMRES_LU      /* lagged LU: Belos GMRES on the whole system, preconditioned by the last MUMPS factorisation
                             (of an earlier Newton iteration or step), refactorised when GMRES needs more than a few
                             iterations, fails, or the pattern changes (docs/linear-solvers.md, "Lagged LU") */
} sk_linear_solver_kind;
#define SK_LINEAR_KIND_LAST SK_LINEAR_GMRES_LU /* the largest valid sk_linear_solver_kind */

/* MueLu's near-nullspace of the nodal block when coordinates are given (sk_linsys_set_coordinates). */
typedef enum {
  SK_NULLSPACE_RIGID_BODY = 0, /* translations and rotations: 3 modes in 2D, 6 in 3D (default) */
  SK_NULLSPACE_TRANSLATIONS    /* the translations only (dim modes), as without coordinates */
} sk_linear_nullspace;

typedef struct {
  sk_linear_solver_kind kind;
  sk_linear_nullspace nullspace; /* for gmres-muelu (default rigid body) */
  double tolerance;        /* Krylov relative residual tolerance (default 1e-10) */
  int max_iterations;      /* Krylov iterations (default 500) */
  int verbose;             /* print solver details on rank 0 */
  /* Where `auto` says what it chose and why (one line per decision, rank 0 only). NULL: stderr on rank 0. */
  void (*log)(void *log_ctx, const char *line);
  void *log_ctx;
} sk_linear_options;

/* Why a solve failed (sk_linsys_solve returned SK_ERR_LINEAR_SOLVER), and what its caller does about it:
 *   NOT_CONVERGED  a Krylov solver missed the tolerance within max_iterations: the system may still be fine for a
 *                  direct solver — switch to it (sk_linsys_set_solver) and solve again; `auto` does so itself.
 *   SINGULAR       a direct solver found the matrix (numerically) singular, or an iterative solver's setup did
 *                  (a singular block of its preconditioner): no other solver helps — the Jacobian at this iterate
 *                  is singular (a body without supports in a quasi-static run, a degenerate contact element).
 *   INPUT          the system's description does not fit the solver (coordinates against the unknowns): fix it. */
typedef enum {
  SK_LINEAR_FAILURE_NONE = 0,
  SK_LINEAR_FAILURE_NOT_CONVERGED,
  SK_LINEAR_FAILURE_SINGULAR,
  SK_LINEAR_FAILURE_INPUT
} sk_linear_failure;

typedef struct {
  sk_linear_solver_kind solver;  /* the backend that produced x (mumps, gmres-muelu, ...; never direct or auto) */
  sk_linear_failure failure;     /* why it failed (NONE on success) */
  int iterations;                /* Krylov iterations (0 for direct; with `auto`, those of every attempt of the solve) */
  double relative_residual;      /* ||b - A x|| / ||b|| measured after the solve */
  double seconds;                /* wall time of the solve (factorisation / preconditioner set-up included) */
  int refactored_symbolic;       /* 1 when a symbolic factorisation / preconditioner set-up had to be redone */
  const char *decision;          /* `auto` decided in this solve: what and why (valid until the next solve); or NULL */
  int solved;                    /* 1 when a solver ran (0: b = 0 gave x = 0 without one) */
  int refinements;               /* iterative-refinement corrections a direct solve needed (0: at round-off at once) */
  int factorisations;            /* numeric LU factorisations of the system matrix in this solve (MUMPS, KLU, KLU2,
                                    gmres-lu's refactorisations; not preconditioner set-ups) */
} sk_linear_report;

typedef struct sk_linear_system sk_linear_system;

void sk_linear_options_default(sk_linear_options *options);
/* direct | gmres-muelu | gmres-ilu | gmres-sgs | gmres-jacobi | gmres-lu | auto | mumps | klu2 | klu */
sk_status sk_linear_solver_from_name(const char *name, sk_linear_solver_kind *kind);
const char *sk_linear_solver_name(sk_linear_solver_kind kind);

sk_status sk_linsys_create(MPI_Comm comm, const sk_linear_options *options, sk_linear_system **sys);
void sk_linsys_destroy(sk_linear_system *sys);
/* Switches the solver (collective; e.g. to `direct` after an iterative solver failed, see sk_linear_failure). */
sk_status sk_linsys_set_solver(sk_linear_system *sys, sk_linear_solver_kind kind);
/* The Krylov relative residual tolerance of the next solves (an inexact Newton's forcing term); direct solvers
 * ignore it. */
sk_status sk_linsys_set_tolerance(sk_linear_system *sys, double tolerance);
/* The time steps left in the run, the one beginning included; called as each step (attempt) begins. `auto` projects
 * the solves left from it and the solves per step so far, and explores other solvers only while their trials can pay
 * for themselves in that projection (docs/linear-solvers.md); never called: trials are not budgeted. */
void sk_linsys_set_steps_left(sk_linear_system *sys, int steps_left);
/* Unknowns per mesh node for systems without coordinates (default 1): MueLu aggregates whole nodes and rows are
 * distributed in whole nodes. Call before sk_linsys_set_pattern. */
sk_status sk_linsys_set_block_size(sk_linear_system *sys, int block_size);
/* The nodal block: this rank's nodal rows are the displacements of the n_nodes mesh nodes it owns, node-major
 * (row = first + dim * node + component, in the order of the coordinates given here); the constraint rows after all
 * nodal ones (a plugin's multipliers) are constraint unknowns. The iterative solvers then run AMG / ILU on the nodal
 * block only — MueLu with whole-node aggregates and the rigid-body modes (3 in 2D, 6 in 3D) as nullspace — and solve
 * the constraint rows through their Schur complement. Without coordinates the whole system is one block (block size
 * from sk_linsys_set_block_size, translations as nullspace). Copied; collective; call before sk_linsys_set_pattern. */
sk_status sk_linsys_set_coordinates(sk_linear_system *sys, int n_nodes, int dim, const double *coordinates);

/* Sets (or replaces) the layout and the sparsity pattern (collective). Layout: this rank owns n_nodal_owned nodal
 * rows, the block after the lower ranks' ones; the n_constraints constraint rows (the same number on every rank)
 * follow all nodal rows and belong to the last rank. Pattern: the n_rows rows this rank writes (global indices
 * `rows`, unique, owned or not), CSR row_ptr[n_rows + 1] with global columns cols[row_ptr[n_rows]] sorted within
 * rows; each owned row of the matrix is the union of every rank's entries of that row. Building a pattern is the
 * expensive part; callers keep it while the structure does not change. */
sk_status sk_linsys_set_pattern(sk_linear_system *sys, int n_nodal_owned, int n_constraints, int n_rows,
                                const int *rows, const int64_t *row_ptr, const int *cols);
/* The rows this rank owns: [*first, *first + return value) of the global numbering. */
int sk_linsys_owned_rows(const sk_linear_system *sys, int *first);
/* This rank's contribution array, aligned with the local pattern's `cols` (length row_ptr[n_rows]). */
double *sk_linsys_values(sk_linear_system *sys);
/* Zeroes this rank's contribution array. */
void sk_linsys_zero(sk_linear_system *sys);
/* Sums all ranks' contributions into the distributed matrix (collective). */
sk_status sk_linsys_assemble(sk_linear_system *sys);
/* Sums a vector given over this rank's local rows (n_rows values, in the order of `rows`) into the owned rows
 * (collective; the same plan as the matrix). */
sk_status sk_linsys_sum_rows(sk_linear_system *sys, const double *local, double *owned);
/* Bytes this rank sent by sk_linsys_assemble and sk_linsys_sum_rows so far (the scaling bench). */
int64_t sk_linsys_bytes_sent(const sk_linear_system *sys);
/* Solves A x = b (collective). b and x are the owned rows' parts. Keeps the symbolic factorisation while the pattern
 * is unchanged, and the AMG hierarchy of the nodal block as long as it keeps GMRES fast (also across pattern
 * changes). SK_ERR_LINEAR_SOLVER if the solve fails, with report->failure saying how. */
sk_status sk_linsys_solve(sk_linear_system *sys, const double *b, double *x, sk_linear_report *report);
/* Drops what a solve keeps while the pattern holds (symbolic factorisation, the solver's matrix copy, preconditioner
 * hierarchy), so that the next solve sets it up as on a new pattern: the test switch
 * STICKSLIP_NO_SKIP=symbolic-setup (docs/performance.md). */
void sk_linsys_forget_setup(sk_linear_system *sys);
/* y = A x with the assembled matrix (owned parts), for tests and residual checks. */
sk_status sk_linsys_apply(sk_linear_system *sys, const double *x, double *y);

/* ---- Newton through NOX --------------------------------------------------------------------------------------
 * The driver owns the nonlinear problem; NOX owns the iteration (status tests, line search). The bridge wraps the
 * callbacks below in a NOX::Abstract::Group, so condensation strategies live in `solve`, inside the group's
 * linear solve, and NOX always sees one fixed vector space of n unknowns. */
typedef struct {
  void *ctx;
  /* F(x) (vectors are this rank's owned part of the unknowns); non-SK_OK (e.g. SK_ERR_INVERTED) makes NOX treat the
   * trial point as failed. Collective. */
  sk_status (*residual)(void *ctx, const double *x, double *F);
  /* Prepare the Jacobian at x (assemble into the driver's linear system). */
  sk_status (*jacobian)(void *ctx, const double *x);
  /* Newton direction: solve J dx = -F at x (with the driver's condensation strategy). */
  sk_status (*solve)(void *ctx, const double *x, const double *F, double *dx);
  /* After each Newton iteration (iterate x accepted by the line search): bookkeeping such as active-set updates. */
  sk_status (*after_iteration)(void *ctx, int iteration, const double *x, double residual_norm);
  /* Optional (NULL: `solve` is used): the Newton direction to a relative linear residual ||J dx + F|| <= tolerance
   * ||F||, the forcing term of an inexact Newton method (sk_newton_options.forcing); a direct solver may ignore it. */
  sk_status (*solve_to_tolerance)(void *ctx, const double *x, const double *F, double tolerance, double *dx);
} sk_newton_callbacks;

typedef enum { SK_LINE_SEARCH_FULL_STEP = 0, SK_LINE_SEARCH_BACKTRACK, SK_LINE_SEARCH_POLYNOMIAL } sk_line_search;

typedef struct {
  double residual_tolerance;  /* absolute ||F||_2 (default 1e-8) */
  double relative_tolerance;  /* ||F|| / ||F_0|| (default 1e-10): either test converges when the update test holds */
  /* ||dx||_2 <= update_tolerance * (1 + ||x||_2) (default 1e-8), applied to the step just taken, or with
   * predicted_update to the smaller of it and the next Newton update predicted from it (||dx_k|| ||F_k|| /
   * ||F_{k-1}||), so that a converged iterate needs no extra solve to prove it (newton.cpp) */
  double update_tolerance;
  int max_iterations;         /* default 25 */
  sk_line_search line_search; /* default full step */
  /* Inexact Newton (used with callbacks.solve_to_tolerance): each linear solve only as accurate as the Newton step
   * can use, from the Eisenstat-Walker forcing term (newton.cpp); never below linear_tolerance (default 1e-10).
   * Default on. */
  int forcing;
  double linear_tolerance;
  int verbose;                /* NOX output on rank 0 */
  /* 1: the update test accepts the predicted next update (one solve less per step). Default 0 here: iterates stop
   * where they are up to the tolerances, and the validation tests with tight energy balances (corot, two-elements
   * none vs reduced: 2.9e-10 against 1e-10) were measured with the confirming solve; the scene reader's default is 0
   * too (solver.newton.predicted_update, docs/hertz.md). */
  int predicted_update;
  /* The size of the quantities the unknowns are measured from (the norm of the reference coordinates of the
   * displacement unknowns; 0 for none): a Newton correction is at round-off when ||dx||_2 <= SK_NEWTON_ROUNDOFF_ULPS
   * machine epsilons times ||x||_2 + roundoff_scale (the positions' rounding reaches the residual, not only x's). */
  double roundoff_scale;
  /* 1: a full-step Newton that makes no progress (over 4 iterations neither ||F|| nor the Newton correction falls
   * below half its value before them: a cycle, newton.cpp's NoProgressTest) goes on from its current iterate with
   * the backtracking line search instead of running out max_iterations. Default 0 here; the scene reader sets it
   * with its default line search (full-step-then-backtrack), docs/stability.md. */
  int backtrack_on_no_progress;
} sk_newton_options;

enum { SK_NEWTON_ROUNDOFF_ULPS = 1000 };

enum { SK_NEWTON_HISTORY_MAX = 64 };

/* How a Newton solve ended, and what the caller (the time stepper) does about it:
 *   CONVERGED        accept the step.
 *   MAX_ITERATIONS,  no convergence within max_iterations, or the line search found no decrease: a shorter step
 *   LINE_SEARCH      may converge — cut the step (SK_ERR_DIVERGED).
 *   RESIDUAL_FAILED  F could not be evaluated along the way (an inverted element, a plugin's local failure) and no
 *                    admissible iterate was found: cut the step (SK_ERR_DIVERGED, or the callback's status).
 *   CALLBACK_FAILED  the Jacobian, the Newton direction (other than the linear solve itself) or after_iteration
 *                    failed: the callback's status decides (SK_ERR_DIVERGED: cut; anything else: stop).
 *   ROUNDOFF_FLOOR   accept the step, with a warning (returned SK_OK, converged = 1): two iterations in a row took
 *                    full Newton corrections at round-off (||dx|| at most SK_NEWTON_ROUNDOFF_ULPS machine epsilons
 *                    of ||x|| + roundoff_scale: x + dx equals x but for its last digits) without halving ||F||,
 *                    which stays above both tolerances: x is the solution as far as double precision resolves it,
 *                    and the tolerances lie below the residual's round-off floor. No iteration and no shorter
 *                    step can lower that floor.
 *   STAGNATED        ||F|| stopped decreasing while the full Newton corrections are below the update tolerance
 *                    (||dx|| <= update_tolerance (1 + ||x||)) but above round-off, above both tolerances. Ends the
 *                    attempt after four stalled iterations instead of max_iterations; the step is cut
 *                    (SK_ERR_DIVERGED, the message gives the numbers): measured, the floor of a shorter step often
 *                    lies below the tolerance (ks-parabolic step 15: ||F||/||F0|| = 4.4e-9 at dt = 1, converged
 *                    after one cut; large sliding with mortar-dual and covariant-penalty likewise).
 *   LINEAR_SOLVER    the linear solve failed (SK_ERR_LINEAR_SOLVER, the linear report's failure says how); a shorter
 *                    step does not change the solver's behaviour on the system: see sk_linear_failure. */
typedef enum {
  SK_NEWTON_CONVERGED = 0,
  SK_NEWTON_MAX_ITERATIONS,
  SK_NEWTON_LINE_SEARCH,
  SK_NEWTON_RESIDUAL_FAILED,
  SK_NEWTON_CALLBACK_FAILED,
  SK_NEWTON_STAGNATED,
  SK_NEWTON_LINEAR_SOLVER,
  SK_NEWTON_ROUNDOFF_FLOOR
} sk_newton_outcome;

typedef struct {
  int converged;
  sk_newton_outcome outcome;
  int iterations;
  int linear_solves;
  int switched_to_backtrack; /* the full step made no progress and the solve went on with backtracking */
  int n_history;
  double residual_history[SK_NEWTON_HISTORY_MAX]; /* ||F|| at the start and after each iteration */
  char reason[384]; /* why it failed, or why it was accepted at the round-off floor, with the numbers */
} sk_newton_report;

void sk_newton_options_default(sk_newton_options *options);
sk_status sk_line_search_from_name(const char *name, sk_line_search *ls); /* full-step|backtrack|polynomial */
/* Runs NOX from the initial guess x (this rank's n owned unknowns, overwritten by the solution, or by the last
 * accepted iterate on failure); norms and inner products are sums over ranks. Collective. On failure returns SK_ERR_LINEAR_SOLVER when the solve callback reported a
 * linear-solver failure, the callback's status when another callback failed with a status other than
 * SK_ERR_DIVERGED, SK_ERR_DIVERGED otherwise; report->outcome and report->reason say which case it was. */
sk_status sk_newton_solve(MPI_Comm comm, const sk_newton_options *options, const sk_newton_callbacks *callbacks,
                          int n, double *x, sk_newton_report *report);

#ifdef __cplusplus
}
#endif
#endif
