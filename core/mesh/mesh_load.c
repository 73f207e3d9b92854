/* sk_mesh_load: .geo scripts are meshed and .msh files read through the gmsh C API; the physical groups become
 * sk_groups with compact 0-based node ids (gmsh's element node ordering is kept). */
#define _DEFAULT_SOURCE /* realpath, mkstemps */

#include <errno.h>
#include <gmshc.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "mesh_internal.h"
#include "stickslip/files.h"

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
static void gmsh_session_begin(void) {
  int ierr = 0;
  gmshInitialize(0, NULL, 0, &ierr);
  gmshOptionSetNumber("General.Terminal", 0, &ierr);
  gmshLoggerStart(&ierr);
}

static void gmsh_session_end(void) {
  int ierr = 0;
  gmshLoggerStop(&ierr);
  gmshFinalize(&ierr);
}

/* Non-zero when the last gmsh call failed (ierr) or logged an error; the message then names the file. */
static int gmsh_failed(int ierr, const char *path, const char *what) {
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

/* ---- .geo parameters --------------------------------------------------------------------------------------- */

static int is_identifier(const char *name) {
  if (!name || !(name[0] == '_' || (name[0] >= 'a' && name[0] <= 'z') || (name[0] >= 'A' && name[0] <= 'Z')))
    return 0;
  for (const char *c = name; *c; ++c)
    if (!(*c == '_' || (*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') || (*c >= '0' && *c <= '9'))) return 0;
  return 1;
}

/* Every parameter must be a DefineConstant of the script: typos are errors, not silently ignored values. */
static sk_status check_parameters(const char *path, const sk_mesh_param *params, int n_params) {
  char **names = NULL;
  int n_names = 0;
  SK_TRY(sk_geo_scan(path, &names, &n_names));
  sk_status status = SK_OK;
  for (int p = 0; p < n_params && status == SK_OK; ++p) {
    const char *name = params[p].name;
    if (!is_identifier(name)) {
      status = sk_error_set(SK_ERR_INPUT, "mesh %s: parameter name '%s' is not a valid identifier", path,
                            name ? name : "(null)");
      break;
    }
    if (!isfinite(params[p].value)) {
      status = sk_error_set(SK_ERR_INPUT, "mesh %s: parameter '%s' has a non-finite value", path, name);
      break;
    }
    int known = 0;
    for (int i = 0; i < n_names; ++i) known |= strcmp(names[i], name) == 0;
    if (!known) {
      char list[1024] = "";
      for (int i = 0; i < n_names; ++i) {
        size_t used = strlen(list);
        snprintf(list + used, sizeof list - used, "%s%s", i ? ", " : "", names[i]);
      }
      status = sk_error_set(SK_ERR_INPUT, "mesh %s: unknown parameter '%s' (the script defines: %s)", path, name,
                            n_names ? list : "none");
    }
  }
  sk_geo_names_free(names, n_names);
  return status;
}

/* gmsh 4.8's ways to set a DefineConstant (-setnumber, ONELAB) outlive gmshFinalize, so a later load would see
 * stale values. Instead a temporary script assigns the values and includes the real one: DefineConstant keeps a
 * value that already exists. */
static sk_status write_wrapper_script(const char *path, const sk_mesh_param *params, int n_params,
                                      char *wrapper, size_t wrapper_size) {
  char *absolute = realpath(path, NULL);
  if (!absolute) return sk_error_set(SK_ERR_IO, "mesh %s: cannot resolve path: %s", path, strerror(errno));
  if (strchr(absolute, '"')) {
    free(absolute);
    return sk_error_set(SK_ERR_INPUT, "mesh %s: the path must not contain a double quote", path);
  }
  const char *tmpdir = getenv("TMPDIR");
  if (!tmpdir || !tmpdir[0]) tmpdir = "/tmp";
  int n = snprintf(wrapper, wrapper_size, "%s/stickslip-mesh-XXXXXX.geo", tmpdir);
  if (n < 0 || (size_t)n >= wrapper_size) {
    free(absolute);
    return sk_error_set(SK_ERR_IO, "mesh %s: TMPDIR path too long", path);
  }
  int fd = mkstemps(wrapper, 4);
  if (fd < 0) {
    free(absolute);
    return sk_error_set(SK_ERR_IO, "mesh %s: cannot create a temporary script in %s: %s", path, tmpdir,
                        strerror(errno));
  }
  FILE *file = fdopen(fd, "w");
  if (!file) {
    close(fd);
    unlink(wrapper);
    free(absolute);
    return sk_error_set(SK_ERR_IO, "mesh %s: cannot write a temporary script: %s", path, strerror(errno));
  }
  for (int p = 0; p < n_params; ++p) fprintf(file, "%s = %.17g;\n", params[p].name, params[p].value);
  fprintf(file, "Include \"%s\";\n", absolute);
  free(absolute);
  if (fclose(file) != 0) {
    unlink(wrapper);
    return sk_error_set(SK_ERR_IO, "mesh %s: cannot write a temporary script: %s", path, strerror(errno));
  }
  return SK_OK;
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
  if (gmsh_failed(ierr, path, "read a physical group name")) {
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
  if (gmsh_failed(ierr, path, "list the entities of a physical group")) {
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
    if (gmsh_failed(ierr, path, "read elements")) status = SK_ERR_INPUT;
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
static sk_status read_model(const char *path, int dim, sk_mesh *mesh) {
  int ierr = 0;
  int *group_tags = NULL;
  size_t n_group_tags = 0;
  gmshModelGetPhysicalGroups(&group_tags, &n_group_tags, -1, &ierr);
  if (gmsh_failed(ierr, path, "list physical groups")) {
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
    if (gmsh_failed(ierr, path, "read nodes")) status = SK_ERR_INPUT;
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
static int highest_group_dimension(const char *path, int *highest) {
  int ierr = 0;
  int *group_tags = NULL;
  size_t n = 0;
  gmshModelGetPhysicalGroups(&group_tags, &n, -1, &ierr);
  if (gmsh_failed(ierr, path, "list physical groups")) {
    gmshFree(group_tags);
    return 0;
  }
  *highest = -1;
  for (size_t g = 0; g < n / 2; ++g)
    if (group_tags[2 * g] > *highest) *highest = group_tags[2 * g];
  gmshFree(group_tags);
  return 1;
}

static sk_status check_plane(const char *path, const sk_mesh *mesh) {
  double extent = 0.0;
  for (int i = 0; i < 3 * mesh->n_nodes; ++i) extent = fmax(extent, fabs(mesh->x[i]));
  for (int n = 0; n < mesh->n_nodes; ++n)
    if (fabs(mesh->x[3 * n + 2]) > 1e-12 * fmax(extent, 1.0))
      return sk_error_set(SK_ERR_INPUT, "mesh %s: a 2D mesh must lie in the plane z = 0, but node %d has z = %g",
                          path, n, mesh->x[3 * n + 2]);
  return SK_OK;
}

/* ---- the work done in the mesh generator's child process ------------------------------------------------------ */

typedef struct {
  const char *path;        /* the file, for messages */
  const char *open_path;   /* the file gmsh opens (the parameter wrapper, or the file itself) */
  int is_geo, dim;
  int order, serendipity;  /* sk_mesh_options' */
  sk_mesh_guard guard;
} load_job;

/* Second-order elements from the first-order mesh of the current model. gmsh puts the new nodes on the geometry
 * (curved boundaries stay curved) for a .geo script and on straight edges for a .msh file, which has no geometry. */
static sk_status raise_order(const char *path, int order, int serendipity) {
  int ierr = 0;
  gmshOptionSetNumber("Mesh.SecondOrderIncomplete", serendipity ? 1 : 0, &ierr);
  if (gmsh_failed(ierr, path, "set Mesh.SecondOrderIncomplete")) return SK_ERR_INPUT;
  gmshModelMeshSetOrder(order, &ierr);
  if (gmsh_failed(ierr, path, "make second-order elements")) return SK_ERR_INPUT;
  return SK_OK;
}

static const char *failed_path; /* the file gmsh_failed names (the child is single-threaded) */

static int stage_failed(int ierr, const char *what) { return gmsh_failed(ierr, failed_path, what); }

static sk_status load_in_child(void *arg, sk_mesh *mesh) {
  load_job *job = arg;
  const char *path = job->path;
  failed_path = path;
  sk_status status = SK_OK;
  int ierr = 0, dim = job->dim;
  sk_mesh_sandbox_phase(job->is_geo ? "evaluating the script" : "reading the file");
  gmsh_session_begin();
  gmshOpen(job->open_path, &ierr);
  if (gmsh_failed(ierr, path, "read the file")) status = SK_ERR_INPUT;

  int highest = -1;
  if (status == SK_OK && !highest_group_dimension(path, &highest)) status = SK_ERR_INPUT;
  if (status == SK_OK && highest < 0)
    status = sk_error_set(SK_ERR_INPUT, "mesh %s: no physical groups (name the bodies and boundaries with "
                                        "Physical Volume/Surface/Curve(\"name\"))", path);
  if (status == SK_OK && dim == 0) {
    dim = highest;
    if (dim != 2 && dim != 3)
      status = sk_error_set(SK_ERR_INPUT, "mesh %s: the highest physical group has dimension %d; stickslip meshes "
                                          "are 2D or 3D", path, dim);
  }
  /* Script errors stay exceptions (the API's General.AbortOnError = 2), which gmshOpen catches: with 0, an Error()
   * followed by Abort inside an Included script double-frees in gmsh 4.8.4. Meshing errors must not be exceptions:
   * thrown inside gmsh's OpenMP regions (a mesh size <= 0 while meshing curves) nothing can catch them and the
   * process aborts. With 0 gmsh logs them and goes on, and stage_failed() stops after the stage. */
  gmshOptionSetNumber("General.AbortOnError", 0, &ierr);
  if (status == SK_OK && job->is_geo) status = sk_mesh_generate_guarded(&job->guard, dim, stage_failed);
  if (status == SK_OK && job->order > 0) {
    sk_mesh_sandbox_phase("making the elements second order");
    status = raise_order(path, job->order, job->serendipity);
  }
  if (status == SK_OK) {
    sk_mesh_sandbox_phase("reading the mesh from gmsh");
    mesh->dim = dim;
    status = read_model(path, dim, mesh);
  }
  if (status == SK_OK && !job->is_geo) {
    double count = 0;
    for (int g = 0; g < mesh->n_groups; ++g) count += mesh->groups[g].dim == dim ? mesh->groups[g].n_elems : 0;
    if (count > (double)job->guard.max_elements)
      status = sk_error_set(SK_ERR_INPUT, "mesh %s has %.0f elements of dimension %d, more than mesh.max_elements = "
                            "%ld; raise mesh.max_elements if such a mesh is meant", path, count, dim,
                            job->guard.max_elements);
  }
  gmsh_session_end();
  return status;
}

/* ---- public -------------------------------------------------------------------------------------------------- */

static int has_suffix(const char *text, const char *suffix) {
  size_t n = strlen(text), m = strlen(suffix);
  return n >= m && strcmp(text + n - m, suffix) == 0;
}

/* gmsh's peak resident memory per element stays below 1 kB on every mesh measured (0.35-0.85 kB with gmsh 4.8.4:
 * build/bin/bench_mesh_limits, tests/bench/mesh-limits), and the child starts with what it shares with stickslip
 * (libraries, MPI): 2 kB per element plus 256 MB is a limit no mesh within mesh.max_elements reaches, which stops a
 * runaway mesh early. */
static size_t memory_limit_for(long max_elements) { return ((size_t)256 << 20) + (size_t)max_elements * 2048; }

void sk_mesh_options_default(sk_mesh_options *options) {
  memset(options, 0, sizeof *options);
  options->max_elements = SK_MESH_DEFAULT_MAX_ELEMENTS;
  options->time_limit = SK_MESH_DEFAULT_TIME_LIMIT;
}

static sk_status finish_load(const char *path, sk_mesh *mesh, sk_status status);

sk_status sk_mesh_load(const char *path, const sk_mesh_param *params, int n_params, int dim, sk_mesh *mesh) {
  sk_mesh_options options;
  sk_mesh_options_default(&options);
  options.dim = dim;
  return sk_mesh_load_with(path, params, n_params, &options, mesh);
}

sk_status sk_mesh_load_with(const char *path, const sk_mesh_param *params, int n_params,
                            const sk_mesh_options *options, sk_mesh *mesh) {
  if (!mesh) return sk_error_set(SK_ERR_INTERNAL, "sk_mesh_load: mesh is NULL");
  memset(mesh, 0, sizeof *mesh);
  if (!path || !path[0]) return sk_error_set(SK_ERR_INPUT, "sk_mesh_load: no mesh file given");
  snprintf(mesh->source, sizeof mesh->source, "%s", path);
  if (n_params < 0 || (n_params > 0 && !params))
    return sk_error_set(SK_ERR_INTERNAL, "mesh %s: bad parameter list (n_params = %d)", path, n_params);
  if (!options) return sk_error_set(SK_ERR_INTERNAL, "mesh %s: no load options", path);
  int dim = options->dim;
  if (dim != 0 && dim != 2 && dim != 3)
    return sk_error_set(SK_ERR_INPUT, "mesh %s: dimension %d requested; stickslip meshes are 2D or 3D", path, dim);
  if (options->max_elements < 1)
    return sk_error_set(SK_ERR_INPUT, "mesh %s: max_elements must be at least 1 (got %ld)", path,
                        options->max_elements);
  if (!(options->time_limit > 0))
    return sk_error_set(SK_ERR_INPUT, "mesh %s: time_limit must be positive (got %g s)", path, options->time_limit);
  if (options->order < 0 || options->order > 2)
    return sk_error_set(SK_ERR_INPUT, "mesh %s: element order %d requested; stickslip elements are of order 1 or 2",
                        path, options->order);
  if (options->serendipity && options->order != 2)
    return sk_error_set(SK_ERR_INPUT, "mesh %s: serendipity elements (quad8, hex20) need element order 2", path);

  int is_geo = has_suffix(path, ".geo");
  if (!is_geo && !has_suffix(path, ".msh"))
    return sk_error_set(SK_ERR_INPUT, "mesh %s: unknown mesh format (expected a gmsh .geo script or .msh file)", path);
  SK_TRY(sk_require_regular_file(path, "mesh"));
  if (!is_geo && n_params > 0)
    return sk_error_set(SK_ERR_INPUT, "mesh %s: parameter '%s' given, but a .msh file takes no parameters", path,
                        params[0].name ? params[0].name : "(null)");
  if (is_geo) SK_TRY(check_parameters(path, params, n_params));

  char parameters[512] = "";
  for (int p = 0; p < n_params; ++p) {
    size_t used = strlen(parameters);
    snprintf(parameters + used, sizeof parameters - used, "%s%s = %g", p ? ", " : "", params[p].name,
             params[p].value);
  }
  /* a script meshed before with the same text and parameters comes from the cache (mesh_cache.c) */
  sk_mesh_cache_key key;
  memset(&key, 0, sizeof key);
  if (is_geo) sk_mesh_cache_key_make(path, parameters, dim, options, &key);
  if (is_geo && sk_mesh_cache_load(&key, mesh)) {
    sk_mesh_cache_note(path, &key, 1);
    return finish_load(path, mesh, SK_OK);
  }
  char wrapper[1024] = "";
  if (n_params > 0) SK_TRY(write_wrapper_script(path, params, n_params, wrapper, sizeof wrapper));
  load_job job = {.path = path, .open_path = wrapper[0] ? wrapper : path, .is_geo = is_geo, .dim = dim,
                  .order = options->order, .serendipity = options->serendipity,
                  .guard = {.path = path, .parameters = parameters, .max_elements = options->max_elements}};
  sk_mesh_sandbox_limits limits = {.time_limit = options->time_limit,
                                   .memory_limit = memory_limit_for(options->max_elements),
                                   .max_elements = options->max_elements};
  sk_status status = sk_mesh_sandbox(load_in_child, &job, &limits, mesh);
  if (wrapper[0]) unlink(wrapper);
  if (status == SK_OK && is_geo && mesh->n_groups > 0) {
    sk_mesh_cache_store(&key, mesh);
    sk_mesh_cache_note(path, &key, 0);
  }
  /* gmsh's own errors say what went wrong but not with which values: name the parameters the scene gave */
  if (status == SK_ERR_INPUT && parameters[0] && !strstr(sk_error_message(), "(parameters: ")) {
    char message[2048];
    snprintf(message, sizeof message, "%s", sk_error_message());
    sk_error_set(status, "%s (parameters: %s)", message, parameters);
  }
  return finish_load(path, mesh, status);
}

/* The checks and orientation of a mesh from gmsh or the cache (the cache holds gmsh's mesh as it came). */
static sk_status finish_load(const char *path, sk_mesh *mesh, sk_status status) {
  if (status == SK_OK && mesh->n_groups == 0)
    status = sk_error_set(SK_ERR_INPUT, "mesh %s: no physical groups of dimension %d or lower", path, mesh->dim);
  if (status == SK_OK && mesh->dim == 2) status = check_plane(path, mesh);
  if (status == SK_OK) status = sk_mesh_orient(mesh);
  if (status == SK_OK) status = sk_mesh_check_elements(mesh);
  if (status != SK_OK) {
    char source[sizeof mesh->source];
    memcpy(source, mesh->source, sizeof source);
    sk_mesh_free(mesh);
    memcpy(mesh->source, source, sizeof source);
  }
  return status;
}

void sk_mesh_free(sk_mesh *mesh) {
  if (!mesh) return;
  for (int g = 0; g < mesh->n_groups; ++g) free(mesh->groups[g].conn);
  free(mesh->groups);
  free(mesh->x);
  memset(mesh, 0, sizeof *mesh);
}
