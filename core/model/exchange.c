/* Owned + ghost exchanges (exchange.h). The plan is made with one all-to-all of counts and one of ids (set-up only);
 * each use is a set of nonblocking point-to-point messages between neighbours, so its cost follows the number of
 * ghosts, not the number of ranks. */
#include "exchange.h"

#include <stdlib.h>
#include <string.h>

static sk_status no_memory(int64_t count) {
  return sk_error_set(SK_ERR_NOMEM, "out of memory for the ghost exchange (%lld entries)", (long long)count);
}

void sk_exchange_free(sk_exchange *x) {
  if (!x) return;
  free(x->send_rank);
  free(x->send_ptr);
  free(x->send_index);
  free(x->recv_rank);
  free(x->recv_ptr);
  free(x->recv_index);
  free(x->send_buffer);
  free(x->recv_buffer);
  free(x->requests);
  const int64_t bytes = x->bytes_sent;
  memset(x, 0, sizeof *x);
  x->bytes_sent = bytes;
}

sk_status sk_exchange_plan(sk_exchange *x, MPI_Comm comm, int64_t n_ghosts, const int64_t *ghost_local,
                           const int64_t *ghost_gid, const int *ghost_owner, sk_exchange_lookup lookup, void *ctx) {
  sk_exchange_free(x);
  x->comm = comm;
  int size, rank;
  MPI_Comm_size(comm, &size);
  MPI_Comm_rank(comm, &rank);
  int *counts = calloc((size_t)size, sizeof(int)), *incoming = calloc((size_t)size, sizeof(int));
  int *displs = calloc((size_t)size + 1, sizeof(int)), *in_displs = calloc((size_t)size + 1, sizeof(int));
  int64_t *order = malloc(sizeof(int64_t) * (size_t)(n_ghosts > 0 ? n_ghosts : 1));
  int64_t *ids = malloc(sizeof(int64_t) * (size_t)(n_ghosts > 0 ? n_ghosts : 1));
  sk_status status = counts && incoming && displs && in_displs && order && ids ? SK_OK : no_memory(n_ghosts);
  for (int64_t g = 0; g < n_ghosts && status == SK_OK; ++g) {
    if (ghost_owner[g] < 0 || ghost_owner[g] >= size || ghost_owner[g] == rank)
      status = sk_error_set(SK_ERR_INTERNAL, "ghost exchange: entry %lld has owner %d on rank %d", (long long)ghost_gid[g],
                            ghost_owner[g], rank);
    else
      counts[ghost_owner[g]]++;
  }
  int bad = status != SK_OK;
  MPI_Allreduce(MPI_IN_PLACE, &bad, 1, MPI_INT, MPI_MAX, comm);
  if (bad) {
    free(counts), free(incoming), free(displs), free(in_displs), free(order), free(ids);
    return status != SK_OK ? status : sk_error_set(SK_ERR_INTERNAL, "ghost exchange: failed on another rank");
  }
  for (int r = 0; r < size; ++r) displs[r + 1] = displs[r] + counts[r];
  /* ghosts grouped by owner, in local order within each owner */
  int *fill = calloc((size_t)size, sizeof(int));
  if (!fill) status = no_memory(size);
  for (int64_t g = 0; g < n_ghosts && status == SK_OK; ++g) {
    const int slot = displs[ghost_owner[g]] + fill[ghost_owner[g]]++;
    order[slot] = ghost_local[g];
    ids[slot] = ghost_gid[g];
  }
  free(fill);
  MPI_Alltoall(counts, 1, MPI_INT, incoming, 1, MPI_INT, comm);
  for (int r = 0; r < size; ++r) in_displs[r + 1] = in_displs[r] + incoming[r];
  const int64_t n_in = in_displs[size];
  int64_t *wanted = malloc(sizeof(int64_t) * (size_t)(n_in > 0 ? n_in : 1));
  if (!wanted) status = no_memory(n_in);
  bad = status != SK_OK;
  MPI_Allreduce(MPI_IN_PLACE, &bad, 1, MPI_INT, MPI_MAX, comm);
  if (!bad)
    MPI_Alltoallv(ids, counts, displs, MPI_INT64_T, wanted, incoming, in_displs, MPI_INT64_T, comm);
  /* the plan: forward sends `wanted` (as owned local indices) to each requester, receives into `order` */
  int n_send = 0, n_recv = 0;
  for (int r = 0; r < size; ++r) {
    n_send += incoming[r] > 0;
    n_recv += counts[r] > 0;
  }
  if (!bad) {
    x->send_rank = malloc(sizeof(int) * (size_t)(n_send + 1));
    x->send_ptr = malloc(sizeof(int) * (size_t)(n_send + 1));
    x->send_index = malloc(sizeof(int) * (size_t)(n_in + 1));
    x->recv_rank = malloc(sizeof(int) * (size_t)(n_recv + 1));
    x->recv_ptr = malloc(sizeof(int) * (size_t)(n_recv + 1));
    x->recv_index = malloc(sizeof(int) * (size_t)(n_ghosts + 1));
    x->send_buffer = malloc(sizeof(double) * (size_t)(n_in + 1));
    x->recv_buffer = malloc(sizeof(double) * (size_t)(n_ghosts + 1));
    x->requests = malloc(sizeof(MPI_Request) * (size_t)(n_send + n_recv + 1));
    if (!x->send_rank || !x->send_ptr || !x->send_index || !x->recv_rank || !x->recv_ptr || !x->recv_index ||
        !x->send_buffer || !x->recv_buffer || !x->requests)
      status = no_memory(n_in + n_ghosts);
  }
  if (!bad && status == SK_OK) {
    x->send_ptr[0] = x->recv_ptr[0] = 0;
    for (int r = 0; r < size; ++r) {
      if (incoming[r] > 0) {
        x->send_rank[x->n_send] = r;
        for (int k = in_displs[r]; k < in_displs[r + 1] && status == SK_OK; ++k) {
          const int64_t local = lookup(ctx, wanted[k]);
          if (local < 0)
            status = sk_error_set(SK_ERR_INTERNAL, "ghost exchange: rank %d asked rank %d for entry %lld, which it "
                                  "does not own", r, rank, (long long)wanted[k]);
          x->send_index[k] = (int)local;
        }
        x->send_ptr[++x->n_send] = in_displs[r + 1];
      }
      if (counts[r] > 0) {
        x->recv_rank[x->n_recv] = r;
        for (int k = displs[r]; k < displs[r + 1]; ++k) x->recv_index[k] = (int)order[k];
        x->recv_ptr[++x->n_recv] = displs[r + 1];
      }
    }
  }
  free(counts), free(incoming), free(displs), free(in_displs), free(order), free(ids), free(wanted);
  bad = status != SK_OK;
  MPI_Allreduce(MPI_IN_PLACE, &bad, 1, MPI_INT, MPI_MAX, comm);
  if (bad) {
    sk_exchange_free(x);
    return status != SK_OK ? status : sk_error_set(SK_ERR_INTERNAL, "ghost exchange: failed on another rank");
  }
  return SK_OK;
}

