/* Solves linear systems written by a run with STICKSLIP_DUMP_SYSTEMS=DIR (core/solver/system_dump.cpp) with each
 * of the given solvers, through the bridge as the stepper does (coordinates, pattern, assembly, solve), and times
 * them: set-up + first solve, then a re-solve of the same system (what a Newton iteration on an unchanged pattern
 * costs; the preconditioner is then reused as in a run).
 *
 *   solve_dumped [--whole] [--csv FILE] DIR INDEX[,INDEX...] SOLVER [SOLVER...]  (SOLVER: mumps, gmres-muelu, ...)
 *
 * --whole withholds the coordinates: the bridge then sees one block (no nodal / constraint split, block size 1,
 * translations as nullspace), which is how GMRES + MueLu saw contact systems before the split.
 * --csv appends one line per system and solver to FILE: dir,index,unknowns,constraints,solver,pattern_cpu,
 * iterations,first_cpu,resolve_iterations,resolve_cpu,residual,difference,failed.
 *
 * Prints one line per system and solver: unknowns, constraint rows, the CPU seconds of sk_linsys_set_pattern,
 * iterations, seconds (wall and CPU), the
 * relative residual and the largest difference from the first solver's solution, relative to its largest entry. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "stickslip/bridge.h"

typedef struct {
  int n, n_coordinates, dim;
  int64_t *row_ptr;
  int *cols;
  double *values, *rhs, *coordinates;
} dumped;

static double cpu_seconds(void) {
  struct timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static FILE *open_part(const char *dir, const char *stem, int index, const char *suffix) {
  char path[1024];
  snprintf(path, sizeof path, "%s/%s-%05d.%s", dir, stem, index, suffix);
  FILE *f = fopen(path, "r");
  if (!f) fprintf(stderr, "solve_dumped: cannot read %s\n", path);
  return f;
}

/* The MatrixMarket file lists entries row by row with sorted columns (as system_dump.cpp writes them). */
static int load(const char *dir, int index, dumped *d) {
  memset(d, 0, sizeof *d);
  FILE *meta = open_part(dir, "meta", index, "txt"), *mtx = open_part(dir, "system", index, "mtx");
  FILE *rhs = open_part(dir, "system", index, "rhs");
  int ok = meta && mtx && rhs;
  int block_size = 0;
  ok = ok && fscanf(meta, "%d %d %d %d", &d->n, &block_size, &d->dim, &d->n_coordinates) == 4;
  if (ok) {
    d->coordinates = malloc(sizeof(double) * (size_t)(d->n_coordinates + 1));
    for (int i = 0; ok && i < d->n_coordinates; ++i) ok = fscanf(meta, "%lf", &d->coordinates[i]) == 1;
  }
  char header[256];
  long long nnz = 0;
  int rows = 0, columns = 0;
  ok = ok && fgets(header, sizeof header, mtx) && fscanf(mtx, "%d %d %lld", &rows, &columns, &nnz) == 3 && rows == d->n;
  if (ok) {
    d->row_ptr = calloc((size_t)d->n + 1, sizeof(int64_t));
    d->cols = malloc(sizeof(int) * (size_t)nnz);
    d->values = malloc(sizeof(double) * (size_t)nnz);
    for (long long k = 0; ok && k < nnz; ++k) {
      int i, j;
      ok = fscanf(mtx, "%d %d %lf", &i, &j, &d->values[k]) == 3 && i >= 1 && i <= d->n;
      if (ok) {
        d->cols[k] = j - 1;
        d->row_ptr[i]++;
      }
    }
    for (int i = 0; i < d->n; ++i) d->row_ptr[i + 1] += d->row_ptr[i];
    d->rhs = malloc(sizeof(double) * (size_t)d->n);
    for (int i = 0; ok && i < d->n; ++i) ok = fscanf(rhs, "%lf", &d->rhs[i]) == 1;
  }
  if (meta) fclose(meta);
  if (mtx) fclose(mtx);
  if (rhs) fclose(rhs);
  if (!ok) fprintf(stderr, "solve_dumped: %s, system %d: unreadable\n", dir, index);
  return ok;
}

static void release(dumped *d) {
  free(d->row_ptr);
  free(d->cols);
  free(d->values);
  free(d->rhs);
  free(d->coordinates);
}

static sk_status assemble(sk_linear_system *sys, const dumped *d) {
  sk_linsys_zero(sys);
  memcpy(sk_linsys_values(sys), d->values, sizeof(double) * (size_t)d->row_ptr[d->n]);
  return sk_linsys_assemble(sys);
}

