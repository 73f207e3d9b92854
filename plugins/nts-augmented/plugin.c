/* nts-augmented — plugin glue: one augmented NTS element per slave node and step (kernel.h), the active set, the
 * friction history and the three strategies:
 *   reduced  f and lambda_aug condensed out exactly per element (same Newton iterates as `none`)
 *   none     the full augmented system, 5 extra unknowns per slave node
 *   direct   the closest point by a local Newton at every evaluation (the paper's reference method); lambda_aug
 *            from (52); the condensed tangent is the exact (consistent) one.
 * Extra unknowns per slave node, at extra_offset + 5 node_index (its index in the whole slave surface, the same on
 * every rank): [lambda_n, f1, f2, lambda_aug1, lambda_aug2]. One slave_point per node of the slave view. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "kernel.h"
#include "stickslip/plugin.h"

enum { N_EXTRA = 5, STRATEGY_REDUCED = 0, STRATEGY_NONE = 1, STRATEGY_DIRECT = 2 };
enum { LOCAL_NEWTON_MAX = 30 };
static const double LOCAL_NEWTON_TOL = 1e-13;

typedef struct {
  int k;                       /* the node in the slave view */
  int64_t node;                /* its mesh id (messages, output) */
  int64_t index;               /* its index in the whole slave surface (extra unknowns at 5 index) */
  /* committed at the end of the last accepted step */
  int c_facet, c_active, c_slip;
  double c_f[2];               /* f at t_n */
  double c_t[2];               /* tangential traction t_n, covariant on c_facet */
  double c_t_vector[3];        /* the same traction as a spatial vector, to map it onto a new facet */
  double c_extra[N_EXTRA];
  /* this step */
  int facet, active, flips;
  int slip;                    /* stick/slip branch of the return map used in this iteration (friction only) */
  int return_map;              /* after max_flips: the return map itself picks the branch at every evaluation */
  int facet_nodes[NTS_MAX_NEN]; /* the facet's nodes in the master view */
  double f_start[2], t_start[2], f_frozen[2];
  double gap_estimate;         /* gap seen at begin_step (for output of inactive points) */
} slave_point;

struct sk_instance {
  const sk_host_api *api;
  sk_host *host;
  const sk_view *slave, *master;
  const char *name;
  nts_facet facet;
  int strategy;
  nts_friction_params friction;
  double c_n, search_margin;
  int max_flips;
  sk_search *search;
  int n_points;
  slave_point *points;
  int64_t n_extra;             /* 5 per node of the whole slave surface */
  double *initial;             /* for the owned points (zero elsewhere: the host sums over ranks) */
  unsigned char *eliminated;
  int *candidates;
  double alpha;                /* 1: backward Euler / quasi-static, 1/2: midpoint */
};

static const char *const strategies[] = {"reduced", "none", "direct", NULL};
static const char *const parameters[] = {
    "mu: Coulomb friction coefficient [0]",
    "epsilon_t: tangential penalty of the regularised friction law, force per unit of f (required if mu > 0)",
    "c_n: weight of the gap in the active-set test -lambda_n - c_n g > 0 [1]",
    "search_margin: inflation of the search boxes (length) [half the mean master edge length]",
    "max_flips: active-set changes of one node per step before its state is frozen [4]",
    NULL};

/* ---- helpers ------------------------------------------------------------------------------------------------------ */
static int owned(const sk_instance *inst, const slave_point *p) { return inst->slave->owned[p->k]; }

/* The element's positions q_A = [slave node | facet nodes] from the positions per view (x[0] slave, x[1] master). */
static void gather(const slave_point *p, int nen, const double *const *x, double *q_A) {
  for (int i = 0; i < 3; ++i) q_A[i] = x[0][3 * p->k + i];
  for (int I = 0; I < nen; ++I)
    for (int i = 0; i < 3; ++i) q_A[3 * (1 + I) + i] = x[1][3 * p->facet_nodes[I] + i];
}

/* Global unknown index of each element unknown (u order: q_A, lambda_n, f, lambda_aug). */
static void element_indices(const sk_instance *inst, const slave_point *p, int64_t extra_base, int64_t *idx) {
  const int nen = inst->facet.nen, nq = 3 + 3 * nen;
  for (int i = 0; i < 3; ++i) idx[i] = inst->slave->dofs[3 * p->k + i];
  for (int I = 0; I < nen; ++I)
    for (int i = 0; i < 3; ++i) idx[3 * (1 + I) + i] = inst->master->dofs[3 * p->facet_nodes[I] + i];
  for (int j = 0; j < N_EXTRA; ++j) idx[nq + j] = extra_base + j;
}

