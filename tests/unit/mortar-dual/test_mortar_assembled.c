/* mortar-dual's assembled operator through the plugin test kit (tests/support/plugin_kit.h), driven as the host
 * drives it: a committed step (the friction history D^n, M^n), then a step to perturbed positions with given
 * multipliers z; the Jacobian the plugin assembles against central differences of the residual it assembles over
 * every unknown (positions of slave and master, z), the active set frozen at that point. Cases: 2D segments (dual
 * and standard bases), concentrated integration with normal fields A and M, moving rigid obstacles (line, circle),
 * 3D quad4/tri3 segments with clipping (both bases) and concentrated points; frictionless, stick and slip; quad9/quad9
 * segments on the faces' quarters (test_mortar_assembled_quad9, MORTAR_ASSEMBLED_QUAD9 = 1). Every entry lies in the declared pattern. Under strategy `condensed` the pairs the plugin declares through
 * stickslip.condense.v1 are the ones the host can eliminate: each slave row with its own node's z, D diagonal (no
 * other paired z in a paired row) and invertible. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mortar.h" /* the instance: the node states the case reaches */
#include "mortar_assembled_meshes.h"
#include "plugin_kit.h"
#include "sk_test.h"

const sk_plugin *stickslip_plugin_entry(void);

#ifndef MORTAR_ASSEMBLED_QUAD9
#define MORTAR_ASSEMBLED_QUAD9 0
#endif
#ifndef MORTAR_ASSEMBLED_TRI6
#define MORTAR_ASSEMBLED_TRI6 0
#endif
#ifndef MORTAR_ASSEMBLED_QUAD8
#define MORTAR_ASSEMBLED_QUAD8 0
#endif

static const double FD_STEP = 1e-7;

/* key=value pairs, numbers as numbers */
static void params(kit *k, const char *const *kv) {
  for (int i = 0; kv[i]; i += 2) {
    char *end = NULL;
    const double v = strtod(kv[i + 1], &end);
    if (end && *end == '\0') kit_param(k, kv[i], v);
    else kit_param_text(k, kv[i], kv[i + 1]);
  }
}

/* The condense pairs: every owned slave node's `dim` z with its `dim` displacement rows (self contact: the nodes on
 * no master-side face); in a paired row no other pair's z, the own D_jj block diagonal and nonzero. */
static void check_pairs(const kit *k, const double *J) {
  const int64_t n = k->n, nd = k->n_dofs;
  SK_CHECK(k->pair_block == k->dim);
  int64_t expected = k->layout.n_extra;
  if (k->instance->self)
    for (int j = 0; j < k->instance->slave->n_nodes; ++j) expected -= k->dim * k->instance->on_master[j];
  SK_CHECK(k->n_pairs == expected);
  int bad = 0;
  for (int64_t p = 0; p < k->n_pairs; ++p) {
    const int64_t row = k->pair_row[p], own = nd + k->pair_extra[p];
    for (int64_t q = 0; q < k->n_pairs; ++q) {
      const double v = J[row * n + nd + k->pair_extra[q]];
      if (q == p) bad += v <= 0.0; /* D_jj = int Phi_j > 0 (the sign of F1: + D^T z on the slave) */
      else bad += v != 0.0;
    }
    bad += J[row * n + own] == 0.0;
  }
  printf("    %lld pairs in blocks of %d, %d violations\n", (long long)k->n_pairs, k->pair_block, bad);
  SK_CHECK(bad == 0);
}

typedef struct {
  const char *label;
  int dim, with_master, strategy;
  const sk_obstacle *obstacle;
  const char *const *kv;
  double tol; /* 0: the common 1e-8 */
} fd_case;

/* First-order pairs run the narrow copy of the evaluation (36 derivative slots, narrow.c): its residual and Jacobian
 * equal the wide copy's (81 slots) to the bit. The record of the integrals is dropped before each pass, so that both
 * copies integrate. */
