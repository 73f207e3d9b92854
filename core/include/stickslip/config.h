/* stickslip — scene configuration: a YAML tree (parsed with libyaml) that remembers where every node came from.
 *
 * Every node knows its key path ("contact.pairs[0].plugin") and its source position ("scenes/x.yaml:12:5", or
 * "--set contact.mu" for nodes created by a command-line override), so every error can point at the culprit.
 * Reading a child with sk_cfg_get / sk_cfg_at marks it as used; sk_cfg_check_unused then reports the first key
 * nobody read, which catches typos ("densty") instead of silently using a default.
 *
 * Supported YAML: block and flow maps and sequences, scalars of any style. Anchors, aliases and multi-document
 * streams are rejected with a clear error. Duplicate keys are errors. The root must be a map. */
#ifndef STICKSLIP_CONFIG_H
#define STICKSLIP_CONFIG_H

#include <stddef.h>
#include <stdio.h>

#include "stickslip/error.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum { SK_CFG_SCALAR, SK_CFG_MAP, SK_CFG_SEQ } sk_cfg_kind;
typedef struct sk_cfg sk_cfg; /* one node; the root owns the whole tree */

/* Loads a YAML file (a regular file of at most SK_MAX_TEXT_FILE_BYTES, see files.h). Errors: missing/unreadable
 * file, a FIFO/device/directory, an oversized file; malformed YAML ("FILE:LINE:COL: <libyaml problem>");
 * root not a map; duplicate keys; anchors/aliases. */
sk_status sk_cfg_load(const char *path, sk_cfg **root);
/* Same from memory; `name` stands for the file in messages and in sk_cfg_resolve_path. */
sk_status sk_cfg_parse_string(const char *text, const char *name, sk_cfg **root);
void sk_cfg_free(sk_cfg *root);

/* Applies one override "a.b.c=value". The value is parsed as YAML ("0.3", "true", "[1, 2, 3]", "{E: 1e9}").
 * Sequence elements are addressed by index ("contact.pairs.0.plugin=x"; "pairs[0]" works too). Missing
 * intermediate maps are created. SK_CFG_MERGE (`--set`): a map landing on a map merges into it key by key (maps in
 * it merge further down), anything else replaces what was there; SK_CFG_REPLACE (`--replace`): the value replaces
 * the node at the path whatever it is. New nodes are reported as "--set a.b.c" ("--replace a.b.c"). */
typedef enum { SK_CFG_MERGE, SK_CFG_REPLACE } sk_cfg_override_mode;
sk_status sk_cfg_override(sk_cfg *root, const char *assignment, sk_cfg_override_mode mode);
sk_status sk_cfg_set(sk_cfg *root, const char *assignment); /* sk_cfg_override(root, assignment, SK_CFG_MERGE) */
/* Sets the scalar at `path` ("contact.0.plugin") to `text` verbatim (not parsed as YAML). The path's parents must
 * exist. `origin` NULL: an existing scalar keeps its position (a mesh path made absolute); otherwise the node is
 * new and reported at `origin` ("--plugin"). */
sk_status sk_cfg_set_text(sk_cfg *root, const char *path, const char *text, const char *origin);
/* Removes the key at `path` ("contact.0.parameters.penalty") from its map; 1 if it was there. */
int sk_cfg_remove(sk_cfg *root, const char *path);

sk_cfg_kind sk_cfg_kind_of(const sk_cfg *node);
const char *sk_cfg_path(const sk_cfg *node);  /* "contact.pairs[0].plugin"; "" for the root */
const char *sk_cfg_where(const sk_cfg *node); /* "scenes/x.yaml:12:5" or "--set contact.mu" */

/* Child `key` of a map, or NULL (also when `map` is NULL or not a map). Marks the child as used. */
const sk_cfg *sk_cfg_get(const sk_cfg *map, const char *key);
int sk_cfg_size(const sk_cfg *node);                 /* entries of a map or sequence, 0 for scalars and NULL */
const sk_cfg *sk_cfg_at(const sk_cfg *node, int i);  /* i-th element of a seq or i-th value of a map; marks used */
const char *sk_cfg_key_at(const sk_cfg *map, int i); /* i-th key of a map, NULL otherwise */
const char *sk_cfg_scalar(const sk_cfg *node);       /* text of a scalar, NULL otherwise */
/* The same as sk_cfg_get and sk_cfg_at without marking anything used or remembering the question: for looking at
 * the tree before it is read (the overrides), so that the unknown-key check still sees every key nobody read. */
