/* The contact fields on the slave surfaces over the ranks (contact_surface.h).
 *
 * A rank holds the faces of its part of each slave surface (model_distribute.c: the faces whose nodes it holds, each
 * with its whole index and owner) and their nodes, the contact nodes. The owner of a node holds every face around it
 * and the owner of a face all of its nodes, so the fields are completed by owners: the points' fields are added where
 * they are reported and summed into the owners (reverse exchanges), the owners of faces take their means and send them
 * to the faces' other holders, the owners of nodes complete theirs from the faces around them and send them on, and
 * the owners of faces without points of their own take their nodes' mean. Each rank writes the faces it owns; no rank
 * holds an array over a whole surface. */
#define _GNU_SOURCE
#include "contact_surface.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "stickslip/contact.h"
#include "vtu_pieces.h"

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

/* A held face by its whole number (a distinct surface's first_face + its index there). */
typedef struct {
  int64_t whole;
  int face;
} face_key;

struct sk_contact_surfaces {
  const sk_model *model;
  int with_friction, with_multipliers;
  int *first_face;           /* per pair: the whole number of its surface's face 0 (pairs on one surface share it) */
  int n_nodes;               /* contact nodes held: the nodes of this rank's parts of the slave surfaces */
  int *node_of;              /* their model nodes */
  int *contact_node;         /* per model node: its contact node, or -1 */
  int n_faces;               /* faces held, over the distinct slave surfaces */
  const sk_surface **face_surface;
  int *face_in_surface, *face_pair;
  int64_t *face_whole;       /* first_face + index in the surface */
  face_key *by_whole;        /* sorted by whole number */
  double *node_values, *face_values, *from_faces; /* N_FIELD per contact node / face */
  sk_exchange node_exchange, face_exchange;       /* over the N_FIELD values of each ghost node / face */
  double *node_fields;       /* per model node this rank holds, VTU_COMPONENTS (the bodies' VTU) */
  int n_node_fields;
  sk_vtu_field node_field_list[N_VTU_FIELDS];
};

static sk_status no_memory(const char *what) { return sk_error_set(SK_ERR_NOMEM, "out of memory for %s", what); }

void sk_contact_surfaces_free(sk_contact_surfaces *cs) {
  if (!cs) return;
  sk_exchange_free(&cs->node_exchange);
  sk_exchange_free(&cs->face_exchange);
  void *all[] = {cs->first_face, cs->node_of,   cs->contact_node, cs->face_surface, cs->face_in_surface,
                 cs->face_pair,  cs->face_whole, cs->by_whole,    cs->node_values,  cs->face_values,
                 cs->from_faces, cs->node_fields};
  for (size_t k = 0; k < sizeof all / sizeof all[0]; ++k) free(all[k]);
  free(cs);
}

static int compare_keys(const void *a, const void *b) {
  const int64_t x = ((const face_key *)a)->whole, y = ((const face_key *)b)->whole;
  return (x > y) - (x < y);
}

/* The held face of whole number `whole`, or -1. */
static int face_of_whole(const sk_contact_surfaces *cs, int64_t whole) {
  const face_key key = {whole, -1};
  const face_key *at = bsearch(&key, cs->by_whole, (size_t)cs->n_faces, sizeof key, compare_keys);
  return at ? at->face : -1;
}

/* The owners' lookups of the exchanges: an entry is (node or face) * N_FIELD + field. */
static int64_t owned_node_entry(void *ctx, int64_t gid) {
  const sk_contact_surfaces *cs = ctx;
  const int node = sk_model_node_of(cs->model, gid / N_FIELD);
  const int c = node >= 0 && cs->model->node_owner[node] == cs->model->rank ? cs->contact_node[node] : -1;
  return c >= 0 ? (int64_t)c * N_FIELD + gid % N_FIELD : -1;
}

static int64_t owned_face_entry(void *ctx, int64_t gid) {
  const sk_contact_surfaces *cs = ctx;
  const int face = face_of_whole(cs, gid / N_FIELD);
  const sk_surface *s = face >= 0 ? cs->face_surface[face] : NULL;
  const int owner = s && s->face_owner ? s->face_owner[cs->face_in_surface[face]] : 0;
  return s && owner == cs->model->rank ? (int64_t)face * N_FIELD + gid % N_FIELD : -1;
}

