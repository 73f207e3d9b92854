/* sk_newton_solve: quadratic convergence on a coupled cubic system (Jacobian solved through the bridge's own
 * linear system), callbacks that fail, and the iteration limit.
 *
 * F_i(x) = x_i^3 + a (x_i - x_{i+1}) - c_i, with c chosen so that x* (known) is the root. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "sk_test.h"
#include "stickslip/bridge.h"

enum { N = 12 };
static const double coupling = 0.5;

typedef struct {
  double c[N];
  double x_star[N];
  sk_linear_system *sys;
  int64_t row_ptr[N + 1];
  int cols[2 * N];
  double fail_above;      /* the residual "inverts" when some x_i exceeds this */
  int fail_jacobian;      /* the Jacobian callback fails */
  int after_calls;
  int after_last_iteration;
  int after_in_order;
  int after_fail_at;      /* after_iteration fails at this iteration (0: never) */
  double floor;           /* amplitude of a round-off-like floor added to F (0: none) */
  int n_tolerances;       /* forcing terms asked for through solve_to_tolerance */
  double tolerances[32], norms[32];
  int singular_jacobian;  /* the Jacobian's last row is zero */
  sk_linear_report last_solve;
} problem;

/* A deterministic stand-in for round-off: a value in [-1, 1] that jumps with the last bits of x. */
static double noise(double x) {
  uint64_t bits;
  memcpy(&bits, &x, sizeof bits);
  bits = (bits ^ (bits >> 29)) * 0xbf58476d1ce4e5b9ULL;
  bits ^= bits >> 32;
  return (double)(bits % 2001) / 1000.0 - 1.0;
}

static sk_status residual(void *ctx, const double *x, double *F) {
  problem *p = ctx;
  for (int i = 0; i < N; ++i) {
    if (x[i] > p->fail_above) return sk_error_set(SK_ERR_INVERTED, "element %d inverted (x = %g)", i, x[i]);
    const double next = i + 1 < N ? x[i + 1] : 0.0;
    F[i] = x[i] * x[i] * x[i] + coupling * (x[i] - next) - p->c[i] + p->floor * noise(x[i]);
  }
  return SK_OK;
}

static sk_status jacobian(void *ctx, const double *x) {
  problem *p = ctx;
  if (p->fail_jacobian) return sk_error_set(SK_ERR_INTERNAL, "assembly exploded");
  sk_linsys_zero(p->sys);
  double *values = sk_linsys_values(p->sys);
  for (int i = 0; i < N; ++i) {
    values[p->row_ptr[i]] = 3.0 * x[i] * x[i] + coupling;
    if (i + 1 < N) values[p->row_ptr[i] + 1] = -coupling;
  }
  if (p->singular_jacobian) values[p->row_ptr[N - 1]] = 0.0;
  return sk_linsys_assemble(p->sys);
}

static sk_status solve(void *ctx, const double *x, const double *F, double *dx) {
  problem *p = ctx;
  double minus_f[N];
  for (int i = 0; i < N; ++i) minus_f[i] = -F[i];
  return sk_linsys_solve(p->sys, minus_f, dx, &p->last_solve);
}

/* Records the forcing term and solves exactly (what a direct solver does with it). */
static sk_status solve_to_tolerance(void *ctx, const double *x, const double *F, double tolerance, double *dx) {
  problem *p = ctx;
  if (p->n_tolerances < 32) {
    double norm = 0;
    for (int i = 0; i < N; ++i) norm += F[i] * F[i];
    p->norms[p->n_tolerances] = sqrt(norm);
    p->tolerances[p->n_tolerances++] = tolerance;
  }
  return solve(ctx, x, F, dx);
}

static sk_status after_iteration(void *ctx, int iteration, const double *x, double residual_norm) {
  problem *p = ctx;
  ++p->after_calls;
  if (iteration != p->after_last_iteration + 1 || !(residual_norm >= 0)) p->after_in_order = 0;
  p->after_last_iteration = iteration;
  if (iteration == p->after_fail_at) return sk_error_set(SK_ERR_INPUT, "active set cycling at iteration %d", iteration);
  return SK_OK;
}

