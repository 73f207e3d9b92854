/* Contact work per rank (contact_balance.h). Time is the time spent in the contact terms' calls (core/model/system.c,
 * t_contact: search, active set, residual, Jacobian and commit of the plugins, the broad phase), cut attempts of the
 * step included, the waits in collectives inside them left out (contact_wait); as wall time and as this thread's CPU
 * time. The rebalancing trigger and the entities' weights read the CPU time: on a shared or oversubscribed machine a
 * rank's wall time grows by the time it is descheduled, which is not its work (docs/scaling.md, "Contact
 * partition"). Entities are the active slave points each rank's plugins report. */
#include "contact_balance.h"

#include <math.h>
#include <stdio.h>

#include "../model/contact_partition.h"

/* min, mean, max over ranks of one value per rank (collective) */
static void reduce_min_mean_max(double value, MPI_Comm comm, int n_ranks, double out[3]) {
  double extremes[2] = {-value, value}, sum = value;
  MPI_Allreduce(MPI_IN_PLACE, extremes, 2, MPI_DOUBLE, MPI_MAX, comm);
  MPI_Allreduce(MPI_IN_PLACE, &sum, 1, MPI_DOUBLE, MPI_SUM, comm);
  out[0] = -extremes[0];
  out[1] = sum / n_ranks;
  out[2] = extremes[1];
}

/* The contact phases' seconds (wall and CPU) of the step and of the run so far, min / mean / max over the ranks: the
 * run's into balance->phase_run, the step's max / mean summed into phase_ratio_sum. Two all-reduces. */
enum { N_PHASE_VALUES = 2 * SK_CONTACT_PHASES };
static void reduce_phases(sk_contact_balance *balance, const sk_system *sys) {
  double extremes[4 * N_PHASE_VALUES], sums[2 * N_PHASE_VALUES];
  for (int q = 0; q < SK_CONTACT_PHASES; ++q)
    for (int c = 0; c < 2; ++c) {
      const int i = 2 * q + c;
      const double step = sys->contact_phase[q][c] - balance->phase_mark[q][c], run = sys->contact_phase[q][c];
      extremes[i] = -step, extremes[N_PHASE_VALUES + i] = step;
      extremes[2 * N_PHASE_VALUES + i] = -run, extremes[3 * N_PHASE_VALUES + i] = run;
      sums[i] = step, sums[N_PHASE_VALUES + i] = run;
      balance->phase_mark[q][c] = run;
    }
  MPI_Allreduce(MPI_IN_PLACE, extremes, 4 * N_PHASE_VALUES, MPI_DOUBLE, MPI_MAX, sys->comm);
  MPI_Allreduce(MPI_IN_PLACE, sums, 2 * N_PHASE_VALUES, MPI_DOUBLE, MPI_SUM, sys->comm);
  for (int q = 0; q < SK_CONTACT_PHASES; ++q)
    for (int c = 0; c < 2; ++c) {
      const int i = 2 * q + c;
      if (sums[i] > 0.0) {
        balance->phase_ratio_sum[q][c] += extremes[N_PHASE_VALUES + i] / (sums[i] / sys->n_ranks);
        balance->phase_steps[q][c]++;
      }
      balance->phase_run[q][c][0] = -extremes[2 * N_PHASE_VALUES + i];
      balance->phase_run[q][c][1] = sums[N_PHASE_VALUES + i] / sys->n_ranks;
      balance->phase_run[q][c][2] = extremes[3 * N_PHASE_VALUES + i];
    }
}

/* The rebalancing trigger (contact_balance.time_ratio, .entity_imbalance): after a step whose contact time max/mean
 * over the ranks or active slave points (max - min) / max exceed them, with a contact partition, the next step starts
 * from a new one (core/model/contact_partition.h). The same decision on every rank (reduced figures). */
static sk_status trigger(sk_system *sys, double ratio, const double active[3], int64_t step, int verbose) {
  const sk_model *m = sys->model;
  int partitioned = 0;
  for (int k = 0; k < m->n_pairs; ++k) partitioned |= m->pairs[k].contact_node_owner != NULL;
  const double spread = active[2] > 0.0 ? (active[2] - active[0]) / active[2] : 0.0;
  if (!partitioned || sys->n_ranks < 2 ||
      !(ratio > m->rebalance_time_ratio || spread > m->rebalance_entity_imbalance))
    return SK_OK;
  sys->contact_rebalance_pending = 1;
  if (verbose && sys->rank == 0)
    fprintf(stderr, "step %lld: contact work uneven over the ranks (max/mean contact CPU time %.2f, limit %g; active "
            "slave points (max - min)/max %.2f, limit %g): the contact partition is rebalanced at the next step\n",
            (long long)step, ratio, m->rebalance_time_ratio, spread, m->rebalance_entity_imbalance);
  return sk_contact_partition_weigh(sys);
}

