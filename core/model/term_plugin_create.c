/* A plugin instance as a term (term_plugin.h), its creation: the views over its surfaces or body, the instance, the
 * declarations of what it needs from the host, the error of a failed create; and a master surface's view renewed
 * when its faces are ghosted again (master_ghosts.h). term_plugin.c runs the ABI calls at the system's stages. */
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "term_plugin.h"
#include "broad_phase.h"
#include "contact_partition.h"
#include "stickslip/fe.h"

static sk_status add_view(plugin_term *term, sk_system *sys, const sk_surface *surface, const char *name, int whole,
                          int body) {
  const sk_model *m = sys->model;
  const int v = term->n_views;
  sk_view_data *data = &term->views[v];
  const unsigned char *held = term->pair >= 0 && surface == &m->pairs[term->pair].master ? m->pairs[term->pair].master_held
                                                                                        : NULL;
  const sk_contact_pair *pair = term->pair >= 0 ? &m->pairs[term->pair] : NULL;
  SK_TRY(surface ? sk_view_surface(m, surface, name, whole, held, pair, data) : sk_view_body(m, body, data));
  term->view_list[v] = &data->view;
  SK_TRY(sk_view_localize(data, sys));
  if (!term->in_view) term->in_view = calloc((size_t)(m->n_nodes > 0 ? m->n_nodes : 1), 1);
  if (!term->in_view) return sk_error_set(SK_ERR_NOMEM, "out of memory for the view of '%s'", name);
  for (int k = 0; k < data->view.n_nodes; ++k) term->in_view[data->local_dofs[(int64_t)k * m->dim] / m->dim] = 1;
  const int n = sk_view_dof_count(&data->view);
  term->x[v] = sk_plugin_zeros(n);
  term->x_n[v] = sk_plugin_zeros(n);
  term->v_n[v] = sk_plugin_zeros(n);
  term->F_view[v] = sk_plugin_zeros(n);
  term->dx_view[v] = sk_plugin_zeros(n);
  term->Jdx_view[v] = sk_plugin_zeros(n);
  if (!term->x[v] || !term->x_n[v] || !term->v_n[v] || !term->F_view[v] || !term->dx_view[v] || !term->Jdx_view[v])
    return sk_error_set(SK_ERR_NOMEM, "out of memory for the state of view '%s'", name);
  term->x_list[v] = term->x[v];
  term->x_n_list[v] = term->x_n[v];
  term->v_n_list[v] = term->v_n[v];
  term->F_list[v] = term->F_view[v];
  term->dx_list[v] = term->dx_view[v];
  term->Jdx_list[v] = term->Jdx_view[v];
  term->n_views++;
  return SK_OK;
}

/* The plugin's table as this host reads it: members beyond its struct_size are NULL. */
static void copy_table(plugin_term *term, const sk_plugin *plugin) {
  memset(&term->table, 0, sizeof term->table);
  size_t size = plugin->struct_size < sizeof term->table ? plugin->struct_size : sizeof term->table;
  memcpy(&term->table, plugin, size);
}