typedef struct {
  nts_element_input in;
  nts_element_system sys;
  double q_A[NTS_MAX_NQ], q_A_start[NTS_MAX_NQ];
  double extra_f[2], extra_lambda_aug[2]; /* the global unknowns (differ from in.f under `direct`) */
} element_eval;

/* Builds the element system of point k at the state's iterate; under `direct` eliminates f and lambda_aug by the
 * local Newton first. */
static sk_status evaluate(sk_instance *inst, int k, const sk_state *state, element_eval *e) {
  const slave_point *p = &inst->points[k];
  const int nen = inst->facet.nen;
  const double *x = state->extra + N_EXTRA * p->index;
  gather(p, nen, state->x, e->q_A);
  gather(p, nen, state->x_n, e->q_A_start);
  nts_element_input *in = &e->in;
  memset(in, 0, sizeof *in);
  in->alpha = inst->alpha;
  in->q_A = e->q_A;
  in->q_A_start = e->q_A_start;
  in->active = p->active;
  if (inst->friction.mu > 0.0 && !p->return_map)
    in->friction_mode = p->slip ? NTS_FRICTION_SLIP : NTS_FRICTION_STICK;
  in->lambda_n = x[0];
  in->f[0] = e->extra_f[0] = x[1];
  in->f[1] = e->extra_f[1] = x[2];
  in->lambda_aug[0] = e->extra_lambda_aug[0] = x[3];
  in->lambda_aug[1] = e->extra_lambda_aug[1] = x[4];
  for (int a = 0; a < 2; ++a) {
    in->f_start[a] = p->f_start[a];
    in->t_start[a] = p->t_start[a];
    in->f_frozen[a] = p->f_frozen[a];
  }
  if (inst->strategy == STRATEGY_DIRECT && p->active) {
    if (nts_direct_eliminate(&inst->facet, in, &inst->friction, LOCAL_NEWTON_TOL, LOCAL_NEWTON_MAX) != 0) {
      /* retry from the start of the step's closest point before giving up */
      in->f[0] = p->f_start[0];
      in->f[1] = p->f_start[1];
      if (nts_direct_eliminate(&inst->facet, in, &inst->friction, LOCAL_NEWTON_TOL, LOCAL_NEWTON_MAX) != 0)
        return inst->api->error(inst->host, SK_ERR_DIVERGED,
                                 "%s: nts-augmented (direct): closest-point Newton of slave node %lld on master face "
                                 "%d did not converge",
                                 inst->name, (long long)p->node, p->facet);
    }
  }
  nts_element_build(&inst->facet, in, &inst->friction, &e->sys);
  return SK_OK;
}

/* Residual rows of the eliminated unknowns as the global system sees them: under `direct` the global f and
 * lambda_aug are tied to the local solution (x_e - x_e,local = 0); otherwise the element's own rows. */
static void extra_rows(const sk_instance *inst, const slave_point *p, const element_eval *e, double R_e[4]) {
  const int nq = e->sys.nq;
  if (inst->strategy == STRATEGY_DIRECT && p->active) {
    for (int a = 0; a < 2; ++a) {
      R_e[a] = e->extra_f[a] - e->in.f[a];
      R_e[2 + a] = e->extra_lambda_aug[a] - e->in.lambda_aug[a];
    }
  } else {
    for (int a = 0; a < 4; ++a) R_e[a] = e->sys.R[nq + 1 + a];
  }
}

static double gap_on_facet(sk_instance *inst, const slave_point *p, const double *const *x, double f_guess[2]) {
  double q_A[NTS_MAX_NQ];
  gather(p, inst->facet.nen, x, q_A);
  if (nts_closest_point(&inst->facet, q_A, f_guess, LOCAL_NEWTON_TOL, LOCAL_NEWTON_MAX) < 0) return HUGE_VAL;
  nts_geometry geo;
  nts_geometry_eval(&inst->facet, q_A, f_guess, &geo);
  return geo.phi[NTS_PHI_N];
}

/* ---- create / destroy --------------------------------------------------------------------------------------------- */
static void destroy(sk_instance *inst) {
  if (!inst) return;
  if (inst->search) inst->api->contact->search_destroy(inst->search);
  free(inst->points);
  free(inst->initial);
  free(inst->eliminated);
  free(inst->candidates);
  free(inst);
}

