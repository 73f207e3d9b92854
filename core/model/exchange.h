/* Owned + ghost exchanges over one rank's local vector (internal to the simulation layer): which local entries are
 * ghosts of which other ranks' owned entries, planned once per layout (docs/design.md, "Exchanges"); per use only
 * point-to-point messages between neighbours:
 *   forward   the owners' values copied into their ghosts (an iterate, an update),
 *   reverse   the ghosts' values added into their owners (a residual assembled over owned and ghost rows). */
#ifndef STICKSLIP_EXCHANGE_H
#define STICKSLIP_EXCHANGE_H

#include <mpi.h>
#include <stdint.h>

#include "stickslip/error.h"

typedef struct {
  MPI_Comm comm;
  int n_send, n_recv;      /* neighbours this rank sends owned values to / receives ghost values from (forward) */
  int *send_rank, *send_ptr, *send_index; /* per neighbour: a range of send_index (local owned entries) */
  int *recv_rank, *recv_ptr, *recv_index; /* per neighbour: a range of recv_index (local ghost entries) */
  double *send_buffer, *recv_buffer;
  MPI_Request *requests;
  int64_t bytes_sent;      /* by forward and reverse so far (the scaling bench) */
} sk_exchange;

/* The owner's local index of a global id it owns, or -1. */
typedef int64_t (*sk_exchange_lookup)(void *ctx, int64_t gid);

/* Plans the exchange (collective): this rank's n_ghosts ghost entries at local indices ghost_local, with their
 * global ids and owner ranks; each owner finds its entries with `lookup`. An id its owner does not own is an internal
 * error. Replaces a previous plan. */
sk_status sk_exchange_plan(sk_exchange *x, MPI_Comm comm, int64_t n_ghosts, const int64_t *ghost_local,
                           const int64_t *ghost_gid, const int *ghost_owner, sk_exchange_lookup lookup, void *ctx);
/* values[ghost] = the owner's values[owned] (collective). */
void sk_exchange_forward(sk_exchange *x, double *values);
/* values[owned] += every ghost's values[ghost] (collective; ghosts keep their values). */
void sk_exchange_reverse(sk_exchange *x, double *values);
void sk_exchange_free(sk_exchange *x);

#endif
