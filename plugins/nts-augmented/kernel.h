/* nts-augmented — the element kernel: one node-to-surface (NTS) element with coordinate augmentation
 * (Franke, Hesch, Betsch 2013, Eqs 48-61, 74-81 and App. B). Pure functions, no host: the facet's shape functions
 * come in through callbacks (the plugin passes host->contact->shape, tests may pass their own).
 *   kernel.c      constraints, their derivatives, the friction law and the element system of (50)/(76)
 *   strategies.c  what the strategies do with it: exact condensation, the paper's reduced scheme (80)/(81), the
 *                 direct method's local elimination (41, 74/75), the closest point, P (54) and lambda_aug (52)
 *
 * Element unknowns, local order: z = [q_s (3) | x_1 .. x_nen (3 each) | f1 f2] (the constraint arguments) and the
 * element system adds the multipliers: u = [q_A (nq = 3 + 3 nen) | lambda_n | f1 f2 | lambda_aug1 lambda_aug2],
 * the order of the plugin's extra unknowns per slave node [lambda_n, f1, f2, lambda_aug1, lambda_aug2].
 *
 * Constraints (k = 0, 1: Phi_aug (48); k = 2: Phi_n (49)), with r = q_s - x(f):
 *   Phi_aug,a = r . a_a(f),   Phi_n = r . n(f),   n = a_1 x a_2 / |a_1 x a_2| (out of the master body).
 * Facets: TRI3, QUAD4 and the second-order TRI6, QUAD8, QUAD9 in 3D, and the 2D segments LINE2 and LINE3 (the
 * curved three-node segment of quadratic elements), embedded in 3D as the facet extruded along e_z: x(f) =
 * sum N_I(f1) x_I + f2 e_z, a_2 = e_z, so n = a_1 x e_z is the core's 2D outward normal. The constraint Hessian
 * needs the third parametric derivatives x,abc, which vanish on all but QUAD8 and QUAD9 (kernel.c). */
#ifndef NTS_AUGMENTED_KERNEL_H
#define NTS_AUGMENTED_KERNEL_H

#include "stickslip/plugin_types.h"

enum {
  NTS_MAX_NEN = 9,                    /* QUAD9 */
  NTS_MAX_NQ = 3 + 3 * NTS_MAX_NEN,  /* 30 */
  NTS_MAX_NZ = NTS_MAX_NQ + 2,        /* q_A and f */
  NTS_MAX_NU = NTS_MAX_NQ + 5,        /* q_A, lambda_n, f, lambda_aug */
  NTS_MAX_NK = NTS_MAX_NQ + 1,        /* the kept unknowns of a condensed element: q_A, lambda_n */
  NTS_PHI_AUG1 = 0,
  NTS_PHI_AUG2 = 1,
  NTS_PHI_N = 2
};

/* Same signatures as sk_contact_services.shape / shape_hessian (dN[a*pdim + k], ddN[(a*pdim + k)*pdim + l]). */
typedef void (*nts_shape_fn)(sk_elem_type type, const double *xi, double *N, double *dN);
typedef void (*nts_shape_hessian_fn)(sk_elem_type type, const double *xi, double *ddN);

typedef struct {
  sk_elem_type type; /* SK_TRI3, SK_QUAD4, SK_TRI6, SK_QUAD8, SK_QUAD9, or SK_LINE2 / SK_LINE3 (2D, extruded) */
  int nen;
  int extruded;      /* 1 for LINE2 and LINE3 */
  int third;         /* 1 where the third parametric derivatives do not vanish: QUAD8, QUAD9 */
  nts_shape_fn shape;
  nts_shape_hessian_fn shape_hessian;
} nts_facet;

/* Fills a facet descriptor; returns -1 for a face type the kernel does not handle. */
int nts_facet_init(nts_facet *facet, sk_elem_type type, nts_shape_fn shape, nts_shape_hessian_fn shape_hessian);

/* How far f lies outside the facet's parametric domain ([-1, 1]^pdim for lines and quadrilaterals, the unit triangle
 * for triangles),
 * in parametric units: 0 inside or on the border. */
double nts_facet_outside(const nts_facet *facet, const double f[2]);

