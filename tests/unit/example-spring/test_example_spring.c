/* example-spring through its ABI: load the module, create an instance with a mock host, compare J with central
 * finite differences of F on every dof, and check that a rank adds nothing for nodes it does not own. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sk_test.h"
#include "stickslip/plugins.h"

enum { DIM = 3, N_NODES = 4, N_DOFS = DIM * N_NODES };

/* The mock's parameters: a pair's `parameters:` mapping in a real scene. */
typedef struct {
  double k, k3;
} mock_params;

static int owned_limit = N_NODES; /* the mock rank owns nodes < owned_limit */
static int mock_owns(const sk_host *h, int node) { (void)h; return node < owned_limit; }
static sk_status mock_double(const sk_host *h, const sk_params *params, const char *key, int required, double dflt,
                             double *out) {
  (void)h, (void)required, (void)dflt;
  const mock_params *p = (const mock_params *)params;
  if (strcmp(key, "k") == 0) *out = p->k;
  else if (strcmp(key, "k3") == 0) *out = p->k3;
  else *out = dflt;
  return SK_OK;
}
static sk_status mock_error(const sk_host *h, sk_status code, const char *fmt, ...) {
  (void)h;
  va_list a;
  va_start(a, fmt);
  vfprintf(stderr, fmt, a);
  va_end(a);
  fputc('\n', stderr);
  return code;
}

/* A dense sink over the N_DOFS unknowns. */
typedef struct {
  double F[N_DOFS], J[N_DOFS][N_DOFS];
} dense;
static void add_vector(sk_sink *s, int n, const int *rows, const double *v) {
  dense *d = s->ctx;
  for (int i = 0; i < n; ++i) d->F[rows[i]] += v[i];
}
static void add_matrix(sk_sink *s, int nr, const int *rows, int nc, const int *cols, const double *v) {
  dense *d = s->ctx;
  for (int i = 0; i < nr; ++i)
    for (int j = 0; j < nc; ++j) d->J[rows[i]][cols[j]] += v[i * nc + j];
}

static void residual(const sk_plugin *p, sk_instance *in, const double *q, double *F) {
  dense d;
  memset(&d, 0, sizeof d);
  sk_sink sink = {.ctx = &d, .add_vector = add_vector, .add_matrix = add_matrix, .add_rhs = NULL};
  sk_state st = {.scheme = SK_SCHEME_QUASISTATIC, .t = 1, .dt = 1, .q_n = q, .q = q};
  SK_CHECK(p->residual(in, &st, &sink) == SK_OK);
  memcpy(F, d.F, sizeof d.F);
}

int main(void) {
  const sk_plugin *p = NULL;
  sk_status status = sk_plugin_open_file(EXAMPLE_SPRING_PATH, &p);
  if (status != SK_OK) fprintf(stderr, "%s\n", sk_error_message());
  SK_CHECK(status == SK_OK && p != NULL);
  if (!p) return sk_test_finish("example-spring");

  /* The table. */
  SK_CHECK(p->abi_version == SK_PLUGIN_ABI_VERSION);
  SK_CHECK(strcmp(p->name, "example-spring") == 0);
  SK_CHECK(strcmp(p->strategies[0], "none") == 0 && p->strategies[1] == NULL);
  SK_CHECK(p->parameters[0] && p->parameters[1] && !p->parameters[2]);
  SK_CHECK(p->create && p->destroy && p->begin_step && p->layout && p->residual && p->jacobian && p->commit_step &&
           p->reject_step && p->report && p->points);
  SK_CHECK(p->recover == NULL);

  /* A mock host and a pair whose slave surface holds nodes 1 and 3. */
  double X[N_DOFS];
  for (int i = 0; i < N_DOFS; ++i) X[i] = 0.1 * i;
  sk_host host = {.abi_version = SK_PLUGIN_ABI_VERSION, .dim = DIM, .n_nodes = N_NODES, .n_dofs = N_DOFS, .X = X,
                  .n_ranks = 1, .owns_node = mock_owns, .param_double = mock_double, .error = mock_error};
  int slave_nodes[2] = {1, 3};
  sk_surface slave;
  memset(&slave, 0, sizeof slave);
  slave.dim = DIM;
  slave.n_nodes = 2;
  slave.nodes = slave_nodes;
  mock_params params = {.k = 5.0, .k3 = 40.0};
  sk_pair pair = {.name = "test", .slave = &slave, .params = (const sk_params *)&params};

  /* Bad parameters are refused. */
  sk_instance *in = NULL;
  mock_params bad = {.k = -1.0};
  pair.params = (const sk_params *)&bad;
  SK_CHECK(p->create(&host, &pair, &in) == SK_ERR_INPUT && in == NULL);
  pair.params = (const sk_params *)&params;
  SK_CHECK(p->create(&host, &pair, &in) == SK_OK && in != NULL);
  if (!in) return sk_test_finish("example-spring");

  double q[N_DOFS];
  for (int i = 0; i < N_DOFS; ++i) q[i] = X[i] + 0.05 * ((i * 7) % 5 - 2);
  sk_state st = {.scheme = SK_SCHEME_QUASISTATIC, .t = 1, .dt = 1, .q_n = X, .q = q};
  sk_layout layout;
  SK_CHECK(p->begin_step(in, &st) == SK_OK);
  SK_CHECK(p->layout(in, &st, &layout) == SK_OK && layout.n_extra == 0);

  /* Jacobian against central differences of the residual, column by column. */
  dense d;
  memset(&d, 0, sizeof d);
  sk_sink sink = {.ctx = &d, .add_vector = add_vector, .add_matrix = add_matrix, .add_rhs = NULL};
  SK_CHECK(p->jacobian(in, &st, &sink) == SK_OK);
  const double h = 1e-6;
  double Fp[N_DOFS], Fm[N_DOFS], worst = 0.0;
  for (int j = 0; j < N_DOFS; ++j) {
    double qj = q[j];
    q[j] = qj + h;
    residual(p, in, q, Fp);
    q[j] = qj - h;
    residual(p, in, q, Fm);
    q[j] = qj;
    for (int i = 0; i < N_DOFS; ++i) {
      double fd = (Fp[i] - Fm[i]) / (2.0 * h);
      double err = fabs(fd - d.J[i][j]);
      if (err > worst) worst = err;
    }
  }
  printf("max |J - J_fd| = %.3e\n", worst);
  SK_CHECK(worst < 1e-6);
  SK_CHECK(d.J[3][3] > params.k); /* node 1's block is there (and stiffer than k: hardening) */
  SK_CHECK(d.J[0][0] == 0.0);     /* node 0 is not a slave node */

  /* Sign: a slave node pulled by +d gets F = +(k + k3|d|^2) d, i.e. a restoring force -F. */
  double F[N_DOFS];
  residual(p, in, q, F);
  double dx = q[3] - X[3];
  SK_CHECK(F[3] * dx > 0.0);

  /* Report: the resultant force on the slave side is -sum F. */
  sk_contact_report r;
  SK_CHECK(p->report(in, &st, &r) == SK_OK);
  SK_CHECK_CLOSE(r.force[0], -(F[3] + F[9]), 1e-14);

  /* MPI rule: a rank that owns only nodes 0..2 adds node 1 but not node 3. */
  owned_limit = 3;
  residual(p, in, q, F);
  SK_CHECK(F[3] != 0.0 && F[9] == 0.0 && F[10] == 0.0 && F[11] == 0.0);
  owned_limit = N_NODES;

  SK_CHECK(p->commit_step(in, &st) == SK_OK);
  p->destroy(in);
  return sk_test_finish("example-spring");
}
