/* nts-augmented plugin through its ABI, with the plugin test kit (a mock host whose contact services are the core's).
 * Scene: the two hex8 blocks of Table I (the upper one shifted by +0.3 in y so that no slave node sits on the
 * master's border), the lower block fixed, every upper node on a spring to an anchor pushed through the master face.
 * A dense "driver" runs Newton per step for each strategy: `none` and `reduced` must give the same iterates,
 * `direct` the same solution; the converged step must be in equilibrium with the reported contact force, satisfy
 * the constraints, and the assembled contact forces must carry no net force or moment. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

#include "nts_test_support.h"
#include "plugin_kit.h"
#include "sk_test.h"

const sk_plugin *stickslip_plugin_entry(void);

enum { N_NODES = 16, N_DOFS = 48, N_SLAVE = 4, N_TOTAL = N_DOFS + 5 * N_SLAVE };
enum { CONDENSED, AUGMENTED, PAPER, DIRECT, DIRECT_ENDPOINT, N_STRATEGIES };
static const char *const NAME[N_STRATEGIES] = {"condensed", "augmented", "paper-reduced", "direct", "direct-endpoint"};
static const double SPRING = 10.0;

static double X[N_DOFS];

/* the two faces of the pair (mesh node ids) */
static const int master_conn[4] = {4, 5, 6, 7}, slave_conn[4] = {8, 11, 10, 9};

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
}

/* A pair on the kit with the test's parameters. */
static void make_pair(kit *k, double mu, int with_epsilon_t) {
  kit_init(k, 3, N_NODES, X);
  kit_surface(k, 0, SK_QUAD4, 4, 1, slave_conn);
  kit_surface(k, 1, SK_QUAD4, 4, 1, master_conn);
  kit_param(k, "mu", mu);
  if (with_epsilon_t) kit_param(k, "epsilon_t", 100.0);
}

/* ---- a dense Newton "driver" ---------------------------------------------------------------------------------- */
typedef struct {
  int strategy;
  double alpha;             /* 1: quasi-static, 1/2: midpoint */
  double mu;
  double q[N_DOFS];         /* positions; the extras are the kit's */
  double q_n[N_DOFS];
  kit k;
  double history[64][N_TOTAL];
  int n_history;
  int loops;                /* outer loops (rejected converged points) of the last step */
  int largest_system;       /* kept unknowns of the largest linear system of the last step */
  sk_contact_report report;
} run;

static void anchors(int step, double *a) {
  static const double shift[3][3] = {{0.01, 0.0, -0.2}, {0.2, 0.06, -0.2}, {0.21, 0.07, -0.2}};
  for (int i = 0; i < N_DOFS; ++i) a[i] = X[i] + (i >= 24 ? shift[step][i % 3] : 0.0);
}

typedef struct {
  double F[N_TOTAL], rhs[N_TOTAL], J[N_TOTAL * N_TOTAL];
} dense_system;

static void assemble(run *r, const double *anchor, dense_system *s, double contact_sum[6]) {
  SK_CHECK(kit_residual(&r->k, r->q, s->F) == SK_OK);
  /* the contact forces alone: no net force or moment */
  if (contact_sum) {
    memset(contact_sum, 0, sizeof(double) * 6);
    /* moments about the origin with the positions where the forces act (midpoint: q_{n+1/2}) */
    const double w = r->alpha;
    for (int I = 0; I < N_NODES; ++I) {
      const double *f = s->F + 3 * I;
      double x[3];
      for (int i = 0; i < 3; ++i) x[i] = w * r->q[3 * I + i] + (1.0 - w) * r->q_n[3 * I + i];
      for (int i = 0; i < 3; ++i) contact_sum[i] += f[i];
      contact_sum[3] += x[1] * f[2] - x[2] * f[1];
      contact_sum[4] += x[2] * f[0] - x[0] * f[2];
      contact_sum[5] += x[0] * f[1] - x[1] * f[0];
    }
  }
  SK_CHECK(kit_jacobian(&r->k, r->q, s->J, s->rhs) == SK_OK);
  for (int i = 0; i < N_DOFS; ++i) {
    if (i < 24) { /* the lower block is fixed */
      for (int j = 0; j < N_TOTAL; ++j) s->J[i * N_TOTAL + j] = 0.0;
      s->J[i * N_TOTAL + i] = 1.0;
      s->F[i] = 0.0;
      s->rhs[i] = 0.0;
      continue;
    }
    s->F[i] += SPRING * (r->q[i] - anchor[i]);
    s->J[i * N_TOTAL + i] += SPRING;
  }
}