static double mean_master_edge(const sk_view *master) {
  double sum = 0.0;
  int count = 0;
  const int corners = master->cell_type == SK_TRI3 ? 3 : 4;
  const double *X = master->X;
  for (int f = 0; f < master->n_cells; ++f)
    for (int e = 0; e < corners; ++e) {
      const int a = master->conn[f * master->nen + e], b = master->conn[f * master->nen + (e + 1) % corners];
      double d2 = 0.0;
      for (int i = 0; i < 3; ++i) d2 += (X[3 * a + i] - X[3 * b + i]) * (X[3 * a + i] - X[3 * b + i]);
      sum += sqrt(d2);
      ++count;
    }
  return count ? sum / count : 1.0;
}

static sk_status create(const sk_host_api *api, sk_host *host, const sk_attach *attach, sk_instance **out) {
  *out = NULL;
  const sk_view *slave = attach->slave, *master = attach->master;
  if (slave->dim != 3)
    return api->error(host, SK_ERR_INPUT, "%s: nts-augmented is a 3D formulation (the scene is %dD)", attach->name,
                      slave->dim);
  if (!master)
    return api->error(host, SK_ERR_INPUT,
                      "%s: nts-augmented needs a deformable master surface (rigid obstacles are not supported)",
                      attach->name);
  sk_instance *inst = calloc(1, sizeof *inst);
  if (!inst) return api->error(host, SK_ERR_NOMEM, "%s: out of memory", attach->name);
  inst->api = api;
  inst->host = host;
  inst->slave = slave;
  inst->master = master;
  inst->name = attach->name;
  if (nts_facet_init(&inst->facet, master->cell_type, api->contact->shape, api->contact->shape_hessian) != 0) {
    destroy(inst);
    return api->error(host, SK_ERR_INPUT,
                      "%s: nts-augmented handles tri3 and quad4 master faces only (master surface '%s')",
                      attach->name, master->name);
  }
  inst->strategy = attach->strategy;
  sk_status st = api->param_double(host, "mu", 0, 0.0, &inst->friction.mu);
  if (st == SK_OK)
    st = api->param_double(host, "epsilon_t", inst->friction.mu > 0.0, 0.0, &inst->friction.epsilon_t);
  if (st == SK_OK) st = api->param_double(host, "c_n", 0, 1.0, &inst->c_n);
  if (st == SK_OK)
    st = api->param_double(host, "search_margin", 0, 0.5 * mean_master_edge(master), &inst->search_margin);
  if (st == SK_OK) st = api->param_int(host, "max_flips", 0, 4, &inst->max_flips);
  if (st != SK_OK) {
    destroy(inst);
    return st;
  }
  if (inst->friction.mu < 0.0 || (inst->friction.mu > 0.0 && inst->friction.epsilon_t <= 0.0) || inst->c_n <= 0.0 ||
      inst->search_margin < 0.0) {
    /* the message reads the instance: record it before freeing */
    st = api->error(host, SK_ERR_INPUT,
                    "%s: nts-augmented needs mu >= 0, epsilon_t > 0 when mu > 0, c_n > 0 and search_margin >= 0 "
                    "(got mu %g, epsilon_t %g, c_n %g, search_margin %g)",
                    attach->name, inst->friction.mu, inst->friction.epsilon_t, inst->c_n, inst->search_margin);
    destroy(inst);
    return st;
  }
  inst->n_points = slave->n_nodes;
  inst->n_extra = N_EXTRA * slave->n_nodes_global;
  inst->points = calloc((size_t)(slave->n_nodes > 0 ? slave->n_nodes : 1), sizeof *inst->points);
  inst->initial = calloc((size_t)inst->n_extra + 1, sizeof *inst->initial);
  inst->eliminated = calloc((size_t)inst->n_extra + 1, 1);
  inst->candidates = malloc(sizeof(int) * (size_t)(master->n_cells > 0 ? master->n_cells : 1));
  if (!inst->points || !inst->initial || !inst->eliminated || !inst->candidates) {
    destroy(inst);
    return api->error(host, SK_ERR_NOMEM, "%s: out of memory", attach->name);
  }
  for (int k = 0; k < slave->n_nodes; ++k) {
    slave_point *p = &inst->points[k];
    p->k = k;
    p->node = slave->node_id[k];
    p->index = slave->node_index[k];
    p->c_facet = p->facet = -1;
  }
  /* the layout is the same on every rank: every node of the whole surface */
  if (inst->strategy != STRATEGY_NONE)
    for (int64_t i = 0; i < inst->n_extra; ++i) inst->eliminated[i] = i % N_EXTRA != 0;
  st = api->contact->search_create(master, &inst->search);
  if (st != SK_OK) {
    destroy(inst);
    return st;
  }
  *out = inst;
  return SK_OK;
}

