/* Closest-point projection onto a contact surface (narrow phase).
 *
 * Per candidate face: Newton on the orthogonality conditions R_a = (x - x(xi)) . a_a = 0 with the full Hessian
 * A_ab = m_ab - (x - x(xi)) . x,ab. A step that would leave the face stops on the edge it crosses; from there the
 * iterate moves on to the neighbouring face, or, at a border (or a ridge it would only bounce back from), slides
 * along the edge. The best candidate is the closest; a result on a shared edge or corner is then handed to the
 * lowest face id that carries it, so the answer does not depend on the candidate list or the start face. */
#include <float.h>
#include <math.h>
#include <string.h>

#include "contact_internal.h"
#include "stickslip/contact.h"

enum {
  PROJECT_MAX_ITERATIONS = 60,
  PROJECT_MAX_SWITCHES = 32, /* face changes per local projection */
  RING_MAX = 64              /* faces walked around a vertex */
};
static const double ON_EDGE_TOL = 1e-13;   /* xi this close to an edge is on it (for the iteration) */
static const double CLASSIFY_TOL = 1e-10;  /* xi this close to an edge is reported EDGE / VERTEX */
static const double STEP_TOL = 1e-13;      /* converged when the accepted step in xi is below this, */
static const double ROUNDOFF_STEPS = 16.0; /* or below this many round-offs of the point's coordinates over |a| */
static const double TIE_TOL = 1e-12;       /* relative distance difference treated as a tie */

typedef struct {
  int face;
  double xi[2];
  int iterations;
  int converged;
} local_result;

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static const int *face_conn(const sk_surface *s, int face) { return s->conn + (size_t)face * s->nen; }

/* Moves a point on edge `edge` of `face` to the same point of neighbour `next`; returns the edge of `next` that it
 * lies on, or -1 if the two faces do not share that edge (an inconsistent adjacency). */
static int map_across_edge(const sk_surface *s, const sk_face_domain *dom, int face, int edge, const double *xi,
                           int next, double *next_xi) {
  const int *c = face_conn(s, face), *cn = face_conn(s, next);
  const int ne = s->n_edges;
  if (dom->pdim == 1) {
    for (int k = 0; k < 2; ++k)
      if (cn[k] == c[edge]) {
        next_xi[0] = dom->corner[k][0];
        next_xi[1] = 0.0;
        return k;
      }
    return -1;
  }
  const int a = c[edge], b = c[(edge + 1) % ne];
  const double *c0 = dom->corner[edge], *c1 = dom->corner[(edge + 1) % ne];
  double d[2] = {c1[0] - c0[0], c1[1] - c0[1]};
  double t = ((xi[0] - c0[0]) * d[0] + (xi[1] - c0[1]) * d[1]) / (d[0] * d[0] + d[1] * d[1]);
  t = fmin(1.0, fmax(0.0, t));
  for (int e = 0; e < ne; ++e) {
    int na = cn[e], nb = cn[(e + 1) % ne];
    if ((na == a && nb == b) || (na == b && nb == a)) {
      double u = na == a ? t : 1.0 - t; /* Lagrange edges are parametrised linearly from either side */
      const double *e0 = dom->corner[e], *e1 = dom->corner[(e + 1) % ne];
      next_xi[0] = e0[0] + u * (e1[0] - e0[0]);
      next_xi[1] = e0[1] + u * (e1[1] - e0[1]);
      return e;
    }
  }
  return -1;
}

/* Solves the 1x1 or 2x2 system A dxi = R; falls back to the metric (a Gauss-Newton step) when A is not positive
 * definite, which happens far from strongly curved faces. */
static void newton_step(int pdim, const double A[2][2], const double m[2][2], const double *R, double *dxi) {
  if (pdim == 1) {
    double a = A[0][0] > 0.0 ? A[0][0] : m[0][0];
    dxi[0] = a > 0.0 ? R[0] / a : 0.0;
    dxi[1] = 0.0;
    return;
  }
  double det = A[0][0] * A[1][1] - A[0][1] * A[1][0];
  const double(*M)[2] = A;
  if (!(A[0][0] > 0.0 && det > 0.0)) {
    M = m;
    det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
  }
  if (!(det > 0.0)) {
    dxi[0] = dxi[1] = 0.0;
    return;
  }
  dxi[0] = (M[1][1] * R[0] - M[0][1] * R[1]) / det;
  dxi[1] = (M[0][0] * R[1] - M[1][0] * R[0]) / det;
}

