/* Test plugin "test-tied-dual": a tied (glued) interface with one multiplier vector per slave node, either kept
 * (strategy saddle-point) or eliminated on the assembled operator through stickslip.condense (strategy dual). It
 * proves the condensation hook: both strategies must give the same displacements (tests/plugins/test_hooks.py).
 *
 * Each slave node k is tied to the master point it projects to in the reference configuration (face f_k, xi_k):
 *   Phi_k = x_k - sum_I N_I(xi_k) x_I = 0,
 * weighted by the slave node's tributary length/area w_k (a dual-mortar D_k = w_k I: diagonal per node):
 *   slave rows      += w_k z_k          master rows of node I  -= w_k N_I z_k          z_k rows = w_k Phi_k.
 * With check_solve_again = 1, recover() also solves with two unit right-hand sides through stickslip.linear and
 * checks that the inverse is symmetric (the operator of this test is), i.e. that solve_again reuses this operator. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "stickslip/plugin.h"

enum { MAX_NEN = 9 };

struct sk_instance {
  const sk_host_api *api;
  sk_host *host;
  const sk_view *slave, *master;
  int dim, dual, check_again;
  int *face;          /* per slave view node: the master face it is tied to */
  double (*N)[MAX_NEN];
  double *w;          /* tributary weights */
  int64_t *extra_index, *rows; /* stickslip.condense pairs of the owned nodes */
  const sk_condense_ext *condense;
  const sk_linear_ext *linear;
  double *b_view[2], *y_view[2], *b_extra, *y_extra, *y2_view[2], *y2_extra;
};

static const char *const strategies[] = {"saddle-point", "dual", NULL};
static const char *const parameters[] = {"check_solve_again: 1 checks stickslip.linear in recover [0]", NULL};

static void destroy(sk_instance *in) {
  if (!in) return;
  free(in->face);
  free(in->N);
  free(in->w);
  free(in->extra_index);
  free(in->rows);
  for (int v = 0; v < 2; ++v) {
    free(in->b_view[v]);
    free(in->y_view[v]);
    free(in->y2_view[v]);
  }
  free(in->b_extra);
  free(in->y_extra);
  free(in->y2_extra);
  free(in);
}

static sk_status create(const sk_host_api *api, sk_host *host, const sk_attach *attach, sk_instance **out) {
  *out = NULL;
  if (!attach->master) return api->error(host, SK_ERR_INPUT, "test-tied-dual needs a master surface");
  sk_instance *in = calloc(1, sizeof *in);
  if (!in) return api->error(host, SK_ERR_NOMEM, "out of memory");
  in->api = api;
  in->host = host;
  in->slave = attach->slave;
  in->master = attach->master;
  in->dim = in->slave->dim;
  in->dual = attach->strategy == 1;
  sk_status st = api->param_int(host, "check_solve_again", 0, 0, &in->check_again);
  const int n = in->slave->n_nodes;
  in->face = calloc((size_t)n + 1, sizeof(int));
  in->N = calloc((size_t)n + 1, sizeof *in->N);
  in->w = calloc((size_t)n + 1, sizeof(double));
  in->extra_index = calloc((size_t)(n * in->dim) + 1, sizeof(int64_t));
  in->rows = calloc((size_t)(n * in->dim) + 1, sizeof(int64_t));
  if (st == SK_OK && (!in->face || !in->N || !in->w || !in->extra_index || !in->rows))
    st = api->error(host, SK_ERR_NOMEM, "out of memory");
  if (st == SK_OK && in->dual) {
    in->condense = api->get_extension(host, SK_EXT_CONDENSE);
    if (!in->condense) st = api->error(host, SK_ERR_PLUGIN, "the host offers no %s", SK_EXT_CONDENSE);
  }
  if (st == SK_OK && in->check_again) {
    in->linear = api->get_extension(host, SK_EXT_LINEAR);
    if (!in->linear) st = api->error(host, SK_ERR_PLUGIN, "the host offers no %s", SK_EXT_LINEAR);
    for (int v = 0; v < attach->n_views && st == SK_OK; ++v) {
      const size_t m = (size_t)attach->views[v]->n_nodes * (size_t)in->dim + 1;
      in->b_view[v] = calloc(m, sizeof(double));
      in->y_view[v] = calloc(m, sizeof(double));
      in->y2_view[v] = calloc(m, sizeof(double));
      if (!in->b_view[v] || !in->y_view[v] || !in->y2_view[v]) st = api->error(host, SK_ERR_NOMEM, "out of memory");
    }
    const size_t ne = (size_t)(in->slave->n_nodes_global * in->dim) + 1;
    in->b_extra = calloc(ne, sizeof(double));
    in->y_extra = calloc(ne, sizeof(double));
    in->y2_extra = calloc(ne, sizeof(double));
    if (st == SK_OK && (!in->b_extra || !in->y_extra || !in->y2_extra))
      st = api->error(host, SK_ERR_NOMEM, "out of memory");
  }
  /* the tie points (reference projection) and the tributary weights */
  const sk_contact_services *cs = api->contact;
  for (int k = 0; k < n && st == SK_OK; ++k) {
    double x[3] = {0, 0, 0};
    for (int i = 0; i < in->dim; ++i) x[i] = in->slave->X[k * in->dim + i];
    sk_projection proj = {.struct_size = sizeof proj};
    st = cs->project(in->master, in->master->X, x, NULL, 0, &proj);
    if (st == SK_OK && proj.face < 0) st = api->error(host, SK_ERR_INPUT, "slave node %lld projects nowhere",
                                                     (long long)in->slave->node_id[k]);
    if (st != SK_OK) break;
    sk_surface_point pt = {.struct_size = sizeof pt};
    cs->geometry(in->master, proj.face, proj.xi, in->master->X, &pt);
    in->face[k] = proj.face;
    for (int I = 0; I < in->master->nen; ++I) in->N[k][I] = pt.N[I];
  }
  double qxi[16][2], qw[16];
  const int nq = cs->quadrature(in->slave->cell_type, 4, 16, qxi, qw);
  for (int f = 0; f < in->slave->n_cells && st == SK_OK; ++f)
    for (int g = 0; g < nq; ++g) {
      sk_surface_point pt = {.struct_size = sizeof pt};
      cs->geometry(in->slave, f, qxi[g], in->slave->X, &pt);
      for (int I = 0; I < in->slave->nen; ++I) in->w[in->slave->conn[f * in->slave->nen + I]] += pt.N[I] * pt.jacobian * qw[g];
    }
  if (st != SK_OK) {
    destroy(in);
    return st;
  }
  api->log(host, 2, "test-tied-dual: this rank sees %d of %lld slave nodes and %d of %lld master nodes", in->slave->n_nodes,
           (long long)in->slave->n_nodes_global, in->master->n_nodes, (long long)in->master->n_nodes_global);
  *out = in;
  return SK_OK;
}

