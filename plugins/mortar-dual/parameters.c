/* mortar-dual glue: the parameters (their defaults computed from the scene: docs/plugins/mortar-dual.md#defaults) and
 * what the plugin refuses at `check` (sk_plugin.check, ABI 2.7). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "defaults.h"
#include "mortar.h"
#include "self_contact.h"

static int choice(const char *value, const char *const *options) {
  for (int i = 0; options[i]; ++i)
    if (strcmp(value, options[i]) == 0) return i;
  return -1;
}

static sk_status read_choice(sk_instance *inst, const char *key, const char *const *options, int *out) {
  const char *value;
  SK_TRY(inst->api->param_string(inst->host, key, 0, options[0], &value));
  *out = choice(value, options);
  if (*out < 0)
    return inst->api->error(inst->host, SK_ERR_INPUT, "mortar-dual: %s must be %s or %s (got '%s')", key, options[0],
                            options[1], value);
  return SK_OK;
}
static double mean_edge(const sk_view *v) {
  double sum = 0.0;
  int count = 0;
  const int corners = v->cell_type == SK_QUAD4 || v->cell_type == SK_QUAD8 || v->cell_type == SK_QUAD9 ? 4
                      : v->cell_type == SK_TRI3 || v->cell_type == SK_TRI6 ? 3
                                                                           : 2;
  for (int f = 0; f < v->n_cells; ++f)
    for (int e = 0; e < (corners == 2 ? 1 : corners); ++e) {
      const int a = v->conn[(int64_t)f * v->nen + e], b = v->conn[(int64_t)f * v->nen + (e + 1) % corners];
      double d2 = 0.0;
      for (int i = 0; i < v->dim; ++i) {
        const double d = v->X[(int64_t)a * v->dim + i] - v->X[(int64_t)b * v->dim + i];
        d2 += d * d;
      }
      sum += sqrt(d2);
      ++count;
    }
  return count ? sum / count : 1.0;
}

/* c_n and c_t: the scene's values, or computed from it (docs/plugins/mortar-dual.md#defaults). A solution does not
 * depend on them, but the semismooth Newton does: with c_t s far below mu z_n the slip branch follows the sign of
 * the iterate z_t and the set cycles (slider-2d at dt 0.4: 5935 Newton iterations in 315 steps at c_n = 1, 336 in
 * 29 steps at c_n = 1000 = E). The rows are tractions (divided by the tributary measure A_j), so c_n is a modulus per
 * length: C_N_FACTOR E* / h with E* the pair's contact modulus and h the slave surface's mean edge; c_t = c_n. */
static const double C_N_FACTOR = 10.0;

static sk_status read_complementarity(sk_instance *inst) {
  const sk_scene_ext *scene = sk_defaults_scene(inst->api, inst->host);
  double computed = 0.0;
  char reason[700] = "";
  if (scene) computed = sk_defaults_stiffness(scene->info(inst->host), C_N_FACTOR, 0, reason, sizeof reason);
  SK_TRY(sk_defaults_param(inst->api, inst->host, scene, "c_n", computed, reason, &inst->ncp.c_n));
  /* frictionless: unused, so not reported */
  return sk_defaults_follow(inst->api, inst->host, scene, "c_t", inst->ncp.c_n, "c_n", inst->ncp.mu > 0.0,
                            &inst->ncp.c_t);
}

/* Slave faces whose multipliers are dual to the transformed functions (TRI6, QUAD8: section 3.5 of the plugin page). */
static int quadratic_quad(sk_elem_type type) { return type == SK_QUAD8 || type == SK_QUAD9; }

static const char *face_name(sk_elem_type type) {
  switch (type) {
    case SK_TRI6: return "TRI6";
    case SK_QUAD8: return "QUAD8";
    case SK_QUAD9: return "QUAD9";
    default: return "second-order";
  }
}

/* alpha of the transformed functions on TRI6 and QUAD8 slave faces (section 3.5 of the plugin page): the vertex
 * functions must integrate to a positive share of the face, 2 alpha / 3 on a flat TRI6 (alpha > 0) and
 * -1/12 + 2 alpha / 3 on a QUAD8 parallelogram (alpha > 1/8), the edge ones (1 - 2 alpha) / 3 (alpha < 1/2). The
 * default on TRI6 is the value whose Hertz tet10 profile error was the smallest measured; QUAD8 keeps 1/5. */
static const double TRI6_ALPHA = 0.1;

