// auto_rule: the comparison `auto` makes, on given costs — set-ups charged as often as they recur (never spread
// over the few solves of a trial), a candidate that failed never chosen, a switch only for a clear advantage, Krylov
// costs compared at the same tolerance.
#include "auto_rule.hpp"
#include "sk_test.h"

using stickslip::bridge::auto_cheapest;
using stickslip::bridge::auto_cost_per_solve;
using stickslip::bridge::AutoEstimate;
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

}  // namespace

int main() {
  check_setup_apart();
  check_failed_excluded();
  check_margin();
  check_tolerance_digits();
  return sk_test_finish("bridge auto rule");
}
