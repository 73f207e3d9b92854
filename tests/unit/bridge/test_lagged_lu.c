/* gmres-lu (core/solver/lagged_lu.cpp): GMRES preconditioned by the last MUMPS factorisation. A sequence of
 * contact-like saddle-point systems on one pattern, as Newton makes them (the nodal diagonal drifting by a few per
 * cent, then jumping), solved by gmres-lu and by MUMPS afresh: the same solutions to the linear tolerance, one
 * factorisation for the drifting ones, a refactorisation when the factors no longer serve, and one at every new
 * pattern. Then `auto` on such sequences (auto_choice.cpp): it takes the lagged LU where the matrix drifts slowly
 * (cheaper per solve, factorisations included) and keeps MUMPS where it changes much between solves, with MUMPS's
 * solutions either way. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bridge_systems.h"
#include "sk_test.h"
#include "stickslip/bridge.h"

enum { kGrid = 8, kActive = 10, kInactive = 5 };

static sk_status set_pattern(sk_linear_system *sys, const test_csr *a) {
  int *rows = malloc(sizeof(int) * (size_t)a->n);
  for (int i = 0; i < a->n; ++i) rows[i] = i;
  const sk_status status = sk_linsys_set_pattern(sys, a->n, 0, a->n, rows, a->row_ptr, a->cols);
  free(rows);
  return status;
}

static sk_status load(sk_linear_system *sys, const test_csr *a) {
  sk_linsys_zero(sys);
  memcpy(sk_linsys_values(sys), a->values, sizeof(double) * (size_t)a->row_ptr[a->n]);
  return sk_linsys_assemble(sys);
}

/* Solves the system of `shift` (pattern of n_active active points) with both solvers; returns gmres-lu's report. */
static sk_linear_report solve_both(sk_linear_system *lagged, sk_linear_system *fresh, int n_active, double shift,
                                   int new_pattern) {
  test_csr a = test_contact_3d(kGrid, n_active, kInactive, 0.0, 1, shift, NULL);
  double *x_ref = malloc(sizeof(double) * (size_t)a.n), *b = malloc(sizeof(double) * (size_t)a.n);
  double *x = malloc(sizeof(double) * (size_t)a.n), *x_mumps = malloc(sizeof(double) * (size_t)a.n);
  test_reference_solution(a.n, x_ref);
  test_csr_multiply(&a, x_ref, b);
  sk_linear_report report = {0}, mumps = {0};
  if (new_pattern) {
    SK_CHECK(set_pattern(lagged, &a) == SK_OK);
    SK_CHECK(set_pattern(fresh, &a) == SK_OK);
  }
  SK_CHECK(load(lagged, &a) == SK_OK && load(fresh, &a) == SK_OK);
  SK_CHECK(sk_linsys_solve(lagged, b, x, &report) == SK_OK);
  SK_CHECK(sk_linsys_solve(fresh, b, x_mumps, &mumps) == SK_OK);
  const double difference = test_max_difference(a.n, x, x_mumps);
  printf("shift %5.2f, %2d active: gmres-lu %2d iterations, %d factorisations, relative residual %.1e, "
         "|x - x_mumps| %.1e\n", shift, n_active, report.iterations, report.factorisations, report.relative_residual,
         difference);
  SK_CHECK(report.solver == SK_LINEAR_GMRES_LU);
  SK_CHECK(mumps.factorisations == 1 && mumps.iterations == 0);
  SK_CHECK(report.relative_residual <= 1e-12);
  SK_CHECK(difference <= 1e-10 * (1.0 + 0.01 * a.n)); /* |x_ref| grows to 0.01 n */
  test_csr_free(&a);
  free(x_ref);
  free(b);
  free(x);
  free(x_mumps);
  return report;
}

/* The contact system of `grid` with its nodal diagonal scaled row by row by 1 + amplitude * r(row, solve), r a
 * fixed pseudo-random number in [0, 1): a matrix that drifts (small amplitude growing with `solve`) or changes
 * much and unpredictably between solves (large amplitude). */
