/* Test plugin "test-points": slave nodes on springs to their reference positions (k = 1000), whose contact points
 * exercise how the host completes a point (docs/plugin-abi.md §8; tests/cli/test_run_results.py, case
 * plugin_points_layouts):
 *   layout 24       a plugin built before ABI 2.6: the point's struct ends after `multiplier` (its struct_size says
 *                   so), pressure 2 is a traction, so the host adds its tributary area and the normal force
 *   layout forces   ABI 2.6 with `forces`: pressure 0.5 and traction (0.1, 0, 0) are the node's forces, which the host
 *                   divides by the node's tributary area */
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "stickslip/plugin.h"

struct sk_instance {
  const sk_host_api *api;
  sk_host *host;
  const sk_view *slave;
  int forces;
};

static const double stiffness = 1000.0;
static const char *const strategies[] = {"none", NULL};
static const char *const parameters[] = {"layout: 24 (a 2.4 point, tractions) or forces (2.6, nodal forces) "
                                         "[required]", NULL};

static void destroy(sk_instance *in) { free(in); }

static sk_status create(const sk_host_api *api, sk_host *host, const sk_attach *attach, sk_instance **out) {
  *out = NULL;
  const char *layout;
  SK_TRY(api->param_string(host, "layout", 1, NULL, &layout));
  if (strcmp(layout, "24") != 0 && strcmp(layout, "forces") != 0)
    return api->error(host, SK_ERR_INPUT, "test-points: layout must be 24 or forces, got '%s'", layout);
  sk_instance *in = calloc(1, sizeof *in);
  if (!in) return api->error(host, SK_ERR_NOMEM, "out of memory");
  *in = (sk_instance){api, host, attach->slave, strcmp(layout, "forces") == 0};
  *out = in;
  return SK_OK;
}

static sk_status nothing(sk_instance *in, const sk_state *st) { return (void)in, (void)st, SK_OK; }
static void reject_step(sk_instance *in) { (void)in; }

static sk_status layout(sk_instance *in, const sk_state *st, sk_layout *layout) {
  (void)in, (void)st, (void)layout;
  return SK_OK;
}

static sk_status residual(sk_instance *in, const sk_state *st, sk_sink *sink) {
  const sk_view *v = in->slave;
  for (int k = 0; k < v->n_nodes; ++k) {
    if (!v->owned[k]) continue;
    double F[3] = {0, 0, 0};
    for (int i = 0; i < v->dim; ++i) F[i] = stiffness * (st->x[0][k * v->dim + i] - v->X[k * v->dim + i]);
    sink->add_vector(sink, v->dim, v->dofs + k * v->dim, F);
  }
  return SK_OK;
}

static sk_status jacobian(sk_instance *in, const sk_state *st, sk_sink *sink) {
  (void)st;
  const sk_view *v = in->slave;
  double K[9] = {0};
  for (int i = 0; i < v->dim; ++i) K[i * v->dim + i] = stiffness;
  for (int k = 0; k < v->n_nodes; ++k)
    if (v->owned[k]) sink->add_matrix(sink, v->dim, v->dofs + k * v->dim, v->dim, v->dofs + k * v->dim, K);
  return SK_OK;
}

static sk_status report(sk_instance *in, const sk_state *st, sk_contact_report *r) {
  return (void)in, (void)st, (void)r, SK_OK;
}

static sk_status points(sk_instance *in, const sk_state *st, sk_point_callback callback, void *ctx) {
  const sk_view *v = in->slave;
  for (int k = 0; k < v->n_nodes; ++k) {
    if (!v->owned[k]) continue;
    sk_contact_point p;
    memset(&p, 0, sizeof p);
    /* a plugin built before 2.6 knew the struct up to `multiplier`: the host must not read further */
    p.struct_size = in->forces ? sizeof p : offsetof(sk_contact_point, forces);
    for (int i = 0; i < v->dim; ++i) p.x[i] = st->x[0][k * v->dim + i];
    p.normal[v->dim - 1] = 1.0;
    p.state = 1;
    p.slave_node = v->node_id[k];
    if (in->forces) {
      p.forces = 1;
      p.pressure = 0.5;
      p.traction[0] = 0.1;
    } else {
      p.pressure = 2.0;
      p.forces = 1; /* beyond the struct_size: must not be read */
      p.area = 99.0;
    }
    callback(ctx, &p);
  }
  return SK_OK;
}

static const sk_plugin plugin = {
    SK_TABLE_HEADER(sk_plugin),
    .name = "test-points",
    .summary = "test: springs whose contact points are reported in the 2.4 layout or as nodal forces",
    .kinds = SK_KIND_PAIR,
    .caps = SK_CAP_2D | SK_CAP_3D | SK_CAP_QUASISTATIC | SK_CAP_RIGID_OBSTACLE | SK_CAP_DEFORMABLE_MASTER,
    .strategies = strategies,
    .parameters = parameters,
    .create = create,
    .destroy = destroy,
    .begin_step = nothing,
    .layout = layout,
    .residual = residual,
    .jacobian = jacobian,
    .commit_step = nothing,
    .reject_step = reject_step,
    .report = report,
    .points = points,
};

__attribute__((visibility("default"))) const sk_plugin *stickslip_plugin_entry(void);
__attribute__((visibility("default"))) const sk_plugin *stickslip_plugin_entry(void) { return &plugin; }
