// stickslip — condensation of paired multipliers on the assembled operator (condense.h).
//
// The full operator A is summed on its owners by sk_linsys_assemble (contiguous row blocks; the multipliers z are
// constraint unknowns, which live on the last rank, the paired rows S nodal rows of any rank). The paired rows are
// gathered to every rank (their structure once per pattern, their values with one Allgatherv per assembly: the
// rows of the contact slave nodes, a small part of A), so that each rank can
//   - form the reduced rows of its owned full rows: row r ← r − A[r, Z_g] D_g⁻¹ A[S_g, ·] for every group g whose
//     multipliers appear in row r, written at r's reduced position (a multiplier row at the place of its paired
//     row, which another rank may own), then summed into the reduced system's owners by sk_linsys_assemble (each
//     reduced row has one writer);
//   - transform its owned entries of the right-hand side the same way (b at the paired rows gathered);
//   - and the last rank recovers dz_g = D_g⁻¹ (b_S − A[S_g, u] du) for every group, from the gathered rows and the
//     entries of du they touch (gathered to it).
// Reduced numbering: nodal unknowns keep their index (the multipliers are all constraint unknowns, after them), a
// constraint unknown moves down by the multipliers before it; rank r owns the same nodal rows as in A.
#include "stickslip/condense.h"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <vector>

#include "bridge_internal.hpp"
#include "linear_system.hpp"

using stickslip::bridge::rows_of;
using stickslip::bridge::status_from_exception;
using stickslip::bridge::system_rows;

struct sk_condenser {
  MPI_Comm comm = MPI_COMM_NULL;
  int rank = 0, size = 1;
  sk_linear_options options{};
  sk_linear_system *reduced = nullptr;

  // the pairs of every rank (full numbering), grouped
  std::vector<int> z, s, block;            // per pair
  std::vector<int> group_of;               // per pair: its group
  std::vector<int> group_first;            // per group: its first pair (groups are consecutive pairs)
  std::vector<std::pair<int, int>> z_sorted, s_sorted_pairs;  // (unknown, pair), ascending
  int n = 0, n_nodal = 0, n_red = 0;
  int built_generation = -1;               // the full pattern's generation the reduced one was built for
  int first_row = 0, n_owned = 0;          // the full system's owned rows
  int red_first = 0, red_owned = 0;        // the reduced system's owned rows

  // gathered paired rows: s rows in increasing order, their structure and (after each assembly) values
  std::vector<int> s_sorted;               // the paired rows, ascending
  std::vector<int> s_index;                // per pair: index of its row in s_sorted
  std::vector<int64_t> s_start;            // per s_sorted row: offset of its entries in s_cols / s_values
  std::vector<int> s_cols;
  std::vector<double> s_values;
  std::vector<int> gather_counts, gather_displs;          // values of the owned paired rows, per rank
  std::vector<int> b_counts, b_displs;                    // the paired rows per rank (right-hand side)
  std::vector<double> send, b_send, b_s;                  // b at the paired rows (gathered)
  std::vector<double> d_inverse;           // per group: block x block, D_g^-1 (rows: z of the group, cols: s)
  std::vector<int64_t> d_start;            // per group: offset into d_inverse

  // the reduced system's local rows: per owned full row (local index) its reduced row's index among them, or -1
  std::vector<int> local_of_owned;
  std::vector<int> red_rows;               // global reduced row of each local reduced row
  std::vector<int64_t> red_row_ptr;
  std::vector<int> red_cols;

  // per owned full row: coefficients c_s of the paired rows subtracted from it (for the right-hand side)
  std::vector<int64_t> coef_ptr;
  std::vector<int> coef_pair;
  std::vector<double> coef_value;

  // the entries of du the recovery reads (the u columns of the paired rows), gathered to the last rank
  std::vector<int> u_needed;               // sorted global columns
  std::vector<int> u_send;                 // this rank's owned ones, as owned row indices
  std::vector<int> u_counts, u_displs;
  std::vector<double> u_send_values, u_values;

  std::vector<double> b_red, x_red;
};

