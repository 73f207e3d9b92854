/* The current gmsh model read into an sk_mesh: gmsh's element types, its start and end, its errors, and the physical
 * groups with the nodes they use (compact 0-based node ids in gmsh tag order; gmsh's element node ordering kept). */
#include <gmshc.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_internal.h"

/* gmsh element type numbers (gmsh manual, "MSH file format") and their stickslip counterparts. */
static const struct {
  int gmsh_type;
  sk_elem_type type;
  int dim, nen;
  const char *name;
} element_types[] = {
    {15, SK_POINT1, 0, 1, "point1"}, {1, SK_LINE2, 1, 2, "line2"},  {8, SK_LINE3, 1, 3, "line3"},
    {2, SK_TRI3, 2, 3, "tri3"},      {3, SK_QUAD4, 2, 4, "quad4"},  {10, SK_QUAD9, 2, 9, "quad9"},
    {4, SK_TET4, 3, 4, "tet4"},      {5, SK_HEX8, 3, 8, "hex8"},    {12, SK_HEX27, 3, 27, "hex27"},
    {9, SK_TRI6, 2, 6, "tri6"},      {16, SK_QUAD8, 2, 8, "quad8"}, {11, SK_TET10, 3, 10, "tet10"},
    {17, SK_HEX20, 3, 20, "hex20"},
};
enum { N_ELEMENT_TYPES = sizeof element_types / sizeof element_types[0] };

static int element_type_index(int gmsh_type) {
  for (int i = 0; i < N_ELEMENT_TYPES; ++i)
    if (element_types[i].gmsh_type == gmsh_type) return i;
  return -1;
}

/* ---- gmsh set-up --------------------------------------------------------------------------------------------- */

/* gmsh keeps global state, so each load runs between its own gmsh initialize and finalize, with the logger on: the
 * terminal stays quiet and errors are collected for our message instead. */
void sk_gmsh_session_begin(void) {
  int ierr = 0;
  gmshInitialize(0, NULL, 0, &ierr);
  gmshOptionSetNumber("General.Terminal", 0, &ierr);
  gmshLoggerStart(&ierr);
}

void sk_gmsh_session_end(void) {
  int ierr = 0;
  gmshLoggerStop(&ierr);
  gmshFinalize(&ierr);
}

/* Non-zero when the last gmsh call failed (ierr) or logged an error; the message then names the file. */
int sk_gmsh_failed(int ierr, const char *path, const char *what) {
  char *last = NULL;
  int ierr2 = 0;
  gmshLoggerGetLastError(&last, &ierr2);
  int failed = ierr != 0 || (last && last[0]);
  if (failed) {
    sk_error_set(SK_ERR_INPUT, "mesh %s: gmsh failed to %s: %s", path, what,
                 last && last[0] ? last : "(no message from gmsh)");
  }
  gmshFree(last);
  return failed;
}

int sk_gmsh_elements_get(int dim, int tag, sk_gmsh_elements *e) {
  int ierr = 0;
  memset(e, 0, sizeof *e);
  gmshModelMeshGetElements(&e->types, &e->n_types, &e->tags, &e->tags_n, &e->tags_nn, &e->nodes, &e->nodes_n,
                           &e->nodes_nn, dim, tag, &ierr);
  return ierr;
}

void sk_gmsh_elements_free(sk_gmsh_elements *e) {
  for (size_t t = 0; t < e->tags_nn; ++t) gmshFree(e->tags[t]);
  for (size_t t = 0; t < e->nodes_nn; ++t) gmshFree(e->nodes[t]);
  gmshFree(e->types);
  gmshFree(e->tags);
  gmshFree(e->tags_n);
  gmshFree(e->nodes);
  gmshFree(e->nodes_n);
  memset(e, 0, sizeof *e);
}

/* ---- reading the gmsh model -------------------------------------------------------------------------------- */

typedef struct {
  size_t tag;
  int index; /* position in gmsh's coordinate array */
} node_entry;

static int compare_node_entries(const void *a, const void *b) {
  size_t ta = ((const node_entry *)a)->tag, tb = ((const node_entry *)b)->tag;
  return (ta > tb) - (ta < tb);
}

static int find_node(const node_entry *nodes, size_t n_nodes, size_t tag) {
  size_t lo = 0, hi = n_nodes;
  while (lo < hi) {
    size_t mid = lo + (hi - lo) / 2;
    if (nodes[mid].tag < tag) lo = mid + 1;
    else hi = mid;
  }
  return lo < n_nodes && nodes[lo].tag == tag ? (int)lo : -1;
}

/* The elements of one physical group, with gmsh node tags (converted to compact ids later). */
typedef struct {
  int gmsh_dim, gmsh_tag;
  size_t *node_tags; /* malloc'ed, n_elems * nen */
} group_source;

