/* The system of terms (core/model/system.c) and the stepper (core/time/run.c) with a mock term, on a model of two
 * 2D nodes and no elements (4 displacement dofs). The mock poses cubic springs and, optionally, one multiplier
 * lambda tying x_0 + x_1 = c:
 *   F_i = k x_i + a x_i^3 - f_i (+ lambda for i = 0, 1),   G = x_0 + x_1 - c.
 * Checked: the saddle-point solve against the closed form; the same solution with lambda eliminated on the assembled
 * operator (pair lambda <-> row 0, D = 1); solve_again (plain and condensed) against J v; update_active_set called
 * once at every new point, before residual and Jacobian; converged() rejecting once; a Jacobian entry outside the
 * declared pattern refused; step cuts, regrowth and giving up in the stepper. */
#include <math.h>
#include <mpi.h>
#include <stdlib.h>
#include <string.h>

#include "sk_test.h"
#include "stickslip/run.h"
#include "system.h"

enum { N_NODES = 2, DIM = 2, N_DOFS = N_NODES * DIM, MAX_POINTS = 256 };

typedef struct {
  sk_term base;
  double k, a, f[N_DOFS], c;
  int constrained, condense, reject_once, undeclared;
  int extra_couplings;      /* bit 0: declares (0,3), (3,0) too, bit 1: (2,4), (4,2): the pattern grows by them */
  double fail_above_dt;     /* residual fails (SK_ERR_DIVERGED) when dt exceeds this */
  /* bookkeeping */
  int rejected, commits, rejects, updates;
  double update_x[MAX_POINTS][N_DOFS + 1];
  int evaluations;
  double eval_x[MAX_POINTS][N_DOFS + 1];
} mock_term;

static void note_point(double (*points)[N_DOFS + 1], int *n, const sk_system *sys) {
  if (*n < MAX_POINTS) memcpy(points[(*n)++], sys->x, sizeof(double) * (size_t)sys->n);
}

static void mock_destroy(sk_term *t) { free(t); }

static sk_status mock_layout(sk_term *t, sk_system *sys) {
  mock_term *m = (mock_term *)t;
  t->n_extra = m->constrained;
  if (m->constrained && m->condense) {
    const int64_t z = t->extra_offset, row = 0;
    SK_TRY(sk_system_condense_pairs(sys, 1, 1, &z, &row));
  }
  return SK_OK;
}

static sk_status mock_pattern(sk_term *t, sk_system *sys, unsigned char *rows) {
  mock_term *m = (mock_term *)t;
  for (int i = 0; i < N_DOFS; ++i) rows[i] = 1;
  if (!m->constrained) return SK_OK;
  const int64_t idx[3] = {0, 1, t->extra_offset};
  SK_TRY(sk_system_declare(sys, 3, idx, 3, idx));
  const int64_t extra[4][2] = {{0, 3}, {3, 0}, {2, t->extra_offset}, {t->extra_offset, 2}};
  for (int k = 0; k < 4; ++k)
    if (m->extra_couplings & (1 << (k / 2))) SK_TRY(sk_system_declare(sys, 1, &extra[k][0], 1, &extra[k][1]));
  return SK_OK;
}

static sk_status mock_update(sk_term *t, sk_system *sys, int *changed) {
  mock_term *m = (mock_term *)t;
  note_point(m->update_x, &m->updates, sys);
  *changed = 0;
  return SK_OK;
}

static sk_status mock_residual(sk_term *t, sk_system *sys) {
  mock_term *m = (mock_term *)t;
  if (sys->dt > m->fail_above_dt) return sk_error_set(SK_ERR_DIVERGED, "mock: dt %g too large", sys->dt);
  note_point(m->eval_x, &m->evaluations, sys);
  const double *x = sys->x;
  for (int i = 0; i < N_DOFS; ++i) sys->F_local[i] += m->k * x[i] + m->a * x[i] * x[i] * x[i] - m->f[i];
  if (m->constrained) {
    const double lambda = x[t->extra_local];
    sys->F_local[0] += lambda;
    sys->F_local[1] += lambda;
    sys->F_local[t->extra_local] += x[0] + x[1] - m->c;
  }
  return SK_OK;
}

