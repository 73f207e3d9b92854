// stickslip — sk_newton_solve: NOX's line-search Newton over the driver's C callbacks.
//
// NOX sees a distributed vector (this rank's owned unknowns; norms and inner products are sums over the ranks, so
// every rank takes the same decisions) and a group whose computeF / computeJacobian / computeNewton call the
// callbacks. A residual callback that fails (for
// instance an inverted element) does not surface as a NOX error, which NOX turns into `throw "NOX Error"`:
// the group reports F = +inf instead, so a backtracking line search shortens the step and the FiniteValue test
// stops a full-step Newton cleanly. The callback's message is kept and reported with SK_ERR_DIVERGED.
#include <algorithm>
#include <cfloat>
#include <cstdarg>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include <NOX.H>
#include <NOX_Abstract_Group.H>
#include <NOX_Abstract_Vector.H>
#include <NOX_Observer.hpp>
#include <NOX_Solver_Factory.H>
#include <NOX_Solver_Generic.H>
#include <NOX_StatusTest_Combo.H>
#include <NOX_StatusTest_FiniteValue.H>
#include <NOX_StatusTest_MaxIters.H>
#include <NOX_StatusTest_NormF.H>
#include <Teuchos_ParameterList.hpp>
#include <Teuchos_oblackholestream.hpp>

#include "bridge_internal.hpp"
#include "newton_group.hpp"
#include "stickslip/bridge.h"

namespace {

using Teuchos::RCP;
using Teuchos::rcp;
using stickslip::bridge::format;
using stickslip::bridge::status_from_exception;
using stickslip::newton::CallbackGroup;
using stickslip::newton::NewtonState;
using stickslip::newton::OwnedVector;

// The update test of sk_newton_options, on min(||s_k||, ||d_k||) with s_k = x_k - x_{k-1} the step just taken and
// d_k the next Newton update predicted without solving for it. The step came from d_{k-1} = -J(x_{k-1})^{-1} F_{k-1},
// so ||J^{-1}|| ~ ||d_{k-1}|| / ||F_{k-1}|| and ||d_k|| ~ ||d_{k-1}|| ||F_k|| / ||F_{k-1}||. Testing s_k alone costs
// one more solve per step to shrink an update that the residual already shows is converged: on the coarse two-tori
// (steps 5-7) ||F|| falls 7e-2 -> 9e-10 in iteration 3 and iteration 4 only confirmed it (||F|| = 8e-10).
class UpdateNormTest : public NOX::StatusTest::Generic {
 public:
  UpdateNormTest(double tolerance, bool use_prediction) : tolerance_(tolerance), use_prediction_(use_prediction) {}
  NOX::StatusTest::StatusType checkStatus(const NOX::Solver::Generic &solver, NOX::StatusTest::CheckType) override {
    status_ = NOX::StatusTest::Unconverged;
    if (solver.getNumIterations() == 0) return status_;
    const auto &group = solver.getSolutionGroup();
    const auto &previous = solver.getPreviousSolutionGroup();
    const auto &xv = dynamic_cast<const OwnedVector &>(group.getX());
    const auto &x = xv.values();
    const auto &x_old = dynamic_cast<const OwnedVector &>(previous.getX()).values();
    double sums[2] = {0, 0};  // ||s||^2, ||x||^2 over the ranks
    for (size_t i = 0; i < x.size(); ++i) {
      sums[0] += (x[i] - x_old[i]) * (x[i] - x_old[i]);
      sums[1] += x[i] * x[i];
    }
    MPI_Allreduce(MPI_IN_PLACE, sums, 2, MPI_DOUBLE, MPI_SUM, xv.comm());
    const double ss = sums[0], xx = sums[1];
    step_ = std::sqrt(ss);
    predicted_ = step_;
    if (use_prediction_ && previous.isNewton() && previous.getNormF() > 0)
      predicted_ = previous.getNewton().norm() * group.getNormF() / previous.getNormF();
    value_ = std::min(step_, predicted_);
    x_norm_ = std::sqrt(xx);
    bound_ = tolerance_ * (1.0 + x_norm_);
    if (value_ <= bound_) status_ = NOX::StatusTest::Converged;
    return status_;
  }
  NOX::StatusTest::StatusType getStatus() const override { return status_; }
  double step() const { return step_; }
  double bound() const { return bound_; }
  double x_norm() const { return x_norm_; }
  std::ostream &print(std::ostream &stream, int indent) const override {
    stream << std::string(indent, ' ') << status_ << "min(||s|| = " << step_ << ", predicted ||dx|| = " << predicted_
           << ") <= " << bound_ << "\n";
    return stream;
  }

