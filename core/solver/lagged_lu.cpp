// stickslip — the lagged LU (`gmres-lu`): GMRES on the current matrix, right-preconditioned by the MUMPS
// factorisation of an earlier one (PETSc SNES's lagged preconditioner).
//
// Why. Newton's matrices of a quasi-static contact step differ little from one iteration to the next (and from one
// step to the next): on 2D Hertz at 22.6k unknowns 94 % of the run went to fresh MUMPS factorisations, one per
// iteration, each 10-20 times the cost of the forward and backward substitution it enables. With the last
// factors as preconditioner, GMRES needs a few substitutions per solve; it always iterates on the current matrix,
// so an older factorisation costs iterations, never accuracy (the Newton iterates are those of the direct path to
// the linear tolerance).
//
// When the factors are renewed (a fresh MUMPS factorisation of the current values, solved directly, refined as
// `mumps` is): at the first solve of a pattern (contact couplings that add entries change the pattern and drop the
// factors: release_pattern), when the last lagged solve needed more than kRefactoriseAbove GMRES iterations (the
// matrix has drifted: the next solve refactorises), and at once when GMRES does not converge in kGiveUpAfter
// iterations or the substitution fails.
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "bridge_internal.hpp"
#include "linear_system.hpp"

namespace stickslip::bridge {

namespace {

constexpr sk_linear_solver_kind kLaggedBackend = SK_LINEAR_DIRECT_MUMPS;
// A lagged solve that needs more GMRES iterations than this makes the next solve refactorise. Each iteration is a
// forward and backward substitution plus a product with the matrix; a numeric factorisation costs 10-30 of them on
// the Hertz ladder (docs/linear-solvers.md, "Lagged LU"), so a few more iterations than the first lagged solves take
// (1-4) are still cheaper than a factorisation.
constexpr int kRefactoriseAbove = 10;
// GMRES gives up on the lagged factors after this many iterations and the system is factorised afresh.
constexpr int kGiveUpAfter = 30;

// The kept factorisation as a Tpetra operator: y = alpha (LU)^-1 x + beta y, column by column (collective).
class LaggedLuOperator : public Operator {
 public:
  explicit LaggedLuOperator(sk_linear_system *sys) : sys_(sys) {}
  RCP<const Map> getDomainMap() const override { return sys_->row_map; }
  RCP<const Map> getRangeMap() const override { return sys_->row_map; }
  void apply(const MultiVector &X, MultiVector &Y, Teuchos::ETransp mode = Teuchos::NO_TRANS,
             Scalar alpha = Teuchos::ScalarTraits<Scalar>::one(),
             Scalar beta = Teuchos::ScalarTraits<Scalar>::zero()) const override {
    if (mode != Teuchos::NO_TRANS) throw std::logic_error("gmres-lu: the transposed factorisation is not applied");
    const size_t n = static_cast<size_t>(sys_->n_owned);
    // solve_lagged_lu's residual check runs after GMRES: owned_a is free while GMRES applies the factors
    std::vector<double> &out = solve_scratch(sys_).owned_a;
    for (size_t j = 0; j < X.getNumVectors(); ++j) {
      auto in = X.getData(j);
      sk_linear_report ignored{};
      if (solve_factorised(sys_, in.getRawPtr(), out.data(), &ignored) != SK_OK)
        throw std::runtime_error(sk_error_message());
      auto y = Y.getDataNonConst(j);
      for (size_t i = 0; i < n; ++i) y[i] = alpha * out[i] + (beta == 0.0 ? 0.0 : beta * y[i]);
    }
  }

 private:
  sk_linear_system *sys_;
};

}  // namespace

sk_status solve_lagged_lu(sk_linear_system *sys, const double *b, double *x, sk_linear_report *report) {
  report->solver = SK_LINEAR_GMRES_LU;
  const bool have = !sys->amesos.is_null() && sys->amesos_kind == kLaggedBackend && !sys->lagged_refactorise;
  int lagged_iterations = 0;
  if (have) {
    SolveScratch &scratch = solve_scratch(sys);
    const RCP<Vector> &xv = scratch.x, &bv = scratch.b;
    copy_to(b, *bv);
    GmresResult result;
    try {
      const int cap = std::min(kGiveUpAfter, sys->options.max_iterations);
      result = run_gmres(sys, rcp(new LaggedLuOperator(sys)), bv, xv, cap);
    } catch (...) {
      result = GmresResult{};  // a failed substitution (on every rank: solve_factorised agrees): refactorise below
      sk_error_clear();
    }
    lagged_iterations = result.iterations;
    if (result.converged) {
      copy_from(*xv, x);
      report->relative_residual = relative_residual(sys, *bv, *xv);
      if (std::isfinite(report->relative_residual)) {
        report->iterations = lagged_iterations;
        sys->lagged_refactorise = lagged_iterations > kRefactoriseAbove;
        return SK_OK;
      }
    }
  }
  // the factors are missing or too old for this matrix: factorise it and solve directly (as `mumps`)
  sys->lagged_refactorise = false;
  const sk_status status = solve_amesos(sys, kLaggedBackend, b, x, report);
  report->solver = SK_LINEAR_GMRES_LU;
  report->iterations = lagged_iterations;  // those of an abandoned lagged attempt
  return status;
}

}  // namespace stickslip::bridge
