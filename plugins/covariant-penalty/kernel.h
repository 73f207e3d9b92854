/* covariant-penalty — the kernel: one contact point of the Konyukhov–Schweizerhof covariant penalty formulation
 * (Konyukhov & Schweizerhof 2005; equation numbers are the paper's, docs/plugins/covariant-penalty.md the design).
 * Pure functions, no host: shape functions come in through callbacks (the plugin passes host->contact->shape).
 *
 * A contact point lives on a small set of local nodes with positions x (3 per node). Its slave point is
 * r_s = S_a x_{slave[a]} (sts: a Gauss point of a slave face, nts: one node) or, for stas, the point of a rigid
 * surface hit by the master's normal ray; its master point is rho(xi) = N_k(xi) x_{master[k]} on one master face.
 *
 * One sign convention: g = (r_s - rho) . n < 0 penetrates, p = eps_n <-g> >= 0, t is the tangential traction on
 * the slave (Cartesian), s = p n + t, and the point adds R = -w A^T s to the residual F = f_int - f_ext + f_c,
 * A = d(r_s - rho)/dz at fixed xi. K = dR/dz = K_main + K_rotational + K_curvature (docs §5). */
#ifndef COVARIANT_PENALTY_KERNEL_H
#define COVARIANT_PENALTY_KERNEL_H

#include "stickslip/plugin_types.h"

enum {
  CP_MAX_FACE_NODES = 9,
  CP_MAX_NODES = 3 * CP_MAX_FACE_NODES, /* slave face, master face, last step's master face */
  CP_MAX_DOFS = 3 * CP_MAX_NODES
};

typedef enum { CP_STS = 0, CP_NTS, CP_STAS } cp_variant;
typedef enum { CP_INACTIVE = 0, CP_STICK = 1, CP_SLIP = 2 } cp_state;
typedef enum { CP_MAIN = 0, CP_ROTATIONAL, CP_CURVATURE, CP_N_PARTS } cp_part;
typedef enum { CP_FORM_EXACT = 0, CP_FORM_PAPER } cp_form;

/* Same signatures as sk_contact_services.shape / shape_hessian (fe.h layout: dN[a*2 + k], ddN[(a*2 + k)*2 + l]). */
typedef void (*cp_shape_fn)(sk_elem_type type, const double *xi, double *N, double *dN);
typedef void (*cp_shape_hessian_fn)(sk_elem_type type, const double *xi, double *ddN);

typedef struct {
  sk_elem_type type; /* SK_QUAD4, SK_QUAD9 or SK_TRI3 */
  int nen;
  cp_shape_fn shape;
  cp_shape_hessian_fn shape_hessian;
} cp_face;

/* Fills a face descriptor; -1 for a type the kernel does not handle. */
int cp_face_init(cp_face *face, sk_elem_type type, cp_shape_fn shape, cp_shape_hessian_fn shape_hessian);

/* Covariant geometry of a face at xi from its node positions xf (3 per face node): the fields of sk_surface_point
 * (position, tangents, normal, metric and inverse, dual tangents, second derivatives, curvature h_ab, Christoffel
 * symbols, area element, N, dN). Returns 0, or -1 for a degenerate point (zero area; n and m_inv left zero). */
int cp_face_point(const cp_face *face, const double *xf, const double xi[2], sk_surface_point *pt);

/* Closest point of r on the polynomial extension of a face: Newton on (r - rho) . rho_i = 0 with the full Hessian
 * a_ij - (r - rho) . rho_ij (21)-(25), from xi. Returns the iterations, or -1 without convergence (step > 1e-13). */
int cp_closest_point(const cp_face *face, const double *xf, const double r[3], double xi[2], int max_iterations);

/* Signed distance of point y to a rigid surface (> 0 outside it) and the surface's outward unit normal at its closest
 * point; returns 0 when it cannot tell. The plugin passes the host's obstacle_project at the step's time. */
typedef int (*cp_distance_fn)(void *ctx, const double y[3], double *distance, double normal[3]);

