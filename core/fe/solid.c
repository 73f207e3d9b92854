/* Total-Lagrangian solid kernels: internal energy/force/stiffness, the energy-momentum (discrete-gradient)
 * midpoint force, consistent mass, volume and Cauchy stress; surface traction loads.
 *
 * Every kernel runs in two passes: pass 1 evaluates all quadrature-point quantities (the only fallible part:
 * inverted elements, bad geometry) into a stack cache, pass 2 assembles. So outputs are untouched on error. */
#include <math.h>
#include <string.h>

#include "fe_internal.h"

enum { MAX_DOF = SK_MAX_NEN * 3 };

/* Voigt pairs (I, J) per dimension: 3D (00, 11, 22, 01, 12, 02); plane strain keeps (00, 11, 01). */
static const int voigt3_i[6] = {0, 1, 2, 0, 1, 0}, voigt3_j[6] = {0, 1, 2, 1, 2, 2};
static const int voigt2_i[3] = {0, 1, 0}, voigt2_j[3] = {0, 1, 1};
static const int voigt2_of3[3] = {0, 1, 3}; /* position of the plane-strain components in the 3D Voigt order */

/* X: the coordinates or the reference geometry. */
static sk_status check_solid(const sk_solid *el, const double *X, const char *what) {
  if (!el || !el->mat || !X)
    return sk_error_set(SK_ERR_INPUT, "%s: NULL element, material, coordinates or geometry", what);
  if (el->dim != 2 && el->dim != 3)
    return sk_error_set(SK_ERR_INPUT, "%s: dimension %d is not 2 or 3", what, el->dim);
  if (sk_elem_pdim(el->type) != el->dim)
    return sk_error_set(SK_ERR_INPUT, "%s: element type %s is not a %dD solid element", what,
                        sk_elem_name(el->type), el->dim);
  return SK_OK;
}

/* Reference gradients of the shape functions dNdX[a*dim + k] and weight * det J at one quadrature point. */
static sk_status reference_gradients(sk_elem_type type, int dim, int nen, const double *X, const double *xi,
                                     double weight, double *N, double *dNdX, double *wdet, int qp) {
  double dN[SK_MAX_NEN * 3];
  sk_elem_shape(type, xi, N, dN);
  double J[9] = {0}; /* J[k*dim + l] = dX_k / dxi_l */
  for (int a = 0; a < nen; ++a)
    for (int k = 0; k < dim; ++k)
      for (int l = 0; l < dim; ++l) J[k * dim + l] += X[a * dim + k] * dN[a * dim + l];
  double detJ, Ji[9];
  if (dim == 2) {
    detJ = J[0] * J[3] - J[1] * J[2];
    Ji[0] = J[3] / detJ, Ji[1] = -J[1] / detJ, Ji[2] = -J[2] / detJ, Ji[3] = J[0] / detJ;
  } else {
    detJ = sk_fe_det3(J);
    if (detJ > 0.0) sk_fe_inverse3(J, detJ, Ji);
  }
  if (!(detJ > 0.0))
    return sk_error_set(SK_ERR_INPUT,
                        "%s element: reference Jacobian det J = %g <= 0 at quadrature point %d (degenerate or "
                        "inside-out node ordering)",
                        sk_elem_name(type), detJ, qp);
  for (int a = 0; a < nen; ++a)
    for (int k = 0; k < dim; ++k) {
      double sum = 0.0;
      for (int l = 0; l < dim; ++l) sum += dN[a * dim + l] * Ji[l * dim + k];
      dNdX[a * dim + k] = sum;
    }
  *wdet = weight * detJ;
  return SK_OK;
}

/* Displacement gradient H (3x3, zero out of plane in 2D). */
static void displacement_gradient(int dim, int nen, const double *dNdX, const double *u, double H[9]) {
  memset(H, 0, 9 * sizeof *H);
  for (int a = 0; a < nen; ++a)
    for (int i = 0; i < dim; ++i)
      for (int k = 0; k < dim; ++k) H[i * 3 + k] += u[a * dim + i] * dNdX[a * dim + k];
}

