/* stickslip — finite elements: shape functions, quadrature, materials, total-Lagrangian solid kernels, mass.
 *
 * Conventions
 * - Node ordering of every element type follows gmsh's (docs: "Node ordering"); sk_mesh_load keeps it.
 * - Element vectors are node-major: entry a*dim + i is component i of node a; element matrices are row-major
 *   (nen*dim) x (nen*dim).
 * - dim is the spatial dimension: 2 (plane strain) or 3. Coordinates X and displacements u are packed nen*dim.
 * - Materials always work with 3x3 tensors (row-major); plane strain sets the out-of-plane stretch to 1.
 * - Parametric coordinates: lines, quads, hexes on [-1, 1]^d; triangles and tets on the unit simplex. */
#ifndef STICKSLIP_FE_H
#define STICKSLIP_FE_H

#include "stickslip/error.h"
#include "stickslip/mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

enum { SK_MAX_NEN = 27, SK_MAX_QP = 64 };

/* ---- element types ---------------------------------------------------------------------------------------- */
int sk_elem_nen(sk_elem_type type);           /* nodes per element */
int sk_elem_pdim(sk_elem_type type);          /* parametric dimension */
int sk_elem_order(sk_elem_type type);         /* polynomial order: 1 (linear) or 2 (quadratic); 0 for point1 */
int sk_elem_corners(sk_elem_type type);       /* corner (vertex) nodes; they come first in the node ordering */
int sk_elem_is_simplex(sk_elem_type type);    /* tri3, tri6, tet4, tet10 */
const char *sk_elem_name(sk_elem_type type);  /* "hex8", ... */
/* Shape functions N[a] and parametric derivatives dN[a*pdim + k] at xi (length pdim). Either output may be NULL. */
void sk_elem_shape(sk_elem_type type, const double *xi, double *N, double *dN);
/* Second parametric derivatives ddN[(a*pdim + k)*pdim + l] (needed for surface curvature). */
void sk_elem_shape_hessian(sk_elem_type type, const double *xi, double *ddN);
/* The element's integration rule (stiffness, loads, areas): n points xi[q*pdim + k], weights w[q]. Gauss with
 * order + 1 points per direction on lines, quads and hexes (quad8/hex20: 3); degree 2 on simplices (3 points on
 * triangles, 4 on tetrahedra), which is exact for the stiffness of an affine tri6/tet10 and the mass of an affine
 * tri3/tet4. sk_solid_mass uses richer rules of its own (exact for curved quadratic elements). */
void sk_elem_quadrature(sk_elem_type type, int *n, const double **xi, const double **w);
/* Gauss rule on a face type (LINE2/3, TRI3, QUAD4/9) exact for polynomials of degree `order` in the face
 * parameters: up to max_points points xi[q][0..pdim) and weights w[q] (summing to the reference face's measure: 2,
 * 1/2, 4). Returns their number, -(the number needed) when max_points is too small, 0 for another type. */
int sk_face_quadrature(sk_elem_type type, int order, int max_points, double (*xi)[2], double *w);
/* Parametric coordinates of the element's nodes, xi[a*pdim + k]. */
const double *sk_elem_node_coords(sk_elem_type type);
/* Boundary faces: the face type and, for face f, its local node list (ordered so that the face normal from
 * sk_surface geometry points out of the element). Returns the number of faces. */
int sk_elem_faces(sk_elem_type type, sk_elem_type *face_type, const int **face_nodes, int *face_nen);

/* ---- materials -------------------------------------------------------------------------------------------- */
typedef enum {
  SK_MAT_HOOKE = 0,        /* small-strain linear elasticity: linearised kinematics, W = lambda/2 (tr eps)^2 + mu eps:eps */
  SK_MAT_SVK,              /* Saint Venant-Kirchhoff: W = lambda/2 (tr E)^2 + mu E:E, E = (C - I)/2 */
  SK_MAT_NEOHOOKE_BONET,   /* compressible Neo-Hooke, volumetric lambda/2 (ln J)^2 (Bonet & Wood):
                            * W = mu/2 (tr C - 3) - mu ln J + lambda/2 (ln J)^2 */
  SK_MAT_NEOHOOKE_CIARLET, /* compressible Neo-Hooke, volumetric lambda/4 (J^2 - 1) - lambda/2 ln J (Ciarlet-Geymonat,
                            * GetFEM's default): W = mu/2 (tr C - 3) - mu ln J + lambda/4 (J^2 - 1) - lambda/2 ln J */
  SK_MAT_MODEL_COUNT
} sk_material_model;

/* The scene names of the models (`material.model`), NULL-terminated: entry m < SK_MAT_MODEL_COUNT names model m;
 * the entries after those are aliases ("neo-hooke" = neo-hooke-bonet, the law of the first releases). Map any
 * entry to its model with sk_material_model_from_name. */
extern const char *const sk_material_model_names[];

typedef struct {
  sk_material_model model;
  double E, nu;        /* Young's modulus, Poisson's ratio */
  double lambda, mu;   /* Lame constants, derived by sk_material_init */
  double density;      /* reference mass density rho0 */
} sk_material;

