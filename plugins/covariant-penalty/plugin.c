/* stickslip plugin "covariant-penalty": Konyukhov-Schweizerhof covariant penalty contact with parallel transport
 * (docs/plugins/covariant-penalty.md). The ABI v2 glue: this file reads the parameters, makes the contact points
 * and holds the plugin table; step.c does the step (search, master faces, history, assembly); kernel.c evaluates
 * one point.
 *
 * Contact points ("entities"): sts, one per Gauss point of each slave face this rank owns; nts, one per slave node it
 * owns; stas, one per Gauss point of each owned face of the deformable surface (the scene's `slave`) against the
 * obstacle. Each has its weight (reference area), its master face selection and its friction history. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "defaults.h"
#include "glue.h"
#include "records.h"

#define CP_EXPORT __attribute__((visibility("default")))

static const char *const cp_strategies[] = {"none", NULL};
static const char *const cp_parameters[] = {
    "penalty: normal penalty eps_n > 0, pressure per length [computed from the scene: 10 E*/h on QUAD4/TRI3 slave "
    "faces, 100 E*/h on QUAD9 (E*: contact modulus of the pair, h: mean edge of the slave surface); nts with "
    "area_weighted 0: times the mean tributary area]",
    "penalty_tangential: tangential penalty eps_t > 0 [computed from the scene: penalty]",
    "mu: Coulomb friction coefficient >= 0 [0]",
    "variant: sts (Gauss points on the slave faces) or nts (slave nodes) against a deformable master; an obstacle "
    "always gives stas [sts]",
    "gauss_points: Gauss points per face direction for sts and stas, 1..5 [computed from the scene: 2 on QUAD4/TRI3, "
    "3 on QUAD9]",
    "tangent: full, no-curvature, no-rotational or main-only [full]",
    "tangent_form: exact (the derivative of the residual) or paper (the printed matrices, symmetric in stick) [exact]",
    "area_weighted: nts: 1 scales the penalties by the slave node's tributary reference area, 0 uses them as nodal "
    "stiffnesses [1]",
    "search_margin: inflation of the search boxes (length) [computed from the scene: half the mean master face size; "
    "0 against an obstacle]",
    "master_extension: a point up to this fraction of a face beyond the master's border stays in contact with the "
    "extrapolated face, 0 switches it off [0.1]",
    NULL};

/* ---- creation ---------------------------------------------------------------------------------------------------- */
static void cp_destroy(sk_instance *in) {
  if (!in) return;
  if (in->search) in->cs->search_destroy(in->search);
  free(in->entities);
  free(in->cand.faces);
  free(in->K[0]);
  free(in);
}

/* Mean diagonal of the cells' bounding boxes in the reference configuration. */
static double mean_face_size(const sk_view *v) {
  double sum = 0.0;
  for (int32_t f = 0; f < v->n_cells; ++f) {
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL}, d2 = 0.0;
    for (int k = 0; k < v->nen; ++k)
      for (int i = 0; i < 3; ++i) {
        double x = v->X[3 * (size_t)v->conn[(size_t)f * v->nen + k] + i];
        lo[i] = fmin(lo[i], x);
        hi[i] = fmax(hi[i], x);
      }
    for (int i = 0; i < 3; ++i) d2 += (hi[i] - lo[i]) * (hi[i] - lo[i]);
    sum += sqrt(d2);
  }
  return v->n_cells > 0 ? sum / v->n_cells : 0.0;
}

/* The penalties: the scene's values, or computed from it (docs/plugins/covariant-penalty.md#defaults): eps_N =
 * c E* / h with c = PENALTY_FACTOR[order of the slave faces], E* the pair's contact modulus and h the slave surface's
 * mean edge; times the mean tributary area per slave node for nts with area_weighted 0 (a nodal stiffness);
 * eps_T = eps_N. */
static const double PENALTY_FACTOR[3] = {0.0, 10.0, 100.0};

static sk_status read_penalties(sk_instance *in) {
  return sk_defaults_penalties(in->api, in->host, PENALTY_FACTOR, in->variant == CP_NTS && !in->area_weighted, in->mu > 0.0, &in->eps_n, &in->eps_t);
}