/* Kinematics of one state: the gradient used in the B matrices (F, or I for Hooke) and the right Cauchy-Green
 * tensor the material sees (C = F^T F, or I + 2 eps for Hooke). Checks det F > 0 for the finite-strain models. */
static sk_status kinematics(const sk_solid *el, const double H[9], double Fb[9], double C[9], int qp) {
  if (el->mat->model == SK_MAT_HOOKE) {
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        Fb[i * 3 + j] = (i == j);
        C[i * 3 + j] = (i == j) + H[i * 3 + j] + H[j * 3 + i];
      }
    return SK_OK;
  }
  for (int i = 0; i < 9; ++i) Fb[i] = H[i];
  Fb[0] += 1.0, Fb[4] += 1.0, Fb[8] += 1.0;
  const double detF = sk_fe_det3(Fb);
  if (!(detF > 0.0))
    return sk_error_set(SK_ERR_INVERTED, "%s element inverted: det F = %g <= 0 at quadrature point %d",
                        sk_elem_name(el->type), detF, qp);
  for (int I = 0; I < 3; ++I)
    for (int J = I; J < 3; ++J) {
      const double c = Fb[I] * Fb[J] + Fb[3 + I] * Fb[3 + J] + Fb[6 + I] * Fb[6 + J];
      C[I * 3 + J] = C[J * 3 + I] = c;
    }
  return SK_OK;
}

/* Kernels below are inlined with dim as a literal so the Voigt loops unroll and the dof loops vectorise. They do not
 * contract to FMA (ISO C mode's default): contraction made the full tori's assembly 8 % faster but moved three
 * round-off-sensitive cases of the suite (docs/fast-solves-tori.md), as OpenBLAS did. */
#define FE_HOT static inline __attribute__((always_inline))

/* The hot kernels are also compiled for x86-64-v3 (AVX2 + FMA) and picked at load time (GNU ifunc), so a portable
 * build still runs them with 256-bit FMA where the CPU has it. */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && defined(__linux__)
#define FE_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define FE_CLONES
#endif

/* Bt[v*MAX_DOF + a*dim + i] = (sym(F^T (e_i (x) dN_a)))_v in engineering Voigt form, so S_v . B = S : dE.
 * Stored transposed (Voigt-major) so loops over dofs are contiguous. */
FE_HOT void build_bt(const int dim, int nen, const double *restrict dNdX, const double *restrict F,
                     double *restrict Bt) {
  const int nv = dim == 3 ? 6 : 3;
  const int *vi = dim == 3 ? voigt3_i : voigt2_i, *vj = dim == 3 ? voigt3_j : voigt2_j;
  for (int a = 0; a < nen; ++a) {
    const double *dN = dNdX + a * dim;
    for (int i = 0; i < dim; ++i) {
      const double *Fi = F + i * 3;
      const int r = a * dim + i;
      for (int v = 0; v < nv; ++v) {
        const int I = vi[v], J = vj[v];
        Bt[v * MAX_DOF + r] = I == J ? Fi[I] * dN[I] : Fi[I] * dN[J] + Fi[J] * dN[I];
      }
    }
  }
}

/* Stress and tangent restricted to the dimension's Voigt components. */
static void compress_voigt(int dim, const double S[9], const double D[36], double *Sv, double *Dv) {
  if (dim == 3) {
    for (int v = 0; v < 6; ++v) Sv[v] = S[voigt3_i[v] * 3 + voigt3_j[v]];
    if (D) memcpy(Dv, D, 36 * sizeof *D);
    return;
  }
  for (int v = 0; v < 3; ++v) {
    Sv[v] = S[voigt2_i[v] * 3 + voigt2_j[v]];
    if (D)
      for (int w = 0; w < 3; ++w) Dv[v * 3 + w] = D[voigt2_of3[v] * 6 + voigt2_of3[w]];
  }
}

typedef struct {
  double F[SK_MAX_QP][9];  /* gradient of the B matrices (F, F_mid for the midpoint force, I for Hooke) */
  double F1[SK_MAX_QP][9]; /* midpoint only: gradient of the end state, for dE1/du1 */
  double S[SK_MAX_QP][9];  /* (algorithmic) second Piola-Kirchhoff stress */
  double D[SK_MAX_QP][36]; /* (algorithmic) tangent, Voigt; not symmetric for the midpoint correction */
} qp_cache;