static test_csr perturbed_system(int grid, double amplitude, int solve) {
  test_csr a = test_contact_3d(grid, kActive, kInactive, 0.0, 1, 1.0, NULL);
  const int n_nodal = 3 * grid * grid * grid;
  for (int i = 0; i < n_nodal; ++i)
    for (int64_t k = a.row_ptr[i]; k < a.row_ptr[i + 1]; ++k)
      if (a.cols[k] == i) {
        const unsigned h = (unsigned)i * 2654435761u ^ (unsigned)solve * 40503u;
        a.values[k] *= 1.0 + amplitude * (double)(h % 1000u) / 1000.0;
      }
  return a;
}

/* `auto` over `solves` systems of one pattern; returns how many of the last `tail` solves ran the lagged LU and
 * counts their factorisations. Every solution equals MUMPS's (solved afresh) to the solve tolerance. */
static int auto_sequence(double amplitude_per_solve, double amplitude_fixed, int solves, int tail,
                         int *tail_factorisations) {
  enum { kAutoGrid = 10 };
  sk_linear_system *sys = test_linear_system(MPI_COMM_WORLD, SK_LINEAR_AUTO);
  sk_linear_system *fresh = test_linear_system(MPI_COMM_WORLD, SK_LINEAR_DIRECT_MUMPS);
  SK_CHECK(sys && fresh);
  int lagged = 0;
  *tail_factorisations = 0;
  for (int solve = 0; sys && fresh && solve < solves; ++solve) {
    test_csr a = perturbed_system(kAutoGrid, amplitude_fixed + amplitude_per_solve * solve, solve);
    double *x_ref = malloc(sizeof(double) * (size_t)a.n), *b = malloc(sizeof(double) * (size_t)a.n);
    double *x = malloc(sizeof(double) * (size_t)a.n), *x_mumps = malloc(sizeof(double) * (size_t)a.n);
    test_reference_solution(a.n, x_ref);
    test_csr_multiply(&a, x_ref, b);
    if (solve == 0) SK_CHECK(set_pattern(sys, &a) == SK_OK && set_pattern(fresh, &a) == SK_OK);
    SK_CHECK(load(sys, &a) == SK_OK && load(fresh, &a) == SK_OK);
    sk_linear_report report = {0};
    SK_CHECK(sk_linsys_solve(sys, b, x, &report) == SK_OK);
    SK_CHECK(sk_linsys_solve(fresh, b, x_mumps, NULL) == SK_OK);
    const double difference = test_max_difference(a.n, x, x_mumps);
    printf("auto solve %2d: %-8s %2d iterations, %d factorisations, |x - x_mumps| %.1e%s%s\n", solve,
           sk_linear_solver_name(report.solver), report.iterations, report.factorisations, difference,
           report.decision ? " - " : "", report.decision ? report.decision : "");
    SK_CHECK(report.solver == SK_LINEAR_DIRECT_MUMPS || report.solver == SK_LINEAR_GMRES_LU);
    SK_CHECK(report.relative_residual <= 1e-12);
    SK_CHECK(difference <= 5e-10); /* measured: at most 1.4e-10 (|x_ref| up to 31) */
    if (solve >= solves - tail) {
      lagged += report.solver == SK_LINEAR_GMRES_LU;
      *tail_factorisations += report.factorisations;
    }
    test_csr_free(&a);
    free(x_ref);
    free(b);
    free(x);
    free(x_mumps);
  }
  sk_linsys_destroy(sys);
  sk_linsys_destroy(fresh);
  return lagged;
}

/* A slowly drifting matrix: after MUMPS's first solve and the lagged LU's measuring window (8 solves, the first a
 * factorisation of its own), `auto` keeps the lagged LU, which refactorises rarely. A matrix that changes much
 * between solves: the old factors are no preconditioner (GMRES gives up and the solve refactorises), so the lagged
 * LU costs more than MUMPS and `auto` goes back to MUMPS. */
