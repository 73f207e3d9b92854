/* stickslip — mesh module internals shared by its source files (not installed, not part of the API). */
#ifndef STICKSLIP_MESH_INTERNAL_H
#define STICKSLIP_MESH_INTERNAL_H

#include "stickslip/mesh.h"

/* The parameter names a .geo script declares with DefineConstant[ name = ..., ... ], read from its text because
 * gmsh 4.8 has no API to list them. On success *names is an array of *n_names malloc'ed strings (free with
 * sk_geo_names_free). */
sk_status sk_geo_defined_constants(const char *path, char ***names, int *n_names);
void sk_geo_names_free(char **names, int n_names);

/* Makes body elements positively oriented and boundary elements face out of the body they bound (see
 * mesh_orient.c). */
sk_status sk_mesh_orient(sk_mesh *mesh);

#endif
