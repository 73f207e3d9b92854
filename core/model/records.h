/* Plugin records (stickslip.checkpoint.v1, docs/plugin-abi.md §9.6) held in memory: the growing byte buffer they are
 * written into, the writer that appends (key, bytes, data) to it, and a set of records sorted by key that serves as
 * the plugins' reader. The checkpoint files (core/time/checkpoint.c), the restart (core/time/restart.c) and the
 * re-creation of a pair's instance when its master faces are ghosted again (master_ghosts.c) share them. */
#ifndef STICKSLIP_RECORDS_H
#define STICKSLIP_RECORDS_H

#include <stddef.h>
#include <stdint.h>

#include "stickslip/plugin.h"

typedef struct {
  unsigned char *data;
  size_t size, cap;
  int failed; /* an allocation failed: later puts are ignored, the caller reports it */
} sk_byte_buffer;

void sk_byte_buffer_put(sk_byte_buffer *b, const void *data, size_t n);

/* Appends each record as (int64 key, uint32 bytes, data) to `out` and counts them. */
typedef struct {
  sk_record_writer abi;
  sk_byte_buffer *out;
  int64_t count;
} sk_buffer_writer;

void sk_buffer_writer_init(sk_buffer_writer *w, sk_byte_buffer *out);

/* Records by key: fill with sk_record_set_add, then sk_record_set_sort makes `abi` the reader. */
typedef struct {
  sk_record_reader abi;
  sk_byte_buffer data;
  int64_t n, cap;
  int64_t *key, *offset;
  uint32_t *bytes;
} sk_record_set;

/* 0: out of memory. */
int sk_record_set_add(sk_record_set *s, int64_t key, const unsigned char *data, uint32_t bytes);
/* Adds `count` records as sk_buffer_writer lays them out from data[0, size); returns the bytes read, or -1 when they
 * run past `size` or memory runs out (*no_memory then says which). */
int64_t sk_record_set_parse(sk_record_set *s, const unsigned char *data, size_t size, int64_t count, int *no_memory);
int sk_record_set_sort(sk_record_set *s);
void sk_record_set_free(sk_record_set *s);

#endif