/* K += w Bt^T D B1t (only c >= r when symmetric; the caller mirrors), plus the geometric part
 * w * geometric_scale * dN_a.S.dN_b on equal components. */
FE_HOT void assemble_stiffness(const int dim, int nen, double w, const double *restrict Bt,
                               const double *restrict B1t, const double *restrict Dv, const double *restrict S,
                               const double *restrict dNdX, double geometric_scale, int symmetric,
                               double *restrict K) {
  const int nv = dim == 3 ? 6 : 3, ndof = nen * dim;
  double DBt[6 * MAX_DOF];
  for (int v = 0; v < nv; ++v) {
    double *db = DBt + v * MAX_DOF;
    for (int c = 0; c < ndof; ++c) db[c] = 0.0;
    for (int x = 0; x < nv; ++x) {
      const double d = w * Dv[v * nv + x];
      const double *b1 = B1t + x * MAX_DOF;
      for (int c = 0; c < ndof; ++c) db[c] += d * b1[c];
    }
  }
  for (int r = 0; r < ndof; ++r) {
    double b[6];
    for (int v = 0; v < nv; ++v) b[v] = Bt[v * MAX_DOF + r];
    double *Kr = K + r * ndof;
    for (int c = symmetric ? r : 0; c < ndof; ++c) {
      double sum = 0.0;
      for (int v = 0; v < nv; ++v) sum += b[v] * DBt[v * MAX_DOF + c];
      Kr[c] += sum;
    }
  }
  if (geometric_scale == 0.0) return;
  for (int a = 0; a < nen; ++a) {
    const double *dNa = dNdX + a * dim;
    double SdNa[3] = {0, 0, 0};
    for (int I = 0; I < dim; ++I)
      for (int J = 0; J < dim; ++J) SdNa[J] += dNa[I] * S[I * 3 + J];
    for (int b = symmetric ? a : 0; b < nen; ++b) {
      const double *dNb = dNdX + b * dim;
      double g = 0.0;
      for (int J = 0; J < dim; ++J) g += SdNa[J] * dNb[J];
      g *= w * geometric_scale;
      for (int i = 0; i < dim; ++i) K[(a * dim + i) * ndof + b * dim + i] += g;
    }
  }
}

/* Assembly of one quadrature point: f += w B^T S, K += w (B^T D B1 + geometric). B1 = B unless the midpoint
 * (F1 differs from the B matrices' F). */
FE_HOT void assemble_qp(const int dim, int nen, double w, const double *dNdX, const double *F, const double *F1,
                        const double *S, const double *D, double geometric_scale, int symmetric, double *f,
                        double *K) {
  const int nv = dim == 3 ? 6 : 3, ndof = nen * dim;
  double Bt[6 * MAX_DOF], B1t[6 * MAX_DOF], Sv[6], Dv[36];
  build_bt(dim, nen, dNdX, F, Bt);
  compress_voigt(dim, S, K ? D : NULL, Sv, Dv);
  if (f)
    for (int v = 0; v < nv; ++v) {
      const double s = w * Sv[v];
      const double *b = Bt + v * MAX_DOF;
      for (int r = 0; r < ndof; ++r) f[r] += s * b[r];
    }
  if (!K) return;
  if (F1 != F) build_bt(dim, nen, dNdX, F1, B1t);
  assemble_stiffness(dim, nen, w, Bt, F1 != F ? B1t : Bt, Dv, S, dNdX, geometric_scale, symmetric, K);
}

/* The dimension as a literal for the inlined kernels. */
FE_CLONES static void assemble_qp_any(int dim, int nen, double w, const double *dNdX, const double *F, const double *F1,
                            const double *S, const double *D, double geometric_scale, int symmetric, double *f,
                            double *K) {
  if (dim == 3)
    assemble_qp(3, nen, w, dNdX, F, F1, S, D, geometric_scale, symmetric, f, K);
  else
    assemble_qp(2, nen, w, dNdX, F, F1, S, D, geometric_scale, symmetric, f, K);
}

