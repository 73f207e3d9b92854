/* corotational — the body instance's setup: the node graph of its view, M and S captured from stickslip.bulk, the
 * parameters, the planes of the registered pairs and their contact nodes, the steady initial state (Sec. 6.1). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "glue.h"

static int compare_int(const void *a, const void *b) {
  const int x = *(const int *)a, y = *(const int *)b;
  return (x > y) - (x < y);
}

static int compare_dof(const void *a, const void *b) {
  const int64_t x = ((const glue_dof *)a)->dof, y = ((const glue_dof *)b)->dof;
  return (x > y) - (x < y);
}

sk_status glue_nomem(sk_instance *inst) { return inst->api->error(inst->host, SK_ERR_NOMEM, "out of memory"); }

/* ---- the node graph of the body view, and M and S captured over it ------------------------------------------------ */

static sk_status build_graph(glue_body *b) {
  const sk_view *v = b->view;
  const int dim = v->dim, n = v->n_nodes * dim;
  if (corot_node_graph(v->n_nodes, v->n_cells, v->nen, v->conn, &b->row_ptr, &b->cols) != 0) return SK_ERR_NOMEM;
  const int64_t used = b->row_ptr[v->n_nodes];
  b->mass = calloc((size_t)used, sizeof(double));
  b->stiffness = calloc((size_t)used * (size_t)(dim * dim), sizeof(double));
  b->dofs = malloc(sizeof(glue_dof) * (size_t)n);
  if (!b->mass || !b->stiffness || !b->dofs) return SK_ERR_NOMEM;
  for (int k = 0; k < n; ++k) b->dofs[k] = (glue_dof){v->dofs[k], k};
  qsort(b->dofs, (size_t)n, sizeof(glue_dof), compare_dof);
  return SK_OK;
}

/* The view slot of a global dof, or -1. */
static int slot_of(const glue_body *b, int64_t dof) {
  const glue_dof key = {dof, 0};
  const glue_dof *hit = bsearch(&key, b->dofs, (size_t)b->view->n_nodes * (size_t)b->view->dim, sizeof key,
                                compare_dof);
  return hit ? hit->slot : -1;
}

/* Graph position of (a, c), or -1. */
static int64_t graph_find(const glue_body *b, int a, int c) {
  const int *begin = b->cols + b->row_ptr[a];
  const int *hit = bsearch(&c, begin, (size_t)(b->row_ptr[a + 1] - b->row_ptr[a]), sizeof(int), compare_int);
  return hit ? b->row_ptr[a] + (hit - begin) : -1;
}

/* A sink that records what stickslip.bulk's add_mass / add_stiffness add: the plugin needs S C_n and rotated S
 * blocks, which add_stiffness's scalar scale cannot express (docs/plugins/corotational.md §8). */
typedef struct {
  sk_sink sink;                  /* first: the host calls through it */
  glue_body *body;
  int mass;                      /* 1: add_mass(I) (keep component 0 of the scalar M), 0: add_stiffness(1) */
  int outside;                   /* entries that fell outside the graph */
} capture_sink;

static void capture_vector(sk_sink *sink, int n, const int64_t *rows, const double *values) {
  (void)sink, (void)n, (void)rows, (void)values;
}

static void capture_matrix(sk_sink *sink, int nr, const int64_t *rows, int nc, const int64_t *cols,
                           const double *values) {
  capture_sink *cs = (capture_sink *)sink;
  glue_body *b = cs->body;
  const int dim = b->view->dim;
  for (int i = 0; i < nr; ++i) {
    const int r = slot_of(b, rows[i]);
    if (r < 0) continue;
    for (int j = 0; j < nc; ++j) {
      const int c = slot_of(b, cols[j]);
      const double value = values[(size_t)i * (size_t)nc + (size_t)j];
      if (c < 0 || value == 0.0) continue;
      const int64_t k = graph_find(b, r / dim, c / dim);
      if (k < 0) {
        cs->outside++;
        continue;
      }
      if (cs->mass) {
        if (r % dim == 0 && c % dim == 0) b->mass[k] += value;
      } else {
        b->stiffness[k * dim * dim + (r % dim) * dim + c % dim] += value;
      }
    }
  }
}

