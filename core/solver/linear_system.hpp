// stickslip — the linear system behind sk_linsys_* (internal to the bridge, not installed).
//
// Layout of the sources: linear_system.cpp (pattern, assembly, the C entry points), direct_solvers.cpp (MUMPS on the
// owned rows through mumps_solver.cpp, Amesos v1 KLU, Amesos2 KLU2), iterative_solvers.cpp (Belos GMRES with MueLu
// or ILU on the nodal block), constraint_block.cpp (the Schur complement of the constraint rows), auto_choice.cpp
// (what `auto` runs), system_dump.cpp (STICKSLIP_DUMP_SYSTEMS).
#ifndef STICKSLIP_LINEAR_SYSTEM_HPP
#define STICKSLIP_LINEAR_SYSTEM_HPP

#include <mpi.h>

#include <chrono>
#include <ctime>
#include <memory>
#include <string>
#include <vector>

#include <Amesos2.hpp>
#include <Amesos_BaseSolver.h>
#include <Epetra_CrsMatrix.h>
#include <Epetra_LinearProblem.h>
#include <Epetra_Map.h>
#include <Epetra_MpiComm.h>
#include <Epetra_Vector.h>
#include <Ifpack2_Preconditioner.hpp>
#include <MueLu_TpetraOperator.hpp>
#include <Teuchos_Comm.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_Vector.hpp>

#include "stickslip/bridge.h"

namespace stickslip::bridge {

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

inline double now_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// CPU time of this process (all its threads): what `auto` compares
inline double cpu_seconds() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// A static-graph Tpetra matrix over a block of the owned rows and columns of the pattern, refilled in place from the
// owned CSR values: entry e of the block takes owned_values[source[e]].
struct SubMatrix {
  RCP<Matrix> matrix;
  std::vector<int64_t> row_ptr;              // local rows of the block, into source / slots
  std::vector<int64_t> source;               // index into owned_values of each entry
  std::vector<LocalOrdinal> slots;           // position of each entry in the matrix's local CRS value array
};

struct ConstraintBlock;  // constraint_block.cpp
struct AutoChoice;       // auto_choice.cpp

// The solvers `auto` chooses among (auto_choice.cpp), and what it remembers of each, across pattern changes.
enum { kAutoCandidates = 5 };
// mumps, gmres-muelu, gmres-sgs, gmres-jacobi, gmres-lu
extern const sk_linear_solver_kind kAutoCandidateKinds[kAutoCandidates];

struct AutoMemory {
  struct Candidate {
    // measured CPU seconds per solve, one-time set-up excluded, / entries^exponent (EWMA), and for a Krylov solver
    // also / tolerance_digits (its cost at another tolerance is this times those digits); 0: not measured (or failed)
    double cost_coefficient = 0;
    double setup_coefficient = 0;  // its last one-time set-up (symbolic factorisation, AMG hierarchy), as above
    int64_t entries_measured = 0;  // the stored entries it was last measured at
    int failed_on_pattern = -1;    // the pattern generation it last failed on (-1: never)
    int failures_in_a_row = 0;     // failed attempts since its last success
    int retry_pattern = 0;         // the first pattern generation it may be tried on again (back-off)
    double iterations_per_digit = 0;  // Krylov iterations of its last successful solve / tolerance_digits
    std::string failure;           // the message of its last failure
    // gmres-lu, whose solves differ by design (a factorisation, then cheap lagged solves): the sum of the cost
    // coefficients of the solves of its measuring window so far and their count; when it may be measured again
    double window_cost = 0;
    int window_solves = 0;
    int losses = 0;       // times another candidate was chosen over it while it ran
    int retry_solve = 0;  // measured again (a new window) from this solve count on, unless it runs
  };
  Candidate candidates[kAutoCandidates];
  sk_linear_solver_kind current = SK_LINEAR_AUTO;  // the candidate in use (SK_LINEAR_AUTO: none yet)
  int solves = 0;                                  // solves so far (a direct set-up recurs per pattern of them)
  int trial_solves_left = 0;                       // solves left in a trial of another candidate
  int iteration_cap = 0;                           // Krylov iterations allowed in this solve (0: max_iterations)
  sk_linear_solver_kind before_trial = SK_LINEAR_AUTO;  // the candidate a trial replaced
  // the run's length as the stepper projects it (sk_linsys_set_steps_left): exploration is budgeted against it
  int steps_left = -1;            // steps left, the current one included (-1: not told; trials are not budgeted)
  int steps_begun = 0;            // steps (attempts) begun
  int solves_at_step_start = 0;   // `solves` when the current step began
  double explored_seconds = 0;    // what trial solves cost beyond the leader's solves they replaced
  double trial_leader_seconds = 0;  // the leader's cost per solve when the current trial began
  std::string reason_class;                        // the kind of the last logged reason (logged when it changes)
  std::string decision;                            // the last decision, for the log and the report
  bool decision_pending = false;                   // decided in this solve: report it
};

// A preconditioner of the nodal block, kept across solves and pattern changes (iterative_solvers.cpp).
// The work space of a solve over the pattern's row map: made at the first solve of a pattern and kept until the
// pattern changes, so that no Newton iteration allocates vectors of its own (solve_scratch).
struct SolveScratch {
  RCP<const Map> map;               // the row map the vectors below were made for
  RCP<Vector> x, b, residual;
  std::vector<double> owned_a, owned_b, owned_c;  // n_owned each
};

struct NodalPreconditioner {
  RCP<MueLuOperator> muelu;           // GMRES_MUELU
  RCP<Ifpack2Preconditioner> ifpack;  // GMRES_ILU, GMRES_SGS, GMRES_JACOBI
  RCP<const Matrix> matrix;           // the K object it was initialised on
  int iterations = 0;                 // GMRES iterations of the first solve after its last computation
  bool refresh = false;               // a later solve needed clearly more iterations: recompute next time
  RCP<Operator> op() const { return muelu.is_null() ? RCP<Operator>(ifpack) : RCP<Operator>(muelu); }
};

}  // namespace stickslip::bridge