static sk_status read_transform_alpha(sk_instance *inst) {
  const sk_elem_type type = inst->slave->cell_type;
  if (!mortar_transformed_face(type)) { /* given for other faces: said so, rather than "unknown key" */
    double given = NAN;
    SK_TRY(inst->api->param_double(inst->host, "transform_alpha", 0, NAN, &given));
    if (!isnan(given))
      return inst->api->error(inst->host, SK_ERR_INPUT, "mortar-dual: transform_alpha applies to TRI6 and QUAD8 slave "
                              "faces (the transformed basis); slave surface '%s' has faces of another type",
                              inst->slave->name);
    char why[200];
    snprintf(why, sizeof why, "unused: slave surface '%s' has no TRI6 or QUAD8 faces (the transformed basis)",
             inst->slave->name);
    sk_defaults_unused(inst->api, inst->host, "transform_alpha", why);
    return SK_OK;
  }
  const double lowest = type == SK_QUAD8 ? 0.125 : 0.0, computed = type == SK_TRI6 ? TRI6_ALPHA : 0.2;
  char reason[200];
  snprintf(reason, sizeof reason, "%s on the slave surface's %s faces (docs/plugins/mortar-dual.md section 3.5)",
           type == SK_TRI6 ? "the measured best" : "Popp et al.'s 1/5", face_name(type));
  double alpha = computed;
  SK_TRY(sk_defaults_param(inst->api, inst->host, sk_defaults_scene(inst->api, inst->host), "transform_alpha",
                           computed, reason, &alpha));
  if (!(alpha > lowest && alpha < 0.5))
    return inst->api->error(inst->host, SK_ERR_INPUT, "mortar-dual: transform_alpha must lie in (%g, 0.5) on %s faces "
                            "(its vertex and edge functions must integrate to positive shares of the face; got %g)",
                            lowest, face_name(type), alpha);
  inst->st.alpha = alpha;
  return SK_OK;
}

/* segment_gauss (2D) and cell_rule (3D): the rules integrating the pair's segments or clipped triangles, reported
 * as the number in use; unused (reported so) by the other dimension, by integration: concentrated and by an obstacle
 * (their Gauss points are face_gauss's). */
static sk_status read_segment_rules(sk_instance *inst) {
  const sk_view *s = inst->slave, *m = inst->master;
  const int segments = inst->integration == INTEGRATION_SEGMENTS && m;
  const char *unused = !m ? "unused: an obstacle pair integrates at face_gauss's points"
                       : !segments ? "unused: integration concentrated integrates at face_gauss's points"
                                   : NULL;
  /* straight faces: Phi_j N_l of degree 2 (line2) or 4 (line3) on a segment; curved LINE3 faces are not polynomial */
  const int curved = s->cell_type == SK_LINE3 || (m && m->cell_type == SK_LINE3);
  const char *why = unused ? unused
           : inst->dim == 3    ? "unused: a 3D pair integrates with cell_rule"
           : curved            ? "a line3 face on the pair (Phi_j N_l of degree 4 on a straight face; curved ones are "
                                 "not polynomial)"
                               : "line2 faces on both sides (Phi_j N_l of degree 2 on a segment)";
  SK_TRY(sk_defaults_count(inst->api, inst->host, "segment_gauss", curved ? 5 : 3, !unused && inst->dim == 2, why,
                           &inst->segment_gauss));
  /* flat faces make the integrands polynomials in the plane: Phi_j N_l of degree 2 (tri3/tri3) or 4 (quad4) */
  const int tri_only = s->cell_type == SK_TRI3 && (!m || m->cell_type == SK_TRI3);
  /* quad9: Phi_j (degree 4 in the plane of a flat quarter) times the gap of a second-order face (degree 2); quad8:
   * Phi_j times N_l, both of degree 3 */
  const int quad9 = quadratic_quad(s->cell_type) || (m && quadratic_quad(m->cell_type));
  why = unused ? unused
           : inst->dim == 2 ? "unused: a 2D pair integrates with segment_gauss"
           : tri_only       ? "tri3 faces on both sides (degree 2 in the plane: exact)"
           : quad9          ? "a quad8 or quad9 face on the pair (degree 6 in the plane of a flat quarter)"
                            : "exact on parallelograms and flat tri6 faces (degree 4 in the plane)";
  return sk_defaults_count(inst->api, inst->host, "cell_rule", tri_only ? 3 : quad9 ? 12 : 6, !unused && inst->dim == 3,
                           why, &inst->cell_rule);
}

