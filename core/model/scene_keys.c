/* `stickslip keys`: every key of a loaded scene with its value (given, or the default the program used), its unit
 * and where the value came from; each pair's and body plugin's parameters from the plugin's table. The keys and
 * defaults are those the reader asked for (config_get.c remembers them), so the listing cannot drift from the
 * reader; only the units are kept here. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "stickslip/plugins.h"
#include "stickslip/scene.h"
#include "system.h"

/* Units of the quantities, by key path without indices. The scene has no unit system of its own: any consistent
 * one (N, mm, s, t/mm³ gives force/area in MPa). */
static const struct {
  const char *key, *unit;
} units[] = {
    {"body_force", "length/time^2"},
    {"mesh.translate", "length"},
    {"mesh.rotate.axis", "direction"},
    {"mesh.rotate.degrees", "degree"},
    {"mesh.time_limit", "s (wall clock)"},
    {"bodies.material.E", "force/area"},
    {"bodies.material.nu", "1"},
    {"bodies.material.density", "mass/volume"},
    {"bodies.velocity", "length/time"},
    {"bodies.angular_velocity", "rad/time"},
    {"bodies.center", "length"},
    {"boundary.displacement", "length"},
    {"boundary.traction", "force/area"},
    {"boundary.resultant", "force"},
    {"boundary.history", "[time, factor]"},
    {"contact.obstacle.point", "length"},
    {"contact.obstacle.normal", "direction"},
    {"contact.obstacle.axis", "direction"},
    {"contact.obstacle.radius", "length"},
    {"contact.obstacle.c", "1/length"},
    {"contact.obstacle.motion", "[time, length, length, length]"},
    {"contact.obstacles.point", "length"},
    {"contact.obstacles.normal", "direction"},
    {"contact.obstacles.axis", "direction"},
    {"contact.obstacles.radius", "length"},
    {"contact.obstacles.c", "1/length"},
    {"contact.obstacles.motion", "[time, length, length, length]"},
    {"contact_balance.time_ratio", "1 (max/mean)"},
    {"contact_balance.entity_imbalance", "1 ((max-min)/max)"},
    {"time.dt", "time"},
    {"time.end", "time"},
    {"time.start", "time"},
    {"solver.newton.tolerance", "1 (relative)"},
    {"solver.newton.absolute_tolerance", "force (residual norm)"},
    {"solver.newton.update_tolerance", "1 (relative)"},
    {"solver.linear.tolerance", "1 (relative)"},
};

/* `path` without its indices ("bodies[0].material.E" → "bodies.material.E"). */
static void without_indices(const char *path, char *out, size_t size) {
  size_t k = 0;
  for (const char *c = path; *c && k + 1 < size; ++c) {
    if (*c == '[') {
      while (*c && *c != ']') ++c;
      if (!*c) break;
      continue;
    }
    out[k++] = *c;
  }
  out[k] = '\0';
}

static const char *unit_of(const sk_cfg_entry *entry) {
  char key[512];
  without_indices(entry->path, key, sizeof key);
  for (size_t i = 0; i < sizeof units / sizeof units[0]; ++i)
    if (strcmp(units[i].key, key) == 0) return units[i].unit;
  if (strstr(key, ".parameters.")) return ""; /* plugin and mesh-script parameters: their meaning says it */
  return entry->quantity ? "?" : "";       /* a quantity without a unit here is a gap (the docs test finds it) */
}

typedef struct {
  char *path, *value, *unit, *origin;
} row;

/* A default a plugin computed from the scene (stickslip.scene.v1), shown as its number in place of the rule. */
typedef struct {
  char path[160];
  double value;
  const char *reason;
} computed_default;

typedef struct {
  row *rows;
  int n, cap;
  const computed_default *computed;
  int n_computed;
} listing;

static char *copy(const char *s) {
  char *d = malloc(strlen(s) + 1);
  if (d) strcpy(d, s);
  return d;
}

