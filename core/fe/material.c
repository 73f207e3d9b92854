/* Hyperelastic materials: Hooke (small strain), Saint Venant-Kirchhoff, and two compressible Neo-Hooke laws that
 * share the isochoric part and differ in the volumetric one (docs/theory/elements.md#materials). */
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
  if ((int)model < SK_MAT_HOOKE || model >= SK_MAT_MODEL_COUNT)
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

const char *const sk_material_model_names[] = {
    [SK_MAT_HOOKE] = "hooke",
    [SK_MAT_SVK] = "svk",
    [SK_MAT_NEOHOOKE_BONET] = "neo-hooke-bonet",
    [SK_MAT_NEOHOOKE_CIARLET] = "neo-hooke-ciarlet",
    [SK_MAT_MODEL_COUNT] = "neo-hooke", /* alias, see material_aliases */
    NULL};
/* Models of the alias names, which follow the SK_MAT_MODEL_COUNT model names in sk_material_model_names. */
static const sk_material_model material_aliases[] = {SK_MAT_NEOHOOKE_BONET};

sk_status sk_material_model_from_name(const char *name, sk_material_model *model) {
  if (!name || !model) return sk_error_set(SK_ERR_INPUT, "material: NULL model name");
  for (int i = 0; sk_material_model_names[i]; ++i) {
    if (strcmp(name, sk_material_model_names[i]) == 0) {
      *model = i < SK_MAT_MODEL_COUNT ? (sk_material_model)i : material_aliases[i - SK_MAT_MODEL_COUNT];
      return SK_OK;
    }
  }
  return sk_error_set(SK_ERR_INPUT,
                      "material: unknown model '%s' (expected hooke, svk, neo-hooke-bonet, neo-hooke-ciarlet or "
                      "neo-hooke)",
                      name);
}

int sk_fe_material_is_quadratic(const sk_material *mat) {
  return mat->model == SK_MAT_HOOKE || mat->model == SK_MAT_SVK;
}

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

/* The two Neo-Hooke laws are W = mu/2 (tr C - 3) - mu ln J + U(J) with the volumetric part
 *   Bonet:   U = lambda/2 (ln J)^2,                 p = J U' = lambda ln J,        J p' = lambda
 *   Ciarlet: U = lambda/4 (J^2 - 1) - lambda/2 ln J, p = J U' = lambda/2 (J^2 - 1), J p' = lambda J^2
 * (both linearise to Hooke with the same lambda, mu; they part at finite volume change). With dJ/dC = J C^-1 / 2,
 *   S  = mu (I - C^-1) + p C^-1,
 *   CC = J p' C^-1 (x) C^-1 + (mu - p) (C^-1_IK C^-1_JL + C^-1_IL C^-1_JK). */
typedef struct {
  double U, p, Jdp; /* U(J), J U'(J), J dp/dJ */
} volumetric_part;

static volumetric_part neohooke_volumetric(const sk_material *mat, double detC) {
  const double lambda = mat->lambda, lnJ = 0.5 * log(detC);
  if (mat->model == SK_MAT_NEOHOOKE_CIARLET)
    return (volumetric_part){0.25 * lambda * (detC - 1.0) - 0.5 * lambda * lnJ, 0.5 * lambda * (detC - 1.0),
                             lambda * detC};
  return (volumetric_part){0.5 * lambda * lnJ * lnJ, lambda * lnJ, lambda};
}

static sk_status neohooke_eval(const sk_material *mat, const double C[9], double *W, double S[9], double D[36]) {
  const double detC = sk_fe_det3(C);
  if (!(detC > 0.0))
    return sk_error_set(SK_ERR_INVERTED, "%s: det C = %g <= 0 (inverted material point)",
                        sk_material_model_names[mat->model], detC);
  const volumetric_part vol = neohooke_volumetric(mat, detC);
  double Ci[9];
  sk_fe_inverse3(C, detC, Ci);
  if (W) *W = 0.5 * mat->mu * (C[0] + C[4] + C[8] - 3.0) - 0.5 * mat->mu * log(detC) + vol.U;
  if (S) {
    for (int i = 0; i < 9; ++i) S[i] = (vol.p - mat->mu) * Ci[i];
    S[0] += mat->mu, S[4] += mat->mu, S[8] += mat->mu;
  }
  if (D) {
    const double shear = mat->mu - vol.p;
    for (int a = 0; a < FE_VOIGT; ++a) {
      const int I = voigt_i[a], J = voigt_j[a];
      for (int b = 0; b < FE_VOIGT; ++b) {
        const int K = voigt_i[b], L = voigt_j[b];
        D[a * 6 + b] = vol.Jdp * Ci[I * 3 + J] * Ci[K * 3 + L] +
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
    case SK_MAT_NEOHOOKE_BONET:
    case SK_MAT_NEOHOOKE_CIARLET:
      return neohooke_eval(mat, C, W, S, D);
    case SK_MAT_MODEL_COUNT:
      break;
  }
  return sk_error_set(SK_ERR_INPUT, "material: unknown model %d", (int)mat->model);
}

double sk_fe_material_midpoint_remainder(const sk_material *mat, const double C0[9], const double C1[9],
                                         const double Cm[9]) {
  if (sk_fe_material_is_quadratic(mat)) return 0.0;
  /* Neo-Hooke. The tr C terms cancel exactly; with dl = ln J1 - ln J0 and A = Cm^-1 : dC what remains is
   *   r = -mu (dl - A/2) + U(J1) - U(J0) - p(Jm) A/2.
   * dl comes from log1p of det C1 / det C0 - 1, whose numerator ddet is expanded in dC (3x3 identity
   * det(A + D) = det A + tr(adj(A) D) + tr(adj(D) A) + det D) so that no O(1) quantities cancel. */
  double dC[9], adj0[9], adjd[9], Cmi[9];
  for (int i = 0; i < 9; ++i) dC[i] = C1[i] - C0[i];
  adjugate3(C0, adj0);
  adjugate3(dC, adjd);
  const double det0 = sk_fe_det3(C0), detm = sk_fe_det3(Cm), detd = sk_fe_det3(dC);
  const double ddet = trace_product(adj0, dC) + trace_product(adjd, C0) + detd;
  const double dl = 0.5 * log1p(ddet / det0);
  sk_fe_inverse3(Cm, detm, Cmi);
  double A = 0.0;
  for (int i = 0; i < 9; ++i) A += Cmi[i] * dC[i];
  if (mat->model == SK_MAT_NEOHOOKE_CIARLET) {
    /* U1 - U0 - pm A/2 = lambda/4 (ddet - detm A) - lambda/2 dl, and the same identity about Cm gives
     * ddet = det(Cm + dC/2) - det(Cm - dC/2) = detm A + det(dC)/4 exactly: no cancellation at all. */
    return -(mat->mu + 0.5 * mat->lambda) * (dl - 0.5 * A) + mat->lambda * detd / 16.0;
  }
  /* Bonet: U1 - U0 - pm A/2 = lambda/2 (dl (l0 + l1) - lm A). */
  const double l0 = 0.5 * log(det0), lm = 0.5 * log(detm), l1 = l0 + dl;
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
