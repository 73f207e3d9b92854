/* The model's finite-element data (model.h): consistent mass, METIS partition and node owners, built once after the
 * scene is read; piecewise-linear histories; freeing. Out of memory is SK_ERR_NOMEM with a message, never an abort. */
#include <stdlib.h>
#include <string.h>

#include "stickslip/model.h"
#include "contact_partition.h"


double sk_history_value(const sk_history *history, double t) {
  if (history->n == 0) return 1.0;
  if (t <= history->t[0]) return history->v[0];
  for (int k = 1; k < history->n; ++k) {
    if (t <= history->t[k]) {
      double s = (t - history->t[k - 1]) / (history->t[k] - history->t[k - 1]);
      return (1.0 - s) * history->v[k - 1] + s * history->v[k];
    }
  }
  return history->v[history->n - 1];
}

static int compare_ints(const void *a, const void *b) {
  int x = *(const int *)a, y = *(const int *)b;
  return (x > y) - (x < y);
}

static sk_status out_of_memory(const char *what) {
  return sk_error_set(SK_ERR_NOMEM, "out of memory building the model's %s", what);
}

/* The node graph of the bodies' elements as a scalar CSR (sorted, unique columns): the mass matrix's pattern. */
sk_status sk_model_build_graph(sk_model *model) {
  const int n = model->n_nodes;
  free(model->mass_row_ptr);
  free(model->mass_cols);
  free(model->mass_values);
  model->mass_row_ptr = NULL;
  model->mass_cols = NULL;
  model->mass_values = NULL;
  int64_t *count = calloc((size_t)n + 1, sizeof *count);
  int64_t *start = malloc(sizeof(int64_t) * ((size_t)n + 1));
  model->mass_row_ptr = malloc(sizeof(int64_t) * ((size_t)n + 1));
  if (!count || !start || !model->mass_row_ptr) {
    free(count);
    free(start);
    return out_of_memory("mass matrix");
  }
  for (int b = 0; b < model->n_bodies; ++b) {
    const sk_group *g = model->bodies[b].group;
    for (int e = 0; e < g->n_elems; ++e)
      for (int a = 0; a < g->nen; ++a) count[g->conn[(size_t)e * g->nen + a]] += g->nen;
  }
  start[0] = 0;
  for (int i = 0; i < n; ++i) start[i + 1] = start[i] + count[i];
  int *cols = malloc(sizeof(int) * (size_t)(start[n] > 0 ? start[n] : 1));
  if (!cols) {
    free(count);
    free(start);
    return out_of_memory("mass matrix");
  }
  memset(count, 0, sizeof(int64_t) * (size_t)n);
  for (int b = 0; b < model->n_bodies; ++b) {
    const sk_group *g = model->bodies[b].group;
    for (int e = 0; e < g->n_elems; ++e)
      for (int a = 0; a < g->nen; ++a) {
        int row = g->conn[(size_t)e * g->nen + a];
        for (int c = 0; c < g->nen; ++c) cols[start[row] + count[row]++] = g->conn[(size_t)e * g->nen + c];
      }
  }
  model->mass_row_ptr[0] = 0;
  int64_t used = 0;
  for (int i = 0; i < n; ++i) {
    int *row = cols + start[i];
    qsort(row, (size_t)count[i], sizeof(int), compare_ints);
    for (int64_t k = 0; k < count[i]; ++k)
      if (k == 0 || row[k] != row[k - 1]) cols[used++] = row[k];
    model->mass_row_ptr[i + 1] = used;
  }
  free(count);
  free(start);
  int *shrunk = realloc(cols, sizeof(int) * (size_t)(used > 0 ? used : 1));
  model->mass_cols = shrunk ? shrunk : cols;
  model->mass_values = calloc((size_t)(used > 0 ? used : 1), sizeof(double));
  if (!model->mass_values) return out_of_memory("mass matrix");
  return SK_OK;
}

/* Consistent nodal mass matrix (scalar) and the element mass matrices (kept: the inertia terms of every Newton
 * iteration reuse them). Built once, when a term declares it needs the mass (system_needs.c). */
