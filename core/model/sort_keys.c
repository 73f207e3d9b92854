/* Sorting the pattern's int64 keys in place (introsort): glibc's qsort merge-sorts through a buffer as large as the
 * array, allocated at each call, and calls the comparison through a pointer at each step. The pattern's widening
 * sorts arrays of millions of keys, and that buffer set a contact rank's peak heap (docs/scaling.md, "Weak scaling
 * in memory"); this sort needs no memory, compares inline and took 0.46 x qsort's time on 4 M random keys. */
#include <stdlib.h>

#include "system.h"

enum { INSERTION_BELOW = 16 };

static void insertion_sort(int64_t *a, int64_t n) {
  for (int64_t i = 1; i < n; ++i) {
    const int64_t v = a[i];
    int64_t j = i;
    for (; j > 0 && a[j - 1] > v; --j) a[j] = a[j - 1];
    a[j] = v;
  }
}

static void sift_down(int64_t *a, int64_t root, int64_t n) {
  const int64_t v = a[root];
  for (int64_t child = 2 * root + 1; child < n; child = 2 * root + 1) {
    if (child + 1 < n && a[child + 1] > a[child]) ++child;
    if (a[child] <= v) break;
    a[root] = a[child];
    root = child;
  }
  a[root] = v;
}

/* the fallback when partitions keep coming out uneven: O(n log n) whatever the keys */
static void heap_sort(int64_t *a, int64_t n) {
  for (int64_t k = n / 2 - 1; k >= 0; --k) sift_down(a, k, n);
  for (int64_t end = n - 1; end > 0; --end) {
    const int64_t t = a[0];
    a[0] = a[end];
    a[end] = t;
    sift_down(a, 0, end);
  }
}

static void swap_keys(int64_t *a, int64_t i, int64_t j) {
  const int64_t t = a[i];
  a[i] = a[j];
  a[j] = t;
}

static void intro_sort(int64_t *a, int64_t n, int depth) {
  while (n > INSERTION_BELOW) {
    if (depth-- == 0) {
      heap_sort(a, n);
      return;
    }
    /* the median of the first, middle and last key becomes a[0], the pivot of Hoare's partition, which then ends
     * with 0 <= j < n - 1: both parts non-empty and shorter than n */
    const int64_t mid = n / 2, last = n - 1;
    if (a[mid] < a[0]) swap_keys(a, mid, 0);
    if (a[last] < a[0]) swap_keys(a, last, 0);
    if (a[last] < a[mid]) swap_keys(a, last, mid);
    swap_keys(a, 0, mid);
    const int64_t pivot = a[0];
    int64_t i = -1, j = n;
    for (;;) {
      do ++i;
      while (a[i] < pivot);
      do --j;
      while (a[j] > pivot);
      if (i >= j) break;
      swap_keys(a, i, j);
    }
    /* the shorter part by recursion, the longer by the loop: the stack stays O(log n) */
    if (j + 1 < n - j - 1) {
      intro_sort(a, j + 1, depth);
      a += j + 1;
      n -= j + 1;
    } else {
      intro_sort(a + j + 1, n - j - 1, depth);
      n = j + 1;
    }
  }
  insertion_sort(a, n);
}

void sk_sort_i64(int64_t *keys, int64_t n) {
  if (n < 2) return;
  int depth = 0;
  for (int64_t m = n; m > 1; m >>= 1) depth += 2;
  intro_sort(keys, n, depth);
}

int sk_compare_i64(const void *a, const void *b) {
  int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
  return (x > y) - (x < y);
}

void sk_sort_unique_i64(int64_t *keys, int64_t *n) {
  if (*n < 2) return; /* also keys == NULL with none */
  sk_sort_i64(keys, *n);
  int64_t unique = 0;
  for (int64_t k = 0; k < *n; ++k)
    if (k == 0 || keys[k] != keys[unique - 1]) keys[unique++] = keys[k];
  *n = unique;
}
