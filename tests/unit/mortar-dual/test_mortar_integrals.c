/* mortar-dual kernel: the mortar integrals of one face pair. Biorthogonality of the dual basis; patch-test-type
 * integrals (a flat non-matching interface: sum_l M_jl = D_jj, linear fields reproduced, constant gap) exact with
 * segment-based integration and only approximate with concentrated integration (deviation printed); invariance
 * under a rigid motion; and a finite-difference check of every derivative of D, M and the weighted gap for 2D
 * segments, 3D segments (tri3/quad4 in all combinations), concentrated points (normal variants A and M) and rigid
 * obstacles; the 3D segments' continuity where a clip-polygon vertex appears and their derivatives on slivers. */
#include "mortar_pair_cases.h"

/* ---- quadrature and bases -------------------------------------------------------------------------------------- */
static void check_quadrature(void) {
  for (int n = 1; n <= 8; ++n) {
    double x[MORTAR_MAX_RULE], w[MORTAR_MAX_RULE];
    mortar_gauss_legendre(n, x, w);
    double err = 0.0;
    for (int p = 0; p <= 2 * n - 1; ++p) {
      double s = 0.0;
      for (int i = 0; i < n; ++i) s += w[i] * pow(x[i], p);
      err = fmax(err, fabs(s - (p % 2 ? 0.0 : 2.0 / (p + 1))));
    }
    SK_CHECK(err < 1e-14);
  }
  static const int sizes[] = {1, 3, 6, 7, 12}, degrees[] = {1, 2, 4, 5, 6};
  for (int r = 0; r < 5; ++r) {
    const double *xi, *w;
    const int n = mortar_triangle_rule(sizes[r], &xi, &w);
    SK_CHECK(n == sizes[r]);
    double err = 0.0;
    for (int a = 0; a <= degrees[r]; ++a)
      for (int b = 0; a + b <= degrees[r]; ++b) {
        double s = 0.0, exact = tgamma(a + 1) * tgamma(b + 1) / tgamma(a + b + 3); /* int x^a y^b */
        for (int q = 0; q < n; ++q) s += w[q] * pow(xi[2 * q], a) * pow(xi[2 * q + 1], b);
        err = fmax(err, fabs(s - exact));
      }
    SK_CHECK(err < 1e-13);
  }
}
/* ---- patch-test-type integrals: a flat slave face over several master faces, summed --------------------------- */
enum { MAX_PATCH_MASTERS = 32 };
typedef struct {
  double D[4], Msum[4], Mx[4][3], Dx[4][3], gap[4];
  double M[MAX_PATCH_MASTERS][4][4]; /* per master face */
} patch_sums;

typedef struct {
  int n;
  double xm[MAX_PATCH_MASTERS][12];
} patch_masters;

/* M and gap of a pair (D, of the slave face alone, is added once by integrate_patch). */
static void add_integrals(const mortar_pair *p, const mortar_integrals *I, const double *xm, int face,
                          patch_sums *s) {
  for (int j = 0; j < p->nen_s; ++j) {
    for (int l = 0; l < p->nen_m; ++l) {
      s->Msum[j] += I->M[j][l].v;
      s->M[face][j][l] += I->M[j][l].v;
      for (int i = 0; i < 3; ++i) s->Mx[j][i] += I->M[j][l].v * xm[3 * l + i];
    }
    s->gap[j] += I->gap[j].v;
  }
}

