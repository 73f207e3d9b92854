/* Reading the configuration tree: navigation, typed getters (which remember what they were asked and the defaults
 * they gave, for suggestions and for sk_cfg_each_entry) and the unknown-key check. */
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "config_tree.h"
#include "stickslip/text.h"

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

/* ---- navigation ------------------------------------------------------------------------------------------- */

sk_cfg_kind sk_cfg_kind_of(const sk_cfg *node) { return node ? node->kind : SK_CFG_SCALAR; }
const char *sk_cfg_path(const sk_cfg *node) { return node ? node->path : ""; }
const char *sk_cfg_where(const sk_cfg *node) { return node ? node->where : "configuration"; }

/* The record of `key` among the keys the program asked `map` for (created on first ask), or NULL without memory:
 * suggestions for misspelt keys and the defaults of the listing come from these, so they are best effort. */
static asked_key *remember_asked(const sk_cfg *map, const char *key) {
  sk_cfg *m = (sk_cfg *)map; /* usage tracking is not part of the logical value */
  for (int i = 0; i < m->n_asked; ++i)
    if (strcmp(m->asked[i].key, key) == 0) return &m->asked[i];
  if (m->n_asked == m->cap_asked) {
    int cap = m->cap_asked ? 2 * m->cap_asked : 8;
    asked_key *asked = realloc(m->asked, (size_t)cap * sizeof *asked);
    if (!asked) return NULL;
    m->asked = asked;
    m->cap_asked = cap;
  }
  char *copy = sk_cfgi_dup(key);
  if (!copy) return NULL;
  m->asked[m->n_asked] = (asked_key){.key = copy, .kind = READ_ANY};
  return &m->asked[m->n_asked++];
}

/* What a typed getter knows of `key`: how it reads it and its default (dflt NULL: required or none). */
static void remember_default(const sk_cfg *map, const char *key, read_kind kind, const char *dflt) {
  if (!map || map->kind != SK_CFG_MAP) return;
  asked_key *asked = remember_asked(map, key);
  if (!asked) return;
  asked->kind = kind;
  free(asked->dflt);
  asked->dflt = dflt ? sk_cfgi_dup(dflt) : NULL;
  asked->literal = 1;
}

void sk_cfg_note_default(const sk_cfg *map, const char *key, const char *text, int literal, const char *meaning) {
  if (!map || map->kind != SK_CFG_MAP || !key) return;
  asked_key *asked = remember_asked(map, key);
  if (!asked) return;
  free(asked->dflt);
  free(asked->meaning);
  asked->dflt = text ? sk_cfgi_dup(text) : NULL;
  asked->meaning = meaning ? sk_cfgi_dup(meaning) : NULL;
  asked->literal = literal;
}

const sk_cfg *sk_cfg_section(const sk_cfg *map, const char *key) {
  const sk_cfg *given = sk_cfg_get(map, key);
  if (given || !map || map->kind != SK_CFG_MAP) return given;
  sk_cfg *m = (sk_cfg *)map; /* the stand-in is bookkeeping, like the asked keys: not part of the scene */
  for (int i = 0; i < m->n_absent; ++i)
    if (strcmp(m->absent_keys[i], key) == 0) return m->absent[i];
  sk_cfg *section = sk_cfgi_node_new(SK_CFG_MAP, m->file, m->where, m->line, m->col);
  char *name = sk_cfgi_dup(key);
  char *path = m->path && m->path[0] ? sk_cfgi_format("%s.%s", m->path, key) : sk_cfgi_dup(key);
  sk_cfg **absent = realloc(m->absent, (size_t)(m->n_absent + 1) * sizeof *absent);
  if (absent) m->absent = absent;
  char **keys = absent ? realloc(m->absent_keys, (size_t)(m->n_absent + 1) * sizeof *keys) : NULL;
  if (keys) m->absent_keys = keys;
  if (!section || !name || !path || !absent || !keys) {
    sk_cfg_free(section);
    free(name);
    free(path);
    return NULL; /* out of memory: read as an absent section, whose keys all take their defaults */
  }
  section->path = path;
  section->used = 1;
  m->absent[m->n_absent] = section;
  m->absent_keys[m->n_absent++] = name;
  return section;
}

