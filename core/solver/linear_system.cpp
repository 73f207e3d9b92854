// stickslip — sk_linsys_*: distributed Tpetra matrix; direct by Amesos v1 MUMPS / KLU (Epetra copy) or Amesos2
// KLU2; Belos GMRES with MueLu or Ifpack2.
//
// Assembly. Each rank writes into a values array laid over the replicated CSR pattern. At set_pattern time the
// ranks agree (once) which of their local rows go to which owner; sk_linsys_assemble then moves the values of
// those rows with one MPI_Alltoallv, sums them into the owner's CSR-ordered `owned_values`, and replaces the
// values of the static-graph Tpetra matrix in place. Because row ownership is in contiguous blocks, the owners'
// `owned_values` concatenated over ranks are exactly the full CSR values array: the direct solver's gather to
// rank 0 is a single MPI_Gatherv.
#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <Amesos.h>
#include <Amesos2.hpp>
#include <Amesos_BaseSolver.h>
#include <Epetra_CrsGraph.h>
#include <Epetra_CrsMatrix.h>
#include <Epetra_LinearProblem.h>
#include <Epetra_Map.h>
#include <Epetra_MpiComm.h>
#include <Epetra_Object.h>
#include <Epetra_Vector.h>
#include <BelosSolverFactory.hpp>
#include <BelosTpetraAdapter.hpp>
#include <Ifpack2_Factory.hpp>
#include <MueLu_CreateTpetraPreconditioner.hpp>
#include <Teuchos_DefaultMpiComm.hpp>
#include <Teuchos_ParameterList.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Details_initializeKokkos.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_Vector.hpp>

#include "bridge_internal.hpp"
#include "stickslip/bridge.h"
#include "stickslip/condense.h"

namespace {

// Debian's Tpetra is instantiated for exactly these types (TpetraCore_config.h: INST_DOUBLE, INST_INT_LONG_LONG,
// INST_SERIAL).
using Scalar = double;
using LocalOrdinal = int;
using GlobalOrdinal = long long;
using Node = Tpetra::Map<>::node_type;
using Map = Tpetra::Map<LocalOrdinal, GlobalOrdinal, Node>;
using Graph = Tpetra::CrsGraph<LocalOrdinal, GlobalOrdinal, Node>;
using Matrix = Tpetra::CrsMatrix<Scalar, LocalOrdinal, GlobalOrdinal, Node>;
using Vector = Tpetra::Vector<Scalar, LocalOrdinal, GlobalOrdinal, Node>;
using MultiVector = Tpetra::MultiVector<Scalar, LocalOrdinal, GlobalOrdinal, Node>;
using Operator = Tpetra::Operator<Scalar, LocalOrdinal, GlobalOrdinal, Node>;
using RowMatrix = Tpetra::RowMatrix<Scalar, LocalOrdinal, GlobalOrdinal, Node>;
using DirectSolver = Amesos2::Solver<Matrix, MultiVector>;
using MueLuOperator = MueLu::TpetraOperator<Scalar, LocalOrdinal, GlobalOrdinal, Node>;
using Ifpack2Preconditioner = Ifpack2::Preconditioner<Scalar, LocalOrdinal, GlobalOrdinal, Node>;
using Teuchos::RCP;
using Teuchos::rcp;

using stickslip::bridge::status_from_exception;

// AUTO's rule, from docs/linear-solvers.md (elasticity benchmark on this machine; re-measured with MUMPS, which
// moves neither crossover enough to change them): the direct solver is faster or level up to
// about 10000 unknowns on 2D-like sparsity (<= 40 entries per row: quad4 elasticity has ~18) and up to about 2000
// on 3D-like sparsity (hex8 elasticity has ~81), where its fill grows much faster; GMRES + MueLu beyond. Ties go
// to the direct solver, which also copes with the indefinite systems of contact.
constexpr int kAutoSparseRowEntries = 40;
constexpr int kAutoDirectMaxUnknownsSparse = 10000;
constexpr int kAutoDirectMaxUnknownsDense = 2000;
constexpr int kGmresRestart = 100;
// A direct solve whose measured residual exceeds this is a (numerically) singular matrix, not round-off.
constexpr double kDirectResidualLimit = 1e-6;
// What `direct` (and AUTO's direct choice, including its fallback) runs: the fastest correct backend on the
// benchmark's hex8/quad4 elasticity and on the contact saddle-point systems (docs/linear-solvers.md).
constexpr sk_linear_solver_kind kDirectBackend = SK_LINEAR_DIRECT_MUMPS;

double now_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

struct sk_linear_system {
  MPI_Comm comm = MPI_COMM_NULL;  // duplicated, so our collectives never interleave with the caller's
  int rank = 0;
  int size = 1;
  sk_linear_options options{};
  int block_size = 1;
  int coordinate_dim = 0;            // 0: no coordinates (translations-only nullspace)
  std::vector<double> coordinates;   // replicated, node-major
  RCP<const Teuchos::Comm<int>> tcomm;

  // replicated pattern and this rank's contributions
  int n = 0;
  std::vector<int64_t> row_ptr;
  std::vector<int> cols;
  std::vector<int> local_rows;
  std::vector<double> values;

  // contiguous row blocks: rank r owns rows [row_offsets[r], row_offsets[r+1])
  std::vector<int> row_offsets;
  int64_t owned_value_begin = 0;  // row_ptr[first owned row]
  std::vector<double> owned_values;
  std::vector<LocalOrdinal> owned_local_cols;  // Tpetra column-map index of each owned CSR entry
  std::vector<int64_t> owned_diagonal;         // index of each owned row's diagonal in owned_values, -1 if absent

  // the once-per-pattern exchange plan of sk_linsys_assemble (counts in values, per rank)
  std::vector<int> send_counts, send_displs, recv_counts, recv_displs;
  std::vector<int> send_rows;  // local rows in send order (sorted; grouped by owner)
  std::vector<int> recv_rows;  // rows received, in receive order
  std::vector<double> send_buffer, recv_buffer;

  RCP<const Map> row_map;
  RCP<Matrix> matrix;
  bool assembled = false;
  // AUTO chose GMRES + MueLu and it did not converge (e.g. a saddle-point contact system): direct for this pattern
  bool auto_fell_back = false;

  // direct: on one rank the distributed matrix itself; on more, a serial copy on rank 0
  RCP<const Map> serial_map;
  RCP<Matrix> serial_matrix;
  std::vector<LocalOrdinal> serial_local_cols;
  std::vector<int> gather_counts, gather_displs;
  std::vector<double> gathered_values;
  RCP<DirectSolver> direct;

