/* corotational — the host-free kernel of the Hauret–Salomon–Weiss–Wohlmuth co-rotational schemes (seed 001).
 *
 * Pure functions over a body's consistent mass M, Hooke stiffness S and nodal data; no core calls. Equation numbers
 * are the paper's; docs/plugins/corotational.md derives every formula used here.
 *
 *   motion       phi = X_c + R_theta (x + u),   x = X - X_c,   Pi y = e x y                        (2.7)
 *   Tisserand    c . u = 0,   c = M Pi x                                                            (2.8), (4.3)
 *   velocity     s = R^T phi' = u' + theta' Pi r,   r = x + u (Model 1) or x + T(u) (Model 2)      (2.14), (2.28)
 *   step         a = 2/dt, w = theta'^{n+1/2}, s = s^{n+1/2}, u_h = u^{n+1/2}
 *     Model 1    u_h = C_n (s + a u^n - w Pi x),  C_n = (aI + w Pi)^-1                              (Sec. 4.2)
 *                R = M((a + w Pi) s - a s^n) + S u_h + alpha c - f,   R + D lambda = 0             (4.2)
 *                Q = c . u_h = 0,   g = -(S u_h + alpha c) . Pi (x + u_h) = 0                      (4.3), (4.4')
 *     Model 2    u_h = (dt/2) s - (dt/2) w Pi (x + T_h) + u^n,  T_h = C_n (T(s) + a T(u^n))          (4.5)
 *                R = M((a + w Pi) s - a s^n) + (dt/2) S s + S u^n - f,   R + D lambda = 0          (4.1)
 *                g = c . u_h = (dt/2)(c . s - w I_e) + c . u^n = 0                                   (2.8)
 *   contact      Laursen–Chawla in velocities, dual multipliers condensed node-wise (3.5)–(3.8), (5.1)
 *
 * Vectors over the body are node-major, dim entries per node (n = dim * n_nodes). Small matrices are row-major.
 * In 2D the axis is e_z and Pi = [[0, -1], [1, 0]]. */
#ifndef COROT_KERNEL_H
#define COROT_KERNEL_H

#include <stdint.h>

enum { COROT_MAX_BORDER = 6 };
/* Within this factor of the tolerance, a Newton update of w that no longer contracts (|dw_k| > |dw_{k-1}| / 2) is
 * round-off and ends the step (corot_step_solve). */
#define COROT_ROUNDOFF_FACTOR 100.0

typedef enum { COROT_MODEL_1 = 1, COROT_MODEL_2 = 2 } corot_model;

/* ---- node-wise algebra ---------------------------------------------------------------------------------------- */
/* out = Pi v (out may alias v). */
void corot_pi(int dim, const double e[3], const double *v, double *out);
/* Pi as a dim x dim matrix. */
void corot_pi_matrix(int dim, const double e[3], double P[9]);
/* R_theta = I + sin(theta) Pi + (1 - cos(theta)) Pi^2, dim x dim. */
void corot_rotation(int dim, const double e[3], double theta, double R[9]);
/* C_n = (aI + w Pi)^-1 = e e^T / a - (a Pi^2 + w Pi) / (a^2 + w^2) (2D: (aI - w Pi)/(a^2 + w^2)). */
void corot_cn(int dim, const double e[3], double a, double w, double C[9]);
/* out = B v and out = B^T v for a dim x dim B (out must not alias v); C = A B for dim x dim matrices. */
void corot_mul(int dim, const double *B, const double *v, double *out);
void corot_mul_t(int dim, const double *B, const double *v, double *out);
void corot_matmul(int dim, const double *A, const double *B, double *C);
/* a . b over n entries (the one dot product of the plugin). */
double corot_dot(int n, const double *a, const double *b);

/* The node graph of n_cells cells of nen nodes (conn, node indices < n_nodes): CSR rows with sorted columns, the
 * diagonal included. *row_ptr (n_nodes + 1) and *cols are the caller's to free. Returns 0 or -1 (memory). */
int corot_node_graph(int n_nodes, int64_t n_cells, int nen, const int32_t *conn, int64_t **row_ptr, int **cols);