sk_status sk_model_build_mass(sk_model *model) {
  if (model->element_mass) return SK_OK;
  double X[SK_MAX_NEN * 3];
  const int dim = model->dim;
  free(model->element_mass_offset); /* a call after a failed one */
  model->element_mass_offset = malloc(sizeof(int64_t) * ((size_t)model->n_elements + 1));
  if (!model->element_mass_offset) return out_of_memory("element mass matrices");
  model->element_mass_offset[0] = 0;
  for (int b = 0, e_global = 0; b < model->n_bodies; ++b)
    for (int e = 0; e < model->bodies[b].group->n_elems; ++e, ++e_global)
      model->element_mass_offset[e_global + 1] =
          model->element_mass_offset[e_global] + model->bodies[b].group->nen * model->bodies[b].group->nen;
  double *element_mass = malloc(sizeof(double) * (size_t)(model->element_mass_offset[model->n_elements] + 1));
  if (!element_mass) return out_of_memory("element mass matrices");
  model->element_mass = element_mass;
  for (int b = 0; b < model->n_bodies; ++b) {
    const sk_body *body = &model->bodies[b];
    const sk_group *g = body->group;
    for (int e = 0; e < g->n_elems; ++e) {
      const int *conn = g->conn + (size_t)e * g->nen;
      for (int a = 0; a < g->nen; ++a)
        for (int i = 0; i < dim; ++i) X[a * dim + i] = model->mesh.x[3 * conn[a] + i];
      double *M = model->element_mass + model->element_mass_offset[body->first_element + e];
      sk_status status = sk_solid_mass(&body->solid, X, M);
      if (status != SK_OK)
        return sk_error_prefix(status, "mesh %s: body '%s', element %d: ", model->mesh.source, body->name,
                               model->element_index[body->first_element + e]);
      for (int a = 0; a < g->nen; ++a) {
        int row = conn[a];
        const int *rc = model->mass_cols + model->mass_row_ptr[row];
        size_t len = (size_t)(model->mass_row_ptr[row + 1] - model->mass_row_ptr[row]);
        for (int c = 0; c < g->nen; ++c) {
          const int *hit = bsearch(&conn[c], rc, len, sizeof(int), compare_ints);
          model->mass_values[model->mass_row_ptr[row] + (hit - rc)] += M[a * g->nen + c];
        }
      }
    }
  }
  return SK_OK;
}

/* METIS partition of all body elements and the owner of every node: the lowest part among the elements holding it
 * (nodes of no body: rank 0). */
static sk_status partition(sk_model *model) {
  model->element_part = calloc((size_t)(model->n_elements > 0 ? model->n_elements : 1), sizeof(int));
  const sk_group **bodies = malloc(sizeof *bodies * (size_t)(model->n_bodies > 0 ? model->n_bodies : 1));
  model->node_owner = malloc(sizeof(int) * (size_t)(model->n_nodes > 0 ? model->n_nodes : 1));
  if (!model->element_part || !bodies || !model->node_owner) {
    free(bodies);
    return out_of_memory("partition");
  }
  for (int b = 0; b < model->n_bodies; ++b) bodies[b] = model->bodies[b].group;
  sk_status status = sk_mesh_partition(&model->mesh, bodies, model->n_bodies, model->n_ranks, model->element_part);
  free(bodies);
  SK_TRY(status);
  for (int a = 0; a < model->n_nodes; ++a) model->node_owner[a] = model->n_ranks;
  for (int b = 0; b < model->n_bodies; ++b) {
    const sk_group *g = model->bodies[b].group;
    for (int e = 0; e < g->n_elems; ++e)
      for (int a = 0; a < g->nen; ++a) {
        int node = g->conn[(size_t)e * g->nen + a], part = model->element_part[model->bodies[b].first_element + e];
        if (part < model->node_owner[node]) model->node_owner[node] = part;
      }
  }
  for (int a = 0; a < model->n_nodes; ++a)
    if (model->node_owner[a] == model->n_ranks) model->node_owner[a] = 0;
  return SK_OK;
}

static int compare_pairs(const void *a, const void *b) {
  const int64_t *x = a, *y = b;
  return (x[0] > y[0]) - (x[0] < y[0]);
}

/* The sorted lookup table of the nodes' mesh ids. */
sk_status sk_model_index_nodes(sk_model *model) {
  const size_t n = (size_t)(model->n_nodes > 0 ? model->n_nodes : 1);
  free(model->gid_sorted);
  model->gid_sorted = malloc(2 * sizeof(int64_t) * n);
  if (!model->gid_sorted) return out_of_memory("node ids");
  for (int a = 0; a < model->n_nodes; ++a) {
    model->gid_sorted[2 * a] = model->node_gid[a];
    model->gid_sorted[2 * a + 1] = a;
  }
  qsort(model->gid_sorted, (size_t)model->n_nodes, 2 * sizeof(int64_t), compare_pairs);
  return SK_OK;
}

