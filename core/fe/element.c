/* Element catalogue: shape functions in gmsh node ordering (tensor-product Lagrange, simplex P1/P2, serendipity),
 * quadrature rules, node coordinates and outward-oriented face tables for every sk_elem_type. */
#include <stddef.h>

#include "stickslip/fe.h"

/* ---- quadrature tables (generated: Gauss-Legendre tensor rules, first coordinate fastest) ------------------ */
static const double gauss2_1d_xi[] = {
    -0.5773502691896258, 0.5773502691896258};
static const double gauss2_1d_w[] = {
    1.0, 1.0};
static const double gauss3_1d_xi[] = {
    -0.7745966692414834, 0.0, 0.7745966692414834};
static const double gauss3_1d_w[] = {
    0.5555555555555556, 0.8888888888888888, 0.5555555555555556};
static const double gauss2_2d_xi[] = {
    -0.5773502691896258, -0.5773502691896258, 0.5773502691896258, -0.5773502691896258, -0.5773502691896258,
    0.5773502691896258, 0.5773502691896258, 0.5773502691896258};
static const double gauss2_2d_w[] = {
    1.0, 1.0, 1.0, 1.0};
static const double gauss3_2d_xi[] = {
    -0.7745966692414834, -0.7745966692414834, 0.0, -0.7745966692414834, 0.7745966692414834, -0.7745966692414834,
    -0.7745966692414834, 0.0, 0.0, 0.0, 0.7745966692414834, 0.0, -0.7745966692414834, 0.7745966692414834, 0.0,
    0.7745966692414834, 0.7745966692414834, 0.7745966692414834};
static const double gauss3_2d_w[] = {
    0.308641975308642, 0.49382716049382713, 0.308641975308642, 0.49382716049382713, 0.7901234567901234,
    0.49382716049382713, 0.308641975308642, 0.49382716049382713, 0.308641975308642};
static const double gauss2_3d_xi[] = {
    -0.5773502691896258, -0.5773502691896258, -0.5773502691896258, 0.5773502691896258, -0.5773502691896258,
    -0.5773502691896258, -0.5773502691896258, 0.5773502691896258, -0.5773502691896258, 0.5773502691896258,
    0.5773502691896258, -0.5773502691896258, -0.5773502691896258, -0.5773502691896258, 0.5773502691896258,
    0.5773502691896258, -0.5773502691896258, 0.5773502691896258, -0.5773502691896258, 0.5773502691896258,
    0.5773502691896258, 0.5773502691896258, 0.5773502691896258, 0.5773502691896258};
static const double gauss2_3d_w[] = {
    1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0};
static const double gauss3_3d_xi[] = {
    -0.7745966692414834, -0.7745966692414834, -0.7745966692414834, 0.0, -0.7745966692414834, -0.7745966692414834,
    0.7745966692414834, -0.7745966692414834, -0.7745966692414834, -0.7745966692414834, 0.0, -0.7745966692414834,
    0.0, 0.0, -0.7745966692414834, 0.7745966692414834, 0.0, -0.7745966692414834, -0.7745966692414834,
    0.7745966692414834, -0.7745966692414834, 0.0, 0.7745966692414834, -0.7745966692414834, 0.7745966692414834,
    0.7745966692414834, -0.7745966692414834, -0.7745966692414834, -0.7745966692414834, 0.0, 0.0,
    -0.7745966692414834, 0.0, 0.7745966692414834, -0.7745966692414834, 0.0, -0.7745966692414834, 0.0, 0.0, 0.0,
    0.0, 0.0, 0.7745966692414834, 0.0, 0.0, -0.7745966692414834, 0.7745966692414834, 0.0, 0.0, 0.7745966692414834,
    0.0, 0.7745966692414834, 0.7745966692414834, 0.0, -0.7745966692414834, -0.7745966692414834,
    0.7745966692414834, 0.0, -0.7745966692414834, 0.7745966692414834, 0.7745966692414834, -0.7745966692414834,
    0.7745966692414834, -0.7745966692414834, 0.0, 0.7745966692414834, 0.0, 0.0, 0.7745966692414834,
    0.7745966692414834, 0.0, 0.7745966692414834, -0.7745966692414834, 0.7745966692414834, 0.7745966692414834, 0.0,
    0.7745966692414834, 0.7745966692414834, 0.7745966692414834, 0.7745966692414834, 0.7745966692414834};