namespace {

// Inverse of a b x b block (b <= 3) by Gauss-Jordan with partial pivoting; false when singular.
bool invert(int b, const double *a, double *inv) {
  double m[3][6];
  for (int i = 0; i < b; ++i)
    for (int j = 0; j < 2 * b; ++j) m[i][j] = j < b ? a[i * b + j] : (j - b == i ? 1.0 : 0.0);
  double scale = 0.0;
  for (int i = 0; i < b * b; ++i) scale = std::max(scale, std::fabs(a[i]));
  for (int c = 0; c < b; ++c) {
    int pivot = c;
    for (int r = c + 1; r < b; ++r)
      if (std::fabs(m[r][c]) > std::fabs(m[pivot][c])) pivot = r;
    // a pivot at round-off of the block's scale: a D block that is not invertible
    if (!(std::fabs(m[pivot][c]) > 1e-13 * scale)) return false;
    for (int j = 0; j < 2 * b; ++j) std::swap(m[c][j], m[pivot][j]);
    const double p = m[c][c];
    for (int j = 0; j < 2 * b; ++j) m[c][j] /= p;
    for (int r = 0; r < b; ++r)
      if (r != c) {
        const double f = m[r][c];
        for (int j = 0; j < 2 * b; ++j) m[r][j] -= f * m[c][j];
      }
  }
  for (int i = 0; i < b; ++i)
    for (int j = 0; j < b; ++j) inv[i * b + j] = m[i][b + j];
  return true;
}

sk_status agree(MPI_Comm comm, sk_status local, const char *what) {
  int code = static_cast<int>(local), worst = 0;
  MPI_Allreduce(&code, &worst, 1, MPI_INT, MPI_MAX, comm);
  if (worst != SK_OK && local == SK_OK)
    return sk_error_set(static_cast<sk_status>(worst), "%s failed on another rank", what);
  return static_cast<sk_status>(worst == SK_OK ? SK_OK : (local != SK_OK ? local : worst));
}

// Every rank's pairs, in rank order.
void gather_pairs(sk_condenser *c, int64_t n_pairs, const int64_t *z, const int64_t *row, const int *block,
                  std::vector<int> &all_z, std::vector<int> &all_s, std::vector<int> &all_block) {
  const int count = static_cast<int>(n_pairs);
  std::vector<int> counts(c->size), displs(c->size);
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, c->comm);
  int total = 0;
  for (int r = 0; r < c->size; ++r) {
    displs[r] = total;
    total += counts[r];
  }
  std::vector<int> mine_z(count), mine_s(count), mine_b(count);
  for (int k = 0; k < count; ++k) {
    mine_z[k] = static_cast<int>(z[k]);
    mine_s[k] = static_cast<int>(row[k]);
    mine_b[k] = block[k];
  }
  all_z.assign(total, 0);
  all_s.assign(total, 0);
  all_block.assign(total, 0);
  MPI_Allgatherv(mine_z.data(), count, MPI_INT, all_z.data(), counts.data(), displs.data(), MPI_INT, c->comm);
  MPI_Allgatherv(mine_s.data(), count, MPI_INT, all_s.data(), counts.data(), displs.data(), MPI_INT, c->comm);
  MPI_Allgatherv(mine_b.data(), count, MPI_INT, all_block.data(), counts.data(), displs.data(), MPI_INT, c->comm);
}

// The pair whose multiplier (z) or paired row (s) is `unknown`, or -1.
int pair_of(const std::vector<std::pair<int, int>> &sorted, int unknown) {
  const auto hit = std::lower_bound(sorted.begin(), sorted.end(), std::make_pair(unknown, -1));
  return hit != sorted.end() && hit->first == unknown ? hit->second : -1;
}

// Reduced index of a full unknown (-1 for a multiplier).
int red_of(const sk_condenser *c, int i) {
  if (i < c->n_nodal) return i;
  const auto below = std::lower_bound(c->z_sorted.begin(), c->z_sorted.end(), std::make_pair(i, -1));
  if (below != c->z_sorted.end() && below->first == i) return -1;
  return i - static_cast<int>(below - c->z_sorted.begin());
}

// The reduced row a full row goes to (-1 for a paired row, which its multiplier's row replaces).
int place_of(const sk_condenser *c, int r) {
  if (pair_of(c->s_sorted_pairs, r) >= 0) return -1;
  const int pz = pair_of(c->z_sorted, r);
  return pz >= 0 ? c->s[pz] : red_of(c, r);
}

