// stickslip — MUMPS fed the bridge's owned rows directly (mumps_solver.hpp).
//
// Before, the bridge copied its rows into an Epetra matrix for Amesos_Mumps, which copied that again into its own
// equal row blocks (a redistributed Epetra matrix, rebuilt at every factorisation) and into triplet arrays of
// rows, columns and values; MUMPS then redistributes the entries to its fronts itself. Here MUMPS gets the owned rows
// as they are (ICNTL(18) = 3 accepts any distribution of the entries): two index arrays made once per pattern, the
// values read in place from sys->owned_values. The ICNTLs are those Amesos_Mumps 13.2 sets after MUMPS's
// initialisation (measured on Debian's build, docs/linear-solvers.md), so the pivot order and the results are those
// of the Amesos path.
#include "mumps_solver.hpp"

#include <algorithm>

#include "linear_system.hpp"

namespace stickslip::bridge {

namespace {

constexpr int kJobInit = -1, kJobEnd = -2, kJobAnalyse = 1, kJobFactorise = 2, kJobSolve = 3;

MUMPS_INT &icntl(DMUMPS_STRUC_C &id, int i) { return id.icntl[i - 1]; }  // MUMPS's 1-based numbering

}  // namespace

MumpsSolver::MumpsSolver(sk_linear_system *sys, int workspace_percent) : sys_(sys), id_() {
  if (sys->epetra_comm.is_null()) sys->epetra_comm = rcp(new Epetra_MpiComm(sys->comm));
  id_.job = kJobInit;
  id_.par = 1;  // the host works too
  id_.sym = 0;  // unsymmetric: contact rows and the multiplier rows are
  id_.comm_fortran = static_cast<MUMPS_INT>(MPI_Comm_c2f(sys->comm));
  dmumps_c(&id_);
  initialised_ = id_.infog[0] >= 0;
  // Amesos_Mumps's settings (Debian's 13.2, read from its instance after its analysis): output off, assembled input,
  // MUMPS's automatic column permutation, ordering and scaling (ICNTL(8) = 7: iterative row and column scaling),
  // A x = b, no iterative refinement or statistics inside MUMPS (the bridge refines: refine_solution), the ScaLAPACK
  // root, the workspace relaxation, no block low-rank; the right-hand side and solution centralised (ICNTL(20) and
  // (21) at their default 0). The rest keep MUMPS's defaults, as there.
  for (int i = 1; i <= 4; ++i) icntl(id_, i) = -1;
  icntl(id_, 5) = 0;
  icntl(id_, 6) = 7;
  icntl(id_, 7) = 7;
  icntl(id_, 8) = 7;
  icntl(id_, 9) = 1;
  for (int i = 10; i <= 13; ++i) icntl(id_, i) = 0;
  icntl(id_, 14) = workspace_percent;
  for (int i = 15; i <= 17; ++i) icntl(id_, i) = 0;
  icntl(id_, 18) = sys->size > 1 ? 3 : 0;

  const size_t entries = sys->owned_values.size();
  rows_.resize(entries);
  cols_.resize(entries);
  for (int i = 0; i < sys->n_owned; ++i)
    for (int64_t p = sys->row_ptr[i]; p < sys->row_ptr[i + 1]; ++p) {
      rows_[static_cast<size_t>(p)] = sys->first_row + i + 1;
      cols_[static_cast<size_t>(p)] = sys->cols[static_cast<size_t>(p)] + 1;
    }
  id_.n = sys->n;
  if (sys->size > 1) {
    id_.nz_loc = static_cast<MUMPS_INT>(entries);
    id_.nnz_loc = static_cast<MUMPS_INT8>(entries);
    id_.irn_loc = rows_.data();
    id_.jcn_loc = cols_.data();
  } else {
    id_.nz = static_cast<MUMPS_INT>(entries);
    id_.nnz = static_cast<MUMPS_INT8>(entries);
    id_.irn = rows_.data();
    id_.jcn = cols_.data();
  }
  if (sys->rank == 0) whole_.resize(static_cast<size_t>(sys->n));
}

MumpsSolver::~MumpsSolver() {
  if (!initialised_) return;
  id_.job = kJobEnd;
  dmumps_c(&id_);
}

const Epetra_Comm &MumpsSolver::Comm() const { return *sys_->epetra_comm; }

int MumpsSolver::call(int job) {
  id_.job = job;
  dmumps_c(&id_);
  if (id_.info[0] != 0) return id_.info[0];
  return id_.infog[0];
}

// The analysis sees the pattern only, as under Amesos_Mumps (which hands MUMPS the values at the factorisation).
int MumpsSolver::SymbolicFactorization() {
  if (!initialised_) return id_.infog[0] != 0 ? id_.infog[0] : -1;
  const int code = call(kJobAnalyse);
  symbolic_ += code == 0;
  return code;
}

int MumpsSolver::NumericFactorization() {
  if (sys_->size > 1) {
    id_.a_loc = sys_->owned_values.data();
  } else {
    id_.a = sys_->owned_values.data();
  }
  const int code = call(kJobFactorise);
  numeric_ += code == 0;
  return code;
}

int MumpsSolver::solve(const double *b, double *x) {
  if (sys_->size > 1) {
    gather_vector(sys_, b, whole_.data());
  } else {
    std::copy(b, b + sys_->n, whole_.begin());
  }
  id_.rhs = sys_->rank == 0 ? whole_.data() : nullptr;
  id_.nrhs = 1;
  id_.lrhs = sys_->n;
  const int code = call(kJobSolve);
  if (code != 0) return code;
  if (sys_->size > 1) {
    scatter_vector(sys_, whole_.data(), x);
  } else {
    std::copy(whole_.begin(), whole_.end(), x);
  }
  ++solves_;
  return 0;
}

}  // namespace stickslip::bridge
