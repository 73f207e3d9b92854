/* The bridge on 2 ranks: every solver kind gives the one-rank answer, with contributions to a row split over
 * ranks — some rows written by a rank that does not own them, some by both, each with part of the row's columns
 * (merged and summed by the bridge). Every direct backend (MUMPS factorising the distributed matrix, Amesos v1 KLU,
 * Amesos2 KLU2 gathered to rank 0) must match the serial KLU2 to 1e-12: Debian's Amesos2 KLU2 on a distributed
 * matrix does not (so this fails if the rank-0 gather were bypassed). Vectors are each rank's owned rows.
 * Also: NOX Newton on 2 ranks over distributed vectors reaches the same answer on every rank. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bridge_systems.h"
#include "sk_test.h"
#include "stickslip/bridge.h"

static int rank = 0, size = 1;

/* The rows a rank owns: the nodal rows [0, n_nodal) split in halves of whole blocks, the rest on the last rank. */
static void owned_range(int n, int n_nodal, int block, int comm_rank, int comm_size, int *first, int *count) {
  const int blocks = n_nodal / block, lower = comm_size == 1 ? blocks : blocks / 2;
  *first = comm_rank == 0 ? 0 : lower * block;
  *count = comm_size == 1 ? n : comm_rank == 0 ? lower * block : n - lower * block;
}

/* (The serial reference is KLU2 on MPI_COMM_SELF, independent of the backend `direct` resolves to.)
 * Rank 0 writes rows r % 3 in {0, 1}, rank 1 rows r % 3 in {1, 2}; rows r % 3 == 1 are shared: rank 0 writes the
 * even entries of the row, rank 1 the odd ones (each a part of the row's columns). */
static sk_linear_system *create_split_with(MPI_Comm comm, sk_linear_solver_kind kind, int block_size,
                                           const double *coordinates, int n_nodes, const test_csr *a) {
  sk_linear_system *sys = test_linear_system(comm, kind);
  if (!sys) return NULL;
  int comm_rank, comm_size;
  MPI_Comm_rank(comm, &comm_rank);
  MPI_Comm_size(comm, &comm_size);
  const int n_nodal = coordinates ? 3 * n_nodes : a->n, block = coordinates ? 3 : block_size;
  int first, count;
  owned_range(a->n, n_nodal, block, comm_rank, comm_size, &first, &count);
  int *rows = malloc(sizeof(int) * (size_t)a->n), n_rows = 0;
  int64_t *row_ptr = malloc(sizeof(int64_t) * (size_t)(a->n + 1));
  int *cols = malloc(sizeof(int) * (size_t)a->row_ptr[a->n]);
  int64_t *source = malloc(sizeof(int64_t) * (size_t)a->row_ptr[a->n]);
  row_ptr[0] = 0;
  for (int i = 0; i < a->n; ++i) {
    const int part = i % 3;
    const int mine = comm_size == 1 || (comm_rank == 0 && part != 2) || (comm_rank == 1 && part != 0);
    if (!mine) continue;
    int64_t used = row_ptr[n_rows];
    for (int64_t k = a->row_ptr[i]; k < a->row_ptr[i + 1]; ++k) {
      const int position = (int)(k - a->row_ptr[i]);
      if (comm_size > 1 && part == 1 && position % 2 != comm_rank) continue;
      cols[used] = a->cols[k];
      source[used++] = k;
    }
    rows[n_rows++] = i;
    row_ptr[n_rows] = used;
  }
  sk_status status = sk_linsys_set_block_size(sys, block_size);
  if (status == SK_OK && coordinates) {
    const int nodal_count = first + count <= n_nodal ? count : n_nodal - first;
    status = sk_linsys_set_coordinates(sys, nodal_count / 3, 3, coordinates + first);
  }
  const int nodal_owned = first + count <= n_nodal ? count : n_nodal - first;
  if (status == SK_OK)
    status = sk_linsys_set_pattern(sys, nodal_owned, a->n - n_nodal, n_rows, rows, row_ptr, cols);
  if (status == SK_OK) {
    int owned_first = -1;
    const int owned = sk_linsys_owned_rows(sys, &owned_first);
    if (owned != count || owned_first != first) status = sk_error_set(SK_ERR_INTERNAL, "owned rows [%d, +%d)", owned_first, owned);
  }
  if (status == SK_OK) {
    sk_linsys_zero(sys);
    double *values = sk_linsys_values(sys);
    for (int64_t e = 0; e < row_ptr[n_rows]; ++e) values[e] = a->values[source[e]];
    status = sk_linsys_assemble(sys);
  }
  free(rows);
  free(row_ptr);
  free(cols);
  free(source);
  if (status != SK_OK) {
    fprintf(stderr, "rank %d: %s\n", rank, sk_error_message());
    sk_linsys_destroy(sys);
    return NULL;
  }
  return sys;
}

