/* Unit tests of the penalty-nts plugin through its ABI table, with the shared plugin test kit (tests/support): a
 * mock host whose contact services are the core's. Checks: residual = gradient of the penalty energy and Jacobian =
 * derivative of the residual (central differences of the assembled operator, inside the declared pattern) for
 * LINE2/LINE3, QUAD4 (warped, a point near an edge), QUAD9 (curved) masters and for plane/sphere/parabolic-cylinder/
 * circle obstacles; friction stick and slip tangents with committed history; force and moment balance; frame
 * indifference; the return map; parameter errors; tributary areas; TRI6 faces (curved master, slave with the
 * modified-basis weights and the lumped pressure recovery) and the QUAD8 slave refusal. */
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "plugin_kit.h"
#include "sk_test.h"
#include "stickslip/contact.h"
#include "stickslip/fe.h"

const sk_plugin *stickslip_plugin_entry(void);

enum { MAX_NODES = 32, MAX_DOFS = 3 * MAX_NODES };

/* ---- scenes on the kit ------------------------------------------------------------------------------------------ */
typedef struct {
  kit k;
  int dim, n_nodes, n_dofs;
  double X[MAX_DOFS];
  const sk_plugin *plugin;
} scene;

/* One step's positions and times as the tests pass them around. */
typedef struct {
  const double *q_n, *q;
  double t_n, t;
} test_step;

static void scene_init(scene *s, int dim, int n_nodes, const double *X) {
  memset(s, 0, sizeof *s);
  s->dim = dim;
  s->n_nodes = n_nodes;
  s->n_dofs = n_nodes * dim;
  memcpy(s->X, X, (size_t)s->n_dofs * sizeof(double));
  kit_init(&s->k, dim, n_nodes, X);
  s->plugin = stickslip_plugin_entry();
}

static void scene_param(scene *s, const char *key, double value) { kit_param(&s->k, key, value); }

static void scene_slave(scene *s, sk_elem_type type, int nen, int n_faces, const int *conn) {
  kit_surface(&s->k, 0, type, nen, n_faces, conn);
}

static void scene_master(scene *s, sk_elem_type type, int nen, int n_faces, const int *conn) {
  kit_surface(&s->k, 1, type, nen, n_faces, conn);
}

static void scene_obstacle(scene *s, const sk_obstacle *ob) { kit_obstacle(&s->k, ob); }

static sk_status scene_create(scene *s) { return kit_create(&s->k, s->plugin, 0); }

static void scene_destroy(scene *s) { kit_free(&s->k); }

static test_step make_state(const scene *s, const double *q_n, const double *q, double t_n, double t) {
  (void)s;
  test_step st = {q_n, q, t_n, t};
  return st;
}

static void use_step(scene *s, const test_step *st, const double *q) {
  kit_state(&s->k, st->q_n, q ? q : st->q, st->t_n, st->t, NULL);
}

static sk_status scene_begin(scene *s, const test_step *st) {
  use_step(s, st, NULL);
  return kit_begin(&s->k);
}

static sk_status scene_report(scene *s, const test_step *st, sk_contact_report *r) {
  use_step(s, st, NULL);
  return kit_report(&s->k, r);
}

static sk_status scene_update(scene *s, const test_step *st, int *changed) {
  use_step(s, st, NULL);
  return kit_update_active_set(&s->k, st->q, changed);
}

static void scene_reject(scene *s) { s->plugin->reject_step(s->k.instance); }

/* ---- evaluations ------------------------------------------------------------------------------------------------ */
static void residual_at(scene *s, const test_step *step, const double *q, double *F) {
  use_step(s, step, q);
  SK_CHECK(kit_residual(&s->k, q, F) == SK_OK);
}

static void jacobian_at(scene *s, const test_step *step, const double *q, double *K) {
  use_step(s, step, q);
  SK_CHECK(kit_jacobian(&s->k, q, K, NULL) == SK_OK);
}

typedef kit_points point_list;

static void points_at(scene *s, const test_step *step, const double *q, point_list *list) {
  use_step(s, step, q);
  SK_CHECK(kit_points_at(&s->k, list) == SK_OK);
}

static const sk_contact_point *point_of(const point_list *list, int node) { return kit_point_of(list, node); }

/* Penalty energy sum eps/2 <-g>^2 (scenes that use this set area_weighted = 0). */
static double energy_at(scene *s, const test_step *step, const double *q, double eps) {
  point_list list;
  points_at(s, step, q, &list);
  double W = 0.0;
  for (int i = 0; i < list.n; ++i)
    if (list.p[i].state != 0) W += 0.5 * eps * fmin(list.p[i].gap, 0.0) * fmin(list.p[i].gap, 0.0);
  return W;
}

static double max_abs(const double *v, int n) {
  double m = 0.0;
  for (int i = 0; i < n; ++i) m = fmax(m, fabs(v[i]));
  return m;
}

static const double fd_step = 1e-6;

/* Residual against central differences of the energy; the relative error must be below tol. */
static void check_residual_is_energy_gradient(scene *s, const test_step *st, double eps, const char *label) {
  double F[MAX_DOFS], q[MAX_DOFS], err = 0.0;
  residual_at(s, st, st->q, F);
  double scale = max_abs(F, s->n_dofs);
  for (int j = 0; j < s->n_dofs; ++j) {
    memcpy(q, st->q, (size_t)s->n_dofs * sizeof(double));
    q[j] += fd_step;
    double Wp = energy_at(s, st, q, eps);
    q[j] -= 2.0 * fd_step;
    double Wm = energy_at(s, st, q, eps);
    err = fmax(err, fabs((Wp - Wm) / (2.0 * fd_step) - F[j]));
  }
  printf("%-40s residual vs energy: |F| %.3e, max error %.3e\n", label, scale, err);
  SK_CHECK(scale > 0.0);
  SK_CHECK(err <= 1e-6 * scale);
}

/* The assembled Jacobian against central differences of the assembled residual (the kit's checker), inside the
 * pattern the plugin declared. */
/* Central differences with step h: a stiff tangential penalty needs h * eps_t well inside the cone's radius. */
static void check_jacobian_with_step(scene *s, const test_step *st, double h, const char *label) {
  use_step(s, st, NULL);
  double scale = 0.0;
  const double err = kit_fd_check(&s->k, st->q, h, &scale);
  printf("%-40s jacobian vs FD: |K| %.3e, max error %.3e\n", label, scale, err);
  SK_CHECK(scale > 0.0);
  SK_CHECK(err <= 1e-6 * scale);
  SK_CHECK(s->k.outside_pattern == 0);
}

static void check_jacobian_is_residual_derivative(scene *s, const test_step *st, const char *label) {
  check_jacobian_with_step(s, st, fd_step, label);
}

/* Sum of the residual's nodal forces and of their moments about the origin. */
static void force_and_moment_sums(const scene *s, const double *q, const double *F, double sum[3], double moment[3]) {
  int dim = s->dim;
  for (int i = 0; i < 3; ++i) sum[i] = moment[i] = 0.0;
  for (int a = 0; a < s->n_nodes; ++a) {
    double x[3] = {0, 0, 0}, f[3] = {0, 0, 0};
    for (int i = 0; i < dim; ++i) {
      x[i] = q[a * dim + i];
      f[i] = F[a * dim + i];
      sum[i] += f[i];
    }
    moment[0] += x[1] * f[2] - x[2] * f[1];
    moment[1] += x[2] * f[0] - x[0] * f[2];
    moment[2] += x[0] * f[1] - x[1] * f[0];
  }
}

/* Runs one step from q_n to q and commits it. */
static void run_step(scene *s, const double *q_n, const double *q, double t_n, double t) {
  test_step st = make_state(s, q_n, q, t_n, t);
  SK_CHECK(scene_begin(s, &st) == SK_OK);
  SK_CHECK(kit_commit(&s->k) == SK_OK);
}

static int count_state(const point_list *list, int state) {
  int c = 0;
  for (int i = 0; i < list->n; ++i) c += list->p[i].state == state;
  return c;
}

/* ---- frictionless, deformable masters -------------------------------------------------------------------------- */

/* 2D: a tilted LINE2 master (normal up) and a LINE2 slave with both nodes penetrating. */
static void test_line2_frictionless(void) {
  const double X[] = {2.0, 0.1, 0.0, -0.05, 0.6, -0.06, 1.5, 0.0};
  scene s;
  scene_init(&s, 2, 4, X);
  const int master[] = {0, 1}, slave[] = {2, 3};
  scene_master(&s, SK_LINE2, 2, 1, master);
  scene_slave(&s, SK_LINE2, 2, 1, slave);
  scene_param(&s, "penalty", 1e3);
  scene_param(&s, "area_weighted", 0);
  SK_CHECK(scene_create(&s) == SK_OK);
  test_step st = make_state(&s, s.X, s.X, 0.0, 1.0);
  SK_CHECK(scene_begin(&s, &st) == SK_OK);
  point_list list;
  points_at(&s, &st, s.X, &list);
  SK_CHECK(list.n == 2 && count_state(&list, 0) == 0);
  check_residual_is_energy_gradient(&s, &st, 1e3, "2D line2 frictionless");
  check_jacobian_is_residual_derivative(&s, &st, "2D line2 frictionless");

  double F[MAX_DOFS], sum[3], moment[3];
  residual_at(&s, &st, s.X, F);
  force_and_moment_sums(&s, s.X, F, sum, moment);
  double scale = max_abs(F, s.n_dofs);
  SK_CHECK(fabs(sum[0]) + fabs(sum[1]) <= 1e-12 * scale);
  SK_CHECK(fabs(moment[2]) <= 1e-12 * scale);

  /* The report: force on the slave = -(slave rows of F), penetration = max(-g). */
  sk_contact_report r;
  SK_CHECK(scene_report(&s, &st, &r) == SK_OK);
  SK_CHECK(r.active == 2);
  SK_CHECK_CLOSE(r.force[0], -(F[4] + F[6]), 1e-12);
  SK_CHECK_CLOSE(r.force[1], -(F[5] + F[7]), 1e-12);
  SK_CHECK_CLOSE(r.constraint_norm, fmax(-list.p[0].gap, -list.p[1].gap), 1e-12);
  scene_destroy(&s);
}