/* ---- step ---------------------------------------------------------------------------------------------------------- */
static sk_status begin_step(sk_instance *inst, const sk_state *state) {
  const sk_contact_services *cs = inst->api->contact;
  const sk_view *master = inst->master;
  inst->alpha = state->alpha;
  cs->search_update(inst->search, state->x_n[1], state->x[1], inst->search_margin);
  for (int k = 0; k < inst->n_points; ++k) {
    slave_point *p = &inst->points[k];
    double *init = inst->initial + N_EXTRA * p->index;
    const double *x_n = state->x_n[0] + 3 * k, *x_p = state->x[0] + 3 * k;
    double lo[3], hi[3];
    for (int i = 0; i < 3; ++i) {
      lo[i] = fmin(x_n[i], x_p[i]) - inst->search_margin;
      hi[i] = fmax(x_n[i], x_p[i]) + inst->search_margin;
    }
    const int n_cand = cs->search_query(inst->search, lo, hi, inst->candidates, master->n_cells);
    sk_projection proj = {.struct_size = sizeof proj, .face = -1};
    if (n_cand > 0) {
      sk_status st = cs->project(master, state->x[1], x_p, inst->candidates,
                                 n_cand < master->n_cells ? n_cand : master->n_cells, &proj);
      if (st != SK_OK) return st;
    }
    p->flips = 0;
    p->slip = 0;
    p->return_map = 0;
    memset(init, 0, sizeof(double) * N_EXTRA);
    if (proj.face < 0 || proj.kind == SK_PROJ_OUTSIDE) {
      /* nothing reachable this step (or beyond the master's border): trivial equations */
      p->facet = -1;
      p->active = 0;
      p->f_frozen[0] = p->f_frozen[1] = 0.0;
      p->f_start[0] = p->f_start[1] = p->t_start[0] = p->t_start[1] = 0.0;
      p->gap_estimate = inst->search_margin;
      continue;
    }
    p->facet = proj.face;
    for (int I = 0; I < inst->facet.nen; ++I) p->facet_nodes[I] = master->conn[proj.face * master->nen + I];
    p->gap_estimate = proj.gap;
    if (p->c_active && p->c_facet >= 0 && p->c_facet != p->facet) {
      /* A contact about to move onto another facet. The step enforces Phi_n = 0 at its end on the new facet, so
       * its normal force does the work -lambda_n (0 - g_n), g_n = the gap of q_n on the new facet. Across a convex
       * kink the slave, still on its old facet at t_n, lies below the new facet's plane (g_n < 0): the switch
       * would put lambda_n g_n > 0 into the bodies (up to 1e-4 of the energy per switch on the coarse tori). Such a
       * contact stays on its old facet (extended beyond its edge) for this step; once it has passed the edge, g_n
       * on the new facet is >= 0 and the switch only loses energy. */
      double f_n[2] = {proj.xi[0], proj.xi[1]};
      const double g_n = gap_on_facet(inst, p, state->x_n, f_n);
      if (g_n < 0.0) {
        double f[2] = {p->c_f[0], p->c_f[1]};
        p->facet = p->c_facet;
        for (int I = 0; I < inst->facet.nen; ++I) p->facet_nodes[I] = master->conn[p->facet * master->nen + I];
        const double g = gap_on_facet(inst, p, state->x, f);
        if (g != HUGE_VAL) {
          proj.gap = p->gap_estimate = g;
        }
      }
    }
    double f_init[2] = {proj.xi[0], proj.xi[1]}, lambda_n = 0.0, lambda_aug[2] = {0.0, 0.0};
    if (p->c_active && p->c_facet == p->facet) {
      /* persisting contact on the same facet: keep f and the history as committed */
      for (int a = 0; a < 2; ++a) {
        p->f_start[a] = f_init[a] = p->c_f[a];
        p->t_start[a] = p->c_t[a];
        lambda_aug[a] = p->c_extra[3 + a];
      }
      lambda_n = p->c_extra[0];
      p->slip = p->c_slip;
    } else {
      /* new contact or a new facet: f from the closest point of q_n on this facet; a committed traction is carried
       * over as a spatial vector (t_a = t . a_a on the new facet) */
      double f_n[2] = {proj.xi[0], proj.xi[1]};
      if (gap_on_facet(inst, p, state->x_n, f_n) == HUGE_VAL) {
        f_n[0] = proj.xi[0];
        f_n[1] = proj.xi[1];
      }
      p->f_start[0] = f_n[0];
      p->f_start[1] = f_n[1];
      p->t_start[0] = p->t_start[1] = 0.0;
      if (p->c_active) {
        double q_A[NTS_MAX_NQ];
        nts_geometry geo;
        gather(p, inst->facet.nen, state->x_n, q_A);
        nts_geometry_eval(&inst->facet, q_A, f_n, &geo);
        for (int a = 0; a < 2; ++a)
          p->t_start[a] = geo.a[a][0] * p->c_t_vector[0] + geo.a[a][1] * p->c_t_vector[1] +
                          geo.a[a][2] * p->c_t_vector[2];
        lambda_n = p->c_extra[0];
      }
    }
    p->f_frozen[0] = f_init[0];
    p->f_frozen[1] = f_init[1];
    /* primal-dual active set at the predictor: active if -lambda_n - c_n g > 0 */
    p->active = -lambda_n - inst->c_n * proj.gap > 0.0;
    if (p->active) {
      init[0] = lambda_n;
      init[3] = lambda_aug[0];
      init[4] = lambda_aug[1];
    }
    init[1] = f_init[0];
    init[2] = f_init[1];
  }
  /* the starting values of the owned points only: the host sums them over ranks */
  for (int k = 0; k < inst->n_points; ++k)
    if (!owned(inst, &inst->points[k])) memset(inst->initial + N_EXTRA * inst->points[k].index, 0, sizeof(double) * N_EXTRA);
  return SK_OK;
}

