/* corotational — kernel: the body's operators, the step system (5.1) and the rotation equation with its derivative
 * (Sec. 5.3); the node-wise algebra is in algebra.c. Equations in kernel.h and docs/plugins/corotational.md. */
#include "kernel.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* out = Pi v for every node. */
static void pi_all(const corot_body *body, const double *v, double *out) {
  for (int a = 0; a < body->n_nodes; ++a) corot_pi(body->dim, body->e, v + a * body->dim, out + a * body->dim);
}

/* ---- the body ------------------------------------------------------------------------------------------------------ */

void corot_mass_apply(const corot_body *body, const double *v, double *out) {
  const int dim = body->dim;
  for (int a = 0; a < body->n_nodes; ++a) {
    double sum[3] = {0, 0, 0};
    for (int64_t k = body->row_ptr[a]; k < body->row_ptr[a + 1]; ++k) {
      const double m = body->mass[k];
      const double *vb = v + body->cols[k] * dim;
      for (int i = 0; i < dim; ++i) sum[i] += m * vb[i];
    }
    memcpy(out + a * dim, sum, sizeof(double) * (size_t)dim);
  }
}

/* S v is applied to v - T(v): the same operator (S t = 0 for a uniform t), but without the cancellation of
 * |S| |T(v)| against itself that u, which keeps the body's translation, would otherwise suffer after a long flight. */
void corot_stiffness_apply(const corot_body *body, const double *v, double *out) {
  const int dim = body->dim, dd = dim * dim;
  double T[3];
  corot_mean(body, v, T);
  for (int a = 0; a < body->n_nodes; ++a) {
    double sum[3] = {0, 0, 0};
    for (int64_t k = body->row_ptr[a]; k < body->row_ptr[a + 1]; ++k) {
      const double *K = body->stiffness + k * dd;
      const double *vb = v + body->cols[k] * dim;
      for (int i = 0; i < dim; ++i)
        for (int j = 0; j < dim; ++j) sum[i] += K[i * dim + j] * (vb[j] - T[j]);
    }
    memcpy(out + a * dim, sum, sizeof(double) * (size_t)dim);
  }
}

void corot_mean(const corot_body *body, const double *v, double T[3]) {
  const int dim = body->dim;
  T[0] = T[1] = T[2] = 0.0;
  for (int a = 0; a < body->n_nodes; ++a)
    for (int64_t k = body->row_ptr[a]; k < body->row_ptr[a + 1]; ++k)
      for (int i = 0; i < dim; ++i) T[i] += body->mass[k] * v[body->cols[k] * dim + i];
  for (int i = 0; i < dim; ++i) T[i] /= body->mass_total;
}

int corot_body_init(corot_body *body, int dim, int n_nodes, const int64_t *row_ptr, const int *cols,
                    const double *mass, const double *stiffness, const double *X, const double e[3]) {
  memset(body, 0, sizeof *body);
  if ((dim != 2 && dim != 3) || n_nodes <= 0) return -1;
  body->dim = dim;
  body->n_nodes = n_nodes;
  body->n = dim * n_nodes;
  body->row_ptr = row_ptr;
  body->cols = cols;
  body->mass = mass;
  body->stiffness = stiffness;
  if (dim == 2) {
    body->e[2] = 1.0;
  } else {
    const double norm = sqrt(corot_dot(3, e, e));
    if (!(norm > 0.0)) return -1;
    for (int i = 0; i < 3; ++i) body->e[i] = e[i] / norm;
  }
  body->x = calloc((size_t)body->n, sizeof(double));
  body->c = calloc((size_t)body->n, sizeof(double));
  body->diag = calloc((size_t)n_nodes, sizeof(int64_t));
  if (!body->x || !body->c || !body->diag) {
    corot_body_free(body);
    return -1;
  }
  double first[3] = {0, 0, 0};
  for (int a = 0; a < n_nodes; ++a) {
    body->diag[a] = -1;
    for (int64_t k = row_ptr[a]; k < row_ptr[a + 1]; ++k) {
      if (cols[k] == a) body->diag[a] = k;
      body->mass_total += mass[k];
      for (int i = 0; i < dim; ++i) first[i] += mass[k] * X[cols[k] * dim + i];
    }
    if (body->diag[a] < 0) {
      corot_body_free(body);
      return -1;
    }
  }
  if (!(body->mass_total > 0.0)) {
    corot_body_free(body);
    return -1;
  }
  for (int i = 0; i < dim; ++i) body->centre[i] = first[i] / body->mass_total;
  for (int a = 0; a < n_nodes; ++a)
    for (int i = 0; i < dim; ++i) body->x[a * dim + i] = X[a * dim + i] - body->centre[i];
  double *pix = calloc((size_t)body->n, sizeof(double));
  if (!pix) {
    corot_body_free(body);
    return -1;
  }
  pi_all(body, body->x, pix);
  corot_mass_apply(body, pix, body->c);
  body->inertia = corot_dot(body->n, body->c, pix);
  free(pix);
  if (!(body->inertia > 0.0)) {
    corot_body_free(body);
    return -1;
  }
  return 0;
}

