/* Scene → model, the `contact:` list (docs/scene-reference.md, contact): explicit pairs (a slave surface against a
 * master surface, an obstacle or itself) and `bodies:` entries that create the pairs among many bodies; each pair's
 * plugin, strategy and the capabilities the scene needs of it. The rest of the scene: scene.c. */
#define _GNU_SOURCE
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene_info.h"
#include "scene_internal.h"
#include "stickslip/plugins.h"
#include "system.h"

static int straight_faces(const sk_surface *surface) {
  return surface->face_type == SK_LINE2 || surface->face_type == SK_TRI3;
}

/* ---- contact ---------------------------------------------------------------------------------------------------- */

static sk_status build_surface(const sk_model *model, const sk_cfg *at, const char *name, sk_surface *surface) {
  const sk_group *faces;
  SK_TRY(sk_scene_require_group(model, at, name, model->dim - 1, &faces));
  int body = faces->n_elems > 0 ? sk_model_body_of_node(model, faces->conn[0]) : -1;
  if (body < 0) return sk_scene_fail_at(at, "surface '%s' does not lie on any body listed under `bodies`", name);
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
  sk_scene_copy_name(obstacle->name, name);
  SK_TRY(sk_cfg_vector(node, "point", 0, 3, (double[3]){0, 0, 0}, obstacle->point));
  double up[3] = {0, dim == 2 ? 1 : 0, dim == 2 ? 0 : 1};
  SK_TRY(sk_cfg_vector(node, "normal", 0, 3, up, obstacle->normal));
  SK_TRY(sk_cfg_vector(node, "axis", 0, 3, (double[3]){0, dim == 2 ? 0 : 1, dim == 2 ? 1 : 0}, obstacle->axis));
  SK_TRY(sk_cfg_double(node, "radius", kind == SK_OBSTACLE_SPHERE || kind == SK_OBSTACLE_CYLINDER, 0,
                       &obstacle->radius));
  SK_TRY(sk_cfg_double(node, "c", kind == SK_OBSTACLE_PARABOLIC_CYLINDER, 0, &obstacle->c));
  if ((kind == SK_OBSTACLE_SPHERE || kind == SK_OBSTACLE_CYLINDER) && !(obstacle->radius > 0))
    return sk_scene_fail_at(sk_cfg_get(node, "radius"), "%s", "must be positive");
  double normal_length = sqrt(obstacle->normal[0] * obstacle->normal[0] + obstacle->normal[1] * obstacle->normal[1] +
                              obstacle->normal[2] * obstacle->normal[2]);
  if (!(normal_length > 0)) return sk_scene_fail_at(node, "%s", "obstacle normal is zero");
  for (int i = 0; i < 3; ++i) obstacle->normal[i] /= normal_length;
  const sk_cfg *motion = sk_cfg_get(node, "motion");
  sk_cfg_note_default(node, "motion", "at rest", 0, NULL);
  int n = sk_cfg_size(motion);
  if (n > SK_OBSTACLE_MOTION_MAX) return sk_scene_fail_at(motion, "%s", "has more than 64 points");
  for (int k = 0; k < n; ++k) {
    const sk_cfg *row = sk_cfg_at(motion, k);
    if (sk_cfg_kind_of(row) != SK_CFG_SEQ || sk_cfg_size(row) != 4)
      return sk_scene_fail_at(row, "%s", "expects [time, dx, dy, dz]");
    SK_TRY(sk_cfg_as_double(sk_cfg_at(row, 0), &obstacle->motion_t[k]));
    for (int i = 0; i < 3; ++i) SK_TRY(sk_cfg_as_double(sk_cfg_at(row, i + 1), &obstacle->motion_d[k][i]));
    if (k > 0 && !(obstacle->motion_t[k] > obstacle->motion_t[k - 1]))
      return sk_scene_fail_at(row, "%s", "times must increase strictly");
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

sk_status sk_scene_check_kind(const sk_cfg *at, const sk_plugin *plugin, sk_kind kind, const char *what,
                            const char *name) {
  if (plugin->kinds & kind) return SK_OK;
  return sk_error_set(SK_ERR_PLUGIN, "%s: %s '%s': plugin '%s' does not attach to a %s (it is a %s plugin)",
                      sk_cfg_where(at), what, name, plugin->name, what, kind == SK_KIND_BODY ? "contact-pair" : "body");
}

/* `strategy:` of a pair or body: one of the plugin's strategies (the first by default). */
sk_status sk_scene_choose_strategy(const sk_cfg *entry, const sk_plugin *plugin, int *strategy) {
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
  SK_TRY(sk_scene_check_kind(sk_cfg_get(entry, "plugin"), pair->plugin, SK_KIND_PAIR, "contact pair", name));
  pair->params = sk_cfg_get(entry, "parameters");
  pair->plugin_node = sk_cfg_get(entry, "plugin");
  return sk_scene_choose_strategy(entry, pair->plugin, &pair->strategy);
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
  sk_scene_copy_name(pair->name, name);
  SK_TRY(read_pair_plugin(entry, name, pair));
  if (sk_cfg_get(entry, "obstacles"))
    return sk_scene_fail_at(sk_cfg_get(entry, "obstacles"), "%s",
                   "goes with `bodies` (every listed body against each obstacle); a pair with one obstacle gives it "
                   "as `obstacle`");
  if (sk_cfg_peek(entry, "self"))
    return sk_scene_fail_at(sk_cfg_peek(entry, "self"), "%s",
                   "goes with `bodies` (each listed body's whole boundary against itself); a single self pair gives "
                   "`master` equal to `slave`");
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
  int self;        /* `self: true`: each listed body's boundary also meets itself (a self pair per body) */
} body_set;

static int body_index_of(const sk_model *model, const char *name) {
  for (int b = 0; b < model->n_bodies; ++b)
    if (strcmp(model->bodies[b].name, name) == 0) return b;
  return -1;
}

/* The bodies of an entry with `bodies:`: `all`, or a list of body names (each known, none twice), at least two of
 * them unless obstacles are listed too or `self: true` asks for each body's self pair. */
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
    return sk_scene_fail_at(obstacles, "%s", "expects a list of obstacles (each as a pair's `obstacle`)");
  set->n_obstacles = sk_cfg_size(obstacles);
  SK_TRY(sk_cfg_bool(entry, "self", 0, 0, &set->self));
  set->bodies = malloc(sizeof(int) * (size_t)(model->n_bodies > 0 ? model->n_bodies : 1));
  if (!set->bodies) return sk_error_set(SK_ERR_NOMEM, "%s: out of memory", sk_cfg_where(node));
  set->n_bodies = 0;
  const char *word = sk_cfg_scalar(node);
  if (word) {
    if (strcmp(word, "all") != 0)
      return sk_scene_fail_at(node, "%s", "expects `all` or a list of body names, e.g. [disk-1, disk-2]");
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
        if (set->bodies[j] == b) return sk_scene_fail_at(item, "body '%s' is listed twice", name);
      set->bodies[set->n_bodies++] = b;
    }
  } else {
    return sk_scene_fail_at(node, "%s", "expects `all` or a list of body names, e.g. [disk-1, disk-2]");
  }
  if (set->n_bodies < 2 && set->n_obstacles == 0 && !set->self)
    return sk_error_set(SK_ERR_INPUT, "%s: `bodies` gives %d body, no `obstacles` and no `self: true`: no pair to "
                        "create (contact among bodies needs two of them; a body against a rigid obstacle is a pair "
                        "with `obstacle`; a body against itself needs `self: true`)",
                        sk_cfg_where(node), set->n_bodies);
  return SK_OK;
}

