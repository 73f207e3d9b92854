/* The contact partition (contact_partition.h; docs/design.md, "Contact partition"). */
#include "contact_partition.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "host.h"
#include "stickslip/plugin.h"

typedef struct {
  double c;
  int i;
} keyed;

static int compare_keyed(const void *a, const void *b) {
  const keyed *x = a, *y = b;
  if (x->c != y->c) return (x->c > y->c) - (x->c < y->c);
  return (x->i > y->i) - (x->i < y->i);
}

/* Bisects the points idx[0..n) (sorted scratch `key`) inside the box [lo, hi] into parts [first, first + n_parts). */
static void bisect(int n, int *idx, const double *pos, const double *weight, int n_parts, int first, int *part,
                   keyed *key, const double lo[3], const double hi[3]) {
  if (n_parts <= 1 || n == 0) {
    for (int j = 0; j < n; ++j) part[idx[j]] = first;
    return;
  }
  double total = 0.0;
  int axis = 0;
  for (int d = 1; d < 3; ++d)
    if (hi[d] - lo[d] > hi[axis] - lo[axis]) axis = d;
  for (int j = 0; j < n; ++j) {
    key[j].c = pos[3 * (size_t)idx[j] + axis];
    key[j].i = idx[j];
    total += weight ? weight[idx[j]] : 1.0;
  }
  qsort(key, (size_t)n, sizeof *key, compare_keyed);
  const int left_parts = n_parts / 2;
  const double target = total * left_parts / n_parts;
  /* the cut: the first points whose weight reaches the left parts' share (the nearer of the two sums) */
  int cut = 0;
  double sum = 0.0;
  while (cut < n) {
    const double w = weight ? weight[key[cut].i] : 1.0;
    if (sum + w > target && fabs(sum + w - target) >= fabs(sum - target)) break;
    sum += w;
    ++cut;
  }
  for (int j = 0; j < n; ++j) idx[j] = key[j].i;
  /* the halves' boxes: this box cut midway between the points either side, not the boxes of the halves' points,
   * so that the bisections of the nodes and of the face centroids choose the same axes where a box is nearly
   * square (docs/scaling.md, "sk_rcb against Zoltan2") */
  const double at = cut == 0 ? lo[axis] : cut == n ? hi[axis] : 0.5 * (key[cut - 1].c + key[cut].c);
  double left_hi[3] = {hi[0], hi[1], hi[2]}, right_lo[3] = {lo[0], lo[1], lo[2]};
  left_hi[axis] = at, right_lo[axis] = at;
  bisect(cut, idx, pos, weight, left_parts, first, part, key, lo, left_hi);
  bisect(n - cut, idx + cut, pos, weight, n_parts - left_parts, first + left_parts, part, key, right_lo, hi);
}

int sk_rcb(int n, const double *pos, const double *weight, int n_parts, int first_part, int *part) {
  int *idx = malloc(sizeof(int) * (size_t)(n > 0 ? n : 1));
  keyed *key = malloc(sizeof(keyed) * (size_t)(n > 0 ? n : 1));
  if (!idx || !key) {
    free(idx);
    free(key);
    return -1;
  }
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (int j = 0; j < n; ++j) {
    idx[j] = j;
    for (int d = 0; d < 3; ++d) {
      lo[d] = fmin(lo[d], pos[3 * (size_t)j + d]);
      hi[d] = fmax(hi[d], pos[3 * (size_t)j + d]);
    }
  }
  bisect(n, idx, pos, weight, n_parts, first_part, part, key, lo, hi);
  free(idx);
  free(key);
  return 0;
}

const char *sk_contact_partition_refused(const sk_model *m, int k) {
  const sk_contact_pair *pair = &m->pairs[k];
  if (pair->self_contact) return "self contact: the slave surface is its own master";
  const sk_plugin *plugin = pair->plugin;
  const sk_checkpoint_ext *ext = plugin && plugin->get_extension ? plugin->get_extension(SK_EXT_CHECKPOINT) : NULL;
  if (!ext || ext->abi_major != SK_ABI_MAJOR)
    return "its plugin keeps no records (stickslip.checkpoint.v1) for its state to move by";
  return NULL;
}