/* Reference geometry layout: per quadrature point q, dN/dX (nen * dim) then w det J. */
static int geometry_stride(const sk_solid *el) { return sk_elem_nen(el->type) * el->dim + 1; }

int sk_solid_geometry_size(const sk_solid *el) {
  int nq;
  const double *qxi, *qw;
  sk_elem_quadrature(el->type, &nq, &qxi, &qw);
  return nq * geometry_stride(el);
}

sk_status sk_solid_geometry(const sk_solid *el, const double *X, double *geometry) {
  SK_TRY(check_solid(el, X, "sk_solid_geometry"));
  const int dim = el->dim, nen = sk_elem_nen(el->type), stride = geometry_stride(el);
  int nq;
  const double *qxi, *qw;
  sk_elem_quadrature(el->type, &nq, &qxi, &qw);
  for (int q = 0; q < nq; ++q) {
    double *g = geometry + q * stride;
    SK_TRY(reference_gradients(el->type, dim, nen, X, qxi + q * dim, qw[q], NULL, g, g + stride - 1, q));
  }
  return SK_OK;
}

/* Geometry buffer of the coordinate-taking kernels (the largest element's). */
typedef double geometry_buffer[SK_MAX_QP * (SK_MAX_NEN * 3 + 1)];

sk_status sk_solid_internal(const sk_solid *el, const double *X, const double *u, double *W, double *f, double *K) {
  SK_TRY(check_solid(el, X, "sk_solid_internal"));
  geometry_buffer geometry;
  SK_TRY(sk_solid_geometry(el, X, geometry));
  return sk_solid_internal_at(el, geometry, u, W, f, K);
}

sk_status sk_solid_internal_at(const sk_solid *el, const double *geometry, const double *u, double *W, double *f,
                               double *K) {
  SK_TRY(check_solid(el, geometry, "sk_solid_internal"));
  if (!u) return sk_error_set(SK_ERR_INPUT, "sk_solid_internal: NULL displacement");
  const int dim = el->dim, nen = sk_elem_nen(el->type), ndof = nen * dim, stride = geometry_stride(el);
  int nq;
  const double *qxi, *qw;
  sk_elem_quadrature(el->type, &nq, &qxi, &qw);
  qp_cache cache;
  double energy = 0.0;
  for (int q = 0; q < nq; ++q) {
    const double *dNdX = geometry + q * stride, wdet = dNdX[stride - 1];
    double H[9], C[9], Wq;
    displacement_gradient(dim, nen, dNdX, u, H);
    SK_TRY(kinematics(el, H, cache.F[q], C, q));
    SK_TRY(sk_fe_material_eval(el->mat, C, &Wq, cache.S[q], K ? cache.D[q] : NULL));
    energy += wdet * Wq;
  }
  if (W) *W = energy;
  if (!f && !K) return SK_OK;
  if (f) memset(f, 0, (size_t)ndof * sizeof *f);
  if (K) memset(K, 0, (size_t)ndof * ndof * sizeof *K);
  const double geometric = el->mat->model == SK_MAT_HOOKE ? 0.0 : 1.0;
  for (int q = 0; q < nq; ++q) {
    const double *dNdX = geometry + q * stride;
    assemble_qp_any(dim, nen, dNdX[stride - 1], dNdX, cache.F[q], cache.F[q], cache.S[q], cache.D[q], geometric, 1,
                    f, K);
  }
  if (K)
    for (int r = 0; r < ndof; ++r)
      for (int c = 0; c < r; ++c) K[r * ndof + c] = K[c * ndof + r];
  return SK_OK;
}

/* Relative size of |dC|^2 below which the discrete-gradient correction is dropped. The remainder is computed
 * without cancellation (sk_fe_material_midpoint_remainder), so the force stays accurate for tiny dC; the limit
 * only keeps the O(eps / |dC|) round-off of the correction's derivative out of K. Dropping changes the
 * energy balance by O(|dC|^3) = O(1e-24) relative, far below round-off. */
static const double MIDPOINT_DROP_TOL = 1e-16;