/* 2D: a curved LINE3 master (nodes: end, end, middle). */
static void test_line3_frictionless(void) {
  const double X[] = {2.0, 0.0, 0.0, 0.0, 1.0, 0.2, 0.4, 0.05, 1.3, 0.12, 1.8, 0.5};
  scene s;
  scene_init(&s, 2, 6, X);
  const int master[] = {0, 1, 2}, slave[] = {3, 4, 4, 5};
  scene_master(&s, SK_LINE3, 3, 1, master);
  scene_slave(&s, SK_LINE2, 2, 2, slave);
  scene_param(&s, "penalty", 500.0);
  scene_param(&s, "area_weighted", 0);
  SK_CHECK(scene_create(&s) == SK_OK);
  test_step st = make_state(&s, s.X, s.X, 0.0, 1.0);
  SK_CHECK(scene_begin(&s, &st) == SK_OK);
  point_list list;
  points_at(&s, &st, s.X, &list);
  SK_CHECK(count_state(&list, 1) == 2); /* nodes 3 and 4 penetrate, node 5 is above */
  check_residual_is_energy_gradient(&s, &st, 500.0, "2D line3 frictionless");
  check_jacobian_is_residual_derivative(&s, &st, "2D line3 frictionless");
  scene_destroy(&s);
}

/* 3D: a warped QUAD4 master; slave QUAD4 with a point near the master edge xi = 1 and one node outside contact. */
static void test_quad4_frictionless(void) {
  const double X[] = {0.0, 0.0, 0.0,  2.0, 0.0, 0.1,   2.0, 2.0, -0.05, 0.0, 2.0, 0.08,
                      0.5, 0.7, -0.02, 1.97, 0.6, 0.03, 1.2, 1.6, -0.01, 0.4, 1.5, 0.3};
  scene s;
  scene_init(&s, 3, 8, X);
  const int master[] = {0, 1, 2, 3}, slave[] = {4, 7, 6, 5};
  scene_master(&s, SK_QUAD4, 4, 1, master);
  scene_slave(&s, SK_QUAD4, 4, 1, slave);
  scene_param(&s, "penalty", 1e3);
  scene_param(&s, "area_weighted", 0);
  SK_CHECK(scene_create(&s) == SK_OK);
  test_step st = make_state(&s, s.X, s.X, 0.0, 1.0);
  SK_CHECK(scene_begin(&s, &st) == SK_OK);
  point_list list;
  points_at(&s, &st, s.X, &list);
  SK_CHECK(count_state(&list, 1) == 3);
  const sk_contact_point *p7 = point_of(&list, 7);
  SK_CHECK(p7 && p7->state == 0 && p7->gap > 0.1);
  check_residual_is_energy_gradient(&s, &st, 1e3, "3D quad4 frictionless (near edge)");
  check_jacobian_is_residual_derivative(&s, &st, "3D quad4 frictionless (near edge)");

  double F[MAX_DOFS], sum[3], moment[3];
  residual_at(&s, &st, s.X, F);
  force_and_moment_sums(&s, s.X, F, sum, moment);
  double scale = max_abs(F, s.n_dofs);
  for (int i = 0; i < 3; ++i) {
    SK_CHECK(fabs(sum[i]) <= 1e-12 * scale);
    SK_CHECK(fabs(moment[i]) <= 1e-12 * scale);
  }
  scene_destroy(&s);
}

/* 3D: a curved QUAD9 master z = 0.2 (x-1)^2 - 0.1 (y-1)^2 + 0.05 x y on [0,2]^2, TRI3 slave. */
static void test_quad9_frictionless(void) {
  const double node_xi[9][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}, {0, -1}, {1, 0}, {0, 1}, {-1, 0}, {0, 0}};
  double X[12 * 3];
  for (int a = 0; a < 9; ++a) {
    double x = 1.0 + node_xi[a][0], y = 1.0 + node_xi[a][1];
    X[3 * a] = x;
    X[3 * a + 1] = y;
    X[3 * a + 2] = 0.2 * (x - 1) * (x - 1) - 0.1 * (y - 1) * (y - 1) + 0.05 * x * y;
  }
  const double slave_x[3][3] = {{0.3, 0.4, 0.03}, {1.6, 0.5, 0.05}, {1.1, 1.8, 0.0}};
  for (int a = 0; a < 3; ++a) memcpy(X + 3 * (9 + a), slave_x[a], sizeof slave_x[a]);
  scene s;
  scene_init(&s, 3, 12, X);
  const int master[] = {0, 1, 2, 3, 4, 5, 6, 7, 8}, slave[] = {9, 11, 10};
  scene_master(&s, SK_QUAD9, 9, 1, master);
  scene_slave(&s, SK_TRI3, 3, 1, slave);
  scene_param(&s, "penalty", 2e3);
  scene_param(&s, "area_weighted", 0);
  SK_CHECK(scene_create(&s) == SK_OK);
  test_step st = make_state(&s, s.X, s.X, 0.0, 1.0);
  SK_CHECK(scene_begin(&s, &st) == SK_OK);
  point_list list;
  points_at(&s, &st, s.X, &list);
  SK_CHECK(count_state(&list, 1) == 3);
  check_residual_is_energy_gradient(&s, &st, 2e3, "3D quad9 curved frictionless");
  check_jacobian_is_residual_derivative(&s, &st, "3D quad9 curved frictionless");
  scene_destroy(&s);

  /* Friction on the curved face (Christoffel terms x,ab . a^c enter the tangent through the metric variation). */
  for (int slip = 0; slip <= 1; ++slip) {
    scene_init(&s, 3, 12, X);
    scene_master(&s, SK_QUAD9, 9, 1, master);
    scene_slave(&s, SK_TRI3, 3, 1, slave);
    scene_param(&s, "penalty", 2e3);
    scene_param(&s, "area_weighted", 0);
    scene_param(&s, "mu", 0.3);
    scene_param(&s, "penalty_tangential", 1e3);
    SK_CHECK(scene_create(&s) == SK_OK);
    double q1[36], q2[36];
    memcpy(q1, X, sizeof q1);
    for (int a = 9; a < 12; ++a) {
      q1[3 * a] += 0.003;
      q1[3 * a + 2] -= 0.01;
    }
    run_step(&s, X, q1, 0.0, 1.0);
    memcpy(q2, q1, sizeof q2);
    for (int a = 9; a < 12; ++a) {
      q2[3 * a] -= slip ? 0.05 : 0.0004;
      q2[3 * a + 1] += slip ? 0.03 : 0.0002;
    }
    q2[3 * 8 + 2] += 0.02; /* the master's middle node rises: the face changes shape during the step */
    test_step fs = make_state(&s, q1, q2, 1.0, 2.0);
    SK_CHECK(scene_begin(&s, &fs) == SK_OK);
    point_list fl;
    points_at(&s, &fs, q2, &fl);
    SK_CHECK(count_state(&fl, slip ? 2 : 1) == 3);
    check_jacobian_is_residual_derivative(&s, &fs, slip ? "3D quad9 friction slip" : "3D quad9 friction stick");
    scene_destroy(&s);
  }
}

/* A stuck slave node carried across the shared end of two collinear LINE2 faces: the anchor moves to the new face
 * through the tangent plane, so on a flat master the traction stays exactly -eps_t (total tangential move). */
