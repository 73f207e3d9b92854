/* The scene around an attachment (scene_info.h): its description for sk_plugin.check and stickslip.scene.v1, the
 * refusals made at `check` time with the plugins that can, and glued contact surfaces. */
#include "scene_info.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "stickslip/config.h"
#include "stickslip/plugins.h"

/* ---- descriptions ----------------------------------------------------------------------------------------------- */

static void describe_body_material(const sk_model *model, int body, sk_scene_side *side) {
  const sk_body *b = &model->bodies[body];
  side->body = body;
  side->body_name = b->name;
  side->E = b->material.E;
  side->nu = b->material.nu;
  for (int i = 0; i < 3; ++i) {
    side->velocity[i] = b->velocity[i];
    side->angular_velocity[i] = b->angular_velocity[i];
    side->center[i] = b->center[i];
  }
}

static void describe_surface(const sk_model *model, const sk_surface *surface, sk_scene_side *side) {
  memset(side, 0, sizeof *side);
  side->struct_size = sizeof *side;
  side->name = surface->name;
  describe_body_material(model, surface->body, side);
  side->cell_type = surface->face_type;
  side->order = sk_elem_order(surface->face_type);
  /* the whole surface's, also once the mesh is distributed (each rank then holds part of it) */
  if (surface->whole_sizes) {
    side->h_min = surface->whole_h_min;
    side->h_mean = surface->whole_h_mean;
    side->h_max = surface->whole_h_max;
    side->measure = surface->whole_measure;
  } else {
    sk_surface_sizes(surface, model->mesh.x, 3, &side->h_min, &side->h_mean, &side->h_max, &side->measure);
  }
  side->n_cells = surface->face_index ? surface->n_faces_global : surface->n_faces;
  side->n_nodes = surface->node_index ? surface->n_nodes_global : surface->n_nodes;
}

_Static_assert(SK_SHAPE_PLANE + SK_OBSTACLE_PARABOLIC_CYLINDER == SK_SHAPE_PARABOLIC_CYLINDER,
               "sk_obstacle_shape lists the obstacle kinds in their order");

static void describe_obstacle(const sk_obstacle *obstacle, sk_scene_side *side) {
  memset(side, 0, sizeof *side);
  side->struct_size = sizeof *side;
  side->name = obstacle->name;
  side->body = -1;
  side->body_name = obstacle->name;
  side->rigid = 1;
  side->shape = (sk_obstacle_shape)(SK_SHAPE_PLANE + (int)obstacle->kind);
  for (int k = 0; k < obstacle->n_motion; ++k)
    for (int i = 0; i < 3; ++i) side->moving |= obstacle->motion_d[k][i] != 0.0;
  side->E = INFINITY;
  side->cell_type = SK_POINT1;
}

/* The integrator the body's terms see: a claiming body plugin's own, else the scene's. */
static void describe_scheme(const sk_model *model, int body, sk_scene_info *info) {
  const sk_body *b = &model->bodies[body];
  const sk_integrator *own = b->plugin && (b->plugin->caps & SK_CAP_OWNS_KINEMATICS) ? b->plugin->integrator : NULL;
  info->scheme = own ? own->name : b->integrator->name;
  info->alpha = own ? own->alpha : b->integrator->alpha;
  info->dynamic = own ? own->dynamic : b->integrator->dynamic;
}

/* mu > 0 in a pair's parameters (a value that is not a number counts as friction: the plugin will say what is
 * wrong with it). */
static int asks_friction(const void *params) {
  const sk_cfg *node = sk_cfg_get((const sk_cfg *)params, "mu");
  double mu = 0.0;
  if (!node) return 0;
  return sk_cfg_as_double(node, &mu) != SK_OK || mu != 0.0;
}

/* What pairs and bodies share: the kind, names, dimension, ranks, strategy and the scheme of `body`. */
static sk_scene_info *describe_attachment(const sk_model *model, sk_kind kind, const char *name, int strategy, int body,
                                          sk_scene_description *d) {
  memset(d, 0, sizeof *d);
  sk_scene_info *info = &d->info;
  info->struct_size = sizeof *info;
  info->kind = kind;
  info->name = name;
  info->dim = model->dim;
  info->n_ranks = model->n_ranks;
  info->strategy = strategy;
  describe_scheme(model, body, info);
  info->slave = &d->slave;
  return info;
}

void sk_describe_pair(const sk_model *model, int pair, sk_scene_description *d) {
  const sk_contact_pair *p = &model->pairs[pair];
  sk_scene_info *info = describe_attachment(model, SK_KIND_PAIR, p->name, p->strategy, p->slave.body, d);
  info->friction = asks_friction(p->params);
  info->self_contact = p->self_contact;
  describe_surface(model, &p->slave, &d->slave);
  if (p->has_obstacle) describe_obstacle(&p->obstacle, &d->master);
  else describe_surface(model, &p->master, &d->master);
  info->master = &d->master;
}

void sk_describe_body(const sk_model *model, int body, sk_scene_description *d) {
  const sk_body *b = &model->bodies[body];
  describe_attachment(model, SK_KIND_BODY, b->name, b->strategy, body, d);
  sk_scene_side *side = &d->slave;
  side->struct_size = sizeof *side;
  side->name = b->name;
  describe_body_material(model, body, side);
  side->cell_type = b->group->type;
  side->order = sk_elem_order(b->group->type);
  if (b->node_index) { /* distributed: the whole body's counts */
    side->n_cells = b->n_elems_global;
    side->n_nodes = b->n_nodes_global;
    return;
  }
  side->n_cells = b->group->n_elems;
  int *nodes = NULL, n_nodes = 0;
  if (sk_group_nodes(b->group, &nodes, &n_nodes) == SK_OK) side->n_nodes = n_nodes;
  free(nodes);
}