static sk_status read_parameters(sk_instance *in) {
  const sk_host_api *api = in->api;
  SK_TRY(api->param_double(in->host, "mu", 0, 0.0, &in->mu));
  if (!(in->mu >= 0.0) || !isfinite(in->mu))
    return api->error(in->host, SK_ERR_INPUT, "covariant-penalty parameter 'mu' must be a finite number >= 0, got %g",
                      in->mu);
  const char *variant, *tangent, *form;
  SK_TRY(api->param_string(in->host, "variant", 0, in->obstacle ? "stas" : "sts", &variant));
  if (in->obstacle) {
    if (strcmp(variant, "stas") != 0)
      return api->error(in->host, SK_ERR_INPUT, "covariant-penalty parameter 'variant': a pair with an obstacle is "
                        "'stas' (Gauss points of the slave faces against the obstacle), got '%s'", variant);
    in->variant = CP_STAS;
  } else if (strcmp(variant, "sts") == 0) {
    in->variant = CP_STS;
  } else if (strcmp(variant, "nts") == 0) {
    in->variant = CP_NTS;
  } else {
    return api->error(in->host, SK_ERR_INPUT, "covariant-penalty parameter 'variant' must be 'sts' or 'nts' with a "
                      "deformable master, got '%s'", variant);
  }
  SK_TRY(api->param_string(in->host, "tangent", 0, "full", &tangent));
  static const char *const tangents[] = {"full", "no-curvature", "no-rotational", "main-only"};
  int which = -1;
  for (int k = 0; k < 4; ++k)
    if (strcmp(tangent, tangents[k]) == 0) which = k;
  if (which < 0)
    return api->error(in->host, SK_ERR_INPUT, "covariant-penalty parameter 'tangent' must be full, no-curvature, "
                      "no-rotational or main-only, got '%s'", tangent);
  in->want[CP_MAIN] = 1;
  in->want[CP_ROTATIONAL] = which == 0 || which == 1;
  in->want[CP_CURVATURE] = which == 0 || which == 2;
  SK_TRY(api->param_string(in->host, "tangent_form", 0, "exact", &form));
  if (strcmp(form, "exact") == 0) in->form = CP_FORM_EXACT;
  else if (strcmp(form, "paper") == 0) in->form = CP_FORM_PAPER;
  else
    return api->error(in->host, SK_ERR_INPUT, "covariant-penalty parameter 'tangent_form' must be exact or paper, "
                      "got '%s'", form);
  const int quadratic = in->slave->cell_type == SK_QUAD9;
  char why[200];
  if (in->variant == CP_NTS)
    snprintf(why, sizeof why, "unused: variant nts puts its points at the slave nodes");
  else
    snprintf(why, sizeof why, "%s slave faces of surface '%s'", quadratic ? "QUAD9" : "first-order", in->slave->name);
  SK_TRY(sk_defaults_count(api, in->host, "gauss_points", quadratic ? 3 : 2, in->variant != CP_NTS, why, &in->gauss));
  if (in->gauss < 1 || in->gauss > 5)
    return api->error(in->host, SK_ERR_INPUT, "covariant-penalty parameter 'gauss_points' must be 1..5, got %d",
                      in->gauss);
  SK_TRY(api->param_int(in->host, "area_weighted", 0, 1, &in->area_weighted));
  if (in->area_weighted != 0 && in->area_weighted != 1)
    return api->error(in->host, SK_ERR_INPUT, "covariant-penalty parameter 'area_weighted' must be 0 or 1, got %d",
                      in->area_weighted);
  SK_TRY(read_penalties(in));
  if (in->master)
    snprintf(why, sizeof why, "half the mean face size of master surface '%s'", in->master->name);
  else
    snprintf(why, sizeof why, "0: a rigid obstacle has no master faces to search");
  SK_TRY(sk_defaults_length(api, in->host, "search_margin", in->master ? 0.5 * mean_face_size(in->master) : 0.0, why,
                            &in->margin));
  if (!(in->margin >= 0.0) || !isfinite(in->margin))
    return api->error(in->host, SK_ERR_INPUT, "covariant-penalty parameter 'search_margin' must be a finite number "
                      ">= 0, got %g", in->margin);
  SK_TRY(api->param_double(in->host, "master_extension", 0, 0.1, &in->extension));
  if (!(in->extension >= 0.0 && in->extension <= 0.5))
    return api->error(in->host, SK_ERR_INPUT, "covariant-penalty parameter 'master_extension' must be in [0, 0.5], "
                      "got %g", in->extension);
  return SK_OK;
}