static void problem_init(problem *p) {
  memset(p, 0, sizeof *p);
  for (int i = 0; i < N; ++i) p->x_star[i] = 1.0 + 0.1 * i;
  for (int i = 0; i < N; ++i) {
    const double next = i + 1 < N ? p->x_star[i + 1] : 0.0;
    p->c[i] = p->x_star[i] * p->x_star[i] * p->x_star[i] + coupling * (p->x_star[i] - next);
  }
  int k = 0;
  for (int i = 0; i < N; ++i) {
    p->row_ptr[i] = k;
    p->cols[k++] = i;
    if (i + 1 < N) p->cols[k++] = i + 1;
  }
  p->row_ptr[N] = k;
  p->fail_above = 1e300;
  p->after_in_order = 1;
  sk_linear_options options;
  sk_linear_options_default(&options);
  options.kind = SK_LINEAR_DIRECT;
  int rows[N];
  for (int i = 0; i < N; ++i) rows[i] = i;
  SK_CHECK(sk_linsys_create(MPI_COMM_WORLD, &options, &p->sys) == SK_OK);
  SK_CHECK(sk_linsys_set_pattern(p->sys, N, 0, N, rows, p->row_ptr, p->cols) == SK_OK);
}

static sk_newton_callbacks callbacks_for(problem *p) {
  sk_newton_callbacks cb = {
      .ctx = p, .residual = residual, .jacobian = jacobian, .solve = solve, .after_iteration = after_iteration};
  return cb;
}

static void check_quadratic_convergence(sk_line_search line_search) {
  problem p;
  problem_init(&p);
  sk_newton_options options;
  sk_newton_options_default(&options);
  options.line_search = line_search;
  options.predicted_update = 1; /* the update test without a confirming solve (checked below) */
  double x[N];
  for (int i = 0; i < N; ++i) x[i] = 2.0 * p.x_star[i];
  sk_newton_callbacks cb = callbacks_for(&p);
  sk_newton_report report;
  const sk_status status = sk_newton_solve(MPI_COMM_WORLD, &options, &cb, N, x, &report);
  if (status != SK_OK) fprintf(stderr, "newton: %s\n", sk_error_message());
  SK_CHECK(status == SK_OK);
  SK_CHECK(report.converged == 1);
  for (int i = 0; i < N; ++i) SK_CHECK_CLOSE(x[i], p.x_star[i], 1e-10);
  SK_CHECK(report.n_history == report.iterations + 1);
  SK_CHECK(report.iterations >= 3 && report.iterations <= 10);
  SK_CHECK(report.linear_solves == report.iterations);
  SK_CHECK(report.outcome == SK_NEWTON_CONVERGED);
  SK_CHECK(report.residual_history[report.n_history - 1] <= options.residual_tolerance);
  /* no solve spent on confirming convergence: every earlier iterate failed the residual test, so the iteration
   * that reached it was the last one (the update test used the predicted next update) */
  for (int k = 0; k + 1 < report.n_history; ++k) SK_CHECK(report.residual_history[k] > options.residual_tolerance);
  /* quadratic: ||F_{k+1}|| <= C ||F_k||^2 once in the asymptotic range, until round-off */
  int quadratic_steps = 0;
  for (int k = 0; k + 1 < report.n_history; ++k) {
    const double e = report.residual_history[k], e_next = report.residual_history[k + 1];
    if (e < 1.0 && e_next > 1e-13) {
      SK_CHECK(e_next <= 0.1 * e * e); /* measured: about 0.02 */
      ++quadratic_steps;
    }
  }
  SK_CHECK(quadratic_steps >= 2);
  /* after_iteration ran once per iteration, in order */
  SK_CHECK(p.after_calls == report.iterations);
  SK_CHECK(p.after_in_order);
  sk_linsys_destroy(p.sys);
}

/* Inexact Newton: the forcing terms follow Eisenstat-Walker (first 1e-4, then 0.9 (||F_k|| / ||F_{k-1}||)^2, at
 * most 1e-4), never below linear_tolerance nor below what the convergence test can use. */
