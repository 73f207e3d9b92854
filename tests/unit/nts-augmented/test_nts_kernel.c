/* nts-augmented element kernel: constraint gradients and Hessians, momentum identities, the paper's identities
 * (Gf = -A, P tT = (44)), friction return map, full element tangent (finite differences), exact condensation and
 * recovery, the direct strategy's tangent, the Table I projections, the closest point on a tiny face far out and the
 * dense solve of a badly scaled saddle block. */
#include <float.h>
#include <stdio.h>

#include "nts_test_support.h"
#include "sk_test.h"

static const double FD_STEP = 1e-6;
static const double FD_TOL = 1e-7;

/* ---- constraints ------------------------------------------------------------------------------------------------ */
static void check_constraint_derivatives(sk_elem_type type) {
  nts_facet facet;
  SK_CHECK(nts_facet_init(&facet, type, test_shape, test_shape_hessian) == 0);
  double q[NTS_MAX_NZ];
  test_element(type, 0.3, q);
  const int nq = 3 + 3 * facet.nen, nz = nq + 2;
  q[nq] = 0.2; /* f, away from the closest point so that Phi_aug != 0 */
  q[nq + 1] = -0.3;
  nts_geometry geo, gp, gm;
  nts_geometry_eval(&facet, q, q + nq, &geo);
  SK_CHECK(geo.n[2] > 0.9); /* outward normal of the facet points up, towards the slave */
  SK_CHECK(fabs(geo.phi[0]) > 1e-3 && fabs(geo.phi[1]) > 1e-3);
  const double lambda[3] = {0.7, -1.3, -2.1};
  double H[NTS_MAX_NZ * NTS_MAX_NZ];
  nts_constraint_hessian(&geo, lambda, H);
  double err_g = 0.0, err_h = 0.0, scale_h = 0.0;
  for (int j = 0; j < nz; ++j) {
    double qp[NTS_MAX_NZ], qm[NTS_MAX_NZ];
    memcpy(qp, q, sizeof q);
    memcpy(qm, q, sizeof q);
    qp[j] += FD_STEP;
    qm[j] -= FD_STEP;
    nts_geometry_eval(&facet, qp, qp + nq, &gp);
    nts_geometry_eval(&facet, qm, qm + nq, &gm);
    for (int k = 0; k < 3; ++k)
      err_g = fmax(err_g, fabs((gp.phi[k] - gm.phi[k]) / (2 * FD_STEP) - geo.grad[k][j]));
    for (int i = 0; i < nz; ++i) {
      double fd = 0.0;
      for (int k = 0; k < 3; ++k) fd += lambda[k] * (gp.grad[k][i] - gm.grad[k][i]) / (2 * FD_STEP);
      err_h = fmax(err_h, fabs(fd - H[i * nz + j]));
      scale_h = fmax(scale_h, fabs(H[i * nz + j]));
    }
  }
  printf("  %s: |grad - FD| = %.2e, |Hessian - FD| = %.2e (scale %.2e)\n", type == SK_QUAD4 ? "quad4" : "tri3",
         err_g, err_h, scale_h);
  SK_CHECK(err_g < FD_TOL);
  SK_CHECK(err_h < FD_TOL * fmax(1.0, scale_h));
  /* symmetry of the Hessian */
  double asym = 0.0;
  for (int i = 0; i < nz; ++i)
    for (int j = 0; j < nz; ++j) asym = fmax(asym, fabs(H[i * nz + j] - H[j * nz + i]));
  SK_CHECK(asym < 1e-13 * fmax(1.0, scale_h));

  /* frame indifference: sum_I grad_I Phi = 0 and sum_I q_I x grad_I Phi = 0, each constraint */
  for (int k = 0; k < 3; ++k) {
    double lin[3] = {0, 0, 0}, ang[3] = {0, 0, 0};
    for (int I = 0; I < 1 + facet.nen; ++I) {
      const double *g = geo.grad[k] + 3 * I, *x = q + 3 * I;
      for (int i = 0; i < 3; ++i) lin[i] += g[i];
      ang[0] += x[1] * g[2] - x[2] * g[1];
      ang[1] += x[2] * g[0] - x[0] * g[2];
      ang[2] += x[0] * g[1] - x[1] * g[0];
    }
    SK_CHECK(max_abs(lin, 3) < 1e-13);
    SK_CHECK(max_abs(ang, 3) < 1e-13);
  }
  /* the identity must be able to fail: perturb one gradient entry */
  {
    double lin = 0.0;
    for (int I = 0; I < 1 + facet.nen; ++I) lin += geo.grad[NTS_PHI_N][3 * I] + (I == 1 ? 1e-6 : 0.0);
    SK_CHECK(fabs(lin) > 1e-7);
  }
}

