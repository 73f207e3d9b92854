/* corotational kernel: node-wise algebra (R_theta, C_n and their derivatives by finite differences), the body's
 * operators (rigid modes cost no strain), the step system's w-derivative and the total g'(w) against finite
 * differences of solved systems (Model 1 and 2, 2D and 3D, with inactive, stick and slip nodes), and the two forms
 * of the rotation equation (4.4) = (4.4'). Dense LU on small meshes. */
#include "corot_test_support.h"
#include "sk_test.h"

static const double axis_z[3] = {0, 0, 1};

static void mat_apply(int dim, const double *A, const double *v, double *out) { corot_mul(dim, A, v, out); }

static void test_algebra(int dim) {
  const double e3[3] = {0.3, -0.4, sqrt(1 - 0.25)}; /* a unit axis off the coordinates */
  const double *e = dim == 2 ? axis_z : e3;
  double P[9], v[3], pv[3], Pv[3];
  corot_pi_matrix(dim, e, P);
  for (int i = 0; i < 3; ++i) v[i] = corot_rand();
  corot_pi(dim, e, v, pv);
  mat_apply(dim, P, v, Pv);
  for (int i = 0; i < dim; ++i) SK_CHECK_CLOSE(pv[i], Pv[i], 1e-15);
  /* R orthogonal, dR/dtheta = Pi R */
  const double theta = 0.7, h = 1e-6;
  double R[9], Rp[9], Rm[9];
  corot_rotation(dim, e, theta, R);
  corot_rotation(dim, e, theta + h, Rp);
  corot_rotation(dim, e, theta - h, Rm);
  for (int i = 0; i < dim; ++i)
    for (int j = 0; j < dim; ++j) {
      double rrt = 0.0, pr = 0.0;
      for (int k = 0; k < dim; ++k) {
        rrt += R[i * dim + k] * R[j * dim + k];
        pr += P[i * dim + k] * R[k * dim + j];
      }
      SK_CHECK_CLOSE(rrt, (double)(i == j), 1e-15);
      SK_CHECK_CLOSE((Rp[i * dim + j] - Rm[i * dim + j]) / (2 * h), pr, 1e-9);
    }
  /* C_n (aI + w Pi) = I and dC_n/dw = -C_n Pi C_n */
  const double a = 2.0 / 0.01, w = 37.0;
  double C[9], Cp[9], Cm[9], CP[9], CPC[9];
  corot_cn(dim, e, a, w, C);
  corot_cn(dim, e, a, w + h * 100, Cp);
  corot_cn(dim, e, a, w - h * 100, Cm);
  for (int i = 0; i < dim; ++i)
    for (int j = 0; j < dim; ++j) {
      double prod = 0.0, cp = 0.0;
      for (int k = 0; k < dim; ++k) {
        prod += C[i * dim + k] * ((k == j) * a + w * P[k * dim + j]);
        cp += C[i * dim + k] * P[k * dim + j];
      }
      CP[i * dim + j] = cp;
      SK_CHECK_CLOSE(prod, (double)(i == j), 1e-14);
    }
  for (int i = 0; i < dim; ++i)
    for (int j = 0; j < dim; ++j) {
      double s = 0.0;
      for (int k = 0; k < dim; ++k) s += CP[i * dim + k] * C[k * dim + j];
      CPC[i * dim + j] = s;
      SK_CHECK(fabs((Cp[i * dim + j] - Cm[i * dim + j]) / (2 * h * 100) + CPC[i * dim + j]) <= 1e-9 / a);
    }
}