static void check_auto_learns(void) {
  int factorisations = 0;
  const int drifting = auto_sequence(0.002, 0.0, 16, 6, &factorisations);
  printf("drifting: %d of the last 6 solves lagged, %d factorisations\n", drifting, factorisations);
  SK_CHECK(drifting == 6 && factorisations <= 2);
  const int jumping = auto_sequence(0.0, 3.0, 16, 6, &factorisations);
  printf("changing: %d of the last 6 solves lagged, %d factorisations\n", jumping, factorisations);
  SK_CHECK(jumping == 0 && factorisations == 6);
}

/* `auto` on a run of known length (sk_linsys_set_steps_left, two solves per step) on a 2D Laplacian of 14 400
 * unknowns (no coordinates: GMRES + MueLu by the size rule, the other four compete): in a run of 3 steps no trial
 * fits the exploration budget, and every solve stays with GMRES + MueLu — the decision names the candidates not
 * tried — where a run of 200 steps tries others within its first 12 solves. Every solution is right either way. */
static int auto_run(int steps, int solves, int *not_tried) {
  test_csr a = test_laplacian_2d(120, 0.0);
  double *x_ref = malloc(sizeof(double) * (size_t)a.n), *b = malloc(sizeof(double) * (size_t)a.n);
  double *x = malloc(sizeof(double) * (size_t)a.n);
  test_reference_solution(a.n, x_ref);
  test_csr_multiply(&a, x_ref, b);
  sk_linear_options options;
  sk_linear_options_default(&options);
  options.kind = SK_LINEAR_AUTO;
  options.tolerance = 1e-10;
  sk_linear_system *sys = NULL;
  SK_CHECK(sk_linsys_create(MPI_COMM_WORLD, &options, &sys) == SK_OK && set_pattern(sys, &a) == SK_OK);
  int other = 0;
  *not_tried = 0;
  for (int solve = 0; sys && solve < solves; ++solve) {
    if (solve % 2 == 0) sk_linsys_set_steps_left(sys, steps - solve / 2);
    sk_linear_report report;
    SK_CHECK(load(sys, &a) == SK_OK && sk_linsys_solve(sys, b, x, &report) == SK_OK);
    SK_CHECK(test_max_difference(a.n, x, x_ref) <= 1e-7);
    other += report.solver != SK_LINEAR_GMRES_MUELU;
    *not_tried += report.decision != NULL && strstr(report.decision, "not tried (") != NULL;
    printf("%d steps, solve %2d: %-12s%s%s\n", steps, solve, sk_linear_solver_name(report.solver),
           report.decision ? " — " : "", report.decision ? report.decision : "");
  }
  sk_linsys_destroy(sys);
  free(x_ref);
  free(b);
  free(x);
  test_csr_free(&a);
  return other;
}

static void check_auto_budget(void) {
  int not_tried = 0;
  SK_CHECK(auto_run(3, 6, &not_tried) == 0);
  SK_CHECK(not_tried == 1);
  SK_CHECK(auto_run(200, 12, &not_tried) >= 2);
  SK_CHECK(not_tried == 0);
}

/* A banded matrix as dense as 3D elasticity: n rows, 2 half_band + 1 entries per row (-1 off the diagonal, 2 half_band
 * + 2 on it: diagonally dominant). */
static test_csr banded_system(int n, int half_band) {
  test_csr a;
  a.n = n;
  a.row_ptr = malloc(sizeof(int64_t) * (size_t)(n + 1));
  a.cols = malloc(sizeof(int) * (size_t)n * (size_t)(2 * half_band + 1));
  a.values = malloc(sizeof(double) * (size_t)n * (size_t)(2 * half_band + 1));
  int64_t k = 0;
  for (int i = 0; i < n; ++i) {
    a.row_ptr[i] = k;
    for (int j = i - half_band; j <= i + half_band; ++j) {
      if (j < 0 || j >= n) continue;
      a.cols[k] = j;
      a.values[k++] = j == i ? 2.0 * half_band + 2.0 : -1.0;
    }
  }
  a.row_ptr[n] = k;
  return a;
}

