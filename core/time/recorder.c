/* The recorder: the result files of a run (history.csv, results.pvd + .vtu, summary.json, scene.yaml, and the contact
 * files of contact_output.c) in a staging folder that is swapped in at the end. It reads the system after a commit, while the state still spans
 * the step (x, v at t); it never feeds anything back into the stepping. */
#define _GNU_SOURCE
#include "recorder.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "../model/assemble.h"
#include "contact_output.h"
#include "stickslip/output.h"

/* history.csv: the fixed columns, by name; then reactions per Dirichlet condition and per obstacle, wall seconds */
typedef enum {
  COL_TIME, COL_STEP, COL_SUBSTEP, COL_DT, COL_NEWTON, COL_KINETIC, COL_STRAIN, COL_TOTAL, COL_MOMENTUM_X, COL_MOMENTUM_Y,
  COL_MOMENTUM_Z, COL_ANGULAR_X, COL_ANGULAR_Y, COL_ANGULAR_Z, COL_FORCE_X, COL_FORCE_Y, COL_FORCE_Z, COL_ACTIVE,
  COL_STICK, COL_SLIP, COL_DISSIPATED, COL_CONSTRAINT, COL_MOMENT_X, COL_MOMENT_Y, COL_MOMENT_Z, COL_MATERIAL,
  N_FIXED_COLUMNS
} history_column;

static const char *const fixed_columns[N_FIXED_COLUMNS] = {
    "time", "step", "substep", "dt", "newton_iterations", "kinetic_energy", "strain_energy", "total_energy", "momentum_x",
    "momentum_y", "momentum_z", "angular_momentum_x", "angular_momentum_y", "angular_momentum_z", "contact_force_x",
    "contact_force_y", "contact_force_z", "active_points", "stick_points", "slip_points", "dissipated_energy",
    "constraint_violation", "contact_moment_x", "contact_moment_y", "contact_moment_z", "material_total_energy"};

struct sk_recorder {
  sk_scene *scene;
  sk_system *sys;
  const sk_run_options *options;
  double wall_start;
  sk_csv *history;
  sk_pvd *pvd;
  sk_contact_output *contact; /* with contact pairs and --out: contact.csv and the contact fields and files */
  char dir[1100];          /* staging folder ("" when nothing is written) */
  int n_columns;
  const char **names;
  char (*name_storage)[96];
  double *row;
  double *reactions;       /* 3 per Dirichlet condition */
  double *obstacle_force;  /* 3 per obstacle pair */
  int n_obstacles;
  double dissipated;       /* accumulated over the steps */
  double total_energy;     /* of the last row */
  int wants_invariants;    /* someone reads the energies and momenta: history.csv (--out) or the progress line */
  int vtu_count;
  int64_t last_step;       /* the last converged step recorded */
  int64_t last_output_step; /* the step of the last output (pictures, contact points) */
  /* the linear solvers that ran, by step ranges: "mumps (steps 1-12), gmres-muelu (steps 13-40)" */
  char solvers_used[1024];
  unsigned range_solvers;  /* of the open range, steps range_first .. range_last */
  int range_first, range_last;
};

