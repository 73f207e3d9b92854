/* nts-augmented: the assembled operator through the plugin interface (the plugin test kit, tests/support), for every
 * strategy, frictionless, in stick and in slip, under backward Euler and the midpoint rule, on a warped QUAD4 and a
 * TRI3 master (3D), a LINE2 master (2D, node-to-segment), a curved LINE3 master under a LINE3 slave face (2D, every
 * face node a slave point, the mid-side node included), a QUAD9 slave face over curved QUAD9, QUAD8 and TRI6 masters
 * (3D; the QUAD8/QUAD9 constraint Hessian takes the faces' third parametric derivatives) and moving plane obstacles
 * (3D and 2D):
 *   condensed, augmented, direct, direct-endpoint: the assembled block and add_rhs equal the Schur complement of
 *     central differences of the assembled residual over the eliminated unknowns (kit_fd_check_condensed);
 *   paper-reduced: each block of (80) against its definition from central differences of the assembled residual:
 *     K_qq + K_qf P^T with P^T = -Gf^-1 Gq from the f rows (Phi_aug at t_{n+1}), the lambda_n row grad_q Phi_n,n+1
 *     (h_f . df dropped), the lambda_n column dR_q/dlambda_n (in slip (80) leaves out dt_T/dlambda_n: measured),
 *     add_rhs = K_qf Gf^-1 Phi_aug; and the recovery: (81) for f, and (52) for lambda_aug at the updated point, whose
 *     rows then vanish.
 * The points are generic: f off the closest point (Phi_aug != 0), lambda_aug arbitrary, lambda_n compressive. */
#include <stdio.h>
#include <stdlib.h>

#include "nts_kit_support.h"
#include "nts_test_support.h"
#include "plugin_kit.h"
#include "sk_test.h"
#include "stickslip/contact.h"

enum { MAX_N = 128 };
/* Central differences with step 1e-6; worst relative errors measured: 2.5e-8 (Schur complements: the local Newton
 * of the direct strategies, tolerance 1e-13, adds noise), 5.5e-10 (the paper's blocks). A wrong term is O(1). */
static const double FD_STEP = 1e-6, SCHUR_TOL = 1e-7, PAPER_TOL = 5e-9;
static const char *const STRATEGY[] = {"condensed", "augmented", "paper-reduced", "direct", "direct-endpoint"};
enum { PAPER = 2 };
enum { GEO_QUAD4, GEO_TRI3, GEO_LINE2, GEO_LINE3, GEO_QUAD9, GEO_QUAD8, GEO_TRI6, GEO_PLANE3, GEO_PLANE2, N_GEO };
static const char *const GEO_NAME[N_GEO] = {"quad4", "tri3", "line2 (2D)", "line3 (2D)", "quad9 on quad9",
                                            "quad9 on quad8", "quad9 on tri6", "plane obstacle",
                                            "plane obstacle (2D)"};

typedef struct {
  kit k;
  sk_obstacle obstacle;
  double q_n[MAX_N], q[MAX_N];
  int n_slave;
} scene;