static void test_friction_face_crossing(void) {
  const double X[] = {2.0, 0.0, 0.0, 0.0, -2.0, 0.0, 0.1, -0.01, 1.0, 0.5};
  const double eps_t = 300.0;
  scene s;
  scene_init(&s, 2, 5, X);
  const int master[] = {0, 1, 1, 2}, slave[] = {3, 4};
  scene_master(&s, SK_LINE2, 2, 2, master);
  scene_slave(&s, SK_LINE2, 2, 1, slave);
  scene_param(&s, "penalty", 1e3);
  scene_param(&s, "mu", 10.0);
  scene_param(&s, "penalty_tangential", eps_t);
  scene_param(&s, "area_weighted", 0);
  SK_CHECK(scene_create(&s) == SK_OK);
  double q1[10], q2[10], q3[10];
  memcpy(q1, X, sizeof q1);
  q1[7] = -0.02;
  run_step(&s, X, q1, 0.0, 1.0);
  memcpy(q2, q1, sizeof q2);
  q2[6] -= 0.002;
  run_step(&s, q1, q2, 1.0, 2.0);
  memcpy(q3, q2, sizeof q3);
  q3[6] -= 0.2; /* now at x = -0.102, on the second face */
  test_step st = make_state(&s, q2, q3, 2.0, 3.0);
  SK_CHECK(scene_begin(&s, &st) == SK_OK);
  point_list list;
  points_at(&s, &st, q3, &list);
  const sk_contact_point *p = point_of(&list, 3);
  SK_CHECK(p && p->state == 1);
  if (p) {
    SK_CHECK_CLOSE(p->traction[0], eps_t * 0.202, 1e-10);
    SK_CHECK(fabs(p->traction[1]) <= 1e-12);
  }
  scene_destroy(&s);
}

/* ---- friction ------------------------------------------------------------------------------------------------------ */

/* 2D flat master y = 0 (normal up), one slave node pressed in, then moved sideways by dx: the analytic stick
 * traction is -eps_t dx, slip gives |t| = mu p with dissipation mu p (eps_t dx - mu p)/eps_t. */
static void test_friction_2d_flat_return_map(void) {
  const double X[] = {2.0, 0.0, -1.0, 0.0, 0.3, -0.01, 0.9, 0.5};
  const double eps = 1e3, eps_t = 500.0, mu = 0.3;
  for (int slip = 0; slip <= 1; ++slip) {
    scene s;
    scene_init(&s, 2, 4, X);
    const int master[] = {0, 1}, slave[] = {2, 3};
    scene_master(&s, SK_LINE2, 2, 1, master);
    scene_slave(&s, SK_LINE2, 2, 1, slave);
    scene_param(&s, "penalty", eps);
    scene_param(&s, "mu", mu);
    scene_param(&s, "penalty_tangential", eps_t);
    scene_param(&s, "area_weighted", 0);
    SK_CHECK(scene_create(&s) == SK_OK);
    double q1[8], q2[8];
    memcpy(q1, X, sizeof q1);
    q1[5] = -0.02; /* step 1: pressed straight down, no tangential traction */
    run_step(&s, X, q1, 0.0, 1.0);
    memcpy(q2, q1, sizeof q2);
    double dx = slip ? 0.02 : 0.002; /* mu p = 6; eps_t dx = 1 (stick) or 10 (slip) */
    q2[4] += dx;
    test_step st = make_state(&s, q1, q2, 1.0, 2.0);
    SK_CHECK(scene_begin(&s, &st) == SK_OK);
    point_list list;
    points_at(&s, &st, q2, &list);
    const sk_contact_point *p = point_of(&list, 2);
    SK_CHECK(p != NULL);
    if (!p) continue;
    double pressure = eps * 0.02;
    SK_CHECK_CLOSE(p->pressure, pressure, 1e-12);
    SK_CHECK_CLOSE(p->gap, -0.02, 1e-12);
    double t_norm = hypot(p->traction[0], p->traction[1]);
    SK_CHECK(t_norm <= mu * pressure * (1.0 + 1e-14));
    sk_contact_report r;
    SK_CHECK(scene_report(&s, &st, &r) == SK_OK);
    if (!slip) {
      SK_CHECK(p->state == 1 && r.stick == 1 && r.slip == 0);
      SK_CHECK_CLOSE(p->traction[0], -eps_t * dx, 1e-10);
      SK_CHECK(fabs(p->traction[1]) <= 1e-12);
      SK_CHECK(r.dissipated == 0.0);
    } else {
      SK_CHECK(p->state == 2 && r.slip == 1 && r.stick == 0);
      SK_CHECK_CLOSE(p->traction[0], -mu * pressure, 1e-12);
      SK_CHECK_CLOSE(r.dissipated, mu * pressure * (eps_t * dx - mu * pressure) / eps_t, 1e-12);
    }
    /* Force on the slave: p n + t. */
    SK_CHECK_CLOSE(r.force[0], p->traction[0], 1e-12);
    SK_CHECK_CLOSE(r.force[1], pressure, 1e-12);
    check_jacobian_is_residual_derivative(&s, &st, slip ? "2D flat friction slip" : "2D flat friction stick");
    scene_destroy(&s);
  }
}

/* 3D warped QUAD4 with friction. Step 1 presses and shifts (history with a nonzero covariant traction), step 2
 * moves the slave nodes further: small moves stick, large ones slip. The Jacobian (consistent tangent of the
 * return map, metric and normal variations included) must match central differences; forces must balance. */
static void quad4_friction_scene_eps(scene *s, const double R[9], const double c[3], double q0[24], double q1[24],
                                     double q2[24], double move, double eps_t) {
  const double X[] = {0.0, 0.0, 0.0,  2.0, 0.0, 0.1,   2.0, 2.0, -0.05, 0.0, 2.0, 0.08,
                      0.5, 0.7, 0.02, 1.5, 0.6, 0.08,  1.2, 1.6, 0.05,  0.4, 1.5, 0.3};
  double Xr[24];
  for (int a = 0; a < 8; ++a)
    for (int i = 0; i < 3; ++i)
      Xr[3 * a + i] = c[i] + R[3 * i] * X[3 * a] + R[3 * i + 1] * X[3 * a + 1] + R[3 * i + 2] * X[3 * a + 2];
  scene_init(s, 3, 8, Xr);
  const int master[] = {0, 1, 2, 3}, slave[] = {4, 7, 6, 5};
  scene_master(s, SK_QUAD4, 4, 1, master);
  scene_slave(s, SK_QUAD4, 4, 1, slave);
  scene_param(s, "penalty", 1e3);
  scene_param(s, "mu", 0.4);
  scene_param(s, "penalty_tangential", eps_t);
  scene_param(s, "area_weighted", 0);
  /* Displacements in the unrotated frame: step 1 down by 0.08 with a small shift, step 2 sideways by `move`. */
  double u1[3] = {0.004, -0.003, -0.08}, u2[3] = {move, 0.6 * move, 0.0};
  for (int a = 0; a < 8; ++a)
    for (int i = 0; i < 3; ++i) {
      double d1 = a >= 4 ? R[3 * i] * u1[0] + R[3 * i + 1] * u1[1] + R[3 * i + 2] * u1[2] : 0.0;
      double d2 = a >= 4 ? R[3 * i] * u2[0] + R[3 * i + 1] * u2[1] + R[3 * i + 2] * u2[2] : 0.0;
      q0[3 * a + i] = Xr[3 * a + i];
      q1[3 * a + i] = Xr[3 * a + i] + d1;
      q2[3 * a + i] = Xr[3 * a + i] + d1 + d2;
    }
  /* A deformed master in step 2 as well, so the metric changes. */
  for (int i = 0; i < 3; ++i) q2[3 * 2 + i] += 0.003 * R[3 * i] + 0.01 * R[3 * i + 2];
}

static void quad4_friction_scene(scene *s, const double R[9], const double c[3], double q0[24], double q1[24],
                                 double q2[24], double move) {
  quad4_friction_scene_eps(s, R, c, q0, q1, q2, move, 800.0);
}

static const double identity3[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
static const double origin3[3] = {0, 0, 0};

static void test_friction_3d_quad4(void) {
  for (int slip = 0; slip <= 1; ++slip) {
    scene s;
    double q0[24], q1[24], q2[24];
    quad4_friction_scene(&s, identity3, origin3, q0, q1, q2, slip ? 0.08 : 0.0005);
    SK_CHECK(scene_create(&s) == SK_OK);
    run_step(&s, q0, q1, 0.0, 1.0);
    test_step st = make_state(&s, q1, q2, 1.0, 2.0);
    SK_CHECK(scene_begin(&s, &st) == SK_OK);
    point_list list;
    points_at(&s, &st, q2, &list);
    SK_CHECK(count_state(&list, slip ? 2 : 1) == 3);
    for (int i = 0; i < list.n; ++i) {
      const sk_contact_point *p = &list.p[i];
      if (p->state == 0) continue;
      double t_norm = sqrt(p->traction[0] * p->traction[0] + p->traction[1] * p->traction[1] +
                           p->traction[2] * p->traction[2]);
      SK_CHECK(t_norm > 0.0);
      SK_CHECK(fabs(p->traction[0] * p->normal[0] + p->traction[1] * p->normal[1] + p->traction[2] * p->normal[2]) <=
               1e-12 * t_norm);
      if (slip) SK_CHECK_CLOSE(t_norm, 0.4 * p->pressure, 1e-12);
      else SK_CHECK(t_norm < 0.4 * p->pressure);
    }
    check_jacobian_is_residual_derivative(&s, &st, slip ? "3D quad4 friction slip" : "3D quad4 friction stick");

    /* Linear momentum: sum of forces = 0. Angular momentum: with friction the moment of the pair is
     * -sum g n x t (tangential forces at x_s and x_m differ by g n), not zero. */
    double F[MAX_DOFS], sum[3], moment[3], expected[3] = {0, 0, 0};
    residual_at(&s, &st, q2, F);
    force_and_moment_sums(&s, q2, F, sum, moment);
    double scale = max_abs(F, s.n_dofs);
    for (int i = 0; i < list.n; ++i) {
      const sk_contact_point *p = &list.p[i];
      if (p->state == 0) continue;
      const double *n = p->normal, *t = p->traction;
      double g = p->gap;
      expected[0] -= g * (n[1] * t[2] - n[2] * t[1]);
      expected[1] -= g * (n[2] * t[0] - n[0] * t[2]);
      expected[2] -= g * (n[0] * t[1] - n[1] * t[0]);
    }
    for (int i = 0; i < 3; ++i) {
      SK_CHECK(fabs(sum[i]) <= 1e-12 * scale);
      SK_CHECK(fabs(moment[i] - expected[i]) <= 1e-12 * scale);
    }
    SK_CHECK(fabs(expected[0]) + fabs(expected[1]) + fabs(expected[2]) > 1e-6 * scale);
    scene_destroy(&s);
  }
}

/* Frame indifference: the same history and step in a rotated and translated frame give rotated forces and the
 * same gaps, pressures and states. And a superposed rigid rotation of the whole pair after a stuck step (no
 * relative motion) keeps the covariant traction: the spatial traction rotates with it and nothing slips. */
static void rotation(double angle, const double axis_in[3], double R[9]) {
  double n = sqrt(axis_in[0] * axis_in[0] + axis_in[1] * axis_in[1] + axis_in[2] * axis_in[2]);
  double k[3] = {axis_in[0] / n, axis_in[1] / n, axis_in[2] / n}, c = cos(angle), s = sin(angle);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) R[3 * i + j] = (i == j ? c : 0.0) + (1 - c) * k[i] * k[j];
  R[1] -= s * k[2];
  R[2] += s * k[1];
  R[3] += s * k[2];
  R[5] -= s * k[0];
  R[6] -= s * k[1];
  R[7] += s * k[0];
}