static int face_owner(const sk_contact_surfaces *cs, int face) {
  const sk_surface *s = cs->face_surface[face];
  return s->face_owner ? s->face_owner[cs->face_in_surface[face]] : 0;
}

/* The exchanges of the ghost nodes' and ghost faces' fields with their owners. Collective. */
static sk_status plan_exchanges(sk_contact_surfaces *cs) {
  const sk_model *m = cs->model;
  int64_t n_ghost_nodes = 0, n_ghost_faces = 0;
  for (int c = 0; c < cs->n_nodes; ++c) n_ghost_nodes += m->node_owner[cs->node_of[c]] != m->rank;
  for (int f = 0; f < cs->n_faces; ++f) n_ghost_faces += face_owner(cs, f) != m->rank;
  const int64_t most = (n_ghost_nodes > n_ghost_faces ? n_ghost_nodes : n_ghost_faces) * N_FIELD + 1;
  int64_t *local = malloc(sizeof(int64_t) * (size_t)most), *gid = malloc(sizeof(int64_t) * (size_t)most);
  int *owner = malloc(sizeof(int) * (size_t)most);
  int ok = local && gid && owner;
  MPI_Allreduce(MPI_IN_PLACE, &ok, 1, MPI_INT, MPI_MIN, m->comm);
  sk_status status = ok ? SK_OK : no_memory("the contact output");
  int64_t g = 0;
  for (int c = 0; ok && c < cs->n_nodes; ++c) {
    const int node = cs->node_of[c];
    if (m->node_owner[node] == m->rank) continue;
    for (int i = 0; i < N_FIELD; ++i, ++g) {
      local[g] = (int64_t)c * N_FIELD + i;
      gid[g] = m->node_gid[node] * N_FIELD + i;
      owner[g] = m->node_owner[node];
    }
  }
  if (ok) status = sk_exchange_plan(&cs->node_exchange, m->comm, g, local, gid, owner, owned_node_entry, cs);
  g = 0;
  for (int f = 0; ok && f < cs->n_faces; ++f) {
    if (face_owner(cs, f) == m->rank) continue;
    for (int i = 0; i < N_FIELD; ++i, ++g) {
      local[g] = (int64_t)f * N_FIELD + i;
      gid[g] = cs->face_whole[f] * N_FIELD + i;
      owner[g] = face_owner(cs, f);
    }
  }
  if (ok && status == SK_OK)
    status = sk_exchange_plan(&cs->face_exchange, m->comm, g, local, gid, owner, owned_face_entry, cs);
  free(local);
  free(gid);
  free(owner);
  return status;
}

/* 1 when pair k's slave surface is an earlier pair's (they share its faces). */
static int surface_seen(const sk_model *m, int k) {
  for (int j = 0; j < k; ++j)
    if (strcmp(m->pairs[j].slave.name, m->pairs[k].slave.name) == 0) return 1;
  return 0;
}