/* Positions at t_n (gap > 0) and at t (penetrating, and moved tangentially by `slide`). */
static void build(scene *s, int geo, double slide) {
  memset(s, 0, sizeof *s);
  test_rng_state = 88172645463325252ull;
  if (geo == GEO_QUAD4 || geo == GEO_TRI3) {
    /* the master: a non-rectangular quad at z = 1 (Table I's), normal +z; the slave: four nodes above it */
    static const double X[8][3] = {{-1, -1, 1}, {1, -1, 1}, {1.2, 1, 1}, {-1.5, 1.5, 1},
                                   {-0.5, -0.8, 1.05}, {0.5, -0.8, 1.05}, {0.5, 0.2, 1.05}, {-0.5, 0.2, 1.05}};
    kit_init(&s->k, 3, 8, &X[0][0]);
    static const int master_quad[4] = {0, 1, 2, 3}, master_tri[6] = {0, 1, 2, 0, 2, 3}, slave[4] = {4, 7, 6, 5};
    kit_surface(&s->k, 0, SK_QUAD4, 4, 1, slave);
    if (geo == GEO_QUAD4)
      kit_surface(&s->k, 1, SK_QUAD4, 4, 1, master_quad);
    else
      kit_surface(&s->k, 1, SK_TRI3, 3, 2, master_tri);
    for (int i = 0; i < 24; ++i) {
      s->q_n[i] = X[i / 3][i % 3] + 0.01 * test_rand();
      s->q[i] = s->q_n[i] + (i < 12 ? 0.02 * test_rand() : (i % 3 == 2 ? -0.08 : i % 3 == 0 ? slide : 0.3 * slide));
    }
    s->n_slave = 4;
  } else if (geo == GEO_LINE2) {
    /* master segments run right to left so that a_1 x e_z = +y points out of the lower body */
    static const double X[5][2] = {{-1, 0}, {0.2, 0.05}, {1.1, 0}, {-0.4, 0.07}, {0.5, 0.08}};
    kit_init(&s->k, 2, 5, &X[0][0]);
    static const int master[4] = {1, 0, 2, 1}, slave[2] = {3, 4};
    kit_surface(&s->k, 0, SK_LINE2, 2, 1, slave);
    kit_surface(&s->k, 1, SK_LINE2, 2, 2, master);
    for (int i = 0; i < 10; ++i) {
      s->q_n[i] = X[i / 2][i % 2] + 0.005 * test_rand();
      s->q[i] = s->q_n[i] + (i < 6 ? 0.01 * test_rand() : (i % 2 == 1 ? -0.11 : slide));
    }
    s->n_slave = 2;
  } else if (geo == GEO_LINE3) {
    /* two curved master segments (nodes: ends, then the mid-side node off the chord), right to left as above, and
     * one curved slave segment whose three nodes are all slave points */
    static const double X[8][2] = {{-1, 0},      {0.2, 0.05},  {1.1, 0},     {-0.4, 0.08},
                                   {0.65, 0.075}, {-0.4, 0.11}, {0.5, 0.12}, {0.05, 0.14}};
    kit_init(&s->k, 2, 8, &X[0][0]);
    static const int master[6] = {1, 0, 3, 2, 1, 4}, slave[3] = {5, 6, 7};
    kit_surface(&s->k, 0, SK_LINE3, 3, 1, slave);
    kit_surface(&s->k, 1, SK_LINE3, 3, 2, master);
    for (int i = 0; i < 16; ++i) {
      s->q_n[i] = X[i / 2][i % 2] + 0.005 * test_rand();
      s->q[i] = s->q_n[i] + (i < 10 ? 0.01 * test_rand() : (i % 2 == 1 ? -0.11 : slide));
    }
    s->n_slave = 3;
  } else if (geo == GEO_QUAD9 || geo == GEO_QUAD8 || geo == GEO_TRI6) {
    /* the master: a warped quad at z = 1 (corners as above) whose edge and centre nodes are lifted (a curved face),
     * as one QUAD9, one QUAD8 (without the centre node) or two TRI6 (the diagonal's mid node is the centre); the
     * slave: one QUAD9 face above it, nodes ordered so that its normal points down */
    static const double X[18][3] = {
        {-1, -1, 1},       {1, -1, 1},         {1.2, 1, 1},        {-1.5, 1.5, 1},   {0, -1, 1.03},
        {1.1, 0, 1.03},    {-0.15, 1.25, 1.03}, {-1.25, 0.25, 1.03}, {-0.1, 0.1, 1.06}, {-0.5, -0.8, 1.12},
        {-0.5, 0.2, 1.13}, {0.5, 0.2, 1.12},   {0.5, -0.8, 1.14},  {-0.5, -0.3, 1.15}, {0, 0.2, 1.14},
        {0.5, -0.3, 1.13}, {0, -0.8, 1.15},    {0, -0.3, 1.16}};
    kit_init(&s->k, 3, 18, &X[0][0]);
    static const int quad9[9] = {0, 1, 2, 3, 4, 5, 6, 7, 8}, tri6[12] = {0, 1, 2, 4, 5, 8, 0, 2, 3, 8, 6, 7};
    static const int slave[9] = {9, 10, 11, 12, 13, 14, 15, 16, 17};
    kit_surface(&s->k, 0, SK_QUAD9, 9, 1, slave);
    if (geo == GEO_QUAD9)
      kit_surface(&s->k, 1, SK_QUAD9, 9, 1, quad9);
    else if (geo == GEO_QUAD8)
      kit_surface(&s->k, 1, SK_QUAD8, 8, 1, quad9);
    else
      kit_surface(&s->k, 1, SK_TRI6, 6, 2, tri6);
    for (int i = 0; i < 54; ++i) {
      s->q_n[i] = X[i / 3][i % 3] + 0.005 * test_rand();
      s->q[i] = s->q_n[i] + (i < 27 ? 0.005 * test_rand() : (i % 3 == 2 ? -0.14 : i % 3 == 0 ? slide : 0.3 * slide));
    }
    s->n_slave = 9;
  } else {
    const int dim = geo == GEO_PLANE3 ? 3 : 2;
    static const double X3[4][3] = {{0.5, 0.2, 0.04}, {-0.4, 0.3, 0.01}, {0.1, -0.5, 0.02}, {0.6, -0.4, 0.03}};
    static const double X2[3][2] = {{0.3, 0.04}, {-0.4, 0.01}, {-0.9, 0.03}};
    kit_init(&s->k, dim, dim == 3 ? 4 : 3, dim == 3 ? &X3[0][0] : &X2[0][0]);
    static const int slave3[4] = {0, 1, 2, 3}, slave2[4] = {0, 1, 1, 2};
    if (dim == 3)
      kit_surface(&s->k, 0, SK_QUAD4, 4, 1, slave3);
    else
      kit_surface(&s->k, 0, SK_LINE2, 2, 2, slave2);
    sk_obstacle *ob = &s->obstacle;
    ob->kind = SK_OBSTACLE_PLANE;
    const double nn = dim == 3 ? sqrt(0.01 + 0.04 + 1.0) : sqrt(0.01 + 1.0);
    ob->normal[0] = 0.1 / nn;
    ob->normal[1] = (dim == 3 ? 0.2 : 1.0) / nn;
    ob->normal[2] = dim == 3 ? 1.0 / nn : 0.0;
    ob->n_motion = 2; /* rises by 0.3 and slides by -slide in x within t in [0, 1] */
    ob->motion_t[1] = 1.0;
    for (int i = 0; i < 3; ++i) ob->motion_d[1][i] = 0.3 * ob->normal[i] + (i == 0 ? -slide : 0.0);
    kit_obstacle(&s->k, ob);
    const int n = s->k.n_dofs;
    for (int i = 0; i < n; ++i) {
      s->q_n[i] = s->k.X[i];
      s->q[i] = s->q_n[i] + 0.01 * test_rand();
    }
    s->n_slave = s->k.n_nodes;
  }
}

