/* Views (host.h, plugin_types.h): a surface or body as one rank sees it, owned cells and nodes plus ghosts, in a
 * local numbering. Built once per instance at scene load. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "contact_partition.h"
#include "host.h"

int sk_compare_int(const void *a, const void *b) {
  int x = *(const int *)a, y = *(const int *)b;
  return (x > y) - (x < y);
}

int64_t sk_index_in_sorted(const int *sorted, int n, int value) {
  const int *hit = bsearch(&value, sorted, (size_t)n, sizeof(int), sk_compare_int);
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
  free(v->local_dofs);
  memset(v, 0, sizeof *v);
}

static sk_status no_memory(sk_view_data *v, const char *name) {
  sk_view_free(v);
  return sk_error_set(SK_ERR_NOMEM, "out of memory for the view of '%s'", name);
}

/* Fills the node arrays of a view from its nodes (model nodes, sorted): their index in the whole surface/body
 * (whole_index per model node, or per position in `all` when it is NULL: an index into the sorted list `all`),
 * mesh id, ownership, ABI dofs and reference positions X. */
static sk_status fill_nodes(sk_view_data *v, const sk_model *m, const int *nodes, int n, const int64_t *whole_index,
                            const int *all, int n_all, int n_global, const char *name) {
  const int dim = m->dim;
  const size_t nn = (size_t)(n > 0 ? n : 1);
  v->local_nodes = malloc(sizeof(int) * nn);
  v->node_index = malloc(sizeof(int64_t) * nn);
  v->node_id = malloc(sizeof(int64_t) * nn);
  v->owned = malloc(nn);
  v->dofs = malloc(sizeof(int64_t) * nn * (size_t)dim);
  v->X = malloc(sizeof(double) * nn * (size_t)dim);
  if (!v->local_nodes || !v->node_index || !v->node_id || !v->owned || !v->dofs || !v->X) return no_memory(v, name);
  for (int k = 0; k < n; ++k) {
    const int a = nodes[k];
    v->local_nodes[k] = k;
    v->node_index[k] = whole_index ? whole_index[k] : sk_index_in_sorted(all, n_all, a);
    v->node_id[k] = m->node_gid[a];
    v->owned[k] = m->node_owner[a] == m->rank;
    for (int i = 0; i < dim; ++i) {
      v->dofs[(size_t)k * dim + i] = m->node_gid[a] * dim + i;
      v->X[(size_t)k * dim + i] = m->X[(size_t)a * dim + i];
    }
  }
  sk_view *view = &v->view;
  view->dim = dim;
  view->n_nodes = n;
  view->n_nodes_global = n_global;
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
  qsort(nodes, (size_t)used, sizeof(int), sk_compare_int);
  int unique = 0;
  for (int64_t k = 0; k < used; ++k)
    if (k == 0 || nodes[k] != nodes[unique - 1]) nodes[unique++] = nodes[k];
  *n_out = unique;
  return nodes;
}

/* A surface view of the faces `selected` (NULL: all) of a (distributed) core surface, in model numbering. */
static sk_status fill_surface(sk_view_data *v, const sk_model *m, const sk_surface *s, const char *name,
                              const unsigned char *selected) {
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
  /* each view node's index in the whole surface */
  int64_t *whole = malloc(sizeof(int64_t) * (size_t)(n_nodes > 0 ? n_nodes : 1));
  for (int k = 0; whole && nodes && k < n_nodes; ++k) {
    const int64_t at = sk_index_in_sorted(s->nodes, s->n_nodes, nodes[k]);
    whole[k] = s->node_index ? s->node_index[at] : at;
  }
  const size_t nc = (size_t)(n_cells > 0 ? n_cells : 1);
  v->conn = malloc(sizeof(int) * nc * (size_t)s->nen);
  v->cell_owned = malloc(nc);
  v->cell_index = malloc(sizeof(int64_t) * nc);
  v->neighbors = malloc(sizeof(int) * nc * (size_t)s->n_edges);
  sk_status status = nodes && whole && v->conn && v->cell_owned && v->cell_index && v->neighbors
                         ? fill_nodes(v, m, nodes, n_nodes, whole, NULL, 0,
                                      s->n_nodes_global > 0 ? s->n_nodes_global : s->n_nodes, name)
                         : no_memory(v, name);
  free(whole);
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
      v->conn[(size_t)c * s->nen + a] = (int)sk_index_in_sorted(nodes, n_nodes, s->conn[(size_t)f * s->nen + a]);
    v->cell_owned[c] = s->face_owner ? s->face_owner[f] == m->rank : 1;
    v->cell_index[c] = s->face_index ? s->face_index[f] : f;
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
  view->dim = m->dim;
  view->body = s->body;
  view->cell_type = s->face_type;
  view->nen = s->nen;
  view->n_cells = n_cells;
  view->conn = v->conn;
  view->cell_owned = v->cell_owned;
  view->cell_index = v->cell_index;
  view->n_cells_global = s->n_faces_global > 0 ? s->n_faces_global : s->n_faces;
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
  local->n_faces_global = n_cells;
  local->n_nodes_global = n_nodes;
  return SK_OK;
}