static sk_status mock_jacobian(sk_term *t, sk_system *sys) {
  mock_term *m = (mock_term *)t;
  note_point(m->eval_x, &m->evaluations, sys);
  sk_sink *sink = &sys->sink.abi;
  for (int64_t i = 0; i < N_DOFS; ++i) {
    const double d = m->k + 3.0 * m->a * sys->x[i] * sys->x[i];
    sink->add_matrix(sink, 1, &i, 1, &i, &d);
  }
  if (m->constrained) {
    const int64_t z = t->extra_offset, r[2] = {0, 1};
    const double one[2] = {1.0, 1.0};
    sink->add_matrix(sink, 2, r, 1, &z, one);
    sink->add_matrix(sink, 1, &z, 2, r, one);
  }
  if (m->undeclared) {
    const int64_t r = 0, c = 2;
    const double v = 1.0;
    sink->add_matrix(sink, 1, &r, 1, &c, &v);
  }
  return SK_OK;
}

static sk_status mock_converged(sk_term *t, sk_system *sys, int *accept) {
  mock_term *m = (mock_term *)t;
  (void)sys;
  *accept = !m->reject_once || m->rejected;
  if (!*accept) {
    m->rejected = 1;
    for (int i = 0; i < N_DOFS; ++i) m->f[i] *= 2.0; /* the set changed: a different load */
  }
  return SK_OK;
}

static sk_status mock_commit(sk_term *t, sk_system *sys) {
  (void)sys;
  ((mock_term *)t)->commits++;
  return SK_OK;
}

static void mock_reject(sk_term *t, sk_system *sys) {
  (void)sys;
  ((mock_term *)t)->rejects++;
}

static const sk_term_ops mock_ops = {.kind = "mock",
                                     .destroy = mock_destroy,
                                     .layout = mock_layout,
                                     .pattern = mock_pattern,
                                     .update_active_set = mock_update,
                                     .residual = mock_residual,
                                     .jacobian = mock_jacobian,
                                     .converged = mock_converged,
                                     .commit = mock_commit,
                                     .reject = mock_reject};

/* ---- a model of two nodes --------------------------------------------------------------------------------------- */

typedef struct {
  sk_model model;
  sk_solver_settings solver;
  sk_system *sys;
  mock_term *mock;
} fixture;

static void fixture_init(fixture *fx, const mock_term *config) {
  memset(fx, 0, sizeof *fx);
  sk_model *m = &fx->model;
  m->comm = MPI_COMM_WORLD;
  MPI_Comm_rank(m->comm, &m->rank);
  MPI_Comm_size(m->comm, &m->n_ranks);
  m->dim = DIM;
  m->n_nodes = N_NODES;
  m->n_dofs = N_DOFS;
  m->X = calloc(N_DOFS, sizeof(double));
  m->X[2] = 1.0; /* node 1 at (1, 0) */
  SK_CHECK(sk_model_build(m) == SK_OK); /* no elements: an empty node graph; the nodes on rank 0 */
  SK_CHECK(sk_model_distribute(m) == SK_OK);
  m->time.integrator = sk_time_integrator_find("quasi-static");
  m->time.dt = 1.0;
  m->time.t_end = 1.0;
  m->time.max_cuts = 3;
  sk_newton_options_default(&fx->solver.newton);
  sk_linear_options_default(&fx->solver.linear);
  fx->solver.linear.kind = SK_LINEAR_DIRECT;
  fx->solver.newton.relative_tolerance = 1e-13;
  fx->solver.newton.residual_tolerance = 1e-13;
  fx->solver.max_active_set_loops = 3;
  SK_CHECK(sk_system_create(m, &fx->solver, &fx->sys) == SK_OK);
  fx->mock = calloc(1, sizeof *fx->mock);
  *fx->mock = *config;
  fx->mock->base.ops = &mock_ops;
  snprintf(fx->mock->base.name, sizeof fx->mock->base.name, "mock");
  SK_CHECK(sk_system_add_term(fx->sys, &fx->mock->base) == SK_OK);
}

static void fixture_free(fixture *fx) {
  sk_system_destroy(fx->sys);
  sk_model_free(&fx->model);
}