static void collect(void *ctx, const sk_cfg_entry *entry) {
  listing *list = ctx;
  if (list->n == list->cap) {
    int cap = list->cap ? 2 * list->cap : 64;
    row *rows = realloc(list->rows, (size_t)cap * sizeof *rows);
    if (!rows) return;
    list->rows = rows;
    list->cap = cap;
  }
  char origin[1024], value[1024];
  const computed_default *computed = NULL;
  for (int k = 0; k < list->n_computed && !entry->given && !computed; ++k)
    if (strcmp(list->computed[k].path, entry->path) == 0) computed = &list->computed[k];
  if (computed) {
    snprintf(origin, sizeof origin, "computed from the scene: %s%s%s", computed->reason, entry->meaning ? "; " : "",
             entry->meaning ? entry->meaning : "");
    snprintf(value, sizeof value, "%.6g", computed->value);
  } else if (entry->given)
    snprintf(origin, sizeof origin, "%s%s%s", entry->where, entry->meaning ? "; " : "",
             entry->meaning ? entry->meaning : "");
  else
    snprintf(origin, sizeof origin, "default%s%s", entry->meaning ? "; " : "", entry->meaning ? entry->meaning : "");
  if (!computed)
    snprintf(value, sizeof value, !entry->literal ? "(%s)" : entry->value[0] ? "%s" : "\"\"", entry->value);
  row r = {copy(entry->path), copy(value), copy(unit_of(entry)), copy(origin)};
  if (!r.path || !r.value || !r.unit || !r.origin) {
    free(r.path);
    free(r.value);
    free(r.unit);
    free(r.origin);
    return;
  }
  list->rows[list->n++] = r;
}

/* The parameters of a plugin's table that `entry` (a pair or body of kind `kind`) does not give, with the declared
 * default and meaning; given ones get the meaning too. */
static void note_plugin_parameters(const sk_cfg *entry, const sk_plugin *plugin, sk_kind kind) {
  const sk_cfg *params = sk_cfg_section(entry, "parameters");
  sk_plugin_parameter parameter;
  for (int k = 0; sk_plugin_parameter_at(plugin, k, &parameter); ++k) {
    if (!(parameter.kinds & kind)) continue;
    char meaning[700];
    snprintf(meaning, sizeof meaning, "%s: %s", plugin->name, parameter.meaning);
    char *end = NULL;
    int number = parameter.dflt[0] && (strtod(parameter.dflt, &end), *end == '\0'); /* "[0.1]" is a value */
    /* "axis_x, axis_y, axis_z: ... [0, 0, 1]": one default per key when the counts match */
    char parts[SK_PLUGIN_PARAMETER_KEYS][64];
    int n_parts = 0;
    for (const char *at = parameter.dflt; *at && n_parts < SK_PLUGIN_PARAMETER_KEYS;) {
      const char *comma = strchr(at, ',');
      size_t n = comma ? (size_t)(comma - at) : strlen(at);
      while (n > 0 && at[n - 1] == ' ') --n;
      snprintf(parts[n_parts++], sizeof parts[0], "%.*s", (int)n, at);
      at = comma ? comma + 1 + strspn(comma + 1, " ") : at + strlen(at);
    }
    for (int i = 0; i < parameter.n_keys; ++i) {
      const char *dflt = parameter.dflt[0] ? parameter.dflt : "not stated";
      int literal = number;
      if (parameter.n_keys > 1 && n_parts == parameter.n_keys) {
        dflt = parts[i];
        literal = (strtod(dflt, &end), *end == '\0');
      }
      sk_cfg_note_default(params, parameter.keys[i], dflt, literal, meaning);
    }
  }
}

/* One line of the listing: each cell starts at its column, or two spaces after a longer cell before it (which then
 * takes the room of the empty or short cells that follow rather than shifting the whole line). */
static void print_row(FILE *out, const int width[3], const char *const cells[4]) {
  int at = 0, column = 0;
  for (int c = 0; c < 4; ++c) {
    if (c > 0) {
      int pad = column - at < 2 ? 2 : column - at;
      if (!cells[c][0] && c < 3) pad = 0; /* an empty cell: the next one decides the spacing */
      at += fprintf(out, "%*s", pad, "");
    }
    at += fprintf(out, "%s", cells[c]);
    if (c < 3) column += width[c] + 2;
  }
  fprintf(out, "\n");
}

