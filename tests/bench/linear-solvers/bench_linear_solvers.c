/* Linear-solver benchmark: small-strain linear elasticity on structured quad4 (2D, plane strain) and hex8 (3D)
 * beams 4 x 1 (x 1), clamped at x = 0 and loaded by gravity, assembled by hand (no FE module). For growing sizes it
 * times each solver of the bridge: setup (pattern + assembly), first solve (symbolic + numeric factorisation or
 * preconditioner setup, then solve) and a re-solve with new values on the same pattern (what Newton iterations do).
 *
 *   bench_linear_solvers [csv-path] [--quick]
 *
 * Writes the CSV (default docs/linear-solvers.csv) and prints a Markdown table. A solver is dropped for larger
 * sizes of a dimension once it fails or one solve takes longer than kSlowSeconds. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "stickslip/bridge.h"

enum { kMaxNodesPerElement = 8, kMaxElementDofs = 24 };
static const double kSlowSeconds = 5.0;
static const double young = 1.0, poisson = 0.3;

typedef struct {
  int dim;
  int cells[3];       /* elements along x, y, z */
  int nodes[3];       /* nodes along x, y, z (z = 1 in 2D) */
  int n_free_nodes;   /* nodes with i > 0 (x = 0 is clamped) */
  int n;              /* unknowns */
  int *node_ptr;      /* node graph (free nodes, stencil neighbours), CSR */
  int *node_adj;
  int64_t *row_ptr;
  int *cols;
  double *values;
  double *rhs;
  double *coordinates;
} problem;

/* Free-node index of grid node (i, j, k), or -1 when clamped / outside. */
static int free_node(const problem *p, int i, int j, int k) {
  if (i <= 0 || i >= p->nodes[0] || j < 0 || j >= p->nodes[1] || k < 0 || k >= p->nodes[2]) return -1;
  return (i - 1) + (p->nodes[0] - 1) * (j + p->nodes[1] * k);
}

/* Element stiffness of an h-sized square / cube, 2^dim Gauss points. Node a sits at offsets (a&1, a>>1&1, a>>2&1). */
static void element_stiffness(int dim, double h, double *ke) {
  const int nen = 1 << dim, ndof = nen * dim, nstrain = dim == 2 ? 3 : 6;
  double d[6][6] = {{0}};
  if (dim == 2) {
    const double f = young / ((1 + poisson) * (1 - 2 * poisson));
    d[0][0] = d[1][1] = f * (1 - poisson);
    d[0][1] = d[1][0] = f * poisson;
    d[2][2] = f * (1 - 2 * poisson) / 2;
  } else {
    const double lambda = young * poisson / ((1 + poisson) * (1 - 2 * poisson)), mu = young / (2 * (1 + poisson));
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) d[a][b] = lambda + (a == b ? 2 * mu : 0);
    d[3][3] = d[4][4] = d[5][5] = mu;
  }
  memset(ke, 0, sizeof(double) * (size_t)(ndof * ndof));
  const double g = 1.0 / sqrt(3.0), det_j = pow(h / 2, dim);
  for (int q = 0; q < nen; ++q) {
    double xi[3];
    for (int c = 0; c < dim; ++c) xi[c] = ((q >> c) & 1) ? g : -g;
    double dn[kMaxNodesPerElement][3];
    for (int a = 0; a < nen; ++a) {
      for (int c = 0; c < dim; ++c) {
        double v = 1.0 / nen;
        for (int e = 0; e < dim; ++e) {
          const double xa = ((a >> e) & 1) ? 1.0 : -1.0;
          v *= e == c ? xa : 1 + xa * xi[e];
        }
        dn[a][c] = v * 2.0 / h;
      }
    }
    double b[6][kMaxElementDofs] = {{0}};
    for (int a = 0; a < nen; ++a) {
      double *col = &b[0][0] + a * dim;
      (void)col;
      if (dim == 2) {
        b[0][2 * a] = dn[a][0];
        b[1][2 * a + 1] = dn[a][1];
        b[2][2 * a] = dn[a][1];
        b[2][2 * a + 1] = dn[a][0];
      } else {
        b[0][3 * a] = dn[a][0];
        b[1][3 * a + 1] = dn[a][1];
        b[2][3 * a + 2] = dn[a][2];
        b[3][3 * a] = dn[a][1];
        b[3][3 * a + 1] = dn[a][0];
        b[4][3 * a + 1] = dn[a][2];
        b[4][3 * a + 2] = dn[a][1];
        b[5][3 * a] = dn[a][2];
        b[5][3 * a + 2] = dn[a][0];
      }
    }
    for (int r = 0; r < ndof; ++r)
      for (int s = 0; s < ndof; ++s) {
        double sum = 0;
        for (int x = 0; x < nstrain; ++x)
          for (int y = 0; y < nstrain; ++y) sum += b[x][r] * d[x][y] * b[y][s];
        ke[r * ndof + s] += sum * det_j;
      }
  }
}

