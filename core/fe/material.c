/* Hyperelastic materials: Hooke (small strain), Saint Venant-Kirchhoff, compressible Neo-Hooke. */
#include <math.h>
#include <string.h>

#include "fe_internal.h"

static const int voigt_i[FE_VOIGT] = {0, 1, 2, 0, 1, 0};
static const int voigt_j[FE_VOIGT] = {0, 1, 2, 1, 2, 2};

double sk_fe_det3(const double A[9]) {
  return A[0] * (A[4] * A[8] - A[5] * A[7]) - A[1] * (A[3] * A[8] - A[5] * A[6]) +
         A[2] * (A[3] * A[7] - A[4] * A[6]);
}

/* Adjugate (transpose of the cofactor matrix): A adj(A) = det(A) I. */
static void adjugate3(const double A[9], double adj[9]) {
  adj[0] = A[4] * A[8] - A[5] * A[7];
  adj[1] = A[2] * A[7] - A[1] * A[8];
  adj[2] = A[1] * A[5] - A[2] * A[4];
  adj[3] = A[5] * A[6] - A[3] * A[8];
  adj[4] = A[0] * A[8] - A[2] * A[6];
  adj[5] = A[2] * A[3] - A[0] * A[5];
  adj[6] = A[3] * A[7] - A[4] * A[6];
  adj[7] = A[1] * A[6] - A[0] * A[7];
  adj[8] = A[0] * A[4] - A[1] * A[3];
}

void sk_fe_inverse3(const double A[9], double det, double Ainv[9]) {
  adjugate3(A, Ainv);
  const double inv_det = 1.0 / det;
  for (int i = 0; i < 9; ++i) Ainv[i] *= inv_det;
}

static double trace_product(const double A[9], const double B[9]) { /* tr(A B) */
  double sum = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) sum += A[i * 3 + k] * B[k * 3 + i];
  return sum;
}

sk_status sk_material_init(sk_material *mat, sk_material_model model, double E, double nu, double density) {
  if (!mat) return sk_error_set(SK_ERR_INPUT, "material: NULL material");
  if ((int)model < SK_MAT_HOOKE || model > SK_MAT_NEOHOOKE)
    return sk_error_set(SK_ERR_INPUT, "material: unknown model %d", (int)model);
  if (!(E > 0.0) || !isfinite(E))
    return sk_error_set(SK_ERR_INPUT, "material: Young's modulus E = %g must be finite and > 0", E);
  if (!(nu > -1.0 && nu < 0.5))
    return sk_error_set(SK_ERR_INPUT, "material: Poisson's ratio nu = %g must satisfy -1 < nu < 0.5", nu);
  if (!(density >= 0.0) || !isfinite(density))
    return sk_error_set(SK_ERR_INPUT, "material: density = %g must be finite and >= 0", density);
  mat->model = model;
  mat->E = E;
  mat->nu = nu;
  mat->lambda = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
  mat->mu = E / (2.0 * (1.0 + nu));
  mat->density = density;
  return SK_OK;
}

sk_status sk_material_model_from_name(const char *name, sk_material_model *model) {
  static const struct {
    const char *name;
    sk_material_model model;
  } names[] = {{"hooke", SK_MAT_HOOKE}, {"svk", SK_MAT_SVK}, {"neo-hooke", SK_MAT_NEOHOOKE}};
  if (!name || !model) return sk_error_set(SK_ERR_INPUT, "material: NULL model name");
  for (size_t i = 0; i < sizeof names / sizeof names[0]; ++i) {
    if (strcmp(name, names[i].name) == 0) {
      *model = names[i].model;
      return SK_OK;
    }
  }
  return sk_error_set(SK_ERR_INPUT, "material: unknown model '%s' (expected hooke, svk or neo-hooke)", name);
}

int sk_fe_material_is_quadratic(const sk_material *mat) { return mat->model != SK_MAT_NEOHOOKE; }

/* W = lambda/2 (tr E)^2 + mu E:E with E = (C - I)/2; Hooke is the same function of eps = (C - I)/2. */
static void quadratic_eval(const sk_material *mat, const double C[9], double *W, double S[9], double D[36]) {
  double E[9];
  for (int i = 0; i < 9; ++i) E[i] = 0.5 * C[i];
  E[0] -= 0.5, E[4] -= 0.5, E[8] -= 0.5;
  const double trE = E[0] + E[4] + E[8];
  if (W) {
    double EE = 0.0;
    for (int i = 0; i < 9; ++i) EE += E[i] * E[i];
    *W = 0.5 * mat->lambda * trE * trE + mat->mu * EE;
  }
  if (S) {
    for (int i = 0; i < 9; ++i) S[i] = 2.0 * mat->mu * E[i];
    S[0] += mat->lambda * trE, S[4] += mat->lambda * trE, S[8] += mat->lambda * trE;
  }
  if (D) {
    memset(D, 0, 36 * sizeof *D);
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) D[a * 6 + b] = mat->lambda;
      D[a * 6 + a] += 2.0 * mat->mu;
      D[(a + 3) * 6 + a + 3] = mat->mu;
    }
  }
}