/* Constraint values, gradients and the facet geometry at (q_A, f). */
typedef struct {
  int nen, nq, nz;
  double N[NTS_MAX_NEN], dN[NTS_MAX_NEN][2], ddN[NTS_MAX_NEN][2][2];
  double x[3], r[3];               /* master point x(f), r = q_s - x(f) */
  double a[2][3], a_ab[2][2][3];   /* a_a = x,a ; a_ab = x,ab */
  double a_abc[2][2][2][3];        /* x,abc (zero unless facet->third) */
  double c[3], c_norm, n[3];       /* c = a_1 x a_2, n = c / |c| */
  double m[2][2];                  /* metric a_a . a_b */
  double phi[3];                   /* Phi_aug1, Phi_aug2, Phi_n */
  double grad[3][NTS_MAX_NZ];      /* d Phi_k / d z */
} nts_geometry;

void nts_geometry_eval(const nts_facet *facet, const double *q_A, const double f[2], nts_geometry *geo);

/* The spatial vector t^a a_a = (m^{-1} t)^a a_a of covariant tangential components t at geo: its length is
 * sqrt(t . m^{-1} t), the norm of the friction law. */
void nts_traction_vector(const nts_geometry *geo, const double t[2], double vector[3]);

/* H = sum_k lambda[k] d2 Phi_k / dz2 (nz x nz, row-major), lambda ordered like phi. */
void nts_constraint_hessian(const nts_geometry *geo, const double lambda[3], double *H);

/* Derivatives of the metric components (m11, m12, m22) with respect to z at geo: dm[3][nz]. */
void nts_metric_gradient(const nts_geometry *geo, double dm[3][NTS_MAX_NZ]);

/* ---- Coulomb friction (App. B), penalty-regularised return map --------------------------------------------------
 * Evaluated with the metric at the evaluation configuration y_hat = (q_hat, f_hat) = alpha y_{n+1} + (1-alpha) y_n:
 *   trial   t_tr = t_n + eps_T m_hat (f_{n+1} - f_n)                        (B.3, end-of-step form)
 *   |t|^2 = t . m_hat^{-1} t; stick if |t_tr| <= mu |lambda_n|, else t_{n+1} = mu |lambda_n| t_tr / |t_tr|  (B.7)
 *   force conjugate to f: t_used = (1 - theta) t_n + theta t_{n+1}, theta = alpha.
 * Derivatives are with respect to the end-of-step unknowns (z_{n+1} and lambda_n): exact, stick and slip. */
typedef struct {
  double mu, epsilon_t;
} nts_friction_params;

/* Which branch of the return map to use: the trial decides (the map itself), or a branch fixed by the caller's
 * stick/slip active set (Newton on the non-smooth map alone can cycle between slip directions when eps_T is stiff
 * compared with the bulk). A fixed slip branch with a vanishing trial falls back to stick. */
typedef enum { NTS_FRICTION_RETURN_MAP = 0, NTS_FRICTION_STICK, NTS_FRICTION_SLIP } nts_friction_mode;

typedef struct {
  double t_next[2];                /* t_{n+1}, covariant */
  double t_used[2];                /* traction conjugate to f in this step's equations */
  double dt_dz[2][NTS_MAX_NZ];     /* d t_used / d z_{n+1} */
  double dt_dlambda_n[2];          /* d t_used / d lambda_n (non-zero when slipping) */
  double trial_norm;               /* |t_tr| in the metric m_hat */
  double cone;                     /* mu |lambda_n| */
  int slip;
} nts_friction;

void nts_friction_eval(const nts_geometry *geo_hat, double alpha, const double f[2], const double f_start[2],
                       const double t_start[2], double lambda_n, const nts_friction_params *params,
                       nts_friction_mode mode, nts_friction *out);

