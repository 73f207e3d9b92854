// stickslip — condensation of paired multipliers on the assembled operator (condense.h).
//
// The full operator A is summed on its owners by sk_linsys_assemble (contiguous row blocks). The paired rows S are
// then gathered to every rank (one Allgatherv per assembly: the rows of the contact slave nodes, a small part of A),
// so that each rank can
//   - form its owned rows of the reduced system: row r ← r − A[r, Z_g] D_g⁻¹ A[S_g, ·] for every group g whose
//     multipliers appear in row r, written at r's reduced position (a multiplier row at the place of its paired
//     row), then summed into the reduced system's owners by sk_linsys_assemble (each reduced row has one writer);
//   - transform its owned entries of the right-hand side the same way (one Allreduce);
//   - recover dz_g = D_g⁻¹ (b_S − A[S_g, u] du) for every group from the gathered rows, identically on every rank.
// The reduced pattern is computed once per pattern of A and set of pairs, from the replicated pattern of A.
#include "stickslip/condense.h"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <vector>

#include "bridge_internal.hpp"

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
  std::vector<int> z_pair, s_pair;         // per full unknown / row: the pair it is the z / s of, or -1
  std::vector<int> red;                    // full -> reduced index (-1 for a z)
  std::vector<int> place;                  // full row -> its row in the reduced system (-1 for a paired row)
  int n = 0, n_red = 0;

  // the full pattern the reduced one was built from
  std::vector<int64_t> full_row_ptr;
  std::vector<int> full_cols;

  // the reduced pattern (replicated)
  std::vector<int64_t> row_ptr;
  std::vector<int> cols;

  // gathered paired rows: s rows in increasing order, their values after each assembly
  std::vector<int> s_sorted;               // the paired rows, ascending
  std::vector<int> s_index;                // per pair: index of its row in s_sorted
  std::vector<int64_t> s_start;            // per s_sorted row: offset of its values in s_values
  std::vector<double> s_values;
  std::vector<int> gather_counts, gather_displs;
  std::vector<double> send;
  std::vector<double> d_inverse;           // per group: block x block, D_g^-1 (rows: z of the group, cols: s)
  std::vector<int64_t> d_start;            // per group: offset into d_inverse

  // per owned full row: coefficients c_s of the paired rows subtracted from it (for the right-hand side)
  std::vector<int64_t> coef_ptr;
  std::vector<int> coef_pair;
  std::vector<double> coef_value;

  std::vector<double> b_red, x_red, work;
};

