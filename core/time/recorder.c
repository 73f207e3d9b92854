/* The recorder: the result files of a run (history.csv, results.pvd + a .pvtu per output step over the ranks' .vtu
 * pieces, summary.json, scene.yaml, and the contact
 * files of contact_output.c) in a staging folder that is swapped in at the end. It reads the system after a commit, while the state still spans
 * the step (x, v at t); it never feeds anything back into the stepping. */
#define _GNU_SOURCE
#include "recorder.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <errno.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#include "../model/assemble.h"
#include "checkpoint.h"
#include "contact_balance.h"
#include "contact_output.h"
#include "penetration.h"
#include "stickslip/output.h"
#include "vtu_pieces.h"

/* history.csv: the fixed columns, by name; then reactions per Dirichlet condition and per obstacle, wall seconds */
typedef enum {
  COL_TIME, COL_STEP, COL_SUBSTEP, COL_DT, COL_NEWTON, COL_KINETIC, COL_STRAIN, COL_TOTAL, COL_MOMENTUM_X, COL_MOMENTUM_Y,
  COL_MOMENTUM_Z, COL_ANGULAR_X, COL_ANGULAR_Y, COL_ANGULAR_Z, COL_FORCE_X, COL_FORCE_Y, COL_FORCE_Z, COL_ACTIVE,
  COL_STICK, COL_SLIP, COL_DISSIPATED, COL_CONSTRAINT, COL_MOMENT_X, COL_MOMENT_Y, COL_MOMENT_Z, COL_MATERIAL, COL_EXTERNAL_WORK,
  N_FIXED_COLUMNS
} history_column;

static const char *const fixed_columns[N_FIXED_COLUMNS] = {
    "time", "step", "substep", "dt", "newton_iterations", "kinetic_energy", "strain_energy", "total_energy", "momentum_x",
    "momentum_y", "momentum_z", "angular_momentum_x", "angular_momentum_y", "angular_momentum_z", "contact_force_x",
    "contact_force_y", "contact_force_z", "active_points", "stick_points", "slip_points", "dissipated_energy",
    "constraint_violation", "contact_moment_x", "contact_moment_y", "contact_moment_z", "material_total_energy",
    "external_work"};

struct sk_recorder {
  sk_scene *scene;
  sk_system *sys;
  const sk_run_options *options;
  double wall_start;
  sk_csv *history;
  sk_pvd *pvd;
  sk_contact_output *contact; /* with contact pairs and --out: contact.csv and the contact fields and files */
  char dir[1100];          /* staging folder ("" when nothing is written; rank 0's) */
  char pieces_dir[1100];   /* the same folder on every rank, where each writes its VTU pieces */
  int n_columns;
  const char **names;
  char (*name_storage)[96];
  double *row;
  double *reactions;       /* 3 per Dirichlet condition */
  double *obstacle_force;  /* 3 per obstacle pair */
  int n_obstacles;
  double dissipated;       /* accumulated over the steps */
  double external_work;    /* of the loads, accumulated over the steps (sk_system_load_work) */
  double *load_scratch;    /* room for the local dofs, for sk_system_load_work */
  double total_energy;     /* of the last row */
  int wants_invariants;    /* someone reads the energies and momenta: history.csv (--out) or the progress line */
  int vtu_count;
  int64_t last_step;       /* the last converged step recorded */
  int64_t last_output_step; /* the step of the last output (pictures, contact points) */
  char restarted_from[4096]; /* the checkpoint a restarted run continues, or "" */
  /* the linear solvers that ran, by step ranges: "mumps (steps 1-12), gmres-muelu (steps 13-40)" */
  char solvers_used[1024];
  unsigned range_solvers;  /* of the open range, steps range_first .. range_last */
  int range_first, range_last;
  sk_contact_balance balance; /* contact work per rank (summary.json, --verbose) */
  sk_penetration_watch penetration; /* a penalty pair's deepest penetration (summary.json, one warning) */
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
  free(rec->load_scratch);
  free(rec);
}

