/* corotational — the host-free step loop (Sec. 5: the active set and the scalar Newton on w, one factorisation per
 * iteration, the derivative solve reusing it) and the steady-spin initial state (Sec. 6.1). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "kernel.h"

int corot_step_solve(corot_step *step, const corot_solver *solver, int max_iterations, double tol) {
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
      /* g at its round-off floor: the update would not change w beyond its last bits, so this solve is the
       * solution (large dt make A stiff, and g's cancellation then sits above tol * g_ref) */
      if (changes == 0 && fabs(dw) <= COROT_W_ROUNDOFF * step->omega_ref) return 0;
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

int corot_initial_state(const corot_body *body, corot_model model, double omega, const double V0[3],
                        const corot_solver *solver, double *u0, double *s0) {
  const int dim = body->dim, n = body->n, dd = dim * dim;
  memset(u0, 0, sizeof(double) * (size_t)n);
  int status = 0;
  if (omega != 0.0) {
    /* Model 1: (S + w0^2 M Pi^2) u0 = -w0^2 M Pi^2 x; Model 2: S u0 = -w0^2 M Pi^2 x. Both bordered by the rigid
     * modes (Z^T M u0 = 0): Model 2 needs them (S is singular); in Model 1 they hold by themselves in 2D (test with
     * v = Pi x, v = t) and keep the system well conditioned for small w0; in 3D they also fix the axial translation
     * (Pi^2 e = 0) and the two rotations about axes normal to e (zero for a body with e as a principal axis). */
    corot_system system;
    const int n_modes = dim == 2 ? 3 : 6;
    if (corot_system_alloc(&system, body, n_modes) != 0) return -1;
    double *rhs = calloc((size_t)(n + n_modes), sizeof(double)), *y = calloc((size_t)(n + n_modes), sizeof(double));
    double *t = calloc((size_t)n, sizeof(double));
    if (!rhs || !y || !t) status = -1;
    if (status == 0) {
      double P[9], P2[9];
      corot_pi_matrix(dim, body->e, P);
      for (int i = 0; i < dim; ++i)
        for (int j = 0; j < dim; ++j) {
          double sum = 0.0;
          for (int k = 0; k < dim; ++k) sum += P[i * dim + k] * P[k * dim + j];
          P2[i * dim + j] = sum;
        }
      const double w2 = omega * omega;
      for (int64_t k = 0; k < body->row_ptr[body->n_nodes]; ++k) {
        double *B = system.blocks + k * dd;
        memcpy(B, body->stiffness + k * dd, sizeof(double) * (size_t)dd);
        if (model == COROT_MODEL_1)
          for (int i = 0; i < dd; ++i) B[i] += w2 * body->mass[k] * P2[i];
      }
      rigid_modes(body, system.border_row);
      for (int j = 0; j < n_modes; ++j) {
        corot_mass_apply(body, system.border_row[j], system.border_col[j]);
        memcpy(system.border_row[j], system.border_col[j], sizeof(double) * (size_t)n);
      }
      for (int a = 0; a < body->n_nodes; ++a) corot_mul(dim, P2, body->x + a * dim, t + a * dim);
      corot_mass_apply(body, t, rhs);
      for (int i = 0; i < n; ++i) rhs[i] *= -w2;
      if (solver->factor(solver->ctx, &system) != 0 || solver->solve(solver->ctx, rhs, y) != 0) status = -1;
      if (status == 0) memcpy(u0, y, sizeof(double) * (size_t)n);
    }
    free(rhs);
    free(y);
    free(t);
    corot_system_free(&system);
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