static int stride_of(const scene *s) { return s->k.dim == 3 ? 5 : 3; }

/* Create, begin the step, put the extras at a generic point and let update_active_set pick stick or slip. Returns 0
 * when every slave node is active in the wanted friction state. */
static int prepare(scene *s, int geo, int strategy, double alpha, int friction) {
  build(s, geo, friction == SLIP ? 0.1 : 0.002);
  nts_kit_start(&s->k, s->q_n, s->q, strategy, alpha, friction);
  kit_points pts;
  SK_CHECK(kit_points_at(&s->k, &pts) == SK_OK);
  int ok = pts.n == s->n_slave;
  for (int i = 0; i < pts.n; ++i) ok &= pts.p[i].state == (friction == SLIP ? 2 : 1);
  if (!ok)
    for (int i = 0; i < pts.n; ++i)
      fprintf(stderr, "  slave node %lld: state %d, gap %.3e, pressure %.3e\n", (long long)pts.p[i].slave_node,
              pts.p[i].state, pts.p[i].gap, pts.p[i].pressure);
  return ok ? 0 : -1;
}

/* ---- the paper's (80) block by block ------------------------------------------------------------------------------ */
typedef struct {
  double block, lambda_row, lambda_col, rhs, recovery_f, recovery_lambda_aug, scale;
} paper_errors;

