/* mortar-dual kernel: nodal quantities and the complementarity functions. Finite-difference checks of the face
 * contributions to averaged nodal normals, their normalisation, the nodal tangents, the pair's contact forces and
 * weighted positions; linear momentum of the pair forces; the objectivity of the weighted slip under a rigid motion
 * (and the non-objectivity of the plain displacement jump); the NCP functions: their roots are the KKT/Coulomb
 * states, their branches, and the derivative of every branch. */
#include "mortar_test_support.h"

static const double FD_STEP = 1e-6;
static const double FD_TOL = 2e-7;

/* ---- normals and tangents -------------------------------------------------------------------------------------- */
typedef struct {
  const mortar_face_type *ft;
  int dim, node;
} normal_case;

static int eval_face_normal(void *ctx, const double *u, int derivatives, fwd *out) {
  const normal_case *c = ctx;
  double x[12] = {0}, cv[3], dc[4][3][3];
  for (int b = 0; b < c->ft->nen; ++b)
    for (int i = 0; i < c->dim; ++i) x[3 * b + i] = u[b * c->dim + i];
  mortar_face_normal_at_node(c->ft, c->dim, x, c->node, cv, dc);
  const int n = derivatives ? c->ft->nen * c->dim : 0;
  for (int i = 0; i < c->dim; ++i) {
    out[i] = fwd_const(cv[i]);
    out[i].n = n;
    for (int b = 0; b < c->ft->nen; ++b)
      for (int j = 0; j < c->dim; ++j)
        if (n) out[i].d[b * c->dim + j] = dc[b][i][j];
  }
  return 0;
}

