/* corotational — the body instance's calls in a step: the attempt (loads, predictor), layout, pattern, the active
 * set, the rows and their Jacobian (world.c), the rotation Newton in recover (solve_again), commit and results. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "glue.h"

/* corot_world_begin for this attempt (once per (t_n, dt)), with the loads at t^{n+1/2}, and the predictor in y. */
static sk_status ensure_attempt(sk_instance *inst, const sk_state *state) {
  glue_body *b = inst->body;
  SK_TRY(glue_ensure_started(inst, state));
  if (!b->contact_ready) SK_TRY(glue_build_contact(inst));
  if (b->step_t_n == state->t_n && b->step_dt == state->dt && state->step > 0) return SK_OK;
  const int n = b->body.n;
  memset(b->f_world, 0, sizeof(double) * (size_t)n);
  SK_TRY(b->bulk->external_force(inst->host, state->t_n + 0.5 * state->dt, b->f_world));
  double load = 0.0;
  for (int i = 0; i < n; ++i) load = fmax(load, fabs(b->f_world[i]));
  corot_world_begin(&b->world, &b->state, state->dt, load > 0.0 ? b->f_world : NULL);
  corot_world_predict(&b->world, b->y);
  b->step_t_n = state->t_n;
  b->step_dt = state->dt;
  b->rotation_updates = 0;
  b->rejections = 0;
  /* g's row in F: g / g_ref times a typical nodal inertial force a (m / nodes) omega_ref L, so that its round-off
   * floor (|g| ~ 1e-12 g_ref, where w is known to its last bits) sits at the body rows' (~1e-7 of ~1e5 for the
   * 6.3 ball): a row scaled as a torque / L stayed at 1.7e-5 there and kept NOX from converging. omega_ref cancels
   * (g_ref = c I_e omega_ref), which keeps the scale finite for a body at rest (omega_ref = 0) */
  b->g_scale = b->world.a * (b->body.mass_total / b->body.n_nodes) * b->l_scale /
               ((b->model == COROT_MODEL_1 ? b->world.a : 0.5 * state->dt) * b->body.inertia);
  return SK_OK;
}

sk_status glue_predict(sk_instance *inst, const sk_state *state, double *u) {
  SK_TRY(ensure_attempt(inst, state));
  const glue_body *b = inst->body;
  for (int i = 0; i < b->body.n; ++i) u[i] = b->y[i] - b->view->X[i];
  return SK_OK;
}

sk_status glue_begin_step(sk_instance *inst, const sk_state *state) {
  SK_TRY(ensure_attempt(inst, state));
  glue_body *b = inst->body;
  for (int k = 0; k < b->n_pairs; ++k) {
    double d0[3], d1[3];
    inst->api->contact->obstacle_displacement(b->pairs[k].obstacle, state->t_n, d0);
    inst->api->contact->obstacle_displacement(b->pairs[k].obstacle, state->t, d1);
    if (corot_dot(3, d0, d0) + corot_dot(3, d1, d1) > 0.0)
      return inst->api->error(b->pairs[k].instance->host, SK_ERR_INPUT,
                              "a moving obstacle: the corotational plugin supports planes at rest");
  }
  return SK_OK;
}

/* ---- one step: layout, pattern, sets, rows, Jacobian, the rotation Newton in recover ----------------------------- */

