/* corotational — ABI v2 glue: a body plugin that claims its body and integrates it with the co-rotational midpoint
 * scheme (world.c), and a pair plugin through which the scene's rigid planes reach that body. The kernel does the
 * mathematics; this file maps it onto the host's calls (docs/plugins/corotational.md §8, docs/plugin-abi.md §11.5).
 *
 * The body instance poses the body's rows (world force balances, so other terms may add to them) and its extra
 * unknowns [w | alpha or tau | lambda per contact node]. The rotation rate w is either kept (strategy monolithic,
 * the default: NOX drives it with the rest) or eliminated by the plugin (nested, dual: the host solves with w
 * frozen, and recover() takes the Newton step of the rotation equation from a second solve with the same
 * factorisation, stickslip.linear's solve_again — the paper's outer scalar Newton, Sec. 5.3). The pair instances
 * own nothing in the system: they register their slave surface, obstacle and mu with the body instance at create
 * (bodies are created first) and report their planes' share of the contact. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "glue.h"

/* monolithic (default): w kept, NOX drives it with the rest (one dense row and column); nested: w eliminated, its
 * Newton step in recover() from a second solve with the same factorisation, the paper's outer Newton (Sec. 5.3);
 * dual: nested, with lambda condensed on the assembled operator by the host (stickslip.condense). Through this host
 * monolithic takes 2-3 iterations per contact step of the 6.3 ball where nested takes 4-5, and half the linear solves
 * (docs/plugins/corotational.md §8.1). */
static const char *const strategies[] = {"monolithic", "nested", "dual", NULL};
static const char *const parameters[] = {
    "model: 1 (lever arm x + u, angular momentum exact) or 2 (linearised lever arm) [1]  (body)",
    "axis_x, axis_y, axis_z: the fixed rotation axis, 3D [0, 0, 1]  (body)",
    "initial_state: steady (the spinning equilibrium of Sec. 6.1) or undeformed [steady]  (body)",
    "tolerance: |g| <= tolerance * g_ref ends the rotation Newton (energy error <= 4 tolerance) [1e-12]  (body)",
    "c_n, c_t: NCP constants of the active set, relative to each node's own scale [1]  (body)",
    "mu: Coulomb coefficient against the pair's plane [0]  (pair)",
    NULL};

/* ---- create ---------------------------------------------------------------------------------------------------- */

static sk_status fail(sk_instance *inst, sk_status code, const char *what) {
  return inst->api->error(inst->host, code, "%s", what);
}

static sk_status create_pair(sk_instance *inst) {
  const sk_attach *at = inst->attach;
  const sk_host_api *api = inst->api;
  if (!at->obstacle)
    return fail(inst, SK_ERR_INPUT,
                "corotational contact needs a rigid obstacle (`obstacle:`): a deformable master is not supported");
  sk_instance *owner = api->body_instance ? api->body_instance(inst->host, at->slave->body) : NULL;
  if (!owner || !owner->body)
    return api->error(inst->host, SK_ERR_INPUT,
                      "the slave surface '%s' belongs to a body that is not a corotational body: give that body "
                      "`plugin: corotational`",
                      at->slave->name);
  double mu = 0.0;
  SK_TRY(api->param_double(inst->host, "mu", 0, 0.0, &mu));
  if (!(mu >= 0.0) || !isfinite(mu)) return api->error(inst->host, SK_ERR_INPUT, "mu = %g: need mu >= 0", mu);
  inst->owner = owner;
  inst->body = owner->body;
  return glue_register_pair(owner, inst, at->slave, at->obstacle, mu, &inst->pair_index);
}

