/* The contact partition in a checkpoint (checkpoint_partition.h): contact-partition.bin, written by rank 0 (the
 * owners and weights are whole-surface arrays, the same on every rank):
 *   magic "SKCPART1", int32 ranks, int32 rebalance pending, int32 pairs; per pair with a contact partition: int32
 *   name length, name, int32 slave nodes n, int32 slave faces nf, int32 owners[n + nf], double weights[n + nf];
 *   then the FNV-1a checksum of all that and the end mark. */
#include "checkpoint_partition.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../model/contact_partition.h"
#include "stickslip/files.h"
#include "checkpoint_format.h"

static const char MAGIC[8] = {'S', 'K', 'C', 'P', 'A', 'R', 'T', '1'};
static const char NAME[] = "contact-partition.bin";

const char *sk_checkpoint_partition_file(void) { return NAME; }

sk_status sk_checkpoint_partition_bytes(const sk_system *sys, sk_byte_buffer *b) {
  const sk_model *m = sys->model;
  int32_t head[3] = {sys->n_ranks, sys->contact_rebalance_pending, 0};
  for (int k = 0; k < m->n_pairs; ++k) head[2] += m->pairs[k].contact_node_owner != NULL;
  if (head[2] == 0) return SK_OK; /* no file */
  sk_byte_buffer_put(b, MAGIC, sizeof MAGIC);
  sk_byte_buffer_put(b, head, sizeof head);
  for (int k = 0; k < m->n_pairs; ++k) {
    const sk_contact_pair *pair = &m->pairs[k];
    if (!pair->contact_node_owner) continue;
    const int32_t len = (int32_t)strlen(pair->name), n = pair->slave.n_nodes_global, nf = pair->slave.n_faces_global;
    sk_byte_buffer_put(b, &len, sizeof len);
    sk_byte_buffer_put(b, pair->name, (size_t)len);
    sk_byte_buffer_put(b, &n, sizeof n);
    sk_byte_buffer_put(b, &nf, sizeof nf);
    for (int j = 0; j < n + nf; ++j) {
      const int32_t owner = j < n ? pair->contact_node_owner[j] : pair->contact_face_owner[j - n];
      sk_byte_buffer_put(b, &owner, sizeof owner);
    }
    sk_byte_buffer_put(b, pair->contact_weight, sizeof(double) * (size_t)(n + nf));
  }
  const uint64_t sum = b->failed ? 0 : sk_fnv1a(SK_CHECKPOINT_FNV_SEED, b->data, b->size);
  sk_byte_buffer_put(b, &sum, sizeof sum);
  sk_byte_buffer_put(b, sk_checkpoint_end_magic, sizeof sk_checkpoint_end_magic);
  return b->failed ? sk_error_set(SK_ERR_NOMEM, "checkpoint: out of memory for the contact partition") : SK_OK;
}

/* Reads the file whole and checks its marks and checksum (every rank; *found = 0 when there is none). */
static sk_status read_file(const char *path, sk_byte_buffer *b, int *found) {
  FILE *f = fopen(path, "rb");
  *found = f != NULL;
  if (!f)
    return errno == ENOENT ? SK_OK : sk_error_set(SK_ERR_INPUT, "--restart: cannot read %s: %s", path, strerror(errno));
  if (sk_checkpoint_slurp(f, b) != 0) return sk_error_set(SK_ERR_NOMEM, "--restart: out of memory reading %s", path);
  if (sk_checkpoint_whole(b, MAGIC, 3 * sizeof(int32_t)) != 1)
    return sk_error_set(SK_ERR_INPUT, "--restart: %s is not a whole stickslip contact partition (truncated or damaged)",
                        path);
  return SK_OK;
}

/* One pair's record at b->data + *at (end: the checksum's offset): its owners when the checkpoint's ranks are
 * these, and its weights; *changed |= an owner differs. */
