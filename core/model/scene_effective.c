/* The effective scene: the command line's overrides applied to the scene's tree (--set merges, --replace replaces,
 * --plugin switches every pair's plugin and keeps what the new plugin takes), a record of where the scene came from,
 * mesh paths made absolute, and the whole written as the results' scene.yaml, which reruns from any folder. */
#define _DEFAULT_SOURCE /* realpath */
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "stickslip/plugins.h"
#include "stickslip/scene.h"
#include "stickslip/text.h"

/* `word` as one shell word: as it is when it is plain, else in single quotes. */
static void add_shell_word(sk_text *b, const char *word) {
  int plain = word[0] != '\0';
  for (const char *c = word; *c && plain; ++c)
    plain = strchr("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789._-=/:+,@%", *c) != NULL;
  if (plain) {
    sk_text_add(b, word);
    return;
  }
  sk_text_add(b, "'");
  for (const char *c = word; *c; ++c) {
    char one[2] = {*c, 0};
    sk_text_add(b, *c == '\'' ? "'\\''" : one);
  }
  sk_text_add(b, "'");
}

static const char provenance_title[] = "# The effective scene of a stickslip run";

/* A scene that is itself a run's effective scene (a results folder rerun) passes its own header on, so the chain
 * back to the first scene file and every command line since stays readable. */
static void add_earlier_provenance(sk_text *note, const char *path) {
  FILE *f = fopen(path, "r");
  if (!f) return;
  char line[4096];
  int first = 1;
  while (fgets(line, sizeof line, f) && line[0] == '#') {
    if (first && strncmp(line, provenance_title, sizeof provenance_title - 1) != 0) break;
    if (first) {
      sk_text_add(note, "# that scene's own header:\n");
      first = 0;
    } else {
      sk_text_add(note, "#   ");
      sk_text_add(note, line + (line[1] == ' ' ? 2 : 1));
    }
  }
  fclose(f);
}

static int from_command_line(const sk_cfg *node) { return strncmp(sk_cfg_where(node), "--", 2) == 0; }

/* --plugin NAME on pair k (the tree is looked at with sk_cfg_peek: marking a key read would hide it from the
 * unknown-key check): the plugin is NAME; a strategy and parameters from the file that NAME does not take are
 * dropped (added to `dropped`). A pair whose file already names NAME keeps everything, so that a misspelt parameter
 * of its own plugin is still an error. */
static sk_status switch_pair(sk_scene *scene, int k, const sk_plugin *plugin, sk_text *dropped) {
  const sk_cfg *entry = sk_cfg_peek_at(sk_cfg_peek(scene->cfg, "contact"), k);
  if (sk_cfg_kind_of(entry) != SK_CFG_MAP) return SK_OK; /* reading the pair will say what is wrong */
  const sk_cfg *current = sk_cfg_peek(entry, "plugin");
  if (sk_cfg_scalar(current) && strcmp(sk_cfg_scalar(current), plugin->name) == 0 && !from_command_line(current))
    return SK_OK;
  char path[64], line[256];
  snprintf(path, sizeof path, "contact.%d.plugin", k);
  SK_TRY(sk_cfg_set_text(scene->cfg, path, plugin->name, "--plugin"));
  const sk_cfg *strategy = sk_cfg_peek(entry, "strategy");
  const char *wanted = sk_cfg_scalar(strategy);
  int known = 0;
  for (int s = 0; wanted && plugin->strategies[s]; ++s) known |= strcmp(plugin->strategies[s], wanted) == 0;
  if (strategy && !known && !from_command_line(strategy)) {
    snprintf(line, sizeof line, "%scontact[%d].strategy (%s)", dropped->used ? ", " : "", k, wanted ? wanted : "?");
    sk_text_add(dropped, line);
    snprintf(path, sizeof path, "contact.%d.strategy", k);
    sk_cfg_remove(scene->cfg, path);
  }
  const sk_cfg *params = sk_cfg_peek(entry, "parameters");
  if (sk_cfg_kind_of(params) != SK_CFG_MAP) return SK_OK;
  /* listed in the order of the file, then removed (removing shifts the keys that follow) */
  int n = sk_cfg_size(params), n_drop = 0;
  char (*drop)[128] = calloc((size_t)(n > 0 ? n : 1), sizeof *drop);
  if (!drop) return sk_error_set(SK_ERR_NOMEM, "out of memory applying --plugin");
  for (int i = 0; i < n; ++i) {
    const char *key = sk_cfg_key_at(params, i);
    if (sk_plugin_takes(plugin, key, SK_KIND_PAIR) || from_command_line(sk_cfg_peek(params, key))) continue;
    snprintf(drop[n_drop++], sizeof drop[0], "%s", key);
    snprintf(line, sizeof line, "%scontact[%d].parameters.%s", dropped->used ? ", " : "", k, key);
    sk_text_add(dropped, line);
  }
  for (int i = 0; i < n_drop; ++i) {
    char removed[192];
    snprintf(removed, sizeof removed, "contact.%d.parameters.%s", k, drop[i]);
    sk_cfg_remove(scene->cfg, removed);
  }
  free(drop);
  return SK_OK;
}

