// stickslip — what NOX sees of a Newton solve (newton.cpp): the state the callbacks share, this rank's part of a
// distributed vector, and the group whose computeF / computeJacobian / computeNewton call the driver's callbacks.
// Internal to the Trilinos bridge.
#ifndef STICKSLIP_SOLVER_NEWTON_GROUP_HPP
#define STICKSLIP_SOLVER_NEWTON_GROUP_HPP

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include <mpi.h>

#include <NOX_Abstract_Group.H>
#include <NOX_Abstract_Vector.H>
#include <Teuchos_RCP.hpp>

#include "bridge_internal.hpp"
#include "stickslip/bridge.h"

namespace stickslip::newton {

using Teuchos::RCP;
using Teuchos::rcp;


// ||F|| reported for a failed residual evaluation. Finite on purpose: +inf turns the polynomial line search's
// interpolation into NaN steps; 1e50 keeps its arithmetic finite while no real residual comes near it.
constexpr double kFailedResidualNorm = 1e50;

// What the callbacks share across the groups NOX clones: the callbacks, the first failure and the counters.
struct NewtonState {
  MPI_Comm comm = MPI_COMM_NULL;
  sk_newton_callbacks callbacks{};
  int linear_solves = 0;
  // which x the driver's Jacobian was last assembled at (groups carry the version of their x)
  long jacobian_version = -1;
  long next_version = 0;
  sk_status callback_failure = SK_OK;  // a jacobian / solve / after_iteration failure: the solve must stop
  std::string callback_message;
  std::string residual_message;  // the last failed residual evaluation (the line search may recover from it)
  sk_status residual_status = SK_OK;
  int residual_failures = 0;
  // inexact Newton: the forcing term of the last solve and the ||F|| it was taken at
  bool forcing = false;
  double linear_tolerance = 1e-10, converged_norm = 0;
  double last_forcing = 0, last_norm_f = 0;

  // Eisenstat & Walker (1996), choice 2 (gamma = 0.9, alpha = 2) with their safeguard, capped at kMaxForcing; not
  // below what the convergence test can use (0.1 of the ||F|| it accepts, relative to this ||F||), nor below the
  // linear solver's own tolerance. Measured on scenes/two-tori-coarse.yaml, 60 steps, GMRES + MueLu (CPU time):
  // exact solves (1e-10) 8.1 s, 208 Newton iterations; first/max forcing 1e-2/1e-2 6.0 s, 224 iterations;
  // 1e-4/1e-2 5.6 s, 221; 1e-4/1e-4 5.2 s, 208 (no extra Newton iteration); 1e-6/1e-4 5.6 s, 208.
  static constexpr double kFirstForcing = 1e-4, kMaxForcing = 1e-4, kGamma = 0.9;
  double forcing_term(double norm_f) {
    double eta = kFirstForcing;
    if (last_norm_f > 0) {
      const double ratio = norm_f / last_norm_f;
      eta = kGamma * ratio * ratio;
      const double safeguard = kGamma * last_forcing * last_forcing;
      if (safeguard > 0.1) eta = std::max(eta, safeguard);
      eta = std::min(eta, kMaxForcing);
    }
    if (norm_f > 0) eta = std::max(eta, std::min(kMaxForcing, 0.1 * converged_norm / norm_f));
    eta = std::max(eta, linear_tolerance);
    last_forcing = eta;
    last_norm_f = norm_f;
    return eta;
  }

  void record_callback_failure(sk_status status, const char *what) {
    if (callback_failure != SK_OK) return;
    callback_failure = status;
    callback_message = std::string(what) + ": " + sk_error_message();
  }
};

// This rank's part of a distributed vector: its n owned values; reductions over the ranks of comm.
class OwnedVector : public NOX::Abstract::Vector {
 public:
  OwnedVector(MPI_Comm comm, size_t n) : comm_(comm), values_(n, 0.0) {}
  OwnedVector(MPI_Comm comm, const double *data, size_t n) : comm_(comm), values_(data, data + n) {}
  OwnedVector(const OwnedVector &) = default;
  // the implicit one would call the base's pure operator= non-virtually
  OwnedVector &operator=(const OwnedVector &y) {
    values_ = y.values_;
    comm_ = y.comm_;
    return *this;
  }
  MPI_Comm comm() const { return comm_; }
  // the sum over the ranks
  double sum(double local) const {
    MPI_Allreduce(MPI_IN_PLACE, &local, 1, MPI_DOUBLE, MPI_SUM, comm_);
    return local;
  }

  std::vector<double> &values() { return values_; }
  const std::vector<double> &values() const { return values_; }

