/* mortar-dual kernel: segment-based integration in 3D — auxiliary plane, polygon clipping, triangulation
 * (Puso & Laursen 2004; Popp, Gitterle, Gee, Wall 2010). Every step in fwd arithmetic, so the integration cells
 * carry their derivatives with respect to the pair's coordinates and normals (kernel.h). */
#include <math.h>
#include <string.h>

#include "kernel.h"
#include "kernel_internal.h"

typedef struct {
  fwd x[2];
} vertex;

static fwd cross_edge(const vertex *a, const vertex *b, const vertex *p) {
  fwd e[2] = {fwd_sub(b->x[0], a->x[0]), fwd_sub(b->x[1], a->x[1])};
  fwd r[2] = {fwd_sub(p->x[0], a->x[0]), fwd_sub(p->x[1], a->x[1])};
  return fwd_cross2(e, r);
}

static fwd polygon_area(const vertex *v, int n) {
  fwd s = fwd_const(0.0);
  for (int i = 0; i < n; ++i) {
    const vertex *a = &v[i], *b = &v[(i + 1) % n];
    s = fwd_add(s, fwd_sub(fwd_mul(a->x[0], b->x[1]), fwd_mul(b->x[0], a->x[1])));
  }
  return fwd_scale(0.5, s);
}

/* Two vertices this close to a clip edge's line (signed area over the squared edge length) lie on it. Measured
 * window: 1e-13 left round-off pairs on the tetrahedral patch test (MUMPS: singular); 1e-11 moved the residual by
 * 1e-11 of the contact forces when a pair entered the band, and the sliding slider-3d at mu = 1 stalled at
 * ||F|| = 2.5e-8 against its tolerance 1e-8 (stress_mu-range-3d). */
static const double kOnClipLine = 1e-12;

/* Sutherland-Hodgman: the polygon `poly` (any) clipped by the convex counter-clockwise polygon `clip`. Returns the
 * number of vertices of the result in `out` (capacity MORTAR_MAX_POLY). */
static int clip_polygon(const vertex *poly, int n_poly, const vertex *clip, int n_clip, vertex *out) {
  vertex buf[2][MORTAR_MAX_POLY];
  int n = n_poly;
  memcpy(buf[0], poly, sizeof(vertex) * (size_t)n_poly);
  int cur = 0;
  for (int e = 0; e < n_clip && n > 0; ++e) {
    const vertex *a = &clip[e], *b = &clip[(e + 1) % n_clip];
    const vertex *in = buf[cur];
    vertex *res = buf[1 - cur];
    /* Two consecutive vertices both within round-off of the clip line (faces that share a boundary line, a block's
     * side, put whole edges there) are both on it, hence inside: their intersection divides by the difference of two
     * round-offs — harmless in value, but its derivative (1/difference^2) put 1e22 into the tangent. A single vertex
     * near the line keeps the exact test: its intersection with a far neighbour is well conditioned. */
    const double ex = b->x[0].v - a->x[0].v, ey = b->x[1].v - a->x[1].v;
    const double on_line = kOnClipLine * (ex * ex + ey * ey);
    int m = 0;
    for (int i = 0; i < n; ++i) {
      const vertex *p = &in[(i + n - 1) % n], *q = &in[i];
      const fwd sp = cross_edge(a, b, p), sq = cross_edge(a, b, q);
      const int both_on_line = fabs(sp.v) <= on_line && fabs(sq.v) <= on_line;
      const int p_in = both_on_line || sp.v >= 0.0, q_in = both_on_line || sq.v >= 0.0;
      if (p_in != q_in && m < MORTAR_MAX_POLY) {
        const fwd t = fwd_div(sp, fwd_sub(sp, sq));
        for (int k = 0; k < 2; ++k) res[m].x[k] = fwd_add(p->x[k], fwd_mul(t, fwd_sub(q->x[k], p->x[k])));
        ++m;
      }
      if (q_in && m < MORTAR_MAX_POLY) res[m++] = *q;
    }
    n = m;
    cur = 1 - cur;
  }
  memcpy(out, buf[cur], sizeof(vertex) * (size_t)n);
  return n;
}

/* Parameters xi of the face point that projects along n0 onto the plane point (p0, p1):
 * F_alpha(xi) = (x(xi) - x0) . t_alpha - p_alpha = 0. Newton on values, derivatives by the implicit function
 * theorem. Returns 0, or -1 if it fails. */
