/* stickslip plugin "example-spring": the smallest complete plugin, written to be read (docs/writing-a-plugin.md).
 *
 * Every slave node s is tied to its reference position X_s by a spring with optional cubic hardening:
 *   d = x_s - X_s,   force on the node  f = -(k + k3 |d|^2) d.
 * The host solves F(x) = 0 where F = internal - external forces, so the plugin ADDS the restoring term with a
 * plus sign to the slave's rows:  F_s += (k + k3 |d|^2) d,  and its derivative to J:
 *   J_ss += (k + k3 |d|^2) I + 2 k3 d d^T.
 * The master (surface or obstacle) is ignored: this is not contact, it only shows the plumbing (parameters, views
 * and owned nodes, global indices, the declared pattern, sinks, report, points). No extra unknowns, no condensation,
 * no history. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "stickslip/plugin.h"

/* Only the entry symbol is exported; CMake builds plugins with hidden visibility by default. */
#define EXPORT __attribute__((visibility("default")))

struct sk_instance {      /* the per-pair state; the core only ever holds a pointer to it */
  const sk_host_api *api; /* the core's functions, valid for the instance's lifetime */
  sk_host *host;          /* the core's handle for this instance: the first argument of every api call */
  const sk_view *slave;   /* the slave surface as this rank sees it (owned nodes and ghosts) */
  double k, k3;           /* parameters */
};

static const char *const strategies[] = {"none", NULL}; /* no condensation: one strategy, "none" */
static const char *const parameters[] = {             /* shown by `stickslip plugins` */
    "k: spring stiffness per slave node (force/length) > 0 [computed from the scene: E h^(dim-2), E of the slave "
    "body, h the mean edge of the slave surface]",
    "k3: cubic hardening, force/length^3 >= 0 [0]", NULL};

/* ---- create / destroy: read and check parameters, allocate the instance ---------------------------------------- */
static void spring_destroy(sk_instance *in) { free(in); }

static sk_status spring_create(const sk_host_api *api, sk_host *host, const sk_attach *attach, sk_instance **out) {
  *out = NULL;
  sk_instance *in = calloc(1, sizeof *in);
  if (!in) return api->error(host, SK_ERR_NOMEM, "example-spring: out of memory");
  in->api = api;
  in->host = host;
  in->slave = attach->slave;
  /* Reading a key marks it used; keys a plugin never reads are reported to the user as unknown. A key whose good
   * value depends on the scene gets its default from it (stickslip.scene.v1): read with the default NaN, and when the
   * scene does not give it, compute it and tell the host why (--explain prints it). Here k = E h^(dim-2), the
   * stiffness of an element of the slave body under a nodal load: E of the slave body, h the mean edge of its
   * surface. */
  sk_status st = api->param_double(host, "k", 0, NAN, &in->k);
  const sk_scene_ext *scene = SK_HAS(api, get_extension) ? api->get_extension(host, SK_EXT_SCENE) : NULL;
  if (st == SK_OK && isnan(in->k)) {
    const sk_scene_info *info = scene ? scene->info(host) : NULL;
    if (!info) {
      st = api->error(host, SK_ERR_INPUT, "example-spring: give k (this stickslip cannot compute it from the scene)");
    } else {
      const sk_scene_side *side = info->slave;
      in->k = side->E * (info->dim == 3 ? side->h_mean : 1.0);
      scene->computed(host, "k", in->k, "E h^(dim-2); E = %g of slave body '%s', h = %g mean edge of slave surface "
                      "'%s'", side->E, side->body_name, side->h_mean, side->name);
    }
  }
  if (st == SK_OK) st = api->param_double(host, "k3", 0, 0.0, &in->k3);
  if (st == SK_OK && !(in->k > 0.0 && in->k3 >= 0.0))
    st = api->error(host, SK_ERR_INPUT, "example-spring needs k > 0 and k3 >= 0 (got k = %g, k3 = %g)", in->k,
                    in->k3);
  if (st != SK_OK) {
    spring_destroy(in);
    return st;
  }
  *out = in;
  return SK_OK;
}

