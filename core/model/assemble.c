/* Finite-element assembly of the bodies (assemble.h): element systems under a time integrator, tractions,
 * invariants and stresses. */
#include "assemble.h"

#include <stdlib.h>
#include <string.h>

int sk_element_dofs(const sk_model *model, int element, int *dofs, const sk_body **body_out, const int **conn_out) {
  int b = 0;
  while (b + 1 < model->n_bodies && element >= model->bodies[b + 1].first_element) ++b;
  const sk_body *body = &model->bodies[b];
  const sk_group *g = body->group;
  const int *conn = g->conn + (size_t)(element - body->first_element) * (size_t)g->nen;
  int dim = model->dim;
  if (dofs)
    for (int a = 0; a < g->nen; ++a)
      for (int i = 0; i < dim; ++i) dofs[a * dim + i] = conn[a] * dim + i;
  if (body_out) *body_out = body;
  if (conn_out) *conn_out = conn;
  return g->nen * dim;
}

static void gather(int n, const int *dofs, const double *global, double *local) {
  for (int k = 0; k < n; ++k) local[k] = global[dofs[k]];
}

static sk_status inverted(const sk_model *model, const sk_body *body, int element) {
  return sk_error_prefix(SK_ERR_INVERTED, "body '%s', element %d: ", body->name, model->element_index[element]);
}

sk_status sk_element_system(const sk_model *model, const sk_bulk_state *state, int element, const double *geometry,
                            int *dofs, int *n_out, double *f, double *K) {
  const sk_body *body;
  int n = sk_element_dofs(model, element, dofs, &body, NULL);
  double X[SK_MAX_NEN * 3], u[SK_MAX_NEN * 3], u0[SK_MAX_NEN * 3];
  gather(n, dofs, state->u, u);
  sk_status status;
  if (state->integrator->discrete_gradient) {
    gather(n, dofs, state->u_n, u0);
    if (geometry) {
      status = sk_solid_internal_midpoint_at(&body->solid, geometry, u0, u, f, K);
    } else {
      gather(n, dofs, model->X, X);
      status = sk_solid_internal_midpoint(&body->solid, X, u0, u, f, K);
    }
  } else if (geometry) {
    status = sk_solid_internal_at(&body->solid, geometry, u, NULL, f, K);
  } else {
    gather(n, dofs, model->X, X);
    status = sk_solid_internal(&body->solid, X, u, NULL, f, K);
  }
  if (status != SK_OK) return inverted(model, body, element);
  *n_out = n;
  return sk_element_inertia(model, state, element, dofs, f, K);
}

sk_status sk_element_inertia(const sk_model *model, const sk_bulk_state *state, int element, const int *dofs,
                             double *f, double *K) {
  const sk_body *body;
  const int n = sk_element_dofs(model, element, NULL, &body, NULL);
  const int nen = body->group->nen, dim = model->dim;
  double c = state->integrator->inertia_coefficient(state->dt);
  int need_mass = c != 0.0 || model->body_force[0] != 0 || model->body_force[1] != 0 || model->body_force[2] != 0;
  if (need_mass) {
    if (!model->element_mass)
      return sk_error_set(SK_ERR_INTERNAL, "body '%s': inertia or body force without the mass (no term declared "
                          "the mass need)", body->name);
    const double *M = model->element_mass + model->element_mass_offset[element];
    /* the load per unit mass at each dof, gathered once (not once per row a: 4 % of a full two-tori run) */
    double load[SK_MAX_NEN * 3];
    for (int kb = 0; kb < n; ++kb) {
      double inertia = 0.0;
      if (c != 0.0) {
        double drift = state->u[dofs[kb]] - state->u_n[dofs[kb]];
        if (state->v_n) drift -= state->dt * state->v_n[dofs[kb]];
        inertia = c * drift;
      }
      load[kb] = inertia - model->body_force[kb % dim];
    }
    for (int a = 0; a < nen; ++a)
      for (int b = 0; b < nen; ++b) {
        const double m = M[a * nen + b];
        for (int i = 0; i < dim; ++i) {
          f[a * dim + i] += m * load[b * dim + i];
          if (K && c != 0.0) K[(a * dim + i) * n + b * dim + i] += c * m;
        }
      }
  }
  return SK_OK;
}

void sk_traction_add(const sk_model *model, int k, double t, double *F) {
  const int dim = model->dim;
  const sk_traction *load = &model->tractions[k];
  double scale = sk_history_value(&load->history, t), traction[3];
  for (int i = 0; i < 3; ++i) traction[i] = scale * load->traction[i];
  const sk_group *g = load->faces;
  for (int e = 0; e < g->n_elems; ++e) {
    double X[SK_MAX_NEN * 3], f[SK_MAX_NEN * 3];
    const int *conn = g->conn + (size_t)e * (size_t)g->nen;
    if (model->node_owner[conn[0]] != model->rank) continue; /* each face once, by the owner of its first node */
    for (int a = 0; a < g->nen; ++a)
      for (int i = 0; i < dim; ++i) X[a * dim + i] = model->X[conn[a] * dim + i];
    sk_face_traction(g->type, dim, X, traction, f);
    for (int a = 0; a < g->nen; ++a)
      for (int i = 0; i < dim; ++i) F[conn[a] * dim + i] -= f[a * dim + i];
  }
}

