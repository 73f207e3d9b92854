/* stickslip — the Trilinos bridge: the only C++ in the tree lives behind this C header.
 *
 * Parallel model. Every rank holds the whole (replicated) vector of unknowns; element and contact work is split
 * over ranks (METIS); the sparse matrix is distributed (Tpetra, contiguous row blocks) and solved by Amesos2 or
 * Belos. Vectors cross this header replicated: identical on every rank, so norms and Newton decisions agree
 * without communication. A matrix is assembled by every rank writing its own contributions into a values array
 * laid over one replicated CSR pattern; sk_linsys_assemble sums them into the owned rows (one MPI_Alltoallv of the
 * written rows to their owners, planned once per pattern; values replaced in place in the static-graph matrix). */
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
  SK_LINEAR_GMRES_MUELU,  /* Belos GMRES preconditioned by MueLu smoothed-aggregation AMG */
  SK_LINEAR_GMRES_ILU,    /* Belos GMRES preconditioned by Ifpack2 ILU(k) */
  SK_LINEAR_AUTO,         /* the measured default: chosen from the size and kind of the system (docs/linear-solvers.md) */
  SK_LINEAR_DIRECT_MUMPS, /* Amesos (v1, Epetra) MUMPS: multifrontal LU, factorised in parallel on the distributed matrix */
  SK_LINEAR_DIRECT_KLU2,  /* Amesos2 KLU2; on more than one rank the matrix is gathered and factorised on rank 0
                             (Debian's Trilinos 13.2 KLU2 gives wrong answers on distributed matrices) */
  SK_LINEAR_DIRECT_KLU    /* Amesos (v1, Epetra) KLU (gathers to rank 0 itself) */
} sk_linear_solver_kind;

typedef struct {
  sk_linear_solver_kind kind;
  double tolerance;        /* Krylov relative residual tolerance (default 1e-10) */
  int max_iterations;      /* Krylov iterations (default 500) */
  int verbose;             /* print solver details on rank 0 */
} sk_linear_options;

typedef struct {
  int iterations;          /* Krylov iterations (0 for direct) */
  double relative_residual;/* ||b - A x|| / ||b|| measured after the solve */
  double seconds;          /* wall time of the solve (factorisation included) */
  int refactored_symbolic; /* 1 when a symbolic factorisation / preconditioner setup had to be redone */
  int solved;              /* 1 when a solver ran (0: b = 0, x = 0 without one) */
  sk_linear_solver_kind backend; /* with solved: the solver that produced x (auto resolved, after any fallback) */
} sk_linear_report;

typedef struct sk_linear_system sk_linear_system;

void sk_linear_options_default(sk_linear_options *options);
sk_status sk_linear_solver_from_name(const char *name, sk_linear_solver_kind *kind); /* direct|gmres-muelu|gmres-ilu|auto|mumps|klu2|klu */
const char *sk_linear_solver_name(sk_linear_solver_kind kind);

sk_status sk_linsys_create(MPI_Comm comm, const sk_linear_options *options, sk_linear_system **sys);
void sk_linsys_destroy(sk_linear_system *sys);
/* Unknowns per mesh node (default 1; the spatial dimension for elasticity): MueLu aggregates whole nodes and
 * builds a block nullspace, and rows are distributed in whole nodes. Call before sk_linsys_set_pattern. */
sk_status sk_linsys_set_block_size(sk_linear_system *sys, int block_size);
/* Optional, for elasticity with GMRES_MUELU: the (replicated) coordinates of the n_nodes mesh nodes, dim per node,
 * whose unknowns are numbered node-major (unknown = dim * node + component) with block size dim (2 or 3). MueLu then
 * uses the rigid-body modes (3 in 2D, 6 in 3D) as its nullspace instead of translations only. Copied. */
sk_status sk_linsys_set_coordinates(sk_linear_system *sys, int n_nodes, int dim, const double *coordinates);

/* Sets (or replaces) the sparsity pattern: n unknowns, CSR row_ptr[n+1], cols[row_ptr[n]] sorted within rows,
 * identical on all ranks. `local_rows` (sorted, n_local_rows entries) lists the rows this rank writes into.
 * Building a pattern is the expensive part; callers keep it while the structure does not change. */
