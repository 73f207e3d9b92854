/* The stepper: steps from t_start to t_end through the system of terms (core/model/system.h), cutting a failed step
 * in half (up to time.max_cuts times in a row, never below time.dt / 2^max_cuts) and letting dt grow back after
 * three good steps; the sub-steps of a cut step land on the scheduled times t_start + n dt again; a SIGINT/SIGTERM
 * ends the run between two steps. The recorder writes the results. Everything a step is made of lives in the
 * terms. Only failures a shorter step can cure are cut: Newton's divergence, a stagnated residual and inverted
 * elements, not a failed linear solve (sk_newton_outcome in bridge.h). With the default line search
 * (full-step-then-backtrack) such a failure first solves the same step again with the backtracking line search, and
 * only a failed retry cuts it: the full step keeps its iteration count where it converges, the backtracking converges
 * what it cannot (docs/linear-solvers.md, "Line search"). */
#define _GNU_SOURCE
#include "stickslip/run.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

#include "../model/contact_partition.h"
#include "checkpoint.h"
#include "recorder.h"
#include "stickslip/interrupt.h"
#include "stickslip/output.h"

static double now_seconds(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* One attempt of the step from sys->t_n with dt: begin, Newton (with outer active-set loops, backtracking or the
 * scene's line search), commit. */
static sk_status attempt(sk_system *sys, double dt, int64_t step, int backtracking) {
  sys->backtracking = backtracking;
  SK_TRY(sk_system_begin(sys, dt, step));
  SK_TRY(sk_system_solve(sys));
  return sk_system_commit(sys);
}

static void fill_summary(const sk_system *sys, double wall_start, sk_status status, sk_run_summary *summary) {
  summary->final_time = sys->t_n;
  summary->linear_solves = sys->linear_solves;
  summary->linear_factorisations = sys->linear_factorisations;
  summary->krylov_iterations = sys->krylov_iterations;
  summary->active_set_loops = sys->active_set_loops;
  summary->pattern_builds = sys->pattern_builds;
  summary->master_reghosts = sys->master_reghosts;
  summary->contact_rebalances = sys->contact_rebalances;
  summary->unknowns_max = sys->unknowns_max;
  summary->linear_size_max = sys->linear_size_max;
  summary->assembly_seconds = sys->t_assembly;
  summary->contact_seconds = sys->t_contact;
  summary->solve_seconds = sys->t_solve;
  summary->wall_seconds = now_seconds() - wall_start;
  if (status != SK_OK) {
    summary->failed = 1;
    summary->interrupted = status == SK_ERR_INTERRUPTED;
    snprintf(summary->message, sizeof summary->message, "%s", sk_error_message());
  }
}

/* With STICKSLIP_RANK_STATS=PREFIX each rank writes PREFIX-RRRR.json at the end of the run: what it holds (elements,
 * owned and ghost nodes, unknowns), the bytes it sent point to point (ghost exchanges and the linear system's
 * off-rank entries), its Newton iterations, CPU seconds, peak resident memory and the phases' wall seconds. The
 * scaling bench reads them (tests/bench/scaling, docs/scaling.md). */
static void write_rank_stats(const sk_system *sys, const sk_run_summary *summary) {
  const char *prefix = getenv("STICKSLIP_RANK_STATS");
  if (!prefix || !prefix[0]) return;
  const sk_model *m = sys->model;
  char path[4200];
  snprintf(path, sizeof path, "%s-%04d.json", prefix, m->rank);
  int elements_owned = 0, nodes_owned = 0, nodes_ghost = 0;
  for (int e = 0; e < m->n_elements; ++e) elements_owned += m->element_part[e] == m->rank;
  for (int a = 0; a < m->n_nodes; ++a) {
    nodes_owned += m->node_owner[a] == m->rank;
    nodes_ghost += sys->node_role[a] == SK_NODE_GHOST;
  }
  struct rusage usage;
  getrusage(RUSAGE_SELF, &usage);
  const double cpu = (double)usage.ru_utime.tv_sec + 1e-6 * (double)usage.ru_utime.tv_usec +
                     (double)usage.ru_stime.tv_sec + 1e-6 * (double)usage.ru_stime.tv_usec;
  sk_json *json;
  if (sk_json_open(path, &json) != SK_OK) {
    fprintf(stderr, "warning: STICKSLIP_RANK_STATS: %s\n", sk_error_message());
    return;
  }
  sk_json_int(json, "rank", m->rank);
  sk_json_int(json, "ranks", m->n_ranks);
  sk_json_int(json, "elements_owned", elements_owned);
  sk_json_int(json, "elements_held", m->n_elements);
  sk_json_int(json, "nodes_owned", nodes_owned);
  sk_json_int(json, "nodes_ghost", nodes_ghost); /* exchanged (at the end of the run) */
  /* kept but not exchanged: the master nodes outside the faces held at the end of the run (master_ghosts.h) */
  sk_json_int(json, "nodes_idle", m->n_nodes - nodes_owned - nodes_ghost);
  sk_json_int(json, "unknowns_held", (long)sys->n);
  sk_json_int(json, "unknowns_owned", (long)sys->n_owned);
  sk_json_number(json, "exchange_bytes_sent", (double)(sys->ghost_dofs.bytes_sent + sys->ghost_extras.bytes_sent));
  sk_json_number(json, "linear_system_bytes_sent", sys->linsys ? (double)sk_linsys_bytes_sent(sys->linsys) : 0.0);
  sk_json_int(json, "newton_iterations", summary->newton_iterations);
  sk_json_int(json, "steps", summary->steps);
  sk_json_number(json, "cpu_seconds", cpu);
  sk_json_number(json, "peak_rss_kib", (double)usage.ru_maxrss);
  sk_json_number(json, "wall_seconds", summary->wall_seconds);
  sk_json_number(json, "assembly_seconds", sys->t_assembly);
  sk_json_number(json, "contact_seconds", sys->t_contact);
  sk_json_number(json, "solve_seconds", sys->t_solve);
  /* settling the pattern at the attempts' starts (system.h: t_pattern), outside the phases above */
  sk_json_int(json, "pattern_builds", sys->pattern_builds);
  sk_json_number(json, "pattern_seconds", sys->t_pattern[0]);
  sk_json_number(json, "pattern_cpu_seconds", sys->t_pattern[1]);
  sk_json_number(json, "pattern_build_cpu_seconds", sys->t_pattern_build[1]);
  sk_json_number(json, "pattern_bridge_cpu_seconds", sys->t_pattern_bridge[1]);
  sk_json_number(json, "pattern_keys_declared", (double)sys->pattern_keys_declared);
  sk_json_number(json, "pattern_keys_kept", (double)sys->pattern_keys_kept);
  if (sk_json_close(json) != SK_OK) fprintf(stderr, "warning: STICKSLIP_RANK_STATS: %s\n", sk_error_message());
}

/* The n-th scheduled time t_start + n dt (the last one is t_end): computed, never accumulated, so that the times of
 * the schedule do not drift by a round-off per step. */
static double scheduled_time(const sk_time_options *time, int64_t n) {
  return fmin(time->t_start + (double)n * time->dt, time->t_end);
}

/* The step from t_n with the current dt, stopped at the next scheduled time `target`; a rest below t_eps is taken
 * with it, so that the step lands on the schedule exactly instead of leaving a round-off sliver. */
static double step_size(double t_n, double dt, double target, double t_eps) {
  return target - (t_n + dt) < t_eps ? target - t_n : dt;
}

/* Polled before every step attempt (collective, so that all ranks stop after the same step). */
static sk_status interrupted(const sk_system *sys, int steps) {
  const int signal_number = sk_interrupt_agreed(sys->comm);
  if (!signal_number) return SK_OK;
  return sk_error_set(SK_ERR_INTERRUPTED, "interrupted by %s after step %d (t = %.6g)",
                      sk_interrupt_name(signal_number), steps, sys->t_n);
}

/* The Newton work of the attempt just made, into the run's counts. */
static void count_attempt(const sk_system *sys, sk_run_summary *summary) {
  summary->newton_iterations += sys->newton.iterations;
  summary->newton_backtrack_switches += sys->newton.switched_to_backtrack;
}

/* The failed attempt of `step` solved again from its start with the backtracking line search. A linear solver that
 * fails on the retry's iterates (a singular matrix on a shortened step) is no reason to stop a run the full step's
 * failure would have cut: it returns SK_ERR_DIVERGED with both reasons, and the stepper cuts. */
static sk_status retry_backtracking(sk_system *sys, double dt, int64_t step, int verbose, sk_run_summary *summary) {
  char first[600];
  snprintf(first, sizeof first, "%s", sk_error_message());
  sk_system_reject(sys);
  summary->backtrack_retries++;
  if (sys->rank == 0 && verbose)
    fprintf(stderr, "step %lld at t = %.6g: %s — solving it again with the backtracking line search\n",
            (long long)step, sys->t_n, first);
  sk_status status = attempt(sys, dt, step, 1);
  count_attempt(sys, summary);
  if (status == SK_OK) summary->backtrack_rescues++;
  if (status == SK_ERR_LINEAR_SOLVER)
    status = sk_error_set(SK_ERR_DIVERGED, "%s; with backtracking: %s", first, sk_error_message());
  return status;
}

/* The stepper's counters for a checkpoint, or from a restart. */
static void note_progress(sk_progress *p, const sk_run_summary *summary, int64_t scheduled, int substep, double dt,
                          int cuts_in_a_row, int good_steps) {
  p->steps = summary->steps;
  p->scheduled = scheduled;
  p->substep = substep;
  p->dt = dt;
  p->cuts_in_a_row = cuts_in_a_row;
  p->good_steps = good_steps;
  p->newton_iterations = summary->newton_iterations;
  p->cuts = summary->cuts;
}

sk_status sk_run(sk_scene *scene, const sk_run_options *options, sk_run_summary *summary) {
  const double wall_start = now_seconds();
  memset(summary, 0, sizeof *summary);
  sk_model *m = &scene->model;
  sk_system *sys = scene->system;
  sys->verbose = options->verbose;
  const sk_time_options *time = &m->time;
  sk_recorder *rec = NULL;
  sk_status status = sk_system_collective(sys, sk_recorder_open(scene, sys, options, wall_start, &rec));
  if (status == SK_OK) status = sk_checkpoint_check(sys, options);
  sk_progress progress = {.dt = time->dt};
  if (status == SK_OK && options->restart) {
    status = sk_restart_apply(options->restart, sys, &progress);
    if (status == SK_OK) status = sk_system_collective(sys, sk_recorder_resume(rec, options->restart));
  } else if (status == SK_OK) {
    status = sk_recorder_initial(rec);
  }
  summary->steps = (int)progress.steps;
  summary->newton_iterations = (int)progress.newton_iterations;
  summary->cuts = (int)progress.cuts;
  if (options->progress && m->rank == 0) sk_progress_begin(scene->path, time->t_end);
  if (options->verbose && m->rank == 0 && m->contact_rebalance) sk_contact_partition_explain(m, stderr);

  const double t_eps = 1e-12 * fmax(1.0, fabs(time->t_end));
  double dt = progress.dt;
  int cuts_in_a_row = progress.cuts_in_a_row, good_steps = progress.good_steps;
  int64_t scheduled = progress.scheduled; /* scheduled times reached */
  int substep = progress.substep;         /* converged sub-steps since the last scheduled time */
  int steps_here = 0;                     /* this run's steps (--steps counts these) */
  while (status == SK_OK && sys->t_n < time->t_end - t_eps) {
    if (options->max_steps > 0 && steps_here >= options->max_steps) break;
    if ((status = interrupted(sys, summary->steps)) != SK_OK) break;
    const double target = scheduled_time(time, scheduled + 1);
    const double step_dt = step_size(sys->t_n, dt, target, t_eps);
    const int on_schedule = step_dt == target - sys->t_n;
    const int64_t step = summary->steps + 1;
    if (sys->linsys) { /* the run's projected length, for `auto`'s exploration budget */
      double left = ceil((time->t_end - sys->t_n) / time->dt - 1e-9);
      if (options->max_steps > 0) left = fmin(left, (double)(options->max_steps - steps_here));
      sk_linsys_set_steps_left(sys->linsys, (int)fmax(1.0, fmin(left, 1e9)));
    }
    status = attempt(sys, step_dt, step, 0);
    count_attempt(sys, summary);
    if ((status == SK_ERR_DIVERGED || status == SK_ERR_INVERTED) && scene->solver.backtrack_retry)
      status = retry_backtracking(sys, step_dt, step, options->verbose, summary);
    if (status == SK_OK) {
      summary->steps++;
      steps_here++;
      /* accepted at the residual's round-off floor: a warning for the first few, all counted in summary.json */
      if (sys->newton.outcome == SK_NEWTON_ROUNDOFF_FLOOR && ++summary->roundoff_floor_steps <= 3 && m->rank == 0)
        fprintf(stderr, "stickslip: warning: step %lld (t = %.6g): Newton %s%s\n", (long long)step, sys->t,
                sys->newton.reason, summary->roundoff_floor_steps == 3 ? " (further such steps are counted in "
                "summary.json, roundoff_floor_steps)" : "");
      if (on_schedule) {
        sys->t = target; /* t_n + (target - t_n) may differ from target in the last bit */
        scheduled++;
        substep = 0;
      } else {
        substep++;
      }
      const int last = !(sys->t < time->t_end - t_eps) || (options->max_steps > 0 && steps_here >= options->max_steps);
      status = sk_recorder_step(rec, scheduled, substep, last);
      cuts_in_a_row = 0;
      if (dt < time->dt && ++good_steps >= 3) {
        dt = fmin(time->dt, 2.0 * dt);
        good_steps = 0;
      }
      if (status == SK_OK && options->checkpoint_every > 0 && summary->steps % options->checkpoint_every == 0) {
        /* the state spanning the step (before it advances), the counters as the next step starts with them */
        sk_progress now;
        note_progress(&now, summary, scheduled, substep, dt, cuts_in_a_row, good_steps);
        sk_recorder_state state;
        sk_recorder_checkpoint_state(rec, &state);
        status = sk_checkpoint_write(options, sys, &now, &state);
      }
      sk_system_advance(sys);
      if (options->progress && m->rank == 0) {
        char extra[128];
        snprintf(extra, sizeof extra, "dt %.3g  E %.6g", step_dt, sk_recorder_total_energy(rec));
        sk_progress_update(summary->steps, sys->t_n, sys->newton.iterations, extra);
      }
    } else if (status == SK_ERR_DIVERGED || status == SK_ERR_INVERTED) {
      /* cut the step and retry */
      sk_system_reject(sys);
      summary->cuts++;
      /* dt never goes below time.dt / 2^max_cuts: good sub-steps in between reset the count of cuts in a row, and a
       * step that fails at a floor a shorter step cannot lower (Newton stagnating at round-off) would otherwise halve
       * on and on (measured: a block on a plane at penalty 1e8 crept down to dt = 1.8e-16 before the run failed) */
      const int at_smallest_step = dt <= time->dt * ldexp(1.0, -time->max_cuts) * (1.0 + 1e-9);
      if (++cuts_in_a_row > time->max_cuts || at_smallest_step) {
        char reason[600], where[256];
        snprintf(reason, sizeof reason, "%s", sk_error_message());
        sk_system_describe_worst(sys, where, sizeof where);
        char cuts[96];
        if (cuts_in_a_row > time->max_cuts) snprintf(cuts, sizeof cuts, "after %d step cuts", time->max_cuts);
        else snprintf(cuts, sizeof cuts, "at the smallest step time.dt / 2^%d", time->max_cuts);
        status = sk_error_set(SK_ERR_DIVERGED, "step %lld from t = %.6g: no convergence %s (dt = %.3g): %s%s%s",
                              (long long)step, sys->t_n, cuts, step_dt, reason, where[0] ? "; " : "", where);
        break;
      }
      if (m->rank == 0 && options->verbose)
        fprintf(stderr, "step %lld at t = %.6g: %s — cutting dt to %.3g\n", (long long)step, sys->t_n,
                sk_error_message(), 0.5 * step_dt);
      dt = 0.5 * step_dt;
      good_steps = 0;
      status = SK_OK;
    } else if (status == SK_ERR_LINEAR_SOLVER) {
      sk_error_prefix(status, "step %lld from t = %.6g (dt = %.3g), not cut (a shorter step does not help here): ",
                      (long long)step, sys->t_n, step_dt);
    }
  }
  if (options->progress && m->rank == 0)
    sk_progress_end(status == SK_OK ? NULL : status == SK_ERR_INTERRUPTED ? "interrupted" : "failed");
  fill_summary(sys, wall_start, status, summary);
  write_rank_stats(sys, summary);
  if (rec) status = sk_recorder_close(rec, summary, status);
  sk_recorder_free(rec);
  return status;
}