static sk_status capture_operators(sk_instance *inst) {
  glue_body *b = inst->body;
  const int dim = b->view->dim;
  double identity[9] = {0};
  for (int i = 0; i < dim; ++i) identity[i * dim + i] = 1.0;
  capture_sink cs = {.sink = {SK_TABLE_HEADER(sk_sink), .add_vector = capture_vector, .add_matrix = capture_matrix,
                              .add_rhs = capture_vector},
                     .body = b,
                     .mass = 1};
  SK_TRY(b->bulk->add_mass(inst->host, identity, &cs.sink));
  cs.mass = 0;
  SK_TRY(b->bulk->add_stiffness(inst->host, 1.0, &cs.sink));
  if (cs.outside)
    return inst->api->error(inst->host, SK_ERR_INTERNAL,
                            "%d entries of the body's mass or stiffness fell outside its element graph", cs.outside);
  return SK_OK;
}

/* ---- create -------------------------------------------------------------------------------------------------------- */

static sk_status read_parameters(sk_instance *inst) {
  const sk_host_api *api = inst->api;
  sk_host *host = inst->host;
  glue_body *b = inst->body;
  int model = 1;
  const char *initial = NULL;
  SK_TRY(api->param_int(host, "model", 0, 1, &model));
  if (model != 1 && model != 2) return api->error(host, SK_ERR_INPUT, "model = %d: use 1 or 2", model);
  b->model = (corot_model)model;
  SK_TRY(api->param_double(host, "axis_x", 0, 0.0, &b->axis[0]));
  SK_TRY(api->param_double(host, "axis_y", 0, 0.0, &b->axis[1]));
  SK_TRY(api->param_double(host, "axis_z", 0, 1.0, &b->axis[2]));
  SK_TRY(api->param_double(host, "tolerance", 0, 1e-12, &b->tolerance));
  SK_TRY(api->param_double(host, "c_n", 0, 1.0, &b->c_n));
  SK_TRY(api->param_double(host, "c_t", 0, 1.0, &b->c_t));
  SK_TRY(api->param_string(host, "initial_state", 0, "steady", &initial));
  if (b->view->dim == 2 && (b->axis[0] != 0.0 || b->axis[1] != 0.0))
    return api->error(host, SK_ERR_INPUT, "in 2D the rotation axis is e_z: axis_x and axis_y must be 0");
  if (!(sqrt(corot_dot(3, b->axis, b->axis)) > 0.0)) return api->error(host, SK_ERR_INPUT, "the axis must not be zero");
  if (!(b->tolerance > 0.0 && b->tolerance < 1.0))
    return api->error(host, SK_ERR_INPUT, "tolerance = %g: need 0 < tolerance < 1", b->tolerance);
  if (!(b->c_n > 0.0) || !(b->c_t > 0.0))
    return api->error(host, SK_ERR_INPUT, "c_n = %g, c_t = %g: both must be > 0", b->c_n, b->c_t);
  /* the scene's spin must be about the axis (the velocity field v + w x (X - c) is rigid by construction): refused
   * here, at check time, where the scene tells it (ABI 2.7); glue_ensure_started checks the field on older hosts */
  const sk_scene_ext *scene = SK_HAS(api, get_extension) ? api->get_extension(host, SK_EXT_SCENE) : NULL;
  if (scene) {
    const double *w = scene->info(host)->slave->angular_velocity;
    const double length = sqrt(corot_dot(3, b->axis, b->axis)), along = corot_dot(3, w, b->axis) / length;
    double off = 0.0;
    for (int i = 0; i < 3; ++i) off += (w[i] - along * b->axis[i] / length) * (w[i] - along * b->axis[i] / length);
    if (sqrt(off) > 1e-12 * sqrt(corot_dot(3, w, w)))
      return api->error(host, SK_ERR_INPUT, "the body's angular_velocity (%g, %g, %g) is not along the plugin's axis "
                        "(%g, %g, %g): give axis_x, axis_y, axis_z along the spin, or a spin about the axis", w[0],
                        w[1], w[2], b->axis[0], b->axis[1], b->axis[2]);
  }
  if (strcmp(initial, "steady") == 0)
    b->steady = 1;
  else if (strcmp(initial, "undeformed") == 0)
    b->steady = 0;
  else
    return api->error(host, SK_ERR_INPUT, "initial_state = '%s': use steady or undeformed", initial);
  return SK_OK;
}

