/* covariant-penalty kernel: each tangent part against central differences of the residual through its own channel
 * (main: the kinematics, rotational: the frame at fixed xi and the weights, curvature: the frame through xi), the
 * sum against differences of the whole residual; stick and slip; sts and nts on a warped QUAD4 (the contact point
 * crossed over from a neighbouring face) and a curved QUAD9 master, stas against the parabolic cylinder, plane and
 * sphere; the paper form's stick matrix symmetric, the exact one not; frame indifference. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "kernel.h"
#include "sk_test.h"
#include "stickslip/fe.h"

static const double FD_STEP = 1e-6;
/* |K - FD| / max|K| measured 4e-12 ... 2.4e-10 (the sphere, whose ray has the largest third derivative) */
static const double FD_TOL = 1e-9;

static double K_store[CP_N_PARTS][CP_MAX_DOFS * CP_MAX_DOFS];
static double *K_parts[CP_N_PARTS] = {K_store[0], K_store[1], K_store[2]};
static const int ALL_PARTS[CP_N_PARTS] = {1, 1, 1};
static int last_nd; /* local dofs of the last check_parts */

/* The master surface z = surface(x, y): curved and twisted so that h_ab, h_12 and the Christoffel symbols are not 0. */
static double surface(double x, double y) { return -0.15 * x * x - 0.08 * y * y + 0.06 * x * y + 0.02 * x; }

/* A face over [x0, x0 + 1] x [0, 1], distorted in plane, nodes on the surface (QUAD4: warped, QUAD9: curved). */
static void face_nodes(sk_elem_type type, double x0, double *xf) {
  const double *xi = sk_elem_node_coords(type);
  for (int a = 0; a < sk_elem_nen(type); ++a) {
    double u = xi[2 * a], v = xi[2 * a + 1];
    double x = x0 + 0.5 + 0.5 * u + 0.04 * u * v, y = 0.5 + 0.5 * v + 0.03 * u * u;
    xf[3 * a] = x;
    xf[3 * a + 1] = y;
    xf[3 * a + 2] = surface(x, y);
  }
}

typedef struct {
  const char *name;
  cp_point pt;
  cp_params par;
  double x[3 * CP_MAX_NODES];
  sk_obstacle obstacle;
} scenario;

static void gather(const cp_point *pt, const double *x, double *xf) {
  for (int k = 0; k < pt->master.nen; ++k) memcpy(xf + 3 * k, x + 3 * pt->master_nodes[k], 3 * sizeof *xf);
}

static void slave_point(const cp_point *pt, const double *x, double *r) {
  r[0] = r[1] = r[2] = 0.0;
  for (int a = 0; a < pt->n_slave; ++a)
    for (int i = 0; i < 3; ++i) r[i] += pt->S[a] * x[3 * pt->slave[a] + i];
}

/* The closest point of the slave point at positions x, Newton from xi. */
static int closest(const cp_point *pt, const double *x, double xi[2]) {
  if (pt->variant == CP_STAS) return 1;
  double xf[3 * CP_MAX_FACE_NODES], r[3];
  gather(pt, x, xf);
  slave_point(pt, x, r);
  return cp_closest_point(&pt->master, xf, r, xi, 50) > 0;
}

/* sts or nts over a QUAD4 or QUAD9 master face; `crossed`: the last step's contact point was on the neighbouring
 * face to the left (QUAD4 only), otherwise on the same face. t_n picks stick or slip. */