/* ---- refusals at check time ------------------------------------------------------------------------------------- */

/* Why `plugin` cannot run the attachment (capabilities first, then its check hook), or 0 when it can. */
static int cannot_run(const sk_plugin *plugin, const sk_scene_info *info, uint64_t needed, char *reason, int size) {
  reason[0] = '\0';
  if (!(plugin->kinds & info->kind)) {
    snprintf(reason, (size_t)size, "it does not attach to a %s", info->kind == SK_KIND_PAIR ? "contact pair" : "body");
    return 1;
  }
  const uint64_t missing = needed & ~plugin->caps;
  if (missing) {
    char text[256];
    sk_capabilities_string(missing, text, sizeof text);
    snprintf(reason, (size_t)size, "it lacks what this scene needs: %s", text);
    return 1;
  }
  if (plugin->check && plugin->check(info, reason, size) != SK_OK) {
    if (!reason[0]) snprintf(reason, (size_t)size, "its check refused the attachment without saying why");
    return 1;
  }
  return 0;
}

typedef struct {
  const sk_scene_info *info; /* the scene's; each probe changes its strategy */
  uint64_t needed;
  const sk_plugin *refused; /* the plugin the scene names, with its strategy info->strategy */
  char list[2048];
} alternatives;

/* 1 when `name` is the name of an entry of the ", "-separated `list` (an entry may go on " with strategy: ..."). */
static int listed(const char *list, const char *name) {
  const size_t n = strlen(name);
  for (const char *at = list; *at; at += strcspn(at, ",") + (at[strcspn(at, ",")] ? 2 : 0))
    if (strncmp(at, name, n) == 0 && (at[n] == ',' || at[n] == ' ' || at[n] == '\0')) return 1;
  return 0;
}

/* The first strategy of `plugin` that can run the attachment (the default first), or -1. The refused plugin is
 * tried with its other strategies only; a strategy past the first needs the condensation capability. */
static int strategy_that_can(const alternatives *a, const sk_plugin *plugin) {
  sk_scene_info probe = *a->info; /* the sides stay the scene's */
  probe.probe = 1;
  char reason[512];
  for (int s = 0; plugin->strategies && plugin->strategies[s]; ++s) {
    if (strcmp(plugin->name, a->refused->name) == 0 && s == a->info->strategy) continue;
    probe.strategy = s;
    if (!cannot_run(plugin, &probe, a->needed | (s > 0 ? SK_CAP_CONDENSATION : 0), reason, sizeof reason)) return s;
  }
  return -1;
}

static void consider(void *ctx, const sk_plugin *plugin, const char *path) {
  (void)path;
  alternatives *a = ctx;
  if (listed(a->list, plugin->name)) return; /* a shadowed library: once */
  const int s = strategy_that_can(a, plugin);
  if (s < 0) return;
  const size_t used = strlen(a->list);
  /* the setting it needs: a strategy other than its default, or any other than the one the scene names */
  if (s > 0 || strcmp(plugin->name, a->refused->name) == 0)
    snprintf(a->list + used, sizeof a->list - used, "%s%s with strategy: %s", used ? ", " : "", plugin->name,
             plugin->strategies[s]);
  else
    snprintf(a->list + used, sizeof a->list - used, "%s%s", used ? ", " : "", plugin->name);
}

sk_status sk_check_attachment(const sk_plugin *plugin, const sk_scene_description *d, uint64_t needed,
                              const char *where) {
  char reason[512];
  if (!cannot_run(plugin, &d->info, needed, reason, sizeof reason)) return SK_OK;
  alternatives a = {.info = &d->info, .needed = needed, .refused = plugin, .list = ""};
  sk_plugin_each(consider, NULL, &a);
  return sk_error_set(SK_ERR_PLUGIN, "%s: plugin '%s' cannot run it: %s. %s%s%s", where, plugin->name, reason,
                      a.list[0] ? "Plugins that can: " : "No plugin on the search path can run it",
                      a.list, a.list[0] ? " (`stickslip plugins` describes them)" : "");
}

/* ---- glued surfaces --------------------------------------------------------------------------------------------- */

sk_status sk_check_glued(const sk_model *model, int pair, const char *where) {
  const sk_contact_pair *p = &model->pairs[pair];
  if (p->has_obstacle || p->self_contact) return SK_OK;
  /* both node lists are sorted */
  int shared = 0, first = -1;
  for (int i = 0, j = 0; i < p->slave.n_nodes && j < p->master.n_nodes;) {
    if (p->slave.nodes[i] < p->master.nodes[j]) {
      ++i;
    } else if (p->slave.nodes[i] > p->master.nodes[j]) {
      ++j;
    } else {
      if (first < 0) first = p->slave.nodes[i];
      ++shared;
      ++i;
      ++j;
    }
  }
  if (!shared) return SK_OK;
  const double *x = model->mesh.x + 3 * (size_t)first;
  return sk_error_set(SK_ERR_INPUT,
                      "%s: the slave surface '%s' and the master surface '%s' share %d of their %d and %d mesh nodes "
                      "(e.g. node %d at (%g, %g, %g)): the bodies are meshed as one, glued at the interface, so "
                      "contact cannot act there. Mesh the bodies separately: give each body its own entry in the "
                      "scene's `mesh` list (with a `name`), or in gmsh keep their geometries apart (no BooleanFragments "
                      "or Coherence across the interface, Geometry.AutoCoherence = 0 where their points touch)",
                      where, p->slave.name, p->master.name, shared, p->slave.n_nodes, p->master.n_nodes, first, x[0],
                      x[1], x[2]);
}