static void check_forcing_terms(void) {
  problem p;
  problem_init(&p);
  sk_newton_options options;
  sk_newton_options_default(&options);
  SK_CHECK(options.forcing == 1 && options.linear_tolerance == 1e-10);
  double x[N];
  for (int i = 0; i < N; ++i) x[i] = 2.0 * p.x_star[i];
  sk_newton_callbacks cb = callbacks_for(&p);
  cb.solve_to_tolerance = solve_to_tolerance;
  sk_newton_report report;
  SK_CHECK(sk_newton_solve(MPI_COMM_WORLD, &options, &cb, N, x, &report) == SK_OK);
  SK_CHECK(p.n_tolerances == report.linear_solves && p.n_tolerances >= 3);
  SK_CHECK(p.tolerances[0] == 1e-4);
  const double converged = fmax(options.residual_tolerance, options.relative_tolerance * report.residual_history[0]);
  for (int k = 1; k < p.n_tolerances; ++k) {
    const double ratio = p.norms[k] / p.norms[k - 1];
    double expected = fmin(0.9 * ratio * ratio, 1e-4);
    if (0.9 * p.tolerances[k - 1] * p.tolerances[k - 1] > 0.1) expected = fmax(expected, 0.9 * p.tolerances[k - 1] * p.tolerances[k - 1]);
    expected = fmax(fmax(expected, fmin(1e-4, 0.1 * converged / p.norms[k])), options.linear_tolerance);
    printf("forcing %d: ||F|| = %.3e, tolerance %.3e (expected %.3e)\n", k, p.norms[k], p.tolerances[k], expected);
    SK_CHECK_CLOSE(p.tolerances[k], expected, 1e-12 * expected);
  }
  /* without the callback (or with forcing off) every solve goes through `solve` */
  options.forcing = 0;
  p.n_tolerances = 0;
  for (int i = 0; i < N; ++i) x[i] = 2.0 * p.x_star[i];
  SK_CHECK(sk_newton_solve(MPI_COMM_WORLD, &options, &cb, N, x, &report) == SK_OK);
  SK_CHECK(p.n_tolerances == 0);
  sk_linsys_destroy(p.sys);
}

/* The full Newton step from x0 = 0.1 jumps to x ~ 30; a residual that "inverts" above 3 must not crash NOX. */
static void check_residual_failure(void) {
  for (int ls = SK_LINE_SEARCH_FULL_STEP; ls <= SK_LINE_SEARCH_POLYNOMIAL; ++ls) {
    problem p;
    problem_init(&p);
    p.fail_above = 3.0;
    sk_newton_options options;
    sk_newton_options_default(&options);
    options.line_search = (sk_line_search)ls;
    double x[N];
    for (int i = 0; i < N; ++i) x[i] = 0.1;
    sk_newton_callbacks cb = callbacks_for(&p);
    sk_newton_report report;
    const sk_status status = sk_newton_solve(MPI_COMM_WORLD, &options, &cb, N, x, &report);
    if (ls == SK_LINE_SEARCH_FULL_STEP) {
      /* nothing to fall back on: a clean failure that keeps the callback's message */
      SK_CHECK(status == SK_ERR_INVERTED); /* the callback's status: the stepper cuts the step */
      SK_CHECK(report.converged == 0);
      SK_CHECK(report.outcome == SK_NEWTON_RESIDUAL_FAILED);
      SK_CHECK(strstr(sk_error_message(), "inverted") != NULL);
      SK_CHECK(strstr(report.reason, "inverted") != NULL);
      for (int i = 0; i < N; ++i) SK_CHECK(x[i] <= 3.0); /* x is left at the last good iterate */
    } else {
      /* the line search shortens the step into the admissible region and converges */
      if (status != SK_OK) fprintf(stderr, "line search %d: %s\n", ls, sk_error_message());
      SK_CHECK(status == SK_OK);
      for (int i = 0; i < N; ++i) SK_CHECK_CLOSE(x[i], p.x_star[i], 1e-10);
    }
    sk_linsys_destroy(p.sys);
  }

  /* failure at the initial guess */
  problem p;
  problem_init(&p);
  p.fail_above = 0.0;
  sk_newton_options options;
  sk_newton_options_default(&options);
  double x[N];
  for (int i = 0; i < N; ++i) x[i] = 1.0;
  sk_newton_callbacks cb = callbacks_for(&p);
  sk_newton_report report;
  SK_CHECK(sk_newton_solve(MPI_COMM_WORLD, &options, &cb, N, x, &report) == SK_ERR_INVERTED);
  SK_CHECK(report.outcome == SK_NEWTON_RESIDUAL_FAILED);
  SK_CHECK(strstr(sk_error_message(), "inverted") != NULL);
  sk_linsys_destroy(p.sys);
}

static void check_jacobian_failure(void) {
  problem p;
  problem_init(&p);
  p.fail_jacobian = 1;
  sk_newton_options options;
  sk_newton_options_default(&options);
  double x[N];
  for (int i = 0; i < N; ++i) x[i] = 2.0;
  sk_newton_callbacks cb = callbacks_for(&p);
  sk_newton_report report;
  /* a bug in assembly is not a reason to cut the step: its own status comes back */
  SK_CHECK(sk_newton_solve(MPI_COMM_WORLD, &options, &cb, N, x, &report) == SK_ERR_INTERNAL);
  SK_CHECK(report.outcome == SK_NEWTON_CALLBACK_FAILED);
  SK_CHECK(strstr(sk_error_message(), "assembly exploded") != NULL);
  SK_CHECK(report.converged == 0);
  sk_linsys_destroy(p.sys);
}