sk_status glue_create_body(sk_instance *inst) {
  const sk_host_api *api = inst->api;
  sk_host *host = inst->host;
  int rank = 0, n_ranks = 1;
  api->ranks(host, &rank, &n_ranks);
  if (n_ranks > 1)
    return api->error(host, SK_ERR_INPUT, "the corotational body plugin runs on one rank (this run has %d)", n_ranks);
  glue_body *b = inst->body = calloc(1, sizeof *b);
  if (!b) return glue_nomem(inst);
  b->view = inst->attach->body;
  SK_TRY(read_parameters(inst));
  b->bulk = api->get_extension(host, SK_EXT_BULK);
  b->linear = api->get_extension(host, SK_EXT_LINEAR);
  if (!b->bulk || !b->linear)
    return api->error(host, SK_ERR_PLUGIN, "this stickslip lacks the extension %s, which the corotational plugin needs",
                      b->bulk ? SK_EXT_LINEAR : SK_EXT_BULK);
  SK_TRY(b->bulk->claim(host));
  if (build_graph(b) != SK_OK) return glue_nomem(inst);
  SK_TRY(capture_operators(inst));
  if (corot_body_init(&b->body, b->view->dim, b->view->n_nodes, b->row_ptr, b->cols, b->mass, b->stiffness,
                      b->view->X, b->axis) != 0)
    return api->error(host, SK_ERR_INPUT, "the body has no mass or no moment of inertia about the axis");
  double mass = 0.0, centre[3] = {0, 0, 0};
  SK_TRY(b->bulk->mass_properties(host, &mass, centre));
  if (fabs(mass - b->body.mass_total) > 1e-10 * mass)
    return api->error(host, SK_ERR_INTERNAL, "the captured mass matrix sums to %.17g, the host's mass is %.17g",
                      b->body.mass_total, mass);
  b->l_scale = sqrt(b->body.inertia / b->body.mass_total);
  if (corot_state_alloc(&b->state, &b->body) != 0 || corot_state_alloc(&b->next, &b->body) != 0) return glue_nomem(inst);
  b->contact_of_node = malloc(sizeof(int) * (size_t)b->view->n_nodes);
  b->q = calloc((size_t)b->body.n, sizeof(double));
  b->v = calloc((size_t)b->body.n, sizeof(double));
  b->f_world = calloc((size_t)b->body.n, sizeof(double));
  if (!b->contact_of_node || !b->q || !b->v || !b->f_world) return glue_nomem(inst);
  for (int a = 0; a < b->view->n_nodes; ++a) b->contact_of_node[a] = -1;
  b->monolithic = inst->attach->strategy == 0;
  b->dual = inst->attach->strategy == 2;
  if (b->dual && !(b->condense = api->get_extension(host, SK_EXT_CONDENSE)))
    return api->error(host, SK_ERR_PLUGIN, "strategy dual needs the extension %s, which this stickslip lacks",
                      SK_EXT_CONDENSE);
  return SK_OK;
}

void glue_destroy_body(sk_instance *inst) {
  glue_body *b = inst->body;
  if (!b || inst->kind != SK_KIND_BODY) return;
  corot_world_jacobian_free(&b->J);
  corot_world_free(&b->world);
  corot_contact_free(&b->contact);
  corot_state_free(&b->state);
  corot_state_free(&b->next);
  corot_body_free(&b->body);
  void *arrays[] = {b->row_ptr, b->cols,    b->mass,       b->stiffness,  b->dofs,     b->contact_of_node,
                    b->y,       b->F,       b->dF,         b->dgy,        b->y2_view,  b->y2_extra,
                    b->rhs_extra, b->f_world, b->q,        b->v,          b->initial,  b->eliminated,
                    b->index,   b->block,   b->work_node,  b->slip_increment, b->slip_length};
  for (size_t k = 0; k < sizeof arrays / sizeof arrays[0]; ++k) free(arrays[k]);
  for (int k = 0; k < b->n_pairs; ++k) free(b->pairs[k].body_node);
  free(b);
  inst->body = NULL;
}