int owner_of(const int *row_offsets, int size, int row) {
  return static_cast<int>(std::upper_bound(row_offsets, row_offsets + size + 1, row) - row_offsets) - 1;
}

// The value A[s_sorted[i], col] from the gathered paired rows (0 when absent).
double s_value(const sk_condenser *c, int i, int col) {
  const auto begin = c->s_cols.begin() + c->s_start[i], end = c->s_cols.begin() + c->s_start[i + 1];
  const auto hit = std::lower_bound(begin, end, col);
  return hit != end && *hit == col ? c->s_values[static_cast<size_t>(hit - c->s_cols.begin())] : 0.0;
}

// The reduced numbering, groups, gathered paired rows and the reduced pattern of this rank's owned full rows.
sk_status build(sk_condenser *c, const system_rows &full) {
  const int n_pairs = static_cast<int>(c->z.size());
  c->n = full.n;
  c->n_nodal = full.n_nodal;
  c->first_row = full.first_row;
  c->n_owned = full.n_owned;
  c->z_sorted.clear();
  c->s_sorted_pairs.clear();
  c->group_of.assign(n_pairs, -1);
  c->group_first.clear();
  for (int k = 0; k < n_pairs;) {
    const int b = c->block[k];
    if (b < 1 || k + b > n_pairs)
      return sk_error_set(SK_ERR_PLUGIN, "stickslip.condense: pair %d: a group of %d pairs is cut off", k, b);
    for (int j = 0; j < b; ++j) {
      const int p = k + j;
      if (c->block[p] != b)
        return sk_error_set(SK_ERR_PLUGIN, "stickslip.condense: pair %d: group sizes %d and %d mixed", p, b,
                            c->block[p]);
      if (c->z[p] < c->n_nodal || c->z[p] >= c->n || c->s[p] < 0 || c->s[p] >= c->n_nodal)
        return sk_error_set(SK_ERR_PLUGIN, "stickslip.condense: pair %d (%d, %d): the multiplier must be a "
                            "constraint unknown and the row a nodal one of the system of %d", p, c->z[p], c->s[p], c->n);
      c->z_sorted.emplace_back(c->z[p], p);
      c->s_sorted_pairs.emplace_back(c->s[p], p);
      c->group_of[p] = static_cast<int>(c->group_first.size());
    }
    c->group_first.push_back(k);
    k += b;
  }
  std::sort(c->z_sorted.begin(), c->z_sorted.end());
  std::sort(c->s_sorted_pairs.begin(), c->s_sorted_pairs.end());
  for (size_t k = 1; k < c->z_sorted.size(); ++k)
    if (c->z_sorted[k].first == c->z_sorted[k - 1].first)
      return sk_error_set(SK_ERR_PLUGIN, "stickslip.condense: unknown %d is paired twice", c->z_sorted[k].first);
  for (size_t k = 1; k < c->s_sorted_pairs.size(); ++k)
    if (c->s_sorted_pairs[k].first == c->s_sorted_pairs[k - 1].first)
      return sk_error_set(SK_ERR_PLUGIN, "stickslip.condense: row %d is paired twice", c->s_sorted_pairs[k].first);
  c->n_red = c->n - n_pairs;

  // paired rows, ascending, and where each pair's row sits among them
  c->s_sorted.resize(c->s_sorted_pairs.size());
  for (size_t k = 0; k < c->s_sorted_pairs.size(); ++k) c->s_sorted[k] = c->s_sorted_pairs[k].first;
  c->s_index.assign(n_pairs, 0);
  for (size_t k = 0; k < c->s_sorted_pairs.size(); ++k) c->s_index[c->s_sorted_pairs[k].second] = static_cast<int>(k);

  // the paired rows' structure, gathered from their owners (each rank's owned ones are consecutive in s_sorted)
  std::vector<int> my_lengths, my_cols;
  c->b_counts.assign(c->size, 0);
  for (int row : c->s_sorted) {
    const int owner = owner_of(full.row_offsets, c->size, row);
    ++c->b_counts[owner];
    if (owner != c->rank) continue;
    const int i = row - full.first_row;
    my_lengths.push_back(static_cast<int>(full.row_ptr[i + 1] - full.row_ptr[i]));
    my_cols.insert(my_cols.end(), full.cols + full.row_ptr[i], full.cols + full.row_ptr[i + 1]);
  }
  c->b_displs.assign(c->size, 0);
  for (int r = 1; r < c->size; ++r) c->b_displs[r] = c->b_displs[r - 1] + c->b_counts[r - 1];
  std::vector<int> lengths(c->s_sorted.size());
  MPI_Allgatherv(my_lengths.data(), static_cast<int>(my_lengths.size()), MPI_INT, lengths.data(), c->b_counts.data(),
                 c->b_displs.data(), MPI_INT, c->comm);
  c->s_start.assign(c->s_sorted.size() + 1, 0);
  for (size_t i = 0; i < c->s_sorted.size(); ++i) c->s_start[i + 1] = c->s_start[i] + lengths[i];
  c->gather_counts.assign(c->size, 0);
  c->gather_displs.assign(c->size, 0);
  for (int r = 0; r < c->size; ++r)
    for (int i = c->b_displs[r]; i < c->b_displs[r] + c->b_counts[r]; ++i) c->gather_counts[r] += lengths[i];
  for (int r = 1; r < c->size; ++r) c->gather_displs[r] = c->gather_displs[r - 1] + c->gather_counts[r - 1];
  c->s_cols.assign(static_cast<size_t>(c->s_start.back()), 0);
  MPI_Allgatherv(my_cols.data(), static_cast<int>(my_cols.size()), MPI_INT, c->s_cols.data(),
                 c->gather_counts.data(), c->gather_displs.data(), MPI_INT, c->comm);
  c->s_values.assign(c->s_cols.size(), 0.0);
  c->send.assign(my_cols.size(), 0.0);
  c->b_send.assign(my_lengths.size(), 0.0);
  c->b_s.assign(c->s_sorted.size(), 0.0);

  // reduced rows of the owned full rows: each non-paired row's u columns, plus the u columns of the paired rows of
  // every group whose multipliers it touches
  std::vector<std::pair<int, std::vector<int>>> rows;  // (reduced row, columns)
  c->local_of_owned.assign(static_cast<size_t>(c->n_owned), -1);
  std::vector<char> group_seen(c->group_first.size(), 0);
  std::vector<int> touched;
  for (int i = 0; i < c->n_owned; ++i) {
    const int target = place_of(c, full.first_row + i);
    if (target < 0) continue;
    c->local_of_owned[i] = static_cast<int>(rows.size());
    rows.emplace_back(target, std::vector<int>());
    std::vector<int> &out = rows.back().second;
    touched.clear();
    for (int64_t k = full.row_ptr[i]; k < full.row_ptr[i + 1]; ++k) {
      const int col = full.cols[k], pz = pair_of(c->z_sorted, col);
      if (pz < 0) {
        out.push_back(red_of(c, col));
      } else if (!group_seen[c->group_of[pz]]) {
        group_seen[c->group_of[pz]] = 1;
        touched.push_back(c->group_of[pz]);
      }
    }
    for (int g : touched) {
      group_seen[g] = 0;
      const int first = c->group_first[g], b = c->block[first];
      for (int j = 0; j < b; ++j) {
        const int idx = c->s_index[first + j];
        for (int64_t k = c->s_start[idx]; k < c->s_start[idx + 1]; ++k)
          if (pair_of(c->z_sorted, c->s_cols[k]) < 0) out.push_back(red_of(c, c->s_cols[k]));
      }
    }
    out.push_back(target);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
  }
  c->red_rows.clear();
  c->red_row_ptr.assign(1, 0);
  c->red_cols.clear();
  for (const auto &row : rows) {
    c->red_rows.push_back(row.first);
    c->red_cols.insert(c->red_cols.end(), row.second.begin(), row.second.end());
    c->red_row_ptr.push_back(static_cast<int64_t>(c->red_cols.size()));
  }

  // the du entries of the recovery (u columns of all paired rows), gathered to the last rank
  c->u_needed.clear();
  for (int col : c->s_cols)
    if (pair_of(c->z_sorted, col) < 0) c->u_needed.push_back(col);
  std::sort(c->u_needed.begin(), c->u_needed.end());
  c->u_needed.erase(std::unique(c->u_needed.begin(), c->u_needed.end()), c->u_needed.end());
  c->u_send.clear();
  c->u_counts.assign(c->size, 0);
  for (int col : c->u_needed) {
    const int owner = owner_of(full.row_offsets, c->size, col);
    ++c->u_counts[owner];
    if (owner == c->rank) c->u_send.push_back(col - full.first_row);
  }
  c->u_displs.assign(c->size, 0);
  for (int r = 1; r < c->size; ++r) c->u_displs[r] = c->u_displs[r - 1] + c->u_counts[r - 1];
  c->u_send_values.assign(c->u_send.size(), 0.0);
  c->u_values.assign(c->rank == c->size - 1 ? c->u_needed.size() : 0, 0.0);

  c->d_start.assign(c->group_first.size() + 1, 0);
  for (size_t g = 0; g < c->group_first.size(); ++g) {
    const int b = c->block[c->group_first[g]];
    c->d_start[g + 1] = c->d_start[g] + b * b;
  }
  c->d_inverse.assign(static_cast<size_t>(c->d_start.back()), 0.0);
  const int nodal_owned = std::max(0, std::min(full.n_owned, full.n_nodal - full.first_row));
  const int constraints = c->n_red - c->n_nodal;
  SK_TRY(sk_linsys_set_pattern(c->reduced, nodal_owned, constraints, static_cast<int>(c->red_rows.size()),
                               c->red_rows.data(), c->red_row_ptr.data(), c->red_cols.data()));
  c->red_owned = sk_linsys_owned_rows(c->reduced, &c->red_first);
  c->b_red.assign(c->red_rows.size(), 0.0);
  c->x_red.assign(static_cast<size_t>(c->red_owned), 0.0);
  return SK_OK;
}

