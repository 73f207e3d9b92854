/* nts-augmented glue: the history of a step (commit, reject), the results (report, the points of contact.csv) and
 * checkpoints (stickslip.checkpoint.v1: the committed history of each slave node). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "glue.h"
#include "records.h"

sk_status nts_commit_step(sk_instance *inst, const sk_state *state) {
  for (int k = 0; k < inst->n_points; ++k) {
    slave_point *p = &inst->points[k];
    const double *x = state->extra + inst->stride * p->index;
    p->c_facet = p->facet;
    p->c_active = p->facet >= 0 && p->active;
    p->c_slip = p->c_active && p->slip;
    memcpy(p->c_extra, x, sizeof(double) * (size_t)inst->stride);
    memset(p->c_t, 0, sizeof p->c_t);
    memset(p->c_t_vector, 0, sizeof p->c_t_vector);
    memset(p->slip_increment, 0, sizeof p->slip_increment);
    if (!p->c_active) {
      p->c_f[0] = p->f_frozen[0];
      p->c_f[1] = p->f_frozen[1];
      continue;
    }
    nts_element e;
    SK_TRY(nts_element_eval(inst, k, state, &e));
    if (e.in.lambda_n > 0.0)
      inst->api->log(inst->host, 2, "%s: nts-augmented: slave node %lld ends the step active with a tensile "
                     "multiplier %g", inst->name, (long long)p->node, e.in.lambda_n);
    const nts_friction *fr = nts_element_friction(&e);
    p->c_slip = fr->slip;
    /* f at t_{n+1}: the unknown, or under `direct` (74) the closest point of q_{n+1} (f there is 2 xi_{n+1/2} - xi_n,
     * which is no closest point) */
    const double *f = e.in.f_gap ? e.in.f_gap : e.in.f;
    const double *lambda_aug = e.paper_active ? e.paper.lambda_aug : e.in.lambda_aug;
    for (int a = 0; a < 2; ++a) {
      p->c_f[a] = f[a];
      p->c_t[a] = fr->t_next[a];
      const int fs = nts_slot_of_e(inst, a), ls = nts_slot_of_e(inst, 2 + a);
      if (fs >= 0) p->c_extra[fs] = f[a];
      if (ls >= 0) p->c_extra[ls] = lambda_aug[a];
    }
    /* spatial traction t = t_a a^a at t_{n+1} */
    nts_geometry g;
    nts_geometry_eval(&inst->facet, e.q_A, f, &g);
    nts_traction_vector(&g, p->c_t, p->c_t_vector);
    if (inst->friction.mu > 0.0) { /* the slave's closest point moved on the facet by f - f_start */
      double length = 0.0;
      for (int i = 0; i < 3; ++i) {
        p->slip_increment[i] = (f[0] - p->f_start[0]) * g.a[0][i] + (f[1] - p->f_start[1]) * g.a[1][i];
        length += p->slip_increment[i] * p->slip_increment[i];
      }
      p->slip_length += sqrt(length);
    }
  }
  return SK_OK;
}

void nts_reject_step(sk_instance *inst) {
  /* begin_step rebuilds everything of the step from the committed data; only forget this attempt's state */
  for (int k = 0; k < inst->n_points; ++k) {
    slave_point *p = &inst->points[k];
    p->active = p->slip = p->return_map = p->flips = p->wants_in = 0;
  }
}

/* 1 stick (or in contact without friction), 2 slip. */
static int point_state(const sk_instance *inst, const nts_friction *fr) {
  return inst->friction.mu > 0.0 && fr->slip ? 2 : 1;
}

/* Tangential penalty energy psi = t . m^{-1} t / (2 eps). */
static double friction_energy(const double m[2][2], const double t[2], double eps) {
  const double det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
  const double tau0 = (m[1][1] * t[0] - m[0][1] * t[1]) / det, tau1 = (-m[1][0] * t[0] + m[0][0] * t[1]) / det;
  return 0.5 * (tau0 * t[0] + tau1 * t[1]) / eps;
}

