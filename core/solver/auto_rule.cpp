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

const char *auto_trial_refusal(const AutoTrial &t) {
  if (t.solves_left < 0) return nullptr;  // a run of unknown length: explore
  const double after = t.solves_left - t.trial_solves;
  if (after < 1) return "too few solves left to use its result";
  const double cost = t.extra_seconds + t.setup_seconds;  // a trial pays its candidate's set-up before a solve
  if (cost >= std::max(0.0, t.leader_seconds - t.optimistic_seconds) * after)
    return "it could not repay its trial in the solves left";
  if (t.spent_seconds + cost > t.share * t.leader_seconds * t.solves_total)
    return "the exploration budget of this run is spent";
  return nullptr;
}

bool auto_trial_lost(const AutoEstimate &trial, const AutoEstimate &holder, double switch_margin) {
  return trial.eligible && holder.eligible &&
         auto_cost_per_solve(trial) * switch_margin >= auto_cost_per_solve(holder);
}

}  // namespace stickslip::bridge
