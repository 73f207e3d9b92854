#define _POSIX_C_SOURCE 200809L
#include "stickslip/error.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

enum { SK_ERROR_MESSAGE_MAX = 2048 };
static char error_message[SK_ERROR_MESSAGE_MAX];

sk_status sk_error_set(sk_status code, const char *fmt, ...) {
  va_list args;
  va_start(args, fmt);
  vsnprintf(error_message, sizeof error_message, fmt, args);
  va_end(args);
  return code;
}

sk_status sk_error_prefix(sk_status code, const char *fmt, ...) {
  char prefix[SK_ERROR_MESSAGE_MAX];
  char previous[SK_ERROR_MESSAGE_MAX];
  va_list args;
  va_start(args, fmt);
  vsnprintf(prefix, sizeof prefix, fmt, args);
  va_end(args);
  memcpy(previous, error_message, sizeof previous);
  /* concatenated by hand: truncation of an over-long message is intended */
  size_t used = strnlen(prefix, sizeof error_message - 1);
  memcpy(error_message, prefix, used);
  size_t rest = strnlen(previous, sizeof error_message - 1 - used);
  memcpy(error_message + used, previous, rest);
  error_message[used + rest] = '\0';
  return code;
}

const char *sk_error_message(void) { return error_message; }

void sk_error_clear(void) { error_message[0] = '\0'; }