static void build_deformable(scenario *sc, const char *name, cp_variant variant, sk_elem_type master_type,
                             int crossed, const double t_n[3], double mu) {
  memset(sc, 0, sizeof *sc);
  sc->name = name;
  cp_point *pt = &sc->pt;
  pt->variant = variant;
  pt->x = sc->x;
  int nl = 0;
  /* below the curved surface; a bilinear QUAD4 master lies below it (chords of a concave surface) */
  const double depth = master_type == SK_QUAD4 ? 0.06 : 0.012;
  /* crossed: the point is just past the shared edge, so that a stuck point has a small slip increment */
  const double xc = crossed ? 0.08 : 0.42;
  /* slave: a QUAD4 face above the master (sts: its Gauss point at eta = (0.3, -0.2)) or one node (nts) */
  if (variant == CP_STS) {
    const double eta[2] = {0.3, -0.2};
    double N[4];
    sk_elem_shape(SK_QUAD4, eta, N, NULL);
    const double *xi = sk_elem_node_coords(SK_QUAD4);
    for (int a = 0; a < 4; ++a) {
      double x = xc + 0.18 * xi[2 * a] + 0.02 * xi[2 * a + 1], y = 0.55 + 0.15 * xi[2 * a + 1];
      sc->x[3 * a] = x;
      sc->x[3 * a + 1] = y;
      sc->x[3 * a + 2] = surface(x, y) - depth + 0.004 * xi[2 * a];
      pt->slave[a] = a;
      pt->S[a] = N[a];
    }
    pt->n_slave = 4;
    nl = 4;
  } else {
    sc->x[0] = xc + 0.01;
    sc->x[1] = 0.52;
    sc->x[2] = surface(sc->x[0], 0.52) - depth;
    pt->slave[0] = 0;
    pt->S[0] = 1.0;
    pt->n_slave = 1;
    nl = 1;
  }
  cp_face_init(&pt->master, master_type, sk_elem_shape, sk_elem_shape_hessian);
  double xf[3 * CP_MAX_FACE_NODES];
  face_nodes(master_type, 0.0, xf);
  for (int k = 0; k < pt->master.nen; ++k) {
    memcpy(sc->x + 3 * (nl + k), xf + 3 * k, 3 * sizeof(double));
    pt->master_nodes[k] = nl + k;
  }
  const int master0 = nl;
  nl += pt->master.nen;
  if (crossed) { /* the neighbour [-1, 0] x [0, 1] shares the master's nodes 0 and 3 (its nodes 1 and 2) */
    double xo[3 * 4];
    face_nodes(SK_QUAD4, -1.0, xo);
    int old[4] = {nl, master0 + 0, master0 + 3, nl + 1};
    memcpy(sc->x + 3 * nl, xo, 3 * sizeof(double));
    memcpy(sc->x + 3 * (nl + 1), xo + 9, 3 * sizeof(double));
    nl += 2;
    const double xi_n[2] = {0.85, 0.1};
    sk_elem_shape(SK_QUAD4, xi_n, pt->N_old, NULL);
    memcpy(pt->old_nodes, old, sizeof old);
    pt->n_old = 4;
  } else {
    const double xi_n[2] = {-0.25, 0.15};
    sk_elem_shape(master_type, xi_n, pt->N_old, NULL);
    for (int k = 0; k < pt->master.nen; ++k) pt->old_nodes[k] = pt->master_nodes[k];
    pt->n_old = pt->master.nen;
  }
  pt->n_local = nl;
  pt->history = 1;
  memcpy(pt->t_n, t_n, 3 * sizeof(double));
  pt->xi[0] = pt->xi[1] = 0.0;
  SK_CHECK(closest(pt, sc->x, pt->xi));
  sc->par = (cp_params){.eps_n = 1e4, .eps_t = 150.0, .mu = mu, .weight = 0.37, .touch_tol = 1e-12};
}

/* stas: a deformable face (normal down) over the parabolic cylinder z = c x^2 (or a plane / sphere), Gauss point
 * xi = (0.35, -0.45). */
static void build_stas(scenario *sc, const char *name, sk_elem_type type, sk_obstacle_kind kind, const double t_n[3],
                       double mu) {
  memset(sc, 0, sizeof *sc);
  sc->name = name;
  cp_point *pt = &sc->pt;
  pt->variant = CP_STAS;
  pt->x = sc->x;
  cp_face_init(&pt->master, type, sk_elem_shape, sk_elem_shape_hessian);
  const double *xi = sk_elem_node_coords(type);
  for (int a = 0; a < pt->master.nen; ++a) {
    double u = xi[2 * a], v = xi[2 * a + 1];
    double x = 0.8 + 0.4 * v + 0.03 * u * v, y = 0.3 + 0.4 * u; /* a1 ~ +y, a2 ~ +x: n = a1 x a2 ~ -z */
    sc->x[3 * a] = x;
    sc->x[3 * a + 1] = y;
    sc->x[3 * a + 2] = 0.05 * x * x - 0.02 + 0.01 * u * v + 0.006 * u;
    pt->master_nodes[a] = a;
  }
  pt->n_local = pt->master.nen;
  pt->xi[0] = 0.35;
  pt->xi[1] = -0.45;
  sk_obstacle *ob = &sc->obstacle;
  ob->kind = kind;
  ob->point[2] = kind == SK_OBSTACLE_SPHERE ? -3.0 : kind == SK_OBSTACLE_PLANE ? 0.1 : 0.0;
  ob->normal[0] = kind == SK_OBSTACLE_PLANE ? 0.1 : 0.0;
  ob->normal[2] = 1.0;
  ob->axis[1] = 1.0;
  ob->c = 0.05;
  ob->radius = 3.2;
  pt->obstacle = ob;
  pt->obstacle_d[0] = 0.01;
  pt->obstacle_d[1] = -0.02;
  pt->max_depth = 0.5;
  pt->history = 1;
  memcpy(pt->t_n, t_n, 3 * sizeof(double));
  pt->anchor[0] = 0.60; /* the Gauss point is near (0.62, 0.44) */
  pt->anchor[1] = 0.465;
  pt->anchor[2] = 0.0;
  sc->par = (cp_params){.eps_n = 1e4, .eps_t = 300.0, .mu = mu, .weight = 0.21, .touch_tol = 1e-12};
}

static double max_abs(const double *v, int n) {
  double m = 0.0;
  for (int i = 0; i < n; ++i) m = fmax(m, fabs(v[i]));
  return m;
}

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
  return sk_test_finish("test_covariant_kernel");
}
