// stickslip — sk_linsys_*: the distributed Tpetra matrix, its assembly, and the dispatch to the solvers.
//
// Layout. Rank r owns a contiguous block of rows: its nodal rows (as many as the caller owns, in whole nodes) and,
// on the last rank, the constraint rows after every nodal row. Nobody holds the whole pattern: each rank gives the
// rows it writes (owned or not), and sk_linsys_set_pattern merges them on their owners (one exchange of the
// non-owned rows' columns per pattern), builds the static-graph Tpetra matrix of the owned rows and plans the
// assembly: sk_linsys_assemble adds the owned contributions in place and sends the others to their owners, point to
// point between neighbours, where they are added at planned positions. Vectors are the owned rows' parts.
// The pattern set-up is linear_system_pattern.cpp.
#include "linear_system.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include <Teuchos_DefaultMpiComm.hpp>
#include <Tpetra_Details_initializeKokkos.hpp>

#include "bridge_internal.hpp"
#include "stickslip/condense.h"

namespace stickslip::bridge {

namespace {

// Severity for agree(): the worst status wins. A linear-solver failure ranks with Newton's own failures, below
// input, I/O, plugin and internal errors.
int severity(sk_status status) { return status == SK_ERR_LINEAR_SOLVER ? 9 : 2 * static_cast<int>(status); }

// Sends send_buffer / row_send_buffer-style arrays to the neighbours and receives theirs (point to point).
void neighbour_exchange(sk_linear_system *sys, const std::vector<int> &send_ptr, const double *send,
                        const std::vector<int> &recv_ptr, double *recv) {
  std::vector<MPI_Request> requests;
  requests.reserve(sys->send_ranks.size() + sys->recv_ranks.size());
  for (size_t k = 0; k < sys->recv_ranks.size(); ++k) {
    requests.emplace_back();
    MPI_Irecv(recv + recv_ptr[k], recv_ptr[k + 1] - recv_ptr[k], MPI_DOUBLE, sys->recv_ranks[k], 0, sys->comm,
              &requests.back());
  }
  for (size_t k = 0; k < sys->send_ranks.size(); ++k) {
    requests.emplace_back();
    MPI_Isend(send + send_ptr[k], send_ptr[k + 1] - send_ptr[k], MPI_DOUBLE, sys->send_ranks[k], 0, sys->comm,
              &requests.back());
    sys->bytes_sent += static_cast<int64_t>(sizeof(double)) * (send_ptr[k + 1] - send_ptr[k]);
  }
  MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
}

sk_status solve_with(sk_linear_system *sys, sk_linear_solver_kind kind, const double *b, double *x,
                     sk_linear_report *report) {
  sk_status status;
  report->solver = kind;
  sys->setup_cpu_seconds = 0;
  try {
    status = kind == SK_LINEAR_DIRECT_KLU2 ? solve_klu2(sys, b, x, report)
             : is_direct(kind)             ? solve_amesos(sys, kind, b, x, report)
             : kind == SK_LINEAR_GMRES_LU  ? solve_lagged_lu(sys, b, x, report)
                                           : solve_iterative(sys, kind, b, x, report);
  } catch (...) {
    status = status_from_exception(SK_ERR_LINEAR_SOLVER, sk_linear_solver_name(kind), std::current_exception());
    if (is_direct(kind) || kind == SK_LINEAR_GMRES_LU) release_direct(sys);
    report->failure = is_direct(kind) ? SK_LINEAR_FAILURE_SINGULAR : SK_LINEAR_FAILURE_NOT_CONVERGED;
  }
  status = agree(sys->comm, status, "sk_linsys_solve");
  if (status != SK_OK && report->failure == SK_LINEAR_FAILURE_NONE)
    report->failure = status == SK_ERR_INPUT ? SK_LINEAR_FAILURE_INPUT
                      : is_direct(kind)      ? SK_LINEAR_FAILURE_SINGULAR
                                             : SK_LINEAR_FAILURE_NOT_CONVERGED;
  return status;
}

}  // namespace

void release_pattern(sk_linear_system *sys) {
  release_direct(sys);
  release_iterative_pattern(sys);
  sys->matrix = Teuchos::null;
  sys->row_map = Teuchos::null;
  sys->scratch = SolveScratch{};
  sys->assembled = false;
  sys->gathered_pattern = false;
  sys->full_row_ptr.clear();
  sys->full_cols.clear();
  sys->gathered_values.clear();
}

SolveScratch &solve_scratch(sk_linear_system *sys) {
  SolveScratch &s = sys->scratch;
  if (s.map.get() != sys->row_map.get()) {
    s.map = sys->row_map;
    s.x = rcp(new Vector(sys->row_map));
    s.b = rcp(new Vector(sys->row_map));
    s.residual = rcp(new Vector(sys->row_map));
    const size_t n = static_cast<size_t>(sys->n_owned);
    s.owned_a.assign(n, 0.0);
    s.owned_b.assign(n, 0.0);
    s.owned_c.assign(n, 0.0);
  }
  return s;
}

void copy_to(const double *owned, Vector &v) {
  auto data = v.getDataNonConst();
  std::copy(owned, owned + data.size(), data.getRawPtr());
}

void copy_from(const Vector &v, double *owned) {
  auto data = v.getData();
  std::copy(data.getRawPtr(), data.getRawPtr() + data.size(), owned);
}

void gather_to_root(sk_linear_system *sys) {
  if (!sys->gathered_pattern) {
    const int size = sys->size;
    sys->gather_counts.assign(size, 0);
    sys->gather_displs.assign(size, 0);
    const int entries = static_cast<int>(sys->cols.size());
    MPI_Gather(&entries, 1, MPI_INT, sys->gather_counts.data(), 1, MPI_INT, 0, sys->comm);
    for (int r = 1; r < size; ++r) sys->gather_displs[r] = sys->gather_displs[r - 1] + sys->gather_counts[r - 1];
    std::vector<int> lengths(static_cast<size_t>(sys->n_owned));
    for (int i = 0; i < sys->n_owned; ++i) lengths[i] = static_cast<int>(sys->row_ptr[i + 1] - sys->row_ptr[i]);
    std::vector<int> all_lengths(sys->rank == 0 ? static_cast<size_t>(sys->n) : 0);
    MPI_Gatherv(lengths.data(), sys->n_owned, MPI_INT, all_lengths.data(), sys->row_counts.data(),
                sys->row_offsets.data(), MPI_INT, 0, sys->comm);
    if (sys->rank == 0) {
      sys->full_row_ptr.assign(static_cast<size_t>(sys->n) + 1, 0);
      for (int i = 0; i < sys->n; ++i) sys->full_row_ptr[i + 1] = sys->full_row_ptr[i] + all_lengths[i];
      sys->full_cols.assign(static_cast<size_t>(sys->full_row_ptr[sys->n]), 0);
      sys->gathered_values.assign(sys->full_cols.size(), 0.0);
    }
    MPI_Gatherv(sys->cols.data(), entries, MPI_INT, sys->full_cols.data(), sys->gather_counts.data(),
                sys->gather_displs.data(), MPI_INT, 0, sys->comm);
    sys->gathered_pattern = true;
  }
  MPI_Gatherv(sys->owned_values.data(), static_cast<int>(sys->owned_values.size()), MPI_DOUBLE,
              sys->gathered_values.data(), sys->gather_counts.data(), sys->gather_displs.data(), MPI_DOUBLE, 0,
              sys->comm);
}

// Per solve: the counts come with the layout (sk_linsys_set_pattern), so nothing is allocated here.
void gather_vector(const sk_linear_system *sys, const double *owned, double *whole) {
  MPI_Gatherv(owned, sys->n_owned, MPI_DOUBLE, whole, sys->row_counts.data(), sys->row_offsets.data(), MPI_DOUBLE, 0,
              sys->comm);
}

void scatter_vector(const sk_linear_system *sys, const double *whole, double *owned) {
  MPI_Scatterv(whole, sys->row_counts.data(), sys->row_offsets.data(), MPI_DOUBLE, owned, sys->n_owned, MPI_DOUBLE, 0,
               sys->comm);
}

double relative_residual(sk_linear_system *sys, const Vector &b, const Vector &x) {
  Vector &r = *solve_scratch(sys).residual;
  sys->matrix->apply(x, r);
  r.update(1.0, b, -1.0);
  const double norm_b = b.norm2();
  return norm_b > 0 ? r.norm2() / norm_b : r.norm2();
}

// The same status on every rank: the worst wins, with rank-local messages kept where they arose and a generic one
// elsewhere.
sk_status agree(MPI_Comm comm, sk_status local, const char *what) {
  int mine = severity(local), worst = 0;
  MPI_Allreduce(&mine, &worst, 1, MPI_INT, MPI_MAX, comm);
  if (worst == 0) return SK_OK;
  if (worst == mine) return local;
  const sk_status other = worst == 9 ? SK_ERR_LINEAR_SOLVER : static_cast<sk_status>(worst / 2);
  return sk_error_set(other, "%s failed on another rank", what);
}

// Writes the values of a fill-complete static-graph matrix straight into its local CRS value array: entry e of the
// CSR rows [first_row, first_row + n_rows) (values aligned with row_ptr) goes to slot[e]. The matrix stays
// fill-complete (no resumeFill / fillComplete, which cost 10 % of a full two-tori contact step with the row-wise
// replaceLocalValues it replaces).
void replace_values(Matrix &matrix, const std::vector<int64_t> &row_ptr, int first_row, int n_rows,
                    const double *values, const std::vector<LocalOrdinal> &slot) {
  const auto stored = matrix.getLocalValuesView();  // host memory: Kokkos is built for Serial only
  const int64_t n_entries = row_ptr[first_row + n_rows] - row_ptr[first_row];
  const int64_t offset = row_ptr[first_row];
  for (int64_t e = 0; e < n_entries; ++e) stored(slot[static_cast<size_t>(e)]) = values[offset + e];
}

// A fill-complete static graph from local CSR rows with global column indices (sorted within rows), and the
// position of each CSR entry in the local CRS arrays (Tpetra keeps a row sorted by column-map index, which is not
// the global order once remote columns come after the owned ones). Built from local indices: inserting global
// indices row by row took 0.27 s for the 76k-unknown two-tori matrix, a cost paid at every contact pattern change.
RCP<Graph> build_graph(const RCP<const Map> &row_map, const RCP<const Map> &domain_map, const RCP<const Map> &range_map,
                       const int64_t *row_ptr, const GlobalOrdinal *cols, std::vector<LocalOrdinal> &slots) {
  const size_t n_rows = row_map->getNodeNumElements();
  const size_t n_entries = static_cast<size_t>(row_ptr[n_rows] - row_ptr[0]);
  // the column map: the domain's own columns first (in order), then the others by owning rank (Tpetra's layout)
  std::vector<GlobalOrdinal> used(cols, cols + n_entries);
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  std::vector<GlobalOrdinal> own, remote;
  for (GlobalOrdinal g : used) (domain_map->isNodeGlobalElement(g) ? own : remote).push_back(g);
  std::vector<int> owners(remote.size());
  domain_map->getRemoteIndexList(Teuchos::ArrayView<const GlobalOrdinal>(remote.data(), remote.size()),
                                 Teuchos::ArrayView<int>(owners.data(), owners.size()));
  std::vector<std::pair<int, GlobalOrdinal>> by_owner(remote.size());
  for (size_t i = 0; i < remote.size(); ++i) by_owner[i] = {owners[i], remote[i]};
  std::sort(by_owner.begin(), by_owner.end());
  std::vector<GlobalOrdinal> column_gids(own);
  for (const auto &entry : by_owner) column_gids.push_back(entry.second);
  // the column-map index of each used global column, in the order of `used`
  std::vector<LocalOrdinal> local_of(used.size());
  for (size_t c = 0; c < column_gids.size(); ++c)
    local_of[static_cast<size_t>(std::lower_bound(used.begin(), used.end(), column_gids[c]) - used.begin())] =
        static_cast<LocalOrdinal>(c);
  auto col_map = rcp(new Map(Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid(),
                             Teuchos::ArrayView<const GlobalOrdinal>(column_gids.data(), column_gids.size()), 0,
                             row_map->getComm()));
  slots.resize(n_entries);
  Teuchos::ArrayRCP<size_t> graph_row_ptr(n_rows + 1);
  Teuchos::ArrayRCP<LocalOrdinal> graph_cols(n_entries);
  for (size_t i = 0; i <= n_rows; ++i) graph_row_ptr[i] = static_cast<size_t>(row_ptr[i] - row_ptr[0]);
  std::vector<std::pair<LocalOrdinal, LocalOrdinal>> row;  // (column-map index, entry within the row)
  for (size_t i = 0; i < n_rows; ++i) {
    const size_t b = graph_row_ptr[i], e = graph_row_ptr[i + 1];
    row.clear();
    for (size_t k = b; k < e; ++k) {
      const size_t u = static_cast<size_t>(std::lower_bound(used.begin(), used.end(), cols[k]) - used.begin());
      row.emplace_back(local_of[u], static_cast<LocalOrdinal>(k - b));
    }
    std::sort(row.begin(), row.end());
    for (size_t p = 0; p < row.size(); ++p) {
      graph_cols[b + p] = row[p].first;
      slots[b + static_cast<size_t>(row[p].second)] = static_cast<LocalOrdinal>(b + p);
    }
  }
  auto graph = rcp(new Graph(row_map, col_map, graph_row_ptr, graph_cols));
  graph->fillComplete(domain_map, range_map);
  return graph;
}

// The static-graph matrix of CSR rows [first_row, first_row + map's local count) and the CSR -> CRS value slot table.
RCP<Matrix> build_matrix(const RCP<const Map> &row_map, const RCP<const Map> &domain_map,
                         const std::vector<int64_t> &row_ptr, const std::vector<int> &cols, int first_row,
                         std::vector<LocalOrdinal> &slots) {
  const size_t n_rows = row_map->getNodeNumElements();
  const int64_t begin = row_ptr[first_row];
  std::vector<GlobalOrdinal> global_cols(cols.begin() + begin, cols.begin() + row_ptr[first_row + n_rows]);
  auto graph = build_graph(row_map, domain_map, row_map, row_ptr.data() + first_row, global_cols.data(), slots);
  auto matrix = rcp(new Matrix(graph));
  matrix->fillComplete(domain_map, row_map);
  return matrix;
}

SubMatrix build_submatrix(const sk_linear_system *sys, int row_begin, int row_end, int col_begin, int col_end,
                          const RCP<const Map> &row_map, const RCP<const Map> &domain_map,
                          const RCP<const Map> &range_map) {
  SubMatrix block;
  const int n_rows = row_end - row_begin;
  block.row_ptr.assign(static_cast<size_t>(n_rows) + 1, 0);
  std::vector<GlobalOrdinal> block_cols;
  for (int i = 0; i < n_rows; ++i) {
    const int local = row_begin + i - sys->first_row;
    for (int64_t k = sys->row_ptr[local]; k < sys->row_ptr[local + 1]; ++k) {
      if (sys->cols[k] < col_begin || sys->cols[k] >= col_end) continue;
      block.source.push_back(k);
      block_cols.push_back(sys->cols[k] - col_begin);
    }
    block.row_ptr[i + 1] = static_cast<int64_t>(block.source.size());
  }
  auto graph = build_graph(row_map, domain_map, range_map, block.row_ptr.data(), block_cols.data(), block.slots);
  block.matrix = rcp(new Matrix(graph));
  block.matrix->fillComplete(domain_map, range_map);
  return block;
}

void refill_submatrix(const sk_linear_system *sys, SubMatrix &block) {
  const auto stored = block.matrix->getLocalValuesView();
  for (size_t e = 0; e < block.source.size(); ++e)
    stored(block.slots[e]) = sys->owned_values[static_cast<size_t>(block.source[e])];
}

}  // namespace stickslip::bridge

