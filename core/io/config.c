/* The scene configuration tree: libyaml events → nodes with key paths and source positions, overrides, typed
 * getters, unused-key detection and YAML output. */
#define _POSIX_C_SOURCE 200809L

#include "stickslip/config.h"
#include "stickslip/files.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <yaml.h>

enum { MAX_DEPTH = 200 }; /* deeper nesting is surely an error and would only risk the stack */

struct sk_cfg {
  sk_cfg_kind kind;
  char *text;               /* scalar text */
  yaml_scalar_style_t style; /* scalar style as written, kept when writing back */
  int flow;                 /* map/seq written in flow style ([1, 2]) */
  int n, cap;
  char **keys;              /* map keys (NULL for sequences) */
  sk_cfg **items;           /* map values or sequence elements */
  char *path;               /* "contact.pairs[0].plugin" */
  char *where;              /* "file:line:col" or "--set key" */
  char *file;               /* file the node came from (for messages and relative paths) */
  int line, col;            /* 1-based; 0 for nodes created by --set */
  int key_line, key_col;    /* position of the key naming this node in its parent map */
  int used;
  char **asked;             /* keys the program asked this map for, found or not (for suggestions) */
  int n_asked, cap_asked;
};

/* ---- small helpers ---------------------------------------------------------------------------------------- */

static char *dup_n(const char *s, size_t n) {
  char *d = malloc(n + 1);
  if (d) {
    memcpy(d, s, n);
    d[n] = '\0';
  }
  return d;
}

static char *dup_s(const char *s) { return dup_n(s, strlen(s)); }

static char *format_alloc(const char *fmt, const char *a, const char *b) {
  size_t n = (size_t)snprintf(NULL, 0, fmt, a, b) + 1;
  char *s = malloc(n);
  if (s) snprintf(s, n, fmt, a, b);
  return s;
}

static sk_status no_memory(void) { return sk_error_set(SK_ERR_NOMEM, "out of memory while reading the configuration"); }

static sk_cfg *node_new(sk_cfg_kind kind, const char *file, const char *origin, int line, int col) {
  sk_cfg *node = calloc(1, sizeof *node);
  if (!node) return NULL;
  node->kind = kind;
  node->line = line;
  node->col = col;
  node->file = dup_s(file ? file : "");
  if (origin) {
    node->where = dup_s(origin);
  } else {
    char pos[64];
    snprintf(pos, sizeof pos, "%d:%d", line, col);
    node->where = format_alloc("%s:%s", node->file ? node->file : "", pos);
  }
  if (!node->file || !node->where) {
    free(node->file);
    free(node->where);
    free(node);
    return NULL;
  }
  return node;
}

void sk_cfg_free(sk_cfg *node) {
  if (!node) return;
  for (int i = 0; i < node->n; ++i) {
    if (node->keys) free(node->keys[i]);
    sk_cfg_free(node->items[i]);
  }
  for (int i = 0; i < node->n_asked; ++i) free(node->asked[i]);
  free(node->asked);
  free(node->keys);
  free(node->items);
  free(node->text);
  free(node->path);
  free(node->where);
  free(node->file);
  free(node);
}

/* Appends child (and its key for maps); takes ownership of `key` on success. */
static int node_append(sk_cfg *parent, char *key, sk_cfg *child) {
  if (parent->n == parent->cap) {
    int cap = parent->cap ? 2 * parent->cap : 4;
    sk_cfg **items = realloc(parent->items, (size_t)cap * sizeof *items);
    if (!items) return 0;
    parent->items = items;
    if (parent->kind == SK_CFG_MAP) {
      char **keys = realloc(parent->keys, (size_t)cap * sizeof *keys);
      if (!keys) return 0;
      parent->keys = keys;
    }
    parent->cap = cap;
  }
  if (parent->kind == SK_CFG_MAP) parent->keys[parent->n] = key;
  parent->items[parent->n++] = child;
  return 1;
}

static int map_find(const sk_cfg *map, const char *key) {
  if (!map || map->kind != SK_CFG_MAP) return -1;
  for (int i = 0; i < map->n; ++i)
    if (strcmp(map->keys[i], key) == 0) return i;
  return -1;
}

/* Recomputes the key paths of a subtree placed at `path`. */
static int assign_paths(sk_cfg *node, const char *path) {
  free(node->path);
  node->path = dup_s(path);
  if (!node->path) return 0;
  for (int i = 0; i < node->n; ++i) {
    char *child;
    if (node->kind == SK_CFG_MAP) {
      child = path[0] ? format_alloc("%s.%s", path, node->keys[i]) : dup_s(node->keys[i]);
    } else {
      char index[32];
      snprintf(index, sizeof index, "[%d]", i);
      child = format_alloc("%s%s", path, index);
    }
    int ok = child && assign_paths(node->items[i], child);
    free(child);
    if (!ok) return 0;
  }
  return 1;
}

