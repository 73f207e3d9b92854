/* nts-augmented: self contact (a pair whose master is its slave) through the plugin interface (the plugin test kit):
 * one surface with two facing walls, in 2D (two LINE2 chains) and 3D (two QUAD4 faces, offset so that each wall
 * has a node over the other), pressed into each other.
 *   - the walls form one zone: its nodes face each other both ways, so one side alone carries the constraints
 *     (plugins/nts-augmented/self.c): exactly the expected slave nodes are active, the other side's nodes are master
 *     nodes only, and no node is constrained against a face of its own;
 *   - the assembled operator equals the Schur complement of central differences of the assembled residual
 *     (kit_fd_check_condensed) for condensed, augmented, direct and direct-endpoint, frictionless, in stick and in
 *     slip, under backward Euler and the midpoint rule (paper-reduced's blocks are checked on the two-body pairs of
 *     test_nts_assembled; their structure is the same per element);
 *   - self_exclusion is read, with the largest face as its default, and a node within it of a face does not take
 *     that face;
 *   - a node level with the master's border (a hair beyond it, as round-off puts the free end of a crushed tube)
 *     that crosses a face within one step is in contact (master_extension), its operator checked the same way; one
 *     far beyond the border is not, nor is the hair-beyond node with master_extension 0. */
#include <stdio.h>
#include <stdlib.h>

#include "nts_kit_support.h"
#include "nts_test_support.h"
#include "plugin_kit.h"
#include "sk_test.h"
#include "stickslip/contact.h"

enum { MAX_N = 64 };
/* as in test_nts_assembled: central differences with step 1e-6, the direct strategies' local Newton adds ~1e-8 */
static const double FD_STEP = 1e-6, SCHUR_TOL = 1e-7;
static const char *const STRATEGY[] = {"condensed", "augmented", "paper-reduced", "direct", "direct-endpoint"};
enum { PAPER = 2 };
/* below the walls' distance 0.06, so that the facing wall is a candidate */
static const double EXCLUSION = 0.03;

typedef struct {
  kit k;
  double q_n[MAX_N], q[MAX_N];
  int n_expected;          /* slave nodes expected active */
  int64_t expected[4];     /* their mesh ids */
} scene;

/* 2D: the bottom chain 0-1-2 (normal +y) and the top chain 3-4-5 (normal -y) of one surface, 0.06 apart; the top
 * moves down by 0.1 (and along x by slide). Nodes 1, 2 lie under the top chain, 3, 4 over the bottom one; they face
 * each other both ways, sides {1, 2} and {3, 4} tie, and the side holding the smallest index (1) is slave.
 * 3D: the bottom quad 0-3 (normal +z) and the top quad 4-7 (normal -z), offset by half a face: node 2 lies under
 * the top quad, node 4 over the bottom one; node 2 is slave. */
static void build(scene *s, int dim, double slide) {
  memset(s, 0, sizeof *s);
  test_rng_state = 88172645463325252ull;
  if (dim == 2) {
    static const double X[6][2] = {{-1, 0}, {0.2, 0.02}, {1.1, 0}, {-0.4, 0.06}, {0.5, 0.07}, {1.3, 0.065}};
    kit_init(&s->k, 2, 6, &X[0][0]);
    static const int conn[8] = {1, 0, 2, 1, 3, 4, 4, 5};
    kit_surface(&s->k, 0, SK_LINE2, 2, 4, conn);
    kit_surface(&s->k, 1, SK_LINE2, 2, 4, conn);
    for (int i = 0; i < 12; ++i) {
      s->q_n[i] = X[i / 2][i % 2] + 0.002 * test_rand();
      s->q[i] = s->q_n[i] + (i < 6 ? 0.005 * test_rand() : (i % 2 == 1 ? -0.1 : slide));
    }
    s->n_expected = 2;
    s->expected[0] = 1;
    s->expected[1] = 2;
  } else {
    static const double X[8][3] = {{-1, -1, 0},     {1, -1, 0.01},   {1, 1, 0},      {-1, 1, -0.01},
                                   {-0.5, -0.5, 0.06}, {-0.5, 1.5, 0.07}, {1.5, 1.5, 0.06}, {1.5, -0.5, 0.05}};
    kit_init(&s->k, 3, 8, &X[0][0]);
    static const int conn[8] = {0, 1, 2, 3, 4, 5, 6, 7};
    kit_surface(&s->k, 0, SK_QUAD4, 4, 2, conn);
    kit_surface(&s->k, 1, SK_QUAD4, 4, 2, conn);
    for (int i = 0; i < 24; ++i) {
      s->q_n[i] = X[i / 3][i % 3] + 0.002 * test_rand();
      s->q[i] = s->q_n[i] + (i < 12 ? 0.005 * test_rand() : (i % 3 == 2 ? -0.1 : i % 3 == 0 ? slide : 0.3 * slide));
    }
    s->n_expected = 1;
    s->expected[0] = 2;
  }
  s->k.attach.self_contact = 1;
}

