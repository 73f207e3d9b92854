/* mortar-dual — the host-free kernel: segment-to-segment mortar integrals with standard or dual Lagrange multipliers,
 * their directional derivatives, nodal normals and tangents, and the nonlinear complementarity functions of the
 * semismooth Newton method. Pure functions: the face shape functions come in through callbacks (the plugin passes
 * host->contact->shape / shape_hessian, tests may pass their own); nothing here calls the host.
 * Equations and references: docs/plugins/mortar-dual.md (numbers in brackets below are its equation labels).
 *
 * Notation. Slave (non-mortar) face with nodes j, k; master (mortar) face with nodes l. Positions are current
 * coordinates x. A "pair" is one slave face and one master face (or none, for a rigid obstacle); its local unknowns,
 * with respect to which every fwd result carries derivatives, are
 *   u = [x_s (nen_s * dim) | x_m (nen_m * dim) | n_s (nen_s * dim)]
 * with n_s the unit averaged nodal normals of the slave face's nodes (their own derivatives with respect to the
 * coordinates of the neighbouring faces come from mortar_face_normal_at_node and are chained by the caller).
 * Faces: LINE2 and LINE3 in 2D, TRI3, TRI6, QUAD4, QUAD8 and QUAD9 in 3D (the parametric Hessian enters as values
 * only: in the Jacobians of local Newton iterations and in the derivative of the tangents, so third derivatives are
 * never needed). */
#ifndef MORTAR_KERNEL_H
#define MORTAR_KERNEL_H

#include "fwd.h"
#include "stickslip/mesh.h"

/* face nodes: 9 (QUAD9), 4 in the narrow copy (fwd.h) */
enum { MORTAR_MAX_NEN_NARROW = 4, MORTAR_MAX_POLY = 16, MORTAR_MAX_RULE = 16 };
#ifdef MORTAR_NARROW
enum { MORTAR_MAX_NEN = MORTAR_MAX_NEN_NARROW };
#else
enum { MORTAR_MAX_NEN = 9 };
#endif

/* Same signatures as sk_contact_services.shape / shape_hessian (dN[a*pdim + k], ddN[(a*pdim + k)*pdim + l]). */
typedef void (*mortar_shape_fn)(sk_elem_type type, const double *xi, double *N, double *dN);
typedef void (*mortar_shape_hessian_fn)(sk_elem_type type, const double *xi, double *ddN);

typedef struct {
  sk_elem_type type; /* SK_LINE2, SK_LINE3, SK_TRI3, SK_TRI6, SK_QUAD4, SK_QUAD8 or SK_QUAD9 */
  int nen, pdim;
  mortar_shape_fn shape;
  mortar_shape_hessian_fn shape_hessian;
  double alpha; /* TRI6 and QUAD8: alpha of the transformed functions (mortar_transform); SK_MODIFIED_BASIS_ALPHA */
} mortar_face_type;

/* Fills a face descriptor; returns -1 for a face type the kernel does not handle. */
int mortar_face_type_init(mortar_face_type *ft, sk_elem_type type, mortar_shape_fn shape,
                          mortar_shape_hessian_fn shape_hessian);

/* MORTAR_DUAL_TRANSFORMED (TRI6 and QUAD8 slave faces): dual to the transformed functions N~ = T N (mortar_transform),
 * so D_jk = int Phi_j N_k is not diagonal; no shortcut of MORTAR_DUAL (D_jj alone, diagonal forces) applies. */
typedef enum { MORTAR_STANDARD = 0, MORTAR_DUAL = 1, MORTAR_DUAL_TRANSFORMED = 2 } mortar_basis;
/* Normal field of the kinematics (Hammer 2012, ch. 4): A = averaged continuous slave normal, M = non-continuous
 * master normal (closest-point projection). Segment-based integration uses A. */
typedef enum { MORTAR_NORMAL_A = 0, MORTAR_NORMAL_M = 1 } mortar_normal;

/* ---- a face pair and its local unknowns ------------------------------------------------------------------------ */
typedef struct {
  int dim;
  const mortar_face_type *slave, *master; /* master NULL for a rigid obstacle */
  int nen_s, nen_m;
  int n_local;                            /* derivative slots in use (0: values only) */
  fwd xs[MORTAR_MAX_NEN][3], xm[MORTAR_MAX_NEN][3], ns[MORTAR_MAX_NEN][3];
} mortar_pair;