static void apply(const double R[9], const double c[3], const double *x, double *y) {
  for (int i = 0; i < 3; ++i) y[i] = c[i] + R[3 * i] * x[0] + R[3 * i + 1] * x[1] + R[3 * i + 2] * x[2];
}

static void test_frame_indifference(void) {
  const double axis[3] = {0.3, -0.5, 0.8}, shift[3] = {1.5, -2.0, 0.7};
  double R[9];
  rotation(0.9, axis, R);
  for (int slip = 0; slip <= 1; ++slip) {
    scene a, b;
    double a0[24], a1[24], a2[24], b0[24], b1[24], b2[24];
    double move = slip ? 0.08 : 0.0005;
    quad4_friction_scene(&a, identity3, origin3, a0, a1, a2, move);
    quad4_friction_scene(&b, R, shift, b0, b1, b2, move);
    SK_CHECK(scene_create(&a) == SK_OK && scene_create(&b) == SK_OK);
    run_step(&a, a0, a1, 0.0, 1.0);
    run_step(&b, b0, b1, 0.0, 1.0);
    test_step sa = make_state(&a, a1, a2, 1.0, 2.0), sb = make_state(&b, b1, b2, 1.0, 2.0);
    SK_CHECK(scene_begin(&a, &sa) == SK_OK && scene_begin(&b, &sb) == SK_OK);
    double Fa[MAX_DOFS], Fb[MAX_DOFS];
    residual_at(&a, &sa, a2, Fa);
    residual_at(&b, &sb, b2, Fb);
    double scale = max_abs(Fa, 24), err = 0.0;
    for (int n = 0; n < 8; ++n) {
      double rotated[3];
      apply(R, origin3, Fa + 3 * n, rotated);
      for (int i = 0; i < 3; ++i) err = fmax(err, fabs(rotated[i] - Fb[3 * n + i]));
    }
    printf("frame indifference (%s): |F| %.3e, max error %.3e\n", slip ? "slip" : "stick", scale, err);
    SK_CHECK(scale > 0.0 && err <= 1e-10 * scale);
    point_list la, lb;
    points_at(&a, &sa, a2, &la);
    points_at(&b, &sb, b2, &lb);
    SK_CHECK(la.n == lb.n);
    for (int i = 0; i < la.n && i < lb.n; ++i) {
      SK_CHECK(la.p[i].state == lb.p[i].state);
      if (la.p[i].state == 0) continue;
      SK_CHECK_CLOSE(lb.p[i].gap, la.p[i].gap, 1e-10);
      SK_CHECK_CLOSE(lb.p[i].pressure, la.p[i].pressure, 1e-10);
    }
    scene_destroy(&a);
    scene_destroy(&b);
  }

  /* Superposed rigid rotation of a stuck configuration: a1 (committed, stuck with traction) -> R a1 + shift. */
  scene s;
  double q0[24], q1[24], q2[24], q3[24];
  quad4_friction_scene(&s, identity3, origin3, q0, q1, q2, 0.0005);
  SK_CHECK(scene_create(&s) == SK_OK);
  run_step(&s, q0, q1, 0.0, 1.0);
  run_step(&s, q1, q2, 1.0, 2.0); /* stuck with a traction, committed */
  test_step st2 = make_state(&s, q1, q2, 1.0, 2.0);
  point_list before, after;
  points_at(&s, &st2, q2, &before); /* history now committed: evaluating at q2 again gives the same as the trial */
  for (int n = 0; n < 8; ++n) apply(R, shift, q2 + 3 * n, q3 + 3 * n);
  test_step st3 = make_state(&s, q2, q3, 2.0, 3.0);
  SK_CHECK(scene_begin(&s, &st3) == SK_OK);
  points_at(&s, &st3, q3, &after);
  SK_CHECK(before.n == after.n);
  double tmax = 0.0;
  for (int i = 0; i < before.n && i < after.n; ++i) {
    if (before.p[i].state == 0) continue;
    SK_CHECK(after.p[i].state == 1);
    double rotated[3];
    apply(R, origin3, before.p[i].traction, rotated);
    for (int k = 0; k < 3; ++k) {
      SK_CHECK(fabs(after.p[i].traction[k] - rotated[k]) <= 1e-9);
      tmax = fmax(tmax, fabs(rotated[k]));
    }
    SK_CHECK_CLOSE(after.p[i].pressure, before.p[i].pressure, 1e-10);
  }
  SK_CHECK(tmax > 1e-3); /* the traction carried through the rotation is not trivial */
  scene_destroy(&s);
}

/* ---- rigid obstacles ------------------------------------------------------------------------------------------------ */
static void obstacle_scene(scene *s, int dim, const sk_obstacle *ob, double mu) {
  if (dim == 3) {
    const double X[] = {0.5, 0.2, 0.04, -0.4, 0.3, 0.01, 0.1, -0.5, 0.02};
    scene_init(s, 3, 3, X);
    const int slave[] = {0, 1, 2};
    scene_slave(s, SK_TRI3, 3, 1, slave);
  } else {
    const double X[] = {0.3, 0.04, -0.4, 0.01, -0.9, 0.4};
    scene_init(s, 2, 3, X);
    const int slave[] = {0, 1, 1, 2};
    scene_slave(s, SK_LINE2, 2, 2, slave);
  }
  scene_obstacle(s, ob);
  scene_param(s, "penalty", 1e3);
  scene_param(s, "area_weighted", 0);
  if (mu > 0.0) {
    scene_param(s, "mu", mu);
    scene_param(s, "penalty_tangential", 700.0);
  }
}

