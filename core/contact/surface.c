/* Contact surfaces: building them from face groups (outward orientation, node list, edge adjacency), covariant
 * geometry at a surface point and averaged nodal normals. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "contact_internal.h"
#include "stickslip/contact.h"
#include "stickslip/fe.h"
#include "stickslip/modified_basis.h"

/* One parametric domain per face shape; they differ only in the Lebesgue constant max sum |N_a| of the face's
 * interpolation (linear 1; line3 5/4; tri6 5/3 in the centroid, where the corner functions are -1/9 and the edge
 * functions 4/9; quad8 3 in the centre, corner functions -1/4 and edge functions 1/2 there; quad9 (5/4)^2). */
#define LINE_DOMAIN(L)                                                                                              \
  {.pdim = 1, .n_corners = 2, .corner = {{-1, 0}, {1, 0}}, .edge_w = {{1, 0}, {-1, 0}}, .edge_offset = {1, 1},        \
   .centre = {0, 0}, .lebesgue = (L)}
#define TRI_DOMAIN(L)                                                                                               \
  {.pdim = 2, .n_corners = 3, .corner = {{0, 0}, {1, 0}, {0, 1}}, .edge_w = {{0, 1}, {-1, -1}, {1, 0}},               \
   .edge_offset = {0, 1, 0}, .centre = {1.0 / 3.0, 1.0 / 3.0}, .lebesgue = (L)}
#define QUAD_DOMAIN(L)                                                                                              \
  {.pdim = 2, .n_corners = 4, .corner = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}},                                       \
   .edge_w = {{0, 1}, {-1, 0}, {0, -1}, {1, 0}}, .edge_offset = {1, 1, 1, 1}, .centre = {0, 0}, .lebesgue = (L)}
static const sk_face_domain line_domain = LINE_DOMAIN(1.0), line3_domain = LINE_DOMAIN(1.25);
static const sk_face_domain tri_domain = TRI_DOMAIN(1.0), tri6_domain = TRI_DOMAIN(5.0 / 3.0);
static const sk_face_domain quad_domain = QUAD_DOMAIN(1.0), quad8_domain = QUAD_DOMAIN(3.0),
                            quad9_domain = QUAD_DOMAIN(1.5625);
#undef LINE_DOMAIN
#undef TRI_DOMAIN
#undef QUAD_DOMAIN

const sk_face_domain *sk_face_domain_of(sk_elem_type type) {
  switch (type) {
  case SK_LINE2: return &line_domain;
  case SK_LINE3: return &line3_domain;
  case SK_TRI3: return &tri_domain;
  case SK_QUAD4: return &quad_domain;
  case SK_QUAD9: return &quad9_domain;
  case SK_TRI6: return &tri6_domain;
  case SK_QUAD8: return &quad8_domain;
  default: return NULL;
  }
}

/* ---- building ------------------------------------------------------------------------------------------------ */
enum { SK_FACE_KEY_MAX = 9 };

typedef struct {
  int key[SK_FACE_KEY_MAX]; /* sorted node ids, padded with -1 */
  int elem, local_face;
} face_record;

static int compare_int(const void *a, const void *b) {
  int x = *(const int *)a, y = *(const int *)b;
  return (x > y) - (x < y);
}

static int compare_face_record(const void *a, const void *b) {
  const face_record *r = a, *s = b;
  for (int k = 0; k < SK_FACE_KEY_MAX; ++k)
    if (r->key[k] != s->key[k]) return (r->key[k] > s->key[k]) - (r->key[k] < s->key[k]);
  return 0;
}

static void sorted_key(const int *nodes, int nen, int *key) {
  memcpy(key, nodes, (size_t)nen * sizeof *key);
  qsort(key, (size_t)nen, sizeof *key, compare_int);
  for (int k = nen; k < SK_FACE_KEY_MAX; ++k) key[k] = -1;
}

typedef struct {
  int lo, hi; /* corner node ids of the edge, lo <= hi */
  int face, edge;
} edge_record;

static int compare_edge_record(const void *a, const void *b) {
  const edge_record *r = a, *s = b;
  if (r->lo != s->lo) return (r->lo > s->lo) - (r->lo < s->lo);
  if (r->hi != s->hi) return (r->hi > s->hi) - (r->hi < s->hi);
  if (r->face != s->face) return (r->face > s->face) - (r->face < s->face);
  return (r->edge > s->edge) - (r->edge < s->edge);
}