/* Sets up a pair from plain coordinates (3 per node, z = 0 in 2D) and unit slave nodal normals; seeds u when
 * `derivatives` is non-zero. master may be NULL (xm ignored). */
void mortar_pair_set(mortar_pair *p, int dim, const mortar_face_type *slave, const mortar_face_type *master,
                     const double *xs, const double *xm, const double *ns, int derivatives);
/* Local slot of component i of slave node a, master node b, slave normal a. */
static inline int mortar_slot_xs(const mortar_pair *p, int a, int i) { return a * p->dim + i; }
static inline int mortar_slot_xm(const mortar_pair *p, int b, int i) { return (p->nen_s + b) * p->dim + i; }
static inline int mortar_slot_ns(const mortar_pair *p, int a, int i) {
  return (p->nen_s + p->nen_m + a) * p->dim + i;
}

/* ---- shape functions, face geometry ---------------------------------------------------------------------------- */
/* N and dN at parameters xi given as fwd (derivatives flow through xi, dN's through the shape functions' Hessian). */
void mortar_shape(const mortar_face_type *ft, const fwd *xi, fwd *N, fwd dN[][2]);
/* Position x(xi) and tangents a_alpha(xi) of a face with node positions x (fwd, 3 per node). */
void mortar_face_point(const mortar_face_type *ft, fwd x[][3], const fwd *xi, fwd *pos, fwd a[2][3]);

/* ---- multiplier bases [B1-B3] ---------------------------------------------------------------------------------- */
/* Phi_j = sum_k coeff[j][k] N_k on the slave face. The coefficients depend on x_s alone, whose slots are the same in a
 * face-only pair and in every pair of that face: one computation serves them all. Standard: the identity. Dual (Wohlmuth 2000): A_e = D_e M_e^-1
 * with D_e = diag(int N_j), M_e = int N_j N_k over the whole current slave face, so int Phi_j N_k = delta_jk int N_k.
 * LINE2 and TRI3 give the constants (2, -1 / 3, -1), QUAD4, LINE3 and QUAD9 depend on the face's shape (derivatives
 * included). QUAD9's shape functions integrate to 1/36, 1/9, 4/9 of a parallelogram (corner, mid-side, centre):
 * admissible as well. LINE3's shape functions integrate to the positive weights 1/6, 1/6, 2/3 of a straight face with its
 * middle node in the middle, so this standard dual basis is admissible there (D_jj = int N_j > 0). TRI6's and QUAD8's
 * vertex functions integrate to 0 and -1/12 of the face: MORTAR_DUAL_TRANSFORMED builds A~ = D~ M~^-1 on N~ = T N
 * (D~ = diag(int N~_j), M~ = int N~_j N~_k) and returns A = A~ T, so Phi_j = sum_k A_jk N_k and int Phi_j N~_k =
 * delta_jk int N~_k. */
typedef struct {
  int nen;
  fwd coeff[MORTAR_MAX_NEN][MORTAR_MAX_NEN];
} mortar_basis_coeffs;
void mortar_basis_coefficients(const mortar_pair *p, mortar_basis basis, mortar_basis_coeffs *A);
/* TRI6 and QUAD8 (gmsh order: the corners, then the mid-side node of the edge from corner e to e + 1): T[j][k] with
 * N~_j = sum_k T_jk N_k, N~_v = N_v + alpha (N_e1 + N_e2) for the vertex v and its two edges, N~_e = (1 - 2 alpha) N_e,
 * alpha = ft->alpha (mortar_face_type_init: 1/5, SK_MODIFIED_BASIS_ALPHA, the host's tributary weights; the plugin's
 * `transform_alpha`): every N~ integrates to a positive share of a flat face (at 1/5, TRI6: 2/15 at the vertices, 1/5
 * at the edges; QUAD8: 1/20 and 1/5 of a parallelogram) and sum_j N~_j = 1. Returns the number of face nodes, 0 (T
 * untouched) for a face type that is not transformed. */
int mortar_transform(const mortar_face_type *ft, double T[MORTAR_MAX_NEN][MORTAR_MAX_NEN]);
/* Nt = T N (values, nen entries). */
void mortar_transform_values(int nen, double T[MORTAR_MAX_NEN][MORTAR_MAX_NEN], const double *N, double *Nt);