static int expected(const scene *s, int64_t node) {
  for (int i = 0; i < s->n_expected; ++i)
    if (s->expected[i] == node) return 1;
  return 0;
}

/* Create, begin the step, put the extras at a generic point and let update_active_set pick stick or slip. Returns 0
 * when exactly the expected nodes are active, in the wanted friction state. */
static int prepare(scene *s, int dim, int strategy, double alpha, int friction) {
  build(s, dim, friction == SLIP ? 0.1 : 0.002);
  kit_param(&s->k, "self_exclusion", EXCLUSION);
  nts_kit_start(&s->k, s->q_n, s->q, strategy, alpha, friction);
  kit_points pts;
  SK_CHECK(kit_points_at(&s->k, &pts) == SK_OK);
  int active = 0, ok = 1;
  for (int i = 0; i < pts.n; ++i) {
    const sk_contact_point *p = &pts.p[i];
    if (p->state == 0) continue;
    ++active;
    ok &= expected(s, p->slave_node) && p->state == (friction == SLIP ? 2 : 1) && p->gap > -0.2 && p->gap < 0.0;
  }
  ok &= active == s->n_expected;
  if (!ok)
    for (int i = 0; i < pts.n; ++i)
      fprintf(stderr, "  node %lld: state %d, gap %.3e, pressure %.3e\n", (long long)pts.p[i].slave_node,
              pts.p[i].state, pts.p[i].gap, pts.p[i].pressure);
  return ok ? 0 : -1;
}

/* The default of self_exclusion is the largest face's reference box diagonal; with it the 2D walls (faces ~1 long,
 * 0.06 apart) do not see each other, so nothing is active. */
static void default_exclusion(void) {
  scene s;
  build(&s, 2, 0.002);
  SK_CHECK(kit_create(&s.k, stickslip_plugin_entry(), 0) == SK_OK);
  const double largest = sqrt(1.2 * 1.2 + 0.02 * 0.02); /* face 1-0: from (0.2, 0.02) to (-1, 0) */
  printf("self_exclusion default %.6f (largest face %.6f)\n", kit_computed(&s.k, "self_exclusion"), largest);
  SK_CHECK(fabs(kit_computed(&s.k, "self_exclusion") - largest) < 1e-12);
  kit_state(&s.k, s.q_n, s.q, 0.0, 1.0, NULL);
  SK_CHECK(kit_begin(&s.k) == SK_OK);
  int changed = 0;
  SK_CHECK(kit_update_active_set(&s.k, s.q, &changed) == SK_OK);
  kit_points pts;
  SK_CHECK(kit_points_at(&s.k, &pts) == SK_OK);
  for (int i = 0; i < pts.n; ++i) SK_CHECK(pts.p[i].state == 0);
  kit_free(&s.k);
}

/* 3D: the bottom wall's quad 0-3 (z = 0, normal +z, x and y in [0, 1]) and the top wall's quad 4-7 (z = 0.06,
 * normal -z, x in [1 + 1e-9, 2], y in [0.2, 0.8]) of one surface. Nodes 4 and 5 lie over the bottom quad's border
 * edge x = 1, beyond it by 1e-9 (the core's projection reports OUTSIDE there); nodes 6 and 7 a whole face beyond.
 * The bottom nodes face nothing (the top quad is 0.2 beyond them in y: beyond the band). In the step the top wall
 * moves down by 0.1: it crosses the bottom wall within one step, so nodes 4 and 5 must end in contact. */
