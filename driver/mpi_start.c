/* stickslip driver — MPI only where a communicator is needed, and a cheap start for a single process.
 *
 * Measured on the 2-core build machine (Open MPI 4.1.4, docs/performance.md): MPI_Init of a process started
 * without mpirun (a "singleton") took 0.31-0.44 s wall for 0.05 s CPU — it forks an orted daemon (~0.15 s) and the
 * UCX transport calibrates its clock by sleeping (~0.2 s, 850 nanosleeps). With the two MCA settings below it takes
 * 0.04 s. Neither matters to a single process: an isolated singleton has no daemon to spawn further processes
 * with (stickslip never does), and ob1 with the self transport is how one process talks to itself. Settings the
 * user made in the environment are kept; under mpirun nothing is changed. --version, --help (of every command),
 * plugins and a command line refused before the scene is read do not start MPI at all.
 * Isolated singletons all use job family 0, so they would share the session directory /tmp/ompi.HOST.UID/jf.0: one
 * process finishing removed it while another was creating its own below it (MPI_Init aborted, seen in
 * cli_hostile_non_finite with two tests at once). Each process gets a session base of its own, removed after
 * MPI_Finalize. */
#define _POSIX_C_SOURCE 200112L /* setenv */
#include "mpi_start.h"

#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

static char session_base[512]; /* set when this process chose its own Open MPI session directory */

/* Environment variables a launcher (mpirun of Open MPI or MPICH, srun) sets for the processes it starts. */
static const char *const launcher_variables[] = {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE",
                                                 "SLURM_PROCID", NULL};

static int launched_by_mpirun(void) {
  for (int i = 0; launcher_variables[i]; ++i)
    if (getenv(launcher_variables[i])) return 1;
  return 0;
}

void sk_driver_mpi_init(int *argc, char ***argv) {
  int initialized = 0;
  MPI_Initialized(&initialized);
  if (initialized) return;
  if (!launched_by_mpirun()) {
    setenv("OMPI_MCA_ess_singleton_isolated", "1", 0);
    setenv("OMPI_MCA_pml", "ob1", 0);
    if (!getenv("OMPI_MCA_orte_tmpdir_base")) {
      const char *tmp = getenv("TMPDIR");
      snprintf(session_base, sizeof session_base, "%s/stickslip-mpi-%ld", tmp && *tmp ? tmp : "/tmp", (long)getpid());
      setenv("OMPI_MCA_orte_tmpdir_base", session_base, 1);
    }
  }
  MPI_Init(argc, argv);
}

void sk_driver_mpi_finalize(void) {
  int initialized = 0, finalized = 0;
  MPI_Initialized(&initialized);
  MPI_Finalized(&finalized);
  if (initialized && !finalized) MPI_Finalize();
  if (session_base[0]) rmdir(session_base); /* Open MPI emptied it; a failure leaves only an empty directory */
}

int sk_driver_rank(void) {
  int initialized = 0;
  MPI_Initialized(&initialized);
  if (initialized) {
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    return rank;
  }
  /* before (or without) MPI_Init: the launcher's rank, so `mpirun -np 2 stickslip --version` prints once */
  static const char *const rank_variables[] = {"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK", "SLURM_PROCID", NULL};
  for (int i = 0; rank_variables[i]; ++i) {
    const char *value = getenv(rank_variables[i]);
    if (value) return atoi(value);
  }
  return 0;
}