static void check_after_iteration_failure(void) {
  problem p;
  problem_init(&p);
  p.after_fail_at = 2;
  sk_newton_options options;
  sk_newton_options_default(&options);
  double x[N];
  for (int i = 0; i < N; ++i) x[i] = 2.0 * p.x_star[i];
  sk_newton_callbacks cb = callbacks_for(&p);
  sk_newton_report report;
  SK_CHECK(sk_newton_solve(MPI_COMM_WORLD, &options, &cb, N, x, &report) == SK_ERR_INPUT);
  SK_CHECK(report.outcome == SK_NEWTON_CALLBACK_FAILED);
  SK_CHECK(strstr(sk_error_message(), "active set cycling at iteration 2") != NULL);
  SK_CHECK(report.converged == 0);
  SK_CHECK(p.after_calls == 2); /* the solve stopped right after the failing callback */
  sk_linsys_destroy(p.sys);
}

static void check_max_iterations(void) {
  problem p;
  problem_init(&p);
  sk_newton_options options;
  sk_newton_options_default(&options);
  options.max_iterations = 2;
  double x[N];
  for (int i = 0; i < N; ++i) x[i] = 10.0;
  sk_newton_callbacks cb = callbacks_for(&p);
  sk_newton_report report;
  SK_CHECK(sk_newton_solve(MPI_COMM_WORLD, &options, &cb, N, x, &report) == SK_ERR_DIVERGED);
  SK_CHECK(report.converged == 0);
  SK_CHECK(report.iterations == 2);
  SK_CHECK(report.n_history == 3);
  SK_CHECK(report.outcome == SK_NEWTON_MAX_ITERATIONS);
  SK_CHECK(strstr(report.reason, "2 iterations") != NULL);
  SK_CHECK(strstr(sk_error_message(), "2 iterations") != NULL);
  sk_linsys_destroy(p.sys);
}

/* A residual with a floor of 1e-9 per entry (standing in for round-off) above an absolute tolerance of 1e-11:
 * Newton stops as stagnated within a few iterations (not max_iterations), says so with the numbers in %g. */
static void check_stagnation(void) {
  problem p;
  problem_init(&p);
  p.floor = 1e-9;
  sk_newton_options options;
  sk_newton_options_default(&options);
  options.residual_tolerance = 1e-11;
  options.relative_tolerance = 1e-14;
  options.max_iterations = 50;
  double x[N];
  for (int i = 0; i < N; ++i) x[i] = 2.0 * p.x_star[i];
  sk_newton_callbacks cb = callbacks_for(&p);
  sk_newton_report report;
  SK_CHECK(sk_newton_solve(MPI_COMM_WORLD, &options, &cb, N, x, &report) == SK_ERR_DIVERGED);
  printf("stagnation after %d iterations: %s\n", report.iterations, report.reason);
  SK_CHECK(report.outcome == SK_NEWTON_STAGNATED);
  SK_CHECK(report.iterations <= 12); /* measured: 8 (6 to converge onto the floor, 2 stalled) */
  SK_CHECK(strstr(report.reason, "stagnated") != NULL);
  SK_CHECK(strstr(report.reason, "0.000000") == NULL); /* %g, not %f */
  SK_CHECK(strstr(report.reason, "e-09") != NULL || strstr(report.reason, "e-10") != NULL);
  SK_CHECK(strstr(report.reason, "absolute tolerance 1e-11") != NULL);
  SK_CHECK(strstr(sk_error_message(), "stagnated") != NULL);
  for (int i = 0; i < N; ++i) SK_CHECK_CLOSE(x[i], p.x_star[i], 1e-8); /* as close as the floor allows */
  /* the same floor under a tolerance above it converges */
  options.residual_tolerance = 1e-7;
  for (int i = 0; i < N; ++i) x[i] = 2.0 * p.x_star[i];
  SK_CHECK(sk_newton_solve(MPI_COMM_WORLD, &options, &cb, N, x, &report) == SK_OK);
  sk_linsys_destroy(p.sys);
}

