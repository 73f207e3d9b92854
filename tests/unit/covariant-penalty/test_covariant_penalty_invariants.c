/* covariant-penalty kernel: the paper's checks that are not finite differences.
 * - The paper form's stick matrix is symmetric to round-off (the paper: ||K - K^T|| / ||K|| ~ 1e-15); the exact
 *   tangent of the discrete algorithm is not (docs §5).
 * - Frictionless, the paper's parts are the leading terms of the exact ones: the main parts agree to round-off, the
 *   rotational and curvature parts differ by O(p g), i.e. by a quarter when the penetration halves.
 * - Frame indifference: the same step in a rotated and translated frame gives the rotated residual and tangent.
 * - Flat and C1 surfaces: a stuck point carries |t| = eps_t |x - x_0| (80), transported components are unchanged
 *   without motion (52), a slipping one |t| = mu p, and a point that crosses an element edge gets exactly the
 *   tractions it gets on one face spanning both (no jump, (47) and (51)). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cp_test_support.h"

static double K_store[CP_N_PARTS][CP_MAX_DOFS * CP_MAX_DOFS];
static double *K_parts[CP_N_PARTS] = {K_store[0], K_store[1], K_store[2]};
static const int ALL_PARTS[CP_N_PARTS] = {1, 1, 1};
static double K_sum[CP_MAX_DOFS * CP_MAX_DOFS];

static int eval_sum(const scenario *sc, cp_form form, cp_result *res) {
  SK_CHECK(cp_point_eval(&sc->pt, &sc->par, form, ALL_PARTS, res, K_parts) == 0);
  const int nd = res->nd;
  for (int i = 0; i < nd * nd; ++i) K_sum[i] = K_parts[0][i] + K_parts[1][i] + K_parts[2][i];
  return nd;
}

static double asymmetry(const double *K, int nd) {
  double a = 0.0;
  for (int i = 0; i < nd; ++i)
    for (int j = 0; j < nd; ++j) a = fmax(a, fabs(K[i * nd + j] - K[j * nd + i]));
  return a / max_abs(K, nd * nd);
}

/* ---- symmetry ------------------------------------------------------------------------------------------------- */
static void check_symmetry(void) {
  const double stick_t[3] = {3.0, -2.0, 0.5}, stas_t[3] = {1.0, 2.0, 0.3};
  scenario sc;
  struct { const char *name; int kind; } cases[] = {
      {"sts QUAD4 crossed edge", 0}, {"sts QUAD9 curved", 1}, {"nts QUAD9 curved", 2}, {"stas QUAD4 parabolic", 3}};
  printf("stick: ||K - K^T|| / ||K|| (paper form; exact form)\n");
  for (int k = 0; k < 4; ++k) {
    switch (cases[k].kind) {
    case 0: build_deformable(&sc, cases[k].name, CP_STS, SK_QUAD4, 1, stick_t, 0.3); break;
    case 1: build_deformable(&sc, cases[k].name, CP_STS, SK_QUAD9, 0, stick_t, 0.3); break;
    case 2: build_deformable(&sc, cases[k].name, CP_NTS, SK_QUAD9, 0, stick_t, 0.3); break;
    default: build_stas(&sc, cases[k].name, SK_QUAD4, SK_OBSTACLE_PARABOLIC_CYLINDER, stas_t, 0.3); break;
    }
    cp_result res;
    int nd = eval_sum(&sc, CP_FORM_PAPER, &res);
    SK_CHECK(res.state == CP_STICK);
    double paper = asymmetry(K_sum, nd), parts = 0.0;
    for (int part = 0; part < CP_N_PARTS; ++part)
      if (max_abs(K_parts[part], nd * nd) > 0.0) parts = fmax(parts, asymmetry(K_parts[part], nd));
    nd = eval_sum(&sc, CP_FORM_EXACT, &res);
    double exact = asymmetry(K_sum, nd);
    printf("  %-24s paper %.1e (parts %.1e); exact %.1e\n", cases[k].name, paper, parts, exact);
    SK_CHECK(paper < 1e-15 && parts < 1e-15);
    SK_CHECK(exact > 1e-5); /* the exact tangent of (47), (51), (77) is not symmetric (docs §5) */
  }
}