 private:
  double tolerance_;
  bool use_prediction_;
  double step_ = 0, predicted_ = 0, value_ = 0, bound_ = 0, x_norm_ = 0;
  NOX::StatusTest::StatusType status_ = NOX::StatusTest::Unevaluated;
};

// Stagnation: ||F|| stops decreasing while the full Newton corrections d_{k-1} are small. Two levels:
//  - the round-off floor: ||d_{k-1}|| <= SK_NEWTON_ROUNDOFF_ULPS eps (||x|| + roundoff_scale), so that x + d equals x
//    but for its last digits, in kFloorIterations iterations in a row that do not lower ||F|| below kStallRatio of
//    its previous value. x is the solution as far as double precision resolves it: the solve ends as converged (the
//    caller warns, SK_NEWTON_ROUNDOFF_FLOOR). Measured on the contact patch test at penalty 1e9 (penalty-range,
//    factor 1e6): ||F|| = 1.5e-10 ... 2.2e-10 against the absolute tolerance 1e-10 with ||d|| = 2e-17 ... 8e-17,
//    1.5 ... 6 eps ||x||; without this level every such step was cut until max_cuts ended the run.
//  - above it, up to the update tolerance (||d_{k-1}|| <= update_tolerance (1 + ||x||)), kStalledIterations such
//    iterations fail the attempt (SK_NEWTON_STAGNATED), which is cut: there a shorter step often converges
//    (bridge.h). Without this test such a step ran max_iterations (50) seven times over, one per step cut.
// The full correction d, not the step taken s: a line search that backtracks to a tiny s from a large d is stuck far
// from the solution (large sliding: ||F||/||F0|| = 0.22 with ||s|| = 6e-10), a failure a shorter time step does cure.
class StagnationTest : public NOX::StatusTest::Generic {
 public:
  // A Newton step at round-off that still converges lowers ||F|| by orders of magnitude; at the floor ||F||
  // fluctuates by tens of percent.
  static constexpr double kStallRatio = 0.5;
  static constexpr int kStalledIterations = 4, kFloorIterations = 2;
  StagnationTest(const UpdateNormTest &update, double roundoff_scale)
      : update_(update), roundoff_scale_(roundoff_scale) {}
  NOX::StatusTest::StatusType checkStatus(const NOX::Solver::Generic &solver, NOX::StatusTest::CheckType) override {
    status_ = NOX::StatusTest::Unconverged;
    if (solver.getNumIterations() == 0) return status_;
    norm_f_ = solver.getSolutionGroup().getNormF();
    previous_norm_f_ = solver.getPreviousSolutionGroup().getNormF();
    const auto &previous = solver.getPreviousSolutionGroup();
    correction_ = previous.isNewton() ? previous.getNewton().norm() : update_.step();
    floor_ = SK_NEWTON_ROUNDOFF_ULPS * DBL_EPSILON * (update_.x_norm() + roundoff_scale_);
    const bool not_falling = norm_f_ >= kStallRatio * previous_norm_f_;
    stalled_ = not_falling && correction_ <= update_.bound() ? stalled_ + 1 : 0;
    at_floor_ = not_falling && correction_ <= floor_ ? at_floor_ + 1 : 0;
    if (at_floor_ >= kFloorIterations) status_ = NOX::StatusTest::Converged;
    else if (stalled_ >= kStalledIterations) status_ = NOX::StatusTest::Failed;
    return status_;
  }
  NOX::StatusTest::StatusType getStatus() const override { return status_; }
  void reset() { stalled_ = at_floor_ = 0; }
  bool at_floor() const { return status_ == NOX::StatusTest::Converged; }
  double norm_f() const { return norm_f_; }
  double previous_norm_f() const { return previous_norm_f_; }
  double correction() const { return correction_; }
  double floor() const { return floor_; }
  std::ostream &print(std::ostream &stream, int indent) const override {
    stream << std::string(indent, ' ') << status_ << "stalled iterations " << stalled_ << " < " << kStalledIterations
           << ", at the round-off floor " << at_floor_ << " < " << kFloorIterations << "\n";
    return stream;
  }