/* Restricts the step to edge `edge` (a 1D Newton along it); in 2D (pdim 1) an end point admits no motion. */
static void constrain_to_edge(const sk_face_domain *dom, int edge, const double A[2][2], const double m[2][2],
                              const double *R, double *dxi) {
  if (dom->pdim == 1) {
    dxi[0] = dxi[1] = 0.0;
    return;
  }
  const double *c0 = dom->corner[edge], *c1 = dom->corner[(edge + 1) % dom->n_corners];
  double d[2] = {c1[0] - c0[0], c1[1] - c0[1]};
  double dAd = d[0] * (A[0][0] * d[0] + A[0][1] * d[1]) + d[1] * (A[1][0] * d[0] + A[1][1] * d[1]);
  if (!(dAd > 0.0)) dAd = d[0] * (m[0][0] * d[0] + m[0][1] * d[1]) + d[1] * (m[1][0] * d[0] + m[1][1] * d[1]);
  double s = dAd > 0.0 ? (d[0] * R[0] + d[1] * R[1]) / dAd : 0.0;
  dxi[0] = s * d[0];
  dxi[1] = s * d[1];
}

static void residual_and_hessian(int pdim, const sk_surface_point *p, const double *x, double *r, double R[2],
                                 double A[2][2]) {
  for (int i = 0; i < 3; ++i) r[i] = x[i] - p->x[i];
  for (int k = 0; k < 2; ++k) {
    R[k] = k < pdim ? dot3(r, p->a[k]) : 0.0;
    for (int l = 0; l < 2; ++l)
      A[k][l] = (k < pdim && l < pdim) ? p->m[k][l] - dot3(r, p->a_ab[k][l]) : (k == l ? 1.0 : 0.0);
  }
}

static void project_local(const sk_surface *s, const sk_face_domain *dom, const double *q, const double *x,
                          int start_face, local_result *out) {
  const int pdim = dom->pdim, ne = s->n_edges;
  int face = start_face, previous_face = -1, entry_edge = -1, switches = 0;
  double xi[2] = {dom->centre[0], dom->centre[1]};
  sk_surface_point p;
  out->converged = 0;
  int it;
  for (it = 1; it <= PROJECT_MAX_ITERATIONS; ++it) {
    double r[3], R[2], A[2][2], dxi[2];
    sk_surface_geometry(s, face, xi, q, &p);
    residual_and_hessian(pdim, &p, x, r, R, A);
    newton_step(pdim, A, p.m, R, dxi);

    /* Edges the iterate sits on and the step would cross: move to the neighbour, or slide along the edge. */
    int blocked = 0, switched = 0;
    for (int e = 0; e < ne && !switched; ++e) {
      if (sk_face_edge_value(dom, e, xi) > ON_EDGE_TOL) continue;
      double out_rate = dom->edge_w[e][0] * dxi[0] + (pdim == 2 ? dom->edge_w[e][1] * dxi[1] : 0.0);
      if (out_rate >= 0.0) continue;
      int next = s->face_neighbors[(size_t)face * ne + e];
      int bounce = next == previous_face && e == entry_edge; /* a ridge: the neighbour would send us back */
      if (next >= 0 && !bounce && switches < PROJECT_MAX_SWITCHES) {
        double next_xi[2];
        int next_edge = map_across_edge(s, dom, face, e, xi, next, next_xi);
        if (next_edge >= 0) {
          previous_face = face;
          entry_edge = next_edge;
          face = next;
          xi[0] = next_xi[0];
          xi[1] = next_xi[1];
          ++switches;
          switched = 1;
          continue;
        }
      }
      if (++blocked > 1) {
        dxi[0] = dxi[1] = 0.0; /* held in a corner */
      } else {
        constrain_to_edge(dom, e, A, p.m, R, dxi);
        e = -1; /* recheck the other edges against the constrained step */
      }
    }
    if (switched) continue;

    /* Stop at the first edge the step crosses, exactly on it. */
    double t = 1.0;
    int hit = -1;
    for (int e = 0; e < ne; ++e) {
      double rate = dom->edge_w[e][0] * dxi[0] + (pdim == 2 ? dom->edge_w[e][1] * dxi[1] : 0.0);
      if (rate >= 0.0) continue;
      double te = -sk_face_edge_value(dom, e, xi) / rate;
      if (te < t) {
        t = fmax(te, 0.0);
        hit = e;
      }
    }
    xi[0] += t * dxi[0];
    xi[1] += t * dxi[1];
    if (hit >= 0) {
      const double *w = dom->edge_w[hit];
      double g = sk_face_edge_value(dom, hit, xi), ww = w[0] * w[0] + (pdim == 2 ? w[1] * w[1] : 0.0);
      xi[0] -= g * w[0] / ww;
      if (pdim == 2) xi[1] -= g * w[1] / ww;
    }
    double step = t * sqrt(dxi[0] * dxi[0] + dxi[1] * dxi[1]);
    /* R = (x - x(xi)) . a carries round-off eps |x| |a|, so the step in xi is noise below eps |x| / |a|: on a face
     * 4e-4 long at x = 1 that is 5e-13, above STEP_TOL (a graded patch test never converged, xi right to 1e-12). */
    double a_min = sqrt(pdim == 2 ? fmin(p.m[0][0], p.m[1][1]) : p.m[0][0]);
    double scale = fmax(fabs(x[0]), fmax(fabs(x[1]), fabs(x[2])));
    double step_tol = a_min > 0.0 ? fmax(STEP_TOL, ROUNDOFF_STEPS * DBL_EPSILON * scale / a_min) : STEP_TOL;
    if (step <= step_tol && hit < 0) {
      out->converged = 1;
      break;
    }
    if (step <= step_tol && blocked) {
      out->converged = 1;
      break;
    }
  }
  out->face = face;
  out->xi[0] = xi[0];
  out->xi[1] = pdim == 2 ? xi[1] : 0.0;
  out->iterations = it > PROJECT_MAX_ITERATIONS ? PROJECT_MAX_ITERATIONS : it;
}

