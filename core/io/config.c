/* The scene configuration tree: libyaml events → nodes with key paths and source positions, and paths relative to
 * the scene file. Reading (typed getters, unknown keys) is config_get.c's, overrides config_set.c's, output
 * config_write.c's; the node is config_tree.h's. */
#define _POSIX_C_SOURCE 200809L

#include "stickslip/config.h"
#include "stickslip/files.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "config_tree.h"

enum { MAX_DEPTH = 200 }; /* deeper nesting is surely an error and would only risk the stack */

/* ---- small helpers ---------------------------------------------------------------------------------------- */

char *sk_cfgi_dup_n(const char *s, size_t n) {
  char *d = malloc(n + 1);
  if (d) {
    memcpy(d, s, n);
    d[n] = '\0';
  }
  return d;
}

char *sk_cfgi_dup(const char *s) { return sk_cfgi_dup_n(s, strlen(s)); }

char *sk_cfgi_format(const char *fmt, const char *a, const char *b) {
  size_t n = (size_t)snprintf(NULL, 0, fmt, a, b) + 1;
  char *s = malloc(n);
  if (s) snprintf(s, n, fmt, a, b);
  return s;
}

sk_status sk_cfgi_no_memory(void) {
  return sk_error_set(SK_ERR_NOMEM, "out of memory while reading the configuration");
}

