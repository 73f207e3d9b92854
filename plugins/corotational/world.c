/* corotational — the step posed in world positions (the unknowns of the plugin ABI): rows, their derivative in the
 * unknowns and in the rotation rate w, and the gradient of the rotation equation. The equations are the s-form's
 * (kernel.c) under the change of variables x -> u^{n+1} -> s; kernel.h states them. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "kernel.h"

int corot_world_init(corot_world *cw, corot_model model, const corot_body *body, corot_contact *contact) {
  memset(cw, 0, sizeof *cw);
  if (model != COROT_MODEL_1 && model != COROT_MODEL_2) return -1;
  cw->model = model;
  cw->body = body;
  cw->contact = contact;
  cw->n_border = model == COROT_MODEL_1 ? 1 : body->dim;
  cw->n_lambda = contact ? body->dim * contact->n : 0;
  cw->N = body->n + cw->n_border + cw->n_lambda;
  corot_pi_matrix(body->dim, body->e, cw->P);
  double **vectors[] = {&cw->f, &cw->u1, &cw->u_h, &cw->s, &cw->Su_h, &cw->Rin, &cw->work, &cw->work2};
  for (size_t k = 0; k < sizeof vectors / sizeof vectors[0]; ++k) {
    *vectors[k] = calloc((size_t)body->n, sizeof(double));
    if (!*vectors[k]) {
      corot_world_free(cw);
      return -1;
    }
  }
  return 0;
}

void corot_world_free(corot_world *cw) {
  double *vectors[] = {cw->f, cw->u1, cw->u_h, cw->s, cw->Su_h, cw->Rin, cw->work, cw->work2};
  for (size_t k = 0; k < sizeof vectors / sizeof vectors[0]; ++k) free(vectors[k]);
  memset(cw, 0, sizeof *cw);
}

int corot_world_jacobian_alloc(corot_world_jacobian *J, const corot_world *cw) {
  memset(J, 0, sizeof *J);
  const corot_body *body = cw->body;
  const int dd = body->dim * body->dim, nc = cw->contact ? cw->contact->n : 0;
  const size_t m = (size_t)(nc > 0 ? nc : 1);
  J->blocks = calloc((size_t)body->row_ptr[body->n_nodes] * (size_t)dd, sizeof(double));
  int ok = J->blocks != NULL;
  for (int j = 0; j < cw->n_border; ++j) {
    ok = ok && (J->col[j] = calloc((size_t)body->n, sizeof(double)));
    ok = ok && (J->row[j] = calloc((size_t)body->n, sizeof(double)));
  }
  ok = ok && (J->body_lambda = calloc(m * dd, sizeof(double))) && (J->lambda_x = calloc(m * dd, sizeof(double))) &&
       (J->lambda_lambda = calloc(m * dd, sizeof(double))) && (J->lambda_border = calloc(m * 9, sizeof(double)));
  if (!ok) corot_world_jacobian_free(J);
  return ok ? 0 : -1;
}

void corot_world_jacobian_free(corot_world_jacobian *J) {
  free(J->blocks);
  for (int j = 0; j < 3; ++j) {
    free(J->col[j]);
    free(J->row[j]);
  }
  free(J->body_lambda);
  free(J->lambda_x);
  free(J->lambda_lambda);
  free(J->lambda_border);
  memset(J, 0, sizeof *J);
}

void corot_world_set_w(corot_world *cw, double w) {
  const corot_body *body = cw->body;
  const int dim = body->dim;
  cw->w = w;
  corot_rotation(dim, body->e, cw->state_n->theta + cw->dt * w, cw->R1);
  corot_rotation(dim, body->e, cw->state_n->theta + 0.5 * cw->dt * w, cw->Rm);
  for (int a = 0; a < body->n_nodes; ++a) {
    if (cw->f_world)
      corot_mul_t(dim, cw->Rm, cw->f_world + a * dim, cw->f + a * dim);
    else
      memset(cw->f + a * dim, 0, sizeof(double) * (size_t)dim);
  }
}

void corot_world_begin(corot_world *cw, const corot_state *state_n, double dt, const double *f_world) {
  cw->state_n = state_n;
  cw->dt = dt;
  cw->a = 2.0 / dt;
  cw->f_world = f_world;
  cw->energy_n = corot_energy(cw->body, state_n->u, state_n->s, cw->work);
  corot_world_set_w(cw, state_n->w);
  corot_contact *contact = cw->contact;
  if (!contact) return;
  corot_contact_begin_step(contact, cw->body, state_n, state_n->theta + 0.5 * dt * state_n->w);
  for (int p = 0; p < contact->n; ++p)
    contact->kappa[p] = corot_row_scale(cw->body, cw->model, dt, state_n->w, contact->node[p]);
}

/* ds/dx_a (the same for every node) and the matrix aI + w Pi. */
static void velocity_gradient(const corot_world *cw, double Gs[9], double A[9]) {
  const int dim = cw->body->dim;
  double G0[9];
  for (int i = 0; i < dim; ++i)
    for (int j = 0; j < dim; ++j) {
      G0[i * dim + j] = 0.5 * cw->R1[j * dim + i];
      A[i * dim + j] = (i == j) * cw->a + cw->w * cw->P[i * dim + j];
    }
  if (cw->model == COROT_MODEL_1)
    corot_matmul(dim, A, G0, Gs);
  else
    for (int i = 0; i < dim * dim; ++i) Gs[i] = cw->a * G0[i];
}