static int newton_step(run *r, int step, double *residual_norm, double *momentum_error) {
  double anchor[N_DOFS];
  anchors(step, anchor);
  *momentum_error = 0.0;
  r->loops = 0;
  r->largest_system = 0;
  int iterations = 0;
  for (int it = 0; it < 60; ++it) {
    static dense_system s;
    double sums[6];
    assemble(r, anchor, &s, sums);
    *momentum_error = fmax(*momentum_error, max_abs(sums, 6));
    *residual_norm = max_abs(s.F, N_TOTAL);
    if (*residual_norm < 1e-11) {
      /* the host's outer loop: the plugin may reject the converged point and lay out its unknowns again */
      int accept = 1;
      SK_CHECK(kit_converged(&r->k, r->q, &accept) == SK_OK);
      if (accept) return iterations;
      ++r->loops;
      SK_CHECK(kit_layout_again(&r->k) == SK_OK);
      continue;
    }
    const unsigned char *elim = r->k.layout.eliminated;
    double dx[N_TOTAL];
    int kept = 0;
    for (int i = 0; i < N_TOTAL; ++i) {
      const int e = i >= N_DOFS && elim && elim[i - N_DOFS];
      kept += !e;
      dx[i] = e ? 0.0 : -s.F[i] + s.rhs[i];
      if (e) { /* eliminated unknowns: the plugin never touched their rows and columns */
        for (int j = 0; j < N_TOTAL; ++j) SK_CHECK(s.J[i * N_TOTAL + j] == 0.0 && s.J[j * N_TOTAL + i] == 0.0);
        s.J[i * N_TOTAL + i] = 1.0;
      }
    }
    if (kept > r->largest_system) r->largest_system = kept;
    if (nts_solve_dense(N_TOTAL, s.J, dx, 1) != 0) {
      SK_CHECK(!"singular global system");
      return -1;
    }
    if (elim) SK_CHECK(kit_recover(&r->k, r->q, s.F, dx) == SK_OK);
    for (int i = 0; i < N_DOFS; ++i) r->q[i] += dx[i];
    for (int i = N_DOFS; i < N_TOTAL; ++i) r->k.extra[i - N_DOFS] += dx[i];
    ++iterations;
    if (r->n_history < 64) {
      memcpy(r->history[r->n_history], r->q, sizeof r->q);
      memcpy(r->history[r->n_history] + N_DOFS, r->k.extra, sizeof(double) * 5 * N_SLAVE);
      r->n_history++;
    }
    int changed = 0;
    SK_CHECK(kit_update_active_set(&r->k, r->q, &changed) == SK_OK);
  }
  return -1;
}

static void run_init(run *r, int strategy, double mu) {
  memset(r, 0, sizeof *r);
  r->strategy = strategy;
  r->alpha = 1.0;
  r->mu = mu;
  memcpy(r->q, X, sizeof X);
  memcpy(r->q_n, X, sizeof X);
  make_pair(&r->k, mu, 1);
  SK_CHECK(kit_create(&r->k, stickslip_plugin_entry(), strategy) == SK_OK);
}

/* One step: begin, layout, Newton, report, commit. Returns the Newton iterations. */
static int run_step(run *r, int step) {
  kit_integrator(&r->k, r->alpha, r->alpha != 1.0);
  kit_state(&r->k, r->q_n, r->q, 0.0, 1.0, NULL);
  r->k.state.step = step;
  SK_CHECK(kit_begin(&r->k) == SK_OK);
  SK_CHECK(r->k.layout.n_extra == 5 * N_SLAVE && r->k.layout.eliminated != NULL);
  r->n_history = 0;
  double norm, momentum;
  const int its = newton_step(r, step, &norm, &momentum);
  SK_CHECK(its > 0);
  if (!(momentum < 1e-12)) fprintf(stderr, "net contact force/moment %.3e (strategy %d, step %d)\n", momentum,
                                   r->strategy, step);
  SK_CHECK(momentum < 1e-12);
  SK_CHECK(kit_report(&r->k, &r->report) == SK_OK);
  SK_CHECK(kit_commit(&r->k) == SK_OK);
  memcpy(r->q_n, r->q, sizeof r->q_n);
  return its;
}