void corot_body_free(corot_body *body) {
  free(body->x);
  free(body->c);
  free(body->diag);
  body->x = body->c = NULL;
  body->diag = NULL;
}

void corot_energy_parts(const corot_body *body, const double *u, const double *s, double *work, double *kinetic,
                        double *strain) {
  corot_mass_apply(body, s, work);
  *kinetic = 0.5 * corot_dot(body->n, s, work);
  double T[3];
  corot_stiffness_apply(body, u, work);
  corot_mean(body, u, T);
  *strain = 0.0;
  for (int a = 0; a < body->n_nodes; ++a)
    for (int i = 0; i < body->dim; ++i) *strain += 0.5 * (u[a * body->dim + i] - T[i]) * work[a * body->dim + i];
}

double corot_energy(const corot_body *body, const double *u, const double *s, double *work) {
  double kinetic, strain;
  corot_energy_parts(body, u, s, work, &kinetic, &strain);
  return kinetic + strain;
}

double corot_angular_momentum(const corot_body *body, corot_model model, const double *u, const double *s,
                              double *work) {
  const int dim = body->dim;
  double *Ms = work;
  corot_mass_apply(body, s, Ms);
  double T[3] = {0, 0, 0};
  if (model == COROT_MODEL_2) corot_mean(body, u, T);
  double J = 0.0;
  for (int a = 0; a < body->n_nodes; ++a) {
    double r[3], pr[3];
    for (int i = 0; i < dim; ++i) r[i] = body->x[a * dim + i] + (model == COROT_MODEL_1 ? u[a * dim + i] : T[i]);
    corot_pi(dim, body->e, r, pr);
    J += corot_dot(dim, Ms + a * dim, pr);
  }
  return J;
}

void corot_world_state(const corot_body *body, double theta, const double *u, const double *s, double *q, double *v) {
  const int dim = body->dim;
  double R[9];
  corot_rotation(dim, body->e, theta, R);
  for (int a = 0; a < body->n_nodes; ++a) {
    double r[3];
    for (int i = 0; i < dim; ++i) r[i] = body->x[a * dim + i] + u[a * dim + i];
    if (q) {
      corot_mul(dim, R, r, q + a * dim);
      for (int i = 0; i < dim; ++i) q[a * dim + i] += body->centre[i];
    }
    if (v) corot_mul(dim, R, s + a * dim, v + a * dim);
  }
}

/* ---- systems ------------------------------------------------------------------------------------------------------- */

int corot_system_alloc(corot_system *system, const corot_body *body, int n_border) {
  memset(system, 0, sizeof *system);
  if (n_border < 0 || n_border > COROT_MAX_BORDER) return -1;
  system->dim = body->dim;
  system->n_nodes = body->n_nodes;
  system->n = body->n;
  system->n_border = n_border;
  system->row_ptr = body->row_ptr;
  system->cols = body->cols;
  const size_t nnz = (size_t)body->row_ptr[body->n_nodes];
  system->blocks = calloc(nnz * (size_t)(body->dim * body->dim), sizeof(double));
  int ok = system->blocks != NULL;
  for (int j = 0; j < n_border; ++j) {
    system->border_col[j] = calloc((size_t)body->n, sizeof(double));
    system->border_row[j] = calloc((size_t)body->n, sizeof(double));
    ok = ok && system->border_col[j] && system->border_row[j];
  }
  if (!ok) corot_system_free(system);
  return ok ? 0 : -1;
}