static void check_face_normals(void) {
  const double quad[] = {0, 0, 0, 0, 1.1, 0.1, 0.9, 1.2, -0.2, 1.0, -0.1, 0.05};
  const double tri[] = {0, 0, 0, 0.1, 1.0, 0.2, 1.1, 0.1, -0.1};
  const double line[] = {0, 0, 1.2, 0.3};
  for (int node = 0; node < 4; ++node) {
    normal_case q = {&ft_quad4, 3, node};
    SK_CHECK(test_fd_check("normal at quad4 node", eval_face_normal, &q, quad, 12, 3, FD_STEP) < FD_TOL);
    if (node < 3) {
      normal_case t = {&ft_tri3, 3, node};
      SK_CHECK(test_fd_check("normal at tri3 node", eval_face_normal, &t, tri, 9, 3, FD_STEP) < FD_TOL);
    }
    if (node < 2) {
      normal_case l = {&ft_line2, 2, node};
      SK_CHECK(test_fd_check("normal at line2 node", eval_face_normal, &l, line, 4, 2, FD_STEP) < FD_TOL);
    }
  }
  /* orientation: a counter-clockwise quad in the plane z = 0 (seen from +z) has its normal along +z; the line from
   * (0,0) to (1,0) has a1 x e_z = -e_y */
  const double flat[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  double c[3], dc[4][3][3];
  mortar_face_normal_at_node(&ft_quad4, 3, flat, 2, c, dc);
  SK_CHECK(c[2] > 0.0 && fabs(c[0]) < 1e-15 && fabs(c[1]) < 1e-15);
  const double seg[] = {0, 0, 0, 1, 0, 0};
  mortar_face_normal_at_node(&ft_line2, 2, seg, 0, c, dc);
  SK_CHECK(c[1] < 0.0 && fabs(c[0]) < 1e-15);
}

typedef struct {
  int dim;
  double ref[3];
} tangent_case;

static int eval_normalize(void *ctx, const double *u, int derivatives, fwd *out) {
  (void)ctx;
  double n[3], dn[3][3];
  mortar_normalize(u, n, dn);
  for (int i = 0; i < 3; ++i) {
    out[i] = fwd_const(n[i]);
    if (derivatives) {
      out[i].n = 3;
      for (int j = 0; j < 3; ++j) out[i].d[j] = dn[i][j];
    }
  }
  return 0;
}

static int eval_tangents(void *ctx, const double *u, int derivatives, fwd *out) {
  const tangent_case *c = ctx;
  double n[3] = {u[0], u[1], c->dim == 3 ? u[2] : 0.0}, tau[2][3], dtau[2][3][3];
  if (mortar_tangents(c->dim, n, c->ref, tau, dtau) != 0) return -1;
  for (int a = 0; a < 2; ++a)
    for (int i = 0; i < 3; ++i) {
      out[3 * a + i] = fwd_const(tau[a][i]);
      if (derivatives) {
        out[3 * a + i].n = c->dim;
        for (int j = 0; j < c->dim; ++j) out[3 * a + i].d[j] = dtau[a][i][j];
      }
    }
  return 0;
}

static void check_tangents(void) {
  const double c[3] = {0.3, -0.5, 1.1};
  SK_CHECK(test_fd_check("normalize", eval_normalize, NULL, c, 3, 3, FD_STEP) < FD_TOL);
  const double n3[3] = {0.2, -0.3, 0.93}, n2[3] = {0.6, -0.8, 0.0};
  tangent_case t3 = {3, {1, 0, 0}}, t2 = {2, {0, 0, 0}};
  SK_CHECK(test_fd_check("tangents 3D", eval_tangents, &t3, n3, 3, 6, FD_STEP) < FD_TOL);
  SK_CHECK(test_fd_check("tangent 2D", eval_tangents, &t2, n2, 2, 6, FD_STEP) < FD_TOL);
  double nu[3], tau[2][3], dtau[2][3][3];
  mortar_normalize(n3, nu, NULL);
  SK_CHECK(mortar_tangents(3, nu, t3.ref, tau, dtau) == 0);
  double orth = 0.0;
  for (int a = 0; a < 2; ++a) {
    double tn = 0.0, tt = 0.0, t12 = 0.0;
    for (int i = 0; i < 3; ++i) {
      tn += tau[a][i] * nu[i];
      tt += tau[a][i] * tau[a][i];
      t12 += tau[0][i] * tau[1][i];
    }
    orth = fmax(orth, fmax(fabs(tn), fmax(fabs(tt - 1.0), fabs(t12))));
  }
  SK_CHECK(orth < 1e-15);
  const double along[3] = {1, 0, 0};
  SK_CHECK(mortar_tangents(3, along, along, tau, dtau) == -1); /* reference parallel to n: refused */
}

/* ---- the pair's forces and weighted positions ------------------------------------------------------------------ */
typedef struct {
  mortar_basis basis;
  double z[4][3];
} force_case;

static const double quad_s[] = {0, 0, 0, 0, 1, 0.02, 1, 1, 0, 1, 0, -0.03};
static const double tri_m[] = {-0.2, -0.1, -0.05, 0.9, -0.2, -0.04, 0.1, 0.8, -0.06};

static void pair_from(const double *u, int derivatives, mortar_basis basis, mortar_pair *p, mortar_integrals *I) {
  double xs[12], xm[9], ns[12];
  memcpy(xs, u, sizeof xs);
  memcpy(xm, u + 12, sizeof xm);
  memcpy(ns, u + 21, sizeof ns);
  mortar_pair_set(p, 3, &ft_quad4, &ft_tri3, xs, xm, ns, derivatives);
  mortar_basis_coeffs A;
  mortar_basis_coefficients(p, basis, &A);
  mortar_integrals_zero(I, p);
  double xi[MORTAR_MAX_RULE * MORTAR_MAX_RULE * 2], w[MORTAR_MAX_RULE * MORTAR_MAX_RULE];
  const int nq = mortar_face_rule(SK_QUAD4, 3, xi, w);
  mortar_slave_integrals(p, &A, basis, nq, xi, w, I);
  mortar_segments_3d(p, &A, basis, 7, I);
}

static int eval_forces(void *ctx, const double *u, int derivatives, fwd *out) {
  const force_case *c = ctx;
  mortar_pair p;
  mortar_integrals I;
  pair_from(u, derivatives, c->basis, &p, &I);
  fwd f[8][3], W[4][3];
  mortar_pair_forces(&p, &I, c->basis, c->z, f);
  mortar_pair_weighted_positions(&p, &I, c->basis, W);
  int m = 0;
  for (int a = 0; a < 7; ++a)
    for (int i = 0; i < 3; ++i) out[m++] = f[a][i];
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 3; ++i) out[m++] = W[j][i];
  return 0;
}

static void generic_pair(double *u) {
  memcpy(u, quad_s, sizeof quad_s);
  memcpy(u + 12, tri_m, sizeof tri_m);
  for (int a = 0; a < 4; ++a) {
    double n[3] = {0.05 * test_rand(), 0.05 * test_rand(), -1.0}, len = sqrt(n[0] * n[0] + n[1] * n[1] + 1.0);
    for (int i = 0; i < 3; ++i) u[21 + 3 * a + i] = n[i] / len;
  }
}