static void test_obstacles(void) {
  sk_obstacle plane, sphere, parabola, circle;
  memset(&plane, 0, sizeof plane);
  plane.kind = SK_OBSTACLE_PLANE;
  double nn = sqrt(0.01 + 0.04 + 1.0);
  plane.normal[0] = 0.1 / nn;
  plane.normal[1] = 0.2 / nn;
  plane.normal[2] = 1.0 / nn;
  plane.n_motion = 2;
  plane.motion_t[1] = 1.0;
  for (int i = 0; i < 3; ++i) plane.motion_d[1][i] = 0.2 * plane.normal[i]; /* rises: all penetrate at t = 1 */
  sphere = plane;
  sphere.kind = SK_OBSTACLE_SPHERE;
  sphere.n_motion = 0;
  sphere.point[2] = -1.0;
  sphere.radius = 1.2;
  parabola = sphere;
  parabola.kind = SK_OBSTACLE_PARABOLIC_CYLINDER;
  parabola.point[2] = 0.05;
  parabola.axis[1] = 1.0;
  parabola.normal[0] = parabola.normal[1] = 0.0;
  parabola.normal[2] = 1.0;
  parabola.c = 0.3;
  circle = sphere;
  circle.point[1] = -1.0;
  circle.point[2] = 0.0;
  const struct {
    const char *label;
    int dim;
    const sk_obstacle *ob;
  } cases[] = {{"plane (moving)", 3, &plane}, {"sphere", 3, &sphere}, {"parabolic cylinder", 3, &parabola},
               {"2D circle", 2, &circle}};
  for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
    char label[96];
    scene s;
    obstacle_scene(&s, cases[c].dim, cases[c].ob, 0.0);
    SK_CHECK(scene_create(&s) == SK_OK);
    test_step st = make_state(&s, s.X, s.X, 0.0, 1.0);
    SK_CHECK(scene_begin(&s, &st) == SK_OK);
    point_list list;
    points_at(&s, &st, s.X, &list);
    SK_CHECK(count_state(&list, 1) >= 2);
    if (cases[c].ob == &plane) /* gap against the plane translated to t = 1 */
      for (int i = 0; i < list.n; ++i) {
        const double *x = list.p[i].x;
        double g = x[0] * plane.normal[0] + x[1] * plane.normal[1] + x[2] * plane.normal[2] - 0.2;
        SK_CHECK_CLOSE(list.p[i].gap, g, 1e-12);
      }
    if (cases[c].ob == &sphere)
      for (int i = 0; i < list.n; ++i) {
        const double *x = list.p[i].x;
        SK_CHECK_CLOSE(list.p[i].gap, sqrt(x[0] * x[0] + x[1] * x[1] + (x[2] + 1.0) * (x[2] + 1.0)) - 1.2, 1e-12);
      }
    snprintf(label, sizeof label, "obstacle %s", cases[c].label);
    check_residual_is_energy_gradient(&s, &st, 1e3, label);
    check_jacobian_is_residual_derivative(&s, &st, label);
    scene_destroy(&s);

    /* Friction against the obstacle: commit a pressed state, then slide: mu = 0.3 with a tiny move sticks,
     * mu = 0.02 with a move of 0.01 slips. */
    for (int slip = 0; slip <= 1; ++slip) {
      double mu = slip ? 0.02 : 0.3;
      obstacle_scene(&s, cases[c].dim, cases[c].ob, mu);
      SK_CHECK(scene_create(&s) == SK_OK);
      double q1[9], q2[9];
      int nd = s.n_dofs, dim = s.dim;
      memcpy(q1, s.X, (size_t)nd * sizeof(double));
      for (int a = 0; a < 3; ++a) q1[a * dim + dim - 1] -= 0.01;
      run_step(&s, s.X, q1, 0.0, 0.5);
      memcpy(q2, q1, (size_t)nd * sizeof(double));
      for (int a = 0; a < 3; ++a) q2[a * dim] += slip ? 0.01 : 0.0003;
      test_step fs = make_state(&s, q1, q2, 0.5, 1.0);
      SK_CHECK(scene_begin(&s, &fs) == SK_OK);
      points_at(&s, &fs, q2, &list);
      int active = 0;
      for (int i = 0; i < list.n; ++i) {
        const sk_contact_point *p = &list.p[i];
        if (p->state == 0) continue;
        ++active;
        SK_CHECK(p->state == (slip ? 2 : 1));
        double t = sqrt(p->traction[0] * p->traction[0] + p->traction[1] * p->traction[1] +
                        p->traction[2] * p->traction[2]);
        if (slip) SK_CHECK_CLOSE(t, mu * p->pressure, 1e-12);
        else SK_CHECK(t > 0.0 && t < mu * p->pressure);
      }
      SK_CHECK(active >= 2);
      snprintf(label, sizeof label, "obstacle %s friction %s", cases[c].label, slip ? "slip" : "stick");
      check_jacobian_is_residual_derivative(&s, &fs, label);
      scene_destroy(&s);
    }
  }
}

/* ---- areas, parameters, history ----------------------------------------------------------------------------------- */

/* Tributary areas: a 2D slave of two LINE2 faces of length 1 and 2 above a flat master; every node penetrates by
 * 0.01, so the nodal forces are eps * A * 0.01 with A = 0.5, 1.5, 1 and the reported pressure is eps * 0.01. */
static void test_area_weighting(void) {
  const double X[] = {10.0, 0.0, -10.0, 0.0, 0.0, -0.01, 1.0, -0.01, 3.0, -0.01};
  scene s;
  scene_init(&s, 2, 5, X);
  const int master[] = {0, 1}, slave[] = {2, 3, 3, 4};
  scene_master(&s, SK_LINE2, 2, 1, master);
  scene_slave(&s, SK_LINE2, 2, 2, slave);
  scene_param(&s, "penalty", 200.0);
  SK_CHECK(scene_create(&s) == SK_OK);
  test_step st = make_state(&s, s.X, s.X, 0.0, 1.0);
  SK_CHECK(scene_begin(&s, &st) == SK_OK);
  double F[MAX_DOFS];
  residual_at(&s, &st, s.X, F);
  const double area[3] = {0.5, 1.5, 1.0};
  for (int k = 0; k < 3; ++k) SK_CHECK_CLOSE(-F[(2 + k) * 2 + 1], 200.0 * area[k] * 0.01, 1e-12);
  point_list list;
  points_at(&s, &st, s.X, &list);
  SK_CHECK(list.n == 3);
  for (int i = 0; i < list.n; ++i) SK_CHECK_CLOSE(list.p[i].pressure, 2.0, 1e-12);
  scene_destroy(&s);
}

/* Just touching (g = 0): no force, but the penetrating side's stiffness eps n n^T, so a body resting on the master
 * without other support still gives a regular Newton matrix. A node 1e-3 above stays inactive. */
static void test_touching_is_active(void) {
  const double X[] = {10.0, 0.0, -10.0, 0.0, 0.0, 0.0, 1.0, 1e-3};
  scene s;
  scene_init(&s, 2, 4, X);
  const int master[] = {0, 1}, slave[] = {2, 3};
  scene_master(&s, SK_LINE2, 2, 1, master);
  scene_slave(&s, SK_LINE2, 2, 1, slave);
  scene_param(&s, "penalty", 300.0);
  scene_param(&s, "area_weighted", 0);
  SK_CHECK(scene_create(&s) == SK_OK);
  test_step st = make_state(&s, s.X, s.X, 0.0, 1.0);
  SK_CHECK(scene_begin(&s, &st) == SK_OK);
  double F[MAX_DOFS];
  static double K[MAX_DOFS * MAX_DOFS];
  residual_at(&s, &st, s.X, F);
  jacobian_at(&s, &st, s.X, K);
  SK_CHECK(max_abs(F, s.n_dofs) == 0.0);
  SK_CHECK_CLOSE(K[5 * 8 + 5], 300.0, 1e-12); /* slave node 2, y row and column */
  for (int j = 6; j < 8; ++j) SK_CHECK(K[j * 8 + j] == 0.0);
  sk_contact_report r;
  SK_CHECK(scene_report(&s, &st, &r) == SK_OK);
  SK_CHECK(r.active == 1 && r.constraint_norm == 0.0 && r.force[1] == 0.0);
  scene_destroy(&s);
}

/* Beyond the master's border: a node 1% of a face past the end of a tilted LINE2 master stays in contact with the
 * extrapolated segment (residual and Jacobian still exact); 30% past it, or with master_extension = 0, it is out. */
static void test_master_extension(void) {
  for (int variant = 0; variant < 3; ++variant) {
    double beyond = variant == 1 ? 0.6 : 0.02;
    const double X[] = {2.0, 0.1, 0.0, -0.05, 0.6, -0.06, 2.0 + beyond, 0.1 + 0.075 * beyond - 0.03};
    scene s;
    scene_init(&s, 2, 4, X);
    const int master[] = {0, 1}, slave[] = {2, 3};
    scene_master(&s, SK_LINE2, 2, 1, master);
    scene_slave(&s, SK_LINE2, 2, 1, slave);
    scene_param(&s, "penalty", 1e3);
    scene_param(&s, "area_weighted", 0);
    if (variant == 2) scene_param(&s, "master_extension", 0.0);
    SK_CHECK(scene_create(&s) == SK_OK);
    test_step st = make_state(&s, s.X, s.X, 0.0, 1.0);
    SK_CHECK(scene_begin(&s, &st) == SK_OK);
    point_list list;
    points_at(&s, &st, s.X, &list);
    const sk_contact_point *p = point_of(&list, 3);
    SK_CHECK(p != NULL);
    if (!p) continue;
    if (variant == 0) {
      SK_CHECK(p->state == 1);
      SK_CHECK_CLOSE(p->gap, -0.03 * 2.0 / sqrt(4.0 + 0.15 * 0.15), 1e-12); /* distance to the extended line */
      check_residual_is_energy_gradient(&s, &st, 1e3, "2D line2 beyond the border (extended)");
      check_jacobian_is_residual_derivative(&s, &st, "2D line2 beyond the border (extended)");
    } else {
      SK_CHECK(p->state == 0);
    }
    scene_destroy(&s);
  }
}

static void expect_create_error(const char *what, const char *key, double value, const char *key2, double value2,
                                const char *needle) {
  const double X[] = {1.0, 0.0, -1.0, 0.0, 0.0, 0.1, 0.5, 0.1};
  scene s;
  scene_init(&s, 2, 4, X);
  const int master[] = {0, 1}, slave[] = {2, 3};
  scene_master(&s, SK_LINE2, 2, 1, master);
  scene_slave(&s, SK_LINE2, 2, 1, slave);
  if (key) scene_param(&s, key, value);
  if (key2) scene_param(&s, key2, value2);
  sk_error_clear();
  sk_status status = scene_create(&s);
  if (status == SK_OK) fprintf(stderr, "%s: create succeeded\n", what);
  SK_CHECK(status == SK_ERR_INPUT);
  SK_CHECK(s.k.instance == NULL);
  if (!strstr(sk_error_message(), needle)) fprintf(stderr, "%s: message '%s'\n", what, sk_error_message());
  SK_CHECK(strstr(sk_error_message(), needle) != NULL);
  scene_destroy(&s);
}

