/* Test plugin "test-midpoint-body": a body plugin that claims its body and integrates it itself, through
 * stickslip.bulk, with the energy-momentum midpoint rule of a linear (Hooke) body:
 *   F(u) = (2/dt^2) M (u - u_n - dt v_n) + S (u + u_n)/2 - f_ext(t_n + dt/2) = 0,   v = 2 (u - u_n)/dt - v_n,
 * which is what the core's midpoint scheme does for a Hooke body (its discrete gradient of a quadratic energy is the
 * midpoint force). A free flight must then keep the same invariants as the core midpoint rule
 * (tests/plugins/test_hooks.py). Uses claim, mass_properties, apply_mass, add_mass, apply_stiffness, add_stiffness,
 * external_force, set_state and the plugin's own integrator (predict, velocity, energy). */
#include <stdlib.h>
#include <string.h>

#include "stickslip/plugin.h"

struct sk_instance {
  const sk_host_api *api;
  sk_host *host;
  const sk_bulk_ext *bulk;
  const sk_view *body;
  int n;                  /* dofs of the body view */
  double mass, center[3];
  double energy_offset;   /* added to the reported strain energy (a test of which energy history.csv shows) */
  double *u, *u_n, *v_n, *w, *y, *f, *v;
};

static const char *const strategies[] = {"none", NULL};
static const char *const parameters[] = {"energy_offset: added to the strain energy the integrator reports [0]", NULL};

static void destroy(sk_instance *in) {
  if (!in) return;
  free(in->u);
  free(in->u_n);
  free(in->v_n);
  free(in->w);
  free(in->y);
  free(in->f);
  free(in->v);
  free(in);
}

static sk_status create(const sk_host_api *api, sk_host *host, const sk_attach *attach, sk_instance **out) {
  *out = NULL;
  sk_instance *in = calloc(1, sizeof *in);
  if (!in) return api->error(host, SK_ERR_NOMEM, "out of memory");
  in->api = api;
  in->host = host;
  in->body = attach->body;
  in->n = in->body->n_nodes * in->body->dim;
  double **arrays[] = {&in->u, &in->u_n, &in->v_n, &in->w, &in->y, &in->f, &in->v};
  for (size_t k = 0; k < sizeof arrays / sizeof arrays[0]; ++k) *arrays[k] = calloc((size_t)in->n + 1, sizeof(double));
  sk_status st = in->u && in->u_n && in->v_n && in->w && in->y && in->f && in->v ? SK_OK
                                                                                  : api->error(host, SK_ERR_NOMEM, "out of memory");
  if (st == SK_OK) {
    in->bulk = api->get_extension(host, SK_EXT_BULK);
    if (!in->bulk) st = api->error(host, SK_ERR_PLUGIN, "the host offers no %s", SK_EXT_BULK);
  }
  if (st == SK_OK) st = api->param_double(host, "energy_offset", 0, 0.0, &in->energy_offset);
  if (st == SK_OK) st = in->bulk->claim(host);
  if (st == SK_OK) st = in->bulk->mass_properties(host, &in->mass, in->center);
  if (st == SK_OK && !(in->mass > 0.0)) st = api->error(host, SK_ERR_INPUT, "body '%s' has no mass", attach->name);
  if (st != SK_OK) {
    destroy(in);
    return st;
  }
  api->log(host, 2, "body '%s': mass %g, centre (%g, %g, %g)", attach->name, in->mass, in->center[0], in->center[1],
           in->center[2]);
  *out = in;
  return SK_OK;
}

/* displacements and velocities of the step's start, and u at the iterate */
static void kinematics(sk_instance *in, const sk_state *st) {
  for (int k = 0; k < in->n; ++k) {
    in->u[k] = st->x[0][k] - in->body->X[k];
    in->u_n[k] = st->x_n[0][k] - in->body->X[k];
    in->v_n[k] = st->v_n ? st->v_n[0][k] : 0.0;
  }
}

static sk_status predict(sk_instance *in, const sk_state *st, double *u) {
  kinematics(in, st);
  for (int k = 0; k < in->n; ++k) u[k] = in->u_n[k] + st->dt * in->v_n[k];
  return SK_OK;
}

static sk_status velocity(sk_instance *in, const sk_state *st, double *v) {
  kinematics(in, st);
  for (int k = 0; k < in->n; ++k) v[k] = 2.0 * (in->u[k] - in->u_n[k]) / st->dt - in->v_n[k];
  return SK_OK;
}

