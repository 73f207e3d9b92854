/* Scene → model: every key of docs/scene-reference.md is read here, and every error names the file, line and key. */
#define _GNU_SOURCE
#include "stickslip/scene.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "contact_partition.h"
#include "master_ghosts.h"
#include "scene_info.h"
#include "scene_internal.h"
#include "stickslip/plugins.h"
#include "system.h"

/* ---- helpers -------------------------------------------------------------------------------------------------- */

sk_status sk_scene_fail_at(const sk_cfg *node, const char *fmt, const char *detail) {
  char message[1024];
  snprintf(message, sizeof message, fmt, detail);
  return sk_error_set(SK_ERR_INPUT, "%s: key '%s': %s", sk_cfg_where(node), sk_cfg_path(node), message);
}

void sk_scene_copy_name(char *dst, const char *src) {
  snprintf(dst, SK_NAME_MAX, "%s", src);
}

/* A history: a sequence of [t, value] pairs, strictly increasing in t. Absent → the constant 1. */
static sk_status read_history(const sk_cfg *map, const char *key, sk_history *history) {
  history->n = 0;
  const sk_cfg *node = sk_cfg_get(map, key);
  sk_cfg_note_default(map, key, "constant 1", 0, NULL);
  if (!node) return SK_OK;
  int n = sk_cfg_size(node);
  if (sk_cfg_kind_of(node) != SK_CFG_SEQ || n < 1)
    return sk_scene_fail_at(node, "%s", "expects a list of [time, value] pairs, e.g. [[0, 0], [1, 1]]");
  if (n > SK_HISTORY_MAX) return sk_scene_fail_at(node, "%s", "has more points than the 64 supported");
  for (int k = 0; k < n; ++k) {
    const sk_cfg *pair = sk_cfg_at(node, k);
    if (sk_cfg_kind_of(pair) != SK_CFG_SEQ || sk_cfg_size(pair) != 2)
      return sk_scene_fail_at(pair, "%s", "expects a [time, value] pair");
    SK_TRY(sk_cfg_as_double(sk_cfg_at(pair, 0), &history->t[k]));
    SK_TRY(sk_cfg_as_double(sk_cfg_at(pair, 1), &history->v[k]));
    if (k > 0 && !(history->t[k] > history->t[k - 1]))
      return sk_scene_fail_at(pair, "%s", "times must increase strictly");
  }
  history->n = n;
  return SK_OK;
}

sk_status sk_scene_require_group(const sk_model *model, const sk_cfg *at, const char *name, int dim,
                               const sk_group **group) {
  sk_status status = sk_mesh_require_group(&model->mesh, name, dim, group);
  if (status != SK_OK) return sk_error_prefix(status, "%s: key '%s': ", sk_cfg_where(at), sk_cfg_path(at));
  return SK_OK;
}

/* ---- bodies ----------------------------------------------------------------------------------------------------- */

/* `plugin`, `strategy` and `parameters` of a body: a body plugin (kind "body", docs/plugin-abi.md §2). */
static sk_status read_body_plugin(const sk_cfg *entry, const sk_model *model, sk_body *body) {
  const char *plugin_name;
  SK_TRY(sk_cfg_string(entry, "plugin", 0, NULL, &plugin_name));
  sk_cfg_note_default(entry, "plugin", "none: the core integrates the body", 0, NULL);
  if (!plugin_name) {
    if (sk_cfg_get(entry, "strategy") || sk_cfg_get(entry, "parameters"))
      return sk_error_set(SK_ERR_INPUT, "%s: body '%s': `strategy` and `parameters` need a `plugin`",
                          sk_cfg_where(entry), body->name);
    return SK_OK;
  }
  sk_status status = sk_plugin_load(plugin_name, &body->plugin);
  if (status != SK_OK)
    return sk_error_prefix(status, "%s: body '%s': ", sk_cfg_where(sk_cfg_get(entry, "plugin")), body->name);
  SK_TRY(sk_scene_check_kind(sk_cfg_get(entry, "plugin"), body->plugin, SK_KIND_BODY, "body", body->name));
  SK_TRY(sk_scene_choose_strategy(entry, body->plugin, &body->strategy));
  body->params = sk_cfg_get(entry, "parameters");
  body->plugin_node = sk_cfg_get(entry, "plugin");
  char where[SK_NAME_MAX + 1200];
  snprintf(where, sizeof where, "%s: body '%s'", sk_cfg_where(entry), body->name);
  sk_scene_description description;
  sk_describe_body(model, (int)(body - model->bodies), &description);
  return sk_check_attachment(body->plugin, &description,
                             (model->dim == 2 ? SK_CAP_2D : SK_CAP_3D) | model->time.integrator->plugin_caps, where);
}