/* Messages from `out` (ranges of out_ptr to out_rank) into `in` (ranges of in_ptr from in_rank). */
static void exchange(sk_exchange *x, int n_out, const int *out_rank, const int *out_ptr, const double *out, int n_in,
                     const int *in_rank, const int *in_ptr, double *in) {
  int k = 0;
  for (int j = 0; j < n_in; ++j)
    MPI_Irecv(in + in_ptr[j], in_ptr[j + 1] - in_ptr[j], MPI_DOUBLE, in_rank[j], 7, x->comm, &x->requests[k++]);
  for (int j = 0; j < n_out; ++j) {
    MPI_Isend(out + out_ptr[j], out_ptr[j + 1] - out_ptr[j], MPI_DOUBLE, out_rank[j], 7, x->comm, &x->requests[k++]);
    x->bytes_sent += (int64_t)sizeof(double) * (out_ptr[j + 1] - out_ptr[j]);
  }
  MPI_Waitall(k, x->requests, MPI_STATUSES_IGNORE);
}

void sk_exchange_forward(sk_exchange *x, double *values) {
  if (!x->send_ptr) return; /* no plan: a single rank */
  for (int k = 0; k < x->send_ptr[x->n_send]; ++k) x->send_buffer[k] = values[x->send_index[k]];
  exchange(x, x->n_send, x->send_rank, x->send_ptr, x->send_buffer, x->n_recv, x->recv_rank, x->recv_ptr,
           x->recv_buffer);
  for (int k = 0; k < x->recv_ptr[x->n_recv]; ++k) values[x->recv_index[k]] = x->recv_buffer[k];
}

void sk_exchange_reverse(sk_exchange *x, double *values) {
  if (!x->send_ptr) return;
  for (int k = 0; k < x->recv_ptr[x->n_recv]; ++k) x->recv_buffer[k] = values[x->recv_index[k]];
  exchange(x, x->n_recv, x->recv_rank, x->recv_ptr, x->recv_buffer, x->n_send, x->send_rank, x->send_ptr,
           x->send_buffer);
  for (int k = 0; k < x->send_ptr[x->n_send]; ++k) values[x->send_index[k]] += x->send_buffer[k];
}
