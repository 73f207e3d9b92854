/* corotational, the step in world positions (world.c, the unknowns of the plugin ABI): the Jacobian, dF/dw, dg/dw
 * and dg/dy against central differences (Model 1 and 2, 2D and 3D, inactive, stick and slip nodes), and a Newton
 * loop shaped like the host's (sets updated at every new point, w eliminated by the bordered formula with a second
 * solve of the same matrix) reproducing the s-form's steps (kernel.c) through an impact to round-off. */
#include "corot_test_support.h"
#include "sk_test.h"

/* The dense N x N matrix of the world rows. */
static void world_dense(const corot_world *cw, const corot_world_jacobian *J, double *A) {
  const corot_body *b = cw->body;
  const int dim = b->dim, dd = dim * dim, n = b->n, N = cw->N, nb = cw->n_border;
  memset(A, 0, sizeof(double) * (size_t)N * (size_t)N);
  for (int a = 0; a < b->n_nodes; ++a)
    for (int64_t k = b->row_ptr[a]; k < b->row_ptr[a + 1]; ++k)
      for (int i = 0; i < dim; ++i)
        for (int j = 0; j < dim; ++j) A[(size_t)(a * dim + i) * N + b->cols[k] * dim + j] = J->blocks[k * dd + i * dim + j];
  for (int j = 0; j < nb; ++j)
    for (int i = 0; i < n; ++i) {
      A[(size_t)i * N + n + j] = J->col[j][i];
      A[(size_t)(n + j) * N + i] = J->row[j][i];
    }
  for (int i = 0; i < nb; ++i)
    for (int j = 0; j < nb; ++j) A[(size_t)(n + i) * N + n + j] = J->corner[i * nb + j];
  const corot_contact *c = cw->contact;
  for (int p = 0; c && p < c->n; ++p) {
    const int node = c->node[p], lr = n + nb + p * dim;
    for (int i = 0; i < dim; ++i) {
      for (int j = 0; j < dim; ++j) {
        A[(size_t)(node * dim + i) * N + lr + j] = J->body_lambda[p * dd + i * dim + j];
        A[(size_t)(lr + i) * N + node * dim + j] = J->lambda_x[p * dd + i * dim + j];
        A[(size_t)(lr + i) * N + lr + j] = J->lambda_lambda[p * dd + i * dim + j];
      }
      for (int j = 0; j < nb; ++j) A[(size_t)(lr + i) * N + n + j] = J->lambda_border[p * 9 + i * 3 + j];
    }
  }
}

typedef struct {
  corot_state state;
  corot_contact contact;
  corot_world cw;
  corot_world_jacobian J;
  double *f_world, *y;
} world_fixture;

static void fixture_init(world_fixture *fx, test_body *tb, corot_model model, double mu) {
  const corot_body *b = &tb->body;
  corot_state_alloc(&fx->state, b);
  fx->f_world = calloc((size_t)b->n, sizeof(double));
  random_state(b, &fx->state, fx->f_world);
  corot_plane plane = {.point = {0, 0, 0}, .normal = {0, 1, 0}, .mu = mu};
  corot_contact_init(&fx->contact, b->dim, tb->n_contact, tb->contact_nodes, tb->contact_weight, 1, &plane, 1.0, 1.0);
  corot_world_init(&fx->cw, model, b, &fx->contact);
  corot_world_jacobian_alloc(&fx->J, &fx->cw);
  corot_world_begin(&fx->cw, &fx->state, 0.01, fx->f_world);
  int k = 0;
  for (int p = 0; p < fx->contact.n; ++p) {
    if (!fx->contact.candidate[p]) continue;
    fx->contact.set[p] = (unsigned char)(mu > 0.0 ? k % 3 : 2 * (k % 2));
    fx->contact.dir[2 * p] = b->dim == 3 ? 0.6 : ((k % 2) ? 1.0 : -1.0);
    fx->contact.dir[2 * p + 1] = b->dim == 3 ? ((k % 2) ? 0.8 : -0.8) : 0.0;
    ++k;
  }
  fx->y = calloc((size_t)fx->cw.N, sizeof(double));
  const double L = sqrt(b->inertia / b->mass_total);
  corot_world_predict(&fx->cw, fx->y);
  for (int i = 0; i < fx->cw.N; ++i) fx->y[i] += (i < b->n ? 0.01 * L : 1.0) * corot_rand();
}