/* Algorithmic stress S_algo = S_m + beta dC and its derivative w.r.t. E1 (Voigt, not symmetric):
 *   D_algo = CC_m/2 + dC (x) G + 2 beta II,  G = (2/q)(S1 - S_m - CC_m:dC/4 - 2 beta dC),  q = dC:dC. */
static sk_status midpoint_stress(const sk_material *mat, const double C0[9], const double C1[9], double S[9],
                                 double *D) {
  double Cm[9], dC[9];
  double q = 0.0, cc = 0.0;
  for (int i = 0; i < 9; ++i) {
    Cm[i] = 0.5 * (C0[i] + C1[i]);
    dC[i] = C1[i] - C0[i];
    q += dC[i] * dC[i];
    cc += Cm[i] * Cm[i];
  }
  SK_TRY(sk_fe_material_eval(mat, Cm, NULL, S, D));
  if (D)
    for (int i = 0; i < 36; ++i) D[i] *= 0.5;
  if (sk_fe_material_is_quadratic(mat) || q < MIDPOINT_DROP_TOL * (1.0 + cc)) return SK_OK;
  const double beta = 2.0 * sk_fe_material_midpoint_remainder(mat, C0, C1, Cm) / q;
  if (D) {
    double S1[9], dCv[6], G[6];
    SK_TRY(sk_fe_material_eval(mat, C1, NULL, S1, NULL));
    for (int v = 0; v < 6; ++v) dCv[v] = dC[voigt3_i[v] * 3 + voigt3_j[v]];
    for (int v = 0; v < 6; ++v) {
      /* (CC_m : dC)_v = sum over Voigt of CC_m (engineering: shear components count twice); D holds CC_m/2. */
      double CCdC = 0.0;
      for (int x = 0; x < 6; ++x) CCdC += 2.0 * D[v * 6 + x] * dCv[x] * (x < 3 ? 1.0 : 2.0);
      const int I = voigt3_i[v], J = voigt3_j[v];
      G[v] = (2.0 / q) * (S1[I * 3 + J] - S[I * 3 + J] - 0.25 * CCdC - 2.0 * beta * dCv[v]);
    }
    for (int v = 0; v < 6; ++v) {
      for (int x = 0; x < 6; ++x) D[v * 6 + x] += dCv[v] * G[x];
      D[v * 6 + v] += v < 3 ? 2.0 * beta : beta;
    }
  }
  for (int i = 0; i < 9; ++i) S[i] += beta * dC[i];
  return SK_OK;
}

sk_status sk_solid_internal_midpoint(const sk_solid *el, const double *X, const double *u0, const double *u1,
                                     double *f, double *K) {
  SK_TRY(check_solid(el, X, "sk_solid_internal_midpoint"));
  geometry_buffer geometry;
  SK_TRY(sk_solid_geometry(el, X, geometry));
  return sk_solid_internal_midpoint_at(el, geometry, u0, u1, f, K);
}

sk_status sk_solid_internal_midpoint_at(const sk_solid *el, const double *geometry, const double *u0,
                                        const double *u1, double *f, double *K) {
  SK_TRY(check_solid(el, geometry, "sk_solid_internal_midpoint"));
  if (!u0 || !u1) return sk_error_set(SK_ERR_INPUT, "sk_solid_internal_midpoint: NULL displacement");
  const int dim = el->dim, nen = sk_elem_nen(el->type), ndof = nen * dim, stride = geometry_stride(el);
  int nq;
  const double *qxi, *qw;
  sk_elem_quadrature(el->type, &nq, &qxi, &qw);
  qp_cache cache;
  for (int q = 0; q < nq; ++q) {
    const double *dNdX = geometry + q * stride;
    double H0[9], H1[9], F0[9], C0[9], C1[9];
    displacement_gradient(dim, nen, dNdX, u0, H0);
    displacement_gradient(dim, nen, dNdX, u1, H1);
    SK_TRY(kinematics(el, H0, F0, C0, q));
    SK_TRY(kinematics(el, H1, cache.F1[q], C1, q));
    for (int i = 0; i < 9; ++i) cache.F[q][i] = 0.5 * (F0[i] + cache.F1[q][i]);
    SK_TRY(midpoint_stress(el->mat, C0, C1, cache.S[q], K ? cache.D[q] : NULL));
  }
  if (f) memset(f, 0, (size_t)ndof * sizeof *f);
  if (K) memset(K, 0, (size_t)ndof * ndof * sizeof *K);
  /* dF_mid/du1 = 1/2 dF1/du1: the geometric term carries a factor 1/2. */
  const double geometric = el->mat->model == SK_MAT_HOOKE ? 0.0 : 0.5;
  for (int q = 0; q < nq; ++q) {
    const double *dNdX = geometry + q * stride;
    assemble_qp_any(dim, nen, dNdX[stride - 1], dNdX, cache.F[q], cache.F1[q], cache.S[q], cache.D[q], geometric, 0,
                    f, K);
  }
  return SK_OK;
}