/* A rigid plane from an obstacle: projections of two points must give one normal and one plane. */
static sk_status plane_of(sk_instance *inst, const glue_pair *pair, corot_plane *plane) {
  const sk_contact_services *cs = inst->api->contact;
  const glue_body *b = inst->body;
  const int dim = b->view->dim;
  double probe[2][3] = {{0, 0, 0}, {0, 0, 0}}, gap;
  for (int i = 0; i < dim; ++i) {
    probe[0][i] = b->body.centre[i];
    probe[1][i] = b->body.centre[i] + b->l_scale * (i == 0 ? 0.7 : 0.3);
  }
  sk_surface_point pt[2] = {{.struct_size = sizeof(sk_surface_point)}, {.struct_size = sizeof(sk_surface_point)}};
  for (int k = 0; k < 2; ++k) SK_TRY(cs->obstacle_project(pair->obstacle, 0.0, probe[k], dim, &pt[k], &gap));
  double dn = 0.0, off = 0.0;
  for (int i = 0; i < dim; ++i) {
    dn = fmax(dn, fabs(pt[0].n[i] - pt[1].n[i]));
    off += (pt[1].x[i] - pt[0].x[i]) * pt[0].n[i];
  }
  if (dn > 1e-12 || fabs(off) > 1e-12 * b->l_scale)
    return inst->api->error(pair->instance->host, SK_ERR_INPUT,
                            "the obstacle is not a plane: the corotational plugin supports rigid planes only");
  memset(plane, 0, sizeof *plane);
  for (int i = 0; i < dim; ++i) {
    plane->point[i] = pt[0].x[i];
    plane->normal[i] = pt[0].n[i];
  }
  plane->mu = pair->mu;
  return SK_OK;
}

sk_status glue_register_pair(sk_instance *owner, sk_instance *pair, const sk_view *slave, const sk_obstacle *obstacle,
                             double mu, int *index) {
  glue_body *b = owner->body;
  if (b->contact_ready)
    return pair->api->error(pair->host, SK_ERR_INTERNAL, "a contact pair was created after the body's first step");
  if (b->n_pairs == COROT_MAX_PLANES)
    return pair->api->error(pair->host, SK_ERR_INPUT, "a corotational body takes at most %d contact pairs",
                            COROT_MAX_PLANES);
  b->pairs[b->n_pairs] = (glue_pair){.instance = pair, .slave = slave, .obstacle = obstacle, .mu = mu};
  SK_TRY(plane_of(owner, &b->pairs[b->n_pairs], &b->pairs[b->n_pairs].plane));
  *index = b->n_pairs++;
  return SK_OK;
}

/* ---- the contact of the registered pairs (built once, at the first step) ------------------------------------------ */

typedef struct {
  int64_t id;
  int node;
} id_entry;

static int compare_id(const void *a, const void *b) {
  const int64_t x = ((const id_entry *)a)->id, y = ((const id_entry *)b)->id;
  return (x > y) - (x < y);
}

/* D_pp = integral of phi_p over the slave surface (reference), accumulated into weight[slave view node]. */
static sk_status dual_weights(sk_instance *inst, const sk_view *slave, double *weight) {
  const sk_contact_services *cs = inst->api->contact;
  /* Integrals of phi_p are zero (TRI6) or negative (QUAD8) at the corners of serendipity/P2 faces: their corners
   * would carry no or a tensile contact force (docs/plugins/penalty-nts.md#quadratic-faces). */
  if (slave->cell_type == SK_TRI6 || slave->cell_type == SK_QUAD8)
    return inst->api->error(inst->host, SK_ERR_INPUT, "corotational: slave surface '%s' has %s faces, whose corner "
                            "nodes get no positive contact weight; use first-order elements or hex27 (QUAD9 faces)",
                            slave->name, slave->cell_type == SK_TRI6 ? "TRI6" : "QUAD8");
  double xi[16][2], w[16];
  const int nq = cs->quadrature(slave->cell_type, 3, 16, xi, w);
  if (nq <= 0) return inst->api->error(inst->host, SK_ERR_INTERNAL, "no quadrature for the slave faces");
  for (int32_t f = 0; f < slave->n_cells; ++f)
    for (int q = 0; q < nq; ++q) {
      sk_surface_point pt = {.struct_size = sizeof pt};
      cs->geometry(slave, f, xi[q], slave->X, &pt);
      for (int a = 0; a < slave->nen; ++a) weight[slave->conn[(int64_t)f * slave->nen + a]] += w[q] * pt.jacobian * pt.N[a];
    }
  return SK_OK;
}