/* ---- Gf = -A and P tT = (44) at the closest point ---------------------------------------------------------------- */
static void check_paper_identities(sk_elem_type type, double height) {
  nts_facet facet;
  nts_facet_init(&facet, type, test_shape, test_shape_hessian);
  double q[NTS_MAX_NZ];
  test_element(type, height, q);
  /* make the quad non-planar so that h_12 != 0 and the gap term in (44) matters */
  if (type == SK_QUAD4) q[3 + 3 * 2 + 2] += 0.4;
  const int nq = 3 + 3 * facet.nen;
  double f[2] = {0.0, 0.0};
  SK_CHECK(nts_closest_point(&facet, q, f, 1e-14, 30) > 0);
  nts_geometry geo;
  nts_geometry_eval(&facet, q, f, &geo);
  SK_CHECK(fabs(geo.phi[0]) < 1e-13 && fabs(geo.phi[1]) < 1e-13);
  const double g = geo.phi[NTS_PHI_N];
  double A[2][2];
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b) {
      double h = 0.0;
      for (int i = 0; i < 3; ++i) h += geo.a_ab[a][b][i] * geo.n[i];
      A[a][b] = geo.m[a][b] - g * h;
      SK_CHECK_CLOSE(geo.grad[a][nq + b], -A[a][b], 1e-13);
    }
  if (type == SK_QUAD4) SK_CHECK(fabs(A[0][1] - geo.m[0][1]) > 1e-3); /* the curvature term is really there */
  /* hf = 0 once Phi_aug = 0 */
  SK_CHECK(fabs(geo.grad[NTS_PHI_N][nq]) < 1e-13 && fabs(geo.grad[NTS_PHI_N][nq + 1]) < 1e-13);

  double P[NTS_MAX_NQ * 2];
  SK_CHECK(nts_projection_matrix(&geo, P) == 0);
  const double t[2] = {0.8, -0.45};
  const double det = A[0][0] * A[1][1] - A[0][1] * A[1][0];
  const double Ainv[2][2] = {{A[1][1] / det, -A[0][1] / det}, {-A[1][0] / det, A[0][0] / det}};
  double tA[2]; /* t_a A^ab */
  for (int b = 0; b < 2; ++b) tA[b] = t[0] * Ainv[0][b] + t[1] * Ainv[1][b];
  double direct[NTS_MAX_NQ] = {0};
  for (int i = 0; i < 3; ++i) direct[i] = tA[0] * geo.a[0][i] + tA[1] * geo.a[1][i];
  for (int I = 0; I < facet.nen; ++I)
    for (int i = 0; i < 3; ++i)
      for (int b = 0; b < 2; ++b)
        direct[3 + 3 * I + i] += tA[b] * (-geo.N[I] * geo.a[b][i] + g * geo.dN[I][b] * geo.n[i]);
  double err = 0.0;
  for (int i = 0; i < nq; ++i) err = fmax(err, fabs(P[2 * i] * t[0] + P[2 * i + 1] * t[1] - direct[i]));
  printf("  %s, gap %.2f: |P tT - (44)| = %.2e\n", type == SK_QUAD4 ? "quad4" : "tri3", g, err);
  SK_CHECK(err < 1e-13 * fmax(1.0, max_abs(direct, nq)));
}

