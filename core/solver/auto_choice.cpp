// stickslip — what `auto` runs: the direct solver (MUMPS) or GMRES + MueLu, from what it has measured.
//
// 1. Never a solver that failed on this pattern; after a failure GMRES waits 2, 4, 8 ... patterns before it is
//    tried again (a contact run changes pattern every few steps: before this rule GMRES was retried, and failed,
//    at every one of them: 39 of 39 on scenes/two-tori-coarse.yaml).
// 2. Not GMRES when the nodal block has a zero diagonal (a saddle point given without coordinates, so without a
//    constraint block to take the multiplier rows).
// 3. Both candidates measured at about this size (within kMeasuredRange in stored entries): the cheaper one per
//    solve, set-ups included; a switch needs a kSwitchMargin advantage.
// 4. Otherwise the size rule of the elasticity benchmark (docs/linear-solvers.md): direct up to 10 000 unknowns
//    at <= 40 entries per row (2D-like), up to 2 000 above (3D-like). Within kContestedBand of that crossover the
//    rule is only a first guess: once the chosen solver has a measurement, the other one is tried for
//    kTrialSolves solves, and 3. decides from then on.
// Measurements are kept across pattern changes as cost coefficients (seconds / entries^p, p the measured growth),
// so a pattern that gains a few contact entries keeps its decision. Every decision is logged once, with its reason.
#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>

#include "linear_system.hpp"

