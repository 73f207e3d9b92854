/* mortar-dual glue: the contact terms at one point x (mortar.h). For every needed slave view face: D of the face,
 * M and the weighted gap of each candidate master face (or the obstacle); owned faces add their nodes' forces D^T z
 * and the master's -M^T z [F1]; owned nodes collect g~_j and the weighted slip and add their NCP rows [C1], [C2].
 * Derivatives come from the kernel with respect to the pair's local unknowns [x_s | x_m | n_s] and are chained here
 * to global columns, n_s through the nodal normals' derivatives [N3]. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mortar.h"

/* ---- positions and normals ------------------------------------------------------------------------------------- */
static void gather(const sk_view *v, const double *x, int face, double *out) {
  for (int a = 0; a < v->nen; ++a) {
    const int k = v->conn[(int64_t)face * v->nen + a];
    for (int i = 0; i < 3; ++i) out[3 * a + i] = i < v->dim ? x[(int64_t)k * v->dim + i] : 0.0;
  }
}

/* Averaged nodal normals [N1] and their derivatives [N3] at every slave view node. */
void mortar_compute_normals(sk_instance *inst, const double *xs) {
  const sk_view *v = inst->slave;
  const int nen = v->nen;
  memset(inst->cvec, 0, sizeof(double) * 3 * (size_t)v->n_nodes);
  memset(inst->dc, 0, sizeof(double) * 9 * (size_t)inst->star_node_ptr[v->n_nodes]);
  for (int f = 0; f < v->n_cells; ++f) {
    double xf[3 * MORTAR_MAX_NEN], c[3], dcf[MORTAR_MAX_NEN][3][3];
    gather(v, xs, f, xf);
    for (int a = 0; a < nen; ++a) {
      const int j = v->conn[(int64_t)f * nen + a];
      mortar_face_normal_at_node(&inst->st, inst->dim, xf, a, c, dcf);
      for (int i = 0; i < 3; ++i) inst->cvec[3 * j + i] += c[i];
      for (int b = 0; b < nen; ++b) {
        double *blk = inst->dc + 9 * (size_t)inst->face_star_index[(f * nen + a) * nen + b];
        for (int i = 0; i < 9; ++i) blk[i] += (&dcf[b][0][0])[i];
      }
    }
  }
  for (int j = 0; j < v->n_nodes; ++j) {
    double dn_dc[3][3];
    if (mortar_normalize(inst->cvec + 3 * j, inst->normal + 3 * j, dn_dc) != 0) {
      memset(inst->normal + 3 * j, 0, sizeof(double) * 3); /* a node of no view face: never used */
      continue;
    }
    for (int s = inst->star_node_ptr[j]; s < inst->star_node_ptr[j + 1]; ++s) {
      const double *blk = inst->dc + 9 * (size_t)s;
      double *out = inst->dnormal + 9 * (size_t)s;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
          double val = 0.0;
          for (int k = 0; k < 3; ++k) val += dn_dc[r][k] * blk[k * 3 + c];
          out[r * 3 + c] = val;
        }
    }
  }
}

/* ---- from the pair's local slots to global columns ------------------------------------------------------------- */
static int chain_node(pair_chain *pc, int side, int node) {
  for (int i = 0; i < pc->n_nodes; ++i)
    if (pc->node[i] == node && pc->side[i] == side) return i;
  pc->side[pc->n_nodes] = side;
  pc->node[pc->n_nodes] = node;
  return pc->n_nodes++;
}

/* Slots [x_s | x_m | n_s] of slave face f and master face m (-1: none) -> columns node * dim + component of the
 * chain's nodes. */