/* ---- element system: residual and tangent by finite differences --------------------------------------------------- */
typedef struct {
  nts_facet facet;
  nts_element_input in;
  nts_friction_params params;
  double q[NTS_MAX_NQ], q_start[NTS_MAX_NQ];
} element_case;

static void set_u(element_case *c, const double *u) {
  const int nq = 3 + 3 * c->facet.nen;
  memcpy(c->q, u, sizeof(double) * (size_t)nq);
  c->in.q_A = c->q;
  c->in.lambda_n = u[nq];
  c->in.f[0] = u[nq + 1];
  c->in.f[1] = u[nq + 2];
  c->in.lambda_aug[0] = u[nq + 3];
  c->in.lambda_aug[1] = u[nq + 4];
}

static void get_u(const element_case *c, double *u) {
  const int nq = 3 + 3 * c->facet.nen;
  memcpy(u, c->in.q_A, sizeof(double) * (size_t)nq);
  u[nq] = c->in.lambda_n;
  u[nq + 1] = c->in.f[0];
  u[nq + 2] = c->in.f[1];
  u[nq + 3] = c->in.lambda_aug[0];
  u[nq + 4] = c->in.lambda_aug[1];
}

/* tangential traction chosen to make the case stick (small) or slip (large) */
static void make_case(element_case *c, sk_elem_type type, double alpha, double mu, double t_scale, int active) {
  memset(c, 0, sizeof *c);
  nts_facet_init(&c->facet, type, test_shape, test_shape_hessian);
  const int nq = 3 + 3 * c->facet.nen;
  test_element(type, -0.02, c->q);
  if (type == SK_QUAD4) c->q[3 + 3 * 2 + 2] += 0.3;
  for (int i = 0; i < nq; ++i) c->q_start[i] = c->q[i] + 0.05 * test_rand();
  c->in.alpha = alpha;
  c->in.q_A_start = c->q_start;
  c->in.q_A = c->q;
  c->in.f_start[0] = 0.05;
  c->in.f_start[1] = -0.1;
  c->in.t_start[0] = 0.3 * t_scale;
  c->in.t_start[1] = -0.2 * t_scale;
  c->in.f_frozen[0] = 0.01;
  c->in.f_frozen[1] = 0.02;
  c->in.f[0] = 0.15;
  c->in.f[1] = -0.05;
  c->in.lambda_n = -2.0;
  c->in.lambda_aug[0] = 0.3;
  c->in.lambda_aug[1] = -0.4;
  c->in.active = active;
  c->params.mu = mu;
  c->params.epsilon_t = 10.0 * t_scale;
}

static void check_element_tangent(const char *name, element_case *c, int expect_slip) {
  nts_element_system sys, sp, sm;
  nts_element_build(&c->facet, &c->in, &c->params, &sys);
  if (expect_slip >= 0) SK_CHECK(sys.friction.slip == expect_slip);
  const int nu = sys.nu;
  double u[NTS_MAX_NU], up[NTS_MAX_NU];
  get_u(c, u);
  double err = 0.0, scale = 0.0;
  for (int j = 0; j < nu; ++j) {
    memcpy(up, u, sizeof u);
    up[j] = u[j] + FD_STEP;
    set_u(c, up);
    nts_element_build(&c->facet, &c->in, &c->params, &sp);
    up[j] = u[j] - FD_STEP;
    set_u(c, up);
    nts_element_build(&c->facet, &c->in, &c->params, &sm);
    SK_CHECK(sp.friction.slip == sys.friction.slip && sm.friction.slip == sys.friction.slip);
    for (int i = 0; i < nu; ++i) {
      const double fd = (sp.R[i] - sm.R[i]) / (2 * FD_STEP);
      err = fmax(err, fabs(fd - sys.J[i * nu + j]));
      scale = fmax(scale, fabs(sys.J[i * nu + j]));
    }
  }
  set_u(c, u);
  printf("  %-34s |J - FD| = %.2e (scale %.2e)\n", name, err, scale);
  SK_CHECK(err < FD_TOL * fmax(1.0, scale));
}