void corot_system_free(corot_system *system) {
  free(system->blocks);
  for (int j = 0; j < COROT_MAX_BORDER; ++j) {
    free(system->border_col[j]);
    free(system->border_row[j]);
  }
  memset(system, 0, sizeof *system);
}

void corot_system_apply(const corot_system *system, const double *y, double *out) {
  const int dim = system->dim, dd = dim * dim, n = system->n;
  for (int a = 0; a < system->n_nodes; ++a) {
    double sum[3] = {0, 0, 0};
    for (int64_t k = system->row_ptr[a]; k < system->row_ptr[a + 1]; ++k) {
      const double *B = system->blocks + k * dd;
      const double *yb = y + system->cols[k] * dim;
      for (int i = 0; i < dim; ++i)
        for (int j = 0; j < dim; ++j) sum[i] += B[i * dim + j] * yb[j];
    }
    for (int i = 0; i < dim; ++i) out[a * dim + i] = sum[i];
  }
  for (int j = 0; j < system->n_border; ++j) {
    for (int i = 0; i < n; ++i) out[i] += system->border_col[j][i] * y[n + j];
    out[n + j] = corot_dot(n, system->border_row[j], y);
  }
}

/* ---- the step ------------------------------------------------------------------------------------------------------ */

int corot_state_alloc(corot_state *state, const corot_body *body) {
  memset(state, 0, sizeof *state);
  state->u = calloc((size_t)body->n, sizeof(double));
  state->s = calloc((size_t)body->n, sizeof(double));
  if (state->u && state->s) return 0;
  corot_state_free(state);
  return -1;
}

void corot_state_free(corot_state *state) {
  free(state->u);
  free(state->s);
  state->u = state->s = NULL;
}

static int n_border_of(corot_model model) { return model == COROT_MODEL_1 ? 1 : 0; }

int corot_step_init(corot_step *step, corot_model model, const corot_body *body, corot_contact *contact) {
  memset(step, 0, sizeof *step);
  if (model != COROT_MODEL_1 && model != COROT_MODEL_2) return -1;
  step->model = model;
  step->body = body;
  step->contact = contact;
  const size_t n = (size_t)body->n, N = n + (size_t)n_border_of(model);
  double **vectors[] = {&step->f, &step->u_h, &step->r_h, &step->Su_h, &step->R, &step->work, &step->work2};
  int ok = 1;
  for (size_t k = 0; k < sizeof vectors / sizeof vectors[0]; ++k) ok = ok && (*vectors[k] = calloc(n, sizeof(double)));
  ok = ok && (step->rhs = calloc(N, sizeof(double))) && (step->y = calloc(N, sizeof(double))) &&
       (step->dy = calloc(N, sizeof(double)));
  ok = ok && corot_system_alloc(&step->system, body, n_border_of(model)) == 0;
  if (!ok) corot_step_free(step);
  return ok ? 0 : -1;
}

void corot_step_free(corot_step *step) {
  double *vectors[] = {step->f,    step->u_h, step->r_h, step->Su_h, step->R,
                       step->work, step->work2, step->rhs, step->y,  step->dy};
  for (size_t k = 0; k < sizeof vectors / sizeof vectors[0]; ++k) free(vectors[k]);
  corot_system_free(&step->system);
  memset(step, 0, sizeof *step);
}

