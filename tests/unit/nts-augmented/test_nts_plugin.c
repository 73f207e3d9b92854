/* nts-augmented plugin through its ABI, with a mock host whose contact services are the core's functions.
 * Scene: the two hex8 blocks of Table I (the upper one shifted by +0.3 in y so that no slave node sits on the
 * master's border), the lower block fixed, every upper node on a spring to an anchor pushed through the master face.
 * A dense "driver" runs Newton per step for each strategy: `none` and `reduced` must give the same iterates,
 * `direct` the same solution; the converged step must be in equilibrium with the reported contact force, satisfy
 * the constraints, and the assembled contact forces must carry no net force or moment. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

#include "stickslip/contact.h"
#include "stickslip/fe.h"
#include "stickslip/plugin.h"
#include "nts_test_support.h"
#include "sk_test.h"

const sk_plugin *stickslip_plugin_entry(void);

enum { N_NODES = 16, N_DOFS = 48, N_SLAVE = 4, N_TOTAL = N_DOFS + 5 * N_SLAVE };
static const double SPRING = 10.0;

struct sk_params {
  int n;
  const char *keys[8];
  double values[8];
};

static double X[N_DOFS];
static char last_error[512];

static sk_status mock_error(const sk_host *host, sk_status code, const char *fmt, ...) {
  (void)host;
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(last_error, sizeof last_error, fmt, ap);
  va_end(ap);
  return code;
}

static void mock_log(const sk_host *host, int level, const char *fmt, ...) {
  (void)host;
  (void)level;
  (void)fmt;
}

static sk_status mock_param_double(const sk_host *host, const sk_params *params, const char *key, int required,
                                   double dflt, double *out) {
  for (int i = 0; i < params->n; ++i)
    if (strcmp(params->keys[i], key) == 0) {
      *out = params->values[i];
      return SK_OK;
    }
  if (required) return mock_error(host, SK_ERR_INPUT, "missing required parameter %s", key);
  *out = dflt;
  return SK_OK;
}

static sk_status mock_param_int(const sk_host *host, const sk_params *params, const char *key, int required, int dflt,
                                int *out) {
  double v = dflt;
  sk_status st = mock_param_double(host, params, key, required, dflt, &v);
  *out = (int)v;
  return st;
}

static int mock_owns(const sk_host *host, int node) {
  (void)host;
  (void)node;
  return 1;
}

/* ---- dense sink ---------------------------------------------------------------------------------------------- */
typedef struct {
  double F[N_TOTAL], rhs[N_TOTAL], J[N_TOTAL * N_TOTAL];
} dense_system;

static void sink_vector(sk_sink *sink, int n, const int *rows, const double *values) {
  dense_system *s = sink->ctx;
  for (int i = 0; i < n; ++i) s->F[rows[i]] += values[i];
}
static void sink_matrix(sk_sink *sink, int nr, const int *rows, int nc, const int *cols, const double *values) {
  dense_system *s = sink->ctx;
  for (int i = 0; i < nr; ++i)
    for (int j = 0; j < nc; ++j) s->J[rows[i] * N_TOTAL + cols[j]] += values[i * nc + j];
}
static void sink_rhs(sk_sink *sink, int n, const int *rows, const double *values) {
  dense_system *s = sink->ctx;
  for (int i = 0; i < n; ++i) s->rhs[rows[i]] += values[i];
}

/* ---- scene ----------------------------------------------------------------------------------------------------- */
static sk_surface master, slave;
static int master_conn[4] = {4, 5, 6, 7}, master_nodes[4] = {4, 5, 6, 7}, master_nb[4] = {-1, -1, -1, -1};
static int slave_conn[4] = {8, 11, 10, 9}, slave_nodes[4] = {8, 9, 10, 11}, slave_nb[4] = {-1, -1, -1, -1};

static void build_scene(void) {
  static const double lower[8][3] = {{-1, -1, 0}, {1, -1, 0}, {1.2, 1, 0}, {-1.5, 1.5, 0},
                                     {-1, -1, 1}, {1, -1, 1}, {1.2, 1, 1}, {-1.5, 1.5, 1}};
  static const double upper[8][3] = {{-0.5, -1, 1.1}, {0.5, -1, 1.1}, {0.5, 0, 1.1}, {-0.5, 0, 1.1},
                                     {-0.5, -1, 2.1}, {0.5, -1, 2.1}, {0.5, 0, 2.1}, {-0.5, 0, 2.1}};
  for (int I = 0; I < 8; ++I)
    for (int i = 0; i < 3; ++i) {
      X[3 * I + i] = lower[I][i];
      X[3 * (8 + I) + i] = upper[I][i] + (i == 1 ? 0.3 : 0.0);
    }
  memset(&master, 0, sizeof master);
  snprintf(master.name, sizeof master.name, "master");
  master.dim = 3;
  master.face_type = SK_QUAD4;
  master.nen = 4;
  master.n_faces = 1;
  master.conn = master_conn;
  master.n_nodes = 4;
  master.nodes = master_nodes;
  master.face_neighbors = master_nb;
  master.n_edges = 4;
  master.body = 0;
  slave = master;
  snprintf(slave.name, sizeof slave.name, "slave");
  slave.conn = slave_conn;
  slave.nodes = slave_nodes;
  slave.face_neighbors = slave_nb;
  slave.body = 1;
}


