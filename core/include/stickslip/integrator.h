/* stickslip — time integrators of the bodies as objects (core/time/integrator.c), replacing a closed scheme enum.
 *
 * A step from t_n to t = t_n + dt solves F(u) = c M (u - u_n - dt v_n) + f_int - f_ext(t_f) = 0 for the body's
 * displacements u, with the inertia coefficient c, the internal force f_int at u (or the discrete gradient between
 * u_n and u) and the loads at the force time t_f. After the step the integrator gives the velocity. A body plugin
 * that claims its body replaces all of this by its own integrator (plugin.h: sk_integrator). */
#ifndef STICKSLIP_INTEGRATOR_H
#define STICKSLIP_INTEGRATOR_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sk_time_integrator {
  const char *name;         /* the scene's time.scheme value */
  double alpha;             /* forces balance at t_n + alpha dt (what plugins see as sk_state.alpha) */
  int dynamic;              /* 1: inertia, velocities are meaningful */
  int discrete_gradient;    /* 1: internal forces by the energy-momentum discrete gradient between u_n and u */
  uint64_t plugin_caps;     /* capability a pair plugin needs to run under it (SK_CAP_QUASISTATIC/DYNAMICS) */
  int energy_momentum;      /* 1: pair plugins without SK_CAP_ENERGY_MOMENTUM get a warning */
  /* c of the inertia term c M (u - u_n - dt v_n) */
  double (*inertia_coefficient)(double dt);
  /* the time at which loads are evaluated */
  double (*force_time)(double t_n, double t);
  /* predictor u (n dofs listed in `dofs`, or the first n dofs when dofs is NULL) from u_n and v_n; a quasi-static
   * integrator gets the rate of the previous increment (u_n - u_{n-1}) / dt_n in v_n, or NULL for u = u_n */
  void (*predict)(int64_t n, const int64_t *dofs, const double *u_n, const double *v_n, double dt, double *u);
  /* velocity at t from u_n, v_n and the converged u */
  void (*velocity)(int64_t n, const int64_t *dofs, const double *u_n, const double *v_n, const double *u, double dt,
                   double *v);
} sk_time_integrator;

/* "quasi-static", "backward-euler", "midpoint"; NULL for another name. */
const sk_time_integrator *sk_time_integrator_find(const char *name);
/* The names, NULL-terminated (for messages and the scene reader). */
const char *const *sk_time_integrator_names(void);

#ifdef __cplusplus
}
#endif
#endif