/* The contact points this rank owns, with their reference areas. */
static sk_status make_entities(sk_instance *in) {
  const sk_view *s = in->slave;
  double xi[MAX_GAUSS][2], w[MAX_GAUSS];
  cp_face slave_face;
  cp_face_init(&slave_face, s->cell_type, in->cs->shape, in->cs->shape_hessian);
  if (in->variant == CP_NTS) {
    /* Tributary areas A_k = integral of N_k over the slave faces at X (3x3-point rule, every face of an owned node
     * is in the view). */
    int nq = in->cs->quadrature(s->cell_type, 5, MAX_GAUSS, xi, w);
    double *area = calloc((size_t)s->n_nodes + 1, sizeof *area);
    in->entities = calloc((size_t)s->n_nodes + 1, sizeof *in->entities);
    if (!area || !in->entities) {
      free(area);
      return in->api->error(in->host, SK_ERR_NOMEM, "covariant-penalty: out of memory");
    }
    for (int32_t f = 0; f < s->n_cells; ++f)
      for (int q = 0; q < nq; ++q) {
        sk_surface_point p = cp_new_surface_point();
        in->cs->geometry(s, f, xi[q], s->X, &p);
        for (int k = 0; k < s->nen; ++k) area[s->conn[(size_t)f * s->nen + k]] += p.N[k] * p.jacobian * w[q];
      }
    for (int32_t k = 0; k < s->n_nodes; ++k) {
      if (!s->owned[k]) continue;
      entity *e = &in->entities[in->n_entities++];
      e->cell = -1;
      e->n_slave = 1;
      e->slave[0] = k;
      e->S[0] = 1.0;
      e->weight = in->area_weighted ? area[k] : 1.0;
    }
    free(area);
  } else {
    int nq = in->cs->quadrature(s->cell_type, 2 * in->gauss - 1, MAX_GAUSS, xi, w);
    if (nq <= 0)
      return in->api->error(in->host, SK_ERR_INTERNAL, "covariant-penalty: no %d-point rule for the slave faces",
                            in->gauss);
    in->entities = calloc((size_t)s->n_cells * nq + 1, sizeof *in->entities);
    if (!in->entities) return in->api->error(in->host, SK_ERR_NOMEM, "covariant-penalty: out of memory");
    for (int32_t f = 0; f < s->n_cells; ++f) {
      if (!s->cell_owned[f]) continue;
      for (int q = 0; q < nq; ++q) {
        sk_surface_point p = cp_new_surface_point();
        in->cs->geometry(s, f, xi[q], s->X, &p);
        entity *e = &in->entities[in->n_entities++];
        e->cell = f;
        e->eta[0] = xi[q][0];
        e->eta[1] = xi[q][1];
        e->weight = w[q] * p.jacobian; /* ds held constant: the reference area (docs §2) */
        if (in->variant == CP_STS) {
          e->n_slave = s->nen;
          for (int k = 0; k < s->nen; ++k) {
            e->slave[k] = s->conn[(size_t)f * s->nen + k];
            e->S[k] = p.N[k];
          }
        }
      }
    }
  }
  for (int k = 0; k < in->n_entities; ++k) in->entities[k].sel_face = -1;
  return SK_OK;
}

/* ---- what the plugin cannot run (sk_plugin.check, ABI 2.7; create() asks the same on older hosts) ---------------- */

static int face_supported(sk_elem_type type) { return type == SK_QUAD4 || type == SK_QUAD9 || type == SK_TRI3; }

static int faces_refused(const char *slave_name, sk_elem_type slave, const char *master_name, sk_elem_type master,
                         char *reason, int size) {
  const int slave_ok = face_supported(slave);
  if (slave_ok && (!master_name || face_supported(master))) return 0;
  snprintf(reason, (size_t)size, "covariant-penalty supports QUAD4, QUAD9 and TRI3 faces (not TRI6 or QUAD8); %s "
           "surface '%s' has %s faces", slave_ok ? "master" : "slave", slave_ok ? master_name : slave_name,
           (slave_ok ? master : slave) == SK_TRI6 ? "TRI6" : (slave_ok ? master : slave) == SK_QUAD8 ? "QUAD8" : "other");
  return 1;
}