sk_status sk_contact_surfaces_open(const sk_model *model, int with_friction, int with_multipliers,
                                   sk_contact_surfaces **out) {
  sk_contact_surfaces *cs = calloc(1, sizeof *cs);
  *out = cs;
  int ok = cs != NULL;
  if (cs) {
    cs->model = model;
    cs->with_friction = with_friction;
    cs->with_multipliers = with_multipliers;
    cs->first_face = malloc(sizeof(int) * ((size_t)model->n_pairs + 1));
    cs->contact_node = malloc(sizeof(int) * ((size_t)model->n_nodes + 1));
    ok = cs->first_face && cs->contact_node;
  }
  if (ok) {
    int whole = 0;
    for (int k = 0; k < model->n_pairs; ++k) {
      const sk_surface *s = &model->pairs[k].slave;
      cs->first_face[k] = -1;
      for (int j = 0; j < k && cs->first_face[k] < 0; ++j)
        if (strcmp(model->pairs[j].slave.name, s->name) == 0) cs->first_face[k] = cs->first_face[j];
      if (cs->first_face[k] >= 0) continue;
      cs->first_face[k] = whole;
      whole += s->n_faces_global;
      cs->n_faces += s->n_faces;
    }
    for (int a = 0; a < model->n_nodes; ++a) cs->contact_node[a] = -1;
    for (int k = 0; k < model->n_pairs; ++k)
      for (int i = 0; i < model->pairs[k].slave.n_nodes; ++i) {
        const int a = model->pairs[k].slave.nodes[i];
        if (cs->contact_node[a] < 0) cs->contact_node[a] = cs->n_nodes++;
      }
    const size_t nn = (size_t)cs->n_nodes + 1, nf = (size_t)cs->n_faces + 1;
    cs->node_of = malloc(sizeof(int) * nn);
    cs->face_surface = malloc(sizeof(sk_surface *) * nf);
    cs->face_in_surface = malloc(sizeof(int) * nf);
    cs->face_pair = malloc(sizeof(int) * nf);
    cs->face_whole = malloc(sizeof(int64_t) * nf);
    cs->by_whole = malloc(sizeof(face_key) * nf);
    cs->node_values = malloc(sizeof(double) * N_FIELD * nn);
    cs->from_faces = malloc(sizeof(double) * N_FIELD * nn);
    cs->face_values = malloc(sizeof(double) * N_FIELD * nf);
    ok = cs->node_of && cs->face_surface && cs->face_in_surface && cs->face_pair && cs->face_whole && cs->by_whole &&
         cs->node_values && cs->from_faces && cs->face_values;
  }
  if (ok) {
    for (int a = 0; a < model->n_nodes; ++a)
      if (cs->contact_node[a] >= 0) cs->node_of[cs->contact_node[a]] = a;
    int face = 0;
    for (int k = 0; k < model->n_pairs; ++k) {
      const sk_surface *s = &model->pairs[k].slave;
      if (surface_seen(model, k)) continue;
      for (int f = 0; f < s->n_faces; ++f, ++face) {
        cs->face_surface[face] = s;
        cs->face_in_surface[face] = f;
        cs->face_pair[face] = k;
        cs->face_whole[face] = cs->first_face[k] + (s->face_index ? s->face_index[f] : f);
        cs->by_whole[face] = (face_key){cs->face_whole[face], face};
      }
    }
    qsort(cs->by_whole, (size_t)cs->n_faces, sizeof(face_key), compare_keys);
  }
  MPI_Allreduce(MPI_IN_PLACE, &ok, 1, MPI_INT, MPI_MIN, model->comm);
  if (!ok) return no_memory("the contact output");
  return plan_exchanges(cs);
}

/* ---- the fields of a step ---------------------------------------------------------------------------------------- */

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
static void accumulate(sk_contact_surfaces *cs, const double *records, int n_records) {
  const sk_model *m = cs->model;
  memset(cs->node_values, 0, sizeof(double) * N_FIELD * (size_t)cs->n_nodes);
  memset(cs->face_values, 0, sizeof(double) * N_FIELD * (size_t)cs->n_faces);
  double f[N_FIELD];
  for (int k = 0; k < n_records; ++k) {
    const double *r = records + N_RECORD * (size_t)k;
    point_fields(r, f);
    const int pair = (int)r[R_PAIR];
    if (r[R_NODE] >= 0) {
      const int node = sk_model_node_of(m, (int64_t)r[R_NODE]);
      const int c = node >= 0 ? cs->contact_node[node] : -1;
      if (c < 0) continue; /* not on a slave surface: contact.csv only */
      double *to = cs->node_values + N_FIELD * (size_t)c;
      const int replaces = to[F_WEIGHT] == 0.0 || f[F_STATE] > to[F_STATE] ||
                           (f[F_STATE] == to[F_STATE] && f[F_GAP] < to[F_GAP]);
      if (!replaces) continue;
      memcpy(to, f, sizeof(double) * F_WEIGHT);
      to[F_WEIGHT] = 1.0;
    } else if (r[R_FACE] >= 0 && pair >= 0 && pair < m->n_pairs && r[R_FACE] < m->pairs[pair].slave.n_faces_global) {
      const int face = face_of_whole(cs, cs->first_face[pair] + (int64_t)r[R_FACE]);
      if (face < 0) continue; /* reported by its owner, which holds it */
      double *to = cs->face_values + N_FIELD * (size_t)face;
      const double w = isfinite(r[R_AREA]) && r[R_AREA] > 0.0 ? r[R_AREA] : 1.0;
      for (int i = 0; i < F_WEIGHT; ++i)
        if (i != F_STATE) to[i] += w * f[i];
      to[F_STATE] = fmax(to[F_STATE], f[F_STATE]);
      to[F_WEIGHT] += w;
    }
  }
}