static const double gauss3_3d_w[] = {
    0.1714677640603567, 0.27434842249657065, 0.1714677640603567, 0.27434842249657065, 0.438957475994513,
    0.27434842249657065, 0.1714677640603567, 0.27434842249657065, 0.1714677640603567, 0.27434842249657065,
    0.43895747599451296, 0.27434842249657065, 0.43895747599451296, 0.7023319615912208, 0.43895747599451296,
    0.27434842249657065, 0.43895747599451296, 0.27434842249657065, 0.1714677640603567, 0.27434842249657065,
    0.1714677640603567, 0.27434842249657065, 0.438957475994513, 0.27434842249657065, 0.1714677640603567,
    0.27434842249657065, 0.1714677640603567};

/* Degree-2 simplex rules: exact for the mass matrix of an affine tri3/tet4 and for the stiffness of an affine
 * tri6/tet10 (B is linear there), the standard full integration of both (no spurious zero-energy modes). */
static const double tri3_xi[] = {1.0 / 6.0, 1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0, 1.0 / 6.0, 2.0 / 3.0};
static const double tri3_w[] = {1.0 / 6.0, 1.0 / 6.0, 1.0 / 6.0};
#define TET_A 0.58541019662496845446 /* (5 + 3 sqrt 5) / 20 */
#define TET_B 0.13819660112501051518 /* (5 - sqrt 5) / 20 */
static const double tet4_xi[] = {TET_B, TET_B, TET_B, TET_A, TET_B, TET_B, TET_B, TET_A, TET_B, TET_B, TET_B, TET_A};
static const double tet4_w[] = {1.0 / 24.0, 1.0 / 24.0, 1.0 / 24.0, 1.0 / 24.0};
static const double point1_xi[] = {0.0};
static const double point1_w[] = {1.0};