/* Checks E > 0, -1 < nu < 0.5, density >= 0 and fills the Lame constants. */
sk_status sk_material_init(sk_material *mat, sk_material_model model, double E, double nu, double density);
sk_status sk_material_model_from_name(const char *name, sk_material_model *model);
/* Strain energy density W(C). Returns SK_ERR_INVERTED if det C <= 0 (Neo-Hooke laws). For HOOKE, C is not used:
 * call the Hooke kernel through the solid routines. (If called anyway, HOOKE reads its argument as I + 2 eps with
 * eps the small strain, i.e. the same quadratic function as SVK, and S is then the Cauchy stress.) */
sk_status sk_material_energy(const sk_material *mat, const double C[9], double *W);
/* Second Piola-Kirchhoff stress S = 2 dW/dC. */
sk_status sk_material_stress(const sk_material *mat, const double C[9], double S[9]);
/* Material tangent CC[((I*3+J)*3+K)*3+L] = 4 d2W/dC_IJ dC_KL (= dS_IJ / dE_KL), with minor and major symmetry. */
sk_status sk_material_tangent(const sk_material *mat, const double C[9], double CC[81]);

/* ---- solid elements (total Lagrangian) -------------------------------------------------------------------- */
typedef struct {
  sk_elem_type type;
  int dim;                    /* 2: plane strain, unit thickness; 3 */
  const sk_material *mat;
} sk_solid;

/* Strain energy `W` (may be NULL), internal force f = dW/du (nen*dim, may be NULL) and stiffness K = df/du
 * ((nen*dim)^2 row-major, may be NULL) of one element at displacement u. HOOKE uses linearised kinematics.
 * Returns SK_ERR_INVERTED when det F <= 0 at a quadrature point (nothing else written then). */
sk_status sk_solid_internal(const sk_solid *el, const double *X, const double *u, double *W, double *f, double *K);

/* Energy-momentum internal force of the midpoint scheme: f = integral of F_mid S_algo : Grad(dphi) with
 * F_mid = (F(u0) + F(u1))/2 and the Gonzalez discrete gradient
 *   S_algo = S(C_mid) + 2 [W(C1) - W(C0) - 1/2 S(C_mid):dC] dC / (dC:dC),  dC = C1 - C0,  C_mid = (C0 + C1)/2,
 * so that f.(u1 - u0) = W(u1) - W(u0) exactly. K = df/du1 (exact). For small |dC| the correction term is dropped
 * (it is O(|dC|^2)). HOOKE reduces to the midpoint force of the quadratic energy (already exact). */
sk_status sk_solid_internal_midpoint(const sk_solid *el, const double *X, const double *u0, const double *u1,
                                     double *f, double *K);

/* The reference geometry of a solid element: dN/dX and weight * det J at its stiffness quadrature points, which
 * depend on the reference coordinates only. A body computes it once (sk_solid_geometry_size doubles per element)
 * and evaluates its elements with the _at kernels instead of recomputing it in every Newton iteration; the results
 * are bitwise those of the coordinate-taking kernels. SK_ERR_INPUT when det J <= 0 (degenerate element). */
int sk_solid_geometry_size(const sk_solid *el);
sk_status sk_solid_geometry(const sk_solid *el, const double *X, double *geometry);
sk_status sk_solid_internal_at(const sk_solid *el, const double *geometry, const double *u, double *W, double *f,
                               double *K);
sk_status sk_solid_internal_midpoint_at(const sk_solid *el, const double *geometry, const double *u0,
                                        const double *u1, double *f, double *K);

/* Consistent mass matrix, scalar form M[a*nen + b] = integral rho0 N_a N_b (expand per component). Integrated
 * exactly also on distorted quads/hexes (3 or 5 Gauss points per direction), so sum_ab M_ab X_a X_b^T is the exact
 * inertia integral rho0 X X^T. */
sk_status sk_solid_mass(const sk_solid *el, const double *X, double *M);

/* Element volume (area in 2D) in the reference configuration, with the mass rule (exact for curved elements). */
double sk_solid_volume(const sk_solid *el, const double *X);

/* Cauchy stress (3x3) averaged over the element's quadrature points, for output. */
sk_status sk_solid_cauchy(const sk_solid *el, const double *X, const double *u, double sigma[9]);

/* ---- surface (face) elements ------------------------------------------------------------------------------ */
/* Consistent load vector of a traction t (dim components, per unit reference area/length) on a face element of
 * type `type` (LINE2/LINE3 in 2D, TRI3/QUAD4/QUAD9 in 3D), X packed nen*dim. f is nen*dim. */
void sk_face_traction(sk_elem_type type, int dim, const double *X, const double *t, double *f);
/* Area (length in 2D) of a face at positions X (reference or current). */
double sk_face_area(sk_elem_type type, int dim, const double *X);
/* Nodal weights of a face at positions X: w[a] = integral of N_a dA (they sum to the area; a uniform traction t puts
 * w[a] t on node a) and, when dw is not NULL, their derivatives dw[a*nen*dim + b*dim + j] = d w_a / d X_bj (for loads
 * that follow the current area). With the element rule (exact for N_a on straight faces). */
void sk_face_weights(sk_elem_type type, int dim, const double *X, double *w, double *dw);

#ifdef __cplusplus
}
#endif
#endif