static void chain_build(sk_instance *inst, int f, int m) {
  pair_chain *pc = &inst->chain;
  const sk_view *sv = inst->slave;
  const int dim = inst->dim, ns = sv->nen, nm = m >= 0 && inst->master ? inst->master->nen : 0;
  pc->n_nodes = 0;
  int e = 0, slot = 0;
  for (int a = 0; a < ns; ++a)
    for (int i = 0; i < dim; ++i, ++slot) {
      pc->slot_ptr[slot] = e;
      pc->entry[e++] = (chain_entry){chain_node(pc, SIDE_SLAVE, sv->conn[(int64_t)f * ns + a]) * dim + i, 1.0};
    }
  for (int b = 0; b < nm; ++b)
    for (int i = 0; i < dim; ++i, ++slot) {
      pc->slot_ptr[slot] = e;
      pc->entry[e++] =
          (chain_entry){chain_node(pc, SIDE_MASTER, inst->master->conn[(int64_t)m * nm + b]) * dim + i, 1.0};
    }
  for (int a = 0; a < ns; ++a) {
    const int j = sv->conn[(int64_t)f * ns + a];
    for (int i = 0; i < dim; ++i, ++slot) {
      pc->slot_ptr[slot] = e;
      for (int s = inst->star_node_ptr[j]; s < inst->star_node_ptr[j + 1]; ++s) {
        const int pos = chain_node(pc, SIDE_SLAVE, inst->star_node[s]) * dim;
        const double *dn = inst->dnormal + 9 * (size_t)s;
        for (int c = 0; c < dim; ++c)
          if (dn[i * 3 + c] != 0.0) pc->entry[e++] = (chain_entry){pos + c, dn[i * 3 + c]};
      }
    }
  }
  pc->slot_ptr[slot] = e;
}

/* row[pos] += scale * d y / d (chain columns) */
static void chain_apply(const pair_chain *pc, const fwd *y, double scale, double *row) {
  for (int s = 0; s < y->n; ++s) {
    const double d = scale * y->d[s];
    if (d == 0.0) continue;
    for (int e = pc->slot_ptr[s]; e < pc->slot_ptr[s + 1]; ++e) row[pc->entry[e].pos] += d * pc->entry[e].coef;
  }
}

/* Position of each chain column in owned node o's sorted column list (-1 if absent: not a coupling of the node). */
static void map_to_node(sk_instance *inst, const owned_node *o) {
  const pair_chain *pc = &inst->chain;
  const int64_t *cols = inst->col + o->cols;
  for (int n = 0; n < pc->n_nodes; ++n)
    for (int i = 0; i < inst->dim; ++i) {
      const int64_t key = mortar_node_dof(inst, pc->side[n], pc->node[n], i);
      int lo = 0, hi = o->n_cols - 1, found = -1;
      while (lo <= hi) {
        const int mid = (lo + hi) / 2;
        if (cols[mid] == key) {
          found = mid;
          break;
        }
        if (cols[mid] < key) lo = mid + 1;
        else hi = mid - 1;
      }
      inst->pos_map[n * inst->dim + i] = found;
    }
}

/* acc[pos_map[c]] += d y / d (chain column c) */
static void accumulate(sk_instance *inst, const fwd *y, double *acc) {
  const int nc = inst->chain.n_nodes * inst->dim;
  memset(inst->block, 0, sizeof(double) * (size_t)nc);
  chain_apply(&inst->chain, y, 1.0, inst->block);
  for (int c = 0; c < nc; ++c)
    if (inst->block[c] != 0.0 && inst->pos_map[c] >= 0) acc[inst->pos_map[c]] += inst->block[c];
}

