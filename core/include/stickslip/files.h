/* stickslip — reading input files safely: only regular files, of bounded size, never blocking.
 *
 * A scene or mesh script named on the command line may be anything: a FIFO (opening it for reading would wait for
 * a writer forever), /dev/zero (endless), a directory, or a file far larger than any scene. Every input text goes
 * through sk_read_text_file, which refuses all of these with a message naming the file. */
#ifndef STICKSLIP_FILES_H
#define STICKSLIP_FILES_H

#include <stddef.h>
#include <stdint.h>

#include "stickslip/error.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Largest scene file and largest .geo script read (a scene is a few kB; the largest bundled script is 4 kB). */
#define SK_MAX_TEXT_FILE_BYTES ((size_t)16 << 20)

/* Reads the whole of `path` into a NUL-terminated malloc'ed buffer (*text, length *length without the NUL).
 * `what` names the file's role in messages ("scene file", "mesh script"). Errors (SK_ERR_IO or SK_ERR_INPUT):
 * missing or unreadable; not a regular file (FIFO, device, directory, socket); larger than `max_bytes`; a NUL byte
 * (a binary file). */
sk_status sk_read_text_file(const char *path, const char *what, size_t max_bytes, char **text, size_t *length);

/* SK_OK when `path` is an existing regular file (symbolic links followed), else an error naming it and what it
 * is instead. Never opens the file, so a FIFO cannot block. */
sk_status sk_require_regular_file(const char *path, const char *what);

/* FNV-1a (64 bit) of `n` bytes, continuing from `hash` (a seed or a previous value): the mesh cache's keys and the
 * checkpoints' checksums. Not cryptographic: it detects accidents (a truncated or edited file), not forgeries. */
uint64_t sk_fnv1a(uint64_t hash, const void *data, size_t n);

#ifdef __cplusplus
}
#endif
#endif