static problem build(int dim, int ny) {
  problem p;
  memset(&p, 0, sizeof p);
  p.dim = dim;
  p.cells[0] = 4 * ny;
  p.cells[1] = ny;
  p.cells[2] = dim == 3 ? ny : 0;
  for (int c = 0; c < 3; ++c) p.nodes[c] = p.cells[c] + 1;
  p.n_free_nodes = (p.nodes[0] - 1) * p.nodes[1] * p.nodes[2];
  p.n = p.n_free_nodes * dim;
  const double h = 1.0 / ny;

  /* node graph: the 3^dim stencil, in increasing node order */
  p.node_ptr = malloc(sizeof(int) * (size_t)(p.n_free_nodes + 1));
  p.node_adj = malloc(sizeof(int) * (size_t)p.n_free_nodes * 27);
  p.coordinates = malloc(sizeof(double) * (size_t)p.n);
  int m = 0;
  for (int k = 0; k < p.nodes[2]; ++k)
    for (int j = 0; j < p.nodes[1]; ++j)
      for (int i = 1; i < p.nodes[0]; ++i) {
        const int node = free_node(&p, i, j, k);
        p.node_ptr[node] = m;
        const double x[3] = {i * h, j * h, k * h};
        for (int c = 0; c < dim; ++c) p.coordinates[dim * node + c] = x[c];
        for (int dk = (dim == 3 ? -1 : 0); dk <= (dim == 3 ? 1 : 0); ++dk)
          for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di) {
              const int other = free_node(&p, i + di, j + dj, k + dk);
              if (other >= 0) p.node_adj[m++] = other;
            }
      }
  p.node_ptr[p.n_free_nodes] = m;

  /* dof CSR: row (node, c) holds dim entries per neighbour */
  p.row_ptr = malloc(sizeof(int64_t) * (size_t)(p.n + 1));
  p.cols = malloc(sizeof(int) * (size_t)m * dim * dim);
  int64_t e = 0;
  for (int node = 0; node < p.n_free_nodes; ++node)
    for (int c = 0; c < dim; ++c) {
      p.row_ptr[dim * node + c] = e;
      for (int s = p.node_ptr[node]; s < p.node_ptr[node + 1]; ++s)
        for (int c2 = 0; c2 < dim; ++c2) p.cols[e++] = dim * p.node_adj[s] + c2;
    }
  p.row_ptr[p.n] = e;
  p.values = calloc((size_t)e, sizeof(double));
  p.rhs = calloc((size_t)p.n, sizeof(double));

  double ke[kMaxElementDofs * kMaxElementDofs];
  element_stiffness(dim, h, ke);
  const int nen = 1 << dim, ndof = nen * dim;
  const double nodal_gravity = -pow(h, dim) / nen;
  for (int k = 0; k < (dim == 3 ? p.cells[2] : 1); ++k)
    for (int j = 0; j < p.cells[1]; ++j)
      for (int i = 0; i < p.cells[0]; ++i) {
        int nodes[kMaxNodesPerElement];
        for (int a = 0; a < nen; ++a) nodes[a] = free_node(&p, i + (a & 1), j + ((a >> 1) & 1), k + ((a >> 2) & 1));
        for (int a = 0; a < nen; ++a) {
          if (nodes[a] < 0) continue;
          p.rhs[dim * nodes[a] + 1] += nodal_gravity;
          for (int b = 0; b < nen; ++b) {
            if (nodes[b] < 0) continue;
            int slot = p.node_ptr[nodes[a]];
            while (p.node_adj[slot] != nodes[b]) ++slot;
            const int degree = p.node_ptr[nodes[a] + 1] - p.node_ptr[nodes[a]];
            for (int c = 0; c < dim; ++c)
              for (int c2 = 0; c2 < dim; ++c2)
                p.values[p.row_ptr[dim * nodes[a] + c] + (slot - p.node_ptr[nodes[a]]) * dim + c2] +=
                    ke[(a * dim + c) * ndof + b * dim + c2];
            (void)degree;
          }
        }
      }
  return p;
}

