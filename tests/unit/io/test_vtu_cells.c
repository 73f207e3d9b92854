/* VTU cells of every element type: the VTK cell type, and for each VTK node k the gmsh node sk_vtu_node_order gives
 * sits at VTK's parametric position k (vtkQuadraticEdge/Triangle/Quad/Tetra/Hexahedron, vtkBiQuadraticQuad,
 * vtkTriQuadraticHexahedron; VTK's cubes live on [0,1]^d, gmsh's on [-1,1]^d). */
#include "sk_test.h"
#include "stickslip/fe.h"
#include "stickslip/output.h"

static const double line3_vtk[] = {0, 1, .5};
static const double tri6_vtk[] = {0, 0, 1, 0, 0, 1, .5, 0, .5, .5, 0, .5};
static const double quad9_vtk[] = {0, 0, 1, 0, 1, 1, 0, 1, .5, 0, 1, .5, .5, 1, 0, .5, .5, .5}; /* quad8: 8 first */
static const double tet10_vtk[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, .5, 0, 0,
                                   .5, .5, 0, 0, .5, 0, 0, 0, .5, .5, 0, .5, 0, .5, .5};
/* hex20: the first 20 nodes */
static const double hex27_vtk[] = {0,  0,  0,  1,  0,  0,  1,  1,  0,  0,  1,  0,  0,  0,  1,  1,  0,  1,  1,  1,  1,
                                   0,  1,  1,  .5, 0,  0,  1,  .5, 0,  .5, 1,  0,  0,  .5, 0,  .5, 0,  1,  1,  .5, 1,
                                   .5, 1,  1,  0,  .5, 1,  0,  0,  .5, 1,  0,  .5, 1,  1,  .5, 0,  1,  .5, 0,  .5, .5,
                                   1,  .5, .5, .5, 0,  .5, .5, 1,  .5, .5, .5, 0,  .5, .5, 1,  .5, .5, .5};

static void check_type(sk_elem_type type, int vtk_type, const double *vtk_pcoords) {
  SK_CHECK(sk_vtu_cell_type(type) == vtk_type);
  const int nen = sk_elem_nen(type), pdim = sk_elem_pdim(type);
  const double *xi = sk_elem_node_coords(type);
  const int *order = sk_vtu_node_order(type);
  int wrong = 0, seen[SK_MAX_NEN] = {0};
  for (int k = 0; k < nen; ++k) {
    const int a = order[k];
    wrong += a < 0 || a >= nen;
    if (a < 0 || a >= nen) continue;
    ++seen[a];
    for (int d = 0; d < pdim; ++d) {
      const double gmsh = sk_elem_is_simplex(type) ? xi[a * pdim + d] : 0.5 * (xi[a * pdim + d] + 1.0);
      wrong += gmsh != vtk_pcoords[k * pdim + d];
    }
  }
  for (int a = 0; a < nen; ++a) wrong += seen[a] != 1; /* a permutation */
  if (wrong) fprintf(stderr, "%s: %d node(s) out of VTK's order\n", sk_elem_name(type), wrong);
  SK_CHECK(wrong == 0);
}

int main(void) {
  check_type(SK_LINE3, 21, line3_vtk);
  check_type(SK_TRI6, 22, tri6_vtk);
  check_type(SK_QUAD8, 23, quad9_vtk);
  check_type(SK_QUAD9, 28, quad9_vtk);
  check_type(SK_TET10, 24, tet10_vtk);
  check_type(SK_HEX20, 25, hex27_vtk);
  check_type(SK_HEX27, 29, hex27_vtk);
  return sk_test_finish("test_vtu_cells");
}