sk_status mortar_read_parameters(sk_instance *inst) {
  const sk_host_api *api = inst->api;
  sk_host *host = inst->host;
  static const char *const bases[] = {"dual", "standard", NULL};
  static const char *const integrations[] = {"segments", "concentrated", NULL};
  static const char *const normals[] = {"A", "M", NULL};
  static const char *const sets[] = {"semismooth", "nested", NULL};
  int basis, normal;
  SK_TRY(read_choice(inst, "basis", bases, &basis));
  inst->basis = basis == 0 ? MORTAR_DUAL : MORTAR_STANDARD;
  /* TRI6 and QUAD8 slave faces: the dual basis of the transformed functions (section 3.5 of the plugin page) */
  if (inst->basis == MORTAR_DUAL && mortar_transformed_face(inst->slave->cell_type)) inst->basis = MORTAR_DUAL_TRANSFORMED;
  SK_TRY(read_choice(inst, "integration", integrations, &inst->integration));
  SK_TRY(read_choice(inst, "normal", normals, &normal));
  inst->normal_variant = normal == 0 ? MORTAR_NORMAL_A : MORTAR_NORMAL_M;
  SK_TRY(read_choice(inst, "active_set", sets, &inst->active_set));
  SK_TRY(api->param_double(host, "mu", 0, 0.0, &inst->ncp.mu));
  SK_TRY(read_complementarity(inst));
  SK_TRY(read_transform_alpha(inst));
  SK_TRY(read_segment_rules(inst));
  SK_TRY(api->param_int(host, "face_gauss", 0, 5, &inst->face_gauss));
  SK_TRY(api->param_double(host, "frozen_band", 0, 0.1, &inst->frozen_band));
  SK_TRY(api->param_int(host, "max_flips", 0, 8, &inst->max_flips));
  SK_TRY(api->param_double(host, "min_cover", 0, 0.5, &inst->min_cover));
  const double edge = inst->master ? mean_edge(inst->master) : mean_edge(inst->slave);
  char why[200];
  snprintf(why, sizeof why, "the mean edge of %s surface '%s'%s", inst->master ? "master" : "slave",
           inst->master ? inst->master->name : inst->slave->name,
           inst->master ? "" : " (a rigid obstacle has no master faces)");
  SK_TRY(sk_defaults_length(api, host, "search_margin", edge, why, &inst->search_margin));
  /* read by self.c on a self-contact pair; a pair that is not self contact refuses the key as unknown */
  if (!inst->attach->self_contact) self_contact_exclusion_unused(api, host);
  const double *dummy_xi, *dummy_w;
  if (inst->ncp.mu < 0.0 || !(inst->ncp.c_n > 0.0) || !(inst->ncp.c_t > 0.0) || inst->search_margin < 0.0 ||
      inst->segment_gauss < 1 || inst->segment_gauss > MORTAR_MAX_RULE || inst->face_gauss < 1 ||
      inst->face_gauss > MORTAR_MAX_RULE || mortar_triangle_rule(inst->cell_rule, &dummy_xi, &dummy_w) == 0 ||
      inst->max_flips < 1 || inst->min_cover < 0.0 || inst->min_cover > 1.0 || !(inst->frozen_band >= 0.0) ||
      !(inst->frozen_band <= 1.0))
    return api->error(host, SK_ERR_INPUT,
                      "mortar-dual: need mu >= 0, c_n > 0, c_t > 0, search_margin >= 0, 1 <= segment_gauss, face_gauss "
                      "<= %d, cell_rule in {1, 3, 6, 7, 12}, max_flips >= 1, 0 <= min_cover <= 1, 0 <= frozen_band "
                      "<= 1 (got mu %g, c_n %g, c_t %g, search_margin %g, segment_gauss %d, face_gauss %d, cell_rule "
                      "%d, max_flips %d, min_cover %g, frozen_band %g)",
                      MORTAR_MAX_RULE, inst->ncp.mu, inst->ncp.c_n, inst->ncp.c_t, inst->search_margin,
                      inst->segment_gauss, inst->face_gauss, inst->cell_rule, inst->max_flips, inst->min_cover,
                      inst->frozen_band);
  inst->friction = inst->ncp.mu > 0.0;
  /* c_n h is about the modulus (c_n ~ E / h): 1e-8 of it lies far below any pressure the run resolves and above the
   * round-off of z_n and c_n g at a converged point */
  inst->branch_tol = 1e-8 * inst->ncp.c_n * mean_edge(inst->slave);
  if (inst->strategy == STRATEGY_CONDENSED && inst->basis == MORTAR_DUAL_TRANSFORMED)
    return api->error(host, SK_ERR_INPUT, "mortar-dual: strategy 'condensed' eliminates z with a diagonal D, which TRI6 "
                      "and QUAD8 slave faces do not have (D = diag(int Phi_j) T^-T): use strategy: saddle-point");
  if (inst->strategy == STRATEGY_CONDENSED && inst->basis != MORTAR_DUAL)
    return api->error(host, SK_ERR_INPUT,
                      "mortar-dual: strategy 'condensed' eliminates z with a diagonal D: it needs basis: dual");
  if (inst->integration == INTEGRATION_SEGMENTS && inst->normal_variant == MORTAR_NORMAL_M)
    return api->error(host, SK_ERR_INPUT,
                      "mortar-dual: normal: M (the master normal) has no unique normal at master nodes to segment "
                      "with: use integration: concentrated, or normal: A");
  if (inst->obstacle && inst->normal_variant == MORTAR_NORMAL_M)
    return api->error(host, SK_ERR_INPUT,
                      "mortar-dual: a rigid obstacle measures the gap along its own normal; normal: M is for "
                      "deformable masters");
  return SK_OK;
}