sk_status sk_contact_balance_step(sk_contact_balance *balance, sk_system *sys, const sk_contact_totals *totals,
                             int64_t step, int verbose) {
  double step_seconds[3], active[3];
  reduce_min_mean_max(sys->t_contact - balance->seconds_mark, sys->comm, sys->n_ranks, step_seconds);
  reduce_min_mean_max(sys->t_contact, sys->comm, sys->n_ranks, balance->run_seconds);
  reduce_min_mean_max(totals->active_local, sys->comm, sys->n_ranks, active);
  balance->seconds_mark = sys->t_contact;
  double step_cpu[3];
  sys->contact_step_cpu = sys->t_contact_cpu - balance->cpu_mark;
  reduce_min_mean_max(sys->contact_step_cpu, sys->comm, sys->n_ranks, step_cpu);
  reduce_min_mean_max(sys->t_contact_cpu, sys->comm, sys->n_ranks, balance->run_cpu);
  balance->cpu_mark = sys->t_contact_cpu;
  double cpu_ratio = 0.0;
  if (step_cpu[1] > 0.0) {
    cpu_ratio = step_cpu[2] / step_cpu[1];
    balance->cpu_ratio_sum += cpu_ratio;
    if (balance->cpu_steps++ == 0 || cpu_ratio > balance->cpu_ratio_worst) balance->cpu_ratio_worst = cpu_ratio;
  }
  reduce_phases(balance, sys);
  reduce_min_mean_max(sys->contact_wait[0], sys->comm, sys->n_ranks, balance->run_wait);
  double ratio = 0.0;
  if (step_seconds[1] > 0.0) {
    ratio = step_seconds[2] / step_seconds[1];
    balance->ratio_sum += ratio;
    if (balance->steps++ == 0 || ratio > balance->ratio_worst) {
      balance->ratio_worst = ratio;
      balance->worst_step = step;
    }
  }
  if (balance->active_peak_step == 0 || active[1] > balance->active_peak[1]) {
    for (int i = 0; i < 3; ++i) balance->active_peak[i] = active[i];
    balance->active_peak_step = step;
  }
  if (verbose && sys->rank == 0 && sys->n_ranks > 1 && step_seconds[1] > 0.0)
    fprintf(stderr,
            "step %lld contact balance over %d ranks: evaluation %.3g / %.3g / %.3g s (min / mean / max, max/mean "
            "%.2f; CPU %.3g / %.3g / %.3g s, max/mean %.2f), active slave points %.0f / %.3g / %.0f\n",
            (long long)step, sys->n_ranks, step_seconds[0], step_seconds[1], step_seconds[2], ratio, step_cpu[0],
            step_cpu[1], step_cpu[2], cpu_ratio, active[0], active[1], active[2]);
  return trigger(sys, cpu_ratio, active, step, verbose);
}

sk_status sk_contact_balance_write(const sk_contact_balance *balance, sk_json *json) {
  static const char *const seconds_keys[3] = {"contact_seconds_rank_min", "contact_seconds_rank_mean",
                                              "contact_seconds_rank_max"};
  static const char *const active_keys[3] = {"contact_active_rank_min", "contact_active_rank_mean",
                                             "contact_active_rank_max"};
  for (int i = 0; i < 3; ++i) SK_TRY(sk_json_number(json, seconds_keys[i], balance->run_seconds[i]));
  /* NaN (null) without contact work: no ratio to speak of */
  const double none = NAN;
  SK_TRY(sk_json_number(json, "contact_imbalance_mean", balance->steps ? balance->ratio_sum / balance->steps : none));
  SK_TRY(sk_json_number(json, "contact_imbalance_worst", balance->steps ? balance->ratio_worst : none));
  SK_TRY(sk_json_int(json, "contact_imbalance_worst_step", balance->steps ? (long)balance->worst_step : 0));
  for (int i = 0; i < 3; ++i) SK_TRY(sk_json_number(json, active_keys[i], balance->active_peak[i]));
  SK_TRY(sk_json_int(json, "contact_active_peak_step", (long)balance->active_peak_step));
  static const char *const cpu_keys[3] = {"contact_cpu_seconds_rank_min", "contact_cpu_seconds_rank_mean",
                                          "contact_cpu_seconds_rank_max"};
  for (int i = 0; i < 3; ++i) SK_TRY(sk_json_number(json, cpu_keys[i], balance->run_cpu[i]));
  SK_TRY(sk_json_number(json, "contact_cpu_imbalance_mean",
                        balance->cpu_steps ? balance->cpu_ratio_sum / balance->cpu_steps : none));
  SK_TRY(sk_json_number(json, "contact_cpu_imbalance_worst", balance->cpu_steps ? balance->cpu_ratio_worst : none));
  static const char *const wait_keys[3] = {"contact_wait_seconds_rank_min", "contact_wait_seconds_rank_mean",
                                           "contact_wait_seconds_rank_max"};
  for (int i = 0; i < 3; ++i) SK_TRY(sk_json_number(json, wait_keys[i], balance->run_wait[i]));
  /* by phase: contact_<phase>_{seconds,cpu_seconds}_rank_{min,mean,max} and _imbalance_mean (per step max/mean) */
  static const char *const phases[SK_CONTACT_PHASES] = {"search", "active_set", "residual", "jacobian", "commit",
                                                        "broad_phase"};
  static const char *const clocks[2] = {"", "cpu_"}, *const stats[3] = {"min", "mean", "max"};
  for (int q = 0; q < SK_CONTACT_PHASES; ++q)
    for (int c = 0; c < 2; ++c) {
      char key[96];
      for (int i = 0; i < 3; ++i) {
        snprintf(key, sizeof key, "contact_%s_%sseconds_rank_%s", phases[q], clocks[c], stats[i]);
        SK_TRY(sk_json_number(json, key, balance->phase_run[q][c][i]));
      }
      snprintf(key, sizeof key, "contact_%s_%simbalance_mean", phases[q], clocks[c]);
      SK_TRY(sk_json_number(json, key, balance->phase_steps[q][c] ? balance->phase_ratio_sum[q][c] /
                                                                         balance->phase_steps[q][c] : none));
    }
  return SK_OK;
}