// Position of reduced column `col` in local reduced row `local`.
int64_t red_position(const sk_condenser *c, int local, int col) {
  const auto begin = c->red_cols.begin() + c->red_row_ptr[local], end = c->red_cols.begin() + c->red_row_ptr[local + 1];
  return std::lower_bound(begin, end, col) - c->red_cols.begin();
}

}  // namespace

extern "C" {

sk_status sk_condenser_create(MPI_Comm comm, const sk_linear_options *options, sk_condenser **out) {
  *out = nullptr;
  try {
    auto c = std::make_unique<sk_condenser>();
    c->options = *options;
    MPI_Comm_dup(comm, &c->comm);
    MPI_Comm_rank(c->comm, &c->rank);
    MPI_Comm_size(c->comm, &c->size);
    sk_status status = sk_linsys_create(c->comm, options, &c->reduced);
    if (status != SK_OK) {
      MPI_Comm_free(&c->comm);
      return status;
    }
    *out = c.release();
    return SK_OK;
  } catch (...) {
    return status_from_exception(SK_ERR_NOMEM, "sk_condenser_create", std::current_exception());
  }
}

void sk_condenser_destroy(sk_condenser *c) {
  if (!c) return;
  sk_linsys_destroy(c->reduced);
  if (c->comm != MPI_COMM_NULL) MPI_Comm_free(&c->comm);
  delete c;
}

int sk_condenser_size(const sk_condenser *c) { return c->n_red; }

sk_linear_system *sk_condenser_reduced(sk_condenser *c) { return c->reduced; }

sk_status sk_condenser_set_pairs(sk_condenser *c, sk_linear_system *full, int64_t n_pairs, const int64_t *z,
                                 const int64_t *row, const int *block) {
  sk_status status = SK_OK;
  try {
    std::vector<int> all_z, all_s, all_block;
    gather_pairs(c, n_pairs, z, row, block, all_z, all_s, all_block);
    const bool same = all_z == c->z && all_s == c->s && all_block == c->block &&
                      c->built_generation == full->pattern_generation;
    if (same) return SK_OK;
    c->z = all_z;
    c->s = all_s;
    c->block = all_block;
    c->built_generation = full->pattern_generation;
    status = build(c, rows_of(full));
  } catch (...) {
    status = status_from_exception(SK_ERR_INTERNAL, "sk_condenser_set_pairs", std::current_exception());
  }
  if (status != SK_OK) c->built_generation = -1;
  return agree(c->comm, status, "stickslip.condense");
}

sk_status sk_condenser_assemble(sk_condenser *c, sk_linear_system *full) {
  SK_TRY(sk_linsys_assemble(full));
  sk_status status = SK_OK;
  try {
    const system_rows rows = rows_of(full);
    // gather the paired rows
    size_t k = 0;
    for (int row : c->s_sorted) {
      if (row < rows.first_row || row >= rows.first_row + rows.n_owned) continue;
      const int i = row - rows.first_row;
      std::copy(rows.owned_values + rows.row_ptr[i], rows.owned_values + rows.row_ptr[i + 1], c->send.data() + k);
      k += static_cast<size_t>(rows.row_ptr[i + 1] - rows.row_ptr[i]);
    }
    MPI_Allgatherv(c->send.data(), static_cast<int>(c->send.size()), MPI_DOUBLE, c->s_values.data(),
                   c->gather_counts.data(), c->gather_displs.data(), MPI_DOUBLE, c->comm);
    // D_g = A[S_g, Z_g] and its inverse; the multipliers of a group appear in no other group's paired rows
    for (size_t g = 0; g < c->group_first.size() && status == SK_OK; ++g) {
      const int first = c->group_first[g], b = c->block[first];
      double D[9];
      for (int i = 0; i < b; ++i)
        for (int j = 0; j < b; ++j) D[i * b + j] = s_value(c, c->s_index[first + i], c->z[first + j]);
      if (!invert(b, D, c->d_inverse.data() + c->d_start[g]))
        status = sk_error_set(SK_ERR_DIVERGED, "stickslip.condense: the D block of multiplier %d (row %d) is "
                              "singular", c->z[first], c->s[first]);
    }
    for (size_t i = 0; i < c->s_sorted.size() && status == SK_OK; ++i) {
      const int g = c->group_of[pair_of(c->s_sorted_pairs, c->s_sorted[i])];
      for (int64_t p = c->s_start[i]; p < c->s_start[i + 1]; ++p) {
        const int pz = pair_of(c->z_sorted, c->s_cols[p]);
        if (pz >= 0 && c->group_of[pz] != g && c->s_values[p] != 0.0)
          status = sk_error_set(SK_ERR_PLUGIN, "stickslip.condense: multiplier %d appears in paired row %d of "
                                "another group: D is not block diagonal (a standard, not dual, mortar basis?)",
                                c->s_cols[p], c->s_sorted[i]);
      }
    }
    if (status == SK_OK) {
      // this rank's reduced rows
      sk_linsys_zero(c->reduced);
      double *values = sk_linsys_values(c->reduced);
      c->coef_ptr.assign(static_cast<size_t>(rows.n_owned) + 1, 0);
      c->coef_pair.clear();
      c->coef_value.clear();
      for (int i = 0; i < rows.n_owned; ++i) {
        const int local = c->local_of_owned[i];
        c->coef_ptr[i + 1] = c->coef_ptr[i];
        if (local < 0) continue;
        for (int64_t p = rows.row_ptr[i]; p < rows.row_ptr[i + 1]; ++p) {
          const int col = rows.cols[p];
          const double a = rows.owned_values[p];
          if (a == 0.0) continue;
          const int pz = pair_of(c->z_sorted, col);
          if (pz < 0) {
            values[red_position(c, local, red_of(c, col))] += a;
            continue;
          }
          // c_s = A[r, z_j] (D_g^-1)[j][s] for the paired rows s of z's group
          const int g = c->group_of[pz], first = c->group_first[g], b = c->block[first];
          const int j = pz - first;
          const double *Dinv = c->d_inverse.data() + c->d_start[g];
          for (int si = 0; si < b; ++si) {
            const double coef = a * Dinv[j * b + si];
            if (coef == 0.0) continue;
            c->coef_pair.push_back(first + si);
            c->coef_value.push_back(coef);
            const int idx = c->s_index[first + si];
            for (int64_t q = c->s_start[idx]; q < c->s_start[idx + 1]; ++q) {
              const int scol = c->s_cols[q];
              if (pair_of(c->z_sorted, scol) >= 0) continue;
              if (c->s_values[q] != 0.0) values[red_position(c, local, red_of(c, scol))] -= coef * c->s_values[q];
            }
          }
        }
        c->coef_ptr[i + 1] = static_cast<int64_t>(c->coef_pair.size());
      }
    }
  } catch (...) {
    status = status_from_exception(SK_ERR_INTERNAL, "stickslip.condense assembly", std::current_exception());
  }
  status = agree(c->comm, status, "stickslip.condense assembly");
  if (status != SK_OK) return status;
  return sk_linsys_assemble(c->reduced);
}

namespace {

// The reduced right-hand side, the reduced solve (fresh or again) and the recovery of the multipliers.
sk_status solve_reduced(sk_condenser *c, const double *b, double *x, sk_linear_report *report, bool again) {
  // b at the paired rows, gathered
  size_t k = 0;
  for (int row : c->s_sorted)
    if (row >= c->first_row && row < c->first_row + c->n_owned) c->b_send[k++] = b[row - c->first_row];
  MPI_Allgatherv(c->b_send.data(), static_cast<int>(k), MPI_DOUBLE, c->b_s.data(), c->b_counts.data(),
                 c->b_displs.data(), MPI_DOUBLE, c->comm);
  std::fill(c->b_red.begin(), c->b_red.end(), 0.0);
  for (int i = 0; i < c->n_owned; ++i) {
    const int local = c->local_of_owned[i];
    if (local < 0) continue;
    double v = b[i];
    for (int64_t q = c->coef_ptr[i]; q < c->coef_ptr[i + 1]; ++q) v -= c->coef_value[q] * c->b_s[c->s_index[c->coef_pair[q]]];
    c->b_red[local] = v;
  }
  std::vector<double> b_owned(static_cast<size_t>(c->red_owned));
  SK_TRY(sk_linsys_sum_rows(c->reduced, c->b_red.data(), b_owned.data()));
  SK_TRY(again ? sk_linsys_solve_again(c->reduced, b_owned.data(), c->x_red.data(), report)
               : sk_linsys_solve(c->reduced, b_owned.data(), c->x_red.data(), report));
  for (int i = 0; i < c->n_owned; ++i) {
    const int red = red_of(c, c->first_row + i);
    x[i] = red >= 0 ? c->x_red[red - c->red_first] : 0.0;
  }
  // dz_g = D_g^-1 (b_S - A[S_g, u] du) on the last rank (it owns every multiplier), from the gathered paired rows
  for (size_t j = 0; j < c->u_send.size(); ++j) c->u_send_values[j] = x[c->u_send[j]];
  const int last = c->size - 1;
  MPI_Gatherv(c->u_send_values.data(), static_cast<int>(c->u_send.size()), MPI_DOUBLE, c->u_values.data(),
              c->u_counts.data(), c->u_displs.data(), MPI_DOUBLE, last, c->comm);
  if (c->rank != last) return SK_OK;
  auto du = [c](int col) {
    return c->u_values[static_cast<size_t>(std::lower_bound(c->u_needed.begin(), c->u_needed.end(), col) -
                                           c->u_needed.begin())];
  };
  for (size_t g = 0; g < c->group_first.size(); ++g) {
    const int first = c->group_first[g], bsize = c->block[first];
    double r[3];
    for (int si = 0; si < bsize; ++si) {
      const int idx = c->s_index[first + si];
      double v = c->b_s[idx];
      for (int64_t q = c->s_start[idx]; q < c->s_start[idx + 1]; ++q)
        if (pair_of(c->z_sorted, c->s_cols[q]) < 0) v -= c->s_values[q] * du(c->s_cols[q]);
      r[si] = v;
    }
    const double *Dinv = c->d_inverse.data() + c->d_start[g];
    for (int j = 0; j < bsize; ++j) {
      double dz = 0.0;
      for (int si = 0; si < bsize; ++si) dz += Dinv[j * bsize + si] * r[si];
      x[c->z[first + j] - c->first_row] = dz;
    }
  }
  return SK_OK;
}

}  // namespace

sk_status sk_condenser_solve(sk_condenser *c, sk_linear_system *full, const double *b, double *x,
                             sk_linear_report *report) {
  (void)full;
  try {
    return solve_reduced(c, b, x, report, false);
  } catch (...) {
    return status_from_exception(SK_ERR_INTERNAL, "stickslip.condense solve", std::current_exception());
  }
}

sk_status sk_condenser_solve_again(sk_condenser *c, sk_linear_system *full, const double *b, double *x,
                                   sk_linear_report *report) {
  (void)full;
  try {
    return solve_reduced(c, b, x, report, true);
  } catch (...) {
    return status_from_exception(SK_ERR_INTERNAL, "stickslip.condense solve", std::current_exception());
  }
}

}  // extern "C"