sk_status nts_report(sk_instance *inst, const sk_state *state, sk_contact_report *rep) {
  for (int k = 0; k < inst->n_points; ++k) {
    const slave_point *p = &inst->points[k];
    if (p->facet < 0 || !p->active || !nts_owned(inst, p)) continue;
    nts_element e;
    SK_TRY(nts_element_eval(inst, k, state, &e));
    /* the step's force: under the midpoint scheme its friction part is the mean of the tractions at t_n and t_{n+1}
     * (contact.csv reports the one at t_{n+1}; docs/plugins/nts-augmented.md, "Report") */
    double force[3];
    nts_element_slave_force(inst, &e, force);
    for (int i = 0; i < 3; ++i) rep->force[i] += force[i];
    const double *x = e.q_A;
    rep->moment[0] += x[1] * force[2] - x[2] * force[1];
    rep->moment[1] += x[2] * force[0] - x[0] * force[2];
    rep->moment[2] += x[0] * force[1] - x[1] * force[0];
    ++rep->active;
    const nts_friction *fr = nts_element_friction(&e);
    if (inst->friction.mu > 0.0) { /* frictionless points are neither stuck nor slipping */
      if (point_state(inst, fr) == 2)
        ++rep->slip;
      else
        ++rep->stick;
    }
    if (inst->friction.mu > 0.0) {
      /* work of the tangential traction minus the change of the penalty energy */
      const nts_geometry *gh = nts_element_geometry(&e, 1);
      const double work = fr->t_used[0] * (e.in.f[0] - p->f_start[0]) + fr->t_used[1] * (e.in.f[1] - p->f_start[1]);
      rep->dissipated += work - (friction_energy(gh->m, fr->t_next, inst->friction.epsilon_t) -
                                 friction_energy(gh->m, p->t_start, inst->friction.epsilon_t));
    }
    /* the normal gap (a length, as every plugin reports it); the closest-point conditions Phi_aug are not */
    rep->constraint_norm = fmax(rep->constraint_norm, fabs(nts_element_constraints(&e)[NTS_PHI_N]));
  }
  return SK_OK;
}

sk_status nts_points(sk_instance *inst, const sk_state *state, sk_point_callback callback, void *ctx) {
  for (int k = 0; k < inst->n_points; ++k) {
    const slave_point *p = &inst->points[k];
    if (!nts_owned(inst, p)) continue;
    sk_contact_point cp = {.struct_size = sizeof cp};
    cp.slave_node = p->node;
    cp.forces = 1; /* lambda_n is the node's force: the host divides by the node's tributary measure */
    cp.has_slip = inst->friction.mu > 0.0;
    memcpy(cp.slip_increment, p->slip_increment, sizeof cp.slip_increment);
    cp.slip = p->slip_length;
    for (int i = 0; i < inst->dim; ++i) cp.x[i] = state->x[0][inst->dim * p->k + i];
    /* NaN when no facet is within reach (or none searched yet: the initial output), as every plugin reports it */
    cp.gap = p->facet >= 0 ? p->gap_estimate : NAN;
    if (p->facet >= 0 && state->extra) {
      nts_element e;
      SK_TRY(nts_element_eval(inst, k, state, &e));
      /* an active point's normal is the one lambda_n acts along: the facet's at y_hat (the end's but under the
       * midpoint scheme), so that the points' normal forces sum to the normal part of history.csv's force */
      const nts_geometry *gh = nts_element_geometry(&e, 1), *ge = nts_element_geometry(&e, 0);
      for (int i = 0; i < 3; ++i) cp.normal[i] = p->active ? gh->n[i] : ge->n[i];
      cp.has_multiplier = 1; /* lambda_n, 0 for an inactive point */
      if (p->active) {
        cp.gap = nts_element_constraints(&e)[NTS_PHI_N];
        cp.pressure = -e.in.lambda_n;
        cp.multiplier = e.in.lambda_n;
        /* the tangential force at t_{n+1}, the pair of lambda_n in the friction law */
        nts_element_traction(inst, &e, cp.traction);
        cp.state = point_state(inst, nts_element_friction(&e));
      } else {
        double f[2] = {p->f_frozen[0], p->f_frozen[1]};
        const double g = nts_gap_on_facet(inst, p, state->x, state->t, f);
        if (g != HUGE_VAL) cp.gap = g;
      }
    }
    callback(ctx, &cp);
  }
  return SK_OK;
}

