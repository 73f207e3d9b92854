/* Element catalogue: Lagrange shape functions in gmsh node ordering, quadrature rules, node coordinates and
 * outward-oriented face tables for every sk_elem_type. */
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

/* Degree-2 simplex rules (exact for the mass matrix of an affine triangle/tetrahedron). */
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
static const double quad4_nodes[] = {-1, -1, 1, -1, 1, 1, -1, 1};
static const double quad9_nodes[] = {-1, -1, 1, -1, 1, 1, -1, 1, 0, -1, 1, 0, 0, 1, -1, 0, 0, 0};
static const double tet4_nodes[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
static const double hex8_nodes[] = {-1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1,
                                    -1, -1, 1,  1, -1, 1,  1, 1, 1,  -1, 1, 1};
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

/* ---- faces: node lists ordered so that a1 x a2 (2D: (t_y, -t_x)) points out of the element ---------------- */
static const int line_faces[] = {0, 1};
static const int tri3_faces[] = {0, 1, 1, 2, 2, 0};
static const int quad4_faces[] = {0, 1, 1, 2, 2, 3, 3, 0};
static const int quad9_faces[] = {0, 1, 4, 1, 2, 5, 2, 3, 6, 3, 0, 7};
static const int tet4_faces[] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
/* Order: zeta = -1, eta = -1, xi = -1, xi = +1, eta = +1, zeta = +1 (the order of hex27's face-centre nodes). */
static const int hex8_faces[] = {0, 3, 2, 1, 0, 1, 5, 4, 0, 4, 7, 3, 1, 2, 6, 5, 3, 7, 6, 2, 4, 5, 6, 7};
static const int hex27_faces[] = {0, 3, 2, 1, 9,  13, 11, 8,  20, 0, 1, 5, 4, 8,  12, 16, 10, 21,
                                  0, 4, 7, 3, 10, 17, 15, 9,  22, 1, 2, 6, 5, 11, 14, 18, 12, 23,
                                  3, 7, 6, 2, 15, 19, 14, 13, 24, 4, 5, 6, 7, 16, 18, 19, 17, 25};

typedef struct {
  const char *name;
  int nen, pdim;
  int order;                        /* polynomial order of the 1D factors (tensor-product elements), else 0 */
  const unsigned char *tensor_index; /* NULL for simplices and the point */
  const double *node_xi;
  int n_qp;
  const double *qp_xi, *qp_w;
  sk_elem_type face_type;
  int n_faces, face_nen;
  const int *faces;
} element_info;

static const element_info element_table[SK_ELEM_TYPE_COUNT] = {
    [SK_POINT1] = {"point1", 1, 0, 0, NULL, point1_xi, 1, point1_xi, point1_w, SK_POINT1, 0, 0, NULL},
    [SK_LINE2] = {"line2", 2, 1, 1, line2_index, line2_nodes, 2, gauss2_1d_xi, gauss2_1d_w, SK_POINT1, 2, 1,
                  line_faces},
    [SK_LINE3] = {"line3", 3, 1, 2, line3_index, line3_nodes, 3, gauss3_1d_xi, gauss3_1d_w, SK_POINT1, 2, 1,
                  line_faces},
    [SK_TRI3] = {"tri3", 3, 2, 0, NULL, tri3_nodes, 3, tri3_xi, tri3_w, SK_LINE2, 3, 2, tri3_faces},
    [SK_QUAD4] = {"quad4", 4, 2, 1, quad4_index, quad4_nodes, 4, gauss2_2d_xi, gauss2_2d_w, SK_LINE2, 4, 2,
                  quad4_faces},
    [SK_QUAD9] = {"quad9", 9, 2, 2, quad9_index, quad9_nodes, 9, gauss3_2d_xi, gauss3_2d_w, SK_LINE3, 4, 3,
                  quad9_faces},
    [SK_TET4] = {"tet4", 4, 3, 0, NULL, tet4_nodes, 4, tet4_xi, tet4_w, SK_TRI3, 4, 3, tet4_faces},
    [SK_HEX8] = {"hex8", 8, 3, 1, hex8_index, hex8_nodes, 8, gauss2_3d_xi, gauss2_3d_w, SK_QUAD4, 6, 4,
                 hex8_faces},
    [SK_HEX27] = {"hex27", 27, 3, 2, hex27_index, hex27_nodes, 27, gauss3_3d_xi, gauss3_3d_w, SK_QUAD9, 6, 9,
                  hex27_faces},
};

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

const char *sk_elem_name(sk_elem_type type) {
  const element_info *info = element_lookup(type);
  return info ? info->name : "unknown";
}

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

static void tensor_shape(const element_info *info, const double *xi, double *N, double *dN, double *ddN) {
  const int pdim = info->pdim;
  double L[3][3], dL[3][3], ddL[3][3];
  for (int k = 0; k < pdim; ++k) lagrange_1d(info->order, xi[k], L[k], dL[k], ddL[k]);
  for (int a = 0; a < info->nen; ++a) {
    const unsigned char *id = info->tensor_index + a * pdim;
    if (N) {
      double value = 1.0;
      for (int k = 0; k < pdim; ++k) value *= L[k][id[k]];
      N[a] = value;
    }
    if (dN) {
      for (int k = 0; k < pdim; ++k) {
        double value = dL[k][id[k]];
        for (int m = 0; m < pdim; ++m)
          if (m != k) value *= L[m][id[m]];
        dN[a * pdim + k] = value;
      }
    }
    if (ddN) {
      for (int k = 0; k < pdim; ++k) {
        for (int l = 0; l < pdim; ++l) {
          double value = 1.0;
          for (int m = 0; m < pdim; ++m) {
            if (m == k && m == l) value *= ddL[m][id[m]];
            else if (m == k || m == l) value *= dL[m][id[m]];
            else value *= L[m][id[m]];
          }
          ddN[(a * pdim + k) * pdim + l] = value;
        }
      }
    }
  }
}

void sk_elem_shape(sk_elem_type type, const double *xi, double *N, double *dN) {
  const element_info *info = element_lookup(type);
  if (!info || (!N && !dN) || (!xi && info->pdim > 0)) return;
  switch (type) {
    case SK_POINT1:
      if (N) N[0] = 1.0;
      return;
    case SK_TRI3:
      if (N) N[0] = 1.0 - xi[0] - xi[1], N[1] = xi[0], N[2] = xi[1];
      if (dN) dN[0] = -1.0, dN[1] = -1.0, dN[2] = 1.0, dN[3] = 0.0, dN[4] = 0.0, dN[5] = 1.0;
      return;
    case SK_TET4:
      if (N) N[0] = 1.0 - xi[0] - xi[1] - xi[2], N[1] = xi[0], N[2] = xi[1], N[3] = xi[2];
      if (dN) {
        for (int i = 0; i < 12; ++i) dN[i] = 0.0;
        dN[0] = dN[1] = dN[2] = -1.0;
        dN[3] = dN[7] = dN[11] = 1.0;
      }
      return;
    default:
      tensor_shape(info, xi, N, dN, NULL);
  }
}

void sk_elem_shape_hessian(sk_elem_type type, const double *xi, double *ddN) {
  const element_info *info = element_lookup(type);
  if (!info || !ddN || (!xi && info->pdim > 0)) return;
  if (!info->tensor_index) { /* simplices and the point are affine */
    for (int i = 0; i < info->nen * info->pdim * info->pdim; ++i) ddN[i] = 0.0;
    return;
  }
  tensor_shape(info, xi, NULL, NULL, ddN);
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
