/* mortar-dual glue: the step's broad phase — the candidate master faces of every needed slave face (mortar.h), from
 * the host's search tree through the broad phase the node-to-surface plugins use (plugins/common/candidates.h), and
 * their extension at convergence when the slave surface slid beyond them within the step. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mortar.h"

sk_status mortar_grow(sk_instance *inst, int **array, int *cap, int need) {
  if (need <= *cap) return SK_OK;
  const int grown = 2 * need + 64;
  int *a = realloc(*array, sizeof(int) * (size_t)grown);
  if (!a) return mortar_nomem(inst, "candidate faces");
  *array = a;
  *cap = grown;
  return SK_OK;
}

/* The hits of every needed slave face: the master faces whose boxes (refitted over the master's x_n -> xm,
 * inflated by the search margin) meet the box of the slave face swept from x_n to xs, inflated by the margin —
 * cand_query_swept with the face's box in place of a point's path. */
sk_status mortar_search_faces(sk_instance *inst, const sk_state *state, const double *xs, const double *xm) {
  const sk_view *sv = inst->slave;
  const int dim = inst->dim;
  inst->api->contact->search_update(inst->search, state->x_n[1], xm, inst->search_margin);
  inst->hits.used = 0;
  for (int f = 0; f < sv->n_cells; ++f) {
    inst->hit_ptr[f] = inst->hits.used;
    if (!inst->face_needed[f]) continue;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int a = 0; a < sv->nen; ++a) {
      const int64_t k = sv->conn[(int64_t)f * sv->nen + a];
      for (int i = 0; i < dim; ++i) {
        const double p0 = state->x_n[0][k * dim + i], p1 = xs[k * dim + i];
        lo[i] = fmin(lo[i], fmin(p0, p1));
        hi[i] = fmax(hi[i], fmax(p0, p1));
      }
    }
    int start, count;
    if (cand_query_swept(inst->api->contact, inst->search, lo, hi, dim, inst->search_margin, &inst->hits, &start,
                         &count) != 0)
      return mortar_nomem(inst, "candidate faces");
  }
  inst->hit_ptr[sv->n_cells] = inst->hits.used;
  return SK_OK;
}

/* Slave face f's Gauss point q at positions xs projected onto master face m at xm (variant A or M): 0, or -1 when
 * the projection fails. */
static int project_point(sk_instance *inst, int f, int q, const double *xs, const double *xm, int m, double tol,
                         mortar_point_projection *pr) {
  const sk_view *sv = inst->slave, *mv = inst->master;
  double xf[3 * MORTAR_MAX_NEN], nf[3 * MORTAR_MAX_NEN], xmf[3 * MORTAR_MAX_NEN];
  for (int a = 0; a < sv->nen; ++a) {
    const int k = sv->conn[(int64_t)f * sv->nen + a];
    for (int i = 0; i < 3; ++i) {
      xf[3 * a + i] = i < inst->dim ? xs[(int64_t)k * inst->dim + i] : 0.0;
      nf[3 * a + i] = inst->normal[3 * k + i];
    }
  }
  for (int b = 0; b < mv->nen; ++b) {
    const int l = mv->conn[(int64_t)m * mv->nen + b];
    for (int i = 0; i < 3; ++i) xmf[3 * b + i] = i < inst->dim ? xm[(int64_t)l * inst->dim + i] : 0.0;
  }
  mortar_pair p;
  mortar_pair_set(&p, inst->dim, &inst->st, &inst->mt, xf, xmf, nf, 0);
  return mortar_project_point(&p, inst->normal_variant, inst->face_xi + q * inst->st.pdim, tol, pr);
}

/* Concentrated integration: the master face of slave Gauss point q of face f among the candidates (Hammer 7.2.1):
 * the face it projects into (in-of-both: the smaller |g_n|); none: if its nearest master node is interior, the
 * nearer of that node's faces (out-of-both), else -1 (out-of-first/-last: the point is dropped). */
