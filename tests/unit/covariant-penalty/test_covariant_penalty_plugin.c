/* covariant-penalty through its ABI table, with the plugin test kit (tests/support): the assembled operator.
 * - The assembled Jacobian of each tangent variant against central differences of the assembled residual (full),
 *   and each part (main = J(main-only), rotational = J(full) - J(no-rotational), curvature = J(full) -
 *   J(no-curvature)) against channel-wise differences of the plugin's own contact points assembled the same way:
 *   sts on a curved QUAD9 master, nts on a warped QUAD4 master, stas on the parabolic cylinder; stick and slip with a
 *   committed step; every entry inside the declared pattern.
 * - The paper form's assembled stick operator is symmetric to round-off.
 * - A stuck slave face dragged across a master element edge gets the tractions of a master face spanning both.
 * - Forces balance; parameter errors name the key. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "glue.h"
#include "plugin_kit.h"
#include "sk_test.h"
#include "stickslip/contact.h"
#include "stickslip/fe.h"

const sk_plugin *stickslip_plugin_entry(void);

enum { MAX_NODES = 40, MAX_DOFS = 3 * MAX_NODES };
static const double FD_STEP = 1e-6;
/* |part - channel FD| / |K| and |K - FD| / |K| measured <= 8.8e-11 */
static const double FD_TOL = 5e-10;

static double surface(double x, double y) { return -0.08 * x * x + 0.05 * y * y + 0.04 * x * y; }

/* ---- scenes ------------------------------------------------------------------------------------------------------ */
typedef struct {
  int n_nodes;
  double X[MAX_DOFS];
  int n_slave_faces, slave_nen, slave[4 * 9];
  sk_elem_type slave_type;
  int n_master_faces, master_nen, master[4 * 9];
  sk_elem_type master_type;
  int obstacle;
  sk_obstacle ob;
} layout;

/* nx x ny faces of `type` over [x0, x0 + w] x [y0, y0 + h] at z = surface + dz, nodes appended to L; `up`: normal +z. */
static int patch(layout *L, sk_elem_type type, int nx, int ny, double x0, double y0, double w, double h, double dz,
                 int up, int *conn) {
  const int order = type == SK_QUAD9 ? 2 : 1, px = order * nx + 1, py = order * ny + 1, first = L->n_nodes;
  for (int j = 0; j < py; ++j)
    for (int i = 0; i < px; ++i) {
      double x = x0 + w * i / (px - 1) + 0.02 * sin(3.0 * j), y = y0 + h * j / (py - 1) + 0.015 * cos(2.0 * i);
      double *X = L->X + 3 * L->n_nodes++;
      X[0] = x;
      X[1] = y;
      X[2] = surface(x, y) + dz + 0.003 * ((i + 2 * j) % 3);
    }
  const double *xi = sk_elem_node_coords(type);
  const int nen = sk_elem_nen(type);
  int n = 0;
  for (int fj = 0; fj < ny; ++fj)
    for (int fi = 0; fi < nx; ++fi, ++n)
      for (int a = 0; a < nen; ++a) {
        double u = xi[2 * a], v = up ? xi[2 * a + 1] : -xi[2 * a + 1]; /* mirrored in y: the normal flips */
        int i = order * fi + (int)lround(order * (u + 1) / 2), j = order * fj + (int)lround(order * (v + 1) / 2);
        conn[n * nen + a] = first + j * px + i;
      }
  return n;
}

typedef struct {
  kit k;
  const sk_plugin *plugin;
} instance;