/* ---- node coordinates (gmsh ordering, checked against gmshModelMeshGetElementProperties in the tests) ------ */
static const double line2_nodes[] = {-1, 1};
static const double line3_nodes[] = {-1, 1, 0};
static const double tri3_nodes[] = {0, 0, 1, 0, 0, 1};
static const double tri6_nodes[] = {0, 0, 1, 0, 0, 1, 0.5, 0, 0.5, 0.5, 0, 0.5};
static const double quad4_nodes[] = {-1, -1, 1, -1, 1, 1, -1, 1};
/* quad8 is quad9 without its centre node. */
static const double quad9_nodes[] = {-1, -1, 1, -1, 1, 1, -1, 1, 0, -1, 1, 0, 0, 1, -1, 0, 0, 0};
static const double tet4_nodes[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
static const double tet10_nodes[] = {0,   0, 0,   1, 0,   0,   0, 1,   0,   0, 0,   1,  0.5, 0, 0,
                                     0.5, 0.5, 0, 0, 0.5, 0,   0, 0,   0.5, 0, 0.5, 0.5, 0.5, 0, 0.5};
static const double hex8_nodes[] = {-1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1,
                                    -1, -1, 1,  1, -1, 1,  1, 1, 1,  -1, 1, 1};
/* hex20 is hex27 without its face and body centres (nodes 20-26). */
static const double hex27_nodes[] = {
    -1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1, -1, -1, 1, 1, -1, 1, 1, 1, 1, -1, 1, 1, /* corners */
    0,  -1, -1, -1, 0, -1, -1, -1, 0, 1, 0, -1, 1, -1, 0, 0, 1, -1, 1, 1, 0, -1, 1, 0,  /* edges 8-15 */
    0,  -1, 1,  -1, 0, 1,  1, 0, 1,  0, 1, 1,                                             /* edges 16-19 */
    0,  0,  -1, 0, -1, 0,  -1, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1,                          /* face centres */
    0,  0,  0};

/* Tensor-product elements: per node and direction, which 1D Lagrange function (0: node at -1, 1: at +1,
 * 2: at 0) it uses. Derived from the node coordinates above. */
static const unsigned char line2_index[] = {0, 1};
static const unsigned char line3_index[] = {0, 1, 2};
static const unsigned char quad4_index[] = {0, 0, 1, 0, 1, 1, 0, 1};
static const unsigned char quad9_index[] = {0, 0, 1, 0, 1, 1, 0, 1, 2, 0, 1, 2, 2, 1, 0, 2, 2, 2};
static const unsigned char hex8_index[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
static const unsigned char hex27_index[] = {
    0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1, 2, 0, 0, 0, 2, 0, 0, 0, 2,
    1, 2, 0, 1, 0, 2, 2, 1, 0, 1, 1, 2, 0, 1, 2, 2, 0, 1, 0, 2, 1, 1, 2, 1, 2, 1, 1, 2, 2, 0, 2, 0, 2,
    0, 2, 2, 1, 2, 2, 2, 1, 2, 2, 2, 1, 2, 2, 2};

/* Quadratic simplices: the corner pair of each edge node, in node order (nodes d+1, d+2, ...). */
static const unsigned char tri6_edges[] = {0, 1, 1, 2, 2, 0};
static const unsigned char tet10_edges[] = {0, 1, 1, 2, 2, 0, 0, 3, 2, 3, 1, 3};

/* ---- faces: node lists ordered so that a1 x a2 (2D: (t_y, -t_x)) points out of the element ---------------- */
static const int line_faces[] = {0, 1};
static const int tri3_faces[] = {0, 1, 1, 2, 2, 0};
static const int tri6_faces[] = {0, 1, 3, 1, 2, 4, 2, 0, 5};
static const int quad4_faces[] = {0, 1, 1, 2, 2, 3, 3, 0};
static const int quad9_faces[] = {0, 1, 4, 1, 2, 5, 2, 3, 6, 3, 0, 7}; /* also quad8's */
static const int tet4_faces[] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
/* tet4's faces with their edge nodes (a-b, b-c, c-a) in tri6 order. */
static const int tet10_faces[] = {0, 2, 1, 6, 5, 4, 0, 1, 3, 4, 9, 7, 0, 3, 2, 7, 8, 6, 1, 2, 3, 5, 8, 9};
/* Order: zeta = -1, eta = -1, xi = -1, xi = +1, eta = +1, zeta = +1 (the order of hex27's face-centre nodes). */
static const int hex8_faces[] = {0, 3, 2, 1, 0, 1, 5, 4, 0, 4, 7, 3, 1, 2, 6, 5, 3, 7, 6, 2, 4, 5, 6, 7};
static const int hex20_faces[] = {0, 3, 2, 1, 9,  13, 11, 8,  0, 1, 5, 4, 8,  12, 16, 10,
                                  0, 4, 7, 3, 10, 17, 15, 9,  1, 2, 6, 5, 11, 14, 18, 12,
                                  3, 7, 6, 2, 15, 19, 14, 13, 4, 5, 6, 7, 16, 18, 19, 17};
static const int hex27_faces[] = {0, 3, 2, 1, 9,  13, 11, 8,  20, 0, 1, 5, 4, 8,  12, 16, 10, 21,
                                  0, 4, 7, 3, 10, 17, 15, 9,  22, 1, 2, 6, 5, 11, 14, 18, 12, 23,
                                  3, 7, 6, 2, 15, 19, 14, 13, 24, 4, 5, 6, 7, 16, 18, 19, 17, 25};

typedef enum {
  FAMILY_POINT,
  FAMILY_TENSOR,     /* products of 1D Lagrange factors: line2/3, quad4/9, hex8/27 */
  FAMILY_SIMPLEX,    /* barycentric P1 or P2: tri3/6, tet4/10 */
  FAMILY_SERENDIPITY /* quad8, hex20: corner and edge nodes of the quadratic tensor element, no interior nodes */
} element_family;

typedef struct {
  const char *name;
  int nen, pdim, n_corners;
  element_family family;
  int order;                         /* polynomial order of the 1D factors / the simplex basis */
  const unsigned char *tensor_index; /* tensor-product: 1D factor per node and direction */
  const unsigned char *edges;        /* quadratic simplices: corner pairs of the edge nodes */
  const double *node_xi;
  int n_qp;
  const double *qp_xi, *qp_w;
  sk_elem_type face_type;
  int n_faces, face_nen;
  const int *faces;
} element_info;

#define TENSOR(o, index) FAMILY_TENSOR, o, index, NULL
#define SIMPLEX(o, edges) FAMILY_SIMPLEX, o, NULL, edges
#define SERENDIPITY FAMILY_SERENDIPITY, 2, NULL, NULL
static const element_info element_table[SK_ELEM_TYPE_COUNT] = {
    [SK_POINT1] = {"point1", 1, 0, 1, FAMILY_POINT, 0, NULL, NULL, point1_xi, 1, point1_xi, point1_w, SK_POINT1, 0,
                   0, NULL},
    [SK_LINE2] = {"line2", 2, 1, 2, TENSOR(1, line2_index), line2_nodes, 2, gauss2_1d_xi, gauss2_1d_w, SK_POINT1, 2,
                  1, line_faces},
    [SK_LINE3] = {"line3", 3, 1, 2, TENSOR(2, line3_index), line3_nodes, 3, gauss3_1d_xi, gauss3_1d_w, SK_POINT1, 2,
                  1, line_faces},
    [SK_TRI3] = {"tri3", 3, 2, 3, SIMPLEX(1, NULL), tri3_nodes, 3, tri3_xi, tri3_w, SK_LINE2, 3, 2, tri3_faces},
    [SK_QUAD4] = {"quad4", 4, 2, 4, TENSOR(1, quad4_index), quad4_nodes, 4, gauss2_2d_xi, gauss2_2d_w, SK_LINE2, 4, 2,
                  quad4_faces},
    [SK_QUAD9] = {"quad9", 9, 2, 4, TENSOR(2, quad9_index), quad9_nodes, 9, gauss3_2d_xi, gauss3_2d_w, SK_LINE3, 4, 3,
                  quad9_faces},
    [SK_TET4] = {"tet4", 4, 3, 4, SIMPLEX(1, NULL), tet4_nodes, 4, tet4_xi, tet4_w, SK_TRI3, 4, 3, tet4_faces},
    [SK_HEX8] = {"hex8", 8, 3, 8, TENSOR(1, hex8_index), hex8_nodes, 8, gauss2_3d_xi, gauss2_3d_w, SK_QUAD4, 6, 4,
                 hex8_faces},
    [SK_HEX27] = {"hex27", 27, 3, 8, TENSOR(2, hex27_index), hex27_nodes, 27, gauss3_3d_xi, gauss3_3d_w, SK_QUAD9, 6,
                  9, hex27_faces},
    [SK_TRI6] = {"tri6", 6, 2, 3, SIMPLEX(2, tri6_edges), tri6_nodes, 3, tri3_xi, tri3_w, SK_LINE3, 3, 3, tri6_faces},
    [SK_QUAD8] = {"quad8", 8, 2, 4, SERENDIPITY, quad9_nodes, 9, gauss3_2d_xi, gauss3_2d_w, SK_LINE3, 4, 3,
                  quad9_faces},
    [SK_TET10] = {"tet10", 10, 3, 4, SIMPLEX(2, tet10_edges), tet10_nodes, 4, tet4_xi, tet4_w, SK_TRI6, 4, 6,
                  tet10_faces},
    [SK_HEX20] = {"hex20", 20, 3, 8, SERENDIPITY, hex27_nodes, 27, gauss3_3d_xi, gauss3_3d_w, SK_QUAD8, 6, 8,
                  hex20_faces},
};
#undef TENSOR
#undef SIMPLEX
#undef SERENDIPITY

static const element_info *element_lookup(sk_elem_type type) {
  return ((int)type >= 0 && type < SK_ELEM_TYPE_COUNT) ? &element_table[type] : NULL;
}

int sk_elem_nen(sk_elem_type type) {
  const element_info *info = element_lookup(type);
  return info ? info->nen : 0;
}

int sk_elem_pdim(sk_elem_type type) {
  const element_info *info = element_lookup(type);
  return info ? info->pdim : -1;
}

int sk_elem_order(sk_elem_type type) {
  const element_info *info = element_lookup(type);
  return info ? info->order : 0;
}

int sk_elem_corners(sk_elem_type type) {
  const element_info *info = element_lookup(type);
  return info ? info->n_corners : 0;
}

int sk_elem_is_simplex(sk_elem_type type) {
  const element_info *info = element_lookup(type);
  return info && info->family == FAMILY_SIMPLEX;
}

const char *sk_elem_name(sk_elem_type type) {
  const element_info *info = element_lookup(type);
  return info ? info->name : "unknown";
}

/* ---- shape functions ----------------------------------------------------------------------------------------- */

/* 1D Lagrange factors on nodes {-1, +1} (order 1) or {-1, +1, 0} (order 2): values, first, second derivatives. */
static void lagrange_1d(int order, double x, double L[3], double dL[3], double ddL[3]) {
  if (order == 1) {
    L[0] = 0.5 * (1.0 - x), L[1] = 0.5 * (1.0 + x), L[2] = 0.0;
    dL[0] = -0.5, dL[1] = 0.5, dL[2] = 0.0;
    ddL[0] = ddL[1] = ddL[2] = 0.0;
  } else {
    L[0] = 0.5 * x * (x - 1.0), L[1] = 0.5 * x * (x + 1.0), L[2] = 1.0 - x * x;
    dL[0] = x - 0.5, dL[1] = x + 0.5, dL[2] = -2.0 * x;
    ddL[0] = 1.0, ddL[1] = 1.0, ddL[2] = -2.0;
  }
}

/* P = prod_k h_k(xi_k) from per-direction factors and their first and second derivatives: value, gradient dP[k],
 * Hessian ddP[k*pdim + l] (skipped when ddP is NULL: only the surface geometry asks for it, while the solid kernels
 * call this for every node at every quadrature point — the Hessian loop was 12 % of the full two-tori run's CPU,
 * docs/linear-solvers.md). */
static void product_derivatives(int pdim, const double *h, const double *dh, const double *ddh, double *P,
                                double *dP, double *ddP) {
  *P = 1.0;
  for (int k = 0; k < pdim; ++k) *P *= h[k];
  for (int k = 0; k < pdim; ++k) {
    dP[k] = dh[k];
    for (int m = 0; m < pdim; ++m)
      if (m != k) dP[k] *= h[m];
    for (int l = 0; ddP && l < pdim; ++l) {
      double value = 1.0;
      for (int m = 0; m < pdim; ++m) {
        if (m == k && m == l) value *= ddh[m];
        else if (m == k || m == l) value *= dh[m];
        else value *= h[m];
      }
      ddP[k * pdim + l] = value;
    }
  }
}

/* Writes one node's value, gradient and Hessian into the optional outputs. */
static void store_node(int pdim, int a, double value, const double *grad, const double *hess, double *N, double *dN,
                       double *ddN) {
  if (N) N[a] = value;
  if (dN)
    for (int k = 0; k < pdim; ++k) dN[a * pdim + k] = grad[k];
  if (ddN)
    for (int kl = 0; kl < pdim * pdim; ++kl) ddN[a * pdim * pdim + kl] = hess[kl];
}

static void tensor_shape(const element_info *info, const double *xi, double *N, double *dN, double *ddN) {
  const int pdim = info->pdim;
  double L[3][3], dL[3][3], ddL[3][3];
  for (int k = 0; k < pdim; ++k) lagrange_1d(info->order, xi[k], L[k], dL[k], ddL[k]);
  for (int a = 0; a < info->nen; ++a) {
    const unsigned char *id = info->tensor_index + a * pdim;
    double h[3], dh[3], ddh[3], P, dP[3], ddP[9];
    for (int k = 0; k < pdim; ++k) h[k] = L[k][id[k]], dh[k] = dL[k][id[k]], ddh[k] = ddL[k][id[k]];
    product_derivatives(pdim, h, dh, ddh, &P, dP, ddN ? ddP : NULL);
    store_node(pdim, a, P, dP, ddP, N, dN, ddN);
  }
}

/* Barycentric L_0 = 1 - sum xi, L_k = xi_{k-1}. P1: N_a = L_a. P2: corners L_a (2 L_a - 1), the edge node of corners
 * (i, j) 4 L_i L_j. Gradients and Hessians follow from the constant dL_a/dxi_k. */
static void simplex_shape(const element_info *info, const double *xi, double *N, double *dN, double *ddN) {
  const int pdim = info->pdim;
  double L[4], dL[4][3] = {{0}};
  L[0] = 1.0;
  for (int k = 0; k < pdim; ++k) {
    L[0] -= xi[k];
    L[k + 1] = xi[k];
    dL[0][k] = -1.0;
    dL[k + 1][k] = 1.0;
  }
  for (int a = 0; a <= pdim; ++a) {
    double grad[3], hess[9];
    const double value = info->order == 1 ? L[a] : L[a] * (2.0 * L[a] - 1.0);
    for (int k = 0; k < pdim; ++k) {
      grad[k] = info->order == 1 ? dL[a][k] : (4.0 * L[a] - 1.0) * dL[a][k];
      for (int l = 0; l < pdim; ++l) hess[k * pdim + l] = info->order == 1 ? 0.0 : 4.0 * dL[a][k] * dL[a][l];
    }
    store_node(pdim, a, value, grad, hess, N, dN, ddN);
  }
  for (int e = 0; info->order == 2 && e < info->nen - pdim - 1; ++e) {
    const int i = info->edges[2 * e], j = info->edges[2 * e + 1];
    double grad[3], hess[9];
    for (int k = 0; k < pdim; ++k) {
      grad[k] = 4.0 * (dL[i][k] * L[j] + L[i] * dL[j][k]);
      for (int l = 0; l < pdim; ++l) hess[k * pdim + l] = 4.0 * (dL[i][k] * dL[j][l] + dL[i][l] * dL[j][k]);
    }
    store_node(pdim, pdim + 1 + e, 4.0 * L[i] * L[j], grad, hess, N, dN, ddN);
  }
}

/* Serendipity (quad8, hex20), node coordinates c in {-1, 0, 1}^d, f_k = 1 + c_k xi_k:
 *   corner:            N = 2^-d prod_k f_k (sum_k c_k xi_k - (d - 1))
 *   edge (c_m = 0):    N = 2^-(d-1) (1 - xi_m^2) prod_{k != m} f_k. */
static void serendipity_shape(const element_info *info, const double *xi, double *N, double *dN, double *ddN) {
  const int pdim = info->pdim;
  for (int a = 0; a < info->nen; ++a) {
    const double *c = info->node_xi + a * pdim;
    double h[3], dh[3], ddh[3], P, dP[3], ddP[9] = {0}, grad[3], hess[9], value;
    int mid = -1;
    for (int k = 0; k < pdim; ++k) {
      if (c[k] == 0.0) {
        mid = k;
        h[k] = 1.0 - xi[k] * xi[k], dh[k] = -2.0 * xi[k], ddh[k] = -2.0;
      } else {
        h[k] = 1.0 + c[k] * xi[k], dh[k] = c[k], ddh[k] = 0.0;
      }
    }
    product_derivatives(pdim, h, dh, ddh, &P, dP, ddN ? ddP : NULL);
    if (mid >= 0) {
      const double scale = pdim == 2 ? 0.5 : 0.25;
      value = scale * P;
      for (int k = 0; k < pdim; ++k) grad[k] = scale * dP[k];
      for (int kl = 0; kl < pdim * pdim; ++kl) hess[kl] = scale * ddP[kl];
    } else {
      const double scale = pdim == 2 ? 0.25 : 0.125;
      double S = 1.0 - pdim;
      for (int k = 0; k < pdim; ++k) S += c[k] * xi[k];
      value = scale * P * S;
      for (int k = 0; k < pdim; ++k) {
        grad[k] = scale * (dP[k] * S + P * c[k]);
        for (int l = 0; l < pdim; ++l)
          hess[k * pdim + l] = scale * (ddP[k * pdim + l] * S + dP[k] * c[l] + dP[l] * c[k]);
      }
    }
    store_node(pdim, a, value, grad, hess, N, dN, ddN);
  }
}

static void shape_any(const element_info *info, const double *xi, double *N, double *dN, double *ddN) {
  switch (info->family) {
    case FAMILY_POINT:
      if (N) N[0] = 1.0;
      return;
    case FAMILY_TENSOR: tensor_shape(info, xi, N, dN, ddN); return;
    case FAMILY_SIMPLEX: simplex_shape(info, xi, N, dN, ddN); return;
    case FAMILY_SERENDIPITY: serendipity_shape(info, xi, N, dN, ddN); return;
  }
}

void sk_elem_shape(sk_elem_type type, const double *xi, double *N, double *dN) {
  const element_info *info = element_lookup(type);
  if (!info || (!N && !dN) || (!xi && info->pdim > 0)) return;
  shape_any(info, xi, N, dN, NULL);
}

void sk_elem_shape_hessian(sk_elem_type type, const double *xi, double *ddN) {
  const element_info *info = element_lookup(type);
  if (!info || !ddN || (!xi && info->pdim > 0)) return;
  shape_any(info, xi, NULL, NULL, ddN);
}

void sk_elem_quadrature(sk_elem_type type, int *n, const double **xi, const double **w) {
  const element_info *info = element_lookup(type);
  if (n) *n = info ? info->n_qp : 0;
  if (xi) *xi = info ? info->qp_xi : NULL;
  if (w) *w = info ? info->qp_w : NULL;
}

const double *sk_elem_node_coords(sk_elem_type type) {
  const element_info *info = element_lookup(type);
  return info ? info->node_xi : NULL;
}

int sk_elem_faces(sk_elem_type type, sk_elem_type *face_type, const int **face_nodes, int *face_nen) {
  const element_info *info = element_lookup(type);
  if (face_type) *face_type = info ? info->face_type : SK_POINT1;
  if (face_nodes) *face_nodes = info ? info->faces : NULL;
  if (face_nen) *face_nen = info ? info->face_nen : 0;
  return info ? info->n_faces : 0;
}