static int plane_parameters(const mortar_face_type *ft, fwd x[][3], const fwd *x0, fwd t[2][3], const vertex *pt,
                            fwd xi[2]) {
  double xv[2] = {ft->type == SK_TRI3 ? 1.0 / 3.0 : 0.0, ft->type == SK_TRI3 ? 1.0 / 3.0 : 0.0};
  double J[4];
  for (int it = 0; it < 40; ++it) {
    double pos[3], a[2][3], aa[2][2][3], F[2];
    mortar_face_values(ft, x, xv, pos, a, aa);
    for (int al = 0; al < 2; ++al) {
      double v = -pt->x[al].v;
      for (int i = 0; i < 3; ++i) v += (pos[i] - x0[i].v) * t[al][i].v;
      F[al] = -v;
      for (int be = 0; be < 2; ++be) {
        double s = 0.0;
        for (int i = 0; i < 3; ++i) s += a[be][i] * t[al][i].v;
        J[al * 2 + be] = s;
      }
    }
    if (mortar_solve_small(2, J, F, 1) != 0) return -1;
    xv[0] += F[0];
    xv[1] += F[1];
    if (!isfinite(xv[0]) || fabs(xv[0]) > 1e3 || fabs(xv[1]) > 1e3) return -1;
    if (fabs(F[0]) < 1e-14 && fabs(F[1]) < 1e-14) break;
  }
  const fwd xc[2] = {fwd_const(xv[0]), fwd_const(xv[1])};
  fwd pos[3], a[2][3], diff[3], r[2];
  mortar_face_point(ft, x, xc, pos, a);
  for (int i = 0; i < 3; ++i) diff[i] = fwd_sub(pos[i], x0[i]);
  for (int al = 0; al < 2; ++al) {
    r[al] = fwd_sub(fwd_dot(3, diff, t[al]), pt->x[al]);
    for (int be = 0; be < 2; ++be) J[al * 2 + be] = fwd_dot(3, a[be], t[al]).v;
  }
  return mortar_implicit(2, J, r, xv, xi);
}

/* A cheap test on values: do the boxes of two node sets (slave node positions xs with normals ns, master node
 * positions xm; 3 values per node) in the auxiliary plane (the slave nodes' plane at their centre, coordinates along
 * two in-plane axes) overlap? Most candidate pairs of the broad phase do not, nor most quarter pairs of QUAD9 faces. */
static int plane_boxes_overlap(const double *xs, const double *ns, int n_s, const double *xm, int n_m) {
  double c[3] = {0, 0, 0}, n[3] = {0, 0, 0};
  const double w = 1.0 / n_s;
  for (int a = 0; a < n_s; ++a)
    for (int i = 0; i < 3; ++i) {
      c[i] += w * xs[3 * a + i];
      n[i] += w * ns[3 * a + i];
    }
  /* in-plane axes: the first slave edge and n x it */
  double e[3], t2[3];
  for (int i = 0; i < 3; ++i) e[i] = xs[3 + i] - xs[i];
  const double nn = n[0] * n[0] + n[1] * n[1] + n[2] * n[2], en = (e[0] * n[0] + e[1] * n[1] + e[2] * n[2]) / nn;
  for (int i = 0; i < 3; ++i) e[i] -= en * n[i];
  t2[0] = n[1] * e[2] - n[2] * e[1];
  t2[1] = n[2] * e[0] - n[0] * e[2];
  t2[2] = n[0] * e[1] - n[1] * e[0];
  double lo[2][2] = {{INFINITY, INFINITY}, {INFINITY, INFINITY}};
  double hi[2][2] = {{-INFINITY, -INFINITY}, {-INFINITY, -INFINITY}};
  for (int side = 0; side < 2; ++side) {
    const int count = side ? n_m : n_s;
    for (int a = 0; a < count; ++a) {
      double d[3], u[2] = {0, 0};
      for (int i = 0; i < 3; ++i) d[i] = (side ? xm : xs)[3 * a + i] - c[i];
      for (int i = 0; i < 3; ++i) {
        u[0] += d[i] * e[i];
        u[1] += d[i] * t2[i];
      }
      for (int k = 0; k < 2; ++k) {
        lo[side][k] = fmin(lo[side][k], u[k]);
        hi[side][k] = fmax(hi[side][k], u[k]);
      }
    }
  }
  /* generous: this plane is not exactly the clip's (centre of the nodes, mean normal), and a rejected pair whose true
   * overlap is a sliver would make its (tiny) contribution jump */
  const double tol = 0.05 * (hi[0][0] - lo[0][0] + hi[0][1] - lo[0][1]);
  return lo[1][0] <= hi[0][0] + tol && lo[0][0] <= hi[1][0] + tol && lo[1][1] <= hi[0][1] + tol &&
         lo[0][1] <= hi[1][1] + tol;
}

