/* corotational — the host-free step loop (Sec. 5: the active set and the scalar Newton on w, one factorisation per
 * iteration, the derivative solve reusing it) and the steady-spin initial state (Sec. 6.1). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "kernel.h"

int corot_step_solve(corot_step *step, const corot_solver *solver, int max_iterations, double tol) {
  double last_dw = INFINITY;
  for (step->iterations = 1; step->iterations <= max_iterations; ++step->iterations) {
    corot_step_assemble(step);
    if (solver->factor(solver->ctx, &step->system) != 0) return -1;
    if (solver->solve(solver->ctx, step->rhs, step->y) != 0) return -1;
    const int changes = corot_step_evaluate(step, step->y);
    if (changes == 0 && corot_step_rotation_converged(step, tol)) return 0;
    if (!corot_step_rotation_converged(step, tol)) {
      /* Newton on w with the matrix just factorised: P dy/dw = -d(P y - b)/dw  (Sec. 5.3) */
      corot_step_derivative_rhs(step, step->y, step->rhs);
      if (solver->solve(solver->ctx, step->rhs, step->dy) != 0) return -1;
      step->dg = corot_step_dg(step, step->y, step->dy);
      if (!(fabs(step->dg) > 0.0) || !isfinite(step->dg)) return -1;
      const double dw = -step->g / step->dg;
      /* g at its round-off floor: near the tolerance, an update that no longer contracts is noise, and this solve is
       * as good as the arithmetic allows. Stiff steps put the floor above tol = 1e-12: measured g / g_ref up to
       * 6.5e-12 at w dt = 40 (the 6.4 ball, theta'_0 = 200, dt = 0.2) and 3e-12 at dt = 0.5 (test_corot_step). */
      if (changes == 0 && fabs(step->g) <= COROT_ROUNDOFF_FACTOR * tol * step->g_ref && fabs(dw) > 0.5 * last_dw)
        return 0;
      last_dw = changes == 0 ? fabs(dw) : INFINITY;
      step->w += dw;
    }
    corot_step_apply_sets(step);
  }
  step->iterations = max_iterations;
  return 1;
}

/* Rigid modes Z of the body (translations, then rotations: 2D Pi x; 3D e_i x x). Returns their number. */
static int rigid_modes(const corot_body *body, double *Z[COROT_MAX_BORDER]) {
  const int dim = body->dim, count = dim == 2 ? 3 : 6;
  for (int j = 0; j < count; ++j) memset(Z[j], 0, sizeof(double) * (size_t)body->n);
  for (int a = 0; a < body->n_nodes; ++a) {
    const double *x = body->x + a * dim;
    for (int i = 0; i < dim; ++i) Z[i][a * dim + i] = 1.0;
    if (dim == 2) {
      corot_pi(2, body->e, x, Z[2] + a * dim);
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      const double ek[3] = {k == 0, k == 1, k == 2};
      corot_pi(3, ek, x, Z[3 + k] + a * dim);
    }
  }
  return count;
}

/* v -= Q Q^T v with the orthonormal columns Q[j]. */
static void project(int n, int k, double *const *Q, double *v) {
  for (int j = 0; j < k; ++j) {
    const double c = corot_dot(n, Q[j], v);
    for (int i = 0; i < n; ++i) v[i] -= c * Q[j][i];
  }
}

/* out = K v: S v + w0^2 M Pi^2 v (Model 1) or S v (Model 2). t, Mt: n scratch entries each. */
static void steady_operator(const corot_body *body, corot_model model, double w2, const double *v, double *out,
                            double *t, double *Mt) {
  corot_stiffness_apply(body, v, out);
  if (model != COROT_MODEL_1) return;
  for (int a = 0; a < body->n_nodes; ++a) {
    double pv[3];
    corot_pi(body->dim, body->e, v + a * body->dim, pv);
    corot_pi(body->dim, body->e, pv, t + a * body->dim);
  }
  corot_mass_apply(body, t, Mt);
  for (int i = 0; i < body->n; ++i) out[i] += w2 * Mt[i];
}