/* A residual whose floor lies at round-off of x (1e-14 per entry: Newton corrections of 1e-14 against ||x|| = 3.6)
 * above an absolute tolerance of 1e-16: the step is accepted at the round-off floor (SK_OK, converged, outcome
 * ROUNDOFF_FLOOR, the numbers in the reason) within two stalled iterations, not failed as stagnated. A floor of 1e-10
 * (corrections of about 1e-11, above 1000 eps ||x|| = 1.2e-12) is not round-off of x: it stagnates, unless the
 * positions x is measured from are large enough (roundoff_scale 1e4: 1000 eps 1e4 = 2.2e-9). */
static void check_roundoff_floor(void) {
  problem p;
  problem_init(&p);
  p.floor = 1e-14;
  sk_newton_options options;
  sk_newton_options_default(&options);
  options.residual_tolerance = 1e-16;
  options.relative_tolerance = 1e-20;
  options.max_iterations = 50;
  double x[N];
  for (int i = 0; i < N; ++i) x[i] = 2.0 * p.x_star[i];
  sk_newton_callbacks cb = callbacks_for(&p);
  sk_newton_report report;
  SK_CHECK(sk_newton_solve(MPI_COMM_WORLD, &options, &cb, N, x, &report) == SK_OK);
  printf("round-off floor after %d iterations: %s\n", report.iterations, report.reason);
  SK_CHECK(report.converged == 1 && report.outcome == SK_NEWTON_ROUNDOFF_FLOOR);
  SK_CHECK(report.iterations <= 10); /* measured: 8 (6 to converge onto the floor, 2 at it) */
  SK_CHECK(strstr(report.reason, "round-off floor") != NULL);
  SK_CHECK(strstr(report.reason, "absolute tolerance 1e-16") != NULL);
  SK_CHECK(strstr(report.reason, "e-14") != NULL || strstr(report.reason, "e-15") != NULL);
  for (int i = 0; i < N; ++i) SK_CHECK_CLOSE(x[i], p.x_star[i], 1e-13);
  /* a floor above round-off of x stagnates (cut by the caller) */
  p.floor = 1e-10;
  for (int i = 0; i < N; ++i) x[i] = 2.0 * p.x_star[i];
  SK_CHECK(sk_newton_solve(MPI_COMM_WORLD, &options, &cb, N, x, &report) == SK_ERR_DIVERGED);
  SK_CHECK(report.outcome == SK_NEWTON_STAGNATED);
  /* the same floor at round-off of the positions x is measured from */
  options.roundoff_scale = 1e4;
  for (int i = 0; i < N; ++i) x[i] = 2.0 * p.x_star[i];
  SK_CHECK(sk_newton_solve(MPI_COMM_WORLD, &options, &cb, N, x, &report) == SK_OK);
  SK_CHECK(report.outcome == SK_NEWTON_ROUNDOFF_FLOOR);
  sk_linsys_destroy(p.sys);
}

/* A singular Jacobian: the linear solver fails, and Newton reports that as its own status. */
static void check_linear_solver_failure(void) {
  problem p;
  problem_init(&p);
  p.singular_jacobian = 1;
  sk_newton_options options;
  sk_newton_options_default(&options);
  double x[N];
  for (int i = 0; i < N; ++i) x[i] = 2.0 * p.x_star[i];
  sk_newton_callbacks cb = callbacks_for(&p);
  sk_newton_report report;
  SK_CHECK(sk_newton_solve(MPI_COMM_WORLD, &options, &cb, N, x, &report) == SK_ERR_LINEAR_SOLVER);
  SK_CHECK(report.outcome == SK_NEWTON_LINEAR_SOLVER);
  SK_CHECK(report.converged == 0 && report.iterations == 0);
  SK_CHECK(p.last_solve.failure == SK_LINEAR_FAILURE_SINGULAR);
  SK_CHECK(p.last_solve.solver == SK_LINEAR_DIRECT_MUMPS);
  SK_CHECK(strstr(report.reason, "linear solve failed in iteration 1") != NULL);
  SK_CHECK(strstr(sk_error_message(), "MUMPS") != NULL);
  sk_linsys_destroy(p.sys);
}

/* A scalar residual on which the full Newton step makes no progress: F(x) = x (1 + x^2)^(-0.3) grows like
 * sign(x) |x|^0.4, whose Newton step overshoots the root by 1.5 x: the Newton map here is
 * x -> -0.6 x^3 / (1 + 0.4 x^2), so from x0 = 10 the iterates alternate in sign and grow (-14.6, 21.6, ...), and so
 * do ||F|| and the correction. A shortened step lands near the root, where F ~ x and Newton converges quadratically. */
