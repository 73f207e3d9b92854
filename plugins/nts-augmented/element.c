/* nts-augmented — one slave node's element under each strategy (glue.h): what its residual rows are, which
 * Jacobian block it adds and how the eliminated unknowns are recovered.
 *
 *   strategy         residual rows (q_A | lambda_n | f | lambda_aug)          linear system        recovery
 *   condensed        (76): force | Phi_n | (76)_3 | Phi_aug                    Schur complement     (59) exact
 *   augmented        (76)                                                      the whole element    -
 *   paper-reduced    (78)_2 | Phi_n | Phi_aug | lambda_aug - (52)              (80)                 (81), (52)
 *   direct           (74)/(75) forces | gap at t_{n+1} | x_e - local | same    Schur complement     linearised local
 *   direct-endpoint  forces at the mean of f | Phi_n | x_e - local | same       (exact derivative)   solution
 * Inactive nodes carry the trivial rows lambda_n = 0, f = f_frozen, lambda_aug = 0 under every strategy. */
#include <math.h>
#include <string.h>

#include "glue.h"

void nts_element_indices(const sk_instance *inst, const slave_point *p, int64_t extra_base, int64_t *idx) {
  const int dim = inst->dim, nen = inst->facet.nen, nq = 3 + 3 * nen;
  for (int i = 0; i < 3; ++i) idx[i] = i < dim ? inst->slave->dofs[dim * p->k + i] : -1;
  for (int I = 0; I < nen; ++I)
    for (int i = 0; i < 3; ++i)
      idx[3 * (1 + I) + i] = inst->master && i < dim ? inst->master->dofs[dim * p->facet_nodes[I] + i] : -1;
  idx[nq] = extra_base;
  for (int e = 0; e < 4; ++e) {
    const int slot = nts_slot_of_e(inst, e);
    idx[nq + 1 + e] = slot < 0 ? -1 : extra_base + slot;
  }
}

sk_status nts_element_eval(sk_instance *inst, int k, const sk_state *state, nts_element *e) {
  const slave_point *p = &inst->points[k];
  const double *x = state->extra + inst->stride * p->index;
  nts_gather(inst, p, state->x, state->t, e->q_A);
  nts_gather(inst, p, state->x_n, state->t_n, e->q_A_start);
  nts_element_indices(inst, p, state->extra_offset + inst->stride * p->index, e->idx);
  nts_element_input *in = &e->in;
  memset(in, 0, sizeof *in);
  in->alpha = inst->alpha;
  in->q_A = e->q_A;
  in->q_A_start = e->q_A_start;
  in->active = p->active;
  if (inst->friction.mu > 0.0 && !p->return_map) in->friction_mode = p->slip ? NTS_FRICTION_SLIP : NTS_FRICTION_STICK;
  in->lambda_n = x[0];
  for (int j = 0; j < 4; ++j) {
    const int slot = nts_slot_of_e(inst, j);
    e->x_e[j] = slot < 0 ? 0.0 : x[slot];
  }
  for (int a = 0; a < 2; ++a) {
    in->f[a] = e->x_e[a];
    in->lambda_aug[a] = e->x_e[2 + a];
    in->f_start[a] = p->f_start[a];
    in->t_start[a] = p->t_start[a];
    in->f_frozen[a] = p->f_frozen[a];
    e->f_gap[a] = p->f_gap[a];
  }
  e->paper_active = 0;
  if (p->active && inst->strategy == NTS_PAPER) {
    if (nts_paper_build(&inst->facet, in, &inst->friction, &e->paper) != 0)
      return inst->api->error(inst->host, SK_ERR_DIVERGED,
                              "%s: nts-augmented: singular Gf (degenerate master face %d at slave node %lld)",
                              inst->name, p->facet, (long long)p->node);
    e->paper_active = 1;
    return SK_OK;
  }
  if (p->active && (inst->strategy == NTS_DIRECT || inst->strategy == NTS_DIRECT_ENDPOINT)) {
    const int midpoint = inst->strategy == NTS_DIRECT;
    if (nts_direct_eliminate(&inst->facet, in, &inst->friction, midpoint, e->f_gap, LOCAL_NEWTON_TOL,
                             LOCAL_NEWTON_MAX) != 0) {
      /* retry from the start of the step's closest point before giving up */
      in->f[0] = e->f_gap[0] = p->f_start[0];
      in->f[1] = e->f_gap[1] = p->f_start[1];
      if (nts_direct_eliminate(&inst->facet, in, &inst->friction, midpoint, e->f_gap, LOCAL_NEWTON_TOL,
                               LOCAL_NEWTON_MAX) != 0)
        return inst->api->error(inst->host, SK_ERR_DIVERGED,
                                "%s: nts-augmented (%s): closest-point Newton of slave node %lld on master face "
                                "%d did not converge",
                                inst->name, midpoint ? "direct" : "direct-endpoint", (long long)p->node, p->facet);
    }
  }
  nts_element_build(&inst->facet, in, &inst->friction, &e->sys);
  return SK_OK;
}