static sk_status make(instance *s, const layout *L, const char *variant, const char *tangent, const char *form,
                      double mu) {
  memset(s, 0, sizeof *s);
  kit_init(&s->k, 3, L->n_nodes, L->X);
  kit_surface(&s->k, 0, L->slave_type, L->slave_nen, L->n_slave_faces, L->slave);
  if (L->obstacle) kit_obstacle(&s->k, &L->ob);
  else kit_surface(&s->k, 1, L->master_type, L->master_nen, L->n_master_faces, L->master);
  kit_param(&s->k, "penalty", 1e4);
  kit_param(&s->k, "penalty_tangential", 3e3);
  kit_param(&s->k, "mu", mu);
  if (variant) kit_param_text(&s->k, "variant", variant);
  kit_param_text(&s->k, "tangent", tangent);
  kit_param_text(&s->k, "tangent_form", form);
  s->plugin = stickslip_plugin_entry();
  return kit_create(&s->k, s->plugin, 0);
}

/* Step 1 from X to q1 (committed), then the state of step 2 from q1 to q2 (begun). */
static void two_steps(instance *s, const double *X, const double *q1, const double *q2) {
  kit_state(&s->k, X, q1, 0.0, 1.0, NULL);
  SK_CHECK(kit_begin(&s->k) == SK_OK);
  SK_CHECK(kit_commit(&s->k) == SK_OK);
  kit_state(&s->k, q1, q2, 1.0, 2.0, NULL);
  SK_CHECK(kit_begin(&s->k) == SK_OK);
}

/* The deformable layouts: a 2 x 2 QUAD4 slave patch (normal down) over a 2 x 2 master patch (normal up). */
static void deformable_layout(layout *L, sk_elem_type master_type) {
  memset(L, 0, sizeof *L);
  L->master_type = master_type;
  L->master_nen = sk_elem_nen(master_type);
  L->n_master_faces = patch(L, master_type, 2, 2, 0.0, 0.0, 2.0, 2.0, 0.0, 1, L->master);
  L->slave_type = SK_QUAD4;
  L->slave_nen = 4;
  L->n_slave_faces = patch(L, SK_QUAD4, 2, 2, 0.35, 0.3, 1.3, 1.35, -0.012, 0, L->slave);
}

/* stas: a 2 x 2 QUAD4 patch (normal down) pressed into the parabolic cylinder z = 0.05 x^2. */
static void stas_layout(layout *L) {
  memset(L, 0, sizeof *L);
  L->slave_type = SK_QUAD4;
  L->slave_nen = 4;
  L->n_slave_faces = patch(L, SK_QUAD4, 2, 2, 0.2, 0.1, 1.2, 1.1, -0.03, 0, L->slave);
  for (int a = 0; a < L->n_nodes; ++a) L->X[3 * a + 2] = 0.05 * L->X[3 * a] * L->X[3 * a] - 0.01 + 0.004 * (a % 3);
  L->obstacle = 1;
  L->ob.kind = SK_OBSTACLE_PARABOLIC_CYLINDER;
  L->ob.normal[2] = 1.0;
  L->ob.axis[1] = 1.0;
  L->ob.c = 0.05;
}

/* Step 1 at the reference positions; step 2 moves the slave by `slide` in x (and a little in y), bends the master. */
static void positions(const layout *L, double slide, double *q1, double *q2) {
  memcpy(q1, L->X, sizeof(double) * 3 * (size_t)L->n_nodes);
  memcpy(q2, L->X, sizeof(double) * 3 * (size_t)L->n_nodes);
  int is_slave[MAX_NODES] = {0};
  for (int f = 0; f < L->n_slave_faces * L->slave_nen; ++f) is_slave[L->slave[f]] = 1;
  for (int a = 0; a < L->n_nodes; ++a) {
    double *x = q2 + 3 * a;
    if (is_slave[a]) {
      x[0] += slide;
      x[1] += 0.3 * slide;
      x[2] -= 0.002;
    } else {
      x[2] += 0.01 * x[0] * x[1]; /* the master turns under the slave: rotational terms */
      x[0] += 0.004 * x[1];
    }
  }
}

/* ---- the assembled parts against channel-wise differences ---------------------------------------------------------- */

/* Adds the channel-wise central differences of every contact point of s at its current state into D[part] (n x n over
 * the kit's unknowns). */