static void test_parameter_errors(void) {
  expect_create_error("negative penalty", "penalty", -1.0, NULL, 0, "'penalty'");
  expect_create_error("negative tangential penalty", "mu", 0.2, "penalty_tangential", -1.0, "'penalty_tangential'");
  expect_create_error("negative mu", "penalty", 1.0, "mu", -0.2, "'mu'");
  expect_create_error("bad area_weighted", "penalty", 1.0, "area_weighted", 2, "'area_weighted'");
  expect_create_error("negative margin", "penalty", 1.0, "search_margin", -1, "'search_margin'");
  expect_create_error("extension too large", "penalty", 1.0, "master_extension", 0.7, "'master_extension'");

  const sk_plugin *pl = stickslip_plugin_entry();
  SK_CHECK(pl->abi_major == SK_ABI_MAJOR && pl->kinds == SK_KIND_PAIR);
  SK_CHECK(strcmp(pl->name, "penalty-nts") == 0);
  SK_CHECK(strcmp(pl->strategies[0], "none") == 0 && pl->strategies[1] == NULL);
  uint64_t need = SK_CAP_2D | SK_CAP_3D | SK_CAP_FRICTION | SK_CAP_QUASISTATIC | SK_CAP_DYNAMICS |
                  SK_CAP_RIGID_OBSTACLE | SK_CAP_DEFORMABLE_MASTER;
  SK_CHECK((pl->caps & need) == need);
  SK_CHECK((pl->caps & (SK_CAP_MULTIPLIERS | SK_CAP_ENERGY_MOMENTUM)) == 0);
}

/* The penalties computed from the scene when it gives none (docs/plugins/penalty-nts.md#defaults): 10 E* / h on linear
 * slave faces, 100 E* / h on quadratic ones, E* of the pair (a rigid obstacle adds no compliance), h the slave surface's
 * mean edge; times the mean tributary length per node without area weighting; eps_T = eps_N; given values win. */
static double computed_penalty(sk_elem_type slave_type, int obstacle, const char *key, double value, const char *key2,
                               double value2, const char *which) {
  const double X[] = {1.0, 0.0, -1.0, 0.0, 0.0, 0.1, 0.5, 0.1, 0.25, 0.1};
  const int master[] = {0, 1}, slave[] = {2, 3, 4};
  scene s;
  scene_init(&s, 2, 5, X);
  if (obstacle) {
    sk_obstacle plane = {.kind = SK_OBSTACLE_PLANE, .normal = {0, 1, 0}};
    scene_obstacle(&s, &plane);
  } else {
    scene_master(&s, SK_LINE2, 2, 1, master);
  }
  scene_slave(&s, slave_type, slave_type == SK_LINE3 ? 3 : 2, 1, slave);
  kit_material(&s.k, 0, 1000.0, 0.3);
  kit_material(&s.k, 1, 1.0e6, 0.3);
  if (key) scene_param(&s, key, value);
  if (key2) scene_param(&s, key2, value2);
  SK_CHECK(scene_create(&s) == SK_OK);
  const double computed = kit_computed(&s.k, which);
  scene_destroy(&s);
  return computed;
}

static void test_computed_defaults(void) {
  const double pair = 1.0 / (0.91 / 1000.0 + 0.91 / 1.0e6), rigid = 1000.0 / 0.91, h = 0.5;
  SK_CHECK_CLOSE(computed_penalty(SK_LINE2, 0, NULL, 0, NULL, 0, "penalty"), 10.0 * pair / h, 1e-12);
  SK_CHECK_CLOSE(computed_penalty(SK_LINE2, 1, NULL, 0, NULL, 0, "penalty"), 10.0 * rigid / h, 1e-12);
  SK_CHECK_CLOSE(computed_penalty(SK_LINE3, 0, NULL, 0, NULL, 0, "penalty"), 300.0 * pair / h, 1e-12);
  /* a nodal stiffness: times the slave's length per node (0.5 over 2 nodes) */
  SK_CHECK_CLOSE(computed_penalty(SK_LINE2, 0, "area_weighted", 0, NULL, 0, "penalty"), 10.0 * pair / h * 0.25,
                 1e-12);
  /* the tangential penalty follows the normal one, computed or given; frictionless it is reported as unused (0) */
  SK_CHECK_CLOSE(computed_penalty(SK_LINE2, 0, "mu", 0.3, NULL, 0, "penalty_tangential"), 10.0 * pair / h, 1e-12);
  SK_CHECK_CLOSE(computed_penalty(SK_LINE2, 0, "mu", 0.3, "penalty", 5.0, "penalty_tangential"), 5.0, 1e-12);
  SK_CHECK(computed_penalty(SK_LINE2, 0, NULL, 0, NULL, 0, "penalty_tangential") == 0.0);
  /* a given value wins and nothing is reported */
  SK_CHECK(isnan(computed_penalty(SK_LINE2, 0, "penalty", 5.0, NULL, 0, "penalty")));
}

/* A rejected step leaves the committed history alone: redoing it gives the same tractions. */
static void test_reject_keeps_history(void) {
  scene s;
  double q0[24], q1[24], q2[24];
  quad4_friction_scene(&s, identity3, origin3, q0, q1, q2, 0.0005);
  SK_CHECK(scene_create(&s) == SK_OK);
  run_step(&s, q0, q1, 0.0, 1.0);
  test_step st = make_state(&s, q1, q2, 1.0, 2.0);
  SK_CHECK(scene_begin(&s, &st) == SK_OK);
  double F1[MAX_DOFS], F2[MAX_DOFS], far[24];
  residual_at(&s, &st, q2, F1);
  /* A failed attempt that went far (everything slipping), then the retry. */
  memcpy(far, q2, sizeof far);
  for (int a = 4; a < 8; ++a) far[3 * a] += 0.3;
  test_step bad = make_state(&s, q1, far, 1.0, 2.0);
  SK_CHECK(scene_begin(&s, &bad) == SK_OK);
  int changed = 0;
  SK_CHECK(scene_update(&s, &bad, &changed) == SK_OK);
  SK_CHECK(changed == 1);
  scene_reject(&s);
  SK_CHECK(scene_begin(&s, &st) == SK_OK);
  residual_at(&s, &st, q2, F2);
  for (int i = 0; i < 24; ++i) SK_CHECK(F1[i] == F2[i]);
  scene_destroy(&s);
}

/* Face selection at a kinked master node (the patch test at refine 3 and 4): a valley of two LINE2 faces (slopes
 * -/+0.01) and a slave node 1e-3 below the shared node. Under a pure closest-point projection the slave's normal
 * jumps from one face's to the other's within a fan of width 2e-5 around the node (x-force -/+ 0.01 p), and Newton
 * cycled across it. The face selected at begin_step is kept while the slave stays within 10 % of a face beyond it:
 * the residual is then smooth (energy gradient and Jacobian exact on the other side of the node), after_iteration
 * keeps the face there, and switches once the slave has moved 30 % of a face into the neighbour. */
static void test_kinked_master_selection(void) {
  const double X[] = {-1.0, 0.01, 0.0, 0.0, 1.0, 0.01, 1e-4, -1e-3, 0.5, 0.5};
  scene s;
  scene_init(&s, 2, 5, X);
  const int master[] = {2, 1, 1, 0}, slave[] = {4, 3};
  scene_master(&s, SK_LINE2, 2, 2, master);
  scene_slave(&s, SK_LINE2, 2, 1, slave);
  scene_param(&s, "penalty", 1e3);
  scene_param(&s, "area_weighted", 0);
  SK_CHECK(scene_create(&s) == SK_OK);
  double q[10], F_right[10], F_left[10], F_far[10], F_fresh[10];
  memcpy(q, s.X, sizeof q);
  test_step st = make_state(&s, s.X, q, 0.0, 1.0);
  SK_CHECK(scene_begin(&s, &st) == SK_OK);
  residual_at(&s, &st, q, F_right);
  SK_CHECK(F_right[6] > 0.0); /* the right face's normal tilts to -x: force on the slave -x, residual +x */
  /* 1e-4 left of the node, where the left face is the closest: still the right face's extension. */
  q[6] = -1e-4;
  int changed = 0;
  SK_CHECK(scene_update(&s, &st, &changed) == SK_OK);
  residual_at(&s, &st, q, F_left);
  printf("kinked master: slave x-residual %.6e right of the node, %.6e left of it\n", F_right[6], F_left[6]);
  SK_CHECK(fabs(F_left[6] - F_right[6]) <= 1e-4); /* the projection would jump by 2 x 0.01 p = 0.02 */
  check_residual_is_energy_gradient(&s, &st, 1e3, "2D kinked master, kept face");
  check_jacobian_is_residual_derivative(&s, &st, "2D kinked master, kept face");
  /* 30 % of a face into the left one: the selection switches, as a fresh step would select. */
  q[6] = -0.3;
  q[7] = 0.003 - 1e-3;
  SK_CHECK(scene_update(&s, &st, &changed) == SK_OK);
  SK_CHECK(changed == 1);
  residual_at(&s, &st, q, F_far);
  SK_CHECK(F_far[6] < 0.0);
  SK_CHECK(scene_begin(&s, &st) == SK_OK);
  residual_at(&s, &st, q, F_fresh);
  for (int i = 0; i < 10; ++i) SK_CHECK(F_far[i] == F_fresh[i]);
  scene_destroy(&s);
}