/* The face with the lowest id among those meeting at corner `corner` of `face`, walking the edge-neighbour ring
 * in both directions; *best_corner is that face's corner at the same node. */
static int lowest_face_at_vertex(const sk_surface *s, int face, int corner, int *best_corner) {
  const int ne = s->n_edges;
  const int vertex = face_conn(s, face)[corner];
  int best = face;
  *best_corner = corner;
  for (int direction = 0; direction < 2; ++direction) {
    int current = face;
    int edge = direction == 0 ? corner : (corner + ne - 1) % ne;
    for (int step = 0; step < RING_MAX; ++step) {
      int next = s->face_neighbors[(size_t)current * ne + edge];
      if (next < 0 || next == face) break;
      const int *c = face_conn(s, current), *cn = face_conn(s, next);
      int other = c[edge] == vertex ? c[(edge + 1) % ne] : c[edge]; /* far node of the edge crossed */
      int next_corner = -1;
      for (int k = 0; k < ne; ++k)
        if (cn[k] == vertex) next_corner = k;
      if (next_corner < 0) break;
      if (next < best) {
        best = next;
        *best_corner = next_corner;
      }
      /* Leave `next` through its other edge at the vertex. */
      int forward = next_corner, backward = (next_corner + ne - 1) % ne;
      edge = cn[(next_corner + 1) % ne] == other ? backward : forward;
      current = next;
    }
  }
  return best;
}