static void check_element_tangents(void) {
  static const sk_elem_type types[2] = {SK_QUAD4, SK_TRI3};
  static const double alphas[2] = {1.0, 0.5};
  for (int it = 0; it < 2; ++it)
    for (int ia = 0; ia < 2; ++ia) {
      char name[64];
      element_case c;
      const char *tn = types[it] == SK_QUAD4 ? "quad4" : "tri3";
      const char *sn = alphas[ia] == 1.0 ? "euler" : "midpoint";
      make_case(&c, types[it], alphas[ia], 0.0, 1.0, 1);
      snprintf(name, sizeof name, "%s %s frictionless:", tn, sn);
      check_element_tangent(name, &c, -1);
      make_case(&c, types[it], alphas[ia], 0.5, 0.1, 1);
      snprintf(name, sizeof name, "%s %s stick:", tn, sn);
      check_element_tangent(name, &c, 0);
      make_case(&c, types[it], alphas[ia], 0.5, 10.0, 1);
      snprintf(name, sizeof name, "%s %s slip:", tn, sn);
      check_element_tangent(name, &c, 1);
    }
  element_case c;
  make_case(&c, SK_QUAD4, 1.0, 0.5, 1.0, 0);
  check_element_tangent("quad4 inactive:", &c, -1);
  /* the FD check must be able to fail: without d t_T / d lambda_n (the tangent (80) would freeze it) the
   * lambda_n column of the f rows is wrong when slipping */
  make_case(&c, SK_QUAD4, 1.0, 0.5, 10.0, 1);
  nts_element_system sys, sp, sm;
  nts_element_build(&c.facet, &c.in, &c.params, &sys);
  const int nq = sys.nq, nu = sys.nu;
  const double lambda_n = c.in.lambda_n;
  c.in.lambda_n = lambda_n + FD_STEP;
  nts_element_build(&c.facet, &c.in, &c.params, &sp);
  c.in.lambda_n = lambda_n - FD_STEP;
  nts_element_build(&c.facet, &c.in, &c.params, &sm);
  c.in.lambda_n = lambda_n;
  double frozen = 0.0;
  for (int b = 0; b < 2; ++b) {
    const double fd = (sp.R[nq + 1 + b] - sm.R[nq + 1 + b]) / (2 * FD_STEP);
    frozen = fmax(frozen, fabs(fd - (sys.J[(nq + 1 + b) * nu + nq] - sys.friction.dt_dlambda_n[b])));
  }
  SK_CHECK(sys.friction.slip == 1);
  SK_CHECK(frozen > 1e-3);
}

