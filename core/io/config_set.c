/* Overrides of the configuration tree: `--set KEY=VALUE` (a map merges into the map it lands on), `--replace
 * KEY=VALUE` (the value replaces whatever was there), and the edits the program makes itself (a scalar set verbatim,
 * a key removed), each node remembering where it came from. */
#include <stdlib.h>
#include <string.h>

#include "config_tree.h"

static int is_index(const char *s) {
  if (!*s) return 0;
  for (; *s; ++s)
    if (*s < '0' || *s > '9') return 0;
  return 1;
}

/* The key path of [begin, end) normalised into a malloc'd *key: blanks trimmed, "a[0]" → "a.0". `what` names the
 * override in messages ("--set 'a.b=1'"). */
static sk_status normalise_key(const char *begin, const char *end, const char *what, char **key_out) {
  *key_out = NULL;
  char *key = malloc(2 * (size_t)(end - begin) + 1);
  if (!key) return sk_cfgi_no_memory();
  size_t k = 0;
  while (begin < end && (*begin == ' ' || *begin == '\t')) ++begin;
  while (end > begin && (end[-1] == ' ' || end[-1] == '\t')) --end;
  int in_brackets = 0;
  const char *bracket_error = NULL;
  for (const char *c = begin; c < end && !bracket_error; ++c) {
    if (*c == '[') {
      if (in_brackets) bracket_error = "nested '['";
      in_brackets = 1;
      key[k++] = '.';
    } else if (*c == ']') {
      if (!in_brackets) {
        bracket_error = "']' without '['";
      } else if (c + 1 < end && c[1] != '.' && c[1] != '[') {
        bracket_error = "expected '.' after ']'";
      }
      in_brackets = 0;
    } else {
      key[k++] = *c;
    }
  }
  if (in_brackets && !bracket_error) bracket_error = "'[' without ']'";
  if (bracket_error) {
    free(key);
    return sk_error_set(SK_ERR_INPUT, "%s: %s in the key path", what, bracket_error);
  }
  key[k] = '\0';
  if (k == 0 || key[0] == '.' || key[k - 1] == '.' || strstr(key, "..") != NULL) {
    free(key);
    return sk_error_set(SK_ERR_INPUT, "%s: the key path has an empty part (expected e.g. contact.mu=0.3)", what);
  }
  *key_out = key;
  return SK_OK;
}

/* Where `key` (normalised, modified in place) lands: *parent is the map or sequence holding it and *index its
 * position there (-1: not in the map yet; *last then points at its name inside `key`). Missing intermediate maps are
 * created at `origin` when `create`; otherwise a missing one is an error. */
static sk_status locate(sk_cfg *root, char *key, const char *origin, int create, sk_cfg **parent, int *index,
                        const char **last) {
  sk_cfg *cur = root;
  char *segment = key;
  for (;;) {
    char *dot = strchr(segment, '.');
    if (dot) *dot = '\0';
    int i;
    if (cur->kind == SK_CFG_MAP) {
      i = sk_cfgi_find(cur, segment);
      if (i < 0 && dot) {
        if (!create)
          return sk_error_set(SK_ERR_INPUT, "%s: '%s' has no key '%s'", origin, cur->path[0] ? cur->path : "(root)",
                              segment);
        sk_cfg *map = sk_cfgi_node_new(SK_CFG_MAP, root->file, origin, 0, 0);
        char *name = sk_cfgi_dup(segment);
        if (!map || !name || !sk_cfgi_append(cur, name, map)) {
          sk_cfg_free(map);
          free(name);
          return sk_cfgi_no_memory();
        }
        i = cur->n - 1;
      }
    } else if (cur->kind == SK_CFG_SEQ) {
      if (!is_index(segment))
        return sk_error_set(SK_ERR_INPUT, "%s: '%s' (%s) is a sequence; expected an index, got '%s'", origin,
                            cur->path, cur->where, segment);
      long at = strtol(segment, NULL, 10);
      if (at >= cur->n)
        return sk_error_set(SK_ERR_INPUT, "%s: index %ld is out of range: '%s' (%s) has %d entr%s (0 to %d)",
                            origin, at, cur->path, cur->where, cur->n, cur->n == 1 ? "y" : "ies", cur->n - 1);
      i = (int)at;
    } else {
      return sk_error_set(SK_ERR_INPUT, "%s: '%s' (%s) is a scalar, it has no entry '%s'", origin, cur->path,
                          cur->where, segment);
    }
    if (!dot) {
      *parent = cur;
      *index = i;
      *last = segment;
      return SK_OK;
    }
    cur = cur->items[i];
    segment = dot + 1;
  }
}

/* Puts `value` (owned) into `parent` at `index` (-1: as the new key `name`); frees it on failure. */
static sk_status put(sk_cfg *parent, int index, const char *name, sk_cfg *value) {
  if (index >= 0) {
    sk_cfg_free(parent->items[index]);
    parent->items[index] = value;
    return SK_OK;
  }
  char *copy = sk_cfgi_dup(name);
  if (!copy || !sk_cfgi_append(parent, copy, value)) {
    free(copy);
    sk_cfg_free(value);
    return sk_cfgi_no_memory();
  }
  return SK_OK;
}

/* Merges map `value` (owned, consumed) into map `target` key by key: a map meeting a map merges further down,
 * anything else replaces what was there. */