static sk_status solve_step(fixture *fx) {
  SK_TRY(sk_system_begin(fx->sys, 1.0, 1));
  return sk_system_solve(fx->sys);
}

static mock_term linear_constrained(void) {
  mock_term m = {.k = 2.0, .f = {1, 2, 3, 4}, .c = 0.5, .constrained = 1, .fail_above_dt = 1e300};
  return m;
}

/* ---- the system ------------------------------------------------------------------------------------------------- */

static void check_constrained_solution(const fixture *fx, double tol) {
  const mock_term *m = fx->mock;
  const double *x = fx->sys->x;
  const double lambda = (m->f[0] + m->f[1] - m->k * m->c) / 2.0;
  SK_CHECK_CLOSE(x[0], (m->f[0] - lambda) / m->k, tol);
  SK_CHECK_CLOSE(x[1], (m->f[1] - lambda) / m->k, tol);
  SK_CHECK_CLOSE(x[2], m->f[2] / m->k, tol);
  SK_CHECK_CLOSE(x[3], m->f[3] / m->k, tol);
  SK_CHECK_CLOSE(x[N_DOFS], lambda, tol);
}

/* J v with the mock's operator at the solution (the constrained, linear case) */
static void apply_J(const fixture *fx, const double *v, double *Jv) {
  const mock_term *m = fx->mock;
  for (int i = 0; i < N_DOFS; ++i) Jv[i] = m->k * v[i];
  Jv[0] += v[N_DOFS];
  Jv[1] += v[N_DOFS];
  Jv[N_DOFS] = v[0] + v[1];
}

static void test_saddle_and_condensed(void) {
  for (int condense = 0; condense <= 1; ++condense) {
    fixture fx;
    mock_term config = linear_constrained();
    config.condense = condense;
    fixture_init(&fx, &config);
    SK_CHECK(solve_step(&fx) == SK_OK);
    SK_CHECK(fx.sys->condensing == condense);
    check_constrained_solution(&fx, 1e-14);
    /* solve_again: J y = J v gives y = v, with the factorisation of the last solve */
    const double v[N_DOFS + 1] = {0.3, -1.2, 2.5, 0.7, -0.4};
    double b[N_DOFS + 1], y[N_DOFS + 1];
    apply_J(&fx, v, b);
    SK_CHECK(sk_system_solve_again(fx.sys, b, y) == SK_OK);
    for (int i = 0; i <= N_DOFS; ++i) SK_CHECK_CLOSE(y[i], v[i], 1e-14);
    printf("%s: x = (%.6f %.6f %.6f %.6f), lambda = %.6f, linear system %lld\n", condense ? "condensed" : "saddle",
           fx.sys->x[0], fx.sys->x[1], fx.sys->x[2], fx.sys->x[3], fx.sys->x[N_DOFS], (long long)fx.sys->linear_size_max);
    SK_CHECK(fx.sys->linear_size_max == (condense ? N_DOFS : N_DOFS + 1));
    fixture_free(&fx);
  }
}

/* update_active_set runs once at every point where F or J is evaluated, before them. */
static void test_active_set_points(void) {
  fixture fx;
  mock_term config = {.k = 1.0, .a = 5.0, .f = {1, -2, 3, 0.5}, .fail_above_dt = 1e300};
  fixture_init(&fx, &config);
  SK_CHECK(solve_step(&fx) == SK_OK);
  const mock_term *m = fx.mock;
  /* the distinct evaluation points, in order, equal the update points */
  int distinct = 0;
  for (int e = 0; e < m->evaluations; ++e) {
    if (e > 0 && memcmp(m->eval_x[e], m->eval_x[e - 1], sizeof(double) * N_DOFS) == 0) continue;
    SK_CHECK(distinct < m->updates && memcmp(m->eval_x[e], m->update_x[distinct], sizeof(double) * N_DOFS) == 0);
    ++distinct;
  }
  printf("active set: %d evaluations at %d points, %d updates, %d Newton iterations\n", m->evaluations, distinct,
         m->updates, fx.sys->newton.iterations);
  SK_CHECK(distinct == m->updates && m->updates > 2);
  for (int i = 0; i < N_DOFS; ++i) {
    const double x = fx.sys->x[i];
    SK_CHECK(fabs(m->k * x + m->a * x * x * x - m->f[i]) < 1e-12);
  }
  fixture_free(&fx);
}

