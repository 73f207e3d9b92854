// stickslip — the constraint rows of a contact system and the block preconditioner built on them.
//
// With the unknowns split into nodal ones u (n_nodal, dim per node) and constraint ones l (a plugin's
// multipliers), the system and its right preconditioner are
//
//   A = [K B]      P^-1 = [K~^-1  -K~^-1 B S~^-1]      S~ = D - C diag_dim(K)^-1 B,
//       [C D]             [0             S~^-1 ]
//
// K~^-1 one application of the nodal preconditioner (MueLu / ILU), diag_dim(K) the dim x dim diagonal blocks of
// K (one per node), S~ the approximate Schur complement, factorised exactly (KLU2). With K~ = K and S~ = S the
// preconditioned operator A P^-1 = [I 0; C K^-1 I] and GMRES converges in two iterations; the approximations cost
// a few more (on the two tori 11-15 iterations against 9-10 for K alone, docs/linear-solvers.md). Inactive
// multipliers (identity rows, no coupling) are exact in S~. Multiplier rows have a zero diagonal, so nothing here
// divides by D.
//
// Parallel layout: the constraint rows all live on the last rank (linear_system.cpp), so S~ is a serial matrix
// there. The diagonal blocks and B rows of the nodes that C couples to are gathered to it once per solve (one
// MPI_Gatherv, planned per pattern: the owner names the nodes, their owners send the rows' structure).
#include <algorithm>
#include <cmath>

#include <Teuchos_DefaultMpiComm.hpp>

#include "bridge_internal.hpp"
#include "linear_system.hpp"

namespace stickslip::bridge {

struct ConstraintBlock {
  int dim = 0;
  int n_constraints = 0;
  int owner = 0;                       // the rank holding the constraint rows
  RCP<const Map> constraint_map;       // the constraint rows (all on `owner`)
  SubMatrix coupling;                  // B: this rank's nodal rows x constraint columns

  // the gather of the needed nodal rows' entries (nodal block of the row's own node, and B), planned per pattern
  std::vector<int64_t> send_positions;  // indices into owned_values, in row order
  std::vector<double> send_values;
  std::vector<int> recv_counts, recv_displs;
  std::vector<double> received;

  // on `owner`: the nodes C couples to and, per needed row, its selected entries within `received`
  std::vector<int> needed_nodes;                 // sorted
  std::vector<int64_t> needed_row_begin;         // per needed row (dim per node), into received / selected_cols
  std::vector<int> selected_cols;                // the global column of each received value
  std::vector<double> node_inverse;              // dim x dim per needed node