/* The normal ray of a master point (rho, n) against a rigid surface (117)-(124): hit = rho + g n with
 * distance(hit) = 0, by Newton on g from 0 (d distance / dg = nu . n, nu the surface normal). Accepted only where
 * the surfaces face each other (nu . n < 0) and |g| <= max_depth. Returns 1 with g, hit and nu, or 0. */
int cp_ray(cp_distance_fn distance, void *ctx, const double rho[3], const double n[3], double max_depth, double *g,
           double hit[3], double nu[3]);

typedef struct {
  double eps_n, eps_t, mu;
  double weight;        /* w: reference area (sts, stas: Gauss weight x area element; nts: tributary area or 1) */
  double touch_tol;     /* active when g <= touch_tol (touching counts: one-sided stiffness) */
} cp_params;

/* A contact point: where it lives and its history. */
typedef struct {
  cp_variant variant;
  int n_local;                      /* local nodes; local dofs 3 n_local, node-major */
  const double *x;                  /* their current positions, 3 per node */
  int n_slave;                      /* sts/nts: r_s = sum_a S[a] x[slave[a]] (0 for stas) */
  int slave[CP_MAX_FACE_NODES];
  double S[CP_MAX_FACE_NODES];
  cp_face master;                   /* the master face (stas: the deformable face carrying the Gauss point) */
  int master_nodes[CP_MAX_FACE_NODES];
  double xi[2];                     /* contact point (sts/nts: the closest point; stas: the Gauss point) */
  /* history (docs §4): valid = 0 means no friction force this step */
  int history;
  double t_n[3];                    /* traction of the last step, Cartesian */
  int n_old;                        /* sts/nts: rho_old = sum_l N_old[l] x[old_nodes[l]] (47) */
  int old_nodes[CP_MAX_FACE_NODES];
  double N_old[CP_MAX_FACE_NODES];
  double anchor[3];                 /* stas: Gauss point position at the last step minus the obstacle translation */
  /* stas: the rigid surface (its distance function) and its current translation */
  cp_distance_fn distance;
  void *distance_ctx;
  double obstacle_d[3];
  double max_depth;                 /* stas: deepest accepted penetration along the ray */
} cp_point;

/* Which copy of the positions and of xi each channel reads (docs §5); NULL members mean "the point's own". The
 * residual is a function of all of them; K_main is its derivative through (x_K, xi_K), K_rotational through
 * (x_F, xi_W) and K_curvature through xi_F. Tests difference one channel at a time. */
typedef struct {
  const double *x_K, *xi_K;  /* kinematics: gap and slip increment */
  const double *x_F, *xi_F;  /* frame: the normal (and P) */
  const double *xi_W;        /* weights A(xi) of the virtual work */
} cp_channels;

typedef struct {
  cp_state state;
  double g, p;                /* gap, pressure */
  double n[3];                /* frame normal */
  double x_master[3];         /* rho */
  double t[3];                /* tangential traction on the slave */
  double tau[3];              /* trial P (t_n - eps_t Delta rho) */
  double slip[3];             /* P Delta rho (47), (48): the step's tangential relative displacement (0 without a
                                 history) */
  double dissipation;         /* w mu p (|tau| - mu p) / eps_t when slipping */
  int nd;                     /* 3 n_local */
  double R[CP_MAX_DOFS];
} cp_result;

/* Residual through the channels (all NULL: the plain residual). Fills every field of *out. */
void cp_point_residual(const cp_point *point, const cp_params *params, const cp_channels *channels, cp_result *out);

/* Residual and the tangent parts: K[part] is nd x nd row-major (stride nd) for parts whose want[part] is nonzero
 * (others are left untouched); the form picks the exact derivative or the paper's printed matrices (docs §5).
 * Returns 0, or -1 when the closest-point Hessian a_ij - g h_ij is singular (a focal point of the master). */
int cp_point_eval(const cp_point *point, const cp_params *params, cp_form form, const int want[CP_N_PARTS],
                  cp_result *out, double *K[CP_N_PARTS]);

#endif