static void release(problem *p) {
  free(p->node_ptr);
  free(p->node_adj);
  free(p->row_ptr);
  free(p->cols);
  free(p->values);
  free(p->rhs);
  free(p->coordinates);
}

static sk_status fill(sk_linear_system *sys, const problem *p, double scale) {
  sk_linsys_zero(sys);
  double *values = sk_linsys_values(sys);
  for (int64_t k = 0; k < p->row_ptr[p->n]; ++k) values[k] = scale * p->values[k];
  return sk_linsys_assemble(sys);
}

typedef struct {
  int ok;
  double setup, first, again, residual;
  int iterations;
} timing;

static timing run(const problem *p, sk_linear_solver_kind kind, double *x) {
  timing t = {0, 0, 0, 0, 0, 0};
  sk_linear_options options;
  sk_linear_options_default(&options);
  options.kind = kind;
  options.tolerance = 1e-8; /* a Newton step's linear solve */
  options.max_iterations = 1000;
  sk_linear_system *sys = NULL;
  if (sk_linsys_create(MPI_COMM_WORLD, &options, &sys) != SK_OK) return t;
  int *rows = malloc(sizeof(int) * (size_t)p->n);
  for (int i = 0; i < p->n; ++i) rows[i] = i;
  double start = MPI_Wtime();
  sk_status status = sk_linsys_set_block_size(sys, p->dim);
  if (status == SK_OK) status = sk_linsys_set_coordinates(sys, p->n_free_nodes, p->dim, p->coordinates);
  if (status == SK_OK) status = sk_linsys_set_pattern(sys, p->n_free_nodes * p->dim, p->n - p->n_free_nodes * p->dim, p->n, rows, p->row_ptr, p->cols);
  if (status == SK_OK) status = fill(sys, p, 1.0);
  t.setup = MPI_Wtime() - start;
  sk_linear_report report;
  if (status == SK_OK) {
    start = MPI_Wtime();
    status = sk_linsys_solve(sys, p->rhs, x, &report);
    t.first = MPI_Wtime() - start;
    t.iterations = report.iterations;
    t.residual = report.relative_residual;
  }
  if (status == SK_OK) {
    /* new values, same pattern: only the numeric factorisation / preconditioner values are redone */
    status = fill(sys, p, 1.5);
    start = MPI_Wtime();
    if (status == SK_OK) status = sk_linsys_solve(sys, p->rhs, x, &report);
    t.again = MPI_Wtime() - start;
    for (int i = 0; i < p->n; ++i) x[i] *= 1.5; /* back to the solution of the unscaled system */
  }
  if (status != SK_OK) fprintf(stderr, "  %s: %s\n", sk_linear_solver_name(kind), sk_error_message());
  t.ok = status == SK_OK;
  free(rows);
  sk_linsys_destroy(sys);
  return t;
}