using namespace stickslip::bridge;

extern "C" {

void sk_linear_options_default(sk_linear_options *options) {
  options->kind = SK_LINEAR_AUTO;
  options->nullspace = SK_NULLSPACE_RIGID_BODY;
  options->tolerance = 1e-10;
  options->max_iterations = 500;
  options->verbose = 0;
  options->log = nullptr;
  options->log_ctx = nullptr;
}

sk_status sk_linear_solver_from_name(const char *name, sk_linear_solver_kind *kind) {
  static const struct {
    const char *name;
    sk_linear_solver_kind kind;
  } names[] = {{"direct", SK_LINEAR_DIRECT},
               {"gmres-muelu", SK_LINEAR_GMRES_MUELU},
               {"gmres-ilu", SK_LINEAR_GMRES_ILU},
               {"gmres-sgs", SK_LINEAR_GMRES_SGS},
               {"gmres-jacobi", SK_LINEAR_GMRES_JACOBI},
               {"gmres-lu", SK_LINEAR_GMRES_LU},
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
  return sk_error_set(SK_ERR_INPUT, "unknown linear solver '%s' (expected direct, gmres-muelu, gmres-ilu, gmres-sgs, "
                      "gmres-jacobi, gmres-lu, auto, mumps, klu2 or klu)",
                      name ? name : "(null)");
}

const char *sk_linear_solver_name(sk_linear_solver_kind kind) {
  switch (kind) {
    case SK_LINEAR_DIRECT: return "direct";
    case SK_LINEAR_GMRES_MUELU: return "gmres-muelu";
    case SK_LINEAR_GMRES_ILU: return "gmres-ilu";
    case SK_LINEAR_GMRES_SGS: return "gmres-sgs";
    case SK_LINEAR_GMRES_JACOBI: return "gmres-jacobi";
    case SK_LINEAR_GMRES_LU: return "gmres-lu";
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
    // read as an int: a C caller may pass any value, and loading an out-of-range enum is undefined in C++ (UBSan)
    static_assert(sizeof(sk_linear_solver_kind) == sizeof(int), "the enum is read as an int");
    int kind_value;
    std::memcpy(&kind_value, &created->options.kind, sizeof kind_value);
    if (kind_value < SK_LINEAR_DIRECT || kind_value > SK_LINEAR_KIND_LAST)
      return sk_error_set(SK_ERR_INPUT, "linear system: unknown solver kind %d", kind_value);
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
    release_iterative(sys);
    sys->epetra_comm = Teuchos::null;
    sys->tcomm = Teuchos::null;
  } catch (...) {
    // destruction must not throw into C; nothing useful to report
  }
  if (sys->comm != MPI_COMM_NULL) MPI_Comm_free(&sys->comm);
  delete sys;
}

void sk_linsys_forget_setup(sk_linear_system *sys) {
  if (!sys) return;
  try {
    release_direct(sys);
    release_iterative(sys);
  } catch (...) {
    // releasing references does not throw; nothing to report into C
  }
}

sk_status sk_linsys_set_solver(sk_linear_system *sys, sk_linear_solver_kind kind) {
  if (kind < SK_LINEAR_DIRECT || kind > SK_LINEAR_KIND_LAST)
    return sk_error_set(SK_ERR_INPUT, "linear system: unknown solver kind %d", (int)kind);
  sys->options.kind = kind;
  return SK_OK;
}

sk_status sk_linsys_set_tolerance(sk_linear_system *sys, double tolerance) {
  if (!(tolerance > 0) || !(tolerance < 1))
    return sk_error_set(SK_ERR_INPUT, "linear system: tolerance %g must lie in (0, 1)", tolerance);
  sys->options.tolerance = tolerance;
  return SK_OK;
}

void sk_linsys_set_steps_left(sk_linear_system *sys, int steps_left) {
  stickslip::bridge::AutoMemory &m = sys->auto_memory;
  m.steps_left = steps_left;
  m.steps_begun += 1;
  m.solves_at_step_start = m.solves;
}

sk_status sk_linsys_set_block_size(sk_linear_system *sys, int block_size) {
  // checked against the unknowns by the next sk_linsys_set_pattern, which callers make after this
  if (block_size < 1) return sk_error_set(SK_ERR_INPUT, "linear system: block size %d must be >= 1", block_size);
  if (block_size != sys->block_size) release_iterative(sys);  // the hierarchy depends on it
  sys->block_size = block_size;
  return SK_OK;
}

sk_status sk_linsys_set_coordinates(sk_linear_system *sys, int n_nodes, int dim, const double *coordinates) {
  int bad = (dim != 2 && dim != 3) || n_nodes < 0 || (n_nodes > 0 && !coordinates);
  const size_t count = bad ? 0 : static_cast<size_t>(n_nodes) * dim;
  int changed = bad || dim != sys->coordinate_dim || count != sys->coordinates.size() ||
                !std::equal(coordinates, coordinates + count, sys->coordinates.begin());
  int flags[2] = {bad, changed};
  MPI_Allreduce(MPI_IN_PLACE, flags, 2, MPI_INT, MPI_MAX, sys->comm);
  if (bad)
    return sk_error_set(SK_ERR_INPUT, "linear system: coordinates need dim 2 or 3 (got %d) and %d nodes", dim,
                        n_nodes);
  if (flags[0]) return sk_error_set(SK_ERR_INPUT, "linear system: bad coordinates on another rank");
  if (flags[1]) release_iterative(sys);  // the nullspace changed (on some rank: the hierarchy is collective)
  sys->coordinate_dim = dim;
  sys->coordinates.assign(coordinates, coordinates + count);
  return SK_OK;
}

int sk_linsys_owned_rows(const sk_linear_system *sys, int *first) {
  if (first) *first = sys->first_row;
  return sys->n_owned;
}

double *sk_linsys_values(sk_linear_system *sys) { return sys->values.empty() ? nullptr : sys->values.data(); }

void sk_linsys_zero(sk_linear_system *sys) { std::fill(sys->values.begin(), sys->values.end(), 0.0); }

int64_t sk_linsys_bytes_sent(const sk_linear_system *sys) { return sys->bytes_sent; }

sk_status sk_linsys_assemble(sk_linear_system *sys) {
  if (sys->matrix.is_null()) return sk_error_set(SK_ERR_INTERNAL, "sk_linsys_assemble: no pattern set");
  sk_status status = SK_OK;
  try {
    for (size_t k = 0; k < sys->send_entries.size(); ++k)
      sys->send_buffer[k] = sys->values[static_cast<size_t>(sys->send_entries[k])];
    std::fill(sys->owned_values.begin(), sys->owned_values.end(), 0.0);
    for (size_t e = 0; e < sys->local_slot.size(); ++e)
      if (sys->local_slot[e] >= 0) sys->owned_values[static_cast<size_t>(sys->local_slot[e])] += sys->values[e];
    neighbour_exchange(sys, sys->send_ptr, sys->send_buffer.data(), sys->recv_ptr, sys->recv_buffer.data());
    for (size_t k = 0; k < sys->recv_slot.size(); ++k)
      sys->owned_values[static_cast<size_t>(sys->recv_slot[k])] += sys->recv_buffer[k];
    replace_values(*sys->matrix, sys->row_ptr, 0, sys->n_owned, sys->owned_values.data(), sys->owned_slots);
    sys->assembled = true;
  } catch (...) {
    status = status_from_exception(SK_ERR_INTERNAL, "sk_linsys_assemble", std::current_exception());
  }
  return agree(sys->comm, status, "sk_linsys_assemble");
}

sk_status sk_linsys_sum_rows(sk_linear_system *sys, const double *local, double *owned) {
  if (sys->matrix.is_null()) return sk_error_set(SK_ERR_INTERNAL, "sk_linsys_sum_rows: no pattern set");
  std::fill(owned, owned + sys->n_owned, 0.0);
  for (size_t i = 0; i < sys->local_rows.size(); ++i) {
    const int row = sys->local_rows[i];
    if (row >= sys->first_row && row < sys->first_row + sys->n_owned) owned[row - sys->first_row] += local[i];
  }
  for (size_t k = 0; k < sys->send_row_index.size(); ++k)
    sys->row_send_buffer[k] = local[static_cast<size_t>(sys->send_row_index[k])];
  neighbour_exchange(sys, sys->send_row_ptr, sys->row_send_buffer.data(), sys->recv_row_ptr,
                     sys->row_recv_buffer.data());
  for (size_t k = 0; k < sys->recv_row_index.size(); ++k) owned[sys->recv_row_index[k]] += sys->row_recv_buffer[k];
  return SK_OK;
}

sk_status sk_linsys_solve(sk_linear_system *sys, const double *b, double *x, sk_linear_report *report) {
  sk_linear_report local_report{};
  if (!report) report = &local_report;
  *report = sk_linear_report{};
  if (!sys->assembled) return sk_error_set(SK_ERR_INTERNAL, "sk_linsys_solve: matrix not assembled");
  dump_system(sys, b);
  const double start = now_seconds();
  double norm_b = 0;
  for (int i = 0; i < sys->n_owned; ++i) norm_b += b[i] * b[i];
  MPI_Allreduce(MPI_IN_PLACE, &norm_b, 1, MPI_DOUBLE, MPI_SUM, sys->comm);
  if (norm_b == 0) {  // x = 0 exactly; Krylov solvers divide by ||b||
    std::fill(x, x + sys->n_owned, 0.0);
    report->solver = sys->options.kind == SK_LINEAR_DIRECT ? SK_LINEAR_DIRECT_MUMPS : sys->options.kind;
    return SK_OK;
  }
  if (!std::isfinite(norm_b)) {
    report->failure = SK_LINEAR_FAILURE_INPUT;
    return sk_error_set(SK_ERR_LINEAR_SOLVER, "sk_linsys_solve: non-finite right-hand side");
  }
  sk_status status;
  if (sys->options.kind != SK_LINEAR_AUTO) {
    const sk_linear_solver_kind kind = sys->options.kind == SK_LINEAR_DIRECT ? SK_LINEAR_DIRECT_MUMPS : sys->options.kind;
    status = solve_with(sys, kind, b, x, report);
  } else {
    // AUTO: the candidate its measurements favour; if an iterative attempt fails, the direct solver on the same
    // system (auto_choice.cpp remembers the failure and does not try that solver again on this pattern). Costs are
    // measured in CPU time: on a shared machine wall time swung by 2x between runs and flipped the choice.
    const sk_linear_solver_kind kind = auto_choose(sys);
    const double attempt_start = cpu_seconds();
    status = solve_with(sys, kind, b, x, report);
    auto_record(sys, kind, status, cpu_seconds() - attempt_start, sys->setup_cpu_seconds, *report);
    // the fallback may be the iterative solver a trial was measured against, which can fail on this system too:
    // fall back again until a solver converges or a MUMPS-backed one (which falls back to a fresh factorisation
    // itself) has answered (at most once per candidate)
    int iterations = report->iterations;
    for (sk_linear_solver_kind tried = kind; status == SK_ERR_LINEAR_SOLVER && !mumps_backed(tried);) {
      tried = auto_fallback(sys);
      const double fallback_start = cpu_seconds();
      status = solve_with(sys, tried, b, x, report);
      auto_record(sys, tried, status, cpu_seconds() - fallback_start, sys->setup_cpu_seconds, *report);
      iterations += report->iterations;
      report->iterations = iterations;
      report->refactored_symbolic = 1;
    }
    if (sys->auto_memory.decision_pending) {
      sys->auto_memory.decision_pending = false;
      report->decision = sys->auto_memory.decision.c_str();
      if (sys->rank == 0) {
        if (sys->options.log) {
          sys->options.log(sys->options.log_ctx, report->decision);
        } else {
          std::fprintf(stderr, "linear solver (auto): %s\n", report->decision);
        }
      }
    }
  }
  sys->last_kind = report->solver;
  report->solved = 1;
  report->seconds = now_seconds() - start;
  if (sys->options.verbose && sys->rank == 0)
    std::printf("linear solve (%s): n = %d, %d iterations, %d factorisations, %d refinements, relative residual %.3g, "
                "%.3f s\n", sk_linear_solver_name(report->solver), sys->n, report->iterations, report->factorisations,
                report->refinements, report->relative_residual, report->seconds);
  return status;
}

sk_status sk_linsys_apply(sk_linear_system *sys, const double *x, double *y) {
  if (!sys->assembled) return sk_error_set(SK_ERR_INTERNAL, "sk_linsys_apply: matrix not assembled");
  try {
    Vector xv(sys->row_map), yv(sys->row_map);
    copy_to(x, xv);
    sys->matrix->apply(xv, yv);
    copy_from(yv, y);
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
  const double start = now_seconds();
  sk_status status = SK_OK;
  try {
    if (!solve_amesos_again(sys, sys->last_kind, b, x, report, &status)) return sk_linsys_solve(sys, b, x, report);
  } catch (...) {
    status = status_from_exception(SK_ERR_LINEAR_SOLVER, "sk_linsys_solve_again", std::current_exception());
  }
  report->solved = 1;
  report->seconds = now_seconds() - start;
  return agree(sys->comm, status, "sk_linsys_solve_again");
}

}  // extern "C"

namespace stickslip::bridge {

system_rows rows_of(const sk_linear_system *sys) {
  system_rows rows;
  rows.n = sys->n;
  rows.n_nodal = sys->n_nodal;
  rows.row_ptr = sys->row_ptr.data();
  rows.cols = sys->cols.data();
  rows.first_row = sys->first_row;
  rows.n_owned = sys->n_owned;
  rows.owned_values = sys->owned_values.data();
  rows.row_offsets = sys->row_offsets.data();
  return rows;
}

}  // namespace stickslip::bridge