/* One RCB of the slave surface's nodes (by position) and one of its faces (by centroid), over the ranks. */
static sk_status plan_pair(sk_model *m, sk_contact_pair *pair) {
  const sk_surface *s = &pair->slave;
  const int n = s->n_nodes > s->n_faces ? s->n_nodes : s->n_faces, dim = m->dim;
  double *pos = calloc(3 * (size_t)(n > 0 ? n : 1), sizeof(double));
  pair->contact_node_owner = malloc(sizeof(int) * (size_t)(s->n_nodes > 0 ? s->n_nodes : 1));
  pair->contact_face_owner = malloc(sizeof(int) * (size_t)(s->n_faces > 0 ? s->n_faces : 1));
  pair->contact_weight = calloc((size_t)(s->n_nodes + s->n_faces) + 1, sizeof(double));
  int failed = !pos || !pair->contact_node_owner || !pair->contact_face_owner || !pair->contact_weight;
  for (int k = 0; !failed && k < s->n_nodes; ++k)
    for (int i = 0; i < dim; ++i) pos[3 * (size_t)k + i] = m->X[(size_t)s->nodes[k] * dim + i];
  failed = failed || sk_rcb(s->n_nodes, pos, NULL, m->n_ranks, 0, pair->contact_node_owner) != 0;
  for (int f = 0; !failed && f < s->n_faces; ++f)
    for (int i = 0; i < dim; ++i) {
      double c = 0.0;
      for (int a = 0; a < s->nen; ++a) c += m->X[(size_t)s->conn[(size_t)f * s->nen + a] * dim + i];
      pos[3 * (size_t)f + i] = c / s->nen;
    }
  failed = failed || sk_rcb(s->n_faces, pos, NULL, m->n_ranks, 0, pair->contact_face_owner) != 0;
  free(pos);
  if (failed) return sk_error_set(SK_ERR_NOMEM, "out of memory for the contact partition of pair %s", pair->name);
  return SK_OK;
}

sk_status sk_contact_partition_plan(sk_model *m) {
  if (!m->contact_rebalance) return SK_OK;
  for (int k = 0; k < m->n_pairs; ++k)
    if (!sk_contact_partition_refused(m, k)) SK_TRY(plan_pair(m, &m->pairs[k]));
  return SK_OK;
}

int sk_contact_node_owner(const sk_model *m, const sk_contact_pair *pair, int k) {
  const sk_surface *s = &pair->slave;
  if (!pair->contact_node_owner) return m->node_owner[s->nodes[k]];
  return pair->contact_node_owner[s->node_index ? s->node_index[k] : k];
}

int sk_contact_face_owner(const sk_model *m, const sk_contact_pair *pair, int f) {
  const sk_surface *s = &pair->slave;
  if (!pair->contact_face_owner) return s->face_owner ? s->face_owner[f] : -1;
  return pair->contact_face_owner[s->face_index ? s->face_index[f] : f];
}

int sk_contact_owner_of_node(const sk_model *m, const sk_contact_pair *pair, int node) {
  if (!pair || !pair->contact_node_owner) return m->node_owner[node];
  const int64_t k = sk_index_in_sorted(pair->slave.nodes, pair->slave.n_nodes, node);
  return k >= 0 ? sk_contact_node_owner(m, pair, (int)k) : m->node_owner[node];
}

/* 1 when this rank contact-owns slave face f or one of its nodes */
static int face_evaluated(const sk_model *m, const sk_contact_pair *pair, int f) {
  const sk_surface *s = &pair->slave;
  if (sk_contact_face_owner(m, pair, f) == m->rank) return 1;
  for (int a = 0; a < s->nen; ++a) {
    const int64_t k = sk_index_in_sorted(s->nodes, s->n_nodes, s->conn[(size_t)f * s->nen + a]);
    if (k >= 0 && sk_contact_node_owner(m, pair, (int)k) == m->rank) return 1;
  }
  return 0;
}

