/* Bounded, non-blocking reads of input files (see stickslip/files.h). */
#define _POSIX_C_SOURCE 200809L

#include "stickslip/files.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static const char *kind_of(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

static sk_status check_mode(const char *path, const char *what, const struct stat *st, size_t max_bytes) {
  if (!S_ISREG(st->st_mode))
    return sk_error_set(SK_ERR_INPUT, "%s '%s' is %s, not a regular file", what, path, kind_of(st->st_mode));
  if (max_bytes > 0 && (unsigned long long)st->st_size > (unsigned long long)max_bytes)
    return sk_error_set(SK_ERR_INPUT, "%s '%s' has %lld bytes; the limit is %zu MiB (is it the right file?)", what,
                        path, (long long)st->st_size, max_bytes >> 20);
  return SK_OK;
}

sk_status sk_require_regular_file(const char *path, const char *what) {
  struct stat st;
  if (stat(path, &st) != 0) return sk_error_set(SK_ERR_IO, "cannot open %s '%s': %s", what, path, strerror(errno));
  return check_mode(path, what, &st, 0);
}

sk_status sk_read_text_file(const char *path, const char *what, size_t max_bytes, char **text, size_t *length) {
  *text = NULL;
  *length = 0;
  /* O_NONBLOCK: opening a FIFO without a writer returns at once instead of waiting; fstat then refuses it. */
  int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return sk_error_set(SK_ERR_IO, "cannot open %s '%s': %s", what, path, strerror(errno));
  struct stat st;
  if (fstat(fd, &st) != 0) {
    sk_status status = sk_error_set(SK_ERR_IO, "cannot inspect %s '%s': %s", what, path, strerror(errno));
    close(fd);
    return status;
  }
  sk_status status = check_mode(path, what, &st, max_bytes);
  if (status != SK_OK) {
    close(fd);
    return status;
  }
  /* The size can change while reading (a file being written): read at most max_bytes + 1 to notice. */
  size_t capacity = (size_t)st.st_size + 1, used = 0;
  char *buffer = malloc(capacity + 1);
  if (!buffer) {
    close(fd);
    return sk_error_set(SK_ERR_NOMEM, "out of memory reading %s '%s'", what, path);
  }
  for (;;) {
    if (used == capacity) {
      if (capacity > max_bytes) break;
      size_t bigger = 2 * capacity;
      char *grown = realloc(buffer, bigger + 1);
      if (!grown) {
        free(buffer);
        close(fd);
        return sk_error_set(SK_ERR_NOMEM, "out of memory reading %s '%s'", what, path);
      }
      buffer = grown;
      capacity = bigger;
    }
    ssize_t got = read(fd, buffer + used, capacity - used);
    if (got == 0) break;
    if (got < 0) {
      if (errno == EINTR) continue;
      status = sk_error_set(SK_ERR_IO, "cannot read %s '%s': %s", what, path, strerror(errno));
      break;
    }
    used += (size_t)got;
  }
  close(fd);
  if (status == SK_OK && used > max_bytes)
    status = sk_error_set(SK_ERR_INPUT, "%s '%s' grew beyond %zu MiB while being read", what, path, max_bytes >> 20);
  if (status == SK_OK && memchr(buffer, '\0', used))
    status = sk_error_set(SK_ERR_INPUT, "%s '%s' holds a NUL byte: a binary file, not text", what, path);
  if (status != SK_OK) {
    free(buffer);
    return status;
  }
  buffer[used] = '\0';
  *text = buffer;
  *length = used;
  return SK_OK;
}

uint64_t sk_fnv1a(uint64_t hash, const void *data, size_t n) {
  const unsigned char *p = data;
  for (size_t k = 0; k < n; ++k) {
    hash ^= p[k];
    hash *= 0x100000001b3ULL;
  }
  return hash;
}
