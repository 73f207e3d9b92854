/* bench_corot: the co-rotational schemes of Hauret et al. on the paper's 2D examples without the host: the kernel's
 * step loop (step.c) with the driver's direct backend (MUMPS through the Trilinos bridge). Writes one CSV row per
 * step (stdout) and a summary (stderr). Used by bench_corot.py for the Delta t sweeps of docs/plugins/corotational.md.
 *
 *   bench_corot SCENE MODEL DT END [SPIN] [MU] [REFINE]
 *   SCENE: ball-on-plane (Sec. 6.3: R 10, gap 0.5, rho 1), two-planes (6.4: R 1, gaps 0.1 / 0.5, rho 2),
 *          free (the 6.4 ball without planes); SPIN theta'_0 (default 2 or 20), MU (0), REFINE (disk.geo, 1).
 *
 * The bridge refactorises on every solve, so each derivative solve here costs a numeric factorisation; the
 * plugin's solve_again reuses the host's. CPU seconds are therefore an upper bound; `factorisations` counts them. */
#define _POSIX_C_SOURCE 200809L
#include <mpi.h>
#include <time.h>

#include "corot_test_support.h"
#include "stickslip/bridge.h"

typedef struct {
  sk_linear_system *sys;
  int n, N, n_border;
  int64_t *row_ptr;
  int *cols;
  int *pos;                      /* CSR position of each block entry (dim*dim per graph entry) */
  int factorisations;
} bridge_solver;