static int pairs_of_set(const body_set *set) {
  return set->n_bodies * (set->n_bodies - 1) / 2 + set->n_bodies * set->n_obstacles + (set->self ? set->n_bodies : 0);
}

/* Reference sizes of a body's boundary: the mean corner-to-corner edge length decides which side is slave. */
static double mean_face_size(const sk_model *model, const sk_surface *surface) {
  double h_min, h_mean, h_max, measure;
  sk_surface_sizes(surface, model->mesh.x, 3, &h_min, &h_mean, &h_max, &measure);
  return h_mean;
}

/* A created pair's shared part: its entry, the entry's plugin, strategy and parameters. */
static sk_status start_created_pair(const sk_cfg *entry, int entry_index, const char *name, sk_contact_pair *pair) {
  pair->entry = entry_index;
  pair->generated = 1;
  return read_pair_plugin(entry, name, pair);
}

/* The whole boundary of body b as a surface named <body>-boundary. */
static sk_status body_boundary(const sk_model *model, int b, sk_surface *surface) {
  char boundary_name[SK_NAME_MAX + 16];
  snprintf(boundary_name, sizeof boundary_name, "%s-boundary", model->bodies[b].name);
  return sk_surface_build_boundary(&model->mesh, model->bodies[b].group, b, boundary_name, surface);
}