static sk_status read_bodies(const sk_cfg *root, sk_model *model) {
  const sk_cfg *list = sk_cfg_get(root, "bodies");
  if (!list || sk_cfg_kind_of(list) != SK_CFG_SEQ || sk_cfg_size(list) < 1)
    return sk_error_set(SK_ERR_INPUT, "%s: key 'bodies' must list at least one body", sk_cfg_where(list ? list : root));
  model->n_bodies = sk_cfg_size(list);
  model->bodies = calloc((size_t)model->n_bodies, sizeof(sk_body));
  if (!model->bodies) return sk_error_set(SK_ERR_NOMEM, "%s: out of memory for the bodies", sk_cfg_where(list));
  int first = 0;
  for (int b = 0; b < model->n_bodies; ++b) {
    const sk_cfg *entry = sk_cfg_at(list, b);
    sk_body *body = &model->bodies[b];
    const char *group_name, *name;
    SK_TRY(sk_cfg_string(entry, "group", 1, NULL, &group_name));
    SK_TRY(sk_cfg_string(entry, "name", 0, group_name, &name));
    sk_scene_copy_name(body->name, name);
    SK_TRY(sk_scene_require_group(model, sk_cfg_get(entry, "group"), group_name, model->dim, &body->group));
    const sk_cfg *material = sk_cfg_get(entry, "material");
    if (!material) return sk_error_set(SK_ERR_INPUT, "%s: body '%s' needs a `material`", sk_cfg_where(entry), name);
    int choice;
    sk_material_model kind;
    double E, nu, density;
    SK_TRY(sk_cfg_choice(material, "model", 1, sk_material_model_names, 0, &choice));
    SK_TRY(sk_material_model_from_name(sk_material_model_names[choice], &kind));
    SK_TRY(sk_cfg_double(material, "E", 1, 0, &E));
    SK_TRY(sk_cfg_double(material, "nu", 1, 0, &nu));
    SK_TRY(sk_cfg_double(material, "density", model->time.integrator->dynamic, 0, &density));
    sk_status status = sk_material_init(&body->material, kind, E, nu, density);
    if (status != SK_OK) {
      /* name the value at fault where it was given (a line of the file, or --set bodies.0.material.E): the one
       * check, sk_material_init, tells which by failing with the others set to harmless values */
      const char *culprit = sk_material_init(&body->material, kind, E, 0.0, 0.0) != SK_OK    ? "E"
                            : sk_material_init(&body->material, kind, E, nu, 0.0) != SK_OK ? "nu"
                                                                                            : "density";
      sk_material_init(&body->material, kind, E, nu, density); /* the first failure's message again */
      const sk_cfg *at = sk_cfg_get(material, culprit);
      return sk_error_prefix(status, "%s: body '%s': ", sk_cfg_where(at ? at : material), name);
    }
    body->solid.type = body->group->type;
    body->solid.dim = model->dim;
    body->solid.mat = &body->material;
    SK_TRY(sk_cfg_vector(entry, "velocity", 0, 3, (double[3]){0, 0, 0}, body->velocity));
    SK_TRY(sk_cfg_vector(entry, "angular_velocity", 0, 3, (double[3]){0, 0, 0}, body->angular_velocity));
    SK_TRY(sk_cfg_vector(entry, "center", 0, 3, (double[3]){0, 0, 0}, body->center));
    body->first_element = first;
    body->integrator = model->time.integrator;
    first += body->group->n_elems;
    SK_TRY(read_body_plugin(entry, model, body));
  }
  model->n_elements = first;
  /* two bodies on one group, or on overlapping groups, would count the same elements twice */
  const sk_group **groups = calloc((size_t)model->n_bodies, sizeof *groups);
  char (*labels)[SK_NAME_MAX + 16] = calloc((size_t)model->n_bodies, sizeof *labels);
  const char **names = calloc((size_t)model->n_bodies, sizeof *names);
  sk_status status = groups && labels && names ? SK_OK : sk_error_set(SK_ERR_NOMEM, "out of memory");
  for (int b = 0; b < model->n_bodies && status == SK_OK; ++b) {
    groups[b] = model->bodies[b].group;
    snprintf(labels[b], sizeof labels[b], "body '%s'", model->bodies[b].name);
    names[b] = labels[b];
  }
  if (status == SK_OK) status = sk_mesh_check_disjoint(&model->mesh, groups, names, model->n_bodies);
  free(groups);
  free(labels);
  free(names);
  if (status != SK_OK) return sk_error_prefix(status, "%s: ", sk_cfg_where(list));
  return SK_OK;
}

