/* stickslip driver — starting MPI lazily and cheaply (mpi_start.c says why and what it measured). */
#ifndef STICKSLIP_DRIVER_MPI_START_H
#define STICKSLIP_DRIVER_MPI_START_H

/* MPI_Init, once; a process started without a launcher gets the single-process settings of mpi_start.c. */
void sk_driver_mpi_init(int *argc, char ***argv);
/* MPI_Finalize if MPI was started. */
void sk_driver_mpi_finalize(void);
/* This process's rank in MPI_COMM_WORLD, also before or without MPI_Init (from the launcher's environment). */
int sk_driver_rank(void);

#endif
