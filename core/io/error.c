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
  snprintf(error_message, sizeof error_message, "%s%s", prefix, previous);
  return code;
}

const char *sk_error_message(void) { return error_message; }

void sk_error_clear(void) { error_message[0] = '\0'; }
