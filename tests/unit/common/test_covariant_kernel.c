/* The shared covariant kernel (plugins/common/covariant.c) against central differences: closest-point kinematics
 * (dg, dxi, dn), the derivatives of tangents, metric, inverse metric and dual tangents at the moving closest point,
 * and the covariant friction traction in stick and slip, on a warped QUAD4, a curved QUAD9, a TRI3 (3D) and a
 * curved LINE3 (2D) master face; the return map's slip traction lies on the cone, its dissipation is >= 0, and the
 * trial is frame indifferent (a rigid rotation of slave and face leaves t_a unchanged).
 *
 * Each evaluation starts from positions q = [x_s | x_1 ... x_nen] (the kernel's local dof order), finds the closest
 * point on the face's polynomial extension by Newton, and evaluates the core's surface geometry there. */
#include <math.h>
#include <string.h>

#include "covariant.h"
#include "sk_test.h"
#include "stickslip/contact.h"
#include "stickslip/fe.h"

typedef struct {
  int dim, nen;
  sk_surface face; /* one face, nodes 1..nen (node 0 is the slave) */
  int conn[COV_MAX_NEN];
} face_setup;

static void setup_face(face_setup *s, int dim, sk_elem_type type) {
  memset(s, 0, sizeof *s);
  s->dim = dim;
  s->nen = sk_elem_nen(type);
  for (int I = 0; I < s->nen; ++I) s->conn[I] = 1 + I;
  s->face.dim = dim;
  s->face.face_type = type;
  s->face.nen = s->nen;
  s->face.n_faces = 1;
  s->face.conn = s->conn;
}

/* Closest point of the slave (q[0..dim)) on the face's extension by Newton from xi = 0 (centroid for TRI3). */
static int closest_point(const face_setup *s, const double *q, sk_surface_point *pt) {
  const int pdim = s->dim - 1;
  double xi[2] = {0.0, 0.0};
  if (s->face.face_type == SK_TRI3) xi[0] = xi[1] = 1.0 / 3.0;
  for (int it = 0; it < 50; ++it) {
    sk_surface_geometry(&s->face, 0, xi, q, pt);
    double d[3] = {0, 0, 0}, r[2] = {0, 0}, J[2][2] = {{1, 0}, {0, 1}}, Jinv[2][2];
    for (int i = 0; i < s->dim; ++i) d[i] = q[i] - pt->x[i];
    for (int a = 0; a < pdim; ++a) {
      for (int i = 0; i < 3; ++i) r[a] += d[i] * pt->a[a][i];
      for (int b = 0; b < pdim; ++b) {
        J[a][b] = 0.0;
        for (int i = 0; i < 3; ++i) J[a][b] += pt->a[a][i] * pt->a[b][i] - d[i] * pt->a_ab[a][b][i];
      }
    }
    if (!cov_invert2(pdim, J, Jinv)) return 0;
    double step = 0.0;
    for (int a = 0; a < pdim; ++a) {
      double dx = 0.0;
      for (int b = 0; b < pdim; ++b) dx += Jinv[a][b] * r[b];
      xi[a] += dx;
      step = fmax(step, fabs(dx));
    }
    if (step < 1e-15) break;
  }
  sk_surface_geometry(&s->face, 0, xi, q, pt);
  pt->xi[0] = xi[0];
  pt->xi[1] = xi[1];
  return 1;
}

static double gap_of(const face_setup *s, const double *q, const sk_surface_point *pt) {
  double g = 0.0;
  for (int i = 0; i < s->dim; ++i) g += (q[i] - pt->x[i]) * pt->n[i];
  return g;
}

/* Everything the test differentiates, as one flat list of scalars. */
enum { N_OUT = 1 + 2 + 3 + 4 + 4 + 6 + 3 + 2 };
typedef struct {
  const double *t_n, *xi_n;
  double eps_n, eps_t, mu;
} friction_setup;