double corot_row_scale(const corot_body *body, corot_model model, double dt, double w, int node) {
  const int dim = body->dim, dd = dim * dim;
  const int64_t k = body->diag[node];
  const double a = 2.0 / dt;
  double P[9], C[9], B[9];
  corot_pi_matrix(dim, body->e, P);
  corot_cn(dim, body->e, a, w, C);
  const double *S = body->stiffness + k * dd;
  if (model == COROT_MODEL_1)
    corot_matmul(dim, S, C, B);
  else
    for (int i = 0; i < dd; ++i) B[i] = 0.5 * dt * S[i];
  for (int i = 0; i < dim; ++i)
    for (int j = 0; j < dim; ++j) B[i * dim + j] += body->mass[k] * ((i == j) * a + w * P[i * dim + j]);
  return sqrt(corot_dot(dd, B, B) / dim);
}

double corot_omega_ref(const corot_body *body, double w, double energy_n, const double *f_world, double dt) {
  /* a body at rest has E^n = 0: the loads' energy keeps the scale of a body they set moving from zero (0/0 else) */
  double load_energy = 0.0;
  for (int i = 0; f_world && i < body->n; ++i) load_energy += f_world[i] * f_world[i];
  load_energy *= 0.5 * dt * dt * body->n_nodes / body->mass_total;
  return fmax(fabs(w), sqrt(fmax(2.0 * fmax(energy_n, load_energy), 0.0) / body->inertia));
}

void corot_step_begin(corot_step *step, const corot_state *state_n, double dt, const double *f_world) {
  step->state_n = state_n;
  step->dt = dt;
  step->a = 2.0 / dt;
  step->f_world = f_world;
  step->w = state_n->w;
  step->energy_n = corot_energy(step->body, state_n->u, state_n->s, step->work);
  step->iterations = 0;
  step->set_changes = 0;
  corot_contact *contact = step->contact;
  if (!contact) return;
  corot_contact_begin_step(contact, step->body, state_n, state_n->theta + 0.5 * dt * state_n->w);
  /* frozen for the step: the kinematic rows kappa nu . s then do not depend on w */
  for (int p = 0; p < contact->n; ++p)
    contact->kappa[p] = corot_row_scale(step->body, step->model, dt, step->w, contact->node[p]);
}

/* C_n, the midpoint rotation and the co-rotated loads f = R_{theta^{n+1/2}}^T f_W at the current w. */
static void rotation_terms(corot_step *step) {
  const corot_body *body = step->body;
  corot_cn(body->dim, body->e, step->a, step->w, step->C);
  corot_rotation(body->dim, body->e, step->state_n->theta + 0.5 * step->dt * step->w, step->Rmid);
  if (!step->f_world) {
    memset(step->f, 0, sizeof(double) * (size_t)body->n);
    return;
  }
  for (int a = 0; a < body->n_nodes; ++a)
    corot_mul_t(body->dim, step->Rmid, step->f_world + a * body->dim, step->f + a * body->dim);
}

/* Applies node p's row transformation (contact.c) to row block `node` of the system and the right-hand side. */
static void transform_rows(corot_step *step, int p, double *rhs) {
  const corot_body *body = step->body;
  corot_system *sys = &step->system;
  const int dim = body->dim, dd = dim * dim, node = step->contact->node[p];
  double lin[3][3];
  int kinematic[3];
  corot_contact_rows(step->contact, dim, p, lin, kinematic);
  for (int64_t k = body->row_ptr[node]; k < body->row_ptr[node + 1]; ++k) {
    double *B = sys->blocks + k * dd, out[9] = {0};
    for (int i = 0; i < dim; ++i) {
      if (kinematic[i]) {
        if (k == body->diag[node])
          for (int j = 0; j < dim; ++j) out[i * dim + j] = step->contact->kappa[p] * step->contact->frame[9 * p + 3 * i + j];
        continue;
      }
      for (int j = 0; j < dim; ++j)
        for (int l = 0; l < dim; ++l) out[i * dim + j] += lin[i][l] * B[l * dim + j];
    }
    memcpy(B, out, sizeof(double) * (size_t)dd);
  }
  double *vectors[2] = {rhs ? rhs + node * dim : NULL, sys->n_border ? sys->border_col[0] + node * dim : NULL};
  for (int v = 0; v < 2; ++v) {
    if (!vectors[v]) continue;
    double out[3] = {0, 0, 0};
    for (int i = 0; i < dim; ++i)
      if (!kinematic[i])
        for (int l = 0; l < dim; ++l) out[i] += lin[i][l] * vectors[v][l];
    memcpy(vectors[v], out, sizeof(double) * (size_t)dim);
  }
}