sk_status glue_layout(sk_instance *inst, const sk_state *state, sk_layout *out) {
  SK_TRY(ensure_attempt(inst, state));
  glue_body *b = inst->body;
  const int n = b->body.n, dim = b->body.dim;
  b->initial[0] = b->world.w;
  b->eliminated[0] = !b->monolithic; /* nested: the plugin's own Newton on w in recover() */
  memcpy(b->initial + 1, b->y + n, sizeof(double) * (size_t)(b->n_extra - 1));
  out->n_extra = b->n_extra;
  out->initial = b->initial;
  out->eliminated = b->eliminated;
  if (SK_HAS(out, recover_needs_jdx)) out->recover_needs_jdx = 0;
  if (!b->dual || b->contact.n == 0) return SK_OK;
  /* dual: lambda_p paired with its node's rows, whose lambda block R_m D_pp is invertible */
  const int nc = b->contact.n, first = 1 + b->world.n_border;
  int64_t *extra_index = malloc(sizeof(int64_t) * (size_t)(nc * dim)), *rows = malloc(sizeof(int64_t) * (size_t)(nc * dim));
  sk_status status = extra_index && rows ? SK_OK : glue_nomem(inst);
  for (int p = 0; p < nc && status == SK_OK; ++p)
    for (int i = 0; i < dim; ++i) {
      extra_index[p * dim + i] = first + p * dim + i;
      rows[p * dim + i] = b->view->dofs[b->contact.node[p] * dim + i];
    }
  if (status == SK_OK) status = b->condense->pair(inst->host, nc, dim, extra_index, rows);
  free(extra_index);
  free(rows);
  return status;
}

sk_status glue_pattern(sk_instance *inst, const sk_state *state, sk_pattern *pat) {
  glue_body *b = inst->body;
  const int n = b->body.n, dim = b->body.dim, nb = b->world.n_border;
  int64_t border[3], lambda[3];
  for (int j = 0; j < nb; ++j) border[j] = state->extra_offset + 1 + j;
  pat->add_block(pat, nb, border, n, b->view->dofs);
  pat->add_block(pat, n, b->view->dofs, nb, border);
  pat->add_block(pat, nb, border, nb, border);
  if (b->monolithic) { /* w's row and column against every unknown of the body */
    const int64_t w = state->extra_offset;
    pat->add_block(pat, 1, &w, n, b->view->dofs);
    pat->add_block(pat, n, b->view->dofs, 1, &w);
    for (int64_t j = 0; j < b->n_extra; ++j) {
      const int64_t e = state->extra_offset + j;
      pat->add_block(pat, 1, &w, 1, &e);
      pat->add_block(pat, 1, &e, 1, &w);
    }
  }
  for (int p = 0; p < b->contact.n; ++p) {
    const int64_t *node = b->view->dofs + b->contact.node[p] * dim;
    for (int i = 0; i < dim; ++i) lambda[i] = state->extra_offset + 1 + nb + p * dim + i;
    pat->add_block(pat, dim, node, dim, lambda);
    pat->add_block(pat, dim, lambda, dim, node);
    pat->add_block(pat, dim, lambda, dim, lambda);
    pat->add_block(pat, dim, lambda, nb, border);
  }
  return SK_OK;
}

/* y = [x | extras after w] from the host's state; w = extra[0]. */
static void load_iterate(glue_body *b, const sk_state *state) {
  const int n = b->body.n;
  memcpy(b->y, state->x[0], sizeof(double) * (size_t)n);
  memcpy(b->y + n, state->extra + 1, sizeof(double) * (size_t)(b->n_extra - 1));
  if (state->extra[0] != b->world.w) corot_world_set_w(&b->world, state->extra[0]);
}

sk_status glue_update_active_set(sk_instance *inst, const sk_state *state, int *changed) {
  glue_body *b = inst->body;
  load_iterate(b, state);
  if (!b->world.contact) return SK_OK;
  *changed = corot_world_propose_sets(&b->world, b->y) > 0;
  corot_contact_apply(&b->contact);
  return SK_OK;
}

sk_status glue_residual(sk_instance *inst, const sk_state *state, sk_sink *sink) {
  glue_body *b = inst->body;
  load_iterate(b, state);
  const int n = b->body.n, ne = (int)b->n_extra;
  double g;
  corot_world_residual(&b->world, b->y, b->F, &g);
  sink->add_vector(sink, n, b->view->dofs, b->F);
  for (int j = 0; j < ne; ++j) b->index[j] = state->extra_offset + j;
  b->block[0] = g * b->g_scale;
  memcpy(b->block + 1, b->F + n, sizeof(double) * (size_t)(ne - 1));
  sink->add_vector(sink, ne, b->index, b->block);
  return SK_OK;
}