/* converged() rejects once: Newton again from the converged point, with the changed set (load doubled). */
static void test_converged_reject(void) {
  fixture fx;
  mock_term config = linear_constrained();
  config.reject_once = 1;
  fixture_init(&fx, &config);
  SK_CHECK(solve_step(&fx) == SK_OK);
  SK_CHECK(fx.sys->active_set_loops == 1 && fx.mock->rejected);
  check_constrained_solution(&fx, 1e-14); /* with the doubled load */
  SK_CHECK_CLOSE(fx.mock->f[3], 8.0, 0);
  fixture_free(&fx);
  /* a set that never settles: the attempt fails after max_active_set_loops */
  config.reject_once = 0;
  fixture_init(&fx, &config);
  fx.mock->reject_once = 1;
  fx.solver.max_active_set_loops = 1;
  const sk_status status = solve_step(&fx);
  SK_CHECK(status == SK_ERR_DIVERGED && strstr(sk_error_message(), "max_active_set_loops"));
  fixture_free(&fx);
}

/* An entry outside the declared pattern is an error naming it (no grow-and-reassemble). */
static void test_undeclared_entry(void) {
  fixture fx;
  mock_term config = linear_constrained();
  config.undeclared = 1;
  fixture_init(&fx, &config);
  const sk_status status = solve_step(&fx);
  SK_CHECK(status == SK_ERR_PLUGIN && strstr(sk_error_message(), "(0, 2) outside the pattern declared"));
  printf("undeclared entry: %s\n", sk_error_message());
  fixture_free(&fx);
}

/* New couplings grow the pattern in place (each row's bulk entries merged with its keys, before, between and after
 * them): the same CSR as a rebuild from scratch, and the solve on it still right. */
static void test_pattern_growth(void) {
  fixture fx;
  mock_term config = linear_constrained();
  fixture_init(&fx, &config);
  SK_CHECK(solve_step(&fx) == SK_OK);
  sk_system *sys = fx.sys;
  const int64_t n = sys->n, before = sys->row_ptr[n]; /* one rank: the local rows are the system's */
  fx.mock->extra_couplings = 3;
  SK_CHECK(sk_system_settle_pattern(sys, 0) == SK_OK);
  SK_CHECK(sys->row_ptr[n] == before + 4);
  int64_t grown_ptr[N_DOFS + 2];
  int grown_cols[64];
  SK_CHECK(n + 1 <= N_DOFS + 2 && sys->row_ptr[n] <= 64);
  memcpy(grown_ptr, sys->row_ptr, sizeof(int64_t) * (size_t)(n + 1));
  memcpy(grown_cols, sys->cols, sizeof(int) * (size_t)sys->row_ptr[n]);
  free(sys->pattern_dof_solver); /* the dofs' numbering forgotten: the layout change builds it from scratch */
  sys->pattern_dof_solver = NULL;
  SK_CHECK(sk_system_settle_pattern(sys, 1) == SK_OK);
  SK_CHECK(memcmp(grown_ptr, sys->row_ptr, sizeof(int64_t) * (size_t)(n + 1)) == 0);
  SK_CHECK(memcmp(grown_cols, sys->cols, sizeof(int) * (size_t)sys->row_ptr[n]) == 0);
  SK_CHECK(sk_system_position(sys, 0, 3) >= 0 && sk_system_position(sys, N_DOFS, 2) >= 0);
  printf("pattern growth: %lld -> %lld entries, equal to the rebuilt pattern\n", (long long)before,
         (long long)sys->row_ptr[n]);
  SK_CHECK(solve_step(&fx) == SK_OK);
  check_constrained_solution(&fx, 1e-14);
  fixture_free(&fx);
}

/* With solver.pattern_margin the pattern is rebuilt around the couplings declared now whenever one is missing:
 * couplings the terms no longer declare are dropped then (margin 0 keeps every coupling ever declared). */