/* A flat facet of a face: the face itself (first-order faces), or one of a QUAD9 or QUAD8 face's four bilinear quarters
 * or a TRI6 face's four sub-triangles (Popp, Wohlmuth, Gee & Wall 2012: the integration cells of quadratic faces are
 * built on linear sub-facets). Its parameters s map onto the face's as xi = c + h s; its nodes are face nodes (or
 * QUAD8's centre, a combination of them), so their positions carry the pair's derivative slots. xv, nv: the nodes'
 * positions and (slave) normals as values, for the box test. */
typedef struct {
  const mortar_face_type *ft; /* the facet's own type (the face's, QUAD4 or TRI3) */
  int n;                      /* its nodes */
  fwd x[4][3];
  double xv[4 * 3], nv[4 * 3];
  double c[2], h;
} facet;

/* The flat sub-facets of a second-order face: per sub-facet its face nodes (counter-clockwise), the face parameters c
 * of its own origin and the scale h of xi = c + h s. QUAD9 and QUAD8: four quarters (quad4, origin at each quarter's
 * centre; node 8 is QUAD9's centre node, and on QUAD8 the serendipity map's point at xi = 0). TRI6: four
 * sub-triangles (tri3, the first node at xi = c, the others at c + h (1, 0), c + h (0, 1)); the middle one is the
 * corner ones turned half a turn (h = -1/2). */
typedef struct {
  int node[4][4];
  double c[4][2], h[4];
} sub_facets;
static const sub_facets quad9_quarters = {{{0, 4, 8, 7}, {4, 1, 5, 8}, {8, 5, 2, 6}, {7, 8, 6, 3}},
                                          {{-0.5, -0.5}, {0.5, -0.5}, {0.5, 0.5}, {-0.5, 0.5}},
                                          {0.5, 0.5, 0.5, 0.5}};
static const sub_facets tri6_triangles = {{{0, 3, 5}, {3, 1, 4}, {5, 4, 2}, {4, 5, 3}},
                                          {{0, 0}, {0.5, 0}, {0, 0.5}, {0.5, 0.5}},
                                          {0.5, 0.5, 0.5, -0.5}};

/* The facets of one side's face (node positions x; slave: its normals ns, else NULL): 1 (the face) or 4 (QUAD9 and
 * QUAD8 quarters of type quad4, TRI6 sub-triangles of type tri3). QUAD8 has no centre node: its quarters meet at the
 * face's own point x(0, 0) = sum_a N_a(0, 0) x_a (-1/4 of each corner, 1/2 of each mid-side node), with the slave
 * normal interpolated there, so the quarters tile the face's parameter square and are exact on flat faces with the
 * mid-side nodes in the middles, as QUAD9's. */
static int face_facets(const mortar_face_type *ft, const mortar_face_type *quad4, const mortar_face_type *tri3,
                       fwd x[][3], const fwd ns[][3], facet *out) {
  const int nen = ft->nen;
  fwd centre[3] = {fwd_const(0.0), fwd_const(0.0), fwd_const(0.0)};
  double n_centre[3] = {0, 0, 0};
  if (ft->type == SK_QUAD8) {
    const fwd xi0[2] = {fwd_const(0.0), fwd_const(0.0)};
    fwd N[MORTAR_MAX_NEN];
    mortar_face_point(ft, x, xi0, centre, NULL);
    mortar_shape(ft, xi0, N, NULL);
    for (int a = 0; ns && a < nen; ++a)
      for (int i = 0; i < 3; ++i) n_centre[i] += N[a].v * ns[a][i].v;
  }
  if (ft->type != SK_QUAD9 && ft->type != SK_QUAD8 && ft->type != SK_TRI6) {
    out->ft = ft;
    out->n = nen;
    memcpy(out->x, x, sizeof(fwd) * 3 * (size_t)nen);
    for (int k = 0; k < nen; ++k)
      for (int i = 0; i < 3; ++i) {
        out->xv[3 * k + i] = x[k][i].v;
        out->nv[3 * k + i] = ns ? ns[k][i].v : 0.0;
      }
    out->c[0] = out->c[1] = 0.0;
    out->h = 1.0;
    return 1;
  }
  const sub_facets *sub = ft->type == SK_TRI6 ? &tri6_triangles : &quad9_quarters;
  const mortar_face_type *sub_type = ft->type == SK_TRI6 ? tri3 : quad4;
  for (int q = 0; q < 4; ++q) {
    out[q].ft = sub_type;
    out[q].n = sub_type->nen;
    for (int k = 0; k < sub_type->nen; ++k) {
      const int a = sub->node[q][k], virtual_centre = a == nen; /* QUAD8's centre */
      memcpy(out[q].x[k], virtual_centre ? centre : x[a], sizeof(fwd) * 3);
      for (int i = 0; i < 3; ++i) {
        out[q].xv[3 * k + i] = out[q].x[k][i].v;
        out[q].nv[3 * k + i] = virtual_centre ? n_centre[i] : ns ? ns[a][i].v : 0.0;
      }
    }
    out[q].c[0] = sub->c[q][0];
    out[q].c[1] = sub->c[q][1];
    out[q].h = sub->h[q];
  }
  return 4;
}