/* ---- checkpoints (stickslip.checkpoint.v1): the committed history of each slave node ---------------------------- */

/* What commit_step keeps of a node, with its facet as the master's whole cell index. */
typedef struct {
  int32_t facet, active, slip, pad;
  double f[2], t[2], t_vector[3], extra[NTS_MAX_STRIDE];
  double slip_length; /* the slip accumulated (contact.csv's `slip`) */
} saved_point;

static sk_status save_state(sk_instance *inst, const sk_state *state, sk_record_writer *writer) {
  (void)state;
  for (int k = 0; k < inst->n_points; ++k) {
    const slave_point *p = &inst->points[k];
    if (!nts_owned(inst, p)) continue;
    saved_point r = {.facet = p->c_facet, .active = p->c_active, .slip = p->c_slip, .slip_length = p->slip_length};
    if (inst->master && p->c_facet >= 0) r.facet = (int32_t)inst->master->cell_index[p->c_facet];
    memcpy(r.f, p->c_f, sizeof r.f);
    memcpy(r.t, p->c_t, sizeof r.t);
    memcpy(r.t_vector, p->c_t_vector, sizeof r.t_vector);
    memcpy(r.extra, p->c_extra, sizeof r.extra);
    writer->put(writer, p->index, &r, (uint32_t)sizeof r);
  }
  return SK_OK;
}

/* Every point this rank holds (owned and ghost: commit_step keeps both). */
static sk_status load_state(sk_instance *inst, const sk_state *state, const sk_record_reader *reader) {
  (void)state;
  int *cells = inst->master ? records_cells_of_view(inst->master) : NULL;
  if (inst->master && !cells) return inst->api->error(inst->host, SK_ERR_NOMEM, "nts-augmented: out of memory");
  sk_status status = SK_OK;
  for (int k = 0; k < inst->n_points && status == SK_OK; ++k) {
    slave_point *p = &inst->points[k];
    saved_point r;
    const int64_t got = reader->get(reader, p->index, &r, (uint32_t)sizeof r);
    if (got != (int64_t)sizeof r) {
      status = inst->api->error(inst->host, SK_ERR_INPUT, "nts-augmented: slave node %lld: %s", (long long)p->node,
                                got < 0 ? "no history in the checkpoint" : "a history record of another size");
      break;
    }
    int facet = r.facet;
    if (inst->master && facet >= 0 && (facet = records_view_cell(cells, inst->master, facet)) < 0)
      status = inst->api->error(inst->host, SK_ERR_INPUT, "nts-augmented: slave node %lld: its facet is a master face "
                                "this rank does not hold", (long long)p->node);
    p->c_facet = facet;
    p->c_active = r.active;
    p->c_slip = r.slip;
    p->slip_length = r.slip_length;
    memcpy(p->c_f, r.f, sizeof r.f);
    memcpy(p->c_t, r.t, sizeof r.t);
    memcpy(p->c_t_vector, r.t_vector, sizeof r.t_vector);
    memcpy(p->c_extra, r.extra, sizeof r.extra);
  }
  free(cells);
  return status;
}

const sk_checkpoint_ext nts_checkpoint = {SK_TABLE_HEADER(sk_checkpoint_ext), .save = save_state,
                                         .load = load_state};