static int is_direct(const sk_instance *inst) {
  return inst->strategy == NTS_DIRECT || inst->strategy == NTS_DIRECT_ENDPOINT;
}

void nts_element_residual(const sk_instance *inst, const slave_point *p, const nts_element *e, double *R) {
  const int nq = 3 + 3 * inst->facet.nen, nu = nq + 5;
  if (e->paper_active) {
    const nts_paper_system *s = &e->paper;
    memcpy(R, s->R_q, sizeof(double) * (size_t)nq);
    R[nq] = s->phi_end[NTS_PHI_N];
    for (int a = 0; a < 2; ++a) {
      R[nq + 1 + a] = s->phi_end[a];
      R[nq + 3 + a] = e->x_e[2 + a] - s->lambda_aug[a];
    }
    return;
  }
  memcpy(R, e->sys.R, sizeof(double) * (size_t)nu);
  if (is_direct(inst) && p->active) {
    /* the global f and lambda_aug are tied to the local solution */
    for (int a = 0; a < 2; ++a) {
      R[nq + 1 + a] = e->x_e[a] - e->in.f[a];
      R[nq + 3 + a] = e->x_e[2 + a] - e->in.lambda_aug[a];
    }
  }
}

sk_status nts_element_jacobian(sk_instance *inst, const slave_point *p, nts_element *e, sk_sink *sink) {
  const int nq = 3 + 3 * inst->facet.nen, nu = nq + 5, nk = nq + 1;
  if (inst->strategy == NTS_AUGMENTED) {
    /* the whole element; a node outside this loop's system is inactive: identity rows, all eliminated */
    if (p->in_system) sink->add_matrix(sink, nu, e->idx, nu, e->idx, e->sys.J);
    return SK_OK;
  }
  if (!p->active) { /* lambda_n = 0 kept; f and lambda_aug eliminated with their identity rows */
    const double one = 1.0;
    sink->add_matrix(sink, 1, e->idx + nq, 1, e->idx + nq, &one);
    return SK_OK;
  }
  double Jc[NTS_MAX_NK * NTS_MAX_NK], rhs[NTS_MAX_NK];
  if (e->paper_active) {
    nts_paper_condensed(&e->paper, Jc, rhs);
  } else if (nts_condense(&e->sys, Jc, rhs) != 0) {
    return inst->api->error(inst->host, SK_ERR_DIVERGED,
                            "%s: nts-augmented: singular augmented block (degenerate master face %d at slave node "
                            "%lld)", inst->name, p->facet, (long long)p->node);
  }
  /* idx[0..nk) are the kept unknowns q_A, lambda_n; under `direct*` R_e = 0 so rhs vanishes */
  sink->add_matrix(sink, nk, e->idx, nk, e->idx, Jc);
  sink->add_rhs(sink, nk, e->idx, rhs);
  return SK_OK;
}

/* `paper-reduced`: lambda_aug = (52) at the point the solve leads to (full Newton step), so that its rows vanish. */
static sk_status paper_lambda_aug(sk_instance *inst, const slave_point *p, const nts_element *e, const double *dk,
                                  const double df[2], double dlambda_n, double lambda_aug[2]) {
  const int nq = 3 + 3 * inst->facet.nen;
  double q[NTS_MAX_NQ];
  nts_element_input in = e->in;
  for (int i = 0; i < nq; ++i) q[i] = e->q_A[i] + dk[i];
  in.q_A = q;
  for (int a = 0; a < 2; ++a) in.f[a] += df[a];
  in.lambda_n += dlambda_n;
  nts_paper_system next;
  if (nts_paper_build(&inst->facet, &in, &inst->friction, &next) != 0)
    return inst->api->error(inst->host, SK_ERR_DIVERGED, "%s: nts-augmented: singular Gf at slave node %lld",
                            inst->name, (long long)p->node);
  lambda_aug[0] = next.lambda_aug[0];
  lambda_aug[1] = next.lambda_aug[1];
  return SK_OK;
}

