/* The Dirichlet term: prescribed displacement components (the scene's `boundary: displacement`). Its stages are a
 * row transformation of the assembled system, the one place Dirichlet conditions are handled:
 *   predict          x_k = value_k(t) at every fixed dof this rank holds;
 *   finish_residual  at the dofs it owns, the support reaction R_k = F_k (summed over ranks) is kept, then
 *                    F_k = x_k - value_k(t);
 *   finish_jacobian  row k of this rank's contributions is zeroed and its owner puts 1 on the diagonal;
 *   finish_rhs       no right-hand-side correction in row k.
 * Other terms add to fixed rows like to any other and need no special case. */
#include <stdlib.h>
#include <string.h>

#include "system.h"

typedef struct {
  sk_term base;
  unsigned char *is_fixed; /* n_dofs (local) */
  double *value;           /* n_dofs, at t */
  double *reaction;        /* n_dofs: the residual at the owned fixed dofs before replacement */
} dirichlet_term;

static void dirichlet_destroy(sk_term *base) {
  dirichlet_term *term = (dirichlet_term *)base;
  free(term->is_fixed);
  free(term->value);
  free(term->reaction);
  free(term);
}

static sk_status dirichlet_predict(sk_term *base, sk_system *sys) {
  dirichlet_term *term = (dirichlet_term *)base;
  const sk_model *m = sys->model;
  for (int k = 0; k < m->n_dirichlet; ++k) {
    const sk_dirichlet *bc = &m->dirichlet[k];
    const double scale = sk_history_value(&bc->history, sys->t);
    for (int j = 0; j < bc->n_nodes; ++j)
      for (int i = 0; i < m->dim; ++i)
        if (bc->fixed[i]) term->value[bc->nodes[j] * m->dim + i] = scale * bc->value[i];
  }
  for (int k = 0; k < m->n_dofs; ++k)
    if (term->is_fixed[k]) sys->x[k] = term->value[k];
  return SK_OK;
}

/* the owners write the unit diagonals */
static sk_status dirichlet_pattern(sk_term *base, sk_system *sys, unsigned char *rows) {
  dirichlet_term *term = (dirichlet_term *)base;
  for (int k = 0; k < sys->model->n_dofs; ++k)
    if (term->is_fixed[k] && sys->role[k] == SK_NODE_OWNED) rows[k] = 1;
  return SK_OK;
}

static sk_status dirichlet_finish_residual(sk_term *base, sk_system *sys, double *F) {
  dirichlet_term *term = (dirichlet_term *)base;
  for (int k = 0; k < sys->model->n_dofs; ++k)
    if (term->is_fixed[k] && sys->role[k] == SK_NODE_OWNED) {
      term->reaction[k] = F[k];
      F[k] = sys->x[k] - term->value[k];
    }
  return SK_OK;
}

static sk_status dirichlet_finish_jacobian(sk_term *base, sk_system *sys) {
  dirichlet_term *term = (dirichlet_term *)base;
  for (int k = 0; k < sys->model->n_dofs; ++k) {
    if (!term->is_fixed[k]) continue;
    for (int64_t p = sys->row_ptr[k]; p < sys->row_ptr[k + 1]; ++p) sys->values[p] = 0.0;
    if (sys->role[k] == SK_NODE_OWNED) sys->values[sk_system_position(sys, k, k)] += 1.0;
  }
  return SK_OK;
}

static void dirichlet_finish_rhs(sk_term *base, sk_system *sys, double *rhs) {
  dirichlet_term *term = (dirichlet_term *)base;
  for (int k = 0; k < sys->model->n_dofs; ++k)
    if (term->is_fixed[k]) rhs[k] = 0.0;
}

static const sk_term_ops dirichlet_ops = {.kind = "dirichlet",
                                          .destroy = dirichlet_destroy,
                                          .predict = dirichlet_predict,
                                          .pattern = dirichlet_pattern,
                                          .finish_residual = dirichlet_finish_residual,
                                          .finish_jacobian = dirichlet_finish_jacobian,
                                          .finish_rhs = dirichlet_finish_rhs};

sk_status sk_term_dirichlet_create(sk_system *sys, sk_term **out) {
  const sk_model *m = sys->model;
  const size_t n = (size_t)(m->n_dofs > 0 ? m->n_dofs : 1);
  dirichlet_term *term = calloc(1, sizeof *term);
  if (term) {
    term->is_fixed = calloc(n, 1);
    term->value = calloc(n, sizeof(double));
    term->reaction = calloc(n, sizeof(double));
  }
  if (!term || !term->is_fixed || !term->value || !term->reaction) {
    if (term) dirichlet_destroy(&term->base);
    return sk_error_set(SK_ERR_NOMEM, "out of memory for the Dirichlet conditions (%d dofs)", m->n_dofs);
  }
  term->base.ops = &dirichlet_ops;
  snprintf(term->base.name, sizeof term->base.name, "Dirichlet conditions");
  for (int k = 0; k < m->n_dirichlet; ++k) {
    const sk_dirichlet *bc = &m->dirichlet[k];
    for (int j = 0; j < bc->n_nodes; ++j)
      for (int i = 0; i < m->dim; ++i)
        if (bc->fixed[i]) term->is_fixed[bc->nodes[j] * m->dim + i] = 1;
  }
  *out = &term->base;
  return SK_OK;
}

void sk_system_reactions(const sk_system *sys, double *sums) {
  const sk_model *m = sys->model;
  memset(sums, 0, sizeof(double) * 3 * (size_t)m->n_dirichlet);
  for (int t = 0; t < sys->n_terms; ++t) {
    if (sys->terms[t]->ops != &dirichlet_ops) continue;
    const dirichlet_term *term = (const dirichlet_term *)sys->terms[t];
    for (int k = 0; k < m->n_dirichlet; ++k) {
      const sk_dirichlet *bc = &m->dirichlet[k];
      for (int j = 0; j < bc->n_nodes; ++j) {
        if (sys->node_role[bc->nodes[j]] != SK_NODE_OWNED) continue;
        for (int i = 0; i < m->dim; ++i)
          if (bc->fixed[i]) sums[3 * k + i] += term->reaction[bc->nodes[j] * m->dim + i];
      }
    }
  }
  if (m->n_dirichlet > 0) MPI_Allreduce(MPI_IN_PLACE, sums, 3 * m->n_dirichlet, MPI_DOUBLE, MPI_SUM, sys->comm);
}