static void fixture_free(world_fixture *fx) {
  corot_world_jacobian_free(&fx->J);
  corot_world_free(&fx->cw);
  corot_contact_free(&fx->contact);
  corot_state_free(&fx->state);
  free(fx->f_world);
  free(fx->y);
}

static void test_derivatives(test_body *tb, corot_model model, double mu) {
  world_fixture fx;
  fixture_init(&fx, tb, model, mu);
  corot_world *cw = &fx.cw;
  const int N = cw->N;
  double *A = malloc(sizeof(double) * (size_t)N * (size_t)N), *Fp = calloc((size_t)N, sizeof(double));
  double *Fm = calloc((size_t)N, sizeof(double)), *y = fx.y, *dF = calloc((size_t)N, sizeof(double));
  double *dgy = calloc((size_t)N, sizeof(double));
  corot_world_jacobian_eval(cw, y, &fx.J);
  world_dense(cw, &fx.J, A);
  const double L = sqrt(tb->body.inertia / tb->body.mass_total);
  double err = 0.0, size = 0.0, gerr = 0.0, gsize = 0.0;
  for (int j = 0; j < N; ++j) {
    const double h = (j < tb->body.n ? 1e-6 * L : 1e-6) * fmax(1.0, fabs(y[j]));
    const double keep = y[j];
    double gp, gm;
    y[j] = keep + h;
    corot_world_residual(cw, y, Fp, &gp);
    y[j] = keep - h;
    corot_world_residual(cw, y, Fm, &gm);
    y[j] = keep;
    for (int i = 0; i < N; ++i) {
      err = fmax(err, fabs((Fp[i] - Fm[i]) / (2 * h) - A[(size_t)i * N + j]));
      size = fmax(size, fabs(A[(size_t)i * N + j]));
    }
    dgy[j] = (gp - gm) / (2 * h);
  }
  double dgw;
  corot_world_dw(cw, y, dF, Fp, &dgw);
  for (int j = 0; j < N; ++j) {
    gerr = fmax(gerr, fabs(Fp[j] - dgy[j]));
    gsize = fmax(gsize, fabs(dgy[j]));
  }
  printf("  world J model %d dim %d mu %g: max |fd - exact| %.2e of %.2e; dg/dy %.2e of %.2e\n", model, tb->dim, mu,
         err, size, gerr, gsize);
  SK_CHECK(err <= 1e-8 * size); /* measured <= 2e-10 */
  SK_CHECK(gerr <= 1e-8 * gsize); /* measured <= 5e-9 */
  /* d/dw at fixed y */
  const double w = cw->w, h = 1e-4 * fabs(w); /* truncation and round-off balance here (measured) */
  double gp, gm, werr = 0.0, wsize = 0.0;
  corot_world_set_w(cw, w + h);
  corot_world_residual(cw, y, Fp, &gp);
  corot_world_set_w(cw, w - h);
  corot_world_residual(cw, y, Fm, &gm);
  corot_world_set_w(cw, w);
  for (int i = 0; i < N; ++i) {
    werr = fmax(werr, fabs((Fp[i] - Fm[i]) / (2 * h) - dF[i]));
    wsize = fmax(wsize, fabs(dF[i]));
  }
  const double fdg = (gp - gm) / (2 * h);
  printf("  world dF/dw: max |fd - exact| %.2e of %.2e; dg/dw %.10e fd %.10e\n", werr, wsize, dgw, fdg);
  SK_CHECK(werr <= 1e-8 * wsize); /* measured <= 5e-10 relative */
  SK_CHECK(fabs(dgw - fdg) <= 1e-7 * fabs(fdg)); /* measured <= 7e-9 */
  free(A);
  free(Fp);
  free(Fm);
  free(dF);
  free(dgy);
  fixture_free(&fx);
}