const sk_cfg *sk_cfg_get(const sk_cfg *map, const char *key) {
  if (!map || !key || map->kind != SK_CFG_MAP) return NULL;
  remember_asked(map, key);
  int i = sk_cfgi_find(map, key);
  if (i < 0) return NULL;
  map->items[i]->used = 1;
  return map->items[i];
}

const sk_cfg *sk_cfg_peek(const sk_cfg *map, const char *key) {
  int i = map && key ? sk_cfgi_find(map, key) : -1;
  return i >= 0 ? map->items[i] : NULL;
}

const sk_cfg *sk_cfg_peek_at(const sk_cfg *node, int i) {
  return node && node->kind != SK_CFG_SCALAR && i >= 0 && i < node->n ? node->items[i] : NULL;
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

/* A key of `map` within edit distance 2 of `key` (a misspelling of the required key), or NULL. */
static const sk_cfg *misspelt_key(const sk_cfg *map, const char *key) {
  for (int i = 0; map && map->kind == SK_CFG_MAP && i < map->n; ++i) {
    sk_closest closest = SK_CLOSEST_NONE;
    sk_closest_offer(&closest, map->keys[i], key);
    if (closest.best && strlen(key) > 2) return map->items[i];
  }
  return NULL;
}

static sk_status lookup(const sk_cfg *map, const char *key, int required, const sk_cfg **node) {
  *node = NULL;
  const sk_cfg *empty = NULL; /* "section:" with nothing below (or ~, null): an empty section */
  if (map && sk_cfgi_is_null(map)) {
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

/* "%.15g": the shortest text of the defaults as written in the code (1e-10, 0.1, 600). */
static void number_text(double x, char *buf, size_t n) { snprintf(buf, n, "%.15g", x); }

sk_status sk_cfg_double(const sk_cfg *map, const char *key, int required, double dflt, double *out) {
  char text[32];
  number_text(dflt, text, sizeof text);
  remember_default(map, key, READ_NUMBER, required ? NULL : text);
  const sk_cfg *node;
  SK_TRY(lookup(map, key, required, &node));
  if (!node) {
    *out = dflt;
    return SK_OK;
  }
  return sk_cfg_as_double(node, out);
}

sk_status sk_cfg_int(const sk_cfg *map, const char *key, int required, int dflt, int *out) {
  char text[32];
  snprintf(text, sizeof text, "%d", dflt);
  remember_default(map, key, READ_INT, required ? NULL : text);
  const sk_cfg *node;
  SK_TRY(lookup(map, key, required, &node));
  if (!node) {
    *out = dflt;
    return SK_OK;
  }
  return sk_cfg_as_int(node, out);
}

sk_status sk_cfg_bool(const sk_cfg *map, const char *key, int required, int dflt, int *out) {
  remember_default(map, key, READ_BOOL, required ? NULL : dflt ? "true" : "false");
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
  remember_default(map, key, READ_STRING, required ? NULL : dflt);
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
  char text[256] = "";
  for (int i = 0; dflt && i < n; ++i) {
    char number[32];
    number_text(dflt[i], number, sizeof number);
    snprintf(text + strlen(text), sizeof text - strlen(text), "%s%s%s", i ? ", " : "[", number, i + 1 < n ? "" : "]");
  }
  remember_default(map, key, READ_VECTOR, required || !dflt ? NULL : text);
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
  const char *dflt_name = NULL;
  for (int i = 0; choices[i] && !dflt_name; ++i)
    if (i == dflt) dflt_name = choices[i];
  remember_default(map, key, READ_CHOICE, required ? NULL : dflt_name);
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

static const char *suggestion(const sk_cfg *map, const char *key) {
  sk_closest closest = SK_CLOSEST_NONE;
  for (int i = 0; i < map->n_asked; ++i) sk_closest_offer(&closest, key, map->asked[i].key);
  return closest.best;
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