static paper_errors check_paper(scene *s) {
  kit *k = &s->k;
  const int n = (int)k->n, nd = k->n_dofs, stride = stride_of(s), pdim = k->dim - 1;
  static double J[MAX_N * MAX_N], Jfd[MAX_N * MAX_N], F[MAX_N], rhs[MAX_N], PT[MAX_N * MAX_N], Ginv_phi[MAX_N];
  SK_CHECK(n <= MAX_N);
  SK_CHECK(kit_jacobian(k, s->q, J, rhs) == SK_OK);
  SK_CHECK(kit_residual(k, s->q, F) == SK_OK);
  kit_fd_jacobian(k, s->q, FD_STEP, Jfd);
  /* P^T = -Gf^-1 Gq per node from the f rows (Phi_aug at t_{n+1}); PT[f unknown][position] */
  memset(PT, 0, sizeof PT);
  for (int node = 0; node < n - nd; node += stride) {
    const int f0 = nd + node + 1;
    double G[2][2] = {{1, 0}, {0, 1}}, Gi[2][2];
    for (int a = 0; a < pdim; ++a)
      for (int b = 0; b < pdim; ++b) G[a][b] = Jfd[(f0 + a) * n + f0 + b];
    SK_CHECK(nts_inverse2(G, Gi) == 0);
    for (int a = 0; a < pdim; ++a) {
      Ginv_phi[f0 + a] = 0.0;
      for (int b = 0; b < pdim; ++b) Ginv_phi[f0 + a] += Gi[a][b] * F[f0 + b];
      for (int j = 0; j < nd; ++j) {
        double v = 0.0;
        for (int b = 0; b < pdim; ++b) v -= Gi[a][b] * Jfd[(f0 + b) * n + j];
        PT[(f0 + a) * n + j] = v;
      }
    }
  }
  paper_errors e = {0};
  for (int i = 0; i < n * n; ++i) e.scale = fmax(e.scale, fabs(J[i]));
  for (int i = 0; i < nd; ++i) {
    double r = 0.0;
    for (int node = 0; node < n - nd; node += stride)
      for (int a = 0; a < pdim; ++a) r += Jfd[i * n + nd + node + 1 + a] * Ginv_phi[nd + node + 1 + a];
    e.rhs = fmax(e.rhs, fabs(rhs[i] - r));
    for (int j = 0; j < nd; ++j) {
      double v = Jfd[i * n + j];
      for (int node = 0; node < n - nd; node += stride)
        for (int a = 0; a < pdim; ++a) v += Jfd[i * n + nd + node + 1 + a] * PT[(nd + node + 1 + a) * n + j];
      e.block = fmax(e.block, fabs(J[i * n + j] - v));
    }
    for (int node = 0; node < n - nd; node += stride) {
      const int l = nd + node;
      e.lambda_col = fmax(e.lambda_col, fabs(J[i * n + l] - Jfd[i * n + l]));
      e.lambda_row = fmax(e.lambda_row, fabs(J[l * n + i] - Jfd[l * n + i]));
    }
  }
  /* recovery: a Newton update (dq, dlambda_n) through recover; then (81) holds and the lambda_aug rows vanish */
  static double dx[MAX_N], q1[MAX_N], F1[MAX_N], extra0[MAX_N];
  for (int i = 0; i < n; ++i) dx[i] = i < nd ? 1e-3 * test_rand() : 0.0;
  for (int node = 0; node < n - nd; node += stride) dx[nd + node] = 0.01 * test_rand();
  SK_CHECK(kit_recover(k, s->q, F, dx) == SK_OK);
  for (int node = 0; node < n - nd; node += stride)
    for (int a = 0; a < pdim; ++a) {
      const int f = nd + node + 1 + a;
      double expect = -Ginv_phi[f];
      for (int j = 0; j < nd; ++j) expect += PT[f * n + j] * dx[j];
      e.recovery_f = fmax(e.recovery_f, fabs(dx[f] - expect));
    }
  memcpy(extra0, k->extra, sizeof(double) * (size_t)(n - nd));
  for (int i = 0; i < nd; ++i) q1[i] = s->q[i] + dx[i];
  for (int i = nd; i < n; ++i) k->extra[i - nd] += dx[i];
  SK_CHECK(kit_residual(k, q1, F1) == SK_OK);
  for (int node = 0; node < n - nd; node += stride)
    for (int a = 0; a < pdim; ++a) e.recovery_lambda_aug = fmax(e.recovery_lambda_aug, fabs(F1[nd + node + 1 + pdim + a]));
  memcpy(k->extra, extra0, sizeof(double) * (size_t)(n - nd));
  kit_residual(k, s->q, F1); /* back to the point (positions) */
  return e;
}

