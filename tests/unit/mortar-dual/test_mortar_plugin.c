/* mortar-dual through its ABI table, with the mock v2 host (mock_host.h): a Newton solve of two spring-held bodies
 * pressed together converges quadratically (semismooth and nested active sets) and the condensed solve (the pairs
 * eliminated as the host's stickslip.condense.v1 does) gives the same iterates; a rigid rotation leaves the NCP
 * rows unchanged. The finite-difference checks of the assembled operator are in test_mortar_assembled.c (the
 * plugin test kit). */
#include <math.h>

#include "mock_host.h"
#include "mortar.h" /* the instance, for the test's look at the node states */
#include "sk_test.h"

typedef struct {
  int dim, n_nodes, n_dofs, n_total;
  double X[192];
  mock_view slave, master;
  int with_master;
  sk_obstacle obstacle;
  sk_host host;
  sk_attach attach;
  const sk_view *views[2];
  sk_instance *inst;
  const sk_plugin *plugin;
} scene;

/* 2D: the upper body's bottom (4 slave nodes, 3 faces, normal -y) over the lower body's top (5 master nodes, 4
 * faces, normal +y), non-matching. */
static void scene_2d(scene *s, int with_master) {
  memset(s, 0, sizeof *s);
  s->dim = 2;
  static const double xs[4] = {0.0, 0.35, 0.7, 1.0}, xm[5] = {1.2, 0.85, 0.5, 0.2, -0.2};
  for (int k = 0; k < 4; ++k) {
    s->X[2 * k] = xs[k];
    s->X[2 * k + 1] = 0.01 * sin(3.0 * xs[k]);
  }
  for (int k = 0; k < 5; ++k) {
    s->X[2 * (4 + k)] = xm[k];
    s->X[2 * (4 + k) + 1] = -0.004 + 0.02 * xm[k] * xm[k];
  }
  static const int sf[6] = {0, 1, 1, 2, 2, 3}, mf[8] = {4, 5, 5, 6, 6, 7, 7, 8};
  mock_view_build(&s->slave, "slave", 2, SK_LINE2, 2, 3, sf, s->X);
  s->with_master = with_master;
  if (with_master) mock_view_build(&s->master, "master", 2, SK_LINE2, 2, 4, mf, s->X);
  s->n_nodes = with_master ? 9 : 4;
  s->n_dofs = 2 * s->n_nodes;
}

static int scene_create(scene *s, int strategy, int n_keys, const char *const *kv) {
  s->host.n_keys = n_keys;
  for (int i = 0; i < n_keys; ++i) {
    s->host.keys[i] = kv[2 * i];
    s->host.values[i] = kv[2 * i + 1];
  }
  s->views[0] = &s->slave.view;
  s->views[1] = &s->master.view;
  s->attach = (sk_attach){.struct_size = sizeof(sk_attach), .kind = SK_KIND_PAIR, .name = "pair", .strategy = strategy,
                          .n_views = s->with_master ? 2 : 1, .views = s->views, .slave = &s->slave.view,
                          .master = s->with_master ? &s->master.view : NULL,
                          .obstacle = s->with_master ? NULL : &s->obstacle};
  s->plugin = stickslip_plugin_entry();
  const sk_status st = s->plugin->create(&mock_api, &s->host, &s->attach, &s->inst);
  if (st != SK_OK) printf("  create: %s\n", s->host.last_error);
  s->n_total = s->n_dofs + s->dim * (int)s->slave.view.n_nodes_global;
  return st;
}

typedef struct {
  sk_state state;
  double xs[96], xm[96], xs_n[96], xm_n[96];
  const double *x[2], *x_n[2], *v_n[2];
} state_buf;

/* The state at unknowns u (global positions then z) with t_n positions u_n. */
static void make_state(const scene *s, const double *u, const double *u_n, double t_n, double t, state_buf *b) {
  mock_view_positions(&s->slave, u, b->xs);
  mock_view_positions(&s->slave, u_n, b->xs_n);
  if (s->with_master) {
    mock_view_positions(&s->master, u, b->xm);
    mock_view_positions(&s->master, u_n, b->xm_n);
  }
  b->x[0] = b->xs;
  b->x[1] = b->xm;
  b->x_n[0] = b->xs_n;
  b->x_n[1] = b->xm_n;
  b->v_n[0] = b->v_n[1] = NULL;
  b->state = (sk_state){.struct_size = sizeof(sk_state), .t_n = t_n, .t = t, .dt = t - t_n, .step = 1,
                        .scheme = "quasi-static", .alpha = 1.0, .dynamic = 0, .n_views = s->with_master ? 2 : 1,
                        .x = b->x, .x_n = b->x_n, .v_n = b->v_n, .extra = u + s->n_dofs,
                        .n_extra = s->n_total - s->n_dofs, .extra_offset = s->n_dofs};
}