static sk_status read_group(const char *path, int dim, int tag, sk_group *group, group_source *source) {
  int ierr = 0;
  char *name = NULL;
  gmshModelGetPhysicalName(dim, tag, &name, &ierr);
  if (sk_gmsh_failed(ierr, path, "read a physical group name")) {
    gmshFree(name);
    return SK_ERR_INPUT;
  }
  if (!name || !name[0]) {
    snprintf(group->name, sizeof group->name, "group-%d-%d", dim, tag); /* gmsh allows unnamed groups */
  } else if (strlen(name) >= sizeof group->name) {
    sk_status status = sk_error_set(SK_ERR_INPUT, "mesh %s: physical group name '%s' is longer than %zu characters",
                                    path, name, sizeof group->name - 1);
    gmshFree(name);
    return status;
  } else {
    snprintf(group->name, sizeof group->name, "%s", name);
  }
  gmshFree(name);
  group->dim = dim;
  source->gmsh_dim = dim;
  source->gmsh_tag = tag;

  int *entities = NULL;
  size_t n_entities = 0;
  gmshModelGetEntitiesForPhysicalGroup(dim, tag, &entities, &n_entities, &ierr);
  if (sk_gmsh_failed(ierr, path, "list the entities of a physical group")) {
    gmshFree(entities);
    return sk_error_prefix(SK_ERR_INPUT, "group '%s': ", group->name);
  }

  sk_status status = SK_OK;
  int type_index = -1;
  size_t n_elems = 0, capacity = 0;
  size_t *conn = NULL;
  for (size_t e = 0; e < n_entities && status == SK_OK; ++e) {
    sk_gmsh_elements got;
    ierr = sk_gmsh_elements_get(dim, entities[e], &got);
    if (sk_gmsh_failed(ierr, path, "read elements")) status = SK_ERR_INPUT;
    for (size_t t = 0; t < got.n_types && status == SK_OK; ++t) {
      int index = element_type_index(got.types[t]);
      if (index < 0) {
        status = sk_error_set(SK_ERR_INPUT,
                              "mesh %s: physical group '%s' has elements of gmsh type %d, which stickslip does not "
                              "support (supported: point1, line2, line3, tri3, tri6, quad4, quad8, quad9, tet4, tet10, "
                              "hex8, hex20, hex27)",
                              path, group->name, got.types[t]);
      } else if (type_index >= 0 && index != type_index) {
        status = sk_error_set(SK_ERR_INPUT,
                              "mesh %s: physical group '%s' mixes element types %s and %s (one type per group: "
                              "split the group or recombine the mesh)",
                              path, group->name, element_types[type_index].name, element_types[index].name);
      } else {
        type_index = index;
        size_t count = got.nodes_n[t];
        if (n_elems * (size_t)element_types[index].nen + count > capacity) {
          size_t new_capacity = 2 * capacity + count;
          size_t *bigger = realloc(conn, new_capacity * sizeof *conn);
          if (!bigger) {
            status = sk_error_set(SK_ERR_NOMEM, "mesh %s: out of memory reading group '%s'", path, group->name);
            break;
          }
          conn = bigger;
          capacity = new_capacity;
        }
        memcpy(conn + n_elems * (size_t)element_types[index].nen, got.nodes[t], count * sizeof *conn);
        n_elems += count / (size_t)element_types[index].nen;
      }
    }
    sk_gmsh_elements_free(&got);
  }
  gmshFree(entities);
  if (status == SK_OK && n_elems == 0)
    status = sk_error_set(SK_ERR_INPUT, "mesh %s: physical group '%s' (dimension %d) has no elements", path,
                          group->name, dim);
  if (status == SK_OK && n_elems > (size_t)(0x7fffffff / element_types[type_index].nen))
    status = sk_error_set(SK_ERR_INPUT, "mesh %s: physical group '%s' has too many elements", path, group->name);
  if (status != SK_OK) {
    free(conn);
    return status;
  }
  group->type = element_types[type_index].type;
  group->nen = element_types[type_index].nen;
  group->n_elems = (int)n_elems;
  source->node_tags = conn;
  return SK_OK;
}