void corot_step_assemble(corot_step *step) {
  const corot_body *body = step->body;
  const corot_state *sn = step->state_n;
  corot_system *sys = &step->system;
  const int dim = body->dim, dd = dim * dim, n = body->n;
  const double a = step->a, w = step->w, half_dt = 0.5 * step->dt;
  rotation_terms(step);
  double P[9];
  corot_pi_matrix(dim, body->e, P);
  /* A = M(aI + w Pi) + S C_n (Model 1) or + (dt/2) S (Model 2)  (Sec. 4.2) */
  for (int64_t k = 0; k < body->row_ptr[body->n_nodes]; ++k) {
    double *B = sys->blocks + k * dd;
    const double m = body->mass[k], *S = body->stiffness + k * dd;
    if (step->model == COROT_MODEL_1) {
      corot_matmul(dim, S, step->C, B);
    } else {
      for (int i = 0; i < dd; ++i) B[i] = half_dt * S[i];
    }
    for (int i = 0; i < dim; ++i)
      for (int j = 0; j < dim; ++j) B[i * dim + j] += m * ((i == j) * a + w * P[i * dim + j]);
  }
  /* b = f + a M s^n - S C_n (a u^n - w Pi x) (Model 1) or f + a M s^n - S u^n (Model 2) */
  double *v = step->work, *Sv = step->Su_h;
  if (step->model == COROT_MODEL_1) {
    for (int b = 0; b < body->n_nodes; ++b) {
      double t[3];
      corot_pi(dim, body->e, body->x + b * dim, t);
      for (int i = 0; i < dim; ++i) t[i] = a * sn->u[b * dim + i] - w * t[i];
      corot_mul(dim, step->C, t, v + b * dim);
    }
  } else {
    memcpy(v, sn->u, sizeof(double) * (size_t)n);
  }
  corot_stiffness_apply(body, v, Sv);
  corot_mass_apply(body, sn->s, step->rhs);
  for (int i = 0; i < n; ++i) step->rhs[i] = step->f[i] + a * step->rhs[i] - Sv[i];
  if (step->model == COROT_MODEL_1) {
    /* border: alpha column c, Tisserand row q_x = C_n^T c, q_rhs = -c . C_n (a u^n - w Pi x)  (4.3) */
    memcpy(sys->border_col[0], body->c, sizeof(double) * (size_t)n);
    for (int b = 0; b < body->n_nodes; ++b) corot_mul_t(dim, step->C, body->c + b * dim, sys->border_row[0] + b * dim);
    step->rhs[n] = -corot_dot(n, body->c, v);
  }
  corot_contact *contact = step->contact;
  if (!contact) return;
  for (int p = 0; p < contact->n; ++p)
    if (contact->set[p] != COROT_INACTIVE) transform_rows(step, p, step->rhs);
}

void corot_step_residual(corot_step *step, const double *y, double *F) {
  corot_system_apply(&step->system, y, F);
  const int N = step->system.n + step->system.n_border;
  for (int i = 0; i < N; ++i) F[i] -= step->rhs[i];
}

