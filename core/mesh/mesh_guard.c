/* Mesh generation one dimension at a time, with the element count estimated before each expensive stage, so that a
 * scene asking for far too fine a mesh (a typo: refine = 1e6, h_contact = 1e-9) is refused in a second with the
 * numbers, instead of meshing until the memory is gone (issue 15, items 2 and 17). Runs in the mesh generator's
 * child process (mesh_sandbox.c), whose time and memory limits remain the last resort.
 *
 * The estimates, each checked against the limit before the next stage runs:
 * - during the curves (1D): gmsh integrates 1/h along each curve to place its nodes and asks the global size callback
 *   at every sample; the asks grow with the nodes being placed (build/bin/bench_mesh_limits, meshes/hertz-2d.geo:
 *   21 660 asks for 208 curve nodes at refine 1, 119 350 for 19 450 at refine 100, 3.1 million for 1.94 million at
 *   refine 10^4), so more than 4 asks per allowed element (+ 10^6 for the fixed share) means the curves alone
 *   exceed the limit (the curve nodes of a mesh are fewer than its elements);
 * - before the surfaces (2D): a surface bounded by n curve segments gets about n^2/16 elements (exact for a
 *   structured square: n = 4k segments, k^2 quads);
 * - before the volumes (3D): a volume bounded by f surface elements gets about (f/6)^(3/2) (exact for a structured
 *   cube: f = 6k^2 faces, k^3 hexes);
 * - after the last stage: the exact count.
 * Estimates of graded meshes are rough (tests/unit/mesh/test_mesh_guard.c prints them beside the exact counts of the
 * bundled meshes); they only need to catch meshes far above the limit, and the exact count catches the rest. */
#include <gmshc.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_internal.h"

/* ---- counting and measuring ---------------------------------------------------------------------------------- */

/* Nodes of the elements of the entity (dim, tag), `nen` per element, first-order corners only (malloc'ed, or NULL
 * when there are none). *count elements. Line, triangle and quadrangle elements: gmsh types 1, 2, 3. */
static size_t *entity_corners(int dim, int tag, int *nen, size_t *count) {
  sk_gmsh_elements got;
  sk_gmsh_elements_get(dim, tag, &got);
  size_t total = 0;
  for (size_t t = 0; t < got.n_types; ++t) total += got.tags_n[t];
  /* one element type per entity is what gmsh makes; a mix is counted as quadrangles (triangles padded) */
  int width = dim == 1 ? 2 : 4;
  size_t *corners = total ? malloc(total * (size_t)width * sizeof *corners) : NULL, k = 0;
  for (size_t t = 0; corners && t < got.n_types; ++t) {
    int per = got.types[t] == 1 ? 2 : got.types[t] == 2 ? 3 : got.types[t] == 3 ? 4 : 0;
    size_t stride = got.tags_n[t] ? got.nodes_n[t] / got.tags_n[t] : 0;
    for (size_t e = 0; per && e < got.tags_n[t]; ++e, ++k)
      for (int a = 0; a < width; ++a)
        corners[k * (size_t)width + (size_t)a] = got.nodes[t][e * stride + (size_t)(a < per ? a : 0)];
  }
  *count = corners ? k : 0;
  *nen = width;
  sk_gmsh_elements_free(&got);
  return corners;
}

/* All mesh nodes, sorted by tag, for coordinate lookups. */
typedef struct {
  size_t *tags, n;
  double *x;
  size_t *order;
} node_table;

static const node_table *sort_table;
static int compare_order(const void *a, const void *b) {
  size_t ta = sort_table->tags[*(const size_t *)a], tb = sort_table->tags[*(const size_t *)b];
  return (ta > tb) - (ta < tb);
}

static int node_table_load(node_table *nodes) {
  int ierr = 0;
  double *param = NULL;
  size_t n_coords = 0, n_param = 0;
  memset(nodes, 0, sizeof *nodes);
  gmshModelMeshGetNodes(&nodes->tags, &nodes->n, &nodes->x, &n_coords, &param, &n_param, -1, -1, 0, 0, &ierr);
  gmshFree(param);
  nodes->order = malloc((nodes->n + 1) * sizeof *nodes->order);
  if (!nodes->order) return 0;
  for (size_t i = 0; i < nodes->n; ++i) nodes->order[i] = i;
  sort_table = nodes;
  qsort(nodes->order, nodes->n, sizeof *nodes->order, compare_order);
  return 1;
}