/* Segments: every pair. Concentrated: each slave point goes to the first master face it projects into. */
static void integrate_patch(const pair_case *c, const double *xs, const double *ns, const patch_masters *pm,
                            patch_sums *s) {
  mortar_pair p;
  mortar_integrals I;
  integrate_case(c, xs, pm->xm[0], ns, 0, &p, &I); /* D of the slave face */
  for (int j = 0; j < p.nen_s; ++j)
    for (int k = 0; k < p.nen_s; ++k) {
      s->D[j] += I.D[j][k].v;
      for (int i = 0; i < 3; ++i) s->Dx[j][i] += I.D[j][k].v * xs[3 * k + i];
    }
  if (c->mode == MODE_SEGMENTS) {
    for (int f = 0; f < pm->n; ++f)
      if (integrate_case(c, xs, pm->xm[f], ns, 0, &p, &I) == 0) add_integrals(&p, &I, pm->xm[f], f, s);
    return;
  }
  double xi[MORTAR_MAX_RULE * MORTAR_MAX_RULE * 2], w[MORTAR_MAX_RULE * MORTAR_MAX_RULE];
  const int nq = mortar_face_rule(c->st->type, c->order, xi, w), pd = c->st->pdim;
  for (int q = 0; q < nq; ++q)
    for (int f = 0; f < pm->n; ++f) {
      mortar_pair_set(&p, c->dim, c->st, c->mt, xs, pm->xm[f], ns, 0);
      mortar_point_projection proj;
      if (mortar_project_point(&p, MORTAR_NORMAL_A, xi + q * pd, 1e-12, &proj) != 0 || !proj.inside) continue;
      mortar_basis_coeffs A;
      mortar_basis_coefficients(&p, c->basis, &A);
      mortar_integrals_zero(&I, &p);
      mortar_points(&p, &A, c->basis, MORTAR_NORMAL_A, 1, xi + q * pd, w + q, &I);
      add_integrals(&p, &I, pm->xm[f], f, s);
      break;
    }
}

/* Returns the largest deviation of sum_l M_jl = sum_k D_jk, sum_l M_jl x_l = sum_k D_jk x_k (in-plane
 * components) and gap_j = delta sum_k D_jk, relative to the face measure. */
static double patch_deviation(const pair_case *c, double delta, patch_sums *sums) {
  const int d = c->dim;
  patch_sums s;
  memset(&s, 0, sizeof s);
  double xs[12] = {0}, ns[12] = {0}, xm[12] = {0};
  double measure;
  patch_masters pm = {0};
  if (d == 2) {
    xs[3] = 1.0; /* slave (0,0)-(1,0), outward normal down */
    ns[1] = ns[4] = -1.0;
    static const double xn[] = {1.25, 0.6, 0.15, -0.3};
    for (int e = 0; e < 3; ++e) {
      xm[0] = xn[e];
      xm[3] = xn[e + 1];
      xm[1] = xm[4] = -delta;
      memcpy(pm.xm[pm.n++], xm, sizeof xm);
    }
    measure = 1.0;
  } else {
    static const double quad[4][2] = {{0, 0}, {0, 1}, {1, 1}, {1, 0}}, tri[3][2] = {{0, 0}, {0, 1}, {1, 0}};
    const int es = c->st->nen;
    for (int a = 0; a < es; ++a) {
      xs[3 * a] = es == 4 ? quad[a][0] : tri[a][0];
      xs[3 * a + 1] = es == 4 ? quad[a][1] : tri[a][1];
      ns[3 * a + 2] = -1.0;
    }
    measure = es == 4 ? 1.0 : 0.5;
    /* master grid over [-0.2, 1.3]^2, irregular lines, facing up (counter-clockwise from above) */
    static const double gx[] = {-0.2, 0.37, 0.81, 1.3}, gy[] = {-0.2, 0.29, 0.74, 1.3};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const double P[4][2] = {{gx[i], gy[j]}, {gx[i + 1], gy[j]}, {gx[i + 1], gy[j + 1]}, {gx[i], gy[j + 1]}};
        if (c->mt->nen == 4) {
          for (int b = 0; b < 4; ++b) {
            xm[3 * b] = P[b][0];
            xm[3 * b + 1] = P[b][1];
            xm[3 * b + 2] = -delta;
          }
          memcpy(pm.xm[pm.n++], xm, sizeof xm);
        } else {
          static const int split[2][3] = {{0, 1, 2}, {0, 2, 3}};
          for (int t = 0; t < 2; ++t) {
            for (int b = 0; b < 3; ++b) {
              xm[3 * b] = P[split[t][b]][0];
              xm[3 * b + 1] = P[split[t][b]][1];
              xm[3 * b + 2] = -delta;
            }
            memcpy(pm.xm[pm.n++], xm, sizeof xm);
          }
        }
      }
  }
  integrate_patch(c, xs, ns, &pm, &s);
  double dev = 0.0, total = 0.0;
  for (int j = 0; j < c->st->nen; ++j) {
    total += s.D[j];
    dev = fmax(dev, fabs(s.Msum[j] - s.D[j]));
    for (int i = 0; i < d - 1; ++i) dev = fmax(dev, fabs(s.Mx[j][i] - s.Dx[j][i]));
    dev = fmax(dev, fabs(s.gap[j] - delta * s.D[j]));
  }
  SK_CHECK(fabs(total - measure) < 1e-13);
  *sums = s;
  return dev / measure;
}