struct sk_linear_system {
  using Map = stickslip::bridge::Map;
  using Matrix = stickslip::bridge::Matrix;
  using LocalOrdinal = stickslip::bridge::LocalOrdinal;
  template <class T>
  using RCP = Teuchos::RCP<T>;

  MPI_Comm comm = MPI_COMM_NULL;  // duplicated, so our collectives never interleave with the caller's
  int rank = 0;
  int size = 1;
  sk_linear_options options{};
  int block_size = 1;
  int coordinate_dim = 0;            // 0: no coordinates (translations-only nullspace, no constraint block)
  std::vector<double> coordinates;   // of the owned nodes, node-major in row order
  RCP<const Teuchos::Comm<int>> tcomm;
  int pattern_generation = 0;        // counts set_pattern calls: `auto` remembers failures per pattern
  double setup_cpu_seconds = 0;      // CPU time of the one-time set-up within the last solve (`auto` keeps it apart)

  // Layout: rank r owns the rows [row_offsets[r], row_offsets[r+1]) — its nodal rows (whole nodes, the count the
  // caller gives) and, on the last rank, the constraint rows [n_nodal, n) after every nodal row.
  int n = 0;
  int n_nodal = 0;                   // unknowns [0, n_nodal) are nodal (block_size per node); the rest: constraints
  std::vector<int> row_offsets;
  int first_row = 0, n_owned = 0;    // this rank's block

  // the owned rows, merged over every rank's contributions: local row i is global row first_row + i, its columns
  // (global, sorted) cols[row_ptr[i] .. row_ptr[i+1]), their summed values owned_values (CSR order)
  std::vector<int64_t> row_ptr;
  std::vector<int> cols;
  std::vector<double> owned_values;
  std::vector<LocalOrdinal> owned_slots;  // position of each owned CSR entry in the matrix's CRS values
  std::vector<int64_t> owned_diagonal;    // index of each owned row's diagonal in owned_values, -1 if absent
  int64_t global_entries = 0;             // stored entries over all ranks

  // this rank's contributions: the rows it writes (owned or not, global ids), CSR with global sorted columns, and
  // their values (sk_linsys_values)
  std::vector<int> local_rows;
  std::vector<int64_t> local_row_ptr;
  std::vector<int> local_cols;
  std::vector<double> values;
  std::vector<int64_t> local_slot;   // per local entry: its place in owned_values, or -1 when it is sent

  // the once-per-pattern plan of sk_linsys_assemble: the values of non-owned local rows go to their owners
  // (neighbours only, point to point), which add them at recv_slot
  std::vector<int> send_ranks, send_ptr;   // per neighbour: a range of send_entries
  std::vector<int64_t> send_entries;       // indices into values
  std::vector<int> recv_ranks, recv_ptr;   // per neighbour: a range of recv_slot
  std::vector<int64_t> recv_slot;          // indices into owned_values
  std::vector<double> send_buffer, recv_buffer;
  // the same plan by rows, for right-hand sides over the local rows (sk_linsys_sum_rows)
  std::vector<int> send_row_ptr, recv_row_ptr;  // per neighbour: a range of send_row_index / recv_row_index
  std::vector<int> send_row_index;         // indices into local_rows
  std::vector<int> recv_row_index;         // owned local row
  std::vector<double> row_send_buffer, row_recv_buffer;
  int64_t bytes_sent = 0;                  // by sk_linsys_assemble and sk_linsys_sum_rows (sk_linsys_bytes_sent)