/* ---- condensation: reduced solve == full solve -------------------------------------------------------------------- */
static void check_condensation(sk_elem_type type, double alpha, double mu, double t_scale) {
  element_case c;
  make_case(&c, type, alpha, mu, t_scale, 1);
  nts_element_system sys;
  nts_element_build(&c.facet, &c.in, &c.params, &sys);
  const int nq = sys.nq, nu = sys.nu, nk = nq + 1;
  /* a "bulk" stiffness on the positions makes the element system solvable, as the global system is */
  double K[NTS_MAX_NU * NTS_MAX_NU], F[NTS_MAX_NU];
  memcpy(K, sys.J, sizeof(double) * (size_t)(nu * nu));
  for (int i = 0; i < nq; ++i) {
    K[i * nu + i] += 50.0 + 10.0 * test_rand();
    if (i + 1 < nq) K[i * nu + i + 1] += 1.0, K[(i + 1) * nu + i] += 1.0;
  }
  for (int i = 0; i < nu; ++i) F[i] = sys.R[i] + (i < nq ? 0.3 * test_rand() : 0.0);
  double Kfull[NTS_MAX_NU * NTS_MAX_NU], dx[NTS_MAX_NU];
  memcpy(Kfull, K, sizeof Kfull);
  for (int i = 0; i < nu; ++i) dx[i] = -F[i];
  SK_CHECK(nts_solve_dense(nu, Kfull, dx, 1) == 0);

  double Jc[(NTS_MAX_NQ + 1) * (NTS_MAX_NQ + 1)], rhs[NTS_MAX_NQ + 1];
  SK_CHECK(nts_condense(&sys, Jc, rhs) == 0);
  double Kc[(NTS_MAX_NQ + 1) * (NTS_MAX_NQ + 1)], dk[NTS_MAX_NQ + 1];
  for (int i = 0; i < nk; ++i) {
    for (int j = 0; j < nk; ++j) Kc[i * nk + j] = Jc[i * nk + j] + (K[i * nu + j] - sys.J[i * nu + j]);
    dk[i] = -F[i] + rhs[i];
  }
  SK_CHECK(nts_solve_dense(nk, Kc, dk, 1) == 0);
  double de[4];
  /* recovery reads the element residual; here the extra rows' residual is the element's own */
  SK_CHECK(nts_recover(&sys, dk, de) == 0);
  double err = 0.0;
  for (int i = 0; i < nk; ++i) err = fmax(err, fabs(dk[i] - dx[i]));
  for (int a = 0; a < 4; ++a) err = fmax(err, fabs(de[a] - dx[nk + a]));
  printf("  condensed vs full (%s, alpha %.1f, mu %.1f): |dx_reduced - dx_full| = %.2e (|dx| %.2e)\n",
         type == SK_QUAD4 ? "quad4" : "tri3", alpha, mu, err, max_abs(dx, nu));
  SK_CHECK(err < 1e-12 * fmax(1.0, max_abs(dx, nu)));
}

/* ---- direct strategy: residual = (43)+(44) forces and the condensed tangent is its exact derivative ------------ */
static void direct_kept_residual(element_case *c, const double *k, double *Rk, nts_element_system *sys) {
  const int nq = 3 + 3 * c->facet.nen;
  memcpy(c->q, k, sizeof(double) * (size_t)nq);
  c->in.q_A = c->q;
  c->in.lambda_n = k[nq];
  double f_gap[2] = {c->in.f[0], c->in.f[1]};
  SK_CHECK(nts_direct_eliminate(&c->facet, &c->in, &c->params, 0, f_gap, 1e-14, 30) == 0);
  nts_element_build(&c->facet, &c->in, &c->params, sys);
  memcpy(Rk, sys->R, sizeof(double) * (size_t)(nq + 1));
}