/* ---- the step ------------------------------------------------------------------------------------------------- */
/* Nothing to search or freeze: a contact plugin would update its broad phase and candidate pairs here. */
static sk_status spring_begin_step(sk_instance *in, const sk_state *st) {
  (void)in, (void)st;
  return SK_OK;
}

/* No extra unknowns (no multipliers), so nothing eliminated either. */
static sk_status spring_layout(sk_instance *in, const sk_state *st, sk_layout *layout) {
  (void)in, (void)st;
  layout->n_extra = 0;
  layout->initial = NULL;
  layout->eliminated = NULL;
  return SK_OK;
}

/* The couplings jacobian() adds: each owned slave node's dofs with themselves. (A node's own block lies in the bulk
 * element graph anyway; a contact plugin declares slave nodes against their candidate master nodes here.) */
static sk_status spring_pattern(sk_instance *in, const sk_state *st, sk_pattern *pattern) {
  (void)st;
  const sk_view *v = in->slave;
  for (int k = 0; k < v->n_nodes; ++k)
    if (v->owned[k]) pattern->add_block(pattern, v->dim, v->dofs + k * v->dim, v->dim, v->dofs + k * v->dim);
  return SK_OK;
}

/* Slave view node k: displacement d = x - X and the factor k + k3 |d|^2. Positions come per view (state->x[0] is the
 * slave view: dim per view node), reference positions from the view. */
static double spring_point(const sk_instance *in, const sk_state *st, int k, double d[3]) {
  const int dim = in->slave->dim;
  const double *x = st->x[0] + k * dim, *X = in->slave->X + k * dim;
  double d2 = 0.0;
  d[0] = d[1] = d[2] = 0.0;
  for (int i = 0; i < dim; ++i) {
    d[i] = x[i] - X[i];
    d2 += d[i] * d[i];
  }
  return in->k + in->k3 * d2;
}

/* Each rank adds only the nodes it owns (view->owned): the host sums the ranks' contributions, so each entry counts
 * once. Rows are global unknown indices: view->dofs. */
static sk_status spring_residual(sk_instance *in, const sk_state *st, sk_sink *sink) {
  const sk_view *v = in->slave;
  for (int k = 0; k < v->n_nodes; ++k) {
    if (!v->owned[k]) continue;
    double d[3], F[3];
    const double s = spring_point(in, st, k, d);
    for (int i = 0; i < 3; ++i) F[i] = s * d[i];       /* F_s += (k + k3|d|^2) d */
    sink->add_vector(sink, v->dim, v->dofs + k * v->dim, F);
  }
  return SK_OK;
}

static sk_status spring_jacobian(sk_instance *in, const sk_state *st, sk_sink *sink) {
  const sk_view *v = in->slave;
  const int dim = v->dim;
  for (int k = 0; k < v->n_nodes; ++k) {
    if (!v->owned[k]) continue;
    double d[3], K[9];
    const double s = spring_point(in, st, k, d);
    for (int i = 0; i < dim; ++i)                     /* row-major dim x dim block: dF_i / dx_j */
      for (int j = 0; j < dim; ++j) K[i * dim + j] = (i == j ? s : 0.0) + 2.0 * in->k3 * d[i] * d[j];
    sink->add_matrix(sink, dim, v->dofs + k * dim, dim, v->dofs + k * dim, K);
  }
  return SK_OK;
}

/* No history: nothing to commit or roll back. */
static sk_status spring_commit_step(sk_instance *in, const sk_state *st) {
  (void)in, (void)st;
  return SK_OK;
}
static void spring_reject_step(sk_instance *in) { (void)in; }
/* Checkpoints: no history to save (the table says so; without it the host could not tell). */
static const sk_checkpoint_ext spring_checkpoint = {SK_TABLE_HEADER(sk_checkpoint_ext), .save = NULL, .load = NULL};
static const void *spring_extension(const char *id) {
  return id && strcmp(id, SK_EXT_CHECKPOINT) == 0 ? &spring_checkpoint : NULL;
}