int sk_contact_faces_used(const sk_model *m, const sk_contact_pair *pair, unsigned char *used) {
  const sk_surface *s = &pair->slave;
  unsigned char *near = calloc((size_t)(s->n_nodes > 0 ? s->n_nodes : 1), 1);
  if (!near) return -1;
  for (int f = 0; f < s->n_faces; ++f) {
    if (!face_evaluated(m, pair, f)) continue;
    for (int a = 0; a < s->nen; ++a) {
      const int64_t k = sk_index_in_sorted(s->nodes, s->n_nodes, s->conn[(size_t)f * s->nen + a]);
      if (k >= 0) near[k] = 1;
    }
  }
  for (int f = 0; f < s->n_faces; ++f) {
    used[f] = 0;
    for (int a = 0; a < s->nen && !used[f]; ++a) {
      const int64_t k = sk_index_in_sorted(s->nodes, s->n_nodes, s->conn[(size_t)f * s->nen + a]);
      used[f] = (unsigned char)(k >= 0 && near[k]);
    }
  }
  free(near);
  return 0;
}

/* min and max over ranks of the entities each contact-owns (owner: whole-surface array of n entries). */
static void per_rank(const int *owner, int n, int n_ranks, int *lo, int *hi) {
  int *count = calloc((size_t)n_ranks, sizeof(int));
  *lo = *hi = 0;
  if (!count) return;
  for (int j = 0; j < n; ++j)
    if (owner[j] >= 0 && owner[j] < n_ranks) count[owner[j]]++;
  *lo = *hi = count[0];
  for (int r = 1; r < n_ranks; ++r) {
    *lo = count[r] < *lo ? count[r] : *lo;
    *hi = count[r] > *hi ? count[r] : *hi;
  }
  free(count);
}

void sk_contact_partition_explain(const sk_model *m, FILE *out) {
  if (m->n_pairs == 0) return;
  fprintf(out, "contact partition (contact_balance.rebalance: %s): %s\n", m->contact_rebalance ? "on" : "off",
          m->contact_rebalance ? "each pair's slave nodes and faces are split over the ranks by a recursive coordinate "
                                 "bisection of their reference positions at set-up; the contact owner evaluates them"
                               : "the slave entities are evaluated by the owners of the body elements they bound");
  if (m->contact_rebalance)
    fprintf(out, "  split again between steps after a step whose max/mean contact CPU time over the ranks exceeds %g "
            "(contact_balance.time_ratio) or whose active slave points per rank, (max - min)/max, exceed %g "
            "(contact_balance.entity_imbalance), each entity weighted by its work: its rank's contact CPU time, split "
            "between the entities in contact and the others\n", m->rebalance_time_ratio,
            m->rebalance_entity_imbalance);
  for (int k = 0; m->contact_rebalance && k < m->n_pairs; ++k) {
    const sk_contact_pair *pair = &m->pairs[k];
    const char *refused = sk_contact_partition_refused(m, k);
    if (refused) {
      fprintf(out, "  contact pair %s: keeps the bulk partition (%s)\n", pair->name, refused);
      continue;
    }
    int node_lo, node_hi, face_lo, face_hi;
    per_rank(pair->contact_node_owner, pair->slave.n_nodes_global > 0 ? pair->slave.n_nodes_global : pair->slave.n_nodes,
             m->n_ranks, &node_lo, &node_hi);
    per_rank(pair->contact_face_owner, pair->slave.n_faces_global > 0 ? pair->slave.n_faces_global : pair->slave.n_faces,
             m->n_ranks, &face_lo, &face_hi);
    fprintf(out, "  contact pair %s: %d to %d slave nodes and %d to %d slave faces per rank over %d rank%s\n",
            pair->name, node_lo, node_hi, face_lo, face_hi, m->n_ranks, m->n_ranks == 1 ? "" : "s");
  }
}

