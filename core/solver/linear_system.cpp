// stickslip — sk_linsys_*: the distributed Tpetra matrix, its assembly, and the dispatch to the solvers.
//
// Assembly. Each rank writes into a values array laid over the replicated CSR pattern. At set_pattern time the
// ranks agree (once) which of their local rows go to which owner; sk_linsys_assemble then moves the values of
// those rows with one MPI_Alltoallv, sums them into the owner's CSR-ordered `owned_values`, and replaces the
// values of the static-graph Tpetra matrix in place. Because row ownership is in contiguous blocks, the owners'
// `owned_values` concatenated over ranks are exactly the full CSR values array: the direct solver's gather to
// rank 0 is a single MPI_Gatherv.
#include "linear_system.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <optional>

#include <Teuchos_DefaultMpiComm.hpp>
#include <Tpetra_Details_initializeKokkos.hpp>

#include "bridge_internal.hpp"
#include "stickslip/condense.h"

namespace stickslip::bridge {

namespace {

// Severity for agree(): the worst status wins. A linear-solver failure ranks with Newton's own failures, below
// input, I/O, plugin and internal errors.
int severity(sk_status status) { return status == SK_ERR_LINEAR_SOLVER ? 9 : 2 * static_cast<int>(status); }

void release_pattern(sk_linear_system *sys) {
  release_direct(sys);
  release_iterative_pattern(sys);
  sys->matrix = Teuchos::null;
  sys->row_map = Teuchos::null;
  sys->assembled = false;
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

// Row blocks: the nodal rows split by node count (whole nodes per rank), the constraint rows on the last rank.
void distribute_rows(sk_linear_system *sys) {
  const int block = sys->coordinate_dim > 0 ? sys->coordinate_dim : sys->block_size;
  const int nodes = sys->n_nodal / block;
  sys->row_offsets.assign(sys->size + 1, 0);
  for (int r = 0; r < sys->size; ++r) {
    const int nodes_r = nodes / sys->size + (r < nodes % sys->size ? 1 : 0);
    sys->row_offsets[r + 1] = sys->row_offsets[r] + nodes_r * block;
  }
  sys->row_offsets[sys->size] = sys->n;
}

// The once-per-pattern plan of sk_linsys_assemble: local rows grouped by owner (already sorted, and owners hold
// increasing row blocks).
void plan_exchange(sk_linear_system *sys) {
  const int64_t *row_ptr = sys->row_ptr.data();
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
  if (sys->size > 1 && sys->rank == 0) sys->gathered_values.assign(static_cast<size_t>(row_ptr[sys->n]), 0.0);
}

sk_status solve_with(sk_linear_system *sys, sk_linear_solver_kind kind, const double *b, double *x,
                     sk_linear_report *report) {
  sk_status status;
  report->solver = kind;
  try {
    status = kind == SK_LINEAR_DIRECT_KLU2 ? solve_klu2(sys, b, x, report)
             : is_direct(kind)             ? solve_amesos(sys, kind, b, x, report)
                                           : solve_iterative(sys, kind, b, x, report);
  } catch (...) {
    status = status_from_exception(SK_ERR_LINEAR_SOLVER, sk_linear_solver_name(kind), std::current_exception());
    if (is_direct(kind)) release_direct(sys);
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

double relative_residual(sk_linear_system *sys, const Vector &b, const Vector &x, Vector *residual) {
  std::optional<Vector> scratch;
  if (!residual) residual = &scratch.emplace(sys->row_map);
  Vector &r = *residual;
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
// CSR rows [first_row, first_row + n_rows) goes to slot[e]. The matrix stays fill-complete (no resumeFill /
// fillComplete, which cost 10 % of a full two-tori contact step with the row-wise replaceLocalValues it replaces).
void replace_values(Matrix &matrix, const std::vector<int64_t> &row_ptr, int64_t value_begin, int first_row,
                    int n_rows, const double *values, const std::vector<LocalOrdinal> &slot) {
  const auto stored = matrix.getLocalValuesView();  // host memory: Kokkos is built for Serial only
  const int64_t n_entries = row_ptr[first_row + n_rows] - row_ptr[first_row];
  const int64_t offset = row_ptr[first_row] - value_begin;
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
  // the column map: the domain's own columns first (in order), then the others by owning rank (Tpetra's layout);
  // a dense table from global column to local index (the domain is at most the replicated system's size)
  std::vector<LocalOrdinal> local_of(domain_map->getGlobalNumElements(), -1);
  for (size_t e = 0; e < n_entries; ++e) local_of[static_cast<size_t>(cols[e])] = 0;
  std::vector<GlobalOrdinal> own, remote;
  for (size_t g = 0; g < local_of.size(); ++g) {
    if (local_of[g] < 0) continue;
    (domain_map->isNodeGlobalElement(static_cast<GlobalOrdinal>(g)) ? own : remote).push_back(static_cast<GlobalOrdinal>(g));
  }
  std::vector<int> owners(remote.size());
  domain_map->getRemoteIndexList(Teuchos::ArrayView<const GlobalOrdinal>(remote.data(), remote.size()),
                                 Teuchos::ArrayView<int>(owners.data(), owners.size()));
  std::vector<std::pair<int, GlobalOrdinal>> by_owner(remote.size());
  for (size_t i = 0; i < remote.size(); ++i) by_owner[i] = {owners[i], remote[i]};
  std::sort(by_owner.begin(), by_owner.end());
  std::vector<GlobalOrdinal> column_gids(own);
  for (const auto &entry : by_owner) column_gids.push_back(entry.second);
  for (size_t c = 0; c < column_gids.size(); ++c) local_of[static_cast<size_t>(column_gids[c])] = static_cast<LocalOrdinal>(c);
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
    for (size_t k = b; k < e; ++k)
      row.emplace_back(local_of[static_cast<size_t>(cols[k])], static_cast<LocalOrdinal>(k - b));
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

// The static-graph matrix of rows [first_row, first_row + map's local count) and the CSR -> CRS value slot table.
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
    const int row = row_begin + i;
    for (int64_t k = sys->row_ptr[row]; k < sys->row_ptr[row + 1]; ++k) {
      if (sys->cols[k] < col_begin || sys->cols[k] >= col_end) continue;
      block.source.push_back(k - sys->owned_value_begin);
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
  return sk_error_set(SK_ERR_INPUT, "unknown linear solver '%s' (expected direct, gmres-muelu, gmres-ilu, gmres-sgs, gmres-jacobi, auto, mumps, "
                      "klu2 or klu)",
                      name ? name : "(null)");
}

const char *sk_linear_solver_name(sk_linear_solver_kind kind) {
  switch (kind) {
    case SK_LINEAR_DIRECT: return "direct";
    case SK_LINEAR_GMRES_MUELU: return "gmres-muelu";
    case SK_LINEAR_GMRES_ILU: return "gmres-ilu";
    case SK_LINEAR_GMRES_SGS: return "gmres-sgs";
    case SK_LINEAR_GMRES_JACOBI: return "gmres-jacobi";
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
    if (kind_value < SK_LINEAR_DIRECT || kind_value > SK_LINEAR_GMRES_JACOBI)
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
  if (kind < SK_LINEAR_DIRECT || kind > SK_LINEAR_GMRES_JACOBI)
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

sk_status sk_linsys_set_block_size(sk_linear_system *sys, int block_size) {
  // checked against the unknowns by the next sk_linsys_set_pattern, which callers make after this
  if (block_size < 1) return sk_error_set(SK_ERR_INPUT, "linear system: block size %d must be >= 1", block_size);
  if (block_size != sys->block_size) release_iterative(sys);  // the hierarchy depends on it
  sys->block_size = block_size;
  return SK_OK;
}

sk_status sk_linsys_set_coordinates(sk_linear_system *sys, int n_nodes, int dim, const double *coordinates) {
  if ((dim != 2 && dim != 3) || n_nodes < 0 || (n_nodes > 0 && !coordinates))
    return sk_error_set(SK_ERR_INPUT, "linear system: coordinates need dim 2 or 3 (got %d) and %d nodes", dim,
                        n_nodes);
  const size_t count = static_cast<size_t>(n_nodes) * dim;
  if (dim != sys->coordinate_dim || count != sys->coordinates.size() ||
      !std::equal(coordinates, coordinates + count, sys->coordinates.begin()))
    release_iterative(sys);  // the nullspace changed
  sys->coordinate_dim = dim;
  sys->coordinates.assign(coordinates, coordinates + count);
  return SK_OK;
}

sk_status sk_linsys_set_pattern(sk_linear_system *sys, int n, const int64_t *row_ptr, const int *cols,
                                int n_local_rows, const int *local_rows) {
  sk_status status = check_pattern(n, row_ptr, cols, n_local_rows, local_rows);
  status = agree(sys->comm, status, "linear system pattern check");
  if (status != SK_OK) return status;
  const int n_nodal = sys->coordinate_dim > 0 ? static_cast<int>(sys->coordinates.size()) : n;
  if (n_nodal > n)
    return sk_error_set(SK_ERR_INPUT, "linear system: the coordinates give %d nodal unknowns, the system has only %d",
                        n_nodal, n);
  if (sys->coordinate_dim == 0 && n % sys->block_size != 0)
    return sk_error_set(SK_ERR_INPUT, "linear system: %d unknowns are not a multiple of the block size %d", n,
                        sys->block_size);
  try {
    release_pattern(sys);
    ++sys->pattern_generation;
    sys->n = n;
    sys->n_nodal = n_nodal;
    sys->row_ptr.assign(row_ptr, row_ptr + n + 1);
    sys->cols.assign(cols, cols + row_ptr[n]);
    sys->local_rows.assign(local_rows, local_rows + n_local_rows);
    sys->values.assign(static_cast<size_t>(row_ptr[n]), 0.0);

    distribute_rows(sys);
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
    plan_exchange(sys);

    // without constraint rows the row map is the nodal map: keep its object while the layout holds, so the
    // preconditioners built on it stay usable on the new pattern (iterative_solvers.cpp)
    const bool same_nodal = n_nodal == n && !sys->nodal_map.is_null() &&
                            sys->nodal_map->getGlobalNumElements() == static_cast<size_t>(n) &&
                            sys->nodal_map->getNodeNumElements() == static_cast<size_t>(n_owned);
    sys->row_map = same_nodal ? sys->nodal_map
                              : RCP<const Map>(rcp(new Map(static_cast<Tpetra::global_size_t>(n),
                                                           static_cast<size_t>(n_owned), 0, sys->tcomm)));
    sys->matrix = build_matrix(sys->row_map, sys->row_map, sys->row_ptr, sys->cols, first_row, sys->owned_slots);
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
                   sys->row_offsets[sys->rank + 1] - first_row, sys->owned_values.data(), sys->owned_slots);
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
  dump_system(sys, b);
  const double start = now_seconds();
  double norm_b = 0;
  for (int i = 0; i < sys->n; ++i) norm_b += b[i] * b[i];
  if (norm_b == 0) {  // x = 0 exactly; Krylov solvers divide by ||b||
    std::fill(x, x + sys->n, 0.0);
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
    auto_record(sys, kind, status, cpu_seconds() - attempt_start, report->iterations);
    if (status == SK_ERR_LINEAR_SOLVER && !is_direct(kind)) {
      const int iterations = report->iterations;
      const sk_linear_solver_kind fallback = auto_fallback(sys);
      const double fallback_start = cpu_seconds();
      status = solve_with(sys, fallback, b, x, report);
      auto_record(sys, fallback, status, cpu_seconds() - fallback_start, report->iterations);
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
    std::printf("linear solve (%s): n = %d, %d iterations, %d refinements, relative residual %.3g, %.3f s\n",
                sk_linear_solver_name(report->solver), sys->n, report->iterations, report->refinements,
                report->relative_residual, report->seconds);
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