/* "file:line" of a node (maps report missing keys this way), or its --set origin. */
static void where_line(const sk_cfg *node, char *buf, size_t n) {
  if (!node) {
    snprintf(buf, n, "configuration");
  } else if (node->line > 0) {
    snprintf(buf, n, "%s:%d", node->file, node->line);
  } else {
    snprintf(buf, n, "%s", node->where);
  }
}

/* Position of the key naming `child` (falls back to the child's own position). */
static void where_key(const sk_cfg *child, char *buf, size_t n) {
  if (child->key_line > 0) {
    snprintf(buf, n, "%s:%d:%d", child->file, child->key_line, child->key_col);
  } else {
    snprintf(buf, n, "%s", child->where);
  }
}

/* ---- parsing ---------------------------------------------------------------------------------------------- */

typedef struct {
  yaml_parser_t parser;
  const char *name;   /* file name used in positions */
  const char *origin; /* non-NULL for --set values: every node's position is this text */
} loader;

static sk_status parser_failure(loader *ld) {
  const yaml_parser_t *p = &ld->parser;
  const char *problem = p->problem ? p->problem : "malformed YAML";
  if (p->error == YAML_MEMORY_ERROR) return no_memory();
  if (ld->origin) {
    return sk_error_set(SK_ERR_INPUT, "%s: malformed value: %s", ld->origin, problem);
  }
  if (p->context) {
    return sk_error_set(SK_ERR_INPUT, "%s:%zu:%zu: %s (%s started at line %zu, column %zu)", ld->name,
                        p->problem_mark.line + 1, p->problem_mark.column + 1, problem, p->context,
                        p->context_mark.line + 1, p->context_mark.column + 1);
  }
  return sk_error_set(SK_ERR_INPUT, "%s:%zu:%zu: %s", ld->name, p->problem_mark.line + 1,
                      p->problem_mark.column + 1, problem);
}

static sk_status next_event(loader *ld, yaml_event_t *ev) {
  if (!yaml_parser_parse(&ld->parser, ev)) return parser_failure(ld);
  return SK_OK;
}

static sk_status unsupported(loader *ld, const yaml_event_t *ev, const char *what) {
  if (ld->origin) return sk_error_set(SK_ERR_INPUT, "%s: %s are not supported", ld->origin, what);
  return sk_error_set(SK_ERR_INPUT, "%s:%zu:%zu: %s are not supported in stickslip scenes", ld->name,
                      ev->start_mark.line + 1, ev->start_mark.column + 1, what);
}

static sk_cfg *node_from_event(loader *ld, const yaml_event_t *ev, sk_cfg_kind kind) {
  if (ld->origin) return node_new(kind, ld->name, ld->origin, 0, 0); /* --set values have no file position */
  return node_new(kind, ld->name, NULL, (int)ev->start_mark.line + 1, (int)ev->start_mark.column + 1);
}