static int outputs(const face_setup *s, const friction_setup *f, const double *q, double *out, int *state) {
  sk_surface_point pt;
  if (!closest_point(s, q, &pt)) return 0;
  const double g = gap_of(s, q, &pt);
  cov_kinematics k;
  if (!cov_kinematics_eval(&pt, s->dim, s->nen, g, &k)) return 0;
  cov_metric_derivatives d;
  cov_metric_derivatives_eval(&pt, &k, &d);
  const double p = -f->eps_n * g;
  double Dp[COV_MAX_DOFS];
  for (int c = 0; c < k.nd; ++c) Dp[c] = -f->eps_n * k.G[c];
  const double dxi[2] = {pt.xi[0] - f->xi_n[0], s->dim == 3 ? pt.xi[1] - f->xi_n[1] : 0.0};
  double t_cov[2], T[3], DT[3][COV_MAX_DOFS], diss;
  int st = cov_friction(&pt, &k, &d, f->t_n, dxi, f->eps_t, f->mu, p, Dp, NULL, t_cov, T, DT, &diss);
  if (state) *state = st;
  int o = 0;
  out[o++] = g;
  for (int a = 0; a < 2; ++a) out[o++] = pt.xi[a];
  for (int i = 0; i < 3; ++i) out[o++] = pt.n[i];
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b) out[o++] = pt.m[a][b];
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b) out[o++] = pt.m_inv[a][b];
  for (int a = 0; a < 2; ++a)
    for (int i = 0; i < 3; ++i) out[o++] = pt.a_dual[a][i];
  for (int i = 0; i < 3; ++i) out[o++] = T[i];
  for (int a = 0; a < 2; ++a) out[o++] = t_cov[a];
  return 1;
}

/* The kernel's derivative of each output of `outputs` with respect to local dof c. */
static int derivatives(const face_setup *s, const friction_setup *f, const double *q, double D[N_OUT][COV_MAX_DOFS]) {
  sk_surface_point pt;
  if (!closest_point(s, q, &pt)) return 0;
  const double g = gap_of(s, q, &pt);
  cov_kinematics k;
  if (!cov_kinematics_eval(&pt, s->dim, s->nen, g, &k)) return 0;
  cov_metric_derivatives d;
  cov_metric_derivatives_eval(&pt, &k, &d);
  const double p = -f->eps_n * g;
  double Dp[COV_MAX_DOFS];
  for (int c = 0; c < k.nd; ++c) Dp[c] = -f->eps_n * k.G[c];
  const double dxi[2] = {pt.xi[0] - f->xi_n[0], s->dim == 3 ? pt.xi[1] - f->xi_n[1] : 0.0};
  double t_cov[2], T[3], DT[3][COV_MAX_DOFS], diss;
  cov_friction(&pt, &k, &d, f->t_n, dxi, f->eps_t, f->mu, p, Dp, NULL, t_cov, T, DT, &diss);
  memset(D, 0, sizeof(double) * N_OUT * COV_MAX_DOFS);
  for (int c = 0; c < k.nd; ++c) {
    int o = 0;
    D[o++][c] = k.G[c];
    for (int a = 0; a < 2; ++a) D[o++][c] = a < k.pdim ? k.Dxi[a][c] : 0.0;
    for (int i = 0; i < 3; ++i) D[o++][c] = k.Dn[i][c];
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) D[o++][c] = a < k.pdim && b < k.pdim ? d.Dm[a][b][c] : 0.0;
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) D[o++][c] = a < k.pdim && b < k.pdim ? d.Dminv[a][b][c] : 0.0;
    for (int a = 0; a < 2; ++a)
      for (int i = 0; i < 3; ++i) D[o++][c] = a < k.pdim ? d.Da_dual[a][i][c] : 0.0;
    for (int i = 0; i < 3; ++i) D[o++][c] = DT[i][c];
    o += 2; /* t_cov: its derivative is folded into DT */
  }
  return 1;
}