/* Rank 0's files: the staging folder, history.csv, scene.yaml and results.pvd. */
static sk_status open_root_files(sk_recorder *rec) {
  SK_TRY(sk_outdir_begin(rec->options->out_dir, rec->dir, sizeof rec->dir));
  char path[1300];
  snprintf(path, sizeof path, "%s/history.csv", rec->dir);
  SK_TRY(sk_csv_open(path, rec->n_columns, rec->names, &rec->history));
  snprintf(path, sizeof path, "%s/scene.yaml", rec->dir);
  SK_TRY(sk_scene_write(rec->scene, path));
  if (rec->scene->output.write_vtu) {
    snprintf(path, sizeof path, "%s/results.pvd", rec->dir);
    SK_TRY(sk_pvd_open(path, &rec->pvd));
  }
  return SK_OK;
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
  rec->n_obstacles = m->n_obstacle_columns;
  rec->n_columns = N_FIXED_COLUMNS + 3 * (m->n_dirichlet + rec->n_obstacles) + 1;
  rec->names = calloc((size_t)rec->n_columns, sizeof(char *));
  rec->name_storage = calloc((size_t)rec->n_columns, sizeof *rec->name_storage);
  rec->row = calloc((size_t)rec->n_columns, sizeof(double));
  rec->reactions = calloc(3 * (size_t)m->n_dirichlet + 1, sizeof(double));
  rec->obstacle_force = calloc(3 * (size_t)rec->n_obstacles + 1, sizeof(double));
  rec->load_scratch = calloc((size_t)m->n_nodes * (size_t)m->dim + 1, sizeof(double));
  *out = rec;
  if (!rec->names || !rec->name_storage || !rec->row || !rec->reactions || !rec->obstacle_force || !rec->load_scratch)
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
  for (int k = 0, columns = 0; k < m->n_pairs; ++k)
    if (m->pairs[k].has_obstacle && m->pairs[k].obstacle_column == columns++)
      for (int i = 0; i < 3; ++i) {
        snprintf(rec->name_storage[c], sizeof rec->name_storage[c], "reaction_%s_%c", m->pairs[k].obstacle.name,
                 "xyz"[i]);
        rec->names[c] = rec->name_storage[c];
        ++c;
      }
  rec->names[c] = "wall_seconds";
  if (!options->out_dir) return SK_OK;
  sk_status status = SK_OK;
  if (m->rank == 0) status = open_root_files(rec);
  /* the staging folder to every rank for its VTU pieces (a shared file system, as MPI codes' output assumes) */
  snprintf(rec->pieces_dir, sizeof rec->pieces_dir, "%s", rec->dir);
  MPI_Bcast(rec->pieces_dir, (int)sizeof rec->pieces_dir, MPI_CHAR, 0, m->comm);
  SK_TRY(sk_system_collective(sys, status));
  const sk_output_settings *o = &scene->output;
  if (m->n_pairs > 0 && (o->write_contact_csv || o->write_vtu))
    SK_TRY(sk_contact_output_open(m, rec->dir, o->write_contact_csv, o->write_vtu, &rec->contact));
  return SK_OK;
}

/* ---- VTU -------------------------------------------------------------------------------------------------------- */

/* Each rank writes its piece of the bodies, step-NNNNNN/rank-RRRR.vtu: the elements it owns, the nodes they use (in
 * its local order) with the displacement, velocity, contact fields and mesh id ("node_id") of each, the Cauchy stress,
 * body, rank and whole cell index ("cell_id": cells numbered body by body, as the scene's groups) of each cell. Rank 0
 * writes step-NNNNNN.pvtu naming the pieces and lists it in results.pvd. A run on one rank writes one piece: every
 * run's pictures have the same form, and no rank needs the whole mesh. */
typedef struct {
  int n_points, n_cells;
  int *point_of;           /* per node this rank holds: its point in the piece, or -1 */
  int *node_of_point;
  double *points, *displacement, *velocity, *node_id, *contact, *stress_local, *stress;
  sk_elem_type *types;
  int *offsets, *conn;
  double *body_id, *rank_id, *cell_id;
} vtu_piece;

static void free_vtu_piece(vtu_piece *p) {
  void *all[] = {p->point_of, p->node_of_point, p->points, p->displacement, p->velocity, p->node_id, p->contact,
                 p->stress_local, p->stress, p->types, p->offsets, p->conn, p->body_id, p->rank_id, p->cell_id};
  for (size_t k = 0; k < sizeof all / sizeof all[0]; ++k) free(all[k]);
}

enum { MAX_CONTACT_FIELDS = 16 };