/* The contact node of a face's a-th node. */
static int face_node(const sk_contact_surfaces *cs, int face, int a) {
  const sk_surface *s = cs->face_surface[face];
  return cs->contact_node[s->conn[(size_t)cs->face_in_surface[face] * s->nen + a]];
}

/* The sums completed (sk_contact_surfaces_fields). */
static void complete(sk_contact_surfaces *cs) {
  const int rank = cs->model->rank;
  sk_exchange_reverse(&cs->node_exchange, cs->node_values);
  sk_exchange_reverse(&cs->face_exchange, cs->face_values);
  /* the faces' means of their Gauss points, at their owners and then at every holder */
  for (int c = 0; c < cs->n_faces; ++c) {
    double *f = cs->face_values + N_FIELD * (size_t)c;
    if (face_owner(cs, c) != rank || f[F_WEIGHT] <= 0.0) continue;
    for (int i = 0; i < F_WEIGHT; ++i)
      if (i != F_STATE) f[i] /= f[F_WEIGHT];
  }
  sk_exchange_forward(&cs->face_exchange, cs->face_values);
  /* the nodes without a point of their own from the faces around them (weighted by the faces' measures): the owner
   * of a node holds all of them */
  memset(cs->from_faces, 0, sizeof(double) * N_FIELD * (size_t)cs->n_nodes);
  for (int c = 0; c < cs->n_faces; ++c) {
    const double *f = cs->face_values + N_FIELD * (size_t)c;
    if (f[F_WEIGHT] <= 0.0) continue;
    for (int a = 0; a < cs->face_surface[c]->nen; ++a) {
      double *to = cs->from_faces + N_FIELD * (size_t)face_node(cs, c, a);
      for (int i = 0; i < F_WEIGHT; ++i)
        if (i != F_STATE) to[i] += f[F_WEIGHT] * f[i];
      to[F_STATE] = fmax(to[F_STATE], f[F_STATE]);
      to[F_WEIGHT] += f[F_WEIGHT];
    }
  }
  for (int a = 0; a < cs->n_nodes; ++a) {
    double *to = cs->node_values + N_FIELD * (size_t)a;
    const double *f = cs->from_faces + N_FIELD * (size_t)a;
    if (cs->model->node_owner[cs->node_of[a]] != rank || to[F_WEIGHT] > 0.0 || f[F_WEIGHT] <= 0.0) continue;
    for (int i = 0; i < F_WEIGHT; ++i) to[i] = i == F_STATE ? f[i] : f[i] / f[F_WEIGHT];
    to[F_NORMAL_FORCE] = 0.0; /* a force belongs to a point, not to a mean */
    to[F_WEIGHT] = f[F_WEIGHT];
  }
  sk_exchange_forward(&cs->node_exchange, cs->node_values);
  /* the faces without Gauss points from their nodes (the faces' owners, which write them) */
  for (int c = 0; c < cs->n_faces; ++c) {
    double *f = cs->face_values + N_FIELD * (size_t)c;
    if (face_owner(cs, c) != rank || f[F_WEIGHT] > 0.0) continue;
    const int nen = cs->face_surface[c]->nen;
    for (int a = 0; a < nen; ++a) {
      const double *from = cs->node_values + N_FIELD * (size_t)face_node(cs, c, a);
      for (int i = 0; i < F_WEIGHT; ++i) f[i] = i == F_STATE ? fmax(f[i], from[i]) : f[i] + from[i] / nen;
    }
  }
}

static int field_wanted(const sk_contact_surfaces *cs, const field_info *f) {
  return f->needs == NEEDS_NOTHING || (f->needs == NEEDS_FRICTION && cs->with_friction) ||
         (f->needs == NEEDS_MULTIPLIERS && cs->with_multipliers);
}

