/* The contact results of a run at its output steps: contact.csv, one long table with a row per contact point and
 * output step; the contact fields on the mesh nodes (the bodies' VTU); the slave surfaces with point and cell fields
 * (contact-NNNNNN.vtu in contact.pvd); the rigid obstacles (obstacles-NNNNNN.vtu in obstacles.pvd).
 *
 * Every column means the same for every plugin (docs/user-guide.md, docs/plugin-abi.md §8): the points a plugin
 * reports are completed here. A plugin that knows only forces (sk_contact_point.forces) gets them divided by the
 * node's tributary reference measure of the slave surface; a plugin that reports tractions gets its normal force as
 * pressure x area.
 *
 * On several ranks each holds its part of the slave surfaces (docs/design.md, "What each rank holds"): the contact
 * nodes and faces are numbered over the whole surfaces (nodes by mesh id, faces by their whole index), each point is
 * reported by the rank that owns its entity, and the node and face fields, the contact nodes' positions and the
 * surfaces' connectivity are sums over ranks to rank 0, which writes the files; contact.csv's rows (the points) are
 * gathered to it and written in an order that does not depend on the partition (pair, node, face). The completed node
 * fields go back to every rank for the nodes of its piece of the bodies' VTU (recorder.c). */
#define _GNU_SOURCE
#include "contact_output.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "obstacle_output.h"
#include "stickslip/contact.h"
#include "stickslip/fe.h"

/* One contact point as contact.csv writes it after `step` and `time`. */
enum {
  R_PAIR, R_NODE, R_FACE, R_X, R_REFERENCE = R_X + 3, R_NORMAL = R_REFERENCE + 3, R_GAP = R_NORMAL + 3, R_STATE,
  R_PRESSURE, R_NORMAL_FORCE, R_AREA, R_TRACTION, R_SLIP_INCREMENT = R_TRACTION + 3, R_SLIP = R_SLIP_INCREMENT + 3,
  R_MULTIPLIER, N_RECORD
};
static const char *const csv_columns[2 + N_RECORD] = {
    "step",        "time",        "pair",        "node",       "face",       "x",
    "y",           "z",           "reference_x", "reference_y", "reference_z", "normal_x",
    "normal_y",    "normal_z",    "gap",         "state",      "pressure",   "normal_force",
    "area",        "traction_x",  "traction_y",  "traction_z", "slip_increment_x", "slip_increment_y",
    "slip_increment_z", "slip",   "multiplier"};

/* The contact fields of a node or a face (VTU), and the weight they were summed with. */
enum {
  F_PRESSURE, F_GAP, F_STATE, F_NORMAL_TRACTION, F_TANGENTIAL_TRACTION = F_NORMAL_TRACTION + 3,
  F_NORMAL_FORCE = F_TANGENTIAL_TRACTION + 3, F_SLIP_INCREMENT, F_SLIP = F_SLIP_INCREMENT + 3, F_MULTIPLIER, F_WEIGHT,
  N_FIELD
};
enum { NEEDS_NOTHING, NEEDS_FRICTION, NEEDS_MULTIPLIERS };
typedef struct {
  const char *name;
  int components, offset, on_faces, needs;
} field_info;
static const field_info vtu_fields[] = {
    {"contact_pressure", 1, F_PRESSURE, 1, NEEDS_NOTHING},
    {"contact_gap", 1, F_GAP, 1, NEEDS_NOTHING},
    {"contact_state", 1, F_STATE, 1, NEEDS_NOTHING},
    {"contact_normal_traction", 3, F_NORMAL_TRACTION, 1, NEEDS_NOTHING},
    {"contact_tangential_traction", 3, F_TANGENTIAL_TRACTION, 1, NEEDS_NOTHING},
    {"contact_normal_force", 1, F_NORMAL_FORCE, 0, NEEDS_NOTHING},
    {"contact_slip_increment", 3, F_SLIP_INCREMENT, 1, NEEDS_FRICTION},
    {"contact_slip", 1, F_SLIP, 1, NEEDS_FRICTION},
    {"contact_multiplier", 1, F_MULTIPLIER, 1, NEEDS_MULTIPLIERS}};
enum { N_VTU_FIELDS = sizeof vtu_fields / sizeof vtu_fields[0], VTU_COMPONENTS = 15 /* theirs together */ };

