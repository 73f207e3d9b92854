/* stickslip — stopping cleanly on SIGINT (Ctrl-C) and SIGTERM (a batch system's time limit, `kill`).
 *
 * The driver calls sk_interrupt_install() once. The handlers only record the signal; whoever runs for long polls:
 * - the time stepper calls sk_interrupt_agreed(comm) once per step, on every rank, before starting the step; when
 *   it returns a signal number it stops, writes the results of the steps completed (summary.json status
 *   "interrupted") and returns SK_ERR_INTERRUPTED;
 * - waits (mesh generation in a child process) call sk_interrupt_requested() and give up.
 * A second signal of the same kind while the first is being handled ends the process at once (the default action):
 * a user who presses Ctrl-C twice means it. The results folder is then left as DIR.partial-PID, which the next run
 * names (see sk_outdir_begin). */
#ifndef STICKSLIP_INTERRUPT_H
#define STICKSLIP_INTERRUPT_H

#include <mpi.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Installs the SIGINT and SIGTERM handlers (idempotent). */
void sk_interrupt_install(void);
/* Back to the default actions (the process ends at once on SIGINT/SIGTERM). */
void sk_interrupt_uninstall(void);
/* The signal received on this process (SIGINT, SIGTERM), or 0. Async-signal-safe to call anywhere. */
int sk_interrupt_requested(void);
/* The signal received on any rank of `comm`, or 0: collective (one MPI_Allreduce of an int), so that all ranks stop
 * after the same step. The one call the stepper makes per step. */
int sk_interrupt_agreed(MPI_Comm comm);
/* "SIGINT (Ctrl-C)" / "SIGTERM" for messages. */
const char *sk_interrupt_name(int signal_number);
/* Forgets a recorded signal (tests). */
void sk_interrupt_clear(void);

#ifdef __cplusplus
}
#endif
#endif