static sk_status create(const sk_host_api *api, sk_host *host, const sk_attach *attach, sk_instance **out) {
  sk_instance *inst = calloc(1, sizeof *inst);
  if (!inst) return api->error(host, SK_ERR_NOMEM, "out of memory");
  inst->kind = attach->kind;
  inst->api = api;
  inst->host = host;
  inst->attach = attach;
  const sk_status status = attach->kind == SK_KIND_BODY ? glue_create_body(inst) : create_pair(inst);
  if (status != SK_OK) {
    glue_destroy_body(inst);
    free(inst);
    return status;
  }
  *out = inst;
  return SK_OK;
}

static void destroy(sk_instance *inst) {
  if (!inst) return;
  if (inst->kind == SK_KIND_BODY) glue_destroy_body(inst);
  free(inst);
}

/* ---- calls that only the body instance answers ------------------------------------------------------------------ */

static sk_status begin_step(sk_instance *inst, const sk_state *state) {
  return inst->kind == SK_KIND_BODY ? glue_begin_step(inst, state) : SK_OK;
}

static sk_status layout(sk_instance *inst, const sk_state *state, sk_layout *out) {
  if (inst->kind == SK_KIND_BODY) return glue_layout(inst, state, out);
  out->n_extra = 0;
  out->initial = NULL;
  out->eliminated = NULL;
  return SK_OK;
}

static sk_status pattern(sk_instance *inst, const sk_state *state, sk_pattern *pat) {
  return inst->kind == SK_KIND_BODY ? glue_pattern(inst, state, pat) : SK_OK;
}

static sk_status update_active_set(sk_instance *inst, const sk_state *state, int *changed) {
  *changed = 0;
  return inst->kind == SK_KIND_BODY ? glue_update_active_set(inst, state, changed) : SK_OK;
}

static sk_status residual(sk_instance *inst, const sk_state *state, sk_sink *sink) {
  return inst->kind == SK_KIND_BODY ? glue_residual(inst, state, sink) : SK_OK;
}

static sk_status jacobian(sk_instance *inst, const sk_state *state, sk_sink *sink) {
  return inst->kind == SK_KIND_BODY ? glue_jacobian(inst, state, sink) : SK_OK;
}

static sk_status recover(sk_instance *inst, const sk_state *state, sk_vectors *vectors) {
  return inst->kind == SK_KIND_BODY ? glue_recover(inst, state, vectors) : SK_OK;
}

static sk_status converged(sk_instance *inst, const sk_state *state, int *accept) {
  *accept = 1;
  return inst->kind == SK_KIND_BODY ? glue_converged(inst, state, accept) : SK_OK;
}

static sk_status commit_step(sk_instance *inst, const sk_state *state) {
  return inst->kind == SK_KIND_BODY ? glue_commit_step(inst, state) : SK_OK;
}

static void reject_step(sk_instance *inst) { (void)inst; /* the step's working copies are rebuilt by begin_step */ }

static sk_status report(sk_instance *inst, const sk_state *state, sk_contact_report *out) {
  return glue_report(inst, state, out);
}

static sk_status points(sk_instance *inst, const sk_state *state, sk_point_callback callback, void *ctx) {
  return inst->kind == SK_KIND_PAIR ? glue_points(inst, state, callback, ctx) : SK_OK;
}

/* ---- checkpoints (stickslip.checkpoint.v1): the body's committed state, one record ----------------------------- */
/* The plugin runs on one rank, where its body view holds every node in a fixed order: one record (key -1) with the
 * scheme's state theta^n, w, u^n, s^n (co-rotated, view order), R_m and the contact's committed sets, slip directions,
 * multipliers (the next step's predictor), last step's work and the accumulated slip per contact node. */
typedef struct {
  int32_t started, n, n_contact, pad;
  double theta, w, Rm[9];
} saved_body;

static size_t body_record_size(const glue_body *b, int n_contact) {
  return sizeof(saved_body) + sizeof(double) * 2 * (size_t)b->body.n +
         (size_t)n_contact * (1 + sizeof(double) * (2 + 3 + 1 + 1));
}

