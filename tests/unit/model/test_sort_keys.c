/* The pattern's in-place key sort (core/model/sort_keys.c) against qsort: random keys, few distinct values, sorted,
 * reversed and organ-pipe orders (quicksort's bad cases, where the heapsort fallback takes over), and the unique
 * variant. */
#include <stdlib.h>
#include <string.h>

#include "sk_test.h"
#include "system.h"

static uint64_t state = 88172645463325252u;
static int64_t next_random(void) { /* xorshift64: the same keys on every machine */
  state ^= state << 13;
  state ^= state >> 7;
  state ^= state << 17;
  return (int64_t)(state >> 1);
}

static int64_t key_of(int order, int64_t k, int64_t n) {
  switch (order) {
  case 0: return next_random() - INT64_MAX / 2;
  case 1: return next_random() % 3;
  case 2: return k;
  case 3: return n - k;
  default: return k % 2 ? k : n - k;
  }
}

int main(void) {
  const int64_t sizes[] = {0, 1, 2, 3, 16, 17, 100, 1000, 100000};
  int mismatches = 0;
  for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; ++s)
    for (int order = 0; order < 5; ++order) {
      const int64_t n = sizes[s];
      int64_t *a = malloc(sizeof(int64_t) * (size_t)(n + 1)), *b = malloc(sizeof(int64_t) * (size_t)(n + 1));
      SK_CHECK(a && b);
      if (!a || !b) return sk_test_finish("test_sort_keys");
      for (int64_t k = 0; k < n; ++k) a[k] = b[k] = key_of(order, k, n);
      sk_sort_i64(a, n);
      qsort(b, (size_t)n, sizeof(int64_t), sk_compare_i64);
      mismatches += n > 0 && memcmp(a, b, sizeof(int64_t) * (size_t)n) != 0;
      /* unique: strictly increasing and the same set */
      int64_t unique = n;
      for (int64_t k = 0; k < n; ++k) a[k] = key_of(order, k, n);
      sk_sort_unique_i64(a, &unique);
      int64_t expected = n > 0;
      for (int64_t k = 1; k < n; ++k) expected += b[k] != b[k - 1];
      SK_CHECK(unique == expected);
      for (int64_t k = 1; k < unique; ++k) mismatches += a[k] <= a[k - 1];
      free(a);
      free(b);
    }
  SK_CHECK(mismatches == 0);
  return sk_test_finish("test_sort_keys");
}