static sk_host make_host(void) {
  sk_host h;
  memset(&h, 0, sizeof h);
  h.abi_version = SK_PLUGIN_ABI_VERSION;
  h.dim = 3;
  h.n_nodes = N_NODES;
  h.n_dofs = N_DOFS;
  h.X = X;
  h.n_ranks = 1;
  h.contact = sk_core_contact_services();
  h.owns_node = mock_owns;
  h.param_double = mock_param_double;
  h.param_int = mock_param_int;
  h.error = mock_error;
  h.log = mock_log;
  return h;
}

/* ---- a dense Newton "driver" ---------------------------------------------------------------------------------- */
typedef struct {
  int strategy;
  sk_scheme scheme;
  double mu;
  double x[N_TOTAL];        /* [q | extra] */
  double q_n[N_DOFS];
  sk_instance *inst;
  sk_host host;
  sk_pair pair;
  struct sk_params params;
  double history[64][N_TOTAL];
  int n_history;
  sk_contact_report report;
} run;

static void anchors(int step, double *a) {
  static const double shift[3][3] = {{0.01, 0.0, -0.2}, {0.2, 0.06, -0.2}, {0.21, 0.07, -0.2}};
  for (int i = 0; i < N_DOFS; ++i) a[i] = X[i] + (i >= 24 ? shift[step][i % 3] : 0.0);
}

static void assemble(run *r, const sk_state *state, const double *anchor, dense_system *s, double contact_sum[6]) {
  memset(s, 0, sizeof *s);
  sk_sink sink = {s, sink_vector, sink_matrix, sink_rhs};
  SK_CHECK(r->pair.strategy >= 0);
  SK_CHECK(stickslip_plugin_entry()->residual(r->inst, state, &sink) == SK_OK);
  /* the contact forces alone: no net force or moment */
  if (contact_sum) {
    memset(contact_sum, 0, sizeof(double) * 6);
    /* moments about the origin with the positions where the forces act (midpoint: q_{n+1/2}) */
    const double w = state->scheme == SK_SCHEME_MIDPOINT ? 0.5 : 1.0;
    for (int I = 0; I < N_NODES; ++I) {
      const double *f = s->F + 3 * I;
      double x[3];
      for (int i = 0; i < 3; ++i) x[i] = w * state->q[3 * I + i] + (1.0 - w) * state->q_n[3 * I + i];
      for (int i = 0; i < 3; ++i) contact_sum[i] += f[i];
      contact_sum[3] += x[1] * f[2] - x[2] * f[1];
      contact_sum[4] += x[2] * f[0] - x[0] * f[2];
      contact_sum[5] += x[0] * f[1] - x[1] * f[0];
    }
  }
  SK_CHECK(stickslip_plugin_entry()->jacobian(r->inst, state, &sink) == SK_OK);
  for (int i = 0; i < N_DOFS; ++i) {
    if (i < 24) { /* the lower block is fixed */
      for (int j = 0; j < N_TOTAL; ++j) s->J[i * N_TOTAL + j] = 0.0;
      s->J[i * N_TOTAL + i] = 1.0;
      s->F[i] = 0.0;
      s->rhs[i] = 0.0;
      continue;
    }
    s->F[i] += SPRING * (state->q[i] - anchor[i]);
    s->J[i * N_TOTAL + i] += SPRING;
  }
}

