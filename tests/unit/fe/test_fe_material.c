/* Materials: parameter validation and messages, Lame constants, stress = 2 dW/dC and tangent = dS/dE by central
 * differences at a random finite strain, tensor symmetries, the stress-free reference state, and the
 * cancellation-free midpoint remainder used by the discrete gradient. */
#include <string.h>

#include "fe_internal.h"
#include "fe_test_util.h"
#include "sk_test.h"

static void check_validation(void) {
  sk_material mat;
  SK_CHECK(sk_material_init(&mat, SK_MAT_SVK, 210.0, 0.3, 7.8) == SK_OK);
  SK_CHECK_CLOSE(mat.lambda, 210.0 * 0.3 / (1.3 * 0.4), 1e-15);
  SK_CHECK_CLOSE(mat.mu, 210.0 / 2.6, 1e-15);
  SK_CHECK(mat.density == 7.8 && mat.model == SK_MAT_SVK);
  SK_CHECK(sk_material_init(&mat, SK_MAT_SVK, -1.0, 0.3, 1.0) == SK_ERR_INPUT);
  SK_CHECK(strstr(sk_error_message(), "E = -1") != NULL);
  SK_CHECK(sk_material_init(&mat, SK_MAT_SVK, 1.0, 0.5, 1.0) == SK_ERR_INPUT);
  SK_CHECK(strstr(sk_error_message(), "nu = 0.5") != NULL);
  SK_CHECK(sk_material_init(&mat, SK_MAT_SVK, 1.0, -1.0, 1.0) == SK_ERR_INPUT);
  SK_CHECK(sk_material_init(&mat, SK_MAT_SVK, 1.0, NAN, 1.0) == SK_ERR_INPUT);
  SK_CHECK(sk_material_init(&mat, SK_MAT_SVK, 1.0, 0.2, -3.0) == SK_ERR_INPUT);
  SK_CHECK(strstr(sk_error_message(), "density = -3") != NULL);
  SK_CHECK(sk_material_init(&mat, (sk_material_model)7, 1.0, 0.2, 1.0) == SK_ERR_INPUT);
  SK_CHECK(sk_material_init(NULL, SK_MAT_SVK, 1.0, 0.2, 1.0) == SK_ERR_INPUT);
  sk_material_model model = SK_MAT_HOOKE;
  /* Every scene name maps to its model; "neo-hooke" stays the Bonet law of the first releases. */
  for (int m = 0; m < SK_MAT_MODEL_COUNT; ++m)
    SK_CHECK(sk_material_model_from_name(sk_material_model_names[m], &model) == SK_OK && model == (sk_material_model)m);
  SK_CHECK(sk_material_model_from_name("neo-hooke", &model) == SK_OK && model == SK_MAT_NEOHOOKE_BONET);
  SK_CHECK(sk_material_model_from_name("neo-hooke-ciarlet", &model) == SK_OK && model == SK_MAT_NEOHOOKE_CIARLET);
  SK_CHECK(sk_material_model_from_name("svk", &model) == SK_OK && model == SK_MAT_SVK);
  SK_CHECK(sk_material_model_from_name("hooke", &model) == SK_OK && model == SK_MAT_HOOKE);
  SK_CHECK(sk_material_model_from_name("mooney", &model) == SK_ERR_INPUT);
  SK_CHECK(strstr(sk_error_message(), "mooney") != NULL);
  SK_CHECK(strstr(sk_error_message(), "neo-hooke-ciarlet") != NULL);
  SK_CHECK(sk_material_model_from_name(NULL, &model) == SK_ERR_INPUT);
}

/* dW/dh for a symmetric perturbation of C_IJ (and C_JI), central differences. */
static double energy_derivative(const sk_material *mat, const double C[9], int I, int J, double h) {
  double Cp[9], Cm[9], Wp, Wm;
  memcpy(Cp, C, sizeof Cp), memcpy(Cm, C, sizeof Cm);
  Cp[I * 3 + J] += h, Cm[I * 3 + J] -= h;
  if (I != J) Cp[J * 3 + I] += h, Cm[J * 3 + I] -= h;
  sk_material_energy(mat, Cp, &Wp);
  sk_material_energy(mat, Cm, &Wm);
  return (Wp - Wm) / (2 * h);
}