  // S~ on `owner`: a serial static-graph matrix and KLU2
  std::vector<int64_t> schur_row_ptr;
  std::vector<int> schur_cols;
  std::vector<double> schur_values;
  std::vector<LocalOrdinal> schur_slots;
  RCP<const Map> serial_map;
  RCP<Matrix> schur;
  RCP<DirectSolver> schur_solver;
};

namespace {

bool is_selected(int col, int node, int dim, int n_nodal) {
  return col >= n_nodal || (col >= node * dim && col < (node + 1) * dim);
}

// Inverts the dim x dim block a (row-major) into inv by Gauss-Jordan with partial pivoting. False if singular.
bool invert_block(int dim, double *a, double *inv) {
  for (int i = 0; i < dim * dim; ++i) inv[i] = (i % (dim + 1)) == 0 ? 1.0 : 0.0;
  double scale = 0;
  for (int i = 0; i < dim * dim; ++i) scale = std::max(scale, std::fabs(a[i]));
  for (int c = 0; c < dim; ++c) {
    int pivot = c;
    for (int r = c + 1; r < dim; ++r)
      if (std::fabs(a[r * dim + c]) > std::fabs(a[pivot * dim + c])) pivot = r;
    if (!(std::fabs(a[pivot * dim + c]) > 1e-14 * scale)) return false;
    for (int j = 0; j < dim; ++j) {
      std::swap(a[c * dim + j], a[pivot * dim + j]);
      std::swap(inv[c * dim + j], inv[pivot * dim + j]);
    }
    const double p = a[c * dim + c];
    for (int j = 0; j < dim; ++j) {
      a[c * dim + j] /= p;
      inv[c * dim + j] /= p;
    }
    for (int r = 0; r < dim; ++r) {
      if (r == c) continue;
      const double f = a[r * dim + c];
      for (int j = 0; j < dim; ++j) {
        a[r * dim + j] -= f * a[c * dim + j];
        inv[r * dim + j] -= f * inv[c * dim + j];
      }
    }
  }
  return true;
}

// The block upper-triangular preconditioner (see the top of this file) as a Tpetra operator on the full row map.
class ConstraintPreconditioner : public Operator {
 public:
  ConstraintPreconditioner(sk_linear_system *sys, ConstraintBlock &block, RCP<Operator> nodal)
      : sys_(sys), block_(block), nodal_(std::move(nodal)) {}
  RCP<const Map> getDomainMap() const override { return sys_->row_map; }
  RCP<const Map> getRangeMap() const override { return sys_->row_map; }
  void apply(const MultiVector &x, MultiVector &y, Teuchos::ETransp = Teuchos::NO_TRANS, Scalar alpha = 1,
             Scalar beta = 0) const override {
    const size_t nv = x.getNumVectors();
    const size_t n_nodal = sys_->nodal_map->getNodeNumElements();
    const size_t n_constraint = block_.constraint_map->getNodeNumElements();
    MultiVector xu(sys_->nodal_map, nv), t(sys_->nodal_map, nv), yu(sys_->nodal_map, nv);
    MultiVector yl(block_.constraint_map, nv);
    for (size_t v = 0; v < nv; ++v) {
      auto in = x.getData(v);
      auto u = xu.getDataNonConst(v);
      std::copy(in.getRawPtr(), in.getRawPtr() + n_nodal, u.getRawPtr());
    }
    if (sys_->rank == block_.owner && n_constraint > 0) {
      // y_l = S~^-1 x_l on the owner (serial)
      MultiVector xs(block_.serial_map, nv), ys(block_.serial_map, nv);
      for (size_t v = 0; v < nv; ++v) {
        auto in = x.getData(v);
        auto s = xs.getDataNonConst(v);
        std::copy(in.getRawPtr() + n_nodal, in.getRawPtr() + n_nodal + n_constraint, s.getRawPtr());
      }
      block_.schur_solver->solve(Teuchos::ptr(&ys), Teuchos::ptr<const MultiVector>(&xs));
      for (size_t v = 0; v < nv; ++v) {
        auto s = ys.getData(v);
        auto l = yl.getDataNonConst(v);
        std::copy(s.getRawPtr(), s.getRawPtr() + n_constraint, l.getRawPtr());
      }
    }
    block_.coupling.matrix->apply(yl, t);  // B y_l (collective)
    t.update(1.0, xu, -1.0);               // x_u - B y_l
    nodal_->apply(t, yu);                  // K~^-1 (x_u - B y_l) (collective)
    // Y = beta Y + alpha [y_u; y_l]; with beta = 0 Y is not read (callers pass it uninitialised: 0 * NaN = NaN)
    for (size_t v = 0; v < nv; ++v) {
      auto out = y.getDataNonConst(v);
      auto u = yu.getData(v);
      auto l = yl.getData(v);
      for (size_t i = 0; i < n_nodal; ++i) out[i] = alpha * u[i] + (beta == 0 ? 0.0 : beta * out[i]);
      for (size_t i = 0; i < n_constraint; ++i)
        out[n_nodal + i] = alpha * l[i] + (beta == 0 ? 0.0 : beta * out[n_nodal + i]);
    }
  }