/* The sums hold for any rule (partition of unity, linear fields); the entries M_jl show the integration error:
 * segment-based entries do not change with the rule (exact), concentrated ones do. */
static double max_entry_difference(const patch_sums *a, const patch_sums *b) {
  double e = 0.0;
  for (int f = 0; f < MAX_PATCH_MASTERS; ++f)
    for (int j = 0; j < 4; ++j)
      for (int l = 0; l < 4; ++l) e = fmax(e, fabs(a->M[f][j][l] - b->M[f][j][l]));
  return e;
}

static void check_patch(void) {
  const mortar_face_type *slaves[] = {&ft_line2, &ft_tri3, &ft_quad4, &ft_quad4, &ft_tri3};
  const mortar_face_type *masters[] = {&ft_line2, &ft_tri3, &ft_quad4, &ft_tri3, &ft_quad4};
  static patch_sums s1, s2, c1;
  for (int t = 0; t < 5; ++t)
    for (int basis = 0; basis < 2; ++basis) {
      const int dim = t == 0 ? 2 : 3;
      pair_case seg = {dim, slaves[t], masters[t], (mortar_basis)basis, MODE_SEGMENTS, dim == 2 ? 2 : 7};
      const double e1 = patch_deviation(&seg, 0.01, &s1);
      seg.order = dim == 2 ? 6 : 12;
      const double e2 = patch_deviation(&seg, 0.01, &s2);
      pair_case con = {dim, slaves[t], masters[t], (mortar_basis)basis, MODE_POINTS_A, dim == 2 ? 5 : 4};
      const double e3 = patch_deviation(&con, 0.01, &c1);
      const double d_seg = max_entry_difference(&s1, &s2), d_con = max_entry_difference(&s2, &c1);
      printf("  patch %s/%s %s: sums %.1e %.1e %.1e; entries: segments rule a vs b %.1e, concentrated %.2e\n",
             sk_elem_name(slaves[t]->type), sk_elem_name(masters[t]->type), basis ? "dual" : "standard", e1, e2, e3,
             d_seg, d_con);
      SK_CHECK(e1 < 1e-14 && e2 < 1e-14 && e3 < 1e-14);
      SK_CHECK(d_seg < 1e-15);
      SK_CHECK(d_con > 1e-4); /* concentrated integration does not see the master kinks */
    }
}

/* ---- a rigid motion leaves D, M and the gap unchanged (the objectivity of the weighted slip rests on it) -------- */
static void check_rigid_motion(pair_case c) {
  double u[FWD_MAX], v[FWD_MAX];
  generic_configuration(&c, u);
  const double ang = 0.7, R[3][3] = {{cos(ang), -sin(ang), 0}, {sin(ang), cos(ang), 0}, {0, 0, 1}};
  const double R3[3][3] = {{1, 0, 0}, {0, cos(0.4), -sin(0.4)}, {0, sin(0.4), cos(0.4)}};
  const int d = c.dim, nodes = n_local(&c) / d, es = c.st->nen, em = c.mt ? c.mt->nen : 0;
  for (int a = 0; a < nodes; ++a) {
    double x[3] = {0, 0, 0}, y[3] = {0, 0, 0};
    for (int i = 0; i < d; ++i) x[i] = u[a * d + i];
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) {
        double Q = 0.0; /* Q = R3 R in 3D, R in 2D */
        for (int m = 0; m < 3; ++m) Q += (d == 3 ? R3[i][m] : (i == m ? 1.0 : 0.0)) * R[m][k];
        y[i] += Q * x[k];
      }
    const int is_normal = a >= es + em;
    for (int i = 0; i < d; ++i) v[a * d + i] = y[i] + (is_normal ? 0.0 : 1.5 + i);
  }
  fwd y0[TEST_MAX_OUT], y1[TEST_MAX_OUT];
  SK_CHECK(eval_pair(&c, u, 0, y0) == 0 && eval_pair(&c, v, 0, y1) == 0);
  double err = 0.0;
  for (int i = 0; i < n_outputs(&c); ++i) err = fmax(err, fabs(y0[i].v - y1[i].v));
  SK_CHECK(err < 1e-13);
}

