/* Finite-element assembly of the bodies (internal to the simulation layer): one element's residual and Jacobian
 * under a body's time integrator, traction loads, and the energies, momenta and stresses written as results. The
 * loops over a rank's elements are the bulk term's (term_bulk.c). */
#ifndef STICKSLIP_ASSEMBLE_H
#define STICKSLIP_ASSEMBLE_H

#include "stickslip/model.h"

/* Where a step stands: the residual of the step from t_n to t for displacement u. */
typedef struct {
  const sk_time_integrator *integrator;
  double t_n, t, dt;
  const double *u_n, *v_n; /* at t_n (v_n NULL without inertia) */
  const double *u;         /* current iterate */
} sk_bulk_state;

/* Global dof ids of element e (global element numbering over bodies): returns nen*dim and fills dofs (if not
 * NULL). */
int sk_element_dofs(const sk_model *model, int element, int *dofs, const sk_body **body, const int **conn);

/* Element e's residual f = c M (u - u_n - dt v_n) + f_int - M b (b the body force per unit mass) and, when K is not
 * NULL, its Jacobian (row-major, zeroed by the caller); n = nen*dim, dofs its global dof ids. SK_ERR_INVERTED (with
 * a message naming the body and element) when the element is inverted. `geometry`: the element's reference
 * geometry (sk_solid_geometry), or NULL to compute it from the coordinates. */
sk_status sk_element_system(const sk_model *model, const sk_bulk_state *state, int element, const double *geometry,
                            int *dofs, int *n, double *f, double *K);

/* The inertia and body-force part of sk_element_system alone, added to f (and K when not NULL): for a bulk term that
 * keeps the internal part's constant stiffness (hooke). dofs from sk_element_dofs. */
sk_status sk_element_inertia(const sk_model *model, const sk_bulk_state *state, int element, const int *dofs,
                             double *f, double *K);

/* Adds traction load k at time t to F (F -= nodal forces), dim per node: the faces whose first node this rank owns. */
void sk_traction_add(const sk_model *model, int k, double t, double *F);

typedef struct {
  double kinetic, strain;
  double momentum[3], angular_momentum[3];
} sk_invariants;

/* Kinetic and strain energy, linear and angular momentum (about the origin) at displacement u and velocity v (over
 * the local dofs; collective: each rank sums its owned nodes and elements). */
sk_status sk_bulk_invariants(const sk_model *model, const double *u, const double *v, sk_invariants *inv);
/* The same for one body (collective). */
sk_status sk_bulk_body_invariants(const sk_model *model, int body, const double *u, const double *v,
                                  sk_invariants *inv);

/* Element-averaged Cauchy stress (9 per element, zero for other ranks' elements: sum over ranks). */
sk_status sk_bulk_stress(const sk_model *model, const double *u, double *stress);

#endif
