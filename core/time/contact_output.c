/* The contact results of a run at its output steps: contact.csv, one long table with a row per contact point and
 * output step; the contact fields on the mesh nodes (the bodies' VTU); the slave surfaces with point and cell fields
 * (contact-NNNNNN.pvtu over the ranks' pieces, in contact.pvd); the rigid obstacles (obstacles-NNNNNN.vtu in
 * obstacles.pvd).
 *
 * Every column means the same for every plugin (docs/user-guide.md, docs/plugin-abi.md §8): the points a plugin
 * reports are completed here. A plugin that knows only forces (sk_contact_point.forces) gets them divided by the
 * node's tributary reference measure of the slave surface; a plugin that reports tractions gets its normal force as
 * pressure x area.
 *
 * On several ranks each holds its part of the slave surfaces (docs/design.md, "What each rank holds"): each point is
 * reported by the rank that owns its entity; contact.csv's rows (the points) are gathered to rank 0 and written in an
 * order that does not depend on the partition (pair, node, face). The fields on the slave surfaces are completed over
 * the ranks and each writes its piece, contact-NNNNNN/rank-RRRR.vtu, named by rank 0's contact-NNNNNN.pvtu
 * (contact_surface.c); the completed node fields stay on each rank for its piece of the bodies' VTU (recorder.c). */
#define _GNU_SOURCE
#include "contact_output.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "contact_surface.h"
#include "obstacle_output.h"
#include "stickslip/contact.h"
#include "stickslip/fe.h"

static const char *const csv_columns[2 + N_RECORD] = {
    "step",        "time",        "pair",        "node",       "face",       "x",
    "y",           "z",           "reference_x", "reference_y", "reference_z", "normal_x",
    "normal_y",    "normal_z",    "gap",         "state",      "pressure",   "normal_force",
    "area",        "traction_x",  "traction_y",  "traction_z", "slip_increment_x", "slip_increment_y",
    "slip_increment_z", "slip",   "multiplier"};

typedef struct {
  const sk_surface *surface; /* the pair's slave surface (this rank's part) */
  double *tributary;         /* reference tributary measure per held surface node (surface->nodes order; right at
                                the nodes this rank owns, whose faces it all holds) */
} pair_info;

struct sk_contact_output {
  const sk_model *model;
  char dir[1100];            /* the staging folder (rank 0), "" elsewhere */
  char pieces_dir[1100];     /* the same on every rank, for its pieces of the slave surfaces */
  int write_csv, write_vtu;
  pair_info *pairs;
  sk_contact_surfaces *surfaces; /* with VTU output */
  double *records;           /* this rank's points of the step, N_RECORD each */
  int n_records, cap_records, failed;
  sk_csv *csv;
  sk_pvd *contact_pvd, *obstacle_pvd;
  sk_obstacle_output *obstacles;
};

static sk_status no_memory(const char *what) { return sk_error_set(SK_ERR_NOMEM, "out of memory for %s", what); }

void sk_contact_output_free(sk_contact_output *co) {
  if (!co) return;
  sk_csv_close(co->csv);
  sk_pvd_close(co->contact_pvd);
  sk_pvd_close(co->obstacle_pvd);
  sk_obstacle_output_free(co->obstacles);
  for (int k = 0; co->pairs && k < co->model->n_pairs; ++k) free(co->pairs[k].tributary);
  sk_contact_surfaces_free(co->surfaces);
  free(co->pairs);
  free(co->records);
  free(co);
}

sk_csv *sk_contact_output_csv(const sk_contact_output *co, int *n_columns) {
  if (n_columns) *n_columns = 2 + N_RECORD;
  return co ? co->csv : NULL;
}

sk_status sk_contact_output_close(sk_contact_output *co) {
  if (!co) return SK_OK;
  sk_status status = sk_csv_close(co->csv);
  co->csv = NULL;
  sk_pvd_close(co->contact_pvd);
  sk_pvd_close(co->obstacle_pvd);
  co->contact_pvd = co->obstacle_pvd = NULL;
  return status;
}