static sk_status cp_check(const sk_scene_info *scene, char *reason, int size) {
  const sk_scene_side *slave = scene->slave, *master = scene->master;
  return faces_refused(slave->name, slave->cell_type, master->rigid ? NULL : master->name, master->cell_type, reason,
                       size)
             ? SK_ERR_PLUGIN
             : SK_OK;
}

static sk_status cp_create_checked(sk_instance *in) {
  const sk_attach *at = in->attach;
  in->slave = at->slave;
  in->master = at->master;
  in->obstacle = at->obstacle;
  if (!in->slave || (!in->master) == (!in->obstacle))
    return in->api->error(in->host, SK_ERR_INPUT, "covariant-penalty needs a slave surface and either a master "
                          "surface or an obstacle");
  if (in->slave->dim != 3)
    return in->api->error(in->host, SK_ERR_INPUT, "covariant-penalty works in 3D, not %dD", in->slave->dim);
  if (at->self_contact)
    return in->api->error(in->host, SK_ERR_INPUT, "covariant-penalty does not handle self contact");
  const sk_view *carrier = in->master ? in->master : in->slave; /* the surface whose faces carry the geometry */
  char reason[300];
  if (faces_refused(in->slave->name, in->slave->cell_type, in->master ? in->master->name : NULL,
                    in->master ? in->master->cell_type : SK_POINT1, reason, sizeof reason))
    return in->api->error(in->host, SK_ERR_INPUT, "%s: %s", at->name, reason);
  if (cp_face_init(&in->face, carrier->cell_type, in->cs->shape, in->cs->shape_hessian) != 0)
    return in->api->error(in->host, SK_ERR_INTERNAL, "%s: covariant-penalty: no face type for %d-node faces", at->name,
                          carrier->nen);
  SK_TRY(read_parameters(in));
  SK_TRY(make_entities(in));
  const double size = mean_face_size(in->slave);
  in->touch_tol = 1e-10 * size; /* the round-off scale of gaps */
  in->max_depth = 0.5 * size;   /* stas: deeper rays are not this face's contact (the far side of a body) */
  in->distance.cs = in->cs;
  in->distance.obstacle = in->obstacle;
  in->K[0] = malloc(sizeof(double) * (CP_N_PARTS + 1) * CP_MAX_DOFS * CP_MAX_DOFS);
  if (!in->K[0]) return in->api->error(in->host, SK_ERR_NOMEM, "covariant-penalty: out of memory");
  for (int part = 1; part < CP_N_PARTS; ++part) in->K[part] = in->K[0] + (size_t)part * CP_MAX_DOFS * CP_MAX_DOFS;
  in->K_sum = in->K[0] + (size_t)CP_N_PARTS * CP_MAX_DOFS * CP_MAX_DOFS;
  if (in->master) SK_TRY(in->cs->search_create(in->master, &in->search));
  static const char *const names[] = {"sts", "nts", "stas"};
  in->api->log(in->host, 2, "covariant-penalty: %s, %d contact points on this rank, tangent %s%s%s (%s form)",
               names[in->variant], in->n_entities, "main", in->want[CP_ROTATIONAL] ? " + rotational" : "",
               in->want[CP_CURVATURE] ? " + curvature" : "", in->form == CP_FORM_EXACT ? "exact" : "paper");
  return SK_OK;
}

static sk_status cp_create(const sk_host_api *api, sk_host *host, const sk_attach *attach, sk_instance **instance) {
  *instance = NULL;
  sk_instance *in = calloc(1, sizeof *in);
  if (!in) return api->error(host, SK_ERR_NOMEM, "covariant-penalty: out of memory");
  in->api = api;
  in->host = host;
  in->attach = attach;
  in->cs = api->contact;
  sk_status status = cp_create_checked(in);
  if (status != SK_OK) {
    cp_destroy(in);
    return status;
  }
  *instance = in;
  return SK_OK;
}

/* ---- checkpoints (stickslip.checkpoint.v1): the committed history of each entity ---------------------------------- */

/* An entity's key: its slave node's whole index (nts), or its face's whole index and Gauss point (sts, stas; the
 * entities of a face are consecutive, one per Gauss point). */
