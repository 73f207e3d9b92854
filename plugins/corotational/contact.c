/* corotational — contact against rigid planes: the world gap at t_n and the frozen co-rotated frame (3.5), the row
 * transformation that condenses the dual multipliers (5.1), and the NCP update of the primal–dual active set
 * (Sec. 5.1; Hüeber–Stadler–Wohlmuth). docs/plugins/corotational.md §3. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "kernel.h"

int corot_contact_init(corot_contact *contact, int dim, int n, const int *node, const double *weight,
                       int n_planes, const corot_plane *planes, double c_n, double c_t) {
  memset(contact, 0, sizeof *contact);
  if (n < 0 || n_planes < 0 || n_planes > COROT_MAX_PLANES || !(c_n > 0.0) || !(c_t > 0.0)) return -1;
  contact->n = n;
  contact->n_planes = n_planes;
  contact->c_n = c_n;
  contact->c_t = c_t;
  /* A 3D slip direction is a fixed point of the iteration; it counts as settled once it moves less than this
   * (its effect on the step is then below the rotation tolerance's). */
  contact->direction_tol = 1e-10;
  const size_t m = (size_t)(n > 0 ? n : 1);
  contact->node = calloc(m, sizeof(int));
  contact->weight = calloc(m, sizeof(double));
  contact->planes = calloc((size_t)(n_planes > 0 ? n_planes : 1), sizeof(corot_plane));
  contact->mask = calloc(m, sizeof(uint32_t));
  contact->plane = calloc(m, sizeof(int));
  contact->gap = calloc(m, sizeof(double));
  contact->candidate = calloc(m, 1);
  contact->frame = calloc(9 * m, sizeof(double));
  contact->kappa = calloc(m, sizeof(double));
  contact->set = calloc(m, 1);
  contact->set_next = calloc(m, 1);
  contact->set_committed = calloc(m, 1);
  contact->dir = calloc(2 * m, sizeof(double));
  contact->dir_next = calloc(2 * m, sizeof(double));
  contact->dir_committed = calloc(2 * m, sizeof(double));
  contact->lambda = calloc(3 * m, sizeof(double));
  if (!contact->node || !contact->weight || !contact->planes || !contact->mask || !contact->plane || !contact->gap ||
      !contact->candidate || !contact->frame || !contact->kappa || !contact->set || !contact->set_next ||
      !contact->set_committed || !contact->dir || !contact->dir_next || !contact->dir_committed ||
      !contact->lambda) {
    corot_contact_free(contact);
    return -1;
  }
  for (int p = 0; p < n; ++p) {
    if (!(weight[p] > 0.0)) {
      corot_contact_free(contact);
      return -1;
    }
    contact->node[p] = node[p];
    contact->weight[p] = weight[p];
    contact->mask[p] = ~0u;
  }
  for (int k = 0; k < n_planes; ++k) {
    corot_plane plane = planes[k];
    if (dim == 2) plane.normal[2] = plane.point[2] = 0.0;
    const double norm = sqrt(corot_dot(3, plane.normal, plane.normal));
    if (!(norm > 0.0) || !(plane.mu >= 0.0)) {
      corot_contact_free(contact);
      return -1;
    }
    for (int i = 0; i < 3; ++i) plane.normal[i] /= norm;
    contact->planes[k] = plane;
  }
  return 0;
}

double corot_contact_mu(const corot_contact *contact, int p) {
  return contact->n_planes > 0 ? contact->planes[contact->plane[p]].mu : 0.0;
}

void corot_contact_free(corot_contact *contact) {
  void *arrays[] = {contact->node,      contact->weight,   contact->planes,        contact->plane,      contact->mask,
                    contact->gap,       contact->candidate, contact->frame,        contact->kappa,
                    contact->set,       contact->set_next, contact->set_committed, contact->dir,
                    contact->dir_next,  contact->dir_committed, contact->lambda};
  for (size_t k = 0; k < sizeof arrays / sizeof arrays[0]; ++k) free(arrays[k]);
  memset(contact, 0, sizeof *contact);
}

/* Orthonormal frame rows nu, tau_1 (, tau_2): 2D tau = Pi nu; 3D tau_1 from the coordinate axis least aligned with
 * nu, tau_2 = nu x tau_1. */