static void channel_differences(instance *s, double *D[CP_N_PARTS]) {
  sk_instance *in = s->k.instance;
  const int64_t n = s->k.n;
  for (int p = 0; p < CP_N_PARTS; ++p) memset(D[p], 0, sizeof(double) * (size_t)(n * n));
  for (int e = 0; e < in->n_entities; ++e) {
    local_point L;
    if (!cp_local_point(in, &in->entities[e], &s->k.state, &L)) continue;
    const cp_params par = cp_point_params(in, &in->entities[e]);
    cp_result r0;
    cp_point_residual(&L.pt, &par, NULL, &r0);
    if (r0.state == CP_INACTIVE) continue;
    const int nd = r0.nd;
    for (int c = 0; c < nd; ++c) {
      double xp[3 * CP_MAX_NODES], xm[3 * CP_MAX_NODES], xip[2], xim[2];
      memcpy(xp, L.x, sizeof xp);
      memcpy(xm, L.x, sizeof xm);
      xp[c] += FD_STEP;
      xm[c] -= FD_STEP;
      memcpy(xip, L.pt.xi, sizeof xip);
      memcpy(xim, L.pt.xi, sizeof xim);
      if (L.pt.variant != CP_STAS) { /* the closest point moves with the positions */
        double fp[3 * CP_MAX_FACE_NODES], fm[3 * CP_MAX_FACE_NODES], rp[3] = {0}, rm[3] = {0};
        for (int k = 0; k < L.pt.master.nen; ++k)
          for (int i = 0; i < 3; ++i) {
            fp[3 * k + i] = xp[3 * L.pt.master_nodes[k] + i];
            fm[3 * k + i] = xm[3 * L.pt.master_nodes[k] + i];
          }
        for (int a = 0; a < L.pt.n_slave; ++a)
          for (int i = 0; i < 3; ++i) {
            rp[i] += L.pt.S[a] * xp[3 * L.pt.slave[a] + i];
            rm[i] += L.pt.S[a] * xm[3 * L.pt.slave[a] + i];
          }
        SK_CHECK(cp_closest_point(&L.pt.master, fp, rp, xip, 50) > 0 && cp_closest_point(&L.pt.master, fm, rm, xim, 50) > 0);
      }
      const cp_channels chp[CP_N_PARTS] = {{.x_K = xp, .xi_K = xip}, {.x_F = xp, .xi_W = xip}, {.xi_F = xip}};
      const cp_channels chm[CP_N_PARTS] = {{.x_K = xm, .xi_K = xim}, {.x_F = xm, .xi_W = xim}, {.xi_F = xim}};
      for (int p = 0; p < CP_N_PARTS; ++p) {
        cp_result rp, rm;
        cp_point_residual(&L.pt, &par, &chp[p], &rp);
        cp_point_residual(&L.pt, &par, &chm[p], &rm);
        SK_CHECK(rp.state == r0.state && rm.state == r0.state);
        for (int r = 0; r < nd; ++r)
          D[p][L.rows[r] * n + L.rows[c]] += (rp.R[r] - rm.R[r]) / (2.0 * FD_STEP);
      }
    }
  }
}

static double max_abs(const double *v, int64_t n) {
  double m = 0.0;
  for (int64_t i = 0; i < n; ++i) m = fmax(m, fabs(v[i]));
  return m;
}

/* Four instances (full, main-only, no-rotational, no-curvature) through the same two steps; each assembled part
 * against the assembled channel differences, and the full Jacobian against differences of the residual. */
