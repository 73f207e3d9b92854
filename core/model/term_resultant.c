/* The resultant-load term: a prescribed total force R(t) = history(t) R on a face group, spread as the uniform
 * traction R / A over the group's faceted area A (docs/scene-reference.md, boundary `resultant`). Node a gets
 *   f_a = R W_a / A,   W_a = sum over the faces of integral N_a dA,   A = sum_a W_a,                         (1)
 * so sum_a f_a = R exactly on any faces (curved, quadratic; the weights of sk_face_weights are those of a uniform
 * traction, consistent with the element). Over the reference area (1) is a dead load. Over the current area, W and A
 * are taken at the configuration where the integrator balances forces, q_alpha = X + u_n + alpha (u - u_n), and
 *   d f_a / d u_bj = alpha R (dW_a/dq_bj / A - W_a dA/dq_bj / A^2),   dA/dq_bj = sum_a dW_a/dq_bj,            (2)
 * whose second part couples every node of the group with every other (a dense block of (n dim)^2 entries, declared
 * in the pattern). Over the reference area each node's owner adds its force; over the current area rank 0 assembles
 * the whole group (its nodes are rank 0's ghosts, model.c: sk_model_node_roles). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "stickslip/fe.h"
#include "system.h"

typedef struct {
  sk_term base;
  int k;                  /* index in model->resultants */
  int body;               /* the body its faces lie on */
  int n_nodes, *nodes;    /* the group's nodes (sorted mesh ids); n dofs = n_nodes * dim */
  int *local_of_face;     /* n_elems * nen: the index in `nodes` of each face node */
  double *W, *dW;         /* W_a (n_nodes); dW (n_nodes x n dofs), current area only */
  double *ratio;          /* reference area: W_a / A, fixed */
  double *dA;             /* current area: dA/dq (n dofs) */
  double *q;              /* current area: q_alpha (mesh numbering, the group's nodes written) */
  int64_t *dofs;          /* n dofs: the local dof of each (node, component) */
  double *K;              /* current area: the dense block (n dofs)^2 */
} resultant_term;

static void resultant_destroy(sk_term *base) {
  resultant_term *term = (resultant_term *)base;
  free(term->nodes);
  free(term->local_of_face);
  free(term->W);
  free(term->dW);
  free(term->ratio);
  free(term->dA);
  free(term->q);
  free(term->dofs);
  free(term->K);
  free(term);
}

static const sk_time_integrator *integrator_of(const sk_system *sys, int body) {
  return body >= 0 ? sys->model->bodies[body].integrator : sys->integrator;
}

/* W_a and, when dW is not NULL, dW_a/dq over the group's faces this rank holds at positions q (model numbering, dim per
 * node); returns their area A, or with owned_area the area of the faces whose first node this rank owns (each face on
 * one rank: the sum over ranks is the group's). */
static double group_weights(const resultant_term *term, const sk_model *m, const double *q, double *W, double *dW,
                            int owned_area) {
  const sk_group *g = m->resultants[term->k].faces;
  const int dim = m->dim, nd = term->n_nodes * dim, fd = g->nen * dim;
  memset(W, 0, sizeof(double) * (size_t)term->n_nodes);
  if (dW) memset(dW, 0, sizeof(double) * (size_t)term->n_nodes * (size_t)nd);
  double area = 0.0;
  for (int e = 0; e < g->n_elems; ++e) {
    const int *conn = g->conn + (size_t)e * g->nen, *local = term->local_of_face + (size_t)e * g->nen;
    double X[SK_MAX_NEN * 3], w[SK_MAX_NEN], dw[SK_MAX_NEN * SK_MAX_NEN * 3];
    for (int a = 0; a < g->nen; ++a)
      for (int i = 0; i < dim; ++i) X[a * dim + i] = q[(size_t)conn[a] * dim + i];
    sk_face_weights(g->type, dim, X, w, dW ? dw : NULL);
    const int counted = !owned_area || m->node_owner[conn[0]] == m->rank;
    for (int a = 0; a < g->nen; ++a) {
      W[local[a]] += w[a];
      if (counted) area += w[a];
      for (int b = 0; dW && b < g->nen; ++b)
        for (int j = 0; j < dim; ++j) dW[(size_t)local[a] * nd + local[b] * dim + j] += dw[a * fd + b * dim + j];
    }
  }
  return area;
}