namespace {

int64_t position(const std::vector<int64_t> &row_ptr, const std::vector<int> &cols, int row, int col) {
  const auto begin = cols.begin() + row_ptr[row], end = cols.begin() + row_ptr[row + 1];
  const auto hit = std::lower_bound(begin, end, col);
  return hit != end && *hit == col ? hit - cols.begin() : -1;
}

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
sk_status gather_pairs(sk_condenser *c, int64_t n_pairs, const int64_t *z, const int64_t *row, const int *block,
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
  return SK_OK;
}

// The reduced numbering, groups and pattern from the full pattern and the pairs.
sk_status build(sk_condenser *c, const system_rows &full) {
  const int n = full.n, n_pairs = static_cast<int>(c->z.size());
  c->n = n;
  c->z_pair.assign(n, -1);
  c->s_pair.assign(n, -1);
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
      if (c->z[p] < 0 || c->z[p] >= n || c->s[p] < 0 || c->s[p] >= n)
        return sk_error_set(SK_ERR_PLUGIN, "stickslip.condense: pair %d (%d, %d) outside the system of %d", p,
                            c->z[p], c->s[p], n);
      if (c->z_pair[c->z[p]] >= 0 || c->s_pair[c->s[p]] >= 0 || c->s_pair[c->z[p]] >= 0 || c->z_pair[c->s[p]] >= 0)
        return sk_error_set(SK_ERR_PLUGIN, "stickslip.condense: unknown %d or row %d is paired twice", c->z[p],
                            c->s[p]);
      c->z_pair[c->z[p]] = p;
      c->s_pair[c->s[p]] = p;
      c->group_of[p] = static_cast<int>(c->group_first.size());
    }
    c->group_first.push_back(k);
    k += b;
  }
  c->red.assign(n, -1);
  int next = 0;
  for (int i = 0; i < n; ++i)
    if (c->z_pair[i] < 0) c->red[i] = next++;
  c->n_red = next;
  c->place.assign(n, -1);
  for (int r = 0; r < n; ++r) {
    if (c->s_pair[r] >= 0) continue;  // a paired row: replaced by its multiplier's row
    c->place[r] = c->z_pair[r] >= 0 ? c->red[c->s[c->z_pair[r]]] : c->red[r];
  }
  // paired rows, ascending, and where each pair's row sits among them
  c->s_sorted.assign(c->s.begin(), c->s.end());
  std::sort(c->s_sorted.begin(), c->s_sorted.end());
  c->s_index.assign(n_pairs, 0);
  for (int p = 0; p < n_pairs; ++p)
    c->s_index[p] = static_cast<int>(std::lower_bound(c->s_sorted.begin(), c->s_sorted.end(), c->s[p]) -
                                      c->s_sorted.begin());
  // reduced pattern: each non-paired row's u columns, plus the u columns of the paired rows of every group whose
  // multipliers it touches
  std::vector<std::vector<int>> rows(c->n_red);
  std::vector<char> group_seen(c->group_first.size(), 0);
  std::vector<int> touched;
  for (int r = 0; r < n; ++r) {
    const int target = c->place[r];
    if (target < 0) continue;
    std::vector<int> &out = rows[target];
    touched.clear();
    for (int64_t k = full.row_ptr[r]; k < full.row_ptr[r + 1]; ++k) {
      const int col = full.cols[k];
      if (c->z_pair[col] < 0) {
        out.push_back(c->red[col]);
      } else {
        const int g = c->group_of[c->z_pair[col]];
        if (!group_seen[g]) {
          group_seen[g] = 1;
          touched.push_back(g);
        }
      }
    }
    for (int g : touched) {
      group_seen[g] = 0;
      const int first = c->group_first[g], b = c->block[first];
      for (int j = 0; j < b; ++j) {
        const int srow = c->s[first + j];
        for (int64_t k = full.row_ptr[srow]; k < full.row_ptr[srow + 1]; ++k)
          if (c->z_pair[full.cols[k]] < 0) out.push_back(c->red[full.cols[k]]);
      }
    }
    out.push_back(target);
  }
  c->row_ptr.assign(c->n_red + 1, 0);
  c->cols.clear();
  for (int r = 0; r < c->n_red; ++r) {
    std::vector<int> &out = rows[r];
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    c->cols.insert(c->cols.end(), out.begin(), out.end());
    c->row_ptr[r + 1] = static_cast<int64_t>(c->cols.size());
  }
  // this rank writes the reduced rows of its owned full rows
  std::vector<int> local;
  for (int r = full.first_row; r < full.first_row + full.n_owned; ++r)
    if (c->place[r] >= 0) local.push_back(c->place[r]);
  std::sort(local.begin(), local.end());
  // gather plan of the paired rows' values (each rank sends its owned paired rows, ascending)
  c->s_start.assign(c->s_sorted.size() + 1, 0);
  for (size_t i = 0; i < c->s_sorted.size(); ++i)
    c->s_start[i + 1] = c->s_start[i] + (full.row_ptr[c->s_sorted[i] + 1] - full.row_ptr[c->s_sorted[i]]);
  c->s_values.assign(static_cast<size_t>(c->s_start.back()), 0.0);
  c->gather_counts.assign(c->size, 0);
  c->gather_displs.assign(c->size, 0);
  for (size_t i = 0; i < c->s_sorted.size(); ++i) {
    const int owner = static_cast<int>(std::upper_bound(full.row_offsets, full.row_offsets + c->size + 1,
                                                        c->s_sorted[i]) - full.row_offsets) - 1;
    c->gather_counts[owner] += static_cast<int>(c->s_start[i + 1] - c->s_start[i]);
  }
  for (int r = 1; r < c->size; ++r) c->gather_displs[r] = c->gather_displs[r - 1] + c->gather_counts[r - 1];
  c->send.assign(static_cast<size_t>(c->gather_counts[c->rank]), 0.0);
  c->d_start.assign(c->group_first.size() + 1, 0);
  for (size_t g = 0; g < c->group_first.size(); ++g) {
    const int b = c->block[c->group_first[g]];
    c->d_start[g + 1] = c->d_start[g] + b * b;
  }
  c->d_inverse.assign(static_cast<size_t>(c->d_start.back()), 0.0);
  c->b_red.assign(c->n_red, 0.0);
  c->x_red.assign(c->n_red, 0.0);
  c->work.assign(n, 0.0);
  c->full_row_ptr.assign(full.row_ptr, full.row_ptr + n + 1);
  c->full_cols.assign(full.cols, full.cols + full.row_ptr[n]);
  return sk_linsys_set_pattern(c->reduced, c->n_red, c->row_ptr.data(), c->cols.data(), static_cast<int>(local.size()),
                               local.data());
}