/* This rank's piece at displacement u and velocity v: its cells, their points and fields (the contact fields of the
 * output step, sk_contact_output_step before). */
static sk_status build_piece(const sk_recorder *rec, const double *u, const double *v, vtu_piece *p) {
  const sk_model *m = &rec->scene->model;
  const int dim = m->dim;
  p->point_of = malloc(sizeof(int) * ((size_t)m->n_nodes + 1));
  p->stress_local = calloc(9 * (size_t)m->n_elements + 1, sizeof(double));
  if (!p->point_of || !p->stress_local) return no_memory("the VTU output");
  for (int a = 0; a < m->n_nodes; ++a) p->point_of[a] = -1;
  size_t slots = 0;
  for (int e = 0; e < m->n_elements; ++e) {
    if (m->element_part[e] != m->rank) continue;
    const sk_body *body;
    const int *ec;
    sk_element_dofs(m, e, NULL, &body, &ec);
    for (int k = 0; k < body->group->nen; ++k)
      if (p->point_of[ec[k]] < 0) p->point_of[ec[k]] = p->n_points++;
    slots += (size_t)body->group->nen;
    p->n_cells++;
  }
  const size_t np = (size_t)p->n_points + 1, nc = (size_t)p->n_cells + 1;
  p->node_of_point = malloc(sizeof(int) * np);
  p->points = calloc(3 * np, sizeof(double));
  p->displacement = calloc(3 * np, sizeof(double));
  p->velocity = calloc(3 * np, sizeof(double));
  p->node_id = malloc(sizeof(double) * np);
  p->contact = malloc(sizeof(double) * MAX_CONTACT_FIELDS * 9 * np);
  p->stress = malloc(sizeof(double) * 9 * nc);
  p->types = malloc(sizeof(sk_elem_type) * nc);
  p->offsets = malloc(sizeof(int) * nc);
  p->conn = malloc(sizeof(int) * (slots + 1));
  p->body_id = malloc(sizeof(double) * nc);
  p->rank_id = malloc(sizeof(double) * nc);
  p->cell_id = malloc(sizeof(double) * nc);
  if (!p->node_of_point || !p->points || !p->displacement || !p->velocity || !p->node_id || !p->contact ||
      !p->stress || !p->types || !p->offsets || !p->conn || !p->body_id || !p->rank_id || !p->cell_id)
    return no_memory("the VTU output");
  for (int a = 0; a < m->n_nodes; ++a) {
    const int k = p->point_of[a];
    if (k < 0) continue;
    p->node_of_point[k] = a;
    p->node_id[k] = (double)m->node_gid[a];
    for (int i = 0; i < dim; ++i) {
      p->displacement[3 * k + i] = u[(int64_t)a * dim + i];
      p->velocity[3 * k + i] = v[(int64_t)a * dim + i];
      p->points[3 * k + i] = m->X[(int64_t)a * dim + i] + p->displacement[3 * k + i];
    }
  }
  SK_TRY(sk_bulk_stress(m, u, p->stress_local));
  p->offsets[0] = 0;
  int c = 0;
  for (int b = 0, base = 0; b < m->n_bodies; base += m->bodies[b].n_elems_global, ++b)
    for (int e = m->bodies[b].first_element; e < m->bodies[b].first_element + m->bodies[b].group->n_elems; ++e) {
      if (m->element_part[e] != m->rank) continue;
      const sk_body *body;
      const int *ec;
      sk_element_dofs(m, e, NULL, &body, &ec);
      const int nen = body->group->nen;
      p->types[c] = body->group->type;
      for (int k = 0; k < nen; ++k) p->conn[p->offsets[c] + k] = p->point_of[ec[k]];
      p->offsets[c + 1] = p->offsets[c] + nen;
      memcpy(p->stress + 9 * (size_t)c, p->stress_local + 9 * (size_t)e, 9 * sizeof(double));
      p->body_id[c] = b;
      p->rank_id[c] = m->rank;
      p->cell_id[c] = base + m->element_index[e];
      ++c;
    }
  return SK_OK;
}