static void check_parts(const char *name, const layout *L, const char *variant, double mu, double slide,
                        int want_slip) {
  static const char *const tangents[4] = {"full", "main-only", "no-rotational", "no-curvature"};
  instance s[4];
  double q1[MAX_DOFS], q2[MAX_DOFS];
  positions(L, slide, q1, q2);
  for (int v = 0; v < 4; ++v) {
    SK_CHECK(make(&s[v], L, variant, tangents[v], "exact", mu) == SK_OK);
    two_steps(&s[v], L->X, q1, q2);
  }
  const int64_t n = s[0].k.n;
  double *J[4], *D[CP_N_PARTS];
  for (int v = 0; v < 4; ++v) {
    J[v] = calloc((size_t)(n * n), sizeof(double));
    SK_CHECK(kit_jacobian(&s[v].k, q2, J[v], NULL) == SK_OK);
  }
  for (int p = 0; p < CP_N_PARTS; ++p) D[p] = calloc((size_t)(n * n), sizeof(double));
  channel_differences(&s[0], D);
  kit_points pts;
  SK_CHECK(kit_points_at(&s[0].k, &pts) == SK_OK);
  int active = 0, slipping = 0;
  for (int i = 0; i < pts.n; ++i) {
    active += pts.p[i].state != 0;
    slipping += pts.p[i].state == 2;
  }
  SK_CHECK(active > 0 && (want_slip ? slipping == active : slipping == 0));
  double scale = max_abs(J[0], n * n), err[CP_N_PARTS] = {0}, size[CP_N_PARTS] = {0};
  for (int64_t i = 0; i < n * n; ++i) {
    const double part[CP_N_PARTS] = {J[1][i], J[0][i] - J[2][i], J[0][i] - J[3][i]};
    for (int p = 0; p < CP_N_PARTS; ++p) {
      err[p] = fmax(err[p], fabs(part[p] - D[p][i]));
      size[p] = fmax(size[p], fabs(part[p]));
    }
  }
  double fd_scale = 0.0;
  const double fd = kit_fd_check(&s[0].k, q2, FD_STEP, &fd_scale);
  printf("  %-30s %d/%d points %s: |K| main %.2e rot %.2e curv %.2e; |part - channel FD|/|K| %.1e %.1e %.1e; "
         "|K - FD|/|K| %.1e\n", name, active, pts.n, want_slip ? "slip " : "stick", size[0], size[1], size[2],
         err[0] / scale, err[1] / scale, err[2] / scale, fd / fd_scale);
  for (int p = 0; p < CP_N_PARTS; ++p) SK_CHECK(err[p] <= FD_TOL * scale);
  SK_CHECK(fd <= FD_TOL * fd_scale);
  SK_CHECK(size[CP_ROTATIONAL] > 1e-4 * scale); /* the parts are there to be checked */
  if (!L->obstacle) SK_CHECK(size[CP_CURVATURE] > 1e-5 * scale);
  for (int v = 0; v < 4; ++v) SK_CHECK(s[v].k.outside_pattern == 0);
  /* the residual's forces balance (equal and opposite on slave and master; an obstacle takes the rest) */
  if (!L->obstacle) {
    double *F = calloc((size_t)n, sizeof(double)), sum[3] = {0, 0, 0};
    SK_CHECK(kit_residual(&s[0].k, q2, F) == SK_OK);
    for (int a = 0; a < L->n_nodes; ++a)
      for (int i = 0; i < 3; ++i) sum[i] += F[3 * a + i];
    SK_CHECK(max_abs(sum, 3) <= 1e-12 * max_abs(F, n));
    free(F);
  }
  for (int v = 0; v < 4; ++v) {
    free(J[v]);
    kit_free(&s[v].k);
  }
  for (int p = 0; p < CP_N_PARTS; ++p) free(D[p]);
}

/* The paper form's assembled stick operator is symmetric (all points stuck), the exact one is not. */
static void check_symmetry(const char *name, const layout *L, const char *variant) {
  double q1[MAX_DOFS], q2[MAX_DOFS], asym[2] = {0, 0};
  positions(L, 0.004, q1, q2);
  for (int f = 0; f < 2; ++f) {
    instance s;
    SK_CHECK(make(&s, L, variant, "full", f == 0 ? "paper" : "exact", 50.0) == SK_OK);
    two_steps(&s, L->X, q1, q2);
    const int64_t n = s.k.n;
    double *J = calloc((size_t)(n * n), sizeof(double));
    SK_CHECK(kit_jacobian(&s.k, q2, J, NULL) == SK_OK);
    for (int64_t i = 0; i < n; ++i)
      for (int64_t j = 0; j < n; ++j) asym[f] = fmax(asym[f], fabs(J[i * n + j] - J[j * n + i]));
    asym[f] /= max_abs(J, n * n);
    free(J);
    kit_free(&s.k);
  }
  printf("  %-30s stick, assembled: ||K - K^T|| / ||K||: paper form %.1e, exact form %.1e\n", name, asym[0], asym[1]);
  SK_CHECK(asym[0] <= 1e-15);
  SK_CHECK(asym[1] > 1e-6);
}

