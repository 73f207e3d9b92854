/* What checkpoint.c writes and restart.c reads: the state file's format number, its marks and checksum seed, and
 * the growing byte buffer both sides fill. Internal to core/time. */
#ifndef SK_CHECKPOINT_FORMAT_H
#define SK_CHECKPOINT_FORMAT_H

#include <stddef.h>

enum { SK_CHECKPOINT_FORMAT = 1 };
#define SK_CHECKPOINT_FNV_SEED 0xcbf29ce484222325ULL
extern const char sk_checkpoint_state_magic[8], sk_checkpoint_end_magic[8];

typedef struct {
  unsigned char *data;
  size_t size, cap;
  int failed; /* an allocation failed: later puts are ignored, the caller reports it */
} sk_byte_buffer;

void sk_byte_buffer_put(sk_byte_buffer *b, const void *data, size_t n);

/* 1 when `path` names a directory. */
int sk_is_directory(const char *path);

#endif