/* ---- the element system ---------------------------------------------------------------------------------------
 * Residual rows (u order) of an active element, y_hat = alpha y_{n+1} + (1 - alpha) y_n:
 *   q_A:        grad_q Phi(y_hat)^T lambda                  (force in F = M + f_int + f_c - f_ext)
 *   lambda_n:   Phi_n(y_{n+1})                               (76)_4
 *   f:          grad_f Phi(y_hat)^T lambda + t_used          (50)_2 / (76)_3
 *   lambda_aug: Phi_aug(y_{n+1})                             (76)_4
 * The direct method of (74)/(75) moves two rows (aug_at_hat, f_gap): lambda_aug: Phi_aug(y_hat), so that f_hat is
 * the closest point of the midpoint configuration; lambda_n: the closest-point gap of q_{n+1}, Phi_n(q_{n+1},
 * f_gap) with f_gap the closest point of q_{n+1} (a function of q alone: its derivative is the q-part of grad Phi_n
 * because d Phi_n / d f = 0 there). For alpha = 1 both coincide with (76).
 * Inactive elements carry the trivial rows lambda_n = 0, f = f_frozen, lambda_aug = 0 (and no force).
 * J = dR/du_{n+1} exactly (d y_hat / d y_{n+1} = alpha). */
typedef struct {
  double alpha;                    /* 1: backward Euler / quasi-static; 1/2: midpoint (energy-momentum) */
  const double *q_A_start;         /* element positions at t_n (nq), used when alpha < 1 */
  const double *q_A;               /* at t_{n+1} (current iterate) */
  double f_start[2];               /* f at t_n in this facet's coordinates (friction reference, midpoint) */
  double t_start[2];               /* committed tangential traction t_n (covariant, this facet) */
  double f_frozen[2];              /* f of an inactive element */
  double lambda_n, f[2], lambda_aug[2];
  int active;
  nts_friction_mode friction_mode; /* 0 (zero-initialised): the return map decides */
  int aug_at_hat;                  /* (75): Phi_aug enforced at y_hat instead of y_{n+1} */
  const double *f_gap;             /* (74)_3: the lambda_n row is Phi_n(q_{n+1}, f_gap); NULL: Phi_n(y_{n+1}) */
} nts_element_input;

typedef struct {
  int nq, nu;                      /* nu = nq + 5 */
  double R[NTS_MAX_NU];
  double J[NTS_MAX_NU * NTS_MAX_NU]; /* row-major nu x nu */
  double phi[3];                   /* the constraint values the rows enforce (Phi_aug1, Phi_aug2, Phi_n) */
  nts_geometry geo_end;            /* at y_{n+1} */
  nts_geometry geo_hat;            /* at y_hat */
  nts_friction friction;
} nts_element_system;

void nts_element_build(const nts_facet *facet, const nts_element_input *in, const nts_friction_params *params,
                       nts_element_system *sys);

/* y_hat = alpha y + (1 - alpha) y_start of the element (positions and f) and its geometry. */
void nts_geometry_hat(const nts_facet *facet, const nts_element_input *in, nts_geometry *geo_hat);

/* ==== strategies.c ==================================================================================================
 * ---- exact static condensation (strategy `condensed`) ----------------------------------------------------------
 * Eliminates e = [f, lambda_aug] (the last 4 unknowns) keeping k = [q_A, lambda_n]:
 *   Jc = J_kk - J_ke J_ee^{-1} J_ek,  rhs = J_ke J_ee^{-1} R_e,  so that  Jc dk = -R_k + rhs,
 *   and recovery  de = -J_ee^{-1} (R_e + J_ek dk)  (59, with the h_f . Delta f term kept).
 * Jc is (nq+1)^2 row-major. Return 0, or -1 when J_ee is singular (degenerate facet). */
int nts_condense(const nts_element_system *sys, double *Jc, double *rhs);
int nts_recover(const nts_element_system *sys, const double *dk, double de[4]);

/* The paper's projection P_A = -Gq^T inv(Gf^T) (54), nq x 2 row-major, at geo. Returns -1 if Gf is singular. */
int nts_projection_matrix(const nts_geometry *geo, double *P);

/* lambda_aug = -inv(Gf^T) (hf^T lambda_n + t)   (52), with Gf, hf at geo. */
int nts_lambda_aug(const nts_geometry *geo, double lambda_n, const double t[2], double lambda_aug[2]);