/* ---- forces of one pair on owned faces [F1] ------------------------------------------------------------------ */
/* Slave rows (the face part: D) or master rows (a pair: M) of face f against master face m. */
static void add_forces(sk_instance *inst, const sk_state *state, eval_mode mode, sk_sink *sink, int f, int m,
                       const mortar_pair *p, const mortar_integrals *I, double z[][3]) {
  const int dim = inst->dim, ns = p->nen_s, nm = p->nen_m;
  const int first = m < 0 ? 0 : ns, last = m < 0 ? ns : ns + nm; /* rows: slave nodes or master nodes */
  fwd F[2 * MORTAR_MAX_NEN][3];
  mortar_pair_forces(p, I, inst->basis, z, F);
  int64_t rows[2 * MORTAR_MAX_NEN * 3];
  int nr = 0;
  for (int a = first; a < last; ++a)
    for (int i = 0; i < dim; ++i)
      rows[nr++] = a < ns ? mortar_node_dof(inst, SIDE_SLAVE, inst->slave->conn[(int64_t)f * ns + a], i)
                          : mortar_node_dof(inst, SIDE_MASTER, inst->master->conn[(int64_t)m * nm + a - ns], i);
  if (mode == EVAL_RESIDUAL) {
    double vals[2 * MORTAR_MAX_NEN * 3];
    int r = 0;
    for (int a = first; a < last; ++a)
      for (int i = 0; i < dim; ++i) vals[r++] = F[a][i].v;
    sink->add_vector(sink, nr, rows, vals);
    return;
  }
  /* geometry columns */
  const pair_chain *pc = &inst->chain;
  const int nc = pc->n_nodes * dim;
  memset(inst->block, 0, sizeof(double) * (size_t)(nr * nc));
  int r = 0;
  for (int a = first; a < last; ++a)
    for (int i = 0; i < dim; ++i, ++r) chain_apply(pc, &F[a][i], 1.0, inst->block + (size_t)r * nc);
  for (int n = 0; n < pc->n_nodes; ++n)
    for (int i = 0; i < dim; ++i) inst->block_cols[n * dim + i] = mortar_node_dof(inst, pc->side[n], pc->node[n], i);
  sink->add_matrix(sink, nr, rows, nc, inst->block_cols, inst->block);
  /* columns of the unknowns z~_j = A_j z_j [U1]: d f_k,i / d z~_j,i = D_jk / A_j (slave rows), -M_jl / A_j (master) */
  int64_t zcols[MORTAR_MAX_NEN * 3];
  double zblk[2 * MORTAR_MAX_NEN * 3 * MORTAR_MAX_NEN * 3];
  const int nzc = ns * dim;
  for (int j = 0; j < ns; ++j)
    for (int i = 0; i < dim; ++i)
      zcols[j * dim + i] =
          state->extra_offset + dim * inst->slave->node_index[inst->slave->conn[(int64_t)f * ns + j]] + i;
  memset(zblk, 0, sizeof(double) * (size_t)(nr * nzc));
  r = 0;
  for (int a = first; a < last; ++a)
    for (int i = 0; i < dim; ++i, ++r)
      for (int j = 0; j < ns; ++j) {
        double coef;
        if (a < ns) coef = (inst->basis == MORTAR_DUAL && j != a) ? 0.0 : I->D[j][a].v;
        else coef = -I->M[j][a - ns].v;
        zblk[r * nzc + j * dim + i] = coef / inst->A_node[inst->slave->conn[(int64_t)f * ns + j]];
      }
  sink->add_matrix(sink, nr, rows, nzc, zcols, zblk);
}

/* ---- one pair's contributions -------------------------------------------------------------------------------- */
typedef struct {
  const sk_state *state;
  eval_mode mode;
  sk_sink *sink;
  double z[MORTAR_MAX_NEN][3];
  const double *xs_n;
} eval_ctx;

/* The face part (m = -1: D, the obstacle's slip jump) or a pair's part (M, gap) of slave face f. */
static void contribute(sk_instance *inst, const eval_ctx *ec, int f, int m, const mortar_pair *p,
                       const mortar_integrals *I) {
  const sk_view *sv = inst->slave;
  const int dim = inst->dim, ns = sv->nen, deriv = ec->mode == EVAL_JACOBIAN;
  if (deriv) chain_build(inst, f, m);
  const int forces_here = (ec->mode == EVAL_RESIDUAL || ec->mode == EVAL_JACOBIAN) && sv->cell_owned[f];
  /* the obstacle takes its force (no master rows) */
  if (forces_here && !(m >= 0 && inst->obstacle))
    add_forces(inst, ec->state, ec->mode, ec->sink, f, m, p, I, (double(*)[3])ec->z);
  if (ec->mode == EVAL_COMMIT && m < 0 && sv->cell_owned[f]) {
    /* the resultant force on the slave and its moment about the origin: minus the residual's D^T z */
    fwd F[2 * MORTAR_MAX_NEN][3];
    mortar_pair_forces(p, I, inst->basis, (double(*)[3])ec->z, F);
    for (int a = 0; a < ns; ++a) {
      double fa[3] = {0, 0, 0}, xa[3] = {0, 0, 0};
      for (int i = 0; i < dim; ++i) {
        fa[i] = -F[a][i].v;
        xa[i] = p->xs[a][i].v;
        inst->force[i] += fa[i];
      }
      inst->moment[0] += xa[1] * fa[2] - xa[2] * fa[1];
      inst->moment[1] += xa[2] * fa[0] - xa[0] * fa[2];
      inst->moment[2] += xa[0] * fa[1] - xa[1] * fa[0];
    }
  }
  fwd W[MORTAR_MAX_NEN][3];
  if (inst->friction && inst->master) mortar_pair_weighted_positions(p, I, inst->basis, W);
  for (int a = 0; a < ns; ++a) {
    const int j = sv->conn[(int64_t)f * ns + a], oi = inst->owned_of_node[j];
    if (oi < 0) continue;
    owned_node *o = &inst->owned[oi];
    if (deriv) map_to_node(inst, o);
    if (m >= 0) { /* a pair: weighted gap and coverage */
      o->gap += I->gap[a].v;
      o->cover += I->cover[a];
      if (deriv) accumulate(inst, &I->gap[a], inst->acc_gap + o->cols);
    }
    if (inst->friction && inst->master) {
      for (int i = 0; i < dim; ++i) {
        o->W[i] += W[a][i].v;
        if (deriv) accumulate(inst, &W[a][i], inst->acc_W + (size_t)i * inst->n_col + o->cols);
      }
    } else if (inst->friction && m < 0) {
      /* obstacle: U_j = sum_k D_jk (x_k - x_k^n - (d - d^n)) */
      for (int k = 0; k < ns; ++k) {
        if (inst->basis == MORTAR_DUAL && k != a) continue;
        const int node = sv->conn[(int64_t)f * ns + k];
        for (int i = 0; i < dim; ++i) {
          const double jump = -ec->xs_n[(int64_t)node * dim + i] - (inst->obstacle_d[i] - inst->obstacle_d_n[i]);
          const fwd u = fwd_mul(I->D[a][k], fwd_addc(p->xs[k][i], jump));
          o->W[i] += u.v;
          if (deriv) accumulate(inst, &u, inst->acc_W + (size_t)i * inst->n_col + o->cols);
        }
      }
    }
    if (ec->mode == EVAL_COMMIT && inst->master) {
      /* D^n (+) on slave nodes, M^n (-) on master nodes, at the node's component-0 columns */
      for (int k = 0; k < (m < 0 ? ns : p->nen_m); ++k) {
        const double coef = m < 0 ? ((inst->basis == MORTAR_DUAL && k != a) ? 0.0 : I->D[a][k].v) : -I->M[a][k].v;
        const int side = m < 0 ? SIDE_SLAVE : SIDE_MASTER;
        const int node = m < 0 ? sv->conn[(int64_t)f * ns + k] : inst->master->conn[(int64_t)m * p->nen_m + k];
        const int64_t key = mortar_node_dof(inst, side, node, 0);
        for (int c = 0; c < o->n_cols; ++c)
          if (inst->col[o->cols + c] == key) {
            inst->commit_rows[o->cols + c] += coef;
            break;
          }
      }
    }
  }
}