/* Central differences of every output; relative error of each derivative column block against the kernel. */
static double fd_error(const face_setup *s, const friction_setup *f, const double *q0) {
  const int nd = s->dim * (1 + s->nen);
  double D[N_OUT][COV_MAX_DOFS];
  SK_CHECK(derivatives(s, f, q0, D));
  double worst = 0.0;
  const double h = 1e-6;
  for (int c = 0; c < nd; ++c) {
    double qp[COV_MAX_DOFS], qm[COV_MAX_DOFS], op[N_OUT], om[N_OUT];
    memcpy(qp, q0, sizeof(double) * (size_t)nd);
    memcpy(qm, q0, sizeof(double) * (size_t)nd);
    qp[c] += h;
    qm[c] -= h;
    SK_CHECK(outputs(s, f, qp, op, NULL) && outputs(s, f, qm, om, NULL));
    for (int o = 0; o < N_OUT - 2; ++o) {
      const double fd = (op[o] - om[o]) / (2 * h);
      const double scale = fmax(1.0, fabs(fd));
      worst = fmax(worst, fabs(fd - D[o][c]) / scale);
    }
  }
  return worst;
}

/* Slave + face positions for each face type: warped / curved faces, slave slightly penetrating near the middle. */
static int positions(sk_elem_type type, double *q) {
  switch (type) {
    case SK_QUAD4: {
      const double v[] = {0.15, -0.1, -0.03, -1, -1, 0.05, 1.1, -0.9, -0.1, 0.95, 1.05, 0.12, -1.05, 0.9, -0.08};
      memcpy(q, v, sizeof v);
      return 15;
    }
    case SK_QUAD9: {
      /* a doubly curved face z = 0.1 (x^2 - 0.5 y^2) on [-1,1]^2, gmsh order: corners, edge midpoints, centre */
      const double xy[9][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}, {0, -1}, {1, 0}, {0, 1}, {-1, 0}, {0, 0}};
      q[0] = 0.2, q[1] = -0.3, q[2] = -0.02;
      for (int I = 0; I < 9; ++I) {
        q[3 + 3 * I] = xy[I][0] * 1.02 + 0.01 * xy[I][1];
        q[4 + 3 * I] = xy[I][1];
        q[5 + 3 * I] = 0.1 * (xy[I][0] * xy[I][0] - 0.5 * xy[I][1] * xy[I][1]);
      }
      return 30;
    }
    case SK_TRI3: {
      const double v[] = {0.3, 0.25, -0.04, 0, 0, 0.02, 1, 0.05, -0.05, 0.1, 1.1, 0.08};
      memcpy(q, v, sizeof v);
      return 12;
    }
    case SK_LINE3: {
      /* gmsh LINE3: end, end, middle: a curved arc */
      const double v[] = {0.1, 0.05, 1, 0, -1, 0.02, 0.0, 0.15};
      memcpy(q, v, sizeof v);
      return 8;
    }
    default: return 0;
  }
}

static void check_type(sk_elem_type type, int dim) {
  face_setup s;
  setup_face(&s, dim, type);
  double q[COV_MAX_DOFS];
  positions(type, q);
  /* LINE3 faces point -y for increasing u in the core's convention: flip the slave's side so it penetrates. */
  sk_surface_point pt;
  SK_CHECK(closest_point(&s, q, &pt));
  if (gap_of(&s, q, &pt) > 0)
    for (int i = 0; i < dim; ++i) q[i] -= 2.0 * gap_of(&s, q, &pt) * pt.n[i];
  SK_CHECK(closest_point(&s, q, &pt));
  SK_CHECK(gap_of(&s, q, &pt) < 0.0);
  const double xi_n[2] = {pt.xi[0] - 0.01, pt.xi[1] + 0.005};
  const double t_n[2] = {0.3, -0.2};
  /* stick: a small slip increment and a large cone */
  friction_setup stick = {.t_n = t_n, .xi_n = xi_n, .eps_n = 100.0, .eps_t = 50.0, .mu = 10.0};
  int state;
  double out[N_OUT];
  SK_CHECK(outputs(&s, &stick, q, out, &state));
  SK_CHECK(state == COV_STICK);
  double err = fd_error(&s, &stick, q);
  printf("  %s stick: worst relative FD error %.2e\n", sk_elem_name(type), err);
  SK_CHECK(err < 3e-7); /* measured <= 4.1e-8 (tri3 slip); a wrong term gives O(1) */
  /* slip: a small cone */
  friction_setup slip = stick;
  slip.mu = 1e-3;
  SK_CHECK(outputs(&s, &slip, q, out, &state));
  SK_CHECK(state == COV_SLIP);
  err = fd_error(&s, &slip, q);
  printf("  %s slip:  worst relative FD error %.2e\n", sk_elem_name(type), err);
  SK_CHECK(err < 3e-7); /* measured <= 4.1e-8 (tri3 slip); a wrong term gives O(1) */
}