static int newton_step(run *r, int step, double *residual_norm, double *momentum_error) {
  const sk_plugin *pl = stickslip_plugin_entry();
  double anchor[N_DOFS];
  anchors(step, anchor);
  sk_state state = {r->scheme, 0.0, 1.0, 1.0, step, r->q_n, r->x, NULL, r->x + N_DOFS, N_DOFS};
  *momentum_error = 0.0;
  for (int it = 0; it < 40; ++it) {
    static dense_system s;
    double sums[6];
    assemble(r, &state, anchor, &s, sums);
    *momentum_error = fmax(*momentum_error, max_abs(sums, 6));
    *residual_norm = max_abs(s.F, N_TOTAL);
    if (*residual_norm < 1e-11) return it;
    double dx[N_TOTAL];
    const unsigned char *elim = NULL;
    sk_layout lay;
    pl->layout(r->inst, &state, &lay);
    elim = lay.eliminated;
    for (int i = 0; i < N_TOTAL; ++i) {
      const int e = i >= N_DOFS && elim && elim[i - N_DOFS];
      dx[i] = e ? 0.0 : -s.F[i] + s.rhs[i];
      if (e) { /* eliminated unknowns: the plugin never touched their rows and columns */
        for (int j = 0; j < N_TOTAL; ++j) SK_CHECK(s.J[i * N_TOTAL + j] == 0.0 && s.J[j * N_TOTAL + i] == 0.0);
        s.J[i * N_TOTAL + i] = 1.0;
      }
    }
    if (nts_solve_dense(N_TOTAL, s.J, dx, 1) != 0) {
      SK_CHECK(!"singular global system");
      return -1;
    }
    if (elim) SK_CHECK(pl->recover(r->inst, &state, s.F, dx) == SK_OK);
    for (int i = 0; i < N_TOTAL; ++i) r->x[i] += dx[i];
    if (r->n_history < 64) memcpy(r->history[r->n_history++], r->x, sizeof r->x);
    int changed = 0;
    SK_CHECK(pl->after_iteration(r->inst, &state, &changed) == SK_OK);
  }
  return -1;
}

static void run_init(run *r, int strategy, sk_scheme scheme, double mu) {
  memset(r, 0, sizeof *r);
  r->strategy = strategy;
  r->scheme = scheme;
  r->mu = mu;
  r->host = make_host();
  r->params.n = 2;
  r->params.keys[0] = "mu";
  r->params.values[0] = mu;
  r->params.keys[1] = "epsilon_t";
  r->params.values[1] = 100.0;
  r->pair.name = "pair 0";
  r->pair.slave = &slave;
  r->pair.master = &master;
  r->pair.params = &r->params;
  r->pair.strategy = strategy;
  memcpy(r->x, X, sizeof X);
  memcpy(r->q_n, X, sizeof X);
  SK_CHECK(stickslip_plugin_entry()->create(&r->host, &r->pair, &r->inst) == SK_OK);
}

/* One step: begin, layout, Newton, report, commit. Returns the Newton iterations. */
static int run_step(run *r, int step) {
  const sk_plugin *pl = stickslip_plugin_entry();
  sk_state state = {r->scheme, 0.0, 1.0, 1.0, step, r->q_n, r->x, NULL, NULL, N_DOFS};
  SK_CHECK(pl->begin_step(r->inst, &state) == SK_OK);
  sk_layout lay;
  SK_CHECK(pl->layout(r->inst, &state, &lay) == SK_OK);
  SK_CHECK(lay.n_extra == 5 * N_SLAVE);
  SK_CHECK((lay.eliminated == NULL) == (r->strategy == 1));
  memcpy(r->x + N_DOFS, lay.initial, sizeof(double) * 5 * N_SLAVE);
  r->n_history = 0;
  double norm, momentum;
  const int its = newton_step(r, step, &norm, &momentum);
  SK_CHECK(its > 0);
  if (!(momentum < 1e-12)) fprintf(stderr, "net contact force/moment %.3e (strategy %d, step %d)\n", momentum,
                                   r->strategy, step);
  SK_CHECK(momentum < 1e-12);
  state.extra = r->x + N_DOFS;
  SK_CHECK(pl->report(r->inst, &state, &r->report) == SK_OK);
  SK_CHECK(pl->commit_step(r->inst, &state) == SK_OK);
  memcpy(r->q_n, r->x, sizeof r->q_n);
  return its;
}

typedef struct {
  int count, active, stick, slip;
  double min_pressure, mu;
  int midpoint;
} point_summary;

static void point_cb(void *ctx, const sk_contact_point *p) {
  point_summary *s = ctx;
  ++s->count;
  if (p->state) {
    ++s->active;
    s->min_pressure = fmin(s->min_pressure, p->pressure);
    SK_CHECK(fabs(p->gap) < 1e-10);
    SK_CHECK_CLOSE(p->normal[2], 1.0, 1e-12);
  }
  if (p->state == 1) ++s->stick;
  if (p->state == 2) {
    /* Coulomb: |tangential force| = mu * normal force when slipping (backward Euler / quasi-static); the
     * midpoint force is the mean of t_n and t_{n+1}, inside the cone */
    ++s->slip;
    const double t = sqrt(p->traction[0] * p->traction[0] + p->traction[1] * p->traction[1] +
                          p->traction[2] * p->traction[2]);
    if (s->midpoint)
      SK_CHECK(t <= s->mu * p->pressure * (1.0 + 1e-12) && t > 0.9 * s->mu * p->pressure);
    else
      SK_CHECK_CLOSE(t, s->mu * p->pressure, 1e-12);
  }
}