 private:
  const UpdateNormTest &update_;
  double roundoff_scale_;
  int stalled_ = 0, at_floor_ = 0;
  double norm_f_ = 0, previous_norm_f_ = 0, correction_ = 0, floor_ = 0;
  NOX::StatusTest::StatusType status_ = NOX::StatusTest::Unevaluated;
};

// No progress under the full step: over the last kIterations iterations ||F|| has not fallen below kRatio of its
// value before them, and the full Newton corrections have not shrunk below kRatio of the one before them either.
// A full-step Newton that converges cuts both by orders of magnitude in that many iterations; one that cycles or
// wanders keeps both. The solve then goes on from the current iterate with the backtracking line search
// (sk_newton_options.backtrack_on_no_progress) instead of running out its max_iterations first. Measured on the
// half cylinder (quad9, mortar-dual, mu 0.2) pressed on a slab, step 1: ||F|| = 0.1437 / 0.1432 alternating from
// iteration 6, corrections 2e-4, until iteration 25 (docs/stability.md, finding 28).
class NoProgressTest : public NOX::StatusTest::Generic {
 public:
  static constexpr int kIterations = 4;
  static constexpr double kRatio = 0.5;
  explicit NoProgressTest(bool enabled) : enabled_(enabled) {}
  void disable() {
    enabled_ = false;
    status_ = NOX::StatusTest::Unconverged;
  }
  NOX::StatusTest::StatusType checkStatus(const NOX::Solver::Generic &solver, NOX::StatusTest::CheckType) override {
    status_ = NOX::StatusTest::Unconverged;
    const int i = solver.getNumIterations();
    if (!enabled_ || i == 0) return status_;
    const auto &previous = solver.getPreviousSolutionGroup();
    // the ring holds ||F_j|| and ||d_{j-1}|| (the correction that led to x_j) for j = i - kIterations ... i
    if (i == 1) norm_f_[0] = previous.getNormF();
    norm_f_[i % kRing] = solver.getSolutionGroup().getNormF();
    correction_[i % kRing] = previous.isNewton() ? previous.getNewton().norm() : 0.0;
    if (i <= kIterations) return status_;  // d_{i-1-kIterations} is needed: x_0 has none before it
    const double f_before = norm_f_[(i - kIterations) % kRing], d_before = correction_[(i - kIterations) % kRing];
    double f_least = norm_f_[i % kRing], d_least = correction_[i % kRing];
    for (int j = i - kIterations + 1; j < i; ++j) {
      f_least = std::min(f_least, norm_f_[j % kRing]);
      d_least = std::min(d_least, correction_[j % kRing]);
    }
    if (f_least > kRatio * f_before && d_least > kRatio * d_before) {
      status_ = NOX::StatusTest::Failed;
      iteration_ = i;
      f_before_ = f_before;
      f_least_ = f_least;
      d_before_ = d_before;
      d_least_ = d_least;
    }
    return status_;
  }
  NOX::StatusTest::StatusType getStatus() const override { return status_; }
  bool fired() const { return status_ == NOX::StatusTest::Failed; }
  std::string describe() const {
    return format("no progress under the full step in iterations %d-%d (least ||F|| %.4g against %.4g before "
                  "them, least ||dx|| %.3g against %.3g)",
                  iteration_ - kIterations + 1, iteration_, f_least_, f_before_, d_least_, d_before_);
  }
  std::ostream &print(std::ostream &stream, int indent) const override {
    stream << std::string(indent, ' ') << status_ << "progress of ||F|| and ||dx|| over " << kIterations
           << " full steps\n";
    return stream;
  }