static sk_status setup(plugin_term *term, sk_system *sys, int body, int pair_index) {
  const sk_model *m = sys->model;
  const int dynamic = sys->integrator->dynamic;
  sk_attach *attach = &term->attach;
  attach->struct_size = sizeof *attach;
  if (pair_index >= 0) {
    const sk_contact_pair *pair = &m->pairs[pair_index];
    term->plugin = pair->plugin;
    term->host.params = pair->params;
    snprintf(term->base.name, sizeof term->base.name, "contact pair '%s'", pair->name);
    attach->kind = SK_KIND_PAIR;
    attach->name = pair->name;
    attach->strategy = pair->strategy;
    /* the slave as this rank sees it; the master whole (every face a slave point could reach) */
    SK_TRY(add_view(term, sys, &pair->slave, pair->slave.name, 0, -1));
    attach->slave = term->view_list[0];
    if (!pair->has_obstacle) {
      SK_TRY(add_view(term, sys, &pair->master, pair->master.name, 1, -1));
      attach->master = term->view_list[1];
    } else {
      attach->obstacle = &pair->obstacle;
    }
    attach->self_contact = pair->self_contact;
    sk_describe_pair(m, pair_index, &term->scene);
    /* The broad phase keeps pairs created by `bodies:` from calling their plugin while their surfaces are apart
     * (docs/contact-services.md); not for plugins with extra unknowns, whose layout must stay the plugin's. The
     * margin, the larger face size of the two surfaces, lets a pair wake a step before its surfaces meet. */
    term->broad_phase = pair->generated && !pair->has_obstacle && !pair->self_contact &&
                        !(pair->plugin->caps & SK_CAP_MULTIPLIERS) && !sk_need_forced(SK_NEED_IDLE_CALLS);
    for (int s = 0; s < 2 && term->broad_phase; ++s) {
      const sk_surface *side = s ? &pair->master : &pair->slave;
      double h_min, h_mean, h_max, measure;
      if (side->whole_sizes) h_max = side->whole_h_max;
      else sk_surface_sizes(side, m->X, m->dim, &h_min, &h_mean, &h_max, &measure);
      term->broad_margin = fmax(term->broad_margin, h_max);
    }
    if (term->broad_phase) {
      SK_TRY(sk_broad_phase_add(sys, pair, term->broad_margin, &term->broad_id));
      term->apart_at_start = sk_broad_phase_apart_at_start(sys, pair, term->broad_margin);
    }
  } else {
    const sk_body *b = &m->bodies[body];
    term->plugin = b->plugin;
    term->host.params = b->params;
    snprintf(term->base.name, sizeof term->base.name, "body '%s'", b->name);
    attach->kind = SK_KIND_BODY;
    attach->name = b->name;
    attach->strategy = b->strategy;
    SK_TRY(add_view(term, sys, NULL, b->name, 0, body));
    attach->body = term->view_list[0];
    sk_describe_body(m, body, &term->scene);
    term->pending_u = sk_plugin_zeros(sk_view_dof_count(attach->body));
    term->pending_v = sk_plugin_zeros(sk_view_dof_count(attach->body));
    term->scratch_K = sk_plugin_zeros((int64_t)(SK_MAX_NEN * 3) * (SK_MAX_NEN * 3));
    if (!term->pending_u || !term->pending_v || !term->scratch_K)
      return sk_error_set(SK_ERR_NOMEM, "body '%s': out of memory", b->name);
  }
  attach->n_views = term->n_views;
  attach->views = term->view_list;
  copy_table(term, term->plugin);
  sk_state *st = &term->state;
  st->struct_size = sizeof *st;
  st->scheme = sys->integrator->name;
  st->alpha = sys->integrator->alpha;
  st->dynamic = dynamic;
  st->n_views = term->n_views;
  st->x = term->x_list;
  st->x_n = term->x_n_list;
  st->v_n = dynamic ? term->v_n_list : NULL;
  term->host.sys = sys;
  term->host.term = term;
  term->host.name = term->base.name;
  return SK_OK;
}

/* The needs the host can tell from the attachment and the capabilities (term.h: sk_need). */
static void declare_needs(plugin_term *term, const sk_system *sys) {
  sk_needs *needs = &term->base.needs;
  const uint64_t caps = term->plugin->caps;
  if (term->body >= 0)
    sk_needs_declare(needs, SK_NEED_MASS, 1, "body plugin %s: its body's mass properties and body force",
                     term->plugin->name);
  else
    sk_needs_declare(needs, SK_NEED_MASS, (caps & SK_CAP_NEEDS_MASS) != 0, "plugin %s %s the needs-mass capability",
                     term->plugin->name, caps & SK_CAP_NEEDS_MASS ? "declares" : "does not declare");
  if (term->pair < 0) return;
  sk_needs_declare(needs, SK_NEED_IDLE_CALLS, !(caps & SK_CAP_SAYS_IDLE),
                   caps & SK_CAP_SAYS_IDLE ? "plugin %s says when it has no candidate (sk_layout.idle)"
                                           : "plugin %s cannot say when it has no candidate: always called",
                   term->plugin->name);
  const sk_contact_pair *pair = &sys->model->pairs[term->pair];
  if (pair->has_obstacle)
    sk_needs_declare(needs, SK_NEED_MASTER_UNKNOWNS, 0, "rigid obstacle '%s': prescribed motion, no unknowns",
                     pair->obstacle.name);
  else
    sk_needs_declare(needs, SK_NEED_MASTER_UNKNOWNS, 1, "%s '%s' (%d nodes)",
                     pair->self_contact ? "self contact on" : "deformable master", pair->master.name,
                     pair->master.n_nodes);
}