static void check_narrow_equals_wide(kit *k, const double *q) {
  const size_t n = (size_t)k->n;
  double *F[2], *J[2];
  for (int wide = 0; wide < 2; ++wide) {
    F[wide] = calloc(n, sizeof(double));
    J[wide] = calloc(n * n, sizeof(double));
    k->instance->narrow = !wide;
    k->instance->cache_valid = 0;
    SK_CHECK(kit_residual(k, q, F[wide]) == SK_OK);
    k->instance->cache_valid = 0;
    SK_CHECK(kit_jacobian(k, q, J[wide], NULL) == SK_OK);
  }
  k->instance->narrow = 1;
  const int same_f = memcmp(F[0], F[1], sizeof(double) * n) == 0;
  const int same_j = memcmp(J[0], J[1], sizeof(double) * n * n) == 0;
  printf("    narrow copy against wide: residual %s, Jacobian %s (%zu unknowns)\n", same_f ? "equal" : "DIFFERENT",
         same_j ? "equal" : "DIFFERENT", n);
  SK_CHECK(same_f && same_j);
  for (int wide = 0; wide < 2; ++wide) {
    free(F[wide]);
    free(J[wide]);
  }
}

/* 2D, saddle point: the slip-branch nodes whose trial traction v = z_t + c_t s points against their z_t (the state of
 * docs/plugins/mortar-dual.md, "c_t too large against the friction bound": c_t |s| above the bound, the sign of v set
 * by the slip). In the slip branch C_T = z_t - r v/|v| with r > 0, so sign(v) = sign(z_t - C_T), C_T from the
 * residual's tangential row (A_j C_T, Cartesian places under saddle point). */
static int count_opposed_slip(kit *k, const double *q) {
  const sk_instance *inst = k->instance;
  double *F = calloc((size_t)k->n, sizeof(double));
  SK_CHECK(kit_residual(k, q, F) == SK_OK);
  int opposed = 0;
  for (int i = 0; i < inst->n_owned; ++i) {
    const owned_node *o = &inst->owned[i];
    if (o->state != MORTAR_SLIP) continue;
    double tau[2][3], dtau[2][3][3];
    SK_CHECK(mortar_tangents(2, inst->normal + 3 * o->node, o->ref, tau, dtau) == 0);
    const double zt = tau[0][0] * o->z[0] + tau[0][1] * o->z[1];
    const double ct = F[k->n_dofs + o->extra + 1] / o->A_ref;
    opposed += zt * (zt - ct) < 0.0;
  }
  free(F);
  return opposed;
}