int corot_initial_state(const corot_body *body, corot_model model, double omega, const double V0[3], double tol,
                        double *u0, double *s0, int *iterations) {
  const int dim = body->dim, n = body->n, k = dim == 2 ? 3 : 6;
  memset(u0, 0, sizeof(double) * (size_t)n);
  *iterations = 0;
  int status = 0;
  if (omega != 0.0) {
    /* Model 1: (S + w0^2 M Pi^2) u0 = -w0^2 M Pi^2 x; Model 2: S u0 = -w0^2 M Pi^2 x; both on Z^T M u0 = 0 with the
     * rigid modes Z: Model 2 needs them (S is singular); in Model 1 they hold by themselves in 2D (test with
     * v = Pi x, v = t) and keep the problem well posed for small w0; in 3D they also fix the axial translation
     * (Pi^2 e = 0) and the two rotations about axes normal to e (zero for a body with e as a principal axis).
     * Projected conjugate gradients (K is symmetric and positive on the complement of Z for w0 below the first
     * elastic frequency): the residual is kept orthogonal to M Z, i.e. K u0 = rhs + M Z mu. */
    double *Z[COROT_MAX_BORDER], *Q[COROT_MAX_BORDER], *r, *p, *q, *t, *t2;
    double *buffer = calloc((size_t)(2 * k + 5) * (size_t)n, sizeof(double));
    if (!buffer) return -1;
    for (int j = 0; j < k; ++j) {
      Z[j] = buffer + (size_t)j * n;
      Q[j] = buffer + (size_t)(k + j) * n;
    }
    r = buffer + (size_t)(2 * k) * n, p = r + n, q = p + n, t = q + n, t2 = t + n;
    rigid_modes(body, Z);
    for (int j = 0; j < k; ++j) { /* Q = orthonormal basis of M Z (Gram-Schmidt, twice for round-off) */
      corot_mass_apply(body, Z[j], Q[j]);
      for (int pass = 0; pass < 2; ++pass) project(n, j, Q, Q[j]);
      const double norm = sqrt(corot_dot(n, Q[j], Q[j]));
      for (int i = 0; i < n; ++i) Q[j][i] /= norm;
    }
    const double w2 = omega * omega;
    for (int a = 0; a < body->n_nodes; ++a) {
      double px[3];
      corot_pi(dim, body->e, body->x + a * dim, px);
      corot_pi(dim, body->e, px, t + a * dim);
    }
    corot_mass_apply(body, t, r);
    for (int i = 0; i < n; ++i) r[i] *= -w2;
    project(n, k, Q, r);
    memcpy(p, r, sizeof(double) * (size_t)n);
    const double r0 = sqrt(corot_dot(n, r, r));
    double rr = r0 * r0;
    status = 1;
    for (int it = 1; it <= 20 * n && r0 > 0.0; ++it) {
      steady_operator(body, model, w2, p, q, t, t2);
      project(n, k, Q, q);
      const double pq = corot_dot(n, p, q);
      if (!(pq > 0.0)) { /* K is not positive on the complement: w0 at or above an elastic frequency */
        status = -1;
        break;
      }
      const double alpha = rr / pq;
      for (int i = 0; i < n; ++i) {
        u0[i] += alpha * p[i];
        r[i] -= alpha * q[i];
      }
      const double rr_next = corot_dot(n, r, r);
      *iterations = it;
      if (sqrt(rr_next) <= tol * r0) {
        status = 0;
        break;
      }
      for (int i = 0; i < n; ++i) p[i] = r[i] + (rr_next / rr) * p[i];
      rr = rr_next;
    }
    if (r0 == 0.0) status = 0;
    project(n, k, Q, u0); /* u0 is in the complement up to the iteration's round-off */
    free(buffer);
    if (status != 0) return status;
  }
  /* s0 = w0 Pi (x + u0) + V0 (Model 1) or w0 Pi x + V0 (Model 2) */
  for (int a = 0; a < body->n_nodes; ++a) {
    double r[3], pr[3];
    for (int i = 0; i < dim; ++i) r[i] = body->x[a * dim + i] + (model == COROT_MODEL_1 ? u0[a * dim + i] : 0.0);
    corot_pi(dim, body->e, r, pr);
    for (int i = 0; i < dim; ++i) s0[a * dim + i] = omega * pr[i] + V0[i];
  }
  return 0;
}