int main(int argc, char **argv) {
  MPI_Init(&argc, &argv);
  int whole = 0;
  FILE *csv = NULL;
  while (argc > 1 && strncmp(argv[1], "--", 2) == 0) {
    if (strcmp(argv[1], "--whole") == 0) {
      whole = 1;
    } else if (strcmp(argv[1], "--csv") == 0 && argc > 2) {
      csv = fopen(argv[2], "a");
      ++argv;
      --argc;
    } else {
      break;
    }
    ++argv;
    --argc;
  }
  if (argc < 4) {
    fprintf(stderr, "usage: solve_dumped [--whole] [--csv FILE] DIR INDEX[,INDEX...] SOLVER [SOLVER...]\n");
    MPI_Finalize();
    return 2;
  }
  int code = 0;
  char *indices = strdup(argv[2]);
  for (char *token = strtok(indices, ","); token; token = strtok(NULL, ",")) {
    dumped d;
    if (!load(argv[1], atoi(token), &d)) {
      code = 1;
      break;
    }
    double *reference = malloc(sizeof(double) * (size_t)d.n), *x = malloc(sizeof(double) * (size_t)d.n);
    int *rows = malloc(sizeof(int) * (size_t)d.n);
    for (int i = 0; i < d.n; ++i) rows[i] = i;
    for (int s = 3; s < argc; ++s) {
      sk_linear_options options;
      sk_linear_options_default(&options);
      sk_linear_system *sys = NULL;
      sk_status status = sk_linear_solver_from_name(argv[s], &options.kind);
      if (status == SK_OK) status = sk_linsys_create(MPI_COMM_WORLD, &options, &sys);
      if (status == SK_OK && d.dim > 0 && !whole) status = sk_linsys_set_coordinates(sys, d.n_coordinates / d.dim, d.dim, d.coordinates);
      const double pattern_start = cpu_seconds();
      const int nodal = d.dim > 0 && !whole ? d.n_coordinates : d.n;
      if (status == SK_OK) status = sk_linsys_set_pattern(sys, nodal, d.n - nodal, d.n, rows, d.row_ptr, d.cols);
      const double pattern_seconds = cpu_seconds() - pattern_start;
      double wall[2] = {0, 0}, cpu[2] = {0, 0};
      sk_linear_report report[2];
      memset(report, 0, sizeof report);
      for (int pass = 0; pass < 2 && status == SK_OK; ++pass) {
        const double c0 = cpu_seconds();
        status = assemble(sys, &d);
        if (status == SK_OK) status = sk_linsys_solve(sys, d.rhs, x, &report[pass]);
        cpu[pass] = cpu_seconds() - c0;
        wall[pass] = report[pass].seconds;
      }
      double difference = 0, largest = 0;
      if (status == SK_OK) {
        if (s == 3) memcpy(reference, x, sizeof(double) * (size_t)d.n);
        for (int i = 0; i < d.n; ++i) {
          difference = fmax(difference, fabs(x[i] - reference[i]));
          largest = fmax(largest, fabs(reference[i]));
        }
      }
      printf("%s %5s %-12s n %6d constraints %5d | pattern cpu %.3f | %3d its, first %.3f s (cpu %.3f) | again %3d "
             "its, %.3f s (cpu %.3f) | residual %.1e | difference %.1e%s%s\n",
             argv[1], token, argv[s], d.n, d.n - d.n_coordinates, pattern_seconds, report[0].iterations, wall[0], cpu[0],
             report[1].iterations, wall[1], cpu[1], report[1].relative_residual,
             largest > 0 ? difference / largest : difference, status == SK_OK ? "" : " FAILED: ",
             status == SK_OK ? "" : sk_error_message());
      fflush(stdout);
      if (csv)
        fprintf(csv, "%s,%s,%d,%d,%s%s,%.4f,%d,%.4f,%d,%.4f,%.2e,%.2e,%d\n", argv[1], token, d.n, d.n - d.n_coordinates,
                argv[s], whole ? "-whole" : "", pattern_seconds, report[0].iterations, cpu[0], report[1].iterations,
                cpu[1], report[1].relative_residual, largest > 0 ? difference / largest : difference, status != SK_OK);
      if (status != SK_OK) code = 1;
      sk_linsys_destroy(sys);
    }
    free(reference);
    free(x);
    free(rows);
    release(&d);
  }
  free(indices);
  if (csv) fclose(csv);
  MPI_Finalize();
  return code;
}