/* ---- paper vs exact, frictionless ------------------------------------------------------------------------------ */
static void paper_leading_order(void) {
  const double none[3] = {0.0, 0.0, 0.0};
  double diff[2][CP_N_PARTS], size[2][CP_N_PARTS];
  static double K_paper[CP_N_PARTS][CP_MAX_DOFS * CP_MAX_DOFS];
  for (int level = 0; level < 2; ++level) {
    scenario sc;
    build_deformable(&sc, "nts QUAD9", CP_NTS, SK_QUAD9, 0, none, 0.0);
    double depth = level == 0 ? 0.012 : 0.006; /* penetration along the vertical */
    sc.x[2] = surface(sc.x[0], sc.x[1]) - depth;
    SK_CHECK(closest(&sc.pt, sc.x, sc.pt.xi));
    cp_result res;
    double *Kp[CP_N_PARTS] = {K_paper[0], K_paper[1], K_paper[2]};
    SK_CHECK(cp_point_eval(&sc.pt, &sc.par, CP_FORM_PAPER, ALL_PARTS, &res, Kp) == 0);
    int nd = eval_sum(&sc, CP_FORM_EXACT, &res);
    for (int part = 0; part < CP_N_PARTS; ++part) {
      double d = 0.0;
      for (int i = 0; i < nd * nd; ++i) d = fmax(d, fabs(K_parts[part][i] - K_paper[part][i]));
      diff[level][part] = d;
      size[level][part] = max_abs(K_parts[part], nd * nd);
    }
  }
  printf("frictionless, paper vs exact (max |difference|, penetration halved):\n");
  const char *names[CP_N_PARTS] = {"main", "rotational", "curvature"};
  for (int part = 0; part < CP_N_PARTS; ++part)
    printf("  %-10s |K| %.3e -> %.3e   difference %.3e -> %.3e\n", names[part], size[0][part], size[1][part],
           diff[0][part], diff[1][part]);
  SK_CHECK(diff[0][CP_MAIN] < 1e-12 * size[0][CP_MAIN] && diff[1][CP_MAIN] < 1e-12 * size[1][CP_MAIN]);
  for (int part = CP_ROTATIONAL; part <= CP_CURVATURE; ++part) {
    double ratio = diff[0][part] / diff[1][part], part_ratio = size[0][part] / size[1][part];
    SK_CHECK(diff[0][part] > 0.0 && diff[0][part] < 0.05 * size[0][part]);
    SK_CHECK(ratio > 3.5 && ratio < 4.5);           /* O(g^2) */
    SK_CHECK(part_ratio > 1.8 && part_ratio < 2.2); /* the parts themselves are O(p) = O(g) */
  }
}

/* ---- frame indifference ---------------------------------------------------------------------------------------- */
static void rotate(const double Q[3][3], const double *v, double *out) {
  for (int i = 0; i < 3; ++i) out[i] = Q[i][0] * v[0] + Q[i][1] * v[1] + Q[i][2] * v[2];
}