static double cpu_seconds(void) {
  struct timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The CSR pattern of [P B_col; B_row^T 0]: the node graph in dim x dim blocks, dense border rows and columns. */
static int bridge_pattern(bridge_solver *bs, const corot_system *sys) {
  const int dim = sys->dim, n = sys->n, nb = sys->n_border, N = n + nb;
  bs->n = n, bs->N = N, bs->n_border = nb;
  bs->row_ptr = calloc((size_t)N + 1, sizeof(int64_t));
  int64_t nnz = 0;
  for (int a = 0; a < sys->n_nodes; ++a)
    for (int i = 0; i < dim; ++i) {
      nnz += (sys->row_ptr[a + 1] - sys->row_ptr[a]) * dim + nb;
      bs->row_ptr[a * dim + i + 1] = nnz;
    }
  for (int j = 0; j < nb; ++j) bs->row_ptr[n + j + 1] = (nnz += n + 1);
  bs->cols = malloc(sizeof(int) * (size_t)nnz);
  bs->pos = malloc(sizeof(int) * (size_t)(sys->row_ptr[sys->n_nodes] * dim * dim));
  for (int a = 0; a < sys->n_nodes; ++a)
    for (int i = 0; i < dim; ++i) {
      int64_t p = bs->row_ptr[a * dim + i];
      for (int64_t k = sys->row_ptr[a]; k < sys->row_ptr[a + 1]; ++k)
        for (int j = 0; j < dim; ++j) {
          bs->pos[k * dim * dim + i * dim + j] = (int)p;
          bs->cols[p++] = sys->cols[k] * dim + j;
        }
      for (int j = 0; j < nb; ++j) bs->cols[p++] = n + j;
    }
  for (int j = 0; j < nb; ++j) {
    int64_t p = bs->row_ptr[n + j];
    for (int c = 0; c < n; ++c) bs->cols[p++] = c;
    bs->cols[p++] = n + j; /* a stored zero keeps the diagonal in the pattern */
  }
  int *rows = malloc(sizeof(int) * (size_t)N);
  for (int r = 0; r < N; ++r) rows[r] = r;
  const sk_status s = sk_linsys_set_pattern(bs->sys, N, bs->row_ptr, bs->cols, N, rows);
  free(rows);
  return s == SK_OK ? 0 : -1;
}

static int bridge_factor(void *ctx, const corot_system *sys) {
  bridge_solver *bs = ctx;
  if (!bs->row_ptr && bridge_pattern(bs, sys) != 0) return -1;
  sk_linsys_zero(bs->sys);
  double *v = sk_linsys_values(bs->sys);
  const int dd = sys->dim * sys->dim, n = sys->n;
  for (int64_t k = 0; k < sys->row_ptr[sys->n_nodes] * dd; ++k) v[bs->pos[k]] += sys->blocks[k];
  for (int j = 0; j < sys->n_border; ++j) {
    for (int r = 0; r < n; ++r) v[bs->row_ptr[r + 1] - sys->n_border + j] = sys->border_col[j][r];
    for (int c = 0; c < n; ++c) v[bs->row_ptr[n + j] + c] = sys->border_row[j][c];
  }
  return sk_linsys_assemble(bs->sys) == SK_OK ? 0 : -1;
}

static int bridge_solve(void *ctx, const double *rhs, double *x) {
  bridge_solver *bs = ctx;
  sk_linear_report report;
  bs->factorisations++;
  return sk_linsys_solve(bs->sys, rhs, x, &report) == SK_OK ? 0 : -1;
}

int main(int argc, char **argv) {
  MPI_Init(&argc, &argv);
  if (argc < 5) {
    fprintf(stderr, "usage: bench_corot ball-on-plane|two-planes|free MODEL DT END [SPIN] [MU] [REFINE]\n");
    return 2;
  }
  const char *scene = argv[1];
  const corot_model model = (corot_model)atoi(argv[2]);
  const double dt = atof(argv[3]), end = atof(argv[4]);
  const int big = strcmp(scene, "ball-on-plane") == 0;
  const double spin = argc > 5 ? atof(argv[5]) : (big ? 2.0 : 20.0), mu = argc > 6 ? atof(argv[6]) : 0.0;
  const double refine = argc > 7 ? atof(argv[7]) : 1.0;
  const double R = big ? 10.0 : 1.0, rho = big ? 1.0 : 2.0, V0[3] = {40.0, -40.0, 0.0}, axis[3] = {0, 0, 1};
  const sk_mesh_param params[] = {{"radius", R}, {"refine", refine}};
  test_body tb;
  if (test_body_load(&tb, "meshes/disk.geo", params, 2, "body", "boundary", 1.62e7, 0.2, rho, axis) != 0) return 1;
  const corot_body *b = &tb.body;
  corot_plane planes[2] = {{.point = {0, big ? -10.5 : -1.1, 0}, .normal = {0, 1, 0}, .mu = mu},
                           {.point = {0, 1.5, 0}, .normal = {0, -1, 0}, .mu = mu}};
  const int n_planes = strcmp(scene, "free") == 0 ? 0 : big ? 1 : 2;
  corot_contact contact;
  if (corot_contact_init(&contact, 2, tb.n_contact, tb.contact_nodes, tb.contact_weight, n_planes, planes, 1.0, 1.0))
    return 1;
  bridge_solver bs = {0};
  sk_linear_options options;
  sk_linear_options_default(&options);
  options.kind = SK_LINEAR_DIRECT;
  if (sk_linsys_create(MPI_COMM_WORLD, &options, &bs.sys) != SK_OK) return 1;
  corot_solver solver = {.ctx = &bs, .factor = bridge_factor, .solve = bridge_solve};
  corot_state state, next;
  corot_state_alloc(&state, b);
  corot_state_alloc(&next, b);
  if (initial_state(b, model, spin, V0, &state) != 0) return 1;
  state.w = spin;
  corot_step step;
  corot_step_init(&step, model, b, n_planes ? &contact : NULL);
  double *work = calloc((size_t)b->n, sizeof(double));
  const double E0 = corot_energy(b, state.u, state.s, work);
  printf("step,t,theta,w,E,J,iterations,active,stick,slip,friction_work,cpu_seconds\n");
  printf("0,0,0,%.17g,%.17g,%.17g,0,0,0,0,0,0\n", spin, E0, corot_angular_momentum(b, model, state.u, state.s, work));
  const int steps = (int)ceil(end / dt - 1e-9);
  double cpu = 0.0, energy_drift = 0.0;
  int iterations = 0, status = 0;
  for (int k = 1; k <= steps; ++k) {
    const double c0 = cpu_seconds();
    corot_step_begin(&step, &state, dt, NULL);
    status = corot_step_solve(&step, &solver, 50, 1e-12);
    cpu += cpu_seconds() - c0;
    if (status != 0) break;
    iterations += step.iterations;
    corot_complementarity cc = {0};
    if (n_planes) corot_contact_check(&contact, 2, step.y, &cc);
    const double friction = corot_step_commit(&step, &next);
    corot_state t = state;
    state = next;
    next = t;
    const double E = corot_energy(b, state.u, state.s, work);
    energy_drift = fmax(energy_drift, fabs(E - E0) / E0);
    printf("%d,%.17g,%.17g,%.17g,%.17g,%.17g,%d,%d,%d,%d,%.17g,%.6f\n", k, k * dt, state.theta, state.w, E,
           corot_angular_momentum(b, model, state.u, state.s, work), step.iterations, cc.active, cc.stick, cc.slip,
           friction, cpu);
  }
  fprintf(stderr, "bench_corot %s model %d dt %g: %s, %d iterations, %d factorisations, cpu %.3f s, max |E - E0|/E0 "
          "%.2e\n", scene, model, dt, status == 0 ? "ok" : "FAILED", iterations, bs.factorisations, cpu, energy_drift);
  free(work);
  corot_step_free(&step);
  corot_state_free(&state);
  corot_state_free(&next);
  corot_contact_free(&contact);
  sk_linsys_destroy(bs.sys);
  free(bs.row_ptr);
  free(bs.cols);
  free(bs.pos);
  test_body_free(&tb);
  MPI_Finalize();
  return status == 0 ? 0 : 1;
}