void corot_world_kinematics(corot_world *cw, const double *y) {
  const corot_body *body = cw->body;
  const corot_state *sn = cw->state_n;
  const int dim = body->dim;
  const double a = cw->a, w = cw->w;
  for (int b = 0; b < body->n_nodes; ++b) {
    double d[3], u1[3];
    for (int i = 0; i < dim; ++i) d[i] = y[b * dim + i] - body->centre[i];
    corot_mul_t(dim, cw->R1, d, u1);
    for (int i = 0; i < dim; ++i) {
      cw->u1[b * dim + i] = u1[i] - body->x[b * dim + i];
      cw->u_h[b * dim + i] = 0.5 * (cw->u1[b * dim + i] + sn->u[b * dim + i]);
    }
  }
  corot_mean(body, cw->u_h, cw->T_h);
  const double *tau = y + body->n;
  for (int b = 0; b < body->n_nodes; ++b) {
    double r[3] = {0, 0, 0}, pr[3], pu[3];
    const double *uh = cw->u_h + b * dim, *un = sn->u + b * dim;
    double *s = cw->s + b * dim;
    if (cw->model == COROT_MODEL_1) {
      for (int i = 0; i < dim; ++i) r[i] = body->x[b * dim + i] + uh[i];
      corot_pi(dim, body->e, r, pr); /* s = a (u_h - u^n) + w Pi (x + u_h)  (3.4) */
      for (int i = 0; i < dim; ++i) s[i] = a * (uh[i] - un[i]) + w * pr[i];
    } else {
      for (int i = 0; i < dim; ++i) r[i] = body->x[b * dim + i] + tau[i];
      corot_pi(dim, body->e, r, pu);
      for (int i = 0; i < dim; ++i) s[i] = a * (uh[i] - un[i]) + w * pu[i];
    }
  }
  corot_stiffness_apply(body, cw->u_h, cw->Su_h);
}