static void check_frame(scenario *sc) {
  const double axis[3] = {1.0 / sqrt(14.0), 2.0 / sqrt(14.0), 3.0 / sqrt(14.0)}, angle = 0.9, shift[3] = {2, -1, 3};
  double Q[3][3], c = cos(angle), s = sin(angle);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double cross = (i == j) ? 0.0 : axis[3 - i - j] * (((j - i + 3) % 3 == 1) ? -1.0 : 1.0);
      Q[i][j] = c * (i == j) + (1.0 - c) * axis[i] * axis[j] + s * cross;
    }
  cp_result r0, r1;
  int nd = eval_sum(sc, CP_FORM_EXACT, &r0);
  static double K0[CP_MAX_DOFS * CP_MAX_DOFS];
  memcpy(K0, K_sum, (size_t)nd * nd * sizeof(double));
  scenario rs = *sc;
  rs.pt.x = rs.x;
  for (int a = 0; a < sc->pt.n_local; ++a) {
    rotate(Q, sc->x + 3 * a, rs.x + 3 * a);
    for (int i = 0; i < 3; ++i) rs.x[3 * a + i] += shift[i];
  }
  rotate(Q, sc->pt.t_n, rs.pt.t_n);
  if (sc->pt.variant == CP_STAS) {
    rs.pt.distance_ctx = &rs.obstacle;
    rotate(Q, sc->obstacle.motion_d[0], rs.obstacle.motion_d[0]);
    rotate(Q, sc->obstacle.point, rs.obstacle.point);
    rotate(Q, sc->obstacle.normal, rs.obstacle.normal);
    rotate(Q, sc->obstacle.axis, rs.obstacle.axis);
    rotate(Q, sc->pt.obstacle_d, rs.pt.obstacle_d);
    rotate(Q, sc->pt.anchor, rs.pt.anchor);
    for (int i = 0; i < 3; ++i) {
      rs.obstacle.point[i] += shift[i];
      rs.pt.anchor[i] += shift[i];
    }
  }
  eval_sum(&rs, CP_FORM_EXACT, &r1);
  SK_CHECK(r1.state == r0.state);
  SK_CHECK_CLOSE(r1.g, r0.g, 1e-12);
  SK_CHECK_CLOSE(r1.p, r0.p, 1e-12);
  double err_R = 0.0, err_K = 0.0, scale_K = max_abs(K0, nd * nd);
  for (int a = 0; a < sc->pt.n_local; ++a) {
    double QR[3];
    rotate(Q, r0.R + 3 * a, QR);
    for (int i = 0; i < 3; ++i) err_R = fmax(err_R, fabs(r1.R[3 * a + i] - QR[i]));
    for (int b = 0; b < sc->pt.n_local; ++b)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) { /* (Q K Q^T)_ij of block (a, b) */
          double v = 0.0;
          for (int k = 0; k < 3; ++k)
            for (int l = 0; l < 3; ++l) v += Q[i][k] * K0[(3 * a + k) * nd + 3 * b + l] * Q[j][l];
          err_K = fmax(err_K, fabs(K_sum[(3 * a + i) * nd + 3 * b + j] - v));
        }
  }
  printf("  %-30s |R' - Q R| %.1e (|R| %.1e), |K' - Q K Q^T| / |K| %.1e\n", sc->name, err_R,
         max_abs(r0.R, nd), err_K / scale_K);
  SK_CHECK(err_R < 1e-12 * max_abs(r0.R, nd));
  SK_CHECK(err_K < 1e-12 * scale_K);
}

static void frame_indifference(void) {
  const double slip_t[3] = {240.0, 90.0, 15.0}, stick_t[3] = {3.0, -2.0, 0.5}, stas_t[3] = {400.0, -250.0, 5.0};
  scenario sc;
  printf("frame indifference (rotation 0.9 rad about (1,2,3), translation):\n");
  build_deformable(&sc, "sts QUAD4 crossed, stick", CP_STS, SK_QUAD4, 1, stick_t, 0.3);
  check_frame(&sc);
  build_deformable(&sc, "sts QUAD9, slip", CP_STS, SK_QUAD9, 0, slip_t, 0.3);
  check_frame(&sc);
  build_stas(&sc, "stas parabolic cylinder, slip", SK_QUAD4, SK_OBSTACLE_PARABOLIC_CYLINDER, stas_t, 0.3);
  check_frame(&sc);
}