/* Builds the node that starts with event `ev` (owned by the caller), reading events up to its end. */
static sk_status parse_node(loader *ld, const yaml_event_t *ev, int depth, sk_cfg **out) {
  *out = NULL;
  if (depth > MAX_DEPTH) return unsupported(ld, ev, "nesting levels beyond 200");
  switch (ev->type) {
    case YAML_ALIAS_EVENT:
      return unsupported(ld, ev, "aliases (*name)");
    case YAML_SCALAR_EVENT: {
      if (ev->data.scalar.anchor) return unsupported(ld, ev, "anchors (&name)");
      sk_cfg *node = node_from_event(ld, ev, SK_CFG_SCALAR);
      if (!node) return no_memory();
      node->text = dup_n((const char *)ev->data.scalar.value, ev->data.scalar.length);
      node->style = ev->data.scalar.style;
      if (!node->text) {
        sk_cfg_free(node);
        return no_memory();
      }
      *out = node;
      return SK_OK;
    }
    case YAML_SEQUENCE_START_EVENT:
    case YAML_MAPPING_START_EVENT: break;
    default: return sk_error_set(SK_ERR_INTERNAL, "%s: unexpected YAML event %d", ld->name, (int)ev->type);
  }

  int is_map = ev->type == YAML_MAPPING_START_EVENT;
  if (is_map ? ev->data.mapping_start.anchor != NULL : ev->data.sequence_start.anchor != NULL) {
    return unsupported(ld, ev, "anchors (&name)");
  }
  sk_cfg *node = node_from_event(ld, ev, is_map ? SK_CFG_MAP : SK_CFG_SEQ);
  if (!node) return no_memory();
  node->flow = is_map ? ev->data.mapping_start.style == YAML_FLOW_MAPPING_STYLE
                      : ev->data.sequence_start.style == YAML_FLOW_SEQUENCE_STYLE;
  yaml_event_type_t end_type = is_map ? YAML_MAPPING_END_EVENT : YAML_SEQUENCE_END_EVENT;
  sk_status status = SK_OK;
  for (;;) {
    yaml_event_t item;
    status = next_event(ld, &item);
    if (status != SK_OK) break;
    if (item.type == end_type) {
      yaml_event_delete(&item);
      break;
    }
    char *key = NULL;
    int key_line = 0, key_col = 0;
    if (is_map) {
      if (item.type != YAML_SCALAR_EVENT || item.data.scalar.anchor) {
        status = item.type == YAML_SCALAR_EVENT ? unsupported(ld, &item, "anchors (&name)")
                                                : unsupported(ld, &item, "keys that are not plain scalars");
        yaml_event_delete(&item);
        break;
      }
      key = dup_n((const char *)item.data.scalar.value, item.data.scalar.length);
      key_line = (int)item.start_mark.line + 1;
      key_col = (int)item.start_mark.column + 1;
      yaml_event_delete(&item);
      if (!key) {
        status = no_memory();
        break;
      }
      int previous = map_find(node, key);
      if (previous >= 0) {
        if (ld->origin) {
          status = sk_error_set(SK_ERR_INPUT, "%s: duplicate key '%s'", ld->origin, key);
        } else {
          status = sk_error_set(SK_ERR_INPUT, "%s:%d:%d: duplicate key '%s' (first given at line %d)", ld->name,
                                key_line, key_col, key, node->items[previous]->key_line);
        }
        free(key);
        break;
      }
      status = next_event(ld, &item);
      if (status != SK_OK) {
        free(key);
        break;
      }
    }
    sk_cfg *child = NULL;
    status = parse_node(ld, &item, depth + 1, &child);
    yaml_event_delete(&item);
    if (status == SK_OK && !node_append(node, key, child)) status = no_memory();
    if (status != SK_OK) {
      free(key);
      sk_cfg_free(child);
      break;
    }
    if (ld->origin == NULL) {
      child->key_line = key_line;
      child->key_col = key_col;
    }
  }
  if (status != SK_OK) {
    sk_cfg_free(node);
    return status;
  }
  *out = node;
  return SK_OK;
}

/* Parses one YAML document. `origin` non-NULL: a --set value (any kind, empty text is an empty scalar). */
static sk_status parse_text(const char *text, size_t length, const char *name, const char *origin, sk_cfg **root) {
  loader ld = {.name = name, .origin = origin};
  *root = NULL;
  if (!yaml_parser_initialize(&ld.parser)) return no_memory();
  yaml_parser_set_input_string(&ld.parser, (const unsigned char *)text, length);

  sk_status status = SK_OK;
  sk_cfg *node = NULL;
  yaml_event_t ev;
  int stage = 0; /* 0: stream start, 1: document start or stream end, 2: root, 3: document end, 4: stream end */
  while (status == SK_OK && stage < 5) {
    status = next_event(&ld, &ev);
    if (status != SK_OK) break;
    switch (stage) {
      case 0: stage = 1; break; /* STREAM_START */
      case 1:
        if (ev.type == YAML_STREAM_END_EVENT) {
          stage = 5; /* empty document */
        } else {
          stage = 2;
        }
        break;
      case 2:
        status = parse_node(&ld, &ev, 0, &node);
        stage = 3;
        break;
      case 3: stage = 4; break; /* DOCUMENT_END */
      case 4:
        if (ev.type != YAML_STREAM_END_EVENT) {
          status = origin ? sk_error_set(SK_ERR_INPUT, "%s: several YAML documents in one value", origin)
                          : sk_error_set(SK_ERR_INPUT, "%s:%zu:%zu: several YAML documents in one file are not "
                                                       "supported", name, ev.start_mark.line + 1,
                                         ev.start_mark.column + 1);
        }
        stage = 5;
        break;
    }
    yaml_event_delete(&ev);
  }
  yaml_parser_delete(&ld.parser);
  if (status != SK_OK) {
    sk_cfg_free(node);
    return status;
  }
  if (!node) {
    if (!origin) return sk_error_set(SK_ERR_INPUT, "%s:1:1: the file is empty, expected a map of settings", name);
    node = node_new(SK_CFG_SCALAR, name, origin, 0, 0);
    if (!node || !(node->text = dup_s(""))) {
      sk_cfg_free(node);
      return no_memory();
    }
    node->style = YAML_PLAIN_SCALAR_STYLE;
  }
  if (!origin && node->kind != SK_CFG_MAP) {
    status = sk_error_set(SK_ERR_INPUT, "%s: the document must be a map of settings (key: value), got a %s",
                          node->where, node->kind == SK_CFG_SEQ ? "sequence" : "scalar");
    sk_cfg_free(node);
    return status;
  }
  if (!assign_paths(node, "")) {
    sk_cfg_free(node);
    return no_memory();
  }
  *root = node;
  return SK_OK;
}