/* q_alpha of the group's nodes (mesh numbering). */
static const double *force_configuration(const resultant_term *term, const sk_system *sys, double alpha) {
  const sk_model *m = sys->model;
  const int dim = m->dim;
  double *q = term->q;
  for (int a = 0; a < term->n_nodes; ++a)
    for (int i = 0; i < dim; ++i) {
      const int64_t d = (int64_t)term->nodes[a] * dim + i;
      q[d] = m->X[d] + sys->u_n[d] + alpha * (sys->x[d] - sys->u_n[d]);
    }
  return q;
}

static sk_status resultant_residual(sk_term *base, sk_system *sys) {
  resultant_term *term = (resultant_term *)base;
  const sk_model *m = sys->model;
  const sk_resultant *load = &m->resultants[term->k];
  if (m->rank != 0 && load->current_area) return SK_OK;
  const sk_time_integrator *integrator = integrator_of(sys, term->body);
  const double scale = sk_history_value(&load->history, integrator->force_time(sys->t_n, sys->t));
  const double *ratio = term->ratio;
  if (load->current_area) {
    const double area = group_weights(term, m, force_configuration(term, sys, integrator->alpha), term->W, NULL, 0);
    if (!(area > 0.0))
      return sk_error_set(SK_ERR_DIVERGED, "resultant load '%s': the current area of its faces is %g", load->name,
                          area);
    for (int a = 0; a < term->n_nodes; ++a) term->W[a] /= area;
    ratio = term->W;
  }
  for (int a = 0; a < term->n_nodes; ++a) {
    if (!load->current_area && m->node_owner[term->nodes[a]] != m->rank) continue;
    for (int i = 0; i < m->dim; ++i) sys->F_local[term->dofs[a * m->dim + i]] -= scale * load->resultant[i] * ratio[a];
  }
  return SK_OK;
}

/* Current area only: the dense block of the group's dofs (rank 0 writes it). */
static sk_status resultant_pattern(sk_term *base, sk_system *sys, unsigned char *rows) {
  resultant_term *term = (resultant_term *)base;
  const sk_model *m = sys->model;
  if (m->rank != 0 || !m->resultants[term->k].current_area) return SK_OK;
  const int nd = term->n_nodes * m->dim;
  for (int r = 0; r < nd; ++r) rows[term->dofs[r]] = 1;
  return sk_system_declare_local(sys, nd, term->dofs, nd, term->dofs);
}

static sk_status resultant_jacobian(sk_term *base, sk_system *sys) {
  resultant_term *term = (resultant_term *)base;
  const sk_model *m = sys->model;
  const sk_resultant *load = &m->resultants[term->k];
  if (m->rank != 0 || !load->current_area) return SK_OK;
  const sk_time_integrator *integrator = integrator_of(sys, term->body);
  const double scale = sk_history_value(&load->history, integrator->force_time(sys->t_n, sys->t));
  const int dim = m->dim, nd = term->n_nodes * dim;
  const double area = group_weights(term, m, force_configuration(term, sys, integrator->alpha), term->W, term->dW, 0);
  if (!(area > 0.0))
    return sk_error_set(SK_ERR_DIVERGED, "resultant load '%s': the current area of its faces is %g", load->name, area);
  /* dA/dq_c = sum_a dW_a/dq_c, then (2); K = dF/du = -df/du */
  double *dA = term->dA;
  for (int c = 0; c < nd; ++c) {
    double s = 0.0;
    for (int a = 0; a < term->n_nodes; ++a) s += term->dW[(size_t)a * nd + c];
    dA[c] = s;
  }
  for (int a = 0; a < term->n_nodes; ++a)
    for (int i = 0; i < dim; ++i) {
      const double R = scale * load->resultant[i];
      for (int c = 0; c < nd; ++c) {
        const double df = integrator->alpha * R *
                          (term->dW[(size_t)a * nd + c] / area - term->W[a] * dA[c] / (area * area));
        term->K[(size_t)(a * dim + i) * nd + c] = -df;
      }
    }
  for (int r = 0; r < nd; ++r) {
    const int64_t row = term->dofs[r];
    if (sys->solver_of[row] < 0) continue;
    for (int c = 0; c < nd; ++c) {
      const int64_t col = term->dofs[c];
      const double v = term->K[(size_t)r * nd + c];
      if (sys->solver_of[col] < 0 || v == 0.0) continue;
      const int64_t p = sk_system_position(sys, row, col);
      if (p < 0)
        return sk_error_set(SK_ERR_INTERNAL, "resultant load '%s': entry (%lld, %lld) outside its pattern", load->name,
                            (long long)term->dofs[r], (long long)term->dofs[c]);
      sys->values[p] += v;
    }
  }
  return SK_OK;
}