static void node_table_free(node_table *nodes) {
  gmshFree(nodes->tags);
  gmshFree(nodes->x);
  free(nodes->order);
}

static const double *node_x(const node_table *nodes, size_t tag) {
  size_t lo = 0, hi = nodes->n;
  while (lo < hi) {
    size_t mid = lo + (hi - lo) / 2;
    if (nodes->tags[nodes->order[mid]] < tag) lo = mid + 1;
    else hi = mid;
  }
  static const double origin[3] = {0, 0, 0};
  return lo < nodes->n && nodes->tags[nodes->order[lo]] == tag ? nodes->x + 3 * nodes->order[lo] : origin;
}

/* The entities bounding (dim, tag), with signs giving their orientation (malloc'ed by gmsh: gmshFree). */
static int *boundary_of(int dim, int tag, size_t *n) {
  int ierr = 0, in[2] = {dim, tag}, *out = NULL;
  *n = 0;
  gmshModelGetBoundary(in, 2, &out, n, 0, 1, 0, &ierr);
  return out;
}

/* A planar surface (2D meshes lie in z = 0) bounded by n segments of total length P, of area A: about A (n/P)^2
 * elements — the area over the square of the mean segment length (a strip two elements wide is not taken for a
 * square). The area is the shoelace sum over the oriented boundary curves. */
static double surface_estimate(int tag, const node_table *nodes) {
  size_t n_bounds = 0;
  int *bounds = boundary_of(2, tag, &n_bounds);
  double area = 0, perimeter = 0, segments = 0;
  for (size_t k = 0; k + 1 < n_bounds; k += 2) {
    int nen;
    size_t count;
    size_t *corners = entity_corners(1, abs(bounds[k + 1]), &nen, &count);
    double sign = bounds[k + 1] < 0 ? -1.0 : 1.0;
    for (size_t e = 0; e < count; ++e) {
      const double *a = node_x(nodes, corners[2 * e]), *b = node_x(nodes, corners[2 * e + 1]);
      area += sign * 0.5 * (a[0] * b[1] - b[0] * a[1]);
      perimeter += hypot(b[0] - a[0], b[1] - a[1]);
      segments += 1;
    }
    free(corners);
  }
  gmshFree(bounds);
  return perimeter > 0 ? fabs(area) * (segments / perimeter) * (segments / perimeter) : 0;
}

/* ---- volumes from their surface mesh -------------------------------------------------------------------------- */

typedef struct {
  size_t a, b;  /* node tags, a < b */
  size_t face;
  int forward;  /* the face runs a -> b */
} edge_record;

static int compare_edges(const void *p, const void *q) {
  const edge_record *x = p, *y = q;
  if (x->a != y->a) return (x->a > y->a) - (x->a < y->a);
  return (x->b > y->b) - (x->b < y->b);
}

/* A volume bounded by f surface elements of total area A, enclosing V: about V (f/A)^(3/2) elements — the volume
 * over the cube of the mean face size (a thin shell is not taken for a cube). V comes from the divergence theorem
 * over the boundary triangles (quadrangles split), oriented consistently by walking across shared edges, because the
 * orientation gmsh gives a surface's elements does not always match its sign in the volume's boundary. */