static double now_seconds(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static sk_status no_memory(const char *what) { return sk_error_set(SK_ERR_NOMEM, "out of memory for %s", what); }

double sk_recorder_total_energy(const sk_recorder *rec) { return rec->total_energy; }

void sk_recorder_free(sk_recorder *rec) {
  if (!rec) return;
  sk_csv_close(rec->history);
  sk_pvd_close(rec->pvd);
  sk_contact_output_free(rec->contact);
  if (rec->dir[0]) sk_outdir_abort(rec->dir);
  free(rec->names);
  free(rec->name_storage);
  free(rec->row);
  free(rec->reactions);
  free(rec->obstacle_force);
  free(rec);
}

sk_status sk_recorder_open(sk_scene *scene, sk_system *sys, const sk_run_options *options, double wall_start,
                           sk_recorder **out) {
  *out = NULL;
  const sk_model *m = &scene->model;
  sk_recorder *rec = calloc(1, sizeof *rec);
  if (!rec) return no_memory("the recorder");
  rec->scene = scene;
  rec->sys = sys;
  rec->options = options;
  rec->wall_start = wall_start;
  /* the energies and momenta (a pass over every element) only for an audience; the same answer on every rank, since
   * sk_bulk_invariants sums over ranks and the progress line is rank 0's; STICKSLIP_NO_SKIP=invariants forces them */
  rec->wants_invariants = options->out_dir || options->progress || sk_skip_forced("invariants");
  MPI_Allreduce(MPI_IN_PLACE, &rec->wants_invariants, 1, MPI_INT, MPI_MAX, m->comm);
  for (int k = 0; k < m->n_pairs; ++k) rec->n_obstacles += m->pairs[k].has_obstacle;
  rec->n_columns = N_FIXED_COLUMNS + 3 * (m->n_dirichlet + rec->n_obstacles) + 1;
  rec->names = calloc((size_t)rec->n_columns, sizeof(char *));
  rec->name_storage = calloc((size_t)rec->n_columns, sizeof *rec->name_storage);
  rec->row = calloc((size_t)rec->n_columns, sizeof(double));
  rec->reactions = calloc(3 * (size_t)m->n_dirichlet + 1, sizeof(double));
  rec->obstacle_force = calloc(3 * (size_t)rec->n_obstacles + 1, sizeof(double));
  *out = rec;
  if (!rec->names || !rec->name_storage || !rec->row || !rec->reactions || !rec->obstacle_force)
    return no_memory("the history columns");
  int c = 0;
  for (; c < N_FIXED_COLUMNS; ++c) rec->names[c] = fixed_columns[c];
  for (int k = 0; k < m->n_dirichlet; ++k)
    for (int i = 0; i < 3; ++i) {
      snprintf(rec->name_storage[c], sizeof rec->name_storage[c], "reaction_%s_%c", m->dirichlet[k].name, "xyz"[i]);
      rec->names[c] = rec->name_storage[c];
      ++c;
    }
  /* the force each rigid obstacle receives (minus the contact force on its slave surface) */
  for (int k = 0; k < m->n_pairs; ++k)
    if (m->pairs[k].has_obstacle)
      for (int i = 0; i < 3; ++i) {
        snprintf(rec->name_storage[c], sizeof rec->name_storage[c], "reaction_%s_%c", m->pairs[k].obstacle.name,
                 "xyz"[i]);
        rec->names[c] = rec->name_storage[c];
        ++c;
      }
  rec->names[c] = "wall_seconds";
  if (!options->out_dir) return SK_OK;
  if (m->rank == 0) {
    SK_TRY(sk_outdir_begin(options->out_dir, rec->dir, sizeof rec->dir));
    char path[1300];
    snprintf(path, sizeof path, "%s/history.csv", rec->dir);
    SK_TRY(sk_csv_open(path, rec->n_columns, rec->names, &rec->history));
    snprintf(path, sizeof path, "%s/scene.yaml", rec->dir);
    SK_TRY(sk_scene_write(scene, path));
    if (scene->output.write_vtu) {
      snprintf(path, sizeof path, "%s/results.pvd", rec->dir);
      SK_TRY(sk_pvd_open(path, &rec->pvd));
    }
  }
  const sk_output_settings *o = &scene->output;
  if (m->n_pairs > 0 && (o->write_contact_csv || o->write_vtu))
    SK_TRY(sk_contact_output_open(m, rec->dir, o->write_contact_csv, o->write_vtu, &rec->contact));
  return SK_OK;
}

/* ---- VTU -------------------------------------------------------------------------------------------------------- */

typedef struct {
  double *points, *displacement, *velocity, *stress, *stress_sum;
  sk_elem_type *types;
  int *offsets, *conn;
  double *body_id, *rank_id;
} vtu_buffers;

static void free_vtu_buffers(vtu_buffers *b) {
  void *all[] = {b->points, b->displacement, b->velocity, b->stress, b->stress_sum, b->types, b->offsets, b->conn,
                 b->body_id, b->rank_id};
  for (size_t k = 0; k < sizeof all / sizeof all[0]; ++k) free(all[k]);
}

enum { MAX_CONTACT_FIELDS = 16 };

/* The mesh at displacement u and velocity v (time t, step), with stresses and the contact fields of the output step
 * (sk_contact_output_step before). Collective. */
static sk_status write_vtu(sk_recorder *rec, const double *u, const double *v, double t, int64_t step) {
  const sk_model *m = &rec->scene->model;
  const int dim = m->dim, nn = m->n_nodes;
  vtu_buffers b = {0};
  b.points = calloc(3 * (size_t)nn, sizeof(double));
  b.displacement = calloc(3 * (size_t)nn, sizeof(double));
  b.velocity = calloc(3 * (size_t)nn, sizeof(double));
  b.stress = calloc(9 * (size_t)m->n_elements, sizeof(double));
  b.stress_sum = calloc(9 * (size_t)m->n_elements, sizeof(double));
  sk_status status =
      b.points && b.displacement && b.velocity && b.stress && b.stress_sum ? SK_OK : no_memory("the VTU output");
  if (status == SK_OK) status = sk_bulk_stress(m, u, b.stress);
  status = sk_system_collective(rec->sys, status);
  if (status != SK_OK) {
    free_vtu_buffers(&b);
    return status;
  }
  MPI_Reduce(b.stress, b.stress_sum, 9 * m->n_elements, MPI_DOUBLE, MPI_SUM, 0, m->comm);
  if (m->rank == 0) {
    for (int a = 0; a < nn; ++a)
      for (int i = 0; i < dim; ++i) {
        b.displacement[3 * a + i] = u[a * dim + i];
        b.velocity[3 * a + i] = v[a * dim + i];
        b.points[3 * a + i] = m->X[a * dim + i] + u[a * dim + i];
      }
    const int n_cells = m->n_elements;
    b.types = calloc((size_t)n_cells + 1, sizeof(sk_elem_type));
    b.offsets = calloc((size_t)n_cells + 1, sizeof(int));
    b.conn = calloc((size_t)n_cells * SK_MAX_NEN + 1, sizeof(int));
    b.body_id = calloc((size_t)n_cells + 1, sizeof(double));
    b.rank_id = calloc((size_t)n_cells + 1, sizeof(double));
    if (!b.types || !b.offsets || !b.conn || !b.body_id || !b.rank_id) status = no_memory("the VTU output");
    for (int e = 0; e < n_cells && status == SK_OK; ++e) {
      const sk_body *body;
      const int *ec;
      int dofs[SK_MAX_NEN * 3];
      sk_element_dofs(m, e, dofs, &body, &ec);
      b.types[e] = body->group->type;
      b.offsets[e + 1] = b.offsets[e] + body->group->nen;
      memcpy(b.conn + b.offsets[e], ec, sizeof(int) * (size_t)body->group->nen);
      b.body_id[e] = (double)(body - m->bodies);
      b.rank_id[e] = m->element_part[e];
    }
    sk_vtu_field point_fields[2 + MAX_CONTACT_FIELDS] = {{"displacement", 3, b.displacement},
                                                         {"velocity", 3, b.velocity}};
    const int n_point_fields =
        2 + sk_contact_output_node_fields(rec->contact, point_fields + 2, MAX_CONTACT_FIELDS);
    sk_vtu_field cell_fields[] = {{"cauchy_stress", 9, b.stress_sum}, {"body", 1, b.body_id}, {"rank", 1, b.rank_id}};
    char file[64], path[1400];
    snprintf(file, sizeof file, "step-%06lld.vtu", (long long)step);
    snprintf(path, sizeof path, "%s/%s", rec->dir, file);
    if (status == SK_OK)
      status = sk_vtu_write(path, nn, b.points, n_cells, b.types, b.offsets, b.conn, n_point_fields, point_fields, 3,
                            cell_fields);
    if (status == SK_OK) status = sk_pvd_add(rec->pvd, t, file);
    rec->vtu_count++;
  }
  free_vtu_buffers(&b);
  return status;
}

/* The output of a step (or of the initial state): the contact points and, with output.vtu, the pictures. Nothing
 * without --out. Collective. */
static sk_status write_output_step(sk_recorder *rec, int initial, const double *u, const double *v, double t,
                                   int64_t step) {
  if (!rec->options->out_dir) return SK_OK;
  rec->last_output_step = step;
  if (rec->contact) SK_TRY(sk_contact_output_step(rec->contact, rec->sys, initial, u, t, step));
  return rec->scene->output.write_vtu ? write_vtu(rec, u, v, t, step) : SK_OK;
}

/* ---- history ---------------------------------------------------------------------------------------------------- */

/* One row for the state (u, v) at time t with the contact totals of the step that led to it. */
static sk_status history_row(sk_recorder *rec, const double *u, const double *v, double t, int64_t step, int substep,
                             int newton_iterations, const sk_contact_totals *contact) {
  const sk_model *m = &rec->scene->model;
  sk_invariants inv = {0};
  /* a body whose plugin scheme conserves another energy than its material's (ABI 2.5) counts with that energy; the
   * material's of every body stays in material_total_energy */
  double scheme[2] = {0, 0}, host[2] = {0, 0};
  if (rec->wants_invariants) {
    SK_TRY(sk_bulk_invariants(m, u, v, &inv));
    SK_TRY(sk_system_scheme_energy(rec->sys, u, v, step == 0, scheme, host));
  }
  sk_system_reactions(rec->sys, rec->reactions);
  rec->dissipated += contact->dissipated;
  double *row = rec->row;
  row[COL_TIME] = t;
  row[COL_STEP] = (double)step;
  row[COL_SUBSTEP] = substep;
  row[COL_DT] = rec->sys->dt;
  row[COL_NEWTON] = newton_iterations;
  row[COL_KINETIC] = inv.kinetic - host[0] + scheme[0];
  row[COL_STRAIN] = inv.strain - host[1] + scheme[1];
  row[COL_TOTAL] = row[COL_KINETIC] + row[COL_STRAIN];
  row[COL_MATERIAL] = inv.kinetic + inv.strain;
  for (int i = 0; i < 3; ++i) {
    row[COL_MOMENTUM_X + i] = inv.momentum[i];
    row[COL_ANGULAR_X + i] = inv.angular_momentum[i];
    row[COL_FORCE_X + i] = contact->force[i];
    row[COL_MOMENT_X + i] = contact->moment[i];
  }
  row[COL_ACTIVE] = contact->active;
  row[COL_STICK] = contact->stick;
  row[COL_SLIP] = contact->slip;
  row[COL_DISSIPATED] = rec->dissipated;
  row[COL_CONSTRAINT] = contact->constraint;
  int c = N_FIXED_COLUMNS;
  for (int k = 0; k < 3 * m->n_dirichlet; ++k) row[c++] = rec->reactions[k];
  for (int k = 0; k < 3 * rec->n_obstacles; ++k) row[c++] = rec->obstacle_force[k];
  row[c++] = now_seconds() - rec->wall_start;
  rec->total_energy = row[COL_TOTAL];
  if (rec->history) SK_TRY(sk_csv_row(rec->history, row));
  return SK_OK;
}

sk_status sk_recorder_initial(sk_recorder *rec) {
  sk_system *sys = rec->sys;
  /* the initial row reports no contact: the pairs have not stepped yet (report() is not called for it) */
  const sk_contact_totals contact = {.obstacle_force = rec->obstacle_force};
  sk_status status = history_row(rec, sys->u_n, sys->v_n, sys->t_n, 0, 0, 0, &contact);
  status = sk_system_collective(sys, status);
  if (status == SK_OK) status = write_output_step(rec, 1, sys->u_n, sys->v_n, sys->t_n, 0);
  return status;
}

/* Appends the open range of steps that used the same linear solvers to solvers_used. */
static void close_solver_range(sk_recorder *rec) {
  if (rec->range_first == 0) return;
  char names[256] = "";
  for (int k = 0; k < 32; ++k)
    if (rec->range_solvers & (1u << k))
      snprintf(names + strlen(names), sizeof names - strlen(names), "%s%s", names[0] ? " + " : "",
               sk_linear_solver_name((sk_linear_solver_kind)k));
  const size_t used = strlen(rec->solvers_used);
  char steps[64];
  if (rec->range_first == rec->range_last) snprintf(steps, sizeof steps, "step %d", rec->range_first);
  else snprintf(steps, sizeof steps, "steps %d-%d", rec->range_first, rec->range_last);
  snprintf(rec->solvers_used + used, sizeof rec->solvers_used - used, "%s%s (%s)", used ? ", " : "",
           names[0] ? names : "none", steps);
  rec->range_first = 0;
}

static void note_solvers(sk_recorder *rec, int step) {
  const unsigned solvers = rec->sys->step_solvers;
  if (rec->range_first > 0 && solvers == rec->range_solvers && step == rec->range_last + 1) {
    rec->range_last = step;
    return;
  }
  close_solver_range(rec);
  rec->range_solvers = solvers;
  rec->range_first = rec->range_last = step;
}

sk_status sk_recorder_step(sk_recorder *rec, int64_t scheduled, int substep, int last) {
  sk_system *sys = rec->sys;
  note_solvers(rec, (int)sys->step);
  sk_contact_totals contact = {.obstacle_force = rec->obstacle_force};
  SK_TRY(sk_system_contact_totals(sys, 0, &contact));
  sk_status status = history_row(rec, sys->x, sys->v, sys->t, sys->step, substep, sys->newton.iterations, &contact);
  status = sk_system_collective(sys, status);
  rec->last_step = sys->step;
  /* vtu_every counts scheduled steps: the sub-steps of a cut step do not shift the pictures off the schedule */
  const int every = rec->scene->output.vtu_every;
  const int on_schedule = substep == 0 && every > 0 && scheduled % every == 0;
  if (status == SK_OK && (on_schedule || last)) status = write_output_step(rec, 0, sys->x, sys->v, sys->t, sys->step);
  return status;
}

static sk_status write_summary(sk_recorder *rec, const sk_run_summary *sum) {
  const sk_model *m = &rec->scene->model;
  char path[1300];
  snprintf(path, sizeof path, "%s/summary.json", rec->dir);
  sk_json *json;
  SK_TRY(sk_json_open(path, &json));
  sk_json_string(json, "status", sum->interrupted ? "interrupted" : sum->failed ? "failed" : "ok");
  if (sum->failed) sk_json_string(json, "message", sum->message);
  sk_json_string(json, "scene", rec->scene->path);
  sk_json_int(json, "steps", sum->steps);
  sk_json_number(json, "final_time", sum->final_time);
  sk_json_int(json, "newton_iterations", sum->newton_iterations);
  sk_json_int(json, "linear_solves", sum->linear_solves);
  sk_json_int(json, "step_cuts", sum->cuts);
  sk_json_int(json, "active_set_loops", sum->active_set_loops);
  sk_json_int(json, "roundoff_floor_steps", sum->roundoff_floor_steps);
  sk_json_int(json, "backtrack_retries", sum->backtrack_retries);
  sk_json_int(json, "backtrack_rescues", sum->backtrack_rescues);
  sk_json_int(json, "dofs", m->n_dofs);
  sk_json_int(json, "unknowns", (int)sum->unknowns_max);
  sk_json_int(json, "linear_system_size", (int)sum->linear_size_max);
  sk_json_int(json, "pattern_builds", sum->pattern_builds);
  sk_json_int(json, "ranks", m->n_ranks);
  char plugins[512] = "", strategies[512] = "";
  for (int k = 0; k < m->n_pairs; ++k) {
    const sk_contact_pair *pair = &m->pairs[k];
    snprintf(plugins + strlen(plugins), sizeof plugins - strlen(plugins), "%s%s", k ? "," : "", pair->plugin->name);
    snprintf(strategies + strlen(strategies), sizeof strategies - strlen(strategies), "%s%s", k ? "," : "",
             pair->plugin->strategies[pair->strategy]);
  }
  sk_json_string(json, "plugin", m->n_pairs ? plugins : "none");
  sk_json_string(json, "strategy", m->n_pairs ? strategies : "none");
  sk_json_string(json, "linear_solver", sk_linear_solver_name(rec->scene->solver.linear.kind));
  close_solver_range(rec);
  sk_json_string(json, "linear_solvers_used", rec->solvers_used[0] ? rec->solvers_used : "none");
  /* 1 when that Krylov solver failed and the direct one took over (core/model/system.c, linear_solve) */
  sk_json_number(json, "linear_solver_replaced_by_direct", rec->sys->linear_fallback);
  sk_json_number(json, "wall_seconds", sum->wall_seconds);
  sk_json_number(json, "assembly_seconds", sum->assembly_seconds);
  sk_json_number(json, "contact_seconds", sum->contact_seconds);
  sk_json_number(json, "solve_seconds", sum->solve_seconds);
  return sk_json_close(json);
}

sk_status sk_recorder_close(sk_recorder *rec, sk_run_summary *summary, sk_status status) {
  const sk_model *m = &rec->scene->model;
  /* results: complete files up to the last converged step, then the folder is swapped in atomically */
  char message[1100];
  snprintf(message, sizeof message, "%s", sk_error_message());
  /* A run stopped by a signal or a failed step between two outputs: its last converged state is the one a user
   * wants to look at, so it gets its pictures and contact points too (collective; the original message is kept).
   * Not after a write or memory error: writing more would fail the same way. */
  const int stopped_by_the_solution = status == SK_ERR_INTERRUPTED || status == SK_ERR_DIVERGED ||
                                     status == SK_ERR_INVERTED || status == SK_ERR_LINEAR_SOLVER;
  if (stopped_by_the_solution && summary->steps > 0 && rec->last_output_step != rec->last_step) {
    if (write_output_step(rec, 0, rec->sys->u_n, rec->sys->v_n, rec->sys->t_n, rec->last_step) != SK_OK &&
        m->rank == 0)
      fprintf(stderr, "warning: the output of the last converged step was not written: %s\n", sk_error_message());
    sk_error_set(status, "%s", message);
  }
  if (rec->options->out_dir && m->rank == 0 && rec->dir[0]) {
    sk_status out_status = sk_contact_output_close(rec->contact);
    sk_csv_close(rec->history);
    rec->history = NULL;
    sk_pvd_close(rec->pvd);
    rec->pvd = NULL;
    if (out_status == SK_OK) out_status = write_summary(rec, summary);
    if (out_status == SK_OK)
      out_status = sk_outdir_commit(rec->dir, rec->options->out_dir,
                                    summary->interrupted ? SK_RESULTS_INTERRUPTED
                                    : summary->failed    ? SK_RESULTS_FAILED
                                                         : SK_RESULTS_OK,
                                    summary->results_dir,
                                    sizeof summary->results_dir);
    else sk_outdir_abort(rec->dir);
    rec->dir[0] = '\0';
    if (status == SK_OK) status = out_status;
    else sk_error_set(status, "%s", message);
  }
  return status;
}
