/* stickslip — condensation on the assembled operator (core/solver/condense.cpp, behind this C header): the
 * elimination of paired multipliers that the dual-mortar method needs (plugin.h: stickslip.condense.v1), done where
 * the summed rows exist — 4C's run_pre_apply_jacobian_inverse, MOOSE's VariableCondensationPreconditioner.
 *
 * Pairs (z_k, s_k) of unknowns of the full system A, grouped in blocks of 1..3 with D_g = A[S_g, Z_g] invertible and
 * the z of a group appearing in the rows S of no other group. The condenser reads the full operator's summed rows,
 * forms the displacement-only system
 *     row r (neither paired row nor multiplier):  A[r, u] - A[r, Z_g] D_g^-1 A[S_g, u]       (summed over groups)
 *     the multiplier rows of group g go to the places of the rows S_g, transformed the same way
 * solves it, and recovers dz_g = D_g^-1 (b_S - A[S_g, u] du). The result equals the saddle-point solve to round-off.
 * The multipliers must be constraint unknowns of the full system, the paired rows nodal ones. All calls are
 * collective; vectors are the owned rows' parts of the full system. */
#ifndef STICKSLIP_CONDENSE_H
#define STICKSLIP_CONDENSE_H

#include <mpi.h>
#include <stdint.h>

#include "stickslip/bridge.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sk_condenser sk_condenser;

sk_status sk_condenser_create(MPI_Comm comm, const sk_linear_options *options, sk_condenser **condenser);
void sk_condenser_destroy(sk_condenser *condenser);
/* The pairs of an attempt: this rank's n_pairs (z[k], row[k]) with their group sizes block[k] (consecutive members of
 * a group are adjacent), in the numbering of `full`, whose pattern must be set. Gathers every rank's pairs and
 * rebuilds the reduced pattern when the pairs or the full pattern changed. */
sk_status sk_condenser_set_pairs(sk_condenser *condenser, sk_linear_system *full, int64_t n_pairs, const int64_t *z,
                                 const int64_t *row, const int *block);
/* Sums the full operator's contributions (sk_linsys_assemble of `full`), reads D, and assembles the reduced system. */
sk_status sk_condenser_assemble(sk_condenser *condenser, sk_linear_system *full);
/* Solves A x = b through the reduced system; b, x over the full system's owned rows. */
sk_status sk_condenser_solve(sk_condenser *condenser, sk_linear_system *full, const double *b, double *x,
                             sk_linear_report *report);
/* The same with the current factorisation of the reduced system (another right-hand side). */
sk_status sk_condenser_solve_again(sk_condenser *condenser, sk_linear_system *full, const double *b, double *x,
                                   sk_linear_report *report);
/* The reduced system's size, over all ranks (for tests and summaries). */
int sk_condenser_size(const sk_condenser *condenser);
/* The reduced system itself (its solver and tolerance are set there: sk_linsys_set_solver, sk_linsys_set_tolerance). */
sk_linear_system *sk_condenser_reduced(sk_condenser *condenser);

/* Solves A x = b again with the factorisation (or preconditioner) of the last sk_linsys_solve of `sys`, with no
 * numeric refactorisation (linear_system.cpp). */
sk_status sk_linsys_solve_again(sk_linear_system *sys, const double *b, double *x, sk_linear_report *report);

#ifdef __cplusplus
}
#endif
#endif