static double volume_estimate(int tag, const node_table *nodes) {
  size_t n_bounds = 0;
  int *bounds = boundary_of(3, tag, &n_bounds);
  size_t n_tri = 0, cap = 0, faces = 0;
  size_t (*tri)[3] = NULL;
  double area = 0;
  for (size_t k = 0; k + 1 < n_bounds; k += 2) {
    int nen;
    size_t count;
    size_t *corners = entity_corners(2, abs(bounds[k + 1]), &nen, &count);
    faces += count;
    for (size_t e = 0; e < count; ++e) {
      const size_t *c = corners + 4 * e;
      int quad = c[3] != c[0];
      for (int half = 0; half <= quad; ++half) {
        if (n_tri == cap) {
          cap = 2 * cap + 1024;
          size_t(*grown)[3] = realloc(tri, cap * sizeof *tri);
          if (!grown) break;
          tri = grown;
        }
        size_t *t = tri[n_tri++];
        t[0] = c[0], t[1] = c[half ? 2 : 1], t[2] = c[half ? 3 : 2];
        const double *x0 = node_x(nodes, t[0]), *x1 = node_x(nodes, t[1]), *x2 = node_x(nodes, t[2]);
        double u[3] = {x1[0] - x0[0], x1[1] - x0[1], x1[2] - x0[2]}, w[3] = {x2[0] - x0[0], x2[1] - x0[1], x2[2] - x0[2]};
        double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
        area += 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      }
    }
    free(corners);
  }
  gmshFree(bounds);
  /* edges -> neighbouring triangles; a shared edge run in the same direction by both means opposite orientations */
  edge_record *edges = malloc((3 * n_tri + 1) * sizeof *edges);
  int *sign = calloc(n_tri + 1, sizeof *sign);
  size_t *queue = malloc((n_tri + 1) * sizeof *queue);
  double volume = 0, largest = 0;
  if (edges && sign && queue && tri) {
    for (size_t t = 0; t < n_tri; ++t)
      for (int j = 0; j < 3; ++j) {
        size_t p = tri[t][j], q = tri[t][(j + 1) % 3];
        edges[3 * t + (size_t)j] = (edge_record){p < q ? p : q, p < q ? q : p, t, p < q};
      }
    qsort(edges, 3 * n_tri, sizeof *edges, compare_edges);
    /* neighbours through the sorted edge list: for each triangle edge, the record next to it with the same nodes */
    size_t *first = malloc((3 * n_tri + 1) * sizeof *first); /* index of each triangle's edges in `edges` */
    size_t *slot = calloc(n_tri + 1, sizeof *slot);
    if (first && slot) {
      for (size_t r = 0; r < 3 * n_tri; ++r) first[3 * edges[r].face + slot[edges[r].face]++] = r;
      /* one shell at a time: |V| of each, the largest is the outside, the others are cavities */
      for (size_t seed = 0; seed < n_tri; ++seed) {
        if (sign[seed]) continue;
        size_t head = 0, tail = 0;
        double shell = 0;
        sign[seed] = 1;
        queue[tail++] = seed;
        while (head < tail) {
          size_t t = queue[head++];
          const double *x0 = node_x(nodes, tri[t][0]), *x1 = node_x(nodes, tri[t][1]), *x2 = node_x(nodes, tri[t][2]);
          shell += sign[t] * (x0[0] * (x1[1] * x2[2] - x1[2] * x2[1]) - x0[1] * (x1[0] * x2[2] - x1[2] * x2[0]) +
                              x0[2] * (x1[0] * x2[1] - x1[1] * x2[0])) / 6.0;
          for (int j = 0; j < 3; ++j) {
            size_t r = first[3 * t + (size_t)j];
            size_t other = r + 1 < 3 * n_tri && !compare_edges(&edges[r], &edges[r + 1]) ? r + 1
                           : r > 0 && !compare_edges(&edges[r], &edges[r - 1])         ? r - 1
                                                                                       : r;
            size_t u = edges[other].face;
            if (other == r || sign[u]) continue;
            sign[u] = edges[other].forward != edges[r].forward ? sign[t] : -sign[t];
            queue[tail++] = u;
          }
        }
        shell = fabs(shell);
        volume += shell;
        if (shell > largest) largest = shell;
      }
      volume = largest - (volume - largest);
    }
    free(first);
    free(slot);
  }
  free(edges);
  free(sign);
  free(queue);
  free(tri);
  if (!(volume > 0) || !(area > 0)) return (double)faces / 6.0; /* each element has at most 6 faces */
  return volume * pow((double)faces / area, 1.5);
}

/* Elements of any type of the entity (dim, tag). */
static double entity_elements(int dim, int tag) {
  sk_gmsh_elements got;
  sk_gmsh_elements_get(dim, tag, &got);
  double count = 0;
  for (size_t t = 0; t < got.n_types; ++t) count += (double)got.tags_n[t];
  sk_gmsh_elements_free(&got);
  return count;
}

/* Elements of dimension `dim` once meshed: counted if `meshed` == dim, else estimated from the mesh of dimension
 * dim - 1 (0 if that is not meshed yet: no estimate). */