/* ---- the body ---------------------------------------------------------------------------------------------------- */
typedef struct {
  int dim, n_nodes, n;           /* n = dim * n_nodes */
  const int64_t *row_ptr;        /* node graph of M and S (CSR, sorted columns, diagonal present) */
  const int *cols;
  const double *mass;            /* scalar M per graph entry (consistent mass) */
  const double *stiffness;       /* dim x dim block of S per graph entry (small-strain Hooke) */
  double e[3];                   /* unit rotation axis (2D: e_z) */
  double centre[3];              /* X_c, the centre of mass of the reference configuration */
  double mass_total;             /* m = sum of M */
  double inertia;                /* I_e = c . Pi x */
  double *x;                     /* X - X_c (n), owned */
  double *c;                     /* M Pi x (n), owned */
  int64_t *diag;                 /* graph position of (a, a) per node, owned */
} corot_body;

/* Derives X_c, x, c, I_e from M and the reference positions X (n). The graph and value arrays are borrowed and must
 * outlive the body. Returns 0, or -1 for a bad graph (missing diagonal), a zero mass or a zero inertia. */
int corot_body_init(corot_body *body, int dim, int n_nodes, const int64_t *row_ptr, const int *cols,
                    const double *mass, const double *stiffness, const double *X, const double e[3]);
void corot_body_free(corot_body *body);
void corot_mass_apply(const corot_body *body, const double *v, double *out);      /* out = M v */
void corot_stiffness_apply(const corot_body *body, const double *v, double *out); /* out = S (v - T(v)) = S v */
/* T(v) = (1^T M v) / m, the mass-weighted mean (2.10). */
void corot_mean(const corot_body *body, const double *v, double T[3]);
/* E = 1/2 (s . M s + u . S u) (Lemma 2.1); J = s . M Pi r with r = x + u (Model 1) or x + T(u) (Model 2).
 * work: n scratch entries. */
double corot_energy(const corot_body *body, const double *u, const double *s, double *work);
/* Its kinetic part 1/2 s . M s and strain part 1/2 u . S u. */
void corot_energy_parts(const corot_body *body, const double *u, const double *s, double *work, double *kinetic,
                        double *strain);
double corot_angular_momentum(const corot_body *body, corot_model model, const double *u, const double *s,
                              double *work);

/* ---- linear systems and the solver interface ---------------------------------------------------------------------- */
/* [P B_col; B_row^T 0] of size n + n_border: P in the body's node-block pattern (dim x dim per graph entry), the
 * border columns and rows dense (n each), the corner zero. */
typedef struct {
  int dim, n_nodes, n, n_border;
  const int64_t *row_ptr;
  const int *cols;
  double *blocks;
  double *border_col[COROT_MAX_BORDER];
  double *border_row[COROT_MAX_BORDER];
} corot_system;

/* A factorisation that can be reused: solve() may be called any number of times after one factor(). Both return
 * 0 on success. The host's linear solver in the plugin, a dense LU in the unit tests. */
typedef struct {
  void *ctx;
  int (*factor)(void *ctx, const corot_system *system);
  int (*solve)(void *ctx, const double *rhs, double *solution);
} corot_solver;

int corot_system_alloc(corot_system *system, const corot_body *body, int n_border);
void corot_system_free(corot_system *system);
/* out = [P B_col; B_row^T 0] y (n + n_border entries). */
void corot_system_apply(const corot_system *system, const double *y, double *out);

/* ---- contact against rigid planes (contact.c) ---------------------------------------------------------------------- */
typedef struct {
  double point[3];
  double normal[3];              /* unit world normal out of the obstacle, towards the body */
  double mu;                     /* Coulomb coefficient against this plane (0: frictionless) */
} corot_plane;

enum { COROT_MAX_PLANES = 32 };

typedef enum { COROT_INACTIVE = 0, COROT_STICK = 1, COROT_SLIP = 2 } corot_set;

typedef struct {
  int n;                         /* slave nodes */
  int *node;                     /* body node of each (owned copy) */
  double *weight;                /* D_pp = integral of phi_p over the contact surface (owned copy) */
  int n_planes;
  corot_plane *planes;           /* owned copy */
  uint32_t *mask;                /* per node: bit k set when the node may touch plane k (all by default) */
  double c_n, c_t;               /* NCP constants relative to the node scale kappa_p / D_pp */
  double direction_tol;          /* 3D slip direction change that counts as a set change */
  /* per step */
  int *plane;                    /* closest plane at t_n */
  double *gap;                   /* world gap at t_n (3.5) */
  unsigned char *candidate;      /* gap <= 0 */
  double *frame;                 /* 9 per node: rows nu, tau_1, tau_2 in the co-rotated frame (dim x dim used) */
  double *kappa;                 /* row scale: norm of the node's diagonal block of A at the step's predictor */
  unsigned char *set, *set_next, *set_committed;
  double *dir, *dir_next, *dir_committed; /* slip direction in the tau basis (2 per node) */
  double *lambda;                /* co-rotated multiplier of the last solve (3 per node) */
} corot_contact;