sk_cfg *sk_cfgi_node_new(sk_cfg_kind kind, const char *file, const char *origin, int line, int col) {
  sk_cfg *node = calloc(1, sizeof *node);
  if (!node) return NULL;
  node->kind = kind;
  node->line = line;
  node->col = col;
  node->file = sk_cfgi_dup(file ? file : "");
  if (origin) {
    node->where = sk_cfgi_dup(origin);
  } else {
    char pos[64];
    snprintf(pos, sizeof pos, "%d:%d", line, col);
    node->where = sk_cfgi_format("%s:%s", node->file ? node->file : "", pos);
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
  for (int i = 0; i < node->n_asked; ++i) {
    free(node->asked[i].key);
    free(node->asked[i].dflt);
    free(node->asked[i].meaning);
  }
  free(node->asked);
  for (int i = 0; i < node->n_absent; ++i) {
    free(node->absent_keys[i]);
    sk_cfg_free(node->absent[i]);
  }
  free(node->absent_keys);
  free(node->absent);
  free(node->keys);
  free(node->items);
  free(node->text);
  free(node->path);
  free(node->where);
  free(node->file);
  free(node);
}

/* Appends child (and its key for maps); takes ownership of `key` on success. */
int sk_cfgi_append(sk_cfg *parent, char *key, sk_cfg *child) {
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

int sk_cfgi_find(const sk_cfg *map, const char *key) {
  if (!map || map->kind != SK_CFG_MAP) return -1;
  for (int i = 0; i < map->n; ++i)
    if (strcmp(map->keys[i], key) == 0) return i;
  return -1;
}

/* Recomputes the key paths of a subtree placed at `path`. */
int sk_cfgi_assign_paths(sk_cfg *node, const char *path) {
  free(node->path);
  node->path = sk_cfgi_dup(path);
  if (!node->path) return 0;
  for (int i = 0; i < node->n; ++i) {
    char *child;
    if (node->kind == SK_CFG_MAP) {
      child = path[0] ? sk_cfgi_format("%s.%s", path, node->keys[i]) : sk_cfgi_dup(node->keys[i]);
    } else {
      char index[32];
      snprintf(index, sizeof index, "[%d]", i);
      child = sk_cfgi_format("%s%s", path, index);
    }
    int ok = child && sk_cfgi_assign_paths(node->items[i], child);
    free(child);
    if (!ok) return 0;
  }
  return 1;
}

/* A plain ~, null or empty scalar: an empty section where a map is expected. */
int sk_cfgi_is_null(const sk_cfg *node) {
  return node->kind == SK_CFG_SCALAR && node->style == YAML_PLAIN_SCALAR_STYLE &&
         (node->text[0] == '\0' || strcmp(node->text, "~") == 0 || strcmp(node->text, "null") == 0);
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
  if (p->error == YAML_MEMORY_ERROR) return sk_cfgi_no_memory();
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
  if (ld->origin) return sk_cfgi_node_new(kind, ld->name, ld->origin, 0, 0); /* --set values have no file position */
  return sk_cfgi_node_new(kind, ld->name, NULL, (int)ev->start_mark.line + 1, (int)ev->start_mark.column + 1);
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
      if (!node) return sk_cfgi_no_memory();
      node->text = sk_cfgi_dup_n((const char *)ev->data.scalar.value, ev->data.scalar.length);
      node->style = ev->data.scalar.style;
      if (!node->text) {
        sk_cfg_free(node);
        return sk_cfgi_no_memory();
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
  if (!node) return sk_cfgi_no_memory();
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
      key = sk_cfgi_dup_n((const char *)item.data.scalar.value, item.data.scalar.length);
      key_line = (int)item.start_mark.line + 1;
      key_col = (int)item.start_mark.column + 1;
      yaml_event_delete(&item);
      if (!key) {
        status = sk_cfgi_no_memory();
        break;
      }
      int previous = sk_cfgi_find(node, key);
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
    if (status == SK_OK && !sk_cfgi_append(node, key, child)) status = sk_cfgi_no_memory();
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
sk_status sk_cfgi_parse_text(const char *text, size_t length, const char *name, const char *origin, sk_cfg **root) {
  loader ld = {.name = name, .origin = origin};
  *root = NULL;
  if (!yaml_parser_initialize(&ld.parser)) return sk_cfgi_no_memory();
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
    node = sk_cfgi_node_new(SK_CFG_SCALAR, name, origin, 0, 0);
    if (!node || !(node->text = sk_cfgi_dup(""))) {
      sk_cfg_free(node);
      return sk_cfgi_no_memory();
    }
    node->style = YAML_PLAIN_SCALAR_STYLE;
  }
  if (!origin && node->kind != SK_CFG_MAP) {
    status = sk_error_set(SK_ERR_INPUT, "%s: the document must be a map of settings (key: value), got a %s",
                          node->where, node->kind == SK_CFG_SEQ ? "sequence" : "scalar");
    sk_cfg_free(node);
    return status;
  }
  if (!sk_cfgi_assign_paths(node, "")) {
    sk_cfg_free(node);
    return sk_cfgi_no_memory();
  }
  *root = node;
  return SK_OK;
}

sk_status sk_cfg_parse_string(const char *text, const char *name, sk_cfg **root) {
  if (!root) return sk_error_set(SK_ERR_INTERNAL, "sk_cfg_parse_string: NULL root");
  *root = NULL;
  if (!text) return sk_error_set(SK_ERR_INTERNAL, "sk_cfg_parse_string: NULL text");
  return sk_cfgi_parse_text(text, strlen(text), name ? name : "<string>", NULL, root);
}

sk_status sk_cfg_load(const char *path, sk_cfg **root) {
  if (!root) return sk_error_set(SK_ERR_INTERNAL, "sk_cfg_load: NULL root");
  *root = NULL;
  char *text = NULL;
  size_t length = 0;
  sk_status status = sk_read_text_file(path, "scene file", SK_MAX_TEXT_FILE_BYTES, &text, &length);
  if (status != SK_OK) {
    /* A results folder given for its scene: say which file reruns it. */
    char inside[4096], message[1024];
    struct stat st;
    if (stat(path, &st) == 0 && S_ISDIR(st.st_mode) &&
        snprintf(inside, sizeof inside, "%s/scene.yaml", path) < (int)sizeof inside && access(inside, R_OK) == 0) {
      snprintf(message, sizeof message, "%s", sk_error_message());
      return sk_error_set(status, "%s (a results folder? its effective scene is %s)", message, inside);
    }
    return status;
  }
  status = sk_cfgi_parse_text(text, length, path, NULL, root);
  free(text);
  return status;
}


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
