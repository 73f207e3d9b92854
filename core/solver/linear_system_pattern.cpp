// stickslip — sk_linsys_set_pattern: the rows each rank writes checked, merged on their owners and turned into the
// owned rows' static graph, with the plan that sk_linsys_assemble follows (which contributions stay, which go to
// which neighbour and where they land). Set-up only: nothing here runs inside a Newton iteration.
#include <algorithm>
#include <cstdio>
#include <cstring>

#include "bridge_internal.hpp"
#include "linear_system.hpp"

namespace stickslip::bridge {

namespace {

sk_status check_pattern(int n, int n_rows, const int *rows, const int64_t *row_ptr, const int *cols) {
  if (n_rows < 0) return sk_error_set(SK_ERR_INPUT, "linear system: negative number of local rows %d", n_rows);
  if (!row_ptr || (n_rows > 0 && (!rows || !cols)))
    return sk_error_set(SK_ERR_INPUT, "linear system: missing CSR arrays");
  if (row_ptr[0] != 0) return sk_error_set(SK_ERR_INPUT, "linear system: row_ptr[0] = %lld, expected 0", (long long)row_ptr[0]);
  for (int i = 0; i < n_rows; ++i) {
    if (rows[i] < 0 || rows[i] >= n)
      return sk_error_set(SK_ERR_INPUT, "linear system: local row %d is outside [0, %d)", rows[i], n);
    if (row_ptr[i + 1] < row_ptr[i])
      return sk_error_set(SK_ERR_INPUT, "linear system: row_ptr decreases at local row %d", i);
    for (int64_t k = row_ptr[i]; k < row_ptr[i + 1]; ++k) {
      if (cols[k] < 0 || cols[k] >= n)
        return sk_error_set(SK_ERR_INPUT, "linear system: column %d of row %d is outside [0, %d)", cols[k], rows[i], n);
      if (k > row_ptr[i] && cols[k] <= cols[k - 1])
        return sk_error_set(SK_ERR_INPUT, "linear system: columns of row %d are not sorted and unique", rows[i]);
    }
  }
  std::vector<int> sorted(rows, rows + n_rows);
  std::sort(sorted.begin(), sorted.end());
  if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
    return sk_error_set(SK_ERR_INPUT, "linear system: local row %d is given twice",
                        *std::adjacent_find(sorted.begin(), sorted.end()));
  return SK_OK;
}

int owner_of(const sk_linear_system *sys, int row) {
  return static_cast<int>(std::upper_bound(sys->row_offsets.begin(), sys->row_offsets.end(), row) -
                          sys->row_offsets.begin()) - 1;
}

// Counts per rank exchanged, then the payloads (set-up only: O(ranks) per pattern).
std::vector<int> exchange_ints(MPI_Comm comm, int size, const std::vector<int> &send_counts,
                               const std::vector<int> &send, std::vector<int> &recv_counts) {
  recv_counts.assign(size, 0);
  MPI_Alltoall(send_counts.data(), 1, MPI_INT, recv_counts.data(), 1, MPI_INT, comm);
  std::vector<int> send_displs(size, 0), recv_displs(size, 0);
  for (int r = 1; r < size; ++r) {
    send_displs[r] = send_displs[r - 1] + send_counts[r - 1];
    recv_displs[r] = recv_displs[r - 1] + recv_counts[r - 1];
  }
  std::vector<int> recv(static_cast<size_t>(recv_displs[size - 1] + recv_counts[size - 1]));
  MPI_Alltoallv(send.data(), send_counts.data(), send_displs.data(), MPI_INT, recv.data(), recv_counts.data(),
                recv_displs.data(), MPI_INT, comm);
  return recv;
}

// The owned rows as the union of every rank's local rows, and the assembly plan (see the top of this file).
void merge_rows(sk_linear_system *sys) {
  const int size = sys->size, n_local = static_cast<int>(sys->local_rows.size());
  // non-owned local rows, grouped by owner: [row, length, columns...]
  std::vector<std::vector<int>> to(size);
  std::vector<std::vector<int>> to_rows(size);  // local row indices sent to each owner, in order
  for (int i = 0; i < n_local; ++i) {
    const int row = sys->local_rows[i], owner = owner_of(sys, row);
    if (owner == sys->rank) continue;
    std::vector<int> &out = to[owner];
    out.push_back(row);
    out.push_back(static_cast<int>(sys->local_row_ptr[i + 1] - sys->local_row_ptr[i]));
    out.insert(out.end(), sys->local_cols.begin() + sys->local_row_ptr[i], sys->local_cols.begin() + sys->local_row_ptr[i + 1]);
    to_rows[owner].push_back(i);
  }
  std::vector<int> send_counts(size), send;
  for (int r = 0; r < size; ++r) {
    send_counts[r] = static_cast<int>(to[r].size());
    send.insert(send.end(), to[r].begin(), to[r].end());
  }
  std::vector<int> recv_counts;
  const std::vector<int> recv = exchange_ints(sys->comm, size, send_counts, send, recv_counts);

  // owned rows: own local rows plus the received ones
  std::vector<std::vector<int>> owned(static_cast<size_t>(sys->n_owned));
  for (int i = 0; i < n_local; ++i) {
    const int row = sys->local_rows[i];
    if (owner_of(sys, row) != sys->rank) continue;
    std::vector<int> &out = owned[static_cast<size_t>(row - sys->first_row)];
    out.insert(out.end(), sys->local_cols.begin() + sys->local_row_ptr[i], sys->local_cols.begin() + sys->local_row_ptr[i + 1]);
  }
  for (size_t k = 0; k < recv.size();) {
    const int row = recv[k], len = recv[k + 1];
    std::vector<int> &out = owned[static_cast<size_t>(row - sys->first_row)];
    out.insert(out.end(), recv.begin() + static_cast<int64_t>(k) + 2, recv.begin() + static_cast<int64_t>(k) + 2 + len);
    k += 2 + static_cast<size_t>(len);
  }
  sys->row_ptr.assign(static_cast<size_t>(sys->n_owned) + 1, 0);
  sys->cols.clear();
  for (int i = 0; i < sys->n_owned; ++i) {
    std::vector<int> &out = owned[static_cast<size_t>(i)];
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    sys->cols.insert(sys->cols.end(), out.begin(), out.end());
    sys->row_ptr[i + 1] = static_cast<int64_t>(sys->cols.size());
  }
  sys->owned_values.assign(sys->cols.size(), 0.0);
  auto slot = [sys](int row, int col) {
    const int i = row - sys->first_row;
    const auto begin = sys->cols.begin() + sys->row_ptr[i], end = sys->cols.begin() + sys->row_ptr[i + 1];
    return static_cast<int64_t>(std::lower_bound(begin, end, col) - sys->cols.begin());
  };
  // own local entries: their slots; the others: sent
  sys->local_slot.assign(sys->local_cols.size(), -1);
  for (int i = 0; i < n_local; ++i) {
    const int row = sys->local_rows[i];
    if (owner_of(sys, row) != sys->rank) continue;
    for (int64_t k = sys->local_row_ptr[i]; k < sys->local_row_ptr[i + 1]; ++k) sys->local_slot[k] = slot(row, sys->local_cols[k]);
  }
  sys->send_ranks.clear();
  sys->send_ptr.assign(1, 0);
  sys->send_entries.clear();
  sys->send_row_ptr.assign(1, 0);
  sys->send_row_index.clear();
  for (int r = 0; r < size; ++r) {
    if (to_rows[r].empty()) continue;
    sys->send_ranks.push_back(r);
    for (int i : to_rows[r]) {
      for (int64_t k = sys->local_row_ptr[i]; k < sys->local_row_ptr[i + 1]; ++k) sys->send_entries.push_back(k);
      sys->send_row_index.push_back(i);
    }
    sys->send_ptr.push_back(static_cast<int>(sys->send_entries.size()));
    sys->send_row_ptr.push_back(static_cast<int>(sys->send_row_index.size()));
  }
  sys->recv_ranks.clear();
  sys->recv_ptr.assign(1, 0);
  sys->recv_slot.clear();
  sys->recv_row_ptr.assign(1, 0);
  sys->recv_row_index.clear();
  for (int r = 0, k = 0; r < size; ++r) {
    if (recv_counts[r] == 0) continue;
    sys->recv_ranks.push_back(r);
    const int end = k + recv_counts[r];
    while (k < end) {
      const int row = recv[k], len = recv[k + 1];
      for (int j = 0; j < len; ++j) sys->recv_slot.push_back(slot(row, recv[k + 2 + j]));
      sys->recv_row_index.push_back(row - sys->first_row);
      k += 2 + len;
    }
    sys->recv_ptr.push_back(static_cast<int>(sys->recv_slot.size()));
    sys->recv_row_ptr.push_back(static_cast<int>(sys->recv_row_index.size()));
  }
  sys->send_buffer.assign(sys->send_entries.size(), 0.0);
  sys->recv_buffer.assign(sys->recv_slot.size(), 0.0);
  sys->row_send_buffer.assign(sys->send_row_index.size(), 0.0);
  sys->row_recv_buffer.assign(sys->recv_row_index.size(), 0.0);
  sys->owned_diagonal.assign(static_cast<size_t>(sys->n_owned), -1);
  for (int i = 0; i < sys->n_owned; ++i) {
    const int row = sys->first_row + i;
    const auto begin = sys->cols.begin() + sys->row_ptr[i], end = sys->cols.begin() + sys->row_ptr[i + 1];
    const auto found = std::lower_bound(begin, end, row);
    if (found != end && *found == row) sys->owned_diagonal[i] = found - sys->cols.begin();
  }
  int64_t entries = static_cast<int64_t>(sys->cols.size());
  MPI_Allreduce(&entries, &sys->global_entries, 1, MPI_INT64_T, MPI_SUM, sys->comm);
}

}  // namespace

}  // namespace stickslip::bridge

