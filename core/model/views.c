/* Views (host.h, plugin_types.h): a surface or body as one rank sees it, owned cells and nodes plus ghosts, in a
 * local numbering. Built once per instance at scene load. */
#include <stdlib.h>
#include <string.h>

#include "host.h"

static int compare_int(const void *a, const void *b) {
  int x = *(const int *)a, y = *(const int *)b;
  return (x > y) - (x < y);
}

static int64_t index_in(const int *sorted, int n, int value) {
  const int *hit = bsearch(&value, sorted, (size_t)n, sizeof(int), compare_int);
  return hit ? hit - sorted : -1;
}

void sk_view_free(sk_view_data *v) {
  if (!v) return;
  free(v->conn);
  free(v->cell_owned);
  free(v->cell_index);
  free(v->neighbors);
  free(v->local_nodes);
  free(v->node_index);
  free(v->node_id);
  free(v->dofs);
  free(v->owned);
  free(v->X);
  free(v->cell_element);
  memset(v, 0, sizeof *v);
}

static sk_status no_memory(sk_view_data *v, const char *name) {
  sk_view_free(v);
  return sk_error_set(SK_ERR_NOMEM, "out of memory for the view of '%s'", name);
}

/* Fills the node arrays of a view from the sorted mesh ids of its nodes: their index in the whole surface/body (the
 * sorted list `all`), ownership (node_owned by mesh id, NULL: all owned), dofs and reference positions X. */
static sk_status fill_nodes(sk_view_data *v, int dim, const double *X, const unsigned char *node_owned,
                            const int *nodes, int n, const int *all, int n_all, const char *name) {
  const size_t nn = (size_t)(n > 0 ? n : 1);
  v->local_nodes = malloc(sizeof(int) * nn);
  v->node_index = malloc(sizeof(int64_t) * nn);
  v->node_id = malloc(sizeof(int64_t) * nn);
  v->owned = malloc(nn);
  v->dofs = malloc(sizeof(int64_t) * nn * (size_t)dim);
  v->X = malloc(sizeof(double) * nn * (size_t)dim);
  if (!v->local_nodes || !v->node_index || !v->node_id || !v->owned || !v->dofs || !v->X) return no_memory(v, name);
  for (int k = 0; k < n; ++k) {
    v->local_nodes[k] = k;
    v->node_index[k] = index_in(all, n_all, nodes[k]);
    v->node_id[k] = nodes[k];
    v->owned[k] = node_owned ? node_owned[nodes[k]] : 1;
    for (int i = 0; i < dim; ++i) {
      v->dofs[(size_t)k * dim + i] = (int64_t)nodes[k] * dim + i;
      v->X[(size_t)k * dim + i] = X[(size_t)nodes[k] * dim + i];
    }
  }
  sk_view *view = &v->view;
  view->dim = dim;
  view->n_nodes = n;
  view->n_nodes_global = n_all;
  view->node_index = v->node_index;
  view->node_id = v->node_id;
  view->owned = v->owned;
  view->dofs = v->dofs;
  view->X = v->X;
  return SK_OK;
}

/* Sorted unique node ids of the selected cells. */
static int *collect_nodes(const int *conn, int nen, const unsigned char *selected, int n_cells, int *n_out) {
  int64_t count = 0;
  for (int c = 0; c < n_cells; ++c) count += selected[c] ? nen : 0;
  int *nodes = malloc(sizeof(int) * (size_t)(count > 0 ? count : 1));
  if (!nodes) return NULL;
  int64_t used = 0;
  for (int c = 0; c < n_cells; ++c)
    if (selected[c])
      for (int a = 0; a < nen; ++a) nodes[used++] = conn[(size_t)c * nen + a];
  qsort(nodes, (size_t)used, sizeof(int), compare_int);
  int unique = 0;
  for (int64_t k = 0; k < used; ++k)
    if (k == 0 || nodes[k] != nodes[unique - 1]) nodes[unique++] = nodes[k];
  *n_out = unique;
  return nodes;
}