static void border_crossing(double extension, int strategy, double alpha, int friction, int n_expected) {
  static const double X[8][3] = {{0, 0, 0},   {1, 0, 0},   {1, 1, 0}, {0, 1, 0}, {1 + 1e-9, 0.2, 0.06},
                                 {1 + 1e-9, 0.8, 0.06}, {2, 0.8, 0.06}, {2, 0.2, 0.06}};
  static const int conn[8] = {0, 1, 2, 3, 4, 5, 6, 7};
  scene s;
  memset(&s, 0, sizeof s);
  kit_init(&s.k, 3, 8, &X[0][0]);
  kit_surface(&s.k, 0, SK_QUAD4, 4, 2, conn);
  kit_surface(&s.k, 1, SK_QUAD4, 4, 2, conn);
  s.k.attach.self_contact = 1;
  for (int i = 0; i < 24; ++i) {
    s.q_n[i] = X[i / 3][i % 3];
    s.q[i] = s.q_n[i] + (i >= 12 && i % 3 == 2 ? -0.1 : 0.0);
  }
  s.n_expected = n_expected;
  s.expected[0] = 4;
  s.expected[1] = 5;
  kit_param(&s.k, "self_exclusion", EXCLUSION);
  if (extension >= 0.0) kit_param(&s.k, "master_extension", extension);
  nts_kit_start(&s.k, s.q_n, s.q, strategy, alpha, friction);
  kit_points pts;
  SK_CHECK(kit_points_at(&s.k, &pts) == SK_OK);
  int active = 0;
  for (int i = 0; i < pts.n; ++i) {
    const sk_contact_point *p = &pts.p[i];
    if (p->state != 0) ++active;
    if (expected(&s, p->slave_node) || p->state != 0) {
      printf("3D border %-15s master_extension %s: node %lld state %d gap %.3e\n", STRATEGY[strategy],
             extension >= 0.0 ? "0" : "default", (long long)p->slave_node, p->state, p->gap);
      SK_CHECK(expected(&s, p->slave_node) && p->state != 0 && fabs(p->gap + 0.04) < 1e-12);
    }
  }
  SK_CHECK(active == n_expected);
  if (n_expected > 0) {
    double scale = 0.0, rhs_error = 0.0;
    const double err = kit_fd_check_condensed(&s.k, s.q, FD_STEP, &scale, &rhs_error);
    printf("3D border %-15s %-8s %-12s |J - Schur(FD)| %.1e, |rhs - FD| %.1e (scale %.1e)\n", STRATEGY[strategy],
           alpha == 1.0 ? "euler" : "midpoint", friction == SLIP ? "slip" : friction == STICK ? "stick" : "frictionless",
           err, rhs_error, scale);
    SK_CHECK(scale > 0.0 && err < SCHUR_TOL * fmax(1.0, scale) && rhs_error < SCHUR_TOL * fmax(1.0, scale));
    SK_CHECK(s.k.outside_pattern == 0);
  }
  kit_free(&s.k);
}

int main(void) {
  static const double alphas[2] = {1.0, 0.5};
  static const char *const friction_name[3] = {"frictionless", "stick", "slip"};
  double worst = 0.0;
  int cases = 0;
  default_exclusion();
  for (int strategy = 0; strategy < 5; ++strategy)
    if (strategy != PAPER) border_crossing(-1.0, strategy, 1.0, FRICTIONLESS, 2);
  border_crossing(-1.0, 0, 0.5, STICK, 2);
  border_crossing(0.0, 0, 1.0, FRICTIONLESS, 0);
  for (int dim = 2; dim <= 3; ++dim)
    for (int strategy = 0; strategy < 5; ++strategy)
      for (int ia = 0; ia < 2; ++ia)
        for (int friction = 0; friction < 3; ++friction) {
          if (strategy == PAPER) continue;
          scene s;
          const int ready = prepare(&s, dim, strategy, alphas[ia], friction);
          if (ready != 0)
            fprintf(stderr, "%dD %s alpha %.1f %s: the active nodes are not the expected slave side\n", dim,
                    STRATEGY[strategy], alphas[ia], friction_name[friction]);
          SK_CHECK(ready == 0);
          double scale = 0.0, rhs_error = 0.0;
          const double err = kit_fd_check_condensed(&s.k, s.q, FD_STEP, &scale, &rhs_error);
          printf("%dD self %-15s %-8s %-12s |J - Schur(FD)| %.1e, |rhs - FD| %.1e (scale %.1e)%s\n", dim,
                 STRATEGY[strategy], ia ? "midpoint" : "euler", friction_name[friction], err, rhs_error, scale,
                 s.k.outside_pattern ? ", OUTSIDE THE PATTERN" : "");
          SK_CHECK(scale > 0.0 && err < SCHUR_TOL * fmax(1.0, scale) && rhs_error < SCHUR_TOL * fmax(1.0, scale));
          SK_CHECK(s.k.outside_pattern == 0);
          worst = fmax(worst, fmax(err, rhs_error) / fmax(1.0, scale));
          ++cases;
          kit_free(&s.k);
        }
  printf("%d cases; worst relative error %.1e\n", cases, worst);
  return sk_test_finish("test_nts_self");
}
