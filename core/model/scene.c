/* Scene → model: every key of docs/scene-reference.md is read here, and every error names the file, line and key. */
#define _GNU_SOURCE
#include "stickslip/scene.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene_info.h"
#include "stickslip/plugins.h"
#include "system.h"

/* ---- helpers -------------------------------------------------------------------------------------------------- */

static sk_status fail_at(const sk_cfg *node, const char *fmt, const char *detail) {
  char message[1024];
  snprintf(message, sizeof message, fmt, detail);
  return sk_error_set(SK_ERR_INPUT, "%s: key '%s': %s", sk_cfg_where(node), sk_cfg_path(node), message);
}

static void copy_name(char *dst, const char *src) {
  snprintf(dst, SK_NAME_MAX, "%s", src);
}

/* A history: a sequence of [t, value] pairs, strictly increasing in t. Absent → the constant 1. */
static sk_status read_history(const sk_cfg *map, const char *key, sk_history *history) {
  history->n = 0;
  const sk_cfg *node = sk_cfg_get(map, key);
  sk_cfg_note_default(map, key, "constant 1", 0, NULL);
  if (!node) return SK_OK;
  int n = sk_cfg_size(node);
  if (sk_cfg_kind_of(node) != SK_CFG_SEQ || n < 1)
    return fail_at(node, "%s", "expects a list of [time, value] pairs, e.g. [[0, 0], [1, 1]]");
  if (n > SK_HISTORY_MAX) return fail_at(node, "%s", "has more points than the 64 supported");
  for (int k = 0; k < n; ++k) {
    const sk_cfg *pair = sk_cfg_at(node, k);
    if (sk_cfg_kind_of(pair) != SK_CFG_SEQ || sk_cfg_size(pair) != 2)
      return fail_at(pair, "%s", "expects a [time, value] pair");
    SK_TRY(sk_cfg_as_double(sk_cfg_at(pair, 0), &history->t[k]));
    SK_TRY(sk_cfg_as_double(sk_cfg_at(pair, 1), &history->v[k]));
    if (k > 0 && !(history->t[k] > history->t[k - 1]))
      return fail_at(pair, "%s", "times must increase strictly");
  }
  history->n = n;
  return SK_OK;
}

/* ---- meshes ----------------------------------------------------------------------------------------------------- */

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
  if (params && sk_cfg_kind_of(params) != SK_CFG_MAP) return fail_at(params, "%s", "expects a map name: value");
  if (n_params > 32) return fail_at(params, "%s", "has more than 32 parameters");
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
    return fail_at(sk_cfg_get(entry, "order"), "%s", "must be 1 or 2 (or absent: the elements as meshed)");
  SK_TRY(sk_cfg_bool(entry, "serendipity", 0, 0, &options.serendipity));
  if (options.serendipity && options.order != 2)
    return fail_at(sk_cfg_get(entry, "serendipity"), "%s", "needs `order: 2` (quad8/hex20 are second-order)");
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
    if (axis[0] == 0 && axis[1] == 0 && axis[2] == 0) return fail_at(rotate, "%s", "rotation axis is zero");
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