/* ---- boundary conditions ---------------------------------------------------------------------------------------- */

/* Two displacement conditions that fix the same dof must prescribe it alike at every time (two fixed faces sharing
 * an edge). Different values would leave the result to the order of the list, silently. Both values are piecewise
 * linear in time and constant beyond their histories' ends, so the union of the breakpoints decides. */
static sk_status read_conditions(const sk_cfg *list, int n, int *entry_of, sk_model *model);

static int prescribe_alike(const sk_dirichlet *a, const sk_dirichlet *b, int i, double *t_differ) {
  const sk_history *h[2] = {&a->history, &b->history};
  for (int side = 0; side < 2; ++side)
    for (int k = 0; k < (h[side]->n > 0 ? h[side]->n : 1); ++k) {
      const double t = h[side]->n > 0 ? h[side]->t[k] : 0.0;
      const double va = a->value[i] * sk_history_value(&a->history, t);
      const double vb = b->value[i] * sk_history_value(&b->history, t);
      if (fabs(va - vb) > 1e-12 * fmax(fabs(va), fabs(vb))) {
        *t_differ = t;
        return 0;
      }
    }
  return 1;
}

static sk_status check_dirichlet_overlaps(const sk_cfg *list, const int *entry_of, const sk_model *model) {
  const int dim = model->dim, n_bc = model->n_dirichlet;
  int *first = malloc(sizeof(int) * (size_t)(model->n_dofs > 0 ? model->n_dofs : 1));
  if (!first) return sk_error_set(SK_ERR_NOMEM, "out of memory checking the boundary conditions");
  for (int d = 0; d < model->n_dofs; ++d) first[d] = -1;
  sk_status status = SK_OK;
  for (int k = 0; k < n_bc && status == SK_OK; ++k) {
    const sk_dirichlet *bc = &model->dirichlet[k];
    for (int j = 0; j < bc->n_nodes && status == SK_OK; ++j)
      for (int i = 0; i < dim && status == SK_OK; ++i) {
        const int d = bc->nodes[j] * dim + i;
        if (!bc->fixed[i]) continue;
        if (first[d] < 0) {
          first[d] = k;
          continue;
        }
        const sk_dirichlet *before = &model->dirichlet[first[d]];
        double t = 0.0;
        if (first[d] == k || prescribe_alike(before, bc, i, &t)) continue;
        const double *X = model->X + (int64_t)bc->nodes[j] * dim;
        status = sk_error_set(SK_ERR_INPUT, "%s: boundary '%s' and boundary '%s' (%s) prescribe different %c "
                              "displacements on the nodes they share, e.g. the node at (%g, %g, %g): %g against %g "
                              "at t = %g; free the component in one of them (~)",
                              sk_cfg_where(sk_cfg_at(list, entry_of[k])), bc->name, before->name,
                              sk_cfg_where(sk_cfg_at(list, entry_of[first[d]])), "xyz"[i], X[0], X[1],
                              dim == 3 ? X[2] : 0.0, bc->value[i] * sk_history_value(&bc->history, t),
                              before->value[i] * sk_history_value(&before->history, t), t);
      }
  }
  free(first);
  return status;
}

static sk_status read_boundary(const sk_cfg *root, sk_model *model) {
  const sk_cfg *list = sk_cfg_get(root, "boundary");
  int n = sk_cfg_size(list);
  if (list && sk_cfg_kind_of(list) != SK_CFG_SEQ) return sk_scene_fail_at(list, "%s", "expects a list of conditions");
  model->dirichlet = calloc((size_t)(n > 0 ? n : 1), sizeof(sk_dirichlet));
  model->tractions = calloc((size_t)(n > 0 ? n : 1), sizeof(sk_traction));
  model->resultants = calloc((size_t)(n > 0 ? n : 1), sizeof(sk_resultant));
  int *entry_of = malloc(sizeof(int) * (size_t)(n > 0 ? n : 1)); /* per displacement condition: its list entry */
  if (!model->dirichlet || !model->tractions || !model->resultants || !entry_of) {
    free(entry_of);
    return sk_error_set(SK_ERR_NOMEM, "%s: out of memory for the boundary conditions", sk_cfg_where(root));
  }
  sk_status status = read_conditions(list, n, entry_of, model);
  if (status == SK_OK) status = check_dirichlet_overlaps(list, entry_of, model);
  free(entry_of);
  SK_TRY(status);
  SK_TRY(sk_cfg_vector(root, "body_force", 0, 3, (double[3]){0, 0, 0}, model->body_force));
  return SK_OK;
}

