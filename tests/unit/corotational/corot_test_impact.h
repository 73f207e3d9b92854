/* The run every impact test of the corotational kernel makes: a disk thrown spinning at rigid planes, stepped with
 * the kernel's loop (dense LU), recording per step what the paper's checks need (Newton iterations, contact, the
 * energy balance, the Model 1 angular-momentum balance, Tisserand, node-wise complementarity). */
#ifndef COROT_TEST_IMPACT_H
#define COROT_TEST_IMPACT_H

#include "corot_test_support.h"
#include "sk_test.h"

enum { IMPACT_MAX_STEPS = 200 };

typedef struct {
  corot_model model;
  int n_planes;
  corot_plane planes[2];
  double omega, V0[3], dt, tol;
  int steps;
} impact_setup;

typedef struct {
  double omega_ref_max, J0;
  int steps, max_active, max_stick, max_iterations, total_iterations;
  double E0, E_drift, J_balance, tisserand, complementarity, friction_balance, dissipated, w_final, w_min;
  double J_defect; /* Model 2: the largest |defect| of a step's J balance, -w c . Pi (u^{n+1} - u^n), relative to J0 */
  double energy_increase;
  int iterations[IMPACT_MAX_STEPS], active[IMPACT_MAX_STEPS]; /* per step (index k - 1) */
} impact_result;

static inline void run_impact(test_body *tb, const impact_setup *setup, impact_result *res) {
  const corot_model model = setup->model;
  const corot_body *b = &tb->body;
  const int n = b->n, dim = b->dim;
  memset(res, 0, sizeof *res);
  dense_lu lu = {0};
  corot_solver solver = dense_solver(&lu);
  corot_contact contact;
  SK_CHECK(corot_contact_init(&contact, dim, tb->n_contact, tb->contact_nodes, tb->contact_weight, setup->n_planes,
                              setup->planes, 1.0, 1.0) == 0);
  corot_state state, next;
  corot_state_alloc(&state, b);
  corot_state_alloc(&next, b);
  const double omega = setup->omega, dt = setup->dt;
  SK_CHECK(initial_state(b, model, omega, setup->V0, &state) == 0);
  state.w = omega;
  corot_step step;
  corot_step_init(&step, model, b, &contact);
  double *work = calloc((size_t)n, sizeof(double)), *Dl = calloc((size_t)n, sizeof(double));
  res->E0 = corot_energy(b, state.u, state.s, work);
  const double J0 = res->J0 = corot_angular_momentum(b, model, state.u, state.s, work);
  res->w_min = omega;
  for (int k = 1; k <= setup->steps && k <= IMPACT_MAX_STEPS; ++k) {
    corot_step_begin(&step, &state, dt, NULL);
    const int status = corot_step_solve(&step, &solver, 40, setup->tol);
    SK_CHECK(status == 0);
    if (status != 0) break;
    res->total_iterations += step.iterations;
    res->max_iterations = step.iterations > res->max_iterations ? step.iterations : res->max_iterations;
    corot_complementarity cc;
    corot_contact_check(&contact, dim, step.y, &cc);
    double lambda_max = 0.0, s_max = 0.0;
    for (int p = 0; p < contact.n; ++p) {
      lambda_max = fmax(lambda_max, vec_norm(dim, contact.lambda + 3 * p));
      s_max = fmax(s_max, vec_norm(dim, step.y + contact.node[p] * dim));
    }
    if (cc.active > 0)
      res->complementarity = fmax(res->complementarity,
                                  fmax(fmax(cc.product / (lambda_max * s_max), cc.negative_pressure / lambda_max),
                                       fmax(cc.penetration_rate / s_max, cc.friction_excess / lambda_max)));
    res->iterations[k - 1] = step.iterations;
    res->active[k - 1] = cc.active;
    res->max_active = cc.active > res->max_active ? cc.active : res->max_active;
    res->max_stick = cc.stick > res->max_stick ? cc.stick : res->max_stick;
    /* D lambda on the contact nodes, for the angular-momentum balance */
    memset(Dl, 0, sizeof(double) * (size_t)n);
    for (int p = 0; p < contact.n; ++p)
      for (int i = 0; i < dim; ++i) Dl[contact.node[p] * dim + i] = contact.weight[p] * contact.lambda[3 * p + i];
    double torque = 0.0;
    for (int a = 0; a < b->n_nodes; ++a) {
      double pr[3];
      corot_pi(dim, b->e, step.r_h + a * dim, pr);
      for (int i = 0; i < dim; ++i) torque -= Dl[a * dim + i] * pr[i];
    }
    /* Model 2's lever arm x + T(u) leaves the defect -w c . Pi (u^{n+1} - u^n) in the J balance (Sec. 2.4) */
    double defect = 0.0;
    if (model == COROT_MODEL_2) {
      for (int a = 0; a < b->n_nodes; ++a) {
        double du[3] = {0, 0, 0}, pdu[3];
        for (int i = 0; i < dim; ++i) du[i] = 2.0 * step.u_h[a * dim + i] - 2.0 * state.u[a * dim + i];
        corot_pi(dim, b->e, du, pdu);
        for (int i = 0; i < dim; ++i) defect -= step.w * b->c[a * dim + i] * pdu[i];
      }
    }
    const double E_n = corot_energy(b, state.u, state.s, work);
    const double J_n = corot_angular_momentum(b, model, state.u, state.s, work);
    const double friction_work = corot_step_commit(&step, &next);
    const double E_next = corot_energy(b, next.u, next.s, work);
    const double J_next = corot_angular_momentum(b, model, next.u, next.s, work);
    res->E_drift = fmax(res->E_drift, fabs(E_next - E_n + friction_work) / res->E0);
    res->energy_increase = fmax(res->energy_increase, (E_next - E_n) / res->E0);
    res->dissipated += friction_work;
    res->friction_balance = fmin(res->friction_balance, friction_work / res->E0);
    /* relative to the initial J: J itself passes through 0 when friction reverses the spin */
    res->J_balance = fmax(res->J_balance, fabs(J_next - J_n - dt * torque - defect) / fabs(J0));
    res->J_defect = fmax(res->J_defect, fabs(defect) / fabs(J0));
    double tis = 0.0;
    for (int i = 0; i < n; ++i) tis += b->c[i] * next.u[i];
    res->tisserand = fmax(res->tisserand, fabs(tis) / b->inertia);
    res->w_min = fmin(res->w_min, step.w);
    res->omega_ref_max = fmax(res->omega_ref_max, step.omega_ref);
    corot_state tmp = state;
    state = next;
    next = tmp;
    res->steps = k;
  }
  res->w_final = state.w;
  free(work);
  free(Dl);
  corot_step_free(&step);
  corot_state_free(&state);
  corot_state_free(&next);
  corot_contact_free(&contact);
  dense_free(&lu);
}

/* The bounds of a converged rotation equation |g| <= tol g_ref: the energy identity holds to dt w g, at most 4 tol
 * E relative; the J balance to dt g, at most 2 tol I_e omega_ref (docs/plugins/corotational.md §4). */
static inline double energy_bound(double tol) { return 4.0 * tol + 1e-14; }
static inline double momentum_bound(const test_body *tb, const impact_result *r, double tol) {
  return 2.0 * tol * tb->body.inertia * r->omega_ref_max / fabs(r->J0) + 1e-14;
}

#endif