/* Dense solve of A x = b (A copied). */
static void dense_solve_copy(int N, const double *A, const double *b, double *x) {
  double *M = malloc(sizeof(double) * (size_t)N * (size_t)N);
  int *piv = malloc(sizeof(int) * (size_t)N);
  memcpy(M, A, sizeof(double) * (size_t)N * (size_t)N);
  memcpy(x, b, sizeof(double) * (size_t)N);
  for (int k = 0; k < N; ++k) {
    int p = k;
    for (int i = k + 1; i < N; ++i)
      if (fabs(M[(size_t)i * N + k]) > fabs(M[(size_t)p * N + k])) p = i;
    piv[k] = p;
    if (p != k) {
      for (int j = 0; j < N; ++j) {
        double t = M[(size_t)k * N + j];
        M[(size_t)k * N + j] = M[(size_t)p * N + j];
        M[(size_t)p * N + j] = t;
      }
      double t = x[k];
      x[k] = x[p];
      x[p] = t;
    }
    for (int i = k + 1; i < N; ++i) {
      const double l = M[(size_t)i * N + k] / M[(size_t)k * N + k];
      if (l == 0.0) continue;
      for (int j = k + 1; j < N; ++j) M[(size_t)i * N + j] -= l * M[(size_t)k * N + j];
      x[i] -= l * x[k];
    }
  }
  for (int i = N - 1; i >= 0; --i) {
    double sum = x[i];
    for (int j = i + 1; j < N; ++j) sum -= M[(size_t)i * N + j] * x[j];
    x[i] = sum / M[(size_t)i * N + i];
  }
  free(M);
  free(piv);
}

/* The host-shaped Newton on the world rows for one step: returns the iterations (linear solves of J). */
static int world_newton(corot_world *cw, corot_world_jacobian *J, double *y, double tol) {
  const int N = cw->N;
  double *A = malloc(sizeof(double) * (size_t)N * (size_t)N), *F = calloc((size_t)N, sizeof(double));
  double *y1 = calloc((size_t)N, sizeof(double)), *y2 = calloc((size_t)N, sizeof(double));
  double *dF = calloc((size_t)N, sizeof(double)), *dgy = calloc((size_t)N, sizeof(double));
  int it = 0;
  for (; it < 40; ++it) {
    /* update_active_set at the new point, then residual and Jacobian there */
    int changes = corot_world_propose_sets(cw, y);
    if (cw->contact) {
      memcpy(cw->contact->set, cw->contact->set_next, (size_t)cw->contact->n);
      memcpy(cw->contact->dir, cw->contact->dir_next, sizeof(double) * 2 * (size_t)cw->contact->n);
    }
    double g, Fn = 0.0, Fs = 0.0;
    corot_world_residual(cw, y, F, &g);
    for (int i = 0; i < N; ++i) Fn = fmax(Fn, fabs(F[i]));
    for (int i = 0; i < cw->body->n; ++i) Fs = fmax(Fs, fabs(cw->Rin[i]) + fabs(cw->Su_h[i]));
    if (it > 0 && changes == 0 && Fn <= 1e-12 * Fs && fabs(g) <= tol * corot_world_g_ref(cw)) break;
    corot_world_jacobian_eval(cw, y, J);
    world_dense(cw, J, A);
    for (int i = 0; i < N; ++i) F[i] = -F[i];
    dense_solve_copy(N, A, F, y1);
    double dgw;
    corot_world_dw(cw, y, dF, dgy, &dgw);
    dense_solve_copy(N, A, dF, y2); /* the "solve_again" */
    double a1 = 0.0, a2 = 0.0;
    for (int i = 0; i < N; ++i) a1 += dgy[i] * y1[i], a2 += dgy[i] * y2[i];
    const double dw = (-g - a1) / (dgw - a2);
    for (int i = 0; i < N; ++i) y[i] += y1[i]; /* the host applies the solve; w moves by the plugin's dw */
    corot_world_set_w(cw, cw->w + dw);
  }
  free(A);
  free(F);
  free(y1);
  free(y2);
  free(dF);
  free(dgy);
  return it;
}