/* The entries of `boundary`, in order; entry_of[k] is the list entry of the k-th displacement condition. */
static sk_status read_conditions(const sk_cfg *list, int n, int *entry_of, sk_model *model) {
  for (int k = 0; k < n; ++k) {
    const sk_cfg *entry = sk_cfg_at(list, k);
    const char *group_name, *name;
    SK_TRY(sk_cfg_string(entry, "group", 1, NULL, &group_name));
    SK_TRY(sk_cfg_string(entry, "name", 0, group_name, &name));
    const sk_cfg *displacement = sk_cfg_get(entry, "displacement");
    const sk_cfg *traction = sk_cfg_get(entry, "traction");
    const sk_cfg *resultant = sk_cfg_get(entry, "resultant");
    if (!!displacement + !!traction + !!resultant != 1)
      return sk_error_set(SK_ERR_INPUT, "%s: boundary '%s' needs exactly one of `displacement`, `traction` or "
                          "`resultant`", sk_cfg_where(entry), name);
    if (!resultant && sk_cfg_get(entry, "area"))
      return sk_scene_fail_at(sk_cfg_get(entry, "area"), "%s", "belongs to a `resultant` condition");
    const sk_group *group;
    if (displacement) {
      SK_TRY(sk_scene_require_group(model, sk_cfg_get(entry, "group"), group_name, -1, &group));
      entry_of[model->n_dirichlet] = k;
      sk_dirichlet *bc = &model->dirichlet[model->n_dirichlet++];
      sk_scene_copy_name(bc->name, name);
      SK_TRY(sk_group_nodes(group, &bc->nodes, &bc->n_nodes));
      if (sk_cfg_kind_of(displacement) != SK_CFG_SEQ || sk_cfg_size(displacement) != model->dim)
        return sk_scene_fail_at(displacement, "expects %s components (a number, or ~ for a free component)",
                       model->dim == 2 ? "2" : "3");
      for (int i = 0; i < model->dim; ++i) {
        const sk_cfg *c = sk_cfg_at(displacement, i);
        const char *text = sk_cfg_scalar(c);
        if (text && (strcmp(text, "~") == 0 || strcmp(text, "null") == 0 || strcmp(text, "") == 0 ||
                     strcmp(text, "free") == 0))
          continue;
        bc->fixed[i] = 1;
        SK_TRY(sk_cfg_as_double(c, &bc->value[i]));
      }
      SK_TRY(read_history(entry, "history", &bc->history));
    } else if (resultant) {
      SK_TRY(sk_scene_require_group(model, sk_cfg_get(entry, "group"), group_name, model->dim - 1, &group));
      sk_resultant *load = &model->resultants[model->n_resultants++];
      sk_scene_copy_name(load->name, name);
      load->faces = group;
      SK_TRY(sk_cfg_vector(entry, "resultant", 1, model->dim, NULL, load->resultant));
      const char *area;
      SK_TRY(sk_cfg_string(entry, "area", 0, "reference", &area));
      if (strcmp(area, "reference") != 0 && strcmp(area, "current") != 0)
        return sk_scene_fail_at(sk_cfg_get(entry, "area"), "is '%s'; expected reference or current", area);
      load->current_area = strcmp(area, "current") == 0;
      SK_TRY(read_history(entry, "history", &load->history));
    } else {
      SK_TRY(sk_scene_require_group(model, sk_cfg_get(entry, "group"), group_name, model->dim - 1, &group));
      sk_traction *load = &model->tractions[model->n_tractions++];
      sk_scene_copy_name(load->name, name);
      load->faces = group;
      SK_TRY(sk_cfg_vector(entry, "traction", 1, model->dim, NULL, load->traction));
      SK_TRY(read_history(entry, "history", &load->history));
    }
  }
  return SK_OK;
}

/* ---- time, solver, output --------------------------------------------------------------------------------------- */

