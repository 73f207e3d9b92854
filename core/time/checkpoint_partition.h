/* The contact partition in a checkpoint (docs/design.md, "Contact partition"): each pair's contact owners, the
 * entities' measured work and whether a rebalance was due, so that a restart resumes with the partition of the
 * checkpointed step. Internal to core/time (checkpoint.c writes, restart.c reads). */
#ifndef STICKSLIP_CHECKPOINT_PARTITION_H
#define STICKSLIP_CHECKPOINT_PARTITION_H

#include "../model/records.h"
#include "../model/system.h"

/* The file's name in a checkpoint's step folder. */
const char *sk_checkpoint_partition_file(void);
/* The file's bytes (rank 0; nothing when no pair has a contact partition). */
sk_status sk_checkpoint_partition_bytes(const sk_system *sys, sk_byte_buffer *b);
/* At a restart, before the master faces are held (collective): with contact_balance.rebalance on and the file in
 * `dir`, on as many ranks as wrote it the checkpointed owners, weights and pending rebalance; on another number of
 * ranks the checkpointed step's weights split again over these (sk_contact_partition_rebalance; the set-up's split
 * when no work was measured). Without the file (rebalance off when written), the set-up's partition. *changed: 1
 * when an owner differs from the set-up's; the caller re-creates the pairs' instances over their new views. */
sk_status sk_restart_partition(const char *dir, sk_system *sys, int *changed);

#endif
