/* Covariant contact kinematics and friction on a master surface — a pure, host-free kernel shared by the plugins
 * (built as the static library stickslip_plugin_common, so plugins still link only libc and libm).
 *
 * Notation (Konyukhov & Schweizerhof 2005, Laursen 2002). A slave point x_s is in contact with the master point
 * x_m = N_I(xi) x_I of a face (nen nodes; nen = 0 for a rigid obstacle) with covariant tangents a_a = x,a, metric
 * m_ab = a_a . a_b, dual tangents a^a = m^ab a_b, second derivatives x,ab, curvature h_ab = x,ab . n. The gap is
 * g = (x_s - x_m) . n. Derivatives are rows over the LOCAL dofs q = [x_s (dim) | x_1 (dim) | ... | x_nen (dim)], so
 * nd = dim (1 + nen).
 *
 * Closest-point kinematics (the closest-point condition (x_s - x_m) . a_a = 0 differentiated):
 *   G        = dg/dq:        G_s = n,  G_I = -N_I n
 *   A Dxi    = C + g E,      A_ab = m_ab - g h_ab,  C_a = a_a . (du at fixed xi),  E_a = n . da_a = dN_I,a n . du_I
 *   Dn       = -a^a (E_a + h_ab Dxi^b) = Dn_rot + Dn_curv
 *   split by what turns the normal (Konyukhov & Schweizerhof's rotational and curvature parts, covariant-penalty):
 *   Dn_rot = -a^a E_a (the face's nodes move at fixed xi),  Dn_curv = -a^a h_ab Dxi^b (the point moves on a curved
 *   face, Weingarten (13)).
 * Metric derivatives (total: nodal part plus x,ab Dxi^b):
 *   Da_a     = x,ab Dxi^b + dN_I,a (du_I),   Dm_ab = a_b . Da_a + a_a . Da_b,
 *   Dm^ab    = -m^ax Dm_xy m^yb,             Da^a = Dm^ab a_b + m^ab Da_b.
 * Friction (penalty regularised Coulomb, covariant components):
 *   t_a^trial = t_n,a - eps_t m_ab dxi^b,     |t| = sqrt(t_a m^ab t_b),
 *   stick t = t^trial;  slip t = mu p t^trial / |t^trial|  (with the derivative of |t^trial| through m^ab),
 *   spatial traction T = t_a a^a,  dissipation of the slip = mu p (|t^trial| - mu p) / eps_t.
 * Every derivative here is checked against central differences in tests/unit/common/test_covariant_kernel.c. */
#ifndef STICKSLIP_PLUGIN_COMMON_COVARIANT_H
#define STICKSLIP_PLUGIN_COMMON_COVARIANT_H

#include "stickslip/plugin_types.h"

enum { COV_MAX_NEN = SK_FACE_NEN_MAX, COV_MAX_DOFS = 3 * (1 + COV_MAX_NEN) };
enum { COV_INACTIVE = 0, COV_STICK = 1, COV_SLIP = 2 };

/* Derivatives of the closest point with respect to the local dofs. */
typedef struct {
  int dim, pdim, nen, nd;
  double g;                        /* gap */
  double G[COV_MAX_DOFS];          /* dg/dq */
  double Dxi[2][COV_MAX_DOFS];     /* dxi^a/dq */
  double Dn[3][COV_MAX_DOFS];      /* dn_i/dq = Dn_rot + Dn_curv */
  double Dn_rot[3][COV_MAX_DOFS];  /* the part at fixed xi */
  double Dn_curv[3][COV_MAX_DOFS]; /* the part through xi */
} cov_kinematics;

/* Derivatives of the tangents, metric, inverse metric and dual tangents at the closest point. */
typedef struct {
  double Da[2][3][COV_MAX_DOFS];
  double Dm[2][2][COV_MAX_DOFS];
  double Dminv[2][2][COV_MAX_DOFS];
  double Da_dual[2][3][COV_MAX_DOFS];
} cov_metric_derivatives;