/* The face parameters of a facet's parameters. */
static void facet_to_face(const facet *f, const fwd s[2], fwd xi[2]) {
  for (int k = 0; k < 2; ++k) {
    xi[k] = f->h == 1.0 ? s[k] : fwd_scale(f->h, s[k]);
    xi[k].v += f->c[k];
  }
}

/* One slave facet against one master facet: the auxiliary plane, the clip and its cells (mortar_segments_3d).
 * Returns 1 if they overlap. */
static int facet_pair(const mortar_pair *p, const mortar_basis_coeffs *A, mortar_basis basis, int rule, facet *sf,
                      facet *mf, fwd xs[][3], fwd xm[][3], mortar_integrals *I) {
  const mortar_face_type *st = p->slave, *mt = p->master, *sft = sf->ft, *mft = mf->ft;
  const int nen_sf = sft->nen, nen_mf = mft->nen;
  fwd(*sx)[3] = sf->x, (*mx)[3] = mf->x;
  /* auxiliary plane: the slave facet's centre x0 and the unit interpolated slave normal n0 there */
  const double centre = sft->type == SK_TRI3 ? 1.0 / 3.0 : 0.0;
  const fwd sc[2] = {fwd_const(centre), fwd_const(centre)};
  fwd xc[2], N[MORTAR_MAX_NEN], x0[3], nc[3], n0[3], t[2][3];
  facet_to_face(sf, sc, xc);
  mortar_shape(st, xc, N, NULL);
  mortar_face_point(sft, sx, sc, x0, NULL);
  mortar_slave_normal(p, N, nc);
  const fwd nlen = fwd_norm(3, nc);
  for (int i = 0; i < 3; ++i) n0[i] = fwd_div(nc[i], nlen);
  /* facets must face each other: the master facet's outward normal at its centre against n0 */
  {
    const double mc = mft->type == SK_TRI3 ? 1.0 / 3.0 : 0.0;
    const fwd xmc[2] = {fwd_const(mc), fwd_const(mc)};
    fwd a[2][3], nm[3];
    mortar_face_point(mft, mx, xmc, NULL, a);
    mortar_face_normal(3, 2, a, nm);
    if (fwd_dot(3, nm, n0).v >= 0.0) return 0;
  }
  /* in-plane basis: t1 along the first slave facet edge, projected; t2 = n0 x t1 */
  fwd e[3];
  for (int i = 0; i < 3; ++i) e[i] = fwd_sub(sx[1][i], sx[0][i]);
  const fwd en = fwd_dot(3, e, n0);
  for (int i = 0; i < 3; ++i) e[i] = fwd_sub(e[i], fwd_mul(en, n0[i]));
  const fwd elen = fwd_norm(3, e);
  for (int i = 0; i < 3; ++i) t[0][i] = fwd_div(e[i], elen);
  fwd_cross3(n0, t[0], t[1]);
  /* both facets in plane coordinates, counter-clockwise about n0 (the master's order reversed) */
  vertex sp[4], mp[4], cell[MORTAR_MAX_POLY];
  for (int k = 0; k < nen_sf; ++k) {
    fwd d[3];
    for (int i = 0; i < 3; ++i) d[i] = fwd_sub(sx[k][i], x0[i]);
    for (int al = 0; al < 2; ++al) sp[k].x[al] = fwd_dot(3, d, t[al]);
  }
  for (int k = 0; k < nen_mf; ++k) {
    fwd d[3];
    for (int i = 0; i < 3; ++i) d[i] = fwd_sub(mx[nen_mf - 1 - k][i], x0[i]);
    for (int al = 0; al < 2; ++al) mp[k].x[al] = fwd_dot(3, d, t[al]);
  }
  const double area_s = polygon_area(sp, nen_sf).v;
  if (!(area_s > 0.0) || !(polygon_area(mp, nen_mf).v > 0.0)) return 0;
  int n = clip_polygon(mp, nen_mf, sp, nen_sf, cell);
  /* drop (nearly) coincident consecutive vertices: a master vertex on a slave edge appears twice */
  const double tol2 = 1e-24 * area_s;
  int m = 0;
  for (int i = 0; i < n; ++i) {
    const vertex *prev = m > 0 ? &cell[m - 1] : NULL;
    const double dx = prev ? cell[i].x[0].v - prev->x[0].v : 1.0, dy = prev ? cell[i].x[1].v - prev->x[1].v : 1.0;
    if (dx * dx + dy * dy > tol2) cell[m++] = cell[i];
  }
  while (m > 1) {
    const double dx = cell[m - 1].x[0].v - cell[0].x[0].v, dy = cell[m - 1].x[1].v - cell[0].x[1].v;
    if (dx * dx + dy * dy > tol2) break;
    --m;
  }
  n = m;
  if (n < 3 || !(polygon_area(cell, n).v > 1e-12 * area_s)) return 0;
  /* triangles about the centre of the polygon's perimeter (its edges' midpoints weighted by their lengths). Not the
   * mean of its vertices: a vertex appears or vanishes where a master edge crosses a slave corner, and the mean then
   * jumps; the rule is not exact for the integrand, so the integrals jumped by the quadrature error (Newton cycled at
   * 1e-9 of the first residual where slave edges lie on master edges). A vertex on its neighbours' line or on a
   * neighbour does not move the perimeter's centre, so the fan changes only by a triangle of zero area. Not the area
   * centroid either, which does the same but divides by the area: on the slivers of faces that share an edge its
   * derivative is 1/area large, and the tangent lost its digits (measured: Newton linear on slider-3d). */
  vertex c;
  {
    fwd perimeter = fwd_const(0.0), moment[2] = {fwd_const(0.0), fwd_const(0.0)};
    for (int i = 0; i < n; ++i) {
      const vertex *a = &cell[i], *b = &cell[(i + 1) % n];
      const fwd edge[2] = {fwd_sub(b->x[0], a->x[0]), fwd_sub(b->x[1], a->x[1])};
      const fwd len = fwd_norm(2, edge); /* > 0: coincident vertices were merged above */
      perimeter = fwd_add(perimeter, len);
      for (int al = 0; al < 2; ++al) moment[al] = fwd_add(moment[al], fwd_mul(len, fwd_add(a->x[al], b->x[al])));
    }
    for (int al = 0; al < 2; ++al) c.x[al] = fwd_div(moment[al], fwd_scale(2.0, perimeter));
  }
  const double *rxi = NULL, *rw = NULL; /* set by the rule (cell_rule is checked at create) */
  const int nq = mortar_triangle_rule(rule, &rxi, &rw);
  for (int tri = 0; tri < n; ++tri) {
    const vertex *a = &cell[tri], *b = &cell[(tri + 1) % n];
    fwd ea[2] = {fwd_sub(a->x[0], c.x[0]), fwd_sub(a->x[1], c.x[1])};
    fwd eb[2] = {fwd_sub(b->x[0], c.x[0]), fwd_sub(b->x[1], c.x[1])};
    const fwd jac_cell = fwd_cross2(ea, eb); /* twice the triangle's area */
    if (!(jac_cell.v > 0.0)) continue;
    for (int q = 0; q < nq; ++q) {
      vertex g;
      for (int al = 0; al < 2; ++al)
        g.x[al] = fwd_add(c.x[al], fwd_lin(rxi[2 * q], ea[al], rxi[2 * q + 1], eb[al]));
      fwd s1[2], s2[2], xi1[2], xi2[2];
      if (plane_parameters(sft, sx, x0, t, &g, s1) != 0 || plane_parameters(mft, mx, x0, t, &g, s2) != 0) continue;
      facet_to_face(sf, s1, xi1);
      facet_to_face(mf, s2, xi2);
      fwd N1[MORTAR_MAX_NEN], N2[MORTAR_MAX_NEN], x1[3], a1[2][3], b1[2][3], x2[3], n1[3], c1[3], diff[3];
      mortar_shape(st, xi1, N1, NULL);
      mortar_shape(mt, xi2, N2, NULL);
      mortar_face_point(st, xs, xi1, x1, a1);
      /* the facet's tangents (the face's own on a first-order face) */
      if (sf->h == 1.0) memcpy(b1, a1, sizeof b1);
      else mortar_face_point(sft, sx, s1, NULL, b1);
      for (int i = 0; i < 3; ++i) { /* x2 = sum_l N_l x_l */
        fwd_set_mul(&x2[i], &N2[0], &xm[0][i]);
        for (int l = 1; l < p->nen_m; ++l) fwd_acc_mul(&x2[i], &N2[l], &xm[l][i]);
      }
      mortar_slave_normal(p, N1, n1);
      /* slave surface measure: dgamma = |a1 x a2| h^2 / |det(b_beta . t_alpha)| dA (the plane's area element through
       * the facet's parameters to the face's; a first-order face is its own facet, h = 1) */
      fwd_cross3(a1[0], a1[1], c1);
      const fwd det = fwd_sub(fwd_mul(fwd_dot(3, b1[0], t[0]), fwd_dot(3, b1[1], t[1])),
                              fwd_mul(fwd_dot(3, b1[1], t[0]), fwd_dot(3, b1[0], t[1])));
      fwd ratio = fwd_div(fwd_norm(3, c1), det.v < 0.0 ? fwd_neg(det) : det);
      if (sf->h != 1.0) ratio = fwd_scale(sf->h * sf->h, ratio);
      for (int i = 0; i < 3; ++i) diff[i] = fwd_sub(x2[i], x1[i]);
      const fwd g_n = fwd_div(fwd_dot(3, diff, n1), fwd_norm(3, n1));
      const fwd weight = fwd_mul(fwd_scale(rw[q], jac_cell), ratio);
      mortar_add_point_shapes(p, A, basis, N1, N2, &weight, &g_n, I);
    }
    I->n_cells += 1;
  }
  return 1;
}