sk_status sk_view_fill_surface(sk_view_data *v, const sk_surface *s, const char *name, int dim, const double *X) {
  /* a model of the surface's nodes alone, all on rank 0 */
  const int n_nodes = s->n_nodes > 0 ? s->nodes[s->n_nodes - 1] + 1 : 1;
  sk_model m = {.dim = dim, .n_nodes = n_nodes, .X = (double *)(uintptr_t)X, .rank = 0};
  m.node_gid = malloc(sizeof(int64_t) * (size_t)n_nodes);
  m.node_owner = calloc((size_t)n_nodes, sizeof(int));
  sk_status status = m.node_gid && m.node_owner ? SK_OK : no_memory(v, name);
  for (int a = 0; status == SK_OK && a < n_nodes; ++a) m.node_gid[a] = a;
  if (status == SK_OK) status = fill_surface(v, &m, s, name, NULL);
  free(m.node_gid);
  free(m.node_owner);
  return status;
}

sk_status sk_view_surface(const sk_model *m, const sk_surface *s, const char *name, int whole,
                          const unsigned char *held, const sk_contact_pair *contact, sk_view_data *v) {
  memset(v, 0, sizeof *v);
  const size_t nf = (size_t)(s->n_faces > 0 ? s->n_faces : 1);
  unsigned char *selected = calloc(nf, 1);
  if (!selected) return no_memory(v, name);
  if (contact && (s != &contact->slave || whole)) contact = NULL;
  /* a pair's slave surface: the faces this rank evaluates (it owns, or with a contact partition contact-owns, the face
   * or one of its nodes) and every face around their nodes (contact_partition.h); other surfaces: every face this
   * rank owns or with a node it owns (with `whole`, every face it holds, or those `held` flags) */
  if (contact && sk_contact_faces_used(m, contact, selected) != 0) {
    free(selected);
    return no_memory(v, name);
  }
  for (int f = 0; f < s->n_faces && !contact; ++f) {
    int take = whole ? !held || held[f] : s->face_owner && s->face_owner[f] == m->rank;
    for (int a = 0; a < s->nen && !take; ++a) take = m->node_owner[s->conn[(size_t)f * s->nen + a]] == m->rank;
    selected[f] = (unsigned char)take;
  }
  const sk_status status = fill_surface(v, m, s, name, selected);
  free(selected);
  /* the contact partition: the view's owned nodes and faces are those this rank contact-owns */
  if (contact && !contact->contact_node_owner) contact = NULL;
  for (int k = 0; status == SK_OK && contact && k < v->view.n_nodes; ++k)
    v->owned[k] = contact->contact_node_owner[v->node_index[k]] == m->rank;
  for (int c = 0; status == SK_OK && contact && c < v->view.n_cells; ++c)
    v->cell_owned[c] = contact->contact_face_owner[v->cell_index[c]] == m->rank;
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
  int *all = body->node_index ? NULL : collect_nodes(g->conn, g->nen, everything, g->n_elems, &n_all);
  int64_t *whole = NULL;
  if (body->node_index && nodes) {
    whole = malloc(sizeof(int64_t) * (size_t)(n_nodes > 0 ? n_nodes : 1));
    for (int k = 0; whole && k < n_nodes; ++k) whole[k] = body->node_index[nodes[k]];
  }
  const int n_global = body->node_index ? body->n_nodes_global : n_all;
  sk_status status = nodes && (all || whole) ? fill_nodes(v, m, nodes, n_nodes, whole, all, n_all, n_global, body->name)
                                             : SK_ERR_NOMEM;
  free(whole);
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
        v->conn[(size_t)c * g->nen + a] = (int)sk_index_in_sorted(nodes, n_nodes, g->conn[(size_t)e * g->nen + a]);
      v->cell_owned[c] = m->element_part[body->first_element + e] == m->rank;
      v->cell_index[c] = m->element_index ? m->element_index[body->first_element + e] : e;
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
  view->n_cells_global = body->n_elems_global > 0 ? body->n_elems_global : g->n_elems;
  return SK_OK;
}

sk_status sk_view_localize(sk_view_data *v, const sk_system *sys) {
  const int64_t n = (int64_t)v->view.n_nodes * v->view.dim;
  free(v->local_dofs);
  v->local_dofs = malloc(sizeof(int64_t) * (size_t)(n > 0 ? n : 1));
  if (!v->local_dofs) return sk_error_set(SK_ERR_NOMEM, "out of memory for the view of '%s'", v->view.name);
  for (int64_t k = 0; k < n; ++k) {
    v->local_dofs[k] = sk_system_local_of(sys, v->dofs[k]);
    if (v->local_dofs[k] < 0)
      return sk_error_set(SK_ERR_INTERNAL, "view '%s': node %lld is not held by rank %d", v->view.name,
                          (long long)v->node_id[k / v->view.dim], sys->rank);
  }
  return SK_OK;
}
