/* Output of the configuration tree: the scene as YAML (the results' scene.yaml) and the listing of every key with
 * its value or default (`stickslip keys`). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <errno.h>

#include "config_tree.h"
#include "stickslip/text.h"

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
  if (!yaml_emitter_initialize(&em)) return sk_cfgi_no_memory();
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

/* ---- listing ---------------------------------------------------------------------------------------------------- */

/* A node as one line of YAML: collections in flow style, quoted scalars quoted again. */
static void flow_text(const sk_cfg *node, sk_text *b) {
  if (node->kind == SK_CFG_SCALAR) {
    int quoted = node->style == YAML_SINGLE_QUOTED_SCALAR_STYLE || node->style == YAML_DOUBLE_QUOTED_SCALAR_STYLE;
    if (!quoted) {
      sk_text_add(b, node->text);
      return;
    }
    sk_text_add(b, "\"");
    for (const char *c = node->text; *c; ++c) {
      char one[3] = {*c, 0, 0};
      if (*c == '"' || *c == '\\') {
        one[0] = '\\';
        one[1] = *c;
      }
      sk_text_add(b, one);
    }
    sk_text_add(b, "\"");
    return;
  }
  sk_text_add(b, node->kind == SK_CFG_MAP ? "{" : "[");
  for (int i = 0; i < node->n; ++i) {
    if (i) sk_text_add(b, ", ");
    if (node->kind == SK_CFG_MAP) {
      sk_text_add(b, node->keys[i]);
      sk_text_add(b, ": ");
    }
    flow_text(node->items[i], b);
  }
  sk_text_add(b, node->kind == SK_CFG_MAP ? "}" : "]");
}

static const asked_key *asked_of(const sk_cfg *map, const char *key) {
  for (int i = 0; i < map->n_asked; ++i)
    if (strcmp(map->asked[i].key, key) == 0) return &map->asked[i];
  return NULL;
}

/* A sequence is entered (its elements listed one by one) when it holds maps: bodies, boundary, contact, mesh. */
static int holds_maps(const sk_cfg *node) {
  for (int i = 0; node->kind == SK_CFG_SEQ && i < node->n; ++i)
    if (node->items[i]->kind == SK_CFG_MAP) return 1;
  return 0;
}

static int is_quantity(const asked_key *asked) {
  return asked && (asked->kind == READ_NUMBER || asked->kind == READ_VECTOR);
}

static void each_given(const sk_cfg *node, const asked_key *asked, void (*each)(void *, const sk_cfg_entry *),
                       void *ctx);

static void each_in_map(const sk_cfg *map, void (*each)(void *, const sk_cfg_entry *), void *ctx) {
  for (int i = 0; i < map->n; ++i) each_given(map->items[i], asked_of(map, map->keys[i]), each, ctx);
  for (int i = 0; i < map->n_asked; ++i) {
    const asked_key *asked = &map->asked[i];
    if (!asked->dflt || sk_cfgi_find(map, asked->key) >= 0) continue;
    int section = 0;
    for (int s = 0; s < map->n_absent && !section; ++s) section = strcmp(map->absent_keys[s], asked->key) == 0;
    if (section) continue;
    char *path = map->path && map->path[0] ? sk_cfgi_format("%s.%s", map->path, asked->key) : sk_cfgi_dup(asked->key);
    if (!path) continue;
    sk_cfg_entry entry = {.path = path, .value = asked->dflt, .given = 0, .literal = asked->literal,
                          .quantity = is_quantity(asked), .where = NULL, .meaning = asked->meaning};
    each(ctx, &entry);
    free(path);
  }
  for (int s = 0; s < map->n_absent; ++s) each_in_map(map->absent[s], each, ctx);
}

static void each_given(const sk_cfg *node, const asked_key *asked, void (*each)(void *, const sk_cfg_entry *),
                       void *ctx) {
  if (node->kind == SK_CFG_MAP && (node->n > 0 || node->n_asked > 0 || node->n_absent > 0)) {
    each_in_map(node, each, ctx);
    return;
  }
  if (holds_maps(node)) {
    for (int i = 0; i < node->n; ++i) each_given(node->items[i], NULL, each, ctx);
    return;
  }
  sk_text value = {0};
  flow_text(node, &value);
  sk_cfg_entry entry = {.path = node->path, .value = value.text ? value.text : "", .given = 1, .literal = 1,
                        .quantity = is_quantity(asked), .where = node->where, .meaning = asked ? asked->meaning : NULL};
  each(ctx, &entry);
  free(value.text);
}

void sk_cfg_each(const sk_cfg *root, void (*each)(void *ctx, const sk_cfg_entry *entry), void *ctx) {
  if (root && each) each_given(root, NULL, each, ctx);
}