/* The fields at the nodes this rank holds (local numbering; 0 away from the contact) for its piece of the bodies' VTU,
 * field after field. */
static sk_status spread_node_fields(sk_contact_surfaces *cs) {
  const int nn = cs->model->n_nodes;
  if (!cs->node_fields && !(cs->node_fields = malloc(sizeof(double) * VTU_COMPONENTS * ((size_t)nn + 1))))
    return no_memory("the VTU output");
  memset(cs->node_fields, 0, sizeof(double) * VTU_COMPONENTS * (size_t)nn);
  double *values = cs->node_fields;
  cs->n_node_fields = 0;
  for (int k = 0; k < N_VTU_FIELDS; ++k) {
    const field_info *f = &vtu_fields[k];
    if (!field_wanted(cs, f)) continue;
    for (int a = 0; a < nn; ++a)
      if (cs->contact_node[a] >= 0)
        memcpy(values + (size_t)f->components * a, cs->node_values + N_FIELD * (size_t)cs->contact_node[a] + f->offset,
               sizeof(double) * (size_t)f->components);
    cs->node_field_list[cs->n_node_fields++] = (sk_vtu_field){f->name, f->components, values};
    values += (size_t)f->components * nn;
  }
  return SK_OK;
}

sk_status sk_contact_surfaces_fields(sk_contact_surfaces *cs, const double *records, int n_records) {
  accumulate(cs, records, n_records);
  complete(cs);
  return spread_node_fields(cs);
}

int sk_contact_surfaces_node_fields(const sk_contact_surfaces *cs, sk_vtu_field *fields, int max) {
  const int n = cs && cs->node_fields ? (cs->n_node_fields < max ? cs->n_node_fields : max) : 0;
  for (int k = 0; k < n; ++k) fields[k] = cs->node_field_list[k];
  return n;
}

/* ---- this rank's piece ------------------------------------------------------------------------------------------- */

typedef struct {
  int n_points, n_cells;
  int *point_of;             /* per contact node: its point, or -1 */
  double *points, *point_values, *cell_values, *node, *node_id, *pair, *face, *cell_id;
  sk_elem_type *types;
  int *offsets, *conn;
} surface_piece;

static void free_piece(surface_piece *p) {
  void *all[] = {p->point_of, p->points, p->point_values, p->cell_values, p->node, p->node_id, p->pair,
                 p->face,     p->cell_id, p->types,       p->offsets,     p->conn};
  for (size_t k = 0; k < sizeof all / sizeof all[0]; ++k) free(all[k]);
}