static double check_case(const fd_case *c, int *opposed) {
  kit k;
  if (c->dim == 3 && c->with_master == 2) mesh_3d_matching(&k);
  else if (c->dim == 3 && c->with_master == 6) mesh_3d_quad9(&k);
  else if (c->dim == 3 && c->with_master == 7) mesh_3d_tri6(&k);
  else if (c->dim == 3 && c->with_master == 8) mesh_3d_quad8(&k);
  else if (c->dim == 3 && c->with_master == 9) mesh_3d_self(&k, SK_QUAD9);
  else if (c->dim == 3 && c->with_master >= 4) mesh_3d_self(&k, c->with_master == 4 ? SK_QUAD4 : SK_TRI3);
  else if (c->dim == 3) mesh_3d(&k);
  else if (c->with_master == 3) mesh_2d_line3(&k);
  else if (c->with_master == 4) mesh_2d_self(&k);
  else mesh_2d(&k, c->with_master);
  if (c->obstacle) kit_obstacle(&k, c->obstacle);
  params(&k, c->kv);
  SK_CHECK(kit_create(&k, stickslip_plugin_entry(), c->strategy) == SK_OK);
  /* the committed step at the reference positions, z = 0 */
  kit_state(&k, k.X, k.X, 0.0, 0.0, NULL);
  SK_CHECK(kit_begin(&k) == SK_OK);
  SK_CHECK(kit_commit(&k) == SK_OK);
  /* the new step: positions perturbed by up to 0.002, compressive z with a tangential part */
  double q[162];
  unsigned long long seed = 12345;
  const int dim = c->dim;
  for (int i = 0; i < k.n_dofs; ++i) {
    seed = seed * 6364136223846793005ull + 1442695040888963407ull;
    q[i] = k.X[i] + 0.004 * ((double)(seed >> 11) / 9007199254740992.0 - 0.5);
  }
  kit_state(&k, k.X, q, 0.0, 1.0, NULL);
  SK_CHECK(kit_begin(&k) == SK_OK);
  for (int64_t e = 0; e < k.layout.n_extra; ++e) {
    seed = seed * 6364136223846793005ull + 1442695040888963407ull;
    const double r = (double)(seed >> 11) / 9007199254740992.0 - 0.5;
    k.extra[e] = e % dim == dim - 1 ? -(1.0 + r) : 0.6 * r; /* slave normal ~ -e_dim: z_n = n.z > 0 */
  }
  int changed = 0;
  SK_CHECK(kit_update_active_set(&k, q, &changed) == SK_OK);
  double scale = 0.0;
  const double err = kit_fd_check(&k, q, FD_STEP, &scale) / scale;
  int states[3] = {0, 0, 0};
  for (int i = 0; i < k.instance->n_owned; ++i) ++states[k.instance->owned[i].state];
  printf("  %s: |J - FD| / max|J| = %.2e (max|J| %.2e), inactive/stick/slip %d/%d/%d, outside pattern %lld\n",
         c->label, err, scale, states[0], states[1], states[2], (long long)k.outside_pattern);
  *opposed = dim == 2 && c->strategy == STRATEGY_SADDLE_POINT ? count_opposed_slip(&k, q) : 0;
  if (*opposed) printf("    %d slip nodes with v = z_t + c_t s against z_t\n", *opposed);
  /* measured 2.9e-9 at worst on the non-matching meshes (3D segments, friction). The nearly matching quad4 pair is
   * consistent too, but its residual is sharply curved on the scale of the edge offsets (nearly parallel slave and
   * master edges cross far out): |J - FD| falls as h^2, 6.8e-5, 6.8e-7, 1.1e-8 at h = 1e-5, 1e-6, 1e-7 */
  SK_CHECK(err < (c->tol > 0.0 ? c->tol : 1e-8));
  SK_CHECK(k.outside_pattern == 0);
  if (k.instance->narrow) check_narrow_equals_wide(&k, q);
  SK_CHECK(scale > 0.0);
  SK_CHECK(states[1] + states[2] > 0);
  if (k.instance->self) {
    /* the top wall and the right end's upper face slave (face 0 seeds the colouring), the lower one and the bottom
     * wall master, the left end idle (no face within reach); node 4 at the right end's tip lies on a slave and a
     * master face: its z is not condensed. In 3D the same per 2D segment (its quad4, its two tri3), at both ends of
     * the extrusion (nodes 4 and 13), except the left end: its quad4 and one of its tri3 reach bottom-wall faces
     * within the search margin (the mean edge, 0.28 here), so they are slave too (inactive, far off; their
     * grazing projections make the quad4 case's |J - FD| fall as h^2: 3.6e-7, 3.6e-9 at h = 1e-6, 1e-7); on QUAD9
     * faces the left end is idle, as in 2D (its faces' segments with the bottom wall lie beyond the margin). */
    const char *sides = dim == 2 || k.instance->slave->cell_type == SK_QUAD9 ? "SSSSMMMMI"
                        : k.instance->slave->n_cells == 9           ? "SSSSMMMMS"
                                                                    : "SSSSSSSSMMMMMMMMIS";
    char got[19] = "";
    for (int f = 0; f < k.instance->slave->n_cells; ++f) got[f] = "ISM"[k.instance->role[f]];
    printf("    sides %s, face pairs", got);
    for (int e = 0; e < k.instance->n_edge; ++e) printf(" %d-%d", k.instance->edge[2 * e], k.instance->edge[2 * e + 1]);
    printf("\n");
    SK_CHECK(strcmp(got, sides) == 0);
    SK_CHECK(k.instance->on_master[4] && !k.instance->on_master[1]);
    if (dim == 3) SK_CHECK(k.instance->on_master[13] && !k.instance->on_master[10]);
  }
  if (c->strategy == STRATEGY_CONDENSED) {
    double *J = calloc((size_t)(k.n * k.n), sizeof(double));
    SK_CHECK(kit_jacobian(&k, q, J, NULL) == SK_OK);
    check_pairs(&k, J);
    free(J);
  }
  kit_free(&k);
  return err;
}

