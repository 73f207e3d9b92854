/* covariant-penalty tests: contact points on warped/curved master faces and against obstacles, shared by the kernel
 * tests (static helpers: each test program includes this once). */
#ifndef CP_TEST_SUPPORT_H
#define CP_TEST_SUPPORT_H

#include <math.h>
#include <string.h>

#include "kernel.h"
#include "sk_test.h"
#include "stickslip/contact.h"
#include "stickslip/fe.h"

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

/* The rigid surface for stas: the core's obstacle projection (what the plugin reaches through the host) at t = 0,
 * where the obstacle's motion table translates it by its first entry. */
static int obstacle_distance(void *ctx, const double y[3], double *distance, double normal[3]) {
  sk_surface_point pt;
  pt.struct_size = sizeof pt;
  if (sk_obstacle_project((const sk_obstacle *)ctx, 0.0, y, 3, &pt, distance) != SK_OK) return 0;
  memcpy(normal, pt.n, 3 * sizeof(double));
  return 1;
}

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
  ob->n_motion = 1; /* translated by (0.01, -0.02, 0) */
  ob->motion_d[0][0] = 0.01;
  ob->motion_d[0][1] = -0.02;
  pt->distance = obstacle_distance;
  pt->distance_ctx = ob;
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

#endif