namespace stickslip::bridge {

namespace {

constexpr int kAutoSparseRowEntries = 40;
constexpr int kAutoDirectMaxUnknownsSparse = 10000;
constexpr int kAutoDirectMaxUnknownsDense = 2000;
constexpr double kContestedBand = 4.0;
// Growth of the cost per solve with the size (docs/linear-solvers.md): MUMPS n^1.6 on hex8, GMRES + MueLu n^1.1.
constexpr double kDirectExponent = 1.6;
constexpr double kIterativeExponent = 1.1;
constexpr double kMeasuredRange = 2.0;
constexpr double kSwitchMargin = 1.2;
constexpr int kTrialSolves = 3;  // the first pays the set-up (symbolic factorisation / AMG hierarchy)
// A diagonal below this fraction of its row's largest entry counts as zero (`reduced` multiplier rows: 1e-23).
constexpr double kZeroDiagonal = 1e-12;
// What `direct` (and AUTO's direct choice) runs: the fastest correct backend on the benchmark's hex8/quad4
// elasticity and on the contact saddle-point systems (docs/linear-solvers.md).
constexpr sk_linear_solver_kind kDirectBackend = SK_LINEAR_DIRECT_MUMPS;
constexpr sk_linear_solver_kind kIterativeBackend = SK_LINEAR_GMRES_MUELU;

AutoMemory::Candidate &candidate(AutoMemory &memory, sk_linear_solver_kind kind) {
  return is_direct(kind) ? memory.direct : memory.iterative;
}

double exponent(sk_linear_solver_kind kind) { return is_direct(kind) ? kDirectExponent : kIterativeExponent; }

double entries(const sk_linear_system *sys) { return static_cast<double>(sys->row_ptr[sys->n]); }

bool measured_here(const AutoMemory::Candidate &c, double size) {
  return c.cost_coefficient > 0 && size <= kMeasuredRange * static_cast<double>(c.entries_measured) &&
         static_cast<double>(c.entries_measured) <= kMeasuredRange * size;
}

double predicted_seconds(const AutoMemory::Candidate &c, sk_linear_solver_kind kind, double size) {
  return c.cost_coefficient * std::pow(size, exponent(kind));
}

// A zero (or absent) diagonal in the nodal block, on any rank (collective).
bool nodal_diagonal_deficient(const sk_linear_system *sys) {
  int deficient = 0;
  const int first_row = sys->row_offsets[sys->rank];
  const int end = std::min(sys->row_offsets[sys->rank + 1], sys->n_nodal);
  for (int row = first_row; row < end && !deficient; ++row) {
    const int64_t d = sys->owned_diagonal[row - first_row];
    double largest = 0;
    for (int64_t k = sys->row_ptr[row]; k < sys->row_ptr[row + 1]; ++k)
      largest = std::max(largest, std::fabs(sys->owned_values[k - sys->owned_value_begin]));
    deficient = d < 0 || !(std::fabs(sys->owned_values[d]) > kZeroDiagonal * largest);
  }
  int any = 0;
  MPI_Allreduce(&deficient, &any, 1, MPI_INT, MPI_MAX, sys->comm);
  return any != 0;
}

// Takes the decision; it is logged when the solver or the kind of reason changes.
sk_linear_solver_kind decide(sk_linear_system *sys, sk_linear_solver_kind kind, const char *reason_class,
                             const std::string &reason) {
  AutoMemory &m = sys->auto_memory;
  if (kind != m.current || m.reason_class != reason_class) {
    m.decision = std::string(sk_linear_solver_name(kind)) + ": " + reason;
    m.decision_pending = true;
  }
  m.current = kind;
  m.reason_class = reason_class;
  return kind;
}

std::string format(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
std::string format(const char *fmt, ...) {
  char text[320];
  va_list args;
  va_start(args, fmt);
  std::vsnprintf(text, sizeof text, fmt, args);
  va_end(args);
  return text;
}

}  // namespace

sk_linear_solver_kind auto_choose(sk_linear_system *sys) {
  AutoMemory &m = sys->auto_memory;
  const int generation = sys->pattern_generation;
  const double size = entries(sys);
  const double per_row = sys->n > 0 ? size / sys->n : 0.0;
  const char *direct_name = sk_linear_solver_name(kDirectBackend);
  const char *iterative_name = sk_linear_solver_name(kIterativeBackend);

  if (m.iterative.failed_on_pattern == generation)
    return decide(sys, kDirectBackend, "failed", format("%s failed on this pattern (%s)", iterative_name,
                                                        m.iterative_failure.c_str()));
  if (generation < m.iterative.retry_pattern)
    return decide(sys, kDirectBackend, "backoff",
                  format("%s failed on %d pattern(s) in a row; tried again from the %d. pattern on", iterative_name,
                         m.iterative.failures_in_a_row, m.iterative.retry_pattern));
  if (nodal_diagonal_deficient(sys))
    return decide(sys, kDirectBackend, "diagonal",
                  "a zero diagonal in the nodal block (a saddle point: multiplier rows without coordinates to "
                  "split them off), which AMG's smoothers divide by");
  if (m.trial_solves_left > 0) {
    --m.trial_solves_left;
    return m.current;
  }

  const bool direct_known = measured_here(m.direct, size), iterative_known = measured_here(m.iterative, size);
  if (direct_known && iterative_known) {
    const double t_direct = predicted_seconds(m.direct, kDirectBackend, size);
    const double t_iterative = predicted_seconds(m.iterative, kIterativeBackend, size);
    // switch only for a clear advantage (timings are noisy on a shared machine)
    sk_linear_solver_kind kind = t_iterative < t_direct ? kIterativeBackend : kDirectBackend;
    if (m.current != SK_LINEAR_AUTO && kind != m.current &&
        std::max(t_direct, t_iterative) < kSwitchMargin * std::min(t_direct, t_iterative))
      kind = m.current;
    return decide(sys, kind, "measured",
                  format("measured %.3g s per solve against %s %.3g s (%d unknowns)",
                         is_direct(kind) ? t_direct : t_iterative,
                         is_direct(kind) ? iterative_name : direct_name, is_direct(kind) ? t_iterative : t_direct,
                         sys->n));
  }

  const int limit = per_row <= kAutoSparseRowEntries ? kAutoDirectMaxUnknownsSparse : kAutoDirectMaxUnknownsDense;
  const sk_linear_solver_kind by_size = sys->n <= limit ? kDirectBackend : kIterativeBackend;
  const std::string size_reason =
      format("%d unknowns, %.0f entries per row (the size rule: direct up to %d unknowns at this sparsity)", sys->n,
             per_row, limit);
  const bool contested = sys->n * kContestedBand >= limit && sys->n <= limit * kContestedBand;
  if (!contested) return decide(sys, by_size, "size", size_reason);
  // near the crossover: measure the rule's choice, then try the other one
  const sk_linear_solver_kind first = m.current == SK_LINEAR_AUTO ? by_size : m.current;
  const sk_linear_solver_kind other = is_direct(first) ? kIterativeBackend : kDirectBackend;
  if (!measured_here(candidate(m, first), size)) return decide(sys, first, "size", size_reason);
  m.trial_solves_left = kTrialSolves - 1;
  return decide(sys, other, "trial",
                format("trying it for %d solves: not measured at %d unknowns (%s: %.3g s per solve)", kTrialSolves,
                       sys->n, sk_linear_solver_name(first),
                       predicted_seconds(candidate(m, first), first, size)));
}

void auto_record(sk_linear_system *sys, sk_linear_solver_kind kind, sk_status status, double seconds) {
  AutoMemory &m = sys->auto_memory;
  double agreed = seconds;  // every rank must take the same decisions: the slowest rank's time
  MPI_Allreduce(&seconds, &agreed, 1, MPI_DOUBLE, MPI_MAX, sys->comm);
  AutoMemory::Candidate &c = candidate(m, kind);
  const double size = entries(sys);
  if (status == SK_OK) {
    const double coefficient = agreed / std::pow(size, exponent(kind));
    c.cost_coefficient = measured_here(c, size) ? 0.7 * c.cost_coefficient + 0.3 * coefficient : coefficient;
    c.entries_measured = static_cast<int64_t>(size);
    c.failures_in_a_row = 0;
    return;
  }
  if (is_direct(kind)) return;  // nothing to fall back to: the caller reports it
  c.failed_on_pattern = sys->pattern_generation;
  ++c.failures_in_a_row;
  c.retry_pattern = sys->pattern_generation + (1 << std::min(c.failures_in_a_row, 16));
  m.iterative_failure = sk_error_message();
  m.trial_solves_left = 0;
}

}  // namespace stickslip::bridge