typedef struct {
  int count, active, stick, slip;
  double min_pressure, mu;
  double force[3]; /* sum of the points' pressure x normal + traction (nodal forces here: forces = 1) */
} point_summary;

static void point_cb(void *ctx, const sk_contact_point *p) {
  point_summary *s = ctx;
  ++s->count;
  if (p->state) {
    ++s->active;
    for (int i = 0; i < 3; ++i) s->force[i] += p->pressure * p->normal[i] + p->traction[i];
    s->min_pressure = fmin(s->min_pressure, p->pressure);
    SK_CHECK(fabs(p->gap) < 1e-10);
    SK_CHECK_CLOSE(p->normal[2], 1.0, 1e-12);
  }
  if (p->state == 1) ++s->stick;
  if (p->state == 2) {
    /* Coulomb: |tangential force| = mu * normal force when slipping, under every scheme: the points report the
     * traction at t_{n+1} (under the midpoint scheme the step's force carries the mean of t_n and t_{n+1}) */
    ++s->slip;
    const double t = sqrt(p->traction[0] * p->traction[0] + p->traction[1] * p->traction[1] +
                          p->traction[2] * p->traction[2]);
    SK_CHECK_CLOSE(t, s->mu * p->pressure, 1e-12);
  }
}

static double solution_difference(const run *a, const run *b) {
  double d = 0.0;
  for (int i = 0; i < N_DOFS; ++i) d = fmax(d, fabs(a->q[i] - b->q[i]));
  for (int k = 0; k < N_SLAVE; ++k) d = fmax(d, fabs(a->k.extra[5 * k] - b->k.extra[5 * k]) / 10.0);
  return d;
}

static double iterate_difference(const run *a, const run *b) {
  if (a->n_history != b->n_history) return HUGE_VAL;
  double d = 0.0;
  for (int k = 0; k < a->n_history; ++k)
    for (int i = 0; i < N_TOTAL; ++i) d = fmax(d, fabs(a->history[k][i] - b->history[k][i]));
  return d;
}

/* converged() on frozen nodes (max_flips 0: every node's contact state is frozen from begin_step): a node found
 * penetrating is put in contact, one in tension released; a node that needs a third correction in one attempt has
 * no consistent state at this dt, and the step is cut (SK_ERR_DIVERGED naming the node) instead of the outer loop
 * cycling to its limit. A new attempt starts afresh. */
static void frozen_node_cycle(const sk_plugin *pl) {
  kit k;
  make_pair(&k, 0.0, 0);
  kit_param(&k, "max_flips", 0.0);
  SK_CHECK(kit_create(&k, pl, CONDENSED) == SK_OK);
  double apart[N_DOFS], pressed[N_DOFS];
  memcpy(apart, X, sizeof X);
  memcpy(pressed, X, sizeof X);
  for (int I = 8; I < N_NODES; ++I) pressed[3 * I + 2] -= 0.2; /* slave face 0.1 below the master face */
  for (int attempt = 0; attempt < 2; ++attempt) {
    kit_state(&k, apart, apart, 0.0, 1.0, NULL);
    SK_CHECK(kit_begin(&k) == SK_OK);
    int accept = 0;
    SK_CHECK(kit_converged(&k, apart, &accept) == SK_OK && accept); /* apart, released: consistent */
    SK_CHECK(kit_converged(&k, pressed, &accept) == SK_OK && !accept); /* penetrates: in contact */
    SK_CHECK(kit_layout_again(&k) == SK_OK);
    for (int n = 0; n < N_SLAVE; ++n) k.extra[5 * n] = 1.0; /* pulls */
    SK_CHECK(kit_converged(&k, apart, &accept) == SK_OK && !accept); /* in tension: released */
    SK_CHECK(kit_layout_again(&k) == SK_OK);
    if (attempt == 0) {
      /* penetrates again: neither state is consistent */
      SK_CHECK(kit_converged(&k, pressed, &accept) == SK_ERR_DIVERGED);
      const char *message = sk_error_message();
      SK_CHECK(strstr(message, "no consistent contact state") && strstr(message, "lambda_n 1") &&
               strstr(message, "gap -0.1"));
      printf("frozen node cycle: %s\n", message);
      if (pl->reject_step) pl->reject_step(k.instance); /* the host cuts the step; the next attempt begins */
    }
  }
  kit_free(&k);
}