static sk_status layout(sk_instance *inst, const sk_state *state, sk_layout *out) {
  (void)state;
  out->n_extra = inst->n_extra;
  out->initial = inst->initial;
  out->eliminated = inst->strategy == STRATEGY_NONE ? NULL : inst->eliminated;
  return SK_OK;
}

/* Each owned point's slave node and extras with its facet's nodes (the facet is fixed for the step). */
static sk_status pattern(sk_instance *inst, const sk_state *state, sk_pattern *out) {
  for (int k = 0; k < inst->n_points; ++k) {
    const slave_point *p = &inst->points[k];
    if (!owned(inst, p)) continue;
    int64_t idx[NTS_MAX_NU];
    const int64_t base = state->extra_offset + N_EXTRA * p->index;
    if (p->facet < 0) {
      for (int j = 0; j < N_EXTRA; ++j) idx[j] = base + j;
      out->add_block(out, N_EXTRA, idx, N_EXTRA, idx);
      continue;
    }
    element_indices(inst, p, base, idx);
    const int nu = 3 + 3 * inst->facet.nen + N_EXTRA;
    out->add_block(out, nu, idx, nu, idx);
  }
  return SK_OK;
}

static sk_status residual(sk_instance *inst, const sk_state *state, sk_sink *sink) {
  for (int k = 0; k < inst->n_points; ++k) {
    const slave_point *p = &inst->points[k];
    if (!owned(inst, p)) continue;
    const int64_t base = state->extra_offset + N_EXTRA * p->index;
    if (p->facet < 0) {
      const double *x = state->extra + N_EXTRA * p->index;
      const int64_t rows[N_EXTRA] = {base, base + 1, base + 2, base + 3, base + 4};
      const double R[N_EXTRA] = {x[0], x[1] - p->f_frozen[0], x[2] - p->f_frozen[1], x[3], x[4]};
      sink->add_vector(sink, N_EXTRA, rows, R);
      continue;
    }
    element_eval e;
    SK_TRY(evaluate(inst, k, state, &e));
    int64_t idx[NTS_MAX_NU];
    element_indices(inst, p, base, idx);
    const int nq = e.sys.nq;
    double R[NTS_MAX_NU];
    memcpy(R, e.sys.R, sizeof(double) * (size_t)(nq + 1));
    extra_rows(inst, p, &e, R + nq + 1);
    sink->add_vector(sink, e.sys.nu, idx, R);
  }
  return SK_OK;
}