static sk_status eval(const scene *s, const double *u, const double *u_n, mock_system *sys, int jac) {
  state_buf b;
  make_state(s, u, u_n, 0.0, 1.0, &b);
  memset(sys, 0, sizeof *sys);
  sys->n = s->n_total;
  sys->bad_row = -1;
  mock_sink sk;
  mock_sink_init(&sk, sys);
  return jac ? s->plugin->jacobian(s->inst, &b.state, &sk.sink) : s->plugin->residual(s->inst, &b.state, &sk.sink);
}

static sk_status begin(const scene *s, const double *u, const double *u_n, double t_n, double t, mock_pattern *pat) {
  state_buf b;
  make_state(s, u, u_n, t_n, t, &b);
  SK_TRY(s->plugin->begin_step(s->inst, &b.state));
  sk_layout layout = {.struct_size = sizeof layout};
  SK_TRY(s->plugin->layout(s->inst, &b.state, &layout));
  if (pat) {
    mock_pattern_init(pat, s->n_total);
    SK_TRY(s->plugin->pattern(s->inst, &b.state, &pat->pattern));
  }
  return SK_OK;
}

static sk_status set_at(const scene *s, const double *u, const double *u_n, int *changed) {
  state_buf b;
  make_state(s, u, u_n, 0.0, 1.0, &b);
  return s->plugin->update_active_set(s->inst, &b.state, changed);
}

/* ---- Newton through the plugin ---------------------------------------------------------------------------------
 * Bulk: every node on a spring (stiffness k) to a target: slave nodes pushed down by 0.02 and sideways by `shift`,
 * master nodes held. Solves F = k (x - target) + F_contact = 0 with the plugin's update_active_set / residual /
 * jacobian / converged, and with the condensed solve built from the pairs the plugin declared (the host's
 * stickslip.condense.v1 algebra). */
static int solve_dense(int n, double *A, double *b) {
  for (int c = 0; c < n; ++c) {
    int p = c;
    for (int r = c + 1; r < n; ++r)
      if (fabs(A[r * n + c]) > fabs(A[p * n + c])) p = r;
    if (fabs(A[p * n + c]) < 1e-300) return -1;
    for (int k = 0; k < n; ++k) {
      const double t = A[c * n + k];
      A[c * n + k] = A[p * n + k];
      A[p * n + k] = t;
    }
    const double t = b[c];
    b[c] = b[p];
    b[p] = t;
    for (int r = c + 1; r < n; ++r) {
      const double f = A[r * n + c] / A[c * n + c];
      for (int k = c; k < n; ++k) A[r * n + k] -= f * A[c * n + k];
      b[r] -= f * b[c];
    }
  }
  for (int c = n - 1; c >= 0; --c) {
    for (int k = c + 1; k < n; ++k) b[c] -= A[c * n + k] * b[k];
    b[c] /= A[c * n + c];
  }
  return 0;
}

/* dx from the condensed system: every row r gets r - J_rz D^-1 [J_s | F_s] for each pair (z <-> s), the z rows take
 * the s rows' places, the displacement-only system is solved, dz recovered from the original s rows. */