static sk_status read_pair(const char *path, const unsigned char *data, size_t *at, size_t end, sk_model *m,
                           int same_ranks, int *changed) {
  int32_t len = 0, n = 0, nf = 0;
  if (*at + sizeof len > end) return SK_ERR_INPUT;
  memcpy(&len, data + *at, sizeof len);
  *at += sizeof len;
  if (len < 0 || *at + (size_t)len + 2 * sizeof(int32_t) > end) return SK_ERR_INPUT;
  const char *name = (const char *)data + *at;
  *at += (size_t)len;
  memcpy(&n, data + *at, sizeof n);
  memcpy(&nf, data + *at + sizeof n, sizeof nf);
  *at += 2 * sizeof(int32_t);
  if (n < 0 || nf < 0 || *at + (size_t)(n + nf) * (sizeof(int32_t) + sizeof(double)) > end) return SK_ERR_INPUT;
  sk_contact_pair *pair = NULL;
  for (int k = 0; k < m->n_pairs && !pair; ++k)
    if ((size_t)len == strlen(m->pairs[k].name) && memcmp(m->pairs[k].name, name, (size_t)len) == 0)
      pair = &m->pairs[k];
  if (!pair || !pair->contact_node_owner || n != pair->slave.n_nodes_global || nf != pair->slave.n_faces_global)
    return sk_error_set(SK_ERR_INPUT, "--restart: %s: contact pair '%.*s' with %d slave nodes and %d faces is not one "
                        "of the scene's pairs with a contact partition", path, (int)len, name, n, nf);
  for (int j = 0; j < n + nf; ++j) {
    int32_t owner;
    memcpy(&owner, data + *at + sizeof owner * (size_t)j, sizeof owner);
    if (owner < 0 || owner >= m->n_ranks) same_ranks = 0; /* defensive: a foreign owner keeps the set-up's */
  }
  for (int j = 0; same_ranks && j < n + nf; ++j) {
    int32_t owner;
    memcpy(&owner, data + *at + sizeof owner * (size_t)j, sizeof owner);
    int *mine = j < n ? &pair->contact_node_owner[j] : &pair->contact_face_owner[j - n];
    *changed |= *mine != owner;
    *mine = owner;
  }
  *at += sizeof(int32_t) * (size_t)(n + nf);
  memcpy(pair->contact_weight, data + *at, sizeof(double) * (size_t)(n + nf));
  *at += sizeof(double) * (size_t)(n + nf);
  return SK_OK;
}

sk_status sk_restart_partition(const char *dir, sk_system *sys, int *changed) {
  sk_model *m = sys->model;
  *changed = 0;
  if (!m->contact_rebalance) return SK_OK;
  char path[4400];
  snprintf(path, sizeof path, "%s/%s", dir, NAME);
  sk_byte_buffer b = {0};
  int found = 0;
  sk_status status = read_file(path, &b, &found);
  int32_t head[3] = {0, 0, 0};
  size_t at = sizeof MAGIC + sizeof head;
  const size_t end = b.size - (found ? sizeof(uint64_t) + sizeof sk_checkpoint_end_magic : 0);
  if (status == SK_OK && found) memcpy(head, b.data + sizeof MAGIC, sizeof head);
  const int same_ranks = head[0] == sys->n_ranks;
  for (int k = 0; status == SK_OK && found && k < head[2]; ++k) {
    status = read_pair(path, b.data, &at, end, m, same_ranks, changed);
    if (status == SK_ERR_INPUT && !sk_error_message()[0])
      sk_error_set(SK_ERR_INPUT, "--restart: %s: its pairs run past the end of the file", path);
  }
  free(b.data);
  SK_TRY(sk_system_collective(sys, status));
  if (!found) return SK_OK; /* a checkpoint written without a contact partition: the set-up's */
  if (same_ranks) sys->contact_rebalance_pending = head[1];
  int measured = 0; /* on other ranks: the checkpointed step's measured work split over these (else the set-up's) */
  for (int k = 0; !same_ranks && k < m->n_pairs; ++k)
    for (int j = 0; m->pairs[k].contact_weight && !measured &&
                    j < m->pairs[k].slave.n_nodes_global + m->pairs[k].slave.n_faces_global;
         ++j)
      measured = m->pairs[k].contact_weight[j] > 0.0;
  if (measured) SK_TRY(sk_contact_partition_rebalance(sys, changed));
  if (sys->verbose && sys->rank == 0) {
    fprintf(stderr, "restart: the contact partition of the checkpoint (written on %d ranks)%s\n", head[0],
            same_ranks ? (head[1] ? ", and its rebalance at the next step" : "")
            : measured ? ": its measured work split again over these ranks"
                       : ": none measured, the set-up's");
    sk_contact_partition_explain(m, stderr);
  }
  return SK_OK;
}