static void check_derivatives(sk_material_model model) {
  sk_material mat;
  SK_CHECK(sk_material_init(&mat, model, 100.0, 0.3, 1.0) == SK_OK);
  for (int trial = 0; trial < 3; ++trial) {
    double F[9], C[9], S[9], CC[81], W;
    fe_random_gradient(3, 0.3, F);
    right_cauchy_green(F, C);
    SK_CHECK(sk_material_energy(&mat, C, &W) == SK_OK);
    SK_CHECK(sk_material_stress(&mat, C, S) == SK_OK);
    SK_CHECK(sk_material_tangent(&mat, C, CC) == SK_OK);
    const double h = 1e-6;
    /* S_IJ = 2 dW/dC_IJ: a symmetric off-diagonal perturbation moves W by S_IJ h. */
    double worst_S = 0.0, Smax = fe_max_abs(S, 9);
    for (int I = 0; I < 3; ++I)
      for (int J = 0; J < 3; ++J) {
        const double fd = (I == J ? 2.0 : 1.0) * energy_derivative(&mat, C, I, J, h);
        worst_S = fmax(worst_S, fabs(fd - S[I * 3 + J]) / Smax);
      }
    /* CC_IJKL = dS_IJ / dE_KL = 2 dS_IJ / dC_KL (symmetric perturbation of C_KL counts twice off-diagonal). */
    double worst_CC = 0.0, CCmax = fe_max_abs(CC, 81), asym = 0.0;
    for (int K = 0; K < 3; ++K)
      for (int L = 0; L < 3; ++L) {
        double Cp[9], Cm[9], Sp[9], Sm[9];
        memcpy(Cp, C, sizeof Cp), memcpy(Cm, C, sizeof Cm);
        Cp[K * 3 + L] += h, Cm[K * 3 + L] -= h;
        if (K != L) Cp[L * 3 + K] += h, Cm[L * 3 + K] -= h;
        sk_material_stress(&mat, Cp, Sp);
        sk_material_stress(&mat, Cm, Sm);
        for (int IJ = 0; IJ < 9; ++IJ) {
          const double fd = (K == L ? 2.0 : 1.0) * (Sp[IJ] - Sm[IJ]) / (2 * h);
          const double analytic = K == L ? CC[IJ * 9 + K * 3 + L] : CC[IJ * 9 + K * 3 + L] + CC[IJ * 9 + L * 3 + K];
          worst_CC = fmax(worst_CC, fabs((K == L ? fd : 2.0 * fd) - analytic) / CCmax);
        }
      }
    for (int I = 0; I < 3; ++I)
      for (int J = 0; J < 3; ++J)
        for (int K = 0; K < 3; ++K)
          for (int L = 0; L < 3; ++L) {
            const double c = CC[((I * 3 + J) * 3 + K) * 3 + L];
            asym = fmax(asym, fabs(c - CC[((J * 3 + I) * 3 + K) * 3 + L]));
            asym = fmax(asym, fabs(c - CC[((I * 3 + J) * 3 + L) * 3 + K]));
            asym = fmax(asym, fabs(c - CC[((K * 3 + L) * 3 + I) * 3 + J]));
          }
    if (trial == 0) printf("  %-9s relative FD error: S %.2e  CC %.2e\n", sk_material_model_names[model], worst_S, worst_CC);
    SK_CHECK(worst_S < 1e-8);
    SK_CHECK(worst_CC < 1e-8);
    SK_CHECK(asym < 1e-12 * CCmax);
  }
  /* Reference state: no energy, no stress, and the tangent is the isotropic Hooke tensor. */
  const double I3[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  double W = 1.0, S[9], CC[81];
  SK_CHECK(sk_material_energy(&mat, I3, &W) == SK_OK);
  sk_material_stress(&mat, I3, S);
  sk_material_tangent(&mat, I3, CC);
  SK_CHECK(fabs(W) < 1e-14);
  SK_CHECK(fe_max_abs(S, 9) < 1e-13);
  double worst = 0.0;
  for (int I = 0; I < 3; ++I)
    for (int J = 0; J < 3; ++J)
      for (int K = 0; K < 3; ++K)
        for (int L = 0; L < 3; ++L) {
          const double hooke =
              mat.lambda * (I == J) * (K == L) + mat.mu * ((I == K) * (J == L) + (I == L) * (J == K));
          worst = fmax(worst, fabs(CC[((I * 3 + J) * 3 + K) * 3 + L] - hooke));
        }
  SK_CHECK(worst < 1e-12 * mat.mu);
}

/* The remainder W1 - W0 - S(Cm):dC/2 agrees with the naive difference for a large step and scales as |dC|^3
 * (the naive difference would be round-off noise of size eps*W there). */
static void check_midpoint_remainder(sk_material_model model) {
  sk_material mat;
  sk_material_init(&mat, model, 100.0, 0.3, 1.0);
  double F0[9], F1[9], C0[9], C1[9], Cm[9], Sm[9], W0, W1;
  fe_random_gradient(3, 0.3, F0);
  fe_random_gradient(3, 0.3, F1);
  right_cauchy_green(F0, C0);
  right_cauchy_green(F1, C1);
  for (int i = 0; i < 9; ++i) Cm[i] = 0.5 * (C0[i] + C1[i]);
  sk_material_energy(&mat, C0, &W0);
  sk_material_energy(&mat, C1, &W1);
  sk_material_stress(&mat, Cm, Sm);
  double naive = W1 - W0;
  for (int i = 0; i < 9; ++i) naive -= 0.5 * Sm[i] * (C1[i] - C0[i]);
  const double r = sk_fe_material_midpoint_remainder(&mat, C0, C1, Cm);
  SK_CHECK(fabs(naive) > 1e-3 * fabs(W1));
  SK_CHECK_CLOSE(r, naive, 1e-12 * fabs(W1));
  double previous = 0.0;
  for (int step = 0; step < 4; ++step) { /* dC -> dC / 10: r / 1000 */
    const double scale = pow(10.0, -2 - step);
    double Ct[9], Ctm[9];
    for (int i = 0; i < 9; ++i) {
      Ct[i] = C0[i] + scale * (C1[i] - C0[i]);
      Ctm[i] = 0.5 * (C0[i] + Ct[i]);
    }
    const double rt = sk_fe_material_midpoint_remainder(&mat, C0, Ct, Ctm);
    if (step > 0) SK_CHECK_CLOSE(previous / rt, 1000.0, 1e-2 * 1000.0);
    previous = rt;
  }
  sk_material svk;
  sk_material_init(&svk, SK_MAT_SVK, 100.0, 0.3, 1.0);
  SK_CHECK(sk_fe_material_midpoint_remainder(&svk, C0, C1, Cm) == 0.0);
}

/* The energies are the documented formulas (docs/theory/elements.md), evaluated here independently at a
 * stretch diag(a, b, c), and the two Neo-Hooke laws part at finite volume change. */
static void check_energy_formulas(void) {
  const double a = 1.3, b = 0.8, c = 1.1, J = a * b * c, trC = a * a + b * b + c * c;
  const double C[9] = {a * a, 0, 0, 0, b * b, 0, 0, 0, c * c};
  sk_material bonet, ciarlet, svk;
  sk_material_init(&bonet, SK_MAT_NEOHOOKE_BONET, 100.0, 0.3, 1.0);
  sk_material_init(&ciarlet, SK_MAT_NEOHOOKE_CIARLET, 100.0, 0.3, 1.0);
  sk_material_init(&svk, SK_MAT_SVK, 100.0, 0.3, 1.0);
  const double mu = bonet.mu, lambda = bonet.lambda, lnJ = log(J);
  const double expected_bonet = mu / 2 * (trC - 3) - mu * lnJ + lambda / 2 * lnJ * lnJ;
  const double expected_ciarlet = mu / 2 * (trC - 3) - mu * lnJ + lambda / 4 * (J * J - 1) - lambda / 2 * lnJ;
  const double E[3] = {(a * a - 1) / 2, (b * b - 1) / 2, (c * c - 1) / 2}, trE = E[0] + E[1] + E[2];
  const double expected_svk = lambda / 2 * trE * trE + mu * (E[0] * E[0] + E[1] * E[1] + E[2] * E[2]);
  double W_bonet, W_ciarlet, W_svk;
  SK_CHECK(sk_material_energy(&bonet, C, &W_bonet) == SK_OK);
  SK_CHECK(sk_material_energy(&ciarlet, C, &W_ciarlet) == SK_OK);
  SK_CHECK(sk_material_energy(&svk, C, &W_svk) == SK_OK);
  SK_CHECK_CLOSE(W_bonet, expected_bonet, 1e-14 * fabs(expected_bonet));
  SK_CHECK_CLOSE(W_ciarlet, expected_ciarlet, 1e-14 * fabs(expected_ciarlet));
  SK_CHECK_CLOSE(W_svk, expected_svk, 1e-14 * fabs(expected_svk));
  printf("  W at stretch (%.1f, %.1f, %.1f), J = %.3f: neo-hooke-bonet %.6f, neo-hooke-ciarlet %.6f\n", a, b, c, J,
         W_bonet, W_ciarlet);
  SK_CHECK(fabs(W_ciarlet - W_bonet) > 1e-3 * W_bonet);
}

int main(void) {
  check_validation();
  for (int m = SK_MAT_HOOKE; m < SK_MAT_MODEL_COUNT; ++m) check_derivatives((sk_material_model)m);
  check_energy_formulas();
  for (int m = SK_MAT_NEOHOOKE_BONET; m <= SK_MAT_NEOHOOKE_CIARLET; ++m) {
    check_midpoint_remainder((sk_material_model)m);
    /* The Neo-Hooke laws reject det C <= 0 as an inverted point. */
    sk_material nh;
    sk_material_init(&nh, (sk_material_model)m, 1.0, 0.3, 1.0);
    const double Cbad[9] = {1, 0, 0, 0, -1, 0, 0, 0, 1};
    double W, S[9], CC[81];
    SK_CHECK(sk_material_energy(&nh, Cbad, &W) == SK_ERR_INVERTED);
    SK_CHECK(sk_material_stress(&nh, Cbad, S) == SK_ERR_INVERTED);
    SK_CHECK(sk_material_tangent(&nh, Cbad, CC) == SK_ERR_INVERTED);
    SK_CHECK(strstr(sk_error_message(), "det C") != NULL);
    SK_CHECK(strstr(sk_error_message(), sk_material_model_names[m]) != NULL);
    SK_CHECK(sk_material_energy(&nh, NULL, &W) == SK_ERR_INPUT);
  }
  return sk_test_finish("fe_material");
}