/* Friction: a plugin with the friction capability takes its Coulomb coefficient as the parameter `mu` (default 0;
 * docs/plugin-abi.md, capabilities) and with mu = 0 evaluates no tangential terms, keeps no slip history and reports
 * no slip. Read after create, so that the plugin validated the value and reading it here hides no unknown key. */
static void declare_friction(plugin_term *term) {
  if (term->pair < 0) return;
  sk_needs *needs = &term->base.needs;
  if (!(term->plugin->caps & SK_CAP_FRICTION)) {
    sk_needs_declare(needs, SK_NEED_FRICTION, 0, "plugin %s is frictionless (no friction capability)",
                     term->plugin->name);
    return;
  }
  const sk_cfg *node = sk_cfg_get(term->host.params, "mu");
  double mu = 0.0;
  if (!node)
    sk_needs_declare(needs, SK_NEED_FRICTION, 0, "mu not given (0: frictionless)");
  else if (sk_cfg_as_double(node, &mu) == SK_OK)
    sk_needs_declare(needs, SK_NEED_FRICTION, mu != 0.0, "mu = %g", mu);
  else /* the plugin accepted a value that is not a number: assume it is used */
    sk_needs_declare(needs, SK_NEED_FRICTION, 1, "mu = %s", sk_cfg_scalar(node) ? sk_cfg_scalar(node) : "?");
}

/* The message of a failed create() as "FILE:LINE:COL: contact pair 'NAME' (plugin P): ...": at the parameter the
 * plugin's message names ('key'), else at the `parameters` map, else (no `parameters`) at the `plugin` key, unless
 * the message has its position already (the host's getters give one); a plugin that names the pair itself
 * ("hertz: ...") would say it twice, so that goes. */
static void create_error(const plugin_term *term, const sk_model *m, sk_status status) {
  char message[2048];
  snprintf(message, sizeof message, "%s", sk_error_message());
  const char *text = message;
  size_t n = strlen(term->attach.name);
  if (n > 0 && strncmp(text, term->attach.name, n) == 0 && text[n] == ':' && text[n + 1] == ' ') text += n + 2;
  const sk_cfg *params = term->host.params, *at = NULL;
  const char *where = sk_cfg_where(params);
  const char *colon = strchr(where, ':');
  int positioned = strncmp(text, "--", 2) == 0 ||
                   (params && colon && strncmp(text, where, (size_t)(colon - where + 1)) == 0);
  for (int i = 0; params && !positioned && !at && i < sk_cfg_size(params); ++i) {
    char quoted[160];
    snprintf(quoted, sizeof quoted, "'%s'", sk_cfg_key_at(params, i));
    if (strstr(text, quoted)) at = sk_cfg_at(params, i);
  }
  if (params && !positioned && !at) at = params;
  if (!positioned && !at) at = term->pair >= 0 ? m->pairs[term->pair].plugin_node : m->bodies[term->body].plugin_node;
  const char *rest = positioned ? strstr(text, ": ") : NULL; /* after the position the message has */
  if (rest)
    sk_error_set(status, "%.*s: %s (plugin %s): %s", (int)(rest - text), text, term->base.name, term->plugin->name,
                 rest + 2);
  else
    sk_error_set(status, "%s%s%s (plugin %s): %s", at ? sk_cfg_where(at) : "", at ? ": " : "", term->base.name,
                 term->plugin->name, text);
}