/* Rin = M((a + w Pi) s - a s^n) + S u_h + alpha c - f + D lambda: the co-rotated momentum balance. */
static void inner_residual(corot_world *cw, const double *y) {
  const corot_body *body = cw->body;
  const int dim = body->dim, n = body->n;
  double *t = cw->work;
  for (int b = 0; b < body->n_nodes; ++b) {
    double ps[3];
    corot_pi(dim, body->e, cw->s + b * dim, ps);
    for (int i = 0; i < dim; ++i)
      t[b * dim + i] = cw->a * (cw->s[b * dim + i] - cw->state_n->s[b * dim + i]) + cw->w * ps[i];
  }
  corot_mass_apply(body, t, cw->Rin);
  const double alpha = cw->model == COROT_MODEL_1 ? y[n] : 0.0;
  for (int i = 0; i < n; ++i) cw->Rin[i] += cw->Su_h[i] + alpha * body->c[i] - cw->f[i];
  const corot_contact *contact = cw->contact;
  if (!contact) return;
  const double *lambda = y + n + cw->n_border;
  for (int p = 0; p < contact->n; ++p)
    for (int i = 0; i < dim; ++i) cw->Rin[contact->node[p] * dim + i] += contact->weight[p] * lambda[p * dim + i];
}

/* The lever arm of g without the translation: r_h - T_h = x + u_h - T(u_h). */
static void lever(const corot_world *cw, int b, double pr[3]) {
  const int dim = cw->body->dim;
  double r[3] = {0, 0, 0};
  for (int i = 0; i < dim; ++i) r[i] = cw->body->x[b * dim + i] + cw->u_h[b * dim + i] - cw->T_h[i];
  corot_pi(dim, cw->body->e, r, pr);
}

void corot_world_residual(corot_world *cw, const double *y, double *F, double *g) {
  const corot_body *body = cw->body;
  const int dim = body->dim, n = body->n;
  corot_world_kinematics(cw, y);
  inner_residual(cw, y);
  for (int b = 0; b < body->n_nodes; ++b) corot_mul(dim, cw->Rm, cw->Rin + b * dim, F + b * dim);
  if (cw->model == COROT_MODEL_1) {
    F[n] = cw->a * corot_dot(n, body->c, cw->u_h);
  } else {
    for (int i = 0; i < dim; ++i) F[n + i] = body->mass_total * (y[n + i] - cw->T_h[i]);
  }
  const corot_contact *contact = cw->contact;
  if (contact) {
    const double *lambda = y + n + cw->n_border;
    double *Fl = F + n + cw->n_border;
    for (int p = 0; p < contact->n; ++p) {
      double lin[3][3];
      int kinematic[3];
      corot_contact_rows(contact, dim, p, lin, kinematic);
      const double *Fr = contact->frame + 9 * p, *sp = cw->s + contact->node[p] * dim;
      for (int i = 0; i < dim; ++i)
        Fl[p * dim + i] = kinematic[i] ? contact->kappa[p] * corot_dot(dim, Fr + 3 * i, sp)
                                       : contact->weight[p] * corot_dot(dim, lin[i], lambda + p * dim);
    }
  }
  if (!g) return;
  if (cw->model == COROT_MODEL_1) {
    const double alpha = y[n];
    double sum = 0.0;
    for (int b = 0; b < body->n_nodes; ++b) {
      double pr[3];
      lever(cw, b, pr);
      for (int i = 0; i < dim; ++i) sum -= (cw->Su_h[b * dim + i] + alpha * body->c[b * dim + i]) * pr[i];
    }
    *g = sum;
  } else {
    *g = corot_dot(n, body->c, cw->u_h);
  }
}