/* ---- flat and C1 surfaces: a node dragged across an element edge --------------------------------------------- */
typedef struct {
  double x[3 * 16];     /* local nodes: 0 the slave node, then the master nodes */
  int n_nodes, n_faces, nen;
  int faces[2][9];
  sk_elem_type type;
} strip;

/* Faces over [0, 2] x [0, 1] on z = c x^2 (exact for QUAD9; c = 0 for QUAD4): one face, or two split at x = 1. */
static void build_strip(strip *s, sk_elem_type type, double c, int two) {
  memset(s, 0, sizeof *s);
  s->type = type;
  s->nen = sk_elem_nen(type);
  s->n_faces = two ? 2 : 1;
  const double *xi = sk_elem_node_coords(type);
  int nl = 1;
  for (int f = 0; f < s->n_faces; ++f)
    for (int a = 0; a < s->nen; ++a) {
      double width = two ? 1.0 : 2.0, x = f + width * 0.5 * (1.0 + xi[2 * a]), y = 0.5 * (1.0 + xi[2 * a + 1]);
      int node = -1;
      for (int b = 1; b < nl && node < 0; ++b) /* shared edge nodes */
        if (fabs(s->x[3 * b] - x) < 1e-14 && fabs(s->x[3 * b + 1] - y) < 1e-14) node = b;
      if (node < 0) {
        node = nl++;
        s->x[3 * node] = x;
        s->x[3 * node + 1] = y;
        s->x[3 * node + 2] = c * x * x;
      }
      s->faces[f][a] = node;
    }
  s->n_nodes = nl;
}

/* Drags a slave node at depth 0.002 below z = c x^2 to x = 0.62 + shift[k] (y along with 0.3 shift[k]), k = 0 ..
 * n_steps, committing history as the plugin does (face, xi, t); tractions go to t_out (3 per step). */
static void drag(strip *s, double c, double mu, int n_steps, const double *shift, double *t_out, cp_state *states) {
  cp_params par = {.eps_n = 1e4, .eps_t = 2e3, .mu = mu, .weight = 1.0, .touch_tol = 1e-12};
  int hist_face = -1;
  double hist_xi[2] = {0, 0}, t_n[3] = {0, 0, 0};
  for (int k = 0; k <= n_steps; ++k) {
    double xs = 0.62 + shift[k], ys = 0.4 + 0.3 * shift[k];
    s->x[0] = xs;
    s->x[1] = ys;
    s->x[2] = c * xs * xs - 0.002;
    cp_point pt;
    memset(&pt, 0, sizeof pt);
    pt.variant = CP_NTS;
    pt.x = s->x;
    pt.n_local = s->n_nodes;
    pt.n_slave = 1;
    pt.S[0] = 1.0;
    cp_face_init(&pt.master, s->type, sk_elem_shape, sk_elem_shape_hessian);
    int face = -1;
    for (int f = 0; f < s->n_faces && face < 0; ++f) {
      double xf[27], xi[2] = {0, 0};
      for (int a = 0; a < s->nen; ++a) memcpy(xf + 3 * a, s->x + 3 * s->faces[f][a], 3 * sizeof(double));
      if (cp_closest_point(&pt.master, xf, s->x, xi, 50) > 0 && fabs(xi[0]) <= 1.0 && fabs(xi[1]) <= 1.0) {
        face = f;
        memcpy(pt.xi, xi, sizeof xi);
      }
    }
    SK_CHECK(face >= 0);
    memcpy(pt.master_nodes, s->faces[face], sizeof pt.master_nodes);
    if (hist_face < 0) { /* the zero-load projection: the starting point is the first anchor, t = 0 */
      hist_face = face;
      memcpy(hist_xi, pt.xi, sizeof hist_xi);
    }
    pt.history = 1;
    memcpy(pt.t_n, t_n, sizeof t_n);
    pt.n_old = s->nen;
    memcpy(pt.old_nodes, s->faces[hist_face], sizeof pt.old_nodes);
    sk_elem_shape(s->type, hist_xi, pt.N_old, NULL);
    cp_result r;
    cp_point_residual(&pt, &par, NULL, &r);
    memcpy(t_out + 3 * k, r.t, 3 * sizeof(double));
    states[k] = r.state;
    if (r.state == CP_SLIP) SK_CHECK_CLOSE(sqrt(r.t[0] * r.t[0] + r.t[1] * r.t[1] + r.t[2] * r.t[2]), mu * r.p, 1e-13);
    hist_face = face; /* commit */
    memcpy(hist_xi, pt.xi, sizeof hist_xi);
    memcpy(t_n, r.t, sizeof t_n);
  }
}

