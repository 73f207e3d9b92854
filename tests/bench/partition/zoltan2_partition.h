/* Zoltan2's geometric partitioners behind a C header, for bench_partition (the C++ is zoltan2_partition.cpp). */
#ifndef STICKSLIP_BENCH_ZOLTAN2_PARTITION_H
#define STICKSLIP_BENCH_ZOLTAN2_PARTITION_H

#ifdef __cplusplus
extern "C" {
#endif

/* Kokkos (which Zoltan2's algorithms use) started after MPI_Init and stopped before MPI_Finalize. */
void bench_zoltan2_initialize(void);
void bench_zoltan2_finalize(void);

/* Partitions n points (pos: 3 coordinates each, dim of them used) with weights into n_parts parts (part[i] in
 * 0 .. n_parts - 1) on this process alone (MPI_COMM_SELF), with Zoltan2's `algorithm` ("rcb": Zoltan's RCB through
 * Zoltan2; "multijagged") and its imbalance_tolerance. Returns 0, or -1 (message on stderr). */
int bench_zoltan2_partition(const char *algorithm, int n, int dim, const double *pos, const double *weight, int n_parts,
                            double imbalance_tolerance, int *part);

#ifdef __cplusplus
}
#endif

#endif