static sk_status jacobian(sk_instance *inst, const sk_state *state, sk_sink *sink) {
  for (int k = 0; k < inst->n_points; ++k) {
    const slave_point *p = &inst->points[k];
    if (!owned(inst, p)) continue;
    const int64_t base = state->extra_offset + N_EXTRA * p->index;
    if (p->facet < 0) {
      const double one = 1.0;
      const int n = inst->strategy == STRATEGY_NONE ? N_EXTRA : 1;
      for (int j = 0; j < n; ++j) {
        const int64_t row = base + j;
        sink->add_matrix(sink, 1, &row, 1, &row, &one);
      }
      continue;
    }
    element_eval e;
    SK_TRY(evaluate(inst, k, state, &e));
    int64_t idx[NTS_MAX_NU];
    element_indices(inst, p, base, idx);
    if (inst->strategy == STRATEGY_NONE) {
      sink->add_matrix(sink, e.sys.nu, idx, e.sys.nu, idx, e.sys.J);
      continue;
    }
    const int nk = e.sys.nq + 1;
    double Jc[(NTS_MAX_NQ + 1) * (NTS_MAX_NQ + 1)], rhs[NTS_MAX_NQ + 1];
    if (nts_condense(&e.sys, Jc, rhs) != 0)
      return inst->api->error(inst->host, SK_ERR_DIVERGED,
                              "%s: nts-augmented: singular augmented block (degenerate master face %d at slave node "
                              "%lld)",
                              inst->name, p->facet, (long long)p->node);
    /* idx[0..nk) are the kept unknowns q_A, lambda_n; under `direct` R_e = 0 so rhs vanishes */
    sink->add_matrix(sink, nk, idx, nk, idx, Jc);
    sink->add_rhs(sink, nk, idx, rhs);
  }
  return SK_OK;
}

static sk_status recover(sk_instance *inst, const sk_state *state, sk_vectors *v) {
  if (inst->strategy == STRATEGY_NONE) return SK_OK;
  for (int k = 0; k < inst->n_points; ++k) {
    const slave_point *p = &inst->points[k];
    if (!owned(inst, p)) continue;
    const int64_t base = N_EXTRA * p->index; /* into the instance's extras */
    const double *F = v->F_extra + base;
    double *dx = v->dx_extra + base;
    if (p->facet < 0) {
      for (int j = 1; j < N_EXTRA; ++j) dx[j] = -F[j];
      continue;
    }
    element_eval e;
    SK_TRY(evaluate(inst, k, state, &e));
    const int nen = inst->facet.nen, nk = e.sys.nq + 1;
    /* the kept unknowns of the element: slave node, facet nodes, lambda_n */
    double dk[NTS_MAX_NQ + 1], de[4];
    for (int i = 0; i < 3; ++i) dk[i] = v->dx_view[0][3 * p->k + i];
    for (int I = 0; I < nen; ++I)
      for (int i = 0; i < 3; ++i) dk[3 * (1 + I) + i] = v->dx_view[1][3 * p->facet_nodes[I] + i];
    dk[nk - 1] = dx[0];
    const int direct = inst->strategy == STRATEGY_DIRECT && p->active;
    /* the element rows' residual as the host has it; under `direct` the local solution's linearisation plus
     * the global unknowns' offset from it */
    for (int a = 0; a < 4; ++a) e.sys.R[nk + a] = direct ? 0.0 : F[1 + a];
    if (nts_recover(&e.sys, dk, de) != 0)
      return inst->api->error(inst->host, SK_ERR_DIVERGED, "%s: nts-augmented: singular augmented block at slave "
                              "node %lld", inst->name, (long long)p->node);
    for (int a = 0; a < 4; ++a) dx[1 + a] = de[a] - (direct ? F[1 + a] : 0.0);
  }
  return SK_OK;
}