/* ---- mortar integrals [I1-I4] ---------------------------------------------------------------------------------
 *   D_jk = int_{slave face} Phi_j N_k^(1)                      (mortar_slave_integrals: the whole slave face)
 *   M_jl = int_{overlap} Phi_j N_l^(2)(xi^(2)),  gap_j = int_{overlap} Phi_j g_n      (the pair functions)
 * D belongs to the slave surface alone (the potential contact surface; Popp et al. 2009), so it is invertible for
 * every slave node, covered by the master or not. With the dual basis (MORTAR_DUAL; not the transformed one of TRI6,
 * QUAD8) D is diagonal, D_jj = int Phi_j (the row sum, equal to int Phi_j N_j where the rule integrates the
 * biorthogonality exactly). Where the master covers a slave
 * face, sum_k D_jk = sum_l M_jl (linear momentum); where it covers only part of it, the slave force exceeds the
 * master's by the uncovered part — at the border of the master surface only. */
typedef struct {
  int nen_s, nen_m;
  fwd D[MORTAR_MAX_NEN][MORTAR_MAX_NEN];
  fwd M[MORTAR_MAX_NEN][MORTAR_MAX_NEN];
  fwd gap[MORTAR_MAX_NEN];
  double cover[MORTAR_MAX_NEN]; /* int_overlap N_j (value; N~_j on TRI6, QUAD8): how much of node j's support the
                                 * master covers */
  double measure;  /* integrated measure (length/area) of the overlap */
  double gap_min;  /* the smallest g_n at an integration point (value; +inf without points) */
  int n_cells;     /* 2D: segments; 3D: integration triangles; concentrated/obstacle: points used */
} mortar_integrals;

void mortar_integrals_zero(mortar_integrals *I, const mortar_pair *p);

/* D of the slave face with a rule on the whole face (exact: degree 2 in the face parameters on affine faces, 3 per
 * direction on planar QUAD4). */
void mortar_slave_integrals(const mortar_pair *p, const mortar_basis_coeffs *A, mortar_basis basis, int n,
                            const double *xi, const double *w, mortar_integrals *I);

/* Segment-based integration, 2D (Popp, Gee, Wall 2009; McDevitt & Laursen 2000): the master nodes are projected onto
 * the slave line along the interpolated averaged slave normal, the overlap [xi_a, xi_b] gets n_gauss Gauss points,
 * each projected onto the master along n(xi^(1)). Exact D and M for straight edges with parallel nodal normals
 * (the patch test). LINE3 faces (either side): the same construction by local Newton iterations on the quadratic
 * slave line and master (n_gauss points on the segment, the slave Jacobian at each). Returns 1 if the faces
 * overlap (integrals added), 0 otherwise. */
int mortar_segments_2d(const mortar_pair *p, const mortar_basis_coeffs *A, mortar_basis basis, int n_gauss,
                       mortar_integrals *I);

/* Segment-based integration, 3D (Puso & Laursen 2004; Popp et al. 2010): auxiliary plane through the slave face's
 * centre with normal n0 = the interpolated slave normal there; both faces projected onto it along n0, the master
 * polygon clipped against the slave polygon (Sutherland-Hodgman), the clip polygon split into triangles about its
 * centroid, a `rule`-point triangle rule on each, every Gauss point projected back onto both faces along n0. The
 * measure is the slave surface's own (the plane's area element scaled by the slave Jacobian ratio). QUAD9 faces (either
 * side; Popp, Wohlmuth, Gee & Wall 2012): the cells are built on the face's four flat bilinear quarters (corner,
 * mid-side and centre nodes), every quarter of the slave against every quarter of the master, each on its own
 * auxiliary plane; a Gauss point's quarter parameters map to the face's (xi = c + s / 2), where the quadratic shape
 * functions, dual functions, positions and the slave Jacobian are evaluated. Exact geometry where the quarters are
 * the faces (flat faces with the mid-side nodes in the middles). QUAD8 faces the same, their quarters meeting at the
 * face's point x(0, 0) (no centre node). TRI6 faces the same on their four flat sub-triangles (xi = c + h s, h = 1/2,
 * or -1/2 for the middle one). Returns 1 if the faces overlap. */