typedef struct {
  const sk_host_api *api;
  const sk_obstacle *obstacle;
  double t;
  int dim;
} obstacle_ctx;

static int project_obstacle(void *ctx, const double *x, double *gap, double *normal) {
  const obstacle_ctx *oc = ctx;
  sk_surface_point pt = {.struct_size = sizeof pt};
  if (oc->api->contact->obstacle_project(oc->obstacle, oc->t, x, oc->dim, &pt, gap) != SK_OK) return -1;
  for (int i = 0; i < 3; ++i) normal[i] = pt.n[i];
  return 0;
}

/* Positions and nodal normals of slave face f. */
static void gather_slave_face(const sk_instance *inst, const double *xs, int f, double *xf, double *nf) {
  const sk_view *sv = inst->slave;
  gather(sv, xs, f, xf);
  for (int a = 0; a < sv->nen; ++a)
    for (int i = 0; i < 3; ++i) nf[3 * a + i] = inst->normal[3 * sv->conn[(int64_t)f * sv->nen + a] + i];
}

/* Segment-based integration of one pair (section 3.1): 2D segments or 3D clipping. */
static void pair_segments(const sk_instance *inst, const mortar_pair *p, const mortar_basis_coeffs *A,
                          mortar_integrals *I) {
  if (inst->dim == 2) mortar_segments_2d(p, A, inst->basis, inst->segment_gauss, I);
  else mortar_segments_3d(p, A, inst->basis, inst->cell_rule, I);
}

int mortar_pair_reaches(sk_instance *inst, int f, int m, const double *xs, const double *xm, double reach) {
  double xf[3 * MORTAR_MAX_NEN], nf[3 * MORTAR_MAX_NEN], xmf[3 * MORTAR_MAX_NEN];
  gather_slave_face(inst, xs, f, xf, nf);
  gather(inst->master, xm, m, xmf);
  mortar_pair p;
  mortar_basis_coeffs A;
  mortar_integrals I;
  mortar_pair_set(&p, inst->dim, &inst->st, &inst->mt, xf, xmf, nf, 0);
  mortar_basis_coefficients(&p, inst->basis, &A);
  mortar_integrals_zero(&I, &p);
  pair_segments(inst, &p, &A, &I);
  return I.n_cells > 0 && I.gap_min <= reach;
}