/* The faces this rank owns and their nodes at displacement u, with their fields (point and cell lists). */
static sk_status build_piece(const sk_contact_surfaces *cs, const double *u, surface_piece *p,
                             sk_vtu_field *point_list, int *n_point_fields, sk_vtu_field *cell_list,
                             int *n_cell_fields) {
  const sk_model *m = cs->model;
  size_t slots = 0;
  p->point_of = malloc(sizeof(int) * ((size_t)cs->n_nodes + 1));
  if (!p->point_of) return no_memory("the contact VTU");
  for (int c = 0; c < cs->n_nodes; ++c) p->point_of[c] = -1;
  for (int c = 0; c < cs->n_faces; ++c) {
    if (face_owner(cs, c) != m->rank) continue;
    for (int a = 0; a < cs->face_surface[c]->nen; ++a)
      if (p->point_of[face_node(cs, c, a)] < 0) p->point_of[face_node(cs, c, a)] = p->n_points++;
    slots += (size_t)cs->face_surface[c]->nen;
    p->n_cells++;
  }
  const size_t np = (size_t)p->n_points + 1, nc = (size_t)p->n_cells + 1;
  p->points = calloc(3 * np, sizeof(double));
  p->point_values = malloc(sizeof(double) * VTU_COMPONENTS * np);
  p->cell_values = malloc(sizeof(double) * VTU_COMPONENTS * nc);
  p->node = malloc(sizeof(double) * np);
  p->node_id = malloc(sizeof(double) * np);
  p->pair = malloc(sizeof(double) * nc);
  p->face = malloc(sizeof(double) * nc);
  p->cell_id = malloc(sizeof(double) * nc);
  p->types = malloc(sizeof(sk_elem_type) * nc);
  p->offsets = malloc(sizeof(int) * nc);
  p->conn = malloc(sizeof(int) * (slots + 1));
  if (!p->points || !p->point_values || !p->cell_values || !p->node || !p->node_id || !p->pair || !p->face ||
      !p->cell_id || !p->types || !p->offsets || !p->conn)
    return no_memory("the contact VTU");
  for (int c = 0; c < cs->n_nodes; ++c) {
    const int k = p->point_of[c], node = cs->node_of[c];
    if (k < 0) continue;
    p->node[k] = p->node_id[k] = (double)m->node_gid[node];
    for (int i = 0; i < m->dim; ++i)
      p->points[3 * k + i] = m->X[(int64_t)node * m->dim + i] + u[(int64_t)node * m->dim + i];
  }
  p->offsets[0] = 0;
  for (int c = 0, cell = 0; c < cs->n_faces; ++c) {
    if (face_owner(cs, c) != m->rank) continue;
    const sk_surface *s = cs->face_surface[c];
    for (int a = 0; a < s->nen; ++a) p->conn[p->offsets[cell] + a] = p->point_of[face_node(cs, c, a)];
    p->offsets[cell + 1] = p->offsets[cell] + s->nen;
    p->types[cell] = s->face_type;
    p->pair[cell] = cs->face_pair[c];
    p->face[cell] = (double)(cs->face_whole[c] - cs->first_face[cs->face_pair[c]]);
    p->cell_id[cell] = (double)cs->face_whole[c];
    ++cell;
  }
  double *pv = p->point_values, *cv = p->cell_values;
  *n_point_fields = *n_cell_fields = 0;
  for (int k = 0; k < N_VTU_FIELDS; ++k) {
    const field_info *f = &vtu_fields[k];
    if (!field_wanted(cs, f)) continue;
    for (int c = 0; c < cs->n_nodes; ++c)
      if (p->point_of[c] >= 0)
        memcpy(pv + (size_t)f->components * p->point_of[c], cs->node_values + N_FIELD * (size_t)c + f->offset,
               sizeof(double) * (size_t)f->components);
    point_list[(*n_point_fields)++] = (sk_vtu_field){f->name, f->components, pv};
    pv += (size_t)f->components * p->n_points;
    if (!f->on_faces) continue;
    for (int c = 0, cell = 0; c < cs->n_faces; ++c)
      if (face_owner(cs, c) == m->rank)
        memcpy(cv + (size_t)f->components * cell++, cs->face_values + N_FIELD * (size_t)c + f->offset,
               sizeof(double) * (size_t)f->components);
    cell_list[(*n_cell_fields)++] = (sk_vtu_field){f->name, f->components, cv};
    cv += (size_t)f->components * p->n_cells;
  }
  point_list[(*n_point_fields)++] = (sk_vtu_field){"node", 1, p->node};
  point_list[(*n_point_fields)++] = (sk_vtu_field){"node_id", 1, p->node_id};
  cell_list[(*n_cell_fields)++] = (sk_vtu_field){"pair", 1, p->pair};
  cell_list[(*n_cell_fields)++] = (sk_vtu_field){"face", 1, p->face};
  cell_list[(*n_cell_fields)++] = (sk_vtu_field){"cell_id", 1, p->cell_id};
  return SK_OK;
}

sk_status sk_contact_surfaces_write(const sk_contact_surfaces *cs, sk_system *sys, const double *u, const char *dir,
                                    const char *prefix) {
  surface_piece p = {0};
  sk_vtu_field point_list[N_VTU_FIELDS + 2], cell_list[N_VTU_FIELDS + 3];
  int n_point_fields = 0, n_cell_fields = 0;
  sk_status status = build_piece(cs, u, &p, point_list, &n_point_fields, cell_list, &n_cell_fields);
  const sk_vtu_piece piece = {p.n_points, p.n_cells, p.points, p.types, p.offsets, p.conn, n_point_fields,
                              n_cell_fields, point_list, cell_list};
  status = sk_vtu_pieces_write(sys, status, dir, prefix, &piece);
  free_piece(&p);
  return status;
}