int mortar_segments_3d(const mortar_pair *p, const mortar_basis_coeffs *A, mortar_basis basis, int rule,
                       mortar_integrals *I);

/* Concentrated integration (Hammer 2012, sec. 6.5.2): the given slave points (fixed parameters, weights of the
 * reference rule) are projected onto this pair's master face with normal variant A or M; each adds its integrand
 * with weight w J^(1). The caller assigns points to master faces (mortar_project_point). */
void mortar_points(const mortar_pair *p, const mortar_basis_coeffs *A, mortar_basis basis, mortar_normal normal,
                   int n, const double *xi, const double *w, mortar_integrals *I);

/* Rigid obstacle as master: the signed distance of x and the obstacle's outward unit normal at its closest point
 * (the distance's gradient). Returns 0, or non-zero when the obstacle cannot project x. */
typedef int (*mortar_obstacle_fn)(void *ctx, const double *x, double *gap, double *normal);
/* Gauss points on the whole slave face (no master face: M stays empty); g_n = the obstacle's distance, with the
 * derivative n_o . d x^(1). Points the obstacle cannot project are skipped. */
void mortar_obstacle_points(const mortar_pair *p, const mortar_basis_coeffs *A, mortar_basis basis, int n,
                            const double *xi, const double *w, mortar_obstacle_fn obstacle, void *ctx,
                            mortar_integrals *I);

/* Projection of one slave point (parameters xi) onto the pair's master face, values only: variant A along the
 * interpolated slave normal, M the closest point (master normal). Fills xi_m and g_n; returns 0, -1 if it fails
 * (parallel faces, no convergence). `inside` is 1 when xi_m lies on the face (tolerance tol in parameters). */
typedef struct {
  double xi[2];
  double gap;
  int inside;
} mortar_point_projection;
int mortar_project_point(const mortar_pair *p, mortar_normal normal, const double *xi, double tol,
                         mortar_point_projection *out);

/* ---- what the pair contributes to the system -------------------------------------------------------------------
 * Contact force on its nodes (residual rows, F = ... + f_c): slave node k: sum_j D_jk z_j; master node l:
 * -sum_j M_jl z_j (z_j the slave node's multiplier vector, traction-like, z_n = n_j . z_j >= 0 in compression).
 * f[a][i] for a < nen_s the slave nodes, then the master nodes. */
void mortar_pair_forces(const mortar_pair *p, const mortar_integrals *I, mortar_basis basis, const double z[][3],
                        fwd f[][3]);
/* Weighted relative position W_j = sum_k D_jk x_k - sum_l M_jl x_l (the slip's moving part [S1]). */
void mortar_pair_weighted_positions(const mortar_pair *p, const mortar_integrals *I, mortar_basis basis,
                                    fwd W[][3]);

/* ---- nodal normals and tangents [N1-N3] ------------------------------------------------------------------------
 * The contribution of one face to the averaged normal of its local node a: c = a_1 x e_z (2D, length-weighted) or
 * a_1 x a_2 at the node (3D, area-weighted), and dc[b][i][j] = d c_i / d x_(b,j) for the face's nodes b. The nodal
 * normal is n = (sum_faces c) / |sum_faces c|. x: 3 per node. */
void mortar_face_normal_at_node(const mortar_face_type *ft, int dim, const double *x, int a, double c[3],
                                double dc[][3][3]);
/* n = c/|c| and dn_dc = (I - n n)/|c|. Returns -1 if |c| = 0. */
int mortar_normalize(const double c[3], double n[3], double dn_dc[3][3]);
/* Tangents of a nodal normal: 2D tau = e_z x n; 3D tau_1 = (r - (r.n) n)/|...| for a reference direction r fixed
 * during the step, tau_2 = n x tau_1. dtau_dn[a][i][j] = d tau_a,i / d n_j. Returns -1 if r is parallel to n. */
int mortar_tangents(int dim, const double n[3], const double ref[3], double tau[2][3], double dtau_dn[2][3][3]);
/* The Cartesian place of each NCP row of a node (place[0] for C_N, place[1 + a] for C_T along tau_a), a permutation
 * of 0 .. dim-1: C_N at the normal's dominant axis, the tangents' rows at the remaining axes where their components
 * are largest. The condensed operator puts constraint row i in the slave's displacement row i; this keeps its
 * diagonal nonzero. */