static void test_pattern_follows_couplings(void) {
  for (int margin = 0; margin <= 1; ++margin) {
    fixture fx;
    mock_term config = linear_constrained();
    fixture_init(&fx, &config);
    fx.solver.pattern_margin = margin;
    SK_CHECK(solve_step(&fx) == SK_OK);
    sk_system *sys = fx.sys;
    const int builds = sys->pattern_builds;
    fx.mock->extra_couplings = 1;
    SK_CHECK(sk_system_settle_pattern(sys, 0) == SK_OK);
    SK_CHECK(sk_system_position(sys, 0, 3) >= 0 && sk_system_position(sys, N_DOFS, 2) < 0);
    fx.mock->extra_couplings = 2; /* the coupling moved on */
    SK_CHECK(sk_system_settle_pattern(sys, 0) == SK_OK);
    SK_CHECK(sys->pattern_builds == builds + 2);
    SK_CHECK(sk_system_position(sys, N_DOFS, 2) >= 0 && sk_system_position(sys, 2, N_DOFS) >= 0);
    SK_CHECK((sk_system_position(sys, 0, 3) >= 0) == (margin == 0));
    SK_CHECK((sk_system_position(sys, 3, 0) >= 0) == (margin == 0));
    fx.mock->extra_couplings = 0; /* nothing missing: the pattern stays as it is */
    SK_CHECK(sk_system_settle_pattern(sys, 0) == SK_OK);
    SK_CHECK(sys->pattern_builds == builds + 2 && sk_system_position(sys, N_DOFS, 2) >= 0);
    printf("pattern margin %d: %lld entries after the coupling moved\n", margin, (long long)sys->row_ptr[sys->n]);
    SK_CHECK(solve_step(&fx) == SK_OK);
    check_constrained_solution(&fx, 1e-14);
    fixture_free(&fx);
  }
}

/* ---- the stepper ------------------------------------------------------------------------------------------------ */

static sk_status run_scene(fixture *fx, sk_run_summary *summary) {
  sk_scene scene;
  memset(&scene, 0, sizeof scene);
  snprintf(scene.path, sizeof scene.path, "mock scene");
  scene.model = fx->model;
  scene.solver = fx->solver;
  scene.system = fx->sys;
  fx->sys->model = &scene.model;
  const sk_run_options options = {.out_dir = NULL};
  const sk_status status = sk_run(&scene, &options, summary);
  fx->sys->model = &fx->model;
  return status;
}

static void test_stepper_cuts(void) {
  fixture fx;
  mock_term config = linear_constrained();
  config.fail_above_dt = 0.3; /* dt 1 and 0.5 fail, 0.25 passes; dt grows back to 0.5 after 3 good steps */
  fixture_init(&fx, &config);
  fx.model.time.t_end = 2.0;
  sk_run_summary summary;
  SK_CHECK(run_scene(&fx, &summary) == SK_OK);
  printf("stepper: %d steps, %d cuts, final time %g\n", summary.steps, summary.cuts, summary.final_time);
  /* 1 and 0.5 fail; 3 steps of 0.25 (t = 0.75); the regrown 0.5 stops at the scheduled t = 1 (0.25 passes); 0.5
   * fails; 3 of 0.25 (t = 1.75); the regrown 0.5 stops at t_end (0.25) */
  SK_CHECK(summary.cuts == 3 && summary.steps == 8);
  SK_CHECK(fx.mock->rejects == summary.cuts && fx.mock->commits == summary.steps);
  SK_CHECK_CLOSE(summary.final_time, 2.0, 1e-15);
  fixture_free(&fx);

  config.fail_above_dt = 0.01; /* needs 7 halvings: more than max_cuts = 3 */
  fixture_init(&fx, &config);
  const sk_status status = run_scene(&fx, &summary);
  SK_CHECK(status == SK_ERR_DIVERGED && strstr(sk_error_message(), "no convergence after 3 step cuts"));
  SK_CHECK(summary.failed && summary.steps == 0 && summary.cuts == 4);
  fixture_free(&fx);
}

int main(int argc, char **argv) {
  MPI_Init(&argc, &argv);
  test_saddle_and_condensed();
  test_active_set_points();
  test_converged_reject();
  test_undeclared_entry();
  test_pattern_growth();
  test_pattern_follows_couplings();
  test_stepper_cuts();
  const int code = sk_test_finish("test_system");
  MPI_Finalize();
  return code;
}