static sk_status read_time(const sk_cfg *root, sk_time_options *time) {
  const sk_cfg *node = sk_cfg_get(root, "time");
  if (!node) return sk_error_set(SK_ERR_INPUT, "%s: missing key 'time'", sk_cfg_where(root));
  int scheme;
  const char *const *scheme_names = sk_time_integrator_names();
  SK_TRY(sk_cfg_choice(node, "scheme", 1, scheme_names, 0, &scheme));
  time->integrator = sk_time_integrator_find(scheme_names[scheme]);
  SK_TRY(sk_cfg_double(node, "dt", 1, 0, &time->dt));
  SK_TRY(sk_cfg_double(node, "end", 1, 0, &time->t_end));
  SK_TRY(sk_cfg_double(node, "start", 0, 0, &time->t_start));
  SK_TRY(sk_cfg_int(node, "max_cuts", 0, 6, &time->max_cuts));
  if (!(time->dt > 0)) return sk_scene_fail_at(sk_cfg_get(node, "dt"), "%s", "must be positive");
  if (!(time->t_end > time->t_start)) return sk_scene_fail_at(sk_cfg_get(node, "end"), "%s", "must be larger than `start`");
  /* a step below the resolution of t would never advance it (t + dt == t): the run would loop forever */
  if (time->dt < 64 * DBL_EPSILON * fmax(fabs(time->t_start), fabs(time->t_end)))
    return sk_scene_fail_at(sk_cfg_get(node, "dt"), "%s", "is too small to advance the time between `start` and `end`");
  if (time->max_cuts < 0 || time->max_cuts > 30) return sk_scene_fail_at(sk_cfg_get(node, "max_cuts"), "%s", "must be 0..30");
  return SK_OK;
}

/* in sk_linear_solver_kind order */
static const char *const linear_names[] = {"direct", "gmres-muelu", "gmres-ilu", "auto",     "mumps",
                                           "klu2",   "klu",         "gmres-sgs", "gmres-jacobi", "gmres-lu", NULL};
/* in sk_line_search order, then the default: the full step, retried with backtracking when the step fails */
static const char *const line_search_names[] = {"full-step", "backtrack", "polynomial", "full-step-then-backtrack", NULL};
enum { FULL_STEP_THEN_BACKTRACK = 3 };
static const char *const predictor_names[] = {"last-state", "previous-increment", NULL};
/* in sk_linear_nullspace order */
static const char *const nullspace_names[] = {"rigid-body", "translations", NULL};

/* The decisions of solver.linear.solver `auto`, as information (not shown with --quiet). */
static void log_linear_decision(void *ctx, const char *line) {
  (void)ctx;
  sk_log_message(0, 0, "linear solver (auto): %s", line); /* the bridge calls it on rank 0 only */
}

/* The line search by default is the full Newton step, and a step whose Newton fails is solved again with backtracking
 * before it is cut: backtracking converges the frictional scenes a user writes from the scene reference where the
 * full step stalls in step 1, but as the only search it fails cases the full step runs (a graded patch test, mortar-dual
 * on stacked blocks) and costs iterations where the full step converges — docs/linear-solvers.md, "Line search". */