int sk_model_node_of(const sk_model *model, int64_t gid) {
  int lo = 0, hi = model->n_nodes;
  while (lo < hi) {
    const int mid = lo + (hi - lo) / 2;
    if (model->gid_sorted[2 * mid] < gid) lo = mid + 1;
    else hi = mid;
  }
  return lo < model->n_nodes && model->gid_sorted[2 * lo] == gid ? (int)model->gid_sorted[2 * lo + 1] : -1;
}

sk_status sk_model_build(sk_model *model) {
  model->n_nodes_global = model->n_nodes;
  model->n_dofs_global = model->n_dofs;
  free(model->node_gid);
  free(model->element_index);
  model->node_gid = malloc(sizeof(int64_t) * (size_t)(model->n_nodes > 0 ? model->n_nodes : 1));
  model->element_index = malloc(sizeof(int) * (size_t)(model->n_elements > 0 ? model->n_elements : 1));
  if (!model->node_gid || !model->element_index) return out_of_memory("node ids");
  for (int a = 0; a < model->n_nodes; ++a) model->node_gid[a] = a;
  for (int b = 0; b < model->n_bodies; ++b)
    for (int e = 0; e < model->bodies[b].group->n_elems; ++e) model->element_index[model->bodies[b].first_element + e] = e;
  for (int b = 0; b < model->n_bodies; ++b) {
    model->bodies[b].n_elems_global = model->bodies[b].group->n_elems;
    model->bodies[b].n_nodes_global = 0; /* sk_model_distribute counts them */
  }
  SK_TRY(sk_model_index_nodes(model));
  return partition(model);
}

void sk_model_layer_roles(const sk_model *m, unsigned char *role) {
  for (int a = 0; a < m->n_nodes; ++a) role[a] = m->node_owner[a] == m->rank ? SK_NODE_OWNED : 0;
  /* the ghost layer: every element this rank owns or that holds a node it owns */
  for (int b = 0; b < m->n_bodies; ++b) {
    const sk_group *g = m->bodies[b].group;
    for (int e = 0; e < g->n_elems; ++e) {
      const int *conn = g->conn + (size_t)e * g->nen;
      int held = m->element_part[m->bodies[b].first_element + e] == m->rank;
      for (int a = 0; a < g->nen && !held; ++a) held = m->node_owner[conn[a]] == m->rank;
      for (int a = 0; held && a < g->nen; ++a)
        if (!role[conn[a]]) role[conn[a]] = SK_NODE_GHOST;
    }
  }
  /* rank 0 assembles the current-area resultant loads (each couples all nodes of its group) */
  for (int k = 0; m->rank == 0 && k < m->n_resultants; ++k) {
    if (!m->resultants[k].current_area) continue;
    const sk_group *g = m->resultants[k].faces;
    for (int64_t j = 0; j < (int64_t)g->n_elems * g->nen; ++j)
      if (!role[g->conn[j]]) role[g->conn[j]] = SK_NODE_GHOST;
  }
}

/* Before distribution, the bulk partition: the nodes of every slave face sharing a node with a face that touches a
 * node held so far (role set), so that after distribution the slave view's second layer of faces is held. */
static sk_status hold_slave_stars(const sk_model *m, const sk_surface *s, unsigned char *role) {
  unsigned char *near = calloc((size_t)(m->n_nodes > 0 ? m->n_nodes : 1), 1);
  if (!near) return sk_error_set(SK_ERR_NOMEM, "out of memory for the slave faces of a contact pair");
  for (int f = 0; f < s->n_faces; ++f) {
    const int *conn = s->conn + (size_t)f * s->nen;
    int touches = 0;
    for (int a = 0; a < s->nen && !touches; ++a) touches = role[conn[a]] != 0;
    for (int a = 0; touches && a < s->nen; ++a) near[conn[a]] = 1;
  }
  for (int f = 0; f < s->n_faces; ++f) {
    const int *conn = s->conn + (size_t)f * s->nen;
    int around = 0;
    for (int a = 0; a < s->nen && !around; ++a) around = near[conn[a]];
    for (int a = 0; around && a < s->nen; ++a)
      if (!role[conn[a]]) role[conn[a]] = SK_NODE_GHOST;
  }
  free(near);
  return SK_OK;
}

