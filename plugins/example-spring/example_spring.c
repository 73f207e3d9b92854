/* stickslip plugin "example-spring": the smallest complete plugin, written to be read (docs/writing-a-plugin.md).
 *
 * Every slave node s is tied to its reference position X_s by a spring with optional cubic hardening:
 *   d = x_s - X_s,   force on the node  f = -(k + k3 |d|^2) d.
 * The driver solves F(x) = 0 where F = internal - external forces, so the plugin ADDS the restoring term with a
 * plus sign to the slave's rows:  F_s += (k + k3 |d|^2) d,  and its derivative to J:
 *   J_ss += (k + k3 |d|^2) I + 2 k3 d d^T.
 * The master (surface or obstacle) is ignored: this is not contact, it only shows the plumbing (parameters, owned
 * nodes, global indices, sinks, report, points). No extra unknowns, no condensation, no history. */
#include <stdlib.h>
#include <string.h>

#include "stickslip/plugin.h"

/* Only the entry symbol is exported; CMake builds plugins with hidden visibility by default. */
#define EXPORT __attribute__((visibility("default")))

struct sk_instance {  /* the per-pair state; the core only ever holds a pointer to it */
  const sk_host *host; /* valid for the instance's lifetime */
  const sk_pair *pair;
  double k, k3;        /* parameters */
};

static const char *const strategies[] = {"none", NULL}; /* no condensation: one strategy, "none" */
static const char *const parameters[] = {             /* shown by `stickslip plugins` */
    "k: spring stiffness per slave node (force/length) > 0 [required]",
    "k3: cubic hardening, force/length^3 >= 0 [0]", NULL};

/* ---- create / destroy: read and check parameters, allocate the instance ---------------------------------------- */
static void spring_destroy(sk_instance *in) { free(in); }