static sk_status update_active_set(sk_instance *inst, const sk_state *state, int *changed) {
  *changed = 0;
  for (int k = 0; k < inst->n_points; ++k) {
    slave_point *p = &inst->points[k];
    if (p->facet < 0) continue;
    const double *x = state->extra + N_EXTRA * p->index;
    double f[2] = {x[1], x[2]}, gap;
    int want_slip = p->slip;
    if (p->active) {
      element_eval e;
      SK_TRY(evaluate(inst, k, state, &e));
      gap = e.sys.geo_end.phi[NTS_PHI_N];
      /* the stick/slip set follows the return map's trial at this iterate */
      if (inst->friction.mu > 0.0) want_slip = e.sys.friction.trial_norm > e.sys.friction.cone;
    } else {
      f[0] = p->f_frozen[0];
      f[1] = p->f_frozen[1];
      gap = gap_on_facet(inst, p, state->x, f);
    }
    const double lambda_n = p->active ? x[0] : 0.0;
    const int want_active = -lambda_n - inst->c_n * gap > 0.0;
    if (want_active == p->active && want_slip == p->slip) continue;
    /* chattering: after max_flips the contact state is kept for the rest of the step and the stick/slip branch
     * is left to the return map (so Coulomb's law still holds exactly at convergence) */
    if (p->flips >= inst->max_flips) continue;
    if (++p->flips == inst->max_flips) {
      p->return_map = 1;
      inst->api->log(inst->host, 2, "%s: nts-augmented: slave node %lld changed its contact state %d times; frozen "
                     "for this step", inst->name, (long long)p->node, p->flips);
    }
    if (want_active != p->active) {
      p->active = want_active;
      p->slip = 0; /* a new contact starts sticking */
      if (!p->active) {
        /* keep f where it is: its trivial equation f = f_frozen is then already satisfied */
        p->f_frozen[0] = x[1];
        p->f_frozen[1] = x[2];
      }
    } else {
      p->slip = want_slip;
    }
    *changed = 1;
  }
  return SK_OK;
}

static sk_status commit_step(sk_instance *inst, const sk_state *state) {
  for (int k = 0; k < inst->n_points; ++k) {
    slave_point *p = &inst->points[k];
    const double *x = state->extra + N_EXTRA * p->index;
    p->c_facet = p->facet;
    p->c_active = p->facet >= 0 && p->active;
    p->c_slip = p->c_active && p->slip;
    memcpy(p->c_extra, x, sizeof p->c_extra);
    memset(p->c_t, 0, sizeof p->c_t);
    memset(p->c_t_vector, 0, sizeof p->c_t_vector);
    if (!p->c_active) {
      p->c_f[0] = p->f_frozen[0];
      p->c_f[1] = p->f_frozen[1];
      continue;
    }
    element_eval e;
    SK_TRY(evaluate(inst, k, state, &e));
    if (e.in.lambda_n > 0.0)
      inst->api->log(inst->host, 2, "%s: nts-augmented: slave node %lld ends the step active with a tensile "
                     "multiplier %g (its contact state was frozen)", inst->name, (long long)p->node, e.in.lambda_n);
    p->c_slip = e.sys.friction.slip;
    for (int a = 0; a < 2; ++a) {
      p->c_f[a] = e.in.f[a];
      p->c_t[a] = e.sys.friction.t_next[a];
      p->c_extra[1 + a] = e.in.f[a];
      p->c_extra[3 + a] = e.in.lambda_aug[a];
    }
    /* spatial traction t = t_a a^a at t_{n+1} */
    const nts_geometry *g = &e.sys.geo_end;
    const double det = g->m[0][0] * g->m[1][1] - g->m[0][1] * g->m[1][0];
    const double tau[2] = {(g->m[1][1] * p->c_t[0] - g->m[0][1] * p->c_t[1]) / det,
                           (-g->m[1][0] * p->c_t[0] + g->m[0][0] * p->c_t[1]) / det};
    for (int i = 0; i < 3; ++i) p->c_t_vector[i] = tau[0] * g->a[0][i] + tau[1] * g->a[1][i];
  }
  return SK_OK;
}

static void reject_step(sk_instance *inst) {
  /* begin_step rebuilds everything of the step from the committed data; only forget this attempt's state */
  for (int k = 0; k < inst->n_points; ++k) {
    inst->points[k].active = 0;
    inst->points[k].slip = 0;
    inst->points[k].return_map = 0;
    inst->points[k].flips = 0;
  }
}

/* Tangential penalty energy psi = t . m^{-1} t / (2 eps). */
static double friction_energy(const double m[2][2], const double t[2], double eps) {
  const double det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
  const double tau0 = (m[1][1] * t[0] - m[0][1] * t[1]) / det, tau1 = (-m[1][0] * t[0] + m[0][0] * t[1]) / det;
  return 0.5 * (tau0 * t[0] + tau1 * t[1]) / eps;
}