static const sk_term_ops resultant_ops = {.kind = "resultant",
                                          .destroy = resultant_destroy,
                                          .pattern = resultant_pattern,
                                          .residual = resultant_residual,
                                          .jacobian = resultant_jacobian};

static int compare_int(const void *a, const void *b) {
  const int x = *(const int *)a, y = *(const int *)b;
  return (x > y) - (x < y);
}

sk_status sk_term_resultant_create(sk_system *sys, int k, sk_term **out) {
  *out = NULL;
  const sk_model *m = sys->model;
  const sk_resultant *load = &m->resultants[k];
  const sk_group *g = load->faces;
  const int dim = m->dim;
  resultant_term *term = calloc(1, sizeof *term);
  if (!term) return sk_error_set(SK_ERR_NOMEM, "out of memory for resultant load '%s'", load->name);
  term->base.ops = &resultant_ops;
  snprintf(term->base.name, sizeof term->base.name, "resultant load '%s'", load->name);
  term->k = k;
  /* the group's body and whether it has faces: from the ranks that hold some */
  int found[2] = {g->n_elems > 0 ? sk_model_body_of_node(m, g->conn[0]) : -1, g->n_elems};
  MPI_Allreduce(MPI_IN_PLACE, found, 2, MPI_INT, MPI_MAX, m->comm);
  term->body = found[0];
  const int dense = load->current_area && m->rank == 0; /* rank 0 assembles the current area's dense block */
  sk_status status = SK_OK;
  if (found[1] == 0) status = sk_error_set(SK_ERR_INPUT, "resultant load '%s': group '%s' has no faces",
                                           load->name, g->name);
  else if (term->body >= 0 && m->bodies[term->body].plugin)
    status = sk_error_set(SK_ERR_INPUT, "resultant load '%s': body '%s' is handled by the body plugin %s, which "
                          "receives tractions only; use `traction` on it", load->name, m->bodies[term->body].name,
                          m->bodies[term->body].plugin->name);
  if (status == SK_OK) status = sk_group_nodes(g, &term->nodes, &term->n_nodes);
  const size_t n = (size_t)term->n_nodes, nd = n * (size_t)dim, slots = (size_t)g->n_elems * (size_t)g->nen;
  if (status == SK_OK) {
    term->local_of_face = malloc(slots * sizeof(int));
    term->W = calloc(n, sizeof(double));
    term->ratio = calloc(n, sizeof(double));
    term->dofs = malloc(nd * sizeof(int64_t));
    if (dense) {
      term->dW = malloc(n * nd * sizeof(double));
      term->K = malloc(nd * nd * sizeof(double));
      term->dA = malloc(nd * sizeof(double));
      term->q = malloc((size_t)m->n_nodes * (size_t)dim * sizeof(double));
    }
    if (!term->local_of_face || !term->W || !term->ratio || !term->dofs ||
        (dense && (!term->dW || !term->K || !term->dA || !term->q)))
      status = sk_error_set(SK_ERR_NOMEM, "out of memory for resultant load '%s' (%d nodes)", load->name,
                            term->n_nodes);
  }
  status = sk_system_collective(sys, status); /* the area below is summed over ranks */
  if (status == SK_OK) {
    for (size_t s = 0; s < slots; ++s) {
      const int *hit = bsearch(&g->conn[s], term->nodes, n, sizeof(int), compare_int);
      term->local_of_face[s] = (int)(hit - term->nodes);
    }
    for (size_t a = 0; a < n; ++a)
      for (int i = 0; i < dim; ++i) term->dofs[a * dim + i] = (int64_t)term->nodes[a] * dim + i;
    double area = group_weights(term, m, m->X, term->W, NULL, 1);
    MPI_Allreduce(MPI_IN_PLACE, &area, 1, MPI_DOUBLE, MPI_SUM, m->comm);
    if (!(area > 0.0))
      status = sk_error_set(SK_ERR_INPUT, "resultant load '%s': the faces of group '%s' have area %g", load->name,
                            g->name, area);
    for (size_t a = 0; a < n; ++a) term->ratio[a] = term->W[a] / area;
  }
  if (status != SK_OK) {
    resultant_destroy(&term->base);
    return status;
  }
  *out = &term->base;
  return SK_OK;
}