sk_status sk_contact_output_open(const sk_model *model, const char *dir, int write_csv, int write_vtu,
                                 sk_contact_output **out) {
  sk_contact_output *co = calloc(1, sizeof *co);
  *out = co;
  if (!co) return no_memory("the contact output");
  co->model = model;
  snprintf(co->dir, sizeof co->dir, "%s", dir);
  co->write_csv = write_csv;
  co->write_vtu = write_vtu;
  co->pairs = calloc((size_t)model->n_pairs + 1, sizeof *co->pairs);
  if (!co->pairs) return no_memory("the contact output");
  int with_friction = 0, with_multipliers = 0;
  for (int k = 0; k < model->n_pairs; ++k) {
    const uint64_t caps = model->pairs[k].plugin->caps;
    with_friction |= (caps & SK_CAP_FRICTION) != 0;
    with_multipliers |= (caps & SK_CAP_MULTIPLIERS) != 0;
    const sk_surface *s = &model->pairs[k].slave;
    co->pairs[k].surface = s;
    co->pairs[k].tributary = malloc(sizeof(double) * ((size_t)s->n_nodes + 1));
    if (!co->pairs[k].tributary) return no_memory("the contact output");
    sk_surface_tributary_measures(s, model->X, co->pairs[k].tributary);
  }
  /* the staging folder to every rank for its pieces (a shared file system, as for the bodies' pieces) */
  snprintf(co->pieces_dir, sizeof co->pieces_dir, "%s", co->dir);
  MPI_Bcast(co->pieces_dir, (int)sizeof co->pieces_dir, MPI_CHAR, 0, model->comm);
  if (write_vtu) SK_TRY(sk_contact_surfaces_open(model, with_friction, with_multipliers, &co->surfaces));
  if (write_vtu) SK_TRY(sk_obstacle_output_open(model, &co->obstacles)); /* collective: the mesh's box */
  if (!co->dir[0]) return SK_OK;
  char path[1300];
  if (write_csv) {
    snprintf(path, sizeof path, "%s/contact.csv", co->dir);
    SK_TRY(sk_csv_open(path, 2 + N_RECORD, csv_columns, &co->csv));
  }
  if (!write_vtu) return SK_OK;
  snprintf(path, sizeof path, "%s/contact.pvd", co->dir);
  SK_TRY(sk_pvd_open(path, &co->contact_pvd));
  if (sk_obstacle_output_count(co->obstacles) > 0) {
    snprintf(path, sizeof path, "%s/obstacles.pvd", co->dir);
    SK_TRY(sk_pvd_open(path, &co->obstacle_pvd));
  }
  return SK_OK;
}

/* ---- the points of a step ---------------------------------------------------------------------------------------- */

/* The tributary measure of the node this rank holds as `node` on pair k's slave surface, NaN when it is not a node
 * of it. */
static double tributary_of(const sk_contact_output *co, int pair, int node) {
  if (pair < 0 || pair >= co->model->n_pairs || node < 0) return NAN;
  const pair_info *p = &co->pairs[pair];
  int lo = 0, hi = p->surface->n_nodes - 1;
  while (lo <= hi) {
    const int mid = lo + (hi - lo) / 2;
    if (p->surface->nodes[mid] == node) return p->tributary[mid];
    if (p->surface->nodes[mid] < node) lo = mid + 1;
    else hi = mid - 1;
  }
  return NAN;
}

/* The point as contact.csv writes it: positions, tractions per reference measure and forces, whatever the plugin
 * gave (docs/plugin-abi.md §8). */
static void complete_point(const sk_contact_output *co, int pair, const sk_contact_point *p, double *r) {
  const sk_model *m = co->model;
  const int64_t node = SK_HAS(p, slave_node) ? p->slave_node : -1; /* a mesh id */
  const int local = node >= 0 ? sk_model_node_of(m, node) : -1;    /* held: the point's owner holds its node */
  const int at_node = local >= 0;
  r[R_PAIR] = pair;
  r[R_NODE] = at_node ? (double)node : -1.0;
  r[R_FACE] = !at_node && SK_HAS(p, slave_face) ? (double)p->slave_face : -1.0;
  for (int i = 0; i < 3; ++i) {
    r[R_X + i] = p->x[i];
    r[R_REFERENCE + i] = at_node        ? (i < m->dim ? m->X[(int64_t)local * m->dim + i] : 0.0)
                         : SK_HAS(p, X) ? p->X[i]
                                        : NAN;
    r[R_NORMAL + i] = p->normal[i];
  }
  r[R_GAP] = p->gap;
  r[R_STATE] = p->state;
  const double tributary = at_node ? tributary_of(co, pair, local) : NAN;
  const int forces = SK_HAS(p, forces) && p->forces;
  const double area = SK_HAS(p, area) && p->area > 0.0 && !forces ? p->area : tributary;
  /* a plugin's forces become tractions over the tributary measure; tractions give forces over their measure */
  const double to_traction = forces ? 1.0 / area : 1.0, to_force = forces ? 1.0 : area;
  r[R_AREA] = area;
  r[R_PRESSURE] = p->pressure * to_traction;
  r[R_NORMAL_FORCE] = p->pressure * to_force;
  for (int i = 0; i < 3; ++i) r[R_TRACTION + i] = p->traction[i] * to_traction;
  const int slip = SK_HAS(p, has_slip) && p->has_slip;
  for (int i = 0; i < 3; ++i) r[R_SLIP_INCREMENT + i] = slip ? p->slip_increment[i] : NAN;
  r[R_SLIP] = slip ? p->slip : NAN;
  r[R_MULTIPLIER] = SK_HAS(p, multiplier) && p->has_multiplier ? p->multiplier : NAN;
}

