/* Energy-momentum midpoint force (Gonzalez discrete gradient): f.(u1 - u0) = W(u1) - W(u0) to round-off at large
 * strain, K = df/du1 against central differences, zero total force and zero total moment about the midpoint
 * configuration, the limit u1 -> u0 (force of the midpoint state, half the stiffness), and accuracy for tiny
 * steps (no cancellation blow-up of the correction); the kernels on a cached reference geometry equal the
 * coordinate-taking ones bitwise. */
#include <string.h>

#include "fe_test_util.h"
#include "sk_test.h"

static sk_material materials[SK_MAT_MODEL_COUNT];

/* The kernels on a precomputed reference geometry (what a body caches) give bitwise the results of the
 * coordinate-taking kernels, f and K of the midpoint force and W, f, K of the state. */
static void check_cached_geometry(const sk_solid *el, const double *X, const double *u0, const double *u1,
                                  const double *f, const double *K) {
  const int ndof = sk_elem_nen(el->type) * el->dim;
  static double geometry[SK_MAX_QP * (SK_MAX_NEN * 3 + 1)], Kc[SK_MAX_NEN * 3 * SK_MAX_NEN * 3],
      Kx[SK_MAX_NEN * 3 * SK_MAX_NEN * 3];
  double fc[SK_MAX_NEN * 3], fx[SK_MAX_NEN * 3], Wc = 0.0, Wx = 0.0;
  SK_CHECK(sk_solid_geometry_size(el) <= (int)(sizeof geometry / sizeof *geometry));
  SK_CHECK(sk_solid_geometry(el, X, geometry) == SK_OK);
  SK_CHECK(sk_solid_internal_midpoint_at(el, geometry, u0, u1, fc, Kc) == SK_OK);
  SK_CHECK(memcmp(fc, f, sizeof(double) * (size_t)ndof) == 0);
  SK_CHECK(memcmp(Kc, K, sizeof(double) * (size_t)ndof * (size_t)ndof) == 0);
  SK_CHECK(sk_solid_internal_at(el, geometry, u1, &Wc, fc, Kc) == SK_OK);
  SK_CHECK(sk_solid_internal(el, X, u1, &Wx, fx, Kx) == SK_OK);
  SK_CHECK(Wc == Wx && memcmp(fc, fx, sizeof(double) * (size_t)ndof) == 0);
  SK_CHECK(memcmp(Kc, Kx, sizeof(double) * (size_t)ndof * (size_t)ndof) == 0);
}