static void check_direct(sk_elem_type type, double mu, double t_scale) {
  element_case c;
  make_case(&c, type, 1.0, mu, t_scale, 1);
  c.in.f[0] = c.in.f[1] = 0.0;
  const int nq = 3 + 3 * c.facet.nen, nk = nq + 1;
  double k[NTS_MAX_NQ + 1], Rk[NTS_MAX_NQ + 1];
  memcpy(k, c.q, sizeof(double) * (size_t)nq);
  k[nq] = -2.0;
  nts_element_system sys, sp;
  direct_kept_residual(&c, k, Rk, &sys);
  /* the extra rows vanish after the local elimination */
  SK_CHECK(max_abs(sys.R + nk, 4) < 1e-12);
  /* R_q = hq lambda_n + P t (43, 44) */
  double P[NTS_MAX_NQ * 2];
  SK_CHECK(nts_projection_matrix(&sys.geo_hat, P) == 0);
  double err = 0.0;
  for (int i = 0; i < nq; ++i) {
    const double expect = sys.geo_hat.grad[NTS_PHI_N][i] * k[nq] + P[2 * i] * sys.friction.t_used[0] +
                          P[2 * i + 1] * sys.friction.t_used[1];
    err = fmax(err, fabs(Rk[i] - expect));
  }
  SK_CHECK(err < 1e-12 * fmax(1.0, max_abs(Rk, nq)));
  SK_CHECK(sys.friction.slip == (mu <= 0.0 || t_scale > 1.0));
  double Jc[(NTS_MAX_NQ + 1) * (NTS_MAX_NQ + 1)], rhs[NTS_MAX_NQ + 1];
  SK_CHECK(nts_condense(&sys, Jc, rhs) == 0);
  SK_CHECK(max_abs(rhs, nk) < 1e-10); /* R_e = 0, so no right-hand-side correction */
  double errj = 0.0, scale = 0.0;
  for (int j = 0; j < nk; ++j) {
    double kp[NTS_MAX_NQ + 1], km[NTS_MAX_NQ + 1], Rp[NTS_MAX_NQ + 1], Rm[NTS_MAX_NQ + 1];
    memcpy(kp, k, sizeof kp);
    memcpy(km, k, sizeof km);
    kp[j] += FD_STEP;
    km[j] -= FD_STEP;
    direct_kept_residual(&c, kp, Rp, &sp);
    direct_kept_residual(&c, km, Rm, &sp);
    for (int i = 0; i < nk; ++i) {
      errj = fmax(errj, fabs((Rp[i] - Rm[i]) / (2 * FD_STEP) - Jc[i * nk + j]));
      scale = fmax(scale, fabs(Jc[i * nk + j]));
    }
  }
  printf("  direct %s: |R_q - (hq lambda_n + P t)| = %.2e, |J_condensed - FD of direct residual| = %.2e\n",
         sys.friction.slip ? "slip" : "stick", err, errj);
  SK_CHECK(errj < FD_TOL * fmax(1.0, scale));
}

/* ---- Table I: initial projections of the slave nodes onto the master facet z = 1 ------------------------------ */
static void check_table1(void) {
  nts_facet facet;
  nts_facet_init(&facet, SK_QUAD4, test_shape, test_shape_hessian);
  /* master facet: lower block nodes 1, 5, 6, 2 (counter-clockwise seen from above: normal +z, out of the block) */
  const double master[4][3] = {{-1, -1, 1}, {1, -1, 1}, {1.2, 1, 1}, {-1.5, 1.5, 1}};
  const double slave[4][3] = {{-0.5, -1, 1.1}, {-0.5, 0, 1.1}, {0.5, -1, 1.1}, {0.5, 0, 1.1}}; /* nodes 3 4 7 8 */
  double q[NTS_MAX_NQ];
  for (int I = 0; I < 4; ++I)
    for (int i = 0; i < 3; ++i) q[3 + 3 * I + i] = master[I][i];
  double xi[4][2];
  for (int s = 0; s < 4; ++s) {
    for (int i = 0; i < 3; ++i) q[i] = slave[s][i];
    xi[s][0] = xi[s][1] = 0.0;
    SK_CHECK(nts_closest_point(&facet, q, xi[s], 1e-14, 30) > 0);
    nts_geometry geo;
    nts_geometry_eval(&facet, q, xi[s], &geo);
    SK_CHECK_CLOSE(geo.phi[NTS_PHI_N], 0.1, 1e-13);
    SK_CHECK_CLOSE(geo.n[2], 1.0, 1e-14);
    printf("  slave node %d: xi = (%.6f, %.6f), gap %.3f\n", s == 0 ? 3 : s == 1 ? 4 : s == 2 ? 7 : 8, xi[s][0],
           xi[s][1], geo.phi[NTS_PHI_N]);
  }
  SK_CHECK_CLOSE(xi[0][1], -1.0, 1e-12); /* nodes 3, 7 on the edge eta = -1 */
  SK_CHECK_CLOSE(xi[2][1], -1.0, 1e-12);
  SK_CHECK_CLOSE(xi[0][0], -0.5, 1e-12);
  SK_CHECK_CLOSE(xi[2][0], 0.5, 1e-12);
  /* nodes 4, 8 (x, y) = (-0.5, 0), (0.5, 0) of Table I (Franke, Hesch & Betsch 2013): the facet is flat (z = 1), so
     their closest points are the inverse of its bilinear map, solved apart from this code: (-0.379400, -0.147067)
     and (0.489909, -0.059940) */
  SK_CHECK(fabs(xi[1][0] + 0.379400) < 1e-6 && fabs(xi[1][1] + 0.147067) < 1e-6);
  SK_CHECK(fabs(xi[3][0] - 0.489909) < 1e-6 && fabs(xi[3][1] + 0.059940) < 1e-6);
}