void corot_world_jacobian_eval(corot_world *cw, const double *y, corot_world_jacobian *J) {
  const corot_body *body = cw->body;
  const int dim = body->dim, dd = dim * dim;
  corot_world_kinematics(cw, y);
  double Gs[9], A[9], G0[9], L[9], T[9];
  velocity_gradient(cw, Gs, A);
  for (int i = 0; i < dim; ++i)
    for (int j = 0; j < dim; ++j) G0[i * dim + j] = 0.5 * cw->R1[j * dim + i];
  corot_matmul(dim, A, Gs, T);
  corot_matmul(dim, cw->Rm, T, L); /* R_m (aI + w Pi) ds/dx */
  /* body rows: R_m (M_ab (aI + w Pi) ds/dx + S_ab G0) */
  for (int64_t k = 0; k < body->row_ptr[body->n_nodes]; ++k) {
    double *B = J->blocks + k * dd, SG[9];
    corot_matmul(dim, body->stiffness + k * dd, G0, SG);
    corot_matmul(dim, cw->Rm, SG, B);
    for (int i = 0; i < dd; ++i) B[i] += body->mass[k] * L[i];
  }
  memset(J->corner, 0, sizeof J->corner);
  if (cw->model == COROT_MODEL_1) {
    for (int b = 0; b < body->n_nodes; ++b) {
      corot_mul(dim, cw->Rm, body->c + b * dim, J->col[0] + b * dim);
      corot_mul_t(dim, G0, body->c + b * dim, J->row[0] + b * dim);
      for (int i = 0; i < dim; ++i) J->row[0][b * dim + i] *= cw->a;
    }
  } else {
    /* d body_a / d tau = R_m m_a (aI + w Pi) w Pi;  d(m tau - 1^T M u_h) / d x_b = -m_b G0 */
    double AP[9], RAP[9];
    corot_matmul(dim, A, cw->P, AP);
    corot_matmul(dim, cw->Rm, AP, RAP);
    for (int b = 0; b < body->n_nodes; ++b) {
      double mb = 0.0;
      for (int64_t k = body->row_ptr[b]; k < body->row_ptr[b + 1]; ++k) mb += body->mass[k];
      for (int i = 0; i < dim; ++i)
        for (int j = 0; j < dim; ++j) {
          J->col[j][b * dim + i] = mb * cw->w * RAP[i * dim + j];
          J->row[i][b * dim + j] = -mb * G0[i * dim + j];
        }
    }
    for (int i = 0; i < dim; ++i) J->corner[i * cw->n_border + i] = body->mass_total;
  }
  const corot_contact *contact = cw->contact;
  if (!contact) return;
  for (int p = 0; p < contact->n; ++p) {
    double lin[3][3];
    int kinematic[3];
    corot_contact_rows(contact, dim, p, lin, kinematic);
    const double *Fr = contact->frame + 9 * p;
    double *BL = J->body_lambda + p * dd, *LX = J->lambda_x + p * dd, *LL = J->lambda_lambda + p * dd;
    double *LB = J->lambda_border + p * 9;
    for (int i = 0; i < dd; ++i) BL[i] = contact->weight[p] * cw->Rm[i];
    memset(LX, 0, sizeof(double) * (size_t)dd);
    memset(LL, 0, sizeof(double) * (size_t)dd);
    memset(LB, 0, 9 * sizeof *LB);
    for (int i = 0; i < dim; ++i) {
      if (!kinematic[i]) {
        for (int j = 0; j < dim; ++j) LL[i * dim + j] = contact->weight[p] * lin[i][j];
        continue;
      }
      for (int j = 0; j < dim; ++j) {
        double sum = 0.0, wp = 0.0;
        for (int l = 0; l < dim; ++l) {
          sum += Fr[3 * i + l] * Gs[l * dim + j];
          wp += Fr[3 * i + l] * cw->w * cw->P[l * dim + j];
        }
        LX[i * dim + j] = contact->kappa[p] * sum;
        if (cw->model == COROT_MODEL_2) LB[i * 3 + j] = contact->kappa[p] * wp;
      }
    }
  }
}