sk_status sk_model_node_roles(const sk_model *m, unsigned char *role) {
  sk_model_layer_roles(m, role);
  /* master surfaces: a slave point may reach any of their faces; with ghost boxes, the faces this rank holds now
   * (master_ghosts.h; before the model is distributed every master node is held, for later re-ghosting) */
  for (int k = 0; k < m->n_pairs; ++k) {
    const sk_contact_pair *pair = &m->pairs[k];
    const sk_surface *s = &pair->master;
    if (pair->has_obstacle) continue;
    if (!pair->master_held) {
      for (int j = 0; j < s->n_nodes; ++j)
        if (!role[s->nodes[j]]) role[s->nodes[j]] = SK_NODE_GHOST;
      continue;
    }
    for (int f = 0; f < s->n_faces; ++f) {
      if (!pair->master_held[f]) continue;
      const int *conn = s->conn + (size_t)f * s->nen;
      for (int a = 0; a < s->nen; ++a)
        if (!role[conn[a]]) role[conn[a]] = SK_NODE_GHOST;
    }
  }
  /* the nodes of the faces of this rank's slave views (contact_partition.h: two layers of faces, the faces it
   * evaluates and every face around their nodes). Before the model is distributed (the surface not localized yet):
   * with a contact partition every slave node, kept for a rebalancing (idle until used); with the bulk partition the
   * faces around the nodes of every face that touches the nodes held so far, a superset of the views' faces */
  for (int k = 0; k < m->n_pairs; ++k) {
    const sk_contact_pair *pair = &m->pairs[k];
    const sk_surface *s = &pair->slave;
    if (!s->face_index && !pair->contact_node_owner) {
      SK_TRY(hold_slave_stars(m, s, role));
      continue;
    }
    if (!s->face_index) {
      for (int j = 0; j < s->n_nodes; ++j)
        if (!role[s->nodes[j]]) role[s->nodes[j]] = SK_NODE_GHOST;
      continue;
    }
    unsigned char *used = malloc((size_t)(s->n_faces > 0 ? s->n_faces : 1));
    if (!used || sk_contact_faces_used(m, pair, used) != 0) {
      free(used);
      return sk_error_set(SK_ERR_NOMEM, "out of memory for the slave faces of contact pair %s", pair->name);
    }
    for (int f = 0; f < s->n_faces; ++f)
      for (int a = 0; used[f] && a < s->nen; ++a)
        if (!role[s->conn[(size_t)f * s->nen + a]]) role[s->conn[(size_t)f * s->nen + a]] = SK_NODE_GHOST;
    free(used);
  }
  return SK_OK;
}

int sk_model_body_of_node(const sk_model *model, int node) {
  for (int b = 0; b < model->n_bodies; ++b) {
    const sk_group *g = model->bodies[b].group;
    for (int64_t k = 0; k < (int64_t)g->n_elems * g->nen; ++k)
      if (g->conn[k] == node) return b;
  }
  return -1;
}

void sk_model_free(sk_model *model) {
  for (int k = 0; k < model->n_pairs; ++k) {
    sk_contact_pair *pair = &model->pairs[k];
    sk_surface_free(&pair->slave);
    if (!pair->has_obstacle && !pair->self_contact) sk_surface_free(&pair->master);
    free(pair->ghost_boxes);
    free(pair->master_held);
    free(pair->master_face_box);
    free(pair->contact_node_owner);
    free(pair->contact_face_owner);
    free(pair->contact_weight);
  }
  free(model->pairs);
  for (int k = 0; k < model->n_dirichlet; ++k) free(model->dirichlet[k].nodes);
  free(model->dirichlet);
  free(model->tractions);
  free(model->resultants);
  for (int b = 0; b < model->n_bodies; ++b) free(model->bodies[b].node_index);
  free(model->bodies);
  free(model->element_index);
  free(model->surface_ptr);
  free(model->surface_cols);
  free(model->element_part);
  free(model->node_owner);
  free(model->node_gid);
  free(model->gid_sorted);
  free(model->X);
  free(model->mass_row_ptr);
  free(model->mass_cols);
  free(model->mass_values);
  free(model->element_mass_offset);
  free(model->element_mass);
  sk_mesh_free(&model->mesh);
  memset(model, 0, sizeof *model);
}