void mortar_ncp_places(int dim, const double n[3], const double tau[2][3], int place[3]);

/* ---- nonlinear complementarity functions [C1-C2] ---------------------------------------------------------------
 * With g = gap_j / A_j and s = tangential weighted slip / A_j (A_j the node's reference tributary measure):
 *   C_N = z_n - max(0, z_n - c_n g)
 *   C_T = z_t - P_B(r)(z_t + c_t s),   r = mu max(0, z_n - c_n g)   (projection onto the disc of radius r)
 * (Hueber & Wohlmuth 2005; Hueber, Stadler & Wohlmuth 2008; the max-form of Gitterle et al. 2010 is C_T times
 * max(r, |z_t + c_t s|): the same roots.) Branches: inactive (z_n - c_n g < 0): C = (z_n, z_t); stick: C_T = -c_t s;
 * slip: C_T = z_t - r v/|v|. Frictionless (mu = 0): C_T = z_t. The derivative is the semismooth (generalised) one of
 * the branch. `force_state` >= 0 evaluates that branch whatever the arguments (the nested active-set loop). */
typedef enum { MORTAR_INACTIVE = 0, MORTAR_STICK = 1, MORTAR_SLIP = 2 } mortar_state;
typedef struct {
  double mu, c_n, c_t;
} mortar_ncp_params;
typedef struct {
  int state;
  double C[3];     /* [C_N, C_T components (dim - 1)] */
  double dC[3][6]; /* derivatives with respect to [z_n, z_t (2), g, s (2)] */
} mortar_ncp;
void mortar_ncp_eval(int n_t, double z_n, const double *z_t, double g, const double *s, const mortar_ncp_params *prm,
                     int force_state, mortar_ncp *out);
/* The same with the slip branch's direction frozen (slip_dir, unit, n_t components; NULL: v / |v|): C_T = z_t - r d.
 * Hammer's nested loop (Algorithm 1, sec. 6.4.1.2) keeps a slipping node's direction for the Newton run and turns it
 * to stick at the outer update when the weighted slip reverses: with v / |v| evaluated at every iterate the slip
 * traction jumps where the slip turns, and Newton on a frozen set does not converge there (the reversal of Hammer's
 * benchmark: 30 iterations stalled at 0.87 of the first residual, the step cut 6 times and failed). */
void mortar_ncp_eval_dir(int n_t, double z_n, const double *z_t, double g, const double *s,
                         const mortar_ncp_params *prm, int force_state, const double *slip_dir, mortar_ncp *out);
/* Whether branch `state` holds at (z_n, z_t, g, s) up to tol (a traction): its defining inequality relaxed by tol —
 * inactive z_n - c_n g < tol; active z_n - c_n g >= -tol, and with friction |z_t + c_t s| <= r + tol (stick) or
 * >= r - tol (slip; with a frozen direction d: along d). A converged point on the border of two branches (touching
 * without pressure, g = z_n = 0 up to round-off; sticking at the slip limit) satisfies both: the set decided there
 * keeps such a node in its branch instead of flipping it on the sign of round-off. */
int mortar_ncp_branch_holds(int n_t, double z_n, const double *z_t, double g, const double *s,
                            const mortar_ncp_params *prm, int state, const double *slip_dir, double tol);

/* ---- quadrature ------------------------------------------------------------------------------------------------ */
/* Gauss-Legendre on [-1, 1], 1 <= n <= MORTAR_MAX_RULE. */
void mortar_gauss_legendre(int n, double *x, double *w);
/* Triangle rules on the unit simplex (weights sum to 1/2): 1, 3, 6, 7, 12 points (degrees 1, 2, 4, 5, 6).
 * Returns the number of points, or 0 for an unsupported count. */
int mortar_triangle_rule(int n, const double **xi, const double **w);
/* Reference rule on a whole slave face with about `order` points per direction: LINE2 and LINE3 n Gauss points, QUAD4
 * and QUAD9 n x n, TRI3 the triangle rule of the nearest supported size. Returns the number of points (<= MORTAR_MAX_RULE^2). */
int mortar_face_rule(sk_elem_type type, int order, double *xi, double *w);
/* Points per direction of the whole-face rule of the dual coefficients and of D: exact on straight/flat faces (LINE3
 * and QUAD9: more, for curved faces). */
int mortar_face_exact_order(sk_elem_type type);

#endif