/* The piece's point and cell fields (the .pvtu lists the same, rank 0's); the contact fields picked at its points. */
static int piece_fields(const sk_recorder *rec, vtu_piece *p, sk_vtu_field *point_fields, sk_vtu_field *cell_fields,
                        int *n_cell_fields) {
  sk_vtu_field contact[MAX_CONTACT_FIELDS];
  const int n_contact = sk_contact_output_node_fields(rec->contact, contact, MAX_CONTACT_FIELDS);
  int n = 0;
  point_fields[n++] = (sk_vtu_field){"displacement", 3, p->displacement};
  point_fields[n++] = (sk_vtu_field){"velocity", 3, p->velocity};
  double *to = p->contact;
  for (int f = 0; f < n_contact; ++f) {
    const int nc = contact[f].components;
    for (int k = 0; k < p->n_points; ++k)
      memcpy(to + (size_t)nc * k, contact[f].values + (size_t)nc * p->node_of_point[k], sizeof(double) * (size_t)nc);
    point_fields[n++] = (sk_vtu_field){contact[f].name, nc, to};
    to += (size_t)nc * p->n_points;
  }
  point_fields[n++] = (sk_vtu_field){"node_id", 1, p->node_id};
  cell_fields[0] = (sk_vtu_field){"cauchy_stress", 9, p->stress};
  cell_fields[1] = (sk_vtu_field){"body", 1, p->body_id};
  cell_fields[2] = (sk_vtu_field){"rank", 1, p->rank_id};
  cell_fields[3] = (sk_vtu_field){"cell_id", 1, p->cell_id};
  *n_cell_fields = 4;
  return n;
}

/* Writes every rank's piece of the bodies at (u, v) and rank 0's .pvtu of the step, listed in results.pvd at time t.
 * Collective. */