/* Gauss-Legendre points on [-1, 1] for the mass rule. */
static const double gauss3_x[3] = {-0.77459666924148337704, 0.0, 0.77459666924148337704};
static const double gauss3_w[3] = {0.55555555555555555556, 0.88888888888888888889, 0.55555555555555555556};
static const double gauss5_x[5] = {-0.90617984593866399280, -0.53846931010568309104, 0.0, 0.53846931010568309104,
                                   0.90617984593866399280};
static const double gauss5_w[5] = {0.23692688505618908751, 0.47862867049936646804, 0.56888888888888888889,
                                   0.47862867049936646804, 0.23692688505618908751};

/* Mass rules. N_a N_b det J on a distorted (non-affine) element has a higher degree than the stiffness rule
 * integrates: per direction 4 on a quad4/hex8, up to 9 on a curved quad9/hex27 (7 on quad8/hex20); total degree 6 on
 * a curved tri6, 7 on a curved tet10. So that the total mass and the inertia tensor sum_ab M_ab X_a X_b^T =
 * integral rho0 X X^T are exact, linear tensor elements use 3 Gauss points per direction, quadratic ones 5, and
 * quadratic simplices the collapsed (Duffy) product of 5-point Gauss rules: with x = u, y = v (1 - u),
 * z = w (1 - u)(1 - v) the Jacobian (1 - u)^(d-1) (1 - v)^(d-2) raises the degree in u by d - 1, so 5 points
 * (degree 9) are exact for total degree 8 on triangles and 7 on tetrahedra. tri3/tet4 use their own rule (affine). */
static int mass_point(sk_elem_type type, int dim, int q, double *xi, double *weight) {
  const int order = sk_elem_order(type), simplex = sk_elem_is_simplex(type);
  if (simplex && order == 1) {
    int nq;
    const double *qxi, *qw;
    sk_elem_quadrature(type, &nq, &qxi, &qw);
    if (q >= nq) return 0;
    for (int k = 0; k < dim; ++k) xi[k] = qxi[q * dim + k];
    *weight = qw[q];
    return 1;
  }
  const int n1 = order == 2 ? 5 : 3;
  const double *gx = order == 2 ? gauss5_x : gauss3_x, *gw = order == 2 ? gauss5_w : gauss3_w;
  if (q >= (dim == 2 ? n1 * n1 : n1 * n1 * n1)) return 0;
  double t[3];
  *weight = 1.0;
  for (int k = 0, rest = q; k < dim; ++k, rest /= n1) {
    t[k] = gx[rest % n1];
    *weight *= gw[rest % n1];
  }
  if (!simplex) {
    for (int k = 0; k < dim; ++k) xi[k] = t[k];
    return 1;
  }
  double remaining = 1.0; /* Duffy: each coordinate takes its share of what the earlier ones left */
  for (int k = 0; k < dim; ++k) {
    const double s = 0.5 * (1.0 + t[k]);
    xi[k] = s * remaining;
    *weight *= 0.5 * remaining;
    remaining *= 1.0 - s;
  }
  return 1;
}