/* The split of dn: Dn_rot is the normal's change with the nodes at fixed xi, Dn_curv its change through xi alone
 * (the closest point of the perturbed positions, on the unperturbed face). */
static void check_normal_split(sk_elem_type type, int dim) {
  face_setup s;
  setup_face(&s, dim, type);
  double q[COV_MAX_DOFS];
  const int nd = positions(type, q);
  sk_surface_point pt;
  SK_CHECK(closest_point(&s, q, &pt));
  cov_kinematics k;
  SK_CHECK(cov_kinematics_eval(&pt, dim, s.nen, gap_of(&s, q, &pt), &k));
  const double h = 1e-6;
  double err_rot = 0.0, err_curv = 0.0, size_curv = 0.0;
  for (int c = 0; c < nd; ++c) {
    double qp[COV_MAX_DOFS], qm[COV_MAX_DOFS];
    memcpy(qp, q, sizeof(double) * (size_t)nd);
    memcpy(qm, q, sizeof(double) * (size_t)nd);
    qp[c] += h;
    qm[c] -= h;
    sk_surface_point np, nm, xp, xm, cp, cm;
    sk_surface_geometry(&s.face, 0, pt.xi, qp, &np); /* nodes moved, xi fixed */
    sk_surface_geometry(&s.face, 0, pt.xi, qm, &nm);
    SK_CHECK(closest_point(&s, qp, &xp) && closest_point(&s, qm, &xm));
    sk_surface_geometry(&s.face, 0, xp.xi, q, &cp); /* xi moved, nodes fixed */
    sk_surface_geometry(&s.face, 0, xm.xi, q, &cm);
    for (int i = 0; i < 3; ++i) {
      err_rot = fmax(err_rot, fabs((np.n[i] - nm.n[i]) / (2 * h) - k.Dn_rot[i][c]));
      err_curv = fmax(err_curv, fabs((cp.n[i] - cm.n[i]) / (2 * h) - k.Dn_curv[i][c]));
      size_curv = fmax(size_curv, fabs(k.Dn_curv[i][c]));
      SK_CHECK(k.Dn[i][c] == k.Dn_rot[i][c] + k.Dn_curv[i][c]);
    }
  }
  printf("  %s dn split: |Dn_rot - FD| %.1e, |Dn_curv - FD| %.1e (|Dn_curv| %.1e)\n", sk_elem_name(type), err_rot,
         err_curv, size_curv);
  SK_CHECK(err_rot < 1e-9 && err_curv < 1e-9); /* measured <= 1.6e-10 (quad9) */
  if (type != SK_TRI3) SK_CHECK(size_curv > 1e-3); /* curved or warped: the curvature part is there to check */
}