/* ---- a stuck slave face dragged across a master element edge ------------------------------------------------------- */

/* The flat master [0, 2] x [0, 1] (z = 0, normal up) as one QUAD4 or as two split at x = 1, and one slave face
 * 0.3 x 0.3 pressed 0.002 into it, dragged by 0.05 per step from x = 0.55 across the edge (12 steps, committed).
 * Tractions of every Gauss point go to t (3 per point per step). */
static int drag_across(int split, double mu, double *t, int *states) {
  layout L;
  memset(&L, 0, sizeof L);
  const double master_x[3] = {0.0, 1.0, 2.0};
  int nodes = split ? 3 : 2;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < nodes; ++i) {
      double *X = L.X + 3 * L.n_nodes++;
      X[0] = split ? master_x[i] : 2.0 * i;
      X[1] = j;
      X[2] = 0.0;
    }
  L.master_type = SK_QUAD4;
  L.master_nen = 4;
  L.n_master_faces = split ? 2 : 1;
  for (int f = 0; f < L.n_master_faces; ++f) {
    int c[4] = {f, f + 1, nodes + f + 1, nodes + f}; /* counter-clockwise from above: normal +z */
    memcpy(L.master + 4 * f, c, sizeof c);
  }
  const int s0 = L.n_nodes;
  const double sx[4] = {0.55, 0.55, 0.85, 0.85}, sy[4] = {0.35, 0.65, 0.65, 0.35};
  for (int a = 0; a < 4; ++a) {
    double *X = L.X + 3 * L.n_nodes++;
    X[0] = sx[a];
    X[1] = sy[a];
    X[2] = -0.002;
    L.slave[a] = s0 + a;
  }
  L.slave_type = SK_QUAD4;
  L.slave_nen = 4;
  L.n_slave_faces = 1;
  instance s;
  SK_CHECK(make(&s, &L, "sts", "full", "exact", mu) == SK_OK);
  double q_n[MAX_DOFS], q[MAX_DOFS];
  memcpy(q_n, L.X, sizeof(double) * 3 * (size_t)L.n_nodes);
  int n = 0;
  for (int step = 0; step <= 12; ++step) {
    memcpy(q, L.X, sizeof q);
    for (int a = 0; a < 4; ++a) q[3 * (s0 + a)] += 0.05 * step;
    kit_state(&s.k, q_n, q, step - 1.0, step, NULL);
    SK_CHECK(kit_begin(&s.k) == SK_OK);
    SK_CHECK(kit_commit(&s.k) == SK_OK);
    kit_points pts;
    SK_CHECK(kit_points_at(&s.k, &pts) == SK_OK);
    for (int i = 0; i < pts.n; ++i, ++n) {
      memcpy(t + 3 * n, pts.p[i].traction, 3 * sizeof(double));
      states[n] = pts.p[i].state;
    }
    memcpy(q_n, q, sizeof q);
  }
  kit_free(&s.k);
  return n;
}