static void check_forces(void) {
  double u[33];
  generic_pair(u);
  for (int basis = 0; basis < 2; ++basis) {
    force_case c = {(mortar_basis)basis, {{0}}};
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 3; ++i) c.z[j][i] = test_rand() + (i == 2 ? 3.0 : 0.0);
    SK_CHECK(test_fd_check(basis ? "forces, weighted positions (dual)" : "forces, weighted positions (standard)",
                           eval_forces, &c, u, 33, 33, FD_STEP) < FD_TOL);
    /* linear momentum: on a planar slave face the master covers, the forces sum to zero (sum_k D_jk = sum_l M_jl;
     * on a warped QUAD4 up to the quadrature error of its non-polynomial Jacobian, 1e-7 here) */
    double big[33];
    memcpy(big, u, sizeof big);
    big[5] = big[11] = 0.0;
    const double cover[9] = {-2.0, -2.0, -0.05, 5.0, -2.0, -0.04, -2.0, 5.0, -0.06};
    memcpy(big + 12, cover, sizeof cover);
    fwd y[TEST_MAX_OUT];
    eval_forces(&c, big, 0, y);
    double sum[3] = {0, 0, 0};
    for (int a = 0; a < 7; ++a)
      for (int i = 0; i < 3; ++i) sum[i] += y[3 * a + i].v;
    printf("  momentum of a covered pair: %.2e %.2e %.2e\n", sum[0], sum[1], sum[2]);
    SK_CHECK(fabs(sum[0]) < 1e-14 && fabs(sum[1]) < 1e-14 && fabs(sum[2]) < 1e-14);
  }
}

/* ---- objectivity of the weighted slip (docs [S1]) -------------------------------------------------------------
 * u_j = -[sum_k (D_jk - D_jk^n) x_k - sum_l (M_jl - M_jl^n) x_l] vanishes for a rigid motion of both faces from
 * the state n (D and M do not change); the plain weighted jump D (x - x^n) - M (x - x^n) does not. */
static void check_slip_objectivity(void) {
  double u[33], v[33];
  generic_pair(u);
  const double ang = 0.6, Q[3][3] = {{1, 0, 0}, {0, cos(ang), -sin(ang)}, {0, sin(ang), cos(ang)}};
  for (int a = 0; a < 11; ++a) {
    for (int i = 0; i < 3; ++i) {
      double y = 0.0;
      for (int k = 0; k < 3; ++k) y += Q[i][k] * u[3 * a + k];
      v[3 * a + i] = y + (a < 7 ? 0.4 + 0.1 * i : 0.0);
    }
  }
  for (int basis = 0; basis < 2; ++basis) {
    mortar_pair p0, p1;
    mortar_integrals I0, I1;
    pair_from(u, 0, (mortar_basis)basis, &p0, &I0);
    pair_from(v, 0, (mortar_basis)basis, &p1, &I1);
    double objective = 0.0, jump = 0.0;
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 3; ++i) {
        double s = 0.0, t = 0.0;
        for (int k = 0; k < 4; ++k) {
          const double dx = v[3 * k + i] - u[3 * k + i];
          s += (I1.D[j][k].v - I0.D[j][k].v) * v[3 * k + i];
          t += I1.D[j][k].v * dx;
        }
        for (int l = 0; l < 3; ++l) {
          const double dx = v[12 + 3 * l + i] - u[12 + 3 * l + i];
          s -= (I1.M[j][l].v - I0.M[j][l].v) * v[12 + 3 * l + i];
          t -= I1.M[j][l].v * dx;
        }
        objective = fmax(objective, fabs(s));
        jump = fmax(jump, fabs(t));
      }
    printf("  rigid rotation by %.1f rad: objective slip %.1e, plain jump %.2e\n", ang, objective, jump);
    SK_CHECK(objective < 1e-13);
    SK_CHECK(jump > 1e-3);
  }
}

/* ---- complementarity functions --------------------------------------------------------------------------------- */
typedef struct {
  mortar_ncp_params prm;
  int n_t, force_state;
  const double *slip_dir; /* a frozen slip direction (the nested loop), or NULL */
} ncp_case;

/* u = [z_n, z_t (2), g, s (2)] */
static int eval_ncp(void *ctx, const double *u, int derivatives, fwd *out) {
  const ncp_case *c = ctx;
  mortar_ncp r;
  mortar_ncp_eval_dir(c->n_t, u[0], u + 1, u[3], u + 4, &c->prm, c->force_state, c->slip_dir, &r);
  for (int i = 0; i < 1 + c->n_t; ++i) {
    out[i] = fwd_const(r.C[i]);
    if (derivatives) {
      out[i].n = 6;
      for (int k = 0; k < 6; ++k) out[i].d[k] = r.dC[i][k];
    }
  }
  return 0;
}

static int ncp_state(const ncp_case *c, const double *u) {
  mortar_ncp r;
  mortar_ncp_eval(c->n_t, u[0], u + 1, u[3], u + 4, &c->prm, -1, &r);
  return r.state;
}

