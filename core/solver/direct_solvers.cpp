// stickslip — the direct solvers: MUMPS on the owned rows themselves (mumps_solver.cpp), Amesos v1 KLU on an Epetra
// copy of the distributed matrix, Amesos2 KLU2 (gathered to rank 0 on more than one rank: Debian's KLU2 is wrong on
// distributed matrices, docs/linear-solvers.md).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <stdexcept>

#include <Amesos.h>
#include <Epetra_CrsGraph.h>
#include <Epetra_Object.h>
#include <Teuchos_DefaultMpiComm.hpp>

#include "bridge_internal.hpp"
#include "linear_system.hpp"
#include "mumps_solver.hpp"

namespace stickslip::bridge {

namespace {

// A direct solve whose measured residual exceeds this is a (numerically) singular matrix, not round-off.
constexpr double kDirectResidualLimit = 1e-6;

const char *amesos_backend_name(sk_linear_solver_kind kind) { return kind == SK_LINEAR_DIRECT_MUMPS ? "MUMPS" : "KLU"; }

// The Epetra copy of the pattern for Amesos v1 (KLU): same map (contiguous row blocks of sys->row_offsets), a static
// graph, and the table from owned CSR entries to Epetra's (column-map ordered) value storage.
void build_epetra(sk_linear_system *sys) {
  if (sys->epetra_comm.is_null()) sys->epetra_comm = rcp(new Epetra_MpiComm(sys->comm));
  const int first_row = sys->first_row, n_owned = sys->n_owned;
  sys->epetra_map = rcp(new Epetra_Map(sys->n, n_owned, 0, *sys->epetra_comm));
  std::vector<int> entries(static_cast<size_t>(n_owned));
  for (int i = 0; i < n_owned; ++i) entries[i] = static_cast<int>(sys->row_ptr[i + 1] - sys->row_ptr[i]);
  Epetra_CrsGraph graph(Epetra_DataAccess::Copy, *sys->epetra_map, entries.data(), true);
  for (int i = 0; i < n_owned; ++i) {
    if (graph.InsertGlobalIndices(first_row + i, entries[i], sys->cols.data() + sys->row_ptr[i]) < 0)
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
    const int64_t base = sys->row_ptr[i];
    if (static_cast<int64_t>(row.size()) != static_cast<int64_t>(entries[i]))
      throw std::runtime_error("Epetra matrix row length differs from the pattern");
    for (size_t k = 0; k < row.size(); ++k) sys->epetra_slots[static_cast<size_t>(base) + k] = row[k].second;
  }
  sys->epetra_x = rcp(new Epetra_Vector(*sys->epetra_map));
  sys->epetra_b = rcp(new Epetra_Vector(*sys->epetra_map));
  sys->epetra_problem = rcp(new Epetra_LinearProblem(sys->epetra_matrix.get(), sys->epetra_x.get(), sys->epetra_b.get()));
}

// STICKSLIP_MUMPS_STATS: the CPU time of a MUMPS solve (a forward and backward substitution)
void mumps_solve_stats(const sk_linear_system *sys, double seconds);

}  // namespace

// (linear_system.hpp)
sk_status solve_factorised(sk_linear_system *sys, const double *b, double *x, sk_linear_report *report) {
  const double start = cpu_seconds();
  auto *mumps = dynamic_cast<MumpsSolver *>(sys->amesos.get());
  if (!mumps) std::copy(b, b + sys->n_owned, sys->epetra_b->Values());
  int code = mumps ? mumps->solve(b, x) : sys->amesos->Solve(), worst = 0;
  code = code < 0 ? code : -code;
  MPI_Allreduce(&code, &worst, 1, MPI_INT, MPI_MIN, sys->comm);  // MUMPS's codes are global; agree anyway
  if (worst != 0) {
    report->failure = SK_LINEAR_FAILURE_SINGULAR;
    return sk_error_set(SK_ERR_LINEAR_SOLVER, "direct solve (%s): solve failed (error %d)",
                        amesos_backend_name(sys->amesos_kind), worst);
  }
  if (!mumps) std::copy(sys->epetra_x->Values(), sys->epetra_x->Values() + sys->n_owned, x);
  mumps_solve_stats(sys, cpu_seconds() - start);
  return SK_OK;
}

namespace {

// Iterative refinement with the factors at hand (Wilkinson; MUMPS's ICNTL(10) does the same inside): x += A^-1 (b - A x)
// while it lowers the residual. The pivot order comes from the analysis of the pattern (MUMPS's, which sees no
// values) and the factorisation's threshold pivoting; contact rows (an active-set flip, a multiplier row at 1e-9
// beside stiffness at 1e9) can leave the factors accurate to 1e-6 only, which two or three corrections bring back to
// round-off. Runs only above kRefineAbove, so a solve that is already at round-off stays bit for bit what it was.
// Sets report->relative_residual.
constexpr double kRefineAbove = 1e-10;
constexpr int kMaxRefinements = 4;

sk_status refine_solution(sk_linear_system *sys, const double *b, double *x, sk_linear_report *report) {
  SolveScratch &scratch = solve_scratch(sys);
  Vector &xv = *scratch.x, &bv = *scratch.b;
  copy_to(b, bv);
  const size_t n = static_cast<size_t>(sys->n_owned);
  auto residual = [&]() {
    copy_to(x, xv);
    return relative_residual(sys, bv, xv);
  };
  report->relative_residual = residual();
  if (!(report->relative_residual > kRefineAbove) || !std::isfinite(report->relative_residual)) return SK_OK;
  std::vector<double> &correction_rhs = scratch.owned_a, &correction = scratch.owned_b, &best = scratch.owned_c;
  std::copy(x, x + n, best.begin());
  double best_residual = report->relative_residual;
  for (int k = 0; k < kMaxRefinements && best_residual > kRefineAbove; ++k) {
    copy_from(*scratch.residual, correction_rhs.data());
    SK_TRY(solve_factorised(sys, correction_rhs.data(), correction.data(), report));
    for (size_t i = 0; i < n; ++i) x[i] += correction[i];
    const double refined = residual();
    if (!(refined < 0.5 * best_residual)) break;  // no longer converging: keep the best
    best_residual = refined;
    std::copy(x, x + n, best.begin());
    ++report->refinements;
  }
  std::copy(best.begin(), best.end(), x);
  report->relative_residual = best_residual;
  return SK_OK;
}

}  // namespace

bool is_direct(sk_linear_solver_kind kind) {
  return kind == SK_LINEAR_DIRECT || kind == SK_LINEAR_DIRECT_MUMPS || kind == SK_LINEAR_DIRECT_KLU2 ||
         kind == SK_LINEAR_DIRECT_KLU;
}

bool mumps_backed(sk_linear_solver_kind kind) { return is_direct(kind) || kind == SK_LINEAR_GMRES_LU; }

namespace {

// The process's peak and current resident memory in KiB (VmHWM, VmRSS; 0 where /proc is missing).
void resident_kib(long *peak, long *now) {
  *peak = *now = 0;
  if (FILE *status = std::fopen("/proc/self/status", "r")) {
    char line[256];
    while (std::fgets(line, sizeof line, status)) {
      std::sscanf(line, "VmHWM: %ld", peak);
      std::sscanf(line, "VmRSS: %ld", now);
    }
    std::fclose(status);
  }
}

// STICKSLIP_MUMPS_STATS set (and not 0): see mumps_stats.
bool mumps_stats_on() {
  static const bool on = [] {
    const char *value = std::getenv("STICKSLIP_MUMPS_STATS");
    return value && *value && std::strcmp(value, "0") != 0;
  }();
  return on;
}

void mumps_solve_stats(const sk_linear_system *sys, double seconds) {
  if (mumps_stats_on() && sys->amesos_kind == SK_LINEAR_DIRECT_MUMPS)
    std::fprintf(stderr, "mumps solve rank %d: %.3f ms CPU\n", sys->rank, 1e3 * seconds);
}

}  // namespace

// Dropping a MUMPS instance (a new pattern, a failure) frees its factors and workspace, but glibc keeps most of it
// resident: MUMPS's first factorisation frees buffers of tens of MB (its matrix redistribution), which raises malloc's
// mmap threshold to their size, so the later workspaces come from the heap, where freed pages stay mapped. The next
// instance is then built beside the old one's pages. malloc_trim gives them back: 26-42 MB per rank, 3-5 ms, at 8 ranks
// of the weak-scaled tori, whose largest peak fell from 146 to 136 MB (docs/scaling.md, "The direct solver's share").
void release_direct(sk_linear_system *sys) {
  [[maybe_unused]] const bool held = !sys->amesos.is_null();
  sys->amesos = Teuchos::null;
  sys->epetra_problem = Teuchos::null;
  sys->epetra_x = Teuchos::null;
  sys->epetra_b = Teuchos::null;
  sys->epetra_matrix = Teuchos::null;
  sys->epetra_slots.clear();
  sys->epetra_map = Teuchos::null;
  sys->direct = Teuchos::null;
  sys->serial_matrix = Teuchos::null;
  sys->serial_map = Teuchos::null;
  sys->serial_slots.clear();
#ifdef __GLIBC__
  if (!held) return;
  long peak = 0, before = 0, after = 0;
  if (mumps_stats_on()) resident_kib(&peak, &before);
  const double start = cpu_seconds();
  malloc_trim(0);
  if (mumps_stats_on()) {
    resident_kib(&peak, &after);
    std::fprintf(stderr, "mumps released rank %d: malloc_trim %.1f ms CPU, RSS %ld -> %ld KiB\n", sys->rank,
                 1e3 * (cpu_seconds() - start), before, after);
  }
#endif
}

// Direct solve. KLU2 always runs on one process: the distributed matrix itself on one rank, the serial copy on
// rank 0 otherwise (Debian's Amesos2 KLU2 returns wrong solutions on distributed matrices; Tacho crashes).
sk_status solve_klu2(sk_linear_system *sys, const double *b, double *x, sk_linear_report *report) {
  const bool gathered = sys->size > 1;
  int status = SK_OK;
  char message[256] = "";
  std::vector<double> whole_b(sys->rank == 0 ? static_cast<size_t>(sys->n) : 0);
  std::vector<double> whole_x(whole_b.size());
  if (gathered) {
    gather_to_root(sys);
    gather_vector(sys, b, whole_b.data());
  } else {
    std::copy(b, b + sys->n, whole_b.begin());
  }
  if (sys->rank == 0) {
    try {
      RCP<Matrix> a = sys->matrix;
      RCP<const Map> map = sys->row_map;
      if (gathered) {
        if (sys->serial_matrix.is_null()) {
          sys->serial_map = rcp(new Map(static_cast<Tpetra::global_size_t>(sys->n), 0,
                                        rcp(new Teuchos::MpiComm<int>(MPI_COMM_SELF))));
          sys->serial_matrix = build_matrix(sys->serial_map, sys->serial_map, sys->full_row_ptr, sys->full_cols, 0,
                                            sys->serial_slots);
        }
        replace_values(*sys->serial_matrix, sys->full_row_ptr, 0, sys->n, sys->gathered_values.data(),
                       sys->serial_slots);
        a = sys->serial_matrix;
        map = sys->serial_map;
      }
      if (sys->direct.is_null()) {
        const double setup_start = cpu_seconds();
        sys->direct = Amesos2::create<Matrix, MultiVector>("KLU2", a);
        sys->direct->symbolicFactorization();
        report->refactored_symbolic = 1;
        sys->setup_cpu_seconds = cpu_seconds() - setup_start;
      }
      sys->direct->numericFactorization();
      report->factorisations = 1;
      Vector xs(map), bs(map);
      copy_to(whole_b.data(), bs);
      sys->direct->solve(Teuchos::ptr<MultiVector>(&xs), Teuchos::ptr<const MultiVector>(&bs));
      copy_from(xs, whole_x.data());
      for (int i = 0; i < sys->n; ++i) {
        if (!std::isfinite(whole_x[i])) {
          status = SK_ERR_LINEAR_SOLVER;
          std::snprintf(message, sizeof message, "direct solve (KLU2): non-finite solution (singular matrix)");
          break;
        }
      }
    } catch (...) {
      // a failed factorisation may leave the solver half-built: start afresh next time
      sys->direct = Teuchos::null;
      status = status_from_exception(SK_ERR_LINEAR_SOLVER, "direct solve (KLU2, singular matrix?)", std::current_exception());
      std::snprintf(message, sizeof message, "%s", sk_error_message());
    }
  }
  if (gathered) {
    MPI_Bcast(&status, 1, MPI_INT, 0, sys->comm);
    MPI_Bcast(message, sizeof message, MPI_CHAR, 0, sys->comm);
    MPI_Bcast(&report->refactored_symbolic, 1, MPI_INT, 0, sys->comm);
    MPI_Bcast(&report->factorisations, 1, MPI_INT, 0, sys->comm);
    if (status == SK_OK) scatter_vector(sys, whole_x.data(), x);
  } else if (status == SK_OK) {
    std::copy(whole_x.begin(), whole_x.end(), x);
  }
  if (status != SK_OK) {
    report->failure = SK_LINEAR_FAILURE_SINGULAR;
    return sk_error_set(static_cast<sk_status>(status), "%s", message);
  }
  SolveScratch &scratch = solve_scratch(sys);
  copy_to(x, *scratch.x);
  copy_to(b, *scratch.b);
  report->relative_residual = relative_residual(sys, *scratch.b, *scratch.x);
  if (!(report->relative_residual <= kDirectResidualLimit)) {
    report->failure = SK_LINEAR_FAILURE_SINGULAR;
    return sk_error_set(SK_ERR_LINEAR_SOLVER, "direct solve (KLU2): relative residual %.3g (singular matrix)",
                        report->relative_residual);
  }
  return SK_OK;
}

namespace {

// MUMPS's INFO(1) of the last call, the most negative over the ranks (0 for KLU or without a solver).
int mumps_info(sk_linear_system *sys, sk_linear_solver_kind kind) {
  int info = 0, worst = 0;
  if (kind == SK_LINEAR_DIRECT_MUMPS && !sys->amesos.is_null())
    if (auto *mumps = dynamic_cast<MumpsSolver *>(sys->amesos.get())) info = mumps->info()[0];
  MPI_Allreduce(&info, &worst, 1, MPI_INT, MPI_MIN, sys->comm);
  return worst;
}

bool mumps_workspace_short(int info) {
  return info == -8 || info == -9 || info == -11 || info == -12 || info == -14 || info == -15 || info == -17 ||
         info == -20;
}

// What MUMPS's INFO(1) means, for the messages.
const char *mumps_meaning(int info) {
  if (info == -10) return "numerically singular matrix";
  if (info == -6) return "structurally singular matrix";
  if (info == -13) return "out of memory";
  if (mumps_workspace_short(info)) return "workspace too small";
  return "see the MUMPS manual";
}

// STICKSLIP_MUMPS_STATS=1 (a measuring aid, docs/linear-solvers.md) prints to stderr, after each MUMPS analysis and
// factorisation, every rank's memory — INFO(15)/(16), the MB MUMPS estimated / allocated for the factorisation (its
// workspace, mostly never touched), INFO(9), the real entries of the rank's factors, and the rank's peak and current
// resident memory — and rank 0's global figures: INFOG(7) ordering used, INFOG(23) column permutation used (0: none),
// INFOG(32) analysis type (1 sequential), INFOG(20)/(29) estimated / effective factor entries, INFOG(16)/(17) and
// (18)/(19) MB of the largest rank / all ranks estimated and allocated, RINFOG(3) flops of the elimination.
void mumps_stats(sk_linear_system *sys, const char *phase, double seconds) {
  auto *mumps = mumps_stats_on() ? dynamic_cast<MumpsSolver *>(sys->amesos.get()) : nullptr;
  if (!mumps) return;
  const int *info = mumps->info(), *infog = mumps->infog();
  long peak = 0, now = 0;
  resident_kib(&peak, &now);
  std::fprintf(stderr,
               "mumps %s rank %d: %.3f ms CPU, INFO(15) %d MB, INFO(16) %d MB, INFO(9) %d, peak RSS %ld KiB, RSS %ld "
               "KiB\n",
               phase, sys->rank, 1e3 * seconds, info[14], info[15], info[8], peak, now);
  if (sys->rank == 0)
    std::fprintf(stderr,
                 "mumps %s: n %d, INFOG(7) %d, INFOG(23) %d, INFOG(32) %d, INFOG(20) %d, INFOG(29) %d, INFOG(16) %d, "
                 "INFOG(17) %d, INFOG(18) %d, INFOG(19) %d, RINFOG(3) %.3g, ICNTL(14) %d\n",
                 phase, sys->n, infog[6], infog[22], infog[31], infog[19], infog[28], infog[15], infog[16], infog[17],
                 infog[18], mumps->rinfog()[2], sys->mumps_workspace_percent);
}

// The symbolic (once per pattern and backend) and numeric factorisation of the current values (MUMPS reads
// sys->owned_values, KLU sys->epetra_matrix); *info:
// MUMPS's INFO(1) when it failed (mumps_info), else 0.
sk_status factorise_amesos(sk_linear_system *sys, sk_linear_solver_kind kind, sk_linear_report *report, int *info) {
  *info = 0;
  const char *backend = amesos_backend_name(kind);
  // all ranks see the same return codes (MUMPS's are global) but agree anyway: a mismatch would deadlock
  auto failed = [sys](int code) {
    int worst = code < 0 ? code : (code > 0 ? -code : 0), result = 0;
    MPI_Allreduce(&worst, &result, 1, MPI_INT, MPI_MIN, sys->comm);
    return result;
  };
  char mumps[128] = "";
  auto describe = [&](int info) {
    if (info != 0)
      std::snprintf(mumps, sizeof mumps, "; MUMPS INFO(1) = %d: %s, ICNTL(14) = %d %%", info, mumps_meaning(info),
                    sys->mumps_workspace_percent);
    return mumps;
  };
  if (sys->amesos.is_null() || sys->amesos_kind != kind) {
    const double setup_start = cpu_seconds();
    if (kind == SK_LINEAR_DIRECT_MUMPS) {
      sys->amesos = rcp(new MumpsSolver(sys, sys->mumps_workspace_percent));
    } else {
      Epetra_Object::SetTracebackMode(sys->options.verbose ? 1 : 0);  // Amesos prints every error code otherwise
      Amesos factory;
      sys->amesos = rcp(factory.Create("Amesos_Klu", *sys->epetra_problem));
      if (sys->amesos.is_null())
        return sk_error_set(SK_ERR_INTERNAL, "direct solve (%s): Amesos has no such solver", backend);
      Teuchos::ParameterList params;
      params.set("OutputLevel", sys->options.verbose ? 1 : 0);
      params.set("ComputeTrueResidual", false);
      params.set("ComputeVectorNorms", false);
      sys->amesos->SetParameters(params);
    }
    sys->amesos_kind = kind;
    if (const int code = failed(sys->amesos->SymbolicFactorization())) {
      describe(*info = mumps_info(sys, kind));
      sys->amesos = Teuchos::null;
      report->failure = SK_LINEAR_FAILURE_SINGULAR;
      return sk_error_set(SK_ERR_LINEAR_SOLVER, "direct solve (%s): symbolic factorisation failed (error %d%s)", backend,
                          code, mumps);
    }
    report->refactored_symbolic = 1;
    sys->setup_cpu_seconds = cpu_seconds() - setup_start;
    mumps_stats(sys, "analysis", sys->setup_cpu_seconds);
  }
  const double start = cpu_seconds();
  if (const int code = failed(sys->amesos->NumericFactorization())) {
    describe(*info = mumps_info(sys, kind));
    sys->amesos = Teuchos::null;  // start afresh (symbolic included) next time
    report->failure = SK_LINEAR_FAILURE_SINGULAR;
    return sk_error_set(SK_ERR_LINEAR_SOLVER, "direct solve (%s): numeric factorisation failed (error %d%s)", backend,
                        code, mumps[0] ? mumps : ", singular matrix");
  }
  ++report->factorisations;
  mumps_stats(sys, "factorisation", cpu_seconds() - start);
  return SK_OK;
}

}  // namespace

// Direct solve by MUMPS on the owned rows (mumps_solver.cpp) or Amesos v1 KLU on the distributed Epetra matrix: both
// are correct on several ranks (MUMPS factorises in parallel; Amesos_Klu gathers to rank 0 itself). The symbolic
// factorisation is computed once per pattern — MUMPS's on the pattern alone: as under Amesos_Mumps, which gave it no
// values at the analysis (no column permutation, INFOG(23) = 0) — and every solve redoes the numeric one only.
sk_status solve_amesos(sk_linear_system *sys, sk_linear_solver_kind kind, const double *b, double *x,
                       sk_linear_report *report) {
  const char *backend = amesos_backend_name(kind);
  if (kind != SK_LINEAR_DIRECT_MUMPS) {  // KLU: the Epetra copy (MUMPS reads the owned rows themselves)
    if (sys->epetra_matrix.is_null()) build_epetra(sys);
    int *offsets = nullptr, *indices = nullptr;
    double *values = nullptr;
    sys->epetra_matrix->ExtractCrsDataPointers(offsets, indices, values);
    for (size_t k = 0; k < sys->owned_values.size(); ++k) values[sys->epetra_slots[k]] = sys->owned_values[k];
  }
  // Amesos reports errors on std::cerr itself; the status and message returned here say it once, so its report is
  // muted unless verbose
  struct MuteCerr {
    std::streambuf *saved = nullptr;
    explicit MuteCerr(bool mute) : saved(mute ? std::cerr.rdbuf(nullptr) : nullptr) {}
    ~MuteCerr() {
      if (saved) std::cerr.rdbuf(saved);  // rdbuf(sb) also clears the badbit set while muted
    }
  } mute(!sys->options.verbose);

  // MUMPS sizes its workspace at the analysis, from the pattern; pivots the factorisation delays for the values (a
  // contact constraint switching on) can need more: INFO(1) -8, -9, -11, -12, -14, -15, -17 or -20. The analysis is
  // then redone with ICNTL(14), the workspace's relaxation in percent, five times larger (up to 2500 %), and the
  // larger value kept for the run.
  int info = 0;
  for (sk_status status; (status = factorise_amesos(sys, kind, report, &info)) != SK_OK;) {
    if (!mumps_workspace_short(info) || sys->mumps_workspace_percent >= 2500) return status;
    sys->mumps_workspace_percent *= 5;
    report->failure = SK_LINEAR_FAILURE_NONE;
    sk_error_clear();
  }
  SK_TRY(solve_factorised(sys, b, x, report));
  SK_TRY(refine_solution(sys, b, x, report));
  if (!(report->relative_residual <= kDirectResidualLimit)) {  // NaN included
    report->failure = SK_LINEAR_FAILURE_SINGULAR;
    return sk_error_set(SK_ERR_LINEAR_SOLVER, "direct solve (%s): relative residual %.3g (singular matrix)", backend,
                        report->relative_residual);
  }
  return SK_OK;
}

// Another right-hand side with the factorisation of the last Amesos v1 solve (MUMPS, KLU); false when there is none
// for `kind` (KLU2 and the iterative solvers solve again in full).
bool solve_amesos_again(sk_linear_system *sys, sk_linear_solver_kind kind, const double *b, double *x,
                        sk_linear_report *report, sk_status *status) {
  if (sys->amesos.is_null() || sys->amesos_kind != kind || !is_direct(kind) || kind == SK_LINEAR_DIRECT_KLU2) return false;
  report->solver = kind;
  *status = solve_factorised(sys, b, x, report);
  return true;
}

}  // namespace stickslip::bridge