  RCP<const Map> row_map;
  RCP<Matrix> matrix;
  bool assembled = false;

  // direct, KLU2: on one rank the distributed matrix itself; on more, a serial copy on rank 0 from the gathered
  // owned rows (built on first use, sk_linsys_gather)
  RCP<const Map> serial_map;
  RCP<Matrix> serial_matrix;
  std::vector<LocalOrdinal> serial_slots;
  std::vector<int> gather_counts, gather_displs;  // values per rank (their owned entries)
  std::vector<int> row_counts;                     // rows per rank (with row_offsets)
  std::vector<int64_t> full_row_ptr;               // rank 0: the whole pattern
  std::vector<int> full_cols;
  std::vector<double> gathered_values;
  bool gathered_pattern = false;
  RCP<stickslip::bridge::DirectSolver> direct;

  // The Amesos v1 interface's direct solvers: KLU on an Epetra copy with the same contiguous row blocks as the Tpetra
  // matrix, or MUMPS on the owned rows themselves (mumps_solver.hpp: no Epetra matrix, map or vectors).
  // Destroyed in reverse order of construction (solver, problem, vectors, matrix, map, comm).
  RCP<Epetra_MpiComm> epetra_comm;
  RCP<Epetra_Map> epetra_map;
  RCP<Epetra_CrsMatrix> epetra_matrix;
  std::vector<int> epetra_slots;  // position, within Epetra's storage of its row, of each owned CSR entry
  RCP<Epetra_Vector> epetra_x, epetra_b;
  RCP<Epetra_LinearProblem> epetra_problem;
  RCP<Amesos_BaseSolver> amesos;
  sk_linear_solver_kind amesos_kind = SK_LINEAR_DIRECT;
  int mumps_workspace_percent = 20;  // MUMPS ICNTL(14): raised, for the rest of the run, when a factorisation ran short
  sk_linear_solver_kind last_kind = SK_LINEAR_AUTO;  // the backend of the last solve (sk_linsys_solve_again)
  // gmres-lu (lagged_lu.cpp): the factorisation in `amesos` is of an earlier matrix; refactorise at the next solve
  bool lagged_refactorise = false;

  // iterative: the nodal block K (the matrix itself when there are no constraint rows) and its preconditioner,
  // which outlives pattern changes while the nodal distribution stays (iterative_solvers.cpp says when it is
  // refreshed); the constraint rows' Schur complement (constraint_block.cpp)
  RCP<const Map> nodal_map;
  stickslip::bridge::SubMatrix nodal;        // K when there are constraint rows (else unused: K is `matrix`)
  stickslip::bridge::NodalPreconditioner preconditioners[4];  // by kind: GMRES_MUELU, GMRES_ILU, GMRES_SGS, GMRES_JACOBI
  std::unique_ptr<stickslip::bridge::ConstraintBlock> constraints;

  stickslip::bridge::AutoMemory auto_memory;
  stickslip::bridge::SolveScratch scratch;

  sk_linear_system();  // both defined where ConstraintBlock is complete (constraint_block.cpp)
  ~sk_linear_system();
};