void corot_world_dw(corot_world *cw, const double *y, double *dF, double *dg_dy, double *dg_dw) {
  const corot_body *body = cw->body;
  const int dim = body->dim, n = body->n;
  corot_world_kinematics(cw, y);
  inner_residual(cw, y);
  const double hdt = 0.5 * cw->dt, a = cw->a, w = cw->w;
  const double *tau = y + n;
  double *du = cw->work2, *ds = dF; /* ds lives in dF's body rows until they are formed */
  /* du_h/dw = -(dt/2) Pi r^{n+1}; ds/dw = Pi (x + u_h) + (aI + w Pi) du (Model 1), a du + Pi (x + tau) (Model 2) */
  for (int b = 0; b < body->n_nodes; ++b) {
    double r1[3] = {0, 0, 0}, pr1[3], r[3] = {0, 0, 0}, pr[3], pdu[3];
    for (int i = 0; i < dim; ++i) r1[i] = body->x[b * dim + i] + cw->u1[b * dim + i];
    corot_pi(dim, body->e, r1, pr1);
    for (int i = 0; i < dim; ++i) du[b * dim + i] = -hdt * pr1[i];
    for (int i = 0; i < dim; ++i)
      r[i] = body->x[b * dim + i] + (cw->model == COROT_MODEL_1 ? cw->u_h[b * dim + i] : tau[i]);
    corot_pi(dim, body->e, r, pr);
    corot_pi(dim, body->e, du + b * dim, pdu);
    for (int i = 0; i < dim; ++i)
      ds[b * dim + i] = pr[i] + (cw->model == COROT_MODEL_1 ? a * du[b * dim + i] + w * pdu[i] : a * du[b * dim + i]);
  }
  /* the kinematic contact rows need ds/dw before dF's body rows overwrite it */
  const corot_contact *contact = cw->contact;
  if (contact) {
    double *dFl = dF + n + cw->n_border;
    for (int p = 0; p < contact->n; ++p) {
      double lin[3][3];
      int kinematic[3];
      corot_contact_rows(contact, dim, p, lin, kinematic);
      for (int i = 0; i < dim; ++i)
        dFl[p * dim + i] = kinematic[i] ? contact->kappa[p] * corot_dot(dim, contact->frame + 9 * p + 3 * i,
                                                                    ds + contact->node[p] * dim)
                                        : 0.0;
    }
  }
  /* dRin/dw = M(Pi s + (aI + w Pi) ds) + S du + (dt/2) Pi f;  dF/dw = (dt/2) Pi R_m Rin + R_m dRin/dw */
  double *t = cw->work;
  for (int b = 0; b < body->n_nodes; ++b) {
    double ps[3], pds[3];
    corot_pi(dim, body->e, cw->s + b * dim, ps);
    corot_pi(dim, body->e, ds + b * dim, pds);
    for (int i = 0; i < dim; ++i) t[b * dim + i] = ps[i] + a * ds[b * dim + i] + w * pds[i];
  }
  double *dRin = ds; /* ds is no longer needed once t holds it */
  corot_mass_apply(body, t, dRin);
  corot_stiffness_apply(body, du, t);
  for (int b = 0; b < body->n_nodes; ++b) {
    double pf[3], rr[3], prr[3], v[3];
    corot_pi(dim, body->e, cw->f + b * dim, pf);
    for (int i = 0; i < dim; ++i) v[i] = dRin[b * dim + i] + t[b * dim + i] + hdt * pf[i];
    corot_mul(dim, cw->Rm, cw->Rin + b * dim, rr);
    corot_pi(dim, body->e, rr, prr);
    corot_mul(dim, cw->Rm, v, dF + b * dim);
    for (int i = 0; i < dim; ++i) dF[b * dim + i] += hdt * prr[i];
  }
  /* border rows */
  if (cw->model == COROT_MODEL_1) {
    dF[n] = a * corot_dot(n, body->c, du);
  } else {
    double Tdu[3];
    corot_mean(body, du, Tdu);
    for (int i = 0; i < dim; ++i) dF[n + i] = -body->mass_total * Tdu[i];
  }
  /* g: Model 1 grad_u g = -S Pi u_h + Pi S u_h + alpha Pi c; Model 2 grad_u g = c. dg/dx_b = G0^T grad_b,
   * dg/dw = grad . du (du still in work2; Rin is free now). */
  memset(dg_dy, 0, sizeof(double) * (size_t)cw->N);
  double *grad = cw->work;
  if (cw->model == COROT_MODEL_1) {
    const double alpha = y[n];
    for (int b = 0; b < body->n_nodes; ++b) corot_pi(dim, body->e, cw->u_h + b * dim, cw->Rin + b * dim);
    corot_stiffness_apply(body, cw->Rin, grad);
    double c_pr = 0.0;
    for (int b = 0; b < body->n_nodes; ++b) {
      double pSu[3], pc[3], pr[3];
      corot_pi(dim, body->e, cw->Su_h + b * dim, pSu);
      corot_pi(dim, body->e, body->c + b * dim, pc);
      for (int i = 0; i < dim; ++i) grad[b * dim + i] = pSu[i] + alpha * pc[i] - grad[b * dim + i];
      lever(cw, b, pr);
      c_pr += corot_dot(dim, body->c + b * dim, pr);
    }
    dg_dy[n] = -c_pr;
  } else {
    memcpy(grad, body->c, sizeof(double) * (size_t)n);
  }
  *dg_dw = corot_dot(n, grad, du);
  for (int b = 0; b < body->n_nodes; ++b) {
    /* G0^T grad_b = (1/2) R1 grad_b */
    corot_mul(dim, cw->R1, grad + b * dim, dg_dy + b * dim);
    for (int i = 0; i < dim; ++i) dg_dy[b * dim + i] *= 0.5;
  }
}