/* Reads the physical groups up to `dim` and the nodes they use from the current gmsh model. */
sk_status sk_gmsh_read_model(const char *path, int dim, sk_mesh *mesh) {
  int ierr = 0;
  int *group_tags = NULL;
  size_t n_group_tags = 0;
  gmshModelGetPhysicalGroups(&group_tags, &n_group_tags, -1, &ierr);
  if (sk_gmsh_failed(ierr, path, "list physical groups")) {
    gmshFree(group_tags);
    return SK_ERR_INPUT;
  }
  int n_groups = 0;
  for (size_t g = 0; g < n_group_tags / 2; ++g) n_groups += group_tags[2 * g] <= dim;

  sk_status status = SK_OK;
  group_source *sources = calloc((size_t)n_groups + 1, sizeof *sources);
  mesh->groups = calloc((size_t)n_groups + 1, sizeof *mesh->groups);
  if (!sources || !mesh->groups) status = sk_error_set(SK_ERR_NOMEM, "mesh %s: out of memory", path);
  for (size_t g = 0; g < n_group_tags / 2 && status == SK_OK; ++g) {
    if (group_tags[2 * g] > dim) continue; /* e.g. volumes of a 3D script loaded as 2D: not meshed */
    status = read_group(path, group_tags[2 * g], group_tags[2 * g + 1], &mesh->groups[mesh->n_groups],
                        &sources[mesh->n_groups]);
    if (status == SK_OK) ++mesh->n_groups;
  }
  gmshFree(group_tags);
  for (int a = 0; a < mesh->n_groups && status == SK_OK; ++a)
    for (int b = a + 1; b < mesh->n_groups && status == SK_OK; ++b)
      if (strcmp(mesh->groups[a].name, mesh->groups[b].name) == 0)
        status = sk_error_set(SK_ERR_INPUT, "mesh %s: two physical groups are named '%s' (dimensions %d and %d)",
                              path, mesh->groups[a].name, mesh->groups[a].dim, mesh->groups[b].dim);

  /* All nodes of the model, sorted by tag for lookup. */
  size_t *node_tags = NULL, n_node_tags = 0, n_coords = 0, n_param = 0;
  double *coords = NULL, *param = NULL;
  node_entry *nodes = NULL;
  int *new_id = NULL;
  if (status == SK_OK) {
    gmshModelMeshGetNodes(&node_tags, &n_node_tags, &coords, &n_coords, &param, &n_param, -1, -1, 0, 0, &ierr);
    if (sk_gmsh_failed(ierr, path, "read nodes")) status = SK_ERR_INPUT;
  }
  if (status == SK_OK) {
    nodes = malloc((n_node_tags + 1) * sizeof *nodes);
    new_id = malloc((n_node_tags + 1) * sizeof *new_id);
    if (!nodes || !new_id) status = sk_error_set(SK_ERR_NOMEM, "mesh %s: out of memory", path);
  }
  if (status == SK_OK) {
    for (size_t i = 0; i < n_node_tags; ++i) {
      nodes[i].tag = node_tags[i];
      nodes[i].index = (int)i;
      new_id[i] = -1;
    }
    qsort(nodes, n_node_tags, sizeof *nodes, compare_node_entries);
    /* Mark the nodes used by some group, then number them 0..n-1 in gmsh tag order. */
    for (int g = 0; g < mesh->n_groups && status == SK_OK; ++g) {
      size_t count = (size_t)mesh->groups[g].n_elems * (size_t)mesh->groups[g].nen;
      for (size_t k = 0; k < count; ++k) {
        int found = find_node(nodes, n_node_tags, sources[g].node_tags[k]);
        if (found < 0) {
          status = sk_error_set(SK_ERR_INPUT, "mesh %s: group '%s' refers to node %zu, which does not exist", path,
                                mesh->groups[g].name, sources[g].node_tags[k]);
          break;
        }
        new_id[found] = 0;
      }
    }
  }
  if (status == SK_OK) {
    int n_used = 0;
    for (size_t i = 0; i < n_node_tags; ++i) /* `nodes` is in tag order; new_id[i] belongs to nodes[i] */
      if (new_id[i] == 0) new_id[i] = n_used++;
    mesh->n_nodes = n_used;
    mesh->x = malloc(((size_t)n_used + 1) * 3 * sizeof *mesh->x);
    if (!mesh->x) status = sk_error_set(SK_ERR_NOMEM, "mesh %s: out of memory", path);
    for (size_t i = 0; i < n_node_tags && status == SK_OK; ++i) {
      if (new_id[i] < 0) continue;
      memcpy(mesh->x + 3 * (size_t)new_id[i], coords + 3 * (size_t)nodes[i].index, 3 * sizeof *coords);
    }
  }
  for (int g = 0; g < mesh->n_groups && status == SK_OK; ++g) {
    sk_group *group = &mesh->groups[g];
    size_t count = (size_t)group->n_elems * (size_t)group->nen;
    group->conn = malloc(count * sizeof *group->conn);
    if (!group->conn) {
      status = sk_error_set(SK_ERR_NOMEM, "mesh %s: out of memory", path);
      break;
    }
    for (size_t k = 0; k < count; ++k) group->conn[k] = new_id[find_node(nodes, n_node_tags, sources[g].node_tags[k])];
  }
  for (int g = 0; g < n_groups && sources; ++g) free(sources[g].node_tags);
  free(sources);
  free(nodes);
  free(new_id);
  gmshFree(node_tags);
  gmshFree(coords);
  gmshFree(param);
  return status;
}

/* Highest dimension that carries a physical group, or -1 when there is none. */
int sk_gmsh_highest_group_dimension(const char *path, int *highest) {
  int ierr = 0;
  int *group_tags = NULL;
  size_t n = 0;
  gmshModelGetPhysicalGroups(&group_tags, &n, -1, &ierr);
  if (sk_gmsh_failed(ierr, path, "list physical groups")) {
    gmshFree(group_tags);
    return 0;
  }
  *highest = -1;
  for (size_t g = 0; g < n / 2; ++g)
    if (group_tags[2 * g] > *highest) *highest = group_tags[2 * g];
  gmshFree(group_tags);
  return 1;
}
