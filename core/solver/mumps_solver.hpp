// stickslip — MUMPS (dmumps_c) fed the bridge's own owned rows, behind Amesos v1's solver interface so that the
// bridge holds it where it holds Amesos's KLU (sk_linear_system::amesos: gmres-lu and `auto` ask whether a
// factorisation is held). Internal to the bridge (direct_solvers.cpp); docs/linear-solvers.md says why.
#ifndef STICKSLIP_MUMPS_SOLVER_HPP
#define STICKSLIP_MUMPS_SOLVER_HPP

#include <vector>

#include <Amesos_BaseSolver.h>
#include <dmumps_c.h>

struct sk_linear_system;

namespace stickslip::bridge {

// One MUMPS instance over one pattern of sys (collective on sys->comm, as every call below): the matrix is given
// distributed (ICNTL(18) = 3; centralised on one rank) as triplets of global 1-based indices made once from the
// owned CSR rows, whose values MUMPS reads in place from sys->owned_values at each factorisation; the right-hand
// side and the solution are centralised on rank 0. Its ICNTLs are those Amesos_Mumps 13.2 sets.
class MumpsSolver final : public Amesos_BaseSolver {
 public:
  // JOB = -1 (initialisation) and the triplets; workspace_percent: ICNTL(14)
  MumpsSolver(sk_linear_system *sys, int workspace_percent);
  ~MumpsSolver() override;  // JOB = -2: frees the factors and workspace
  MumpsSolver(const MumpsSolver &) = delete;
  MumpsSolver &operator=(const MumpsSolver &) = delete;

  // Each returns 0, or MUMPS's INFO(1) (INFOG(1) where INFO(1) is 0) when either is not 0: Amesos_Mumps treats
  // MUMPS's warnings (positive codes) as failures too, and so does the bridge.
  int SymbolicFactorization() override;  // JOB = 1, on the pattern
  int NumericFactorization() override;   // JOB = 2, on the current sys->owned_values
  // JOB = 3: b over the owned rows in, x over the owned rows out (may alias)
  int solve(const double *b, double *x);
  int Solve() override { return -1; }  // Amesos's form (the Epetra problem's vectors): there is no Epetra problem

  const int *info() const { return id_.info; }
  const int *infog() const { return id_.infog; }
  const double *rinfog() const { return id_.rinfog; }

  // Amesos_BaseSolver's other members: no transpose, no parameter list (ICNTL(14) is the constructor's), no problem
  int SetUseTranspose(bool use_transpose) override { return use_transpose ? -1 : 0; }
  bool UseTranspose() const override { return false; }
  int SetParameters(Teuchos::ParameterList &) override { return 0; }
  const Epetra_LinearProblem *GetProblem() const override { return nullptr; }
  bool MatrixShapeOK() const override { return true; }
  const Epetra_Comm &Comm() const override;
  int NumSymbolicFact() const override { return symbolic_; }
  int NumNumericFact() const override { return numeric_; }
  int NumSolve() const override { return solves_; }
  void PrintStatus() const override {}
  void PrintTiming() const override {}

 private:
  int call(int job);  // runs JOB, returns as the members above

  sk_linear_system *sys_;
  DMUMPS_STRUC_C id_;
  bool initialised_ = false;
  std::vector<MUMPS_INT> rows_, cols_;  // the owned entries' global row and column, 1-based, in CSR order
  std::vector<double> whole_;           // rank 0: the centralised right-hand side, then solution
  int symbolic_ = 0, numeric_ = 0, solves_ = 0;
};

}  // namespace stickslip::bridge

#endif