/* The listing of the keys of `root` (sk_cfg_each), in aligned columns after a heading naming `source`; the defaults
 * of `computed` by their numbers. */
static void print_keys(const sk_cfg *root, const char *source, const computed_default *computed, int n_computed,
                       FILE *out) {
  listing list = {.computed = computed, .n_computed = n_computed};
  sk_cfg_each(root, collect, &list);
  int width[3] = {3, 5, 4};
  for (int i = 0; i < list.n; ++i) {
    const char *cells[3] = {list.rows[i].path, list.rows[i].value, list.rows[i].unit};
    for (int c = 0; c < 3; ++c) {
      int n = (int)strlen(cells[c]);
      int cap = c == 0 ? 48 : c == 1 ? 28 : 16; /* longer cells push their line on rather than every line */
      if (n > width[c] && n <= cap) width[c] = n;
    }
  }
  fprintf(out, "# %s: every key with its value (given, or the default in use), unit and origin\n", source);
  fprintf(out, "# units: those of the scene (any consistent system: N, mm, s, t/mm^3 make force/area MPa); a value "
               "in parentheses is a default in words\n");
  print_row(out, width, (const char *[]){"key", "value", "unit", "origin"});
  for (int i = 0; i < list.n; ++i) {
    const row *r = &list.rows[i];
    print_row(out, width, (const char *[]){r->path, r->value, r->unit, r->origin});
    free(r->path);
    free(r->value);
    free(r->unit);
    free(r->origin);
  }
  free(list.rows);
}

/* Every default the plugins computed from the scene, the first report of a key path (a `bodies:` entry's pairs share
 * one path); scene->system is NULL before the system exists (then none). */
static int gather_computed(const sk_scene *scene, computed_default *computed, int capacity) {
  int n = 0;
  const sk_system *sys = scene->system;
  for (int t = 0; sys && t < sys->n_terms; ++t) {
    computed_default c;
    for (int k = 0; n < capacity && sk_term_plugin_computed(sys->terms[t], k, c.path, sizeof c.path, &c.value,
                                                            &c.reason); ++k) {
      int seen = 0;
      for (int i = 0; i < n && !seen; ++i) seen = strcmp(computed[i].path, c.path) == 0;
      if (!seen) computed[n++] = c;
    }
  }
  return n;
}

void sk_scene_keys(const sk_scene *scene, FILE *out) {
  const sk_model *m = &scene->model;
  const sk_cfg *contact = sk_cfg_get(scene->cfg, "contact");
  for (int k = 0; k < m->n_pairs; ++k)
    note_plugin_parameters(sk_cfg_at(contact, k), m->pairs[k].plugin, SK_KIND_PAIR);
  const sk_cfg *bodies = sk_cfg_get(scene->cfg, "bodies");
  for (int b = 0; b < m->n_bodies; ++b)
    if (m->bodies[b].plugin) note_plugin_parameters(sk_cfg_at(bodies, b), m->bodies[b].plugin, SK_KIND_BODY);
  computed_default computed[256];
  print_keys(scene->cfg, scene->path, computed, gather_computed(scene, computed, 256), out);
}

sk_status sk_plugin_keys(const sk_plugin *plugin, FILE *out) {
  sk_cfg *root = NULL;
  SK_TRY(sk_cfg_parse_string("{}", plugin->name, &root));
  /* one section per kind of attachment, named only when the plugin has both */
  int both = (plugin->kinds & SK_KIND_PAIR) && (plugin->kinds & SK_KIND_BODY);
  if (plugin->kinds & SK_KIND_PAIR)
    note_plugin_parameters(both ? sk_cfg_section(root, "pair") : root, plugin, SK_KIND_PAIR);
  if (plugin->kinds & SK_KIND_BODY)
    note_plugin_parameters(both ? sk_cfg_section(root, "body") : root, plugin, SK_KIND_BODY);
  char source[160];
  snprintf(source, sizeof source, "plugin %s", plugin->name);
  print_keys(root, source, NULL, 0, out);
  sk_cfg_free(root);
  return SK_OK;
}