/* ---- continuity where a clip-polygon vertex appears: a master edge crossing a slave corner ---------------------
 * The slave face (a planar trapezoid, so the inverse map and the integrand are not polynomial) has its corner
 * Q = (1, 1, 0) at the end of the edge from P = (1.2, 0, 0); the master quad's right edge crosses the line of PQ at
 * Q + s nu (nu: the edge's outward normal) at 0.2 rad to it. For s < 0 the edge runs inside the slave face and the
 * clip polygon has 4 vertices, for s > 0 it cuts PQ near Q and the polygon has a 5th vertex next to Q. Exact
 * integrals are continuous in s; the rule's over a fan about the mean of the vertices jumped by the quadrature
 * error, which stalled Newton on conforming 3D meshes (docs/plugins/mortar-dual.md, section 10). */
static void vertex_event_outputs(double s, int rule, mortar_basis basis, double *out) {
  const pair_case c = {3, &ft_quad4, &ft_quad4, basis, MODE_SEGMENTS, rule};
  const double xs[12] = {0, 0, 0, 0, 1, 0, 1, 1, 0, 1.2, 0, 0};
  double ns[12] = {0};
  for (int a = 0; a < 4; ++a) ns[3 * a + 2] = -1.0;
  const double P[2] = {1.2, 0.0}, Q[2] = {1.0, 1.0}, theta = 0.2;
  const double len = hypot(Q[0] - P[0], Q[1] - P[1]), d[2] = {(Q[0] - P[0]) / len, (Q[1] - P[1]) / len};
  const double nu[2] = {d[1], -d[0]}; /* outward: to the right of P -> Q */
  const double e[2] = {cos(theta) * d[0] - sin(theta) * d[1], sin(theta) * d[0] + cos(theta) * d[1]};
  const double X[2] = {Q[0] + s * nu[0], Q[1] + s * nu[1]};
  /* the master's right edge X - 1.5 e ... X + 0.5 e, its left edge at x = -0.4; counter-clockwise from above */
  const double xm[12] = {-0.4, X[1] - 1.5 * e[1], -0.05, X[0] - 1.5 * e[0], X[1] - 1.5 * e[1], -0.04,
                         X[0] + 0.5 * e[0], X[1] + 0.5 * e[1], -0.07, -0.4, X[1] + 0.5 * e[1], -0.05};
  mortar_pair p;
  mortar_integrals I;
  SK_CHECK(integrate_case(&c, xs, xm, ns, 0, &p, &I) == 0);
  int m = 0;
  for (int j = 0; j < 4; ++j) {
    for (int l = 0; l < 4; ++l) out[m++] = I.M[j][l].v;
    out[m++] = I.gap[j].v;
  }
}

static void check_vertex_event_continuity(void) {
  for (int basis = 0; basis < 2; ++basis)
    for (int r = 0; r < 2; ++r) {
      const int rule = r ? 6 : 3;
      double lo[20], hi[20], lo2[20], hi2[20];
      const double delta = 1e-10;
      vertex_event_outputs(-delta, rule, (mortar_basis)basis, lo);
      vertex_event_outputs(delta, rule, (mortar_basis)basis, hi);
      vertex_event_outputs(-1e-3, rule, (mortar_basis)basis, lo2);
      vertex_event_outputs(1e-3, rule, (mortar_basis)basis, hi2);
      double jump = 0.0, slope = 0.0;
      for (int i = 0; i < 20; ++i) {
        jump = fmax(jump, fabs(hi[i] - lo[i]));
        slope = fmax(slope, fabs(hi2[i] - lo2[i]) / 2e-3);
      }
      printf("  vertex event, %s basis, cell rule %d: |change| over s = +-1e-10: %.2e (slope %.2e)\n",
             basis ? "dual" : "standard", rule, jump, slope);
      SK_CHECK(jump < 1.5 * 2.0 * delta * slope + 1e-15); /* measured: 1.01 ... 1.03 times 2 delta slope */
    }
}