sk_status sk_solid_mass(const sk_solid *el, const double *X, double *M) {
  SK_TRY(check_solid(el, X, "sk_solid_mass"));
  if (!M) return sk_error_set(SK_ERR_INPUT, "sk_solid_mass: NULL output");
  const int dim = el->dim, nen = sk_elem_nen(el->type);
  const double rho = el->mat->density;
  double Mloc[SK_MAX_NEN * SK_MAX_NEN] = {0};
  double xi[3], weight;
  for (int q = 0; mass_point(el->type, dim, q, xi, &weight); ++q) {
    double N[SK_MAX_NEN], dNdX[SK_MAX_NEN * 3], wdet;
    SK_TRY(reference_gradients(el->type, dim, nen, X, xi, weight, N, dNdX, &wdet, q));
    for (int a = 0; a < nen; ++a)
      for (int b = a; b < nen; ++b) Mloc[a * nen + b] += rho * wdet * N[a] * N[b];
  }
  for (int a = 0; a < nen; ++a)
    for (int b = 0; b < nen; ++b) M[a * nen + b] = b >= a ? Mloc[a * nen + b] : Mloc[b * nen + a];
  return SK_OK;
}

double sk_solid_volume(const sk_solid *el, const double *X) {
  if (!el || !X || (el->dim != 2 && el->dim != 3) || sk_elem_pdim(el->type) != el->dim) return 0.0;
  const int dim = el->dim, nen = sk_elem_nen(el->type);
  double volume = 0.0, xi[3], weight; /* the mass rule: exact also for curved quadratic elements */
  for (int q = 0; mass_point(el->type, dim, q, xi, &weight); ++q) {
    double dN[SK_MAX_NEN * 3], J[9] = {0};
    sk_elem_shape(el->type, xi, NULL, dN);
    for (int a = 0; a < nen; ++a)
      for (int k = 0; k < dim; ++k)
        for (int l = 0; l < dim; ++l) J[k * dim + l] += X[a * dim + k] * dN[a * dim + l];
    volume += weight * (dim == 2 ? J[0] * J[3] - J[1] * J[2] : sk_fe_det3(J));
  }
  return volume;
}

sk_status sk_solid_cauchy(const sk_solid *el, const double *X, const double *u, double sigma[9]) {
  SK_TRY(check_solid(el, X, "sk_solid_cauchy"));
  if (!u || !sigma) return sk_error_set(SK_ERR_INPUT, "sk_solid_cauchy: NULL displacement or output");
  const int dim = el->dim, nen = sk_elem_nen(el->type);
  int nq;
  const double *qxi, *qw;
  sk_elem_quadrature(el->type, &nq, &qxi, &qw);
  double sum[9] = {0}, volume = 0.0;
  for (int q = 0; q < nq; ++q) {
    double dNdX[SK_MAX_NEN * 3], wdet, H[9], F[9], C[9], S[9];
    SK_TRY(reference_gradients(el->type, dim, nen, X, qxi + q * dim, qw[q], NULL, dNdX, &wdet, q));
    displacement_gradient(dim, nen, dNdX, u, H);
    SK_TRY(kinematics(el, H, F, C, q));
    SK_TRY(sk_fe_material_eval(el->mat, C, NULL, S, NULL));
    /* sigma = F S F^T / det F (F = I for Hooke, where S is already sigma). */
    const double scale = wdet / sk_fe_det3(F);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        double s = 0.0;
        for (int I = 0; I < 3; ++I)
          for (int J = 0; J < 3; ++J) s += F[i * 3 + I] * S[I * 3 + J] * F[j * 3 + J];
        sum[i * 3 + j] += scale * s;
      }
    volume += wdet;
  }
  for (int i = 0; i < 9; ++i) sigma[i] = sum[i] / volume;
  return SK_OK;
}

/* Area element J = |a1 x a2| (3D; 2D: |a1|) of the tangents a_k = dX/dxi_k at one point, shape values N and, when
 * dJ is not NULL, dJ[b*dim + j] = dJ/dX_bj: n . (N_b,1 e_j x a2 + N_b,2 a1 x e_j) = N_b,1 (a2 x n)_j + N_b,2 (n x a1)_j
 * in 3D, N_b,1 a1_j / J in 2D. */
