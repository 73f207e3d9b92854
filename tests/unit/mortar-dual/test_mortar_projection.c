/* mortar-dual's special projection cases of concentrated integration (Hammer 2012, sec. 4.3 and 7.2.1, after
 * Zavarise & De Lorenzis 2009), through the ABI with the mock v2 host: which master face each slave Gauss point gets
 * at the start of a step (begin_step), and when it gets another at convergence (the frozen face, H 7.2.3).
 *   in-of-both   the point projects into two master faces (a concave kink, normal field M only): the smaller |g_n|
 *   out-of-both  it projects into neither (a convex kink, M only): the smaller |g_n| of the faces at the nearest
 *                master node
 *   out-of-first / out-of-last  beyond the master surface's first or last node: the point is dropped
 * One slave face with one Gauss point (face_gauss 1, at its centre) over a chain of two master faces. */
#include <math.h>

#include "mock_host.h"
#include "mortar.h" /* the instance: the test reads each point's face, inst->ip_master */
#include "sk_test.h"

typedef struct {
  double X[12]; /* global nodes: 0, 1 slave; 2, 3, 4 master */
  mock_view slave, master;
  sk_host host;
  sk_attach attach;
  const sk_view *views[2];
  sk_instance *inst;
  const sk_plugin *plugin;
} pair_scene;

/* The slave face from (xc - 0.2, yc) to (xc + 0.2, yc) (outward normal -y), the master chain through the nodes
 * (1, y_right), (0, y_mid), (-1, y_left) (outward normal up): faces 0 = right, 1 = left. */
static sk_status scene_make(pair_scene *s, double xc, double yc, double y_right, double y_mid, double y_left,
                            const char *normal) {
  memset(s, 0, sizeof *s);
  const double X[10] = {xc - 0.2, yc, xc + 0.2, yc, 1.0, y_right, 0.0, y_mid, -1.0, y_left};
  memcpy(s->X, X, sizeof X);
  static const int sf[2] = {0, 1}, mf[4] = {2, 3, 3, 4};
  mock_view_build(&s->slave, "slave", 2, SK_LINE2, 2, 1, sf, s->X);
  mock_view_build(&s->master, "master", 2, SK_LINE2, 2, 2, mf, s->X);
  static const char *keys[4] = {"integration", "normal", "face_gauss", "c_n"};
  const char *values[4] = {"concentrated", normal, "1", "100"};
  s->host.n_keys = 4;
  for (int i = 0; i < 4; ++i) {
    s->host.keys[i] = keys[i];
    s->host.values[i] = values[i];
  }
  s->views[0] = &s->slave.view;
  s->views[1] = &s->master.view;
  s->attach = (sk_attach){.struct_size = sizeof(sk_attach), .kind = SK_KIND_PAIR, .name = "pair",
                          .strategy = STRATEGY_SADDLE_POINT, .n_views = 2, .views = s->views,
                          .slave = &s->slave.view, .master = &s->master.view};
  s->plugin = stickslip_plugin_entry();
  const sk_status st = s->plugin->create(&mock_api, &s->host, &s->attach, &s->inst);
  if (st != SK_OK) printf("  create: %s\n", s->host.last_error);
  return st;
}

typedef struct {
  sk_state state;
  double xs[4], xm[6];
  const double *x[2], *v_n[2];
  double extra[4];
} state_at;

/* The state with every node at the global positions u (x_n = x: the start of a step). */
static void state_make(const pair_scene *s, const double *u, state_at *b) {
  mock_view_positions(&s->slave, u, b->xs);
  mock_view_positions(&s->master, u, b->xm);
  b->x[0] = b->xs;
  b->x[1] = b->xm;
  b->v_n[0] = b->v_n[1] = NULL;
  memset(b->extra, 0, sizeof b->extra);
  b->state = (sk_state){.struct_size = sizeof(sk_state), .t_n = 0.0, .t = 1.0, .dt = 1.0, .step = 1,
                        .scheme = "quasi-static", .alpha = 1.0, .n_views = 2, .x = b->x, .x_n = b->x,
                        .v_n = b->v_n, .extra = b->extra, .n_extra = 4, .extra_offset = 10};
}

/* The master face of the Gauss point at the start of a step with the nodes at their reference positions: 0, 1, or
 * -1 when dropped. */
static int face_at_start(pair_scene *s) {
  state_at b;
  state_make(s, s->X, &b);
  if (s->plugin->begin_step(s->inst, &b.state) != SK_OK) return -2;
  return s->inst->ip_master[0];
}

static int selected(double xc, double yc, double y_right, double y_mid, double y_left, const char *normal) {
  pair_scene s;
  if (scene_make(&s, xc, yc, y_right, y_mid, y_left, normal) != SK_OK) return -3;
  const int face = face_at_start(&s);
  s.plugin->destroy(s.inst);
  return face;
}