/* ---- sliver overlaps: the master face beside the slave face, over its edge by 1e-10 or less ----------------------
 * Faces that share an edge (a block on a base with matching nodes) overlap in slivers while Newton moves them. The
 * sliver's integrals are of the order of its area, and their derivatives of the order of its edges. A fan centre
 * that divides by the area (the area centroid) had derivatives of 1/area on the triangular slivers (measured: 8e2
 * and 6e4), and slider-3d's Newton turned linear. Checked: every derivative of M and the gap is bounded by the
 * faces' size (measured 0.83), the values by the sliver's area. */
static void check_sliver_derivatives(void) {
  const pair_case c = {3, &ft_quad4, &ft_quad4, MORTAR_DUAL, MODE_SEGMENTS, 6};
  const double xs[12] = {0, 0, 0, 0, 1, 0, 1, 1, 0, 1, 0, 0};
  double ns[12] = {0};
  for (int a = 0; a < 4; ++a) ns[3 * a + 2] = -1.0;
  /* the master's left edge from (1 - w0, 0) to (1 - w1, 1), beside the slave's right edge x = 1 */
  static const double w[3][2] = {{1e-11, 1e-11}, {1e-10, -1e-12}, {-1e-13, 1e-11}};
  for (int k = 0; k < 3; ++k) {
    const double xm[12] = {1 - w[k][0], 0, -0.01, 2, 0, -0.01, 2, 1, -0.01, 1 - w[k][1], 1, -0.01};
    mortar_pair p;
    mortar_integrals I;
    SK_CHECK(integrate_case(&c, xs, xm, ns, 1, &p, &I) == 0);
    double largest = 0.0, value = 0.0;
    for (int j = 0; j < 4; ++j) {
      for (int l = 0; l < 4; ++l) {
        value = fmax(value, fabs(I.M[j][l].v));
        for (int i = 0; i < I.M[j][l].n; ++i) largest = fmax(largest, fabs(I.M[j][l].d[i]));
      }
      for (int i = 0; i < I.gap[j].n; ++i) largest = fmax(largest, fabs(I.gap[j].d[i]));
    }
    printf("  sliver %g .. %g wide: |M| <= %.2e, largest derivative of M and the gap %.2e\n", w[k][0], w[k][1],
           value, largest);
    SK_CHECK(value > 0.0 && value <= 1.01 * fmax(fabs(w[k][0]), fabs(w[k][1]))); /* measured 1.0, 0.83, 0.83 times */
    SK_CHECK(largest < 1.0);
  }
}

