// stickslip — the comparison `auto` makes between measured candidates (auto_rule.hpp).
#include "auto_rule.hpp"

#include <algorithm>
#include <cmath>

namespace stickslip::bridge {

double auto_cost_per_solve(const AutoEstimate &estimate) {
  return estimate.solve_seconds + estimate.setup_seconds * estimate.setups_per_solve;
}

int auto_cheapest(const AutoEstimate *estimates, int count, int current, double switch_margin) {
  int best = current >= 0 && current < count && estimates[current].eligible ? current : -1;
  // a newcomer must beat the current candidate by the margin; among newcomers, the cheapest
  int newcomer = -1;
  for (int c = 0; c < count; ++c) {
    if (!estimates[c].eligible || c == best) continue;
    if (newcomer < 0 || auto_cost_per_solve(estimates[c]) < auto_cost_per_solve(estimates[newcomer])) newcomer = c;
  }
  if (newcomer < 0) return best;
  if (best < 0) return newcomer;
  return auto_cost_per_solve(estimates[newcomer]) * switch_margin < auto_cost_per_solve(estimates[best]) ? newcomer
                                                                                                         : best;
}

double tolerance_digits(double tolerance) {
  return tolerance > 0 && tolerance < 0.1 ? -std::log10(tolerance) : 1.0;
}

}  // namespace stickslip::bridge