sk_status glue_build_contact(sk_instance *inst) {
  glue_body *b = inst->body;
  const sk_view *v = b->view;
  const int dim = v->dim;
  corot_plane planes[COROT_MAX_PLANES];
  int n_contact = 0;
  int *nodes = malloc(sizeof(int) * (size_t)v->n_nodes);
  double *weights = calloc((size_t)v->n_nodes, sizeof(double));
  uint32_t *masks = calloc((size_t)v->n_nodes, sizeof(uint32_t));
  id_entry *ids = malloc(sizeof(id_entry) * (size_t)v->n_nodes);
  sk_status status = nodes && weights && masks && ids ? SK_OK : glue_nomem(inst);
  if (status == SK_OK) {
    for (int a = 0; a < v->n_nodes; ++a) ids[a] = (id_entry){v->node_id[a], a};
    qsort(ids, (size_t)v->n_nodes, sizeof *ids, compare_id);
  }
  for (int k = 0; k < b->n_pairs && status == SK_OK; ++k) {
    const sk_view *slave = b->pairs[k].slave;
    planes[k] = b->pairs[k].plane;
    double *w = status == SK_OK ? calloc((size_t)slave->n_nodes, sizeof(double)) : NULL;
    b->pairs[k].body_node = status == SK_OK ? malloc(sizeof(int) * (size_t)slave->n_nodes) : NULL;
    if (status == SK_OK && (!w || !b->pairs[k].body_node)) status = glue_nomem(inst);
    if (status == SK_OK) status = dual_weights(inst, slave, w);
    for (int s = 0; s < slave->n_nodes && status == SK_OK; ++s) {
      const id_entry key = {slave->node_id[s], 0};
      const id_entry *hit = bsearch(&key, ids, (size_t)v->n_nodes, sizeof key, compare_id);
      if (!hit) {
        status = inst->api->error(b->pairs[k].instance->host, SK_ERR_INTERNAL, "slave node %lld is not in the body",
                                  (long long)slave->node_id[s]);
        break;
      }
      b->pairs[k].body_node[s] = hit->node;
      int *p = &b->contact_of_node[hit->node];
      if (*p < 0) {
        *p = n_contact;
        nodes[n_contact] = hit->node;
        weights[n_contact++] = w[s]; /* the first surface's D_pp: pairs on one surface agree */
      }
      masks[*p] |= 1u << k;
    }
    free(w);
  }
  if (status == SK_OK && corot_contact_init(&b->contact, dim, n_contact, nodes, weights, b->n_pairs, planes, b->c_n,
                                            b->c_t) != 0)
    status = inst->api->error(inst->host, SK_ERR_INPUT, "a slave node has no surface weight (a degenerate face)");
  if (status == SK_OK) memcpy(b->contact.mask, masks, sizeof(uint32_t) * (size_t)n_contact);
  free(nodes);
  free(weights);
  free(masks);
  free(ids);
  SK_TRY(status);
  if (corot_world_init(&b->world, b->model, &b->body, b->n_pairs ? &b->contact : NULL) != 0 ||
      corot_world_jacobian_alloc(&b->J, &b->world) != 0)
    return glue_nomem(inst);
  const int N = b->world.N, n = b->body.n;
  b->n_extra = 1 + N - n;
  b->y = calloc((size_t)N, sizeof(double));
  b->F = calloc((size_t)N, sizeof(double));
  b->dF = calloc((size_t)N, sizeof(double));
  b->dgy = calloc((size_t)N, sizeof(double));
  b->y2_view = calloc((size_t)n, sizeof(double));
  b->y2_extra = calloc((size_t)b->n_extra, sizeof(double));
  b->rhs_extra = calloc((size_t)b->n_extra, sizeof(double));
  b->initial = calloc((size_t)b->n_extra, sizeof(double));
  b->eliminated = calloc((size_t)b->n_extra, 1);
  const size_t buffer = (size_t)(n > b->n_extra ? n : b->n_extra) + 64; /* the largest row of a sink call */
  b->index = calloc(buffer, sizeof(int64_t));
  b->block = calloc(buffer, sizeof(double));
  b->work_node = calloc((size_t)(n_contact > 0 ? n_contact : 1), sizeof(double));
  b->slip_increment = calloc(3 * (size_t)(n_contact > 0 ? n_contact : 1), sizeof(double));
  b->slip_length = calloc((size_t)(n_contact > 0 ? n_contact : 1), sizeof(double));
  if (!b->y || !b->F || !b->dF || !b->dgy || !b->y2_view || !b->y2_extra || !b->rhs_extra || !b->initial ||
      !b->eliminated || !b->index || !b->block || !b->work_node || !b->slip_increment || !b->slip_length)
    return glue_nomem(inst);
  b->eliminated[0] = 1; /* w: the plugin's own Newton in recover() */
  /* g's row in F: a torque / L (Model 1) or c . u_h a^2 / L (Model 2) is a force, like the body rows */
  b->contact_ready = 1;
  return SK_OK;
}