 private:
  sk_linear_system *sys_;
  ConstraintBlock &block_;
  RCP<Operator> nodal_;
};

}  // namespace

int nodal_row_end(const sk_linear_system *sys) { return std::min(sys->row_offsets[sys->rank + 1], sys->n_nodal); }

void build_constraint_block(sk_linear_system *sys) {
  sys->constraints = std::make_unique<ConstraintBlock>();
  ConstraintBlock *block = sys->constraints.get();
  const int dim = sys->coordinate_dim, n_nodal = sys->n_nodal, n = sys->n;
  block->dim = dim;
  block->n_constraints = n - n_nodal;
  block->owner = sys->size - 1;
  const bool owner = sys->rank == block->owner;
  const int first_row = sys->first_row;
  block->constraint_map =
      rcp(new Map(static_cast<Tpetra::global_size_t>(block->n_constraints),
                  static_cast<size_t>(owner ? block->n_constraints : 0), 0, sys->tcomm));
  block->coupling = build_submatrix(sys, first_row, nodal_row_end(sys), n_nodal, n, sys->nodal_map,
                                    block->constraint_map, sys->nodal_map);

  // the nodes C couples to, from the owner's constraint rows, told to every rank
  const int constraint_local = n_nodal - first_row;  // the owner's first constraint row, local index
  if (owner) {
    std::vector<int> nodes;
    for (int i = 0; i < block->n_constraints; ++i)
      for (int64_t k = sys->row_ptr[constraint_local + i]; k < sys->row_ptr[constraint_local + i + 1]; ++k)
        if (sys->cols[k] < n_nodal) nodes.push_back(sys->cols[k] / dim);
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    block->needed_nodes = nodes;
  }
  int n_needed = static_cast<int>(block->needed_nodes.size());
  MPI_Bcast(&n_needed, 1, MPI_INT, block->owner, sys->comm);
  block->needed_nodes.resize(static_cast<size_t>(n_needed));
  MPI_Bcast(block->needed_nodes.data(), n_needed, MPI_INT, block->owner, sys->comm);

  // what each rank sends: its needed rows' selected entries, in row order (owners hold increasing row blocks, so
  // the owner receives them in global row order), with each row's entry count and columns once per pattern
  std::vector<int> row_counts, row_cols;
  for (int node : block->needed_nodes) {
    if (node * dim < first_row || node * dim >= nodal_row_end(sys)) continue;
    for (int c = 0; c < dim; ++c) {
      const int local = node * dim + c - first_row;
      int count = 0;
      for (int64_t k = sys->row_ptr[local]; k < sys->row_ptr[local + 1]; ++k) {
        if (!is_selected(sys->cols[k], node, dim, n_nodal)) continue;
        block->send_positions.push_back(k);
        row_cols.push_back(sys->cols[k]);
        ++count;
      }
      row_counts.push_back(count);
    }
  }
  block->send_values.assign(block->send_positions.size(), 0.0);
  // the owner gathers the rows' counts (dim per needed node, by rank) and columns
  std::vector<int> rows_per_rank(sys->size, 0), row_displs(sys->size, 0);
  for (int node : block->needed_nodes)
    rows_per_rank[static_cast<int>(std::upper_bound(sys->row_offsets.begin(), sys->row_offsets.end(), node * dim) -
                                   sys->row_offsets.begin()) - 1] += dim;
  for (int r = 1; r < sys->size; ++r) row_displs[r] = row_displs[r - 1] + rows_per_rank[r - 1];
  std::vector<int> all_row_counts(owner ? static_cast<size_t>(n_needed) * dim : 0);
  MPI_Gatherv(row_counts.data(), static_cast<int>(row_counts.size()), MPI_INT, all_row_counts.data(),
              rows_per_rank.data(), row_displs.data(), MPI_INT, block->owner, sys->comm);
  block->recv_counts.assign(sys->size, 0);
  block->recv_displs.assign(sys->size, 0);
  if (owner) {
    for (int r = 0; r < sys->size; ++r)
      for (int k = row_displs[r]; k < row_displs[r] + rows_per_rank[r]; ++k) block->recv_counts[r] += all_row_counts[k];
    for (int r = 1; r < sys->size; ++r) block->recv_displs[r] = block->recv_displs[r - 1] + block->recv_counts[r - 1];
    block->needed_row_begin.assign(all_row_counts.size() + 1, 0);
    for (size_t k = 0; k < all_row_counts.size(); ++k)
      block->needed_row_begin[k + 1] = block->needed_row_begin[k] + all_row_counts[k];
    block->selected_cols.assign(static_cast<size_t>(block->needed_row_begin.back()), 0);
  }
  MPI_Gatherv(row_cols.data(), static_cast<int>(row_cols.size()), MPI_INT, block->selected_cols.data(),
              block->recv_counts.data(), block->recv_displs.data(), MPI_INT, block->owner, sys->comm);
  if (!owner) return;
  block->received.assign(block->selected_cols.size(), 0.0);
  block->node_inverse.assign(block->needed_nodes.size() * static_cast<size_t>(dim * dim), 0.0);

  // the pattern of S~: D's, and every (i, l) reached through C_i (node a) and B's rows of node a
  // Each column enters a row once (seen[] holds the row that took it) and each node once per row (its unknowns are
  // adjacent columns): pushing every reach and sorting the repeats cost 18 % of a 3D frictional mortar run.
  const int nl = block->n_constraints;
  std::vector<std::vector<int>> rows(static_cast<size_t>(nl));
  std::vector<int> seen(static_cast<size_t>(nl), -1);
  for (int i = 0; i < nl; ++i) {
    auto &cols = rows[i];
    const auto take = [&](int c) {
      if (seen[c] == i) return;
      seen[c] = i;
      cols.push_back(c);
    };
    int last_node = -1;
    for (int64_t k = sys->row_ptr[constraint_local + i]; k < sys->row_ptr[constraint_local + i + 1]; ++k) {
      const int col = sys->cols[k];
      if (col >= n_nodal) {
        take(col - n_nodal);
        continue;
      }
      if (col / dim == last_node) continue;
      last_node = col / dim;
      const size_t a = static_cast<size_t>(
          std::lower_bound(block->needed_nodes.begin(), block->needed_nodes.end(), last_node) -
          block->needed_nodes.begin());
      const int64_t begin = block->needed_row_begin[a * dim], end = block->needed_row_begin[(a + 1) * dim];
      for (int64_t e = begin; e < end; ++e)
        if (block->selected_cols[e] >= n_nodal) take(block->selected_cols[e] - n_nodal);
    }
    take(i);  // the diagonal, stored even when zero: KLU2 pivots on the structure
    std::sort(cols.begin(), cols.end());
  }
  block->schur_row_ptr.assign(static_cast<size_t>(nl) + 1, 0);
  for (int i = 0; i < nl; ++i) {
    block->schur_cols.insert(block->schur_cols.end(), rows[i].begin(), rows[i].end());
    block->schur_row_ptr[i + 1] = static_cast<int64_t>(block->schur_cols.size());
  }
  block->schur_values.assign(block->schur_cols.size(), 0.0);
  block->serial_map = rcp(new Map(static_cast<Tpetra::global_size_t>(nl), 0,
                                  rcp(new Teuchos::MpiComm<int>(MPI_COMM_SELF))));
  block->schur = build_matrix(block->serial_map, block->serial_map, block->schur_row_ptr, block->schur_cols, 0,
                              block->schur_slots);
}

void release_constraint_block(sk_linear_system *sys) { sys->constraints.reset(); }

sk_status update_constraint_block(sk_linear_system *sys, ConstraintBlock &block) {
  refill_submatrix(sys, block.coupling);
  for (size_t e = 0; e < block.send_positions.size(); ++e) block.send_values[e] = sys->owned_values[block.send_positions[e]];
  MPI_Gatherv(block.send_values.data(), static_cast<int>(block.send_values.size()), MPI_DOUBLE, block.received.data(),
              block.recv_counts.data(), block.recv_displs.data(), MPI_DOUBLE, block.owner, sys->comm);
  sk_status status = SK_OK;
  if (sys->rank == block.owner) {
    const int dim = block.dim, n_nodal = sys->n_nodal;
    const int constraint_local = n_nodal - sys->first_row;
    // diag_dim(K)^-1 of every needed node
    for (size_t a = 0; a < block.needed_nodes.size() && status == SK_OK; ++a) {
      double k_aa[9] = {0};
      const int node = block.needed_nodes[a];
      for (int c = 0; c < dim; ++c)
        for (int64_t e = block.needed_row_begin[a * dim + c]; e < block.needed_row_begin[a * dim + c + 1]; ++e)
          if (block.selected_cols[e] < n_nodal) k_aa[c * dim + block.selected_cols[e] - node * dim] = block.received[e];
      if (!invert_block(dim, k_aa, &block.node_inverse[a * dim * dim]))
        status = sk_error_set(SK_ERR_LINEAR_SOLVER, "constraint block: singular %d x %d diagonal block of node %d",
                              dim, dim, node);
    }
    // S~ = D - C diag_dim(K)^-1 B, row by row
    auto add = [&block](int i, int l, double value) {
      const auto begin = block.schur_cols.begin() + block.schur_row_ptr[i];
      const auto end = block.schur_cols.begin() + block.schur_row_ptr[i + 1];
      block.schur_values[static_cast<size_t>(std::lower_bound(begin, end, l) - block.schur_cols.begin())] += value;
    };
    std::fill(block.schur_values.begin(), block.schur_values.end(), 0.0);
    for (int i = 0; i < block.n_constraints && status == SK_OK; ++i) {
      int64_t k = sys->row_ptr[constraint_local + i];
      const int64_t end = sys->row_ptr[constraint_local + i + 1];
      while (k < end) {
        const int col = sys->cols[k];
        const double c_value = sys->owned_values[k];
        if (col >= n_nodal) {
          add(i, col - n_nodal, c_value);
          ++k;
          continue;
        }
        // C_i restricted to node a (its entries are consecutive: columns sorted, a node's unknowns adjacent)
        const int node = col / dim;
        double c_a[3] = {0, 0, 0};
        for (; k < end && sys->cols[k] < n_nodal && sys->cols[k] / dim == node; ++k)
          c_a[sys->cols[k] - node * dim] = sys->owned_values[k];
        const size_t a = static_cast<size_t>(
            std::lower_bound(block.needed_nodes.begin(), block.needed_nodes.end(), node) - block.needed_nodes.begin());
        const double *inverse = &block.node_inverse[a * dim * dim];
        for (int m = 0; m < dim; ++m) {
          double t = 0;  // (c_a K_aa^-1)_m
          for (int c = 0; c < dim; ++c) t += c_a[c] * inverse[c * dim + m];
          if (t == 0) continue;
          for (int64_t e = block.needed_row_begin[a * dim + m]; e < block.needed_row_begin[a * dim + m + 1]; ++e)
            if (block.selected_cols[e] >= n_nodal) add(i, block.selected_cols[e] - n_nodal, -t * block.received[e]);
        }
      }
    }
    if (status == SK_OK) {
      try {
        replace_values(*block.schur, block.schur_row_ptr, 0, block.n_constraints, block.schur_values.data(),
                       block.schur_slots);
        if (block.schur_solver.is_null()) {
          block.schur_solver = Amesos2::create<Matrix, MultiVector>("KLU2", block.schur);
          block.schur_solver->symbolicFactorization();
        }
        block.schur_solver->numericFactorization();
      } catch (...) {
        block.schur_solver = Teuchos::null;
        status = status_from_exception(SK_ERR_LINEAR_SOLVER, "constraint block: Schur complement (singular?)",
                                       std::current_exception());
      }
    }
  }
  return agree(sys->comm, status, "constraint block");
}

RCP<Operator> constraint_preconditioner(sk_linear_system *sys, ConstraintBlock &block,
                                        const RCP<Operator> &nodal_preconditioner) {
  return rcp(new ConstraintPreconditioner(sys, block, nodal_preconditioner));
}

}  // namespace stickslip::bridge

sk_linear_system::sk_linear_system() = default;
sk_linear_system::~sk_linear_system() = default;