/* Global corner node ids of edge `edge` of a face (in 2D both are the end point). */
static void edge_nodes(const sk_surface *s, int face, int edge, int *a, int *b) {
  const int *c = s->conn + (size_t)face * s->nen;
  if (s->dim == 2) {
    *a = *b = c[edge];
  } else {
    *a = c[edge];
    *b = c[(edge + 1) % s->n_edges];
  }
}

static sk_status build_neighbors(sk_surface *s) {
  size_t n = (size_t)s->n_faces * s->n_edges;
  edge_record *records = malloc((n ? n : 1) * sizeof *records);
  s->face_neighbors = malloc((n ? n : 1) * sizeof *s->face_neighbors);
  if (!records || !s->face_neighbors) {
    free(records);
    return sk_error_set(SK_ERR_NOMEM, "surface %s: out of memory for face adjacency", s->name);
  }
  for (int f = 0; f < s->n_faces; ++f)
    for (int e = 0; e < s->n_edges; ++e) {
      int a, b;
      edge_nodes(s, f, e, &a, &b);
      edge_record *r = &records[(size_t)f * s->n_edges + e];
      r->lo = a < b ? a : b;
      r->hi = a < b ? b : a;
      r->face = f;
      r->edge = e;
      s->face_neighbors[(size_t)f * s->n_edges + e] = -1;
    }
  qsort(records, n, sizeof *records, compare_edge_record);
  /* Within a run of equal edges (sorted by face id), each face's neighbour is the lowest other face: a manifold
   * edge has exactly two faces, a non-manifold one gets a deterministic choice. */
  for (size_t i = 0; i < n;) {
    size_t j = i;
    while (j < n && records[j].lo == records[i].lo && records[j].hi == records[i].hi) ++j;
    for (size_t k = i; k < j; ++k) {
      int other = -1;
      for (size_t l = i; l < j && other < 0; ++l)
        if (records[l].face != records[k].face) other = records[l].face;
      s->face_neighbors[(size_t)records[k].face * s->n_edges + records[k].edge] = other;
    }
    i = j;
  }
  free(records);
  return SK_OK;
}

static sk_status build_nodes(sk_surface *s) {
  size_t n = (size_t)s->n_faces * s->nen;
  s->nodes = malloc((n ? n : 1) * sizeof *s->nodes);
  if (!s->nodes) return sk_error_set(SK_ERR_NOMEM, "surface %s: out of memory for the node list", s->name);
  memcpy(s->nodes, s->conn, n * sizeof *s->nodes);
  qsort(s->nodes, n, sizeof *s->nodes, compare_int);
  int count = 0;
  for (size_t i = 0; i < n; ++i)
    if (count == 0 || s->nodes[count - 1] != s->nodes[i]) s->nodes[count++] = s->nodes[i];
  s->n_nodes = count;
  return SK_OK;
}

/* Faces of the body's elements that no other element of the body shares: its whole boundary, as a face group in the
 * order of the elements (deterministic), then built as any face group is. */
sk_status sk_surface_build_boundary(const sk_mesh *mesh, const sk_group *body, int body_index, const char *name,
                                    sk_surface *surface) {
  memset(surface, 0, sizeof *surface);
  if (!mesh || !body) return sk_error_set(SK_ERR_INPUT, "body boundary: missing mesh or body group");
  sk_elem_type face_type;
  const int *face_nodes;
  int face_nen;
  const int n_elem_faces = sk_elem_faces(body->type, &face_type, &face_nodes, &face_nen);
  if (n_elem_faces <= 0 || face_nen > SK_FACE_KEY_MAX)
    return sk_error_set(SK_ERR_INPUT, "body %s: its %s elements have no contact face type", body->name,
                        sk_elem_name(body->type));
  const size_t n_records = (size_t)body->n_elems * n_elem_faces;
  face_record *records = malloc((n_records ? n_records : 1) * sizeof *records);
  sk_group boundary = {.dim = mesh->dim - 1, .type = face_type, .nen = face_nen, .n_elems = 0};
  snprintf(boundary.name, sizeof boundary.name, "%s", name);
  boundary.conn = malloc((n_records ? n_records : 1) * (size_t)face_nen * sizeof *boundary.conn);
  if (!records || !boundary.conn) {
    free(records);
    free(boundary.conn);
    return sk_error_set(SK_ERR_NOMEM, "body %s: out of memory for its boundary", body->name);
  }
  for (int e = 0; e < body->n_elems; ++e)
    for (int f = 0; f < n_elem_faces; ++f) {
      face_record *r = &records[(size_t)e * n_elem_faces + f];
      int nodes[SK_FACE_KEY_MAX];
      for (int k = 0; k < face_nen; ++k) nodes[k] = body->conn[(size_t)e * body->nen + face_nodes[f * face_nen + k]];
      sorted_key(nodes, face_nen, r->key);
      r->elem = e;
      r->local_face = f;
    }
  qsort(records, n_records, sizeof *records, compare_face_record);
  /* a face met once is on the boundary; kept in (element, local face) order so the surface does not depend on qsort */
  unsigned char *on_boundary = calloc(n_records ? n_records : 1, 1);
  if (!on_boundary) {
    free(records);
    free(boundary.conn);
    return sk_error_set(SK_ERR_NOMEM, "body %s: out of memory for its boundary", body->name);
  }
  for (size_t i = 0; i < n_records;) {
    size_t j = i + 1;
    while (j < n_records && compare_face_record(&records[i], &records[j]) == 0) ++j;
    if (j == i + 1) on_boundary[(size_t)records[i].elem * n_elem_faces + records[i].local_face] = 1;
    i = j;
  }
  for (size_t r = 0; r < n_records; ++r) {
    if (!on_boundary[r]) continue;
    const int e = (int)(r / n_elem_faces), f = (int)(r % n_elem_faces);
    for (int k = 0; k < face_nen; ++k)
      boundary.conn[(size_t)boundary.n_elems * face_nen + k] =
          body->conn[(size_t)e * body->nen + face_nodes[f * face_nen + k]];
    ++boundary.n_elems;
  }
  free(on_boundary);
  free(records);
  sk_status status = sk_surface_build(mesh, &boundary, body, body_index, surface);
  free(boundary.conn);
  return status;
}