/* Every pair of slave face f. */
static sk_status face_pairs(sk_instance *inst, const eval_ctx *ec, int f, const double *xs, const double *xm) {
  const sk_view *sv = inst->slave;
  const int dim = inst->dim, deriv = ec->mode == EVAL_JACOBIAN;
  double xf[3 * MORTAR_MAX_NEN], nf[3 * MORTAR_MAX_NEN], xmf[3 * MORTAR_MAX_NEN];
  gather_slave_face(inst, xs, f, xf, nf);
  mortar_pair p;
  mortar_basis_coeffs A;
  mortar_integrals I;
  const int read = inst->cache_use == CACHE_READ, nf2 = 2 * sv->n_cells; /* cache entries: mortar.h */
  /* the face part: D over the whole slave face */
  mortar_pair_set(&p, dim, &inst->st, NULL, xf, NULL, nf, deriv);
  if (!read) mortar_basis_coefficients(&p, inst->basis, &A);
  mortar_integrals_zero(&I, &p);
  if (read) mortar_cache_get(inst, f, &I);
  else mortar_slave_integrals(&p, &A, inst->basis, inst->n_d_points, inst->d_xi, inst->d_w, &I);
  mortar_cache_put(inst, f, &I);
  contribute(inst, ec, f, -1, &p, &I);
  if (inst->obstacle) {
    obstacle_ctx oc = {inst->api, inst->obstacle, ec->state->t, dim};
    mortar_integrals_zero(&I, &p);
    if (read) mortar_cache_get(inst, sv->n_cells + f, &I);
    else
      mortar_obstacle_points(&p, &A, inst->basis, inst->n_face_points, inst->face_xi, inst->face_w,
                             project_obstacle, &oc, &I);
    mortar_cache_put(inst, sv->n_cells + f, &I);
    if (I.n_cells > 0) contribute(inst, ec, f, 0, &p, &I); /* m = 0: a pair without master rows */
    return SK_OK;
  }
  const int pd = inst->st.pdim;
  for (int c = inst->cand_ptr[f]; c < inst->cand_ptr[f + 1]; ++c) {
    const int m = inst->cand[c];
    gather(inst->master, xm, m, xmf);
    mortar_pair_set(&p, dim, &inst->st, &inst->mt, xf, xmf, nf, deriv); /* A (of x_s alone) stays valid */
    mortar_integrals_zero(&I, &p);
    if (read && inst->integration == INTEGRATION_SEGMENTS) {
      mortar_cache_get(inst, nf2 + c, &I);
    } else if (inst->integration == INTEGRATION_SEGMENTS) {
      pair_segments(inst, &p, &A, &I);
    } else {
      double xi[MORTAR_MAX_RULE * MORTAR_MAX_RULE * 2], w[MORTAR_MAX_RULE * MORTAR_MAX_RULE];
      int n = 0;
      for (int q = 0; q < inst->n_face_points; ++q)
        if (inst->ip_master[f * inst->n_face_points + q] == m) {
          for (int k = 0; k < pd; ++k) xi[n * pd + k] = inst->face_xi[q * pd + k];
          w[n++] = inst->face_w[q];
        }
      if (read) mortar_cache_get(inst, nf2 + c, &I);
      else mortar_points(&p, &A, inst->basis, inst->normal_variant, n, xi, w, &I);
      if (I.n_cells < n)
        return inst->api->error(inst->host, SK_ERR_DIVERGED,
                                "mortar-dual: a Gauss point of slave face %lld does not project onto its master face "
                                "%lld any more (the step moved too far)",
                                (long long)sv->cell_index[f], (long long)inst->master->cell_index[m]);
    }
    mortar_cache_put(inst, nf2 + c, &I);
    if (I.n_cells > 0) contribute(inst, ec, f, m, &p, &I);
  }
  return SK_OK;
}

/* ---- the NCP rows of an owned node [C1], [C2] ------------------------------------------------------------------ */
static int column_of(const sk_instance *inst, const owned_node *o, int64_t key) {
  const int64_t *cols = inst->col + o->cols;
  int lo = 0, hi = o->n_cols - 1;
  while (lo <= hi) {
    const int mid = (lo + hi) / 2;
    if (cols[mid] == key) return mid;
    if (cols[mid] < key) lo = mid + 1;
    else hi = mid - 1;
  }
  return -1;
}

