/* Internals shared by the fe module's sources (not installed, not part of the public API). */
#ifndef STICKSLIP_FE_INTERNAL_H
#define STICKSLIP_FE_INTERNAL_H

#include "stickslip/fe.h"

/* Voigt order of symmetric 3x3 tensors used inside the kernels: (00, 11, 22, 01, 12, 02). */
enum { FE_VOIGT = 6 };

/* Energy W, stress S (3x3) and tangent D (Voigt 6x6, D[a*6+b] = CC_{IJKL} for a = (IJ), b = (KL)) at C; any
 * output may be NULL. HOOKE reads C as I + 2 eps. Returns SK_ERR_INVERTED (message set) if det C <= 0 where the
 * model needs it. */
sk_status sk_fe_material_eval(const sk_material *mat, const double C[9], double *W, double S[9], double D[36]);

/* Whether W is quadratic in C (HOOKE, SVK): then S(C_mid) is already the exact discrete gradient. */
int sk_fe_material_is_quadratic(const sk_material *mat);

/* W(C1) - W(C0) - S(Cm):(C1 - C0)/2 with Cm = (C0 + C1)/2, evaluated without the cancellation of the naive
 * difference (the result is O(|C1 - C0|^3)). Only for models that are not quadratic. */
double sk_fe_material_midpoint_remainder(const sk_material *mat, const double C0[9], const double C1[9],
                                         const double Cm[9]);

double sk_fe_det3(const double A[9]);
/* Inverse of a 3x3 matrix with determinant det (nonzero). */
void sk_fe_inverse3(const double A[9], double det, double Ainv[9]);

#endif
