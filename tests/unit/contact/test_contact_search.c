/* Broad phase: the AABB tree returns exactly the brute-force overlap set, in face order, on random boxes (after
 * build, refit and rebuild), its face boxes enclose the face throughout the step (also the bulge of a curved QUAD9 face), and the
 * count/truncation contract of sk_search_query. */
#include "contact_test_util.h"
#include "sk_test.h"

/* Reference: the face box from its nodes at q0 and q1 grown by `lebesgue` around its centre, plus margin. */
static void reference_box(const sk_surface *s, int f, const double *q0, const double *q1, double lebesgue,
                          double margin, double *lo, double *hi) {
  for (int i = 0; i < 3; ++i) lo[i] = INFINITY, hi[i] = -INFINITY;
  const double *qs[2] = {q0, q1};
  for (int t = 0; t < 2; ++t)
    for (int a = 0; a < s->nen; ++a)
      for (int i = 0; i < 3; ++i) {
        double v = i < s->dim ? qs[t][s->conn[f * s->nen + a] * s->dim + i] : 0.0;
        lo[i] = fmin(lo[i], v), hi[i] = fmax(hi[i], v);
      }
  for (int i = 0; i < 3; ++i) {
    double c = 0.5 * (lo[i] + hi[i]), h = 0.5 * (hi[i] - lo[i]) * lebesgue + margin;
    lo[i] = c - h, hi[i] = c + h;
  }
}

static void random_queries(const sk_surface *s, const sk_search *search, const double *q0, const double *q1,
                           double lebesgue, double margin, unsigned long long *seed, double extent) {
  int n = s->n_faces;
  int *tree = malloc((size_t)n * sizeof(int)), *brute = malloc((size_t)n * sizeof(int));
  for (int trial = 0; trial < 300; ++trial) {
    double lo[3], hi[3];
    for (int i = 0; i < 3; ++i) {
      double c = -0.5 * extent + 2.0 * extent * test_random(seed), w = 0.5 * extent * test_random(seed) * test_random(seed);
      lo[i] = c - w, hi[i] = c + w;
    }
    if (s->dim == 2) lo[2] = -0.1, hi[2] = 0.1;
    int n_tree = sk_search_query(search, lo, hi, tree, n);
    int n_brute = 0;
    for (int f = 0; f < n; ++f) {
      double blo[3], bhi[3];
      reference_box(s, f, q0, q1, lebesgue, margin, blo, bhi);
      if (lo[0] <= bhi[0] && blo[0] <= hi[0] && lo[1] <= bhi[1] && blo[1] <= hi[1] && lo[2] <= bhi[2] &&
          blo[2] <= hi[2])
        brute[n_brute++] = f;
    }
    SK_CHECK(n_tree == n_brute);
    /* in face order as written (the brute force's), whatever the tree's split */
    int same = n_tree == n_brute;
    for (int k = 0; k < n_tree && same; ++k) same = tree[k] == brute[k];
    SK_CHECK(same);
    int n_library_brute = sk_search_brute_force(search, lo, hi, NULL, 0);
    SK_CHECK(n_library_brute == n_brute);
  }
  free(tree);
  free(brute);
}

static void warped(double u, double v, const void *ctx, double *x) {
  (void)ctx;
  x[0] = u + 0.1 * sin(3 * v);
  x[1] = v + 0.1 * cos(2 * u);
  x[2] = 0.3 * sin(u) * sin(v);
}

static void curve(double u, double v, const void *ctx, double *x) {
  (void)ctx;
  (void)v;
  x[0] = 4 * cos(u);
  x[1] = 4 * sin(u);
  x[2] = 0;
}