/* The return map: a slip traction lies on the cone |t| = mu p (in the metric), and dissipates >= 0. */
static void check_return_map(void) {
  const double trial[2] = {3.0, -1.0}, Dtrial[2] = {0, 0}, Dp[1] = {0};
  const double minv[3][3] = {{0.5, 0.1, 0}, {0.1, 2.0, 0}, {0, 0, 1}};
  double t[2], Dt[2], diss;
  int state = cov_return_map(2, trial, Dtrial, minv, 0.2, 4.0, Dp, 1, 10.0, t, Dt, &diss);
  SK_CHECK(state == COV_SLIP);
  const double norm = sqrt(t[0] * (minv[0][0] * t[0] + minv[0][1] * t[1]) + t[1] * (minv[1][0] * t[0] + minv[1][1] * t[1]));
  SK_CHECK_CLOSE(norm, 0.2 * 4.0, 1e-14);
  SK_CHECK(diss > 0.0);
  state = cov_return_map(2, trial, Dtrial, minv, 10.0, 4.0, Dp, 1, 10.0, t, Dt, &diss);
  SK_CHECK(state == COV_STICK && t[0] == trial[0] && t[1] == trial[1] && diss == 0.0);
  /* With the switch's memory (mu p = 0.8, |trial| = 2.46 in the metric): a held slip traction along the trial keeps
   * the slip; one opposite to it, or at right angles to it (its component along the held direction below mu p),
   * sticks with the stick tangent; the held traction is read in the metric (m^-1). */
  const double Dtrial2[2] = {1.5, -0.5};
  const double along[2] = {0.6, -0.2}, opposite[2] = {-0.6, 0.2};
  const double across[2] = {trial[1] * minv[1][1] + trial[0] * minv[1][0], -(trial[0] * minv[0][0] + trial[1] * minv[0][1])};
  double t_free[2], Dt_free[2];
  cov_return_map(2, trial, Dtrial2, minv, 0.2, 4.0, Dp, 1, 10.0, t_free, Dt_free, &diss);
  state = cov_return_map_held(2, trial, Dtrial2, minv, 0.2, 4.0, Dp, 1, 10.0, along, t, Dt, &diss);
  SK_CHECK(state == COV_SLIP && t[0] == t_free[0] && t[1] == t_free[1] && Dt[0] == Dt_free[0]);
  const double *turned[2] = {opposite, across};
  for (int c = 0; c < 2; ++c) {
    state = cov_return_map_held(2, trial, Dtrial2, minv, 0.2, 4.0, Dp, 1, 10.0, turned[c], t, Dt, &diss);
    SK_CHECK(state == COV_STICK && t[0] == trial[0] && t[1] == trial[1] && Dt[0] == 1.5 && Dt[1] == -0.5);
    SK_CHECK(diss == 0.0);
  }
  SK_CHECK(cov_slip_turned_back(2, trial, minv, 0.8, NULL) == 0);
}

/* A rigid rotation of slave and face leaves the covariant kinematics (xi, g, m_ab) and so the trial unchanged. */
static void check_frame_indifference(void) {
  face_setup s;
  setup_face(&s, 3, SK_QUAD4);
  double q[COV_MAX_DOFS], r[COV_MAX_DOFS];
  const int nd = positions(SK_QUAD4, q);
  const double c = cos(0.7), sn = sin(0.7);
  for (int I = 0; I < nd / 3; ++I) {
    const double *x = q + 3 * I;
    r[3 * I] = c * x[0] - sn * x[2] + 3.0;
    r[3 * I + 1] = x[1] - 1.0;
    r[3 * I + 2] = sn * x[0] + c * x[2];
  }
  sk_surface_point a, b;
  SK_CHECK(closest_point(&s, q, &a) && closest_point(&s, r, &b));
  SK_CHECK_CLOSE(b.xi[0], a.xi[0], 1e-12);
  SK_CHECK_CLOSE(b.xi[1], a.xi[1], 1e-12);
  SK_CHECK_CLOSE(gap_of(&s, r, &b), gap_of(&s, q, &a), 1e-12);
  for (int x = 0; x < 2; ++x)
    for (int y = 0; y < 2; ++y) SK_CHECK_CLOSE(b.m[x][y], a.m[x][y], 1e-12);
}

int main(void) {
  check_type(SK_QUAD4, 3);
  check_type(SK_QUAD9, 3);
  check_type(SK_TRI3, 3);
  check_type(SK_LINE3, 2);
  check_normal_split(SK_QUAD4, 3);
  check_normal_split(SK_QUAD9, 3);
  check_normal_split(SK_TRI3, 3);
  check_return_map();
  check_frame_indifference();
  return sk_test_finish("test_covariant_kernel");
}