/* A point of the step that asks for a rebalance (sk_system_points): marks its slave node, or its face (a Gauss
 * point), in its pair's `active` (whole-surface indices: nodes, then faces) when it is in contact. */
typedef struct {
  const sk_model *m;
  unsigned char **active; /* per pair, NULL without a contact partition */
} marks;

static void mark_point(void *ctx, int k, const sk_contact_point *p) {
  const marks *mk = ctx;
  if (k < 0 || k >= mk->m->n_pairs || !mk->active[k] || p->state <= 0) return;
  const sk_surface *s = &mk->m->pairs[k].slave;
  if (p->slave_node >= 0) {
    const int local = sk_model_node_of(mk->m, p->slave_node);
    const int64_t at = local >= 0 ? sk_index_in_sorted(s->nodes, s->n_nodes, local) : -1;
    if (at >= 0) mk->active[k][s->node_index[at]] = 1;
  } else if (SK_HAS(p, slave_face) && p->slave_face >= 0 && p->slave_face < s->n_faces_global) {
    mk->active[k][s->n_nodes_global + p->slave_face] = 1;
  }
}

/* The per-entity weights of one kind of slave entity (count of them, whole indices; owner[j] its contact owner,
 * active[j] 1 when in contact at the step): each rank's contact seconds of the step, t_r, split into a part per
 * active entity b and a rest a_r shared evenly by the rank's entities, b from a least-squares fit of t_r against the
 * ranks' active entities x_r (t_r = a + b x_r over the ranks; b = 0 when every rank has as many, or the fit slopes
 * down): an active entity weighs a_r / n_r + b, an inactive one a_r / n_r, a_r = max(t_r - b x_r, 0). */
static void entity_weights(const sk_system *sys, int count, const int *owner, const unsigned char *active,
                           double *work, double *weight) {
  const int n_ranks = sys->n_ranks;
  double *t = work, *x = work + n_ranks, *held = work + 2 * (size_t)n_ranks;
  for (int r = 0; r < 3 * n_ranks; ++r) work[r] = 0.0;
  t[sys->rank] = sys->contact_step_cpu; /* CPU seconds: not the time the rank was descheduled (contact_balance.c) */
  for (int j = 0; j < count; ++j) {
    held[owner[j]] += 1.0;
    x[owner[j]] += active[j];
  }
  MPI_Allreduce(MPI_IN_PLACE, t, n_ranks, MPI_DOUBLE, MPI_SUM, sys->comm);
  double t_mean = 0.0, x_mean = 0.0, sxy = 0.0, sxx = 0.0;
  for (int r = 0; r < n_ranks; ++r) t_mean += t[r] / n_ranks, x_mean += x[r] / n_ranks;
  for (int r = 0; r < n_ranks; ++r) {
    sxy += (x[r] - x_mean) * (t[r] - t_mean);
    sxx += (x[r] - x_mean) * (x[r] - x_mean);
  }
  const double b = sxx > 0.0 && sxy > 0.0 ? sxy / sxx : 0.0;
  for (int j = 0; j < count; ++j) {
    const int r = owner[j];
    weight[j] = fmax(t[r] - b * x[r], 0.0) / held[r] + (active[j] ? b : 0.0);
  }
}

/* One pair's weights from its marks (collective): the marks of every rank, then the faces with a node in contact
 * and the nodes of a face with a Gauss point in contact are in contact too. */
static void weigh_pair(const sk_system *sys, sk_contact_pair *pair, unsigned char *active, double *work) {
  const sk_surface *s = &pair->slave;
  const int n = s->n_nodes_global, nf = s->n_faces_global;
  MPI_Allreduce(MPI_IN_PLACE, active, n + nf, MPI_UNSIGNED_CHAR, MPI_MAX, sys->comm);
  for (int f = 0; f < s->n_faces; ++f)
    for (int a = 0; a < s->nen; ++a) {
      const int64_t node = s->node_index[sk_index_in_sorted(s->nodes, s->n_nodes, s->conn[(size_t)f * s->nen + a])];
      const int64_t face = n + s->face_index[f];
      if (active[node] & 1) active[face] |= 2;
      if (active[face] & 1) active[node] |= 2;
    }
  for (int j = 0; j < n + nf; ++j) active[j] = active[j] != 0;
  entity_weights(sys, n, pair->contact_node_owner, active, work, pair->contact_weight);
  entity_weights(sys, nf, pair->contact_face_owner, active + n, work, pair->contact_weight + n);
}

