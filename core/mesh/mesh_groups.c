/* Looking up physical groups by name and listing their nodes. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_internal.h"

const sk_group *sk_mesh_find_group(const sk_mesh *mesh, const char *name) {
  if (!mesh || !name) return NULL;
  for (int g = 0; g < mesh->n_groups; ++g)
    if (strcmp(mesh->groups[g].name, name) == 0) return &mesh->groups[g];
  return NULL;
}

/* "a (3D), b (2D), ..." for messages. */
static void list_groups(const sk_mesh *mesh, char *list, size_t size) {
  list[0] = '\0';
  for (int g = 0; g < mesh->n_groups; ++g) {
    size_t used = strlen(list);
    snprintf(list + used, size - used, "%s%s (%dD)", g ? ", " : "", mesh->groups[g].name, mesh->groups[g].dim);
  }
  if (mesh->n_groups == 0) snprintf(list, size, "none");
}

sk_status sk_mesh_require_group(const sk_mesh *mesh, const char *name, int dim, const sk_group **group) {
  if (group) *group = NULL;
  if (!mesh || !name || !group) return sk_error_set(SK_ERR_INTERNAL, "sk_mesh_require_group: NULL argument");
  const sk_group *found = sk_mesh_find_group(mesh, name);
  char list[1024];
  if (!found) {
    list_groups(mesh, list, sizeof list);
    return sk_error_set(SK_ERR_INPUT, "mesh %s has no physical group '%s' (it has: %s)", mesh->source, name, list);
  }
  /* dim < 0 accepts any dimension. */
  if (dim >= 0 && found->dim != dim)
    return sk_error_set(SK_ERR_INPUT, "mesh %s: physical group '%s' has dimension %d, but dimension %d is needed here",
                        mesh->source, name, found->dim, dim);
  *group = found;
  return SK_OK;
}

static int compare_ints(const void *a, const void *b) {
  int x = *(const int *)a, y = *(const int *)b;
  return (x > y) - (x < y);
}

sk_status sk_group_nodes(const sk_group *group, int **nodes, int *n_nodes) {
  if (!group || !nodes || !n_nodes) return sk_error_set(SK_ERR_INTERNAL, "sk_group_nodes: NULL argument");
  *nodes = NULL;
  *n_nodes = 0;
  size_t count = (size_t)group->n_elems * (size_t)group->nen;
  int *ids = malloc((count + 1) * sizeof *ids);
  if (!ids) return sk_error_set(SK_ERR_NOMEM, "out of memory listing the nodes of group '%s'", group->name);
  if (count) memcpy(ids, group->conn, count * sizeof *ids);
  qsort(ids, count, sizeof *ids, compare_ints);
  size_t unique = 0;
  for (size_t k = 0; k < count; ++k)
    if (unique == 0 || ids[unique - 1] != ids[k]) ids[unique++] = ids[k];
  *nodes = ids;
  *n_nodes = (int)unique;
  return SK_OK;
}
