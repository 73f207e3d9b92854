/* covariant-penalty kernel: each tangent part against central differences of the residual through its own channel
 * (main: the kinematics, rotational: the frame at fixed xi and the weights, curvature: the frame through xi), the
 * sum against differences of the whole residual; stick and slip; sts and nts on a warped QUAD4 (the contact point
 * crossed over from a neighbouring face) and a curved QUAD9 master, stas against the parabolic cylinder, plane and
 * sphere (test_covariant_penalty_invariants.c has the checks that are not differences). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cp_test_support.h"

static const double FD_STEP = 1e-6;
/* |K - FD| / max|K| measured 4e-12 ... 9.4e-10 (the sphere: its ray, by Newton on the distance, has the largest
 * third derivative) */
static const double FD_TOL = 3e-9;

static double K_store[CP_N_PARTS][CP_MAX_DOFS * CP_MAX_DOFS];
static double *K_parts[CP_N_PARTS] = {K_store[0], K_store[1], K_store[2]};
static const int ALL_PARTS[CP_N_PARTS] = {1, 1, 1};
static int last_nd; /* local dofs of the last check_parts */

/* Column c of each part against central differences through its channel; returns the largest relative error. */
static double check_parts(const scenario *sc, cp_form form, cp_state want_state, double tol) {
  cp_result res;
  SK_CHECK(cp_point_eval(&sc->pt, &sc->par, form, ALL_PARTS, &res, K_parts) == 0);
  SK_CHECK(res.state == want_state);
  if (res.state != want_state)
    printf("  %s: state %d (wanted %d), g %.3e, p %.3e, |tau| %.3e, xi (%.3f, %.3f)\n", sc->name, res.state,
           want_state, res.g, res.p, sqrt(res.tau[0] * res.tau[0] + res.tau[1] * res.tau[1] + res.tau[2] * res.tau[2]),
           sc->pt.xi[0], sc->pt.xi[1]);
  const int nd = res.nd;
  last_nd = nd;
  double scale = 0.0, part_size[CP_N_PARTS] = {0}, err[CP_N_PARTS + 1] = {0};
  for (int part = 0; part < CP_N_PARTS; ++part) {
    part_size[part] = max_abs(K_parts[part], nd * nd);
    scale = fmax(scale, part_size[part]);
  }
  for (int c = 0; c < nd; ++c) {
    double xp[3 * CP_MAX_NODES], xm[3 * CP_MAX_NODES], xip[2], xim[2];
    memcpy(xp, sc->x, sizeof xp);
    memcpy(xm, sc->x, sizeof xm);
    xp[c] += FD_STEP;
    xm[c] -= FD_STEP;
    memcpy(xip, sc->pt.xi, sizeof xip);
    memcpy(xim, sc->pt.xi, sizeof xim);
    SK_CHECK(closest(&sc->pt, xp, xip) && closest(&sc->pt, xm, xim));
    cp_channels chp[CP_N_PARTS + 1] = {{.x_K = xp, .xi_K = xip}, {.x_F = xp, .xi_W = xip}, {.xi_F = xip}, {0}};
    cp_channels chm[CP_N_PARTS + 1] = {{.x_K = xm, .xi_K = xim}, {.x_F = xm, .xi_W = xim}, {.xi_F = xim}, {0}};
    cp_point pp = sc->pt, pm = sc->pt;
    pp.x = xp;
    pm.x = xm;
    memcpy(pp.xi, xip, sizeof xip);
    memcpy(pm.xi, xim, sizeof xim);
    for (int part = 0; part <= CP_N_PARTS; ++part) {
      cp_result rp, rm;
      if (part < CP_N_PARTS) {
        cp_point_residual(&sc->pt, &sc->par, &chp[part], &rp);
        cp_point_residual(&sc->pt, &sc->par, &chm[part], &rm);
      } else {
        cp_point_residual(&pp, &sc->par, NULL, &rp);
        cp_point_residual(&pm, &sc->par, NULL, &rm);
      }
      SK_CHECK(rp.state == want_state && rm.state == want_state);
      for (int r = 0; r < nd; ++r) {
        double fd = (rp.R[r] - rm.R[r]) / (2.0 * FD_STEP), k = 0.0;
        if (part < CP_N_PARTS) k = K_parts[part][r * nd + c];
        else
          for (int q = 0; q < CP_N_PARTS; ++q) k += K_parts[q][r * nd + c];
        err[part] = fmax(err[part], fabs(fd - k) / scale);
      }
    }
  }
  double worst = 0.0;
  printf("  %-34s %s: |K| main %.2e rot %.2e curv %.2e; |K - FD|/|K| main %.1e rot %.1e curv %.1e sum %.1e\n",
         sc->name, want_state == CP_SLIP ? "slip " : "stick", part_size[0], part_size[1], part_size[2], err[0],
         err[1], err[2], err[3]);
  for (int part = 0; part <= CP_N_PARTS; ++part) {
    SK_CHECK(err[part] < tol);
    worst = fmax(worst, err[part]);
  }
  return worst;
}