int corot_step_evaluate(corot_step *step, const double *y) {
  const corot_body *body = step->body;
  const corot_state *sn = step->state_n;
  const int dim = body->dim, n = body->n;
  const double a = step->a, w = step->w, half_dt = 0.5 * step->dt;
  const double *s = y, alpha = step->model == COROT_MODEL_1 ? y[n] : 0.0;
  double *t = step->work;
  if (step->model == COROT_MODEL_1) {
    for (int b = 0; b < body->n_nodes; ++b) {
      double v[3];
      corot_pi(dim, body->e, body->x + b * dim, v);
      for (int i = 0; i < dim; ++i) v[i] = s[b * dim + i] + a * sn->u[b * dim + i] - w * v[i];
      corot_mul(dim, step->C, v, step->u_h + b * dim);
    }
    for (int i = 0; i < n; ++i) step->r_h[i] = body->x[i] + step->u_h[i];
    corot_stiffness_apply(body, step->u_h, step->Su_h);
  } else {
    double Ts[3], Tu[3], v[3], T_h[3];
    corot_mean(body, s, Ts);
    corot_mean(body, sn->u, Tu);
    for (int i = 0; i < 3; ++i) v[i] = Ts[i] + a * Tu[i];
    corot_mul(dim, step->C, v, T_h);
    for (int b = 0; b < body->n_nodes; ++b) {
      double r[3] = {0, 0, 0}, pr[3];
      for (int i = 0; i < dim; ++i) r[i] = step->r_h[b * dim + i] = body->x[b * dim + i] + T_h[i];
      corot_pi(dim, body->e, r, pr);
      for (int i = 0; i < dim; ++i)
        step->u_h[b * dim + i] = half_dt * (s[b * dim + i] - w * pr[i]) + sn->u[b * dim + i];
    }
    corot_stiffness_apply(body, step->u_h, step->Su_h);
  }
  /* R = M((a + w Pi) s - a s^n) + S-term + alpha c - f */
  for (int b = 0; b < body->n_nodes; ++b) {
    double ps[3];
    corot_pi(dim, body->e, s + b * dim, ps);
    for (int i = 0; i < dim; ++i) t[b * dim + i] = a * (s[b * dim + i] - sn->s[b * dim + i]) + w * ps[i];
  }
  corot_mass_apply(body, t, step->R);
  if (step->model == COROT_MODEL_1) {
    for (int i = 0; i < n; ++i) step->R[i] += step->Su_h[i] + alpha * body->c[i] - step->f[i];
  } else {
    /* (dt/2) S s + S u^n: the same S-term as the assembled A (S Pi r~ = 0 in exact arithmetic only) */
    for (int i = 0; i < n; ++i) t[i] = half_dt * s[i] + sn->u[i];
    corot_stiffness_apply(body, t, step->work2);
    for (int i = 0; i < n; ++i) step->R[i] += step->work2[i] - step->f[i];
  }
  /* the rotation equation (4.4') or (2.8), and its scale */
  corot_mean(body, step->u_h, step->T_h);
  if (step->model == COROT_MODEL_1) {
    /* the translation T_h of r_h drops out (sum of S u_h and of c vanish), so it is left out of the products */
    double g = 0.0;
    for (int b = 0; b < body->n_nodes; ++b) {
      double r[3] = {0, 0, 0}, pr[3];
      for (int i = 0; i < dim; ++i) r[i] = step->r_h[b * dim + i] - step->T_h[i];
      corot_pi(dim, body->e, r, pr);
      for (int i = 0; i < dim; ++i) g -= (step->Su_h[b * dim + i] + alpha * body->c[b * dim + i]) * pr[i];
    }
    step->g = g;
  } else {
    step->g = corot_dot(n, body->c, step->u_h);
  }
  step->omega_ref = corot_omega_ref(body, w, step->energy_n, step->f_world, step->dt);
  step->g_ref = (step->model == COROT_MODEL_1 ? a : half_dt) * body->inertia * step->omega_ref;
  step->set_changes = step->contact ? corot_contact_update(step->contact, dim, step->R, s) : 0;
  return step->set_changes;
}

int corot_step_rotation_converged(const corot_step *step, double tol) {
  return fabs(step->g) <= tol * step->g_ref || step->g_ref == 0.0;
}