int main(void) {
  static const double alphas[2] = {1.0, 0.5};
  static const char *const friction_name[3] = {"frictionless", "stick", "slip"};
  double worst = 0.0, worst_paper = 0.0, slip_col_min = 1e300;
  int cases = 0;
  for (int geo = 0; geo < N_GEO; ++geo)
    for (int strategy = 0; strategy < 5; ++strategy)
      for (int ia = 0; ia < 2; ++ia)
        for (int friction = 0; friction < 3; ++friction) {
          scene s;
          const int ready = prepare(&s, geo, strategy, alphas[ia], friction);
          if (ready != 0)
            fprintf(stderr, "%s %s alpha %.1f %s: not every slave node is active in that state\n", GEO_NAME[geo],
                    STRATEGY[strategy], alphas[ia], friction_name[friction]);
          SK_CHECK(ready == 0);
          ++cases;
          if (strategy == PAPER) {
            const paper_errors e = check_paper(&s);
            const double tol = PAPER_TOL * fmax(1.0, e.scale);
            printf("%-20s %-15s %-8s %-12s (80): block %.1e, lambda row %.1e, lambda column %.1e, rhs %.1e, "
                   "(81) %.1e, (52) rows %.1e (scale %.1e)\n", GEO_NAME[geo], STRATEGY[strategy],
                   ia ? "midpoint" : "euler", friction_name[friction], e.block, e.lambda_row, e.lambda_col, e.rhs,
                   e.recovery_f, e.recovery_lambda_aug, e.scale);
            SK_CHECK(e.block < tol && e.lambda_row < tol && e.rhs < tol && e.recovery_f < 1e-10);
            SK_CHECK(e.recovery_lambda_aug < 1e-14);
            SK_CHECK(s.k.outside_pattern == 0);
            if (friction == SLIP) {
              slip_col_min = fmin(slip_col_min, e.lambda_col); /* (80) freezes dt_T/dlambda_n */
            } else {
              SK_CHECK(e.lambda_col < tol);
              worst_paper = fmax(worst_paper, e.lambda_col / fmax(1.0, e.scale));
            }
            worst_paper = fmax(worst_paper, fmax(e.block, fmax(e.lambda_row, e.rhs)) / fmax(1.0, e.scale));
          } else {
            double scale = 0.0, rhs_error = 0.0;
            const double err = kit_fd_check_condensed(&s.k, s.q, FD_STEP, &scale, &rhs_error);
            printf("%-20s %-15s %-8s %-12s |J - Schur(FD)| %.1e, |rhs - FD| %.1e (scale %.1e)%s\n", GEO_NAME[geo],
                   STRATEGY[strategy], ia ? "midpoint" : "euler", friction_name[friction], err, rhs_error, scale,
                   s.k.outside_pattern ? ", OUTSIDE THE PATTERN" : "");
            SK_CHECK(scale > 0.0 && err < SCHUR_TOL * fmax(1.0, scale) && rhs_error < SCHUR_TOL * fmax(1.0, scale));
            SK_CHECK(s.k.outside_pattern == 0);
            worst = fmax(worst, fmax(err, rhs_error) / fmax(1.0, scale));
          }
          kit_free(&s.k);
        }
  printf("%d cases; worst relative error: %.1e (Schur complements), %.1e (paper); the paper's lambda_n column "
         "differs from the exact one in slip by at least %.1e\n", cases, worst, worst_paper, slip_col_min);
  SK_CHECK(slip_col_min > 0.1);
  return sk_test_finish("test_nts_assembled");
}