static void check_midpoint(sk_elem_type type, int dim, const sk_material *mat) {
  const int nen = sk_elem_nen(type), ndof = nen * dim;
  const sk_solid el = {type, dim, mat};
  double X[SK_MAX_NEN * 3], u0[SK_MAX_NEN * 3], u1[SK_MAX_NEN * 3], F0[9], F1[9];
  double f[SK_MAX_NEN * 3], fp[SK_MAX_NEN * 3], fm[SK_MAX_NEN * 3];
  static double K[SK_MAX_NEN * 3 * SK_MAX_NEN * 3], Kfull[SK_MAX_NEN * 3 * SK_MAX_NEN * 3];
  fe_distorted_element(type, dim, 0.08, X);
  /* Large strains and a large step between them, drawn again in the rare case that the two states happen to
   * store nearly the same energy (the energy check would then test little). */
  double W0 = 0.0, W1 = 0.0;
  for (int draw = 0; draw < 5; ++draw) {
    fe_random_gradient(dim, 0.3, F0);
    fe_random_gradient(dim, 0.3, F1);
    fe_linear_displacement(dim, nen, F0, X, u0);
    fe_linear_displacement(dim, nen, F1, X, u1);
    for (int i = 0; i < ndof; ++i) u0[i] += 0.03 * fe_rand(), u1[i] += 0.03 * fe_rand();
    SK_CHECK(sk_solid_internal(&el, X, u0, &W0, NULL, NULL) == SK_OK);
    SK_CHECK(sk_solid_internal(&el, X, u1, &W1, NULL, NULL) == SK_OK);
    if (fabs(W1 - W0) > 1e-2 * (fabs(W0) + fabs(W1))) break;
  }
  SK_CHECK(sk_solid_internal_midpoint(&el, X, u0, u1, f, K) == SK_OK);
  check_cached_geometry(&el, X, u0, u1, f, K);
  double work = 0.0;
  for (int i = 0; i < ndof; ++i) work += f[i] * (u1[i] - u0[i]);
  const double energy_error = fabs(work - (W1 - W0)) / (fabs(W0) + fabs(W1));
  SK_CHECK(fabs(W1 - W0) > 1e-2 * (fabs(W0) + fabs(W1))); /* a genuine energy change */
  SK_CHECK(energy_error < 1e-12);

  /* K = df/du1. */
  const double h = 1e-6, Kmax = fe_max_abs(K, ndof * ndof);
  double err_K = 0.0;
  for (int j = 0; j < ndof; ++j) {
    const double keep = u1[j];
    u1[j] = keep + h;
    sk_solid_internal_midpoint(&el, X, u0, u1, fp, NULL);
    u1[j] = keep - h;
    sk_solid_internal_midpoint(&el, X, u0, u1, fm, NULL);
    u1[j] = keep;
    for (int i = 0; i < ndof; ++i) err_K = fmax(err_K, fabs((fp[i] - fm[i]) / (2 * h) - K[i * ndof + j]) / Kmax);
  }
  SK_CHECK(err_K < 1e-7);

  /* Invariants: sum_a f_a = 0 and sum_a x_mid,a x f_a = 0 with x_mid = X + (u0 + u1)/2. */
  const double fscale = fe_max_abs(f, ndof);
  double force[3] = {0, 0, 0}, moment[3] = {0, 0, 0};
  for (int a = 0; a < nen; ++a) {
    double x[3] = {0, 0, 0}, fa[3] = {0, 0, 0};
    for (int i = 0; i < dim; ++i) {
      x[i] = X[a * dim + i] + 0.5 * (u0[a * dim + i] + u1[a * dim + i]);
      fa[i] = f[a * dim + i];
      force[i] += fa[i];
    }
    moment[0] += x[1] * fa[2] - x[2] * fa[1];
    moment[1] += x[2] * fa[0] - x[0] * fa[2];
    moment[2] += x[0] * fa[1] - x[1] * fa[0];
  }
  const double xscale = fe_max_abs(X, ndof) + fe_max_abs(u1, ndof);
  double worst_force = 0.0, worst_moment = 0.0;
  for (int i = 0; i < 3; ++i) {
    worst_force = fmax(worst_force, fabs(force[i]) / fscale);
    worst_moment = fmax(worst_moment, fabs(moment[i]) / (fscale * xscale));
  }
  SK_CHECK(worst_force < 1e-13);
  if (mat->model != SK_MAT_HOOKE) SK_CHECK(worst_moment < 1e-13); /* linearised kinematics is not objective */

  /* u1 = u0: the force of that state and half its stiffness (d/du1 of a midpoint quantity). */
  double f_state[SK_MAX_NEN * 3];
  SK_CHECK(sk_solid_internal(&el, X, u0, NULL, f_state, Kfull) == SK_OK);
  SK_CHECK(sk_solid_internal_midpoint(&el, X, u0, u0, f, K) == SK_OK);
  double err_same_f = 0.0, err_same_K = 0.0;
  for (int i = 0; i < ndof; ++i) err_same_f = fmax(err_same_f, fabs(f[i] - f_state[i]));
  for (int i = 0; i < ndof * ndof; ++i) err_same_K = fmax(err_same_K, fabs(K[i] - 0.5 * Kfull[i]));
  SK_CHECK(err_same_f < 1e-13 * fe_max_abs(f_state, ndof));
  SK_CHECK(err_same_K < 1e-13 * fe_max_abs(Kfull, ndof * ndof));

  /* A tiny step (|dC| ~ 1e-7, above the drop threshold): the force equals the force at the midpoint state to
   * O(|dC|^2); a naive W1 - W0 in the correction would add round-off of size eps W / |dC| ~ 1e-9. */
  double du[SK_MAX_NEN * 3], u_half[SK_MAX_NEN * 3];
  for (int i = 0; i < ndof; ++i) {
    du[i] = 1e-7 * fe_rand();
    u1[i] = u0[i] + du[i];
    u_half[i] = u0[i] + 0.5 * du[i];
  }
  SK_CHECK(sk_solid_internal_midpoint(&el, X, u0, u1, f, NULL) == SK_OK);
  SK_CHECK(sk_solid_internal(&el, X, u_half, NULL, f_state, NULL) == SK_OK);
  double err_tiny = 0.0;
  for (int i = 0; i < ndof; ++i) err_tiny = fmax(err_tiny, fabs(f[i] - f_state[i]));
  err_tiny /= fe_max_abs(f_state, ndof);
  SK_CHECK(err_tiny < 1e-12);

  printf("  %dD %-6s %-9s |f.du - dW| / |W| %.1e  K FD %.1e  sum f %.1e  sum x x f %.1e  tiny step %.1e\n", dim,
         sk_elem_name(type), sk_material_model_names[mat->model], energy_error, err_K, worst_force, worst_moment,
         err_tiny);

  /* An inverted end state is reported and leaves the outputs alone. */
  if (mat->model != SK_MAT_HOOKE) {
    const double Fr[9] = {-1, 0, 0, 0, 1, 0, 0, 0, 1};
    fe_linear_displacement(dim, nen, Fr, X, u1);
    f[0] = 42.0;
    SK_CHECK(sk_solid_internal_midpoint(&el, X, u0, u1, f, K) == SK_ERR_INVERTED);
    SK_CHECK(f[0] == 42.0);
  }
}

int main(void) {
  for (int m = SK_MAT_HOOKE; m < SK_MAT_MODEL_COUNT; ++m)
    if (sk_material_init(&materials[m], (sk_material_model)m, 100.0, 0.3, 1.0) != SK_OK) return 1;
  for (int dim = 2; dim <= 3; ++dim)
    for (int t = 0; t < FE_N_SOLIDS; ++t)
      for (int m = 0; m < SK_MAT_MODEL_COUNT; ++m)
        check_midpoint(dim == 2 ? fe_solids_2d[t] : fe_solids_3d[t], dim, &materials[m]);
  return sk_test_finish("fe_midpoint");
}