static sk_status read_solver(const sk_cfg *root, sk_solver_settings *solver) {
  const sk_cfg *node = sk_cfg_section(root, "solver");
  if (node && sk_cfg_kind_of(node) != SK_CFG_MAP)
    return sk_scene_fail_at(node, "%s", "expects a map with `newton` and/or `linear`");
  sk_newton_options_default(&solver->newton);
  sk_linear_options_default(&solver->linear);
  const sk_cfg *newton = sk_cfg_section(node, "newton");
  const sk_cfg *linear = sk_cfg_section(node, "linear");
  int line_search = FULL_STEP_THEN_BACKTRACK, kind = (int)solver->linear.kind;
  SK_TRY(sk_cfg_double(newton, "tolerance", 0, solver->newton.relative_tolerance, &solver->newton.relative_tolerance));
  SK_TRY(sk_cfg_double(newton, "absolute_tolerance", 0, solver->newton.residual_tolerance,
                       &solver->newton.residual_tolerance));
  SK_TRY(sk_cfg_double(newton, "update_tolerance", 0, solver->newton.update_tolerance,
                       &solver->newton.update_tolerance));
  SK_TRY(sk_cfg_int(newton, "max_iterations", 0, solver->newton.max_iterations, &solver->newton.max_iterations));
  SK_TRY(sk_cfg_choice(newton, "line_search", 0, line_search_names, line_search, &line_search));
  SK_TRY(sk_cfg_bool(newton, "verbose", 0, solver->newton.verbose, &solver->newton.verbose));
  SK_TRY(sk_cfg_bool(newton, "inexact", 0, solver->newton.forcing, &solver->newton.forcing));
  SK_TRY(sk_cfg_choice(newton, "predictor", 0, predictor_names, 0, &solver->predictor));
  /* off by default: accepting the predicted update saves a confirming solve per step (quasi-static Hertz 3D: 1-3
   * of 17-23 iterations) but lets runs that differ at round-off (ranks, partitions, patterns) stop one iteration
   * apart, 1e-10 from each other instead of 1e-13 (docs/hertz.md, "Newton iterations") */
  SK_TRY(sk_cfg_bool(newton, "predicted_update", 0, 0, &solver->newton.predicted_update));
  SK_TRY(sk_cfg_int(newton, "max_active_set_loops", 0, 10, &solver->max_active_set_loops));
  if (solver->max_active_set_loops < 1)
    return sk_scene_fail_at(sk_cfg_get(newton, "max_active_set_loops"), "%s", "must be at least 1");
  SK_TRY(sk_cfg_int(node, "pattern_margin", 0, 0, &solver->pattern_margin));
  if (solver->pattern_margin < 0 || solver->pattern_margin > 3)
    return sk_scene_fail_at(sk_cfg_get(node, "pattern_margin"), "%s", "must be 0..3");
  solver->backtrack_retry = line_search == FULL_STEP_THEN_BACKTRACK;
  solver->newton.line_search = solver->backtrack_retry ? SK_LINE_SEARCH_FULL_STEP : (sk_line_search)line_search;
  solver->newton.backtrack_on_no_progress = solver->backtrack_retry;
  SK_TRY(sk_cfg_choice(linear, "solver", 0, linear_names, kind, &kind));
  solver->linear.kind = (sk_linear_solver_kind)kind;
  solver->linear.log = log_linear_decision;
  SK_TRY(sk_cfg_double(linear, "tolerance", 0, solver->linear.tolerance, &solver->linear.tolerance));
  SK_TRY(sk_cfg_int(linear, "max_iterations", 0, solver->linear.max_iterations, &solver->linear.max_iterations));
  int nullspace = (int)solver->linear.nullspace;
  SK_TRY(sk_cfg_choice(linear, "nullspace", 0, nullspace_names, nullspace, &nullspace));
  solver->linear.nullspace = (sk_linear_nullspace)nullspace;
  if (!(solver->newton.relative_tolerance > 0) || !(solver->newton.residual_tolerance > 0))
    return sk_scene_fail_at(newton, "%s", "tolerances must be positive");
  if (solver->newton.max_iterations < 1) return sk_scene_fail_at(newton, "%s", "max_iterations must be at least 1");
  return SK_OK;
}

static sk_status read_output(const sk_cfg *root, sk_output_settings *output) {
  const sk_cfg *node = sk_cfg_section(root, "output");
  SK_TRY(sk_cfg_int(node, "vtu_every", 0, 10, &output->vtu_every));
  SK_TRY(sk_cfg_bool(node, "vtu", 0, 1, &output->write_vtu));
  SK_TRY(sk_cfg_bool(node, "contact_csv", 0, 1, &output->write_contact_csv));
  if (output->vtu_every < 0) return sk_scene_fail_at(sk_cfg_get(node, "vtu_every"), "%s", "must be >= 0");
  return SK_OK;
}

/* The contact partition (core/model/contact_partition.h): off by default (docs/scaling.md, "Contact partition"). */
static sk_status read_contact_balance(const sk_cfg *root, sk_model *model) {
  static const char *const names[] = {"off", "on", NULL};
  const sk_cfg *node = sk_cfg_section(root, "contact_balance");
  if (node && sk_cfg_kind_of(node) != SK_CFG_MAP) return sk_scene_fail_at(node, "%s", "expects a map with `rebalance`");
  SK_TRY(sk_cfg_choice(node, "rebalance", 0, names, 0, &model->contact_rebalance));
  SK_TRY(sk_cfg_double(node, "time_ratio", 0, 2.0, &model->rebalance_time_ratio));
  SK_TRY(sk_cfg_double(node, "entity_imbalance", 0, 0.5, &model->rebalance_entity_imbalance));
  if (!(model->rebalance_time_ratio >= 1.0))
    return sk_scene_fail_at(sk_cfg_get(node, "time_ratio"), "%s", "must be at least 1 (max / mean over the ranks)");
  if (!(model->rebalance_entity_imbalance >= 0.0 && model->rebalance_entity_imbalance <= 1.0))
    return sk_scene_fail_at(sk_cfg_get(node, "entity_imbalance"), "%s", "must be 0..1 ((max - min) / max)");
  return SK_OK;
}