static sk_status begin_step(sk_instance *in, const sk_state *st) {
  (void)in, (void)st;
  return SK_OK;
}

static int64_t z_of(const sk_instance *in, int k) { return in->slave->node_index[k] * in->dim; }

static sk_status layout(sk_instance *in, const sk_state *st, sk_layout *layout) {
  layout->n_extra = in->slave->n_nodes_global * in->dim;
  layout->recover_needs_jdx = 0;
  if (!in->dual) return SK_OK;
  int64_t n = 0;
  for (int k = 0; k < in->slave->n_nodes; ++k) {
    if (!in->slave->owned[k]) continue;
    for (int i = 0; i < in->dim; ++i) {
      in->extra_index[n] = z_of(in, k) + i;
      in->rows[n++] = in->slave->dofs[k * in->dim + i];
    }
  }
  (void)st;
  return in->condense->pair(in->host, n / in->dim, in->dim, in->extra_index, in->rows);
}

/* the element's unknowns: slave node, the master face's nodes, the node's multipliers */
static int element_rows(const sk_instance *in, const sk_state *st, int k, int64_t *rows) {
  const int dim = in->dim, nen = in->master->nen;
  int n = 0;
  for (int i = 0; i < dim; ++i) rows[n++] = in->slave->dofs[k * dim + i];
  for (int I = 0; I < nen; ++I)
    for (int i = 0; i < dim; ++i) rows[n++] = in->master->dofs[in->master->conn[in->face[k] * nen + I] * dim + i];
  for (int i = 0; i < dim; ++i) rows[n++] = st->extra_offset + z_of(in, k) + i;
  return n;
}

static sk_status pattern(sk_instance *in, const sk_state *st, sk_pattern *p) {
  int64_t rows[3 * (2 + MAX_NEN)];
  for (int k = 0; k < in->slave->n_nodes; ++k) {
    if (!in->slave->owned[k]) continue;
    const int n = element_rows(in, st, k, rows);
    p->add_block(p, n, rows, n, rows);
  }
  return SK_OK;
}

static sk_status residual(sk_instance *in, const sk_state *st, sk_sink *sink) {
  const int dim = in->dim, nen = in->master->nen;
  int64_t rows[3 * (2 + MAX_NEN)];
  double R[3 * (2 + MAX_NEN)];
  for (int k = 0; k < in->slave->n_nodes; ++k) {
    if (!in->slave->owned[k]) continue;
    const int n = element_rows(in, st, k, rows);
    const double *z = st->extra + z_of(in, k), w = in->w[k];
    for (int i = 0; i < dim; ++i) {
      double phi = st->x[0][k * dim + i];
      for (int I = 0; I < nen; ++I) phi -= in->N[k][I] * st->x[1][in->master->conn[in->face[k] * nen + I] * dim + i];
      R[i] = w * z[i];
      for (int I = 0; I < nen; ++I) R[dim * (1 + I) + i] = -w * in->N[k][I] * z[i];
      R[dim * (1 + nen) + i] = w * phi;
    }
    sink->add_vector(sink, n, rows, R);
  }
  return SK_OK;
}