/* Copies the slave nodes, weights and planes (at most COROT_MAX_PLANES); allocates the per-step arrays. Returns 0 or
 * -1 (bad weight, normal or mu). */
int corot_contact_init(corot_contact *contact, int dim, int n, const int *node, const double *weight,
                       int n_planes, const corot_plane *planes, double c_n, double c_t);
/* The Coulomb coefficient of node p against its current plane. */
double corot_contact_mu(const corot_contact *contact, int p);
void corot_contact_free(corot_contact *contact);

/* ---- the step (kernel.c, step.c) --------------------------------------------------------------------------------------- */
typedef struct {
  double theta;                  /* theta^n */
  double w;                      /* theta'^{n-1/2} of the last step (theta'_0 before the first): the predictor */
  double *u, *s;                 /* u^n, s^n (n each, co-rotated) */
} corot_state;

int corot_state_alloc(corot_state *state, const corot_body *body);
void corot_state_free(corot_state *state);

typedef struct {
  corot_model model;
  const corot_body *body;
  corot_contact *contact;        /* NULL: free flight */
  /* step data (corot_step_begin) */
  const corot_state *state_n;
  const double *f_world;         /* world loads at t^{n+1/2} (n), or NULL */
  double dt, a;
  /* the iterate */
  double w;                      /* current theta'^{n+1/2} */
  double C[9];                   /* C_n(w) */
  double Rmid[9];                /* R_{theta^{n+1/2}} */
  double *f;                     /* co-rotated loads f (n) */
  double *u_h, *r_h, *Su_h;      /* u^{n+1/2}, its lever arm, S u_h (n each) */
  double T_h[3];                 /* T(u_h), the translation inside u_h */
  double *R;                     /* momentum residual without contact (4.2)/(4.1) at the last solution (n) */
  double *work, *work2;          /* n each */
  double energy_n;               /* E^n */
  corot_system system;           /* P(w) of (5.1), bordered by alpha (Model 1) */
  double *rhs;                   /* b(w) */
  double *y, *dy;                /* (s, alpha) and d(s, alpha)/dw */
  double g, dg, g_ref;           /* rotation equation, its derivative, its scale */
  double omega_ref;              /* the body's rotation-rate scale (corot_omega_ref) */
  int set_changes;               /* set changes proposed by the last evaluation */
  int iterations;                /* factorisations in this step */
} corot_step;

/* Row scale kappa of a node: the Frobenius norm over sqrt(dim) of its diagonal block of A (Sec. 4.2) at rate w. */
double corot_row_scale(const corot_body *body, corot_model model, double dt, double w, int node);

int corot_step_init(corot_step *step, corot_model model, const corot_body *body, corot_contact *contact);
void corot_step_free(corot_step *step);
/* Starts a step from state_n over dt with world loads f_world (n, at t^{n+1/2}; NULL for none): w = state_n->w,
 * the contact gaps, candidates and frames at t_n, the sets from the committed ones (contact.c). */
void corot_step_begin(corot_step *step, const corot_state *state_n, double dt, const double *f_world);
/* P(w) and b(w) at step->w with the current sets (5.1). */
void corot_step_assemble(corot_step *step);
/* F = P y - b (the residual of the linear step system, for a Newton driver). */
void corot_step_residual(corot_step *step, const double *y, double *F);
/* From a solution y of P y = b: u_h, r_h, R, lambda, g(w), and the proposed sets (set_next); returns the number of
 * nodes whose set (or slip direction) would change. */
int corot_step_evaluate(corot_step *step, const double *y);
/* rhs = -d(P y - b)/dw at fixed y and sets (for the derivative solve with the same factorisation). */
void corot_step_derivative_rhs(corot_step *step, const double *y, double *rhs);
/* g'(w) from y and dy = dy/dw. */
double corot_step_dg(corot_step *step, const double *y, const double *dy);
/* Adopts the proposed sets. */
void corot_step_apply_sets(corot_step *step);
/* |g| <= tol * g_ref. */
int corot_step_rotation_converged(const corot_step *step, double tol);
/* The host-free step loop (Sec. 5): factorise, solve, evaluate; stop when the sets stay and g is converged; else
 * Newton on w with the derivative solve; also stop when g is within COROT_ROUNDOFF_FACTOR * tol * g_ref and the
 * Newton updates stopped contracting (round-off). Returns 0, 1 when max_iterations were used up, -1 on a solver
 * failure. */
