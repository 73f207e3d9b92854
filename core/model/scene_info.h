/* What an attachment is, as the scene describes it (plugin_types.h: sk_scene_info, ABI 2.7), and the checks made
 * on it before any plugin instance exists (internal to the simulation layer): the capabilities and sk_plugin.check
 * of the plugin a pair or body names, the search for the plugins that can run it, and contact surfaces glued to
 * each other by shared nodes. scene.c calls the checks while it reads the scene; term_plugin.c hands the
 * description to the instance through the extension stickslip.scene.v1. */
#ifndef STICKSLIP_SCENE_INFO_H
#define STICKSLIP_SCENE_INFO_H

#include "stickslip/model.h"

/* An sk_scene_info with the sides it points to (the struct holds its own pointers: do not copy it by value). */
typedef struct {
  sk_scene_info info;
  sk_scene_side slave, master;
} sk_scene_description;


/* The description of contact pair `pair` (its surfaces or obstacle built, its plugin and strategy chosen). */
void sk_describe_pair(const sk_model *model, int pair, sk_scene_description *d);
/* The description of body `body` (a body plugin's attachment). */
void sk_describe_body(const sk_model *model, int body, sk_scene_description *d);

/* Refuses an attachment the plugin cannot run, before any instance exists: `needed` capabilities it lacks, or its
 * sk_plugin.check (ABI 2.7). The message (prefixed with `where`, e.g. "scene.yaml:12:5: contact pair 'floor'")
 * names the plugin, the reason and the plugins on the search path that can run it. */
sk_status sk_check_attachment(const sk_plugin *plugin, const sk_scene_description *d, uint64_t needed,
                              const char *where);
/* Contact pair `pair` glued to its master: surfaces sharing mesh nodes (two bodies meshed as one, the gmsh trap of
 * shared interface nodes) are an error naming the node count, one node and the fix. */
sk_status sk_check_glued(const sk_model *model, int pair, const char *where);

#endif
