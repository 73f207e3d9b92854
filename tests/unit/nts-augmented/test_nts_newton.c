/* nts-augmented: Newton on a single element system. A slave node hangs on a spring and is pressed onto a fixed,
 * tilted, non-planar QUAD4 facet by a force; unknowns q_s, lambda_n, f, lambda_aug. Runs the full system (strategy
 * `none`) and the exactly condensed one (`reduced`) side by side: the iterates must agree to round-off and the
 * residual must converge quadratically; at the solution lambda_aug must satisfy (52). */
#include <stdio.h>

#include "nts_test_support.h"
#include "sk_test.h"

enum { NU = 8 }; /* q_s (3), lambda_n, f (2), lambda_aug (2) */

typedef struct {
  const char *name;
  double alpha, mu, epsilon_t;
  double force[3];
} newton_case;

static const double SPRING = 20.0;
static const double ANCHOR[3] = {0.1, 0.05, 0.3};

static void setup(const nts_facet *facet, double *q_A, double *q_start) {
  static const double master[4][3] = {{-1, -1, 0.1}, {1.2, -0.9, -0.1}, {1.1, 1.3, 0.35}, {-0.8, 1.0, 0.0}};
  for (int I = 0; I < facet->nen; ++I)
    for (int i = 0; i < 3; ++i) q_A[3 + 3 * I + i] = q_start[3 + 3 * I + i] = master[I][i];
  for (int i = 0; i < 3; ++i) q_A[i] = q_start[i] = ANCHOR[i];
}

/* Global residual and Jacobian of [q_s, extras] with the master nodes held fixed. */
static void global_system(const nts_facet *facet, nts_element_input *in, const nts_friction_params *params,
                          const double *force, nts_element_system *sys, double *F, double *J) {
  nts_element_build(facet, in, params, sys);
  const int nq = sys->nq, nu = sys->nu;
  static const int map[NU] = {0, 1, 2, 15, 16, 17, 18, 19}; /* global -> element index (nq = 15) */
  for (int i = 0; i < NU; ++i) {
    F[i] = sys->R[map[i]];
    for (int j = 0; j < NU; ++j) J[i * NU + j] = sys->J[map[i] * nu + map[j]];
  }
  for (int i = 0; i < 3; ++i) {
    F[i] += SPRING * (in->q_A[i] - ANCHOR[i]) - force[i];
    J[i * NU + i] += SPRING;
  }
  (void)nq;
}

/* The residual history r_0, r_1, ... converges quadratically in the basin: every pair with r_k < 1e-1 and r_{k+1}
 * above the round-off floor (1e-13 here) has r_{k+1} <= QUADRATIC_C r_k^2, and there is at least one such pair.
 * Measured r_{k+1} / r_k^2 up to 0.045 (slip, backward Euler: 5.1e-2, 7.0e-5, 2.2e-10), so QUADRATIC_C = 0.1; a
 * linear contraction fails it at once (0.9: r_{k+1} = 0.045 against 0.1 * 0.05^2 = 2.5e-4). Returns the number of
 * failures (-1 without a pair to judge). */
#define QUADRATIC_C 0.1
static int quadratic_rate(const double *r, int n) {
  int pairs = 0, failures = 0;
  for (int k = 0; k + 1 < n; ++k)
    if (r[k] < 1e-1 && r[k + 1] > 1e-13) {
      ++pairs;
      failures += !(r[k + 1] <= QUADRATIC_C * r[k] * r[k]);
    }
  return pairs ? failures : -1;
}

/* The check can fail: a linear contraction (0.9, 0.5) and a history that never enters the basin are rejected, a
 * quadratic one accepted. */
static void quadratic_rate_self_test(void) {
  const double linear[] = {8.0, 0.09, 0.081, 0.0729, 0.06561}, halving[] = {8.0, 0.05, 0.025, 0.0125};
  const double quadratic[] = {8.0, 5e-2, 1e-4, 5e-10, 1e-16}, stalled[] = {8.0, 7.0, 6.5};
  SK_CHECK(quadratic_rate(linear, 5) > 0);
  SK_CHECK(quadratic_rate(halving, 4) > 0);
  SK_CHECK(quadratic_rate(quadratic, 5) == 0);
  SK_CHECK(quadratic_rate(stalled, 3) == -1);
}