/* Inverse of the leading n x n block (n = 1 or 2) of a 2x2 matrix; returns 0 when singular. */
int cov_invert2(int n, const double a[2][2], double inv[2][2]);

/* Fills m, m_inv and a_dual of `pt` from its tangents alone (pdim = dim - 1); returns 0 for degenerate tangents. */
int cov_complete_metric(int pdim, sk_surface_point *pt);

/* Closest-point kinematics at `pt` (the closest point of slave position xs on a face with pt->nen nodes, or on an
 * obstacle with nen = 0) for gap g. Returns 0 when A = m - g h is singular (the slave sits at a focal point). */
int cov_kinematics_eval(const sk_surface_point *pt, int dim, int nen, double g, cov_kinematics *k);

/* Metric derivatives from the kinematics (pt->a_ab, pt->dN). */
void cov_metric_derivatives_eval(const sk_surface_point *pt, const cov_kinematics *k, cov_metric_derivatives *d);

/* Coulomb return map on n components with metric_inv (pdim x pdim covariant, or the identity for spatial vectors
 * with n = 3). From the trial and its derivative Dtrial (n x nd) fills t and Dt (n x nd), the dissipation of the
 * slip and returns COV_STICK or COV_SLIP. Under slip, Dt does not contain the derivative of metric_inv (see
 * cov_friction). */
int cov_return_map(int n, const double *trial, const double *Dtrial, const double metric_inv[3][3], double mu,
                   double p, const double *Dp, int nd, double eps_t, double *t, double *Dt, double *dissipation);

/* The branch `state` (COV_STICK or COV_SLIP) of the return map, for a caller that decides stick or slip itself (a
 * tie-break on the cone): the outputs of cov_return_map for that branch. Slip needs |trial| > 0. */
void cov_return_map_branch(int state, int n, const double *trial, const double *Dtrial, const double metric_inv[3][3],
                           double mu, double p, const double *Dp, int nd, double eps_t, double *t, double *Dt,
                           double *dissipation);

/* The stick/slip switch with a memory. `held`: the traction (n components, same basis and metric as the trial) of a
 * point that slipped where the Jacobian was last assembled (the last accepted Newton iterate), NULL when it stuck
 * or had no friction there. Such a point keeps slipping only while its trial's component along the held traction
 * exceeds the cone radius `limit` (its slip goes on in the held direction); otherwise it sticks (t = trial, the
 * stick tangent), instead of slipping the other way. The return map alone sends a slipping point whose Newton step
 * overshoots the stick zone (|trial| <= mu p, a slip of 2 mu p / eps_t across: narrow for a stiff eps_t) to the
 * opposite slip direction, where the tangential stiffness along the slip is again zero, and Newton cycles between
 * the two (docs/stability.md, finding 19). cov_slip_turned_back is the test; cov_return_map_held the return map
 * with it (cov_return_map: held = NULL). A converged point must be checked against the return map alone. */
int cov_slip_turned_back(int n, const double *trial, const double metric_inv[3][3], double limit,
                         const double *held);
int cov_return_map_held(int n, const double *trial, const double *Dtrial, const double metric_inv[3][3], double mu,
                        double p, const double *Dp, int nd, double eps_t, const double *held, double *t, double *Dt,
                        double *dissipation);

/* The covariant friction of a slave point on a deformable master: the trial from the history traction t_n (covariant
 * on the current face) and the parameter increment dxi (xi - xi_n), the return map with the normal force p (and its
 * derivative Dp) and the switch's memory `held` (covariant on the current face, or NULL: cov_return_map_held), and
 * the spatial traction T = t_a a^a with its derivative DT (3 x nd). Fills t_cov (covariant components) and the
 * dissipation; returns COV_STICK or COV_SLIP. */
int cov_friction(const sk_surface_point *pt, const cov_kinematics *k, const cov_metric_derivatives *d,
                 const double t_n[2], const double dxi[2], double eps_t, double mu, double p, const double *Dp,
                 const double *held, double t_cov[2], double T[3], double DT[3][COV_MAX_DOFS], double *dissipation);

#endif