/* The rank owning each face of a surface: the part of the body element whose face it is. */
static sk_status face_owners(const sk_model *m, const sk_surface *s, int *owner) {
  const sk_body *body = &m->bodies[s->body];
  const sk_group *g = body->group;
  /* elements incident to each surface node */
  int *count = calloc((size_t)s->n_nodes + 1, sizeof(int));
  if (!count) return sk_error_set(SK_ERR_NOMEM, "out of memory for the faces of '%s'", s->name);
  for (int e = 0; e < g->n_elems; ++e)
    for (int a = 0; a < g->nen; ++a) {
      const int64_t k = index_in(s->nodes, s->n_nodes, g->conn[(size_t)e * g->nen + a]);
      if (k >= 0) count[k + 1]++;
    }
  for (int k = 0; k < s->n_nodes; ++k) count[k + 1] += count[k];
  int *incident = malloc(sizeof(int) * (size_t)(count[s->n_nodes] > 0 ? count[s->n_nodes] : 1));
  int *fill = calloc((size_t)s->n_nodes + 1, sizeof(int));
  if (!incident || !fill) {
    free(count);
    free(incident);
    free(fill);
    return sk_error_set(SK_ERR_NOMEM, "out of memory for the faces of '%s'", s->name);
  }
  for (int e = 0; e < g->n_elems; ++e)
    for (int a = 0; a < g->nen; ++a) {
      const int64_t k = index_in(s->nodes, s->n_nodes, g->conn[(size_t)e * g->nen + a]);
      if (k >= 0) incident[count[k] + fill[k]++] = e;
    }
  for (int f = 0; f < s->n_faces; ++f) {
    const int *fc = s->conn + (size_t)f * s->nen;
    const int64_t k = index_in(s->nodes, s->n_nodes, fc[0]);
    owner[f] = 0;
    for (int j = count[k]; j < count[k + 1]; ++j) {
      const int *ec = g->conn + (size_t)incident[j] * g->nen;
      int all = 1;
      for (int a = 0; a < s->nen && all; ++a) {
        int found = 0;
        for (int b = 0; b < g->nen && !found; ++b) found = ec[b] == fc[a];
        all = found;
      }
      if (all) {
        owner[f] = m->element_part[body->first_element + incident[j]];
        break;
      }
    }
  }
  free(count);
  free(incident);
  free(fill);
  return SK_OK;
}

sk_status sk_view_fill_surface(sk_view_data *v, const sk_surface *s, const char *name, int dim, const double *X,
                               const unsigned char *selected, const unsigned char *face_owned,
                               const unsigned char *node_owned) {
  memset(v, 0, sizeof *v);
  v->is_surface = 1;
  const size_t nf = (size_t)(s->n_faces > 0 ? s->n_faces : 1);
  unsigned char *all = malloc(nf);
  int *local_face = malloc(sizeof(int) * nf);
  if (!all || !local_face) {
    free(all);
    free(local_face);
    return no_memory(v, name);
  }
  memset(all, 1, nf);
  if (!selected) selected = all;
  int n_cells = 0;
  for (int f = 0; f < s->n_faces; ++f) local_face[f] = selected[f] ? n_cells++ : -1;
  int n_nodes = 0, *nodes = collect_nodes(s->conn, s->nen, selected, s->n_faces, &n_nodes);
  const size_t nc = (size_t)(n_cells > 0 ? n_cells : 1);
  v->conn = malloc(sizeof(int) * nc * (size_t)s->nen);
  v->cell_owned = malloc(nc);
  v->cell_index = malloc(sizeof(int64_t) * nc);
  v->neighbors = malloc(sizeof(int) * nc * (size_t)s->n_edges);
  sk_status status = nodes && v->conn && v->cell_owned && v->cell_index && v->neighbors
                         ? fill_nodes(v, dim, X, node_owned, nodes, n_nodes, s->nodes, s->n_nodes, name)
                         : no_memory(v, name);
  if (status != SK_OK) {
    free(all);
    free(local_face);
    free(nodes);
    return status;
  }
  for (int f = 0; f < s->n_faces; ++f) {
    const int c = local_face[f];
    if (c < 0) continue;
    for (int a = 0; a < s->nen; ++a)
      v->conn[(size_t)c * s->nen + a] = (int)index_in(nodes, n_nodes, s->conn[(size_t)f * s->nen + a]);
    v->cell_owned[c] = face_owned ? face_owned[f] : 1;
    v->cell_index[c] = f;
    for (int e = 0; e < s->n_edges; ++e) {
      const int other = s->face_neighbors[(size_t)f * s->n_edges + e];
      v->neighbors[(size_t)c * s->n_edges + e] = other >= 0 ? local_face[other] : -1;
    }
  }
  free(all);
  free(local_face);
  free(nodes);
  sk_view *view = &v->view;
  view->struct_size = sizeof *view;
  view->name = name;
  view->dim = dim;
  view->body = s->body;
  view->cell_type = s->face_type;
  view->nen = s->nen;
  view->n_cells = n_cells;
  view->conn = v->conn;
  view->cell_owned = v->cell_owned;
  view->cell_index = v->cell_index;
  view->n_cells_global = s->n_faces;
  view->n_edges = s->n_edges;
  view->neighbors = v->neighbors;
  /* the core surface in view numbering, for the contact services */
  sk_surface *local = &v->local;
  snprintf(local->name, sizeof local->name, "%s", s->name);
  local->dim = s->dim;
  local->face_type = s->face_type;
  local->nen = s->nen;
  local->n_faces = n_cells;
  local->conn = v->conn;
  local->n_nodes = n_nodes;
  local->nodes = v->local_nodes;
  local->face_neighbors = v->neighbors;
  local->n_edges = s->n_edges;
  local->body = s->body;
  return SK_OK;
}