/* Resultant force and moment on the slave side (f = -F_s) over this rank's nodes; the host sums over ranks. */
static sk_status spring_report(sk_instance *in, const sk_state *st, sk_contact_report *r) {
  const sk_view *v = in->slave;
  for (int k = 0; k < v->n_nodes; ++k) {
    if (!v->owned[k]) continue;
    double d[3], x[3] = {0, 0, 0};
    const double s = spring_point(in, st, k, d);
    for (int i = 0; i < v->dim; ++i) x[i] = st->x[0][k * v->dim + i];
    const double f[3] = {-s * d[0], -s * d[1], -s * d[2]};
    for (int i = 0; i < 3; ++i) r->force[i] += f[i];
    r->moment[0] += x[1] * f[2] - x[2] * f[1];
    r->moment[1] += x[2] * f[0] - x[0] * f[2];
    r->moment[2] += x[0] * f[1] - x[1] * f[0];
  }
  return SK_OK;
}

/* One output point per owned slave node (contact.csv, VTU): the spring force as the tangential "traction", no
 * pressure or gap. A node's spring has no area: `forces` says so, and the host divides by the node's tributary
 * reference measure of the slave surface, so that contact.csv's traction is a traction as for every plugin. */
static sk_status spring_points(sk_instance *in, const sk_state *st, sk_point_callback callback, void *ctx) {
  const sk_view *v = in->slave;
  for (int k = 0; k < v->n_nodes; ++k) {
    if (!v->owned[k]) continue;
    double d[3];
    const double s = spring_point(in, st, k, d);
    sk_contact_point p = {.struct_size = sizeof p}; /* every struct a plugin hands over says its size */
    for (int i = 0; i < v->dim; ++i) p.x[i] = st->x[0][k * v->dim + i];
    for (int i = 0; i < 3; ++i) p.traction[i] = -s * d[i];
    p.forces = 1; /* ABI 2.6 */
    p.slave_node = v->node_id[k];
    callback(ctx, &p);
  }
  return SK_OK;
}

/* ---- what it cannot run (ABI 2.7): called before any instance exists ------------------------------------------- */
/* The capabilities already say what the host checks (dimension, obstacle or master, scheme, friction). A plugin
 * refuses here what the scene alone decides and the bits cannot say. This one runs anything it is named for, but it
 * is no contact formulation, so it declines when the host looks for plugins that can replace another one. */
static sk_status spring_check(const sk_scene_info *scene, char *reason, int size) {
  if (!scene->probe) return SK_OK;
  snprintf(reason, (size_t)size, "example-spring is a teaching example, not a contact formulation");
  return SK_ERR_PLUGIN;
}

/* ---- the table and the one exported symbol ---------------------------------------------------------------------- */
static const sk_plugin example_spring = {
    SK_TABLE_HEADER(sk_plugin), /* ABI major/minor this plugin is built for, and the table's size */
    .name = "example-spring",   /* the name scenes use */
    .summary = "example: ties every slave node to its reference position by a (cubic-hardening) spring",
    .kinds = SK_KIND_PAIR,      /* one instance per contact pair naming it */
    .caps = SK_CAP_2D | SK_CAP_3D | SK_CAP_QUASISTATIC | SK_CAP_DYNAMICS | SK_CAP_RIGID_OBSTACLE |
            SK_CAP_DEFORMABLE_MASTER,
    .strategies = strategies,
    .parameters = parameters,
    .create = spring_create,
    .destroy = spring_destroy,
    .begin_step = spring_begin_step,
    .layout = spring_layout,
    .pattern = spring_pattern,
    .update_active_set = NULL, /* no active set */
    .residual = spring_residual,
    .jacobian = spring_jacobian,
    .recover = NULL,           /* never eliminates unknowns */
    .converged = NULL,         /* accepts every converged point */
    .commit_step = spring_commit_step,
    .reject_step = spring_reject_step,
    .report = spring_report,
    .points = spring_points,
    .integrator = NULL,        /* not a body plugin */
    .get_extension = spring_extension,
    .check = spring_check,     /* ABI 2.7: what it refuses before any instance exists */
};

EXPORT const sk_plugin *stickslip_plugin_entry(void);
EXPORT const sk_plugin *stickslip_plugin_entry(void) { return &example_spring; }