sk_status sk_surface_project(const sk_surface *surface, const double *q, const double *x, const int *candidates,
                             int n_candidates, sk_projection *projection) {
  memset(projection, 0, sizeof *projection);
  projection->face = -1;
  projection->kind = SK_PROJ_OUTSIDE;
  if (!surface || !q || !x) return sk_error_set(SK_ERR_INPUT, "closest-point projection: missing surface, q or x");
  const sk_face_domain *dom = sk_face_domain_of(surface->face_type);
  if (!dom) return sk_error_set(SK_ERR_INPUT, "surface %s: unsupported face type %d", surface->name,
                                (int)surface->face_type);
  const int pdim = dom->pdim, ne = surface->n_edges;
  int count = candidates ? n_candidates : surface->n_faces;
  double point[3] = {x[0], x[1], surface->dim == 3 ? x[2] : 0.0};

  local_result best = {.face = -1};
  double best_distance = INFINITY;
  sk_surface_point p;
  for (int k = 0; k < count; ++k) {
    int start = candidates ? candidates[k] : k;
    if (start < 0 || start >= surface->n_faces)
      return sk_error_set(SK_ERR_INPUT, "surface %s: candidate face %d out of range (%d faces)", surface->name, start,
                          surface->n_faces);
    local_result result;
    project_local(surface, dom, q, point, start, &result);
    sk_surface_geometry(surface, result.face, result.xi, q, &p);
    double r[3] = {point[0] - p.x[0], point[1] - p.x[1], point[2] - p.x[2]};
    double distance = sqrt(dot3(r, r));
    double tie = TIE_TOL * fmax(distance, sqrt(p.m[0][0])); /* |a_1|: half the face size */
    if (best.face < 0 || distance < best_distance - tie ||
        (distance <= best_distance + tie && result.face < best.face)) {
      best = result;
      best_distance = distance;
    }
  }
  if (best.face < 0) return SK_OK; /* no candidates */

  /* A point reported on an edge lies exactly on it (so equal inputs give equal xi whichever way Newton came);
   * then a point on a shared edge or corner goes to the lowest face id carrying it. */
  int on_edge[4], n_on = 0;
  for (int e = 0; e < ne; ++e)
    if (sk_face_edge_value(dom, e, best.xi) <= CLASSIFY_TOL) on_edge[n_on++] = e;
  for (int k = 0; k < n_on; ++k) {
    const double *w = dom->edge_w[on_edge[k]];
    double g = sk_face_edge_value(dom, on_edge[k], best.xi), ww = w[0] * w[0] + (pdim == 2 ? w[1] * w[1] : 0.0);
    best.xi[0] -= g * w[0] / ww;
    if (pdim == 2) best.xi[1] -= g * w[1] / ww;
  }
  if (n_on >= 2 && pdim == 2) {
    int corner = (on_edge[0] == 0 && on_edge[1] == ne - 1) ? 0 : on_edge[1];
    best.xi[0] = dom->corner[corner][0];
    best.xi[1] = dom->corner[corner][1];
  }
  if (n_on == 1 || (n_on >= 1 && pdim == 1)) {
    int e = on_edge[0];
    int next = surface->face_neighbors[(size_t)best.face * ne + e];
    double next_xi[2];
    if (next >= 0 && next < best.face && map_across_edge(surface, dom, best.face, e, best.xi, next, next_xi) >= 0) {
      best.face = next;
      best.xi[0] = next_xi[0];
      best.xi[1] = next_xi[1];
    }
  } else if (n_on >= 2) {
    int corner = (on_edge[0] == 0 && on_edge[1] == ne - 1) ? 0 : on_edge[1]; /* corner shared by the two edges */
    int best_corner;
    int lowest = lowest_face_at_vertex(surface, best.face, corner, &best_corner);
    best.face = lowest;
    best.xi[0] = dom->corner[best_corner][0];
    best.xi[1] = dom->corner[best_corner][1];
  }

  /* Final geometry, gap and classification on the chosen face. */
  sk_surface_geometry(surface, best.face, best.xi, q, &p);
  double r[3], R[2], A[2][2];
  residual_and_hessian(pdim, &p, point, r, R, A);
  projection->face = best.face;
  projection->xi[0] = best.xi[0];
  projection->xi[1] = best.xi[1];
  projection->gap = dot3(r, p.n);
  projection->distance = sqrt(dot3(r, r));
  projection->iterations = best.iterations;
  /* Parametric direction towards the tangential foot of x: beyond a border edge means OUTSIDE. */
  double toward[2] = {p.m_inv[0][0] * R[0] + p.m_inv[0][1] * R[1], p.m_inv[1][0] * R[0] + p.m_inv[1][1] * R[1]};
  if (pdim == 1) toward[1] = 0.0;
  n_on = 0;
  int outside = 0;
  for (int e = 0; e < ne; ++e) {
    if (sk_face_edge_value(dom, e, best.xi) > CLASSIFY_TOL) continue;
    ++n_on;
    double rate = dom->edge_w[e][0] * toward[0] + (pdim == 2 ? dom->edge_w[e][1] * toward[1] : 0.0);
    if (surface->face_neighbors[(size_t)best.face * ne + e] < 0 && rate < -CLASSIFY_TOL) outside = 1;
  }
  if (outside) projection->kind = SK_PROJ_OUTSIDE;
  else if (n_on == 0) projection->kind = SK_PROJ_INTERIOR;
  else if (n_on == 1 || pdim == 1) projection->kind = SK_PROJ_EDGE;
  else projection->kind = SK_PROJ_VERTEX;

  if (!best.converged)
    return sk_error_set(SK_ERR_DIVERGED,
                        "surface %s: closest-point projection of (%g, %g, %g) did not converge on face %d in %d "
                        "iterations",
                        surface->name, point[0], point[1], point[2], best.face, best.iterations);
  return SK_OK;
}
