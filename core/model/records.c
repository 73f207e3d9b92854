/* Plugin records in memory (records.h). */
#include "records.h"

#include <stdlib.h>
#include <string.h>

void sk_byte_buffer_put(sk_byte_buffer *b, const void *data, size_t n) {
  if (b->failed) return;
  if (b->size + n > b->cap) {
    size_t cap = 2 * (b->size + n) + 4096;
    unsigned char *grown = realloc(b->data, cap);
    if (!grown) {
      b->failed = 1;
      return;
    }
    b->data = grown;
    b->cap = cap;
  }
  memcpy(b->data + b->size, data, n);
  b->size += n;
}

static void writer_put(sk_record_writer *abi, int64_t key, const void *data, uint32_t bytes) {
  sk_buffer_writer *w = (sk_buffer_writer *)abi;
  sk_byte_buffer_put(w->out, &key, sizeof key);
  sk_byte_buffer_put(w->out, &bytes, sizeof bytes);
  sk_byte_buffer_put(w->out, data, bytes);
  w->count++;
}

void sk_buffer_writer_init(sk_buffer_writer *w, sk_byte_buffer *out) {
  *w = (sk_buffer_writer){.abi = {SK_TABLE_HEADER(sk_record_writer), .put = writer_put}, .out = out};
}

static int64_t reader_get(const sk_record_reader *abi, int64_t key, void *data, uint32_t capacity) {
  const sk_record_set *s = (const sk_record_set *)abi;
  int64_t lo = 0, hi = s->n;
  while (lo < hi) {
    const int64_t mid = lo + (hi - lo) / 2;
    if (s->key[mid] < key) lo = mid + 1;
    else hi = mid;
  }
  if (lo >= s->n || s->key[lo] != key) return -1;
  memcpy(data, s->data.data + s->offset[lo], s->bytes[lo] < capacity ? s->bytes[lo] : capacity);
  return s->bytes[lo];
}

int sk_record_set_add(sk_record_set *s, int64_t key, const unsigned char *data, uint32_t bytes) {
  if (s->n == s->cap) {
    const int64_t cap = 2 * s->cap + 256;
    int64_t *k = realloc(s->key, sizeof(int64_t) * (size_t)cap), *o = realloc(s->offset, sizeof(int64_t) * (size_t)cap);
    if (k) s->key = k;
    if (o) s->offset = o;
    uint32_t *b = realloc(s->bytes, sizeof(uint32_t) * (size_t)cap);
    if (b) s->bytes = b;
    if (!k || !o || !b) return 0;
    s->cap = cap;
  }
  s->key[s->n] = key;
  s->offset[s->n] = (int64_t)s->data.size;
  s->bytes[s->n] = bytes;
  sk_byte_buffer_put(&s->data, data, bytes);
  s->n++;
  return !s->data.failed;
}

int64_t sk_record_set_parse(sk_record_set *s, const unsigned char *data, size_t size, int64_t count, int *no_memory) {
  size_t at = 0;
  *no_memory = 0;
  for (int64_t j = 0; j < count; ++j) {
    int64_t key;
    uint32_t bytes;
    if (at + sizeof key + sizeof bytes > size) return -1;
    memcpy(&key, data + at, sizeof key);
    memcpy(&bytes, data + at + sizeof key, sizeof bytes);
    at += sizeof key + sizeof bytes;
    if (at + bytes > size) return -1;
    if (!sk_record_set_add(s, key, data + at, bytes)) {
      *no_memory = 1;
      return -1;
    }
    at += bytes;
  }
  return (int64_t)at;
}

void sk_record_set_free(sk_record_set *s) {
  free(s->data.data);
  free(s->key);
  free(s->offset);
  free(s->bytes);
  memset(s, 0, sizeof *s);
}

/* Sorts a record set by key (an index sort, then the arrays permuted). */
static const sk_record_set *sort_target;
static int compare_records(const void *a, const void *b) {
  const int64_t x = sort_target->key[*(const int64_t *)a], y = sort_target->key[*(const int64_t *)b];
  return (x > y) - (x < y);
}

int sk_record_set_sort(sk_record_set *s) {
  int64_t *order = malloc(sizeof(int64_t) * (size_t)(s->n + 1));
  int64_t *key = malloc(sizeof(int64_t) * (size_t)(s->n + 1)), *offset = malloc(sizeof(int64_t) * (size_t)(s->n + 1));
  uint32_t *bytes = malloc(sizeof(uint32_t) * (size_t)(s->n + 1));
  if (!order || !key || !offset || !bytes) {
    free(order), free(key), free(offset), free(bytes);
    return 0;
  }
  for (int64_t k = 0; k < s->n; ++k) order[k] = k;
  sort_target = s;
  qsort(order, (size_t)s->n, sizeof(int64_t), compare_records);
  for (int64_t k = 0; k < s->n; ++k) {
    key[k] = s->key[order[k]];
    offset[k] = s->offset[order[k]];
    bytes[k] = s->bytes[order[k]];
  }
  free(s->key), free(s->offset), free(s->bytes), free(order);
  s->key = key, s->offset = offset, s->bytes = bytes;
  s->abi = (sk_record_reader){SK_TABLE_HEADER(sk_record_reader), .get = reader_get};
  return 1;
}