/* ---- the paper's reduced scheme (55), (78)-(81) (strategy `paper-reduced`) ------------------------------------
 * lambda_aug is not an unknown of the Newton system: the force on q_A is (78)_2 / (55)_1
 *   R_q = grad_q Phi_n(y_hat) lambda_n + P(y_hat) t_used      (the P grad_f Phi_n lambda_n term of (53) dropped)
 * and Newton solves (80) for [dq, dlambda_n] (our signs: J dx = -F, x += dx):
 *   [K_qq + K_qf P_{n+1}^T   h_hat] [dq      ]   [-R_q + K_qf Gf_{n+1}^{-1} Phi_aug,n+1]
 *   [h_end^T                 0    ] [dlambda_n] = [-Phi_n,n+1                          ]
 * with K_qq, K_qf = dR_q/dq_{n+1}, dR_q/df_{n+1} (consistent, the derivative of P included: the paper's option 1),
 * h_hat = grad_q Phi_n(y_hat) (dt_used/dlambda_n not in the column, as printed), h_end = grad_q Phi_n(y_{n+1})
 * (h_f . Delta f dropped), then (81): df = -Gf_{n+1}^{-1} Phi_aug,n+1 + P_{n+1}^T dq. lambda_aug for output and
 * the next step's start is (52) at y_hat. */
typedef struct {
  int nq;
  double R_q[NTS_MAX_NQ];
  double K_qq[NTS_MAX_NQ * NTS_MAX_NQ];  /* nq x nq row-major */
  double K_qf[NTS_MAX_NQ * 2];
  double h_hat[NTS_MAX_NQ], h_end[NTS_MAX_NQ];
  double phi_end[3];                     /* Phi_aug1, Phi_aug2, Phi_n at y_{n+1} */
  double P_end[NTS_MAX_NQ * 2];          /* (79) */
  double Gf_inv_phi[2];                  /* Gf_{n+1}^{-1} Phi_aug,n+1 */
  double lambda_aug[2];                  /* (52) at y_hat */
  nts_geometry geo_end, geo_hat;
  nts_friction friction;
} nts_paper_system;

/* Returns 0, or -1 when Gf is singular at y_hat or y_{n+1}. in->lambda_aug and in->active are not read. */
int nts_paper_build(const nts_facet *facet, const nts_element_input *in, const nts_friction_params *params,
                    nts_paper_system *sys);
/* (80)'s kept block [q_A, lambda_n] ((nq+1)^2 row-major) and its right-hand side correction (q rows). */
void nts_paper_condensed(const nts_paper_system *sys, double *Jc, double *rhs);
/* (81): df from dq (nq) and the residual Phi_aug,n+1 of the f rows as the host has it. */
void nts_paper_recover(const nts_paper_system *sys, const double *dq, const double phi_aug[2], double df[2]);

/* ---- direct approach --------------------------------------------------------------------------------------------
 * Closest point on the (extended) facet: Newton on Phi_aug(q_A, f) = 0 in f (41), starting from f.
 * Returns the iterations used, or -1 without convergence (|Phi_aug| <= tol * max(1, |a|^2) not reached). */
int nts_closest_point(const nts_facet *facet, const double *q_A, double f[2], double tol, int max_iterations);

/* The direct strategies' local elimination, after which R_f = R_lambda_aug = 0 and the condensed Jacobian of the
 * element is the exact derivative of the direct residual (implicit function theorem: the consistent second
 * variation, with (44)), lambda_aug from (52) at y_hat:
 *   at_midpoint = 0 (`direct-endpoint`): f <- the closest point of q_{n+1}; forces at y_hat = (q_hat, f_hat);
 *   at_midpoint = 1 (`direct`, (74)/(75)): f_hat <- the closest point of q_hat, f = (f_hat - (1 - alpha) f_n) /
 *     alpha; f_gap <- the closest point of q_{n+1} (the normal constraint (74)_3); sets in->aug_at_hat and
 *     in->f_gap = f_gap (which must outlive the element's build).
 * Returns 0, or -1 if a local Newton fails. */
int nts_direct_eliminate(const nts_facet *facet, nts_element_input *in, const nts_friction_params *params,
                         int at_midpoint, double f_gap[2], double tol, int max_iterations);

/* Small dense helpers shared with the plugin. */
int nts_solve_dense(int n, double *A, double *b, int nrhs); /* A (n x n) overwritten, b (n x nrhs) <- A^{-1} b */
int nts_inverse2(const double A[2][2], double Ai[2][2]);

#endif
