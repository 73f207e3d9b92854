/* What checkpoint.c writes and restart.c reads: the state file's format number, its marks and checksum seed, and
 * the growing byte buffer both sides fill. Internal to core/time. */
#ifndef SK_CHECKPOINT_FORMAT_H
#define SK_CHECKPOINT_FORMAT_H

#include <stddef.h>
#include <stdio.h>

#include "../model/records.h"

enum { SK_CHECKPOINT_FORMAT = 1 };
#define SK_CHECKPOINT_FNV_SEED 0xcbf29ce484222325ULL
extern const char sk_checkpoint_state_magic[8], sk_checkpoint_end_magic[8];


/* Reads the open file f whole into b and closes it; 0, or -1 when out of memory (b->failed). */
int sk_checkpoint_slurp(FILE *f, sk_byte_buffer *b);
/* A checkpoint file read whole: 1 when it starts with `magic` (8 bytes) and `head` more bytes, ends with its
 * checksum and the end mark and the checksum matches; 0 when it is not whole (truncated), -1 when only the checksum
 * does not match (damaged). */
int sk_checkpoint_whole(const sk_byte_buffer *b, const char magic[8], size_t head);

/* 1 when `path` names a directory. */
int sk_is_directory(const char *path);

#endif