double corot_world_g_ref(const corot_world *cw) {
  const corot_body *body = cw->body;
  const double omega = corot_omega_ref(body, cw->w, cw->energy_n, cw->f_world, cw->dt);
  return (cw->model == COROT_MODEL_1 ? cw->a : 0.5 * cw->dt) * body->inertia * omega;
}

void corot_world_predict(corot_world *cw, double *y) {
  const corot_body *body = cw->body;
  const corot_state *sn = cw->state_n;
  const int dim = body->dim, n = body->n;
  const double a = cw->a, w = cw->w;
  double C[9], T_h[3] = {0, 0, 0}, Ts[3] = {0, 0, 0}, t_half[3] = {0, 0, 0}, shift[3] = {0, 0, 0};
  corot_cn(dim, body->e, a, w, C);
  /* s^{n+1/2} = s^n, except that its uniform part turns as free flight makes it: M(a(s - s^n) + w Pi s) = 0 gives
   * T(s) = a C_n T(s^n) (the Cayley angle, §5), so steady spin with translation is predicted exactly */
  corot_mean(body, sn->s, Ts);
  corot_mul(dim, C, Ts, t_half);
  for (int i = 0; i < dim; ++i) shift[i] = a * t_half[i] - Ts[i];
  if (cw->model == COROT_MODEL_2) {
    double Tu[3], v[3] = {0, 0, 0};
    corot_mean(body, sn->u, Tu);
    for (int i = 0; i < dim; ++i) v[i] = Ts[i] + shift[i] + a * Tu[i];
    corot_mul(dim, C, v, T_h);
  }
  for (int b = 0; b < body->n_nodes; ++b) {
    double v[3] = {0, 0, 0}, uh[3], r[3] = {0, 0, 0}, pr[3];
    const double *un = sn->u + b * dim, *snb = sn->s + b * dim;
    for (int i = 0; i < dim; ++i) r[i] = body->x[b * dim + i] + (cw->model == COROT_MODEL_2 ? T_h[i] : 0.0);
    corot_pi(dim, body->e, r, pr);
    if (cw->model == COROT_MODEL_1) { /* u_h = C_n (s + a u^n - w Pi x) */
      for (int i = 0; i < dim; ++i) v[i] = snb[i] + shift[i] + a * un[i] - w * pr[i];
      corot_mul(dim, C, v, uh);
    } else { /* u_h = (dt/2)(s - w Pi (x + T_h)) + u^n  (4.5) */
      for (int i = 0; i < dim; ++i) uh[i] = (snb[i] + shift[i] - w * pr[i]) / a + un[i];
    }
    for (int i = 0; i < dim; ++i) r[i] = body->x[b * dim + i] + 2.0 * uh[i] - un[i];
    corot_mul(dim, cw->R1, r, y + b * dim);
    for (int i = 0; i < dim; ++i) y[b * dim + i] += body->centre[i];
  }
  for (int j = 0; j < cw->n_border; ++j) y[n + j] = cw->model == COROT_MODEL_2 ? T_h[j] : 0.0;
  const corot_contact *contact = cw->contact;
  if (!contact) return;
  double *lambda = y + n + cw->n_border;
  for (int p = 0; p < contact->n; ++p)
    for (int i = 0; i < dim; ++i)
      lambda[p * dim + i] = contact->set[p] != COROT_INACTIVE ? contact->lambda[3 * p + i] : 0.0;
}