/* Strategy and basis names as the host passes them; errors that name the problem. */
static void check_errors(void) {
  kit k;
  mesh_2d(&k, 1);
  kit_param_text(&k, "basis", "standard");
  SK_CHECK(kit_create(&k, stickslip_plugin_entry(), STRATEGY_CONDENSED) == SK_ERR_INPUT);
  SK_CHECK(strstr(sk_error_message(), "needs basis: dual") != NULL);
  kit_free(&k);
  mesh_2d(&k, 1);
  kit_param_text(&k, "normal", "M");
  SK_CHECK(kit_create(&k, stickslip_plugin_entry(), STRATEGY_SADDLE_POINT) == SK_ERR_INPUT);
  SK_CHECK(strstr(sk_error_message(), "concentrated") != NULL);
  kit_free(&k);
  /* transform_alpha: the transformed functions' integrals must stay positive (QUAD8 vertices: alpha > 1/8) */
  mesh_3d_quad8(&k);
  kit_param(&k, "transform_alpha", 0.1);
  SK_CHECK(kit_create(&k, stickslip_plugin_entry(), STRATEGY_SADDLE_POINT) == SK_ERR_INPUT);
  SK_CHECK(strstr(sk_error_message(), "transform_alpha must lie in (0.125, 0.5) on QUAD8") != NULL);
  kit_free(&k);
  mesh_3d_tri6(&k);
  kit_param(&k, "transform_alpha", 0.5);
  SK_CHECK(kit_create(&k, stickslip_plugin_entry(), STRATEGY_SADDLE_POINT) == SK_ERR_INPUT);
  SK_CHECK(strstr(sk_error_message(), "transform_alpha must lie in (0, 0.5) on TRI6") != NULL);
  kit_free(&k);
  mesh_2d(&k, 1); /* LINE2 faces: no transformed basis, the key is refused rather than ignored */
  kit_param(&k, "transform_alpha", 0.1);
  SK_CHECK(kit_create(&k, stickslip_plugin_entry(), STRATEGY_SADDLE_POINT) == SK_ERR_INPUT);
  SK_CHECK(strstr(sk_error_message(), "transform_alpha applies to TRI6 and QUAD8") != NULL);
  kit_free(&k);
}

/* Self contact at check (sk_plugin.check): on one rank it runs, in 2D and on 3D first-order and QUAD9 faces, with
 * and without friction; several ranks, and TRI6 and QUAD8 faces, are refused with the reason. */
static void check_self_refusals(void) {
  const sk_plugin *plugin = stickslip_plugin_entry();
  SK_CHECK((plugin->caps & SK_CAP_SELF_CONTACT) != 0);
  sk_scene_side side = {.struct_size = sizeof side, .name = "inner", .body = 0, .body_name = "ring",
                        .E = 1e4, .nu = 0.3, .cell_type = SK_LINE2, .order = 1};
  sk_scene_info info = {.struct_size = sizeof info, .kind = SK_KIND_PAIR, .name = "self", .dim = 2,
                        .scheme = "quasi-static", .alpha = 1.0, .n_ranks = 1, .self_contact = 1, .slave = &side,
                        .master = &side};
  char reason[300] = "";
  SK_CHECK(plugin->check(&info, reason, sizeof reason) == SK_OK);
  for (int t = 0; t < 6; ++t) {
    sk_scene_side s3 = side;
    s3.cell_type = t >= 4 ? SK_QUAD9 : t % 2 ? SK_TRI3 : SK_QUAD4;
    sk_scene_info c = info;
    c.dim = 3;
    c.friction = t / 2;
    c.slave = c.master = &s3;
    SK_CHECK(plugin->check(&c, reason, sizeof reason) == SK_OK);
  }
  static const struct {
    int dim, ranks, friction;
    sk_elem_type type;
    const char *says;
  } refused[] = {{2, 2, 0, SK_LINE2, "one rank"},
                 {3, 2, 1, SK_QUAD4, "one rank"},
                 {3, 1, 0, SK_TRI6, "TRI6"},
                 {3, 1, 0, SK_QUAD8, "QUAD8"}};
  for (size_t i = 0; i < sizeof refused / sizeof refused[0]; ++i) {
    sk_scene_side s = side;
    s.cell_type = refused[i].type;
    sk_scene_info c = info;
    c.dim = refused[i].dim;
    c.n_ranks = refused[i].ranks;
    c.friction = refused[i].friction;
    c.slave = c.master = &s;
    reason[0] = '\0';
    SK_CHECK(plugin->check(&c, reason, sizeof reason) == SK_ERR_PLUGIN);
    SK_CHECK(strstr(reason, refused[i].says) != NULL);
    printf("  self contact refused: %s\n", reason);
  }
}