static sk_status load_meshes(const sk_cfg *root, sk_mesh *mesh) {
  const sk_cfg *node = sk_cfg_get(root, "mesh");
  if (!node) return sk_error_set(SK_ERR_INPUT, "%s: missing key 'mesh'", sk_cfg_where(root));
  int dim_wanted = 0;
  SK_TRY(sk_cfg_int(root, "dimension", 0, 0, &dim_wanted));
  if (dim_wanted != 0 && dim_wanted != 2 && dim_wanted != 3)
    return fail_at(sk_cfg_get(root, "dimension"), "%s", "must be 2 or 3");
  int n_entries = sk_cfg_kind_of(node) == SK_CFG_SEQ ? sk_cfg_size(node) : 1;
  if (n_entries < 1) return fail_at(node, "%s", "lists no mesh");
  memset(mesh, 0, sizeof *mesh);
  for (int e = 0; e < n_entries; ++e) {
    const sk_cfg *entry = sk_cfg_kind_of(node) == SK_CFG_SEQ ? sk_cfg_at(node, e) : node;
    if (sk_cfg_kind_of(entry) != SK_CFG_MAP) return fail_at(entry, "%s", "expects a map with `file`");
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

static sk_status require_group(const sk_model *model, const sk_cfg *at, const char *name, int dim,
                               const sk_group **group) {
  sk_status status = sk_mesh_require_group(&model->mesh, name, dim, group);
  if (status != SK_OK) return sk_error_prefix(status, "%s: key '%s': ", sk_cfg_where(at), sk_cfg_path(at));
  return SK_OK;
}

static sk_status choose_strategy(const sk_cfg *entry, const sk_plugin *plugin, int *strategy);
static int straight_faces(const sk_surface *surface) {
  return surface->face_type == SK_LINE2 || surface->face_type == SK_TRI3;
}

static sk_status check_kind(const sk_cfg *at, const sk_plugin *plugin, sk_kind kind, const char *what, const char *name);

/* ---- bodies ----------------------------------------------------------------------------------------------------- */

/* `plugin`, `strategy` and `parameters` of a body: a body plugin (kind "body", docs/plugin-abi.md §2). */
static sk_status read_body_plugin(const sk_cfg *entry, const sk_model *model, sk_body *body) {
  const char *plugin_name;
  SK_TRY(sk_cfg_string(entry, "plugin", 0, NULL, &plugin_name));
  sk_cfg_note_default(entry, "plugin", "none: the core integrates the body", 0, NULL);
  if (!plugin_name) {
    if (sk_cfg_get(entry, "strategy") || sk_cfg_get(entry, "parameters"))
      return sk_error_set(SK_ERR_INPUT, "%s: body '%s': `strategy` and `parameters` need a `plugin`",
                          sk_cfg_where(entry), body->name);
    return SK_OK;
  }
  sk_status status = sk_plugin_load(plugin_name, &body->plugin);
  if (status != SK_OK)
    return sk_error_prefix(status, "%s: body '%s': ", sk_cfg_where(sk_cfg_get(entry, "plugin")), body->name);
  SK_TRY(check_kind(sk_cfg_get(entry, "plugin"), body->plugin, SK_KIND_BODY, "body", body->name));
  SK_TRY(choose_strategy(entry, body->plugin, &body->strategy));
  body->params = sk_cfg_get(entry, "parameters");
  char where[SK_NAME_MAX + 1200];
  snprintf(where, sizeof where, "%s: body '%s'", sk_cfg_where(entry), body->name);
  sk_scene_description description;
  sk_describe_body(model, (int)(body - model->bodies), &description);
  return sk_check_attachment(body->plugin, &description,
                             (model->dim == 2 ? SK_CAP_2D : SK_CAP_3D) | model->time.integrator->plugin_caps, where);
}

static sk_status read_bodies(const sk_cfg *root, sk_model *model) {
  const sk_cfg *list = sk_cfg_get(root, "bodies");
  if (!list || sk_cfg_kind_of(list) != SK_CFG_SEQ || sk_cfg_size(list) < 1)
    return sk_error_set(SK_ERR_INPUT, "%s: key 'bodies' must list at least one body", sk_cfg_where(list ? list : root));
  model->n_bodies = sk_cfg_size(list);
  model->bodies = calloc((size_t)model->n_bodies, sizeof(sk_body));
  if (!model->bodies) return sk_error_set(SK_ERR_NOMEM, "%s: out of memory for the bodies", sk_cfg_where(list));
  int first = 0;
  for (int b = 0; b < model->n_bodies; ++b) {
    const sk_cfg *entry = sk_cfg_at(list, b);
    sk_body *body = &model->bodies[b];
    const char *group_name, *name;
    SK_TRY(sk_cfg_string(entry, "group", 1, NULL, &group_name));
    SK_TRY(sk_cfg_string(entry, "name", 0, group_name, &name));
    copy_name(body->name, name);
    SK_TRY(require_group(model, sk_cfg_get(entry, "group"), group_name, model->dim, &body->group));
    const sk_cfg *material = sk_cfg_get(entry, "material");
    if (!material) return sk_error_set(SK_ERR_INPUT, "%s: body '%s' needs a `material`", sk_cfg_where(entry), name);
    int choice;
    sk_material_model kind;
    double E, nu, density;
    SK_TRY(sk_cfg_choice(material, "model", 1, sk_material_model_names, 0, &choice));
    SK_TRY(sk_material_model_from_name(sk_material_model_names[choice], &kind));
    SK_TRY(sk_cfg_double(material, "E", 1, 0, &E));
    SK_TRY(sk_cfg_double(material, "nu", 1, 0, &nu));
    SK_TRY(sk_cfg_double(material, "density", model->time.integrator->dynamic, 0, &density));
    sk_status status = sk_material_init(&body->material, kind, E, nu, density);
    if (status != SK_OK) {
      /* name the value at fault where it was given (a line of the file, or --set bodies.0.material.E): the one
       * check, sk_material_init, tells which by failing with the others set to harmless values */
      const char *culprit = sk_material_init(&body->material, kind, E, 0.0, 0.0) != SK_OK    ? "E"
                            : sk_material_init(&body->material, kind, E, nu, 0.0) != SK_OK ? "nu"
                                                                                            : "density";
      sk_material_init(&body->material, kind, E, nu, density); /* the first failure's message again */
      const sk_cfg *at = sk_cfg_get(material, culprit);
      return sk_error_prefix(status, "%s: body '%s': ", sk_cfg_where(at ? at : material), name);
    }
    body->solid.type = body->group->type;
    body->solid.dim = model->dim;
    body->solid.mat = &body->material;
    SK_TRY(sk_cfg_vector(entry, "velocity", 0, 3, (double[3]){0, 0, 0}, body->velocity));
    SK_TRY(sk_cfg_vector(entry, "angular_velocity", 0, 3, (double[3]){0, 0, 0}, body->angular_velocity));
    SK_TRY(sk_cfg_vector(entry, "center", 0, 3, (double[3]){0, 0, 0}, body->center));
    body->first_element = first;
    body->integrator = model->time.integrator;
    first += body->group->n_elems;
    SK_TRY(read_body_plugin(entry, model, body));
  }
  model->n_elements = first;
  /* two bodies on one group, or on overlapping groups, would count the same elements twice */
  const sk_group **groups = calloc((size_t)model->n_bodies, sizeof *groups);
  char (*labels)[SK_NAME_MAX + 16] = calloc((size_t)model->n_bodies, sizeof *labels);
  const char **names = calloc((size_t)model->n_bodies, sizeof *names);
  sk_status status = groups && labels && names ? SK_OK : sk_error_set(SK_ERR_NOMEM, "out of memory");
  for (int b = 0; b < model->n_bodies && status == SK_OK; ++b) {
    groups[b] = model->bodies[b].group;
    snprintf(labels[b], sizeof labels[b], "body '%s'", model->bodies[b].name);
    names[b] = labels[b];
  }
  if (status == SK_OK) status = sk_mesh_check_disjoint(&model->mesh, groups, names, model->n_bodies);
  free(groups);
  free(labels);
  free(names);
  if (status != SK_OK) return sk_error_prefix(status, "%s: ", sk_cfg_where(list));
  return SK_OK;
}

/* ---- boundary conditions ---------------------------------------------------------------------------------------- */

static sk_status read_boundary(const sk_cfg *root, sk_model *model) {
  const sk_cfg *list = sk_cfg_get(root, "boundary");
  int n = sk_cfg_size(list);
  if (list && sk_cfg_kind_of(list) != SK_CFG_SEQ) return fail_at(list, "%s", "expects a list of conditions");
  model->dirichlet = calloc((size_t)(n > 0 ? n : 1), sizeof(sk_dirichlet));
  model->tractions = calloc((size_t)(n > 0 ? n : 1), sizeof(sk_traction));
  model->resultants = calloc((size_t)(n > 0 ? n : 1), sizeof(sk_resultant));
  if (!model->dirichlet || !model->tractions || !model->resultants)
    return sk_error_set(SK_ERR_NOMEM, "%s: out of memory for the boundary conditions", sk_cfg_where(root));
  for (int k = 0; k < n; ++k) {
    const sk_cfg *entry = sk_cfg_at(list, k);
    const char *group_name, *name;
    SK_TRY(sk_cfg_string(entry, "group", 1, NULL, &group_name));
    SK_TRY(sk_cfg_string(entry, "name", 0, group_name, &name));
    const sk_cfg *displacement = sk_cfg_get(entry, "displacement");
    const sk_cfg *traction = sk_cfg_get(entry, "traction");
    const sk_cfg *resultant = sk_cfg_get(entry, "resultant");
    if (!!displacement + !!traction + !!resultant != 1)
      return sk_error_set(SK_ERR_INPUT, "%s: boundary '%s' needs exactly one of `displacement`, `traction` or "
                          "`resultant`", sk_cfg_where(entry), name);
    if (!resultant && sk_cfg_get(entry, "area"))
      return fail_at(sk_cfg_get(entry, "area"), "%s", "belongs to a `resultant` condition");
    const sk_group *group;
    if (displacement) {
      SK_TRY(require_group(model, sk_cfg_get(entry, "group"), group_name, -1, &group));
      sk_dirichlet *bc = &model->dirichlet[model->n_dirichlet++];
      copy_name(bc->name, name);
      SK_TRY(sk_group_nodes(group, &bc->nodes, &bc->n_nodes));
      if (sk_cfg_kind_of(displacement) != SK_CFG_SEQ || sk_cfg_size(displacement) != model->dim)
        return fail_at(displacement, "expects %s components (a number, or ~ for a free component)",
                       model->dim == 2 ? "2" : "3");
      for (int i = 0; i < model->dim; ++i) {
        const sk_cfg *c = sk_cfg_at(displacement, i);
        const char *text = sk_cfg_scalar(c);
        if (text && (strcmp(text, "~") == 0 || strcmp(text, "null") == 0 || strcmp(text, "") == 0 ||
                     strcmp(text, "free") == 0))
          continue;
        bc->fixed[i] = 1;
        SK_TRY(sk_cfg_as_double(c, &bc->value[i]));
      }
      SK_TRY(read_history(entry, "history", &bc->history));
    } else if (resultant) {
      SK_TRY(require_group(model, sk_cfg_get(entry, "group"), group_name, model->dim - 1, &group));
      sk_resultant *load = &model->resultants[model->n_resultants++];
      copy_name(load->name, name);
      load->faces = group;
      SK_TRY(sk_cfg_vector(entry, "resultant", 1, model->dim, NULL, load->resultant));
      const char *area;
      SK_TRY(sk_cfg_string(entry, "area", 0, "reference", &area));
      if (strcmp(area, "reference") != 0 && strcmp(area, "current") != 0)
        return fail_at(sk_cfg_get(entry, "area"), "is '%s'; expected reference or current", area);
      load->current_area = strcmp(area, "current") == 0;
      SK_TRY(read_history(entry, "history", &load->history));
    } else {
      SK_TRY(require_group(model, sk_cfg_get(entry, "group"), group_name, model->dim - 1, &group));
      sk_traction *load = &model->tractions[model->n_tractions++];
      copy_name(load->name, name);
      load->faces = group;
      SK_TRY(sk_cfg_vector(entry, "traction", 1, model->dim, NULL, load->traction));
      SK_TRY(read_history(entry, "history", &load->history));
    }
  }
  SK_TRY(sk_cfg_vector(root, "body_force", 0, 3, (double[3]){0, 0, 0}, model->body_force));
  return SK_OK;
}

/* ---- contact ---------------------------------------------------------------------------------------------------- */

static sk_status build_surface(const sk_model *model, const sk_cfg *at, const char *name, sk_surface *surface) {
  const sk_group *faces;
  SK_TRY(require_group(model, at, name, model->dim - 1, &faces));
  int body = faces->n_elems > 0 ? sk_model_body_of_node(model, faces->conn[0]) : -1;
  if (body < 0) return fail_at(at, "surface '%s' does not lie on any body listed under `bodies`", name);
  sk_status status = sk_surface_build(&model->mesh, faces, model->bodies[body].group, body, surface);
  if (status != SK_OK) return sk_error_prefix(status, "%s: ", sk_cfg_where(at));
  return SK_OK;
}

static const char *const obstacle_names[] = {"plane", "sphere", "cylinder", "parabolic-cylinder", NULL};

static sk_status read_obstacle(const sk_cfg *node, int dim, sk_obstacle *obstacle) {
  int kind;
  SK_TRY(sk_cfg_choice(node, "type", 1, obstacle_names, 0, &kind));
  obstacle->kind = (sk_obstacle_kind)kind;
  const char *name;
  SK_TRY(sk_cfg_string(node, "name", 0, obstacle_names[kind], &name));
  copy_name(obstacle->name, name);
  SK_TRY(sk_cfg_vector(node, "point", 0, 3, (double[3]){0, 0, 0}, obstacle->point));
  double up[3] = {0, dim == 2 ? 1 : 0, dim == 2 ? 0 : 1};
  SK_TRY(sk_cfg_vector(node, "normal", 0, 3, up, obstacle->normal));
  SK_TRY(sk_cfg_vector(node, "axis", 0, 3, (double[3]){0, dim == 2 ? 0 : 1, dim == 2 ? 1 : 0}, obstacle->axis));
  SK_TRY(sk_cfg_double(node, "radius", kind == SK_OBSTACLE_SPHERE || kind == SK_OBSTACLE_CYLINDER, 0,
                       &obstacle->radius));
  SK_TRY(sk_cfg_double(node, "c", kind == SK_OBSTACLE_PARABOLIC_CYLINDER, 0, &obstacle->c));
  if ((kind == SK_OBSTACLE_SPHERE || kind == SK_OBSTACLE_CYLINDER) && !(obstacle->radius > 0))
    return fail_at(sk_cfg_get(node, "radius"), "%s", "must be positive");
  double normal_length = sqrt(obstacle->normal[0] * obstacle->normal[0] + obstacle->normal[1] * obstacle->normal[1] +
                              obstacle->normal[2] * obstacle->normal[2]);
  if (!(normal_length > 0)) return fail_at(node, "%s", "obstacle normal is zero");
  for (int i = 0; i < 3; ++i) obstacle->normal[i] /= normal_length;
  const sk_cfg *motion = sk_cfg_get(node, "motion");
  sk_cfg_note_default(node, "motion", "at rest", 0, NULL);
  int n = sk_cfg_size(motion);
  if (n > SK_OBSTACLE_MOTION_MAX) return fail_at(motion, "%s", "has more than 64 points");
  for (int k = 0; k < n; ++k) {
    const sk_cfg *row = sk_cfg_at(motion, k);
    if (sk_cfg_kind_of(row) != SK_CFG_SEQ || sk_cfg_size(row) != 4)
      return fail_at(row, "%s", "expects [time, dx, dy, dz]");
    SK_TRY(sk_cfg_as_double(sk_cfg_at(row, 0), &obstacle->motion_t[k]));
    for (int i = 0; i < 3; ++i) SK_TRY(sk_cfg_as_double(sk_cfg_at(row, i + 1), &obstacle->motion_d[k][i]));
    if (k > 0 && !(obstacle->motion_t[k] > obstacle->motion_t[k - 1]))
      return fail_at(row, "%s", "times must increase strictly");
  }
  obstacle->n_motion = n;
  return SK_OK;
}

static uint64_t capabilities_needed(const sk_model *model, const sk_contact_pair *pair) {
  uint64_t caps = model->dim == 2 ? SK_CAP_2D : SK_CAP_3D;
  caps |= pair->has_obstacle ? SK_CAP_RIGID_OBSTACLE : SK_CAP_DEFORMABLE_MASTER;
  if (pair->self_contact) caps |= SK_CAP_SELF_CONTACT;
  return caps | model->time.integrator->plugin_caps;
}

static sk_status check_kind(const sk_cfg *at, const sk_plugin *plugin, sk_kind kind, const char *what,
                            const char *name) {
  if (plugin->kinds & kind) return SK_OK;
  return sk_error_set(SK_ERR_PLUGIN, "%s: %s '%s': plugin '%s' does not attach to a %s (it is a %s plugin)",
                      sk_cfg_where(at), what, name, plugin->name, what, kind == SK_KIND_BODY ? "contact-pair" : "body");
}

/* `strategy:` of a pair or body: one of the plugin's strategies (the first by default). */
static sk_status choose_strategy(const sk_cfg *entry, const sk_plugin *plugin, int *strategy) {
  const char *name;
  SK_TRY(sk_cfg_string(entry, "strategy", 0, plugin->strategies[0], &name));
  *strategy = -1;
  for (int s = 0; plugin->strategies[s]; ++s)
    if (strcmp(plugin->strategies[s], name) == 0) *strategy = s;
  if (*strategy < 0) {
    char allowed[256] = "";
    for (int s = 0; plugin->strategies[s]; ++s)
      snprintf(allowed + strlen(allowed), sizeof allowed - strlen(allowed), "%s%s", s ? ", " : "",
               plugin->strategies[s]);
    return sk_error_set(SK_ERR_INPUT, "%s: plugin '%s' has no strategy '%s' (it offers: %s)",
                        sk_cfg_where(sk_cfg_get(entry, "strategy")), plugin->name, name, allowed);
  }
  if (*strategy > 0 && !(plugin->caps & SK_CAP_CONDENSATION))
    return sk_error_set(SK_ERR_PLUGIN, "%s: plugin '%s' offers strategy '%s' without the condensation capability",
                        sk_cfg_where(sk_cfg_get(entry, "strategy")), plugin->name, name);
  return SK_OK;
}

/* What every pair of an entry shares: the plugin, its kind, strategy and parameters. */
static sk_status read_pair_plugin(const sk_cfg *entry, const char *name, sk_contact_pair *pair) {
  const char *plugin_name;
  SK_TRY(sk_cfg_string(entry, "plugin", 1, NULL, &plugin_name));
  sk_status status = sk_plugin_load(plugin_name, &pair->plugin);
  if (status != SK_OK)
    return sk_error_prefix(status, "%s: contact pair '%s': ", sk_cfg_where(sk_cfg_get(entry, "plugin")), name);
  SK_TRY(check_kind(sk_cfg_get(entry, "plugin"), pair->plugin, SK_KIND_PAIR, "contact pair", name));
  pair->params = sk_cfg_get(entry, "parameters");
  return choose_strategy(entry, pair->plugin, &pair->strategy);
}

/* Whatever the plugin cannot run is refused now, naming the plugins that can (not in begin_step). */
static sk_status check_pair(const sk_cfg *entry, sk_model *model, int k) {
  sk_contact_pair *pair = &model->pairs[k];
  char where[SK_NAME_MAX + 1200];
  snprintf(where, sizeof where, "%s: contact pair '%s'", sk_cfg_where(entry), pair->name);
  sk_scene_description description;
  sk_describe_pair(model, k, &description);
  SK_TRY(sk_check_attachment(pair->plugin, &description,
                             capabilities_needed(model, pair) | (description.info.friction ? SK_CAP_FRICTION : 0),
                             where));
  SK_TRY(sk_check_glued(model, k, where));
  /* the warnings once per entry, not once per pair it creates */
  if (k > 0 && model->pairs[k - 1].entry == pair->entry) return SK_OK;
  if (model->time.integrator->energy_momentum && !(pair->plugin->caps & SK_CAP_ENERGY_MOMENTUM))
    sk_log_message(model->rank, 1,
                   "contact pair '%s': plugin '%s' is not energy-consistent with the midpoint scheme: momenta are "
                   "kept, energy is not conserved through contact",
                   pair->name, pair->plugin->name);
  if ((pair->plugin->caps & SK_CAP_NEEDS_CURVATURE) &&
      (straight_faces(&pair->slave) || (!pair->has_obstacle && straight_faces(&pair->master))))
    sk_log_message(model->rank, 1,
                   "contact pair '%s': plugin '%s' uses surface curvature, which vanishes on straight (LINE2/TRI3) "
                   "faces",
                   pair->name, pair->plugin->name);
  return SK_OK;
}

static sk_status read_explicit_pair(const sk_cfg *entry, sk_model *model, int k) {
  sk_contact_pair *pair = &model->pairs[k];
  const char *name, *slave_name, *master_name;
  char default_name[32];
  snprintf(default_name, sizeof default_name, "pair-%d", pair->entry);
  SK_TRY(sk_cfg_string(entry, "name", 0, default_name, &name));
  copy_name(pair->name, name);
  SK_TRY(read_pair_plugin(entry, name, pair));
  if (sk_cfg_get(entry, "obstacles"))
    return fail_at(sk_cfg_get(entry, "obstacles"), "%s",
                   "goes with `bodies` (every listed body against each obstacle); a pair with one obstacle gives it "
                   "as `obstacle`");
  SK_TRY(sk_cfg_string(entry, "slave", 1, NULL, &slave_name));
  SK_TRY(build_surface(model, sk_cfg_get(entry, "slave"), slave_name, &pair->slave));
  SK_TRY(sk_cfg_string(entry, "master", 0, NULL, &master_name));
  const sk_cfg *obstacle = sk_cfg_get(entry, "obstacle");
  if (!!master_name == !!obstacle)
    return sk_error_set(SK_ERR_INPUT, "%s: contact pair '%s' needs exactly one of `master` or `obstacle`",
                        sk_cfg_where(entry), name);
  if (master_name && strcmp(master_name, slave_name) == 0) {
    pair->self_contact = 1;
    pair->master = pair->slave; /* shares the slave's arrays (freed once) */
  } else if (master_name) {
    SK_TRY(build_surface(model, sk_cfg_get(entry, "master"), master_name, &pair->master));
  } else {
    SK_TRY(read_obstacle(obstacle, model->dim, &pair->obstacle));
    pair->has_obstacle = 1;
  }
  return SK_OK;
}

/* ---- pairs created among many bodies: contact: [{name: all, bodies: all | [a, b, ...], obstacles: [...]}] ------- */

typedef struct {
  int n_bodies;
  int *bodies;     /* model body indices, in the order listed (`all`: the scene's order) */
  int n_obstacles;
} body_set;

static int body_index_of(const sk_model *model, const char *name) {
  for (int b = 0; b < model->n_bodies; ++b)
    if (strcmp(model->bodies[b].name, name) == 0) return b;
  return -1;
}

/* The bodies of an entry with `bodies:`: `all`, or a list of body names (each known, none twice), at least two of
 * them unless obstacles are listed too. */
static sk_status read_body_set(const sk_cfg *entry, const sk_model *model, body_set *set) {
  const sk_cfg *node = sk_cfg_get(entry, "bodies");
  const sk_cfg *obstacles = sk_cfg_get(entry, "obstacles");
  static const char *const per_pair[] = {"slave", "master", "obstacle"};
  for (int k = 0; k < 3; ++k)
    if (sk_cfg_peek(entry, per_pair[k]))
      return sk_error_set(SK_ERR_INPUT, "%s: `%s` does not go with `bodies`: the entry creates its pairs from the "
                          "bodies' boundaries (obstacles: `obstacles`); a single pair gives `slave` and `master` or "
                          "`obstacle` without `bodies`", sk_cfg_where(sk_cfg_peek(entry, per_pair[k])), per_pair[k]);
  if (obstacles && sk_cfg_kind_of(obstacles) != SK_CFG_SEQ)
    return fail_at(obstacles, "%s", "expects a list of obstacles (each as a pair's `obstacle`)");
  set->n_obstacles = sk_cfg_size(obstacles);
  set->bodies = malloc(sizeof(int) * (size_t)(model->n_bodies > 0 ? model->n_bodies : 1));
  if (!set->bodies) return sk_error_set(SK_ERR_NOMEM, "%s: out of memory", sk_cfg_where(node));
  set->n_bodies = 0;
  const char *word = sk_cfg_scalar(node);
  if (word) {
    if (strcmp(word, "all") != 0)
      return fail_at(node, "%s", "expects `all` or a list of body names, e.g. [disk-1, disk-2]");
    for (int b = 0; b < model->n_bodies; ++b) set->bodies[set->n_bodies++] = b;
  } else if (sk_cfg_kind_of(node) == SK_CFG_SEQ) {
    for (int i = 0; i < sk_cfg_size(node); ++i) {
      const sk_cfg *item = sk_cfg_at(node, i);
      const char *name = sk_cfg_scalar(item);
      const int b = name ? body_index_of(model, name) : -1;
      if (b < 0) {
        char known[1024] = "";
        for (int c = 0; c < model->n_bodies; ++c)
          snprintf(known + strlen(known), sizeof known - strlen(known), "%s%s", c ? ", " : "", model->bodies[c].name);
        return sk_error_set(SK_ERR_INPUT, "%s: unknown body '%s' (the scene's bodies: %s)", sk_cfg_where(item),
                            name ? name : "(not a name)", known);
      }
      for (int j = 0; j < set->n_bodies; ++j)
        if (set->bodies[j] == b) return fail_at(item, "body '%s' is listed twice", name);
      set->bodies[set->n_bodies++] = b;
    }
  } else {
    return fail_at(node, "%s", "expects `all` or a list of body names, e.g. [disk-1, disk-2]");
  }
  if (set->n_bodies < 2 && set->n_obstacles == 0)
    return sk_error_set(SK_ERR_INPUT, "%s: `bodies` gives %d body and no `obstacles`: no pair to create (contact among "
                        "bodies needs two of them; a body against a rigid obstacle is a pair with `obstacle`)",
                        sk_cfg_where(node), set->n_bodies);
  return SK_OK;
}

static int pairs_of_set(const body_set *set) {
  return set->n_bodies * (set->n_bodies - 1) / 2 + set->n_bodies * set->n_obstacles;
}

/* Reference sizes of a body's boundary: the mean corner-to-corner edge length decides which side is slave. */
static double mean_face_size(const sk_model *model, const sk_surface *surface) {
  double h_min, h_mean, h_max, measure;
  sk_surface_sizes(surface, model->mesh.x, 3, &h_min, &h_mean, &h_max, &measure);
  return h_mean;
}

/* The pairs of one `bodies:` entry, from pairs[*k] on. Between two bodies the slave is the one whose boundary has the
 * smaller mean face size (the finer mesh: its nodes do not fall between the master's); within 1e-9 relative the
 * one listed first (deterministic). */
static sk_status create_body_pairs(const sk_cfg *entry, int entry_index, sk_model *model, const body_set *set,
                                   int *k) {
  const char *name;
  SK_TRY(sk_cfg_string(entry, "name", 0, "all", &name));
  for (int i = 0; i < set->n_bodies; ++i) {
    for (int j = i + 1; j < set->n_bodies + set->n_obstacles; ++j) {
      sk_contact_pair *pair = &model->pairs[*k];
      pair->entry = entry_index;
      pair->generated = 1;
      SK_TRY(read_pair_plugin(entry, name, pair));
      const sk_body *a = &model->bodies[set->bodies[i]];
      char boundary_name[SK_NAME_MAX + 16];
      snprintf(boundary_name, sizeof boundary_name, "%s-boundary", a->name);
      sk_surface first;
      SK_TRY(sk_surface_build_boundary(&model->mesh, a->group, set->bodies[i], boundary_name, &first));
      if (j >= set->n_bodies) {
        pair->slave = first;
        pair->has_obstacle = 1;
        model->n_pairs = *k + 1; /* sk_model_free frees its surface on an error */
        SK_TRY(read_obstacle(sk_cfg_at(sk_cfg_get(entry, "obstacles"), j - set->n_bodies), model->dim,
                             &pair->obstacle));
        snprintf(pair->name, sizeof pair->name, "%s:%s/%s", name, a->name, pair->obstacle.name);
      } else {
        const sk_body *b = &model->bodies[set->bodies[j]];
        snprintf(boundary_name, sizeof boundary_name, "%s-boundary", b->name);
        sk_surface second;
        sk_status status = sk_surface_build_boundary(&model->mesh, b->group, set->bodies[j], boundary_name, &second);
        if (status != SK_OK) {
          sk_surface_free(&first);
          return status;
        }
        const double h_first = mean_face_size(model, &first), h_second = mean_face_size(model, &second);
        const int swap = h_second < h_first * (1.0 - 1e-9);
        pair->slave = swap ? second : first;
        pair->master = swap ? first : second;
        snprintf(pair->name, sizeof pair->name, "%s:%s/%s", name, swap ? b->name : a->name, swap ? a->name : b->name);
      }
      model->n_pairs = ++*k;
      SK_TRY(check_pair(entry, model, *k - 1));
    }
  }
  return SK_OK;
}

/* Two entries must not both create contact between the same two bodies (or a body and the same obstacle entry):
 * the forces would be added twice. Explicit pairs between two bodies count as that pair of bodies. */
static sk_status check_pairs_unique(const sk_cfg *list, const sk_model *model) {
  for (int k = 0; k < model->n_pairs; ++k) {
    const sk_contact_pair *p = &model->pairs[k];
    if (p->has_obstacle || p->self_contact) continue;
    for (int l = k + 1; l < model->n_pairs; ++l) {
      const sk_contact_pair *q = &model->pairs[l];
      if (q->has_obstacle || q->self_contact || (!p->generated && !q->generated)) continue;
      const int same = (p->slave.body == q->slave.body && p->master.body == q->master.body) ||
                       (p->slave.body == q->master.body && p->master.body == q->slave.body);
      if (!same) continue;
      const sk_cfg *at = sk_cfg_at(list, q->entry);
      return sk_error_set(SK_ERR_INPUT,
                          "%s: contact pair '%s' puts bodies '%s' and '%s' in contact, and so does pair '%s' (%s): "
                          "contact between two bodies is given once (leave one of them out of `bodies`, or drop the "
                          "explicit pair)",
                          sk_cfg_where(at), q->name, model->bodies[q->slave.body].name,
                          model->bodies[q->master.body].name, p->name, sk_cfg_where(sk_cfg_at(list, p->entry)));
    }
  }
  return SK_OK;
}

static sk_status read_contact(const sk_cfg *root, sk_scene *scene) {
  sk_model *model = &scene->model;
  const sk_cfg *list = sk_cfg_get(root, "contact");
  const int n_entries = sk_cfg_size(list);
  if (list && sk_cfg_kind_of(list) != SK_CFG_SEQ) return fail_at(list, "%s", "expects a list of contact pairs");
  body_set *sets = calloc((size_t)(n_entries > 0 ? n_entries : 1), sizeof *sets);
  if (!sets) return sk_error_set(SK_ERR_NOMEM, "%s: out of memory for the contact pairs", sk_cfg_where(root));
  sk_status status = SK_OK;
  int n = 0;
  for (int e = 0; e < n_entries && status == SK_OK; ++e) {
    const sk_cfg *entry = sk_cfg_at(list, e);
    if (sk_cfg_peek(entry, "bodies")) {
      status = read_body_set(entry, model, &sets[e]);
      n += pairs_of_set(&sets[e]);
    } else {
      n += 1;
    }
  }
  if (status == SK_OK) {
    model->pairs = calloc((size_t)(n > 0 ? n : 1), sizeof(sk_contact_pair));
    if (!model->pairs)
      status = sk_error_set(SK_ERR_NOMEM, "%s: out of memory for %d contact pairs", sk_cfg_where(root), n);
  }
  int k = 0;
  for (int e = 0; e < n_entries && status == SK_OK; ++e) {
    const sk_cfg *entry = sk_cfg_at(list, e);
    if (sets[e].bodies) {
      status = create_body_pairs(entry, e, model, &sets[e], &k);
    } else {
      model->pairs[k].entry = e;
      model->n_pairs = ++k; /* what is built so far: sk_model_free frees it on an error */
      status = read_explicit_pair(entry, model, k - 1);
      if (status == SK_OK) status = check_pair(entry, model, k - 1);
    }
  }
  for (int e = 0; e < n_entries; ++e) free(sets[e].bodies);
  free(sets);
  if (status == SK_OK) status = check_pairs_unique(list, model);
  /* one reaction per obstacle: the pairs of one entry's obstacle share it */
  for (int p = 0; p < model->n_pairs; ++p) {
    sk_contact_pair *pair = &model->pairs[p];
    pair->obstacle_column = -1;
    if (!pair->has_obstacle) continue;
    for (int q = 0; q < p && pair->obstacle_column < 0; ++q)
      if (model->pairs[q].has_obstacle && model->pairs[q].generated && pair->generated &&
          model->pairs[q].entry == pair->entry && strcmp(model->pairs[q].obstacle.name, pair->obstacle.name) == 0)
        pair->obstacle_column = model->pairs[q].obstacle_column;
    if (pair->obstacle_column < 0) pair->obstacle_column = model->n_obstacle_columns++;
  }
  return status;
}

/* ---- time, solver, output --------------------------------------------------------------------------------------- */

static sk_status read_time(const sk_cfg *root, sk_time_options *time) {
  const sk_cfg *node = sk_cfg_get(root, "time");
  if (!node) return sk_error_set(SK_ERR_INPUT, "%s: missing key 'time'", sk_cfg_where(root));
  int scheme;
  const char *const *scheme_names = sk_time_integrator_names();
  SK_TRY(sk_cfg_choice(node, "scheme", 1, scheme_names, 0, &scheme));
  time->integrator = sk_time_integrator_find(scheme_names[scheme]);
  SK_TRY(sk_cfg_double(node, "dt", 1, 0, &time->dt));
  SK_TRY(sk_cfg_double(node, "end", 1, 0, &time->t_end));
  SK_TRY(sk_cfg_double(node, "start", 0, 0, &time->t_start));
  SK_TRY(sk_cfg_int(node, "max_cuts", 0, 6, &time->max_cuts));
  if (!(time->dt > 0)) return fail_at(sk_cfg_get(node, "dt"), "%s", "must be positive");
  if (!(time->t_end > time->t_start)) return fail_at(sk_cfg_get(node, "end"), "%s", "must be larger than `start`");
  /* a step below the resolution of t would never advance it (t + dt == t): the run would loop forever */
  if (time->dt < 64 * DBL_EPSILON * fmax(fabs(time->t_start), fabs(time->t_end)))
    return fail_at(sk_cfg_get(node, "dt"), "%s", "is too small to advance the time between `start` and `end`");
  if (time->max_cuts < 0 || time->max_cuts > 30) return fail_at(sk_cfg_get(node, "max_cuts"), "%s", "must be 0..30");
  return SK_OK;
}

/* in sk_linear_solver_kind order */
static const char *const linear_names[] = {"direct", "gmres-muelu", "gmres-ilu", "auto",     "mumps",
                                           "klu2",   "klu",         "gmres-sgs", "gmres-jacobi", NULL};
/* in sk_line_search order, then the default: the full step, retried with backtracking when the step fails */
static const char *const line_search_names[] = {"full-step", "backtrack", "polynomial", "full-step-then-backtrack", NULL};
enum { FULL_STEP_THEN_BACKTRACK = 3 };
static const char *const predictor_names[] = {"last-state", "previous-increment", NULL};

/* The decisions of solver.linear.solver `auto`, as information (not shown with --quiet). */
static void log_linear_decision(void *ctx, const char *line) {
  (void)ctx;
  sk_log_message(0, 0, "linear solver (auto): %s", line); /* the bridge calls it on rank 0 only */
}

/* The line search by default is the full Newton step, and a step whose Newton fails is solved again with backtracking
 * before it is cut: backtracking converges the frictional scenes a user writes from the scene reference where the
 * full step stalls in step 1, but as the only search it fails cases the full step runs (a graded patch test, mortar-dual
 * on stacked blocks) and costs iterations where the full step converges — docs/linear-solvers.md, "Line search". */
static sk_status read_solver(const sk_cfg *root, sk_solver_settings *solver) {
  const sk_cfg *node = sk_cfg_section(root, "solver");
  if (node && sk_cfg_kind_of(node) != SK_CFG_MAP)
    return fail_at(node, "%s", "expects a map with `newton` and/or `linear`");
  sk_newton_options_default(&solver->newton);
  sk_linear_options_default(&solver->linear);
  const sk_cfg *newton = sk_cfg_section(node, "newton");
  const sk_cfg *linear = sk_cfg_section(node, "linear");
  int line_search = FULL_STEP_THEN_BACKTRACK, kind = (int)solver->linear.kind;
  SK_TRY(sk_cfg_double(newton, "tolerance", 0, solver->newton.relative_tolerance, &solver->newton.relative_tolerance));
  SK_TRY(sk_cfg_double(newton, "absolute_tolerance", 0, solver->newton.residual_tolerance,
                       &solver->newton.residual_tolerance));
  SK_TRY(sk_cfg_double(newton, "update_tolerance", 0, solver->newton.update_tolerance,
                       &solver->newton.update_tolerance));
  SK_TRY(sk_cfg_int(newton, "max_iterations", 0, solver->newton.max_iterations, &solver->newton.max_iterations));
  SK_TRY(sk_cfg_choice(newton, "line_search", 0, line_search_names, line_search, &line_search));
  SK_TRY(sk_cfg_bool(newton, "verbose", 0, solver->newton.verbose, &solver->newton.verbose));
  SK_TRY(sk_cfg_bool(newton, "inexact", 0, solver->newton.forcing, &solver->newton.forcing));
  SK_TRY(sk_cfg_choice(newton, "predictor", 0, predictor_names, 0, &solver->predictor));
  SK_TRY(sk_cfg_bool(newton, "predicted_update", 0, 0, &solver->newton.predicted_update));
  SK_TRY(sk_cfg_int(newton, "max_active_set_loops", 0, 10, &solver->max_active_set_loops));
  if (solver->max_active_set_loops < 1)
    return fail_at(sk_cfg_get(newton, "max_active_set_loops"), "%s", "must be at least 1");
  SK_TRY(sk_cfg_int(node, "pattern_margin", 0, 0, &solver->pattern_margin));
  if (solver->pattern_margin < 0 || solver->pattern_margin > 3)
    return fail_at(sk_cfg_get(node, "pattern_margin"), "%s", "must be 0..3");
  solver->backtrack_retry = line_search == FULL_STEP_THEN_BACKTRACK;
  solver->newton.line_search = solver->backtrack_retry ? SK_LINE_SEARCH_FULL_STEP : (sk_line_search)line_search;
  SK_TRY(sk_cfg_choice(linear, "solver", 0, linear_names, kind, &kind));
  solver->linear.kind = (sk_linear_solver_kind)kind;
  solver->linear.log = log_linear_decision;
  SK_TRY(sk_cfg_double(linear, "tolerance", 0, solver->linear.tolerance, &solver->linear.tolerance));
  SK_TRY(sk_cfg_int(linear, "max_iterations", 0, solver->linear.max_iterations, &solver->linear.max_iterations));
  if (!(solver->newton.relative_tolerance > 0) || !(solver->newton.residual_tolerance > 0))
    return fail_at(newton, "%s", "tolerances must be positive");
  if (solver->newton.max_iterations < 1) return fail_at(newton, "%s", "max_iterations must be at least 1");
  return SK_OK;
}

static sk_status read_output(const sk_cfg *root, sk_output_settings *output) {
  const sk_cfg *node = sk_cfg_section(root, "output");
  SK_TRY(sk_cfg_int(node, "vtu_every", 0, 10, &output->vtu_every));
  SK_TRY(sk_cfg_bool(node, "vtu", 0, 1, &output->write_vtu));
  SK_TRY(sk_cfg_bool(node, "contact_csv", 0, 1, &output->write_contact_csv));
  if (output->vtu_every < 0) return fail_at(sk_cfg_get(node, "vtu_every"), "%s", "must be >= 0");
  return SK_OK;
}

/* ---- the whole scene -------------------------------------------------------------------------------------------- */

static sk_status build(sk_scene *scene) {
  sk_model *model = &scene->model;
  const sk_cfg *root = scene->cfg;
  const char *description;
  SK_TRY(sk_cfg_string(root, "description", 0, "", &description));
  snprintf(scene->description, sizeof scene->description, "%s", description);
  SK_TRY(read_time(root, &model->time));
  SK_TRY(read_solver(root, &scene->solver));
  SK_TRY(read_output(root, &scene->output));
  SK_TRY(load_meshes(root, &model->mesh));
  model->dim = model->mesh.dim;
  char from_mesh[32];
  snprintf(from_mesh, sizeof from_mesh, "from the mesh: %d", model->dim);
  sk_cfg_note_default(root, "dimension", from_mesh, 0, NULL);
  model->n_nodes = model->mesh.n_nodes;
  model->n_dofs = model->n_nodes * model->dim;
  model->X = malloc(sizeof(double) * (size_t)(model->n_dofs > 0 ? model->n_dofs : 1));
  if (!model->X) return sk_error_set(SK_ERR_NOMEM, "%s: out of memory for %d nodes", scene->path, model->n_nodes);
  for (int a = 0; a < model->n_nodes; ++a)
    for (int i = 0; i < model->dim; ++i) model->X[a * model->dim + i] = model->mesh.x[3 * a + i];
  SK_TRY(read_bodies(root, model));
  SK_TRY(read_boundary(root, model));
  SK_TRY(read_contact(root, scene));
  SK_TRY(sk_model_build(model));
  SK_TRY(sk_model_distribute(model));
  /* The system of terms creates the plugin instances now, so that their parameters are validated (and read) before
   * the unknown-key check. */
  SK_TRY(sk_system_create(model, &scene->solver, &scene->system));
  return sk_cfg_check_unused(root);
}

sk_status sk_scene_load_with(const char *path, const sk_scene_overrides *overrides, MPI_Comm comm,
                             sk_scene *scene) {
  memset(scene, 0, sizeof *scene);
  snprintf(scene->path, sizeof scene->path, "%s", path);
  scene->model.comm = comm;
  MPI_Comm_rank(comm, &scene->model.rank);
  MPI_Comm_size(comm, &scene->model.n_ranks);
  SK_TRY(sk_cfg_load(path, &scene->cfg));
  SK_TRY(sk_scene_apply_overrides(scene, overrides));
  SK_TRY(build(scene));
  return sk_scene_absolute_mesh_paths(scene);
}

sk_status sk_scene_load(const char *path, int n_sets, const char *const *sets, const char *plugin_override,
                        MPI_Comm comm, sk_scene *scene) {
  sk_scene_overrides overrides = {.n = n_sets, .assignments = sets, .modes = NULL, .plugin = plugin_override};
  return sk_scene_load_with(path, &overrides, comm, scene);
}

void sk_scene_free(sk_scene *scene) {
  sk_system_destroy(scene->system);
  scene->system = NULL;
  sk_model_free(&scene->model);
  sk_cfg_free(scene->cfg);
  scene->cfg = NULL;
  free(scene->provenance);
  scene->provenance = NULL;
}

/* What Newton does with a step (solver.newton; `stickslip keys` shows where each value comes from). */
static void explain_newton(const sk_solver_settings *solver, FILE *out) {
  const sk_newton_options *n = &solver->newton;
  fprintf(out, "Newton (solver.newton):\n");
  if (solver->backtrack_retry)
    fprintf(out, "  %-16s %s: full Newton steps; a step whose Newton fails is solved again from its start with the "
            "backtracking line search, and cut only if that fails too\n", "line_search",
            line_search_names[FULL_STEP_THEN_BACKTRACK]);
  else
    fprintf(out, "  %-16s %s in every iteration; a step whose Newton fails is cut\n", "line_search",
            line_search_names[n->line_search]);
  fprintf(out, "  %-16s ||F|| <= %g or ||F||/||F0|| <= %g, with ||dx|| <= %g (1 + ||x||); at most %d iterations\n",
          "convergence", n->residual_tolerance, n->relative_tolerance, n->update_tolerance, n->max_iterations);
}

void sk_scene_explain(const sk_scene *scene, const char *out_dir, int progress, FILE *out) {
  sk_mesh_cache_explain(out);
  const sk_system *sys = scene->system;
  int computed = 0;
  for (int k = 0; k < sys->n_terms; ++k) computed += sk_term_plugin_explain_defaults(sys->terms[k], NULL);
  if (computed) {
    fprintf(out, "parameters computed from the scene (a value the scene gives wins; the plugins' pages state the "
            "rules):\n");
    for (int k = 0; k < sys->n_terms; ++k) sk_term_plugin_explain_defaults(sys->terms[k], out);
  }
  int created = 0;
  for (int k = 0; k < sys->n_terms; ++k) created += sk_term_plugin_explain_pair(sys->terms[k], NULL);
  if (created) {
    fprintf(out, "contact pairs created by `bodies:` (%d; the broad phase keeps pairs whose surfaces are apart from "
            "calling their plugin, docs/contact-services.md):\n", created);
    for (int k = 0; k < sys->n_terms; ++k) sk_term_plugin_explain_pair(sys->terms[k], out);
  }
  sk_system_explain(sys, out);
  explain_newton(&scene->solver, out);
  const sk_output_settings *o = &scene->output;
  fprintf(out, "outputs:\n");
  if (out_dir || progress || sk_skip_forced("invariants"))
    fprintf(out, "  %-16s computed: strain and kinetic energy, momenta, reactions and contact totals per step (%s)\n",
            "history", out_dir ? "history.csv" : progress ? "the progress line shows the energy" : "STICKSLIP_NO_SKIP");
  else
    fprintf(out, "  %-16s skipped: energies and momenta (--quiet and no --out: nobody reads them)\n", "invariants");
  if (!out_dir) {
    fprintf(out, "  %-16s skipped: no --out DIR, no result files (with --out: output.vtu, output.vtu_every)\n",
            "stress, vtu");
  } else if (!o->write_vtu) {
    fprintf(out, "  %-16s skipped: output.vtu is false\n", "stress, vtu");
  } else {
    if (o->vtu_every > 0)
      fprintf(out, "  %-16s computed every %d steps and at the last (output.vtu_every)\n", "stress, vtu", o->vtu_every);
    else
      fprintf(out, "  %-16s computed at the last step only (output.vtu_every: 0)\n", "stress, vtu");
  }
  if (!out_dir || !o->write_contact_csv || scene->model.n_pairs == 0)
    fprintf(out, "  %-16s skipped: %s\n", "contact.csv",
            !out_dir ? "no --out DIR" : !o->write_contact_csv ? "output.contact_csv is false" : "no contact pairs");
  else if (o->vtu_every > 0)
    fprintf(out, "  %-16s computed: the contact points every %d steps and at the last (output.vtu_every)\n",
            "contact.csv", o->vtu_every);
  else
    fprintf(out, "  %-16s computed: the contact points of the initial state and the last step (output.vtu_every: "
            "0)\n", "contact.csv");
}