sk_status sk_cfg_parse_string(const char *text, const char *name, sk_cfg **root) {
  if (!root) return sk_error_set(SK_ERR_INTERNAL, "sk_cfg_parse_string: NULL root");
  *root = NULL;
  if (!text) return sk_error_set(SK_ERR_INTERNAL, "sk_cfg_parse_string: NULL text");
  return parse_text(text, strlen(text), name ? name : "<string>", NULL, root);
}

sk_status sk_cfg_load(const char *path, sk_cfg **root) {
  if (!root) return sk_error_set(SK_ERR_INTERNAL, "sk_cfg_load: NULL root");
  *root = NULL;
  char *text = NULL;
  size_t length = 0;
  SK_TRY(sk_read_text_file(path, "scene file", SK_MAX_TEXT_FILE_BYTES, &text, &length));
  sk_status status = parse_text(text, length, path, NULL, root);
  free(text);
  return status;
}

/* ---- overrides -------------------------------------------------------------------------------------------- */

static int is_index(const char *s) {
  if (!*s) return 0;
  for (; *s; ++s)
    if (*s < '0' || *s > '9') return 0;
  return 1;
}

sk_status sk_cfg_set(sk_cfg *root, const char *assignment) {
  if (!root || root->kind != SK_CFG_MAP) return sk_error_set(SK_ERR_INTERNAL, "sk_cfg_set: root is not a map");
  const char *eq = assignment ? strchr(assignment, '=') : NULL;
  if (!eq) {
    return sk_error_set(SK_ERR_INPUT, "--set '%s': expected KEY=VALUE, e.g. contact.mu=0.3",
                        assignment ? assignment : "");
  }
  /* Normalise the key: trim blanks, "a[0]" → "a.0". */
  size_t raw_len = (size_t)(eq - assignment);
  char *key = malloc(2 * raw_len + 1);
  if (!key) return no_memory();
  size_t k = 0;
  const char *begin = assignment, *end = eq;
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
    return sk_error_set(SK_ERR_INPUT, "--set '%s': %s in the key path", assignment, bracket_error);
  }
  key[k] = '\0';
  int bad = k == 0 || key[0] == '.' || key[k - 1] == '.' || strstr(key, "..") != NULL;
  if (bad) {
    free(key);
    return sk_error_set(SK_ERR_INPUT, "--set '%s': the key path has an empty part (expected e.g. contact.mu=0.3)",
                        assignment);
  }

  char *origin = format_alloc("%s%s", "--set ", key);
  if (!origin) {
    free(key);
    return no_memory();
  }
  const char *value = eq + 1;
  sk_cfg *new_node = NULL;
  sk_status status = parse_text(value, strlen(value), root->file, origin, &new_node);

  sk_cfg *cur = root;
  char *segment = key;
  while (status == SK_OK) {
    char *dot = strchr(segment, '.');
    int last = dot == NULL;
    if (dot) *dot = '\0';
    if (cur->kind == SK_CFG_MAP) {
      int i = map_find(cur, segment);
      if (last) {
        if (i >= 0) {
          sk_cfg_free(cur->items[i]);
          cur->items[i] = new_node;
        } else {
          char *name = dup_s(segment);
          if (!name || !node_append(cur, name, new_node)) {
            free(name);
            status = no_memory();
            break;
          }
        }
        new_node = NULL; /* owned by the tree now */
        break;
      }
      if (i < 0) {
        sk_cfg *map = node_new(SK_CFG_MAP, root->file, origin, 0, 0);
        char *name = dup_s(segment);
        if (!map || !name || !node_append(cur, name, map)) {
          sk_cfg_free(map);
          free(name);
          status = no_memory();
          break;
        }
        i = cur->n - 1;
      }
      cur = cur->items[i];
    } else if (cur->kind == SK_CFG_SEQ) {
      if (!is_index(segment)) {
        status = sk_error_set(SK_ERR_INPUT, "%s: '%s' (%s) is a sequence; expected an index, got '%s'", origin,
                              cur->path, cur->where, segment);
        break;
      }
      long i = strtol(segment, NULL, 10);
      if (i >= cur->n) {
        status = sk_error_set(SK_ERR_INPUT, "%s: index %ld is out of range: '%s' (%s) has %d entries", origin, i,
                              cur->path, cur->where, cur->n);
        break;
      }
      if (last) {
        sk_cfg_free(cur->items[i]);
        cur->items[i] = new_node;
        new_node = NULL;
        break;
      }
      cur = cur->items[i];
    } else {
      status = sk_error_set(SK_ERR_INPUT, "%s: '%s' (%s) is a scalar, it has no entry '%s'", origin, cur->path,
                            cur->where, segment);
      break;
    }
    segment = dot + 1;
  }
  sk_cfg_free(new_node);
  free(origin);
  free(key);
  /* New nodes (and intermediate maps) need their key paths. */
  if (status == SK_OK && !assign_paths(root, "")) status = no_memory();
  return status;
}