static double run(const newton_case *c) {
  nts_facet facet;
  nts_facet_init(&facet, SK_QUAD4, test_shape, test_shape_hessian);
  const nts_friction_params params = {c->mu, c->epsilon_t};
  double q_full[NTS_MAX_NQ], q_red[NTS_MAX_NQ], q_start[NTS_MAX_NQ];
  setup(&facet, q_full, q_start);
  setup(&facet, q_red, q_start);
  nts_element_input full = {0}, red = {0};
  full.alpha = c->alpha;
  full.q_A_start = q_start;
  full.q_A = q_full;
  full.active = 1;
  full.f[0] = full.f[1] = 0.0;
  SK_CHECK(nts_closest_point(&facet, q_start, full.f, 1e-14, 30) > 0);
  full.f_start[0] = full.f[0];
  full.f_start[1] = full.f[1];
  red = full;
  red.q_A = q_red;

  double history[40];
  int n_it = 0, converged = 0;
  double max_diff = 0.0;
  for (int it = 0; it < 30; ++it) {
    nts_element_system sys_f, sys_r;
    double F[NU], J[NU * NU], Fr[NU], Jr[NU * NU];
    global_system(&facet, &full, &params, c->force, &sys_f, F, J);
    global_system(&facet, &red, &params, c->force, &sys_r, Fr, Jr);
    history[n_it++] = max_abs(F, NU);
    if (history[n_it - 1] < 1e-13) {
      converged = 1;
      break;
    }
    /* full Newton step */
    double dx[NU];
    for (int i = 0; i < NU; ++i) dx[i] = -F[i];
    SK_CHECK(nts_solve_dense(NU, J, dx, 1) == 0);
    /* reduced: condensed element blocks + the spring, kept unknowns [q_s, lambda_n] */
    double Jc[16 * 16], rhs[16], K[16], dk[4];
    SK_CHECK(nts_condense(&sys_r, Jc, rhs) == 0);
    static const int kept[4] = {0, 1, 2, 15};
    for (int i = 0; i < 4; ++i) {
      for (int j = 0; j < 4; ++j) K[i * 4 + j] = Jc[kept[i] * 16 + kept[j]] + (i == j && i < 3 ? SPRING : 0.0);
      dk[i] = -Fr[i] + rhs[kept[i]];
    }
    SK_CHECK(nts_solve_dense(4, K, dk, 1) == 0);
    double dk_elem[16] = {0}, de[4];
    for (int i = 0; i < 4; ++i) dk_elem[kept[i]] = dk[i];
    SK_CHECK(nts_recover(&sys_r, dk_elem, de) == 0);
    /* update both */
    for (int i = 0; i < 3; ++i) {
      q_full[i] += dx[i];
      q_red[i] += dk[i];
    }
    full.lambda_n += dx[3];
    red.lambda_n += dk[3];
    for (int a = 0; a < 2; ++a) {
      full.f[a] += dx[4 + a];
      full.lambda_aug[a] += dx[6 + a];
      red.f[a] += de[a];
      red.lambda_aug[a] += de[2 + a];
    }
    double diff = 0.0;
    for (int i = 0; i < 3; ++i) diff = fmax(diff, fabs(q_full[i] - q_red[i]));
    diff = fmax(diff, fabs(full.lambda_n - red.lambda_n));
    for (int a = 0; a < 2; ++a)
      diff = fmax(diff, fmax(fabs(full.f[a] - red.f[a]), fabs(full.lambda_aug[a] - red.lambda_aug[a])));
    max_diff = fmax(max_diff, diff);
  }
  printf("%s: residual history", c->name);
  for (int k = 0; k < n_it; ++k) printf(" %.1e", history[k]);
  printf("\n  max |iterate(none) - iterate(reduced)| = %.1e\n", max_diff);
  SK_CHECK(converged);
  SK_CHECK(max_diff < 1e-12);
  /* quadratic convergence once in the basin (the residual below 1e-1, forces ~8 here) */
  SK_CHECK(quadratic_rate(history, n_it) == 0);

  /* the solution: constraints satisfied, lambda_aug from (52), compressive lambda_n */
  nts_element_system sys;
  nts_element_build(&facet, &full, &params, &sys);
  for (int k = 0; k < 3; ++k) SK_CHECK(fabs(sys.geo_end.phi[k]) < 1e-13);
  double la[2];
  SK_CHECK(nts_lambda_aug(&sys.geo_hat, full.lambda_n, sys.friction.t_used, la) == 0);
  SK_CHECK_CLOSE(la[0], full.lambda_aug[0], 1e-12);
  SK_CHECK_CLOSE(la[1], full.lambda_aug[1], 1e-12);
  SK_CHECK(full.lambda_n < 0.0);
  printf("  lambda_n = %.6f, f = (%.6f, %.6f), t_T = (%.6f, %.6f), %s\n", full.lambda_n, full.f[0], full.f[1],
         sys.friction.t_used[0], sys.friction.t_used[1], sys.friction.slip ? "slip" : "stick");
  return sys.friction.slip;
}

int main(void) {
  const newton_case frictionless = {"frictionless, backward Euler", 1.0, 0.0, 0.0, {2.0, -1.0, -8.0}};
  const newton_case stick = {"mu 0.5 stick, backward Euler", 1.0, 0.5, 50.0, {0.5, -0.3, -8.0}};
  const newton_case slip = {"mu 0.5 slip, backward Euler", 1.0, 0.5, 50.0, {5.0, -3.0, -8.0}};
  const newton_case mid_stick = {"mu 0.5 stick, midpoint", 0.5, 0.5, 50.0, {0.5, -0.3, -8.0}};
  const newton_case mid_slip = {"mu 0.5 slip, midpoint", 0.5, 0.5, 50.0, {5.0, -3.0, -8.0}};
  quadratic_rate_self_test();
  run(&frictionless);
  SK_CHECK(run(&stick) == 0);
  SK_CHECK(run(&slip) == 1);
  SK_CHECK(run(&mid_stick) == 0);
  SK_CHECK(run(&mid_slip) == 1);
  return sk_test_finish("test_nts_newton");
}