sk_status sk_surface_build(const sk_mesh *mesh, const sk_group *faces, const sk_group *body, int body_index,
                           sk_surface *surface) {
  memset(surface, 0, sizeof *surface);
  if (!mesh || !faces || !body)
    return sk_error_set(SK_ERR_INPUT, "contact surface: missing mesh, face group or body group");
  snprintf(surface->name, sizeof surface->name, "%s", faces->name);
  const sk_face_domain *domain = sk_face_domain_of(faces->type);
  if (!domain || domain->pdim != mesh->dim - 1)
    return sk_error_set(SK_ERR_INPUT, "contact surface %s: element type %d is not a face type of a %dD mesh",
                        faces->name, (int)faces->type, mesh->dim);
  sk_elem_type elem_face_type;
  const int *elem_face_nodes;
  int elem_face_nen;
  int n_elem_faces = sk_elem_faces(body->type, &elem_face_type, &elem_face_nodes, &elem_face_nen);
  if (n_elem_faces <= 0 || elem_face_type != faces->type || elem_face_nen != faces->nen)
    return sk_error_set(SK_ERR_INPUT, "contact surface %s: its faces (%s) are not faces of the %s elements of body %s",
                        faces->name, sk_elem_name(faces->type), sk_elem_name(body->type), body->name);

  surface->dim = mesh->dim;
  surface->face_type = faces->type;
  surface->nen = faces->nen;
  surface->n_faces = faces->n_elems;
  surface->n_edges = domain->n_corners;
  surface->body = body_index;

  /* All element faces of the body, keyed by their sorted node sets. */
  size_t n_records = (size_t)body->n_elems * n_elem_faces;
  face_record *records = malloc((n_records ? n_records : 1) * sizeof *records);
  surface->conn = malloc(((size_t)surface->n_faces * surface->nen + 1) * sizeof *surface->conn);
  if (!records || !surface->conn) {
    free(records);
    sk_surface_free(surface);
    return sk_error_set(SK_ERR_NOMEM, "contact surface %s: out of memory", faces->name);
  }
  for (int e = 0; e < body->n_elems; ++e)
    for (int f = 0; f < n_elem_faces; ++f) {
      face_record *r = &records[(size_t)e * n_elem_faces + f];
      int nodes[SK_FACE_KEY_MAX];
      for (int k = 0; k < faces->nen; ++k)
        nodes[k] = body->conn[(size_t)e * body->nen + elem_face_nodes[f * elem_face_nen + k]];
      sorted_key(nodes, faces->nen, r->key);
      r->elem = e;
      r->local_face = f;
    }
  qsort(records, n_records, sizeof *records, compare_face_record);

  sk_status status = SK_OK;
  for (int f = 0; f < faces->n_elems; ++f) {
    face_record probe;
    const int *face_conn = faces->conn + (size_t)f * faces->nen;
    sorted_key(face_conn, faces->nen, probe.key);
    const face_record *hit = bsearch(&probe, records, n_records, sizeof *records, compare_face_record);
    if (!hit) {
      char list[256] = "";
      size_t used = 0;
      for (int k = 0; k < faces->nen && used < sizeof list - 16; ++k)
        used += (size_t)snprintf(list + used, sizeof list - used, "%s%d", k ? " " : "", face_conn[k]);
      status = sk_error_set(SK_ERR_INPUT, "contact surface %s: face %d (nodes %s) is not a face of body %s",
                            faces->name, f, list, body->name);
      break;
    }
    /* The element's own face ordering is outward (fe.h), so it replaces the group's ordering. */
    for (int k = 0; k < faces->nen; ++k)
      surface->conn[(size_t)f * faces->nen + k] =
          body->conn[(size_t)hit->elem * body->nen + elem_face_nodes[hit->local_face * elem_face_nen + k]];
  }
  free(records);
  if (status == SK_OK) status = build_nodes(surface);
  if (status == SK_OK) status = build_neighbors(surface);
  surface->n_faces_global = surface->n_faces;
  surface->n_nodes_global = surface->n_nodes;
  if (status != SK_OK) sk_surface_free(surface);
  return status;
}