/* The pairs of one `bodies:` entry, from pairs[*k] on. Between two bodies the slave is the one whose boundary has the
 * smaller mean face size (the finer mesh: its nodes do not fall between the master's); within 1e-9 relative the
 * one listed first (deterministic). With `self: true` each body's self pair follows, in the order listed. */
static sk_status create_body_pairs(const sk_cfg *entry, int entry_index, sk_model *model, const body_set *set,
                                   int *k) {
  const char *name;
  SK_TRY(sk_cfg_string(entry, "name", 0, "all", &name));
  for (int i = 0; i < set->n_bodies; ++i) {
    for (int j = i + 1; j < set->n_bodies + set->n_obstacles; ++j) {
      sk_contact_pair *pair = &model->pairs[*k];
      SK_TRY(start_created_pair(entry, entry_index, name, pair));
      const sk_body *a = &model->bodies[set->bodies[i]];
      sk_surface first;
      SK_TRY(body_boundary(model, set->bodies[i], &first));
      if (j >= set->n_bodies) {
        pair->slave = first;
        pair->has_obstacle = 1;
        model->n_pairs = *k + 1; /* sk_model_free frees its surface on an error */
        SK_TRY(read_obstacle(sk_cfg_at(sk_cfg_get(entry, "obstacles"), j - set->n_bodies), model->dim,
                             &pair->obstacle));
        snprintf(pair->name, sizeof pair->name, "%s:%s/%s", name, a->name, pair->obstacle.name);
      } else {
        const sk_body *b = &model->bodies[set->bodies[j]];
        sk_surface second;
        sk_status status = body_boundary(model, set->bodies[j], &second);
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
  for (int i = 0; set->self && i < set->n_bodies; ++i) {
    sk_contact_pair *pair = &model->pairs[*k];
    SK_TRY(start_created_pair(entry, entry_index, name, pair));
    SK_TRY(body_boundary(model, set->bodies[i], &pair->slave));
    pair->self_contact = 1;
    pair->master = pair->slave; /* shares the slave's arrays (freed once), as an explicit pair with master = slave */
    snprintf(pair->name, sizeof pair->name, "%s:%s/self", name, model->bodies[set->bodies[i]].name);
    model->n_pairs = ++*k;
    SK_TRY(check_pair(entry, model, *k - 1));
  }
  return SK_OK;
}

/* Two entries must not both create contact between the same two bodies (or a body and the same obstacle entry), nor
 * both a body's self contact: the forces would be added twice. Explicit pairs between two bodies count as that pair
 * of bodies, an explicit self pair on a body's surface as that body's self contact. */
static sk_status check_pairs_unique(const sk_cfg *list, const sk_model *model) {
  for (int k = 0; k < model->n_pairs; ++k) {
    const sk_contact_pair *p = &model->pairs[k];
    if (p->has_obstacle) continue;
    for (int l = k + 1; l < model->n_pairs; ++l) {
      const sk_contact_pair *q = &model->pairs[l];
      if (q->has_obstacle || q->self_contact != p->self_contact || (!p->generated && !q->generated)) continue;
      const int same = (p->slave.body == q->slave.body && p->master.body == q->master.body) ||
                       (p->slave.body == q->master.body && p->master.body == q->slave.body);
      if (!same) continue;
      const sk_cfg *at = sk_cfg_at(list, q->entry);
      if (p->self_contact)
        return sk_error_set(SK_ERR_INPUT,
                            "%s: contact pair '%s' puts body '%s' in contact with itself, and so does pair '%s' (%s): "
                            "a body's self contact is given once (drop `self: true` or the explicit self pair)",
                            sk_cfg_where(at), q->name, model->bodies[q->slave.body].name, p->name,
                            sk_cfg_where(sk_cfg_at(list, p->entry)));
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

sk_status sk_scene_read_contact(const sk_cfg *root, sk_scene *scene) {
  sk_model *model = &scene->model;
  const sk_cfg *list = sk_cfg_get(root, "contact");
  const int n_entries = sk_cfg_size(list);
  if (list && sk_cfg_kind_of(list) != SK_CFG_SEQ) return sk_scene_fail_at(list, "%s", "expects a list of contact pairs");
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