static sk_status ncp_rows(sk_instance *inst, const eval_ctx *ec, owned_node *o, const double *xs, const double *xm,
                          int *changed) {
  const int dim = inst->dim, nt = dim - 1, j = o->node, nc = o->n_cols;
  const double *n = inst->normal + 3 * j, *z = o->z;
  double tau[2][3], dtau_dn[2][3][3];
  if (mortar_tangents(dim, n, o->ref, tau, dtau_dn) != 0)
    return inst->api->error(inst->host, SK_ERR_DIVERGED,
                            "mortar-dual: the normal of slave node %lld turned onto its tangent reference direction "
                            "within one step",
                            (long long)inst->slave->node_id[j]);
  /* the weighted slip u~ [S1]: -(W - W^n(x)) on a deformable master, the weighted jump on an obstacle */
  double u[3] = {0, 0, 0};
  for (int i = 0; i < dim; ++i) u[i] = inst->master ? -o->W[i] : o->W[i];
  if (inst->master && inst->friction)
    for (int h = o->hist; h < o->hist + o->n_hist; ++h) {
      const double *x = inst->hist_side[h] == SIDE_SLAVE ? xs : xm;
      for (int i = 0; i < dim; ++i) u[i] += inst->hist_value[h] * x[(int64_t)inst->hist_node[h] * dim + i];
    }
  const double A = o->A_ref;
  double zn = 0.0, zt[2] = {0, 0}, s[2] = {0, 0};
  for (int i = 0; i < dim; ++i) zn += n[i] * z[i];
  for (int a = 0; a < nt; ++a)
    for (int i = 0; i < dim; ++i) {
      zt[a] += tau[a][i] * z[i];
      s[a] += tau[a][i] * u[i] / A;
    }
  const double g = o->gap / A;
  /* the branch: decided at a new point (update_active_set), frozen for F and J there */
  int force = o->state;
  const int uncovered = o->cover < inst->min_cover * A;
  /* decided afresh at every new point (semismooth, until max_flips froze the branch) and always at convergence: a
   * branch frozen by max_flips must be checked there, or a penetrating node frozen inactive (or a sliding node
   * frozen in stick) would be accepted (found: slider-2d at dt 0.4, a trailing corner 5e-3 deep with no force) */
  if (ec->mode == EVAL_SET &&
      (inst->deciding || (inst->active_set == ACTIVE_SET_SEMISMOOTH && o->flips < inst->max_flips)))
    force = -1;
  if (uncovered) force = MORTAR_INACTIVE; /* no master under the node: no contact (docs §5) */
  /* the nested loop keeps a slipping node's direction for the Newton run (mortar_ncp_eval_dir) */
  double dir[2] = {0, 0}, dlen = 0.0;
  if (inst->active_set == ACTIVE_SET_NESTED && inst->friction && o->state == MORTAR_SLIP) {
    for (int a = 0; a < nt; ++a) {
      for (int i = 0; i < dim; ++i) dir[a] += tau[a][i] * o->slip_dir[i];
      dlen += dir[a] * dir[a];
    }
    dlen = sqrt(dlen);
    for (int a = 0; a < nt; ++a) dir[a] /= dlen > 0.0 ? dlen : 1.0;
  }
  const double *frozen_dir = dlen > 0.0 ? dir : NULL;
  mortar_ncp r;
  mortar_ncp_eval_dir(nt, zn, zt, g, s, &inst->ncp, force, force == o->state ? frozen_dir : NULL, &r);
  if (ec->mode == EVAL_COMMIT && inst->recording_start) return SK_OK;
  if (ec->mode == EVAL_COMMIT) {
    o->dissipation = 0.0; /* z_t . u~_t: friction force times the weighted slip of the step */
    for (int a = 0; a < nt; ++a) o->dissipation += zt[a] * s[a] * A;
    memset(o->slip_increment, 0, sizeof o->slip_increment);
    if (inst->friction && r.state != MORTAR_INACTIVE) {
      for (int a = 0; a < nt; ++a)
        for (int i = 0; i < dim; ++i) o->slip_increment[i] += s[a] * tau[a][i];
      o->slip_length += sqrt(o->slip_increment[0] * o->slip_increment[0] + o->slip_increment[1] * o->slip_increment[1] +
                             o->slip_increment[2] * o->slip_increment[2]);
    }
    return SK_OK;
  }
  if (ec->mode == EVAL_SET) {
    /* at a converged point a node on the border of two branches keeps its own (mortar_ncp_branch_holds): the
     * decision on the sign of round-off cycled Hammer's nested loop when the block of his benchmark touched the
     * slab at the end of step 1 (g = z_n = 0 at 25 nodes; 10 outer loops, then step cuts) */
    if (inst->deciding && !uncovered &&
        mortar_ncp_branch_holds(nt, zn, zt, g, s, &inst->ncp, o->state, frozen_dir, inst->branch_tol))
      return SK_OK;
    /* a slip that turned against its frozen direction is a change as well: Newton again with the new direction */
    if (r.state != o->state || (frozen_dir && r.state == MORTAR_SLIP)) {
      ++*changed;
      ++o->flips;
      o->state = r.state;
    }
    if (inst->active_set == ACTIVE_SET_NESTED && r.state == MORTAR_SLIP) {
      /* the direction of the trial traction v = z_t + c_t s, frozen for the next Newton run */
      double v[3] = {0, 0, 0}, vlen = 0.0;
      for (int a = 0; a < nt; ++a) {
        const double va = zt[a] + inst->ncp.c_t * s[a];
        for (int i = 0; i < dim; ++i) v[i] += va * tau[a][i];
        vlen += va * va;
      }
      vlen = sqrt(vlen);
      for (int i = 0; i < 3; ++i) o->slip_dir[i] = vlen > 0.0 ? v[i] / vlen : 0.0;
    }
    return SK_OK;
  }
  /* NCP c goes to the node's constraint row place[c]. Under `condensed` the host puts constraint row i in the place
   * of the slave's displacement row i, so C_N takes the row of the normal's dominant axis and each C_T that of its
   * tangent's: the condensed operator keeps a nonzero diagonal (in the Cartesian order, C_N of a node with normal
   * -e_z sat in the x row, whose d_x entry is n_x c_n D_jj = 0, and MueLu's smoother divided by it: NaN in GMRES,
   * docs/plugins/mortar-dual.md section 7). The roots are the same. Saddle-point keeps the Cartesian order: there
   * the order changes only the round-off of the solve, and slider-2d at dt 0.8 (validation_mortar_large_sliding)
   * showed that its 31-iteration step 7 then lands on another converged state (2 nodes active, F_y 34.2). */
  int place[3] = {0, 1, 2};
  if (inst->strategy == STRATEGY_CONDENSED) mortar_ncp_places(dim, n, tau, place);
  int64_t rows[3], zcols[3];
  for (int c = 0; c < dim; ++c) {
    rows[c] = mortar_z_index(inst, ec->state, o->extra, place[c]);
    zcols[c] = mortar_z_index(inst, ec->state, o->extra, c);
  }
  /* the rows in force units, A_j C [U1] (with the columns z~ = A_j z, d(A_j C)/dz~ = dC/dz) */
  if (ec->mode == EVAL_RESIDUAL) {
    double scaled[3];
    for (int c = 0; c < dim; ++c) scaled[c] = A * r.C[c];
    ec->sink->add_vector(ec->sink, dim, rows, scaled);
    return SK_OK;
  }
  if (ec->mode != EVAL_JACOBIAN) return SK_OK;
  /* z columns: dC/dz = dC/dz_n n + sum_a dC/dz_ta tau_a */
  double zblk[9];
  for (int c = 0; c < dim; ++c) {
    for (int i = 0; i < dim; ++i) {
      double v = r.dC[c][0] * n[i];
      for (int a = 0; a < nt; ++a) v += r.dC[c][1 + a] * tau[a][i];
      zblk[c * dim + i] = v;
    }
  }
  ec->sink->add_matrix(ec->sink, dim, rows, dim, zcols, zblk);
  /* geometry columns: through n, tau (star of j), g~ and u~ (the accumulators) */
  double *blk = inst->block;
  memset(blk, 0, sizeof(double) * (size_t)(dim * nc));
  for (int c = 0; c < dim; ++c) {
    double *row = blk + (size_t)c * nc;
    for (int k = 0; k < nc; ++k) row[k] += r.dC[c][3] * inst->acc_gap[o->cols + k] / A;
    for (int a = 0; a < nt; ++a) {
      const double ds = r.dC[c][4 + a] / A; /* d C / d s_a, s_a = tau_a . u~ / A */
      if (ds == 0.0) continue;
      for (int i = 0; i < dim; ++i) {
        const double sign = inst->master ? -1.0 : 1.0;
        const double *dW = inst->acc_W + (size_t)i * inst->n_col + o->cols;
        for (int k = 0; k < nc; ++k) row[k] += ds * tau[a][i] * sign * dW[k];
      }
      if (inst->master)
        for (int h = o->hist; h < o->hist + o->n_hist; ++h)
          for (int i = 0; i < dim; ++i) {
            const int pos = column_of(inst, o, mortar_node_dof(inst, inst->hist_side[h], inst->hist_node[h], i));
            if (pos >= 0) row[pos] += ds * tau[a][i] * inst->hist_value[h];
          }
    }
    /* n and tau: d n / d x_k over the star of j */
    for (int e = inst->star_node_ptr[j]; e < inst->star_node_ptr[j + 1]; ++e) {
      const double *dn = inst->dnormal + 9 * (size_t)e;
      for (int mcomp = 0; mcomp < dim; ++mcomp) {
        const int pos = column_of(inst, o, mortar_node_dof(inst, SIDE_SLAVE, inst->star_node[e], mcomp));
        if (pos < 0) continue;
        double v = 0.0;
        for (int i = 0; i < dim; ++i) v += r.dC[c][0] * z[i] * dn[i * 3 + mcomp];
        for (int a = 0; a < nt; ++a)
          for (int i = 0; i < dim; ++i)
            for (int q = 0; q < dim; ++q) {
              const double dtau = dtau_dn[a][i][q] * dn[q * 3 + mcomp];
              v += (r.dC[c][1 + a] * z[i] + r.dC[c][4 + a] * u[i] / A) * dtau;
            }
        row[pos] += v;
      }
    }
  }
  for (int k = 0; k < dim * nc; ++k) blk[k] *= A;
  ec->sink->add_matrix(ec->sink, dim, rows, nc, inst->col + o->cols, blk);
  return SK_OK;
}

