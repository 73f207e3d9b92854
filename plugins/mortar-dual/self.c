/* mortar-dual glue: self contact — the step's slave and master sides of one surface (docs/plugins/mortar-dual.md
 * section 3.6). The face pairs that reach each other are coloured breadth first, each pair's faces on opposite
 * sides; the slave faces' candidates are their partners on the master side. Everything else (D, M, the weighted gap,
 * the NCP rows) is the two-surface code: a face that is not slave this step has no candidates, so its nodes stay
 * inactive (z = 0). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "defaults.h"
#include "mortar.h"

/* The point and normal of face f at its parametric centre in the reference configuration. */
static void reference_centre(const sk_instance *inst, int f, sk_surface_point *p) {
  const sk_view *v = inst->master;
  const int simplex = v->cell_type == SK_TRI3 || v->cell_type == SK_TRI6;
  const double xi[2] = {simplex ? 1.0 / 3.0 : 0.0, simplex ? 1.0 / 3.0 : 0.0};
  *p = (sk_surface_point){.struct_size = sizeof *p};
  inst->api->contact->geometry(v, f, xi, v->X, p);
}

/* 1 when faces f and m never meet: a node of one within self_exclusion of a node of the other in the reference
 * configuration (the faces sharing a node and their neighbours), or the centre of one lying behind the other's
 * plane there (the material between them: the undeformed body does not penetrate itself, so it reaches such a face
 * only through one in front). The node-to-surface rule (plugins/common/self_contact.c) taken from a point to a
 * face: any node for the distance, both ways round. The side is read off the face's tangent plane at its centre,
 * not off a closest-point projection: the projection walks across the surface from the face it starts on, and on
 * the one surface that holds both faces it ends at the centre itself (gap 0 to round-off, whose sign then decided:
 * on the tube of scenes/tube-crush-3d.yaml it excluded facing walls, which then passed through each other). */
static int excluded(const sk_instance *inst, int f, int m) {
  const sk_view *v = inst->master;
  const int dim = inst->dim, nen = v->nen;
  const double r2 = inst->self_exclusion * inst->self_exclusion;
  for (int a = 0; a < nen; ++a)
    for (int b = 0; b < nen; ++b) {
      const double *Xa = v->X + (int64_t)v->conn[(int64_t)f * nen + a] * dim;
      const double *Xb = v->X + (int64_t)v->conn[(int64_t)m * nen + b] * dim;
      double d2 = 0.0;
      for (int i = 0; i < dim; ++i) d2 += (Xa[i] - Xb[i]) * (Xa[i] - Xb[i]);
      if (d2 <= r2) return 1;
    }
  sk_surface_point pf, pm;
  reference_centre(inst, f, &pf);
  reference_centre(inst, m, &pm);
  double f_over_m = 0.0, m_over_f = 0.0;
  for (int i = 0; i < 3; ++i) {
    f_over_m += (pf.x[i] - pm.x[i]) * pm.n[i];
    m_over_f += (pm.x[i] - pf.x[i]) * pf.n[i];
  }
  return f_over_m < 0.0 || m_over_f < 0.0;
}

/* Face pairs (f, m), f < m, in lexicographic order. */
static int edge_order(const void *a, const void *b) {
  const int *p = a, *q = b;
  return p[0] != q[0] ? (p[0] > q[0]) - (p[0] < q[0]) : (p[1] > q[1]) - (p[1] < q[1]);
}

/* 1 when (lo, hi) is among the first n pairs (sorted). */
static int has_edge(const sk_instance *inst, int lo, int hi, int n) {
  const int key[2] = {lo, hi};
  return n > 0 && bsearch(key, inst->edge, (size_t)n, 2 * sizeof(int), edge_order) != NULL;
}

/* The pairs (f < m) among the search hits that are not excluded and have a mortar segment within the search
 * margin's reach either way round, added to the sorted edge list when new; returns how many were new. A pair found
 * from both of its faces' hits is tested twice (the tests are symmetric) and kept once. */