namespace stickslip::bridge {

// linear_system.cpp
// Vectors over this rank's owned rows in and out of Tpetra.
void copy_to(const double *owned, Vector &v);
void copy_from(const Vector &v, double *owned);
// The work space of a solve on the current pattern (SolveScratch), made when the row map is new.
SolveScratch &solve_scratch(sk_linear_system *sys);
// The whole matrix on rank 0 (KLU2 on several ranks, the dump): the pattern gathered once per pattern, the values
// at every call into sys->gathered_values (collective).
void gather_to_root(sk_linear_system *sys);
// b over the owned rows gathered to rank 0 (whole on rank 0), and back (collective).
void gather_vector(const sk_linear_system *sys, const double *owned, double *whole);
void scatter_vector(const sk_linear_system *sys, const double *whole, double *owned);
// ||b - A x|| / ||b|| (||b - A x|| when b = 0); leaves b - A x in solve_scratch(sys).residual
double relative_residual(sk_linear_system *sys, const Vector &b, const Vector &x);
sk_status agree(MPI_Comm comm, sk_status local, const char *what);
// Drops the pattern and everything built on it (matrix, maps, solver set-ups that depend on it).
void release_pattern(sk_linear_system *sys);
RCP<Matrix> build_matrix(const RCP<const Map> &row_map, const RCP<const Map> &domain_map,
                         const std::vector<int64_t> &row_ptr, const std::vector<int> &cols, int first_row,
                         std::vector<LocalOrdinal> &slots);
void replace_values(Matrix &matrix, const std::vector<int64_t> &row_ptr, int first_row, int n_rows,
                    const double *values, const std::vector<LocalOrdinal> &slots);
// The block of owned rows [row_begin, row_end) (global, within this rank's rows) and columns [col_begin, col_end),
// its columns renumbered from col_begin; its matrix has the given row, domain and range maps.
SubMatrix build_submatrix(const sk_linear_system *sys, int row_begin, int row_end, int col_begin, int col_end,
                          const RCP<const Map> &row_map, const RCP<const Map> &domain_map,
                          const RCP<const Map> &range_map);
void refill_submatrix(const sk_linear_system *sys, SubMatrix &block);

// direct_solvers.cpp
bool is_direct(sk_linear_solver_kind kind);
// A direct solver, or gmres-lu (whose GMRES falls back to a fresh factorisation): it answers whenever the matrix
// can be factorised, so `auto` does not fall back from it and charges it as a direct solve.
bool mumps_backed(sk_linear_solver_kind kind);
sk_status solve_klu2(sk_linear_system *sys, const double *b, double *x, sk_linear_report *report);
sk_status solve_amesos(sk_linear_system *sys, sk_linear_solver_kind kind, const double *b, double *x,
                       sk_linear_report *report);
void release_direct(sk_linear_system *sys);
// Forward and backward substitution with the current MUMPS or KLU factorisation (collective); b and x over the
// owned rows.
sk_status solve_factorised(sk_linear_system *sys, const double *b, double *x, sk_linear_report *report);
bool solve_amesos_again(sk_linear_system *sys, sk_linear_solver_kind kind, const double *b, double *x,
                        sk_linear_report *report, sk_status *status);

// lagged_lu.cpp: GMRES preconditioned by the last MUMPS factorisation (gmres-lu)
sk_status solve_lagged_lu(sk_linear_system *sys, const double *b, double *x, sk_linear_report *report);

// iterative_solvers.cpp
struct GmresResult {
  bool converged = false;
  int iterations = 0;
};
// Belos GMRES on the whole matrix (x starts at 0), right-preconditioned, to options.tolerance in max_iterations.
GmresResult run_gmres(sk_linear_system *sys, const RCP<Operator> &preconditioner, const RCP<Vector> &b,
                      const RCP<Vector> &x, int max_iterations);
sk_status solve_iterative(sk_linear_system *sys, sk_linear_solver_kind kind, const double *b, double *x,
                          sk_linear_report *report);
void release_iterative_pattern(sk_linear_system *sys);  // what depends on the pattern (not the hierarchy)
void release_iterative(sk_linear_system *sys);          // everything, the hierarchy included

// constraint_block.cpp
void build_constraint_block(sk_linear_system *sys);  // sys->constraints for the current pattern
void release_constraint_block(sk_linear_system *sys);
// The nodal rows this rank owns: [row_offsets[rank], nodal_row_end(sys)).
int nodal_row_end(const sk_linear_system *sys);
// Refills the Schur complement from the current values and factorises it (collective).
sk_status update_constraint_block(sk_linear_system *sys, ConstraintBlock &block);
// The block upper-triangular preconditioner [K B; C D]^-1 ~ [K~^-1 -K~^-1 B S~^-1; 0 S~^-1].
RCP<Operator> constraint_preconditioner(sk_linear_system *sys, ConstraintBlock &block,
                                        const RCP<Operator> &nodal_preconditioner);

// auto_choice.cpp: which solver AUTO runs for this solve, and what it learns from the outcome
sk_linear_solver_kind auto_choose(sk_linear_system *sys);
// After an iterative candidate failed (recorded), for this solve: the candidate a failed trial replaced, or the
// direct solver.
sk_linear_solver_kind auto_fallback(sk_linear_system *sys);
// `seconds`: CPU time of the attempt, of which `setup_seconds` went to a one-time set-up.
void auto_record(sk_linear_system *sys, sk_linear_solver_kind kind, sk_status status, double seconds,
                 double setup_seconds, const sk_linear_report &report);

// system_dump.cpp
void dump_system(sk_linear_system *sys, const double *b);

}  // namespace stickslip::bridge

#endif