sk_status sk_contact_partition_weigh(sk_system *sys) {
  sk_model *m = sys->model;
  unsigned char **active = calloc((size_t)m->n_pairs + 1, sizeof *active);
  double *work = malloc(sizeof(double) * 3 * (size_t)m->n_ranks);
  int ok = active && work;
  for (int k = 0; ok && k < m->n_pairs; ++k)
    if (m->pairs[k].contact_weight) {
      active[k] = calloc((size_t)(m->pairs[k].slave.n_nodes_global + m->pairs[k].slave.n_faces_global) + 1, 1);
      ok = active[k] != NULL;
    }
  sk_status status = ok ? SK_OK : sk_error_set(SK_ERR_NOMEM, "out of memory weighing the contact partition");
  if (status == SK_OK) {
    marks mk = {m, active};
    status = sk_system_points(sys, 0, mark_point, &mk);
  }
  status = sk_system_collective(sys, status);
  for (int k = 0; status == SK_OK && k < m->n_pairs; ++k)
    if (active[k]) weigh_pair(sys, &m->pairs[k], active[k], work);
  for (int k = 0; active && k < m->n_pairs; ++k) free(active[k]);
  free(active), free(work);
  return status;
}

/* With STICKSLIP_DUMP_CONTACT_PARTITION=DIR, rank 0 writes a rebalance's input, DIR/<pair>-step-NNNNNN.txt: per
 * slave node its position at t_n and weight, per slave face its centroid, weight and nodes (whole indices), for
 * tests/bench/partition (sk_rcb against Zoltan2 on the same entities). */
static void dump_input(const sk_system *sys, const sk_contact_pair *pair, const double *pos, const double *weight) {
  const char *dir = getenv("STICKSLIP_DUMP_CONTACT_PARTITION");
  if (!dir || sys->rank != 0) return;
  const sk_surface *s = &pair->slave;
  const int n = s->n_nodes_global, nf = s->n_faces_global;
  char path[4096];
  snprintf(path, sizeof path, "%s/%s-step-%06lld.txt", dir, pair->name, (long long)sys->step);
  FILE *out = fopen(path, "w");
  if (!out) {
    fprintf(stderr, "warning: cannot write %s (STICKSLIP_DUMP_CONTACT_PARTITION)\n", path);
    return;
  }
  fprintf(out, "# contact partition input: pair %s, step %lld, %d ranks\nnodes %d faces %d nen %d\n", pair->name,
          (long long)sys->step, sys->n_ranks, n, nf, s->nen);
  for (int j = 0; j < n; ++j)
    fprintf(out, "%.17g %.17g %.17g %.17g\n", pos[3 * j], pos[3 * j + 1], pos[3 * j + 2], weight[j]);
  int *conn = malloc(sizeof(int) * ((size_t)nf * s->nen + 1));
  for (int f = 0; conn && f < s->n_faces; ++f)
    for (int a = 0; a < s->nen; ++a)
      conn[(size_t)s->face_index[f] * s->nen + a] =
          (int)s->node_index[sk_index_in_sorted(s->nodes, s->n_nodes, s->conn[(size_t)f * s->nen + a])];
  for (int f = 0; conn && f < nf; ++f) {
    const double *c = pos + 3 * ((size_t)n + f);
    fprintf(out, "%.17g %.17g %.17g %.17g", c[0], c[1], c[2], weight[n + f]);
    for (int a = 0; a < s->nen; ++a) fprintf(out, " %d", conn[(size_t)f * s->nen + a]);
    fputc('\n', out);
  }
  free(conn);
  fclose(out);
}