static void collect_point(void *ctx, int pair, const sk_contact_point *p) {
  sk_contact_output *co = ctx;
  if (co->failed) return;
  if (co->n_records == co->cap_records) {
    const int cap = 2 * co->cap_records + 256;
    double *grown = realloc(co->records, sizeof(double) * N_RECORD * (size_t)cap);
    if (!grown) {
      co->failed = 1;
      return;
    }
    co->records = grown;
    co->cap_records = cap;
  }
  complete_point(co, pair, p, co->records + N_RECORD * (size_t)co->n_records++);
}

typedef struct {
  double pair, node, face;
  int index;
} row_key;

static int compare_rows(const void *a, const void *b) {
  const row_key *x = a, *y = b;
  if (x->pair != y->pair) return x->pair < y->pair ? -1 : 1;
  if (x->node != y->node) return x->node < y->node ? -1 : 1;
  if (x->face != y->face) return x->face < y->face ? -1 : 1;
  return (x->index > y->index) - (x->index < y->index); /* a face's Gauss points in their plugin's order */
}

/* contact.csv's rows of the step: every rank's points, gathered to rank 0 and written by pair, node and face, so
 * that the file does not depend on the number of ranks. */
static sk_status write_rows(sk_contact_output *co, double t, int64_t step) {
  const sk_model *m = co->model;
  int count = co->n_records * N_RECORD;
  int *counts = calloc((size_t)m->n_ranks, sizeof(int)), *displs = calloc((size_t)m->n_ranks, sizeof(int));
  if (!counts || !displs) {
    free(counts);
    free(displs);
    return no_memory("the contact points");
  }
  MPI_Gather(&count, 1, MPI_INT, counts, 1, MPI_INT, 0, m->comm);
  int total = 0;
  for (int r = 0; r < m->n_ranks; ++r) {
    displs[r] = total;
    total += counts[r];
  }
  double *all = m->rank == 0 ? malloc(sizeof(double) * ((size_t)total + 1)) : NULL;
  int ok = m->rank != 0 || all != NULL;
  MPI_Bcast(&ok, 1, MPI_INT, 0, m->comm);
  sk_status status = ok ? SK_OK : no_memory("the contact points");
  if (ok) MPI_Gatherv(co->records, count, MPI_DOUBLE, all, counts, displs, MPI_DOUBLE, 0, m->comm);
  const int n_rows = total / N_RECORD;
  row_key *order = ok && co->csv ? malloc(sizeof(row_key) * ((size_t)n_rows + 1)) : NULL;
  if (ok && co->csv && !order) status = no_memory("the contact points");
  if (order) {
    for (int k = 0; k < n_rows; ++k) {
      const double *r = all + N_RECORD * (size_t)k;
      order[k] = (row_key){r[R_PAIR], r[R_NODE], r[R_FACE], k};
    }
    qsort(order, (size_t)n_rows, sizeof(row_key), compare_rows);
    double row[2 + N_RECORD];
    row[0] = (double)step;
    row[1] = t;
    for (int k = 0; k < n_rows && status == SK_OK; ++k) {
      memcpy(row + 2, all + N_RECORD * (size_t)order[k].index, sizeof(double) * N_RECORD);
      status = sk_csv_row(co->csv, row);
    }
  }
  free(order);
  free(all);
  free(counts);
  free(displs);
  return status;
}

int sk_contact_output_node_fields(const sk_contact_output *co, sk_vtu_field *fields, int max) {
  return co ? sk_contact_surfaces_node_fields(co->surfaces, fields, max) : 0;
}

sk_status sk_contact_output_step(sk_contact_output *co, sk_system *sys, int initial, const double *u, double t,
                                 int64_t step) {
  const sk_model *m = co->model;
  co->n_records = 0;
  co->failed = 0;
  sk_status status = sk_system_points(sys, initial, collect_point, co);
  if (status == SK_OK && co->failed) status = no_memory("the contact points");
  SK_TRY(sk_system_collective(sys, status));
  if (co->write_csv) SK_TRY(sk_system_collective(sys, write_rows(co, t, step)));
  if (!co->write_vtu) return SK_OK;
  status = sk_system_collective(sys, sk_contact_surfaces_fields(co->surfaces, co->records, co->n_records));
  if (status == SK_OK && co->pieces_dir[0]) {
    char prefix[64];
    snprintf(prefix, sizeof prefix, "contact-%06lld", (long long)step);
    status = sk_contact_surfaces_write(co->surfaces, sys, u, co->pieces_dir, prefix);
  }
  if (status == SK_OK && m->rank == 0 && co->dir[0]) {
    char file[64], path[1400];
    snprintf(file, sizeof file, "contact-%06lld.pvtu", (long long)step);
    status = sk_pvd_add(co->contact_pvd, t, file);
    if (status == SK_OK && co->obstacle_pvd) {
      snprintf(file, sizeof file, "obstacles-%06lld.vtu", (long long)step);
      snprintf(path, sizeof path, "%s/%s", co->dir, file);
      status = sk_obstacle_output_write(co->obstacles, t, path);
      if (status == SK_OK) status = sk_pvd_add(co->obstacle_pvd, t, file);
    }
  }
  return sk_system_collective(sys, status);
}