static void check_edge_crossing(double mu, const char *name) {
  double t1[3 * 64], t2[3 * 64];
  int s1[64], s2[64];
  const int n1 = drag_across(0, mu, t1, s1), n2 = drag_across(1, mu, t2, s2);
  SK_CHECK(n1 == n2 && n1 == 4 * 13);
  double diff = 0.0, scale = max_abs(t1, 3 * n1);
  int stuck = 0, states_equal = 1;
  for (int i = 0; i < n1; ++i) {
    stuck += s1[i] == 1;
    states_equal &= s1[i] == s2[i];
    for (int c = 0; c < 3; ++c) diff = fmax(diff, fabs(t1[3 * i + c] - t2[3 * i + c]));
  }
  printf("  %-22s %d of %d point-steps stuck, |t| up to %.3e: two master faces vs one, max |difference| %.1e\n", name,
         stuck, n1, scale, diff);
  SK_CHECK(states_equal && scale > 0.0);
  SK_CHECK(diff <= 1e-12 * scale);
  if (mu > 10.0) { /* stuck throughout: t = -eps_t (x - x_0) along x, (80) */
    SK_CHECK(stuck == n1);
    SK_CHECK(fabs(t2[3 * (n1 - 1)] + 3e3 * 0.6) <= 1e-10 * scale);
  }
}

/* ---- parameter errors ------------------------------------------------------------------------------------------------ */
static void check_parameter_error(const char *key, const char *text, double value, const char *expect) {
  layout L;
  deformable_layout(&L, SK_QUAD4);
  instance s;
  memset(&s, 0, sizeof s);
  kit_init(&s.k, 3, L.n_nodes, L.X);
  kit_surface(&s.k, 0, L.slave_type, L.slave_nen, L.n_slave_faces, L.slave);
  kit_surface(&s.k, 1, L.master_type, L.master_nen, L.n_master_faces, L.master);
  if (strcmp(key, "penalty") != 0) kit_param(&s.k, "penalty", 1e4);
  if (text) kit_param_text(&s.k, key, text);
  else kit_param(&s.k, key, value);
  sk_status status = kit_create(&s.k, stickslip_plugin_entry(), 0);
  const char *msg = sk_error_message();
  printf("  %s: %s\n", key, msg);
  SK_CHECK(status == SK_ERR_INPUT);
  SK_CHECK(strstr(msg, expect) != NULL);
  kit_free(&s.k);
}

int main(void) {
  layout L;
  printf("assembled parts against channel differences, full Jacobian against differences of the residual:\n");
  deformable_layout(&L, SK_QUAD9);
  check_parts("sts, curved QUAD9 master", &L, "sts", 50.0, 0.004, 0);
  check_parts("sts, curved QUAD9 master", &L, "sts", 0.2, 0.05, 1);
  check_symmetry("sts, curved QUAD9 master", &L, "sts");
  deformable_layout(&L, SK_QUAD4);
  check_parts("nts, warped QUAD4 master", &L, "nts", 50.0, 0.004, 0);
  check_parts("nts, warped QUAD4 master", &L, "nts", 0.2, 0.05, 1);
  check_symmetry("nts, warped QUAD4 master", &L, "nts");
  stas_layout(&L);
  check_parts("stas, parabolic cylinder", &L, NULL, 50.0, 0.004, 0);
  check_parts("stas, parabolic cylinder", &L, NULL, 0.2, 0.05, 1);
  check_symmetry("stas, parabolic cylinder", &L, NULL);
  printf("a slave face dragged across a master element edge (sts):\n");
  check_edge_crossing(100.0, "stuck");
  check_edge_crossing(0.3, "sliding");
  printf("parameter errors:\n");
  check_parameter_error("penalty", NULL, -1.0, "'penalty' must be a finite number > 0, got -1");
  check_parameter_error("tangent", "curvature-only", 0.0, "'tangent' must be full, no-curvature, no-rotational or main-only");
  check_parameter_error("tangent_form", "printed", 0.0, "'tangent_form' must be exact or paper");
  check_parameter_error("variant", "stas", 0.0, "'variant' must be 'sts' or 'nts'");
  check_parameter_error("gauss_points", NULL, 7.0, "'gauss_points' must be 1..5, got 7");
  check_parameter_error("mu", NULL, -0.1, "'mu' must be a finite number >= 0");
  check_parameter_error("master_extension", NULL, 0.9, "'master_extension' must be in [0, 0.5]");
  return sk_test_finish("test_covariant_penalty_plugin");
}