sk_status glue_jacobian(sk_instance *inst, const sk_state *state, sk_sink *sink) {
  glue_body *b = inst->body;
  load_iterate(b, state);
  const corot_body *body = &b->body;
  const int n = body->n, dim = body->dim, dd = dim * dim, nb = b->world.n_border;
  const corot_world_jacobian *J = &b->J;
  corot_world_jacobian_eval(&b->world, b->y, &b->J);
  const int64_t *dofs = b->view->dofs;
  for (int a = 0; a < body->n_nodes; ++a)
    for (int64_t k = body->row_ptr[a]; k < body->row_ptr[a + 1]; ++k)
      sink->add_matrix(sink, dim, dofs + a * dim, dim, dofs + body->cols[k] * dim, J->blocks + k * dd);
  int64_t border[3], lambda[3];
  for (int j = 0; j < nb; ++j) {
    border[j] = state->extra_offset + 1 + j;
    sink->add_matrix(sink, n, dofs, 1, &border[j], J->col[j]);
    sink->add_matrix(sink, 1, &border[j], n, dofs, J->row[j]);
  }
  sink->add_matrix(sink, nb, border, nb, border, J->corner);
  for (int p = 0; p < b->contact.n; ++p) {
    const int64_t *node = dofs + b->contact.node[p] * dim;
    double LB[9];
    for (int i = 0; i < dim; ++i) {
      lambda[i] = state->extra_offset + 1 + nb + p * dim + i;
      for (int j = 0; j < nb; ++j) LB[i * nb + j] = J->lambda_border[p * 9 + i * 3 + j];
    }
    sink->add_matrix(sink, dim, node, dim, lambda, J->body_lambda + p * dd);
    sink->add_matrix(sink, dim, lambda, dim, node, J->lambda_x + p * dd);
    sink->add_matrix(sink, dim, lambda, dim, lambda, J->lambda_lambda + p * dd);
    sink->add_matrix(sink, dim, lambda, nb, border, LB);
  }
  if (b->monolithic) { /* w kept: its column dF/dw and its row g_scale dg/dy, g_scale dg/dw (world.c) */
    double g_w;
    corot_world_dw(&b->world, b->y, b->dF, b->dgy, &g_w);
    const int64_t w = state->extra_offset, ne = b->n_extra;
    sink->add_matrix(sink, n, dofs, 1, &w, b->dF);
    for (int64_t j = 1; j < ne; ++j) b->index[j - 1] = w + j;
    sink->add_matrix(sink, (int)(ne - 1), b->index, 1, &w, b->dF + n);
    for (int i = 0; i < n; ++i) b->block[i] = b->g_scale * b->dgy[i];
    sink->add_matrix(sink, 1, &w, n, dofs, b->block);
    for (int64_t j = 1; j < ne; ++j) b->block[j - 1] = b->g_scale * b->dgy[n + j - 1];
    sink->add_matrix(sink, 1, &w, (int)(ne - 1), b->index, b->block);
    const double ww = b->g_scale * g_w;
    sink->add_matrix(sink, 1, &w, 1, &w, &ww);
  }
  return SK_OK;
}

/* The host solved J dy1 = -F with w frozen (w is eliminated). The Newton step of the whole system would be
 *   dw = (-g - g_y . dy1) / (g_w - g_y . dy2),  J dy2 = dF/dw   (bordered elimination, Sec. 5.3)
 * with the second solve reusing the factorisation. The host applies dy1 (the exact solve at the frozen w); w moves
 * by dw: the paper's outer Newton on w with s solved for the current w. */