void sk_surface_sizes(const sk_surface *surface, const double *X_nodes, int stride, double *h_min, double *h_mean,
                      double *h_max, double *measure) {
  const int dim = surface->dim, nen = surface->nen, corners = sk_elem_corners(surface->face_type);
  const int edges = corners == 2 ? 1 : corners;
  double lo = INFINITY, hi = 0.0, sum = 0.0, area = 0.0;
  long count = 0;
  double X[SK_FACE_NEN_MAX * 3];
  for (int f = 0; f < surface->n_faces; ++f) {
    const int *conn = surface->conn + (size_t)f * nen;
    for (int a = 0; a < nen; ++a)
      for (int i = 0; i < dim; ++i) X[a * dim + i] = X_nodes[(size_t)stride * (size_t)conn[a] + i];
    for (int e = 0; e < edges; ++e) {
      const double *p = X + e * dim, *q = X + ((e + 1) % corners) * dim;
      double d2 = 0.0;
      for (int i = 0; i < dim; ++i) d2 += (q[i] - p[i]) * (q[i] - p[i]);
      const double h = sqrt(d2);
      lo = fmin(lo, h);
      hi = fmax(hi, h);
      sum += h;
      ++count;
    }
    area += sk_face_area(surface->face_type, dim, X);
  }
  *h_min = count ? lo : 0.0;
  *h_mean = count ? sum / (double)count : 0.0;
  *h_max = hi;
  *measure = area;
}

void sk_surface_free(sk_surface *surface) {
  if (!surface) return;
  free(surface->conn);
  free(surface->nodes);
  free(surface->face_neighbors);
  free(surface->face_index);
  free(surface->node_index);
  free(surface->face_owner);
  surface->conn = surface->nodes = surface->face_neighbors = surface->face_owner = NULL;
  surface->face_index = surface->node_index = NULL;
  surface->n_faces = surface->n_nodes = 0;
}

/* ---- geometry ------------------------------------------------------------------------------------------------ */
static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void cross3(const double *a, const double *b, double *c) {
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}

void sk_surface_geometry(const sk_surface *surface, int face, const double *xi, const double *q,
                         sk_surface_point *point) {
  memset(point, 0, sizeof *point);
  const int dim = surface->dim, nen = surface->nen;
  const int pdim = dim - 1;
  const int *conn = surface->conn + (size_t)face * nen;
  double dN[SK_MAX_NEN * 2], ddN[SK_MAX_NEN * 4];
  point->face = face;
  point->xi[0] = xi[0];
  point->xi[1] = pdim == 2 ? xi[1] : 0.0;
  point->nen = nen;
  sk_elem_shape(surface->face_type, xi, point->N, dN);
  sk_elem_shape_hessian(surface->face_type, xi, ddN);
  for (int a = 0; a < nen; ++a) {
    const double *xa = q + (size_t)conn[a] * dim;
    for (int k = 0; k < pdim; ++k) point->dN[a][k] = dN[a * pdim + k];
    for (int i = 0; i < dim; ++i) {
      point->x[i] += point->N[a] * xa[i];
      for (int k = 0; k < pdim; ++k) {
        point->a[k][i] += dN[a * pdim + k] * xa[i];
        for (int l = 0; l < pdim; ++l) point->a_ab[k][l][i] += ddN[(a * pdim + k) * pdim + l] * xa[i];
      }
    }
  }
  if (pdim == 1) point->a[1][2] = 1.0; /* e_z: the 2D case reads as a 3D one */

  double normal[3];
  cross3(point->a[0], point->a[1], normal);
  point->jacobian = sqrt(dot3(normal, normal));
  for (int k = 0; k < 2; ++k)
    for (int l = 0; l < 2; ++l) point->m[k][l] = dot3(point->a[k], point->a[l]);
  double det = point->m[0][0] * point->m[1][1] - point->m[0][1] * point->m[1][0];
  /* A degenerate face (zero area) leaves n, m_inv and what depends on them zero instead of producing NaNs. */
  if (point->jacobian <= 0.0 || det <= 0.0) return;
  for (int i = 0; i < 3; ++i) point->n[i] = normal[i] / point->jacobian;
  point->m_inv[0][0] = point->m[1][1] / det;
  point->m_inv[1][1] = point->m[0][0] / det;
  point->m_inv[0][1] = point->m_inv[1][0] = -point->m[0][1] / det;
  for (int k = 0; k < 2; ++k)
    for (int i = 0; i < 3; ++i) point->a_dual[k][i] = point->m_inv[k][0] * point->a[0][i] + point->m_inv[k][1] * point->a[1][i];
  for (int k = 0; k < 2; ++k)
    for (int l = 0; l < 2; ++l) {
      point->h[k][l] = dot3(point->a_ab[k][l], point->n);
      for (int c = 0; c < 2; ++c) point->christoffel[k][l][c] = dot3(point->a_ab[k][l], point->a_dual[c]);
    }
}