/* The invariants of body `only` (all bodies when negative), whose nodes `in_body` marks. */
static sk_status invariants(const sk_model *model, int only, const unsigned char *in_body, const double *u,
                            const double *v, sk_invariants *inv) {
  memset(inv, 0, sizeof *inv);
  int dim = model->dim;
  /* M v per owned node (consistent mass: its row is whole on its owner), kinetic energy and momenta */
  for (int a = 0; a < model->n_nodes; ++a) {
    if (model->node_owner[a] != model->rank || (in_body && !in_body[a])) continue;
    double mv[3] = {0, 0, 0};
    for (int64_t k = model->mass_row_ptr[a]; k < model->mass_row_ptr[a + 1]; ++k) {
      int b = model->mass_cols[k];
      for (int i = 0; i < dim; ++i) mv[i] += model->mass_values[k] * v[b * dim + i];
    }
    double q[3] = {0, 0, 0};
    for (int i = 0; i < dim; ++i) {
      q[i] = model->X[a * dim + i] + u[a * dim + i];
      inv->kinetic += 0.5 * v[a * dim + i] * mv[i];
      inv->momentum[i] += mv[i];
    }
    inv->angular_momentum[0] += q[1] * mv[2] - q[2] * mv[1];
    inv->angular_momentum[1] += q[2] * mv[0] - q[0] * mv[2];
    inv->angular_momentum[2] += q[0] * mv[1] - q[1] * mv[0];
  }
  double strain = 0.0;
  int dofs[SK_MAX_NEN * 3];
  for (int e = 0; e < model->n_elements; ++e) {
    if (model->element_part[e] != model->rank) continue;
    const sk_body *body;
    int n = sk_element_dofs(model, e, dofs, &body, NULL);
    if (only >= 0 && body - model->bodies != only) continue;
    double X[SK_MAX_NEN * 3], ue[SK_MAX_NEN * 3], W = 0.0;
    gather(n, dofs, model->X, X);
    gather(n, dofs, u, ue);
    if (sk_solid_internal(&body->solid, X, ue, &W, NULL, NULL) != SK_OK) return inverted(model, body, e);
    strain += W;
  }
  double sums[11] = {inv->kinetic, strain};
  for (int i = 0; i < 3; ++i) {
    sums[2 + i] = inv->momentum[i];
    sums[5 + i] = inv->angular_momentum[i];
  }
  MPI_Allreduce(MPI_IN_PLACE, sums, 8, MPI_DOUBLE, MPI_SUM, model->comm);
  inv->kinetic = sums[0];
  inv->strain = sums[1];
  for (int i = 0; i < 3; ++i) {
    inv->momentum[i] = sums[2 + i];
    inv->angular_momentum[i] = sums[5 + i];
  }
  return SK_OK;
}

sk_status sk_bulk_invariants(const sk_model *model, const double *u, const double *v, sk_invariants *inv) {
  return invariants(model, -1, NULL, u, v, inv);
}

sk_status sk_bulk_body_invariants(const sk_model *model, int body, const double *u, const double *v,
                                  sk_invariants *inv) {
  unsigned char *in_body = calloc((size_t)model->n_nodes + 1, 1);
  if (!in_body) return sk_error_set(SK_ERR_NOMEM, "out of memory for the invariants of body %d", body);
  const sk_group *g = model->bodies[body].group;
  for (int64_t k = 0; k < (int64_t)g->n_elems * g->nen; ++k) in_body[g->conn[k]] = 1;
  const sk_status status = invariants(model, body, in_body, u, v, inv);
  free(in_body);
  return status;
}

sk_status sk_bulk_stress(const sk_model *model, const double *u, double *stress) {
  int dofs[SK_MAX_NEN * 3];
  memset(stress, 0, sizeof(double) * 9 * (size_t)model->n_elements);
  for (int e = 0; e < model->n_elements; ++e) {
    if (model->element_part[e] != model->rank) continue;
    const sk_body *body;
    int n = sk_element_dofs(model, e, dofs, &body, NULL);
    double X[SK_MAX_NEN * 3], ue[SK_MAX_NEN * 3];
    gather(n, dofs, model->X, X);
    gather(n, dofs, u, ue);
    if (sk_solid_cauchy(&body->solid, X, ue, stress + 9 * (size_t)e) != SK_OK) return inverted(model, body, e);
  }
  return SK_OK;
}