int main(int argc, char **argv) {
  MPI_Init(&argc, &argv);
  const char *csv_path = "docs/linear-solvers.csv";
  int quick = 0;
  for (int i = 1; i < argc; ++i) {
    if (strcmp(argv[i], "--quick") == 0) quick = 1;
    else csv_path = argv[i];
  }
  FILE *csv = fopen(csv_path, "w");
  if (!csv) {
    fprintf(stderr, "bench_linear_solvers: cannot write %s\n", csv_path);
    MPI_Finalize();
    return 1;
  }
  fprintf(csv, "dim,unknowns,nonzeros,solver,ok,iterations,setup_s,first_solve_s,resolve_s,relative_residual,"
               "max_difference_to_direct\n");
  printf("| dim | unknowns | solver | iterations | setup + first solve [s] | re-solve [s] | rel. residual |\n");
  printf("|----:|---------:|:-------|-----------:|------------------------:|-------------:|--------------:|\n");
  const int sizes2d[] = {8, 16, 32, 48, 64, 96}, sizes3d[] = {3, 4, 6, 8, 10, 12, 14, 16};
  /* the direct backends by name (`direct` is whichever of them the bridge measured fastest); the first successful
   * one is the reference solution of the others */
  const sk_linear_solver_kind kinds[] = {SK_LINEAR_DIRECT_KLU2, SK_LINEAR_DIRECT_KLU, SK_LINEAR_DIRECT_MUMPS,
                                         SK_LINEAR_GMRES_MUELU, SK_LINEAR_GMRES_ILU};
  enum { n_kinds = sizeof kinds / sizeof kinds[0] };
  for (int dim = 2; dim <= 3; ++dim) {
    const int *sizes = dim == 2 ? sizes2d : sizes3d;
    const int n_sizes = quick ? 2 : (dim == 2 ? 6 : 8);
    int dropped[n_kinds] = {0};
    for (int s = 0; s < n_sizes; ++s) {
      problem p = build(dim, sizes[s]);
      double *x_direct = calloc((size_t)p.n, sizeof(double)), *x = calloc((size_t)p.n, sizeof(double));
      int have_direct = 0;
      for (int k = 0; k < n_kinds; ++k) {
        if (dropped[k]) continue;
        timing t = run(&p, kinds[k], x);
        double difference = NAN;
        const int direct = kinds[k] != SK_LINEAR_GMRES_MUELU && kinds[k] != SK_LINEAR_GMRES_ILU;
        if (t.ok && direct && !have_direct) {
          memcpy(x_direct, x, sizeof(double) * (size_t)p.n);
          have_direct = 1;
        }
        if (t.ok && have_direct) {
          double worst = 0, scale = 0;
          for (int i = 0; i < p.n; ++i) {
            worst = fmax(worst, fabs(x[i] - x_direct[i]));
            scale = fmax(scale, fabs(x_direct[i]));
          }
          difference = worst / scale;
        }
        fprintf(csv, "%d,%d,%lld,%s,%d,%d,%.4f,%.4f,%.4f,%.3e,%.3e\n", dim, p.n, (long long)p.row_ptr[p.n],
                sk_linear_solver_name(kinds[k]), t.ok, t.iterations, t.setup, t.first, t.again, t.residual,
                difference);
        fflush(csv);
        if (t.ok)
          printf("| %d | %d | %s | %d | %.3f | %.3f | %.1e |\n", dim, p.n, sk_linear_solver_name(kinds[k]),
                 t.iterations, t.setup + t.first, t.again, t.residual);
        else
          printf("| %d | %d | %s | failed | | | |\n", dim, p.n, sk_linear_solver_name(kinds[k]));
        fflush(stdout);
        if (!t.ok || t.setup + t.first > kSlowSeconds) dropped[k] = 1;
      }
      free(x_direct);
      free(x);
      release(&p);
    }
  }
  fclose(csv);
  MPI_Finalize();
  return 0;
}