 private:
  static constexpr int kRing = kIterations + 1;
  bool enabled_;
  double norm_f_[kRing] = {}, correction_[kRing] = {};
  int iteration_ = 0;
  double f_before_ = 0, f_least_ = 0, d_before_ = 0, d_least_ = 0;
  NOX::StatusTest::StatusType status_ = NOX::StatusTest::Unevaluated;
};

// Fails the solve once a Jacobian / solve / after_iteration callback has failed, or when the accepted iterate's
// residual evaluation failed (a full step, or a line search that gave up).
class CallbackFailureTest : public NOX::StatusTest::Generic {
 public:
  explicit CallbackFailureTest(std::shared_ptr<NewtonState> state) : state_(std::move(state)) {}
  NOX::StatusTest::StatusType checkStatus(const NOX::Solver::Generic &solver, NOX::StatusTest::CheckType) override {
    const auto &group = dynamic_cast<const CallbackGroup &>(solver.getSolutionGroup());
    status_ = state_->callback_failure != SK_OK || group.residualFailed() ? NOX::StatusTest::Failed
                                                                          : NOX::StatusTest::Unconverged;
    return status_;
  }
  NOX::StatusTest::StatusType getStatus() const override { return status_; }
  std::ostream &print(std::ostream &stream, int indent) const override {
    stream << std::string(indent, ' ') << status_ << "callbacks succeeded\n";
    return stream;
  }

 private:
  std::shared_ptr<NewtonState> state_;
  NOX::StatusTest::StatusType status_ = NOX::StatusTest::Unevaluated;
};

// Records ||F|| after each iteration and runs the driver's after_iteration callback on the accepted iterate.
class IterationObserver : public NOX::Observer {
 public:
  IterationObserver(std::shared_ptr<NewtonState> state, sk_newton_report *report, int offset)
      : state_(std::move(state)), report_(report), offset_(offset) {}
  void runPostIterate(const NOX::Solver::Generic &solver) override {
    const auto &group = dynamic_cast<const CallbackGroup &>(solver.getSolutionGroup());
    const double norm_f = group.getNormF();
    if (report_->n_history < SK_NEWTON_HISTORY_MAX) report_->residual_history[report_->n_history++] = norm_f;
    if (state_->callbacks.after_iteration && state_->callback_failure == SK_OK && !group.residualFailed()) {
      const sk_status status = state_->callbacks.after_iteration(
          state_->callbacks.ctx, offset_ + solver.getNumIterations(), group.x().data(), norm_f);
      if (status != SK_OK) state_->record_callback_failure(status, "after_iteration");
    }
  }

 private:
  std::shared_ptr<NewtonState> state_;
  sk_newton_report *report_;
  int offset_;  // iterations of an earlier phase of the same solve (the full step before a switch)
};

const char *line_search_method(sk_line_search ls) {
  switch (ls) {
    case SK_LINE_SEARCH_BACKTRACK: return "Backtrack";
    case SK_LINE_SEARCH_POLYNOMIAL: return "Polynomial";
    case SK_LINE_SEARCH_FULL_STEP:
    default: return "Full Step";
  }
}

sk_status fail(sk_newton_report *report, sk_newton_outcome outcome, const std::string &reason,
               sk_status status = SK_ERR_DIVERGED) {
  report->outcome = outcome;
  std::snprintf(report->reason, sizeof report->reason, "%s", reason.c_str());
  return sk_error_set(status, "Newton (NOX): %s", reason.c_str());
}


// The residual callback's own status (SK_ERR_INVERTED, a plugin's SK_ERR_DIVERGED, or a bug's), so the caller
// tells a reason to cut the step from a reason to stop; a non-finite F without a failed callback is DIVERGED.
sk_status residual_failure_status(sk_status status) { return status == SK_OK ? SK_ERR_DIVERGED : status; }

}  // namespace