/* ---- quadratic faces ------------------------------------------------------------------------------------------ */
static const double tri6_xi[6][2] = {{0, 0}, {1, 0}, {0, 1}, {0.5, 0}, {0.5, 0.5}, {0, 0.5}};

/* A curved TRI6 master under a TRI3 slave: residual = energy gradient and Jacobian = its derivative, frictionless and
 * with friction (the curvature h_ab and the Christoffel symbols of the quadratic face enter both). */
static void test_tri6_master(void) {
  double X[9 * 3];
  for (int a = 0; a < 6; ++a) {
    const double x = 2.0 * tri6_xi[a][0], y = 2.0 * tri6_xi[a][1];
    X[3 * a] = x, X[3 * a + 1] = y, X[3 * a + 2] = 0.15 * x * x - 0.1 * y * y + 0.05 * x * y;
  }
  const double slave_x[3][3] = {{0.3, 0.3, 0.02}, {1.1, 0.4, 0.1}, {0.4, 1.1, -0.05}};
  for (int a = 0; a < 3; ++a) memcpy(X + 3 * (6 + a), slave_x[a], sizeof slave_x[a]);
  const int master[] = {0, 1, 2, 3, 4, 5}, slave[] = {6, 8, 7};
  for (int friction = 0; friction <= 1; ++friction) {
    scene s;
    scene_init(&s, 3, 9, X);
    scene_master(&s, SK_TRI6, 6, 1, master);
    scene_slave(&s, SK_TRI3, 3, 1, slave);
    scene_param(&s, "penalty", 2e3);
    scene_param(&s, "area_weighted", 0);
    if (friction) scene_param(&s, "mu", 0.3), scene_param(&s, "penalty_tangential", 1e3);
    SK_CHECK(scene_create(&s) == SK_OK);
    double q1[27];
    memcpy(q1, X, sizeof q1);
    for (int a = 6; a < 9; ++a) q1[3 * a] += 0.01, q1[3 * a + 2] -= 0.03;
    q1[3 * 4 + 2] += 0.02; /* the master's edge node rises: the face bends during the step */
    test_step st = make_state(&s, X, q1, 0.0, 1.0);
    SK_CHECK(scene_begin(&s, &st) == SK_OK);
    point_list list;
    points_at(&s, &st, q1, &list);
    SK_CHECK(count_state(&list, 0) == 0);
    if (!friction) check_residual_is_energy_gradient(&s, &st, 2e3, "3D tri6 curved master frictionless");
    const char *label = friction ? "3D tri6 curved master friction" : "3D tri6 curved master frictionless";
    check_jacobian_is_residual_derivative(&s, &st, label);
    scene_destroy(&s);
  }
}

/* A flat TRI6 slave (nodes 4-9 at 2 tri6_xi, legs 2, area 2; corners 4, 5, 6) over a flat QUAD4 master (nodes 0-3),
 * area weighted, penalty eps: X gets the reference positions. */
static void tri6_slave_scene(scene *s, double X[30], double eps) {
  const double square[4][2] = {{-1, -1}, {3, -1}, {3, 3}, {-1, 3}};
  for (int a = 0; a < 4; ++a) X[3 * a] = square[a][0], X[3 * a + 1] = square[a][1], X[3 * a + 2] = 0.0;
  for (int a = 0; a < 6; ++a) {
    double *x = X + 3 * (4 + a);
    x[0] = 2.0 * tri6_xi[a][0], x[1] = 2.0 * tri6_xi[a][1], x[2] = 0.0; /* flat in the reference: weights exact */
  }
  const int master[] = {0, 1, 2, 3}, slave[] = {4, 6, 5, 9, 8, 7}; /* clockwise seen from above: normal -z */
  scene_init(s, 3, 10, X);
  scene_master(s, SK_QUAD4, 4, 1, master);
  scene_slave(s, SK_TRI6, 6, 1, slave);
  scene_param(s, "penalty", eps);
  SK_CHECK(scene_create(s) == SK_OK);
}

/* A flat TRI6 slave (legs 2, area 2) over a flat QUAD4 master, area weighted. Weights of the modified basis: 2/15 of
 * the area at the corners, 1/5 at the edge nodes. With the corners touching and the edge nodes penetrating so that
 * their forces are the consistent loads of a uniform pressure p (0 at corners, A/3 at edge nodes), every node reports
 * p through the lumped recovery, where the plain force / weight would give 0 and 5/3 p. The Jacobian of the slave
 * (all six nodes active) is checked by central differences. */
static void test_tri6_slave(void) {
  const double eps = 1e3, p = 2.0, A = 2.0;
  double X[10 * 3];
  scene s;
  tri6_slave_scene(&s, X, eps);
  double q0[30];
  memcpy(q0, X, sizeof q0);
  for (int a = 3; a < 6; ++a) q0[3 * (4 + a) + 2] = -p * (A / 3.0) / (eps * A / 5.0);
  test_step st = make_state(&s, s.X, q0, 0.0, 1.0);
  SK_CHECK(scene_begin(&s, &st) == SK_OK);
  double F[MAX_DOFS];
  residual_at(&s, &st, q0, F);
  double total = 0.0;
  for (int a = 0; a < 6; ++a) {
    const double expected = a < 3 ? 0.0 : p * A / 3.0; /* force on the slave node, +z */
    SK_CHECK_CLOSE(-F[(4 + a) * 3 + 2], expected, 1e-12);
    total += -F[(4 + a) * 3 + 2];
  }
  SK_CHECK_CLOSE(total, p * A, 1e-12);
  point_list list;
  points_at(&s, &st, q0, &list);
  SK_CHECK(list.n == 6);
  for (int i = 0; i < list.n; ++i) SK_CHECK_CLOSE(list.p[i].pressure, p, 1e-12);
  /* All nodes penetrating (no node at the kink of the penalty): the Jacobian by central differences. */
  double q[30];
  memcpy(q, X, sizeof q);
  for (int a = 0; a < 6; ++a) q[3 * (4 + a) + 2] -= 0.002 * (1 + a);
  test_step moved = make_state(&s, s.X, q, 0.0, 1.0);
  SK_CHECK(scene_begin(&s, &moved) == SK_OK);
  check_jacobian_is_residual_derivative(&s, &moved, "3D tri6 slave area weighted");
  scene_destroy(&s);
}

/* The rim of a contact zone on a TRI6 slave (the flat face of test_tri6_slave): corner 4 opens, its edge node 9 is
 * off the master, its edge node 7 penetrates by d. A corner open by about the penetration around it (2 d) reports the
 * recovered pressure alpha f_7 / (2/15 A), where requiring every neighbour in contact reported 0 (the tet10 Hertz
 * rim); a corner open by the geometry's gap (10 d) reports none. */
static void test_tri6_slave_rim(void) {
  const double eps = 1e3, A = 2.0, d = 1e-3, alpha = 0.2;
  double X[10 * 3];
  scene s;
  tri6_slave_scene(&s, X, eps);
  for (int lifted = 0; lifted < 2; ++lifted) {
    const double opening = lifted ? 10.0 * d : 2.0 * d;
    double q[30];
    memcpy(q, X, sizeof q);
    q[3 * 4 + 2] = opening; /* corner 4 open */
    q[3 * 7 + 2] = -d;      /* its edge node 7 (between corners 4 and 5) penetrates */
    q[3 * 9 + 2] = 0.1;     /* its edge node 9 (between corners 4 and 6) is off the master */
    q[3 * 8 + 2] = -d;
    test_step st = make_state(&s, s.X, q, 0.0, 1.0);
    SK_CHECK(scene_begin(&s, &st) == SK_OK);
    point_list list;
    points_at(&s, &st, q, &list);
    const sk_contact_point *corner = point_of(&list, 4);
    SK_CHECK(corner != NULL && corner->state == 0 && corner->gap > 0.0);
    const double expected = lifted ? 0.0 : alpha * (eps * d * A / 5.0) / (2.0 * A / 15.0);
    if (corner) SK_CHECK_CLOSE(corner->pressure, expected, 1e-9);
  }
  scene_destroy(&s);
}