static void deformable_cases(void) {
  const double stick_t[3] = {3.0, -2.0, 0.5}, slip_t[3] = {240.0, 90.0, 15.0};
  scenario sc;
  for (int variant = CP_STS; variant <= CP_NTS; ++variant) {
    const cp_variant v = (cp_variant)variant;
    const int sts = v == CP_STS;
    build_deformable(&sc, sts ? "sts QUAD4 warped, crossed edge" : "nts QUAD4 warped, crossed edge", v, SK_QUAD4, 1,
                     stick_t, 0.3);
    check_parts(&sc, CP_FORM_EXACT, CP_STICK, FD_TOL);
    build_deformable(&sc, sc.name, v, SK_QUAD4, 1, slip_t, 0.3);
    check_parts(&sc, CP_FORM_EXACT, CP_SLIP, FD_TOL);
    build_deformable(&sc, sts ? "sts QUAD9 curved" : "nts QUAD9 curved", v, SK_QUAD9, 0, stick_t, 0.3);
    check_parts(&sc, CP_FORM_EXACT, CP_STICK, FD_TOL);
    /* the curvature part must be there to be checked */
    SK_CHECK(max_abs(K_parts[CP_CURVATURE], last_nd * last_nd) > 1e-3 * max_abs(K_parts[CP_MAIN], last_nd * last_nd));
    build_deformable(&sc, sc.name, v, SK_QUAD9, 0, slip_t, 0.3);
    check_parts(&sc, CP_FORM_EXACT, CP_SLIP, FD_TOL);
    build_deformable(&sc, sts ? "sts QUAD9 frictionless" : "nts QUAD9 frictionless", v, SK_QUAD9, 0, slip_t, 0.0);
    check_parts(&sc, CP_FORM_EXACT, CP_STICK, FD_TOL);
  }
}

static void stas_cases(void) {
  const double stick_t[3] = {1.0, 2.0, 0.3}, slip_t[3] = {400.0, -250.0, 5.0};
  const sk_obstacle_kind kinds[3] = {SK_OBSTACLE_PARABOLIC_CYLINDER, SK_OBSTACLE_PLANE, SK_OBSTACLE_SPHERE};
  const char *names[3] = {"stas QUAD4 parabolic cylinder", "stas QUAD4 plane", "stas QUAD4 sphere"};
  scenario sc;
  for (int k = 0; k < 3; ++k) {
    build_stas(&sc, names[k], SK_QUAD4, kinds[k], stick_t, 0.3);
    check_parts(&sc, CP_FORM_EXACT, CP_STICK, FD_TOL);
    SK_CHECK(max_abs(K_parts[CP_CURVATURE], last_nd * last_nd) == 0.0); /* xi fixed: no curvature part */
    build_stas(&sc, names[k], SK_QUAD4, kinds[k], slip_t, 0.3);
    check_parts(&sc, CP_FORM_EXACT, CP_SLIP, FD_TOL);
  }
  build_stas(&sc, "stas QUAD9 parabolic cylinder", SK_QUAD9, SK_OBSTACLE_PARABOLIC_CYLINDER, slip_t, 0.3);
  check_parts(&sc, CP_FORM_EXACT, CP_SLIP, FD_TOL);
}

int main(void) {
  printf("tangent parts against channel differences (exact form):\n");
  deformable_cases();
  stas_cases();
  return sk_test_finish("test_covariant_penalty_kernel");
}