int corot_step_solve(corot_step *step, const corot_solver *solver, int max_iterations, double tol);
/* Writes state_next from the converged step: s^{n+1} = 2s - s^n, u^{n+1} = 2u_h - u^n, theta^{n+1}, w; commits the
 * sets. Returns the friction work Delta t sum_p D_pp s_tau . lambda_tau (>= 0) of the step. */
double corot_step_commit(corot_step *step, corot_state *state_next);

/* ---- contact per step (contact.c) ---------------------------------------------------------------------------------- */
/* World gap, closest plane, candidate flag and co-rotated frame of every slave node at t_n, for the frozen angle
 * theta_star (the predicted midpoint angle); sets start from the committed ones on candidates. */
void corot_contact_begin_step(corot_contact *contact, const corot_body *body, const corot_state *state_n,
                              double theta_star);
/* Row transformation of node p for the current set: lin[k][0..dim) is the combination of the node's momentum
 * rows that row k holds, or, when kinematic[k], row k is kappa * (frame row k) . s_p. */
void corot_contact_rows(const corot_contact *contact, int dim, int p, double lin[3][3], int kinematic[3]);
/* lambda from R (-R_p / D_pp), the NCP update into set_next/dir_next; returns the number of changes. */
int corot_contact_update(corot_contact *contact, int dim, const double *R, const double *s);
/* The NCP update from contact->lambda and the velocities s (body vector): proposes set_next/dir_next, returns the
 * number of changes. */
int corot_contact_propose(corot_contact *contact, int dim, const double *s);
/* Adopts the proposed sets and slip directions. */
void corot_contact_apply(corot_contact *contact);
/* Node-wise complementarity of the last solution: the largest of |lambda_nu s_nu|, max(0, -lambda_nu),
 * max(0, s_nu) over candidates and max(0, |lambda_tau| - mu lambda_nu), each relative to the given scales. */
typedef struct {
  double product, negative_pressure, penetration_rate, friction_excess;
  int active, stick, slip;
} corot_complementarity;
void corot_contact_check(const corot_contact *contact, int dim, const double *s, corot_complementarity *out);

/* ---- initial state (step.c) ------------------------------------------------------------------------------------------ */
/* Steady spin theta'_0 = omega about e with world translation velocity V0 (Sec. 6.1): u0, s0 (n each). Model 1
 * solves (S + w0^2 M Pi^2) u0 = -w0^2 M Pi^2 x, Model 2 S u0 = -w0^2 M Pi^2 x, both with the rigid modes fixed
 * (Z^T M u0 = 0), by projected conjugate gradients to the relative residual tol. Returns 0, 1 when the iterations
 * ran out, -1 when the operator is not positive (w0 at an elastic frequency) or out of memory. */
int corot_initial_state(const corot_body *body, corot_model model, double omega, const double V0[3], double tol,
                        double *u0, double *s0, int *iterations);

/* World positions q = X_c + R_theta (x + u) and velocities v = R_theta s (n each), for output and invariants. */
void corot_world_state(const corot_body *body, double theta, const double *u, const double *s, double *q, double *v);

/* ---- the same step posed in world positions (world.c): the unknowns of the plugin ABI -------------------------------- *
 * The host's unknowns for a body are its world positions x at t^{n+1}; rows must stay world force balances so that
 * other terms can add to them. With R_1 = R(theta^n + dt w), R_m = R(theta^{n+1/2}) node by node:
 *   u^{n+1} = R_1^T (x - X_c) - x_ref,  u_h = (u^{n+1} + u^n)/2,
 *   s = (aI + w Pi) u_h - a u^n + w Pi x_ref (Model 1, (3.4)),  s = a (u_h - u^n) + w Pi (x_ref + tau) (Model 2)
 * and the unknowns y = [x (n) | border: alpha (Model 1) or tau = T(u_h) (Model 2, dim) | lambda (dim per contact
 * node, co-rotated)], with the rows
 *   body      R_m [M((a + w Pi) s - a s^n) + S u_h + alpha c - f + D lambda]            (4.2)/(4.1) rotated
 *   border    a c . u_h (Model 1, (4.3))  or  m tau - 1^T M u_h (Model 2)
 *   lambda    inactive: D_pp lambda_p;  stick: kappa nu.s_p, kappa tau_k.s_p;  slip: kappa nu.s_p,
 *             D_pp (tau_k - mu d_k nu).lambda_p                                              (5.1) with lambda kept
 * and the rotation equation g(w) (4.4')/(2.8), which the plugin eliminates: w is updated from a second solve with
 * the same matrix (the derivative column dF/dw), as the paper's outer Newton (Sec. 5.3). For fixed w and sets the
 * rows are linear in y; their solution is the solution of the s-form above. */