static sk_status save_state(sk_instance *inst, const sk_state *state, sk_record_writer *writer) {
  (void)state;
  if (inst->kind != SK_KIND_BODY) return SK_OK;
  const glue_body *b = inst->body;
  const int n = b->body.n, nc = b->contact_ready ? b->contact.n : 0;
  unsigned char *r = malloc(body_record_size(b, nc));
  if (!r) return glue_nomem(inst);
  saved_body head = {.started = b->started, .n = n, .n_contact = nc, .theta = b->state.theta, .w = b->state.w};
  memcpy(head.Rm, b->Rm, sizeof head.Rm);
  unsigned char *at = r;
  memcpy(at, &head, sizeof head), at += sizeof head;
  memcpy(at, b->state.u, sizeof(double) * (size_t)n), at += sizeof(double) * (size_t)n;
  memcpy(at, b->state.s, sizeof(double) * (size_t)n), at += sizeof(double) * (size_t)n;
  if (nc > 0) {
    memcpy(at, b->contact.set_committed, (size_t)nc), at += nc;
    memcpy(at, b->contact.dir_committed, sizeof(double) * 2 * (size_t)nc), at += sizeof(double) * 2 * (size_t)nc;
    memcpy(at, b->contact.lambda, sizeof(double) * 3 * (size_t)nc), at += sizeof(double) * 3 * (size_t)nc;
    memcpy(at, b->work_node, sizeof(double) * (size_t)nc), at += sizeof(double) * (size_t)nc;
    memcpy(at, b->slip_length, sizeof(double) * (size_t)nc), at += sizeof(double) * (size_t)nc;
  }
  writer->put(writer, -1, r, (uint32_t)(at - r));
  free(r);
  return SK_OK;
}

static sk_status load_state(sk_instance *inst, const sk_state *state, const sk_record_reader *reader) {
  (void)state;
  if (inst->kind != SK_KIND_BODY) return SK_OK;
  glue_body *b = inst->body;
  if (!b->contact_ready) SK_TRY(glue_build_contact(inst));
  const int n = b->body.n, nc = b->contact.n;
  const size_t size = body_record_size(b, nc);
  unsigned char *r = malloc(size);
  if (!r) return glue_nomem(inst);
  const int64_t got = reader->get(reader, -1, r, (uint32_t)size);
  saved_body head = {0};
  if (got >= (int64_t)sizeof head) memcpy(&head, r, sizeof head);
  if (got != (int64_t)body_record_size(b, head.n_contact) || head.n != n || head.n_contact != nc) {
    free(r);
    return inst->api->error(inst->host, SK_ERR_INPUT, "corotational: the checkpoint's body state %s (%d unknowns, %d "
                            "contact nodes; this body %d and %d)", got < 0 ? "is missing" : "does not fit this body",
                            head.n, head.n_contact, n, nc);
  }
  const unsigned char *at = r + sizeof head;
  b->started = head.started;
  b->state.theta = head.theta;
  b->state.w = head.w;
  memcpy(b->Rm, head.Rm, sizeof head.Rm);
  memcpy(b->state.u, at, sizeof(double) * (size_t)n), at += sizeof(double) * (size_t)n;
  memcpy(b->state.s, at, sizeof(double) * (size_t)n), at += sizeof(double) * (size_t)n;
  if (nc > 0) {
    memcpy(b->contact.set_committed, at, (size_t)nc), at += nc;
    memcpy(b->contact.dir_committed, at, sizeof(double) * 2 * (size_t)nc), at += sizeof(double) * 2 * (size_t)nc;
    memcpy(b->contact.lambda, at, sizeof(double) * 3 * (size_t)nc), at += sizeof(double) * 3 * (size_t)nc;
    memcpy(b->work_node, at, sizeof(double) * (size_t)nc), at += sizeof(double) * (size_t)nc;
    memcpy(b->slip_length, at, sizeof(double) * (size_t)nc);
  }
  free(r);
  return SK_OK;
}