static void check_special_cases(void) {
  /* in-of-both: a valley (y = |x|); the point (0.1, 0.5) projects onto the right face (foot (0.3, 0.3), g = 0.283)
   * and onto the left one (foot (-0.2, 0.2), g = 0.424): the right face. Mirrored: the left face. */
  SK_CHECK(selected(0.1, 0.5, 1.0, 0.0, 1.0, "M") == 0);
  SK_CHECK(selected(-0.1, 0.5, 1.0, 0.0, 1.0, "M") == 1);
  /* with the averaged slave normal (A) the point projects along -y: into the right face only, no in-of-both */
  SK_CHECK(selected(0.1, 0.5, 1.0, 0.0, 1.0, "A") == 0);
  SK_CHECK(selected(-0.1, 0.5, 1.0, 0.0, 1.0, "A") == 1);
  /* out-of-both: a ridge (y = 1 - |x|); the point (0.05, 1.5) projects beyond both faces (feet (-0.225, 1.225) on
   * the right face's line, g = 0.389; (0.275, 1.275) on the left one's, g = 0.318): the nearest master node is the
   * interior ridge node, so the face with the smaller gap, the left one. Mirrored: the right face. */
  SK_CHECK(selected(0.05, 1.5, 0.0, 1.0, 0.0, "M") == 1);
  SK_CHECK(selected(-0.05, 1.5, 0.0, 1.0, 0.0, "M") == 0);
  /* out-of-first / out-of-last: beyond the chain's end nodes (border nodes) the point is dropped, either field */
  SK_CHECK(selected(1.5, 0.1, 0.0, 0.0, 0.0, "M") == -1);
  SK_CHECK(selected(-1.5, 0.1, 0.0, 0.0, 0.0, "M") == -1);
  SK_CHECK(selected(1.5, 0.1, 0.0, 0.0, 0.0, "A") == -1);
  SK_CHECK(selected(-1.5, 0.1, 0.0, 0.0, 0.0, "A") == -1);
  /* and over the chain's faces, inside: kept */
  SK_CHECK(selected(0.9, 0.1, 0.0, 0.0, 0.0, "M") == 0);
  SK_CHECK(selected(-0.9, 0.1, 0.0, 0.0, 0.0, "M") == 1);
}

/* The frozen face (H 7.2.3): within a step the point keeps its face while it projects at most 10 % of the face
 * beyond its edge (a round-off outside either face at a master node would otherwise alternate between them);
 * beyond that band the converged point is rejected and the point moved to the face it now lies over. */
static void check_frozen_face(void) {
  pair_scene s;
  SK_CHECK(scene_make(&s, 0.05, 0.1, 0.0, 0.0, 0.0, "M") == SK_OK);
  SK_CHECK(face_at_start(&s) == 0);
  /* the right face runs from x = 1 (parameter -1) to x = 0 (+1): the point at x = 0.05 has 0.9. Slid by -0.08 it
   * has 1.06, inside the band (1.1): kept, the point accepted; slid by -0.15, 1.2: moved to the left face and the
   * converged point rejected (Newton again with it) */
  const double shifts[2] = {-0.08, -0.15};
  const int expect_kept[2] = {1, 0};
  for (int c = 0; c < 2; ++c) {
    double u[10];
    memcpy(u, s.X, sizeof u);
    u[0] += shifts[c];
    u[2] += shifts[c];
    state_at b;
    state_make(&s, s.X, &b);
    SK_CHECK(s.plugin->begin_step(s.inst, &b.state) == SK_OK && s.inst->ip_master[0] == 0);
    double xs[4];
    mock_view_positions(&s.slave, u, xs);
    b.x[0] = xs;
    int accept = -1;
    SK_CHECK(s.plugin->converged(s.inst, &b.state, &accept) == SK_OK);
    printf("  slave shifted by %g: face %d, converged point %s\n", shifts[c], s.inst->ip_master[0],
           accept ? "accepted" : "rejected");
    SK_CHECK(accept == expect_kept[c]);
    SK_CHECK(s.inst->ip_master[0] == (expect_kept[c] ? 0 : 1));
  }
  s.plugin->destroy(s.inst);
}

/* The kernel's projection far from the origin: a slave point about 110 mm out projected onto a master face of
 * 1.4 mm whose line it meets 6 to 8 faces beyond the face (parameter -12 to -15), with either normal field. The
 * parameter's Newton step stalls at the coordinates' round-off over the face length (about 1e-14 here); an absolute
 * tolerance of 1e-14 failed it ("a Gauss point ... does not project onto its master face any more": the deep ironing
 * at refine 2 cut its press to dt / 64). */
static void check_far_projection(void) {
  mortar_face_type line;
  mortar_face_type_init(&line, SK_LINE2, sk_elem_shape, sk_elem_shape_hessian);
  const double xs[6] = {108.3, -27.2, 0, 109.9, -28.9, 0}; /* slave face, normal towards the master */
  const double ns[6] = {-0.7071067811865476, -0.7071067811865476, 0, -0.7071067811865476, -0.7071067811865476, 0};
  const double xm[6] = {101.0, -21.0, 0, 100.0, -20.0, 0}; /* master face, 45 degrees */
  mortar_pair p;
  mortar_pair_set(&p, 2, &line, &line, xs, xm, ns, 0);
  for (int variant = 0; variant < 2; ++variant) {
    const mortar_normal normal = variant ? MORTAR_NORMAL_M : MORTAR_NORMAL_A;
    for (int q = 0; q < 7; ++q) {
      const double xi1 = -0.9 + 0.3 * q;
      mortar_point_projection pr;
      const int status = mortar_project_point(&p, normal, &xi1, 0.0, &pr);
      /* the exact answer: both faces lie on lines of slope -1 (the master through (100, -20)), so the
       * point's distance along the master line from its centre, over the half-length */
      const double x1[2] = {xs[0] + 0.5 * (1 + xi1) * (xs[3] - xs[0]), xs[1] + 0.5 * (1 + xi1) * (xs[4] - xs[1])};
      const double along = ((x1[0] - 100.5) - (x1[1] + 20.5)) / sqrt(2.0), exact = -along / (sqrt(2.0) / 2);
      SK_CHECK(status == 0 && !pr.inside && fabs(pr.xi[0] - exact) < 1e-9);
      if (q == 0) printf("  far projection (%s): xi %.12g, exact %.12g\n", variant ? "M" : "A", pr.xi[0], exact);
    }
  }
}

int main(void) {
  check_far_projection();
  check_special_cases();
  check_frozen_face();
  return sk_test_finish("test_mortar_projection");
}