static int64_t entity_key(const sk_instance *in, int k) {
  const entity *e = &in->entities[k];
  if (e->cell < 0) return in->slave->node_index[e->slave[0]];
  int q = 0;
  while (k - q - 1 >= 0 && in->entities[k - q - 1].cell == e->cell) ++q;
  return in->slave->cell_index[e->cell] * (int64_t)MAX_GAUSS + q;
}

/* An entity's record: its committed history and the slip it has accumulated (contact.csv's `slip`). */
typedef struct {
  history committed;
  double slip;
} saved_entity;

static sk_status cp_save(sk_instance *in, const sk_state *st, sk_record_writer *writer) {
  (void)st;
  for (int k = 0; k < in->n_entities; ++k) {
    saved_entity r = {.committed = in->entities[k].committed, .slip = in->entities[k].slip};
    if (!r.committed.valid && r.slip == 0.0) continue;
    if (in->master && r.committed.valid) r.committed.face = (int)in->master->cell_index[r.committed.face];
    writer->put(writer, entity_key(in, k), &r, (uint32_t)sizeof r);
  }
  return SK_OK;
}

static sk_status cp_load(sk_instance *in, const sk_state *st, const sk_record_reader *reader) {
  (void)st;
  int *cells = in->master ? records_cells_of_view(in->master) : NULL;
  if (in->master && !cells) return in->api->error(in->host, SK_ERR_NOMEM, "covariant-penalty: out of memory");
  sk_status status = SK_OK;
  for (int k = 0; k < in->n_entities && status == SK_OK; ++k) {
    entity *e = &in->entities[k];
    saved_entity r;
    memset(&e->committed, 0, sizeof e->committed);
    e->slip = 0.0;
    const int64_t got = reader->get(reader, entity_key(in, k), &r, (uint32_t)sizeof r);
    if (got < 0) continue;
    if (got != (int64_t)sizeof r)
      status = in->api->error(in->host, SK_ERR_INPUT, "covariant-penalty: a history record of %lld bytes, expected %zu",
                              (long long)got, sizeof r);
    else if (in->master && r.committed.valid &&
             (r.committed.face = records_view_cell(cells, in->master, r.committed.face)) < 0)
      status = in->api->error(in->host, SK_ERR_INPUT, "covariant-penalty: a contact point's history lies on a master "
                              "face this rank does not hold");
    else {
      e->committed = r.committed;
      e->slip = r.slip;
    }
  }
  free(cells);
  return status;
}

static const sk_checkpoint_ext cp_checkpoint = {SK_TABLE_HEADER(sk_checkpoint_ext), .save = cp_save,
                                                .load = cp_load};

static const void *cp_extension(const char *id) {
  return id && strcmp(id, SK_EXT_CHECKPOINT) == 0 ? &cp_checkpoint : NULL;
}

static const sk_plugin cp_plugin = {
    SK_TABLE_HEADER(sk_plugin),
    .name = "covariant-penalty",
    .summary = "Konyukhov-Schweizerhof covariant penalty contact (STS, NTS, STAS) with parallel transport and the "
               "main/rotational/curvature tangent split",
    .kinds = SK_KIND_PAIR,
    .caps = SK_CAP_3D | SK_CAP_FRICTION | SK_CAP_QUASISTATIC | SK_CAP_DYNAMICS | SK_CAP_RIGID_OBSTACLE |
            SK_CAP_DEFORMABLE_MASTER | SK_CAP_NEEDS_CURVATURE | SK_CAP_SAYS_IDLE,
    .strategies = cp_strategies,
    .parameters = cp_parameters,
    .create = cp_create,
    .destroy = cp_destroy,
    .begin_step = cp_begin_step,
    .layout = cp_layout,
    .pattern = cp_pattern,
    .update_active_set = cp_update_active_set,
    .residual = cp_residual,
    .jacobian = cp_jacobian,
    .recover = NULL,
    .converged = cp_converged,
    .commit_step = cp_commit_step,
    .reject_step = cp_reject_step,
    .report = cp_report,
    .points = cp_points,
    .integrator = NULL,
    .get_extension = cp_extension,
    .check = cp_check,
};

CP_EXPORT const sk_plugin *stickslip_plugin_entry(void);
CP_EXPORT const sk_plugin *stickslip_plugin_entry(void) { return &cp_plugin; }
