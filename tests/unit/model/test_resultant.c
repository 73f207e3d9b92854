/* The resultant-load term (core/model/term_resultant.c) through the system of terms, on scenes/compressed-block.yaml
 * and scenes/cantilever-2d.yaml made second order: the nodal forces sum to the prescribed resultant on QUAD9, QUAD8
 * (negative corner weights) and LINE3 faces, over the reference and the current area, at a deformed state; over the
 * reference area they equal the consistent loads of the uniform traction R / A; and the term's assembled Jacobian
 * (in the declared pattern) equals central differences of its residual, under the quasi-static and the midpoint
 * scheme (forces at q_alpha = X + u_n + alpha (u - u_n)). */
#include <math.h>
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sk_test.h"
#include "stickslip/fe.h"
#include "stickslip/scene.h"
#include "assemble.h"
#include "system.h"

static sk_term *resultant_term(sk_system *sys) {
  for (int k = 0; k < sys->n_terms; ++k)
    if (strcmp(sys->terms[k]->ops->kind, "resultant") == 0) return sys->terms[k];
  return NULL;
}

static void term_residual(sk_system *sys, sk_term *term, double *F) {
  memset(sys->F_local, 0, sizeof(double) * (size_t)sys->n);
  SK_CHECK(term->ops->residual(term, sys) == SK_OK);
  memcpy(F, sys->F_local, sizeof(double) * (size_t)sys->model->n_dofs);
}

/* A deterministic deformation of size `amplitude` (a stretch with shear, plus a wobble per dof). */
static void deform(const sk_model *m, double amplitude, double *u) {
  for (int a = 0; a < m->n_nodes; ++a)
    for (int i = 0; i < m->dim; ++i) {
      const double *X = m->X + a * m->dim;
      u[a * m->dim + i] = amplitude * (0.3 * X[i] + 0.2 * X[(i + 1) % m->dim] + 0.05 * sin(3.0 * a + i));
    }
}

/* The scene with `sets` as --replace: each value replaces what the scene has there (a boundary condition, the
 * mesh parameters) rather than merging into it. */
static sk_status load_replacing(const char *path, int n_sets, const char *const *sets, sk_scene *scene) {
  sk_cfg_override_mode modes[8] = {SK_CFG_REPLACE, SK_CFG_REPLACE, SK_CFG_REPLACE, SK_CFG_REPLACE,
                                   SK_CFG_REPLACE, SK_CFG_REPLACE, SK_CFG_REPLACE, SK_CFG_REPLACE};
  const sk_scene_overrides overrides = {.n = n_sets, .assignments = sets, .modes = modes, .plugin = NULL};
  return n_sets <= 8 ? sk_scene_load_with(path, &overrides, MPI_COMM_WORLD, scene) : SK_ERR_INTERNAL;
}

static void check_scene(const char *scene_path, int n_sets, const char *const *sets, const double *R,
                        int current, const char *label) {
  sk_scene scene;
  sk_status status = load_replacing(scene_path, n_sets, sets, &scene);
  if (status != SK_OK) fprintf(stderr, "%s: %s\n", label, sk_error_message());
  SK_CHECK(status == SK_OK);
  if (status != SK_OK) return;
  sk_system *sys = scene.system;
  const sk_model *m = &scene.model;
  const int n = m->n_dofs, dim = m->dim;
  sk_term *term = resultant_term(sys);
  SK_CHECK(term != NULL);
  SK_CHECK(sk_system_begin(sys, 0.5, 1) == SK_OK); /* t = 0.5: the history [[0, 0], [1, 1]] scales R by 0.5 */
  double *F = calloc((size_t)n, sizeof(double)), *Fp = calloc((size_t)n, sizeof(double));
  double *Fm = calloc((size_t)n, sizeof(double));
  deform(m, 0.02, sys->u_n);
  deform(m, 0.1, sys->x);
  const double scale = sk_history_value(&m->resultants[0].history, sys->integrator->force_time(sys->t_n, sys->t));

  /* the nodal forces sum to the resultant */
  term_residual(sys, term, F);
  double sum[3] = {0, 0, 0};
  for (int d = 0; d < n; ++d) sum[d % dim] -= F[d];
  for (int i = 0; i < dim; ++i)
    SK_CHECK_CLOSE(sum[i], scale * R[i], 1e-13 * fabs(R[i]) + 1e-15);

  /* over the reference area: the consistent loads of the uniform traction R / A_ref */
  if (!current) {
    const sk_group *g = m->resultants[0].faces;
    double area = 0.0, *f_traction = calloc((size_t)n, sizeof(double));
    for (int e = 0; e < g->n_elems; ++e) {
      double X[SK_MAX_NEN * 3];
      for (int a = 0; a < g->nen; ++a)
        for (int i = 0; i < dim; ++i) X[a * dim + i] = m->X[g->conn[e * g->nen + a] * dim + i];
      area += sk_face_area(g->type, dim, X);
    }
    sk_traction load = {.faces = g, .history = m->resultants[0].history};
    for (int i = 0; i < dim; ++i) load.traction[i] = R[i] / area;
    sk_model copy = *m;
    copy.tractions = &load, copy.n_tractions = 1;
    sk_traction_add(&copy, 0, sys->integrator->force_time(sys->t_n, sys->t), f_traction);
    double worst = 0.0;
    for (int d = 0; d < n; ++d) worst = fmax(worst, fabs(F[d] - f_traction[d]));
    SK_CHECK(worst <= 1e-14 * fabs(R[dim - 1]));
    free(f_traction);
  }

  /* the assembled Jacobian against central differences of the residual */
  memset(sys->values, 0, sizeof(double) * (size_t)sys->row_ptr[sys->n_kept]);
  SK_CHECK(term->ops->jacobian(term, sys) == SK_OK);
  const double h = 1e-6;
  double worst = 0.0, largest = 0.0, undeclared = 0.0;
  for (int c = 0; c < n; ++c) {
    const double keep = sys->x[c];
    sys->x[c] = keep + h;
    term_residual(sys, term, Fp);
    sys->x[c] = keep - h;
    term_residual(sys, term, Fm);
    sys->x[c] = keep;
    for (int r = 0; r < n; ++r) {
      const double fd = (Fp[r] - Fm[r]) / (2.0 * h);
      const int64_t p = sk_system_position(sys, r, c);
      const double K = p >= 0 ? sys->values[p] : 0.0;
      if (p < 0) undeclared = fmax(undeclared, fabs(fd));
      worst = fmax(worst, fabs(K - fd));
      largest = fmax(largest, fabs(fd));
    }
  }
  printf("%s: sum of nodal forces - R = (%.1e, %.1e, %.1e); Jacobian: largest %.3e, FD error %.2e relative, "
         "outside the pattern %.1e\n", label, sum[0] - scale * R[0], sum[1] - scale * R[1],
         dim == 3 ? sum[2] - scale * R[2] : 0.0, largest, worst / (largest > 0 ? largest : 1), undeclared);
  if (current) {
    SK_CHECK(largest > 1e-3 * fabs(R[dim - 1])); /* the current area does change the forces */
    SK_CHECK(worst <= 1e-9 * largest); /* measured 1.1e-10 ... 3.5e-10 */
  } else {
    SK_CHECK(largest == 0.0 && worst == 0.0); /* a dead load */
  }
  SK_CHECK(undeclared <= 1e-7 * (largest > 0 ? largest : 1));
  free(F), free(Fp), free(Fm);
  sk_scene_free(&scene);
}

