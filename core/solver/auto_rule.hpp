// stickslip — the comparison `auto` makes between its measured candidates, free of Trilinos so that it can be
// tested on given costs (tests/unit/bridge/test_auto_rule.cpp). auto_choice.cpp feeds it its measurements.
#pragma once

namespace stickslip::bridge {

// What `auto` predicts for one candidate on the system at hand.
struct AutoEstimate {
  bool eligible = false;        // may run here (no failure on this pattern, not in back-off, measured at this size)
  double solve_seconds = 0;     // CPU seconds of one solve at this size and tolerance, one-time set-ups excluded
  double setup_seconds = 0;     // CPU seconds of its one-time set-up (symbolic factorisation, AMG hierarchy)
  double setups_per_solve = 0;  // how often that set-up recurs per solve from now on
};

// The cost `auto` compares: a solve plus the share of the set-up that recurs with it. Every candidate is charged
// alike; a set-up that is paid once (an AMG hierarchy kept across patterns) is not spread over the few solves of a
// trial, which made GMRES + MueLu look 4x dearer than it is.
double auto_cost_per_solve(const AutoEstimate &estimate);

// The cheapest eligible candidate; the current one (if eligible) is kept unless another is cheaper by
// `switch_margin` (measurements are noisy on a shared machine). -1 if none is eligible.
int auto_cheapest(const AutoEstimate *estimates, int count, int current, double switch_margin);

// Decimal digits a Krylov solve to relative residual `tolerance` gains (at least 1): its iterations, and so its
// cost, grow with them. Measurements taken at one tolerance are compared at another by this factor.
double tolerance_digits(double tolerance);

// A trial `auto` considers: what it is expected to cost beyond the leader's solves, against what the rest of the
// run can repay. Solve counts are projections (the stepper's steps left times the solves per step so far).
struct AutoTrial {
  double solves_left = -1;         // projected solves from this one on; < 0: unknown (every trial is affordable)
  double solves_total = 0;         // projected solves of the whole run (those made and those left)
  int trial_solves = 1;            // solves the trial takes
  double extra_seconds = 0;        // its expected cost beyond that of the leader's solves it replaces
  double setup_seconds = 0;        // the one-time set-up it would pay first (a hierarchy, an analysis not yet made)
  double optimistic_seconds = 0;   // the least the candidate can cost per solve afterwards
  double leader_seconds = 0;       // the leader's (cheapest measured candidate's) cost per solve
  double spent_seconds = 0;        // what the trials so far cost beyond the leader's solves
  double share = 0;                // the part of the run's projected solve time exploration may take
};

// nullptr if the trial is worth starting; otherwise why not: too few solves left to use its result, its expected
// extra cost (its set-up included) exceeds what the candidate could save over the rest of the run at its optimistic
// cost, or the exploration so far plus this trial would exceed `share` of the projected linear-solve time at the
// leader's cost.
const char *auto_trial_refusal(const AutoTrial &trial);

// Whether a trial that has measured its candidate (`trial`) ends before its planned solves: the candidate would not
// be chosen over the candidate it is measured against (`holder`), its cost per solve times `switch_margin` not below
// the holder's. Its later solves would have to be cheaper than its first by more than the margin to change that,
// and a preconditioner kept across solves (MueLu's aggregates) ages on a drifting matrix: on the 2D Hertz quad9
// refine 1 GMRES + MueLu took 19, 25 and 26 iterations in its trial's three solves.
bool auto_trial_lost(const AutoEstimate &trial, const AutoEstimate &holder, double switch_margin);

}  // namespace stickslip::bridge