static sk_status write_vtu(sk_recorder *rec, const double *u, const double *v, double t, int64_t step) {
  const sk_model *m = &rec->scene->model;
  vtu_piece p = {0};
  sk_vtu_field point_fields[3 + MAX_CONTACT_FIELDS], cell_fields[4];
  int n_point_fields = 0, n_cell_fields = 0;
  char prefix[64];
  snprintf(prefix, sizeof prefix, "step-%06lld", (long long)step);
  sk_status status = build_piece(rec, u, v, &p);
  if (status == SK_OK) n_point_fields = piece_fields(rec, &p, point_fields, cell_fields, &n_cell_fields);
  const sk_vtu_piece piece = {p.n_points, p.n_cells, p.points, p.types, p.offsets, p.conn, n_point_fields,
                              n_cell_fields, point_fields, cell_fields};
  status = sk_vtu_pieces_write(rec->sys, status, rec->pieces_dir, prefix, &piece);
  if (status == SK_OK && m->rank == 0) {
    char file[80];
    snprintf(file, sizeof file, "%s.pvtu", prefix);
    status = sk_pvd_add(rec->pvd, t, file);
  }
  rec->vtu_count++;
  free_vtu_piece(&p);
  return sk_system_collective(rec->sys, status);
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
  row[COL_EXTERNAL_WORK] = rec->external_work;
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

/* The rows of a checkpoint's table `name` (as the interrupted run wrote them, %.17g: they read back exactly) into
 * `csv`, whose rows have `n_columns` values (row: room for them). A checkpoint of a run without --out has none. */
static sk_status carry_rows(const sk_restart *restart, const char *name, sk_csv *csv, int n_columns, double *row) {
  char path[4200];
  snprintf(path, sizeof path, "%s/%s", restart->dir, name);
  FILE *f = fopen(path, "r");
  if (!f) return SK_OK;
  char *line = NULL;
  size_t cap = 0;
  sk_status status = SK_OK;
  int number = 0;
  while (status == SK_OK && getline(&line, &cap, f) > 0) {
    if (number++ == 0) continue; /* the header */
    int c = 0;
    for (char *p = line, *end; c < n_columns && *p && *p != '\n'; ++c, p = *end == ',' ? end + 1 : end) {
      row[c] = strtod(p, &end);
      if (end == p) break;
    }
    if (c != n_columns)
      status = sk_error_set(SK_ERR_INPUT, "--restart: %s, line %d: %d columns, this scene's %s has %d", path, number,
                            c, name, n_columns);
    else
      status = sk_csv_row(csv, row);
  }
  free(line);
  fclose(f);
  return status;
}

sk_status sk_recorder_resume(sk_recorder *rec, const sk_restart *restart) {
  rec->dissipated = restart->dissipated;
  rec->external_work = restart->external_work;
  rec->last_output_step = restart->last_vtu_step;
  rec->last_step = restart->progress.steps;
  snprintf(rec->restarted_from, sizeof rec->restarted_from, "%s", restart->dir);
  if (rec->history) SK_TRY(carry_rows(restart, "history.csv", rec->history, rec->n_columns, rec->row));
  int n_contact_columns = 0;
  sk_csv *contact = sk_contact_output_csv(rec->contact, &n_contact_columns);
  if (!contact) return SK_OK;
  double *row = malloc(sizeof(double) * ((size_t)n_contact_columns + 1));
  if (!row) return no_memory("the contact rows");
  const sk_status status = carry_rows(restart, "contact.csv", contact, n_contact_columns, row);
  free(row);
  return status;
}

void sk_recorder_checkpoint_state(sk_recorder *rec, sk_recorder_state *state) {
  static char path[1300];
  state->dissipated = rec->dissipated;
  state->external_work = rec->external_work;
  state->last_vtu_step = rec->last_output_step;
  static char contact_path[1300];
  state->history_path = state->contact_path = NULL;
  if (rec->history) {
    snprintf(path, sizeof path, "%s/history.csv", rec->dir);
    state->history_path = path;
  }
  if (sk_contact_output_csv(rec->contact, NULL)) {
    snprintf(contact_path, sizeof contact_path, "%s/contact.csv", rec->dir);
    state->contact_path = contact_path;
  }
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
  sk_penetration_watch_step(&rec->penetration, sys, &contact);
  double load_work = 0.0;
  SK_TRY(sk_system_load_work(sys, rec->load_scratch, &load_work));
  rec->external_work += load_work;
  if (rec->scene->model.n_pairs > 0)
    SK_TRY(sk_contact_balance_step(&rec->balance, sys, &contact, sys->step, rec->options->verbose));
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
  if (rec->restarted_from[0]) sk_json_string(json, "restarted_from", rec->restarted_from);
  sk_json_int(json, "steps", sum->steps);
  sk_json_number(json, "final_time", sum->final_time);
  sk_json_int(json, "newton_iterations", sum->newton_iterations);
  sk_json_int(json, "linear_solves", sum->linear_solves);
  sk_json_int(json, "linear_factorisations", sum->linear_factorisations);
  sk_json_int(json, "krylov_iterations", (long)sum->krylov_iterations);
  sk_json_int(json, "step_cuts", sum->cuts);
  sk_json_int(json, "active_set_loops", sum->active_set_loops);
  sk_json_int(json, "roundoff_floor_steps", sum->roundoff_floor_steps);
  sk_json_int(json, "backtrack_retries", sum->backtrack_retries);
  sk_json_int(json, "backtrack_rescues", sum->backtrack_rescues);
  sk_json_int(json, "newton_backtrack_switches", sum->newton_backtrack_switches);
  sk_json_int(json, "dofs", (int)m->n_dofs_global);
  sk_json_int(json, "unknowns", (int)sum->unknowns_max);
  sk_json_int(json, "linear_system_size", (int)sum->linear_size_max);
  sk_json_int(json, "pattern_builds", sum->pattern_builds);
  sk_json_int(json, "master_reghosts", sum->master_reghosts);
  sk_json_int(json, "contact_rebalances", sum->contact_rebalances);
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
  sk_json_number(json, "broad_phase_seconds", rec->sys->t_broad_phase);
  sk_json_int(json, "broad_phase_sweeps", (long)rec->sys->broad_phase_sweeps);
  sk_json_int(json, "pair_attempts", (long)rec->sys->pair_attempts);
  sk_json_int(json, "pair_attempts_apart", (long)rec->sys->far_pair_attempts);
  sk_json_number(json, "solve_seconds", sum->solve_seconds);
  sk_json_number(json, "pattern_seconds", rec->sys->t_pattern[0]); /* rank 0's settling of the pattern (system.h) */
  sk_contact_balance_write(&rec->balance, json);
  sk_penetration_watch_write(&rec->penetration, json);
  return sk_json_close(json);
}

sk_status sk_recorder_close(sk_recorder *rec, sk_run_summary *summary, sk_status status) {
  const sk_model *m = &rec->scene->model;
  summary->contact_seconds_largest = rec->balance.run_seconds[2];
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