static int select_master(sk_instance *inst, int f, int q, const double *xs, const double *xm, const int *cands,
                         int nc) {
  const sk_view *sv = inst->slave, *mv = inst->master;
  const double *xi = inst->face_xi + q * inst->st.pdim;
  double N[MORTAR_MAX_NEN], dN[2 * MORTAR_MAX_NEN], x1[3] = {0, 0, 0};
  inst->api->contact->shape(inst->st.type, xi, N, dN);
  for (int a = 0; a < sv->nen; ++a)
    for (int i = 0; i < inst->dim; ++i) x1[i] += N[a] * xs[(int64_t)sv->conn[(int64_t)f * sv->nen + a] * inst->dim + i];
  /* the nearest master node of the candidates */
  int nearest = -1;
  double d_near = INFINITY;
  for (int c = 0; c < nc; ++c)
    for (int b = 0; b < mv->nen; ++b) {
      const int l = mv->conn[(int64_t)cands[c] * mv->nen + b];
      double d2 = 0.0;
      for (int i = 0; i < inst->dim; ++i) {
        const double d = xm[(int64_t)l * inst->dim + i] - x1[i];
        d2 += d * d;
      }
      if (d2 < d_near) {
        d_near = d2;
        nearest = l;
      }
    }
  int best_inside = -1, best_any = -1;
  double gap_inside = INFINITY, gap_near = INFINITY;
  for (int c = 0; c < nc; ++c) {
    const int m = cands[c];
    mortar_point_projection pr;
    if (project_point(inst, f, q, xs, xm, m, 1e-12, &pr) != 0) continue;
    if (pr.inside && fabs(pr.gap) < gap_inside) {
      gap_inside = fabs(pr.gap);
      best_inside = m;
    }
    int touches = 0;
    for (int b = 0; b < mv->nen; ++b) touches |= mv->conn[(int64_t)m * mv->nen + b] == nearest;
    if (touches && fabs(pr.gap) < gap_near) {
      gap_near = fabs(pr.gap);
      best_any = m;
    }
  }
  if (best_inside >= 0) return best_inside;
  if (nearest >= 0 && !inst->master_border[nearest]) return best_any;
  return -1;
}

/* The distinct master faces of face f's Gauss points: appended to cand from *n. */
static sk_status point_faces(sk_instance *inst, int f, int **cand, int *cap, int *n) {
  SK_TRY(mortar_grow(inst, cand, cap, *n + inst->n_face_points));
  const int first = *n;
  for (int q = 0; q < inst->n_face_points; ++q) {
    const int m = inst->ip_master[f * inst->n_face_points + q];
    int seen = m < 0;
    for (int c = first; c < *n && !seen; ++c) seen = (*cand)[c] == m;
    if (!seen) (*cand)[(*n)++] = m;
  }
  return SK_OK;
}

sk_status mortar_step_candidates(sk_instance *inst, const sk_state *state) {
  const sk_view *sv = inst->slave;
  memset(inst->cand_ptr, 0, sizeof(int) * ((size_t)sv->n_cells + 1));
  if (!inst->master) return SK_OK;
  SK_TRY(mortar_search_faces(inst, state, state->x[0], state->x[1]));
  if (inst->self) {
    int added;
    return mortar_self_assign(inst, state->x[0], 0, &added);
  }
  if (inst->integration == INTEGRATION_CONCENTRATED) mortar_compute_normals(inst, state->x[0]);
  int n = 0;
  for (int f = 0; f < sv->n_cells; ++f) {
    inst->cand_ptr[f] = n;
    const int h0 = inst->hit_ptr[f], nh = inst->hit_ptr[f + 1] - h0;
    if (inst->integration == INTEGRATION_SEGMENTS) {
      SK_TRY(mortar_grow(inst, &inst->cand, &inst->cand_cap, n + nh));
      if (nh > 0) memcpy(inst->cand + n, inst->hits.faces + h0, sizeof(int) * (size_t)nh); /* cand may be NULL */
      n += nh;
      continue;
    }
    /* each Gauss point's master face, frozen for the step (H 7.2.3) */
    for (int q = 0; q < inst->n_face_points && nh > 0; ++q)
      inst->ip_master[f * inst->n_face_points + q] =
          select_master(inst, f, q, state->x[0], state->x[1], inst->hits.faces + h0, nh);
    if (nh == 0)
      for (int q = 0; q < inst->n_face_points; ++q) inst->ip_master[f * inst->n_face_points + q] = -1;
    SK_TRY(point_faces(inst, f, &inst->cand, &inst->cand_cap, &n));
  }
  inst->cand_ptr[sv->n_cells] = n;
  return SK_OK;
}