const sk_cfg *sk_cfg_peek(const sk_cfg *map, const char *key);
const sk_cfg *sk_cfg_peek_at(const sk_cfg *node, int i);
/* Marks a node and everything below it as used (for subtrees handed over verbatim, e.g. plugin parameters). */
void sk_cfg_mark_used(const sk_cfg *node);
/* Child map `key` of `map` as sk_cfg_get gives it; when absent, an empty map that stands in for it (never written
 * and never listed as given), so that the defaults the program reads from it are known to sk_cfg_each. */
const sk_cfg *sk_cfg_section(const sk_cfg *map, const char *key);

/* Typed getters. `map` may be NULL (an absent optional section): then every key is absent.
 * Absent key: *out = dflt and SK_OK, unless `required` (then "FILE:LINE: missing key 'a.b.key'").
 * An empty section ("material:" or "material: ~") counts as an empty map; a required key then fails with
 * "FILE:LINE:COL: 'bodies[0].material' is empty; missing key 'bodies[0].material.model'".
 * Wrong type: "FILE:LINE:COL: key 'a.b.key' expects a number, got 'abc'". Numbers accept YAML forms such as
 * 1e-3 and 1.0e5 and must be finite: .inf, .nan, 1e999 are refused ("expects a finite number, got '.nan'");
 * integers accept integral values written as 1e3; booleans accept true/false/yes/no/on/off. */
sk_status sk_cfg_double(const sk_cfg *map, const char *key, int required, double dflt, double *out);
sk_status sk_cfg_int(const sk_cfg *map, const char *key, int required, int dflt, int *out);
sk_status sk_cfg_bool(const sk_cfg *map, const char *key, int required, int dflt, int *out);
/* *out points into the tree (valid until sk_cfg_free) or is dflt. */
sk_status sk_cfg_string(const sk_cfg *map, const char *key, int required, const char *dflt, const char **out);
/* A sequence of exactly n numbers ([30, 0, 23]). dflt may be NULL when required. */
sk_status sk_cfg_vector(const sk_cfg *map, const char *key, int required, int n, const double *dflt, double *out);
/* A string among `choices` (NULL-terminated); *out is its index (or dflt). Errors list the allowed values. */
sk_status sk_cfg_choice(const sk_cfg *map, const char *key, int required, const char *const *choices, int dflt,
                        int *out);

/* Converts a scalar node itself (e.g. an element reached with sk_cfg_at); errors name the node's path. */
sk_status sk_cfg_as_double(const sk_cfg *node, double *out);
sk_status sk_cfg_as_int(const sk_cfg *node, int *out);

/* First map key never read (document order): "FILE:LINE:COL: unknown key 'bodies[1].densty' (did you mean
 * 'density'?)". The suggestion comes from keys the program asked for or read in the same map. */
sk_status sk_cfg_check_unused(const sk_cfg *root);

/* `relative` resolved against the directory of the file `node` came from (absolute paths are kept). */
sk_status sk_cfg_resolve_path(const sk_cfg *node, const char *relative, char *out, size_t out_size);

/* Every key the program read and its default are remembered by the typed getters. This replaces the default of
 * `key` in `map` as sk_cfg_each shows it: `text` a value (literal 1, "0.5") or a description (literal 0, "from the
 * mesh: 3"), `meaning` (may be NULL) an explanation. */
void sk_cfg_note_default(const sk_cfg *map, const char *key, const char *text, int literal, const char *meaning);

typedef struct {
  const char *path;    /* "time.dt", "contact[0].parameters.mu" */
  const char *value;   /* given: the value as one line of YAML (collections in flow style); absent: the default */
  int given;           /* 1: in the scene or set on the command line; 0: a default */
  int literal;         /* the value is a value (0: a default described in words, e.g. "from the mesh") */
  int quantity;        /* read as a number or numbers: a unit applies */
  const char *where;   /* given: "scene.yaml:12:5", "--set time.dt"; NULL for defaults */
  const char *meaning; /* an explanation of the default (plugin parameters), or NULL */
} sk_cfg_entry;
/* Calls `each` for every key of the tree: the given keys in document order (maps and sequences of maps entered,
 * anything else one value), each map followed by the absent keys the program read from it with their defaults,
 * then its absent sections (sk_cfg_section). */
void sk_cfg_each(const sk_cfg *root, void (*each)(void *ctx, const sk_cfg_entry *entry), void *ctx);

/* Writes the whole tree (overrides included) as YAML. */
sk_status sk_cfg_write(const sk_cfg *root, FILE *out);
/* Same into a file (created or truncated). */
sk_status sk_cfg_write_file(const sk_cfg *root, const char *path);

#ifdef __cplusplus
}
#endif
#endif