sk_status glue_recover(sk_instance *inst, const sk_state *state, sk_vectors *vectors) {
  glue_body *b = inst->body;
  if (b->monolithic) return SK_OK; /* w was solved with the rest */
  load_iterate(b, state);
  const int n = b->body.n, N = b->world.N;
  const double g = vectors->F_extra[0] / b->g_scale;
  double g_w;
  corot_world_dw(&b->world, b->y, b->dF, b->dgy, &g_w);
  const double *dx = vectors->dx_view[0], *dxe = vectors->dx_extra + 1;
  const double a1 = corot_dot(n, b->dgy, dx) + corot_dot(N - n, b->dgy + n, dxe);
  /* g after the host's update at the frozen w, to first order: within the tolerance, w is converged (Sec. 5.3's
   * test) and neither the second solve nor a w update (which at round-off only jitters w) is needed */
  if (fabs(g + a1) <= b->tolerance * corot_world_g_ref(&b->world)) {
    vectors->dx_extra[0] = 0.0;
    return SK_OK;
  }
  b->rhs_extra[0] = 0.0;
  memcpy(b->rhs_extra + 1, b->dF + n, sizeof(double) * (size_t)(N - n));
  const double *rhs_view[1] = {b->dF};
  double *y2_view[1] = {b->y2_view};
  SK_TRY(b->linear->solve_again(inst->host, rhs_view, b->rhs_extra, y2_view, b->y2_extra));
  const double a2 = corot_dot(n, b->dgy, b->y2_view) + corot_dot(N - n, b->dgy + n, b->y2_extra + 1);
  const double denominator = g_w - a2;
  if (!(fabs(denominator) > 0.0) || !isfinite(denominator))
    return inst->api->error(inst->host, SK_ERR_DIVERGED, "the rotation equation lost its derivative (g' = %g)",
                            denominator);
  vectors->dx_extra[0] = (-g - a1) / denominator;
  b->rotation_updates++;
  return SK_OK;
}

/* NOX stopped: accept only a rotation equation within the plugin's tolerance (the energy identity of Model 1 needs
 * it, §4). A rejection makes the host run Newton again from here, and its update test forces one iteration, whose
 * recover updates w. After three rejections the round-off floor of stiff steps (up to 6.5e-12, step.c) is
 * accepted up to COROT_ROUNDOFF_FACTOR times the tolerance. */
sk_status glue_converged(sk_instance *inst, const sk_state *state, int *accept) {
  glue_body *b = inst->body;
  load_iterate(b, state);
  double g;
  corot_world_residual(&b->world, b->y, b->F, &g);
  const double limit = b->tolerance * corot_world_g_ref(&b->world);
  *accept = fabs(g) <= limit || (b->rejections >= 3 && fabs(g) <= COROT_ROUNDOFF_FACTOR * limit);
  if (!*accept && b->rejections >= 3)
    return inst->api->error(inst->host, SK_ERR_DIVERGED, "the rotation equation stays at |g| = %.3g g_ref",
                            fabs(g) / corot_world_g_ref(&b->world));
  b->rejections += !*accept;
  return SK_OK;
}

sk_status glue_velocity(sk_instance *inst, const sk_state *state, double *v) {
  glue_body *b = inst->body;
  load_iterate(b, state);
  corot_world_kinematics(&b->world, b->y);
  const int dim = b->body.dim;
  for (int a = 0; a < b->body.n_nodes; ++a) {
    double s1[3];
    for (int i = 0; i < dim; ++i) s1[i] = 2.0 * b->world.s[a * dim + i] - b->state.s[a * dim + i];
    corot_mul(dim, b->world.R1, s1, v + a * dim);
  }
  return SK_OK;
}

/* The energy the scheme conserves (Lemma 2.1): 1/2 s.Ms + 1/2 u.Su of the committed state, or of the initial state
 * (which the first row of history.csv asks for before any step). The host's SVK energy of the world displacement is
 * another number: not the linear co-rotated strain energy (docs/plugins/corotational.md §8.3). */
sk_status glue_energy(sk_instance *inst, const sk_state *state, double *kinetic, double *strain) {
  const glue_body *b = inst->body;
  if (state->step == 0) SK_TRY(glue_ensure_started(inst, state));
  *kinetic = b->energy[0];
  *strain = b->energy[1];
  return SK_OK;
}