static sk_status jacobian(sk_instance *in, const sk_state *st, sk_sink *sink) {
  const int dim = in->dim, nen = in->master->nen;
  int64_t rows[3 * (2 + MAX_NEN)];
  double J[(3 * (2 + MAX_NEN)) * (3 * (2 + MAX_NEN))];
  for (int k = 0; k < in->slave->n_nodes; ++k) {
    if (!in->slave->owned[k]) continue;
    const int n = element_rows(in, st, k, rows), zc = dim * (1 + nen);
    const double w = in->w[k];
    memset(J, 0, sizeof(double) * (size_t)(n * n));
    for (int i = 0; i < dim; ++i) {
      /* slave and master rows: d/dz; multiplier rows: d/dx */
      J[i * n + zc + i] = w;
      J[(zc + i) * n + i] = w;
      for (int I = 0; I < nen; ++I) {
        J[(dim * (1 + I) + i) * n + zc + i] = -w * in->N[k][I];
        J[(zc + i) * n + dim * (1 + I) + i] = -w * in->N[k][I];
      }
    }
    sink->add_matrix(sink, n, rows, n, rows, J);
  }
  return SK_OK;
}

/* solve_again with unit right-hand sides at the first and last owned slave dofs of rank 0 (the other ranks give zero
 * right-hand sides: they are summed): (J^-1)_ij = (J^-1)_ji for this operator, symmetric on the free dofs. */
static sk_status recover(sk_instance *in, const sk_state *st, sk_vectors *v) {
  (void)v, (void)st;
  if (!in->check_again) return SK_OK;
  const sk_view *s = in->slave;
  int rank, n_ranks, first = -1, last = -1;
  in->api->ranks(in->host, &rank, &n_ranks);
  for (int k = 0; k < s->n_nodes && rank == 0; ++k)
    if (s->owned[k]) {
      if (first < 0) first = k;
      last = k;
    }
  const int check = first >= 0 && last != first;
  const int i = check ? first * in->dim : 0, j = check ? last * in->dim + in->dim - 1 : 0;
  memset(in->b_view[0], 0, sizeof(double) * (size_t)(s->n_nodes * in->dim));
  if (check) in->b_view[0][i] = 1.0;
  SK_TRY(in->linear->solve_again(in->host, (const double *const *)in->b_view, in->b_extra, in->y_view, in->y_extra));
  if (check) {
    in->b_view[0][i] = 0.0;
    in->b_view[0][j] = 1.0;
  }
  SK_TRY(in->linear->solve_again(in->host, (const double *const *)in->b_view, in->b_extra, in->y2_view, in->y2_extra));
  if (!check) return SK_OK;
  const double a = in->y_view[0][j], b = in->y2_view[0][i];
  in->api->log(in->host, 2, "solve_again: (J^-1)_ij = %.17g, (J^-1)_ji = %.17g", a, b);
  if (!(fabs(a - b) <= 1e-10 * fabs(a)) || a == 0.0)
    return in->api->error(in->host, SK_ERR_INTERNAL, "solve_again: (J^-1)_ij = %.17g but (J^-1)_ji = %.17g", a, b);
  return SK_OK;
}

static sk_status commit_step(sk_instance *in, const sk_state *st) {
  (void)in, (void)st;
  return SK_OK;
}

static void reject_step(sk_instance *in) { (void)in; }

/* the force on the slave side: -w z per owned node */
static sk_status report(sk_instance *in, const sk_state *st, sk_contact_report *r) {
  for (int k = 0; k < in->slave->n_nodes; ++k) {
    if (!in->slave->owned[k]) continue;
    for (int i = 0; i < in->dim; ++i) r->force[i] -= in->w[k] * st->extra[z_of(in, k) + i];
    ++r->active;
  }
  return SK_OK;
}

static const sk_plugin plugin = {
    SK_TABLE_HEADER(sk_plugin),
    .name = "test-tied-dual",
    .summary = "test: a tied interface with dual multipliers, kept or condensed through stickslip.condense",
    .kinds = SK_KIND_PAIR,
    .caps = SK_CAP_2D | SK_CAP_3D | SK_CAP_QUASISTATIC | SK_CAP_DYNAMICS | SK_CAP_DEFORMABLE_MASTER |
            SK_CAP_MULTIPLIERS | SK_CAP_CONDENSATION,
    .strategies = strategies,
    .parameters = parameters,
    .create = create,
    .destroy = destroy,
    .begin_step = begin_step,
    .layout = layout,
    .pattern = pattern,
    .residual = residual,
    .jacobian = jacobian,
    .recover = recover,
    .commit_step = commit_step,
    .reject_step = reject_step,
    .report = report,
};

__attribute__((visibility("default"))) const sk_plugin *stickslip_plugin_entry(void);
__attribute__((visibility("default"))) const sk_plugin *stickslip_plugin_entry(void) { return &plugin; }