/* QUAD8 slave faces are refused with a message that names the way out; as a master QUAD8 works. */
static void test_quad8_slave_refused(void) {
  double X[12 * 3] = {0};
  const double quad8_xi[8][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}, {0, -1}, {1, 0}, {0, 1}, {-1, 0}};
  for (int a = 0; a < 8; ++a) X[3 * a] = quad8_xi[a][0], X[3 * a + 1] = quad8_xi[a][1];
  for (int a = 0; a < 4; ++a) X[3 * (8 + a)] = 0.5 * quad8_xi[a][0], X[3 * (8 + a) + 1] = 0.5 * quad8_xi[a][1],
                              X[3 * (8 + a) + 2] = 0.01;
  const int quad8[] = {0, 1, 2, 3, 4, 5, 6, 7}, quad4[] = {8, 11, 10, 9};
  scene s;
  scene_init(&s, 3, 12, X);
  scene_master(&s, SK_QUAD4, 4, 1, quad4);
  scene_slave(&s, SK_QUAD8, 8, 1, quad8);
  scene_param(&s, "penalty", 1e3);
  SK_CHECK(scene_create(&s) == SK_ERR_INPUT);
  SK_CHECK(strstr(sk_error_message(), "QUAD8") != NULL && strstr(sk_error_message(), "hex27") != NULL);
  scene_destroy(&s);
  scene_init(&s, 3, 12, X);
  scene_master(&s, SK_QUAD8, 8, 1, quad8);
  scene_slave(&s, SK_QUAD4, 4, 1, quad4);
  scene_param(&s, "penalty", 1e3);
  scene_param(&s, "area_weighted", 0);
  SK_CHECK(scene_create(&s) == SK_OK);
  double q[36];
  memcpy(q, X, sizeof q);
  for (int a = 8; a < 12; ++a) q[3 * a + 2] = -0.01 - 0.001 * a;
  test_step st = make_state(&s, X, q, 0.0, 1.0);
  SK_CHECK(scene_begin(&s, &st) == SK_OK);
  check_jacobian_is_residual_derivative(&s, &st, "3D quad8 master");
  scene_destroy(&s);
}

/* A stiff tangential penalty (eps_t = 1e6 and 1e7, 1e3 and 1e4 x the normal penalty) keeps a consistent tangent: a
 * slave QUAD4 pressed straight onto a flat master QUAD4 (no history traction, mu p = 12 per node), then moved
 * sideways by 0.4 mu p / eps_t (stick) or by 0.08 with the master deformed (slip), against central differences of
 * step 1e-9 (eps_t h <= 0.01, far inside the cone's radius 12). */
static void test_stiff_tangential_penalty(void) {
  const double X[] = {0.0, 0.0, 0.0,  2.0, 0.0, 0.0,  2.0, 2.0, 0.0,  0.0, 2.0, 0.0,
                      0.5, 0.5, 0.05, 1.5, 0.5, 0.05, 1.5, 1.5, 0.05, 0.5, 1.5, 0.05};
  const double stiff[] = {1e6, 1e7};
  for (int e = 0; e < 2; ++e)
    for (int slip = 0; slip <= 1; ++slip) {
      scene s;
      scene_init(&s, 3, 8, X);
      const int master[] = {0, 1, 2, 3}, slave[] = {4, 7, 6, 5};
      scene_master(&s, SK_QUAD4, 4, 1, master);
      scene_slave(&s, SK_QUAD4, 4, 1, slave);
      scene_param(&s, "penalty", 1e3);
      scene_param(&s, "mu", 0.4);
      scene_param(&s, "penalty_tangential", stiff[e]);
      scene_param(&s, "area_weighted", 0);
      SK_CHECK(scene_create(&s) == SK_OK);
      double q1[24], q2[24];
      memcpy(q1, X, sizeof q1);
      for (int a = 4; a < 8; ++a) q1[3 * a + 2] -= 0.08;
      run_step(&s, X, q1, 0.0, 1.0);
      memcpy(q2, q1, sizeof q2);
      const double move = slip ? 0.08 : 0.4 * 12.0 / (stiff[e] * hypot(1.0, 0.6));
      for (int a = 4; a < 8; ++a) {
        q2[3 * a] += move;
        q2[3 * a + 1] += 0.6 * move;
      }
      if (slip) q2[3 * 2] += 0.003, q2[3 * 2 + 2] += 0.01;
      test_step st = make_state(&s, q1, q2, 1.0, 2.0);
      SK_CHECK(scene_begin(&s, &st) == SK_OK);
      point_list list;
      points_at(&s, &st, q2, &list);
      SK_CHECK(count_state(&list, slip ? 2 : 1) == 4);
      char label[80];
      snprintf(label, sizeof label, "3D quad4 eps_t %.0e %s", stiff[e], slip ? "slip" : "stick");
      check_jacobian_with_step(&s, &st, 1e-9, label);
      scene_destroy(&s);
    }
}

/* The switch's memory (cov_return_map_held). The 2D flat master with a slave node pressed in (mu p = 6,
 * eps_t = 1e6): at q_a it slips to +x (traction -6). After the Jacobian there, a point q_b whose trial turned back
 * (the node 0.02 to -x of its start: trial +2e4) sticks, traction = trial, where the return map alone slips the
 * other way (+6); a point further along +x slips as before. A converged point where the memory holds a node in
 * stick that the return map lets slip is rejected, and the node then follows the return map. */
static void test_friction_switch_memory(void) {
  const double X[] = {2.0, 0.0, -1.0, 0.0, 0.3, -0.01, 0.9, 0.5};
  const double eps = 1e3, eps_t = 1e6, mu = 0.3, pressure = eps * 0.02;
  scene s;
  scene_init(&s, 2, 4, X);
  const int master[] = {0, 1}, slave[] = {2, 3};
  scene_master(&s, SK_LINE2, 2, 1, master);
  scene_slave(&s, SK_LINE2, 2, 1, slave);
  scene_param(&s, "penalty", eps);
  scene_param(&s, "mu", mu);
  scene_param(&s, "penalty_tangential", eps_t);
  scene_param(&s, "area_weighted", 0);
  SK_CHECK(scene_create(&s) == SK_OK);
  double q1[8], qa[8], qb[8], qc[8], F[MAX_DOFS], K[MAX_DOFS * MAX_DOFS];
  memcpy(q1, X, sizeof q1);
  q1[5] = -0.02;
  run_step(&s, X, q1, 0.0, 1.0);
  memcpy(qa, q1, sizeof qa);
  memcpy(qb, q1, sizeof qb);
  memcpy(qc, q1, sizeof qc);
  qa[4] += 0.02;
  qb[4] -= 0.02;
  qc[4] += 0.05;
  test_step st = make_state(&s, q1, qa, 1.0, 2.0);
  SK_CHECK(scene_begin(&s, &st) == SK_OK);
  /* the return map alone at q_b (no Jacobian yet in this step): slip to -x, traction +mu p */
  residual_at(&s, &st, qb, F);
  SK_CHECK_CLOSE(F[4], -mu * pressure, 1e-12);
  jacobian_at(&s, &st, qa, K); /* q_a accepted: the node slips to +x there */
  residual_at(&s, &st, qa, F);
  SK_CHECK_CLOSE(F[4], mu * pressure, 1e-12);
  residual_at(&s, &st, qb, F); /* turned back: stuck, t = trial = -eps_t (-0.02) */
  SK_CHECK_CLOSE(F[4], -eps_t * 0.02, 1e-12);
  point_list list;
  points_at(&s, &st, qb, &list);
  SK_CHECK(point_of(&list, 2) && point_of(&list, 2)->state == 1);
  residual_at(&s, &st, qc, F); /* on along the held direction: slip as by the return map */
  SK_CHECK_CLOSE(F[4], mu * pressure, 1e-12);
  /* converged at q_b with the node held in stick: rejected; the node then slips to -x */
  int accept = 1;
  SK_CHECK(kit_converged(&s.k, qb, &accept) == SK_OK);
  SK_CHECK(accept == 0);
  residual_at(&s, &st, qb, F);
  SK_CHECK_CLOSE(F[4], -mu * pressure, 1e-12);
  accept = 0;
  SK_CHECK(kit_converged(&s.k, qb, &accept) == SK_OK);
  SK_CHECK(accept == 1);
  /* The tangent follows the branch: at q_b after a Jacobian at q_a the stuck node's x row has the stick stiffness
   * eps_t (slip: 0 along the slip on a flat master); the memory is then q_b's (stuck there), and the return map
   * decides the points after it. */
  jacobian_at(&s, &st, qa, K);
  jacobian_at(&s, &st, qb, K);
  SK_CHECK_CLOSE(K[4 * 8 + 4], eps_t, 1e-12);
  residual_at(&s, &st, qb, F);
  SK_CHECK_CLOSE(F[4], -mu * pressure, 1e-12);
  jacobian_at(&s, &st, qb, K);
  SK_CHECK(fabs(K[4 * 8 + 4]) <= 1e-9 * eps_t);
  scene_destroy(&s);
}

int main(void) {
  test_line2_frictionless();
  test_line3_frictionless();
  test_quad4_frictionless();
  test_quad9_frictionless();
  test_friction_2d_flat_return_map();
  test_friction_3d_quad4();
  test_friction_face_crossing();
  test_frame_indifference();
  test_obstacles();
  test_area_weighting();
  test_touching_is_active();
  test_master_extension();
  test_kinked_master_selection();
  test_parameter_errors();
  test_computed_defaults();
  test_reject_keeps_history();
  test_tri6_master();
  test_tri6_slave();
  test_tri6_slave_rim();
  test_quad8_slave_refused();
  test_stiff_tangential_penalty();
  test_friction_switch_memory();
  return sk_test_finish("penalty-nts");
}
