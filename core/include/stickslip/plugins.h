/* stickslip — finding and loading formulation plugins (dlopen). */
#ifndef STICKSLIP_PLUGINS_H
#define STICKSLIP_PLUGINS_H

#include "stickslip/error.h"
#include "stickslip/plugin.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Directories searched, in order: those of STICKSLIP_PLUGIN_PATH (':'-separated), then the build/install folder
 * next to the running executable (<exe>/../lib/stickslip/plugins). Libraries are named libstickslip-<name>.so. */

/* Loads the plugin called `name`. Errors: unknown name (the message lists the plugins found), a library without the
 * entry symbol, a wrong ABI version. The library stays loaded for the process lifetime. */
sk_status sk_plugin_load(const char *name, const sk_plugin **plugin);
/* Calls `callback` for every loadable plugin; libraries that fail to load are reported through `broken`
 * (path, message) and skipped. Returns the number of plugins found. */
int sk_plugin_each(void (*callback)(void *ctx, const sk_plugin *plugin, const char *path),
                   void (*broken)(void *ctx, const char *path, const char *message), void *ctx);
/* Loads one library file (for tests): checks the symbol, the ABI major version (any minor is accepted) and the
 * required entries. *plugin is the table as this host reads it (members beyond the plugin's struct_size NULL). */
sk_status sk_plugin_open_file(const char *path, const sk_plugin **plugin);
/* Human-readable capability list: "2d 3d friction ..." */
void sk_capabilities_string(uint64_t caps, char *out, int size);
/* Human-readable kinds: "pair", "body" or "pair, body". */
void sk_kinds_string(uint32_t kinds, char *out, int size);

/* One line of a plugin's parameter table (sk_plugin.parameters, printed by `stickslip plugins`) as the host reads
 * it: "key, key2: meaning [default]", ending in "(pair)" or "(body)" when the keys apply to one kind only. */
enum { SK_PLUGIN_PARAMETER_KEYS = 8 };
typedef struct {
  char keys[SK_PLUGIN_PARAMETER_KEYS][64];
  int n_keys;
  char meaning[512]; /* the text after the colon without the default */
  char dflt[256];    /* the text of the last [...]; "" when the line states no default */
  uint32_t kinds;    /* SK_KIND_PAIR | SK_KIND_BODY, or one of them */
} sk_plugin_parameter;
/* Line k of the plugin's table, parsed; 0 past the end. */
int sk_plugin_parameter_at(const sk_plugin *plugin, int k, sk_plugin_parameter *out);
/* 1 when the table names `key` for an attachment of `kind`. */
int sk_plugin_takes(const sk_plugin *plugin, const char *key, sk_kind kind);

#ifdef __cplusplus
}
#endif
#endif