/* ---- navigation ------------------------------------------------------------------------------------------- */

sk_cfg_kind sk_cfg_kind_of(const sk_cfg *node) { return node ? node->kind : SK_CFG_SCALAR; }
const char *sk_cfg_path(const sk_cfg *node) { return node ? node->path : ""; }
const char *sk_cfg_where(const sk_cfg *node) { return node ? node->where : "configuration"; }

/* Remembers that the program asked `map` for `key`: suggestions for misspelt keys come from these. */
static void remember_asked(sk_cfg *map, const char *key) {
  for (int i = 0; i < map->n_asked; ++i)
    if (strcmp(map->asked[i], key) == 0) return;
  if (map->n_asked == map->cap_asked) {
    int cap = map->cap_asked ? 2 * map->cap_asked : 8;
    char **asked = realloc(map->asked, (size_t)cap * sizeof *asked);
    if (!asked) return; /* suggestions are best effort */
    map->asked = asked;
    map->cap_asked = cap;
  }
  char *copy = dup_s(key);
  if (copy) map->asked[map->n_asked++] = copy;
}

const sk_cfg *sk_cfg_get(const sk_cfg *map, const char *key) {
  if (!map || !key || map->kind != SK_CFG_MAP) return NULL;
  sk_cfg *mutable_map = (sk_cfg *)map; /* usage tracking is not part of the logical value */
  remember_asked(mutable_map, key);
  int i = map_find(map, key);
  if (i < 0) return NULL;
  map->items[i]->used = 1;
  return map->items[i];
}

int sk_cfg_size(const sk_cfg *node) { return node && node->kind != SK_CFG_SCALAR ? node->n : 0; }

const sk_cfg *sk_cfg_at(const sk_cfg *node, int i) {
  if (!node || node->kind == SK_CFG_SCALAR || i < 0 || i >= node->n) return NULL;
  node->items[i]->used = 1;
  return node->items[i];
}

const char *sk_cfg_key_at(const sk_cfg *map, int i) {
  if (!map || map->kind != SK_CFG_MAP || i < 0 || i >= map->n) return NULL;
  return map->keys[i];
}

const char *sk_cfg_scalar(const sk_cfg *node) { return node && node->kind == SK_CFG_SCALAR ? node->text : NULL; }

void sk_cfg_mark_used(const sk_cfg *node) {
  if (!node) return;
  ((sk_cfg *)node)->used = 1;
  for (int i = 0; i < node->n; ++i) sk_cfg_mark_used(node->items[i]);
}

/* ---- typed getters ---------------------------------------------------------------------------------------- */

static const char *kind_text(const sk_cfg *node) {
  return node->kind == SK_CFG_MAP ? "a map" : node->kind == SK_CFG_SEQ ? "a sequence" : "a scalar";
}

static void key_path(const sk_cfg *map, const char *key, char *buf, size_t n) {
  if (map && map->path && map->path[0]) {
    snprintf(buf, n, "%s.%s", map->path, key);
  } else {
    snprintf(buf, n, "%s", key);
  }
}

/* Finds `key`; absent and required → error naming the map's position. *node NULL when absent. */
static int is_null(const sk_cfg *node) {
  return node->kind == SK_CFG_SCALAR && node->style == YAML_PLAIN_SCALAR_STYLE &&
         (node->text[0] == '\0' || strcmp(node->text, "~") == 0 || strcmp(node->text, "null") == 0);
}

static int edit_distance(const char *a, const char *b);

/* A key of `map` within edit distance 2 of `key` (a misspelling of the required key), or NULL. */
static const sk_cfg *misspelt_key(const sk_cfg *map, const char *key) {
  for (int i = 0; map && map->kind == SK_CFG_MAP && i < map->n; ++i)
    if (strcmp(map->keys[i], key) != 0 && edit_distance(map->keys[i], key) <= 2 && strlen(key) > 2)
      return map->items[i];
  return NULL;
}

static sk_status lookup(const sk_cfg *map, const char *key, int required, const sk_cfg **node) {
  *node = NULL;
  const sk_cfg *empty = NULL; /* "section:" with nothing below (or ~, null): an empty section */
  if (map && is_null(map)) {
    empty = map;
    map = NULL;
  }
  if (map && map->kind != SK_CFG_MAP) {
    return sk_error_set(SK_ERR_INPUT, "%s: '%s' should be a map (key: value), got %s", map->where,
                        map->path[0] ? map->path : "(root)", kind_text(map));
  }
  *node = sk_cfg_get(map, key);
  if (!*node && required) {
    char where[600], path[600];
    if (empty) {
      /* The empty section still knows where it is and what it is called: name both. */
      where_key(empty, where, sizeof where);
      key_path(empty, key, path, sizeof path);
      return sk_error_set(SK_ERR_INPUT, "%s: '%s' is empty; missing key '%s'", where, empty->path, path);
    }
    key_path(map, key, path, sizeof path);
    const sk_cfg *near = misspelt_key(map, key);
    if (near) {
      /* name the line of the misspelt key, where the user will look */
      where_key(near, where, sizeof where);
      return sk_error_set(SK_ERR_INPUT, "%s: missing key '%s' ('%s' is there: a misspelling?)", where, path,
                          near->path);
    }
    where_line(map, where, sizeof where);
    return sk_error_set(SK_ERR_INPUT, "%s: missing key '%s'", where, path);
  }
  return SK_OK;
}