sk_status sk_view_surface(const sk_model *m, const sk_surface *s, const char *name, int whole, sk_view_data *v) {
  memset(v, 0, sizeof *v);
  const size_t nf = (size_t)(s->n_faces > 0 ? s->n_faces : 1);
  int *owner = malloc(sizeof(int) * nf);
  unsigned char *selected = malloc(nf), *face_owned = malloc(nf);
  unsigned char *node_owned = malloc((size_t)(m->n_nodes > 0 ? m->n_nodes : 1));
  sk_status status = owner && selected && face_owned && node_owned ? face_owners(m, s, owner) : SK_ERR_NOMEM;
  for (int a = 0; a < m->n_nodes && status == SK_OK; ++a) node_owned[a] = m->node_owner[a] == m->rank;
  for (int f = 0; f < s->n_faces && status == SK_OK; ++f) {
    int take = whole || owner[f] == m->rank;
    for (int a = 0; a < s->nen && !take; ++a) take = node_owned[s->conn[(size_t)f * s->nen + a]];
    selected[f] = (unsigned char)take;
    face_owned[f] = owner[f] == m->rank;
  }
  if (status == SK_OK) status = sk_view_fill_surface(v, s, name, m->dim, m->X, selected, face_owned, node_owned);
  else if (status == SK_ERR_NOMEM) status = no_memory(v, name);
  free(owner);
  free(selected);
  free(face_owned);
  free(node_owned);
  return status;
}

sk_status sk_view_body(const sk_model *m, int b, sk_view_data *v) {
  memset(v, 0, sizeof *v);
  const sk_body *body = &m->bodies[b];
  const sk_group *g = body->group;
  const size_t ne = (size_t)(g->n_elems > 0 ? g->n_elems : 1);
  unsigned char *selected = malloc(ne), *everything = malloc(ne);
  if (!selected || !everything) {
    free(selected);
    free(everything);
    return no_memory(v, body->name);
  }
  int n_cells = 0;
  for (int e = 0; e < g->n_elems; ++e) {
    int take = m->element_part[body->first_element + e] == m->rank;
    for (int a = 0; a < g->nen && !take; ++a) take = m->node_owner[g->conn[(size_t)e * g->nen + a]] == m->rank;
    selected[e] = (unsigned char)take;
    everything[e] = 1;
    n_cells += take;
  }
  int n_nodes = 0, n_all = 0;
  int *nodes = collect_nodes(g->conn, g->nen, selected, g->n_elems, &n_nodes);
  int *all = collect_nodes(g->conn, g->nen, everything, g->n_elems, &n_all);
  unsigned char *node_owned = malloc((size_t)(m->n_nodes > 0 ? m->n_nodes : 1));
  for (int a = 0; node_owned && a < m->n_nodes; ++a) node_owned[a] = m->node_owner[a] == m->rank;
  sk_status status = nodes && all && node_owned
                         ? fill_nodes(v, m->dim, m->X, node_owned, nodes, n_nodes, all, n_all, body->name)
                         : SK_ERR_NOMEM;
  free(node_owned);
  const size_t nc = (size_t)(n_cells > 0 ? n_cells : 1);
  if (status == SK_OK) {
    v->conn = malloc(sizeof(int) * nc * (size_t)g->nen);
    v->cell_owned = malloc(nc);
    v->cell_index = malloc(sizeof(int64_t) * nc);
    v->cell_element = malloc(sizeof(int) * nc);
    if (!v->conn || !v->cell_owned || !v->cell_index || !v->cell_element) status = SK_ERR_NOMEM;
  }
  if (status == SK_OK) {
    for (int e = 0, c = 0; e < g->n_elems; ++e) {
      if (!selected[e]) continue;
      for (int a = 0; a < g->nen; ++a)
        v->conn[(size_t)c * g->nen + a] = (int)index_in(nodes, n_nodes, g->conn[(size_t)e * g->nen + a]);
      v->cell_owned[c] = m->element_part[body->first_element + e] == m->rank;
      v->cell_index[c] = e;
      v->cell_element[c] = body->first_element + e;
      ++c;
    }
  }
  free(selected);
  free(everything);
  free(nodes);
  free(all);
  if (status != SK_OK) return no_memory(v, body->name);
  sk_view *view = &v->view;
  view->struct_size = sizeof *view;
  view->name = body->name;
  view->body = b;
  view->cell_type = g->type;
  view->nen = g->nen;
  view->n_cells = n_cells;
  view->conn = v->conn;
  view->cell_owned = v->cell_owned;
  view->cell_index = v->cell_index;
  view->n_cells_global = g->n_elems;
  return SK_OK;
}