typedef struct {
  corot_model model;
  const corot_body *body;
  corot_contact *contact;        /* NULL: free flight */
  int n_border, n_lambda, N;     /* N = n + n_border + n_lambda */
  const corot_state *state_n;
  const double *f_world;
  double dt, a, w;
  double R1[9], Rm[9], P[9];
  double energy_n;
  double *f, *u1, *u_h, *s, *Su_h, *Rin, *work, *work2; /* n each */
  double T_h[3];
} corot_world;

/* d(rows)/dy in blocks: the body rows over the node graph, the border, and per contact node. */
typedef struct {
  double *blocks;                /* d body_a / d x_b per graph entry (dim x dim) */
  double *col[3];                /* d body / d border_j (n each) */
  double *row[3];                /* d border_i / d x (n each) */
  double corner[9];              /* d border_i / d border_j, row-major n_border x n_border */
  double *body_lambda;           /* per contact node p: d body_{node p} / d lambda_p (dim x dim) */
  double *lambda_x;              /* per p: d lambda-rows_p / d x_{node p} (dim x dim) */
  double *lambda_lambda;         /* per p: d lambda-rows_p / d lambda_p (dim x dim) */
  double *lambda_border;         /* per p: d lambda-rows_p / d border (dim x 3) */
} corot_world_jacobian;

int corot_world_init(corot_world *cw, corot_model model, const corot_body *body, corot_contact *contact);
void corot_world_free(corot_world *cw);
int corot_world_jacobian_alloc(corot_world_jacobian *J, const corot_world *cw);
void corot_world_jacobian_free(corot_world_jacobian *J);
/* Starts a step like corot_step_begin (w = state_n->w, gaps, frames, row scales). */
void corot_world_begin(corot_world *cw, const corot_state *state_n, double dt, const double *f_world);
/* Sets the rotation rate: R_1, R_m and the co-rotated loads. */
void corot_world_set_w(corot_world *cw, double w);
/* u^{n+1}, u_h, s, T(u_h) from y. */
void corot_world_kinematics(corot_world *cw, const double *y);
/* F (N entries) and g at y (after corot_world_kinematics(y)). */
void corot_world_residual(corot_world *cw, const double *y, double *F, double *g);
/* dF/dy at y. */
void corot_world_jacobian_eval(corot_world *cw, const double *y, corot_world_jacobian *J);
/* dF/dw (N entries) and the gradient of g: dg/dy (N entries, zero on lambda) and dg/dw, at fixed y. */
void corot_world_dw(corot_world *cw, const double *y, double *dF, double *dg_dy, double *dg_dw);
/* The scale of g (as corot_step) and g's row scale in F: 1/L (Model 1, a torque) or a^2/L (Model 2). */
double corot_world_g_ref(const corot_world *cw);
/* The body's rotation-rate scale max(|w|, sqrt(2 E / I_e)), E the larger of E^n and the kinetic energy the step's
 * world loads f_world (n, or NULL) give nodes at rest, 1/2 dt^2 sum |f_a|^2 / (m / nodes). */
double corot_omega_ref(const corot_body *body, double w, double energy_n, const double *f_world, double dt);
/* The predictor: positions y[0..n) at t from s = s^n and w = state_n->w, border values (alpha = 0, tau), lambda from
 * the committed multipliers (contact->lambda). */
void corot_world_predict(corot_world *cw, double *y);
/* lambda of y into contact->lambda and the proposed sets; returns the number of changes. */
int corot_world_propose_sets(corot_world *cw, const double *y);
/* The converged step: state_next (u^{n+1}, s^{n+1}, theta^{n+1}, w), committed sets; returns the friction work. */
double corot_world_commit(corot_world *cw, const double *y, corot_state *state_next);
/* The terms of the discrete angular-momentum balance of the step at y (after corot_world_kinematics(y)):
 *   J^{n+1} - J^n = impulse + defect,   impulse = dt (f - D lambda) . Pi r_h   (Lemma 2.2 discrete, Sec. 3.2)
 * with r_h = x + u_h (Model 1, defect 0) or x + T(u_h) (Model 2, whose lever arm leaves the defect
 * -w c . Pi (u^{n+1} - u^n), c = M Pi x: Sec. 2.4's theta' m(Pi x, Pi(u' - T(u'))) over the step). */
void corot_world_momentum_balance(const corot_world *cw, const double *y, double *impulse, double *defect);

#endif