static sk_status type_error(const sk_cfg *node, const char *expected) {
  if (node->kind != SK_CFG_SCALAR) {
    return sk_error_set(SK_ERR_INPUT, "%s: key '%s' expects %s, got %s", node->where, node->path, expected,
                        kind_text(node));
  }
  return sk_error_set(SK_ERR_INPUT, "%s: key '%s' expects %s, got '%s'", node->where, node->path, expected,
                      node->text);
}

static int text_equal_nocase(const char *a, const char *b) {
  for (; *a && *b; ++a, ++b) {
    char ca = (*a >= 'A' && *a <= 'Z') ? (char)(*a - 'A' + 'a') : *a;
    if (ca != *b) return 0;
  }
  return *a == *b;
}

static int parse_number(const char *s, double *v) {
  if (!s || !*s) return 0;
  const char *body = (*s == '+' || *s == '-') ? s + 1 : s;
  if (text_equal_nocase(body, ".inf")) {
    *v = *s == '-' ? -INFINITY : INFINITY;
    return 1;
  }
  if (text_equal_nocase(s, ".nan")) {
    *v = NAN;
    return 1;
  }
  char *end = NULL;
  errno = 0;
  double x = strtod(s, &end);
  if (end == s || *end != '\0') return 0;
  if (errno == ERANGE && fabs(x) > 1.0) x = copysign(INFINITY, x); /* 1e999: out of range, refused as non-finite */
  *v = x;
  return 1;
}

/* Every number of a scene is read here, so this is the one place non-finite values are refused: a nan or inf
 * velocity, load, tolerance or end time would otherwise be accepted by `check` and surface later as a Newton
 * failure, a run of 0 steps reported "ok", or silently wrong output. */
sk_status sk_cfg_as_double(const sk_cfg *node, double *out) {
  double value;
  if (!node || node->kind != SK_CFG_SCALAR || !parse_number(node->text, &value)) {
    return node ? type_error(node, "a number") : sk_error_set(SK_ERR_INPUT, "missing number");
  }
  if (!isfinite(value)) return type_error(node, "a finite number");
  /* a subnormal (0 < |x| < 2.2e-308) is never a meant quantity: a density of 5e-324 gives a mass matrix of round-off
   * and a run that stalls in step cuts instead of an error */
  if (fpclassify(value) == FP_SUBNORMAL) return type_error(node, "0 or a number of normal size (|x| >= 2.2e-308)");
  *out = value;
  return SK_OK;
}

sk_status sk_cfg_as_int(const sk_cfg *node, int *out) {
  double x;
  if (!node || node->kind != SK_CFG_SCALAR || !parse_number(node->text, &x) || x != floor(x) || x < INT_MIN ||
      x > INT_MAX) {
    return node ? type_error(node, "an integer") : sk_error_set(SK_ERR_INPUT, "missing integer");
  }
  *out = (int)x;
  return SK_OK;
}

sk_status sk_cfg_double(const sk_cfg *map, const char *key, int required, double dflt, double *out) {
  const sk_cfg *node;
  SK_TRY(lookup(map, key, required, &node));
  if (!node) {
    *out = dflt;
    return SK_OK;
  }
  return sk_cfg_as_double(node, out);
}

sk_status sk_cfg_int(const sk_cfg *map, const char *key, int required, int dflt, int *out) {
  const sk_cfg *node;
  SK_TRY(lookup(map, key, required, &node));
  if (!node) {
    *out = dflt;
    return SK_OK;
  }
  return sk_cfg_as_int(node, out);
}

sk_status sk_cfg_bool(const sk_cfg *map, const char *key, int required, int dflt, int *out) {
  const sk_cfg *node;
  SK_TRY(lookup(map, key, required, &node));
  if (!node) {
    *out = dflt;
    return SK_OK;
  }
  static const char *const truths[] = {"true", "yes", "on"};
  static const char *const lies[] = {"false", "no", "off"};
  if (node->kind == SK_CFG_SCALAR) {
    for (int i = 0; i < 3; ++i) {
      if (text_equal_nocase(node->text, truths[i])) {
        *out = 1;
        return SK_OK;
      }
      if (text_equal_nocase(node->text, lies[i])) {
        *out = 0;
        return SK_OK;
      }
    }
  }
  return type_error(node, "a boolean (true or false)");
}

