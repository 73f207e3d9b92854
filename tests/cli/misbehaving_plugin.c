/* Test plugin "test-misbehaving": slave nodes on springs to their reference positions (k = 1000), with one fault
 * chosen by the parameter `fault`, for the CLI tests of what the host does with a plugin that misbehaves (issue 15,
 * items 4, 11, 15; tests/cli/test_run_results.py):
 *   1 report: a NaN force          2 report: a negative count       3 residual: a row beyond the unknowns
 *   4 residual: an internal error without a message                 5 layout: 2e9 extra unknowns
 *   6 residual: every other step attempt fails (Newton cannot converge), so cuts alternate with good sub-steps */
#include <math.h>
#include <stdlib.h>

#include "stickslip/plugin.h"

struct sk_instance {
  const sk_host_api *api;
  sk_host *host;
  const sk_view *slave;
  int fault;
  int attempts; /* step attempts begun */
};

enum { REPORT_NAN = 1, REPORT_NEGATIVE = 2, ROW_BEYOND = 3, SILENT_ERROR = 4, HUGE_LAYOUT = 5, ALTERNATE_FAILURE = 6 };
static const double stiffness = 1000.0;

static const char *const strategies[] = {"none", NULL};
static const char *const parameters[] = {"fault: 1 NaN report, 2 negative count, 3 row beyond the unknowns, "
                                         "4 error without message, 5 2e9 extra unknowns, 6 every other step attempt "
                                         "fails [required]", NULL};

static void destroy(sk_instance *in) { free(in); }

static sk_status create(const sk_host_api *api, sk_host *host, const sk_attach *attach, sk_instance **out) {
  *out = NULL;
  sk_instance *in = calloc(1, sizeof *in);
  if (!in) return api->error(host, SK_ERR_NOMEM, "out of memory");
  in->api = api;
  in->host = host;
  in->slave = attach->slave;
  sk_status st = api->param_int(host, "fault", 1, 0, &in->fault);
  if (st != SK_OK) {
    destroy(in);
    return st;
  }
  *out = in;
  return SK_OK;
}

static sk_status begin_step(sk_instance *in, const sk_state *st) {
  (void)st;
  in->attempts++;
  return SK_OK;
}

static sk_status layout(sk_instance *in, const sk_state *st, sk_layout *layout) {
  (void)st;
  if (in->fault == HUGE_LAYOUT) layout->n_extra = 2000000000;
  return SK_OK;
}

static sk_status residual(sk_instance *in, const sk_state *st, sk_sink *sink) {
  if (in->fault == SILENT_ERROR) return SK_ERR_INTERNAL;
  if (in->fault == ALTERNATE_FAILURE && in->attempts % 2 == 1)
    return in->api->error(in->host, SK_ERR_DIVERGED, "test fault 6: step attempt %d fails", in->attempts);
  const sk_view *v = in->slave;
  for (int k = 0; k < v->n_nodes; ++k) {
    if (!v->owned[k]) continue;
    double F[3] = {0, 0, 0};
    for (int i = 0; i < v->dim; ++i) F[i] = stiffness * (st->x[0][k * v->dim + i] - v->X[k * v->dim + i]);
    sink->add_vector(sink, v->dim, v->dofs + k * v->dim, F);
  }
  if (in->fault == ROW_BEYOND) {
    const int64_t row = st->extra_offset + st->n_extra + 7;
    const double one = 1.0;
    sink->add_vector(sink, 1, &row, &one);
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

static sk_status commit_step(sk_instance *in, const sk_state *st) {
  (void)in, (void)st;
  return SK_OK;
}

static void reject_step(sk_instance *in) { (void)in; }

static sk_status report(sk_instance *in, const sk_state *st, sk_contact_report *r) {
  (void)st;
  if (in->fault == REPORT_NAN) r->force[1] = NAN;
  if (in->fault == REPORT_NEGATIVE) r->active = -3;
  return SK_OK;
}

static const sk_plugin plugin = {
    SK_TABLE_HEADER(sk_plugin),
    .name = "test-misbehaving",
    .summary = "test: springs with one chosen fault (NaN report, bad row, silent error, huge layout, failing attempts)",
    .kinds = SK_KIND_PAIR,
    .caps = SK_CAP_2D | SK_CAP_3D | SK_CAP_QUASISTATIC | SK_CAP_DYNAMICS | SK_CAP_RIGID_OBSTACLE |
            SK_CAP_DEFORMABLE_MASTER | SK_CAP_MULTIPLIERS,
    .strategies = strategies,
    .parameters = parameters,
    .create = create,
    .destroy = destroy,
    .begin_step = begin_step,
    .layout = layout,
    .residual = residual,
    .jacobian = jacobian,
    .commit_step = commit_step,
    .reject_step = reject_step,
    .report = report,
};

__attribute__((visibility("default"))) const sk_plugin *stickslip_plugin_entry(void);
__attribute__((visibility("default"))) const sk_plugin *stickslip_plugin_entry(void) { return &plugin; }
