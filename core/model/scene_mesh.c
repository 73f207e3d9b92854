/* Scene → model, the `mesh:` key: each entry's file loaded (gmsh .msh, or a .geo meshed by gmsh), moved, rotated and
 * prefixed, and the entries merged into one mesh (docs/scene-reference.md); every error names the file, line and key. */
#define _GNU_SOURCE
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene_internal.h"

static void rotate_vector(const double axis_in[3], double angle, double v[3]) {
  double norm = sqrt(axis_in[0] * axis_in[0] + axis_in[1] * axis_in[1] + axis_in[2] * axis_in[2]);
  double k[3] = {axis_in[0] / norm, axis_in[1] / norm, axis_in[2] / norm};
  double c = cos(angle), s = sin(angle);
  double kv = k[0] * v[0] + k[1] * v[1] + k[2] * v[2];
  double cross[3] = {k[1] * v[2] - k[2] * v[1], k[2] * v[0] - k[0] * v[2], k[0] * v[1] - k[1] * v[0]};
  for (int i = 0; i < 3; ++i) v[i] = v[i] * c + cross[i] * s + k[i] * kv * (1.0 - c);
}

/* Loads one mesh entry {file, parameters, order, serendipity, max_elements, time_limit, name, rotate, translate}. */
static sk_status load_mesh_entry(const sk_cfg *entry, int dim_wanted, sk_mesh *mesh, char *prefix) {
  const char *file;
  SK_TRY(sk_cfg_string(entry, "file", 1, NULL, &file));
  char path[1024];
  SK_TRY(sk_cfg_resolve_path(entry, file, path, sizeof path));
  const sk_cfg *params = sk_cfg_get(entry, "parameters");
  sk_cfg_note_default(entry, "parameters", "none: the script's own values", 0, NULL);
  sk_mesh_param list[32];
  int n_params = sk_cfg_size(params);
  if (params && sk_cfg_kind_of(params) != SK_CFG_MAP) return sk_scene_fail_at(params, "%s", "expects a map name: value");
  if (n_params > 32) return sk_scene_fail_at(params, "%s", "has more than 32 parameters");
  for (int i = 0; i < n_params; ++i) {
    list[i].name = sk_cfg_key_at(params, i);
    SK_TRY(sk_cfg_as_double(sk_cfg_at(params, i), &list[i].value));
  }
  sk_mesh_options options;
  sk_mesh_options_default(&options);
  options.dim = dim_wanted;
  int max_elements = (int)options.max_elements;
  SK_TRY(sk_cfg_int(entry, "max_elements", 0, max_elements, &max_elements));
  SK_TRY(sk_cfg_double(entry, "time_limit", 0, options.time_limit, &options.time_limit));
  options.max_elements = max_elements;
  SK_TRY(sk_cfg_int(entry, "order", 0, 0, &options.order));
  sk_cfg_note_default(entry, "order", "as meshed", 0, NULL);
  if (options.order < 0 || options.order > 2)
    return sk_scene_fail_at(sk_cfg_get(entry, "order"), "%s", "must be 1 or 2 (or absent: the elements as meshed)");
  SK_TRY(sk_cfg_bool(entry, "serendipity", 0, 0, &options.serendipity));
  if (options.serendipity && options.order != 2)
    return sk_scene_fail_at(sk_cfg_get(entry, "serendipity"), "%s", "needs `order: 2` (quad8/hex20 are second-order)");
  const char *name;
  SK_TRY(sk_cfg_string(entry, "name", 0, "", &name));
  snprintf(prefix, SK_NAME_MAX, "%s", name);
  sk_status status = sk_mesh_load_with(path, list, n_params, &options, mesh);
  if (status != SK_OK) return sk_error_prefix(status, "%s: ", sk_cfg_where(entry));

  double translate[3] = {0, 0, 0}, axis[3] = {0, 0, 1}, angle = 0;
  SK_TRY(sk_cfg_vector(entry, "translate", 0, 3, translate, translate));
  const sk_cfg *rotate = sk_cfg_get(entry, "rotate");
  sk_cfg_note_default(entry, "rotate", "none", 0, NULL);
  if (rotate) {
    SK_TRY(sk_cfg_vector(rotate, "axis", 1, 3, NULL, axis));
    SK_TRY(sk_cfg_double(rotate, "degrees", 1, 0, &angle));
    if (axis[0] == 0 && axis[1] == 0 && axis[2] == 0) return sk_scene_fail_at(rotate, "%s", "rotation axis is zero");
  }
  for (int a = 0; a < mesh->n_nodes; ++a) {
    double *x = mesh->x + 3 * a;
    if (angle != 0) rotate_vector(axis, angle * M_PI / 180.0, x);
    for (int i = 0; i < 3; ++i) x[i] += translate[i];
  }
  status = sk_mesh_check_elements(mesh); /* a translation by 1e308 overflows */
  if (status != SK_OK) return sk_error_prefix(status, "%s: after translate/rotate: ", sk_cfg_where(entry));
  return SK_OK;
}

