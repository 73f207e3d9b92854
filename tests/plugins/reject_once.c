/* Test plugin "test-reject-once": every slave node on a spring to its reference position (as example-spring), with
 * an "active set" of one member: the stiffness. Each step starts with k_first; when Newton has converged, the
 * converged() hook switches to k_final and rejects the converged point once, so the host must run Newton again
 * from there (an outer active-set loop). The step then ends in equilibrium with k_final, which a host that ignored
 * the rejection would miss (tests/plugins/test_hooks.py compares with example-spring at k = k_final). */
#include <stdlib.h>

#include "stickslip/plugin.h"

struct sk_instance {
  const sk_host_api *api;
  sk_host *host;
  const sk_view *slave;
  double k_first, k_final, k;
  int rejected;        /* this step's converged point was rejected once */
};

static const char *const strategies[] = {"none", NULL};
static const char *const parameters[] = {"k_first: the spring stiffness Newton starts each step with [required]",
                                         "k_final: the stiffness after the one rejection [required]", NULL};

static void destroy(sk_instance *in) { free(in); }

static sk_status create(const sk_host_api *api, sk_host *host, const sk_attach *attach, sk_instance **out) {
  *out = NULL;
  sk_instance *in = calloc(1, sizeof *in);
  if (!in) return api->error(host, SK_ERR_NOMEM, "out of memory");
  in->api = api;
  in->host = host;
  in->slave = attach->slave;
  sk_status st = api->param_double(host, "k_first", 1, 0.0, &in->k_first);
  if (st == SK_OK) st = api->param_double(host, "k_final", 1, 0.0, &in->k_final);
  if (st != SK_OK) {
    destroy(in);
    return st;
  }
  *out = in;
  return SK_OK;
}

static sk_status begin_step(sk_instance *in, const sk_state *st) {
  (void)st;
  in->k = in->k_first;
  in->rejected = 0;
  return SK_OK;
}

static sk_status layout(sk_instance *in, const sk_state *st, sk_layout *layout) {
  (void)in, (void)st, (void)layout;
  return SK_OK;
}

static sk_status residual(sk_instance *in, const sk_state *st, sk_sink *sink) {
  const sk_view *v = in->slave;
  for (int k = 0; k < v->n_nodes; ++k) {
    if (!v->owned[k]) continue;
    double F[3] = {0, 0, 0};
    for (int i = 0; i < v->dim; ++i) F[i] = in->k * (st->x[0][k * v->dim + i] - v->X[k * v->dim + i]);
    sink->add_vector(sink, v->dim, v->dofs + k * v->dim, F);
  }
  return SK_OK;
}

static sk_status jacobian(sk_instance *in, const sk_state *st, sk_sink *sink) {
  (void)st;
  const sk_view *v = in->slave;
  double K[9] = {0};
  for (int i = 0; i < v->dim; ++i) K[i * v->dim + i] = in->k;
  for (int k = 0; k < v->n_nodes; ++k)
    if (v->owned[k]) sink->add_matrix(sink, v->dim, v->dofs + k * v->dim, v->dim, v->dofs + k * v->dim, K);
  return SK_OK;
}

/* the set changes once per step, at the first converged point */
static sk_status converged(sk_instance *in, const sk_state *st, int *accept) {
  (void)st;
  *accept = in->rejected;
  if (!in->rejected) {
    in->rejected = 1;
    in->k = in->k_final;
  }
  return SK_OK;
}

static sk_status commit_step(sk_instance *in, const sk_state *st) {
  (void)st;
  if (in->k != in->k_final)
    return in->api->error(in->host, SK_ERR_INTERNAL, "committed with k = %g: the rejected point was accepted", in->k);
  return SK_OK;
}

static void reject_step(sk_instance *in) { (void)in; }

static sk_status report(sk_instance *in, const sk_state *st, sk_contact_report *r) {
  const sk_view *v = in->slave;
  for (int k = 0; k < v->n_nodes; ++k)
    if (v->owned[k])
      for (int i = 0; i < v->dim; ++i) r->force[i] -= in->k * (st->x[0][k * v->dim + i] - v->X[k * v->dim + i]);
  return SK_OK;
}

static const sk_plugin plugin = {
    SK_TABLE_HEADER(sk_plugin),
    .name = "test-reject-once",
    .summary = "test: springs whose stiffness (the active set) changes once per step in converged()",
    .kinds = SK_KIND_PAIR,
    .caps = SK_CAP_2D | SK_CAP_3D | SK_CAP_QUASISTATIC | SK_CAP_DYNAMICS | SK_CAP_RIGID_OBSTACLE |
            SK_CAP_DEFORMABLE_MASTER,
    .strategies = strategies,
    .parameters = parameters,
    .create = create,
    .destroy = destroy,
    .begin_step = begin_step,
    .layout = layout,
    .residual = residual,
    .jacobian = jacobian,
    .converged = converged,
    .commit_step = commit_step,
    .reject_step = reject_step,
    .report = report,
};

__attribute__((visibility("default"))) const sk_plugin *stickslip_plugin_entry(void);
__attribute__((visibility("default"))) const sk_plugin *stickslip_plugin_entry(void) { return &plugin; }
