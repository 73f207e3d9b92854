/* The core's time integrators (stickslip/integrator.h): quasi-static, backward Euler and the energy-momentum
 * midpoint rule (Gonzalez's discrete gradient for the internal forces, loads at t_{n+1/2}). */
#include "stickslip/integrator.h"

#include <string.h>

#include "stickslip/plugin_types.h"

static int64_t dof_at(const int64_t *dofs, int64_t k) { return dofs ? dofs[k] : k; }

static double no_inertia(double dt) {
  (void)dt;
  return 0.0;
}
static double euler_inertia(double dt) { return 1.0 / (dt * dt); }
static double midpoint_inertia(double dt) { return 2.0 / (dt * dt); }

static double end_time(double t_n, double t) {
  (void)t_n;
  return t;
}
static double mid_time(double t_n, double t) { return 0.5 * (t_n + t); }

/* constant velocity (quasi-static: the previous increment continued over dt) */
static void predict_drift(int64_t n, const int64_t *dofs, const double *u_n, const double *v_n, double dt, double *u) {
  for (int64_t k = 0; k < n; ++k) {
    const int64_t i = dof_at(dofs, k);
    u[i] = u_n[i] + dt * v_n[i];
  }
}

/* quasi-static: u_n continued at the rate of the previous increment, or u_n itself without one */
static void predict_increment(int64_t n, const int64_t *dofs, const double *u_n, const double *rate_n, double dt,
                              double *u) {
  if (rate_n) {
    predict_drift(n, dofs, u_n, rate_n, dt, u);
    return;
  }
  for (int64_t k = 0; k < n; ++k) u[dof_at(dofs, k)] = u_n[dof_at(dofs, k)];
}

static void velocity_zero(int64_t n, const int64_t *dofs, const double *u_n, const double *v_n, const double *u,
                          double dt, double *v) {
  (void)u_n, (void)v_n, (void)u, (void)dt;
  for (int64_t k = 0; k < n; ++k) v[dof_at(dofs, k)] = 0.0;
}

/* backward Euler: v = (u - u_n) / dt */
static void velocity_euler(int64_t n, const int64_t *dofs, const double *u_n, const double *v_n, const double *u,
                           double dt, double *v) {
  (void)v_n;
  for (int64_t k = 0; k < n; ++k) {
    const int64_t i = dof_at(dofs, k);
    const double du = u[i] - u_n[i];
    v[i] = du / dt;
  }
}

/* midpoint: (v + v_n)/2 = (u - u_n)/dt */
static void velocity_midpoint(int64_t n, const int64_t *dofs, const double *u_n, const double *v_n, const double *u,
                              double dt, double *v) {
  for (int64_t k = 0; k < n; ++k) {
    const int64_t i = dof_at(dofs, k);
    const double du = u[i] - u_n[i];
    v[i] = 2.0 * du / dt - v_n[i];
  }
}

static const sk_time_integrator integrators[] = {
    {.name = "quasi-static", .alpha = 1.0, .dynamic = 0, .discrete_gradient = 0, .plugin_caps = SK_CAP_QUASISTATIC,
     .energy_momentum = 0, .inertia_coefficient = no_inertia, .force_time = end_time, .predict = predict_increment,
     .velocity = velocity_zero},
    {.name = "backward-euler", .alpha = 1.0, .dynamic = 1, .discrete_gradient = 0, .plugin_caps = SK_CAP_DYNAMICS,
     .energy_momentum = 0, .inertia_coefficient = euler_inertia, .force_time = end_time, .predict = predict_drift,
     .velocity = velocity_euler},
    {.name = "midpoint", .alpha = 0.5, .dynamic = 1, .discrete_gradient = 1, .plugin_caps = SK_CAP_DYNAMICS,
     .energy_momentum = 1, .inertia_coefficient = midpoint_inertia, .force_time = mid_time,
     .predict = predict_drift, .velocity = velocity_midpoint},
};

static const char *const names[] = {"quasi-static", "backward-euler", "midpoint", NULL};

const sk_time_integrator *sk_time_integrator_find(const char *name) {
  for (size_t k = 0; k < sizeof integrators / sizeof integrators[0]; ++k)
    if (name && strcmp(integrators[k].name, name) == 0) return &integrators[k];
  return NULL;
}

const char *const *sk_time_integrator_names(void) { return names; }