static int solve_condensed(const scene *s, const mock_system *sys, double *dx) {
  static double J[MOCK_MAX_UNKNOWNS * MOCK_MAX_UNKNOWNS], R[MOCK_MAX_UNKNOWNS * MOCK_MAX_UNKNOWNS];
  static double F[MOCK_MAX_UNKNOWNS], b[MOCK_MAX_UNKNOWNS];
  const int n = s->n_total, nd = s->n_dofs;
  memcpy(J, sys->J, sizeof(double) * (size_t)(n * n));
  memcpy(F, sys->F, sizeof(double) * (size_t)n);
  const sk_host *h = &s->host;
  for (int p = 0; p < h->n_pairs; ++p) {
    const int zc = nd + (int)h->pair_extra[p], sr = (int)h->pair_row[p];
    const double D = sys->J[sr * n + zc];
    for (int r = 0; r < n; ++r) {
      if (r == sr) continue;
      const double f = J[r * n + zc] / D;
      if (f == 0.0) continue;
      for (int c = 0; c < n; ++c) J[r * n + c] -= f * sys->J[sr * n + c];
      F[r] -= f * sys->F[sr];
    }
  }
  /* displacement unknowns; equations: non-paired displacement rows, the paired z rows in their s rows' places */
  int row_of[MOCK_MAX_UNKNOWNS];
  for (int r = 0; r < nd; ++r) row_of[r] = r;
  for (int p = 0; p < h->n_pairs; ++p) row_of[h->pair_row[p]] = nd + (int)h->pair_extra[p];
  for (int r = 0; r < nd; ++r) {
    for (int c = 0; c < nd; ++c) R[r * nd + c] = J[row_of[r] * n + c];
    b[r] = -F[row_of[r]];
  }
  if (solve_dense(nd, R, b) != 0) return -1;
  memcpy(dx, b, sizeof(double) * (size_t)nd);
  for (int p = 0; p < h->n_pairs; ++p) {
    const int zc = nd + (int)h->pair_extra[p], sr = (int)h->pair_row[p];
    double v = -sys->F[sr];
    for (int c = 0; c < nd; ++c) v -= sys->J[sr * n + c] * dx[c];
    dx[zc] = v / sys->J[sr * n + zc];
  }
  return 0;
}

typedef struct {
  int iterations, loops;
  double residuals[32];
} newton_log;

static void add_springs(const scene *s, const double *u, const double *target, mock_system *sys, double k) {
  for (int i = 0; i < s->n_dofs; ++i) {
    sys->F[i] += k * (u[i] - target[i]);
    sys->J[i * sys->n + i] += k;
  }
}

/* One quasi-static step from u (converged at u_n) to the targets; returns 0 when converged. */
static int newton_step(scene *s, double *u, const double *u_n, const double *target, int condensed, newton_log *log) {
  static mock_system sys;
  double dx[MOCK_MAX_UNKNOWNS], dx_full[MOCK_MAX_UNKNOWNS];
  static double Jc[MOCK_MAX_UNKNOWNS * MOCK_MAX_UNKNOWNS];
  memset(log, 0, sizeof *log);
  if (begin(s, u, u_n, 0.0, 1.0, NULL) != SK_OK) return -1;
  for (int loop = 0; loop < 10; ++loop) {
    for (int it = 0; it < 30; ++it) {
      int changed;
      if (set_at(s, u, u_n, &changed) != SK_OK) return -1;
      eval(s, u, u_n, &sys, 0);
      double fnorm = 0.0;
      static mock_system jsys;
      eval(s, u, u_n, &jsys, 1);
      memcpy(jsys.F, sys.F, sizeof(double) * (size_t)s->n_total);
      add_springs(s, u, target, &jsys, 100.0);
      for (int i = 0; i < s->n_total; ++i) fnorm += jsys.F[i] * jsys.F[i];
      fnorm = sqrt(fnorm);
      if (log->iterations < 32) log->residuals[log->iterations] = fnorm;
      ++log->iterations;
      if (fnorm < 1e-11) break;
      memcpy(Jc, jsys.J, sizeof(double) * (size_t)(s->n_total * s->n_total));
      for (int i = 0; i < s->n_total; ++i) dx_full[i] = -jsys.F[i];
      if (solve_dense(s->n_total, Jc, dx_full) != 0) return -1;
      if (condensed) {
        if (solve_condensed(s, &jsys, dx) != 0) return -1;
        double diff = 0.0, size = 0.0;
        for (int i = 0; i < s->n_total; ++i) {
          diff = fmax(diff, fabs(dx[i] - dx_full[i]));
          size = fmax(size, fabs(dx_full[i]));
        }
        SK_CHECK(diff <= 1e-10 * fmax(size, 1e-3)); /* condensed = saddle-point to round-off */
      } else {
        memcpy(dx, dx_full, sizeof dx_full);
      }
      for (int i = 0; i < s->n_total; ++i) u[i] += dx[i];
    }
    state_buf b;
    make_state(s, u, u_n, 0.0, 1.0, &b);
    int accept = 1;
    if (s->plugin->converged(s->inst, &b.state, &accept) != SK_OK) return -1;
    log->loops = loop + 1;
    if (accept) {
      s->plugin->commit_step(s->inst, &b.state);
      return 0;
    }
  }
  return -1;
}

/* Quadratic decay: r_(k+1) <= 10 r_k^2 once r_k < 0.2, above round-off (after a converged r_k the nested loop
 * starts its next Newton run); measured factors below 1. */