/* ---- the evaluation ------------------------------------------------------------------------------------------- */
sk_status mortar_evaluate(sk_instance *inst, const sk_state *state, eval_mode mode, sk_sink *sink, int *changed) {
  const sk_view *sv = inst->slave;
  const int dim = inst->dim;
  const double *xs = state->x[0], *xm = inst->master ? state->x[1] : NULL;
  eval_ctx ec = {state, mode, sink, {{0}}, state->x_n[0]};
  mortar_compute_normals(inst, xs);
  for (int i = 0; i < inst->n_owned; ++i) {
    owned_node *o = &inst->owned[i];
    o->gap = o->cover = 0.0;
    for (int c = 0; c < 3; ++c) {
      o->W[c] = 0.0;
      o->z[c] = c < dim && state->extra ? state->extra[o->extra + c] / o->A_ref : 0.0; /* [U1] */
    }
  }
  if (mode == EVAL_JACOBIAN && inst->n_col > 0) {
    memset(inst->acc_gap, 0, sizeof(double) * (size_t)inst->n_col);
    memset(inst->acc_W, 0, sizeof(double) * 3 * (size_t)inst->n_col);
  }
  if (mode == EVAL_COMMIT) {
    if (inst->n_col > 0) memset(inst->commit_rows, 0, sizeof(double) * (size_t)inst->n_col);
    memset(inst->force, 0, sizeof inst->force);
    memset(inst->moment, 0, sizeof inst->moment);
  }
  if (inst->obstacle) {
    inst->api->contact->obstacle_displacement(inst->obstacle, state->t, inst->obstacle_d);
    inst->api->contact->obstacle_displacement(inst->obstacle, state->t_n, inst->obstacle_d_n);
  }
  mortar_cache_begin(inst, state, mode != EVAL_JACOBIAN);
  for (int f = 0; f < sv->n_cells; ++f) {
    if (!inst->face_needed[f]) continue;
    for (int a = 0; a < sv->nen; ++a) {
      const int k = sv->conn[(int64_t)f * sv->nen + a];
      const int64_t g = sv->node_index[k];
      for (int i = 0; i < 3; ++i)
        ec.z[a][i] = i < dim && state->extra ? state->extra[dim * g + i] / inst->A_node[k] : 0.0;
    }
    const sk_status st = face_pairs(inst, &ec, f, xs, xm);
    if (st != SK_OK) {
      mortar_cache_end(inst, st);
      return st;
    }
  }
  mortar_cache_end(inst, SK_OK);
  int count = 0;
  for (int i = 0; i < inst->n_owned; ++i) SK_TRY(ncp_rows(inst, &ec, &inst->owned[i], xs, xm, &count));
  if (changed) *changed = count;
  return SK_OK;
}
