/* The contact phases' clocks (system.h): wall and thread CPU time, with the waits in collectives inside contact calls
 * kept apart (sk_system_charge_wait) and left out of the contact time (sk_system_charge_contact). */
#define _GNU_SOURCE
#include <time.h>

#include "system.h"

sk_clock sk_system_clock(void) {
  struct timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return (sk_clock){sk_system_seconds(), (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec, 0.0, 0.0};
}

sk_clock sk_system_contact_clock(const sk_system *sys) {
  sk_clock t = sk_system_clock();
  t.wait_wall = sys->contact_wait[0];
  t.wait_cpu = sys->contact_wait[1];
  return t;
}

void sk_system_charge_contact(sk_system *sys, int phase, sk_clock t0) {
  const sk_clock t = sk_system_clock();
  const double wall = t.wall - t0.wall - (sys->contact_wait[0] - t0.wait_wall);
  const double cpu = t.cpu - t0.cpu - (sys->contact_wait[1] - t0.wait_cpu);
  sys->t_contact += wall;
  sys->t_contact_cpu += cpu;
  sys->contact_phase[phase][0] += wall;
  sys->contact_phase[phase][1] += cpu;
}

void sk_system_charge_wait(sk_system *sys, sk_clock t0) {
  const sk_clock t = sk_system_clock();
  sys->contact_wait[0] += t.wall - t0.wall;
  sys->contact_wait[1] += t.cpu - t0.cpu;
}