static sk_status spring_create(const sk_host *host, const sk_pair *pair, sk_instance **out) {
  *out = NULL;
  if (host->abi_version != SK_PLUGIN_ABI_VERSION)
    return host->error(host, SK_ERR_PLUGIN, "example-spring built for ABI %u, host has %u", SK_PLUGIN_ABI_VERSION,
                       host->abi_version);
  sk_instance *in = calloc(1, sizeof *in);
  if (!in) return host->error(host, SK_ERR_NOMEM, "%s: example-spring: out of memory", pair->name);
  in->host = host;
  in->pair = pair;
  /* Reading a key marks it used; keys a plugin never reads are reported to the user as unknown. */
  sk_status st = host->param_double(host, pair->params, "k", 1, 0.0, &in->k);
  if (st == SK_OK) st = host->param_double(host, pair->params, "k3", 0, 0.0, &in->k3);
  if (st == SK_OK && !(in->k > 0.0 && in->k3 >= 0.0))
    st = host->error(host, SK_ERR_INPUT, "%s: example-spring needs k > 0 and k3 >= 0 (got k = %g, k3 = %g)",
                     pair->name, in->k, in->k3);
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

/* Slave node k (index into pair->slave->nodes): global dof rows, displacement d and the factor k + k3 |d|^2. */
static double spring_point(const sk_instance *in, const sk_state *st, int k, int rows[3], double d[3]) {
  const int dim = in->host->dim, node = in->pair->slave->nodes[k];
  double d2 = 0.0;
  d[0] = d[1] = d[2] = 0.0;
  for (int i = 0; i < dim; ++i) {
    rows[i] = node * dim + i;                        /* displacement dofs are node-major: node*dim + i */
    d[i] = st->q[rows[i]] - in->host->X[rows[i]];    /* q: current positions, X: reference positions */
    d2 += d[i] * d[i];
  }
  return in->k + in->k3 * d2;
}

/* Each rank adds only the nodes it owns: the driver sums the ranks' contributions, so each entry counts once. */
static int owned(const sk_instance *in, int k) { return in->host->owns_node(in->host, in->pair->slave->nodes[k]); }

static sk_status spring_residual(sk_instance *in, const sk_state *st, sk_sink *sink) {
  for (int k = 0; k < in->pair->slave->n_nodes; ++k) {
    if (!owned(in, k)) continue;
    int rows[3];
    double d[3], F[3];
    double s = spring_point(in, st, k, rows, d);
    for (int i = 0; i < 3; ++i) F[i] = s * d[i];       /* F_s += (k + k3|d|^2) d */
    sink->add_vector(sink, in->host->dim, rows, F);
  }
  return SK_OK;
}

static sk_status spring_jacobian(sk_instance *in, const sk_state *st, sk_sink *sink) {
  const int dim = in->host->dim;
  for (int k = 0; k < in->pair->slave->n_nodes; ++k) {
    if (!owned(in, k)) continue;
    int rows[3];
    double d[3], K[9];
    double s = spring_point(in, st, k, rows, d);
    for (int i = 0; i < dim; ++i)                     /* row-major dim x dim block: dF_i / dx_j */
      for (int j = 0; j < dim; ++j) K[i * dim + j] = (i == j ? s : 0.0) + 2.0 * in->k3 * d[i] * d[j];
    sink->add_matrix(sink, dim, rows, dim, rows, K);
  }
  return SK_OK;
}

/* No history: nothing to commit or roll back. */
static sk_status spring_commit_step(sk_instance *in, const sk_state *st) {
  (void)in, (void)st;
  return SK_OK;
}
static void spring_reject_step(sk_instance *in) { (void)in; }

/* Resultant force on the slave side (f = -F_s) over this rank's nodes; the driver sums over ranks. Also called for
 * the initial state, before any begin_step. */
static sk_status spring_report(sk_instance *in, const sk_state *st, sk_contact_report *r) {
  memset(r, 0, sizeof *r);
  for (int k = 0; k < in->pair->slave->n_nodes; ++k) {
    if (!owned(in, k)) continue;
    int rows[3];
    double d[3], x[3] = {0, 0, 0};
    double s = spring_point(in, st, k, rows, d);
    for (int i = 0; i < in->host->dim; ++i) x[i] = st->q[rows[i]];
    double f[3] = {-s * d[0], -s * d[1], -s * d[2]};
    for (int i = 0; i < 3; ++i) r->force[i] += f[i];
    r->moment[0] += x[1] * f[2] - x[2] * f[1];
    r->moment[1] += x[2] * f[0] - x[0] * f[2];
    r->moment[2] += x[0] * f[1] - x[1] * f[0];
  }
  return SK_OK;
}

/* One output point per owned slave node (contact.csv, VTU): the spring force as "traction", no pressure or gap. */
static sk_status spring_points(sk_instance *in, const sk_state *st, sk_point_callback callback, void *ctx) {
  for (int k = 0; k < in->pair->slave->n_nodes; ++k) {
    if (!owned(in, k)) continue;
    int rows[3];
    double d[3];
    double s = spring_point(in, st, k, rows, d);
    sk_contact_point p;
    memset(&p, 0, sizeof p);
    for (int i = 0; i < in->host->dim; ++i) p.x[i] = st->q[rows[i]];
    for (int i = 0; i < 3; ++i) p.traction[i] = -s * d[i];
    p.slave_node = in->pair->slave->nodes[k];
    callback(ctx, &p);
  }
  return SK_OK;
}

/* ---- the table and the one exported symbol ---------------------------------------------------------------------- */
static const sk_plugin example_spring = {
    .abi_version = SK_PLUGIN_ABI_VERSION,
    .name = "example-spring", /* must match the library name libstickslip-<name>.so */
    .summary = "example: ties every slave node to its reference position by a (cubic-hardening) spring",
    .caps = SK_CAP_2D | SK_CAP_3D | SK_CAP_QUASISTATIC | SK_CAP_DYNAMICS | SK_CAP_RIGID_OBSTACLE |
            SK_CAP_DEFORMABLE_MASTER,
    .strategies = strategies,
    .parameters = parameters,
    .create = spring_create,
    .destroy = spring_destroy,
    .begin_step = spring_begin_step,
    .layout = spring_layout,
    .residual = spring_residual,
    .jacobian = spring_jacobian,
    .recover = NULL,          /* never eliminates unknowns */
    .after_iteration = NULL,  /* no active set */
    .commit_step = spring_commit_step,
    .reject_step = spring_reject_step,
    .report = spring_report,
    .points = spring_points,
    .get_extension = NULL,
};

EXPORT const sk_plugin *stickslip_plugin_entry(void);
EXPORT const sk_plugin *stickslip_plugin_entry(void) { return &example_spring; }