sk_status sk_cfg_string(const sk_cfg *map, const char *key, int required, const char *dflt, const char **out) {
  const sk_cfg *node;
  SK_TRY(lookup(map, key, required, &node));
  if (!node) {
    *out = dflt;
    return SK_OK;
  }
  if (node->kind != SK_CFG_SCALAR) return type_error(node, "a string");
  *out = node->text;
  return SK_OK;
}

sk_status sk_cfg_vector(const sk_cfg *map, const char *key, int required, int n, const double *dflt, double *out) {
  const sk_cfg *node;
  SK_TRY(lookup(map, key, required, &node));
  if (!node) {
    for (int i = 0; dflt && i < n; ++i) out[i] = dflt[i];
    return SK_OK;
  }
  char expected[64];
  snprintf(expected, sizeof expected, "a sequence of %d numbers", n);
  if (node->kind != SK_CFG_SEQ) return type_error(node, expected);
  if (node->n != n) {
    return sk_error_set(SK_ERR_INPUT, "%s: key '%s' expects %s, got %d", node->where, node->path, expected, node->n);
  }
  for (int i = 0; i < n; ++i) SK_TRY(sk_cfg_as_double(sk_cfg_at(node, i), &out[i]));
  return SK_OK;
}

sk_status sk_cfg_choice(const sk_cfg *map, const char *key, int required, const char *const *choices, int dflt,
                        int *out) {
  const sk_cfg *node;
  SK_TRY(lookup(map, key, required, &node));
  if (!node) {
    *out = dflt;
    return SK_OK;
  }
  if (node->kind == SK_CFG_SCALAR) {
    for (int i = 0; choices[i]; ++i) {
      if (strcmp(node->text, choices[i]) == 0) {
        *out = i;
        return SK_OK;
      }
    }
  }
  char allowed[1024] = "one of ";
  for (int i = 0; choices[i]; ++i) {
    size_t used = strlen(allowed);
    snprintf(allowed + used, sizeof allowed - used, "%s'%s'", i ? ", " : "", choices[i]);
  }
  return type_error(node, allowed);
}

/* ---- unused keys ------------------------------------------------------------------------------------------ */

/* Optimal string alignment distance (a transposition counts as one edit). Long keys: no suggestion. */
static int edit_distance(const char *a, const char *b) {
  enum { MAXLEN = 64 };
  size_t la = strlen(a), lb = strlen(b);
  if (la >= MAXLEN || lb >= MAXLEN) return INT_MAX;
  int d[MAXLEN + 1][MAXLEN + 1];
  for (size_t i = 0; i <= la; ++i) d[i][0] = (int)i;
  for (size_t j = 0; j <= lb; ++j) d[0][j] = (int)j;
  for (size_t i = 1; i <= la; ++i) {
    for (size_t j = 1; j <= lb; ++j) {
      int cost = a[i - 1] != b[j - 1];
      int best = d[i - 1][j] + 1;
      if (d[i][j - 1] + 1 < best) best = d[i][j - 1] + 1;
      if (d[i - 1][j - 1] + cost < best) best = d[i - 1][j - 1] + cost;
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] && d[i - 2][j - 2] + 1 < best) {
        best = d[i - 2][j - 2] + 1;
      }
      d[i][j] = best;
    }
  }
  return d[la][lb];
}

static const char *suggestion(const sk_cfg *map, const char *key) {
  const char *best = NULL;
  int best_distance = 3; /* suggest only within distance 2 */
  for (int i = 0; i < map->n_asked; ++i) {
    const char *candidate = map->asked[i];
    if (strcmp(candidate, key) == 0) continue;
    int d = edit_distance(key, candidate);
    if (d < best_distance && (size_t)d < strlen(candidate)) {
      best = candidate;
      best_distance = d;
    }
  }
  return best;
}

static sk_status find_unused(const sk_cfg *node) {
  for (int i = 0; i < node->n; ++i) {
    const sk_cfg *child = node->items[i];
    if (node->kind == SK_CFG_MAP && !child->used) {
      char where[600];
      where_key(child, where, sizeof where);
      const char *hint = suggestion(node, node->keys[i]);
      if (hint) {
        return sk_error_set(SK_ERR_INPUT, "%s: unknown key '%s' (did you mean '%s'?)", where, child->path, hint);
      }
      return sk_error_set(SK_ERR_INPUT, "%s: unknown key '%s'", where, child->path);
    }
    /* Unread sequence elements are not keys: nothing to report inside them. */
    if (child->used) SK_TRY(find_unused(child));
  }
  return SK_OK;
}

sk_status sk_cfg_check_unused(const sk_cfg *root) { return root ? find_unused(root) : SK_OK; }