/* ---- what the plugin cannot run (sk_plugin.check, ABI 2.7) ----------------------------------------------------- */

/* Contact is enforced at t_(n+1): a scheme balancing forces elsewhere (the midpoint rule) is refused. */
int mortar_scheme_refused(const char *scheme, double alpha, char *reason, int size) {
  if (alpha == 1.0) return 0;
  snprintf(reason, (size_t)size, "the scheme '%s' balances forces at t_n + %g dt, and mortar-dual enforces contact at "
           "t_(n+1): it supports quasi-static and backward-euler", scheme, alpha);
  return 1;
}

/* Faces the kernel integrates: first-order ones, LINE3 in 2D and QUAD9 in 3D (their standard dual bases are
 * admissible: the shape functions integrate to the positive weights 1/6, 2/3, 1/6 and 1/36, 1/9, 4/9 of the face),
 * and TRI6 and QUAD8 with the dual basis of the transformed functions (Popp, Wohlmuth, Gee & Wall 2012; their vertex
 * functions integrate to 0 and -1/12 of the face). Every face type of the ABI. */
static int face_supported(sk_elem_type type) {
  return type == SK_LINE2 || type == SK_LINE3 || type == SK_TRI3 || type == SK_QUAD4 || type == SK_QUAD9 ||
         type == SK_TRI6 || type == SK_QUAD8;
}

int mortar_faces_refused(const char *slave_name, sk_elem_type slave, const char *master_name, int has_master,
                         sk_elem_type master, char *reason, int size) {
  const int slave_ok = face_supported(slave);
  if (slave_ok && (!has_master || face_supported(master))) return 0;
  snprintf(reason, (size_t)size, "mortar-dual handles line2 and line3 faces in 2D, tri3, tri6, quad4, quad8 and quad9 "
           "in 3D; %s surface '%s' has %s faces", slave_ok ? "master" : "slave",
           slave_ok ? master_name : slave_name, face_name(slave_ok ? master : slave));
  return 1;
}

/* Self contact (section 3.6 of the plugin page): LINE2, LINE3, TRI3, QUAD4 and QUAD9 faces, one rank. */
static int self_refused(int self, int n_ranks, sk_elem_type type, char *reason, int size) {
  if (self && mortar_transformed_face(type)) {
    snprintf(reason, (size_t)size, "mortar-dual's self contact runs on line2, line3, tri3, quad4 and quad9 faces; on "
             "%s faces the multipliers are dual to transformed functions that mix each face's vertex and mid-side "
             "nodes, which a self pair's per-step slave and master sides are not built for", face_name(type));
    return 1;
  }
  if (!self || n_ranks <= 1) return 0;
  snprintf(reason, (size_t)size, "mortar-dual's self contact runs on one rank (the slave/master assignment colours "
           "the whole surface's face pairs on one rank; this run has %d)", n_ranks);
  return 1;
}

/* TRI6 and QUAD8 slave faces: D = diag(int Phi_j) T^-T is not diagonal in the slave unknowns, and strategy
 * 'condensed' eliminates z node by node with a diagonal D (section 3.5 of the plugin page). */
static int condensed_refused(int strategy, sk_elem_type slave, char *reason, int size) {
  if (strategy != STRATEGY_CONDENSED || !mortar_transformed_face(slave)) return 0;
  snprintf(reason, (size_t)size, "mortar-dual's strategy 'condensed' eliminates the multipliers with a diagonal D; on "
           "the slave surface's %s faces D = diag(int Phi_j) T^-T is not diagonal (the dual basis of the transformed "
           "functions): use strategy: saddle-point", face_name(slave));
  return 1;
}

sk_status mortar_check(const sk_scene_info *scene, char *reason, int size) {
  const sk_scene_side *slave = scene->slave, *master = scene->master;
  if (mortar_scheme_refused(scene->scheme, scene->alpha, reason, size) ||
      self_refused(scene->self_contact, scene->n_ranks, slave->cell_type, reason, size) ||
      condensed_refused(scene->strategy, slave->cell_type, reason, size) ||
      mortar_faces_refused(slave->name, slave->cell_type, master->name, !master->rigid, master->cell_type, reason, size))
    return SK_ERR_PLUGIN;
  return SK_OK;
}