/* ---- the whole scene -------------------------------------------------------------------------------------------- */

static sk_status build(sk_scene *scene) {
  sk_model *model = &scene->model;
  const sk_cfg *root = scene->cfg;
  const char *description;
  SK_TRY(sk_cfg_string(root, "description", 0, "", &description));
  snprintf(scene->description, sizeof scene->description, "%s", description);
  SK_TRY(read_time(root, &model->time));
  SK_TRY(read_solver(root, &scene->solver));
  SK_TRY(read_output(root, &scene->output));
  SK_TRY(sk_scene_load_meshes(root, &model->mesh));
  model->dim = model->mesh.dim;
  char from_mesh[32];
  snprintf(from_mesh, sizeof from_mesh, "from the mesh: %d", model->dim);
  sk_cfg_note_default(root, "dimension", from_mesh, 0, NULL);
  model->n_nodes = model->mesh.n_nodes;
  model->n_dofs = model->n_nodes * model->dim;
  model->X = malloc(sizeof(double) * (size_t)(model->n_dofs > 0 ? model->n_dofs : 1));
  if (!model->X) return sk_error_set(SK_ERR_NOMEM, "%s: out of memory for %d nodes", scene->path, model->n_nodes);
  for (int a = 0; a < model->n_nodes; ++a)
    for (int i = 0; i < model->dim; ++i) model->X[a * model->dim + i] = model->mesh.x[3 * a + i];
  SK_TRY(read_bodies(root, model));
  SK_TRY(read_boundary(root, model));
  SK_TRY(sk_scene_read_contact(root, scene));
  SK_TRY(read_contact_balance(root, model));
  SK_TRY(sk_model_build(model));
  SK_TRY(sk_model_distribute(model));
  /* The system of terms creates the plugin instances now, so that their parameters are validated (and read) before
   * the unknown-key check. */
  SK_TRY(sk_system_create(model, &scene->solver, &scene->system));
  return sk_cfg_check_unused(root);
}

sk_status sk_scene_load_with(const char *path, const sk_scene_overrides *overrides, MPI_Comm comm,
                             sk_scene *scene) {
  memset(scene, 0, sizeof *scene);
  snprintf(scene->path, sizeof scene->path, "%s", path);
  scene->model.comm = comm;
  MPI_Comm_rank(comm, &scene->model.rank);
  MPI_Comm_size(comm, &scene->model.n_ranks);
  SK_TRY(sk_cfg_load(path, &scene->cfg));
  SK_TRY(sk_scene_apply_overrides(scene, overrides));
  SK_TRY(build(scene));
  return sk_scene_absolute_mesh_paths(scene);
}

sk_status sk_scene_load(const char *path, int n_sets, const char *const *sets, const char *plugin_override,
                        MPI_Comm comm, sk_scene *scene) {
  sk_scene_overrides overrides = {.n = n_sets, .assignments = sets, .modes = NULL, .plugin = plugin_override};
  return sk_scene_load_with(path, &overrides, comm, scene);
}

void sk_scene_free(sk_scene *scene) {
  sk_system_destroy(scene->system);
  scene->system = NULL;
  sk_model_free(&scene->model);
  sk_cfg_free(scene->cfg);
  scene->cfg = NULL;
  free(scene->provenance);
  scene->provenance = NULL;
}