int mortar_segments_3d(const mortar_pair *p, const mortar_basis_coeffs *A, mortar_basis basis, int rule,
                       mortar_integrals *I) {
  fwd xs[MORTAR_MAX_NEN][3], xm[MORTAR_MAX_NEN][3];
  mortar_face_type quad4_s, quad4_m, tri3_s, tri3_m;
  mortar_face_type_init(&quad4_s, SK_QUAD4, p->slave->shape, p->slave->shape_hessian);
  mortar_face_type_init(&quad4_m, SK_QUAD4, p->master->shape, p->master->shape_hessian);
  mortar_face_type_init(&tri3_s, SK_TRI3, p->slave->shape, p->slave->shape_hessian);
  mortar_face_type_init(&tri3_m, SK_TRI3, p->master->shape, p->master->shape_hessian);
  /* the whole faces' box test first, on values */
  {
    double vs[MORTAR_MAX_NEN * 3], vn[MORTAR_MAX_NEN * 3], vm[MORTAR_MAX_NEN * 3];
    for (int a = 0; a < p->nen_s; ++a)
      for (int i = 0; i < 3; ++i) {
        vs[3 * a + i] = p->xs[a][i].v;
        vn[3 * a + i] = p->ns[a][i].v;
      }
    for (int b = 0; b < p->nen_m; ++b)
      for (int i = 0; i < 3; ++i) vm[3 * b + i] = p->xm[b][i].v;
    if (!plane_boxes_overlap(vs, vn, p->nen_s, vm, p->nen_m)) return 0;
  }
  memcpy(xs, p->xs, sizeof(fwd) * 3 * (size_t)p->nen_s);
  memcpy(xm, p->xm, sizeof(fwd) * 3 * (size_t)p->nen_m);
  facet sf[4], mf[4];
  const int n_s = face_facets(p->slave, &quad4_s, &tri3_s, xs, p->ns, sf);
  const int n_m = face_facets(p->master, &quad4_m, &tri3_m, xm, NULL, mf);
  int overlap = 0;
  for (int a = 0; a < n_s; ++a)
    for (int b = 0; b < n_m; ++b)
      if ((n_s == 1 && n_m == 1) || plane_boxes_overlap(sf[a].xv, sf[a].nv, sf[a].n, mf[b].xv, mf[b].n))
        overlap |= facet_pair(p, A, basis, rule, &sf[a], &mf[b], xs, xm, I);
  return overlap;
}