static sk_status merge(sk_cfg *target, sk_cfg *value) {
  sk_status status = SK_OK;
  for (int k = 0; k < value->n; ++k) {
    sk_cfg *item = value->items[k];
    value->items[k] = NULL;
    if (status != SK_OK) {
      sk_cfg_free(item);
      continue;
    }
    int i = sk_cfgi_find(target, value->keys[k]);
    if (i >= 0 && target->items[i]->kind == SK_CFG_MAP && item->kind == SK_CFG_MAP)
      status = merge(target->items[i], item);
    else
      status = put(target, i, value->keys[k], item);
  }
  for (int k = 0; k < value->n; ++k) free(value->keys[k]);
  value->n = 0; /* its items are gone into the target (or freed) */
  sk_cfg_free(value);
  return status;
}

sk_status sk_cfg_override(sk_cfg *root, const char *assignment, sk_cfg_override_mode mode) {
  const char *option = mode == SK_CFG_REPLACE ? "--replace" : "--set";
  if (!root || root->kind != SK_CFG_MAP) return sk_error_set(SK_ERR_INTERNAL, "%s: the root is not a map", option);
  const char *eq = assignment ? strchr(assignment, '=') : NULL;
  if (!eq)
    return sk_error_set(SK_ERR_INPUT, "%s '%s': expected KEY=VALUE, e.g. contact.0.parameters.mu=0.3", option,
                        assignment ? assignment : "");
  char *what = sk_cfgi_format("%s '%s'", option, assignment);
  if (!what) return sk_cfgi_no_memory();
  char *key = NULL;
  sk_status status = normalise_key(assignment, eq, what, &key);
  free(what);
  if (status != SK_OK) return status;
  char *origin = sk_cfgi_format("%s %s", option, key);
  if (!origin) {
    free(key);
    return sk_cfgi_no_memory();
  }
  sk_cfg *value = NULL;
  status = sk_cfgi_parse_text(eq + 1, strlen(eq + 1), root->file, origin, &value);
  sk_cfg *parent = NULL;
  int index = -1;
  const char *name = NULL;
  if (status == SK_OK) status = locate(root, key, origin, 1, &parent, &index, &name);
  if (status == SK_OK) {
    sk_cfg *old = index >= 0 ? parent->items[index] : NULL;
    if (mode == SK_CFG_MERGE && old && old->kind == SK_CFG_MAP && value->kind == SK_CFG_MAP)
      status = merge(old, value);
    else
      status = put(parent, index, name, value);
    value = NULL; /* the tree's now (or freed) */
  }
  sk_cfg_free(value);
  free(origin);
  free(key);
  /* New nodes (and intermediate maps) need their key paths. */
  if (status == SK_OK && !sk_cfgi_assign_paths(root, "")) status = sk_cfgi_no_memory();
  return status;
}

sk_status sk_cfg_set(sk_cfg *root, const char *assignment) { return sk_cfg_override(root, assignment, SK_CFG_MERGE); }

sk_status sk_cfg_set_text(sk_cfg *root, const char *path, const char *text, const char *origin) {
  if (!root || root->kind != SK_CFG_MAP || !path || !text)
    return sk_error_set(SK_ERR_INTERNAL, "sk_cfg_set_text: bad arguments");
  char *key = NULL;
  SK_TRY(normalise_key(path, path + strlen(path), path, &key));
  sk_cfg *parent = NULL;
  int index = -1;
  const char *name = NULL;
  sk_status status = locate(root, key, origin ? origin : path, 0, &parent, &index, &name);
  sk_cfg *old = status == SK_OK && index >= 0 ? parent->items[index] : NULL;
  if (status == SK_OK && old && old->kind == SK_CFG_SCALAR && !origin) {
    char *copy = sk_cfgi_dup(text); /* the same node, now with this text: it keeps its position */
    if (!copy) {
      status = sk_cfgi_no_memory();
    } else {
      free(old->text);
      old->text = copy;
      old->style = YAML_PLAIN_SCALAR_STYLE; /* written as the emitter sees fit (quoted when it must be) */
    }
  } else if (status == SK_OK) {
    sk_cfg *node = sk_cfgi_node_new(SK_CFG_SCALAR, root->file, origin ? origin : path, 0, 0);
    if (!node || !(node->text = sk_cfgi_dup(text))) {
      sk_cfg_free(node);
      status = sk_cfgi_no_memory();
    } else {
      node->style = YAML_PLAIN_SCALAR_STYLE;
      status = put(parent, index, name, node);
    }
  }
  free(key);
  if (status == SK_OK && !sk_cfgi_assign_paths(root, "")) status = sk_cfgi_no_memory();
  return status;
}

int sk_cfg_remove(sk_cfg *root, const char *path) {
  char *key = NULL;
  if (!root || root->kind != SK_CFG_MAP || !path || normalise_key(path, path + strlen(path), path, &key) != SK_OK)
    return 0;
  sk_cfg *map = NULL;
  int i = -1;
  const char *name = NULL;
  int found = locate(root, key, path, 0, &map, &i, &name) == SK_OK && map->kind == SK_CFG_MAP && i >= 0;
  free(key);
  if (!found) return 0;
  free(map->keys[i]);
  sk_cfg_free(map->items[i]);
  memmove(map->keys + i, map->keys + i + 1, (size_t)(map->n - i - 1) * sizeof *map->keys);
  memmove(map->items + i, map->items + i + 1, (size_t)(map->n - i - 1) * sizeof *map->items);
  map->n--;
  return 1;
}
