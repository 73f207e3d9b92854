/* stickslip — error reporting shared by core, driver and plugins.
 *
 * Every fallible core call returns an sk_status. On failure the callee records one human-readable message
 * (naming the file, key, line, group or parameter at fault) with sk_error_set(); callers up the stack may prefix
 * context with sk_error_prefix(). The driver prints the final message once and exits non-zero. */
#ifndef STICKSLIP_ERROR_H
#define STICKSLIP_ERROR_H

#include "stickslip/plugin_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/* sk_status (SK_OK, SK_ERR_INPUT, ...) and SK_TRY are part of the plugin ABI: plugin_types.h defines them. */

/* Records the message of the current failure (printf-style), replacing any earlier one. Returns `code`. */
sk_status sk_error_set(sk_status code, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* Prepends context ("scene.yaml: ") to the current message. Returns `code`. */
sk_status sk_error_prefix(sk_status code, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* The current message ("" when none). */
const char *sk_error_message(void);
void sk_error_clear(void);


#ifdef __cplusplus
}
#endif
#endif