/* The new owners of one pair's slave nodes and faces (whole-surface arrays) from its weights; *changed |= any
 * differs. */
static sk_status rebalance_pair(sk_system *sys, sk_contact_pair *pair, int *changed) {
  const sk_model *m = sys->model;
  const sk_surface *s = &pair->slave;
  const int n = s->n_nodes_global, nf = s->n_faces_global, dim = m->dim;
  double *pos = calloc(3 * (size_t)(n + nf) + 1, sizeof(double));
  double *weight = malloc(sizeof(double) * ((size_t)(n + nf) + 1));
  int *owner = malloc(sizeof(int) * ((size_t)(n + nf) + 1));
  int ok = pos && weight && owner;
  MPI_Allreduce(MPI_IN_PLACE, &ok, 1, MPI_INT, MPI_MIN, sys->comm);
  if (!ok) {
    free(pos), free(weight), free(owner);
    return sk_error_set(SK_ERR_NOMEM, "out of memory rebalancing the contact partition of pair %s", pair->name);
  }
  /* positions at t_n from the nodes' owners; the faces' centroids (every rank holds every slave face) */
  for (int k = 0; k < s->n_nodes; ++k)
    if (m->node_owner[s->nodes[k]] == m->rank)
      for (int i = 0; i < dim; ++i) pos[3 * s->node_index[k] + i] = sys->q_n[(int64_t)s->nodes[k] * dim + i];
  MPI_Allreduce(MPI_IN_PLACE, pos, 3 * n, MPI_DOUBLE, MPI_SUM, sys->comm);
  for (int f = 0; f < s->n_faces; ++f)
    for (int a = 0; a < s->nen; ++a) {
      const int64_t k = sk_index_in_sorted(s->nodes, s->n_nodes, s->conn[(size_t)f * s->nen + a]);
      for (int i = 0; i < 3; ++i) pos[3 * (n + s->face_index[f]) + i] += pos[3 * s->node_index[k] + i] / s->nen;
    }
  /* a floor of 1e-3 of the mean weight keeps entities of a rank without contact time in the split */
  for (int part = 0; part < 2; ++part) {
    const double *from = pair->contact_weight + (part ? n : 0);
    double *w = weight + (part ? n : 0), total = 0.0;
    const int count = part ? nf : n;
    for (int j = 0; j < count; ++j) total += from[j];
    for (int j = 0; j < count; ++j) w[j] = total > 0.0 ? from[j] + 1e-3 * total / count : 1.0;
  }
  dump_input(sys, pair, pos, weight);
  sk_status status = sk_rcb(n, pos, weight, m->n_ranks, 0, owner) == 0 &&
                             sk_rcb(nf, pos + 3 * (size_t)n, weight + n, m->n_ranks, 0, owner + n) == 0
                         ? SK_OK
                         : sk_error_set(SK_ERR_NOMEM, "out of memory rebalancing the contact partition of pair %s",
                                        pair->name);
  for (int j = 0; status == SK_OK && j < n; ++j) *changed |= owner[j] != pair->contact_node_owner[j];
  for (int f = 0; status == SK_OK && f < nf; ++f) *changed |= owner[n + f] != pair->contact_face_owner[f];
  if (status == SK_OK) {
    memcpy(pair->contact_node_owner, owner, sizeof(int) * (size_t)n);
    memcpy(pair->contact_face_owner, owner + n, sizeof(int) * (size_t)nf);
  }
  free(pos), free(weight), free(owner);
  return sk_system_collective(sys, status);
}

sk_status sk_contact_partition_rebalance(sk_system *sys, int *changed) {
  sk_model *m = sys->model;
  sys->contact_rebalance_pending = 0;
  *changed = 0;
  for (int k = 0; k < m->n_pairs; ++k)
    if (m->pairs[k].contact_node_owner) SK_TRY(rebalance_pair(sys, &m->pairs[k], changed));
  return SK_OK;
}