static void edge_crossing(sk_elem_type type, double c, double mu, const char *name) {
  enum { STEPS = 14 };
  const double dx = 0.05; /* x from 0.62 to 1.32: crosses x = 1 between steps 7 and 8 */
  strip one, two;
  build_strip(&one, type, c, 0);
  build_strip(&two, type, c, 1);
  double t1[3 * (STEPS + 1)], t2[3 * (STEPS + 1)], shift[STEPS + 1];
  cp_state s1[STEPS + 1], s2[STEPS + 1];
  for (int k = 0; k <= STEPS; ++k) shift[k] = k * dx;
  drag(&one, c, mu, STEPS, shift, t1, s1);
  drag(&two, c, mu, STEPS, shift, t2, s2);
  double jump = 0.0, scale = max_abs(t1, 3 * (STEPS + 1));
  int slips = 0;
  for (int k = 0; k <= STEPS; ++k) {
    SK_CHECK(s1[k] == s2[k]);
    slips += s1[k] == CP_SLIP;
    for (int i = 0; i < 3; ++i) jump = fmax(jump, fabs(t1[3 * k + i] - t2[3 * k + i]));
  }
  printf("  %-28s |t| up to %.3e, %2d of %d steps slipping; two faces vs one: max |difference| %.1e\n", name, scale,
         slips, STEPS + 1, jump);
  SK_CHECK(scale > 0.0 && jump < 1e-12 * scale);
  if (c == 0.0 && mu > 1.0) { /* flat, stuck throughout: t = -eps_t (x - x_0), (80) */
    double err = 0.0;
    for (int k = 0; k <= STEPS; ++k) {
      double expect[2] = {-2e3 * k * dx, -2e3 * 0.3 * k * dx};
      err = fmax(err, fmax(fabs(t2[3 * k] - expect[0]), fabs(t2[3 * k + 1] - expect[1])));
    }
    printf("  %-28s stuck: |t - (-eps_t (x - x_0))| %.1e\n", "", err);
    SK_CHECK(err < 1e-12 * scale);
  }
}

/* Without motion the transported traction keeps its components (52): a stuck node on the curved strip moves in two
 * steps, then stays for one; its traction stays the same to round-off. */
static void transport_without_motion(void) {
  strip s;
  build_strip(&s, SK_QUAD9, 0.1, 1);
  const double shift[4] = {0.0, 0.03, 0.06, 0.06};
  double t[12];
  cp_state st[4];
  drag(&s, 0.1, 10.0, 3, shift, t, st);
  double change = fmax(fabs(t[9] - t[6]), fmax(fabs(t[10] - t[7]), fabs(t[11] - t[8])));
  printf("  curved QUAD9, a stuck node at rest for a step: |t| %.3e, change %.1e\n", max_abs(t + 6, 3), change);
  SK_CHECK(st[3] == CP_STICK && max_abs(t + 6, 3) > 10.0);
  SK_CHECK(change < 1e-13 * max_abs(t + 6, 3));
}

/* On the cone to round-off (a point that slipped in the last step begins the next one there) the tangent is the slip
 * branch's: equal to that of the same point a hair outside the cone, not to the stick tangent, while the traction
 * (the reported state: stick) is the stick law's. Both forms. */
