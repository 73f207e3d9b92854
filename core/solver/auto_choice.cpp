// stickslip — what `auto` runs: the direct solver (MUMPS), its lagged factorisation, or GMRES + MueLu, from what it
// has measured.
//
// The candidates: MUMPS, GMRES + MueLu (bounded iterations under refinement) and GMRES + one symmetric Gauss-Seidel
// sweep (no set-up, half the cost per iteration: cheap where inertia dominates the stiffness), GMRES + Jacobi (a
// diagonal scaling: a third of SGS's cost per iteration; on the paper tori 0.195 s per solve against 0.236 s), and
// the lagged LU (gmres-lu: GMRES preconditioned by the last MUMPS factorisation, refactorised when GMRES needs more
// than 10 iterations; lagged_lu.cpp), which is as robust as MUMPS (its fallback is a fresh factorisation).
// 1. Never a solver that failed on this pattern; after a failure an iterative solver waits 2, 4, 8 ... patterns
//    before it is tried again (a contact run changes pattern every few steps: before this rule GMRES was retried,
//    and failed, at every one of them: 39 of 39 on scenes/two-tori-coarse.yaml). A failure also discards the
//    solver's measurement: it comes back only through a capped trial, never on the cost it had measured before.
// 2. Not GMRES with a nodal preconditioner when the nodal block has a zero diagonal (a saddle point given without
//    coordinates, so without a constraint block to take the multiplier rows): MUMPS and the lagged LU only.
// 3. Up to kAutoDirectOutrightUnknowns (800) unknowns MUMPS outright. Above, the size rule of the elasticity
//    benchmark (docs/linear-solvers.md): direct up to 10 000 unknowns at <= 40
//    entries per row (2D-like), up to 2 000 above (3D-like). Within kContestedBand of that crossover it is only a
//    first guess and the direct solver competes with the iterative ones; beyond it only the iterative ones and the
//    lagged LU do (up to kLaggedBand x the crossover); below it MUMPS alone (factorisations cost milliseconds there).
// 4. Every competing candidate is measured (a trial of kTrialSolves solves each, kLaggedWindow for the lagged LU,
//    once the current one has a measurement at this size, within kMeasuredRange in stored entries); then the
//    cheapest per solve wins — a switch needs a kSwitchMargin advantage (auto_rule.cpp). Fair trials: a one-time
//    set-up (MUMPS's analysis, MueLu's hierarchy) is measured apart from the solves and charged as often as it
//    recurs (MUMPS's at every pattern, for the lagged LU as for MUMPS; MueLu's once: it is kept across patterns) —
//    counted into a 3-solve trial it made GMRES + MueLu 6.24 s per solve on the 3D Hertz tet4 where it takes 1.6 s;
//    and a Krylov cost is per digit of the tolerance it was measured at, compared at the current one (inexact
//    Newton's tolerances span 1e-4 ... 1e-10, so a trial at 1e-4 looked 2.5x cheaper than the same solver at
//    1e-10). The lagged LU is judged by its mean cost per solve over a window that starts with a factorisation of
//    its own (not on the factors of the MUMPS solve before it) and counts every refactorisation in it: one solve at
//    a time, it is either a factorisation (dearer than MUMPS) or a few substitutions (far cheaper). While it runs,
//    its mean is kept up to date, so a phase in which the matrix changes much between solves sends `auto` back;
//    after a loss it is measured again after kLaggedRetrySolves, 2x, 4x ... solves.
// 5. On a run of known length (sk_linsys_set_steps_left) a trial starts only while the rest of the run can pay for
//    it: solves left to use its result, an expected extra cost below what it could save, and the trials' extra cost
//    within kExplorationShare of the projected linear-solve time (auto_trial_refusal, auto_rule.cpp), a trial's
//    one-time set-up counted in (trial_setup_seconds). On the Hertz ladder (17-33 solves) five candidates' trials
//    took a large share of the run; on the 2D quad9 GMRES + MueLu's trial, priced without its hierarchy, fitted
//    the budget and cost its hierarchy and three solves each dearer than the lagged LU's.
// 6. A trial of an iterative candidate ends as soon as its candidate would not be chosen (auto_trial_lost).
// Measurements are kept across pattern changes as cost coefficients (seconds / entries^p, p the measured growth),
// so a pattern that gains a few contact entries keeps its decision. Every decision is logged once, with its reason.
#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>