static const sk_checkpoint_ext checkpoint = {SK_TABLE_HEADER(sk_checkpoint_ext), .save = save_state,
                                             .load = load_state};

static const void *extension(const char *id) { return id && strcmp(id, SK_EXT_CHECKPOINT) == 0 ? &checkpoint : NULL; }

/* ---- the integrator ------------------------------------------------------------------------------------------------ */

static const sk_integrator integrator = {
    SK_TABLE_HEADER(sk_integrator),
    .name = "corotational-midpoint",
    .alpha = 0.5,
    .dynamic = 1,
    .predict = glue_predict,
    .velocity = glue_velocity,
    .energy = glue_energy,
};

/* ---- what the plugin cannot run (sk_plugin.check, ABI 2.7) ----------------------------------------------------- */

static sk_status check(const sk_scene_info *scene, char *reason, int size) {
  if (scene->kind == SK_KIND_BODY) {
    if (scene->n_ranks == 1) return SK_OK;
    snprintf(reason, (size_t)size, "the corotational body plugin runs on one rank (this run has %d)", scene->n_ranks);
    return SK_ERR_PLUGIN;
  }
  const sk_scene_side *slave = scene->slave, *master = scene->master;
  if (strcmp(scene->scheme, integrator.name) != 0)
    snprintf(reason, (size_t)size, "its contact acts on corotational bodies only: the body of slave surface '%s' "
             "is integrated by '%s' (give that body `plugin: corotational`)", slave->name, scene->scheme);
  else if (!master->rigid || master->shape != SK_SHAPE_PLANE)
    snprintf(reason, (size_t)size, "the corotational plugin supports rigid planes only (the master of this pair is "
             "%s '%s')", master->rigid ? "a curved obstacle" : "the deformable surface", master->name);
  else if (master->moving)
    snprintf(reason, (size_t)size, "the corotational plugin supports planes at rest: obstacle '%s' has a motion",
             master->name);
  else if (slave->cell_type == SK_TRI6 || slave->cell_type == SK_QUAD8)
    snprintf(reason, (size_t)size, "slave surface '%s' has %s faces, whose corner nodes get no positive contact "
             "weight; use first-order elements or hex27 (QUAD9 faces)", slave->name,
             slave->cell_type == SK_TRI6 ? "TRI6" : "QUAD8");
  else
    return SK_OK;
  return SK_ERR_PLUGIN;
}

static const sk_plugin plugin = {
    SK_TABLE_HEADER(sk_plugin),
    .name = "corotational",
    .summary = "Hauret-Salomon-Weiss-Wohlmuth co-rotational energy-consistent schemes (Models 1 and 2) with a "
               "primal-dual active set against rigid planes",
    .kinds = SK_KIND_BODY | SK_KIND_PAIR,
    .caps = SK_CAP_2D | SK_CAP_3D | SK_CAP_FRICTION | SK_CAP_DYNAMICS | SK_CAP_ENERGY_MOMENTUM |
            SK_CAP_RIGID_OBSTACLE | SK_CAP_MULTIPLIERS | SK_CAP_CONDENSATION | SK_CAP_NEEDS_MASS |
            SK_CAP_OWNS_KINEMATICS,
    .strategies = strategies,
    .parameters = parameters,
    .create = create,
    .destroy = destroy,
    .begin_step = begin_step,
    .layout = layout,
    .pattern = pattern,
    .update_active_set = update_active_set,
    .residual = residual,
    .jacobian = jacobian,
    .recover = recover,
    .converged = converged,
    .commit_step = commit_step,
    .reject_step = reject_step,
    .report = report,
    .points = points,
    .integrator = &integrator,
    .get_extension = extension,
    .check = check,
};

__attribute__((visibility("default"))) const sk_plugin *stickslip_plugin_entry(void);
const sk_plugin *stickslip_plugin_entry(void) { return &plugin; }