/* Appends mesh `part` to `merged`, prefixing group names with "prefix." when a prefix is given. */
static sk_status merge_mesh(sk_mesh *merged, const sk_mesh *part, const char *prefix) {
  if (merged->n_nodes == 0 && merged->n_groups == 0) merged->dim = part->dim;
  if (merged->dim != part->dim)
    return sk_error_set(SK_ERR_INPUT, "mesh %s is %dD but earlier meshes are %dD", part->source, part->dim,
                        merged->dim);
  int offset = merged->n_nodes;
  double *x = realloc(merged->x, sizeof(double) * 3 * (size_t)(offset + part->n_nodes));
  sk_group *groups = realloc(merged->groups, sizeof(sk_group) * (size_t)(merged->n_groups + part->n_groups));
  if (!x || !groups) return sk_error_set(SK_ERR_NOMEM, "out of memory merging meshes");
  merged->x = x;
  merged->groups = groups;
  memcpy(merged->x + 3 * offset, part->x, sizeof(double) * 3 * (size_t)part->n_nodes);
  for (int g = 0; g < part->n_groups; ++g) {
    sk_group *dst = &merged->groups[merged->n_groups + g];
    *dst = part->groups[g];
    if (prefix[0]) snprintf(dst->name, sizeof dst->name, "%s.%s", prefix, part->groups[g].name);
    for (int k = 0; k < merged->n_groups; ++k)
      if (strcmp(merged->groups[k].name, dst->name) == 0)
        return sk_error_set(SK_ERR_INPUT,
                            "physical group '%s' appears in two meshes: give the meshes distinct `name`s", dst->name);
    size_t count = (size_t)dst->n_elems * (size_t)dst->nen;
    dst->conn = malloc(sizeof(int) * (count ? count : 1));
    if (!dst->conn) return sk_error_set(SK_ERR_NOMEM, "out of memory merging meshes");
    for (size_t k = 0; k < count; ++k) dst->conn[k] = part->groups[g].conn[k] + offset;
  }
  merged->n_nodes += part->n_nodes;
  merged->n_groups += part->n_groups;
  if (!merged->source[0]) snprintf(merged->source, sizeof merged->source, "%s", part->source);
  return SK_OK;
}

sk_status sk_scene_load_meshes(const sk_cfg *root, sk_mesh *mesh) {
  const sk_cfg *node = sk_cfg_get(root, "mesh");
  if (!node) return sk_error_set(SK_ERR_INPUT, "%s: missing key 'mesh'", sk_cfg_where(root));
  int dim_wanted = 0;
  SK_TRY(sk_cfg_int(root, "dimension", 0, 0, &dim_wanted));
  if (dim_wanted != 0 && dim_wanted != 2 && dim_wanted != 3)
    return sk_scene_fail_at(sk_cfg_get(root, "dimension"), "%s", "must be 2 or 3");
  int n_entries = sk_cfg_kind_of(node) == SK_CFG_SEQ ? sk_cfg_size(node) : 1;
  if (n_entries < 1) return sk_scene_fail_at(node, "%s", "lists no mesh");
  memset(mesh, 0, sizeof *mesh);
  for (int e = 0; e < n_entries; ++e) {
    const sk_cfg *entry = sk_cfg_kind_of(node) == SK_CFG_SEQ ? sk_cfg_at(node, e) : node;
    if (sk_cfg_kind_of(entry) != SK_CFG_MAP) return sk_scene_fail_at(entry, "%s", "expects a map with `file`");
    sk_mesh part;
    char prefix[SK_NAME_MAX];
    memset(&part, 0, sizeof part);
    sk_status status = load_mesh_entry(entry, dim_wanted, &part, prefix);
    if (status == SK_OK) status = merge_mesh(mesh, &part, prefix);
    sk_mesh_free(&part);
    if (status != SK_OK) return status;
  }
  return SK_OK;
}