/* The parametric distance beyond a facet's border (the facet-switch rule of begin_step). */
static void check_facet_outside(void) {
  nts_facet line, tri, quad;
  SK_CHECK(nts_facet_init(&line, SK_LINE2, test_shape, test_shape_hessian) == 0);
  SK_CHECK(nts_facet_init(&tri, SK_TRI3, test_shape, test_shape_hessian) == 0);
  SK_CHECK(nts_facet_init(&quad, SK_QUAD4, test_shape, test_shape_hessian) == 0);
  SK_CHECK(nts_facet_outside(&line, (double[]){1.0, 5.0}) == 0.0); /* f2 is no coordinate of a segment */
  SK_CHECK_CLOSE(nts_facet_outside(&line, (double[]){-1.25, 0.0}), 0.25, 1e-15);
  SK_CHECK(nts_facet_outside(&quad, (double[]){-1.0, 1.0}) == 0.0);
  SK_CHECK_CLOSE(nts_facet_outside(&quad, (double[]){0.5, 1.5}), 0.5, 1e-15);
  SK_CHECK_CLOSE(nts_facet_outside(&quad, (double[]){-1.1, -1.3}), 0.3, 1e-15);
  SK_CHECK(nts_facet_outside(&tri, (double[]){0.5, 0.5}) == 0.0);
  SK_CHECK_CLOSE(nts_facet_outside(&tri, (double[]){0.75, 0.5}), 0.25, 1e-15);
  SK_CHECK_CLOSE(nts_facet_outside(&tri, (double[]){0.2, -0.1}), 0.1, 1e-15);
}

/* The closest point on a face 3e-4 long far from the origin (stability.md finding 21): its step in f is round-off
 * at eps |x| / |a| = 1.5e-9 here, far above LOCAL_NEWTON_TOL, and it converged only once the iteration accepted steps
 * at that floor. The point found is the closest one to the floor: (x - x(f)) . a_1 at round-off of |x| |a|. */