static int quadratic(const newton_log *log) {
  for (int k = 0; k + 1 < log->iterations && k + 1 < 32; ++k) {
    const double r = log->residuals[k], next = log->residuals[k + 1];
    if (r < 0.2 && r > 1e-11 && next > 1e-12 && next > 10.0 * r * r) return 0;
  }
  return 1;
}

static void check_newton(const char *label, const char *const *kv, int n_keys, int strategy, int max_iterations,
                         int max_loops) {
  scene s;
  scene_2d(&s, 1);
  SK_CHECK(scene_create(&s, strategy, n_keys, kv) == SK_OK);
  double u[MOCK_MAX_UNKNOWNS] = {0}, u_n[MOCK_MAX_UNKNOWNS] = {0}, target[MOCK_MAX_UNKNOWNS] = {0};
  memcpy(u, s.X, sizeof(double) * (size_t)s.n_dofs);
  memcpy(target, s.X, sizeof(double) * (size_t)s.n_dofs);
  newton_log log;
  const double shifts[3] = {0.0, 0.004, 0.03};
  for (int step = 0; step < 3; ++step) {
    const int d = s.dim, ns = (int)s.slave.view.n_nodes;
    for (int k = 0; k < ns; ++k) { /* slave nodes: down 0.02, sideways by the step's shift */
      target[d * k] = s.X[d * k] + shifts[step];
      target[d * k + d - 1] = s.X[d * k + d - 1] - 0.02;
    }
    memcpy(u_n, u, sizeof u);
    const int st = newton_step(&s, u, u_n, target, strategy == 1, &log);
    SK_CHECK(st == 0);
    int n_state[3] = {0, 0, 0};
    for (int oi = 0; oi < s.inst->n_owned; ++oi) ++n_state[s.inst->owned[oi].state];
    printf("  %s, step %d: %d Newton iterations in %d active-set loops, inactive/stick/slip %d/%d/%d, |F|:", label,
           step + 1, log.iterations, log.loops, n_state[0], n_state[1], n_state[2]);
    for (int i = 0; i < log.iterations && i < 32; ++i) printf(" %.1e", log.residuals[i]);
    printf("\n");
    SK_CHECK(log.iterations <= max_iterations && log.loops <= max_loops);
    SK_CHECK(quadratic(&log));
  }
  s.plugin->destroy(s.inst);
}

/* The rows of each owned node's NCP functions at the normals of the last evaluation (Cartesian under
 * saddle-point, at the normal's and tangents' axes under condensed). */
static void ncp_places(const sk_instance *inst, int place[4][3]) {
  for (int k = 0; k < 4; ++k) {
    place[k][0] = 0;
    place[k][1] = 1;
    if (inst->strategy != STRATEGY_CONDENSED) continue;
    const owned_node *o = &inst->owned[k];
    double tau[2][3], dtau[2][3][3];
    SK_CHECK(mortar_tangents(2, inst->normal + 3 * o->node, o->ref, tau, dtau) == 0);
    mortar_ncp_places(2, inst->normal + 3 * o->node, tau, place[k]);
  }
}

/* ---- objectivity through the plugin --------------------------------------------------------------------------
 * A step whose end state is the start state rigidly rotated by 60 degrees and translated (both bodies, z rotated
 * with them): the NCP rows are those of the unmoved state (the weighted slip [S1] vanishes, the gaps and the
 * stick/slip states are unchanged) and the force rows are rotated. */
