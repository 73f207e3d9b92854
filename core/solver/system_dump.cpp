// stickslip — STICKSLIP_DUMP_SYSTEMS=DIR: every linear solve writes its system for offline study (a debugging and
// benchmarking aid, docs/linear-solvers.md): DIR/system-NNNNN.mtx (MatrixMarket, the assembled matrix),
// DIR/system-NNNNN.rhs (b, one value per line) and DIR/meta-NNNNN.txt ("n block_size coordinate_dim
// n_coordinates", then the coordinates, one per line). STICKSLIP_DUMP_FIRST=K and
// STICKSLIP_DUMP_LAST=L write only solves K..L (counted from 0). Rank 0
// writes; the other ranks send their rows (in the global row numbering of the bridge's layout).
#include <cstdio>
#include <cstdlib>

#include "linear_system.hpp"

namespace stickslip::bridge {

void dump_system(sk_linear_system *sys, const double *b) {
  static int counter = 0;
  const char *dir = std::getenv("STICKSLIP_DUMP_SYSTEMS");
  if (!dir || !*dir) return;
  const char *first = std::getenv("STICKSLIP_DUMP_FIRST"), *last = std::getenv("STICKSLIP_DUMP_LAST");
  if ((first && counter < std::atoi(first)) || (last && counter > std::atoi(last))) {
    ++counter;
    return;
  }
  gather_to_root(sys);
  std::vector<double> whole_b(sys->rank == 0 ? static_cast<size_t>(sys->n) : 0);
  gather_vector(sys, b, whole_b.data());
  std::vector<double> coordinates;  // all ranks' owned nodes, in row order
  {
    std::vector<int> counts(sys->size), displs(sys->size, 0);
    const int mine = static_cast<int>(sys->coordinates.size());
    MPI_Gather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, sys->comm);
    for (int r = 1; r < sys->size; ++r) displs[r] = displs[r - 1] + counts[r - 1];
    if (sys->rank == 0) coordinates.resize(static_cast<size_t>(displs[sys->size - 1] + counts[sys->size - 1]));
    MPI_Gatherv(sys->coordinates.data(), mine, MPI_DOUBLE, coordinates.data(), counts.data(), displs.data(),
                MPI_DOUBLE, 0, sys->comm);
  }
  const int index = counter++;
  if (sys->rank != 0) return;
  const std::vector<int64_t> &row_ptr = sys->size > 1 ? sys->full_row_ptr : sys->row_ptr;
  const std::vector<int> &cols = sys->size > 1 ? sys->full_cols : sys->cols;
  const std::vector<double> &all = sys->size > 1 ? sys->gathered_values : sys->owned_values;
  char path[1024];
  std::snprintf(path, sizeof path, "%s/system-%05d.mtx", dir, index);
  if (FILE *f = std::fopen(path, "w")) {
    std::fprintf(f, "%%%%MatrixMarket matrix coordinate real general\n%d %d %lld\n", sys->n, sys->n,
                 static_cast<long long>(row_ptr[sys->n]));
    for (int i = 0; i < sys->n; ++i)
      for (int64_t k = row_ptr[i]; k < row_ptr[i + 1]; ++k) std::fprintf(f, "%d %d %.17g\n", i + 1, cols[k] + 1, all[k]);
    std::fclose(f);
  }
  std::snprintf(path, sizeof path, "%s/system-%05d.rhs", dir, index);
  if (FILE *f = std::fopen(path, "w")) {
    for (int i = 0; i < sys->n; ++i) std::fprintf(f, "%.17g\n", whole_b[i]);
    std::fclose(f);
  }
  std::snprintf(path, sizeof path, "%s/meta-%05d.txt", dir, index);
  if (FILE *f = std::fopen(path, "w")) {
    std::fprintf(f, "%d %d %d %zu\n", sys->n, sys->block_size, sys->coordinate_dim, coordinates.size());
    for (double c : coordinates) std::fprintf(f, "%.17g\n", c);
    std::fclose(f);
  }
}

}  // namespace stickslip::bridge