int main(int argc, char **argv) {
  MPI_Init(&argc, &argv);
  const double R3[3] = {3.0, -2.0, -10.0}, R2[2] = {0.4, -1.5};
  const char *block = "scenes/compressed-block.yaml", *cantilever = "scenes/cantilever-2d.yaml";
  const char *load_ref = "boundary.3={name: load, group: zmax, resultant: [3, -2, -10], history: [[0, 0], [1, 1]]}";
  const char *load_cur = "boundary.3={name: load, group: zmax, resultant: [3, -2, -10], area: current, "
                         "history: [[0, 0], [1, 1]]}";
  const char *coarse = "mesh.parameters={nx: 2, ny: 2, nz: 1}";
  for (int current = 0; current <= 1; ++current) {
    const char *load = current ? load_cur : load_ref;
    const char *quad9[] = {"mesh.order=2", coarse, load};
    const char *quad8[] = {"mesh.order=2", "mesh.serendipity=true", coarse, load};
    const char *midpoint[] = {"mesh.order=2", coarse, load, "time.scheme=midpoint"};
    check_scene(block, 3, quad9, R3, current, current ? "hex27/QUAD9, current area" : "hex27/QUAD9, reference area");
    check_scene(block, 4, quad8, R3, current, current ? "hex20/QUAD8, current area" : "hex20/QUAD8, reference area");
    check_scene(block, 4, midpoint, R3, current,
                current ? "hex27 midpoint, current area" : "hex27 midpoint, reference area");
    const char *line3[] = {"mesh.order=2", current ? "boundary.1={name: load, group: right, resultant: [0.4, -1.5], "
                                                     "area: current, history: [[0, 0], [1, 1]]}"
                                                   : "boundary.1={name: load, group: right, resultant: [0.4, -1.5], "
                                                     "history: [[0, 0], [1, 1]]}"};
    check_scene(cantilever, 2, line3, R2, current, current ? "2D LINE3, current area" : "2D LINE3, reference area");
  }
  /* scene errors name the key */
  sk_scene scene;
  const char *bad_area[] = {"boundary.3={name: load, group: zmax, resultant: [0, 0, -1], area: deformed}"};
  SK_CHECK(load_replacing(block, 1, bad_area, &scene) == SK_ERR_INPUT);
  SK_CHECK(strstr(sk_error_message(), "area") && strstr(sk_error_message(), "reference or current"));
  const char *two[] = {"boundary.3={name: load, group: zmax, resultant: [0, 0, -1], traction: [0, 0, 1]}"};
  SK_CHECK(load_replacing(block, 1, two, &scene) == SK_ERR_INPUT);
  SK_CHECK(strstr(sk_error_message(), "exactly one of"));
  const char *stray[] = {"boundary.3={name: load, group: zmax, traction: [0, 0, -1], area: current}"};
  SK_CHECK(load_replacing(block, 1, stray, &scene) == SK_ERR_INPUT);
  SK_CHECK(strstr(sk_error_message(), "resultant"));
  const int code = sk_test_finish("test_resultant");
  MPI_Finalize();
  return code;
}