  NOX::Abstract::Vector &init(double gamma) override {
    std::fill(values_.begin(), values_.end(), gamma);
    return *this;
  }
  // Deterministic (each rank's seed from the given one and its rank); NOX only uses it in some line searches.
  NOX::Abstract::Vector &random(bool use_seed, int seed) override {
    int rank = 0;
    MPI_Comm_rank(comm_, &rank);
    unsigned long state = (use_seed ? static_cast<unsigned long>(seed) : 12345UL) + 7919UL * static_cast<unsigned long>(rank);
    for (double &v : values_) {
      state = state * 6364136223846793005UL + 1442695040888963407UL;
      v = static_cast<double>(state >> 11) / static_cast<double>(1UL << 53) * 2.0 - 1.0;
    }
    return *this;
  }
  NOX::Abstract::Vector &abs(const NOX::Abstract::Vector &y) override {
    const auto &o = cast(y);
    for (size_t i = 0; i < values_.size(); ++i) values_[i] = std::fabs(o[i]);
    return *this;
  }
  NOX::Abstract::Vector &operator=(const NOX::Abstract::Vector &y) override {
    values_ = cast(y);
    return *this;
  }
  NOX::Abstract::Vector &reciprocal(const NOX::Abstract::Vector &y) override {
    const auto &o = cast(y);
    for (size_t i = 0; i < values_.size(); ++i) values_[i] = 1.0 / o[i];
    return *this;
  }
  NOX::Abstract::Vector &scale(double gamma) override {
    for (double &v : values_) v *= gamma;
    return *this;
  }
  NOX::Abstract::Vector &scale(const NOX::Abstract::Vector &a) override {
    const auto &o = cast(a);
    for (size_t i = 0; i < values_.size(); ++i) values_[i] *= o[i];
    return *this;
  }
  NOX::Abstract::Vector &update(double alpha, const NOX::Abstract::Vector &a, double gamma) override {
    const auto &o = cast(a);
    for (size_t i = 0; i < values_.size(); ++i) values_[i] = alpha * o[i] + gamma * values_[i];
    return *this;
  }
  NOX::Abstract::Vector &update(double alpha, const NOX::Abstract::Vector &a, double beta,
                                const NOX::Abstract::Vector &b, double gamma) override {
    const auto &oa = cast(a);
    const auto &ob = cast(b);
    for (size_t i = 0; i < values_.size(); ++i) values_[i] = alpha * oa[i] + beta * ob[i] + gamma * values_[i];
    return *this;
  }
  RCP<NOX::Abstract::Vector> clone(NOX::CopyType type) const override {
    auto copy = rcp(new OwnedVector(comm_, values_.size()));
    if (type == NOX::DeepCopy) copy->values_ = values_;
    return copy;
  }
  double norm(NOX::Abstract::Vector::NormType type) const override {
    double result = 0;
    switch (type) {
      case NOX::Abstract::Vector::MaxNorm:
        for (double v : values_) result = std::max(result, std::fabs(v));
        MPI_Allreduce(MPI_IN_PLACE, &result, 1, MPI_DOUBLE, MPI_MAX, comm_);
        return result;
      case NOX::Abstract::Vector::OneNorm:
        for (double v : values_) result += std::fabs(v);
        return sum(result);
      case NOX::Abstract::Vector::TwoNorm:
      default:
        for (double v : values_) result += v * v;
        return std::sqrt(sum(result));
    }
  }
  double norm(const NOX::Abstract::Vector &weights) const override {
    const auto &w = cast(weights);
    double result = 0;
    for (size_t i = 0; i < values_.size(); ++i) result += w[i] * values_[i] * values_[i];
    return std::sqrt(sum(result));
  }
  double innerProduct(const NOX::Abstract::Vector &y) const override {
    const auto &o = cast(y);
    double result = 0;
    for (size_t i = 0; i < values_.size(); ++i) result += values_[i] * o[i];
    return sum(result);
  }
  NOX::size_type length() const override {
    long long n = static_cast<long long>(values_.size());
    MPI_Allreduce(MPI_IN_PLACE, &n, 1, MPI_LONG_LONG, MPI_SUM, comm_);
    return static_cast<NOX::size_type>(n);
  }

 private:
  static const std::vector<double> &cast(const NOX::Abstract::Vector &v) {
    return dynamic_cast<const OwnedVector &>(v).values_;
  }
  MPI_Comm comm_;
  std::vector<double> values_;
};

class CallbackGroup : public NOX::Abstract::Group {
 public:
  CallbackGroup(const std::shared_ptr<NewtonState> &state, const double *x, size_t n)
      : state_(state), x_(rcp(new OwnedVector(state->comm, x, n))), f_(rcp(new OwnedVector(state->comm, n))),
        newton_(rcp(new OwnedVector(state->comm, n))), version_(state->next_version++) {}