static sk_status report(sk_instance *inst, const sk_state *state, sk_contact_report *rep) {
  for (int k = 0; k < inst->n_points; ++k) {
    const slave_point *p = &inst->points[k];
    if (p->facet < 0 || !p->active || !owned(inst, p)) continue;
    element_eval e;
    SK_TRY(evaluate(inst, k, state, &e));
    const nts_geometry *gh = &e.sys.geo_hat, *ge = &e.sys.geo_end;
    const double lambda[3] = {e.in.lambda_aug[0], e.in.lambda_aug[1], e.in.lambda_n};
    double force[3];
    for (int i = 0; i < 3; ++i) {
      force[i] = 0.0;
      for (int c = 0; c < 3; ++c) force[i] -= lambda[c] * gh->grad[c][i]; /* force on the slave node */
      rep->force[i] += force[i];
    }
    const double *x = e.q_A;
    rep->moment[0] += x[1] * force[2] - x[2] * force[1];
    rep->moment[1] += x[2] * force[0] - x[0] * force[2];
    rep->moment[2] += x[0] * force[1] - x[1] * force[0];
    ++rep->active;
    if (e.sys.friction.slip)
      ++rep->slip;
    else
      ++rep->stick;
    if (inst->friction.mu > 0.0) {
      /* work of the tangential traction minus the change of the penalty energy */
      const nts_friction *fr = &e.sys.friction;
      const double work =
          fr->t_used[0] * (e.in.f[0] - p->f_start[0]) + fr->t_used[1] * (e.in.f[1] - p->f_start[1]);
      rep->dissipated += work - (friction_energy(gh->m, fr->t_next, inst->friction.epsilon_t) -
                                 friction_energy(gh->m, p->t_start, inst->friction.epsilon_t));
    }
    for (int c = 0; c < 3; ++c) rep->constraint_norm = fmax(rep->constraint_norm, fabs(ge->phi[c]));
  }
  return SK_OK;
}

static sk_status points(sk_instance *inst, const sk_state *state, sk_point_callback callback, void *ctx) {
  for (int k = 0; k < inst->n_points; ++k) {
    const slave_point *p = &inst->points[k];
    if (!owned(inst, p)) continue;
    sk_contact_point cp = {.struct_size = sizeof cp};
    cp.slave_node = p->node;
    for (int i = 0; i < 3; ++i) cp.x[i] = state->x[0][3 * p->k + i];
    cp.gap = p->gap_estimate;
    if (p->facet >= 0) {
      element_eval e;
      SK_TRY(evaluate(inst, k, state, &e));
      const nts_geometry *gh = &e.sys.geo_hat, *ge = &e.sys.geo_end;
      for (int i = 0; i < 3; ++i) cp.normal[i] = ge->n[i];
      if (p->active) {
        cp.gap = ge->phi[NTS_PHI_N];
        cp.pressure = -e.in.lambda_n;
        for (int i = 0; i < 3; ++i)
          cp.traction[i] = -(e.in.lambda_aug[0] * gh->grad[0][i] + e.in.lambda_aug[1] * gh->grad[1][i]);
        cp.state = e.sys.friction.slip ? 2 : 1;
      } else {
        double f[2] = {p->f_frozen[0], p->f_frozen[1]};
        const double g = gap_on_facet(inst, p, state->x, f);
        if (g != HUGE_VAL) cp.gap = g;
      }
    }
    callback(ctx, &cp);
  }
  return SK_OK;
}

static const sk_plugin plugin = {
    SK_TABLE_HEADER(sk_plugin),
    .name = "nts-augmented",
    .summary = "node-to-surface contact with coordinate augmentation and size reduction (Franke, Hesch, Betsch 2013)",
    .kinds = SK_KIND_PAIR,
    .caps = SK_CAP_3D | SK_CAP_FRICTION | SK_CAP_QUASISTATIC | SK_CAP_DYNAMICS | SK_CAP_ENERGY_MOMENTUM |
            SK_CAP_DEFORMABLE_MASTER | SK_CAP_MULTIPLIERS | SK_CAP_CONDENSATION,
    .strategies = strategies,
    .parameters = parameters,
    .create = create,
    .destroy = destroy,
    .begin_step = begin_step,
    .layout = layout,
    .pattern = pattern,
    .update_active_set = update_active_set,
    .residual = residual,
    .jacobian = jacobian,
    .recover = recover,
    .commit_step = commit_step,
    .reject_step = reject_step,
    .report = report,
    .points = points,
};

__attribute__((visibility("default"))) const sk_plugin *stickslip_plugin_entry(void);
__attribute__((visibility("default"))) const sk_plugin *stickslip_plugin_entry(void) { return &plugin; }