sk_status sk_linsys_set_pattern(sk_linear_system *sys, int n, const int64_t *row_ptr, const int *cols,
                                int n_local_rows, const int *local_rows);
/* This rank's contribution array, aligned with `cols` (length row_ptr[n]); only local rows are read. */
double *sk_linsys_values(sk_linear_system *sys);
/* Zeroes this rank's contribution array. */
void sk_linsys_zero(sk_linear_system *sys);
/* Sums all ranks' contributions into the distributed matrix (collective). */
sk_status sk_linsys_assemble(sk_linear_system *sys);
/* Solves A x = b (collective). b and x are replicated, length n. Re-uses the symbolic factorisation or the
 * preconditioner hierarchy's structure while the pattern is unchanged. SK_ERR_DIVERGED if the solve fails. */
sk_status sk_linsys_solve(sk_linear_system *sys, const double *b, double *x, sk_linear_report *report);
/* y = A x with the assembled matrix (replicated vectors), for tests and residual checks. */
sk_status sk_linsys_apply(sk_linear_system *sys, const double *x, double *y);

/* ---- Newton through NOX --------------------------------------------------------------------------------------
 * The driver owns the nonlinear problem; NOX owns the iteration (status tests, line search). The bridge wraps the
 * callbacks below in a NOX::Abstract::Group, so condensation strategies live in `solve`, inside the group's
 * linear solve, and NOX always sees one fixed vector space of n unknowns. */
typedef struct {
  void *ctx;
  /* F(x), replicated; non-SK_OK (e.g. SK_ERR_INVERTED) makes NOX treat the trial point as failed. */
  sk_status (*residual)(void *ctx, const double *x, double *F);
  /* Prepare the Jacobian at x (assemble into the driver's linear system). */
  sk_status (*jacobian)(void *ctx, const double *x);
  /* Newton direction: solve J dx = -F at x (with the driver's condensation strategy). */
  sk_status (*solve)(void *ctx, const double *x, const double *F, double *dx);
  /* After each Newton iteration (iterate x accepted by the line search): bookkeeping such as active-set updates. */
  sk_status (*after_iteration)(void *ctx, int iteration, const double *x, double residual_norm);
} sk_newton_callbacks;

typedef enum { SK_LINE_SEARCH_FULL_STEP = 0, SK_LINE_SEARCH_BACKTRACK, SK_LINE_SEARCH_POLYNOMIAL } sk_line_search;

typedef struct {
  double residual_tolerance;  /* absolute ||F||_2 (default 1e-8) */
  double relative_tolerance;  /* ||F|| / ||F_0|| (default 1e-10): either test converges when the update test holds */
  double update_tolerance;    /* ||dx||_2 <= update_tolerance * (1 + ||x||_2)... weighted RMS as NOX NormUpdate (1e-8) */
  int max_iterations;         /* default 25 */
  sk_line_search line_search; /* default full step */
  int verbose;                /* NOX output on rank 0 */
} sk_newton_options;

enum { SK_NEWTON_HISTORY_MAX = 64 };

typedef struct {
  int converged;
  int iterations;
  int linear_solves;
  int n_history;
  double residual_history[SK_NEWTON_HISTORY_MAX]; /* ||F|| at the start and after each iteration */
  char reason[128];                               /* NOX's status on failure */
} sk_newton_report;

void sk_newton_options_default(sk_newton_options *options);
sk_status sk_line_search_from_name(const char *name, sk_line_search *ls); /* full-step|backtrack|polynomial */
/* Runs NOX from the replicated initial guess x (length n, overwritten by the solution). Collective.
 * Returns SK_ERR_DIVERGED (with the reason in report and the error message) if NOX does not converge. */
sk_status sk_newton_solve(MPI_Comm comm, const sk_newton_options *options, const sk_newton_callbacks *callbacks,
                          int n, double *x, sk_newton_report *report);

#ifdef __cplusplus
}
#endif
#endif