extern "C" {

void sk_newton_options_default(sk_newton_options *options) {
  options->residual_tolerance = 1e-8;
  options->relative_tolerance = 1e-10;
  options->update_tolerance = 1e-8;
  options->max_iterations = 25;
  options->line_search = SK_LINE_SEARCH_FULL_STEP;
  options->forcing = 1;
  options->linear_tolerance = 1e-10;
  options->verbose = 0;
  options->predicted_update = 0;
  options->roundoff_scale = 0;
  options->backtrack_on_no_progress = 0;
}

sk_status sk_line_search_from_name(const char *name, sk_line_search *ls) {
  static const struct {
    const char *name;
    sk_line_search ls;
  } names[] = {{"full-step", SK_LINE_SEARCH_FULL_STEP},
               {"backtrack", SK_LINE_SEARCH_BACKTRACK},
               {"polynomial", SK_LINE_SEARCH_POLYNOMIAL}};
  for (const auto &entry : names) {
    if (name && std::strcmp(name, entry.name) == 0) {
      *ls = entry.ls;
      return SK_OK;
    }
  }
  return sk_error_set(SK_ERR_INPUT, "unknown line search '%s' (expected full-step, backtrack or polynomial)",
                      name ? name : "(null)");
}

sk_status sk_newton_solve(MPI_Comm comm, const sk_newton_options *options, const sk_newton_callbacks *callbacks,
                          int n, double *x, sk_newton_report *report) {
  sk_newton_report local_report;
  if (!report) report = &local_report;
  std::memset(report, 0, sizeof *report);
  sk_newton_options opts;
  if (options) {
    opts = *options;
  } else {
    sk_newton_options_default(&opts);
  }
  if (!callbacks || !callbacks->residual || !callbacks->jacobian || !callbacks->solve)
    return sk_error_set(SK_ERR_INPUT, "sk_newton_solve: residual, jacobian and solve callbacks are required");
  long long total = n;  // a rank may own no unknowns; the problem may not be empty
  MPI_Allreduce(MPI_IN_PLACE, &total, 1, MPI_LONG_LONG, MPI_SUM, comm);
  if (n < 0 || (n > 0 && !x) || total <= 0)
    return sk_error_set(SK_ERR_INPUT, "sk_newton_solve: empty problem (n = %d)", n);
  if (opts.max_iterations < 1)
    return sk_error_set(SK_ERR_INPUT, "sk_newton_solve: max_iterations %d must be >= 1", opts.max_iterations);
  int rank = 0;
  MPI_Comm_rank(comm, &rank);

  auto state = std::make_shared<NewtonState>();
  state->comm = comm;
  state->callbacks = *callbacks;
  try {
    auto group = rcp(new CallbackGroup(state, x, static_cast<size_t>(n)));
    group->computeF();
    if (group->residualFailed())
      return fail(report, SK_NEWTON_RESIDUAL_FAILED,
                  "residual evaluation failed at the initial guess: " + state->residual_message,
                  residual_failure_status(state->residual_status));
    report->residual_history[report->n_history++] = group->getNormF();
    if (!std::isfinite(group->getNormF()))
      return fail(report, SK_NEWTON_RESIDUAL_FAILED, "non-finite residual at the initial guess");
    const double norm_f0 = group->getNormF();
    state->forcing = opts.forcing && callbacks->solve_to_tolerance;
    state->linear_tolerance = opts.linear_tolerance;
    state->converged_norm = std::max(opts.residual_tolerance, opts.relative_tolerance * norm_f0);

    // converged = (absolute ||F|| or relative ||F||/||F0||) and the update test; stopped by failures and max iterations
    auto norm_f_absolute = rcp(new NOX::StatusTest::NormF(opts.residual_tolerance, NOX::Abstract::Vector::TwoNorm,
                                                          NOX::StatusTest::NormF::Unscaled));
    auto norm_f_relative = rcp(new NOX::StatusTest::NormF(*group, opts.relative_tolerance,
                                                          NOX::Abstract::Vector::TwoNorm,
                                                          NOX::StatusTest::NormF::Unscaled));
    auto residual_small = rcp(new NOX::StatusTest::Combo(NOX::StatusTest::Combo::OR, norm_f_absolute, norm_f_relative));
    auto update_small = rcp(new UpdateNormTest(opts.update_tolerance, opts.predicted_update != 0));
    auto converged = rcp(new NOX::StatusTest::Combo(NOX::StatusTest::Combo::AND, residual_small, update_small));
    auto finite = rcp(new NOX::StatusTest::FiniteValue);
    auto callbacks_ok = rcp(new CallbackFailureTest(state));
    auto max_iterations = rcp(new NOX::StatusTest::MaxIters(opts.max_iterations));
    auto stagnation = rcp(new StagnationTest(*update_small, opts.roundoff_scale));
    auto tests = rcp(new NOX::StatusTest::Combo(NOX::StatusTest::Combo::OR));
    tests->addStatusTest(finite);
    tests->addStatusTest(callbacks_ok);
    tests->addStatusTest(converged);  // before stagnation: a converged iterate is never reported as stagnated
    tests->addStatusTest(stagnation);
    auto no_progress =
        rcp(new NoProgressTest(opts.backtrack_on_no_progress && opts.line_search == SK_LINE_SEARCH_FULL_STEP));
    tests->addStatusTest(no_progress);
    tests->addStatusTest(max_iterations);

    auto params = rcp(new Teuchos::ParameterList);
    params->set("Nonlinear Solver", "Line Search Based");
    params->sublist("Printing").set("Output Information",
                                    opts.verbose && rank == 0
                                        ? NOX::Utils::Error + NOX::Utils::Warning + NOX::Utils::OuterIteration +
                                              NOX::Utils::InnerIteration + NOX::Utils::OuterIterationStatusTest
                                        : 0);
    if (!(opts.verbose && rank == 0)) {
      // some NOX classes print their errors whatever the print level: send them nowhere
      auto silent = rcp(new Teuchos::oblackholestream);
      params->sublist("Printing").set("Output Stream", RCP<std::ostream>(silent));
      params->sublist("Printing").set("Error Stream", RCP<std::ostream>(silent));
    }
    params->sublist("Line Search").set("Method", line_search_method(opts.line_search));
    params->sublist("Direction").set("Method", "Newton");
    // a failed linear solve stops the solve instead of stepping along a wrong direction
    params->sublist("Direction").sublist("Newton").set("Rescue Bad Newton Solve", false);
    params->sublist("Solver Options").set("Observer", RCP<NOX::Observer>(rcp(new IterationObserver(state, report, 0))));

    auto solver = NOX::Solver::buildSolver(group, tests, params);
    NOX::StatusTest::StatusType status = NOX::StatusTest::Unconverged;
    std::string exception_text;
    const auto run = [&]() {
      try {
        status = solver->solve();
      } catch (...) {
        // NOX throws (`throw "NOX Error"`) when a direction or line search step fails; the reason is recorded below
        status_from_exception(SK_ERR_DIVERGED, "NOX", std::current_exception());
        exception_text = sk_error_message();
        status = NOX::StatusTest::Failed;
      }
    };
    run();
    // no progress under the full step (NoProgressTest): on from the current iterate with the backtracking line
    // search, with a budget of max_iterations of its own (what a retry of the step would have)
    int earlier_iterations = 0;
    if (status == NOX::StatusTest::Failed && no_progress->fired() && exception_text.empty() &&
        state->callback_failure == SK_OK &&
        !dynamic_cast<const CallbackGroup &>(solver->getSolutionGroup()).residualFailed()) {
      earlier_iterations = solver->getNumIterations();
      if (opts.verbose && rank == 0)
        std::fprintf(stderr, "sk_newton_solve: %s: on with the backtracking line search\n",
                     no_progress->describe().c_str());
      no_progress->disable();
      stagnation->reset();
      params->sublist("Line Search").set("Method", line_search_method(SK_LINE_SEARCH_BACKTRACK));
      params->sublist("Solver Options")
          .set("Observer", RCP<NOX::Observer>(rcp(new IterationObserver(state, report, earlier_iterations))));
      solver = NOX::Solver::buildSolver(solver->getSolutionGroup().clone(NOX::DeepCopy), tests, params);
      run();
    }

    const auto &solution = dynamic_cast<const CallbackGroup &>(solver->getSolutionGroup());
    report->iterations = earlier_iterations + solver->getNumIterations();
    report->switched_to_backtrack = earlier_iterations > 0;
    report->linear_solves = state->linear_solves;
    // the best iterate NOX has (the last accepted one), also on failure: the caller decides what to do with it
    if (!solution.residualFailed()) std::copy(solution.x().begin(), solution.x().end(), x);

    const double norm_f = solution.getNormF();
    const std::string tolerances =
        format("the absolute tolerance %g and the relative tolerance %g (||F||/||F0|| = %.3g)", opts.residual_tolerance,
               opts.relative_tolerance, norm_f0 > 0 ? norm_f / norm_f0 : 0.0);
    if (state->callback_failure == SK_ERR_LINEAR_SOLVER)
      return fail(report, SK_NEWTON_LINEAR_SOLVER,
                  format("linear solve failed in iteration %d: ", report->iterations + 1) + state->callback_message,
                  SK_ERR_LINEAR_SOLVER);
    if (state->callback_failure != SK_OK)
      return fail(report, SK_NEWTON_CALLBACK_FAILED, state->callback_message, state->callback_failure);
    if (status == NOX::StatusTest::Converged) {
      report->converged = 1;
      report->outcome = SK_NEWTON_CONVERGED;
      if (stagnation->at_floor() && converged->getStatus() != NOX::StatusTest::Converged) {
        report->outcome = SK_NEWTON_ROUNDOFF_FLOOR;
        std::snprintf(report->reason, sizeof report->reason, "%s",
                      (format("accepted at the round-off floor in iteration %d: ||F|| = %.3g (%.3g before) with "
                              "Newton corrections at round-off (||dx|| = %.3g <= %.3g), above ",
                              report->iterations, norm_f, stagnation->previous_norm_f(), stagnation->correction(),
                              stagnation->floor()) +
                       tolerances)
                          .c_str());
      }
      return SK_OK;
    }
    if (solution.residualFailed() || callbacks_ok->getStatus() == NOX::StatusTest::Failed ||
        finite->getStatus() == NOX::StatusTest::Failed) {
      const std::string cause = state->residual_message.empty() ? "non-finite residual" : state->residual_message;
      return fail(report, SK_NEWTON_RESIDUAL_FAILED, "residual evaluation failed (" + cause + ")",
                  residual_failure_status(state->residual_status));
    }
    if (stagnation->getStatus() == NOX::StatusTest::Failed)
      return fail(report, SK_NEWTON_STAGNATED,
                  format("stagnated in iteration %d: ||F|| = %.3g (%.3g before) stalls while the Newton corrections "
                         "are below the update tolerance (||dx|| = %.3g <= %.3g; round-off: %.3g), above ",
                         report->iterations, norm_f, stagnation->previous_norm_f(), stagnation->correction(),
                         update_small->bound(), stagnation->floor()) +
                      tolerances);
    if (max_iterations->getStatus() == NOX::StatusTest::Failed)
      return fail(report, SK_NEWTON_MAX_ITERATIONS,
                  format("no convergence in %d iterations (||F|| = %.3g from ||F0|| = %.3g; ", opts.max_iterations,
                         norm_f, norm_f0) +
                      tolerances + ")");
    if (!exception_text.empty()) {
      std::string reason = exception_text;
      if (state->residual_failures > 0) reason += " after failed residual evaluations: " + state->residual_message;
      return fail(report, SK_NEWTON_LINE_SEARCH, reason);
    }
    return fail(report, SK_NEWTON_LINE_SEARCH, format("line search failed (||F|| = %g)", norm_f));
  } catch (...) {
    status_from_exception(SK_ERR_DIVERGED, "sk_newton_solve", std::current_exception());
    return fail(report, SK_NEWTON_CALLBACK_FAILED, sk_error_message());
  }
}

}  // extern "C"