int main(void) {
  sk_obstacle line, circle;
  memset(&line, 0, sizeof line);
  line.kind = SK_OBSTACLE_PLANE; /* y = -0.002, moving along x by 0.01 per unit time */
  line.point[1] = -0.002;
  line.normal[1] = 1.0;
  line.n_motion = 2;
  line.motion_t[1] = 1.0;
  line.motion_d[1][0] = 0.01;
  circle = line;
  circle.kind = SK_OBSTACLE_SPHERE; /* a circle of radius 1.998 centred 2 below x = 0.5 */
  circle.point[0] = 0.5;
  circle.point[1] = -2.0;
  circle.radius = 1.998;
  static const char *const dual[] = {"mu", "0.3", "c_n", "30", NULL};
  static const char *const standard[] = {"mu", "0.3", "c_n", "30", "basis", "standard", NULL};
  static const char *const frictionless[] = {"c_n", "30", NULL};
  static const char *const frictionless_std[] = {"c_n", "30", "basis", "standard", NULL};
  static const char *const slip[] = {"mu", "0.05", "c_n", "30", NULL};
  static const char *const con_a[] = {"mu", "0.3", "c_n", "30", "integration", "concentrated", NULL};
  static const char *const con_m[] = {"mu", "0.3", "c_n", "30", "integration", "concentrated", "normal", "M", NULL};
  static const char *const con_3d[] = {"mu", "0.3", "c_n", "30", "integration", "concentrated", "face_gauss", "3",
                                       NULL};
  static const char *const self[] = {"c_n", "30", "self_exclusion", "0.008", NULL};
  static const char *const self_stick[] = {"mu", "0.3", "c_n", "30", "self_exclusion", "0.008", NULL};
  static const char *const self_slip[] = {"mu", "0.05", "c_n", "30", "self_exclusion", "0.008", NULL};
  const fd_case cases[] = {
      {"2D self contact (slot), frictionless", 2, 4, STRATEGY_SADDLE_POINT, NULL, self, 0.0},
      {"2D self contact (slot), frictionless (condensed)", 2, 4, STRATEGY_CONDENSED, NULL, self, 0.0},
      {"3D self contact (slot), quad4, frictionless", 3, 4, STRATEGY_SADDLE_POINT, NULL, self, 0.0},
      {"3D self contact (slot), tri3, frictionless (condensed)", 3, 5, STRATEGY_CONDENSED, NULL, self, 0.0},
      {"2D self contact (slot), mu 0.3", 2, 4, STRATEGY_SADDLE_POINT, NULL, self_stick, 0.0},
      {"2D self contact (slot), mu 0.05 (condensed)", 2, 4, STRATEGY_CONDENSED, NULL, self_slip, 0.0},
      {"3D self contact (slot), quad4, mu 0.3", 3, 4, STRATEGY_SADDLE_POINT, NULL, self_stick, 0.0},
      {"3D self contact (slot), tri3, mu 0.05 (condensed)", 3, 5, STRATEGY_CONDENSED, NULL, self_slip, 0.0},
      {"2D segments dual, mu 0.3", 2, 1, STRATEGY_SADDLE_POINT, NULL, dual, 0.0},
      {"2D segments dual, mu 0.3 (condensed)", 2, 1, STRATEGY_CONDENSED, NULL, dual, 0.0},
      {"2D segments dual, mu 0.05 (condensed)", 2, 1, STRATEGY_CONDENSED, NULL, slip, 0.0},
      {"2D segments standard, mu 0.3", 2, 1, STRATEGY_SADDLE_POINT, NULL, standard, 0.0},
      {"2D segments dual frictionless (condensed)", 2, 1, STRATEGY_CONDENSED, NULL, frictionless, 0.0},
      {"2D concentrated A, mu 0.3", 2, 1, STRATEGY_SADDLE_POINT, NULL, con_a, 0.0},
      {"2D concentrated M, mu 0.3", 2, 1, STRATEGY_SADDLE_POINT, NULL, con_m, 0.0},
      {"2D moving line obstacle, mu 0.3", 2, 0, STRATEGY_SADDLE_POINT, &line, dual, 0.0},
      {"2D moving circle obstacle, mu 0.3 (condensed)", 2, 0, STRATEGY_CONDENSED, &circle, dual, 0.0},
      {"2D segments line3 dual, mu 0.3", 2, 3, STRATEGY_SADDLE_POINT, NULL, dual, 0.0},
      {"2D segments line3 dual, mu 0.3 (condensed)", 2, 3, STRATEGY_CONDENSED, NULL, dual, 0.0},
      {"2D segments line3 dual, mu 0.05 (condensed)", 2, 3, STRATEGY_CONDENSED, NULL, slip, 0.0},
      {"2D segments line3 standard frictionless", 2, 3, STRATEGY_SADDLE_POINT, NULL, frictionless_std, 0.0},
      {"2D concentrated line3 A, mu 0.3", 2, 3, STRATEGY_SADDLE_POINT, NULL, con_a, 0.0},
      {"3D segments quad4/tri3 dual, mu 0.3", 3, 1, STRATEGY_SADDLE_POINT, NULL, dual, 0.0},
      {"3D segments quad4/tri3 dual, mu 0.3 (condensed)", 3, 1, STRATEGY_CONDENSED, NULL, dual, 0.0},
      {"3D segments quad4/tri3 standard frictionless", 3, 1, STRATEGY_SADDLE_POINT, NULL, frictionless_std, 0.0},
      {"3D concentrated A, mu 0.3", 3, 1, STRATEGY_SADDLE_POINT, NULL, con_3d, 0.0},
      {"3D segments quad4/quad4 matching dual frictionless", 3, 2, STRATEGY_SADDLE_POINT, NULL, frictionless, 1.5e-8},
      {"3D segments quad4/quad4 matching dual, mu 0.3 (condensed)", 3, 2, STRATEGY_CONDENSED, NULL, dual, 1.5e-8},
  };
  /* QUAD9 pairs (16 quarter pairs each, 99 unknowns: about 2 s of CPU a case) run as their own test,
   * test_mortar_assembled_quad9 (this file with MORTAR_ASSEMBLED_QUAD9 = 1). Measured |J - FD| / max|J|: 3.7e-9 (stick
   * and slip), 1.7e-9 (slip, condensed). */
  const fd_case quad9_cases[] = {
      {"3D segments quad9/quad9 dual, mu 0.3", 3, 6, STRATEGY_SADDLE_POINT, NULL, dual, 0.0},
      {"3D segments quad9/quad9 dual, mu 0.05 (condensed)", 3, 6, STRATEGY_CONDENSED, NULL, slip, 0.0},
  };
  /* A QUAD9 self pair (the slot on 9 QUAD9 faces, 54 nodes, 324 unknowns: about 5 s of CPU) runs as its own test,
   * test_mortar_assembled_quad9_self (MORTAR_ASSEMBLED_QUAD9 = 2). Measured |J - FD| / max|J| 2.0e-9. */
  const fd_case quad9_self_cases[] = {
      {"3D self contact (slot), quad9, mu 0.3", 3, 9, STRATEGY_SADDLE_POINT, NULL, self_stick, 0.0},
  };
  /* TRI6 pairs (the dual basis of the transformed functions, D not diagonal: saddle point only) run as their own
   * test, test_mortar_assembled_tri6 (MORTAR_ASSEMBLED_TRI6 = 1) */
  const fd_case tri6_cases[] = {
      {"3D segments tri6/tri6 dual, mu 0.3", 3, 7, STRATEGY_SADDLE_POINT, NULL, dual, 0.0},
      {"3D segments tri6/tri6 dual, mu 0.05", 3, 7, STRATEGY_SADDLE_POINT, NULL, slip, 0.0},
      {"3D segments tri6/tri6 standard frictionless", 3, 7, STRATEGY_SADDLE_POINT, NULL, frictionless_std, 0.0},
  };
  /* QUAD8 pairs (the same, on the quarters that meet at the serendipity map's centre) run as their own test,
   * test_mortar_assembled_quad8 (MORTAR_ASSEMBLED_QUAD8 = 1) */
  const fd_case quad8_cases[] = {
      {"3D segments quad8/quad8 dual, mu 0.3", 3, 8, STRATEGY_SADDLE_POINT, NULL, dual, 0.0},
      {"3D segments quad8/quad8 dual, mu 0.05", 3, 8, STRATEGY_SADDLE_POINT, NULL, slip, 0.0},
      {"3D segments quad8/quad8 standard frictionless", 3, 8, STRATEGY_SADDLE_POINT, NULL, frictionless_std, 0.0},
  };
  const fd_case *list = MORTAR_ASSEMBLED_QUAD8  ? quad8_cases
                        : MORTAR_ASSEMBLED_TRI6 ? tri6_cases
                        : MORTAR_ASSEMBLED_QUAD9 == 2 ? quad9_self_cases
                        : MORTAR_ASSEMBLED_QUAD9 ? quad9_cases
                                                 : cases;
  const size_t n_cases = MORTAR_ASSEMBLED_QUAD8   ? sizeof quad8_cases / sizeof quad8_cases[0]
                         : MORTAR_ASSEMBLED_TRI6  ? sizeof tri6_cases / sizeof tri6_cases[0]
                         : MORTAR_ASSEMBLED_QUAD9 == 2 ? sizeof quad9_self_cases / sizeof quad9_self_cases[0]
                         : MORTAR_ASSEMBLED_QUAD9 ? sizeof quad9_cases / sizeof quad9_cases[0]
                                                  : sizeof cases / sizeof cases[0];
  double worst = 0.0;
  int opposed = 0;
  for (size_t i = 0; i < n_cases; ++i) worst = fmax(worst, check_case(&list[i], &opposed));
  printf("worst |J - FD| / max|J| over %zu cases: %.2e\n", n_cases, worst);
  if (!MORTAR_ASSEMBLED_QUAD9 && !MORTAR_ASSEMBLED_TRI6 && !MORTAR_ASSEMBLED_QUAD8) {
    /* LINE3 faces (quad9, quad8) in the slip branch with c_t |s| far above the friction bound: the sign of the trial
     * traction v = z_t + c_t s is the slip's, against z_t at some nodes (the state in which the slip direction cycles,
     * docs/plugins/mortar-dual.md, "c_t"); there the tangent must take the sign of v, not of z_t. Measured: all 5
     * nodes slip, 2 of them against z_t, |J - FD| / max|J| = 9.2e-10 under both strategies */
    static const char *const slip_stiff[] = {"mu", "0.05", "c_n", "30", "c_t", "3000", NULL};
    const fd_case against[] = {
        {"2D segments line3 dual, mu 0.05, c_t 3000", 2, 3, STRATEGY_SADDLE_POINT, NULL, slip_stiff, 0.0},
        {"2D segments line3 dual, mu 0.05, c_t 3000 (condensed)", 2, 3, STRATEGY_CONDENSED, NULL, slip_stiff, 0.0},
    };
    SK_CHECK(check_case(&against[0], &opposed) < 1e-8);
    SK_CHECK(opposed > 0);
    SK_CHECK(check_case(&against[1], &opposed) < 1e-8);
    check_errors();
    check_self_refusals();
  }
  return sk_test_finish(MORTAR_ASSEMBLED_QUAD8   ? "test_mortar_assembled_quad8"
                        : MORTAR_ASSEMBLED_TRI6  ? "test_mortar_assembled_tri6"
                        : MORTAR_ASSEMBLED_QUAD9 == 2 ? "test_mortar_assembled_quad9_self"
                        : MORTAR_ASSEMBLED_QUAD9 ? "test_mortar_assembled_quad9"
                                                 : "test_mortar_assembled");
}