static sk_status apply_plugin(sk_scene *scene, const char *name, sk_text *dropped) {
  const sk_plugin *plugin;
  sk_status status = sk_plugin_load(name, &plugin);
  if (status != SK_OK) return sk_error_prefix(status, "--plugin %s: ", name);
  const sk_cfg *contact = sk_cfg_peek(scene->cfg, "contact");
  int n = sk_cfg_kind_of(contact) == SK_CFG_SEQ ? sk_cfg_size(contact) : 0;
  if (n == 0)
    return sk_error_set(SK_ERR_INPUT, "--plugin %s: %s has no contact pairs (no `contact` list), so no plugin would "
                        "be used", name, scene->path);
  if (!(plugin->kinds & SK_KIND_PAIR))
    return sk_error_set(SK_ERR_PLUGIN, "--plugin %s: plugin '%s' does not attach to contact pairs (it is a body "
                        "plugin)", name, name);
  for (int k = 0; k < n; ++k) SK_TRY(switch_pair(scene, k, plugin, dropped));
  if (dropped->used)
    sk_log_message(scene->model.rank, 1, "--plugin %s: dropped what %s does not take, its defaults apply: %s", name,
                   name, dropped->text);
  return SK_OK;
}

sk_status sk_scene_apply_overrides(sk_scene *scene, const sk_scene_overrides *overrides) {
  char *real = realpath(scene->path, NULL);
  snprintf(scene->source, sizeof scene->source, "%s", real ? real : scene->path);
  free(real);
  sk_text command = {0}, dropped = {0};
  sk_status status = SK_OK;
  for (int k = 0; overrides && k < overrides->n && status == SK_OK; ++k) {
    sk_cfg_override_mode mode = overrides->modes ? overrides->modes[k] : SK_CFG_MERGE;
    status = sk_cfg_override(scene->cfg, overrides->assignments[k], mode);
    sk_text_add(&command, command.used ? " " : "");
    sk_text_add(&command, mode == SK_CFG_REPLACE ? "--replace " : "--set ");
    add_shell_word(&command, overrides->assignments[k]);
  }
  if (status == SK_OK && overrides && overrides->plugin) {
    status = apply_plugin(scene, overrides->plugin, &dropped);
    sk_text_add(&command, command.used ? " " : "");
    sk_text_add(&command, "--plugin ");
    add_shell_word(&command, overrides->plugin);
  }
  if (status == SK_OK) {
    sk_text note = {0};
    sk_text_add(&note, provenance_title);
    sk_text_add(&note, ": rerun it with `stickslip run scene.yaml` (from any folder).\n# scene: ");
    sk_text_add(&note, scene->source);
    sk_text_add(&note, "\n# overrides: ");
    sk_text_add(&note, command.used ? command.text : "none");
    sk_text_add(&note, command.used ? " (applied below)\n" : "\n");
    if (dropped.used) {
      sk_text_add(&note, "# dropped by --plugin (not parameters of ");
      sk_text_add(&note, overrides->plugin);
      sk_text_add(&note, ", whose defaults apply): ");
      sk_text_add(&note, dropped.text);
      sk_text_add(&note, "\n");
    }
    sk_text_add(&note, "# mesh files: absolute paths\n");
    add_earlier_provenance(&note, scene->path);
    scene->provenance = note.text;
  }
  free(command.text);
  free(dropped.text);
  return status;
}

void sk_scene_note(sk_scene *scene, const char *line) {
  sk_text note = {scene->provenance, scene->provenance ? strlen(scene->provenance) : 0,
                  scene->provenance ? strlen(scene->provenance) + 1 : 0};
  sk_text_add(&note, "# ");
  sk_text_add(&note, line);
  sk_text_add(&note, "\n");
  scene->provenance = note.text;
}

sk_status sk_scene_absolute_mesh_paths(sk_scene *scene) {
  const sk_cfg *mesh = sk_cfg_get(scene->cfg, "mesh");
  int n = sk_cfg_kind_of(mesh) == SK_CFG_SEQ ? sk_cfg_size(mesh) : 1;
  for (int e = 0; e < n; ++e) {
    const sk_cfg *entry = sk_cfg_kind_of(mesh) == SK_CFG_SEQ ? sk_cfg_at(mesh, e) : mesh;
    const sk_cfg *file = sk_cfg_get(entry, "file");
    if (!sk_cfg_scalar(file)) continue; /* the scene was read, so this does not happen */
    char path[PATH_MAX];
    SK_TRY(sk_cfg_resolve_path(file, sk_cfg_scalar(file), path, sizeof path));
    char *real = realpath(path, NULL);
    if (!real) continue; /* the mesh was read; a file gone since keeps its path as given */
    char key[PATH_MAX + 32];
    snprintf(key, sizeof key, "%s.file", sk_cfg_path(entry));
    sk_status status = sk_cfg_set_text(scene->cfg, key, real, NULL);
    free(real);
    SK_TRY(status);
  }
  return SK_OK;
}

sk_status sk_scene_write(const sk_scene *scene, const char *path) {
  FILE *f = fopen(path, "w");
  if (!f) return sk_error_set(SK_ERR_IO, "cannot create '%s'", path);
  fputs(scene->provenance ? scene->provenance : "", f);
  sk_status status = sk_cfg_write(scene->cfg, f);
  if (fclose(f) != 0 && status == SK_OK) status = sk_error_set(SK_ERR_IO, "cannot write '%s'", path);
  if (status != SK_OK) sk_error_prefix(status, "%s: ", path);
  return status;
}
