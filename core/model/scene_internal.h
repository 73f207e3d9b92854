/* What scene.c, scene_mesh.c and scene_contact.c share: errors that name the file, line and key, and the readers one part uses of
 * the other. */
#ifndef STICKSLIP_SCENE_INTERNAL_H
#define STICKSLIP_SCENE_INTERNAL_H

#include "stickslip/config.h"
#include "stickslip/plugins.h"
#include "stickslip/scene.h"

/* An input error at `node`: "FILE:LINE: key 'PATH': " and fmt with its one %s. */
sk_status sk_scene_fail_at(const sk_cfg *node, const char *fmt, const char *detail);
void sk_scene_copy_name(char *dst, const char *src);
/* The mesh group `name` of dimension dim, or an error naming the key at `at`. */
sk_status sk_scene_require_group(const sk_model *model, const sk_cfg *at, const char *name, int dim,
                                 const sk_group **group);
/* A plugin that does not attach to `kind` (body or contact pair), refused naming the entry. */
sk_status sk_scene_check_kind(const sk_cfg *at, const sk_plugin *plugin, sk_kind kind, const char *what,
                              const char *name);
/* `strategy:` of a pair or body: one of the plugin's strategies (the first by default). */
sk_status sk_scene_choose_strategy(const sk_cfg *entry, const sk_plugin *plugin, int *strategy);
/* The `mesh:` entries loaded and merged into *mesh (scene_mesh.c). */
sk_status sk_scene_load_meshes(const sk_cfg *root, sk_mesh *mesh);
/* The `contact:` list into scene->model's pairs. */
sk_status sk_scene_read_contact(const sk_cfg *root, sk_scene *scene);

#endif
