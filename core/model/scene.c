/* Scene → model: every key of docs/scene-reference.md is read here, and every error names the file, line and key. */
#define _GNU_SOURCE
#include "stickslip/scene.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "stickslip/plugins.h"

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

double sk_history_value(const sk_history *history, double t) {
  if (history->n == 0) return 1.0;
  if (t <= history->t[0]) return history->v[0];
  for (int k = 1; k < history->n; ++k) {
    if (t <= history->t[k]) {
      double s = (t - history->t[k - 1]) / (history->t[k] - history->t[k - 1]);
      return (1.0 - s) * history->v[k - 1] + s * history->v[k];
    }
  }
  return history->v[history->n - 1];
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

/* Loads one mesh entry {file, parameters, name, rotate, translate}. */
static sk_status load_mesh_entry(const sk_cfg *entry, int dim_wanted, sk_mesh *mesh, char *prefix) {
  const char *file;
  SK_TRY(sk_cfg_string(entry, "file", 1, NULL, &file));
  char path[1024];
  SK_TRY(sk_cfg_resolve_path(entry, file, path, sizeof path));
  const sk_cfg *params = sk_cfg_get(entry, "parameters");
  sk_mesh_param list[32];
  int n_params = sk_cfg_size(params);
  if (params && sk_cfg_kind_of(params) != SK_CFG_MAP) return fail_at(params, "%s", "expects a map name: value");
  if (n_params > 32) return fail_at(params, "%s", "has more than 32 parameters");
  for (int i = 0; i < n_params; ++i) {
    list[i].name = sk_cfg_key_at(params, i);
    SK_TRY(sk_cfg_as_double(sk_cfg_at(params, i), &list[i].value));
  }
  const char *name;
  SK_TRY(sk_cfg_string(entry, "name", 0, "", &name));
  snprintf(prefix, SK_NAME_MAX, "%s", name);
  sk_mesh_options options;
  sk_mesh_options_default(&options);
  options.dim = dim_wanted;
  int max_elements = (int)options.max_elements;
  SK_TRY(sk_cfg_int(entry, "max_elements", 0, max_elements, &max_elements));
  SK_TRY(sk_cfg_double(entry, "time_limit", 0, options.time_limit, &options.time_limit));
  options.max_elements = max_elements;
  sk_status status = sk_mesh_load_with(path, list, n_params, &options, mesh);
  if (status != SK_OK) return sk_error_prefix(status, "%s: ", sk_cfg_where(entry));

  double translate[3] = {0, 0, 0}, axis[3] = {0, 0, 1}, angle = 0;
  SK_TRY(sk_cfg_vector(entry, "translate", 0, 3, translate, translate));
  const sk_cfg *rotate = sk_cfg_get(entry, "rotate");
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

/* ---- bodies ----------------------------------------------------------------------------------------------------- */

static const char *const material_names[] = {"hooke", "svk", "neo-hooke", NULL};

static sk_status read_bodies(const sk_cfg *root, sk_model *model) {
  const sk_cfg *list = sk_cfg_get(root, "bodies");
  if (!list || sk_cfg_kind_of(list) != SK_CFG_SEQ || sk_cfg_size(list) < 1)
    return sk_error_set(SK_ERR_INPUT, "%s: key 'bodies' must list at least one body", sk_cfg_where(list ? list : root));
  model->n_bodies = sk_cfg_size(list);
  model->bodies = calloc((size_t)model->n_bodies, sizeof(sk_body));
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
    int kind;
    double E, nu, density;
    SK_TRY(sk_cfg_choice(material, "model", 1, material_names, 0, &kind));
    SK_TRY(sk_cfg_double(material, "E", 1, 0, &E));
    SK_TRY(sk_cfg_double(material, "nu", 1, 0, &nu));
    SK_TRY(sk_cfg_double(material, "density", model->time.scheme != SK_SCHEME_QUASISTATIC, 0, &density));
    sk_status status = sk_material_init(&body->material, (sk_material_model)kind, E, nu, density);
    if (status != SK_OK) return sk_error_prefix(status, "%s: body '%s': ", sk_cfg_where(material), name);
    body->solid.type = body->group->type;
    body->solid.dim = model->dim;
    body->solid.mat = &body->material;
    SK_TRY(sk_cfg_vector(entry, "velocity", 0, 3, (double[3]){0, 0, 0}, body->velocity));
    SK_TRY(sk_cfg_vector(entry, "angular_velocity", 0, 3, (double[3]){0, 0, 0}, body->angular_velocity));
    SK_TRY(sk_cfg_vector(entry, "center", 0, 3, (double[3]){0, 0, 0}, body->center));
    body->first_element = first;
    first += body->group->n_elems;
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
  for (int k = 0; k < n; ++k) {
    const sk_cfg *entry = sk_cfg_at(list, k);
    const char *group_name, *name;
    SK_TRY(sk_cfg_string(entry, "group", 1, NULL, &group_name));
    SK_TRY(sk_cfg_string(entry, "name", 0, group_name, &name));
    const sk_cfg *displacement = sk_cfg_get(entry, "displacement");
    const sk_cfg *traction = sk_cfg_get(entry, "traction");
    if (!!displacement == !!traction)
      return sk_error_set(SK_ERR_INPUT, "%s: boundary '%s' needs exactly one of `displacement` or `traction`",
                          sk_cfg_where(entry), name);
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

/* The body whose elements carry the surface's first node. */
static int body_of_group(const sk_model *model, const sk_group *faces) {
  if (faces->n_elems == 0) return -1;
  int node = faces->conn[0];
  for (int b = 0; b < model->n_bodies; ++b) {
    const sk_group *g = model->bodies[b].group;
    for (long k = 0; k < (long)g->n_elems * g->nen; ++k)
      if (g->conn[k] == node) return b;
  }
  return -1;
}

static sk_status build_surface(const sk_model *model, const sk_cfg *at, const char *name, sk_surface *surface) {
  const sk_group *faces;
  SK_TRY(require_group(model, at, name, model->dim - 1, &faces));
  int body = body_of_group(model, faces);
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

static uint64_t capabilities_needed(const sk_model *model, const sk_contact_pair *pair, double mu) {
  uint64_t caps = model->dim == 2 ? SK_CAP_2D : SK_CAP_3D;
  caps |= pair->has_obstacle ? SK_CAP_RIGID_OBSTACLE : SK_CAP_DEFORMABLE_MASTER;
  if (mu > 0) caps |= SK_CAP_FRICTION;
  switch (model->time.scheme) {
    case SK_SCHEME_QUASISTATIC: caps |= SK_CAP_QUASISTATIC; break;
    case SK_SCHEME_BACKWARD_EULER: caps |= SK_CAP_DYNAMICS; break;
    case SK_SCHEME_MIDPOINT: caps |= SK_CAP_DYNAMICS; break; /* energy consistency: a warning, see below */
  }
  return caps;
}

static sk_status read_contact(const sk_cfg *root, const char *plugin_override, sk_scene *scene) {
  sk_model *model = &scene->model;
  const sk_cfg *list = sk_cfg_get(root, "contact");
  int n = sk_cfg_size(list);
  if (list && sk_cfg_kind_of(list) != SK_CFG_SEQ) return fail_at(list, "%s", "expects a list of contact pairs");
  model->pairs = calloc((size_t)(n > 0 ? n : 1), sizeof(sk_contact_pair));
  model->n_pairs = n;
  for (int k = 0; k < n; ++k) {
    const sk_cfg *entry = sk_cfg_at(list, k);
    sk_contact_pair *pair = &model->pairs[k];
    const char *plugin_name, *name, *slave_name, *master_name;
    char default_name[32];
    snprintf(default_name, sizeof default_name, "pair-%d", k);
    SK_TRY(sk_cfg_string(entry, "name", 0, default_name, &name));
    copy_name(pair->name, name);
    SK_TRY(sk_cfg_string(entry, "plugin", 1, NULL, &plugin_name));
    if (plugin_override) plugin_name = plugin_override;
    sk_status status = sk_plugin_load(plugin_name, &pair->plugin);
    if (status != SK_OK)
      return sk_error_prefix(status, "%s: contact pair '%s': ", sk_cfg_where(sk_cfg_get(entry, "plugin")), name);
    SK_TRY(sk_cfg_string(entry, "slave", 1, NULL, &slave_name));
    SK_TRY(build_surface(model, sk_cfg_get(entry, "slave"), slave_name, &pair->slave));
    SK_TRY(sk_cfg_string(entry, "master", 0, NULL, &master_name));
    const sk_cfg *obstacle = sk_cfg_get(entry, "obstacle");
    if (!!master_name == !!obstacle)
      return sk_error_set(SK_ERR_INPUT, "%s: contact pair '%s' needs exactly one of `master` or `obstacle`",
                          sk_cfg_where(entry), name);
    if (master_name) {
      SK_TRY(build_surface(model, sk_cfg_get(entry, "master"), master_name, &pair->master));
      if (strcmp(master_name, slave_name) == 0)
        return sk_error_set(SK_ERR_INPUT, "%s: contact pair '%s': self contact (slave == master) is not supported yet",
                            sk_cfg_where(entry), name);
    } else {
      SK_TRY(read_obstacle(obstacle, model->dim, &pair->obstacle));
      pair->has_obstacle = 1;
    }
    const sk_cfg *params = sk_cfg_get(entry, "parameters");
    pair->params = (void *)params;
    const char *strategy;
    SK_TRY(sk_cfg_string(entry, "strategy", 0, pair->plugin->strategies[0], &strategy));
    pair->strategy = -1;
    for (int s = 0; pair->plugin->strategies[s]; ++s)
      if (strcmp(pair->plugin->strategies[s], strategy) == 0) pair->strategy = s;
    if (pair->strategy < 0) {
      char allowed[256] = "";
      for (int s = 0; pair->plugin->strategies[s]; ++s)
        snprintf(allowed + strlen(allowed), sizeof allowed - strlen(allowed), "%s%s", s ? ", " : "",
                 pair->plugin->strategies[s]);
      return sk_error_set(SK_ERR_INPUT, "%s: plugin '%s' has no strategy '%s' (it offers: %s)",
                          sk_cfg_where(sk_cfg_get(entry, "strategy")), pair->plugin->name, strategy, allowed);
    }
    /* Capabilities the scene needs: friction when a positive `mu` is among the parameters. */
    double mu = 0;
    const sk_cfg *mu_node = params ? sk_cfg_get(params, "mu") : NULL;
    if (mu_node) SK_TRY(sk_cfg_as_double(mu_node, &mu));
    uint64_t need = capabilities_needed(model, pair, mu);
    uint64_t missing = need & ~pair->plugin->caps;
    if (missing) {
      char text[256];
      sk_capabilities_string(missing, text, sizeof text);
      return sk_error_set(SK_ERR_PLUGIN, "%s: contact pair '%s': plugin '%s' lacks what this scene needs: %s",
                          sk_cfg_where(entry), name, pair->plugin->name, text);
    }
    if (model->time.scheme == SK_SCHEME_MIDPOINT && !(pair->plugin->caps & SK_CAP_ENERGY_MOMENTUM) &&
        model->rank == 0)
      fprintf(stderr,
              "warning: contact pair '%s': plugin '%s' is not energy-consistent with the midpoint scheme: momenta are "
              "kept, energy is not conserved through contact\n",
              name, pair->plugin->name);
    pair->pair.name = pair->name;
    pair->pair.slave = &pair->slave;
    pair->pair.master = pair->has_obstacle ? NULL : &pair->master;
    pair->pair.obstacle = pair->has_obstacle ? &pair->obstacle : NULL;
    pair->pair.params = (const sk_params *)params;
    pair->pair.strategy = pair->strategy;
  }
  return SK_OK;
}

/* ---- time, solver, output --------------------------------------------------------------------------------------- */

static const char *const scheme_names[] = {"quasi-static", "backward-euler", "midpoint", NULL};

static sk_status read_time(const sk_cfg *root, sk_time_options *time) {
  const sk_cfg *node = sk_cfg_get(root, "time");
  if (!node) return sk_error_set(SK_ERR_INPUT, "%s: missing key 'time'", sk_cfg_where(root));
  int scheme;
  SK_TRY(sk_cfg_choice(node, "scheme", 1, scheme_names, 0, &scheme));
  time->scheme = (sk_scheme)scheme;
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
  time->dt_min = time->dt / pow(2.0, time->max_cuts);
  return SK_OK;
}

/* in sk_linear_solver_kind order */
static const char *const linear_names[] = {"direct", "gmres-muelu", "gmres-ilu", "auto", "mumps", "klu2", "klu", NULL};
static const char *const line_search_names[] = {"full-step", "backtrack", "polynomial", NULL};

static sk_status read_solver(const sk_cfg *root, sk_solver_settings *solver) {
  const sk_cfg *node = sk_cfg_get(root, "solver");
  if (node && sk_cfg_kind_of(node) != SK_CFG_MAP)
    return fail_at(node, "%s", "expects a map with `newton` and/or `linear`");
  sk_newton_options_default(&solver->newton);
  sk_linear_options_default(&solver->linear);
  const sk_cfg *newton = sk_cfg_get(node, "newton");
  const sk_cfg *linear = sk_cfg_get(node, "linear");
  int line_search = (int)solver->newton.line_search, kind = (int)solver->linear.kind;
  SK_TRY(sk_cfg_double(newton, "tolerance", 0, solver->newton.relative_tolerance, &solver->newton.relative_tolerance));
  SK_TRY(sk_cfg_double(newton, "absolute_tolerance", 0, solver->newton.residual_tolerance,
                       &solver->newton.residual_tolerance));
  SK_TRY(sk_cfg_double(newton, "update_tolerance", 0, solver->newton.update_tolerance,
                       &solver->newton.update_tolerance));
  SK_TRY(sk_cfg_int(newton, "max_iterations", 0, solver->newton.max_iterations, &solver->newton.max_iterations));
  SK_TRY(sk_cfg_choice(newton, "line_search", 0, line_search_names, line_search, &line_search));
  SK_TRY(sk_cfg_bool(newton, "verbose", 0, solver->newton.verbose, &solver->newton.verbose));
  solver->newton.line_search = (sk_line_search)line_search;
  SK_TRY(sk_cfg_choice(linear, "solver", 0, linear_names, kind, &kind));
  solver->linear.kind = (sk_linear_solver_kind)kind;
  SK_TRY(sk_cfg_double(linear, "tolerance", 0, solver->linear.tolerance, &solver->linear.tolerance));
  SK_TRY(sk_cfg_int(linear, "max_iterations", 0, solver->linear.max_iterations, &solver->linear.max_iterations));
  if (!(solver->newton.relative_tolerance > 0) || !(solver->newton.residual_tolerance > 0))
    return fail_at(newton, "%s", "tolerances must be positive");
  if (solver->newton.max_iterations < 1) return fail_at(newton, "%s", "max_iterations must be at least 1");
  return SK_OK;
}

static sk_status read_output(const sk_cfg *root, sk_output_settings *output) {
  const sk_cfg *node = sk_cfg_get(root, "output");
  SK_TRY(sk_cfg_int(node, "vtu_every", 0, 10, &output->vtu_every));
  SK_TRY(sk_cfg_bool(node, "vtu", 0, 1, &output->write_vtu));
  SK_TRY(sk_cfg_bool(node, "contact_csv", 0, 1, &output->write_contact_csv));
  if (output->vtu_every < 0) return fail_at(sk_cfg_get(node, "vtu_every"), "%s", "must be >= 0");
  return SK_OK;
}

/* ---- mass ------------------------------------------------------------------------------------------------------- */

static int compare_ints(const void *a, const void *b) {
  int x = *(const int *)a, y = *(const int *)b;
  return (x > y) - (x < y);
}

/* Consistent nodal mass matrix (scalar, n_nodes x n_nodes CSR) and its row sums. */
static sk_status build_mass(sk_model *model) {
  int n = model->n_nodes;
  int *count = calloc((size_t)n + 1, sizeof(int));
  for (int b = 0; b < model->n_bodies; ++b) {
    const sk_group *g = model->bodies[b].group;
    for (int e = 0; e < g->n_elems; ++e)
      for (int a = 0; a < g->nen; ++a) count[g->conn[e * g->nen + a]] += g->nen;
  }
  int64_t *start = malloc(sizeof(int64_t) * ((size_t)n + 1));
  start[0] = 0;
  for (int i = 0; i < n; ++i) start[i + 1] = start[i] + count[i];
  int *cols = malloc(sizeof(int) * (size_t)(start[n] > 0 ? start[n] : 1));
  memset(count, 0, sizeof(int) * (size_t)n);
  for (int b = 0; b < model->n_bodies; ++b) {
    const sk_group *g = model->bodies[b].group;
    for (int e = 0; e < g->n_elems; ++e)
      for (int a = 0; a < g->nen; ++a) {
        int row = g->conn[e * g->nen + a];
        for (int c = 0; c < g->nen; ++c) cols[start[row] + count[row]++] = g->conn[e * g->nen + c];
      }
  }
  /* sort and deduplicate each row */
  model->mass_row_ptr = malloc(sizeof(int64_t) * ((size_t)n + 1));
  model->mass_row_ptr[0] = 0;
  int64_t used = 0;
  for (int i = 0; i < n; ++i) {
    int *row = cols + start[i];
    qsort(row, (size_t)count[i], sizeof(int), compare_ints);
    for (int k = 0; k < count[i]; ++k)
      if (k == 0 || row[k] != row[k - 1]) cols[used++] = row[k];
    model->mass_row_ptr[i + 1] = used;
  }
  model->mass_cols = realloc(cols, sizeof(int) * (size_t)(used > 0 ? used : 1));
  model->mass_values = calloc((size_t)(used > 0 ? used : 1), sizeof(double));
  model->lumped_mass = calloc((size_t)n, sizeof(double));
  free(count);
  free(start);

  double X[SK_MAX_NEN * 3];
  int dim = model->dim;
  model->total_mass = 0;
  /* element mass matrices are kept: the inertia terms of every Newton iteration reuse them */
  model->element_mass_offset = malloc(sizeof(int64_t) * ((size_t)model->n_elements + 1));
  model->element_mass_offset[0] = 0;
  for (int b = 0, e_global = 0; b < model->n_bodies; ++b)
    for (int e = 0; e < model->bodies[b].group->n_elems; ++e, ++e_global)
      model->element_mass_offset[e_global + 1] =
          model->element_mass_offset[e_global] + model->bodies[b].group->nen * model->bodies[b].group->nen;
  model->element_mass = malloc(sizeof(double) * (size_t)(model->element_mass_offset[model->n_elements] + 1));
  for (int b = 0; b < model->n_bodies; ++b) {
    const sk_body *body = &model->bodies[b];
    const sk_group *g = body->group;
    for (int e = 0; e < g->n_elems; ++e) {
      const int *conn = g->conn + e * g->nen;
      for (int a = 0; a < g->nen; ++a)
        for (int i = 0; i < dim; ++i) X[a * dim + i] = model->mesh.x[3 * conn[a] + i];
      double *M = model->element_mass + model->element_mass_offset[body->first_element + e];
      sk_status status = sk_solid_mass(&body->solid, X, M);
      if (status != SK_OK)
        return sk_error_prefix(status, "mesh %s: body '%s', element %d: ", model->mesh.source, body->name, e);
      for (int a = 0; a < g->nen; ++a) {
        int row = conn[a];
        const int *rc = model->mass_cols + model->mass_row_ptr[row];
        int len = (int)(model->mass_row_ptr[row + 1] - model->mass_row_ptr[row]);
        for (int c = 0; c < g->nen; ++c) {
          const int *hit = bsearch(&conn[c], rc, (size_t)len, sizeof(int), compare_ints);
          model->mass_values[model->mass_row_ptr[row] + (hit - rc)] += M[a * g->nen + c];
          model->lumped_mass[row] += M[a * g->nen + c];
          model->total_mass += M[a * g->nen + c];
        }
      }
    }
  }
  return SK_OK;
}

/* ---- the whole scene -------------------------------------------------------------------------------------------- */

static sk_status build(const char *plugin_override, sk_scene *scene) {
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
  model->n_nodes = model->mesh.n_nodes;
  model->n_dofs = model->n_nodes * model->dim;
  model->X = malloc(sizeof(double) * (size_t)(model->n_dofs > 0 ? model->n_dofs : 1));
  for (int a = 0; a < model->n_nodes; ++a)
    for (int i = 0; i < model->dim; ++i) model->X[a * model->dim + i] = model->mesh.x[3 * a + i];
  SK_TRY(read_bodies(root, model));
  SK_TRY(read_boundary(root, model));
  SK_TRY(build_mass(model));
  sk_host_init(&scene->host, model);
  SK_TRY(read_contact(root, plugin_override, scene));

  /* METIS partition of all body elements */
  model->element_part = calloc((size_t)(model->n_elements > 0 ? model->n_elements : 1), sizeof(int));
  const sk_group *bodies[64];
  if (model->n_bodies > 64) return sk_error_set(SK_ERR_INPUT, "%s: more than 64 bodies", scene->path);
  for (int b = 0; b < model->n_bodies; ++b) bodies[b] = model->bodies[b].group;
  SK_TRY(sk_mesh_partition(&model->mesh, bodies, model->n_bodies, model->n_ranks, model->element_part));
  model->node_owner = malloc(sizeof(int) * (size_t)(model->n_nodes > 0 ? model->n_nodes : 1));
  for (int a = 0; a < model->n_nodes; ++a) model->node_owner[a] = model->n_ranks; /* nodes of no body: see below */
  for (int b = 0; b < model->n_bodies; ++b) {
    const sk_group *g = model->bodies[b].group;
    for (int e = 0; e < g->n_elems; ++e)
      for (int a = 0; a < g->nen; ++a) {
        int node = g->conn[e * g->nen + a], part = model->element_part[model->bodies[b].first_element + e];
        if (part < model->node_owner[node]) model->node_owner[node] = part;
      }
  }
  for (int a = 0; a < model->n_nodes; ++a)
    if (model->node_owner[a] == model->n_ranks) model->node_owner[a] = 0;

  /* Plugin instances: created now so that their parameters are validated (and read) before the unknown-key check. */
  for (int k = 0; k < model->n_pairs; ++k) {
    sk_contact_pair *pair = &model->pairs[k];
    sk_status status = pair->plugin->create(&scene->host, &pair->pair, &pair->instance);
    if (status != SK_OK)
      return sk_error_prefix(status, "%s: contact pair '%s' (plugin %s): ", scene->path, pair->name,
                             pair->plugin->name);
  }
  return sk_cfg_check_unused(root);
}

sk_status sk_scene_load(const char *path, int n_sets, const char *const *sets, const char *plugin_override,
                        MPI_Comm comm, sk_scene *scene) {
  memset(scene, 0, sizeof *scene);
  snprintf(scene->path, sizeof scene->path, "%s", path);
  scene->model.comm = comm;
  MPI_Comm_rank(comm, &scene->model.rank);
  MPI_Comm_size(comm, &scene->model.n_ranks);
  SK_TRY(sk_cfg_load(path, &scene->cfg));
  for (int k = 0; k < n_sets; ++k) {
    sk_status status = sk_cfg_set(scene->cfg, sets[k]);
    if (status != SK_OK) return sk_error_prefix(status, "--set %s: ", sets[k]);
  }
  return build(plugin_override, scene);
}

void sk_model_free(sk_model *model) {
  for (int k = 0; k < model->n_pairs; ++k) {
    sk_contact_pair *pair = &model->pairs[k];
    if (pair->instance) pair->plugin->destroy(pair->instance);
    sk_surface_free(&pair->slave);
    if (!pair->has_obstacle) sk_surface_free(&pair->master);
  }
  free(model->pairs);
  for (int k = 0; k < model->n_dirichlet; ++k) free(model->dirichlet[k].nodes);
  free(model->dirichlet);
  free(model->tractions);
  free(model->bodies);
  free(model->element_part);
  free(model->node_owner);
  free(model->X);
  free(model->mass_row_ptr);
  free(model->mass_cols);
  free(model->mass_values);
  free(model->lumped_mass);
  free(model->element_mass_offset);
  free(model->element_mass);
  sk_mesh_free(&model->mesh);
  memset(model, 0, sizeof *model);
}

void sk_scene_free(sk_scene *scene) {
  sk_model_free(&scene->model);
  sk_cfg_free(scene->cfg);
  scene->cfg = NULL;
}