static double total_elements(int dim, int meshed) {
  if (meshed < dim - 1) return 0;
  int ierr = 0, *entities = NULL;
  size_t n = 0;
  node_table nodes = {0};
  if (meshed < dim && !node_table_load(&nodes)) return 0;
  gmshModelGetEntities(&entities, &n, dim, &ierr);
  double count = 0;
  for (size_t k = 0; k + 1 < n; k += 2)
    count += meshed == dim   ? entity_elements(dim, entities[k + 1])
             : dim == 2      ? surface_estimate(entities[k + 1], &nodes)
                             : volume_estimate(entities[k + 1], &nodes);
  gmshFree(entities);
  if (meshed < dim) node_table_free(&nodes);
  return count;
}

/* ---- the 1D watchdog ---------------------------------------------------------------------------------------- */

static double size_asks, size_ask_limit;
static const sk_mesh_guard *active_guard;

static sk_status too_large(const sk_mesh_guard *guard, const char *how, double count) {
  return sk_error_set(SK_ERR_INPUT,
                      "mesh %s: %s %.3g elements, more than mesh.max_elements = %ld%s%s%s; check the mesh sizes and "
                      "refinement, or raise mesh.max_elements if such a mesh is meant",
                      guard->path, how, count, guard->max_elements, guard->parameters[0] ? " (parameters: " : "",
                      guard->parameters, guard->parameters[0] ? ")" : "");
}

/* gmsh's global mesh size callback, only while the curves are meshed: counts the asks and never changes a size
 * (gmsh takes the smaller of its own size and ours). */
static double count_size_asks(int dim, int tag, double x, double y, double z, void *data) {
  (void)dim, (void)tag, (void)x, (void)y, (void)z, (void)data;
  if (++size_asks > size_ask_limit) {
    const sk_mesh_guard *g = active_guard;
    sk_error_set(SK_ERR_INPUT,
                 "mesh %s: meshing the curves alone asked for the mesh size at %.3g points, more than a mesh of "
                 "mesh.max_elements = %ld elements needs%s%s%s; check the mesh sizes and refinement, or raise "
                 "mesh.max_elements if such a mesh is meant",
                 g->path, size_asks, g->max_elements, g->parameters[0] ? " (parameters: " : "", g->parameters,
                 g->parameters[0] ? ")" : "");
    sk_mesh_sandbox_fail(SK_ERR_INPUT); /* does not return: gmsh offers no other way out of a meshing call */
  }
  return 1e22;
}

/* ---- staged generation ---------------------------------------------------------------------------------------- */

/* The estimates of the bundled meshes lie between 0.65 and 1.11 times the exact counts (build/tests/test_mesh_guard
 * prints them; an all-triangle mesh comes out at about half, two triangles per estimated square): a mesh is refused
 * on its estimate only when that is 1.5 times the limit, so an estimate does not refuse a mesh within the limit; the
 * exact count does the rest. */
static const double estimate_margin = 1.5;

sk_status sk_mesh_generate_guarded(const sk_mesh_guard *guard, int dim, int (*failed)(int ierr, const char *what)) {
  static const char *const stage_names[] = {"", "meshing the curves (1D)", "meshing the surfaces (2D)",
                                            "meshing the volumes (3D)"};
  const double limit = (double)guard->max_elements;
  for (int stage = 1; stage <= dim; ++stage) {
    int ierr = 0;
    sk_mesh_sandbox_phase("%s", stage_names[stage]);
    if (stage == 1) {
      size_asks = 0;
      size_ask_limit = 4.0 * limit + 1e6;
      active_guard = guard;
      gmshModelMeshSetSizeCallback(count_size_asks, NULL, &ierr);
    }
    gmshModelMeshGenerate(stage, &ierr);
    if (stage == 1) {
      int ignored = 0;
      gmshModelMeshRemoveSizeCallback(&ignored);
    }
    char what[64];
    snprintf(what, sizeof what, "generate the %dD mesh", stage);
    if (failed(ierr, what)) return SK_ERR_INPUT;
    /* exact after the last stage; before it, the estimate (rough: refused only well above the limit) */
    double count = total_elements(dim, stage);
    if (stage == dim && count > limit) return too_large(guard, "the mesh has", count);
    if (stage < dim && count > estimate_margin * limit) return too_large(guard, "the mesh would have about", count);
  }
  return SK_OK;
}