/* What Newton does with a step (solver.newton; `stickslip keys` shows where each value comes from). */
static void explain_newton(const sk_solver_settings *solver, FILE *out) {
  const sk_newton_options *n = &solver->newton;
  fprintf(out, "Newton (solver.newton):\n");
  if (solver->backtrack_retry)
    fprintf(out, "  %-16s %s: full Newton steps; a step whose Newton fails is solved again from its start with the "
            "backtracking line search, and cut only if that fails too; a full step that makes no progress for 4 "
            "iterations goes on with backtracking at once (docs/stability.md, finding 28)\n", "line_search",
            line_search_names[FULL_STEP_THEN_BACKTRACK]);
  else
    fprintf(out, "  %-16s %s in every iteration; a step whose Newton fails is cut\n", "line_search",
            line_search_names[n->line_search]);
  fprintf(out, "  %-16s ||F|| <= %g or ||F||/||F0|| <= %g, with ||dx|| <= %g (1 + ||x||); at most %d iterations\n",
          "convergence", n->residual_tolerance, n->relative_tolerance, n->update_tolerance, n->max_iterations);
  fprintf(out, "  %-16s %s\n", "predicted_update",
          n->predicted_update ? "true: the update test also accepts the next update predicted from the residual's "
                                "decrease (no confirming solve)"
                              : "false: the update test reads the step taken (a confirming solve; the default)");
  fprintf(out, "  %-16s %s\n", "predictor",
          solver->predictor ? "previous-increment: quasi-static steps start from u_n plus the previous increment "
                              "scaled to dt"
                            : "last-state: quasi-static steps start from u_n (dynamic schemes predict from v_n)");
  const sk_linear_options *l = &solver->linear;
  fprintf(out, "linear solver (solver.linear):\n  %-16s %s\n", "solver", linear_names[l->kind]);
  fprintf(out, "  %-16s Krylov relative residual <= %g in at most %d iterations (direct solvers ignore it)\n",
          "tolerance", l->tolerance, l->max_iterations);
  fprintf(out, "  %-16s %s: MueLu's near-nullspace of the displacements (%s)\n", "nullspace",
          nullspace_names[l->nullspace],
          l->nullspace == SK_NULLSPACE_RIGID_BODY ? "translations and rotations" : "translations only");
}

void sk_scene_explain(const sk_scene *scene, const char *out_dir, int progress, FILE *out) {
  sk_mesh_cache_explain(out);
  const sk_system *sys = scene->system;
  int computed = 0;
  for (int k = 0; k < sys->n_terms; ++k) computed += sk_term_plugin_explain_defaults(sys->terms[k], NULL);
  if (computed) {
    fprintf(out, "parameters computed from the scene (a value the scene gives wins; the plugins' pages state the "
            "rules):\n");
    for (int k = 0; k < sys->n_terms; ++k) sk_term_plugin_explain_defaults(sys->terms[k], out);
  }
  int created = 0;
  for (int k = 0; k < sys->n_terms; ++k) created += sk_term_plugin_explain_pair(sys->terms[k], NULL);
  if (created) {
    fprintf(out, "contact pairs created by `bodies:` (%d; the broad phase keeps pairs whose surfaces are apart from "
            "calling their plugin, docs/contact-services.md):\n", created);
    for (int k = 0; k < sys->n_terms; ++k) sk_term_plugin_explain_pair(sys->terms[k], out);
  }
  sk_master_ghosts_explain(sys->model, out);
  sk_contact_partition_explain(sys->model, out);
  sk_system_explain(sys, out);
  explain_newton(&scene->solver, out);
  const sk_output_settings *o = &scene->output;
  fprintf(out, "outputs:\n");
  if (out_dir || progress || sk_skip_forced("invariants"))
    fprintf(out, "  %-16s computed: strain and kinetic energy, momenta, reactions and contact totals per step (%s)\n",
            "history", out_dir ? "history.csv" : progress ? "the progress line shows the energy" : "STICKSLIP_NO_SKIP");
  else
    fprintf(out, "  %-16s skipped: energies and momenta (--quiet and no --out: nobody reads them)\n", "invariants");
  if (!out_dir) {
    fprintf(out, "  %-16s skipped: no --out DIR, no result files (with --out: output.vtu, output.vtu_every)\n",
            "stress, vtu");
  } else if (!o->write_vtu) {
    fprintf(out, "  %-16s skipped: output.vtu is false\n", "stress, vtu");
  } else {
    if (o->vtu_every > 0)
      fprintf(out, "  %-16s computed every %d steps and at the last (output.vtu_every)\n", "stress, vtu", o->vtu_every);
    else
      fprintf(out, "  %-16s computed at the last step only (output.vtu_every: 0)\n", "stress, vtu");
  }
  if (!out_dir || !o->write_contact_csv || scene->model.n_pairs == 0)
    fprintf(out, "  %-16s skipped: %s\n", "contact.csv",
            !out_dir ? "no --out DIR" : !o->write_contact_csv ? "output.contact_csv is false" : "no contact pairs");
  else if (o->vtu_every > 0)
    fprintf(out, "  %-16s computed: the contact points every %d steps and at the last (output.vtu_every)\n",
            "contact.csv", o->vtu_every);
  else
    fprintf(out, "  %-16s computed: the contact points of the initial state and the last step (output.vtu_every: "
            "0)\n", "contact.csv");
  sk_scene_keys(scene, out); /* every key a scene can have: its value and where it came from */
}