#include "auto_rule.hpp"
#include "bridge_internal.hpp"
#include "linear_system.hpp"

namespace stickslip::bridge {

namespace {

constexpr int kAutoSparseRowEntries = 40;
constexpr int kAutoDirectMaxUnknownsSparse = 10000;
constexpr int kAutoDirectMaxUnknownsDense = 2000;
constexpr double kContestedBand = 4.0;
// Up to this many unknowns the direct solver outright, whatever the contested band says: no trial, no lagged LU.
// Measured (docs/linear-solvers.md, "Tiny systems"): on two crossing hex8 bars (nts-augmented, 3D, 8 steps, 1 rank)
// every candidate costs 2.6-4.9 ms per solve at 513 unknowns and MUMPS is within the switch margin of the cheapest
// at 741 (10.6 ms against gmres-lu's 9.0), while `auto`'s trials and lagged-LU windows made it the dearest: 8.5 and
// 16.4 ms per solve. At 969 unknowns GMRES + SGS is 1.35x cheaper than MUMPS (6.8 against 9.2 ms).
constexpr int kAutoDirectOutrightUnknowns = 800;
// Growth of the cost per solve with the size (docs/linear-solvers.md): MUMPS n^1.6 on hex8, GMRES + MueLu n^1.1.
constexpr double kDirectExponent = 1.6;
constexpr double kIterativeExponent = 1.1;
constexpr double kMeasuredRange = 2.0;
constexpr double kSwitchMargin = 1.2;
constexpr int kTrialSolves = 3;  // at most: a trial ends once its candidate has lost (auto_trial_lost)
// MUMPS's trial: one solve (its analysis is timed apart, and every solve is a fresh numeric factorisation)
constexpr int kDirectTrialSolves = 1;
// The exploration budget of a run of known length: trials may cost (beyond the leader's solves they replace) this
// share of the run's projected linear-solve time at the leader's cost.
constexpr double kExplorationShare = 0.05;
// The order in which unmeasured candidates are tried: the iterative ones first (a capped trial costs about a solve
// of the leader), then the lagged LU (its first solve is a fresh factorisation solved directly, which measures MUMPS
// too), MUMPS last (measured by then wherever the lagged LU was tried).
// A trial of an iterative candidate may take kTrialIterationFactor x the iterations of the current iterative
// solver (at least kTrialIterationFloor), or kTrialIterationFloor against a direct one; beyond that it is not
// competitive and counts as failed. On the quasi-static Hertz 2D (refine 4) GMRES + SGS needs > 500 iterations
// where GMRES + MueLu needs 10: its uncapped trial cost 6.5 s of a 12 s run.
constexpr int kTrialIterationFactor = 4;
constexpr int kTrialIterationFloor = 30;
// The lagged LU: measured over kLaggedWindow solves (on the Hertz ladder it refactorises every 3 (3D) to 6 (2D)
// solves, so a window holds 1-3 of its cycles), competing up to kLaggedBand x the size rule's crossover (3D Hertz
// tet10 refine 1, 8 901 unknowns, is 4.5x the crossover of 2 000, beyond the contested band, and gmres-lu is 1.8x
// faster than MUMPS there; 16x is a factor 4 beyond the band, not measured further); a window that costs more than
// kLaggedWindow solves of the cheapest candidate measured is cut short (it cannot win); after a loss it is
// measured again after kLaggedRetrySolves x 2^(losses - 1) solves.
constexpr int kLaggedWindow = 8;
constexpr double kLaggedBand = 16.0;
constexpr int kLaggedRetrySolves = 16;
// A diagonal below this fraction of its row's largest entry counts as zero (`reduced` multiplier rows: 1e-23).
constexpr double kZeroDiagonal = 1e-12;
constexpr double kTiniestCost = 1e-300;  // a measured cost coefficient below the clock's resolution
// What `direct` (and AUTO's direct choice) runs: the fastest correct backend on the benchmark's hex8/quad4
// elasticity and on the contact saddle-point systems (docs/linear-solvers.md).
constexpr sk_linear_solver_kind kDirectBackend = SK_LINEAR_DIRECT_MUMPS;
constexpr sk_linear_solver_kind kIterativeBackend = SK_LINEAR_GMRES_MUELU;
constexpr sk_linear_solver_kind kLaggedBackend = SK_LINEAR_GMRES_LU;

int index_of(sk_linear_solver_kind kind) {
  for (int c = 0; c < kAutoCandidates; ++c)
    if (kAutoCandidateKinds[c] == kind) return c;
  return 0;
}

// the lagged LU grows like the factorisations it makes
double exponent(sk_linear_solver_kind kind) { return mumps_backed(kind) ? kDirectExponent : kIterativeExponent; }

double entries(const sk_linear_system *sys) { return static_cast<double>(sys->global_entries); }

bool measured_here(const AutoMemory::Candidate &c, double size) {
  return c.cost_coefficient > 0 && size <= kMeasuredRange * static_cast<double>(c.entries_measured) &&
         static_cast<double>(c.entries_measured) <= kMeasuredRange * size;
}

// The digits a solve of `kind` at the system's tolerance must gain (1 for a direct solve: its cost does not depend
// on them; 1 for the lagged LU too: its cost is that of its factorisations and a few substitutions).
double digits(const sk_linear_system *sys, sk_linear_solver_kind kind) {
  return mumps_backed(kind) ? 1.0 : tolerance_digits(sys->options.tolerance);
}

double predicted_seconds(const sk_linear_system *sys, const AutoMemory::Candidate &c, sk_linear_solver_kind kind,
                         double size) {
  return c.cost_coefficient * std::pow(size, exponent(kind)) * digits(sys, kind);
}

// What `auto` expects of candidate c on this system (auto_rule.hpp).
AutoEstimate estimate(const sk_linear_system *sys, int c, bool eligible, double size) {
  const AutoMemory &m = sys->auto_memory;
  const sk_linear_solver_kind kind = kAutoCandidateKinds[c];
  AutoEstimate e;
  e.eligible = eligible;
  e.solve_seconds = predicted_seconds(sys, m.candidates[c], kind, size);
  e.setup_seconds = m.candidates[c].setup_coefficient * std::pow(size, exponent(kind));
  // a direct solver's analysis recurs at every pattern; a preconditioner built from scratch is kept across them
  e.setups_per_solve =
      mumps_backed(kind) ? static_cast<double>(sys->pattern_generation) / std::max(1, m.solves) : 0.0;
  return e;
}

// A zero (or absent) diagonal in the nodal block, on any rank (collective).
bool nodal_diagonal_deficient(const sk_linear_system *sys) {
  int deficient = 0;
  const int end = nodal_row_end(sys) - sys->first_row;
  for (int i = 0; i < end && !deficient; ++i) {
    const int64_t d = sys->owned_diagonal[i];
    double largest = 0;
    for (int64_t k = sys->row_ptr[i]; k < sys->row_ptr[i + 1]; ++k)
      largest = std::max(largest, std::fabs(sys->owned_values[k]));
    deficient = d < 0 || !(std::fabs(sys->owned_values[d]) > kZeroDiagonal * largest);
  }
  int any = 0;
  MPI_Allreduce(&deficient, &any, 1, MPI_INT, MPI_MAX, sys->comm);
  return any != 0;
}

// The solves left in the run, this one included, projected from the steps left (sk_linsys_set_steps_left) and the
// solves per step so far (the current step's count so far, plus one, as a lower bound); -1 if not told.
double projected_solves_left(const AutoMemory &m) {
  if (m.steps_left < 0) return -1;
  const int this_step = m.solves - m.solves_at_step_start;
  const int completed = m.steps_begun - 1;
  const double per_step =
      std::max(completed > 0 ? static_cast<double>(m.solves_at_step_start) / completed : 0.0, this_step + 1.0);
  return std::max(1.0, per_step * m.steps_left - this_step);
}

// The one-time set-up a trial of `kind` pays before its first solve: none for GMRES + SGS and + Jacobi (their
// set-up, the inverse diagonal, is part of every solve) or where it is made already (MueLu's hierarchy is kept
// across patterns, MUMPS's analysis within one); else the candidate's own set-up measured at this size, else the
// largest one-time set-up another candidate measured at this size: MUMPS's analysis and MueLu's hierarchy are
// both graph work over the same entries: MueLu's hierarchy measured 0.8-1.0 x MUMPS's analysis on the 2D Hertz
// ladder (quad4 refine 2 and 3, quad9 refine 1 and 1.6), 1.0-2.3 x on the 3D one (docs/linear-solvers.md).
double trial_setup_seconds(const sk_linear_system *sys, sk_linear_solver_kind kind, double size) {
  const AutoMemory &m = sys->auto_memory;
  const bool made = mumps_backed(kind)           ? !sys->amesos.is_null() && sys->amesos_kind == kDirectBackend
                    : kind == kIterativeBackend ? !sys->preconditioners[0].muelu.is_null()  // GMRES_MUELU's slot
                                                : true;
  if (made) return 0;
  const int own = index_of(kind);
  double seconds = 0;
  for (int c = 0; c < kAutoCandidates; ++c) {
    const AutoMemory::Candidate &k = m.candidates[c];
    if (k.setup_coefficient <= 0 || !measured_here(k, size)) continue;
    const double setup = estimate(sys, c, true, size).setup_seconds;
    if (c == own) return setup;
    seconds = std::max(seconds, setup);
  }
  return seconds;
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


}  // namespace

sk_linear_solver_kind auto_fallback(sk_linear_system *sys) {
  AutoMemory &m = sys->auto_memory;
  const sk_linear_solver_kind failed_kind = m.current;
  const AutoMemory::Candidate &failed = m.candidates[index_of(failed_kind)];
  const sk_linear_solver_kind back = m.before_trial;
  const bool back_usable =
      back != SK_LINEAR_AUTO && back != failed_kind &&
      (mumps_backed(back) || m.candidates[index_of(back)].failed_on_pattern != sys->pattern_generation);
  const sk_linear_solver_kind kind = back_usable ? back : kDirectBackend;
  m.before_trial = SK_LINEAR_AUTO;
  return decide(sys, kind, "fallback",
                format("%s failed (%s); not tried again on this pattern", sk_linear_solver_name(failed_kind),
                       failed.failure.c_str()));
}

sk_linear_solver_kind auto_choose(sk_linear_system *sys) {
  AutoMemory &m = sys->auto_memory;
  const int generation = sys->pattern_generation;
  const double size = entries(sys);
  const double per_row = sys->n > 0 ? size / sys->n : 0.0;

  // which candidates may run: the MUMPS-backed ones always; iterative ones not after a failure on this pattern,
  // not in back-off, and not on a nodal block with a zero diagonal
  const bool deficient = nodal_diagonal_deficient(sys);
  bool allowed[kAutoCandidates];
  std::string excluded;
  for (int c = 0; c < kAutoCandidates; ++c) {
    const sk_linear_solver_kind kind = kAutoCandidateKinds[c];
    const AutoMemory::Candidate &k = m.candidates[c];
    allowed[c] = mumps_backed(kind) || (!deficient && k.failed_on_pattern != generation && generation >= k.retry_pattern);
    if (allowed[c] || deficient) continue;
    excluded += format("%s%s %s", excluded.empty() ? "" : "; ", sk_linear_solver_name(kind),
                       k.failed_on_pattern == generation
                           ? ("failed on this pattern (" + k.failure + ")").c_str()
                           : format("failed on %d pattern(s) in a row, tried again from the %d. pattern on",
                                    k.failures_in_a_row, k.retry_pattern)
                                 .c_str());
  }
  if (m.trial_solves_left > 0 && m.current != SK_LINEAR_AUTO && allowed[index_of(m.current)]) {
    // an iterative candidate that would not be chosen over the candidate it is measured against ends its trial
    // (auto_trial_lost): on the 2D Hertz quad9 refine 1.6 GMRES + MueLu measured 0.19 s per solve against the
    // lagged LU's 0.20 s at its first solve (not 1.2 x cheaper), and its two further solves cost 0.13 and 0.53 s
    const int trial = index_of(m.current);
    const bool lost = !mumps_backed(m.current) && m.before_trial != SK_LINEAR_AUTO &&
                      measured_here(m.candidates[trial], size) &&
                      auto_trial_lost(estimate(sys, trial, true, size),
                                      estimate(sys, index_of(m.before_trial),
                                               measured_here(m.candidates[index_of(m.before_trial)], size), size),
                                      kSwitchMargin);
    if (!lost) {
      --m.trial_solves_left;
      return m.current;  // the trial goes on, with its iteration cap
    }
  }
  m.trial_solves_left = 0;
  m.iteration_cap = 0;
  // the candidate a trial that just ended was measured against keeps the switch margin, not the trial's candidate
  // (on the 2D Hertz quad9 refine 1.6 MUMPS, measured within the lagged LU's window, took over from the lagged LU
  // at 0.160 against 0.174 s per solve when the margin went to GMRES + MueLu's trial: 15 factorisations against 6)
  const sk_linear_solver_kind trial_incumbent = m.before_trial;
  m.before_trial = SK_LINEAR_AUTO;  // no trial running: a failure falls back to the direct solver
  bool any_iterative = false;
  for (int c = 0; c < kAutoCandidates; ++c)
    any_iterative = any_iterative || (allowed[c] && !mumps_backed(kAutoCandidateKinds[c]));

  // the size rule, and where it is only a first guess
  const int limit = per_row <= kAutoSparseRowEntries ? kAutoDirectMaxUnknownsSparse : kAutoDirectMaxUnknownsDense;
  const sk_linear_solver_kind by_size = sys->n <= limit ? kDirectBackend : kIterativeBackend;
  const bool tiny = sys->n <= kAutoDirectOutrightUnknowns;
  const bool contested = !tiny && sys->n * kContestedBand >= limit && sys->n <= limit * kContestedBand;
  const bool direct_only = deficient || !any_iterative;
  // the candidates to compare: MUMPS below and near the crossover, the iterative ones near and above it, the lagged
  // LU from the band's lower edge up to kLaggedBand x the crossover (below the band a factorisation costs
  // milliseconds, and a choice by timing there would make the results of small runs vary at round-off from run to
  // run: two-elements' histories digit for digit); MUMPS and the lagged LU alone where no iterative solver may run
  const bool lagged_size = !tiny && sys->n * kContestedBand >= limit && sys->n <= limit * kLaggedBand;
  bool eligible[kAutoCandidates];
  for (int c = 0; c < kAutoCandidates; ++c) {
    const sk_linear_solver_kind kind = kAutoCandidateKinds[c];
    eligible[c] = kind == kLaggedBackend   ? lagged_size
                  : is_direct(kind)        ? direct_only || contested || is_direct(by_size)
                                           : allowed[c] && !direct_only && (contested || !is_direct(by_size));
  }
  if (m.current == SK_LINEAR_AUTO || !eligible[index_of(m.current)]) {
    if (deficient)
      return decide(sys, kDirectBackend, "diagonal",
                    "a zero diagonal in the nodal block (a saddle point: multiplier rows without coordinates to "
                    "split them off), which the iterative solvers' smoothers divide by");
    if (!any_iterative) {
      bool failed_here = false;
      for (const AutoMemory::Candidate &k : m.candidates) failed_here = failed_here || k.failed_on_pattern == generation;
      return decide(sys, kDirectBackend, failed_here ? "failed" : "backoff", excluded);
    }
    const std::string size_reason =
        tiny ? format("%d unknowns (up to %d: the direct solver outright, a solve costs milliseconds)", sys->n,
                      kAutoDirectOutrightUnknowns)
             : format("%d unknowns, %.0f entries per row (the size rule: direct up to %d unknowns at this sparsity)",
                      sys->n, per_row, limit);
    // on elasticity (coordinates given: the dimension is known) the lagged LU first where the direct solver would
    // be, in 2D and on saddle points (multiplier rows): the best fixed solver on the 2D Hertz ladder and with
    // mortar-dual (docs/linear-solvers.md); its first solve measures MUMPS as well. GMRES + MueLu first in 3D above
    // the crossover; without coordinates the size rule's guess.
    int first = index_of(by_size);
    const int lagged_first = index_of(kLaggedBackend);
    if (eligible[lagged_first] && sys->coordinate_dim > 0 &&
        (is_direct(by_size) || sys->coordinate_dim == 2 || sys->n > sys->n_nodal))
      first = lagged_first;
    for (int c = 0; c < kAutoCandidates && !eligible[first]; ++c) first = c;
    return decide(sys, kAutoCandidateKinds[first], "size",
                  excluded.empty() ? size_reason : size_reason + "; " + excluded);
  }
  const int current = index_of(m.current);
  const int lagged = index_of(kLaggedBackend);
  AutoMemory::Candidate &lu = m.candidates[lagged];
  if (!measured_here(m.candidates[current], size)) return m.current;  // being measured
  // the lagged LU measured again, after a loss, once its wait is over
  if (m.current != kLaggedBackend && lu.retry_solve > 0 && m.solves >= lu.retry_solve) {
    lu.cost_coefficient = 0;
    lu.retry_solve = 0;
  }
  // a trial is measured against, and falls back to, the cheapest candidate measured so far, not the one that ran
  // last (after its own trial, MUMPS at 0.30 s per solve on the 3D Hertz tet4 refine 2, where GMRES + MueLu takes
  // 0.042 s and the failed trials of GMRES + SGS and + Jacobi fell back to it: 4 factorisations)
  AutoEstimate measured[kAutoCandidates];
  for (int c = 0; c < kAutoCandidates; ++c)
    measured[c] = estimate(sys, c, eligible[c] && measured_here(m.candidates[c], size), size);
  const int holder = trial_incumbent != SK_LINEAR_AUTO && measured[index_of(trial_incumbent)].eligible
                         ? index_of(trial_incumbent)
                         : current;
  const int cheapest = auto_cheapest(measured, kAutoCandidates, holder, kSwitchMargin);
  const int incumbent = cheapest >= 0 ? cheapest : current;
  // a trial only where the rest of the run can pay for it (auto_rule.cpp); a factorisation not yet measured is
  // priced by the size rule (at the crossover it costs what an iterative solve does, and grows n^0.5 faster
  // beyond it: an optimistic price in 3D, where the Hertz tet4 refine 2 measured 7x the GMRES + MueLu solve)
  const int direct = index_of(kDirectBackend);
  const double leader = auto_cost_per_solve(estimate(sys, incumbent, true, size));
  const double factorisation =
      measured_here(m.candidates[direct], size)
          ? auto_cost_per_solve(estimate(sys, direct, true, size))
          : mumps_backed(kAutoCandidateKinds[incumbent])
                ? leader
                : leader * std::pow(std::max(1.0, static_cast<double>(sys->n) / limit), kDirectExponent - kIterativeExponent);
  const double solves_left = projected_solves_left(m);
  std::string skipped;
  const sk_linear_solver_kind trial_order[] = {kIterativeBackend, SK_LINEAR_GMRES_SGS, SK_LINEAR_GMRES_JACOBI,
                                               kLaggedBackend, kDirectBackend};
  for (const sk_linear_solver_kind kind : trial_order) {
    const int c = index_of(kind);
    if (!eligible[c] || measured_here(m.candidates[c], size)) continue;
    const bool window = kind == kLaggedBackend;
    AutoTrial trial;
    trial.solves_left = solves_left;
    trial.solves_total = m.solves + solves_left;
    trial.trial_solves = window ? kLaggedWindow : is_direct(kind) ? kDirectTrialSolves : kTrialSolves;
    // a capped iterative trial that fails wastes about one solve of the leader; a factorising one its factorisation
    trial.extra_seconds = mumps_backed(kind) ? std::max(0.0, factorisation - leader) : leader;
    trial.setup_seconds = trial_setup_seconds(sys, kind, size);
    trial.optimistic_seconds = is_direct(kind) ? factorisation : 0.0;
    trial.leader_seconds = leader;
    trial.spent_seconds = m.explored_seconds;
    trial.share = kExplorationShare;
    if (const char *refusal = auto_trial_refusal(trial)) {
      skipped += format("%s%s not tried (%s)", skipped.empty() ? "" : "; ", sk_linear_solver_name(kind), refusal);
      continue;
    }
    m.trial_solves_left = trial.trial_solves - 1;
    m.trial_leader_seconds = leader;
    m.before_trial = kAutoCandidateKinds[incumbent];
    // the competitor's iterations at this tolerance (a trial is capped at the same tolerance it will run at)
    const double competitor_iterations =
        m.candidates[incumbent].iterations_per_digit * tolerance_digits(sys->options.tolerance);
    m.iteration_cap = mumps_backed(kind)             ? 0
                      : mumps_backed(m.before_trial) ? kTrialIterationFloor
                                                : std::max(kTrialIterationFloor,
                                                           static_cast<int>(std::ceil(kTrialIterationFactor *
                                                                                      competitor_iterations)));
    if (window) {  // a window of its own: it starts with a factorisation, not on the factors of a MUMPS solve
      lu.cost_coefficient = 0;
      lu.window_cost = 0;
      lu.window_solves = 0;
      sys->lagged_refactorise = true;
    }
    return decide(sys, kind, "trial",
                  format("trying it for %d solves: not measured at %d unknowns (%s: %.3g s per solve)",
                         trial.trial_solves, sys->n, sk_linear_solver_name(m.before_trial), leader));
  }
  // all measured (or not worth a trial): the cheapest, if clearly cheaper than the current one (timings are noisy
  // on a shared machine)
  AutoEstimate estimates[kAutoCandidates];
  for (int c = 0; c < kAutoCandidates; ++c)
    estimates[c] = estimate(sys, c, eligible[c] && measured_here(m.candidates[c], size), size);
  const int best = auto_cheapest(estimates, kAutoCandidates, holder, kSwitchMargin);
  // the lagged LU lost: measured again later, and more rarely with every loss (a win does not reset the count: on
  // scenes/two-tori-coarse.yaml it won at tight tolerances and lost at loose ones, and was re-measured every 16
  // solves)
  if (best != lagged && m.current == kLaggedBackend) {
    lu.retry_solve = m.solves + (kLaggedRetrySolves << std::min(lu.losses, 16));
    ++lu.losses;
  }
  std::string others;
  for (int c = 0; c < kAutoCandidates; ++c)
    if (estimates[c].eligible && c != best)
      others += format("%s %s %.3g s", others.empty() ? "" : ",", sk_linear_solver_name(kAutoCandidateKinds[c]),
                       auto_cost_per_solve(estimates[c]));
  return decide(sys, kAutoCandidateKinds[best], skipped.empty() ? "measured" : "budget",
                format("measured %.3g s per solve against%s (%d unknowns, tolerance %.2g)%s%s",
                       auto_cost_per_solve(estimates[best]), others.c_str(), sys->n, sys->options.tolerance,
                       skipped.empty() ? "" : "; ", skipped.c_str()));
}

namespace {

// The lagged LU's solve of cost coefficient `coefficient`: into its window while it is measured (the window's
// mean becomes its cost; cut short once it has cost more than kLaggedWindow solves of the cheapest other candidate
// measured), then into a running mean over about a window's solves.
void record_lagged(sk_linear_system *sys, AutoMemory::Candidate &c, double coefficient, double size) {
  AutoMemory &m = sys->auto_memory;
  if (c.cost_coefficient > 0 && !measured_here(c, size)) {  // measured at another size: a new window
    c.cost_coefficient = 0;
    c.window_cost = 0;
    c.window_solves = 0;
  }
  if (c.cost_coefficient > 0) {
    c.cost_coefficient += (coefficient - c.cost_coefficient) / kLaggedWindow;
    return;
  }
  c.window_cost += coefficient;
  ++c.window_solves;
  const double scale = std::pow(size, kDirectExponent);
  // the cheapest other candidate measured at this size: a window that has cost more than kLaggedWindow of its solves
  // cannot win (on the 3D Hertz tet4 refine 2 GMRES + MueLu takes 0.044 s per solve, a factorisation 0.3 s)
  double rival = -1;
  for (int k = 0; k < kAutoCandidates; ++k) {
    if (kAutoCandidateKinds[k] == kLaggedBackend || !measured_here(m.candidates[k], size)) continue;
    const double seconds = estimate(sys, k, true, size).solve_seconds;
    rival = rival < 0 ? seconds : std::min(rival, seconds);
  }
  const bool hopeless = rival >= 0 && c.window_cost * scale > kLaggedWindow * rival;
  if (c.window_solves >= kLaggedWindow || hopeless) {
    c.cost_coefficient = std::max(c.window_cost / c.window_solves, kTiniestCost);
    m.trial_solves_left = 0;
  }
}

}  // namespace

void auto_record(sk_linear_system *sys, sk_linear_solver_kind kind, sk_status status, double seconds,
                 double setup_seconds, const sk_linear_report &report) {
  AutoMemory &m = sys->auto_memory;
  ++m.solves;
  double local[2] = {seconds, setup_seconds}, agreed[2];  // every rank must take the same decisions: the slowest's
  MPI_Allreduce(local, agreed, 2, MPI_DOUBLE, MPI_MAX, sys->comm);
  AutoMemory::Candidate &c = m.candidates[index_of(kind)];
  const double size = entries(sys);
  const double scale = std::pow(size, exponent(kind));
  // a trial's solve: what it cost beyond the leader's solve it replaced (all of it if it failed: the fallback solves)
  if (m.before_trial != SK_LINEAR_AUTO && kind == m.current && kind != m.before_trial)
    m.explored_seconds += status == SK_OK ? std::max(0.0, agreed[0] - m.trial_leader_seconds) : agreed[0];
  if (status == SK_OK) {
    const double setup = std::min(agreed[1], agreed[0]);
    const double coefficient = (agreed[0] - setup) / (scale * digits(sys, kind));
    if (kind == kLaggedBackend) {
      record_lagged(sys, c, coefficient, size);
      // a lagged solve that factorised afresh and solved directly was a MUMPS solve: it measures MUMPS (which then
      // needs no trial of its own) and keeps its cost current
      AutoMemory::Candidate &direct = m.candidates[index_of(kDirectBackend)];
      if (report.factorisations == 1 && report.iterations == 0) {
        direct.cost_coefficient = measured_here(direct, size)
                                      ? 0.7 * direct.cost_coefficient + 0.3 * coefficient
                                      : std::max(coefficient, kTiniestCost);
        if (setup > 0) direct.setup_coefficient = setup / scale;
        direct.entries_measured = static_cast<int64_t>(size);
      }
    } else {
      c.cost_coefficient = measured_here(c, size) ? 0.7 * c.cost_coefficient + 0.3 * coefficient : coefficient;
      c.cost_coefficient = std::max(c.cost_coefficient, kTiniestCost);  // > 0: measured
    }
    if (setup > 0) c.setup_coefficient = setup / scale;
    c.entries_measured = static_cast<int64_t>(size);
    c.failures_in_a_row = 0;
    c.iterations_per_digit = report.iterations / digits(sys, kind);
    return;
  }
  if (mumps_backed(kind)) return;  // nothing to fall back to: the caller reports it
  c.cost_coefficient = 0;          // its measurement no longer holds: back only through a capped trial
  c.failed_on_pattern = sys->pattern_generation;
  ++c.failures_in_a_row;
  c.retry_pattern = sys->pattern_generation + (1 << std::min(c.failures_in_a_row, 16));
  c.failure = sk_error_message();
  if (m.iteration_cap > 0) c.failure += " (a trial, capped at its competitors' cost)";
  m.trial_solves_left = 0;
  m.iteration_cap = 0;
}

const sk_linear_solver_kind kAutoCandidateKinds[kAutoCandidates] = {
    kDirectBackend, kIterativeBackend, SK_LINEAR_GMRES_SGS, SK_LINEAR_GMRES_JACOBI, kLaggedBackend};

}  // namespace stickslip::bridge
