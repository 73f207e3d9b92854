/* A plugin's parameter table as the host reads it: the lines `stickslip plugins` prints ("key, key2: meaning
 * [default]", optionally ending in "(pair)" or "(body)" when the keys apply to one kind of attachment only). The
 * host learns from them which keys a plugin takes (`--plugin` keeps those) and their declared defaults (`stickslip
 * keys`). */
#include <ctype.h>
#include <stdio.h>
#include <string.h>

#include "stickslip/plugins.h"

/* [begin, end) without blanks at either end, into out. */
static void trimmed(const char *begin, const char *end, char *out, size_t size) {
  while (begin < end && isspace((unsigned char)*begin)) ++begin;
  while (end > begin && isspace((unsigned char)end[-1])) --end;
  snprintf(out, size, "%.*s", (int)(end - begin), begin);
}

int sk_plugin_parameter_at(const sk_plugin *plugin, int k, sk_plugin_parameter *out) {
  memset(out, 0, sizeof *out);
  if (!plugin || !plugin->parameters || k < 0) return 0;
  for (int i = 0; i < k; ++i)
    if (!plugin->parameters[i]) return 0;
  const char *line = plugin->parameters[k];
  if (!line) return 0;
  const char *colon = strchr(line, ':');
  const char *end = line + strlen(line);
  out->kinds = SK_KIND_PAIR | SK_KIND_BODY;
  /* a trailing "(pair)" or "(body)" narrows the line to one kind of attachment */
  char tail[512];
  trimmed(colon ? colon + 1 : end, end, tail, sizeof tail);
  size_t n = strlen(tail);
  if (n >= 6 && (strcmp(tail + n - 6, "(pair)") == 0 || strcmp(tail + n - 6, "(body)") == 0)) {
    out->kinds = tail[n - 5] == 'p' ? SK_KIND_PAIR : SK_KIND_BODY;
    n -= 6;
    while (n > 0 && isspace((unsigned char)tail[n - 1])) --n;
    tail[n] = '\0';
  }
  /* the default: the last [...] */
  char *open = strrchr(tail, '[');
  char *close = open ? strchr(open, ']') : NULL;
  if (open && close) {
    trimmed(open + 1, close, out->dflt, sizeof out->dflt);
    char rest[512];
    snprintf(rest, sizeof rest, "%.*s%s", (int)(open - tail), tail, close + 1);
    trimmed(rest, rest + strlen(rest), out->meaning, sizeof out->meaning);
  } else {
    snprintf(out->meaning, sizeof out->meaning, "%s", tail);
  }
  /* the keys: the comma-separated names before the colon */
  const char *key = line;
  const char *keys_end = colon ? colon : end;
  while (key < keys_end && out->n_keys < SK_PLUGIN_PARAMETER_KEYS) {
    const char *comma = memchr(key, ',', (size_t)(keys_end - key));
    const char *stop = comma ? comma : keys_end;
    trimmed(key, stop, out->keys[out->n_keys], sizeof out->keys[0]);
    if (out->keys[out->n_keys][0]) out->n_keys++;
    key = comma ? comma + 1 : keys_end;
  }
  return 1;
}

int sk_plugin_takes(const sk_plugin *plugin, const char *key, sk_kind kind) {
  sk_plugin_parameter parameter;
  for (int k = 0; sk_plugin_parameter_at(plugin, k, &parameter); ++k)
    for (int i = 0; i < parameter.n_keys; ++i)
      if ((parameter.kinds & kind) && strcmp(parameter.keys[i], key) == 0) return 1;
  return 0;
}