/* ---- paths ------------------------------------------------------------------------------------------------ */

sk_status sk_cfg_resolve_path(const sk_cfg *node, const char *relative, char *out, size_t out_size) {
  if (!relative || !out || out_size == 0) return sk_error_set(SK_ERR_INTERNAL, "sk_cfg_resolve_path: bad arguments");
  const char *file = node && node->file ? node->file : "";
  const char *slash = strrchr(file, '/');
  int n;
  if (relative[0] == '/' || !slash) {
    n = snprintf(out, out_size, "%s", relative);
  } else {
    n = snprintf(out, out_size, "%.*s/%s", (int)(slash - file), file, relative);
  }
  if (n < 0 || (size_t)n >= out_size) {
    return sk_error_set(SK_ERR_INPUT, "%s: path '%s' is too long (limit %zu characters)", sk_cfg_where(node),
                        relative, out_size - 1);
  }
  return SK_OK;
}

/* ---- writing ---------------------------------------------------------------------------------------------- */

static int emit_node(yaml_emitter_t *em, const sk_cfg *node) {
  yaml_event_t ev;
  if (node->kind == SK_CFG_SCALAR) {
    yaml_scalar_style_t style = node->style == YAML_PLAIN_SCALAR_STYLE ? YAML_ANY_SCALAR_STYLE : node->style;
    if (!yaml_scalar_event_initialize(&ev, NULL, NULL, (yaml_char_t *)node->text, (int)strlen(node->text), 1, 1,
                                      style)) {
      return 0;
    }
    return yaml_emitter_emit(em, &ev);
  }
  int ok = node->kind == SK_CFG_MAP
               ? yaml_mapping_start_event_initialize(&ev, NULL, NULL, 1,
                                                     node->flow ? YAML_FLOW_MAPPING_STYLE : YAML_BLOCK_MAPPING_STYLE)
               : yaml_sequence_start_event_initialize(
                     &ev, NULL, NULL, 1, node->flow ? YAML_FLOW_SEQUENCE_STYLE : YAML_BLOCK_SEQUENCE_STYLE);
  if (!ok || !yaml_emitter_emit(em, &ev)) return 0;
  for (int i = 0; i < node->n; ++i) {
    if (node->kind == SK_CFG_MAP) {
      if (!yaml_scalar_event_initialize(&ev, NULL, NULL, (yaml_char_t *)node->keys[i], (int)strlen(node->keys[i]),
                                        1, 1, YAML_ANY_SCALAR_STYLE) ||
          !yaml_emitter_emit(em, &ev)) {
        return 0;
      }
    }
    if (!emit_node(em, node->items[i])) return 0;
  }
  ok = node->kind == SK_CFG_MAP ? yaml_mapping_end_event_initialize(&ev) : yaml_sequence_end_event_initialize(&ev);
  return ok && yaml_emitter_emit(em, &ev);
}

sk_status sk_cfg_write(const sk_cfg *root, FILE *out) {
  if (!root || !out) return sk_error_set(SK_ERR_INTERNAL, "sk_cfg_write: NULL argument");
  yaml_emitter_t em;
  yaml_event_t ev;
  if (!yaml_emitter_initialize(&em)) return no_memory();
  yaml_emitter_set_output_file(&em, out);
  yaml_emitter_set_unicode(&em, 1);
  yaml_emitter_set_width(&em, 120);
  int ok = yaml_stream_start_event_initialize(&ev, YAML_UTF8_ENCODING) && yaml_emitter_emit(&em, &ev) &&
           yaml_document_start_event_initialize(&ev, NULL, NULL, NULL, 1) && yaml_emitter_emit(&em, &ev) &&
           emit_node(&em, root) && yaml_document_end_event_initialize(&ev, 1) && yaml_emitter_emit(&em, &ev) &&
           yaml_stream_end_event_initialize(&ev) && yaml_emitter_emit(&em, &ev) && yaml_emitter_flush(&em);
  sk_status status = SK_OK;
  if (!ok) {
    status = sk_error_set(SK_ERR_IO, "cannot write the configuration as YAML: %s",
                          em.problem ? em.problem : "write error");
  }
  yaml_emitter_delete(&em);
  if (status == SK_OK && ferror(out)) status = sk_error_set(SK_ERR_IO, "cannot write the configuration as YAML");
  return status;
}

sk_status sk_cfg_write_file(const sk_cfg *root, const char *path) {
  FILE *f = fopen(path, "w");
  if (!f) return sk_error_set(SK_ERR_IO, "cannot create '%s': %s", path, strerror(errno));
  sk_status status = sk_cfg_write(root, f);
  if (fclose(f) != 0 && status == SK_OK) status = sk_error_set(SK_ERR_IO, "cannot write '%s'", path);
  if (status != SK_OK) sk_error_prefix(status, "%s: ", path);
  return status;
}