int main(void) {
  build_scene();
  const sk_plugin *pl = stickslip_plugin_entry();
  SK_CHECK(pl->abi_major == SK_ABI_MAJOR);
  for (int i = 0; i < N_STRATEGIES; ++i) SK_CHECK(strcmp(pl->strategies[i], NAME[i]) == 0);

  /* epsilon_t and c_n computed from the scene when it gives none (docs/plugins/nts-augmented.md#defaults): nodal
   * stiffnesses 10 E* / h A and E* / h A; a given value wins */
  {
    kit k;
    make_pair(&k, 0.3, 0);
    kit_material(&k, 0, 2000.0, 0.25);
    kit_material(&k, 1, 3000.0, 0.0);
    SK_CHECK(kit_create(&k, pl, 0) == SK_OK);
    const sk_scene_side *slave = k.scene.slave;
    const double modulus = 1.0 / ((1.0 - 0.0625) / 2000.0 + 1.0 / 3000.0);
    const double nodal = modulus / slave->h_mean * slave->measure / (double)slave->n_nodes;
    SK_CHECK(slave->h_mean > 0.0 && slave->measure > 0.0);
    SK_CHECK_CLOSE(kit_computed(&k, "epsilon_t"), 10.0 * nodal, 1e-12);
    SK_CHECK_CLOSE(kit_computed(&k, "c_n"), nodal, 1e-12);
    kit_free(&k);
    make_pair(&k, 0.3, 0);
    kit_param(&k, "epsilon_t", 5.0);
    SK_CHECK(kit_create(&k, pl, 0) == SK_OK);
    SK_CHECK(isnan(kit_computed(&k, "epsilon_t")) && kit_computed(&k, "c_n") > 0.0);
    kit_free(&k);
  }
  /* the deprecated names are the same strategies: `reduced` keeps lambda_n of every node like `condensed`, `none`
   * nothing while no node is in contact, like `augmented` */
  for (int alias = 5; alias <= 6; ++alias) {
    kit k;
    make_pair(&k, 0.3, 1);
    SK_CHECK(strcmp(pl->strategies[alias], alias == 5 ? "reduced" : "none") == 0);
    SK_CHECK(kit_create(&k, pl, alias) == SK_OK);
    kit_state(&k, X, X, 0.0, 1.0, NULL);
    SK_CHECK(kit_begin(&k) == SK_OK);
    for (int j = 0; j < 5 * N_SLAVE; ++j) SK_CHECK(k.layout.eliminated[j] == (alias == 6 || j % 5 != 0));
    kit_free(&k);
  }

  frozen_node_cycle(pl);

  static run runs[N_STRATEGIES];
  for (int s = 0; s < N_STRATEGIES; ++s) run_init(&runs[s], s, 0.5);
  run *const cond = &runs[CONDENSED];
  for (int step = 0; step < 3; ++step) {
    const int midpoint = step == 2;
    int its[N_STRATEGIES];
    for (int s = 0; s < N_STRATEGIES; ++s) {
      runs[s].alpha = midpoint ? 0.5 : 1.0;
      its[s] = run_step(&runs[s], step);
    }
    printf("step %d (%s): Newton iterations", step, midpoint ? "midpoint" : "quasi-static");
    for (int s = 0; s < N_STRATEGIES; ++s) printf(" %s %d%s", NAME[s], its[s], runs[s].loops ? "*" : "");
    printf(" (* outer loops: augmented %d); largest system: condensed %d, augmented %d unknowns\n",
           runs[AUGMENTED].loops, cond->largest_system, runs[AUGMENTED].largest_system);
    const double d_aug = solution_difference(cond, &runs[AUGMENTED]);
    const double it_aug = iterate_difference(cond, &runs[AUGMENTED]);
    const double d_paper = solution_difference(cond, &runs[PAPER]);
    const double d_direct = solution_difference(cond, &runs[DIRECT]);
    const double d_end = solution_difference(cond, &runs[DIRECT_ENDPOINT]);
    printf("  |solution - condensed|: augmented %.1e (iterates %.1e), paper-reduced %.1e, direct %.1e, "
           "direct-endpoint %.1e\n", d_aug, it_aug, d_paper, d_direct, d_end);
    printf("  report: force (%.6f, %.6f, %.6f), active %lld, stick %lld, slip %lld, dissipated %.3e, max|Phi| %.1e\n",
           cond->report.force[0], cond->report.force[1], cond->report.force[2], (long long)cond->report.active,
           (long long)cond->report.stick, (long long)cond->report.slip, cond->report.dissipated,
           cond->report.constraint_norm);
    /* the system sizes: n + n_s (condensed), n + 5 n_c (augmented, all four nodes active) */
    SK_CHECK(cond->largest_system == N_DOFS + N_SLAVE);
    SK_CHECK(runs[AUGMENTED].largest_system == N_DOFS + 5 * N_SLAVE);
    /* a new contact is taken in by an outer loop under augmented only; a persisting one needs none */
    SK_CHECK(runs[AUGMENTED].loops == (step == 0 ? 1 : 0) && cond->loops == 0);
    if (step > 0) SK_CHECK(it_aug < 1e-12);
    /* the master facet is planar and fixed here: h_f(y_hat) = 0 and the term (78) drops from (53) vanishes */
    SK_CHECK(d_aug < 1e-11 && d_end < 1e-11 && d_paper < 1e-11);
    SK_CHECK(midpoint ? d_direct > 1e-6 : d_direct < 1e-11);
    for (int s = 0; s < N_STRATEGIES; ++s) {
      run *r = &runs[s];
      SK_CHECK(r->report.active == N_SLAVE && r->report.constraint_norm < 1e-10);
      /* equilibrium: the contact force on the slave (the step's) balances the springs of the upper block */
      double anchor[N_DOFS], spring[3] = {0, 0, 0};
      anchors(step, anchor);
      for (int i = 24; i < N_DOFS; ++i) spring[i % 3] += SPRING * (r->q[i] - anchor[i]);
      for (int i = 0; i < 3; ++i) SK_CHECK_CLOSE(r->report.force[i], spring[i], 1e-9);
      /* step 0 sticks (tiny shift), step 1 slips (shift beyond mu |lambda_n|) */
      if (step == 0) SK_CHECK(r->report.stick == N_SLAVE);
      if (step == 1) SK_CHECK(r->report.slip == N_SLAVE && r->report.dissipated > 0.0);
      point_summary ps = {0, 0, 0, 0, 1e300, 0.5, {0, 0, 0}};
      SK_CHECK(pl->points(r->k.instance, &r->k.state, point_cb, &ps) == SK_OK);
      SK_CHECK(ps.count == N_SLAVE && ps.active == N_SLAVE && ps.min_pressure > 0.0);
      SK_CHECK(ps.slip == r->report.slip && ps.stick == r->report.stick);
      /* the points' forces sum to the report's; under the midpoint step only its normal part (z): the points'
       * tractions are those at t_{n+1}, the step's force carries the mean of t_n and t_{n+1} */
      for (int i = midpoint ? 2 : 0; i < 3; ++i) SK_CHECK_CLOSE(ps.force[i], r->report.force[i], 1e-12);
      if (midpoint) SK_CHECK(fabs(ps.force[0] - r->report.force[0]) > 1e-3);
    }
  }
  for (int s = 0; s < N_STRATEGIES; ++s) kit_free(&runs[s].k);
  return sk_test_finish("test_nts_plugin");
}