/* S Pi x = 0 and S t = 0: rigid motion costs no strain in the co-rotated frame. */
static void test_rigid_modes(test_body *tb) {
  const corot_body *b = &tb->body;
  double *t = calloc((size_t)b->n, sizeof(double)), *St = calloc((size_t)b->n, sizeof(double));
  double *px = calloc((size_t)b->n, sizeof(double));
  for (int a = 0; a < b->n_nodes; ++a) corot_pi(b->dim, b->e, b->x + a * b->dim, px + a * b->dim);
  double S_norm = 0.0;
  for (int64_t k = 0; k < b->row_ptr[b->n_nodes] * b->dim * b->dim; ++k) S_norm = fmax(S_norm, fabs(b->stiffness[k]));
  corot_stiffness_apply(b, px, St);
  SK_CHECK(vec_norm(b->n, St) <= 1e-13 * S_norm * vec_norm(b->n, px));
  for (int a = 0; a < b->n_nodes; ++a)
    for (int i = 0; i < b->dim; ++i) t[a * b->dim + i] = i == 0 ? 1.0 : 0.5;
  corot_stiffness_apply(b, t, St);
  SK_CHECK(vec_norm(b->n, St) <= 1e-13 * S_norm * vec_norm(b->n, t));
  /* x is centred: T(x) = 0 */
  double T[3];
  corot_mean(b, b->x, T);
  for (int i = 0; i < b->dim; ++i) SK_CHECK(fabs(T[i]) <= 1e-14 * sqrt(b->inertia / b->mass_total));
  free(t);
  free(St);
  free(px);
}

/* A step with a random state, loads and a fixed mix of sets on the contact nodes. */
typedef struct {
  corot_state state;
  corot_contact contact;
  corot_step step;
  double *f_world;
} step_fixture;

static void fixture_init(step_fixture *fx, test_body *tb, corot_model model, double mu) {
  const corot_body *b = &tb->body;
  corot_state_alloc(&fx->state, b);
  fx->f_world = calloc((size_t)b->n, sizeof(double));
  random_state(b, &fx->state, fx->f_world);
  corot_plane plane = {.point = {0, 0, 0}, .normal = {0, 1, 0}, .mu = mu};
  /* a plane through the centre: half the contact nodes are candidates */
  corot_contact_init(&fx->contact, b->dim, tb->n_contact, tb->contact_nodes, tb->contact_weight, 1, &plane, 1.0, 1.0);
  corot_step_init(&fx->step, model, b, &fx->contact);
  corot_step_begin(&fx->step, &fx->state, 0.01, fx->f_world);
  int k = 0;
  for (int p = 0; p < fx->contact.n; ++p) {
    if (!fx->contact.candidate[p]) continue;
    fx->contact.set[p] = (unsigned char)(mu > 0.0 ? k % 3 : 2 * (k % 2)); /* inactive, stick, slip */
    fx->contact.dir[2 * p] = (k % 2) ? 1.0 : -1.0;
    if (b->dim == 3) {
      fx->contact.dir[2 * p] = 0.6;
      fx->contact.dir[2 * p + 1] = (k % 2) ? 0.8 : -0.8;
    }
    ++k;
  }
  SK_CHECK(k >= 3);
}

static void fixture_free(step_fixture *fx) {
  corot_step_free(&fx->step);
  corot_contact_free(&fx->contact);
  corot_state_free(&fx->state);
  free(fx->f_world);
}

/* -d(P y - b)/dw against central differences of the assembled residual, at a random y. */
static void test_residual_derivative(test_body *tb, corot_model model, double mu) {
  step_fixture fx;
  fixture_init(&fx, tb, model, mu);
  corot_step *st = &fx.step;
  const int N = st->system.n + st->system.n_border;
  double *y = calloc((size_t)N, sizeof(double)), *Fp = calloc((size_t)N, sizeof(double));
  double *Fm = calloc((size_t)N, sizeof(double)), *d = calloc((size_t)N, sizeof(double));
  for (int i = 0; i < N; ++i) y[i] = corot_rand();
  const double w = st->w, h = 1e-5 * fabs(w);
  st->w = w + h;
  corot_step_assemble(st);
  corot_step_residual(st, y, Fp);
  st->w = w - h;
  corot_step_assemble(st);
  corot_step_residual(st, y, Fm);
  st->w = w;
  corot_step_assemble(st);
  corot_step_evaluate(st, y);
  corot_step_derivative_rhs(st, y, d);
  double err = 0.0, size = 0.0;
  for (int i = 0; i < N; ++i) {
    const double fd = -(Fp[i] - Fm[i]) / (2 * h);
    err = fmax(err, fabs(fd - d[i]));
    size = fmax(size, fabs(d[i]));
  }
  printf("  dR/dw model %d dim %d mu %g: max |fd - exact| = %.2e of %.2e\n", model, tb->dim, mu, err, size);
  SK_CHECK(size > 0.0 && err <= 1e-8 * size); /* measured <= 4e-10: central-difference truncation */
  free(y);
  free(Fp);
  free(Fm);
  free(d);
  fixture_free(&fx);
}

