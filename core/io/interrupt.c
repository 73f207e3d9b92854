/* SIGINT/SIGTERM recorded in a flag that long-running loops poll (see stickslip/interrupt.h). */
#define _POSIX_C_SOURCE 200809L

#include "stickslip/interrupt.h"

#include <signal.h>
#include <string.h>

static volatile sig_atomic_t received = 0;

/* Records the first signal; the handler then resets itself (SA_RESETHAND), so a second one ends the process. */
static void on_signal(int signal_number) {
  if (!received) received = signal_number;
}

void sk_interrupt_install(void) {
  struct sigaction action;
  memset(&action, 0, sizeof action);
  action.sa_handler = on_signal;
  sigemptyset(&action.sa_mask);
  /* No SA_RESTART: a blocking wait (poll on the mesh generator) returns EINTR and looks at the flag. */
  action.sa_flags = SA_RESETHAND;
  sigaction(SIGINT, &action, NULL);
  sigaction(SIGTERM, &action, NULL);
}

void sk_interrupt_uninstall(void) {
  signal(SIGINT, SIG_DFL);
  signal(SIGTERM, SIG_DFL);
}

int sk_interrupt_requested(void) { return (int)received; }

int sk_interrupt_agreed(MPI_Comm comm) {
  int local = (int)received, any = 0;
  MPI_Allreduce(&local, &any, 1, MPI_INT, MPI_MAX, comm);
  return any;
}

const char *sk_interrupt_name(int signal_number) {
  switch (signal_number) {
    case SIGINT: return "SIGINT (Ctrl-C)";
    case SIGTERM: return "SIGTERM";
    default: return "a signal";
  }
}

void sk_interrupt_clear(void) { received = 0; }
