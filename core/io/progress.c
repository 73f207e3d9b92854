/* Progress reporting on stderr: an updating line on a terminal, a line per ~10% of simulated time in logs. */
#define _POSIX_C_SOURCE 200809L

#include <stdio.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "stickslip/output.h"

static struct {
  char label[64];
  double t_end;
  double start;         /* wall clock at begin */
  double last_print;    /* wall clock of the last terminal update */
  int tty;
  int next_decile;      /* log mode: next 10% mark to report */
  int step;
  int active;
} progress;

static double wall_seconds(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void format_duration(char *buf, size_t n, double s) {
  if (s < 0 || s != s) {
    snprintf(buf, n, "?");
  } else if (s < 60) {
    snprintf(buf, n, "%.1fs", s);
  } else if (s < 3600) {
    snprintf(buf, n, "%dm%02ds", (int)(s / 60), (int)s % 60);
  } else {
    snprintf(buf, n, "%dh%02dm", (int)(s / 3600), ((int)s % 3600) / 60);
  }
}

void sk_progress_begin(const char *label, double t_end) {
  snprintf(progress.label, sizeof progress.label, "%s", label ? label : "run");
  progress.t_end = t_end;
  progress.start = wall_seconds();
  progress.last_print = -1.0;
  progress.tty = isatty(fileno(stderr));
  progress.next_decile = 1;
  progress.step = 0;
  progress.active = 1;
}

void sk_progress_update(int step, double t, int newton_its, const char *extra) {
  if (!progress.active) return;
  progress.step = step;
  double now = wall_seconds();
  double elapsed = now - progress.start;
  double fraction = progress.t_end > 0 ? t / progress.t_end : 0.0;
  if (fraction > 1.0) fraction = 1.0;
  if (progress.tty) {
    if (progress.last_print >= 0 && now - progress.last_print < 0.1) return; /* ~10 updates per second */
    progress.last_print = now;
  } else {
    if (fraction * 10.0 < progress.next_decile) return;
    while (progress.next_decile <= fraction * 10.0) ++progress.next_decile;
  }
  char spent[32], eta[32];
  format_duration(spent, sizeof spent, elapsed);
  format_duration(eta, sizeof eta, fraction > 0 ? elapsed * (1.0 - fraction) / fraction : -1.0);
  fprintf(stderr, "%s%s: step %d  t=%.4g/%.4g (%3.0f%%)  newton %d  wall %s  ETA %s%s%s%s", progress.tty ? "\r" : "",
          progress.label, step, t, progress.t_end, 100.0 * fraction, newton_its, spent, eta, extra ? "  " : "",
          extra ? extra : "", progress.tty ? "\033[K" : "\n");
  fflush(stderr);
}

void sk_progress_end(const char *stopped) {
  if (!progress.active) return;
  char spent[32];
  format_duration(spent, sizeof spent, wall_seconds() - progress.start);
  if (stopped)
    fprintf(stderr, "%s%s: %s after %d steps, %s%s\n", progress.tty ? "\r" : "", progress.label, stopped,
            progress.step, spent, progress.tty ? "\033[K" : "");
  else
    fprintf(stderr, "%s%s: done, %d steps in %s%s\n", progress.tty ? "\r" : "", progress.label, progress.step, spent,
            progress.tty ? "\033[K" : "");
  fflush(stderr);
  progress.active = 0;
}
