/* Bulk (non-contact) parts of a step's nonlinear system: internal, inertial and external forces of the bodies, with
 * their Jacobian, and the invariants written to history.csv. Internal to the simulation layer. */
#ifndef STICKSLIP_ASSEMBLE_H
#define STICKSLIP_ASSEMBLE_H

#include "stickslip/model.h"

/* Where a step stands: the residual of the step from t_n to t for displacement u. */
typedef struct {
  sk_scheme scheme;
  double t_n, t, dt;
  const double *u_n, *v_n; /* at t_n (v_n NULL when quasi-static) */
  const double *u;         /* current iterate */
} sk_bulk_state;

/* Coefficient of the mass matrix in the step's residual: F = c M (u - u_n - dt v_n) + ... */
double sk_bulk_mass_coefficient(const sk_bulk_state *state);

/* Velocity at t from the scheme: BE v = (u - u_n)/dt; midpoint v = 2 (u - u_n)/dt - v_n; quasi-static 0. */
void sk_bulk_velocity(const sk_model *model, const sk_bulk_state *state, double *v);

/* Adds this rank's elements' residual (internal + inertial - body force) and, on rank 0, the tractions, to F.
 * SK_ERR_INVERTED (with a message naming the body and element) when an element is inverted. */
sk_status sk_bulk_residual(const sk_model *model, const sk_bulk_state *state, double *F);

/* Calls `scatter` with each of this rank's element Jacobians (dofs: global dof ids, K row-major). */
typedef void (*sk_element_scatter)(void *ctx, int element, int n, const int *dofs, const double *K);
sk_status sk_bulk_jacobian(const sk_model *model, const sk_bulk_state *state, sk_element_scatter scatter, void *ctx);

/* Global dof ids of element e (global element numbering over bodies): returns nen*dim and fills dofs. */
int sk_element_dofs(const sk_model *model, int element, int *dofs, const sk_body **body, const int **conn);

typedef struct {
  double kinetic, strain;
  double momentum[3], angular_momentum[3];
} sk_invariants;

/* Kinetic and strain energy, linear and angular momentum (about the origin) at displacement u and velocity v
 * (collective: strain energy is summed over ranks). */
sk_status sk_bulk_invariants(const sk_model *model, const double *u, const double *v, sk_invariants *inv);

/* Element-averaged Cauchy stress (9 per element, zero for other ranks' elements: sum over ranks). */
sk_status sk_bulk_stress(const sk_model *model, const double *u, double *stress);

#endif