static void check_ncp(void) {
  ncp_case fr = {{0.3, 10.0, 5.0}, 2, -1, NULL}, fl = {{0.0, 10.0, 5.0}, 2, -1, NULL};
  const double inactive[6] = {0.2, 0.1, -0.2, 0.05, 0.3, 0.1};   /* z_n - c_n g = -0.3 */
  const double stick[6] = {2.0, 0.1, -0.2, 0.01, 0.02, 0.01};    /* |v| = 0.2 < 0.3 * 1.9 */
  const double slip[6] = {2.0, 0.4, -0.2, 0.01, 0.3, 0.1};       /* |v| = 2.1 > 0.57 */
  SK_CHECK(ncp_state(&fr, inactive) == MORTAR_INACTIVE);
  SK_CHECK(ncp_state(&fr, stick) == MORTAR_STICK);
  SK_CHECK(ncp_state(&fr, slip) == MORTAR_SLIP);
  SK_CHECK(ncp_state(&fl, stick) == MORTAR_SLIP); /* frictionless contact slides */
  const double *pts[3] = {inactive, stick, slip};
  for (int n_t = 1; n_t <= 2; ++n_t)
    for (int i = 0; i < 3; ++i) {
      fr.n_t = fl.n_t = n_t;
      SK_CHECK(test_fd_check("NCP (mu 0.3)", eval_ncp, &fr, pts[i], 6, 1 + n_t, FD_STEP) < FD_TOL);
      SK_CHECK(test_fd_check("NCP (frictionless)", eval_ncp, &fl, pts[i], 6, 1 + n_t, FD_STEP) < FD_TOL);
    }
  /* a forced branch is evaluated whatever the arguments (the nested active-set loop) */
  ncp_case forced = fr;
  forced.force_state = MORTAR_STICK;
  SK_CHECK(test_fd_check("NCP forced stick", eval_ncp, &forced, slip, 6, 3, FD_STEP) < FD_TOL);
  /* the roots are the KKT / Coulomb states: C = 0 exactly */
  mortar_ncp r;
  const double zt_stick[2] = {0.2, -0.1}, s0[2] = {0.0, 0.0};
  mortar_ncp_eval(2, 1.5, zt_stick, 0.0, s0, &fr.prm, -1, &r); /* contact, |z_t| < mu z_n, no slip */
  SK_CHECK(r.state == MORTAR_STICK && r.C[0] == 0.0 && r.C[1] == 0.0 && r.C[2] == 0.0);
  const double s_dir[2] = {0.6, 0.8}, zt_slip[2] = {0.3 * 1.5 * 0.6, 0.3 * 1.5 * 0.8};
  mortar_ncp_eval(2, 1.5, zt_slip, 0.0, s_dir, &fr.prm, -1, &r); /* z_t = mu z_n s/|s| */
  SK_CHECK(r.state == MORTAR_SLIP && fabs(r.C[1]) < 1e-15 && fabs(r.C[2]) < 1e-15);
  const double z0[2] = {0.0, 0.0};
  mortar_ncp_eval(2, 0.0, z0, 0.2, s_dir, &fr.prm, -1, &r); /* open gap, no traction */
  SK_CHECK(r.state == MORTAR_INACTIVE && r.C[0] == 0.0 && r.C[1] == 0.0);
  const double zt_wrong[2] = {-0.3 * 1.5 * 0.6, -0.3 * 1.5 * 0.8};
  mortar_ncp_eval(2, 1.5, zt_wrong, 0.0, s_dir, &fr.prm, -1, &r); /* friction along the slip: not a root */
  SK_CHECK(fabs(r.C[1]) > 0.1);
}

/* The border of two branches at a converged point: touching without pressure (g = z_n = 0 up to round-off) satisfies
 * inactive and active, sticking at the slip limit satisfies stick and slip; a clear state holds in its own branch
 * only. */