/* `auto` on a tiny system as dense as 3D elasticity (663 unknowns, 45 entries per row: inside the contested band of
 * the 3D size rule, 500 ... 8 000 unknowns): MUMPS outright in every solve, no trial of an iterative candidate or of
 * the lagged LU (without the rule, kAutoDirectOutrightUnknowns in auto_choice.cpp, its second solve already was a
 * trial), and the first decision says why. */
static void check_auto_tiny(void) {
  test_csr a = banded_system(663, 22);
  double *x_ref = malloc(sizeof(double) * (size_t)a.n), *b = malloc(sizeof(double) * (size_t)a.n);
  double *x = malloc(sizeof(double) * (size_t)a.n);
  test_reference_solution(a.n, x_ref);
  test_csr_multiply(&a, x_ref, b);
  sk_linear_system *sys = test_linear_system(MPI_COMM_WORLD, SK_LINEAR_AUTO);
  SK_CHECK(sys && set_pattern(sys, &a) == SK_OK);
  int mumps = 0, outright = 0;
  for (int solve = 0; sys && solve < 10; ++solve) {
    sk_linear_report report;
    SK_CHECK(load(sys, &a) == SK_OK && sk_linsys_solve(sys, b, x, &report) == SK_OK);
    SK_CHECK(test_max_difference(a.n, x, x_ref) <= 1e-8);
    mumps += report.solver == SK_LINEAR_DIRECT_MUMPS;
    outright += report.decision != NULL && strstr(report.decision, "the direct solver outright") != NULL;
    printf("tiny (%d unknowns), solve %d: %s%s%s\n", a.n, solve, sk_linear_solver_name(report.solver),
           report.decision ? " - " : "", report.decision ? report.decision : "");
  }
  SK_CHECK(a.n == 663);
  SK_CHECK(mumps == 10);
  SK_CHECK(outright == 1);
  sk_linsys_destroy(sys);
  test_csr_free(&a);
  free(x_ref);
  free(b);
  free(x);
}

int main(int argc, char **argv) {
  MPI_Init(&argc, &argv);
  sk_linear_system *lagged = test_linear_system(MPI_COMM_WORLD, SK_LINEAR_GMRES_LU), *fresh = test_linear_system(MPI_COMM_WORLD, SK_LINEAR_DIRECT_MUMPS);
  SK_CHECK(lagged && fresh);
  if (lagged && fresh) {
    /* the first solve of a pattern factorises and solves directly */
    sk_linear_report r = solve_both(lagged, fresh, kActive, 1.0, 1);
    SK_CHECK(r.factorisations == 1 && r.iterations == 0);
    /* a drifting matrix: the factors of shift 1 precondition GMRES, no factorisation */
    const double drift[] = {1.01, 1.03, 1.1};
    for (int k = 0; k < 3; ++k) {
      r = solve_both(lagged, fresh, kActive, drift[k], 0);
      SK_CHECK(r.factorisations == 0 && r.iterations >= 1 && r.iterations <= 10);
    }
    /* a jump: the old factors take more than 10 iterations or fail (then this solve refactorises at once); after
     * more than 10 the next solve refactorises */
    r = solve_both(lagged, fresh, kActive, 6.0, 0);
    SK_CHECK(r.factorisations == 1 || r.iterations > 10);
    if (r.factorisations == 0) {
      r = solve_both(lagged, fresh, kActive, 6.0, 0);
      SK_CHECK(r.factorisations == 1);
    }
    r = solve_both(lagged, fresh, kActive, 6.05, 0); /* and the new factors serve the next ones */
    SK_CHECK(r.factorisations == 0 && r.iterations <= 10);
    /* contact points entering: a new pattern, a new factorisation */
    r = solve_both(lagged, fresh, kActive + 4, 6.05, 1);
    SK_CHECK(r.factorisations == 1 && r.iterations == 0);
    r = solve_both(lagged, fresh, kActive + 4, 6.1, 0);
    SK_CHECK(r.factorisations == 0);
  }
  sk_linsys_destroy(lagged);
  sk_linsys_destroy(fresh);
  check_auto_learns();
  check_auto_budget();
  check_auto_tiny();
  const int result = sk_test_finish("bridge gmres-lu");
  MPI_Finalize();
  return result;
}