sk_status sk_term_plugin_create(sk_system *sys, int body, int pair, sk_term **out) {
  plugin_term *term = calloc(1, sizeof *term);
  if (!term) return sk_error_set(SK_ERR_NOMEM, "out of memory for a plugin instance");
  term->base.ops = sk_plugin_term_ops();
  term->body = body;
  term->pair = pair;
  sk_status status = setup(term, sys, body, pair);
  /* A plugin built before ABI 2.1 does not know the second-order element types: it would misread them. */
  for (int v = 0; status == SK_OK && term->plugin->abi_minor < 1 && v < term->attach.n_views; ++v)
    if (term->attach.views[v]->cell_type >= SK_TRI6)
      status = sk_error_set(SK_ERR_PLUGIN, "%s: plugin '%s' is built for plugin ABI %u.%u, which predates the "
                            "second-order element types of '%s' (%s cells): rebuild it against ABI %u.%u",
                            term->base.name, term->plugin->name, term->plugin->abi_major, term->plugin->abi_minor,
                            term->attach.views[v]->name, sk_elem_name(term->attach.views[v]->cell_type),
                            SK_ABI_MAJOR, SK_ABI_MINOR);
  if (status == SK_OK) declare_needs(term, sys);
  /* before create: a body plugin may ask for its mass properties there */
  if (status == SK_OK && term->base.needs.needed[SK_NEED_MASS]) status = sk_model_build_mass(sys->model);
  if (status == SK_OK) {
    status = PLUGIN_CALL(term, create, sk_host_api_table(), &term->host, &term->attach, &term->instance);
    if (status != SK_OK) create_error(term, sys->model, status);
  }
  if (status == SK_OK) declare_friction(term);
  /* a body plugin's pair instances (its contacts, docs/plugin-abi.md §11.5) share the table but claim nothing */
  if (status == SK_OK && body >= 0 && term->table.integrator && !term->claimed)
    status = sk_error_set(SK_ERR_PLUGIN, "%s: plugin '%s' supplies an integrator but did not claim the body "
                          "(stickslip.bulk claim)", term->base.name, term->plugin->name);
  if (status == SK_OK && term->claimed) {
    term->integrator = term->table.integrator;
    if (term->integrator) {
      term->state.scheme = term->integrator->name;
      term->state.alpha = term->integrator->alpha;
      term->state.dynamic = term->integrator->dynamic;
      term->state.v_n = term->integrator->dynamic ? term->v_n_list : NULL;
    }
  }
  if (status != SK_OK) {
    sk_plugin_term_ops()->destroy(&term->base);
    return status;
  }
  *out = &term->base;
  return SK_OK;
}

sk_status sk_term_plugin_recreate(sk_term *base, sk_system *sys, const sk_record_reader *records,
                                      int slave_too) {
  plugin_term *term = (plugin_term *)base;
  const sk_contact_pair *pair = &sys->model->pairs[term->pair];
  term->table.destroy(term->instance);
  term->instance = NULL;
  const int first = slave_too ? 0 : 1; /* the views built again: the master's, with slave_too the slave's first */
  double **arrays[] = {term->x, term->x_n, term->v_n, term->F_view, term->dx_view, term->Jdx_view};
  for (int v = first; v < term->n_views; ++v) {
    sk_view_free(&term->views[v]);
    for (size_t j = 0; j < sizeof arrays / sizeof arrays[0]; ++j) {
      free(arrays[j][v]);
      arrays[j][v] = NULL;
    }
  }
  term->n_views = first;
  memset(term->in_view, 0, (size_t)(sys->model->n_nodes > 0 ? sys->model->n_nodes : 1));
  if (slave_too) {
    SK_TRY(add_view(term, sys, &pair->slave, pair->slave.name, 0, -1));
    term->attach.slave = term->view_list[0];
    term->anchor_count = -1; /* the extras' owners follow the slave nodes' contact owners (combine_anchors) */
  } else {
    SK_TRY(sk_view_localize(&term->views[0], sys)); /* the slave view's nodes keep their local dofs */
    for (int k = 0; k < term->views[0].view.n_nodes; ++k)
      term->in_view[term->views[0].local_dofs[(int64_t)k * sys->model->dim] / sys->model->dim] = 1;
  }
  if (!pair->has_obstacle) {
    SK_TRY(add_view(term, sys, &pair->master, pair->master.name, 1, -1));
    term->attach.master = term->view_list[1];
  }
  term->x_version = 0;
  sk_status status = PLUGIN_CALL(term, create, sk_host_api_table(), &term->host, &term->attach, &term->instance);
  if (status != SK_OK) {
    create_error(term, sys->model, status);
    return status;
  }
  return sk_term_plugin_load(base, sys, records);
}