static void check_type(sk_elem_type type, double lebesgue) {
  test_patch patch;
  int two_d = type == SK_LINE2 || type == SK_LINE3;
  if (two_d) test_patch_make(&patch, type, 500, 1, 0, 6, 0, 0, curve, NULL);
  else test_patch_make(&patch, type, 30, 25, -3, 3, -3, 3, warped, NULL);
  const sk_surface *s = &patch.surface;
  int dofs = patch.n_nodes * s->dim;
  unsigned long long seed = 2024u + (unsigned)type;
  double *q0 = malloc((size_t)dofs * sizeof(double)), *q1 = malloc((size_t)dofs * sizeof(double));
  for (int i = 0; i < dofs; ++i) {
    q0[i] = patch.q[i] + 0.02 * (test_random(&seed) - 0.5);
    q1[i] = q0[i] + 0.05 * (test_random(&seed) - 0.5);
  }
  sk_search *search;
  SK_CHECK(sk_search_create(s, &search) == SK_OK);
  double lo[3] = {-10, -10, -10}, hi[3] = {10, 10, 10};
  SK_CHECK(sk_search_query(search, lo, hi, NULL, 0) == 0); /* nothing before the first update */
  sk_search_update(search, q0, q1, 0.01);
  random_queries(s, search, q0, q1, lebesgue, 0.01, &seed, 4.0);
  /* Everything: total count even when nothing is written; truncation writes at most max_faces. */
  SK_CHECK(sk_search_query(search, lo, hi, NULL, 0) == s->n_faces);
  int few[5] = {-1, -1, -1, -1, -1};
  SK_CHECK(sk_search_query(search, lo, hi, few, 3) == s->n_faces);
  SK_CHECK(few[2] >= 0 && few[3] == -1);

  /* Refit after a large motion (the split stays), then a fresh split: both still exact. */
  for (int i = 0; i < dofs; ++i) {
    q0[i] = q1[i];
    q1[i] = q0[i] + 0.5 * sin(0.37 * i);
  }
  sk_search_update(search, q0, q1, 0.0);
  random_queries(s, search, q0, q1, lebesgue, 0.0, &seed, 4.0);
  sk_search_rebuild(search);
  sk_search_update(search, q0, q1, 0.0);
  random_queries(s, search, q0, q1, lebesgue, 0.0, &seed, 4.0);

  /* Any point of any face at any instant of the step lies in a returned box. */
  sk_surface_point p;
  double *qs = malloc((size_t)dofs * sizeof(double));
  int *found = malloc((size_t)s->n_faces * sizeof(int));
  int missed = 0;
  for (int trial = 0; trial < 200; ++trial) {
    double t = test_random(&seed);
    for (int i = 0; i < dofs; ++i) qs[i] = (1 - t) * q0[i] + t * q1[i];
    int f = (int)(test_random(&seed) * s->n_faces);
    double xi[2] = {-1 + 2 * test_random(&seed), two_d ? 0 : -1 + 2 * test_random(&seed)};
    if (sk_elem_is_simplex(type)) xi[0] = 0.5 * (xi[0] + 1) * 0.5, xi[1] = 0.5 * (xi[1] + 1) * 0.5;
    sk_surface_geometry(s, f, xi, qs, &p);
    int n = sk_search_query(search, p.x, p.x, found, s->n_faces), hit = 0;
    for (int k = 0; k < n; ++k) hit |= found[k] == f;
    missed += !hit;
  }
  SK_CHECK(missed == 0);
  free(qs);
  free(found);
  sk_search_destroy(search);
  free(q0);
  free(q1);
  test_patch_free(&patch);
}

/* One QUAD9 face whose edge mid node is pushed along the edge: the edge overshoots the box of the nodes; the
 * tree's box must still hold the face. */
static void quad9_bulge(void) {
  test_patch patch;
  test_patch_make(&patch, SK_QUAD9, 1, 1, -1, 1, -1, 1, map_flat, NULL);
  /* Grid node (1, 0) is the mid node of edge 0; moving it along the edge makes x(xi) overshoot past x = 1. */
  patch.q[3 * 1 + 0] = 0.9;
  sk_search *search;
  SK_CHECK(sk_search_create(&patch.surface, &search) == SK_OK);
  sk_search_update(search, patch.q, patch.q, 0.0);
  double worst = -INFINITY;
  sk_surface_point p;
  int *found = malloc(sizeof(int));
  for (int k = 0; k <= 100; ++k) {
    double xi[2] = {-1 + 0.02 * k, -1};
    sk_surface_geometry(&patch.surface, 0, xi, patch.q, &p);
    worst = fmax(worst, p.x[0]);
    SK_CHECK(sk_search_query(search, p.x, p.x, found, 1) == 1);
  }
  SK_CHECK(worst > 1.0); /* the overshoot really exists */
  free(found);
  sk_search_destroy(search);
  test_patch_free(&patch);
}

int main(void) {
  check_type(SK_QUAD4, 1.0);
  check_type(SK_TRI3, 1.0);
  check_type(SK_QUAD9, 1.5625);
  check_type(SK_TRI6, 5.0 / 3.0);
  check_type(SK_QUAD8, 3.0);
  check_type(SK_LINE2, 1.0);
  check_type(SK_LINE3, 1.25);
  quad9_bulge();
  return sk_test_finish("test_contact_search");
}