void corot_step_derivative_rhs(corot_step *step, const double *y, double *rhs) {
  const corot_body *body = step->body;
  const int dim = body->dim, n = body->n;
  const double half_dt = 0.5 * step->dt;
  double *t = step->work;
  /* -dR/dw = -M Pi s + S C_n Pi r_h (Model 1) + d f/dw,  d f/dw = -(dt/2) Pi f */
  pi_all(body, y, t);
  corot_mass_apply(body, t, rhs);
  for (int i = 0; i < n; ++i) rhs[i] = -rhs[i];
  if (step->model == COROT_MODEL_1) {
    double *cpr = step->work2; /* C_n Pi r_h */
    for (int b = 0; b < body->n_nodes; ++b) {
      double pr[3];
      corot_pi(dim, body->e, step->r_h + b * dim, pr);
      corot_mul(dim, step->C, pr, cpr + b * dim);
    }
    corot_stiffness_apply(body, cpr, t);
    for (int i = 0; i < n; ++i) rhs[i] += t[i];
    rhs[n] = corot_dot(n, body->c, cpr); /* -dQ/dw */
  }
  pi_all(body, step->f, t);
  for (int i = 0; i < n; ++i) rhs[i] -= half_dt * t[i];
  corot_contact *contact = step->contact;
  if (!contact) return;
  for (int p = 0; p < contact->n; ++p) {
    if (contact->set[p] == COROT_INACTIVE) continue;
    double lin[3][3], out[3] = {0, 0, 0};
    int kinematic[3];
    double *r = rhs + contact->node[p] * dim;
    corot_contact_rows(contact, dim, p, lin, kinematic);
    for (int i = 0; i < dim; ++i)
      if (!kinematic[i])
        for (int l = 0; l < dim; ++l) out[i] += lin[i][l] * r[l];
    memcpy(r, out, sizeof(double) * (size_t)dim);
  }
}

double corot_step_dg(corot_step *step, const double *y, const double *dy) {
  const corot_body *body = step->body;
  const int dim = body->dim, n = body->n;
  if (step->model == COROT_MODEL_2) return 0.5 * step->dt * (corot_dot(n, body->c, dy) - body->inertia);
  /* dg/dw = grad_u g . (C_n ds/dw - C_n Pi r_h) - (c . Pi r_h) dalpha/dw,
   * grad_u g = -S Pi u_h + Pi S u_h + alpha Pi c */
  const double alpha = y[n];
  double *t = step->work, *SPu = step->work2, dg = 0.0, c_pr = 0.0;
  pi_all(body, step->u_h, t);
  corot_stiffness_apply(body, t, SPu);
  for (int b = 0; b < body->n_nodes; ++b) {
    double r[3] = {0, 0, 0}, pr[3], v[3], du[3], pSu[3], pc[3];
    for (int i = 0; i < dim; ++i) r[i] = step->r_h[b * dim + i] - step->T_h[i]; /* T_h drops out, as in g */
    corot_pi(dim, body->e, r, pr);
    for (int i = 0; i < dim; ++i) v[i] = dy[b * dim + i] - pr[i];
    corot_mul(dim, step->C, v, du);
    corot_pi(dim, body->e, step->Su_h + b * dim, pSu);
    corot_pi(dim, body->e, body->c + b * dim, pc);
    for (int i = 0; i < dim; ++i) {
      dg += (-SPu[b * dim + i] + pSu[i] + alpha * pc[i]) * du[i];
      c_pr += body->c[b * dim + i] * pr[i];
    }
  }
  return dg - c_pr * dy[n];
}

void corot_step_apply_sets(corot_step *step) {
  if (step->contact) corot_contact_apply(step->contact);
}

double corot_step_commit(corot_step *step, corot_state *next) {
  const corot_body *body = step->body;
  const corot_state *sn = step->state_n;
  const int n = body->n, dim = body->dim;
  double work = 0.0;
  corot_contact *contact = step->contact;
  if (contact) {
    for (int p = 0; p < contact->n; ++p)
      work += contact->weight[p] * corot_dot(dim, step->y + contact->node[p] * dim, contact->lambda + 3 * p);
    memcpy(contact->set_committed, contact->set, (size_t)contact->n);
    memcpy(contact->dir_committed, contact->dir, sizeof(double) * 2 * (size_t)contact->n);
  }
  for (int i = 0; i < n; ++i) {
    const double s_next = 2.0 * step->y[i] - sn->s[i], u_next = 2.0 * step->u_h[i] - sn->u[i];
    next->s[i] = s_next;
    next->u[i] = u_next;
  }
  next->theta = sn->theta + step->dt * step->w;
  next->w = step->w;
  return step->dt * work;
}