static void check_closest_point_tiny_face_far_out(void) {
  nts_facet line;
  SK_CHECK(nts_facet_init(&line, SK_LINE2, test_shape, test_shape_hessian) == 0);
  const double x1[3] = {1000.0, 0.2, 0.0}, x2[3] = {1000.0 + 2.9e-4, 0.2 + 7.0e-5, 0.0};
  int converged = 0, trials = 0;
  double worst = 0.0;
  for (int k = 0; k < 40; ++k, ++trials) {
    double q_A[NTS_MAX_NQ] = {0};
    const double s = -0.9 + 1.8 * k / 39.0, height = 1e-5 * (1 + k % 5);
    for (int i = 0; i < 3; ++i) {
      q_A[3 + i] = x1[i];
      q_A[6 + i] = x2[i];
      q_A[i] = 0.5 * (1 - s) * x1[i] + 0.5 * (1 + s) * x2[i];
    }
    q_A[0] -= height * 7.0e-5 / 3e-4; /* off the face along its normal (-dy, dx) */
    q_A[1] += height * 2.9e-4 / 3e-4;
    double f[2] = {0.0, 0.0};
    if (nts_closest_point(&line, q_A, f, 1e-13, 30) < 0) continue;
    ++converged;
    nts_geometry geo;
    nts_geometry_eval(&line, q_A, f, &geo);
    worst = fmax(worst, fabs(geo.phi[0]) / (1000.0 * sqrt(geo.m[0][0]) * DBL_EPSILON));
    SK_CHECK_CLOSE(f[0], s, 1e-6);
  }
  printf("  tiny face at x = 1000: %d of %d closest points converged, |Phi_1| <= %.1f eps |x| |a|\n", converged, trials,
         worst);
  SK_CHECK(converged == trials);
  SK_CHECK(worst < 64.0);
}

/* The (f, lambda_aug) block of the coarse frictional ring (stability.md finding 20): eps_t = 1e6 times the facet
 * metric (0.25, 25) against the metric itself. Regular (det = 0.25^2 25^2), its rows 1e8 apart; the solver called it
 * singular while it tested pivots against the largest entry of the whole block. A block with two dependent rows stays
 * singular. */
static void check_dense_solve_scaled_saddle(void) {
  const double K[2] = {2.5e5, 2.50004e7}, B[2] = {0.25, 25.0001};
  double A[16] = {0}, b[4] = {1.0, -2.0, 3.0, -4.0}, x_exact[4];
  for (int a = 0; a < 2; ++a) {
    A[a * 4 + a] = K[a];
    A[a * 4 + 2 + a] = A[(2 + a) * 4 + a] = -B[a];
  }
  /* -B f = b_lambda gives f; K f - B lambda = b_f gives lambda */
  for (int a = 0; a < 2; ++a) {
    x_exact[a] = -b[2 + a] / B[a];
    x_exact[2 + a] = (K[a] * x_exact[a] - b[a]) / B[a];
  }
  SK_CHECK(nts_solve_dense(4, A, b, 1) == 0);
  for (int i = 0; i < 4; ++i) SK_CHECK_CLOSE(b[i], x_exact[i], 1e-14 * fabs(x_exact[i]));
  double singular[9] = {1e6, 2.0, 3.0, 1.0, 2e-6, 3e-6, 0.5, 1.0, 1.0}, c[3] = {1.0, 1.0, 1.0};
  SK_CHECK(nts_solve_dense(3, singular, c, 1) != 0);
}

int main(void) {
  printf("facet domains\n");
  check_facet_outside();
  check_closest_point_tiny_face_far_out();
  printf("constraint derivatives and frame indifference\n");
  check_constraint_derivatives(SK_QUAD4);
  check_constraint_derivatives(SK_TRI3);
  printf("Gf = -A and P tT = (44)\n");
  check_paper_identities(SK_QUAD4, 0.25);
  check_paper_identities(SK_QUAD4, -0.1);
  check_paper_identities(SK_TRI3, 0.25);
  printf("element tangents\n");
  check_element_tangents();
  printf("condensation\n");
  check_condensation(SK_QUAD4, 1.0, 0.0, 1.0);
  check_condensation(SK_QUAD4, 0.5, 0.5, 0.1);
  check_condensation(SK_QUAD4, 1.0, 0.5, 10.0);
  check_condensation(SK_TRI3, 0.5, 0.5, 10.0);
  check_dense_solve_scaled_saddle();
  printf("direct strategy\n");
  check_direct(SK_QUAD4, 0.5, 10.0);
  check_direct(SK_QUAD4, 0.5, 0.1);
  check_direct(SK_TRI3, 0.0, 1.0);
  printf("Table I projections\n");
  check_table1();
  return sk_test_finish("test_nts_kernel");
}
