// Zoltan2's geometric partitioners behind a C header (zoltan2_partition.h).
#include "zoltan2_partition.h"

#include <mpi.h>

#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include <Kokkos_Core.hpp>
#include <Teuchos_DefaultMpiComm.hpp>
#include <Teuchos_ParameterList.hpp>
#include <Zoltan2_BasicVectorAdapter.hpp>
#include <Zoltan2_PartitioningProblem.hpp>

namespace {
using user_types = Zoltan2::BasicUserTypes<double, int, long long>;
using adapter = Zoltan2::BasicVectorAdapter<user_types>;
}  // namespace

extern "C" void bench_zoltan2_initialize(void) { Kokkos::initialize(); }

extern "C" void bench_zoltan2_finalize(void) { Kokkos::finalize(); }

extern "C" int bench_zoltan2_partition(const char *algorithm, int n, int dim, const double *pos,
                                       const double *weight, int n_parts, double imbalance_tolerance, int *part) {
  try {
    std::vector<long long> ids(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) ids[static_cast<size_t>(i)] = i;
    std::vector<const double *> coords, weights;
    std::vector<int> coord_strides, weight_strides;
    for (int d = 0; d < dim; ++d) {
      coords.push_back(pos + d);
      coord_strides.push_back(3);
    }
    weights.push_back(weight);
    weight_strides.push_back(1);
    adapter input(n, ids.data(), coords, coord_strides, weights, weight_strides);
    Teuchos::ParameterList params("bench_partition");
    params.set("algorithm", std::string(algorithm));
    params.set("num_global_parts", n_parts);
    params.set("imbalance_tolerance", imbalance_tolerance);
    params.set("error_check_level", std::string("no_assertions"));
    params.sublist("zoltan_parameters").set("DEBUG_LEVEL", std::string("0"));
    Zoltan2::PartitioningProblem<adapter> problem(&input, &params, MPI_COMM_SELF);
    problem.solve();
    const int *parts = problem.getSolution().getPartListView();
    for (int i = 0; i < n; ++i) part[i] = parts[i];
    return 0;
  } catch (const std::exception &e) {
    std::fprintf(stderr, "bench_partition: Zoltan2 %s: %s\n", algorithm, e.what());
    return -1;
  }
}
