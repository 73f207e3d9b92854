/* The model's finite-element data (model.h): consistent mass, METIS partition and node owners, built once after the
 * scene is read; piecewise-linear histories; freeing. Out of memory is SK_ERR_NOMEM with a message, never an abort. */
#include <stdlib.h>
#include <string.h>

#include "stickslip/model.h"

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
static sk_status build_node_graph(sk_model *model) {
  const int n = model->n_nodes;
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
        return sk_error_prefix(status, "mesh %s: body '%s', element %d: ", model->mesh.source, body->name, e);
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

sk_status sk_model_build(sk_model *model) {
  SK_TRY(build_node_graph(model));
  return partition(model);
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
  }
  free(model->pairs);
  for (int k = 0; k < model->n_dirichlet; ++k) free(model->dirichlet[k].nodes);
  free(model->dirichlet);
  free(model->tractions);
  free(model->resultants);
  free(model->bodies);
  free(model->element_part);
  free(model->node_owner);
  free(model->X);
  free(model->mass_row_ptr);
  free(model->mass_cols);
  free(model->mass_values);
  free(model->element_mass_offset);
  free(model->element_mass);
  sk_mesh_free(&model->mesh);
  memset(model, 0, sizeof *model);
}
