/* Node ordering: every element type's parametric node coordinates equal gmsh's own (gmsh C API), so meshes can
 * be used as loaded. Quads/hexes: gmsh's reference is [-1, 1]^d like ours; simplices: the unit simplex. */
#include <gmshc.h>

#include "fe_test_util.h"
#include "sk_test.h"

int main(void) {
  static const int gmsh_type[SK_ELEM_TYPE_COUNT] = {15, 1, 8, 2, 3, 10, 4, 5, 12, 9, 16, 11, 17};
  int ierr = 0;
  gmshInitialize(0, NULL, 0, &ierr);
  SK_CHECK(ierr == 0);
  for (int t = 0; t < SK_ELEM_TYPE_COUNT; ++t) {
    char *name = NULL;
    int dim = -1, order = 0, nn = 0, nprimary = 0;
    double *coords = NULL;
    size_t ncoords = 0;
    gmshModelMeshGetElementProperties(gmsh_type[t], &name, &dim, &order, &nn, &coords, &ncoords, &nprimary, &ierr);
    SK_CHECK(ierr == 0);
    SK_CHECK(nn == sk_elem_nen((sk_elem_type)t));
    SK_CHECK(dim == sk_elem_pdim((sk_elem_type)t));
    const double *ours = sk_elem_node_coords((sk_elem_type)t);
    /* The point has no parametric coordinates of ours to compare (gmsh still reports one entry). */
    int same = nn == sk_elem_nen((sk_elem_type)t) && (dim == 0 || (size_t)(nn * dim) == ncoords);
    for (size_t i = 0; same && dim > 0 && i < ncoords; ++i) same = fabs(coords[i] - ours[i]) < 1e-14;
    if (!same) fprintf(stderr, "node coordinates of %s differ from gmsh's %s\n", sk_elem_name((sk_elem_type)t), name);
    SK_CHECK(same);
    gmshFree(name);
    gmshFree(coords);
  }
  gmshFinalize(&ierr);
  return sk_test_finish("fe_gmsh_ordering");
}