int main(void) {
  build_scene();
  const sk_plugin *pl = stickslip_plugin_entry();
  SK_CHECK(pl->abi_version == SK_PLUGIN_ABI_VERSION);
  SK_CHECK(strcmp(pl->strategies[0], "reduced") == 0 && strcmp(pl->strategies[1], "none") == 0 &&
           strcmp(pl->strategies[2], "direct") == 0 && pl->strategies[3] == NULL);

  /* epsilon_t is required with friction */
  {
    sk_host h = make_host();
    struct sk_params params = {1, {"mu"}, {0.3}};
    sk_pair pair = {"pair 0", &slave, &master, NULL, &params, 0};
    sk_instance *inst = NULL;
    SK_CHECK(pl->create(&h, &pair, &inst) == SK_ERR_INPUT && inst == NULL);
    SK_CHECK(strstr(last_error, "epsilon_t") != NULL);
  }

  static run none, reduced, direct;
  run_init(&none, 1, SK_SCHEME_QUASISTATIC, 0.5);
  run_init(&reduced, 0, SK_SCHEME_QUASISTATIC, 0.5);
  run_init(&direct, 2, SK_SCHEME_QUASISTATIC, 0.5);
  for (int step = 0; step < 3; ++step) {
    const sk_scheme scheme = step == 2 ? SK_SCHEME_MIDPOINT : SK_SCHEME_QUASISTATIC;
    none.scheme = reduced.scheme = direct.scheme = scheme;
    const int it_none = run_step(&none, step), it_red = run_step(&reduced, step), it_dir = run_step(&direct, step);
    /* none and reduced: the same iterates */
    double diff = 0.0;
    SK_CHECK(none.n_history == reduced.n_history);
    for (int k = 0; k < none.n_history && k < reduced.n_history; ++k)
      for (int i = 0; i < N_TOTAL; ++i)
        diff = fmax(diff, fabs(none.history[k][i] - reduced.history[k][i]));
    double diff_direct = 0.0;
    for (int i = 0; i < N_DOFS + 1; ++i) diff_direct = fmax(diff_direct, fabs(none.x[i] - direct.x[i]));
    for (int k = 0; k < N_SLAVE; ++k) diff_direct = fmax(diff_direct, fabs(none.x[N_DOFS + 5 * k] - direct.x[N_DOFS + 5 * k]));
    printf("step %d (%s): iterations none %d, reduced %d, direct %d; |iterates none - reduced| = %.1e, "
           "|solution none - direct| = %.1e\n",
           step, scheme == SK_SCHEME_MIDPOINT ? "midpoint" : "quasi-static", it_none, it_red, it_dir, diff,
           diff_direct);
    printf("  report: force (%.6f, %.6f, %.6f), active %d, stick %d, slip %d, dissipated %.3e, max|Phi| %.1e\n",
           none.report.force[0], none.report.force[1], none.report.force[2], none.report.active, none.report.stick,
           none.report.slip, none.report.dissipated, none.report.constraint_norm);
    SK_CHECK(diff < 1e-10);
    SK_CHECK(diff_direct < 1e-9);
    SK_CHECK(none.report.active == N_SLAVE && reduced.report.active == N_SLAVE && direct.report.active == N_SLAVE);
    SK_CHECK(none.report.constraint_norm < 1e-10);
    /* equilibrium: the contact force on the slave balances the springs of the upper block */
    double anchor[N_DOFS], spring[3] = {0, 0, 0};
    anchors(step, anchor);
    for (int i = 24; i < N_DOFS; ++i) spring[i % 3] += SPRING * (none.x[i] - anchor[i]);
    for (int i = 0; i < 3; ++i) SK_CHECK_CLOSE(none.report.force[i], spring[i], 1e-9);
    /* step 0 sticks (tiny shift), step 1 slips (shift beyond mu |lambda_n|) */
    if (step == 0) SK_CHECK(none.report.stick == N_SLAVE);
    if (step == 1) {
      SK_CHECK(none.report.slip == N_SLAVE);
      SK_CHECK(none.report.dissipated > 0.0);
    }
    point_summary ps = {0, 0, 0, 0, 1e300, 0.5, scheme == SK_SCHEME_MIDPOINT};
    SK_CHECK(pl->points(none.inst, &(sk_state){scheme, 0, 1, 1, step, none.q_n, none.x, NULL, none.x + N_DOFS, N_DOFS},
                        point_cb, &ps) == SK_OK);
    SK_CHECK(ps.count == N_SLAVE && ps.active == N_SLAVE && ps.min_pressure > 0.0);
    SK_CHECK(ps.slip == none.report.slip && ps.stick == none.report.stick);
  }
  pl->destroy(none.inst);
  pl->destroy(reduced.inst);
  pl->destroy(direct.inst);
  return sk_test_finish("test_nts_plugin");
}