static double face_measure(sk_elem_type type, int dim, const double *X, const double *xi, double *N, double *dJ) {
  const int nen = sk_elem_nen(type), pdim = sk_elem_pdim(type);
  double dN[SK_MAX_NEN * 3], a[2][3] = {{0}};
  sk_elem_shape(type, xi, N, dN);
  if (pdim == 0) {
    if (dJ)
      for (int i = 0; i < nen * dim; ++i) dJ[i] = 0.0;
    return 1.0;
  }
  for (int k = 0; k < pdim; ++k)
    for (int n = 0; n < nen; ++n)
      for (int i = 0; i < dim; ++i) a[k][i] += X[n * dim + i] * dN[n * pdim + k];
  if (pdim == 1) {
    const double J = sqrt(a[0][0] * a[0][0] + a[0][1] * a[0][1] + a[0][2] * a[0][2]);
    for (int b = 0; dJ && b < nen; ++b)
      for (int j = 0; j < dim; ++j) dJ[b * dim + j] = J > 0.0 ? dN[b] * a[0][j] / J : 0.0;
    return J;
  }
  const double c[3] = {a[0][1] * a[1][2] - a[0][2] * a[1][1], a[0][2] * a[1][0] - a[0][0] * a[1][2],
                       a[0][0] * a[1][1] - a[0][1] * a[1][0]};
  const double J = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
  if (dJ) {
    double a2xn[3] = {0, 0, 0}, nxa1[3] = {0, 0, 0};
    if (J > 0.0) {
      const double n[3] = {c[0] / J, c[1] / J, c[2] / J};
      a2xn[0] = a[1][1] * n[2] - a[1][2] * n[1], a2xn[1] = a[1][2] * n[0] - a[1][0] * n[2];
      a2xn[2] = a[1][0] * n[1] - a[1][1] * n[0];
      nxa1[0] = n[1] * a[0][2] - n[2] * a[0][1], nxa1[1] = n[2] * a[0][0] - n[0] * a[0][2];
      nxa1[2] = n[0] * a[0][1] - n[1] * a[0][0];
    }
    for (int b = 0; b < nen; ++b)
      for (int j = 0; j < dim; ++j) dJ[b * dim + j] = dN[b * 2] * a2xn[j] + dN[b * 2 + 1] * nxa1[j];
  }
  return J;
}

static int face_valid(sk_elem_type type, int dim, const double *X) {
  const int pdim = sk_elem_pdim(type);
  return X && (dim == 2 || dim == 3) && pdim >= 0 && pdim < dim && pdim <= 2;
}

void sk_face_weights(sk_elem_type type, int dim, const double *X, double *w, double *dw) {
  const int nen = sk_elem_nen(type), ndof = nen * dim;
  if (w)
    for (int a = 0; a < nen; ++a) w[a] = 0.0;
  if (dw)
    for (int i = 0; i < nen * ndof; ++i) dw[i] = 0.0;
  if (!face_valid(type, dim, X)) return;
  const int pdim = sk_elem_pdim(type);
  int nq;
  const double *qxi, *qw;
  sk_elem_quadrature(type, &nq, &qxi, &qw);
  for (int q = 0; q < nq; ++q) {
    double N[SK_MAX_NEN], dJ[SK_MAX_NEN * 3];
    const double J = face_measure(type, dim, X, qxi + q * pdim, N, dw ? dJ : NULL);
    for (int a = 0; a < nen; ++a) {
      if (w) w[a] += qw[q] * N[a] * J;
      for (int c = 0; dw && c < ndof; ++c) dw[a * ndof + c] += qw[q] * N[a] * dJ[c];
    }
  }
}

void sk_face_traction(sk_elem_type type, int dim, const double *X, const double *t, double *f) {
  if (!f) return;
  const int nen = sk_elem_nen(type);
  double w[SK_MAX_NEN];
  sk_face_weights(type, dim, X, w, NULL);
  for (int a = 0; a < nen; ++a)
    for (int i = 0; i < dim; ++i) f[a * dim + i] = t ? w[a] * t[i] : 0.0;
}

double sk_face_area(sk_elem_type type, int dim, const double *X) {
  double w[SK_MAX_NEN], area = 0.0;
  sk_face_weights(type, dim, X, w, NULL);
  for (int a = 0; a < sk_elem_nen(type); ++a) area += w[a];
  return area;
}