static sk_status find_pairs(sk_instance *inst, const double *xs, int *added) {
  const sk_view *v = inst->slave;
  const int known = inst->n_edge;
  *added = 0;
  for (int f = 0; f < v->n_cells; ++f)
    for (int h = inst->hit_ptr[f]; h < inst->hit_ptr[f + 1]; ++h) {
      const int m = inst->hits.faces[h], lo = f < m ? f : m, hi = f < m ? m : f;
      if (m == f || has_edge(inst, lo, hi, known) || excluded(inst, f, m)) continue;
      if (!mortar_pair_reaches(inst, f, m, xs, xs, inst->search_margin) &&
          !mortar_pair_reaches(inst, m, f, xs, xs, inst->search_margin))
        continue;
      SK_TRY(mortar_grow(inst, &inst->edge, &inst->edge_cap, 2 * inst->n_edge + 2));
      inst->edge[2 * inst->n_edge] = lo;
      inst->edge[2 * inst->n_edge + 1] = hi;
      ++inst->n_edge;
    }
  qsort(inst->edge, (size_t)inst->n_edge, 2 * sizeof(int), edge_order);
  int n = 0;
  for (int e = 0; e < inst->n_edge; ++e)
    if (n == 0 || edge_order(inst->edge + 2 * e, inst->edge + 2 * (n - 1)) != 0) {
      inst->edge[2 * n] = inst->edge[2 * e];
      inst->edge[2 * n + 1] = inst->edge[2 * e + 1];
      ++n;
    }
  inst->n_edge = n;
  *added = n - known;
  return SK_OK;
}

/* The pairs as a graph over faces (CSR), both directions. */
static void build_graph(sk_instance *inst) {
  const int nf = inst->slave->n_cells;
  memset(inst->adj_ptr, 0, sizeof(int) * ((size_t)nf + 1));
  for (int e = 0; e < 2 * inst->n_edge; ++e) ++inst->adj_ptr[inst->edge[e] + 1];
  for (int f = 0; f < nf; ++f) inst->adj_ptr[f + 1] += inst->adj_ptr[f];
  for (int f = 0; f < nf; ++f) inst->queue[f] = inst->adj_ptr[f]; /* fill positions */
  for (int e = 0; e < inst->n_edge; ++e) {
    const int a = inst->edge[2 * e], b = inst->edge[2 * e + 1];
    inst->adj[inst->queue[a]++] = b;
    inst->adj[inst->queue[b]++] = a;
  }
}

/* Breadth-first colouring from `seed` (given side `side`): each pair's faces on opposite sides. */
static void colour_from(sk_instance *inst, int seed, unsigned char side) {
  int head = 0, tail = 0;
  inst->role[seed] = side;
  inst->queue[tail++] = seed;
  while (head < tail) {
    const int f = inst->queue[head++];
    const unsigned char other = inst->role[f] == FACE_SLAVE ? FACE_MASTER : FACE_SLAVE;
    for (int k = inst->adj_ptr[f]; k < inst->adj_ptr[f + 1]; ++k) {
      const int m = inst->adj[k];
      if (inst->role[m] == FACE_IDLE) {
        inst->role[m] = other;
        inst->queue[tail++] = m;
      }
    }
  }
}

sk_status mortar_self_assign(sk_instance *inst, const double *xs, int keep, int *added) {
  const sk_view *v = inst->slave;
  const int nf = v->n_cells;
  mortar_compute_normals(inst, xs);
  if (!keep) inst->n_edge = 0;
  SK_TRY(find_pairs(inst, xs, added));
  if (keep && *added == 0) return SK_OK;
  SK_TRY(mortar_grow(inst, &inst->adj, &inst->adj_cap, 2 * inst->n_edge));
  build_graph(inst);
  /* seeds: the faces that keep their side (the last committed one, or the attempt's when the point is extended),
   * slave before master, then the rest by index as slave */
  const unsigned char *prefer = keep ? inst->role : inst->role_committed;
  unsigned char *previous = inst->role_preferred; /* the preferred sides, before role is rewritten */
  memcpy(previous, prefer, (size_t)nf);
  memset(inst->role, FACE_IDLE, (size_t)nf);
  for (int pass = 0; pass < 3; ++pass)
    for (int f = 0; f < nf; ++f) {
      if (inst->role[f] != FACE_IDLE || inst->adj_ptr[f] == inst->adj_ptr[f + 1]) continue;
      if (pass == 0 && previous[f] == FACE_SLAVE) colour_from(inst, f, FACE_SLAVE);
      if (pass == 1 && previous[f] == FACE_MASTER) colour_from(inst, f, FACE_MASTER);
      if (pass == 2) colour_from(inst, f, FACE_SLAVE);
    }
  /* the slave faces' candidates: their partners on the master side; pairs with both faces on one side dropped */
  int n = 0;
  inst->dropped = 0;
  for (int f = 0; f < nf; ++f) {
    inst->cand_ptr[f] = n;
    for (int k = inst->adj_ptr[f]; k < inst->adj_ptr[f + 1]; ++k) {
      const int m = inst->adj[k];
      if (inst->role[m] == inst->role[f]) inst->dropped += f < m;
      else if (inst->role[f] == FACE_SLAVE) {
        SK_TRY(mortar_grow(inst, &inst->cand, &inst->cand_cap, n + 1));
        inst->cand[n++] = m;
      }
    }
  }
  inst->cand_ptr[nf] = n;
  if (inst->dropped > 0)
    inst->api->log(inst->host, 1, "mortar-dual: self contact: %d face pair(s) left out: both faces fell on one "
                   "side (an odd cycle of pairs, three or more parts of the surface meeting)", inst->dropped);
  memset(inst->on_master, 0, (size_t)v->n_nodes);
  for (int f = 0; f < nf; ++f)
    if (inst->role[f] == FACE_MASTER)
      for (int a = 0; a < v->nen; ++a) inst->on_master[v->conn[(int64_t)f * v->nen + a]] = 1;
  return SK_OK;
}