sk_status glue_commit_step(sk_instance *inst, const sk_state *state) {
  glue_body *b = inst->body;
  load_iterate(b, state);
  corot_world *cw = &b->world;
  double g;
  corot_world_residual(cw, b->y, b->F, &g); /* kinematics and g of the converged point */
  const int dim = b->body.dim, n = b->body.n;
  const double *lambda = b->y + n + cw->n_border;
  /* the friction work of the step, dt D_pp s_T . lambda_T (history.csv's dissipated_energy is friction work for every
   * plugin): the normal part s_n lambda_n vanishes with the complementarity the scheme enforces (to round-off; it
   * made a frictionless run report 1.8e-7 of dissipation on E 5.3e5) */
  for (int p = 0; p < b->contact.n; ++p) {
    const double *sp = cw->s + b->contact.node[p] * dim, *lp = lambda + p * dim, *nu = b->contact.frame + 9 * p;
    const double tangential = corot_dot(dim, sp, lp) - corot_dot(dim, nu, sp) * corot_dot(dim, nu, lp);
    b->work_node[p] = cw->dt * b->contact.weight[p] * tangential;
  }
  /* the slip of the step: dt times the tangential part of the midpoint velocity s_p against the plane, in the world */
  for (int p = 0; p < b->contact.n; ++p) {
    double *slip = b->slip_increment + 3 * p, sT[3] = {0, 0, 0};
    memset(slip, 0, 3 * sizeof *slip);
    if (b->contact.set[p] == COROT_INACTIVE || corot_contact_mu(&b->contact, p) <= 0.0) continue;
    const double *sp = cw->s + b->contact.node[p] * dim, *nu = b->contact.frame + 9 * p;
    const double sn = corot_dot(dim, nu, sp);
    for (int i = 0; i < dim; ++i) sT[i] = cw->dt * (sp[i] - sn * nu[i]);
    corot_mul(dim, cw->Rm, sT, slip);
    b->slip_length[p] += sqrt(corot_dot(dim, slip, slip));
  }
  memcpy(b->Rm, cw->Rm, sizeof b->Rm);
  double impulse, defect;
  corot_world_momentum_balance(cw, b->y, &impulse, &defect);
  const double work = corot_world_commit(cw, b->y, &b->next);
  corot_state t = b->state;
  b->state = b->next;
  b->next = t;
  SK_TRY(glue_publish_state(inst));
  /* the scheme's record of the step (--verbose): its energy and angular momentum with the terms of their discrete
   * balances (Lemmas 2.1, 2.2: E^{n+1} - E^n = -friction, J^{n+1} - J^n = impulse + defect), and the world centre
   * of mass X_c + R_theta T(u) */
  const double J = corot_angular_momentum(&b->body, b->model, b->state.u, b->state.s, b->F);
  double T[3] = {0, 0, 0}, centre[3] = {0, 0, 0}, R[9];
  corot_mean(&b->body, b->state.u, T);
  corot_rotation(b->body.dim, b->body.e, b->state.theta, R);
  corot_mul(b->body.dim, R, T, centre);
  for (int i = 0; i < 3; ++i) centre[i] += b->body.centre[i];
  inst->api->log(inst->host, 2,
                 "corotational: step %lld t %.9g theta %.17g w %.17g E %.17e J %.17e friction %.17e g/g_ref %.2e "
                 "w-updates %d impulse %.17e defect %.17e centre %.17g %.17g %.17g",
                 (long long)state->step, state->t, b->state.theta, b->state.w, b->energy[0] + b->energy[1], J, work,
                 g / corot_world_g_ref(cw), b->rotation_updates, impulse, defect, centre[0], centre[1], centre[2]);
  return SK_OK;
}

/* ---- results -------------------------------------------------------------------------------------------------------- */