static void complete_frame(int dim, const double e[3], double *F) {
  const double *nu = F;
  if (dim == 2) {
    corot_pi(2, e, nu, F + 3);
    return;
  }
  int j = 0;
  for (int i = 1; i < 3; ++i)
    if (fabs(nu[i]) < fabs(nu[j])) j = i;
  double *t1 = F + 3, *t2 = F + 6;
  for (int i = 0; i < 3; ++i) t1[i] = (i == j) - nu[j] * nu[i];
  const double norm = sqrt(corot_dot(3, t1, t1));
  for (int i = 0; i < 3; ++i) t1[i] /= norm;
  t2[0] = nu[1] * t1[2] - nu[2] * t1[1];
  t2[1] = nu[2] * t1[0] - nu[0] * t1[2];
  t2[2] = nu[0] * t1[1] - nu[1] * t1[0];
}

void corot_contact_begin_step(corot_contact *contact, const corot_body *body, const corot_state *state_n,
                              double theta_star) {
  const int dim = body->dim;
  double Rn[9], Rs[9];
  corot_rotation(dim, body->e, state_n->theta, Rn);
  corot_rotation(dim, body->e, theta_star, Rs);
  for (int p = 0; p < contact->n; ++p) {
    const int a = contact->node[p];
    double r[3] = {0, 0, 0}, phi[3] = {0, 0, 0};
    for (int i = 0; i < dim; ++i) r[i] = body->x[a * dim + i] + state_n->u[a * dim + i];
    corot_mul(dim, Rn, r, phi);
    for (int i = 0; i < dim; ++i) phi[i] += body->centre[i];
    int best = 0;
    double best_gap = INFINITY;
    for (int k = 0; k < contact->n_planes; ++k) {
      if (!(contact->mask[p] >> k & 1u)) continue;
      double d[3];
      for (int i = 0; i < 3; ++i) d[i] = phi[i] - contact->planes[k].point[i];
      const double gap = corot_dot(dim, d, contact->planes[k].normal);
      if (gap < best_gap) best_gap = gap, best = k;
    }
    contact->plane[p] = best;
    contact->gap[p] = best_gap;
    contact->candidate[p] = best_gap <= 0.0; /* INFINITY when the node may touch no plane */
    double *F = contact->frame + 9 * p, mn[3];
    memset(F, 0, 9 * sizeof *F);
    for (int i = 0; i < dim; ++i) mn[i] = contact->n_planes > 0 ? -contact->planes[best].normal[i] : (i == 1);
    corot_mul_t(dim, Rs, mn, F); /* nu = -R_{theta*}^T n: the body's side of the back-rotated plane */
    complete_frame(dim, body->e, F);
    contact->set[p] = contact->candidate[p] ? contact->set_committed[p] : COROT_INACTIVE;
    contact->dir[2 * p] = contact->dir_committed[2 * p];
    contact->dir[2 * p + 1] = contact->dir_committed[2 * p + 1];
  }
}

void corot_contact_rows(const corot_contact *contact, int dim, int p, double lin[3][3], int kinematic[3]) {
  memset(lin, 0, 9 * sizeof(double));
  const double *F = contact->frame + 9 * p;
  for (int i = 0; i < 3; ++i) kinematic[i] = 0;
  switch (contact->set[p]) {
    case COROT_INACTIVE:
      for (int i = 0; i < dim; ++i) lin[i][i] = 1.0;
      break;
    case COROT_STICK:
      for (int i = 0; i < dim; ++i) kinematic[i] = 1;
      break;
    case COROT_SLIP:
      /* nu . s = 0; (tau_k - mu d_k nu) . R_p = 0 (lambda_tau = mu lambda_nu d, lambda = -R_p / D_pp) */
      kinematic[0] = 1;
      for (int k = 1; k < dim; ++k)
        for (int l = 0; l < dim; ++l) lin[k][l] = F[3 * k + l] - corot_contact_mu(contact, p) * contact->dir[2 * p + k - 1] * F[l];
      break;
  }
}