// The value A[s_sorted[i], col] from the gathered paired rows (0 when absent).
double s_value(const sk_condenser *c, int i, int col) {
  const int row = c->s_sorted[i];
  const int64_t p = position(c->full_row_ptr, c->full_cols, row, col);
  return p < 0 ? 0.0 : c->s_values[c->s_start[i] + (p - c->full_row_ptr[row])];
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
    SK_TRY(gather_pairs(c, n_pairs, z, row, block, all_z, all_s, all_block));
    const system_rows rows = rows_of(full);
    const bool same = all_z == c->z && all_s == c->s && all_block == c->block && rows.n == c->n &&
                      c->full_row_ptr.size() == static_cast<size_t>(rows.n + 1) &&
                      std::equal(c->full_row_ptr.begin(), c->full_row_ptr.end(), rows.row_ptr) &&
                      std::equal(c->full_cols.begin(), c->full_cols.end(), rows.cols);
    if (same) return SK_OK;
    c->z = all_z;
    c->s = all_s;
    c->block = all_block;
    status = build(c, rows);
  } catch (...) {
    status = status_from_exception(SK_ERR_INTERNAL, "sk_condenser_set_pairs", std::current_exception());
  }
  return agree(c->comm, status, "stickslip.condense");
}

sk_status sk_condenser_assemble(sk_condenser *c, sk_linear_system *full) {
  SK_TRY(sk_linsys_assemble(full));
  sk_status status = SK_OK;
  try {
    const system_rows rows = rows_of(full);
    // gather the paired rows
    size_t k = 0;
    for (size_t i = 0; i < c->s_sorted.size(); ++i) {
      const int r = c->s_sorted[i];
      if (r < rows.first_row || r >= rows.first_row + rows.n_owned) continue;
      const double *begin = rows.owned_values + (rows.row_ptr[r] - rows.owned_value_begin);
      const int64_t len = rows.row_ptr[r + 1] - rows.row_ptr[r];
      std::copy(begin, begin + len, c->send.data() + k);
      k += static_cast<size_t>(len);
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
      const int r = c->s_sorted[i], g = c->group_of[c->s_pair[r]];
      for (int64_t p = c->full_row_ptr[r]; p < c->full_row_ptr[r + 1]; ++p) {
        const int col = c->full_cols[p];
        if (c->z_pair[col] >= 0 && c->group_of[c->z_pair[col]] != g && c->s_values[c->s_start[i] + p - c->full_row_ptr[r]] != 0.0)
          status = sk_error_set(SK_ERR_PLUGIN, "stickslip.condense: multiplier %d appears in paired row %d of "
                                "another group: D is not block diagonal (a standard, not dual, mortar basis?)", col, r);
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
        const int r = rows.first_row + i, target = c->place[r];
        c->coef_ptr[i + 1] = c->coef_ptr[i];
        if (target < 0) continue;
        const double *row_values = rows.owned_values + (rows.row_ptr[r] - rows.owned_value_begin);
        for (int64_t p = rows.row_ptr[r]; p < rows.row_ptr[r + 1]; ++p) {
          const int col = rows.cols[p];
          const double a = row_values[p - rows.row_ptr[r]];
          if (c->z_pair[col] < 0) {
            if (a != 0.0) values[position(c->row_ptr, c->cols, target, c->red[col])] += a;
            continue;
          }
          if (a == 0.0) continue;
          // c_s = A[r, z_j] (D_g^-1)[j][s] for the paired rows s of z's group
          const int pz = c->z_pair[col], g = c->group_of[pz], first = c->group_first[g], b = c->block[first];
          const int j = pz - first;
          const double *Dinv = c->d_inverse.data() + c->d_start[g];
          for (int si = 0; si < b; ++si) {
            const double coef = a * Dinv[j * b + si];
            if (coef == 0.0) continue;
            c->coef_pair.push_back(first + si);
            c->coef_value.push_back(coef);
            const int idx = c->s_index[first + si], srow = c->s_sorted[idx];
            for (int64_t q = c->full_row_ptr[srow]; q < c->full_row_ptr[srow + 1]; ++q) {
              const int scol = c->full_cols[q];
              if (c->z_pair[scol] >= 0) continue;
              const double sv = c->s_values[c->s_start[idx] + q - c->full_row_ptr[srow]];
              if (sv != 0.0) values[position(c->row_ptr, c->cols, target, c->red[scol])] -= coef * sv;
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
sk_status solve_reduced(sk_condenser *c, sk_linear_system *full, const double *b, double *x, sk_linear_report *report,
                        bool again) {
  const system_rows rows = rows_of(full);
  std::fill(c->b_red.begin(), c->b_red.end(), 0.0);
  for (int i = 0; i < rows.n_owned; ++i) {
    const int r = rows.first_row + i, target = c->place[r];
    if (target < 0) continue;
    double v = b[r];
    for (int64_t k = c->coef_ptr[i]; k < c->coef_ptr[i + 1]; ++k) v -= c->coef_value[k] * b[c->s[c->coef_pair[k]]];
    c->b_red[target] = v;
  }
  MPI_Allreduce(MPI_IN_PLACE, c->b_red.data(), c->n_red, MPI_DOUBLE, MPI_SUM, c->comm);
  SK_TRY(again ? sk_linsys_solve_again(c->reduced, c->b_red.data(), c->x_red.data(), report)
               : sk_linsys_solve(c->reduced, c->b_red.data(), c->x_red.data(), report));
  for (int i = 0; i < c->n; ++i) x[i] = c->red[i] >= 0 ? c->x_red[c->red[i]] : 0.0;
  // dz_g = D_g^-1 (b_S - A[S_g, u] du) from the gathered paired rows (the same on every rank)
  for (size_t g = 0; g < c->group_first.size(); ++g) {
    const int first = c->group_first[g], bsize = c->block[first];
    double r[3];
    for (int si = 0; si < bsize; ++si) {
      const int idx = c->s_index[first + si], srow = c->s_sorted[idx];
      double v = b[srow];
      for (int64_t q = c->full_row_ptr[srow]; q < c->full_row_ptr[srow + 1]; ++q) {
        const int col = c->full_cols[q];
        if (c->z_pair[col] < 0) v -= c->s_values[c->s_start[idx] + q - c->full_row_ptr[srow]] * x[col];
      }
      r[si] = v;
    }
    const double *Dinv = c->d_inverse.data() + c->d_start[g];
    for (int j = 0; j < bsize; ++j) {
      double dz = 0.0;
      for (int si = 0; si < bsize; ++si) dz += Dinv[j * bsize + si] * r[si];
      x[c->z[first + j]] = dz;
    }
  }
  return SK_OK;
}

}  // namespace

sk_status sk_condenser_solve(sk_condenser *c, sk_linear_system *full, const double *b, double *x,
                             sk_linear_report *report) {
  try {
    return solve_reduced(c, full, b, x, report, false);
  } catch (...) {
    return status_from_exception(SK_ERR_INTERNAL, "stickslip.condense solve", std::current_exception());
  }
}

sk_status sk_condenser_solve_again(sk_condenser *c, sk_linear_system *full, const double *b, double *x,
                                   sk_linear_report *report) {
  try {
    return solve_reduced(c, full, b, x, report, true);
  } catch (...) {
    return status_from_exception(SK_ERR_INTERNAL, "stickslip.condense solve", std::current_exception());
  }
}

}  // extern "C"