int main(void) {
  test_face_types();
  check_quadrature();
  const double line[] = {0.1, 0.2, 0, 1.3, 0.7, 0};
  const double tri[] = {0, 0, 0, 1.2, 0.1, 0.2, 0.3, 0.9, -0.1};
  const double quad[] = {0, 0, 0, 1.3, -0.1, 0.0, 1.1, 1.2, 0.0, -0.2, 0.8, 0};
  const double warped[] = {0, 0, 0, 1.3, -0.1, 0.1, 1.1, 1.2, 0.3, -0.2, 0.8, 0};
  check_biorthogonality(&ft_line2, line, 1e-15);
  check_biorthogonality(&ft_tri3, tri, 1e-15);
  check_biorthogonality(&ft_quad4, quad, 1e-15);
  check_biorthogonality(&ft_quad4, warped, 3e-6); /* measured 2.1e-6 (face area 1.4) */
  /* LINE3 (gmsh order: ends, middle): straight with the middle node in the middle, straight with it moved by 10 % of
   * the length (a distorted parametrisation: N_j N_k J is not polynomial), a curved arc (30 degrees) */
  const double line3_straight[] = {0.1, 0.2, 0, 1.3, 0.7, 0, 0.7, 0.45, 0};
  const double line3_distorted[] = {0.1, 0.2, 0, 1.3, 0.7, 0, 0.82, 0.5, 0};
  double line3_arc[9];
  for (int a = 0; a < 3; ++a) {
    const double angle = (a == 2 ? 0.0 : a == 0 ? -1.0 : 1.0) * 3.14159265358979323846 / 12.0;
    line3_arc[3 * a] = 2.0 * sin(angle);
    line3_arc[3 * a + 1] = 2.0 * cos(angle);
    line3_arc[3 * a + 2] = 0.0;
  }
  check_biorthogonality(&ft_line3, line3_straight, 1e-15);
  check_biorthogonality(&ft_line3, line3_distorted, 1e-15); /* measured 3.9e-16 */
  check_biorthogonality(&ft_line3, line3_arc, 1e-15);       /* measured 1.5e-16 with the kernel's 10 points */
  check_patch();
  check_vertex_event_continuity();
  check_sliver_derivatives();

  const mortar_face_type *st3[] = {&ft_tri3, &ft_quad4, &ft_quad4, &ft_tri3};
  const mortar_face_type *mt3[] = {&ft_tri3, &ft_quad4, &ft_tri3, &ft_quad4};
  for (int basis = 0; basis < 2; ++basis) {
    char label[96];
    const mortar_basis b = (mortar_basis)basis;
    /* 2D pairs: slave, master, segment rule (LINE3: the plugin's default 5); points on LINE2 and LINE3 pairs */
    const struct { const mortar_face_type *s, *m; int segment_rule, points; } pairs2d[] = {
        {&ft_line2, &ft_line2, 3, 1}, {&ft_line3, &ft_line3, 5, 1}, {&ft_line3, &ft_line2, 5, 0}};
    for (int t = 0; t < 3; ++t) {
      const char *s_name = sk_elem_name(pairs2d[t].s->type), *m_name = sk_elem_name(pairs2d[t].m->type);
      snprintf(label, sizeof label, "2D segments %s/%s (%s)", s_name, m_name, basis ? "dual" : "standard");
      check_derivatives(label, (pair_case){2, pairs2d[t].s, pairs2d[t].m, b, MODE_SEGMENTS, pairs2d[t].segment_rule});
      for (int mode = MODE_POINTS_A; pairs2d[t].points && mode <= MODE_POINTS_M; ++mode) {
        snprintf(label, sizeof label, "2D points %s %s/%s (%s)", mode == MODE_POINTS_A ? "A" : "M", s_name, m_name,
                 basis ? "dual" : "standard");
        check_derivatives(label, (pair_case){2, pairs2d[t].s, pairs2d[t].m, b, (pair_mode)mode, 4});
      }
    }
    check_derivatives("2D obstacle plane", (pair_case){2, &ft_line2, NULL, b, MODE_OBSTACLE_PLANE, 3});
    check_derivatives("2D obstacle circle", (pair_case){2, &ft_line2, NULL, b, MODE_OBSTACLE_SPHERE, 3});
    for (int t = 0; t < 4; ++t) {
      snprintf(label, sizeof label, "3D segments %s/%s (%s)", sk_elem_name(st3[t]->type), sk_elem_name(mt3[t]->type),
               basis ? "dual" : "standard");
      check_derivatives(label, (pair_case){3, st3[t], mt3[t], (mortar_basis)basis, MODE_SEGMENTS, 7});
      snprintf(label, sizeof label, "3D points A %s/%s", sk_elem_name(st3[t]->type), sk_elem_name(mt3[t]->type));
      check_derivatives(label, (pair_case){3, st3[t], mt3[t], (mortar_basis)basis, MODE_POINTS_A, 3});
      snprintf(label, sizeof label, "3D points M %s/%s", sk_elem_name(st3[t]->type), sk_elem_name(mt3[t]->type));
      check_derivatives(label, (pair_case){3, st3[t], mt3[t], (mortar_basis)basis, MODE_POINTS_M, 3});
    }
    check_derivatives("3D obstacle sphere quad4", (pair_case){3, &ft_quad4, NULL, b, MODE_OBSTACLE_SPHERE, 3});
    check_derivatives("3D obstacle sphere tri3", (pair_case){3, &ft_tri3, NULL, b, MODE_OBSTACLE_SPHERE, 3});
    check_rigid_motion((pair_case){2, &ft_line2, &ft_line2, (mortar_basis)basis, MODE_SEGMENTS, 3});
    check_rigid_motion((pair_case){2, &ft_line3, &ft_line3, (mortar_basis)basis, MODE_SEGMENTS, 5});
    check_rigid_motion((pair_case){3, &ft_quad4, &ft_tri3, (mortar_basis)basis, MODE_SEGMENTS, 7});
    check_rigid_motion((pair_case){3, &ft_tri3, &ft_quad4, (mortar_basis)basis, MODE_POINTS_A, 3});
  }
  return sk_test_finish("test_mortar_integrals");
}