static void check_objectivity(int strategy) {
  static mock_system a, b;
  scene s;
  scene_2d(&s, 1);
  const char *kv[] = {"mu", "0.3", "c_n", "30"};
  SK_CHECK(scene_create(&s, strategy, 2, kv) == SK_OK);
  double u_n[MOCK_MAX_UNKNOWNS] = {0}, u[MOCK_MAX_UNKNOWNS] = {0}, v[MOCK_MAX_UNKNOWNS] = {0};
  memcpy(u_n, s.X, sizeof(double) * (size_t)s.n_dofs);
  SK_CHECK(begin(&s, u_n, u_n, 0.0, 0.0, NULL) == SK_OK);
  state_buf st;
  make_state(&s, u_n, u_n, 0.0, 0.0, &st);
  SK_CHECK(s.plugin->commit_step(s.inst, &st.state) == SK_OK);
  /* the unmoved end state: slave nodes pressed 0.004 into the master, z compressive with some friction */
  memcpy(u, u_n, sizeof u);
  for (int k = 0; k < 4; ++k) u[2 * k + 1] -= 0.004;
  for (int k = 0; k < 4; ++k) {
    u[s.n_dofs + 2 * k] = 0.05 * (k - 1.5);
    u[s.n_dofs + 2 * k + 1] = -1.0 - 0.1 * k;
  }
  const double ang = 1.0471975511965976, c = cos(ang), sn = sin(ang), shift[2] = {0.3, -0.2};
  memcpy(v, u, sizeof v);
  for (int k = 0; k < s.n_nodes + 4; ++k) {
    const int at = k < s.n_nodes ? 2 * k : s.n_dofs + 2 * (k - s.n_nodes);
    const double x = u[at], y = u[at + 1], t[2] = {k < s.n_nodes ? shift[0] : 0.0, k < s.n_nodes ? shift[1] : 0.0};
    v[at] = c * x - sn * y + t[0];
    v[at + 1] = sn * x + c * y + t[1];
  }
  int changed, states_a[4], states_b[4], place_a[4][3], place_b[4][3];
  SK_CHECK(begin(&s, u, u_n, 0.0, 1.0, NULL) == SK_OK);
  SK_CHECK(set_at(&s, u, u_n, &changed) == SK_OK);
  for (int k = 0; k < 4; ++k) states_a[k] = s.inst->owned[k].state;
  SK_CHECK(eval(&s, u, u_n, &a, 0) == SK_OK);
  ncp_places(s.inst, place_a);
  SK_CHECK(begin(&s, v, u_n, 0.0, 1.0, NULL) == SK_OK);
  SK_CHECK(set_at(&s, v, u_n, &changed) == SK_OK);
  for (int k = 0; k < 4; ++k) states_b[k] = s.inst->owned[k].state;
  SK_CHECK(eval(&s, v, u_n, &b, 0) == SK_OK);
  ncp_places(s.inst, place_b);
  /* the NCP rows sit at the axes of the normal and tangent (mortar_ncp_places), which the rotation moves */
  double d_ncp = 0.0, d_force = 0.0, scale = 0.0;
  for (int k = 0; k < 4; ++k) {
    const int64_t row = s.n_dofs + s.inst->owned[k].extra;
    for (int q = 0; q < 2; ++q) d_ncp = fmax(d_ncp, fabs(a.F[row + place_a[k][q]] - b.F[row + place_b[k][q]]));
  }
  for (int k = 0; k < s.n_nodes; ++k) {
    const double fx = a.F[2 * k], fy = a.F[2 * k + 1];
    d_force = fmax(d_force, fmax(fabs(b.F[2 * k] - (c * fx - sn * fy)), fabs(b.F[2 * k + 1] - (sn * fx + c * fy))));
    scale = fmax(scale, fmax(fabs(fx), fabs(fy)));
  }
  int stick = 0;
  for (int k = 0; k < 4; ++k) stick += states_a[k] == MORTAR_STICK;
  printf("  %s, rigid rotation by 60 degrees: NCP rows differ by %.1e, forces by %.1e (scale %.2e); states "
         "%d %d %d %d (%d stick)\n", strategy == STRATEGY_CONDENSED ? "condensed" : "saddle-point", d_ncp, d_force,
         scale, states_a[0], states_a[1], states_a[2], states_a[3], stick);
  SK_CHECK(memcmp(states_a, states_b, sizeof states_a) == 0);
  SK_CHECK(stick >= 2);
  SK_CHECK(d_ncp < 1e-12);
  SK_CHECK(d_force < 1e-12 * scale);
  s.plugin->destroy(s.inst);
}

int main(void) {
  check_objectivity(STRATEGY_SADDLE_POINT);
  check_objectivity(STRATEGY_CONDENSED);
  const char *newton_fl[] = {"c_n", "100"};
  check_newton("frictionless semismooth, saddle-point", newton_fl, 1, 0, 5, 1); /* measured 5, 4, 4 */
  const char *newton_semi[] = {"mu", "0.3", "c_n", "100"};
  check_newton("semismooth, saddle-point", newton_semi, 2, 0, 6, 1); /* measured 5, 5, 6 */
  check_newton("semismooth, condensed", newton_semi, 2, 1, 6, 1);
  const char *newton_nested[] = {"mu", "0.3", "c_n", "100", "active_set", "nested"};
  check_newton("nested, saddle-point", newton_nested, 3, 0, 10, 2); /* one extra loop per set change: 7, 8, 10 */
  return sk_test_finish("test_mortar_plugin");
}