int corot_contact_update(corot_contact *contact, int dim, const double *R, const double *s) {
  for (int p = 0; p < contact->n; ++p)
    for (int i = 0; i < dim; ++i) contact->lambda[3 * p + i] = -R[contact->node[p] * dim + i] / contact->weight[p];
  return corot_contact_propose(contact, dim, s);
}

int corot_contact_propose(corot_contact *contact, int dim, const double *s) {
  int changes = 0;
  for (int p = 0; p < contact->n; ++p) {
    const int a = contact->node[p];
    const double *lambda = contact->lambda + 3 * p;
    unsigned char next = COROT_INACTIVE;
    double dir[2] = {contact->dir[2 * p], contact->dir[2 * p + 1]};
    if (contact->candidate[p]) {
      const double *F = contact->frame + 9 * p, *sp = s + a * dim;
      const double scale = contact->kappa[p] / contact->weight[p];
      const double Lambda_n = corot_dot(dim, F, lambda) + contact->c_n * scale * corot_dot(dim, F, sp);
      if (Lambda_n > 0.0) {
        next = COROT_SLIP;
        const double mu = corot_contact_mu(contact, p);
        if (mu > 0.0) {
          double Lt[2] = {0, 0}, norm = 0.0;
          for (int k = 1; k < dim; ++k) {
            Lt[k - 1] = corot_dot(dim, F + 3 * k, lambda) + contact->c_t * scale * corot_dot(dim, F + 3 * k, sp);
            norm += Lt[k - 1] * Lt[k - 1];
          }
          norm = sqrt(norm);
          if (norm < mu * Lambda_n) {
            next = COROT_STICK;
          } else {
            double d[2] = {Lt[0] / norm, dim == 3 ? Lt[1] / norm : 0.0};
            /* A slip that reverses its direction passes through stick: proposing the opposite slip straight away
             * made the iteration cycle (two rim nodes of the ball between two planes flipped +1/-1 every iteration
             * while w swung between -1 and 7: test_corot_step, test_two_planes). */
            if (contact->set[p] == COROT_SLIP && d[0] * dir[0] + d[1] * dir[1] < 0.0) {
              next = COROT_STICK;
            } else {
              dir[0] = d[0];
              dir[1] = d[1];
            }
          }
        }
      }
    }
    int changed = next != contact->set[p];
    if (!changed && next == COROT_SLIP && corot_contact_mu(contact, p) > 0.0) {
      const double d0 = dir[0] - contact->dir[2 * p], d1 = dir[1] - contact->dir[2 * p + 1];
      changed = sqrt(d0 * d0 + d1 * d1) > contact->direction_tol;
    }
    changes += changed;
    contact->set_next[p] = next;
    contact->dir_next[2 * p] = dir[0];
    contact->dir_next[2 * p + 1] = dir[1];
  }
  return changes;
}

void corot_contact_apply(corot_contact *contact) {
  memcpy(contact->set, contact->set_next, (size_t)contact->n);
  memcpy(contact->dir, contact->dir_next, sizeof(double) * 2 * (size_t)contact->n);
}

void corot_contact_check(const corot_contact *contact, int dim, const double *s, corot_complementarity *out) {
  memset(out, 0, sizeof *out);
  for (int p = 0; p < contact->n; ++p) {
    if (!contact->candidate[p]) continue;
    const double *F = contact->frame + 9 * p, *lambda = contact->lambda + 3 * p, *sp = s + contact->node[p] * dim;
    const double ln = corot_dot(dim, F, lambda), sn = corot_dot(dim, F, sp);
    double lt2 = 0.0;
    for (int k = 1; k < dim; ++k) {
      const double lt = corot_dot(dim, F + 3 * k, lambda);
      lt2 += lt * lt;
    }
    out->product = fmax(out->product, fabs(ln * sn));
    out->negative_pressure = fmax(out->negative_pressure, -ln);
    out->penetration_rate = fmax(out->penetration_rate, sn);
    out->friction_excess = fmax(out->friction_excess, sqrt(lt2) - corot_contact_mu(contact, p) * fmax(ln, 0.0));
    out->active += contact->set[p] != COROT_INACTIVE;
    out->stick += contact->set[p] == COROT_STICK;
    out->slip += contact->set[p] == COROT_SLIP;
  }
}
