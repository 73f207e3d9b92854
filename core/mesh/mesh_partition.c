/* METIS k-way partition of the elements of some groups on their dual graph (elements adjacent across a face). */
#include <metis.h>
#include <stdlib.h>

#include "mesh_internal.h"
#include "stickslip/fe.h"

/* Corners shared by two elements adjacent across a face (the corners of a face; 1 for lines). Corner nodes come
 * first in gmsh's ordering, so quadratic elements are partitioned by their corners. */
static int face_corner_count(sk_elem_type type) {
  sk_elem_type face_type;
  if (sk_elem_faces(type, &face_type, NULL, NULL) <= 0) return 1;
  return sk_elem_corners(face_type);
}

sk_status sk_mesh_partition(const sk_mesh *mesh, const sk_group *const *bodies, int n_bodies, int n_parts, int *part) {
  if (!mesh || (n_bodies > 0 && !bodies) || n_bodies < 0 || !part)
    return sk_error_set(SK_ERR_INTERNAL, "sk_mesh_partition: NULL or negative argument");
  if (n_parts < 1) return sk_error_set(SK_ERR_INPUT, "mesh %s: cannot split into %d parts", mesh->source, n_parts);
  size_t n_elems = 0, n_corners = 0;
  int ncommon = 0;
  for (int b = 0; b < n_bodies; ++b) {
    if (!bodies[b]) return sk_error_set(SK_ERR_INTERNAL, "sk_mesh_partition: body %d is NULL", b);
    n_elems += (size_t)bodies[b]->n_elems;
    n_corners += (size_t)bodies[b]->n_elems * (size_t)sk_elem_corners(bodies[b]->type);
    int common = face_corner_count(bodies[b]->type);
    if (ncommon == 0 || common < ncommon) ncommon = common;
  }
  if (n_parts == 1 || n_elems == 0) {
    for (size_t e = 0; e < n_elems; ++e) part[e] = 0;
    return SK_OK;
  }
  if ((size_t)n_parts > n_elems)
    return sk_error_set(SK_ERR_INPUT, "mesh %s: cannot split %zu elements into %d parts", mesh->source, n_elems,
                        n_parts);

  idx_t *eptr = malloc((n_elems + 1) * sizeof *eptr);
  idx_t *eind = malloc((n_corners + 1) * sizeof *eind);
  idx_t *epart = malloc(n_elems * sizeof *epart);
  idx_t *npart = malloc(((size_t)mesh->n_nodes + 1) * sizeof *npart);
  sk_status status = SK_OK;
  if (!eptr || !eind || !epart || !npart) {
    status = sk_error_set(SK_ERR_NOMEM, "mesh %s: out of memory partitioning", mesh->source);
  } else {
    size_t e = 0, k = 0;
    eptr[0] = 0;
    for (int b = 0; b < n_bodies; ++b) {
      const sk_group *group = bodies[b];
      int corners = sk_elem_corners(group->type);
      for (int i = 0; i < group->n_elems; ++i, ++e) {
        for (int a = 0; a < corners; ++a) eind[k++] = group->conn[(size_t)i * (size_t)group->nen + (size_t)a];
        eptr[e + 1] = (idx_t)k;
      }
    }
    idx_t options[METIS_NOPTIONS];
    METIS_SetDefaultOptions(options);
    options[METIS_OPTION_SEED] = 12345; /* fixed: the same mesh always gives the same partition */
    options[METIS_OPTION_NUMBERING] = 0;
    idx_t ne = (idx_t)n_elems, nn = (idx_t)mesh->n_nodes, common = ncommon, nparts = n_parts, objval = 0;
    int result = METIS_PartMeshDual(&ne, &nn, eptr, eind, NULL, NULL, &common, &nparts, NULL, options, &objval,
                                    epart, npart);
    if (result != METIS_OK) {
      status = sk_error_set(SK_ERR_INTERNAL, "mesh %s: METIS failed to partition %zu elements into %d parts (code %d)",
                            mesh->source, n_elems, n_parts, result);
    } else {
      for (size_t i = 0; i < n_elems; ++i) part[i] = (int)epart[i];
    }
  }
  free(eptr);
  free(eind);
  free(epart);
  free(npart);
  return status;
}