typedef struct {
  double slope;
  int after_calls, after_last_iteration, after_in_order;
} wander;

static sk_status wander_residual(void *ctx, const double *x, double *F) {
  (void)ctx;
  F[0] = x[0] * pow(1.0 + x[0] * x[0], -0.3);
  return SK_OK;
}

static sk_status wander_jacobian(void *ctx, const double *x) {
  wander *w = ctx;
  w->slope = pow(1.0 + x[0] * x[0], -1.3) * (1.0 + 0.4 * x[0] * x[0]);
  return SK_OK;
}

static sk_status wander_solve(void *ctx, const double *x, const double *F, double *dx) {
  (void)x;
  dx[0] = -F[0] / ((wander *)ctx)->slope;
  return SK_OK;
}

static sk_status wander_after(void *ctx, int iteration, const double *x, double residual_norm) {
  wander *w = ctx;
  (void)x;
  (void)residual_norm;
  w->after_in_order = w->after_in_order && iteration == w->after_last_iteration + 1;
  w->after_last_iteration = iteration;
  ++w->after_calls;
  return SK_OK;
}

/* Without backtrack_on_no_progress the full step runs out max_iterations (25); with it the solve goes on from its
 * iterate with the backtracking line search after the 4 iterations of the test's window (plus the one before it)
 * and converges, iterations counted on and after_iteration numbered on across the switch. Measured: 13 iterations
 * (5 full steps with ||F|| = 2.50 ... 5.55, then 8 with backtracking down to ||F|| = 0). */
static void check_no_progress_switch(void) {
  for (int on = 0; on <= 1; ++on) {
    wander w = {.after_in_order = 1};
    const sk_newton_callbacks cb = {.ctx = &w, .residual = wander_residual, .jacobian = wander_jacobian,
                                    .solve = wander_solve, .after_iteration = wander_after};
    sk_newton_options options;
    sk_newton_options_default(&options);
    SK_CHECK(options.backtrack_on_no_progress == 0);
    options.backtrack_on_no_progress = on;
    double x = 10.0;
    sk_newton_report report;
    const sk_status status = sk_newton_solve(MPI_COMM_WORLD, &options, &cb, 1, &x, &report);
    if (!on) {
      SK_CHECK(status == SK_ERR_DIVERGED);
      SK_CHECK(report.outcome == SK_NEWTON_MAX_ITERATIONS);
      SK_CHECK(report.iterations == 25 && report.switched_to_backtrack == 0);
      continue;
    }
    SK_CHECK(status == SK_OK && report.converged == 1 && report.outcome == SK_NEWTON_CONVERGED);
    SK_CHECK(report.switched_to_backtrack == 1);
    SK_CHECK(report.iterations == 13);
    SK_CHECK(fabs(x) < 1e-8);
    SK_CHECK(w.after_in_order && w.after_calls == report.iterations && w.after_last_iteration == report.iterations);
    SK_CHECK(report.n_history == report.iterations + 1);
  }
}

static void check_names_and_defaults(void) {
  const char *names[] = {"full-step", "backtrack", "polynomial"};
  for (int i = 0; i < 3; ++i) {
    sk_line_search ls;
    SK_CHECK(sk_line_search_from_name(names[i], &ls) == SK_OK);
    SK_CHECK((int)ls == i);
  }
  sk_line_search ls;
  SK_CHECK(sk_line_search_from_name("trust-region", &ls) == SK_ERR_INPUT);
  sk_newton_options options;
  sk_newton_options_default(&options);
  SK_CHECK(options.residual_tolerance == 1e-8 && options.relative_tolerance == 1e-10);
  SK_CHECK(options.update_tolerance == 1e-8 && options.max_iterations == 25);
  SK_CHECK(options.line_search == SK_LINE_SEARCH_FULL_STEP && options.verbose == 0);
}

int main(int argc, char **argv) {
  MPI_Init(&argc, &argv);
  check_names_and_defaults();
  check_quadratic_convergence(SK_LINE_SEARCH_FULL_STEP);
  check_quadratic_convergence(SK_LINE_SEARCH_BACKTRACK);
  check_residual_failure();
  check_jacobian_failure();
  check_after_iteration_failure();
  check_max_iterations();
  check_stagnation();
  check_roundoff_floor();
  check_forcing_terms();
  check_linear_solver_failure();
  check_no_progress_switch();
  const int result = sk_test_finish("bridge newton");
  MPI_Finalize();
  return result;
}