int corot_world_propose_sets(corot_world *cw, const double *y) {
  corot_contact *contact = cw->contact;
  if (!contact) return 0;
  const int dim = cw->body->dim;
  const double *lambda = y + cw->body->n + cw->n_border;
  for (int p = 0; p < contact->n; ++p)
    for (int i = 0; i < dim; ++i) contact->lambda[3 * p + i] = lambda[p * dim + i];
  corot_world_kinematics(cw, y);
  return corot_contact_propose(contact, dim, cw->s);
}

double corot_world_commit(corot_world *cw, const double *y, corot_state *next) {
  const corot_body *body = cw->body;
  const corot_state *sn = cw->state_n;
  const int n = body->n, dim = body->dim;
  corot_world_kinematics(cw, y);
  double work = 0.0;
  corot_contact *contact = cw->contact;
  if (contact) {
    const double *lambda = y + n + cw->n_border;
    for (int p = 0; p < contact->n; ++p) {
      for (int i = 0; i < dim; ++i) contact->lambda[3 * p + i] = lambda[p * dim + i];
      work += contact->weight[p] * corot_dot(dim, cw->s + contact->node[p] * dim, lambda + p * dim);
    }
    memcpy(contact->set_committed, contact->set, (size_t)contact->n);
    memcpy(contact->dir_committed, contact->dir, sizeof(double) * 2 * (size_t)contact->n);
  }
  for (int i = 0; i < n; ++i) {
    const double s_next = 2.0 * cw->s[i] - sn->s[i], u_next = cw->u1[i];
    next->s[i] = s_next;
    next->u[i] = u_next;
  }
  next->theta = sn->theta + cw->dt * cw->w;
  next->w = cw->w;
  return cw->dt * work;
}

void corot_world_momentum_balance(const corot_world *cw, const double *y, double *impulse, double *defect) {
  const corot_body *body = cw->body;
  const int dim = body->dim, n = body->n;
  double *force = cw->work2; /* f - D lambda, co-rotated */
  memcpy(force, cw->f, sizeof(double) * (size_t)n);
  const corot_contact *contact = cw->contact;
  if (contact) {
    const double *lambda = y + n + cw->n_border;
    for (int p = 0; p < contact->n; ++p)
      for (int i = 0; i < dim; ++i) force[contact->node[p] * dim + i] -= contact->weight[p] * lambda[p * dim + i];
  }
  double sum = 0.0, lost = 0.0;
  for (int b = 0; b < body->n_nodes; ++b) {
    double r[3] = {0, 0, 0}, pr[3], du[3] = {0, 0, 0}, pdu[3];
    for (int i = 0; i < dim; ++i) {
      r[i] = body->x[b * dim + i] + (cw->model == COROT_MODEL_1 ? cw->u_h[b * dim + i] : cw->T_h[i]);
      du[i] = cw->u1[b * dim + i] - cw->state_n->u[b * dim + i];
    }
    corot_pi(dim, body->e, r, pr);
    corot_pi(dim, body->e, du, pdu);
    for (int i = 0; i < dim; ++i) {
      sum += force[b * dim + i] * pr[i];
      lost += body->c[b * dim + i] * pdu[i];
    }
  }
  *impulse = cw->dt * sum;
  *defect = cw->model == COROT_MODEL_1 ? 0.0 : -cw->w * lost;
}
