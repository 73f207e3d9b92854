// auto_rule: the comparison `auto` makes, on given costs — set-ups charged as often as they recur (never spread
// over the few solves of a trial), a candidate that failed never chosen, a switch only for a clear advantage, Krylov
// costs compared at the same tolerance; a trial priced with its candidate's set-up, and ended once its candidate
// has lost.
#include "auto_rule.hpp"
#include "sk_test.h"

using stickslip::bridge::auto_cheapest;
using stickslip::bridge::auto_cost_per_solve;
using stickslip::bridge::auto_trial_lost;
using stickslip::bridge::auto_trial_refusal;
using stickslip::bridge::AutoEstimate;
using stickslip::bridge::AutoTrial;
using stickslip::bridge::tolerance_digits;

namespace {

enum { kMumps, kMuelu, kSgs, kJacobi, kCount };

AutoEstimate candidate(bool eligible, double solve, double setup = 0, double setups_per_solve = 0) {
  AutoEstimate e;
  e.eligible = eligible;
  e.solve_seconds = solve;
  e.setup_seconds = setup;
  e.setups_per_solve = setups_per_solve;
  return e;
}

// The 3D Hertz tet4 case of the measurement: GMRES + MueLu 1.6 s per solve after a 13.9 s hierarchy (a 3-solve
// trial averaged 6.24 s), GMRES + Jacobi 2.5 s per solve. The hierarchy is kept across patterns: MueLu wins.
void check_setup_apart() {
  AutoEstimate e[kCount] = {candidate(false, 0), candidate(true, 1.6, 13.9, 0.0), candidate(false, 0),
                            candidate(true, 2.5)};
  SK_CHECK(auto_cheapest(e, kCount, kJacobi, 1.2) == kMuelu);
  SK_CHECK(auto_cheapest(e, kCount, kMuelu, 1.2) == kMuelu);
  // the set-up spread over a 3-solve trial, as before: Jacobi would have been taken
  AutoEstimate spread[kCount] = {candidate(false, 0), candidate(true, (3 * 1.6 + 13.9) / 3), candidate(false, 0),
                                 candidate(true, 2.5)};
  SK_CHECK(auto_cheapest(spread, kCount, kMuelu, 1.2) == kJacobi);
  // a set-up that recurs at every pattern (a direct analysis) is charged at its rate: 1 s + 2 s / 2 solves
  AutoEstimate direct[kCount] = {candidate(true, 1.0, 2.0, 0.5), candidate(true, 1.8), candidate(false, 0),
                                 candidate(false, 0)};
  SK_CHECK_CLOSE(auto_cost_per_solve(direct[kMumps]), 2.0, 1e-15);
  SK_CHECK(auto_cheapest(direct, kCount, kMumps, 1.2) == kMumps);  // 1.8 * 1.2 > 2.0: no switch
  direct[kMumps].setups_per_solve = 1.0;                            // a new pattern at every solve: 3 s
  SK_CHECK(auto_cheapest(direct, kCount, kMumps, 1.2) == kMuelu);
}

// A candidate that failed (not eligible) is never chosen, however cheap it measured; if the current one failed,
// the cheapest eligible one takes over without a margin; nothing eligible: -1.
void check_failed_excluded() {
  AutoEstimate e[kCount] = {candidate(true, 3.0), candidate(true, 2.0), candidate(false, 0.1),
                            candidate(false, 0.05)};
  SK_CHECK(auto_cheapest(e, kCount, kMumps, 1.2) == kMuelu);
  SK_CHECK(auto_cheapest(e, kCount, kJacobi, 1.2) == kMuelu);
  e[kMuelu].eligible = false;
  SK_CHECK(auto_cheapest(e, kCount, kJacobi, 1.2) == kMumps);
  e[kMumps].eligible = false;
  SK_CHECK(auto_cheapest(e, kCount, kMumps, 1.2) == -1);
}

// The current candidate keeps its place unless another is cheaper by the margin.
void check_margin() {
  AutoEstimate e[kCount] = {candidate(true, 1.0), candidate(true, 0.9), candidate(true, 0.95), candidate(false, 0)};
  SK_CHECK(auto_cheapest(e, kCount, kMumps, 1.2) == kMumps);
  e[kSgs].solve_seconds = 0.8;
  SK_CHECK(auto_cheapest(e, kCount, kMumps, 1.2) == kSgs);
  SK_CHECK(auto_cheapest(e, kCount, -1, 1.2) == kSgs);  // nothing current: the cheapest
}

// Krylov costs scale with the digits the solve gains: a measurement at 1e-4 is 2.5x dearer at 1e-10.
void check_tolerance_digits() {
  SK_CHECK_CLOSE(tolerance_digits(1e-10), 10.0, 1e-12);
  SK_CHECK_CLOSE(tolerance_digits(1e-4), 4.0, 1e-12);
  SK_CHECK_CLOSE(tolerance_digits(0.5), 1.0, 0.0);
  SK_CHECK_CLOSE(tolerance_digits(0.0), 1.0, 0.0);
}

// The exploration budget, on the 3D Hertz tet4 refine 2 costs (4 steps, 21 solves; GMRES + MueLu the leader at
// 0.043 s per solve, a MUMPS factorisation 0.28 s): the lagged LU's window (8 solves, its first a factorisation) and
// MUMPS's one-solve trial are refused on a run of 21 solves, the window taken on one of 400 (MUMPS, dearer than the
// leader, never); a capped iterative trial (one leader solve of expected waste) fits the budget of 21 solves once
// (5 %: 1.05 leader solves), not twice; no trial without solves left to use its result; a run of unknown length
// explores.
AutoTrial tet4_trial(double solves_left, double solves_total, int trial_solves, double extra, double optimistic,
                     double spent) {
  AutoTrial t;
  t.solves_left = solves_left;
  t.solves_total = solves_total;
  t.trial_solves = trial_solves;
  t.extra_seconds = extra;
  t.optimistic_seconds = optimistic;
  t.leader_seconds = 0.043;
  t.spent_seconds = spent;
  t.share = 0.05;
  return t;
}

void check_exploration_budget() {
  const double leader = 0.043, factorisation = 0.28;
  // short run (19 solves left of 21): the factorising trials cost more than the budget (0.05 x 21 x 0.043 = 0.045 s)
  const AutoTrial lagged_short = tet4_trial(19, 21, 8, factorisation - leader, 0.0, 0.0);
  SK_CHECK(auto_trial_refusal(lagged_short) != nullptr);
  const AutoTrial mumps_short = tet4_trial(19, 21, 1, factorisation - leader, factorisation, 0.0);
  SK_CHECK(auto_trial_refusal(mumps_short) != nullptr);  // cannot beat the leader even at its optimistic cost
  // capped iterative trials: one within the budget, not a second
  SK_CHECK(auto_trial_refusal(tet4_trial(19, 21, 3, leader, 0.0, 0.0)) == nullptr);
  SK_CHECK(auto_trial_refusal(tet4_trial(16, 21, 3, leader, 0.0, leader)) != nullptr);
  // long run (398 solves left): the lagged LU's window is worth its factorisation; MUMPS still cannot win
  SK_CHECK(auto_trial_refusal(tet4_trial(398, 400, 8, factorisation - leader, 0.0, 0.0)) == nullptr);
  SK_CHECK(auto_trial_refusal(tet4_trial(398, 400, 1, factorisation - leader, factorisation, 0.0)) != nullptr);
  // no solves left after the trial
  SK_CHECK(auto_trial_refusal(tet4_trial(3, 21, 3, 0.0, 0.0, 0.0)) != nullptr);
  SK_CHECK(auto_trial_refusal(tet4_trial(4, 21, 3, 0.0, 0.0, 0.0)) == nullptr);
  // unknown length: every trial
  SK_CHECK(auto_trial_refusal(tet4_trial(-1, 0, 8, 10.0, 0.0, 10.0)) == nullptr);
}

// A trial pays its candidate's one-time set-up. The 2D Hertz quad9 refine 1 (measured, 19 solves): the lagged LU
// leads at 0.033 s per solve after its window of 8, 15 solves projected left; GMRES + MueLu's trial (3 solves, its
// hierarchy priced at MUMPS's measured analysis, 0.036 s) exceeds the run's 5 % budget (0.05 x 23 x 0.033 = 0.038 s)
// with its set-up and fits it without; on a run of 400 solves it is taken. A set-up larger than all the candidate
// could save (the leader's cost over the solves after the trial) refuses it whatever the budget.
void check_trial_setup() {
  AutoTrial t;
  t.solves_left = 15;
  t.solves_total = 23;
  t.trial_solves = 3;
  t.extra_seconds = 0.033;  // a capped iterative trial: about one solve of the leader wasted
  t.leader_seconds = 0.033;
  t.share = 0.05;
  SK_CHECK(auto_trial_refusal(t) == nullptr);
  t.setup_seconds = 0.036;
  SK_CHECK(auto_trial_refusal(t) != nullptr);
  t.solves_left = 398;
  t.solves_total = 400;
  SK_CHECK(auto_trial_refusal(t) == nullptr);
  t.share = 1.0;  // no budget to speak of: only what it could save limits it
  t.setup_seconds = 0.033 * 393;  // with the solve wasted: 394 of the 395 leader solves after the trial
  SK_CHECK(auto_trial_refusal(t) == nullptr);
  t.setup_seconds = 0.033 * 395;
  SK_CHECK(auto_trial_refusal(t) != nullptr);
}

// A trial ends once its candidate would not be chosen over the one it is measured against (its cost times the
// switch margin not below the holder's), and not before: GMRES + MueLu's first solve on the 2D Hertz quad9 refine
// 1.6 (0.19 s against the lagged LU's 0.20 s) ends its trial, on quad4 refine 2 (0.020 s against 0.034 s) it goes
// on; a candidate not measured (or a holder not measured) decides nothing.
void check_trial_lost() {
  SK_CHECK(auto_trial_lost(candidate(true, 0.19), candidate(true, 0.20), 1.2));
  SK_CHECK(!auto_trial_lost(candidate(true, 0.19), candidate(true, 0.20), 1.0));  // without the margin: goes on
  SK_CHECK(auto_trial_lost(candidate(true, 0.25), candidate(true, 0.20), 1.0));
  SK_CHECK(!auto_trial_lost(candidate(true, 0.020), candidate(true, 0.034), 1.2));
  SK_CHECK(!auto_trial_lost(candidate(false, 0.19), candidate(true, 0.20), 1.2));
  SK_CHECK(!auto_trial_lost(candidate(true, 0.19), candidate(false, 0.20), 1.2));
  // a recurring set-up counts as in the comparison: 0.02 s + 0.04 s analysis per solve against 0.06 s
  SK_CHECK(auto_trial_lost(candidate(true, 0.02, 0.04, 1.0), candidate(true, 0.06), 1.2));
  SK_CHECK(!auto_trial_lost(candidate(true, 0.02, 0.04, 0.0), candidate(true, 0.06), 1.2));
}

}  // namespace

int main() {
  check_trial_setup();
  check_trial_lost();
  check_exploration_budget();
  check_setup_apart();
  check_failed_excluded();
  check_margin();
  check_tolerance_digits();
  return sk_test_finish("bridge auto rule");
}
