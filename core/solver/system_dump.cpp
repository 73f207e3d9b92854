// stickslip — STICKSLIP_DUMP_SYSTEMS=DIR: every linear solve writes its system for offline study (a debugging and
// benchmarking aid, docs/linear-solvers.md): DIR/system-NNNNN.mtx (MatrixMarket, the assembled matrix),
// DIR/system-NNNNN.rhs (b, one value per line) and DIR/meta-NNNNN.txt ("n block_size coordinate_dim
// n_coordinates", then the coordinates, one per line). STICKSLIP_DUMP_FIRST=K and
// STICKSLIP_DUMP_LAST=L write only solves K..L (counted from 0). Rank 0
// writes; the other ranks send their rows.
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
  std::vector<double> all(sys->rank == 0 ? static_cast<size_t>(sys->row_ptr[sys->n]) : 0);
  MPI_Gatherv(sys->owned_values.data(), sys->gather_counts[sys->rank], MPI_DOUBLE, all.data(),
              sys->gather_counts.data(), sys->gather_displs.data(), MPI_DOUBLE, 0, sys->comm);
  const int index = counter++;
  if (sys->rank != 0) return;
  char path[1024];
  std::snprintf(path, sizeof path, "%s/system-%05d.mtx", dir, index);
  if (FILE *f = std::fopen(path, "w")) {
    std::fprintf(f, "%%%%MatrixMarket matrix coordinate real general\n%d %d %lld\n", sys->n, sys->n,
                 static_cast<long long>(sys->row_ptr[sys->n]));
    for (int i = 0; i < sys->n; ++i)
      for (int64_t k = sys->row_ptr[i]; k < sys->row_ptr[i + 1]; ++k)
        std::fprintf(f, "%d %d %.17g\n", i + 1, sys->cols[k] + 1, all[k]);
    std::fclose(f);
  }
  std::snprintf(path, sizeof path, "%s/system-%05d.rhs", dir, index);
  if (FILE *f = std::fopen(path, "w")) {
    for (int i = 0; i < sys->n; ++i) std::fprintf(f, "%.17g\n", b[i]);
    std::fclose(f);
  }
  std::snprintf(path, sizeof path, "%s/meta-%05d.txt", dir, index);
  if (FILE *f = std::fopen(path, "w")) {
    std::fprintf(f, "%d %d %d %zu\n", sys->n, sys->block_size, sys->coordinate_dim, sys->coordinates.size());
    for (double c : sys->coordinates) std::fprintf(f, "%.17g\n", c);
    std::fclose(f);
  }
}

}  // namespace stickslip::bridge