sk_status nts_element_recover(sk_instance *inst, const slave_point *p, nts_element *e, const sk_state *state,
                              sk_vectors *v) {
  (void)state;
  const int nq = 3 + 3 * inst->facet.nen, nk = nq + 1, dim = inst->dim;
  const double *F = v->F_extra + inst->stride * p->index;
  double *dx = v->dx_extra + inst->stride * p->index;
  if (!p->active) { /* identity rows */
    for (int j = 1; j < inst->stride; ++j) dx[j] = -F[j];
    return SK_OK;
  }
  /* the kept unknowns of the element: slave node, facet nodes (none for a rigid facet), lambda_n */
  double dk[NTS_MAX_NK] = {0}, de[4];
  for (int i = 0; i < dim; ++i) dk[i] = v->dx_view[0][dim * p->k + i];
  if (inst->master)
    for (int I = 0; I < inst->facet.nen; ++I)
      for (int i = 0; i < dim; ++i) dk[3 * (1 + I) + i] = v->dx_view[1][dim * p->facet_nodes[I] + i];
  dk[nq] = dx[0];
  if (e->paper_active) {
    const double phi_aug[2] = {F[nts_slot_of_e(inst, 0)], inst->pdim == 2 ? F[2] : 0.0};
    double df[2], lambda_aug[2];
    nts_paper_recover(&e->paper, dk, phi_aug, df);
    SK_TRY(paper_lambda_aug(inst, p, e, dk, df, dk[nq], lambda_aug));
    de[0] = df[0];
    de[1] = df[1];
    de[2] = lambda_aug[0] - e->x_e[2];
    de[3] = lambda_aug[1] - e->x_e[3];
  } else {
    const int direct = is_direct(inst);
    /* the element rows' residual as the host has it; under `direct*` the local solution's linearisation plus the
     * global unknowns' offset from it */
    for (int j = 0; j < 4; ++j) {
      const int slot = nts_slot_of_e(inst, j);
      e->sys.R[nk + j] = direct || slot < 0 ? 0.0 : F[slot];
    }
    if (nts_recover(&e->sys, dk, de) != 0)
      return inst->api->error(inst->host, SK_ERR_DIVERGED, "%s: nts-augmented: singular augmented block at slave "
                              "node %lld", inst->name, (long long)p->node);
    if (direct) {
      const double local[4] = {e->in.f[0], e->in.f[1], e->in.lambda_aug[0], e->in.lambda_aug[1]};
      for (int j = 0; j < 4; ++j) de[j] -= e->x_e[j] - local[j];
    }
  }
  for (int j = 0; j < 4; ++j) {
    const int slot = nts_slot_of_e(inst, j);
    if (slot >= 0) dx[slot] = de[j];
  }
  return SK_OK;
}

void nts_element_slave_force(const sk_instance *inst, const nts_element *e, double force[3]) {
  (void)inst;
  const double *R = e->paper_active ? e->paper.R_q : e->sys.R;
  for (int i = 0; i < 3; ++i) force[i] = -R[i];
}

void nts_element_traction(const sk_instance *inst, const nts_element *e, double traction[3]) {
  if (e->in.alpha == 1.0) { /* t_used is t_{n+1}: the tangential part of the step's force */
    const nts_geometry *gh = nts_element_geometry(e, 1);
    nts_element_slave_force(inst, e, traction);
    for (int i = 0; i < 3; ++i) traction[i] += e->in.lambda_n * gh->n[i];
    return;
  }
  /* t_{n+1} as the vector t^a a_a at y_hat, whose length is the one the return map bounds by mu |lambda_n| (the
   * step's force maps t_used through Gf, which differs from the metric where Phi_aug is not zero, as at y_hat); the
   * force on the slave is minus it */
  nts_traction_vector(nts_element_geometry(e, 1), nts_element_friction(e)->t_next, traction);
  for (int i = 0; i < 3; ++i) traction[i] = -traction[i];
}

const double *nts_element_constraints(const nts_element *e) {
  return e->paper_active ? e->paper.phi_end : e->sys.phi;
}

const nts_friction *nts_element_friction(const nts_element *e) {
  return e->paper_active ? &e->paper.friction : &e->sys.friction;
}

const nts_geometry *nts_element_geometry(const nts_element *e, int at_hat) {
  if (e->paper_active) return at_hat ? &e->paper.geo_hat : &e->paper.geo_end;
  return at_hat ? &e->sys.geo_hat : &e->sys.geo_end;
}
