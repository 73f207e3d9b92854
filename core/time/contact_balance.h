/* How evenly the ranks share the contact work (issue "contact load balance" measures it before it balances it):
 * per step the contact terms' evaluation time and active slave entities of every rank, reduced to min/mean/max,
 * printed with --verbose and summed up in summary.json. */
#ifndef STICKSLIP_CONTACT_BALANCE_H
#define STICKSLIP_CONTACT_BALANCE_H

#include <stdint.h>

#include "../model/system.h"
#include "stickslip/output.h"

typedef struct {
  double seconds_mark;      /* this rank's contact seconds (sys->t_contact) at the last recorded step */
  double run_seconds[3];    /* the run's contact seconds per rank so far: min, mean, max over ranks */
  int steps;                /* recorded steps with contact work on some rank */
  double ratio_sum;         /* sum over those steps of max / mean of the step's contact time per rank */
  double ratio_worst;       /* the largest of them, at step worst_step */
  int64_t worst_step;
  double active_peak[3];    /* active slave entities per rank (min, mean, max) at the step with the most in all */
  int64_t active_peak_step;
  /* the same in this thread's CPU seconds (sys->t_contact_cpu) */
  double cpu_mark, run_cpu[3], cpu_ratio_sum, cpu_ratio_worst;
  double run_wait[3];       /* the run's waits in contact calls per rank (sys->contact_wait, wall): min, mean, max */
  int cpu_steps;
  /* by contact phase (SK_CONTACT_*), wall [0] and CPU [1]: this rank's seconds at the last recorded step, the run's
   * seconds per rank (min, mean, max over ranks), and the sum over steps of the step's max / mean (with its count) */
  double phase_mark[SK_CONTACT_PHASES][2], phase_run[SK_CONTACT_PHASES][2][3];
  double phase_ratio_sum[SK_CONTACT_PHASES][2];
  int phase_steps[SK_CONTACT_PHASES][2];
} sk_contact_balance;

/* After a converged step (collective): reduces this step's contact time and the totals' per-rank active entities;
 * with verbose and more than one rank, rank 0 prints one line. With a contact partition and the step's contact work
 * uneven beyond contact_balance.time_ratio or .entity_imbalance, sets sys->contact_rebalance_pending and weighs
 * the slave entities by their work (sk_contact_partition_weigh). */
sk_status sk_contact_balance_step(sk_contact_balance *balance, sk_system *sys, const sk_contact_totals *totals,
                             int64_t step, int verbose);
/* The contact_balance_* keys of summary.json (rank 0). */
sk_status sk_contact_balance_write(const sk_contact_balance *balance, sk_json *json);

#endif