/* Position of surface node `node` (global id) in surface->nodes, or -1. */
static int surface_node_index(const sk_surface *surface, int node) {
  int lo = 0, hi = surface->n_nodes - 1;
  while (lo <= hi) {
    int mid = lo + (hi - lo) / 2;
    if (surface->nodes[mid] == node) return mid;
    if (surface->nodes[mid] < node) lo = mid + 1;
    else hi = mid - 1;
  }
  return -1;
}

void sk_surface_nodal_normals(const sk_surface *surface, const double *q, double *normals) {
  memset(normals, 0, (size_t)surface->n_nodes * 3 * sizeof *normals);
  const double *node_xi = sk_elem_node_coords(surface->face_type);
  const int pdim = surface->dim - 1;
  int n_qp;
  const double *qp_xi, *qp_w;
  sk_elem_quadrature(surface->face_type, &n_qp, &qp_xi, &qp_w);
  sk_surface_point point;
  for (int f = 0; f < surface->n_faces; ++f) {
    double area = 0.0;
    for (int p = 0; p < n_qp; ++p) {
      sk_surface_geometry(surface, f, qp_xi + p * pdim, q, &point);
      area += qp_w[p] * point.jacobian;
    }
    /* Each node takes the face normal at its own parametric position (exact for curved quadratic faces), weighted
     * by the face area. */
    for (int a = 0; a < surface->nen; ++a) {
      sk_surface_geometry(surface, f, node_xi + a * pdim, q, &point);
      int index = surface_node_index(surface, surface->conn[(size_t)f * surface->nen + a]);
      if (index < 0) continue;
      for (int i = 0; i < 3; ++i) normals[3 * index + i] += area * point.n[i];
    }
  }
  for (int k = 0; k < surface->n_nodes; ++k) {
    double length = sqrt(dot3(normals + 3 * k, normals + 3 * k));
    if (length > 0.0)
      for (int i = 0; i < 3; ++i) normals[3 * k + i] /= length;
  }
}

void sk_surface_tributary_measures(const sk_surface *surface, const double *q, double *measure) {
  memset(measure, 0, (size_t)surface->n_nodes * sizeof *measure);
  enum { MAX_POINTS = 16 };
  double xi[MAX_POINTS][2], w[MAX_POINTS];
  /* exact for N_I times the area element of straight faces (degree 2 on TRI3, 4 on TRI6, 5 otherwise) */
  const sk_elem_type type = surface->face_type;
  const int n = sk_face_quadrature(type, type == SK_TRI3 ? 2 : type == SK_TRI6 ? 4 : 5, MAX_POINTS, xi, w);
  sk_surface_point point;
  for (int f = 0; f < surface->n_faces; ++f) {
    double A[SK_FACE_NEN_MAX] = {0};
    for (int p = 0; p < n; ++p) {
      sk_surface_geometry(surface, f, xi[p], q, &point);
      for (int a = 0; a < surface->nen; ++a) A[a] += point.N[a] * point.jacobian * w[p];
    }
    sk_modified_basis_weights(type, A); /* TRI6/QUAD8: positive weights (modified_basis.h) */
    for (int a = 0; a < surface->nen; ++a) {
      const int index = surface_node_index(surface, surface->conn[(size_t)f * surface->nen + a]);
      if (index >= 0) measure[index] += A[a];
    }
  }
}