  CallbackGroup(const CallbackGroup &) = delete;
  CallbackGroup &operator=(const CallbackGroup &source) {
    assign(source);
    return *this;
  }
  NOX::Abstract::Group &operator=(const NOX::Abstract::Group &source) override {
    assign(dynamic_cast<const CallbackGroup &>(source));
    return *this;
  }
  void assign(const CallbackGroup &o) {
    if (this == &o) return;
    *x_ = *o.x_;
    *f_ = *o.f_;
    *newton_ = *o.newton_;
    version_ = o.version_;  // same x, so the driver's Jacobian (if assembled there) is valid for it too
    f_valid_ = o.f_valid_;
    f_failed_ = o.f_failed_;
    newton_valid_ = o.newton_valid_;
    norm_f_ = o.norm_f_;
  }

  void setX(const NOX::Abstract::Vector &y) override {
    *x_ = y;
    reset();
  }
  void computeX(const NOX::Abstract::Group &grp, const NOX::Abstract::Vector &d, double step) override {
    const auto &o = dynamic_cast<const CallbackGroup &>(grp);
    x_->update(1.0, *o.x_, step, d, 0.0);
    reset();
  }

  ReturnType computeF() override {
    if (f_valid_) return Ok;
    const sk_status status = state_->callbacks.residual(state_->callbacks.ctx, x_->values().data(), f_->values().data());
    f_valid_ = true;
    f_failed_ = status != SK_OK;
    if (f_failed_) {
      // a huge residual, not an error: line searches back off from it; ResidualFailureTest stops a full step
      ++state_->residual_failures;
      state_->residual_status = status;
      state_->residual_message = sk_error_message();
      f_->init(kFailedResidualNorm / std::sqrt(static_cast<double>(f_->length())));
      norm_f_ = kFailedResidualNorm;
    } else {
      norm_f_ = f_->norm(NOX::Abstract::Vector::TwoNorm);
    }
    return Ok;
  }

  ReturnType computeJacobian() override {
    if (state_->callback_failure != SK_OK || !f_valid_ || f_failed_) return Failed;
    if (isJacobianAssembled()) return Ok;
    const sk_status status = state_->callbacks.jacobian(state_->callbacks.ctx, x_->values().data());
    if (status != SK_OK) {
      state_->record_callback_failure(status, "Jacobian");
      return Failed;
    }
    state_->jacobian_version = version_;
    return Ok;
  }

  ReturnType computeNewton(Teuchos::ParameterList &) override {
    if (newton_valid_) return Ok;
    if (!isJacobianAssembled() && computeJacobian() != Ok) return Failed;
    ++state_->linear_solves;
    const sk_newton_callbacks &cb = state_->callbacks;
    const sk_status status =
        state_->forcing ? cb.solve_to_tolerance(cb.ctx, x_->values().data(), f_->values().data(),
                                                state_->forcing_term(norm_f_), newton_->values().data())
                        : cb.solve(cb.ctx, x_->values().data(), f_->values().data(), newton_->values().data());
    if (status != SK_OK) {
      state_->record_callback_failure(status, "Newton direction");
      return Failed;
    }
    newton_valid_ = true;
    return Ok;
  }

  bool isF() const override { return f_valid_; }
  // NOX's merit functions would call applyJacobian (not available through the callbacks) when this is true; they
  // fall back to a finite-difference slope when it is false. computeJacobian tracks the real state.
  bool isJacobian() const override { return false; }
  bool isNewton() const override { return newton_valid_; }

  const NOX::Abstract::Vector &getX() const override { return *x_; }
  const NOX::Abstract::Vector &getF() const override { return *f_; }
  double getNormF() const override { return norm_f_; }
  const NOX::Abstract::Vector &getGradient() const override { return *newton_; }  // no gradient: isGradient false
  const NOX::Abstract::Vector &getNewton() const override { return *newton_; }
  RCP<const NOX::Abstract::Vector> getXPtr() const override { return x_; }
  RCP<const NOX::Abstract::Vector> getFPtr() const override { return f_; }
  RCP<const NOX::Abstract::Vector> getGradientPtr() const override { return newton_; }
  RCP<const NOX::Abstract::Vector> getNewtonPtr() const override { return newton_; }

  RCP<NOX::Abstract::Group> clone(NOX::CopyType type) const override {
    auto copy = rcp(new CallbackGroup(state_, x_->values().data(), x_->values().size()));
    if (type == NOX::DeepCopy) *copy = *this;
    return copy;
  }

  bool residualFailed() const { return f_valid_ && f_failed_; }
  const std::vector<double> &x() const { return x_->values(); }

 private:
  bool isJacobianAssembled() const { return state_->jacobian_version == version_; }
  void reset() {
    version_ = state_->next_version++;
    f_valid_ = f_failed_ = newton_valid_ = false;
    norm_f_ = 0;
  }

  std::shared_ptr<NewtonState> state_;
  RCP<OwnedVector> x_, f_, newton_;
  long version_;
  bool f_valid_ = false, f_failed_ = false, newton_valid_ = false;
  double norm_f_ = 0;
};

}  // namespace stickslip::newton

#endif