/* ---- the initial state (Sec. 6.1), from the host's initial velocities ---------------------------------------------- */

/* World displacements and velocities of the committed state, to the host (history, VTU, the next v_n). */
sk_status glue_publish_state(sk_instance *inst) {
  glue_body *b = inst->body;
  corot_energy_parts(&b->body, b->state.u, b->state.s, b->v, &b->energy[0], &b->energy[1]); /* b->v: scratch here */
  corot_world_state(&b->body, b->state.theta, b->state.u, b->state.s, b->q, b->v);
  for (int i = 0; i < b->body.n; ++i) b->q[i] -= b->view->X[i];
  return b->bulk->set_state(inst->host, b->q, b->v);
}

sk_status glue_ensure_started(sk_instance *inst, const sk_state *state) {
  glue_body *b = inst->body;
  if (b->started) return SK_OK;
  const corot_body *body = &b->body;
  const int dim = body->dim;
  const double *v = state->v_n ? state->v_n[0] : NULL;
  if (!v) return inst->api->error(inst->host, SK_ERR_INPUT, "the corotational plugin needs a dynamic scheme");
  /* the rigid motion V0 + w0 Pi x that the scene's velocity and spin give */
  double V0[3] = {0, 0, 0};
  corot_mean(body, v, V0);
  corot_mass_apply(body, v, b->q);
  double J = 0.0, misfit = 0.0, size = 0.0;
  for (int a = 0; a < body->n_nodes; ++a) {
    double px[3];
    corot_pi(dim, body->e, body->x + a * dim, px);
    J += corot_dot(dim, b->q + a * dim, px);
  }
  const double omega = J / body->inertia;
  for (int a = 0; a < body->n_nodes; ++a) {
    double px[3];
    corot_pi(dim, body->e, body->x + a * dim, px);
    for (int i = 0; i < dim; ++i) {
      misfit = fmax(misfit, fabs(v[a * dim + i] - V0[i] - omega * px[i]));
      size = fmax(size, fabs(v[a * dim + i]));
    }
  }
  if (misfit > 1e-10 * fmax(size, 1e-300))
    return inst->api->error(inst->host, SK_ERR_INPUT,
                            "the body's initial velocity is not a rigid motion about the plugin's axis (misfit %.3g of "
                            "%.3g): give `velocity` and an `angular_velocity` along the axis only",
                            misfit, size);
  int iterations = 0;
  const int status = corot_initial_state(body, b->model, b->steady ? omega : 0.0, V0, 1e-13, b->state.u, b->state.s,
                                         &iterations);
  if (status != 0)
    return inst->api->error(inst->host, SK_ERR_INPUT,
                            "no steady spin at theta'_0 = %g (%s): the spin is at or above an elastic frequency; use "
                            "initial_state: undeformed",
                            omega, status > 0 ? "CG did not converge" : "the operator is not positive");
  if (!b->steady) /* undeformed: the scene's rigid field itself, s = V0 + w0 Pi x */
    for (int a = 0; a < body->n_nodes; ++a) {
      double px[3];
      corot_pi(dim, body->e, body->x + a * dim, px);
      for (int i = 0; i < dim; ++i) b->state.s[a * dim + i] = V0[i] + omega * px[i];
    }
  b->state.theta = 0.0;
  b->state.w = omega;
  inst->api->log(inst->host, 2, "corotational: steady initial state, theta'_0 = %.15g, %d CG iterations", omega,
                 iterations);
  b->started = 1;
  return glue_publish_state(inst);
}