static sk_linear_system *create_split(MPI_Comm comm, sk_linear_solver_kind kind, int block_size, const test_csr *a) {
  return create_split_with(comm, kind, block_size, NULL, 0, a);
}

/* This rank's owned part of a whole vector. */
static const double *owned_part(const sk_linear_system *sys, const double *whole) {
  int first = 0;
  sk_linsys_owned_rows(sys, &first);
  return whole + first;
}

/* The largest |x - reference| over the owned rows of every rank. */
static double owned_difference(const sk_linear_system *sys, const double *x, const double *reference) {
  int first = 0;
  const int count = sk_linsys_owned_rows(sys, &first);
  double worst = test_max_difference(count, x, reference + first);
  MPI_Allreduce(MPI_IN_PLACE, &worst, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  return worst;
}

static void check_system(const char *name, double convection) {
  test_csr a = test_laplacian_2d(50, convection); /* 2500 unknowns: above MueLu's coarse size, so AMG has levels */
  const int n = a.n;
  double *x_ref = malloc(sizeof(double) * (size_t)n), *b = malloc(sizeof(double) * (size_t)n);
  double *x_serial = malloc(sizeof(double) * (size_t)n), *x = malloc(sizeof(double) * (size_t)n);
  test_reference_solution(n, x_ref);
  test_csr_multiply(&a, x_ref, b);

  /* the one-rank answer, computed on every rank with its own communicator */
  sk_linear_system *serial = create_split(MPI_COMM_SELF, SK_LINEAR_DIRECT_KLU2, 1, &a);
  SK_CHECK(serial != NULL);
  if (!serial) return;
  SK_CHECK(sk_linsys_solve(serial, b, x_serial, NULL) == SK_OK);
  SK_CHECK(test_max_difference(n, x_serial, x_ref) <= 1e-10);
  sk_linsys_destroy(serial);

  const sk_linear_solver_kind kinds[] = {SK_LINEAR_DIRECT,      SK_LINEAR_DIRECT_MUMPS, SK_LINEAR_DIRECT_KLU2,
                                         SK_LINEAR_DIRECT_KLU, SK_LINEAR_GMRES_MUELU,  SK_LINEAR_GMRES_ILU};
  for (size_t k = 0; k < sizeof kinds / sizeof kinds[0]; ++k) {
    for (int block_size = 1; block_size <= 2; ++block_size) {
      sk_linear_system *sys = create_split(MPI_COMM_WORLD, kinds[k], block_size, &a);
      SK_CHECK(sys != NULL);
      if (!sys) continue;
      /* apply sums the split contributions exactly like the serial matrix */
      double *y = malloc(sizeof(double) * (size_t)n);
      SK_CHECK(sk_linsys_apply(sys, owned_part(sys, x_ref), y) == SK_OK);
      SK_CHECK(owned_difference(sys, y, b) <= 1e-12);
      free(y);
      /* two solves: the second re-uses the factorisation / preconditioner structure */
      for (int pass = 0; pass < 2; ++pass) {
        sk_linear_report report;
        memset(x, 0, sizeof(double) * (size_t)n);
        const sk_status status = sk_linsys_solve(sys, owned_part(sys, b), x, &report);
        if (status != SK_OK) fprintf(stderr, "rank %d, %s: %s\n", rank, name, sk_error_message());
        SK_CHECK(status == SK_OK);
        SK_CHECK(report.refactored_symbolic == (pass == 0));
        const double difference = owned_difference(sys, x, x_serial);
        const int direct = kinds[k] != SK_LINEAR_GMRES_MUELU && kinds[k] != SK_LINEAR_GMRES_ILU;
        const double tolerance = direct ? 1e-12 : 1e-8;
        if (difference > tolerance && rank == 0)
          fprintf(stderr, "%s, %s, block %d: max |x - x_serial| = %.3g\n", name, sk_linear_solver_name(kinds[k]),
                  block_size, difference);
        SK_CHECK(difference <= tolerance);
        if (rank == 0 && pass == 0)
          printf("%-14s %-12s block %d: %3d iterations, relative residual %.2e, |x - x_serial| %.2e\n", name,
                 sk_linear_solver_name(kinds[k]), block_size, report.iterations, report.relative_residual,
                 difference);
      }
      sk_linsys_destroy(sys);
    }
  }
  test_csr_free(&a);
  free(x_ref);
  free(b);
  free(x_serial);
  free(x);
}

/* A contact-like system with a nodal block (coordinates) and multiplier rows (on the last rank), split over the
 * ranks: the iterative solvers' Schur complement gathers its nodal blocks from both ranks and matches the serial
 * direct solve. */
static void check_contact_system(void) {
  const int m = 10;
  double *coordinates = malloc(sizeof(double) * 3 * (size_t)(m * m * m));
  test_csr a = test_contact_3d(m, 20, 30, 1e-24, 1, 0.5, coordinates);
  const int n = a.n;
  double *x_ref = malloc(sizeof(double) * (size_t)n), *b = malloc(sizeof(double) * (size_t)n);
  double *x_serial = malloc(sizeof(double) * (size_t)n), *x = malloc(sizeof(double) * (size_t)n);
  test_reference_solution(n, x_ref);
  test_csr_multiply(&a, x_ref, b);
  sk_linear_system *serial = create_split(MPI_COMM_SELF, SK_LINEAR_DIRECT_KLU2, 1, &a);
  SK_CHECK(serial != NULL);
  if (!serial) return;
  SK_CHECK(sk_linsys_solve(serial, b, x_serial, NULL) == SK_OK);
  sk_linsys_destroy(serial);
  double largest = 0;
  for (int i = 0; i < n; ++i) largest = fmax(largest, fabs(x_serial[i]));
  /* gmres-lu: pass 0 factorises, pass 1 runs GMRES with those distributed factors */
  const sk_linear_solver_kind kinds[] = {SK_LINEAR_GMRES_MUELU,  SK_LINEAR_GMRES_ILU, SK_LINEAR_GMRES_SGS,
                                         SK_LINEAR_GMRES_JACOBI, SK_LINEAR_DIRECT_MUMPS, SK_LINEAR_AUTO,
                                         SK_LINEAR_GMRES_LU};
  for (size_t k = 0; k < sizeof kinds / sizeof kinds[0]; ++k) {
    sk_linear_system *sys = create_split_with(MPI_COMM_WORLD, kinds[k], 1, coordinates, m * m * m, &a);
    SK_CHECK(sys != NULL);
    if (!sys) continue;
    for (int pass = 0; pass < 2; ++pass) {
      sk_linear_report report;
      memset(x, 0, sizeof(double) * (size_t)n);
      const sk_status status = sk_linsys_solve(sys, owned_part(sys, b), x, &report);
      if (status != SK_OK) fprintf(stderr, "rank %d, contact: %s\n", rank, sk_error_message());
      SK_CHECK(status == SK_OK);
      const double difference = owned_difference(sys, x, x_serial) / largest;
      SK_CHECK(difference <= 1e-9); /* measured: GMRES 1e-11 .. 1e-10, MUMPS 1e-14 */
      if (kinds[k] == SK_LINEAR_GMRES_LU) SK_CHECK(report.factorisations == (pass == 0) && (pass == 0 || report.iterations > 0));
      if (rank == 0 && (pass == 0 || kinds[k] == SK_LINEAR_GMRES_LU))
        printf("contact        %-12s        : %3d iterations, relative residual %.2e, |x - x_serial| / |x| %.2e\n",
               sk_linear_solver_name(report.solver), report.iterations, report.relative_residual, difference);
    }
    sk_linsys_destroy(sys);
  }
  test_csr_free(&a);
  free(coordinates);
  free(x_ref);
  free(b);
  free(x_serial);
  free(x);
}

/* A failure on the direct path is reported on every rank (not only on rank 0, which factorises). */
static void check_singular(void) {
  test_csr a = test_laplacian_2d(10, 0.0);
  for (int64_t k = a.row_ptr[a.n - 1]; k < a.row_ptr[a.n]; ++k) a.values[k] = 0.0;
  const sk_linear_solver_kind kinds[] = {SK_LINEAR_DIRECT, SK_LINEAR_DIRECT_MUMPS, SK_LINEAR_DIRECT_KLU2,
                                         SK_LINEAR_DIRECT_KLU};
  for (size_t d = 0; d < sizeof kinds / sizeof kinds[0]; ++d) {
    sk_linear_system *sys = create_split(MPI_COMM_WORLD, kinds[d], 1, &a);
    SK_CHECK(sys != NULL);
    if (!sys) continue;
    double *b = malloc(sizeof(double) * (size_t)a.n), *x = malloc(sizeof(double) * (size_t)a.n);
    for (int i = 0; i < a.n; ++i) b[i] = 1.0;
    SK_CHECK(sk_linsys_solve(sys, owned_part(sys, b), x, NULL) == SK_ERR_LINEAR_SOLVER);
    SK_CHECK(strstr(sk_error_message(), "direct solve") != NULL);
    free(b);
    free(x);
    sk_linsys_destroy(sys);
  }
  test_csr_free(&a);
}

/* Newton through NOX on 2 ranks: F_i = x_i^3 + (x_i - x_{i+1}) / 2 - c_i, Jacobian solved by the distributed direct
 * solver. NOX runs on each rank's owned unknowns (norms summed over ranks); every rank reaches the same answer in the
 * same iterations. */
enum { NEWTON_N = 40 };
typedef struct {
  double c[NEWTON_N];
  int64_t row_ptr[NEWTON_N + 1];
  int cols[2 * NEWTON_N];
  int first, count;
  sk_linear_system *sys;
} cubic_problem;

/* The whole x from every rank's owned part (the test's own ghost exchange). */
static void whole_x(const cubic_problem *p, const double *x, double *all) {
  int counts[2], displs[2];
  MPI_Allgather(&p->count, 1, MPI_INT, counts, 1, MPI_INT, MPI_COMM_WORLD);
  MPI_Allgather(&p->first, 1, MPI_INT, displs, 1, MPI_INT, MPI_COMM_WORLD);
  MPI_Allgatherv(x, p->count, MPI_DOUBLE, all, counts, displs, MPI_DOUBLE, MPI_COMM_WORLD);
}

static sk_status cubic_residual(void *ctx, const double *x, double *F) {
  const cubic_problem *p = ctx;
  double all[NEWTON_N];
  whole_x(p, x, all);
  for (int j = 0; j < p->count; ++j) {
    const int i = p->first + j;
    F[j] = all[i] * all[i] * all[i] + 0.5 * (all[i] - (i + 1 < NEWTON_N ? all[i + 1] : 0.0)) - p->c[i];
  }
  return SK_OK;
}

static sk_status cubic_jacobian(void *ctx, const double *x) {
  cubic_problem *p = ctx;
  double all[NEWTON_N];
  whole_x(p, x, all);
  sk_linsys_zero(p->sys);
  double *values = sk_linsys_values(p->sys);
  /* each rank contributes half of every row it writes (rank r writes rows of parity r, and row 0 on both) */
  for (int i = 0, k = 0; i < NEWTON_N; ++i) {
    if (!(i % size == rank || i == 0)) continue;
    const double share = i == 0 ? 1.0 / size : 1.0;
    values[k++] = share * (3.0 * all[i] * all[i] + 0.5);
    if (i + 1 < NEWTON_N) values[k++] = -0.5 * share;
  }
  return sk_linsys_assemble(p->sys);
}

static sk_status cubic_solve(void *ctx, const double *x, const double *F, double *dx) {
  cubic_problem *p = ctx;
  (void)x;
  double minus_f[NEWTON_N];
  for (int j = 0; j < p->count; ++j) minus_f[j] = -F[j];
  return sk_linsys_solve(p->sys, minus_f, dx, NULL);
}

static void check_newton(void) {
  cubic_problem p;
  double x_star[NEWTON_N], x[NEWTON_N];
  for (int i = 0; i < NEWTON_N; ++i) x_star[i] = 1.0 + 0.05 * i;
  for (int i = 0; i < NEWTON_N; ++i)
    p.c[i] = x_star[i] * x_star[i] * x_star[i] + 0.5 * (x_star[i] - (i + 1 < NEWTON_N ? x_star[i + 1] : 0.0));
  int rows[NEWTON_N], n_rows = 0, k = 0;
  p.row_ptr[0] = 0;
  for (int i = 0; i < NEWTON_N; ++i) {
    if (!(i % size == rank || i == 0)) continue;
    p.cols[k++] = i;
    if (i + 1 < NEWTON_N) p.cols[k++] = i + 1;
    rows[n_rows++] = i;
    p.row_ptr[n_rows] = k;
  }
  owned_range(NEWTON_N, NEWTON_N, 1, rank, size, &p.first, &p.count);
  sk_linear_options options;
  sk_linear_options_default(&options);
  options.kind = SK_LINEAR_DIRECT;
  SK_CHECK(sk_linsys_create(MPI_COMM_WORLD, &options, &p.sys) == SK_OK);
  SK_CHECK(sk_linsys_set_pattern(p.sys, p.count, 0, n_rows, rows, p.row_ptr, p.cols) == SK_OK);
  sk_newton_options newton;
  sk_newton_options_default(&newton);
  newton.line_search = SK_LINE_SEARCH_BACKTRACK;
  sk_newton_callbacks callbacks = {
      .ctx = &p, .residual = cubic_residual, .jacobian = cubic_jacobian, .solve = cubic_solve};
  for (int j = 0; j < p.count; ++j) x[j] = 3.0;
  sk_newton_report report;
  const sk_status status = sk_newton_solve(MPI_COMM_WORLD, &newton, &callbacks, p.count, x, &report);
  if (status != SK_OK) fprintf(stderr, "rank %d: %s\n", rank, sk_error_message());
  SK_CHECK(status == SK_OK && report.converged);
  for (int j = 0; j < p.count; ++j) SK_CHECK_CLOSE(x[j], x_star[p.first + j], 1e-10);
  int iterations[2] = {report.iterations, -report.iterations}, extremes[2];
  MPI_Allreduce(iterations, extremes, 2, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  SK_CHECK(extremes[0] == -extremes[1]); /* same iteration count on every rank */
  sk_linsys_destroy(p.sys);
}

int main(int argc, char **argv) {
  MPI_Init(&argc, &argv);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  SK_CHECK(size == 2);
  check_system("laplacian", 0.0);
  check_system("nonsymmetric", 0.8);
  check_singular();
  check_contact_system();
  check_newton();
  /* every rank's verdict counts */
  int failures = sk_test_failures, total = 0;
  MPI_Allreduce(&failures, &total, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  sk_test_failures = total;
  int result = 0;
  if (rank == 0) result = sk_test_finish("bridge on 2 ranks");
  MPI_Bcast(&result, 1, MPI_INT, 0, MPI_COMM_WORLD);
  MPI_Finalize();
  return result;
}