/* The largest face of the surface: the diagonal of its reference box (penalty-nts's default for self_exclusion). */
static double largest_face(const sk_view *v) {
  double largest = 0.0;
  for (int f = 0; f < v->n_cells; ++f) {
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, d2 = 0.0;
    for (int a = 0; a < v->nen; ++a)
      for (int i = 0; i < v->dim; ++i) {
        const double X = v->X[(int64_t)v->conn[(int64_t)f * v->nen + a] * v->dim + i];
        lo[i] = fmin(lo[i], X);
        hi[i] = fmax(hi[i], X);
      }
    for (int i = 0; i < v->dim; ++i) d2 += (hi[i] - lo[i]) * (hi[i] - lo[i]);
    largest = fmax(largest, sqrt(d2));
  }
  return largest;
}

sk_status mortar_self_create(sk_instance *inst) {
  const sk_host_api *api = inst->api;
  const sk_view *s = inst->slave, *m = inst->master;
  const char *refused = NULL;
  if (inst->integration != INTEGRATION_SEGMENTS)
    refused = "integrates segments (integration: segments): the slave/master split is made per face pair";
  else if (!m || s->n_cells != m->n_cells || s->n_nodes != m->n_nodes || s->nen != m->nen ||
           s->n_nodes != s->n_nodes_global ||
           memcmp(s->conn, m->conn, sizeof(int32_t) * (size_t)s->n_cells * (size_t)s->nen) != 0)
    refused = "runs on one rank (the slave/master assignment colours the whole surface's face pairs on one rank)";
  if (refused) return api->error(inst->host, SK_ERR_INPUT, "%s: mortar-dual's self contact %s", inst->attach->name,
                                 refused);
  char why[300];
  snprintf(why, sizeof why, "the largest face of surface '%s' (diagonal of its reference box): the faces at a face "
           "and their neighbours", s->name);
  SK_TRY(sk_defaults_param(api, inst->host, sk_defaults_scene(api, inst->host), "self_exclusion", largest_face(s), why,
                           &inst->self_exclusion));
  if (!(inst->self_exclusion >= 0.0) || !isfinite(inst->self_exclusion))
    return api->error(inst->host, SK_ERR_INPUT, "%s: mortar-dual: need self_exclusion >= 0 (got %g)",
                      inst->attach->name, inst->self_exclusion);
  const size_t nf = (size_t)s->n_cells;
  inst->role = calloc(nf + 1, 1);
  inst->role_committed = calloc(nf + 1, 1);
  inst->role_preferred = calloc(nf + 1, 1);
  inst->on_master = calloc((size_t)s->n_nodes + 1, 1);
  inst->adj_ptr = calloc(nf + 1, sizeof(int));
  inst->queue = calloc(nf + 1, sizeof(int));
  if (!inst->role || !inst->role_committed || !inst->role_preferred || !inst->on_master || !inst->adj_ptr ||
      !inst->queue)
    return mortar_nomem(inst, "self contact");
  return SK_OK;
}
