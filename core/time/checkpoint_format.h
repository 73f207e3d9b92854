/* What checkpoint.c writes and restart.c reads: the state file's format number, its marks and checksum seed, and
 * the growing byte buffer both sides fill. Internal to core/time. */
#ifndef SK_CHECKPOINT_FORMAT_H
#define SK_CHECKPOINT_FORMAT_H

#include <stddef.h>

#include "../model/records.h"

enum { SK_CHECKPOINT_FORMAT = 1 };
#define SK_CHECKPOINT_FNV_SEED 0xcbf29ce484222325ULL
extern const char sk_checkpoint_state_magic[8], sk_checkpoint_end_magic[8];


/* 1 when `path` names a directory. */
int sk_is_directory(const char *path);

#endif