/* g at w from a fresh solve (sets fixed). */
static double solved_g(corot_step *st, const corot_solver *solver, double w) {
  st->w = w;
  corot_step_assemble(st);
  solver->factor(solver->ctx, &st->system);
  solver->solve(solver->ctx, st->rhs, st->y);
  corot_step_evaluate(st, st->y);
  return st->g;
}

/* The total g'(w) of solved systems (the derivative solve reusing the factorisation) against central differences;
 * and (Model 1) the paper's form (4.4) of g against the kernel's (4.4'). */
static void test_total_derivative(test_body *tb, corot_model model, double mu) {
  step_fixture fx;
  fixture_init(&fx, tb, model, mu);
  corot_step *st = &fx.step;
  dense_lu lu = {0};
  corot_solver solver = dense_solver(&lu);
  const corot_body *b = &tb->body;
  const double w = st->w, h = 1e-5 * fabs(w);
  const double gp = solved_g(st, &solver, w + h), gm = solved_g(st, &solver, w - h);
  const double g = solved_g(st, &solver, w);
  corot_step_derivative_rhs(st, st->y, st->rhs);
  solver.solve(solver.ctx, st->rhs, st->dy);
  const double dg = corot_step_dg(st, st->y, st->dy), fd = (gp - gm) / (2 * h);
  printf("  g'(w) model %d dim %d mu %g: exact %.12e fd %.12e (g %.3e, g_ref %.3e)\n", model, tb->dim, mu, dg, fd, g,
         st->g_ref);
  SK_CHECK(fabs(dg - fd) <= 1e-9 * fabs(fd)); /* measured <= 3e-11 relative */
  if (model == COROT_MODEL_1) {
    /* (4.4): (M(a(s - s^n) + w Pi s) + D lambda - f) . Pi r_h, D lambda = -R on the contact nodes, 0 elsewhere */
    const int n = b->n, dim = b->dim;
    double *t = calloc((size_t)n, sizeof(double)), *Mt = calloc((size_t)n, sizeof(double));
    for (int a = 0; a < b->n_nodes; ++a) {
      double ps[3];
      corot_pi(dim, b->e, st->y + a * dim, ps);
      for (int i = 0; i < dim; ++i) t[a * dim + i] = st->a * (st->y[a * dim + i] - fx.state.s[a * dim + i]) + w * ps[i];
    }
    corot_mass_apply(b, t, Mt);
    for (int i = 0; i < n; ++i) Mt[i] -= st->f[i];
    for (int p = 0; p < fx.contact.n; ++p)
      for (int i = 0; i < dim; ++i) Mt[fx.contact.node[p] * dim + i] -= st->R[fx.contact.node[p] * dim + i];
    double paper = 0.0, scale = 0.0;
    for (int a = 0; a < b->n_nodes; ++a) {
      double pr[3];
      corot_pi(dim, b->e, st->r_h + a * dim, pr);
      for (int i = 0; i < dim; ++i) {
        paper += Mt[a * dim + i] * pr[i];
        scale += fabs(Mt[a * dim + i] * pr[i]);
      }
    }
    printf("  (4.4) %.15e  (4.4') %.15e  (sum of |terms| %.3e)\n", paper, g, scale);
    SK_CHECK(fabs(paper - g) <= 1e-11 * scale);
    free(t);
    free(Mt);
  }
  dense_free(&lu);
  fixture_free(&fx);
}

int main(void) {
  test_algebra(2);
  test_algebra(3);
  test_body disk, cube;
  SK_CHECK(load_unit_disk(&disk) == 0);
  SK_CHECK(load_tilted_cube(&cube) == 0);
  if (sk_test_failures) return sk_test_finish("test_corot_kernel");
  test_rigid_modes(&disk);
  test_rigid_modes(&cube);
  test_body *bodies[2] = {&disk, &cube};
  for (int k = 0; k < 2; ++k) {
    for (int model = 1; model <= 2; ++model)
      for (int f = 0; f < 2; ++f) {
        test_residual_derivative(bodies[k], (corot_model)model, f ? 0.3 : 0.0);
        test_total_derivative(bodies[k], (corot_model)model, f ? 0.3 : 0.0);
      }
  }
  test_body_free(&disk);
  test_body_free(&cube);
  return sk_test_finish("test_corot_kernel");
}