/* A Gauss point keeps its frozen master face within frozen_band beyond the face's edge (face parameters, default
 * 0.1): at a master node the point's projection may sit a round-off outside either face, and reselecting there would
 * alternate between the two faces from one Newton run to the next (Hammer 7.2.3 saw the same within Newton, and holds
 * the face for the whole step); penalty-nts keeps its face with the same hysteresis (SELECT_BAND). The band makes
 * the converged state depend slightly on the path (a point kept on a face's extension instead of its neighbour):
 * Hammer 8.1's step 70 against step 10, 1.1e-4 of F_y with the default, 1e-15 with frozen_band 0. */

static int among(const int *list, int n, int face) {
  for (int c = 0; c < n; ++c)
    if (list[c] == face) return 1;
  return 0;
}

/* The candidates of a step come from the slave faces' boxes swept from x_n to the predictor, which for quasi-static
 * steps is x_n itself on the slave surface (the drive acts on other nodes): a slave face that slides further within
 * the step than the search margin reaches overlaps master faces that are not its candidates, and their share of
 * g~_j, M and the slip is missing at the converged point — nodes lose contact without a message (found: slider-2d at
 * dt = 0.8, 3.2 master faces per step, lost every node). At convergence the faces are searched again over the path
 * x_n -> x; a master face that overlaps a slave face there within the search margin's reach along the normal
 * (segments), or a Gauss point that left its frozen master face or now lies over one (concentrated), extends the
 * candidates, and the converged point is rejected: the host lays out again (pattern) and Newton runs again from x.
 * The old candidates stay (Newton may move back). The reach: the search margin bounds the gap at which a face is a
 * candidate at all; without it the elastic ring's flanks found faces that their normals hit 8 - 11 away (margin 5)
 * in every step, harmless (inactive) and each worth a second Newton run. */
sk_status mortar_extend_candidates(sk_instance *inst, const sk_state *state, int *added) {
  *added = 0;
  if (!inst->master) return SK_OK;
  const sk_view *sv = inst->slave;
  const double *xs = state->x[0], *xm = state->x[1];
  SK_TRY(mortar_search_faces(inst, state, xs, xm));
  if (inst->self) {
    SK_TRY(mortar_self_assign(inst, xs, 1, added));
    return *added ? mortar_build_columns(inst) : SK_OK;
  }
  mortar_compute_normals(inst, xs);
  int n = 0;
  for (int f = 0; f < sv->n_cells; ++f) {
    inst->cand_ptr_next[f] = n;
    const int c0 = inst->cand_ptr[f], nc = inst->cand_ptr[f + 1] - c0;
    const int h0 = inst->hit_ptr[f], nh = inst->hit_ptr[f + 1] - h0;
    if (inst->integration == INTEGRATION_SEGMENTS) {
      SK_TRY(mortar_grow(inst, &inst->cand_next, &inst->cand_next_cap, n + nc + nh));
      if (nc > 0) memcpy(inst->cand_next + n, inst->cand + c0, sizeof(int) * (size_t)nc); /* either may be NULL */
      n += nc;
      for (int h = h0; h < h0 + nh; ++h) {
        const int m = inst->hits.faces[h];
        if (among(inst->cand + c0, nc, m) || !mortar_pair_reaches(inst, f, m, xs, xm, inst->search_margin)) continue;
        inst->cand_next[n++] = m;
        ++*added;
      }
      continue;
    }
    for (int q = 0; q < inst->n_face_points && nh > 0; ++q) {
      int *frozen = &inst->ip_master[f * inst->n_face_points + q];
      /* the frozen face is kept while the point projects into it or within frozen_band beyond its edge */
      mortar_point_projection pr;
      if (*frozen >= 0 && project_point(inst, f, q, xs, xm, *frozen, inst->frozen_band, &pr) == 0 && pr.inside)
        continue;
      const int m = select_master(inst, f, q, xs, xm, inst->hits.faces + h0, nh);
      if (m == *frozen) continue;
      *frozen = m;
      ++*added;
    }
    SK_TRY(point_faces(inst, f, &inst->cand_next, &inst->cand_next_cap, &n));
  }
  inst->cand_ptr_next[sv->n_cells] = n;
  if (*added == 0) return SK_OK;
  int *t = inst->cand;
  inst->cand = inst->cand_next;
  inst->cand_next = t;
  t = inst->cand_ptr;
  inst->cand_ptr = inst->cand_ptr_next;
  inst->cand_ptr_next = t;
  const int cap = inst->cand_cap;
  inst->cand_cap = inst->cand_next_cap;
  inst->cand_next_cap = cap;
  return mortar_build_columns(inst);
}