static void tangent_on_the_cone(void) {
  static double K_slip[CP_MAX_DOFS * CP_MAX_DOFS], K_cone[CP_MAX_DOFS * CP_MAX_DOFS];
  const double none[3] = {0.0, 0.0, 0.0}, u[3] = {0.6, 0.8, 0.0};
  scenario sc;
  printf("a trial on the Coulomb cone to round-off: |K - K(slip)| / |K|, |K(stick) - K(slip)| / |K|\n");
  for (int form = CP_FORM_EXACT; form <= CP_FORM_PAPER; ++form) {
    build_deformable(&sc, "sts QUAD9 curved", CP_STS, SK_QUAD9, 0, none, 0.3);
    cp_result res;
    eval_sum(&sc, (cp_form)form, &res); /* t_n = 0: tau = -eps_t P Delta rho */
    double base[3], e[3], tn[3];
    memcpy(base, res.tau, sizeof base);
    double un = u[0] * res.n[0] + u[1] * res.n[1] + u[2] * res.n[2], norm = 0.0; /* a tangent direction */
    for (int i = 0; i < 3; ++i) norm += (u[i] - un * res.n[i]) * (u[i] - un * res.n[i]);
    for (int i = 0; i < 3; ++i) e[i] = (u[i] - un * res.n[i]) / sqrt(norm);
    const double limit = sc.par.mu * res.p, factors[3] = {1.0 - 1e-14, 1.0 + 1e-9, 0.9}; /* cone, slip, stick */
    double diff[3] = {0.0, 0.0, 0.0}, scale = 0.0;
    cp_state states[3];
    for (int k = 0; k < 3; ++k) {
      for (int i = 0; i < 3; ++i) tn[i] = factors[k] * limit * e[i] - base[i]; /* tau = P t_n + base */
      memcpy(sc.pt.t_n, tn, sizeof tn);
      const int nd = eval_sum(&sc, (cp_form)form, &res);
      states[k] = res.state;
      if (k == 1) {
        memcpy(K_slip, K_sum, sizeof(double) * (size_t)(nd * nd));
        scale = max_abs(K_slip, nd * nd);
      }
      if (k == 0) memcpy(K_cone, K_sum, sizeof(double) * (size_t)(nd * nd));
      if (k == 2)
        for (int i = 0; i < nd * nd; ++i) {
          diff[0] = fmax(diff[0], fabs(K_cone[i] - K_slip[i]));
          diff[2] = fmax(diff[2], fabs(K_sum[i] - K_slip[i]));
        }
    }
    printf("  %-6s states %d %d %d: on the cone %.1e, stick %.1e\n", form == CP_FORM_EXACT ? "exact" : "paper",
           states[0], states[1], states[2], diff[0] / scale, diff[2] / scale);
    SK_CHECK(states[0] == CP_STICK && states[1] == CP_SLIP && states[2] == CP_STICK);
    SK_CHECK(diff[0] < 1e-7 * scale);  /* the slip branch, to the 1e-9 the comparison point lies outside */
    SK_CHECK(diff[2] > 1e-2 * scale);  /* and not the stick tangent */
  }
}

int main(void) {
  tangent_on_the_cone();
  check_symmetry();
  paper_leading_order();
  frame_indifference();
  printf("a node dragged across an element edge (two faces against one face over both):\n");
  edge_crossing(SK_QUAD4, 0.0, 100.0, "flat QUAD4, stuck");
  edge_crossing(SK_QUAD4, 0.0, 0.3, "flat QUAD4, stick-slip");
  edge_crossing(SK_QUAD9, 0.1, 100.0, "z = 0.1 x^2 QUAD9, stuck");
  edge_crossing(SK_QUAD9, 0.1, 0.3, "z = 0.1 x^2 QUAD9, stick-slip");
  transport_without_motion();
  return sk_test_finish("test_covariant_penalty_invariants");
}