  // Amesos v1 (Epetra) direct solvers, MUMPS or KLU: on the same contiguous row blocks as the Tpetra matrix.
  // Destroyed in reverse order of construction (solver, problem, vectors, matrix, map, comm).
  RCP<Epetra_MpiComm> epetra_comm;
  RCP<Epetra_Map> epetra_map;
  RCP<Epetra_CrsMatrix> epetra_matrix;
  std::vector<int> epetra_slots;  // position, within Epetra's storage of its row, of each owned CSR entry
  RCP<Epetra_Vector> epetra_x, epetra_b;
  RCP<Epetra_LinearProblem> epetra_problem;
  RCP<Amesos_BaseSolver> amesos;
  sk_linear_solver_kind amesos_kind = SK_LINEAR_DIRECT;
  sk_linear_solver_kind last_kind = SK_LINEAR_AUTO;  // the backend of the last solve (sk_linsys_solve_again)

  // iterative
  RCP<MueLuOperator> muelu;
  RCP<Ifpack2Preconditioner> ilu;
};

namespace {

bool is_direct(sk_linear_solver_kind kind) {
  return kind == SK_LINEAR_DIRECT || kind == SK_LINEAR_DIRECT_MUMPS || kind == SK_LINEAR_DIRECT_KLU2 ||
         kind == SK_LINEAR_DIRECT_KLU;
}

// The backend that actually runs: `direct` is the measured-fastest direct solver, AUTO picks by size and sparsity.
sk_linear_solver_kind resolve_kind(const sk_linear_system *sys) {
  sk_linear_solver_kind kind = sys->options.kind;
  if (kind == SK_LINEAR_AUTO) {
    const double entries_per_row = sys->n > 0 ? static_cast<double>(sys->row_ptr[sys->n]) / sys->n : 0.0;
    const int limit =
        entries_per_row <= kAutoSparseRowEntries ? kAutoDirectMaxUnknownsSparse : kAutoDirectMaxUnknownsDense;
    kind = sys->auto_fell_back || sys->n <= limit ? SK_LINEAR_DIRECT : SK_LINEAR_GMRES_MUELU;
  }
  return kind == SK_LINEAR_DIRECT ? kDirectBackend : kind;
}

// Drops everything derived from the pattern (maps, matrices, factorisations, preconditioners).
void release_amesos(sk_linear_system *sys) {
  sys->amesos = Teuchos::null;
  sys->epetra_problem = Teuchos::null;
  sys->epetra_x = Teuchos::null;
  sys->epetra_b = Teuchos::null;
  sys->epetra_matrix = Teuchos::null;
  sys->epetra_slots.clear();
  sys->epetra_map = Teuchos::null;
}

void release_pattern(sk_linear_system *sys) {
  release_amesos(sys);
  sys->direct = Teuchos::null;
  sys->muelu = Teuchos::null;
  sys->ilu = Teuchos::null;
  sys->serial_matrix = Teuchos::null;
  sys->serial_map = Teuchos::null;
  sys->matrix = Teuchos::null;
  sys->row_map = Teuchos::null;
  sys->assembled = false;
  sys->auto_fell_back = false;
}

// Copies the owned slice of a replicated array into a distributed vector on the row map.
void scatter_to(const sk_linear_system *sys, const double *replicated, Vector &v) {
  auto data = v.getDataNonConst();
  const int begin = sys->row_offsets[sys->rank];
  for (size_t i = 0; i < static_cast<size_t>(data.size()); ++i) data[i] = replicated[begin + static_cast<int>(i)];
}

// Every rank receives the whole vector (row blocks are contiguous, so this is an Allgatherv).
void gather_from(const sk_linear_system *sys, const Vector &v, double *replicated) {
  auto data = v.getData();
  std::vector<int> counts(sys->size), displs(sys->size);
  for (int r = 0; r < sys->size; ++r) {
    displs[r] = sys->row_offsets[r];
    counts[r] = sys->row_offsets[r + 1] - sys->row_offsets[r];
  }
  MPI_Allgatherv(data.getRawPtr(), counts[sys->rank], MPI_DOUBLE, replicated, counts.data(), displs.data(),
                 MPI_DOUBLE, sys->comm);
}

// Replaces the values of a static-graph matrix row by row (entries addressed by column-map index).
void replace_values(Matrix &matrix, const std::vector<int64_t> &row_ptr, int64_t value_begin, int first_row,
                    int n_rows, const double *values, const std::vector<LocalOrdinal> &local_cols) {
  if (matrix.isFillComplete()) matrix.resumeFill();
  for (int i = 0; i < n_rows; ++i) {
    const int64_t b = row_ptr[first_row + i] - value_begin, e = row_ptr[first_row + i + 1] - value_begin;
    matrix.replaceLocalValues(i, static_cast<LocalOrdinal>(e - b), values + b, local_cols.data() + b);
  }
  matrix.fillComplete(matrix.getDomainMap(), matrix.getRangeMap());
}

// Builds the static graph of rows [first_row, first_row + map's local count) and the CSR -> column-map index table.
RCP<Matrix> build_matrix(const RCP<const Map> &row_map, const RCP<const Map> &domain_map,
                         const std::vector<int64_t> &row_ptr, const std::vector<int> &cols, int first_row,
                         std::vector<LocalOrdinal> &local_cols) {
  const int n_rows = static_cast<int>(row_map->getNodeNumElements());
  std::vector<size_t> entries(n_rows);
  for (int i = 0; i < n_rows; ++i) entries[i] = static_cast<size_t>(row_ptr[first_row + i + 1] - row_ptr[first_row + i]);
  auto graph = rcp(new Graph(row_map, Teuchos::ArrayView<const size_t>(entries.data(), n_rows)));
  std::vector<GlobalOrdinal> row_cols;
  for (int i = 0; i < n_rows; ++i) {
    row_cols.assign(cols.begin() + row_ptr[first_row + i], cols.begin() + row_ptr[first_row + i + 1]);
    graph->insertGlobalIndices(first_row + i, static_cast<LocalOrdinal>(row_cols.size()), row_cols.data());
  }
  graph->fillComplete(domain_map, row_map);
  const int64_t begin = row_ptr[first_row], end = row_ptr[first_row + n_rows];
  local_cols.resize(static_cast<size_t>(end - begin));
  auto col_map = graph->getColMap();
  for (int64_t k = begin; k < end; ++k) local_cols[k - begin] = col_map->getLocalElement(cols[k]);
  auto matrix = rcp(new Matrix(graph));
  matrix->fillComplete(domain_map, row_map);
  return matrix;
}

sk_status check_pattern(int n, const int64_t *row_ptr, const int *cols, int n_local_rows, const int *local_rows) {
  if (n < 0) return sk_error_set(SK_ERR_INPUT, "linear system: negative size %d", n);
  if (!row_ptr || (n > 0 && !cols)) return sk_error_set(SK_ERR_INPUT, "linear system: missing CSR arrays");
  if (row_ptr[0] != 0) return sk_error_set(SK_ERR_INPUT, "linear system: row_ptr[0] = %lld, expected 0", (long long)row_ptr[0]);
  for (int i = 0; i < n; ++i) {
    if (row_ptr[i + 1] < row_ptr[i])
      return sk_error_set(SK_ERR_INPUT, "linear system: row_ptr decreases at row %d", i);
    for (int64_t k = row_ptr[i]; k < row_ptr[i + 1]; ++k) {
      if (cols[k] < 0 || cols[k] >= n)
        return sk_error_set(SK_ERR_INPUT, "linear system: column %d of row %d is outside [0, %d)", cols[k], i, n);
      if (k > row_ptr[i] && cols[k] <= cols[k - 1])
        return sk_error_set(SK_ERR_INPUT, "linear system: columns of row %d are not sorted and unique", i);
    }
  }
  if (n_local_rows < 0 || (n_local_rows > 0 && !local_rows))
    return sk_error_set(SK_ERR_INPUT, "linear system: bad local rows (%d)", n_local_rows);
  for (int i = 0; i < n_local_rows; ++i) {
    if (local_rows[i] < 0 || local_rows[i] >= n || (i > 0 && local_rows[i] <= local_rows[i - 1]))
      return sk_error_set(SK_ERR_INPUT, "linear system: local rows must be sorted, unique and in [0, %d)", n);
  }
  return SK_OK;
}

// The same status on every rank: the worst (largest code) wins, with rank-local messages kept where they arose
// and a generic one elsewhere.
sk_status agree(MPI_Comm comm, sk_status local, const char *what) {
  int code = static_cast<int>(local), worst = 0;
  MPI_Allreduce(&code, &worst, 1, MPI_INT, MPI_MAX, comm);
  if (worst != SK_OK && local == SK_OK) return sk_error_set(static_cast<sk_status>(worst), "%s failed on another rank", what);
  return static_cast<sk_status>(worst == SK_OK ? SK_OK : (local != SK_OK ? local : worst));
}

double relative_residual(sk_linear_system *sys, const Vector &b, const Vector &x) {
  Vector r(sys->row_map);
  sys->matrix->apply(x, r);
  r.update(1.0, b, -1.0);
  const double norm_b = b.norm2();
  return norm_b > 0 ? r.norm2() / norm_b : r.norm2();
}

// Direct solve. KLU2 always runs on one process: the distributed matrix itself on one rank, the serial copy on
// rank 0 otherwise (Debian's Amesos2 KLU2 returns wrong solutions on distributed matrices; Tacho crashes).
sk_status solve_direct(sk_linear_system *sys, const double *b, double *x, sk_linear_report *report) {
  const bool gathered = sys->size > 1;
  int status = SK_OK;
  char message[256] = "";
  if (gathered) {
    MPI_Gatherv(sys->owned_values.data(), sys->gather_counts[sys->rank], MPI_DOUBLE, sys->gathered_values.data(),
                sys->gather_counts.data(), sys->gather_displs.data(), MPI_DOUBLE, 0, sys->comm);
  }
  if (sys->rank == 0) {
    try {
      RCP<Matrix> a = sys->matrix;
      RCP<const Map> map = sys->row_map;
      if (gathered) {
        if (sys->serial_matrix.is_null()) {
          sys->serial_map = rcp(new Map(static_cast<Tpetra::global_size_t>(sys->n), 0,
                                        rcp(new Teuchos::MpiComm<int>(MPI_COMM_SELF))));
          sys->serial_matrix = build_matrix(sys->serial_map, sys->serial_map, sys->row_ptr, sys->cols, 0,
                                            sys->serial_local_cols);
        }
        replace_values(*sys->serial_matrix, sys->row_ptr, 0, 0, sys->n, sys->gathered_values.data(),
                       sys->serial_local_cols);
        a = sys->serial_matrix;
        map = sys->serial_map;
      }
      if (sys->direct.is_null()) {
        sys->direct = Amesos2::create<Matrix, MultiVector>("KLU2", a);
        sys->direct->symbolicFactorization();
        report->refactored_symbolic = 1;
      }
      sys->direct->numericFactorization();
      Vector xs(map), bs(map);
      auto bd = bs.getDataNonConst();
      std::copy(b, b + sys->n, bd.getRawPtr());
      sys->direct->solve(Teuchos::ptr<MultiVector>(&xs), Teuchos::ptr<const MultiVector>(&bs));
      auto xd = xs.getData();
      std::copy(xd.getRawPtr(), xd.getRawPtr() + sys->n, x);
      for (int i = 0; i < sys->n; ++i) {
        if (!std::isfinite(x[i])) {
          status = SK_ERR_DIVERGED;
          std::snprintf(message, sizeof message, "direct solve (KLU2): non-finite solution (singular matrix)");
          break;
        }
      }
    } catch (...) {
      // a failed factorisation may leave the solver half-built: start afresh next time
      sys->direct = Teuchos::null;
      status = status_from_exception(SK_ERR_DIVERGED, "direct solve (KLU2, singular matrix?)", std::current_exception());
      std::snprintf(message, sizeof message, "%s", sk_error_message());
    }
  }
  if (gathered) {
    MPI_Bcast(&status, 1, MPI_INT, 0, sys->comm);
    MPI_Bcast(message, sizeof message, MPI_CHAR, 0, sys->comm);
    MPI_Bcast(&report->refactored_symbolic, 1, MPI_INT, 0, sys->comm);
    if (status == SK_OK) MPI_Bcast(x, sys->n, MPI_DOUBLE, 0, sys->comm);
  }
  if (status != SK_OK) return sk_error_set(static_cast<sk_status>(status), "%s", message);
  Vector xv(sys->row_map), bv(sys->row_map);
  scatter_to(sys, x, xv);
  scatter_to(sys, b, bv);
  report->relative_residual = relative_residual(sys, bv, xv);
  if (!(report->relative_residual <= kDirectResidualLimit))
    return sk_error_set(SK_ERR_DIVERGED, "direct solve (KLU2): relative residual %.3g (singular matrix)",
                        report->relative_residual);
  return SK_OK;
}

const char *amesos_backend_name(sk_linear_solver_kind kind) { return kind == SK_LINEAR_DIRECT_MUMPS ? "MUMPS" : "KLU"; }

// The Epetra copy of the pattern for Amesos v1: same map (contiguous row blocks of sys->row_offsets), a static
// graph, and the table from owned CSR entries to Epetra's (column-map ordered) value storage.
void build_epetra(sk_linear_system *sys) {
  if (sys->epetra_comm.is_null()) sys->epetra_comm = rcp(new Epetra_MpiComm(sys->comm));
  const int first_row = sys->row_offsets[sys->rank];
  const int n_owned = sys->row_offsets[sys->rank + 1] - first_row;
  sys->epetra_map = rcp(new Epetra_Map(sys->n, n_owned, 0, *sys->epetra_comm));
  std::vector<int> entries(static_cast<size_t>(n_owned));
  for (int i = 0; i < n_owned; ++i)
    entries[i] = static_cast<int>(sys->row_ptr[first_row + i + 1] - sys->row_ptr[first_row + i]);
  Epetra_CrsGraph graph(Epetra_DataAccess::Copy, *sys->epetra_map, entries.data(), true);
  for (int i = 0; i < n_owned; ++i) {
    if (graph.InsertGlobalIndices(first_row + i, entries[i], sys->cols.data() + sys->row_ptr[first_row + i]) < 0)
      throw std::runtime_error("Epetra_CrsGraph::InsertGlobalIndices failed");
  }
  if (graph.FillComplete() != 0 || graph.OptimizeStorage() != 0)
    throw std::runtime_error("Epetra_CrsGraph::FillComplete failed");
  sys->epetra_matrix = rcp(new Epetra_CrsMatrix(Epetra_DataAccess::Copy, graph));
  if (sys->epetra_matrix->FillComplete() != 0 || sys->epetra_matrix->OptimizeStorage() != 0)
    throw std::runtime_error("Epetra_CrsMatrix::FillComplete failed");
  int *offsets = nullptr, *indices = nullptr;
  double *values = nullptr;
  sys->epetra_matrix->ExtractCrsDataPointers(offsets, indices, values);
  sys->epetra_slots.assign(sys->owned_values.size(), 0);
  std::vector<std::pair<int, int>> row;  // (global column, storage position)
  for (int i = 0; i < n_owned; ++i) {
    row.clear();
    for (int p = offsets[i]; p < offsets[i + 1]; ++p) row.emplace_back(sys->epetra_matrix->GCID(indices[p]), p);
    std::sort(row.begin(), row.end());  // CSR columns are sorted: the k-th smallest column is the k-th CSR entry
    const int64_t base = sys->row_ptr[first_row + i] - sys->owned_value_begin;
    if (static_cast<int64_t>(row.size()) != static_cast<int64_t>(entries[i]))
      throw std::runtime_error("Epetra matrix row length differs from the pattern");
    for (size_t k = 0; k < row.size(); ++k) sys->epetra_slots[static_cast<size_t>(base) + k] = row[k].second;
  }
  sys->epetra_x = rcp(new Epetra_Vector(*sys->epetra_map));
  sys->epetra_b = rcp(new Epetra_Vector(*sys->epetra_map));
  sys->epetra_problem = rcp(new Epetra_LinearProblem(sys->epetra_matrix.get(), sys->epetra_x.get(), sys->epetra_b.get()));
}

// Direct solve by Amesos v1 (MUMPS or KLU) on the distributed Epetra matrix: both are correct on several ranks
// (MUMPS factorises in parallel; Amesos_Klu gathers to rank 0 itself). The symbolic factorisation is computed once
// per pattern (with the first values: MUMPS's analysis uses them for its scaling / zero-free-diagonal permutation,
// which matters for the multiplier rows of contact); every solve redoes the numeric factorisation only.
sk_status solve_amesos(sk_linear_system *sys, sk_linear_solver_kind kind, const double *b, double *x,
                       sk_linear_report *report) {
  const char *backend = amesos_backend_name(kind);
  if (sys->epetra_matrix.is_null()) build_epetra(sys);
  {
    int *offsets = nullptr, *indices = nullptr;
    double *values = nullptr;
    sys->epetra_matrix->ExtractCrsDataPointers(offsets, indices, values);
    for (size_t k = 0; k < sys->owned_values.size(); ++k) values[sys->epetra_slots[k]] = sys->owned_values[k];
  }
  // Amesos_Mumps reports every MUMPS error (a singular matrix: INFOG(1) = -10) on std::cerr itself; the status and
  // message returned here say it once, so its report is muted unless verbose
  struct MuteCerr {
    std::streambuf *saved = nullptr;
    explicit MuteCerr(bool mute) : saved(mute ? std::cerr.rdbuf(nullptr) : nullptr) {}
    ~MuteCerr() {
      if (saved) std::cerr.rdbuf(saved);  // rdbuf(sb) also clears the badbit set while muted
    }
  } mute(!sys->options.verbose);
  // all ranks see the same return codes (MUMPS's are global) but agree anyway: a mismatch would deadlock
  auto failed = [sys](int code) {
    int worst = code < 0 ? code : (code > 0 ? -code : 0), result = 0;
    MPI_Allreduce(&worst, &result, 1, MPI_INT, MPI_MIN, sys->comm);
    return result;
  };
  if (sys->amesos.is_null() || sys->amesos_kind != kind) {
    Epetra_Object::SetTracebackMode(sys->options.verbose ? 1 : 0);  // Amesos prints every error code otherwise
    Amesos factory;
    sys->amesos = rcp(factory.Create(kind == SK_LINEAR_DIRECT_MUMPS ? "Amesos_Mumps" : "Amesos_Klu",
                                     *sys->epetra_problem));
    if (sys->amesos.is_null()) return sk_error_set(SK_ERR_INTERNAL, "direct solve (%s): Amesos has no such solver", backend);
    sys->amesos_kind = kind;
    Teuchos::ParameterList params;
    params.set("OutputLevel", sys->options.verbose ? 1 : 0);
    params.set("ComputeTrueResidual", false);
    params.set("ComputeVectorNorms", false);
    sys->amesos->SetParameters(params);
    if (const int code = failed(sys->amesos->SymbolicFactorization())) {
      sys->amesos = Teuchos::null;
      return sk_error_set(SK_ERR_DIVERGED, "direct solve (%s): symbolic factorisation failed (error %d)", backend, code);
    }
    report->refactored_symbolic = 1;
  }
  if (const int code = failed(sys->amesos->NumericFactorization())) {
    sys->amesos = Teuchos::null;  // start afresh (symbolic included) next time
    return sk_error_set(SK_ERR_DIVERGED, "direct solve (%s): numeric factorisation failed (error %d, singular matrix)",
                        backend, code);
  }
  const int first_row = sys->row_offsets[sys->rank];
  const int n_owned = sys->row_offsets[sys->rank + 1] - first_row;
  std::copy(b + first_row, b + first_row + n_owned, sys->epetra_b->Values());
  if (const int code = failed(sys->amesos->Solve()))
    return sk_error_set(SK_ERR_DIVERGED, "direct solve (%s): solve failed (error %d)", backend, code);
  std::vector<int> counts(sys->size), displs(sys->size);
  for (int r = 0; r < sys->size; ++r) {
    displs[r] = sys->row_offsets[r];
    counts[r] = sys->row_offsets[r + 1] - sys->row_offsets[r];
  }
  MPI_Allgatherv(sys->epetra_x->Values(), n_owned, MPI_DOUBLE, x, counts.data(), displs.data(), MPI_DOUBLE, sys->comm);
  Vector xv(sys->row_map), bv(sys->row_map);
  scatter_to(sys, x, xv);
  scatter_to(sys, b, bv);
  report->relative_residual = relative_residual(sys, bv, xv);
  if (!(report->relative_residual <= kDirectResidualLimit))  // NaN included
    return sk_error_set(SK_ERR_DIVERGED, "direct solve (%s): relative residual %.3g (singular matrix)", backend,
                        report->relative_residual);
  return SK_OK;
}

RCP<Teuchos::ParameterList> muelu_parameters(const sk_linear_system *sys) {
  auto p = rcp(new Teuchos::ParameterList);
  p->set("verbosity", sys->options.verbose ? "low" : "none");
  p->set("multigrid algorithm", "sa");
  p->set("number of equations", sys->block_size);
  // keep the aggregates (tentative prolongator) when only the values change
  p->set("reuse: type", "tP");
  if (sys->size > 1) {
    // the default coarse solver is Amesos2 KLU2 on the distributed coarse matrix: the defective path
    p->set("coarse: type", "RELAXATION");
    p->sublist("coarse: params").set("relaxation: type", "Symmetric Gauss-Seidel");
    p->sublist("coarse: params").set("relaxation: sweeps", 4);
  }
  return p;
}

// Rigid-body modes on this rank's rows (coordinates centred, so the rotations are well scaled against the
// translations): 2D (1,0) (0,1) (-y,x); 3D adds (0,0,1) and the rotations about x, y, z.
RCP<MultiVector> rigid_body_modes(const sk_linear_system *sys) {
  const int dim = sys->coordinate_dim;
  const int n_modes = dim == 2 ? 3 : 6;
  const size_t n_nodes = sys->coordinates.size() / static_cast<size_t>(dim);
  double centre[3] = {0, 0, 0};
  for (size_t node = 0; node < n_nodes; ++node)
    for (int c = 0; c < dim; ++c) centre[c] += sys->coordinates[node * dim + c] / static_cast<double>(n_nodes);
  auto modes = rcp(new MultiVector(sys->row_map, static_cast<size_t>(n_modes)));
  const int first_row = sys->row_offsets[sys->rank], n_owned = sys->row_offsets[sys->rank + 1] - first_row;
  for (int m = 0; m < n_modes; ++m) {
    auto data = modes->getDataNonConst(static_cast<size_t>(m));
    for (int i = 0; i < n_owned; ++i) {
      const int row = first_row + i, node = row / dim, c = row % dim;
      const double x = sys->coordinates[node * dim] - centre[0], y = sys->coordinates[node * dim + 1] - centre[1];
      const double z = dim == 3 ? sys->coordinates[node * dim + 2] - centre[2] : 0.0;
      double v = m == c ? 1.0 : 0.0;  // translations
      if (dim == 2 && m == 2) v = c == 0 ? -y : x;
      if (dim == 3 && m == 3) v = c == 0 ? -y : (c == 1 ? x : 0.0);  // about z
      if (dim == 3 && m == 4) v = c == 1 ? -z : (c == 2 ? y : 0.0);  // about x
      if (dim == 3 && m == 5) v = c == 2 ? -x : (c == 0 ? z : 0.0);  // about y
      data[i] = v;
    }
  }
  return modes;
}

sk_status solve_iterative(sk_linear_system *sys, sk_linear_solver_kind kind, const double *b, double *x,
                          sk_linear_report *report) {
  RCP<Vector> xv = rcp(new Vector(sys->row_map)), bv = rcp(new Vector(sys->row_map));
  scatter_to(sys, b, *bv);
  RCP<Operator> preconditioner;
  if (kind == SK_LINEAR_GMRES_MUELU) {
    if (sys->muelu.is_null()) {
      auto params = muelu_parameters(sys);
      if (sys->coordinate_dim > 0) {
        if (static_cast<size_t>(sys->n) != sys->coordinates.size() || sys->block_size != sys->coordinate_dim)
          return sk_error_set(SK_ERR_INPUT,
                              "gmres-muelu: coordinates give %zu unknowns with block size %d, the system has %d "
                              "unknowns with block size %d",
                              sys->coordinates.size(), sys->coordinate_dim, sys->n, sys->block_size);
        params->sublist("user data").set("Nullspace", rigid_body_modes(sys));
      }
      sys->muelu = MueLu::CreateTpetraPreconditioner(RCP<Operator>(sys->matrix), *params);
      report->refactored_symbolic = 1;
    } else {
      MueLu::ReuseTpetraPreconditioner(sys->matrix, *sys->muelu);
    }
    preconditioner = sys->muelu;
  } else {
    if (sys->ilu.is_null()) {
      sys->ilu = Ifpack2::Factory::create<RowMatrix>("RILUK", sys->matrix);
      Teuchos::ParameterList p;
      p.set("fact: iluk level-of-fill", 1);
      sys->ilu->setParameters(p);
      sys->ilu->initialize();
      report->refactored_symbolic = 1;
    }
    sys->ilu->compute();
    preconditioner = sys->ilu;
  }
  auto params = rcp(new Teuchos::ParameterList);
  params->set("Convergence Tolerance", sys->options.tolerance);
  params->set("Maximum Iterations", sys->options.max_iterations);
  params->set("Num Blocks", std::min(kGmresRestart, std::max(1, sys->options.max_iterations)));
  params->set("Implicit Residual Scaling", "Norm of RHS");
  params->set("Explicit Residual Scaling", "Norm of RHS");
  params->set("Verbosity", sys->options.verbose && sys->rank == 0
                               ? Belos::Errors + Belos::Warnings + Belos::FinalSummary
                               : static_cast<int>(Belos::Errors));
  auto problem = rcp(new Belos::LinearProblem<Scalar, MultiVector, Operator>(sys->matrix, xv, bv));
  problem->setRightPrec(preconditioner);
  problem->setProblem();
  Belos::SolverFactory<Scalar, MultiVector, Operator> factory;
  auto solver = factory.create("GMRES", params);
  solver->setProblem(problem);
  const Belos::ReturnType result = solver->solve();
  report->iterations = solver->getNumIters();
  gather_from(sys, *xv, x);
  report->relative_residual = relative_residual(sys, *bv, *xv);
  if (result != Belos::Converged || !std::isfinite(report->relative_residual))
    return sk_error_set(SK_ERR_DIVERGED, "%s: no convergence to %.3g in %d iterations (relative residual %.3g)",
                        sk_linear_solver_name(kind), sys->options.tolerance, report->iterations,
                        report->relative_residual);
  return SK_OK;
}

}  // namespace

extern "C" {

void sk_linear_options_default(sk_linear_options *options) {
  options->kind = SK_LINEAR_AUTO;
  options->tolerance = 1e-10;
  options->max_iterations = 500;
  options->verbose = 0;
}

sk_status sk_linear_solver_from_name(const char *name, sk_linear_solver_kind *kind) {
  static const struct {
    const char *name;
    sk_linear_solver_kind kind;
  } names[] = {{"direct", SK_LINEAR_DIRECT},
               {"gmres-muelu", SK_LINEAR_GMRES_MUELU},
               {"gmres-ilu", SK_LINEAR_GMRES_ILU},
               {"auto", SK_LINEAR_AUTO},
               {"mumps", SK_LINEAR_DIRECT_MUMPS},
               {"klu2", SK_LINEAR_DIRECT_KLU2},
               {"klu", SK_LINEAR_DIRECT_KLU}};
  for (const auto &entry : names) {
    if (name && std::strcmp(name, entry.name) == 0) {
      *kind = entry.kind;
      return SK_OK;
    }
  }
  return sk_error_set(SK_ERR_INPUT, "unknown linear solver '%s' (expected direct, gmres-muelu, gmres-ilu, auto, mumps, klu2 or klu)",
                      name ? name : "(null)");
}

const char *sk_linear_solver_name(sk_linear_solver_kind kind) {
  switch (kind) {
    case SK_LINEAR_DIRECT: return "direct";
    case SK_LINEAR_GMRES_MUELU: return "gmres-muelu";
    case SK_LINEAR_GMRES_ILU: return "gmres-ilu";
    case SK_LINEAR_AUTO: return "auto";
    case SK_LINEAR_DIRECT_MUMPS: return "mumps";
    case SK_LINEAR_DIRECT_KLU2: return "klu2";
    case SK_LINEAR_DIRECT_KLU: return "klu";
  }
  return "unknown";
}

sk_status sk_linsys_create(MPI_Comm comm, const sk_linear_options *options, sk_linear_system **sys) {
  *sys = nullptr;
  try {
    Tpetra::Details::initializeKokkos();
    auto created = std::make_unique<sk_linear_system>();
    if (options) {
      created->options = *options;
    } else {
      sk_linear_options_default(&created->options);
    }
    if (created->options.kind < SK_LINEAR_DIRECT || created->options.kind > SK_LINEAR_DIRECT_KLU)
      return sk_error_set(SK_ERR_INPUT, "linear system: unknown solver kind %d", (int)created->options.kind);
    if (!(created->options.tolerance > 0) || created->options.max_iterations < 1)
      return sk_error_set(SK_ERR_INPUT, "linear system: tolerance (%g) and max_iterations (%d) must be positive",
                          created->options.tolerance, created->options.max_iterations);
    MPI_Comm_dup(comm, &created->comm);
    MPI_Comm_rank(created->comm, &created->rank);
    MPI_Comm_size(created->comm, &created->size);
    created->tcomm = rcp(new Teuchos::MpiComm<int>(created->comm));
    *sys = created.release();
    return SK_OK;
  } catch (...) {
    return status_from_exception(SK_ERR_INTERNAL, "sk_linsys_create", std::current_exception());
  }
}

void sk_linsys_destroy(sk_linear_system *sys) {
  if (!sys) return;
  try {
    release_pattern(sys);
    sys->epetra_comm = Teuchos::null;
    sys->tcomm = Teuchos::null;
  } catch (...) {
    // destruction must not throw into C; nothing useful to report
  }
  if (sys->comm != MPI_COMM_NULL) MPI_Comm_free(&sys->comm);
  delete sys;
}

sk_status sk_linsys_set_block_size(sk_linear_system *sys, int block_size) {
  // checked against the unknowns by the next sk_linsys_set_pattern, which callers make after this
  if (block_size < 1) return sk_error_set(SK_ERR_INPUT, "linear system: block size %d must be >= 1", block_size);
  if (block_size != sys->block_size) sys->muelu = Teuchos::null;  // the hierarchy depends on it
  sys->block_size = block_size;
  return SK_OK;
}

sk_status sk_linsys_set_coordinates(sk_linear_system *sys, int n_nodes, int dim, const double *coordinates) {
  if ((dim != 2 && dim != 3) || n_nodes < 0 || (n_nodes > 0 && !coordinates))
    return sk_error_set(SK_ERR_INPUT, "linear system: coordinates need dim 2 or 3 (got %d) and %d nodes", dim,
                        n_nodes);
  sys->coordinate_dim = dim;
  sys->coordinates.assign(coordinates, coordinates + static_cast<size_t>(n_nodes) * dim);
  sys->muelu = Teuchos::null;  // the nullspace changed
  return SK_OK;
}

sk_status sk_linsys_set_pattern(sk_linear_system *sys, int n, const int64_t *row_ptr, const int *cols,
                                int n_local_rows, const int *local_rows) {
  sk_status status = check_pattern(n, row_ptr, cols, n_local_rows, local_rows);
  status = agree(sys->comm, status, "linear system pattern check");
  if (status != SK_OK) return status;
  if (n % sys->block_size != 0)
    return sk_error_set(SK_ERR_INPUT, "linear system: %d unknowns are not a multiple of the block size %d", n,
                        sys->block_size);
  try {
    release_pattern(sys);
    sys->n = n;
    sys->row_ptr.assign(row_ptr, row_ptr + n + 1);
    sys->cols.assign(cols, cols + row_ptr[n]);
    sys->local_rows.assign(local_rows, local_rows + n_local_rows);
    sys->values.assign(static_cast<size_t>(row_ptr[n]), 0.0);

    // contiguous blocks, whole nodes (block_size unknowns) kept on one rank so MueLu's aggregates see them
    const int nodes = n / sys->block_size;
    sys->row_offsets.assign(sys->size + 1, 0);
    for (int r = 0; r < sys->size; ++r) {
      const int nodes_r = nodes / sys->size + (r < nodes % sys->size ? 1 : 0);
      sys->row_offsets[r + 1] = sys->row_offsets[r] + nodes_r * sys->block_size;
    }
    const int first_row = sys->row_offsets[sys->rank];
    const int n_owned = sys->row_offsets[sys->rank + 1] - first_row;
    sys->owned_value_begin = row_ptr[first_row];
    sys->owned_values.assign(static_cast<size_t>(row_ptr[first_row + n_owned] - row_ptr[first_row]), 0.0);
    sys->owned_diagonal.assign(static_cast<size_t>(n_owned), -1);
    for (int i = 0; i < n_owned; ++i) {
      const int row = first_row + i;
      const int *found = std::lower_bound(cols + row_ptr[row], cols + row_ptr[row + 1], row);
      if (found != cols + row_ptr[row + 1] && *found == row) sys->owned_diagonal[i] = (found - cols) - row_ptr[first_row];
    }

    // exchange plan: local rows grouped by owner (already sorted, and owners hold increasing row blocks)
    std::vector<int> send_row_counts(sys->size, 0), recv_row_counts(sys->size, 0);
    sys->send_counts.assign(sys->size, 0);
    sys->send_rows = sys->local_rows;
    for (int row : sys->local_rows) {
      const int owner = static_cast<int>(std::upper_bound(sys->row_offsets.begin(), sys->row_offsets.end(), row) -
                                         sys->row_offsets.begin()) - 1;
      ++send_row_counts[owner];
      sys->send_counts[owner] += static_cast<int>(row_ptr[row + 1] - row_ptr[row]);
    }
    MPI_Alltoall(send_row_counts.data(), 1, MPI_INT, recv_row_counts.data(), 1, MPI_INT, sys->comm);
    std::vector<int> send_row_displs(sys->size, 0), recv_row_displs(sys->size, 0);
    for (int r = 1; r < sys->size; ++r) {
      send_row_displs[r] = send_row_displs[r - 1] + send_row_counts[r - 1];
      recv_row_displs[r] = recv_row_displs[r - 1] + recv_row_counts[r - 1];
    }
    sys->recv_rows.assign(static_cast<size_t>(recv_row_displs[sys->size - 1] + recv_row_counts[sys->size - 1]), 0);
    MPI_Alltoallv(sys->send_rows.data(), send_row_counts.data(), send_row_displs.data(), MPI_INT,
                  sys->recv_rows.data(), recv_row_counts.data(), recv_row_displs.data(), MPI_INT, sys->comm);
    sys->recv_counts.assign(sys->size, 0);
    for (int r = 0, k = 0; r < sys->size; ++r) {
      for (int i = 0; i < recv_row_counts[r]; ++i, ++k)
        sys->recv_counts[r] += static_cast<int>(row_ptr[sys->recv_rows[k] + 1] - row_ptr[sys->recv_rows[k]]);
    }
    sys->send_displs.assign(sys->size, 0);
    sys->recv_displs.assign(sys->size, 0);
    for (int r = 1; r < sys->size; ++r) {
      sys->send_displs[r] = sys->send_displs[r - 1] + sys->send_counts[r - 1];
      sys->recv_displs[r] = sys->recv_displs[r - 1] + sys->recv_counts[r - 1];
    }
    sys->send_buffer.assign(static_cast<size_t>(sys->send_displs[sys->size - 1] + sys->send_counts[sys->size - 1]), 0);
    sys->recv_buffer.assign(static_cast<size_t>(sys->recv_displs[sys->size - 1] + sys->recv_counts[sys->size - 1]), 0);

    // the direct solver's gather: each rank's owned values, CSR-ordered, land at their place in the full array
    sys->gather_counts.assign(sys->size, 0);
    sys->gather_displs.assign(sys->size, 0);
    for (int r = 0; r < sys->size; ++r) {
      sys->gather_displs[r] = static_cast<int>(row_ptr[sys->row_offsets[r]]);
      sys->gather_counts[r] = static_cast<int>(row_ptr[sys->row_offsets[r + 1]] - row_ptr[sys->row_offsets[r]]);
    }
    if (sys->size > 1 && sys->rank == 0) sys->gathered_values.assign(static_cast<size_t>(row_ptr[n]), 0.0);

    sys->row_map = rcp(new Map(static_cast<Tpetra::global_size_t>(n), static_cast<size_t>(n_owned), 0, sys->tcomm));
    sys->matrix = build_matrix(sys->row_map, sys->row_map, sys->row_ptr, sys->cols, first_row, sys->owned_local_cols);
    status = SK_OK;
  } catch (...) {
    release_pattern(sys);
    status = status_from_exception(SK_ERR_INTERNAL, "sk_linsys_set_pattern", std::current_exception());
  }
  return agree(sys->comm, status, "sk_linsys_set_pattern");
}

double *sk_linsys_values(sk_linear_system *sys) { return sys->values.empty() ? nullptr : sys->values.data(); }

void sk_linsys_zero(sk_linear_system *sys) { std::fill(sys->values.begin(), sys->values.end(), 0.0); }

sk_status sk_linsys_assemble(sk_linear_system *sys) {
  if (sys->matrix.is_null()) return sk_error_set(SK_ERR_INTERNAL, "sk_linsys_assemble: no pattern set");
  sk_status status = SK_OK;
  try {
    size_t k = 0;
    for (int row : sys->send_rows) {
      const double *begin = sys->values.data() + sys->row_ptr[row];
      const double *end = sys->values.data() + sys->row_ptr[row + 1];
      std::copy(begin, end, sys->send_buffer.data() + k);
      k += static_cast<size_t>(end - begin);
    }
    MPI_Alltoallv(sys->send_buffer.data(), sys->send_counts.data(), sys->send_displs.data(), MPI_DOUBLE,
                  sys->recv_buffer.data(), sys->recv_counts.data(), sys->recv_displs.data(), MPI_DOUBLE, sys->comm);
    std::fill(sys->owned_values.begin(), sys->owned_values.end(), 0.0);
    k = 0;
    for (int row : sys->recv_rows) {
      double *target = sys->owned_values.data() + (sys->row_ptr[row] - sys->owned_value_begin);
      const int64_t count = sys->row_ptr[row + 1] - sys->row_ptr[row];
      for (int64_t j = 0; j < count; ++j) target[j] += sys->recv_buffer[k + static_cast<size_t>(j)];
      k += static_cast<size_t>(count);
    }
    const int first_row = sys->row_offsets[sys->rank];
    replace_values(*sys->matrix, sys->row_ptr, sys->owned_value_begin, first_row,
                   sys->row_offsets[sys->rank + 1] - first_row, sys->owned_values.data(), sys->owned_local_cols);
    sys->assembled = true;
  } catch (...) {
    status = status_from_exception(SK_ERR_INTERNAL, "sk_linsys_assemble", std::current_exception());
  }
  return agree(sys->comm, status, "sk_linsys_assemble");
}

sk_status sk_linsys_solve(sk_linear_system *sys, const double *b, double *x, sk_linear_report *report) {
  sk_linear_report local_report{};
  if (!report) report = &local_report;
  *report = sk_linear_report{};
  if (!sys->assembled) return sk_error_set(SK_ERR_INTERNAL, "sk_linsys_solve: matrix not assembled");
  const double start = now_seconds();
  double norm_b = 0;
  for (int i = 0; i < sys->n; ++i) norm_b += b[i] * b[i];
  if (norm_b == 0) {  // x = 0 exactly; Krylov solvers divide by ||b||
    std::fill(x, x + sys->n, 0.0);
    return SK_OK;
  }
  if (!std::isfinite(norm_b)) return sk_error_set(SK_ERR_DIVERGED, "sk_linsys_solve: non-finite right-hand side");
  sk_linear_solver_kind kind = resolve_kind(sys);
  if (sys->options.kind == SK_LINEAR_AUTO && kind == SK_LINEAR_GMRES_MUELU) {
    // a saddle point (a zero or absent diagonal: contact multiplier rows) defeats AMG's smoothers; measured, GMRES +
    // MueLu then fails after max_iterations, so AUTO goes direct at once (for this pattern, like the fallback)
    int zero_diagonal = 0;
    for (const int64_t d : sys->owned_diagonal) {
      if (d < 0 || sys->owned_values[static_cast<size_t>(d)] == 0.0) {
        zero_diagonal = 1;
        break;
      }
    }
    int any = 0;
    MPI_Allreduce(&zero_diagonal, &any, 1, MPI_INT, MPI_MAX, sys->comm);
    if (any) {
      if (sys->options.verbose && sys->rank == 0) std::printf("linear solve (auto): zero diagonal (saddle point): direct\n");
      sys->auto_fell_back = true;
      kind = resolve_kind(sys);
    }
  }
  sk_status status;
  try {
    status = kind == SK_LINEAR_DIRECT_KLU2 ? solve_direct(sys, b, x, report)
             : is_direct(kind)             ? solve_amesos(sys, kind, b, x, report)
                                           : solve_iterative(sys, kind, b, x, report);
  } catch (...) {
    status = status_from_exception(SK_ERR_DIVERGED, sk_linear_solver_name(kind), std::current_exception());
    if (is_direct(kind)) sys->amesos = Teuchos::null;
  }
  status = agree(sys->comm, status, "sk_linsys_solve");
  sys->last_kind = kind;
  report->solved = 1;
  report->backend = kind;
  if (status == SK_ERR_DIVERGED && sys->options.kind == SK_LINEAR_AUTO && !is_direct(kind)) {
    // AUTO promises an answer when one exists: fall back to the direct solver, for this pattern from now on
    if (sys->options.verbose && sys->rank == 0)
      std::printf("linear solve (auto): %s; falling back to direct\n", sk_error_message());
    sys->auto_fell_back = true;
    sys->muelu = Teuchos::null;
    kind = resolve_kind(sys);
    const int iterations = report->iterations;
    try {
      status = kind == SK_LINEAR_DIRECT_KLU2 ? solve_direct(sys, b, x, report) : solve_amesos(sys, kind, b, x, report);
    } catch (...) {
      status = status_from_exception(SK_ERR_DIVERGED, "direct", std::current_exception());
    }
    status = agree(sys->comm, status, "sk_linsys_solve");
    sys->last_kind = kind;
    report->backend = kind;
    report->iterations = iterations;
    report->refactored_symbolic = 1;
  }
  report->seconds = now_seconds() - start;
  if (sys->options.verbose && sys->rank == 0)
    std::printf("linear solve (%s): n = %d, %d iterations, relative residual %.3g, %.3f s\n",
                sk_linear_solver_name(kind), sys->n, report->iterations, report->relative_residual, report->seconds);
  return status;
}

sk_status sk_linsys_apply(sk_linear_system *sys, const double *x, double *y) {
  if (!sys->assembled) return sk_error_set(SK_ERR_INTERNAL, "sk_linsys_apply: matrix not assembled");
  try {
    Vector xv(sys->row_map), yv(sys->row_map);
    scatter_to(sys, x, xv);
    sys->matrix->apply(xv, yv);
    gather_from(sys, yv, y);
    return SK_OK;
  } catch (...) {
    return status_from_exception(SK_ERR_INTERNAL, "sk_linsys_apply", std::current_exception());
  }
}

// Another right-hand side with the operator of the last solve (condense.h): Amesos v1 (MUMPS, KLU — the direct
// default) solves with its current factorisation; the other backends solve again in full (the same answer without
// the saving).
sk_status sk_linsys_solve_again(sk_linear_system *sys, const double *b, double *x, sk_linear_report *report) {
  sk_linear_report local_report{};
  if (!report) report = &local_report;
  *report = sk_linear_report{};
  const sk_linear_solver_kind kind = sys->last_kind;
  if (sys->amesos.is_null() || sys->amesos_kind != kind || !is_direct(kind) || kind == SK_LINEAR_DIRECT_KLU2)
    return sk_linsys_solve(sys, b, x, report);
  report->solved = 1;
  report->backend = kind;
  const double start = now_seconds();
  sk_status status = SK_OK;
  try {
    const int first_row = sys->row_offsets[sys->rank];
    const int n_owned = sys->row_offsets[sys->rank + 1] - first_row;
    std::copy(b + first_row, b + first_row + n_owned, sys->epetra_b->Values());
    int code = sys->amesos->Solve(), worst = 0;
    code = code < 0 ? code : -code;
    MPI_Allreduce(&code, &worst, 1, MPI_INT, MPI_MIN, sys->comm);
    if (worst != 0) return sk_error_set(SK_ERR_DIVERGED, "solve again (%s): error %d", amesos_backend_name(kind), worst);
    std::vector<int> counts(sys->size), displs(sys->size);
    for (int r = 0; r < sys->size; ++r) {
      displs[r] = sys->row_offsets[r];
      counts[r] = sys->row_offsets[r + 1] - sys->row_offsets[r];
    }
    MPI_Allgatherv(sys->epetra_x->Values(), n_owned, MPI_DOUBLE, x, counts.data(), displs.data(), MPI_DOUBLE,
                   sys->comm);
  } catch (...) {
    status = status_from_exception(SK_ERR_DIVERGED, "sk_linsys_solve_again", std::current_exception());
  }
  report->seconds = now_seconds() - start;
  return agree(sys->comm, status, "sk_linsys_solve_again");
}

}  // extern "C"

namespace stickslip::bridge {

system_rows rows_of(const sk_linear_system *sys) {
  system_rows rows;
  rows.n = sys->n;
  rows.row_ptr = sys->row_ptr.data();
  rows.cols = sys->cols.data();
  rows.first_row = sys->row_offsets.empty() ? 0 : sys->row_offsets[sys->rank];
  rows.n_owned = sys->row_offsets.empty() ? 0 : sys->row_offsets[sys->rank + 1] - rows.first_row;
  rows.owned_values = sys->owned_values.data();
  rows.owned_value_begin = sys->owned_value_begin;
  rows.row_offsets = sys->row_offsets.data();
  return rows;
}

}  // namespace stickslip::bridge