typedef struct {
  const sk_surface *surface; /* the pair's slave surface (this rank's part) */
  int first_face;            /* its whole faces in the face arrays (pairs on one surface share them) */
  double *tributary;         /* reference tributary measure per held surface node (surface->nodes order; right at
                                the nodes this rank owns, whose faces it all holds) */
} pair_info;

struct sk_contact_output {
  const sk_model *model;
  char dir[1100];            /* the staging folder (rank 0), "" elsewhere */
  int write_csv, write_vtu;
  int with_friction, with_multipliers; /* the optional VTU fields: some pair's plugin has friction / multipliers */
  pair_info *pairs;
  int n_cnodes;              /* contact nodes: the nodes of every whole slave surface */
  int64_t *cnode_gid;        /* their mesh ids, sorted (every rank) */
  int *cnode_of_node;        /* per node this rank holds: index among the contact nodes, or -1 */
  int n_faces;               /* faces of every distinct whole slave surface */
  sk_elem_type *face_type;   /* rank 0, as the four below */
  int *face_offsets, *face_conn; /* the faces as cells over contact nodes */
  double *face_pair;         /* the pair of each face (the first one on a shared surface) */
  double *face_index;        /* its index in its slave surface (contact.csv's `face`) */
  double *cnode_id;          /* the mesh node id of each contact node */
  double *cnode_X;           /* rank 0: the contact nodes' reference positions, 3 each */
  double *cnode_u_local, *cnode_u; /* their displacements: this rank's owned ones, the sum on rank 0 */
  double *node_local, *node_sum; /* n_cnodes x N_FIELD */
  double *face_local, *face_sum; /* n_faces x N_FIELD */
  double *records;           /* this rank's points of the step, N_RECORD each */
  int n_records, cap_records, failed;
  double *node_fields;       /* the fields at the nodes this rank holds, for its piece of the bodies' VTU */
  int n_node_fields;
  sk_vtu_field node_field_list[N_VTU_FIELDS];
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
  void *all[] = {co->pairs,        co->cnode_gid,  co->cnode_of_node, co->face_type,     co->face_offsets,
                 co->face_conn,    co->face_pair,  co->face_index,    co->cnode_id,      co->cnode_X,
                 co->cnode_u_local, co->cnode_u,   co->node_local,    co->node_sum,      co->face_local,
                 co->face_sum,     co->records,    co->node_fields};
  for (size_t k = 0; k < sizeof all / sizeof all[0]; ++k) free(all[k]);
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

static int compare_int64(const void *a, const void *b) {
  const int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
  return (x > y) - (x < y);
}

/* The contact node of mesh id `gid`, or -1. */
static int cnode_of_gid(const sk_contact_output *co, int64_t gid) {
  const int64_t *at = bsearch(&gid, co->cnode_gid, (size_t)co->n_cnodes, sizeof(int64_t), compare_int64);
  return at ? (int)(at - co->cnode_gid) : -1;
}

static int owns_node(const sk_model *m, int node) { return m->node_owner[node] == m->rank; }

/* 1 when pair k's slave surface is an earlier pair's (they share its faces). */
static int surface_seen(const sk_contact_output *co, int k) {
  for (int j = 0; j < k; ++j)
    if (co->pairs[j].first_face == co->pairs[k].first_face) return 1;
  return 0;
}

/* The contact nodes (the mesh ids of the whole slave surfaces, from the ranks that own them; every rank gets the
 * list, which is surface-sized) and this rank's lookup from its nodes. Collective. */
static sk_status number_contact_nodes(sk_contact_output *co) {
  const sk_model *m = co->model;
  int n_mine = 0;
  for (int k = 0; k < m->n_pairs; ++k) n_mine += m->pairs[k].slave.n_nodes;
  int64_t *mine = malloc(sizeof(int64_t) * ((size_t)n_mine + 1));
  int *counts = calloc((size_t)m->n_ranks, sizeof(int)), *displs = calloc((size_t)m->n_ranks, sizeof(int));
  int ok = mine && counts && displs;
  n_mine = 0;
  for (int k = 0; ok && k < m->n_pairs; ++k) {
    const sk_surface *s = &m->pairs[k].slave;
    for (int i = 0; i < s->n_nodes; ++i)
      if (owns_node(m, s->nodes[i])) mine[n_mine++] = m->node_gid ? m->node_gid[s->nodes[i]] : s->nodes[i];
  }
  if (ok) { /* one entry per mesh id from this rank: fewer to send */
    qsort(mine, (size_t)n_mine, sizeof(int64_t), compare_int64);
    int unique = 0;
    for (int i = 0; i < n_mine; ++i)
      if (unique == 0 || mine[i] != mine[unique - 1]) mine[unique++] = mine[i];
    n_mine = unique;
  }
  MPI_Allreduce(MPI_IN_PLACE, &ok, 1, MPI_INT, MPI_MIN, m->comm);
  if (!ok) {
    free(mine), free(counts), free(displs);
    return no_memory("the contact output");
  }
  MPI_Allgather(&n_mine, 1, MPI_INT, counts, 1, MPI_INT, m->comm);
  int total = 0;
  for (int r = 0; r < m->n_ranks; ++r) {
    displs[r] = total;
    total += counts[r];
  }
  co->cnode_gid = malloc(sizeof(int64_t) * ((size_t)total + 1));
  co->cnode_of_node = malloc(sizeof(int) * ((size_t)m->n_nodes + 1));
  ok = co->cnode_gid && co->cnode_of_node;
  MPI_Allreduce(MPI_IN_PLACE, &ok, 1, MPI_INT, MPI_MIN, m->comm);
  if (ok) MPI_Allgatherv(mine, n_mine, MPI_INT64_T, co->cnode_gid, counts, displs, MPI_INT64_T, m->comm);
  free(mine), free(counts), free(displs);
  if (!ok) return no_memory("the contact output");
  /* each node has one owner: the list has each mesh id once; sorted for the lookups */
  qsort(co->cnode_gid, (size_t)total, sizeof(int64_t), compare_int64);
  co->n_cnodes = total;
  for (int a = 0; a < m->n_nodes; ++a) co->cnode_of_node[a] = -1;
  for (int k = 0; k < m->n_pairs; ++k) {
    const sk_surface *s = &m->pairs[k].slave;
    for (int i = 0; i < s->n_nodes; ++i)
      co->cnode_of_node[s->nodes[i]] = cnode_of_gid(co, m->node_gid ? m->node_gid[s->nodes[i]] : s->nodes[i]);
  }
  return SK_OK;
}

/* The contact nodes and the faces of the distinct whole slave surfaces, as cells over them (rank 0), from the
 * faces and nodes each rank owns. Collective. */
static sk_status build_surfaces(sk_contact_output *co) {
  const sk_model *m = co->model;
  const int root = m->rank == 0;
  SK_TRY(number_contact_nodes(co));
  size_t n_conn = 0;
  for (int k = 0; k < m->n_pairs; ++k) {
    const sk_surface *s = &m->pairs[k].slave;
    pair_info *p = &co->pairs[k];
    p->surface = s;
    p->first_face = -1;
    for (int j = 0; j < k && p->first_face < 0; ++j)
      if (strcmp(m->pairs[j].slave.name, s->name) == 0) p->first_face = co->pairs[j].first_face;
    p->tributary = malloc(sizeof(double) * ((size_t)s->n_nodes + 1));
    if (!p->tributary) return no_memory("the contact output");
    sk_surface_tributary_measures(s, m->X, p->tributary);
    if (p->first_face >= 0) continue;
    p->first_face = co->n_faces;
    co->n_faces += s->n_faces_global;
    n_conn += (size_t)s->n_faces_global * (size_t)s->nen;
  }
  /* the connectivity over contact nodes: each face filled by its owner, summed to rank 0 (as the positions) */
  int *conn_local = calloc(n_conn + 1, sizeof(int));
  double *X_local = calloc(3 * (size_t)co->n_cnodes + 1, sizeof(double));
  co->face_conn = root ? calloc(n_conn + 1, sizeof(int)) : NULL;
  co->cnode_X = root ? calloc(3 * (size_t)co->n_cnodes + 1, sizeof(double)) : NULL;
  co->face_offsets = malloc(sizeof(int) * ((size_t)co->n_faces + 1));
  int ok = conn_local && X_local && co->face_offsets && (!root || (co->face_conn && co->cnode_X));
  MPI_Allreduce(MPI_IN_PLACE, &ok, 1, MPI_INT, MPI_MIN, m->comm);
  if (!ok) {
    free(conn_local), free(X_local);
    return no_memory("the contact output");
  }
  co->face_offsets[0] = 0;
  for (int k = 0; k < m->n_pairs; ++k) {
    const sk_surface *s = co->pairs[k].surface;
    const int first = co->pairs[k].first_face;
    if (surface_seen(co, k)) continue;
    for (int f = 0; f < s->n_faces_global; ++f) co->face_offsets[first + f + 1] = co->face_offsets[first + f] + s->nen;
    for (int f = 0; f < s->n_faces; ++f) {
      if ((s->face_owner ? s->face_owner[f] : 0) != m->rank) continue;
      const int64_t c = first + (s->face_index ? s->face_index[f] : f);
      for (int a = 0; a < s->nen; ++a)
        conn_local[co->face_offsets[c] + a] = co->cnode_of_node[s->conn[(size_t)f * s->nen + a]];
    }
  }
  for (int a = 0; a < m->n_nodes; ++a)
    if (co->cnode_of_node[a] >= 0 && owns_node(m, a))
      for (int i = 0; i < m->dim; ++i) X_local[3 * (size_t)co->cnode_of_node[a] + i] = m->X[(int64_t)a * m->dim + i];
  MPI_Reduce(conn_local, co->face_conn, (int)n_conn, MPI_INT, MPI_SUM, 0, m->comm);
  MPI_Reduce(X_local, co->cnode_X, 3 * co->n_cnodes, MPI_DOUBLE, MPI_SUM, 0, m->comm);
  free(conn_local);
  free(X_local);
  co->cnode_u_local = malloc(sizeof(double) * (3 * (size_t)co->n_cnodes + 1));
  co->cnode_u = root ? malloc(sizeof(double) * (3 * (size_t)co->n_cnodes + 1)) : NULL;
  const size_t node_values = (size_t)N_FIELD * ((size_t)co->n_cnodes + 1);
  const size_t face_values = (size_t)N_FIELD * ((size_t)co->n_faces + 1);
  co->node_local = malloc(sizeof(double) * node_values);
  co->node_sum = malloc(sizeof(double) * node_values);
  co->face_local = malloc(sizeof(double) * face_values);
  co->face_sum = malloc(sizeof(double) * face_values);
  ok = co->cnode_u_local && (!root || co->cnode_u) && co->node_local && co->node_sum && co->face_local && co->face_sum;
  if (ok && root) {
    co->face_type = malloc(sizeof(sk_elem_type) * ((size_t)co->n_faces + 1));
    co->face_pair = malloc(sizeof(double) * ((size_t)co->n_faces + 1));
    co->face_index = malloc(sizeof(double) * ((size_t)co->n_faces + 1));
    co->cnode_id = malloc(sizeof(double) * ((size_t)co->n_cnodes + 1));
    ok = co->face_type && co->face_pair && co->face_index && co->cnode_id;
  }
  MPI_Allreduce(MPI_IN_PLACE, &ok, 1, MPI_INT, MPI_MIN, m->comm);
  if (!ok) return no_memory("the contact output");
  if (!root) return SK_OK;
  for (int a = 0; a < co->n_cnodes; ++a) co->cnode_id[a] = (double)co->cnode_gid[a];
  for (int k = 0; k < m->n_pairs; ++k) {
    const int first = co->pairs[k].first_face;
    if (surface_seen(co, k)) continue;
    for (int f = 0; f < co->pairs[k].surface->n_faces_global; ++f) {
      co->face_type[first + f] = co->pairs[k].surface->face_type;
      co->face_pair[first + f] = k;
      co->face_index[first + f] = f;
    }
  }
  return SK_OK;
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
  for (int k = 0; k < model->n_pairs; ++k) {
    const uint64_t caps = model->pairs[k].plugin->caps;
    co->with_friction |= (caps & SK_CAP_FRICTION) != 0;
    co->with_multipliers |= (caps & SK_CAP_MULTIPLIERS) != 0;
  }
  SK_TRY(build_surfaces(co));
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

/* The VTU fields of a point (finite numbers: a missing quantity reads 0 there). */
static void point_fields(const double *r, double *f) {
  const double pressure = isfinite(r[R_PRESSURE]) ? r[R_PRESSURE] : 0.0;
  f[F_PRESSURE] = pressure;
  f[F_GAP] = isfinite(r[R_GAP]) ? r[R_GAP] : 0.0;
  f[F_STATE] = r[R_STATE];
  for (int i = 0; i < 3; ++i) {
    f[F_NORMAL_TRACTION + i] = pressure * r[R_NORMAL + i];
    f[F_TANGENTIAL_TRACTION + i] = isfinite(r[R_TRACTION + i]) ? r[R_TRACTION + i] : 0.0;
    f[F_SLIP_INCREMENT + i] = isfinite(r[R_SLIP_INCREMENT + i]) ? r[R_SLIP_INCREMENT + i] : 0.0;
  }
  f[F_NORMAL_FORCE] = isfinite(r[R_NORMAL_FORCE]) ? r[R_NORMAL_FORCE] : 0.0;
  f[F_SLIP] = isfinite(r[R_SLIP]) ? r[R_SLIP] : 0.0;
  f[F_MULTIPLIER] = isfinite(r[R_MULTIPLIER]) ? r[R_MULTIPLIER] : 0.0;
}

/* This rank's points on the contact nodes (a node reported by several pairs shows the one most in contact) and the
 * Gauss points on their faces (sums weighted by each point's measure; the state is the face's largest). */
static void accumulate(sk_contact_output *co) {
  memset(co->node_local, 0, sizeof(double) * N_FIELD * (size_t)co->n_cnodes);
  memset(co->face_local, 0, sizeof(double) * N_FIELD * (size_t)co->n_faces);
  double f[N_FIELD];
  for (int k = 0; k < co->n_records; ++k) {
    const double *r = co->records + N_RECORD * (size_t)k;
    point_fields(r, f);
    const int node = (int)r[R_NODE], face = (int)r[R_FACE], pair = (int)r[R_PAIR];
    if (node >= 0) {
      const int cnode = cnode_of_gid(co, node);
      if (cnode < 0) continue; /* not on a slave surface: contact.csv only */
      double *to = co->node_local + N_FIELD * (size_t)cnode;
      const int replaces = to[F_WEIGHT] == 0.0 || f[F_STATE] > to[F_STATE] ||
                           (f[F_STATE] == to[F_STATE] && f[F_GAP] < to[F_GAP]);
      if (!replaces) continue;
      memcpy(to, f, sizeof(double) * F_WEIGHT);
      to[F_WEIGHT] = 1.0;
    } else if (face >= 0 && pair >= 0 && pair < co->model->n_pairs && face < co->pairs[pair].surface->n_faces_global) {
      double *to = co->face_local + N_FIELD * (size_t)(co->pairs[pair].first_face + face);
      const double w = isfinite(r[R_AREA]) && r[R_AREA] > 0.0 ? r[R_AREA] : 1.0;
      for (int i = 0; i < F_WEIGHT; ++i)
        if (i != F_STATE) to[i] += w * f[i];
      to[F_STATE] = fmax(to[F_STATE], f[F_STATE]);
      to[F_WEIGHT] += w;
    }
  }
}

/* Rank 0, after the sums: the face means of Gauss points, faces without them from their nodes, nodes without a point
 * of their own from the faces around them (weighted by the faces' measures). */
static void complete_fields(sk_contact_output *co) {
  double *nodes = co->node_sum, *faces = co->face_sum;
  for (int c = 0; c < co->n_faces; ++c) {
    double *f = faces + N_FIELD * (size_t)c;
    if (f[F_WEIGHT] <= 0.0) continue;
    for (int i = 0; i < F_WEIGHT; ++i)
      if (i != F_STATE) f[i] /= f[F_WEIGHT];
  }
  double *from_faces = co->node_local; /* free after the sums: node means of the Gauss faces */
  memset(from_faces, 0, sizeof(double) * N_FIELD * (size_t)co->n_cnodes);
  for (int c = 0; c < co->n_faces; ++c) {
    const double *f = faces + N_FIELD * (size_t)c;
    if (f[F_WEIGHT] <= 0.0) continue;
    for (int k = co->face_offsets[c]; k < co->face_offsets[c + 1]; ++k) {
      double *to = from_faces + N_FIELD * (size_t)co->face_conn[k];
      for (int i = 0; i < F_WEIGHT; ++i)
        if (i != F_STATE) to[i] += f[F_WEIGHT] * f[i];
      to[F_STATE] = fmax(to[F_STATE], f[F_STATE]);
      to[F_WEIGHT] += f[F_WEIGHT];
    }
  }
  for (int a = 0; a < co->n_cnodes; ++a) {
    double *to = nodes + N_FIELD * (size_t)a;
    const double *f = from_faces + N_FIELD * (size_t)a;
    if (to[F_WEIGHT] > 0.0 || f[F_WEIGHT] <= 0.0) continue;
    for (int i = 0; i < F_WEIGHT; ++i) to[i] = i == F_STATE ? f[i] : f[i] / f[F_WEIGHT];
    to[F_NORMAL_FORCE] = 0.0; /* a force belongs to a point, not to a mean */
    to[F_WEIGHT] = f[F_WEIGHT];
  }
  for (int c = 0; c < co->n_faces; ++c) {
    double *f = faces + N_FIELD * (size_t)c;
    if (f[F_WEIGHT] > 0.0) continue;
    const int nen = co->face_offsets[c + 1] - co->face_offsets[c];
    for (int k = co->face_offsets[c]; k < co->face_offsets[c + 1]; ++k) {
      const double *from = nodes + N_FIELD * (size_t)co->face_conn[k];
      for (int i = 0; i < F_WEIGHT; ++i)
        f[i] = i == F_STATE ? fmax(f[i], from[i]) : f[i] + from[i] / nen;
    }
  }
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

static int field_wanted(const sk_contact_output *co, const field_info *f) {
  return f->needs == NEEDS_NOTHING || (f->needs == NEEDS_FRICTION && co->with_friction) ||
         (f->needs == NEEDS_MULTIPLIERS && co->with_multipliers);
}

/* The fields at the nodes this rank holds (local numbering; 0 away from the contact) for its piece of the bodies' VTU,
 * field after field, from the completed node sums (every rank has them). */
static sk_status spread_node_fields(sk_contact_output *co) {
  const int nn = co->model->n_nodes;
  if (!co->node_fields && !(co->node_fields = malloc(sizeof(double) * VTU_COMPONENTS * ((size_t)nn + 1))))
    return no_memory("the VTU output");
  memset(co->node_fields, 0, sizeof(double) * VTU_COMPONENTS * (size_t)nn);
  double *values = co->node_fields;
  co->n_node_fields = 0;
  for (int k = 0; k < N_VTU_FIELDS; ++k) {
    const field_info *f = &vtu_fields[k];
    if (!field_wanted(co, f)) continue;
    for (int a = 0; a < nn; ++a)
      if (co->cnode_of_node[a] >= 0)
        memcpy(values + (size_t)f->components * a, co->node_sum + N_FIELD * (size_t)co->cnode_of_node[a] + f->offset,
               sizeof(double) * (size_t)f->components);
    co->node_field_list[co->n_node_fields++] = (sk_vtu_field){f->name, f->components, values};
    values += (size_t)f->components * nn;
  }
  return SK_OK;
}

int sk_contact_output_node_fields(const sk_contact_output *co, sk_vtu_field *fields, int max) {
  const int n = co && co->node_fields ? (co->n_node_fields < max ? co->n_node_fields : max) : 0;
  for (int k = 0; k < n; ++k) fields[k] = co->node_field_list[k];
  return n;
}

/* contact-NNNNNN.vtu: the slave surfaces at the displacement of the step (cnode_u) with the contact fields on their
 * nodes and faces (rank 0). */
static sk_status write_surfaces(sk_contact_output *co, double t, int64_t step) {
  const int n_points = co->n_cnodes, n_cells = co->n_faces;
  double *points = calloc(3 * (size_t)n_points + 1, sizeof(double));
  double *point_values = malloc(sizeof(double) * VTU_COMPONENTS * ((size_t)n_points + 1));
  double *cell_values = malloc(sizeof(double) * VTU_COMPONENTS * ((size_t)n_cells + 1));
  sk_status status = points && point_values && cell_values ? SK_OK : no_memory("the contact VTU");
  sk_vtu_field point_list[N_VTU_FIELDS + 1], cell_list[N_VTU_FIELDS + 2];
  int n_point_fields = 0, n_cell_fields = 0;
  if (status == SK_OK) {
    for (int k = 0; k < 3 * n_points; ++k) points[k] = co->cnode_X[k] + co->cnode_u[k];
    double *pv = point_values, *cv = cell_values;
    for (int k = 0; k < N_VTU_FIELDS; ++k) {
      const field_info *f = &vtu_fields[k];
      if (!field_wanted(co, f)) continue;
      for (int a = 0; a < n_points; ++a)
        memcpy(pv + (size_t)f->components * a, co->node_sum + N_FIELD * (size_t)a + f->offset,
               sizeof(double) * (size_t)f->components);
      point_list[n_point_fields++] = (sk_vtu_field){f->name, f->components, pv};
      pv += (size_t)f->components * n_points;
      if (!f->on_faces) continue;
      for (int c = 0; c < n_cells; ++c)
        memcpy(cv + (size_t)f->components * c, co->face_sum + N_FIELD * (size_t)c + f->offset,
               sizeof(double) * (size_t)f->components);
      cell_list[n_cell_fields++] = (sk_vtu_field){f->name, f->components, cv};
      cv += (size_t)f->components * n_cells;
    }
    point_list[n_point_fields++] = (sk_vtu_field){"node", 1, co->cnode_id};
    cell_list[n_cell_fields++] = (sk_vtu_field){"pair", 1, co->face_pair};
    cell_list[n_cell_fields++] = (sk_vtu_field){"face", 1, co->face_index};
    char file[64], path[1400];
    snprintf(file, sizeof file, "contact-%06lld.vtu", (long long)step);
    snprintf(path, sizeof path, "%s/%s", co->dir, file);
    status = sk_vtu_write(path, n_points, points, n_cells, co->face_type, co->face_offsets, co->face_conn,
                          n_point_fields, point_list, n_cell_fields, cell_list);
    if (status == SK_OK) status = sk_pvd_add(co->contact_pvd, t, file);
  }
  free(points);
  free(point_values);
  free(cell_values);
  return status;
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
  accumulate(co);
  /* the contact nodes' displacements, each from its owner */
  memset(co->cnode_u_local, 0, sizeof(double) * 3 * (size_t)co->n_cnodes);
  for (int a = 0; a < m->n_nodes; ++a)
    if (co->cnode_of_node[a] >= 0 && owns_node(m, a))
      for (int i = 0; i < m->dim; ++i)
        co->cnode_u_local[3 * (size_t)co->cnode_of_node[a] + i] = u[(int64_t)a * m->dim + i];
  MPI_Reduce(co->cnode_u_local, co->cnode_u, 3 * co->n_cnodes, MPI_DOUBLE, MPI_SUM, 0, m->comm);
  MPI_Reduce(co->node_local, co->node_sum, N_FIELD * co->n_cnodes, MPI_DOUBLE, MPI_SUM, 0, m->comm);
  MPI_Reduce(co->face_local, co->face_sum, N_FIELD * co->n_faces, MPI_DOUBLE, MPI_SUM, 0, m->comm);
  status = SK_OK;
  if (m->rank == 0) {
    complete_fields(co);
    if (co->dir[0]) status = write_surfaces(co, t, step);
    if (status == SK_OK && co->dir[0] && co->obstacle_pvd) {
      char file[64], path[1400];
      snprintf(file, sizeof file, "obstacles-%06lld.vtu", (long long)step);
      snprintf(path, sizeof path, "%s/%s", co->dir, file);
      status = sk_obstacle_output_write(co->obstacles, t, path);
      if (status == SK_OK) status = sk_pvd_add(co->obstacle_pvd, t, file);
    }
  }
  /* the completed node fields (a surface's worth) to every rank, for the nodes of its piece of the bodies' VTU */
  MPI_Bcast(co->node_sum, N_FIELD * co->n_cnodes, MPI_DOUBLE, 0, m->comm);
  if (status == SK_OK) status = spread_node_fields(co);
  return sk_system_collective(sys, status);
}
