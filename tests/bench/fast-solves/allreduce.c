/* Benchmark (issue 8, weak-scaling model in docs/linear-solvers.md): the cost of the one collective of a Newton
 * iteration whose size is the global system, MPI_Allreduce of the replicated residual (n doubles, core/model/system.c
 * cb_residual), and of a one-double reduction (a Krylov dot product).
 *   mpicc -O2 tests/bench/fast-solves/allreduce.c -o /tmp/allreduce && mpirun -np 2 /tmp/allreduce 92276 */
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
int main(int c, char **v) {
  if (c < 2) {
    fprintf(stderr, "usage: allreduce N\n");
    return 1;
  }
  MPI_Init(&c, &v);
  int n = atoi(v[1]), reps = 50, r;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  double *a = calloc(n, 8), *b = calloc(n, 8);
  MPI_Allreduce(a, b, n, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  double t0 = MPI_Wtime(), c0 = (double)clock() / CLOCKS_PER_SEC;
  for (int k = 0; k < reps; ++k) MPI_Allreduce(a, b, n, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  double t1 = MPI_Wtime(), c1 = (double)clock() / CLOCKS_PER_SEC;
  double s = 0, one = 1;
  double t2 = MPI_Wtime();
  for (int k = 0; k < 1000; ++k) MPI_Allreduce(&one, &s, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  double t3 = MPI_Wtime();
  if (r == 0) printf("n %d: allreduce %.3f ms wall, %.3f ms cpu; 1 double: %.1f us\n", n, (t1 - t0) / reps * 1e3, (c1 - c0) / reps * 1e3, (t3 - t2) / 1000 * 1e6);
  MPI_Finalize();
}