/* The disk thrown at a plane (test_corot_step's impact): the world-form steps equal the s-form's. */
static void test_equivalence(test_body *tb, corot_model model, double mu) {
  const corot_body *b = &tb->body;
  const int n = b->n, dim = b->dim;
  dense_lu lu = {0};
  corot_solver solver = dense_solver(&lu);
  corot_plane plane = {.point = {0, -1.1, 0}, .normal = {0, 1, 0}, .mu = mu};
  corot_contact c1, c2;
  corot_contact_init(&c1, dim, tb->n_contact, tb->contact_nodes, tb->contact_weight, 1, &plane, 1.0, 1.0);
  corot_contact_init(&c2, dim, tb->n_contact, tb->contact_nodes, tb->contact_weight, 1, &plane, 1.0, 1.0);
  corot_state s1, s2;
  corot_state_alloc(&s1, b);
  corot_state_alloc(&s2, b);
  const double V0[3] = {2.0, -5.0, 0.0}, dt = 0.004;
  SK_CHECK(initial_state(b, model, 3.0, V0, &s1) == 0);
  memcpy(s2.u, s1.u, sizeof(double) * (size_t)n);
  memcpy(s2.s, s1.s, sizeof(double) * (size_t)n);
  s1.w = s2.w = 3.0;
  corot_step step;
  corot_step_init(&step, model, b, &c1);
  corot_world cw;
  corot_world_jacobian J;
  corot_world_init(&cw, model, b, &c2);
  corot_world_jacobian_alloc(&J, &cw);
  double *y = calloc((size_t)cw.N, sizeof(double));
  double ds = 0.0, dw = 0.0, dl = 0.0, lmax = 0.0;
  int iters_s = 0, iters_w = 0, active = 0;
  for (int k = 1; k <= 40; ++k) {
    corot_step_begin(&step, &s1, dt, NULL);
    SK_CHECK(corot_step_solve(&step, &solver, 40, 1e-13) == 0);
    iters_s += step.iterations;
    corot_world_begin(&cw, &s2, dt, NULL);
    corot_world_predict(&cw, y);
    iters_w += world_newton(&cw, &J, y, 1e-13);
    corot_world_kinematics(&cw, y);
    for (int i = 0; i < n; ++i) ds = fmax(ds, fabs(cw.s[i] - step.y[i]) / (3.0 + vec_norm(3, V0)));
    dw = fmax(dw, fabs(cw.w - step.w) / 3.0);
    for (int p = 0; p < c1.n; ++p)
      for (int i = 0; i < dim; ++i) {
        dl = fmax(dl, fabs(y[n + cw.n_border + p * dim + i] - c1.lambda[3 * p + i]));
        lmax = fmax(lmax, fabs(c1.lambda[3 * p + i]));
      }
    for (int p = 0; p < c1.n; ++p) active += c1.set[p] != COROT_INACTIVE;
    corot_step_commit(&step, &s1);
    corot_world_commit(&cw, y, &s2);
  }
  printf("  world vs s-form model %d mu %g, 40 steps (%d node-steps in contact): |ds| %.1e, |dw| %.1e, |dlambda| "
         "%.1e of %.2e; iterations %d (s-form) %d (world)\n", model, mu, active, ds, dw, dl, lmax, iters_s, iters_w);
  SK_CHECK(active > 0);
  SK_CHECK(ds <= 1e-10);
  SK_CHECK(dw <= 1e-10);
  SK_CHECK(dl <= 1e-9 * lmax);
  free(y);
  corot_world_jacobian_free(&J);
  corot_world_free(&cw);
  corot_step_free(&step);
  corot_state_free(&s1);
  corot_state_free(&s2);
  corot_contact_free(&c1);
  corot_contact_free(&c2);
  dense_free(&lu);
}

int main(void) {
  test_body disk, cube;
  SK_CHECK(load_unit_disk(&disk) == 0);
  SK_CHECK(load_tilted_cube(&cube) == 0);
  if (sk_test_failures) return sk_test_finish("test_corot_world");
  for (int model = 1; model <= 2; ++model)
    for (int f = 0; f < 2; ++f) {
      test_derivatives(&disk, (corot_model)model, f ? 0.3 : 0.0);
      test_derivatives(&cube, (corot_model)model, f ? 0.3 : 0.0);
    }
  for (int model = 1; model <= 2; ++model) {
    test_equivalence(&disk, (corot_model)model, 0.0);
    test_equivalence(&disk, (corot_model)model, 0.3);
  }
  test_body_free(&disk);
  test_body_free(&cube);
  return sk_test_finish("test_corot_world");
}