sk_status glue_report(sk_instance *inst, const sk_state *state, sk_contact_report *out) {
  if (inst->kind == SK_KIND_BODY) /* the initial row: start from the scene's velocities if the host gives them */
    return state->step == 0 && state->v_n && state->v_n[0] ? glue_ensure_started(inst, state) : SK_OK;
  const glue_body *b = inst->body;
  if (state->step == 0 || !b->contact_ready) return SK_OK;
  const corot_contact *c = &b->contact;
  const int dim = b->body.dim;
  for (int p = 0; p < c->n; ++p) {
    if (c->plane[p] != inst->pair_index || c->set[p] == COROT_INACTIVE) continue;
    double f[3] = {0, 0, 0}, x[3] = {0, 0, 0}, l[3];
    for (int i = 0; i < dim; ++i) l[i] = -c->weight[p] * c->lambda[3 * p + i];
    corot_mul(dim, b->Rm, l, f); /* the force on the body: -R_m D_pp lambda_p */
    const int a = c->node[p];
    for (int i = 0; i < dim; ++i) x[i] = b->view->X[a * dim + i] + b->q[a * dim + i];
    for (int i = 0; i < 3; ++i) out->force[i] += f[i];
    out->moment[0] += x[1] * f[2] - x[2] * f[1];
    out->moment[1] += x[2] * f[0] - x[0] * f[2];
    out->moment[2] += x[0] * f[1] - x[1] * f[0];
    out->active++;
    out->stick += c->set[p] == COROT_STICK && corot_contact_mu(c, p) > 0.0;
    out->slip += c->set[p] == COROT_SLIP && corot_contact_mu(c, p) > 0.0;
    out->dissipated += b->work_node[p];
    const corot_plane *pl = &c->planes[inst->pair_index];
    double gap = 0.0;
    for (int i = 0; i < dim; ++i) gap += (x[i] - pl->point[i]) * pl->normal[i];
    out->constraint_norm = fmax(out->constraint_norm, -gap); /* penetration: (3.5) allows O(|s| dt) */
  }
  return SK_OK;
}

sk_status glue_points(sk_instance *inst, const sk_state *state, sk_point_callback callback, void *ctx) {
  const glue_body *b = inst->body;
  const glue_pair *pair = &b->pairs[inst->pair_index];
  const sk_view *slave = pair->slave;
  const corot_contact *c = &b->contact;
  /* before the first step (the initial output) the contact is not built yet: the slave nodes against the plane */
  const corot_plane *pl = b->contact_ready ? &c->planes[inst->pair_index] : &pair->plane;
  const int dim = slave->dim;
  for (int k = 0; k < slave->n_nodes; ++k) {
    if (!slave->owned[k]) continue;
    const int p = b->contact_ready ? b->contact_of_node[pair->body_node[k]] : -1;
    const int mine = p >= 0 && c->plane[p] == inst->pair_index && state->step > 0;
    sk_contact_point pt = {.struct_size = sizeof pt, .slave_node = slave->node_id[k]};
    for (int i = 0; i < dim; ++i) {
      pt.x[i] = state->x[0][k * dim + i];
      pt.normal[i] = pl->normal[i];
      pt.gap += (pt.x[i] - pl->point[i]) * pl->normal[i];
    }
    if (p >= 0) { /* D_pp: the node's reference measure; its slip (friction against this plane) */
      pt.area = c->weight[p];
      pt.has_slip = pl->mu > 0.0;
      if (pt.has_slip && mine) {
        memcpy(pt.slip_increment, b->slip_increment + 3 * p, sizeof pt.slip_increment);
        pt.slip = b->slip_length[p];
      }
    }
    if (mine && c->set[p] != COROT_INACTIVE) {
      const double *l = c->lambda + 3 * p, *nu = c->frame + 9 * p;
      const double ln = corot_dot(dim, nu, l);
      double lt[3] = {0, 0, 0};
      for (int i = 0; i < dim; ++i) lt[i] = -(l[i] - ln * nu[i]);
      pt.pressure = ln;
      corot_mul(dim, b->Rm, lt, pt.traction);
      /* the force on the body is -R_m D_pp lambda_p: its normal part acts along -R_m nu (the co-rotated frame of the
       * step), which differs from the plane's normal by the rotation within the step */
      double nu_world[3] = {0, 0, 0};
      corot_mul(dim, b->Rm, nu, nu_world);
      for (int i = 0; i < dim; ++i) pt.normal[i] = -nu_world[i];
      pt.state = c->set[p] == COROT_STICK && corot_contact_mu(c, p) > 0.0 ? 1 : (corot_contact_mu(c, p) > 0.0 ? 2 : 1);
    }
    callback(ctx, &pt);
  }
  return SK_OK;
}