static void check_branch_holds(void) {
  const mortar_ncp_params fr = {0.3, 10.0, 5.0}, fl = {0.0, 10.0, 5.0};
  const double tol = 1e-8, z0[2] = {0.0, 0.0}, s0[2] = {0.0, 0.0};
  /* touching: z_n = 1e-13, g = -1e-15 (zeta = 1.1e-13 > 0: the sign alone says active) */
  mortar_ncp r;
  mortar_ncp_eval(1, 1e-13, z0, -1e-15, s0, &fl, -1, &r);
  SK_CHECK(r.state == MORTAR_SLIP);
  SK_CHECK(mortar_ncp_branch_holds(1, 1e-13, z0, -1e-15, s0, &fl, MORTAR_INACTIVE, NULL, tol));
  SK_CHECK(mortar_ncp_branch_holds(1, 1e-13, z0, -1e-15, s0, &fl, MORTAR_SLIP, NULL, tol));
  SK_CHECK(mortar_ncp_branch_holds(1, -1e-13, z0, 1e-15, s0, &fr, MORTAR_STICK, NULL, tol));
  /* the band is tol wide, no wider: tension of 2 tol is inactive, penetration of 2 tol / c_n active */
  SK_CHECK(!mortar_ncp_branch_holds(1, -2 * tol, z0, 0.0, s0, &fl, MORTAR_SLIP, NULL, tol));
  SK_CHECK(!mortar_ncp_branch_holds(1, 0.0, z0, -2 * tol / fl.c_n, s0, &fl, MORTAR_INACTIVE, NULL, tol));
  /* clear states: open gap, pressed */
  SK_CHECK(!mortar_ncp_branch_holds(1, 0.0, z0, 0.1, s0, &fr, MORTAR_STICK, NULL, tol));
  SK_CHECK(!mortar_ncp_branch_holds(1, 2.0, z0, 0.0, s0, &fr, MORTAR_INACTIVE, NULL, tol));
  /* at the slip limit: |z_t| = mu z_n, no slip: stick and slip both hold; below it only stick, with slip only slip */
  const double zt_limit[2] = {0.3 * 2.0, 0.0}, zt_below[2] = {0.3, 0.0}, s_fwd[2] = {0.1, 0.0};
  SK_CHECK(mortar_ncp_branch_holds(1, 2.0, zt_limit, 0.0, s0, &fr, MORTAR_STICK, NULL, tol));
  SK_CHECK(mortar_ncp_branch_holds(1, 2.0, zt_limit, 0.0, s0, &fr, MORTAR_SLIP, NULL, tol));
  SK_CHECK(!mortar_ncp_branch_holds(1, 2.0, zt_below, 0.0, s0, &fr, MORTAR_SLIP, NULL, tol));
  SK_CHECK(!mortar_ncp_branch_holds(1, 2.0, zt_limit, 0.0, s_fwd, &fr, MORTAR_STICK, NULL, tol));
  SK_CHECK(mortar_ncp_branch_holds(2, 2.0, zt_limit, 0.0, s_fwd, &fr, MORTAR_SLIP, NULL, tol));
  /* a frozen slip direction (the nested loop): the slip holds along it, not once it turned */
  const double d_fwd[2] = {1.0, 0.0}, d_back[2] = {-1.0, 0.0};
  SK_CHECK(mortar_ncp_branch_holds(1, 2.0, zt_limit, 0.0, s_fwd, &fr, MORTAR_SLIP, d_fwd, tol));
  SK_CHECK(!mortar_ncp_branch_holds(1, 2.0, zt_limit, 0.0, s_fwd, &fr, MORTAR_SLIP, d_back, tol));
}

/* The slip branch with a frozen direction d (Hammer's nested loop): C_T = z_t - mu (z_n - c_n g) d, exact
 * derivatives, no dependence on the slip s; its root is z_t = mu z_n d whatever the slip, which the outer update then
 * checks. */
static void check_frozen_slip(void) {
  static const double dir[2] = {0.6, -0.8};
  ncp_case c = {{0.3, 10.0, 5.0}, 2, MORTAR_SLIP, dir};
  const double u[6] = {2.0, 0.4, -0.2, 0.01, -0.3, 0.1}; /* v = (-1.1, 0.3): against d */
  SK_CHECK(test_fd_check("NCP slip, frozen direction", eval_ncp, &c, u, 6, 3, FD_STEP) < FD_TOL);
  mortar_ncp r;
  const double zt[2] = {0.3 * 1.9 * 0.6, -0.3 * 1.9 * 0.8}, s[2] = {-0.3, 0.1};
  mortar_ncp_eval_dir(2, 1.9, zt, 0.0, s, &c.prm, MORTAR_SLIP, dir, &r);
  SK_CHECK(r.state == MORTAR_SLIP && fabs(r.C[1]) < 1e-15 && fabs(r.C[2]) < 1e-15);
  SK_CHECK(r.dC[1][4] == 0.0 && r.dC[2][5] == 0.0); /* no slip column */
}

int main(void) {
  test_face_types();
  check_branch_holds();
  check_frozen_slip();
  check_face_normals();
  check_tangents();
  check_forces();
  check_slip_objectivity();
  check_ncp();
  return sk_test_finish("test_mortar_nodes");
}