using namespace stickslip::bridge;

extern "C" {

sk_status sk_linsys_set_pattern(sk_linear_system *sys, int n_nodal_owned, int n_constraints, int n_rows,
                                const int *rows, const int64_t *row_ptr, const int *cols) {
  // the layout first: every rank's nodal count, then the global size
  std::vector<int> nodal_counts(sys->size, 0);
  MPI_Allgather(&n_nodal_owned, 1, MPI_INT, nodal_counts.data(), 1, MPI_INT, sys->comm);
  int64_t n_nodal = 0;
  for (int c : nodal_counts) n_nodal += c;
  int constraint_range[2] = {n_constraints, -n_constraints};
  MPI_Allreduce(MPI_IN_PLACE, constraint_range, 2, MPI_INT, MPI_MAX, sys->comm);
  sk_status status = SK_OK;
  const int64_t n = n_nodal + n_constraints;
  const int block = sys->coordinate_dim > 0 ? sys->coordinate_dim : sys->block_size;
  if (n_nodal_owned < 0 || n_constraints < 0 || constraint_range[0] != -constraint_range[1])
    status = sk_error_set(SK_ERR_INPUT, "linear system: %d nodal rows and %d constraint rows (the same on every rank)",
                          n_nodal_owned, n_constraints);
  else if (n > INT32_MAX - 16)
    status = sk_error_set(SK_ERR_INPUT, "linear system: %lld unknowns exceed the int numbering", (long long)n);
  else if (sys->coordinate_dim > 0 && static_cast<size_t>(n_nodal_owned) != sys->coordinates.size())
    status = sk_error_set(SK_ERR_INPUT, "linear system: the coordinates give %zu nodal unknowns on this rank, the "
                          "layout %d", sys->coordinates.size(), n_nodal_owned);
  else if (sys->coordinate_dim == 0 && (n_nodal_owned % block != 0 || (sys->rank == sys->size - 1 && n_constraints % block != 0)))
    status = sk_error_set(SK_ERR_INPUT, "linear system: %d unknowns are not a multiple of the block size %d",
                          n_nodal_owned, block);
  else
    status = check_pattern(static_cast<int>(n), n_rows, rows, row_ptr, cols);
  status = agree(sys->comm, status, "linear system pattern check");
  if (status != SK_OK) return status;
  try {
    const int previous_n_owned = sys->n_owned, previous_n = sys->n, previous_nodal = sys->n_nodal;
    release_pattern(sys);
    ++sys->pattern_generation;
    sys->n = static_cast<int>(n);
    // without coordinates the whole system is one block (the constraint rows are nodal ones of the last rank)
    sys->n_nodal = sys->coordinate_dim > 0 ? static_cast<int>(n_nodal) : sys->n;
    sys->row_offsets.assign(sys->size + 1, 0);
    for (int r = 0; r < sys->size; ++r) sys->row_offsets[r + 1] = sys->row_offsets[r] + nodal_counts[r];
    sys->row_offsets[sys->size] = sys->n;
    sys->row_counts.assign(sys->size, 0);
    for (int r = 0; r < sys->size; ++r) sys->row_counts[r] = sys->row_offsets[r + 1] - sys->row_offsets[r];
    sys->first_row = sys->row_offsets[sys->rank];
    sys->n_owned = sys->row_offsets[sys->rank + 1] - sys->first_row;
    sys->local_rows.assign(rows, rows + n_rows);
    sys->local_row_ptr.assign(row_ptr, row_ptr + n_rows + 1);
    sys->local_cols.assign(cols, cols + row_ptr[n_rows]);
    sys->values.assign(static_cast<size_t>(row_ptr[n_rows]), 0.0);
    merge_rows(sys);

    // without constraint rows the row map is the nodal map: keep its object while the layout holds, so the
    // preconditioners built on it stay usable on the new pattern (iterative_solvers.cpp)
    int same = sys->n_nodal == sys->n && !sys->nodal_map.is_null() && previous_n == sys->n &&
               previous_nodal == sys->n_nodal && previous_n_owned == sys->n_owned;
    MPI_Allreduce(MPI_IN_PLACE, &same, 1, MPI_INT, MPI_MIN, sys->comm);
    sys->row_map = same ? sys->nodal_map
                        : RCP<const Map>(rcp(new Map(static_cast<Tpetra::global_size_t>(sys->n),
                                                     static_cast<size_t>(sys->n_owned), 0, sys->tcomm)));
    sys->matrix = build_matrix(sys->row_map, sys->row_map, sys->row_ptr, sys->cols, 0, sys->owned_slots);
    status = SK_OK;
  } catch (...) {
    release_pattern(sys);
    status = status_from_exception(SK_ERR_INTERNAL, "sk_linsys_set_pattern", std::current_exception());
  }
  return agree(sys->comm, status, "sk_linsys_set_pattern");
}

}  // extern "C"