/* W = mu/2 (tr C - 3) - mu ln J + lambda/2 (ln J)^2; S = mu (I - C^-1) + lambda ln J C^-1;
 * CC = lambda C^-1 (x) C^-1 + (mu - lambda ln J) (C^-1_IK C^-1_JL + C^-1_IL C^-1_JK). */
static sk_status neohooke_eval(const sk_material *mat, const double C[9], double *W, double S[9], double D[36]) {
  const double detC = sk_fe_det3(C);
  if (!(detC > 0.0))
    return sk_error_set(SK_ERR_INVERTED, "neo-hooke: det C = %g <= 0 (inverted material point)", detC);
  const double lnJ = 0.5 * log(detC);
  double Ci[9];
  sk_fe_inverse3(C, detC, Ci);
  if (W) *W = 0.5 * mat->mu * (C[0] + C[4] + C[8] - 3.0) - mat->mu * lnJ + 0.5 * mat->lambda * lnJ * lnJ;
  if (S) {
    for (int i = 0; i < 9; ++i) S[i] = (mat->lambda * lnJ - mat->mu) * Ci[i];
    S[0] += mat->mu, S[4] += mat->mu, S[8] += mat->mu;
  }
  if (D) {
    const double shear = mat->mu - mat->lambda * lnJ;
    for (int a = 0; a < FE_VOIGT; ++a) {
      const int I = voigt_i[a], J = voigt_j[a];
      for (int b = 0; b < FE_VOIGT; ++b) {
        const int K = voigt_i[b], L = voigt_j[b];
        D[a * 6 + b] = mat->lambda * Ci[I * 3 + J] * Ci[K * 3 + L] +
                       shear * (Ci[I * 3 + K] * Ci[J * 3 + L] + Ci[I * 3 + L] * Ci[J * 3 + K]);
      }
    }
  }
  return SK_OK;
}

sk_status sk_fe_material_eval(const sk_material *mat, const double C[9], double *W, double S[9], double D[36]) {
  switch (mat->model) {
    case SK_MAT_HOOKE:
    case SK_MAT_SVK:
      quadratic_eval(mat, C, W, S, D);
      return SK_OK;
    case SK_MAT_NEOHOOKE:
      return neohooke_eval(mat, C, W, S, D);
  }
  return sk_error_set(SK_ERR_INPUT, "material: unknown model %d", (int)mat->model);
}

double sk_fe_material_midpoint_remainder(const sk_material *mat, const double C0[9], const double C1[9],
                                         const double Cm[9]) {
  if (sk_fe_material_is_quadratic(mat)) return 0.0;
  /* Neo-Hooke. The tr C terms cancel exactly; what remains is
   *   r = -mu (dl - A/2) + lambda/2 (dl (l0 + l1) - lm A),  dl = ln J1 - ln J0,  A = Cm^-1 : dC.
   * dl comes from log1p of det C1 / det C0 - 1, whose numerator is expanded in dC (3x3 identity
   * det(A + D) = det A + tr(adj(A) D) + tr(adj(D) A) + det D) so that no O(1) quantities cancel. */
  double dC[9], adj0[9], adjd[9], Cmi[9];
  for (int i = 0; i < 9; ++i) dC[i] = C1[i] - C0[i];
  adjugate3(C0, adj0);
  adjugate3(dC, adjd);
  const double det0 = sk_fe_det3(C0), detm = sk_fe_det3(Cm);
  const double ddet = trace_product(adj0, dC) + trace_product(adjd, C0) + sk_fe_det3(dC);
  const double dl = 0.5 * log1p(ddet / det0);
  const double l0 = 0.5 * log(det0), lm = 0.5 * log(detm), l1 = l0 + dl;
  sk_fe_inverse3(Cm, detm, Cmi);
  double A = 0.0;
  for (int i = 0; i < 9; ++i) A += Cmi[i] * dC[i];
  return -mat->mu * (dl - 0.5 * A) + 0.5 * mat->lambda * (dl * (l0 + l1) - lm * A);
}

static sk_status check_args(const sk_material *mat, const double *C, const void *out) {
  if (!mat || !C || !out) return sk_error_set(SK_ERR_INPUT, "material: NULL argument");
  return SK_OK;
}

sk_status sk_material_energy(const sk_material *mat, const double C[9], double *W) {
  SK_TRY(check_args(mat, C, W));
  return sk_fe_material_eval(mat, C, W, NULL, NULL);
}

sk_status sk_material_stress(const sk_material *mat, const double C[9], double S[9]) {
  SK_TRY(check_args(mat, C, S));
  return sk_fe_material_eval(mat, C, NULL, S, NULL);
}

sk_status sk_material_tangent(const sk_material *mat, const double C[9], double CC[81]) {
  SK_TRY(check_args(mat, C, CC));
  double D[36];
  SK_TRY(sk_fe_material_eval(mat, C, NULL, NULL, D));
  static const int voigt_of[3][3] = {{0, 3, 5}, {3, 1, 4}, {5, 4, 2}};
  for (int I = 0; I < 3; ++I)
    for (int J = 0; J < 3; ++J)
      for (int K = 0; K < 3; ++K)
        for (int L = 0; L < 3; ++L) CC[((I * 3 + J) * 3 + K) * 3 + L] = D[voigt_of[I][J] * 6 + voigt_of[K][L]];
  return SK_OK;
}