/* ABI 2.5: the scheme's energy 1/2 v.Mv + 1/2 u.Su (this rank's part: apply_* return this rank's contributions),
 * plus the parameter energy_offset on the strain, so that a test sees which energy history.csv carries. The committed
 * state (commit_step keeps u and v), or the initial one for step 0. */
static sk_status energy(sk_instance *in, const sk_state *st, double *kinetic, double *strain) {
  if (st->step == 0) {
    kinematics(in, st);
    memcpy(in->v, in->v_n, sizeof(double) * (size_t)in->n);
  }
  SK_TRY(in->bulk->apply_mass(in->host, in->v, in->y));
  *kinetic = 0.0;
  for (int k = 0; k < in->n; ++k) *kinetic += 0.5 * in->v[k] * in->y[k];
  SK_TRY(in->bulk->apply_stiffness(in->host, in->u, in->y));
  *strain = 0.0;
  for (int k = 0; k < in->n; ++k) *strain += 0.5 * in->u[k] * in->y[k];
  int rank, n_ranks;
  in->api->ranks(in->host, &rank, &n_ranks);
  if (rank == 0) *strain += in->energy_offset;
  return SK_OK;
}

static const sk_integrator integrator = {SK_TABLE_HEADER(sk_integrator),
                                         .name = "test-midpoint",
                                         .alpha = 0.5,
                                         .dynamic = 1,
                                         .predict = predict,
                                         .velocity = velocity,
                                         .energy = energy};

static sk_status begin_step(sk_instance *in, const sk_state *st) {
  (void)in, (void)st;
  return SK_OK;
}

static sk_status layout(sk_instance *in, const sk_state *st, sk_layout *layout) {
  (void)in, (void)st, (void)layout;
  return SK_OK;
}

/* this rank's element contributions (the host sums them): (2/dt^2) M (u - u_n - dt v_n) + S (u + u_n)/2 - f_ext */
static sk_status residual(sk_instance *in, const sk_state *st, sk_sink *sink) {
  kinematics(in, st);
  const double c = 2.0 / (st->dt * st->dt);
  for (int k = 0; k < in->n; ++k) in->w[k] = in->u[k] - in->u_n[k] - st->dt * in->v_n[k];
  SK_TRY(in->bulk->apply_mass(in->host, in->w, in->y));
  for (int k = 0; k < in->n; ++k) {
    in->f[k] = c * in->y[k];
    in->w[k] = 0.5 * (in->u[k] + in->u_n[k]);
  }
  SK_TRY(in->bulk->apply_stiffness(in->host, in->w, in->y));
  for (int k = 0; k < in->n; ++k) in->f[k] += in->y[k];
  SK_TRY(in->bulk->external_force(in->host, 0.5 * (st->t_n + st->t), in->y));
  for (int k = 0; k < in->n; ++k) in->f[k] -= in->y[k];
  sink->add_vector(sink, in->n, in->body->dofs, in->f);
  return SK_OK;
}

static sk_status jacobian(sk_instance *in, const sk_state *st, sk_sink *sink) {
  const int dim = in->body->dim;
  const double c = 2.0 / (st->dt * st->dt);
  double block[9] = {0};
  for (int i = 0; i < dim; ++i) block[i * dim + i] = c;
  SK_TRY(in->bulk->add_mass(in->host, block, sink));
  return in->bulk->add_stiffness(in->host, 0.5, sink);
}

/* the state for output and invariants: the same u and v (exercises set_state) */
static sk_status commit_step(sk_instance *in, const sk_state *st) {
  SK_TRY(velocity(in, st, in->v));
  return in->bulk->set_state(in->host, in->u, in->v);
}

static void reject_step(sk_instance *in) { (void)in; }

static sk_status report(sk_instance *in, const sk_state *st, sk_contact_report *r) {
  (void)in, (void)st, (void)r;
  return SK_OK;
}

static const sk_plugin plugin = {
    SK_TABLE_HEADER(sk_plugin),
    .name = "test-midpoint-body",
    .summary = "test: a body plugin integrating a Hooke body with the midpoint rule through stickslip.bulk",
    .kinds = SK_KIND_BODY,
    .caps = SK_CAP_2D | SK_CAP_3D | SK_CAP_DYNAMICS | SK_CAP_ENERGY_MOMENTUM | SK_CAP_NEEDS_MASS |
            SK_CAP_OWNS_KINEMATICS,
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
    .integrator = &integrator,
};

__attribute__((visibility("default"))) const sk_plugin *stickslip_plugin_entry(void);
__attribute__((visibility("default"))) const sk_plugin *stickslip_plugin_entry(void) { return &plugin; }
