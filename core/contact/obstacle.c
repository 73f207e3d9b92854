/* Rigid analytical obstacles: closest point, orthonormal frame, curvature and gap; prescribed translation. */
#include <math.h>
#include <string.h>

#include "stickslip/contact.h"

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void cross3(const double *a, const double *b, double *c) {
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}

static int normalise(const double *v, double *u) {
  double length = sqrt(dot3(v, v));
  if (!(length > 0.0) || !isfinite(length)) return 0;
  for (int i = 0; i < 3; ++i) u[i] = v[i] / length;
  return 1;
}

void sk_obstacle_displacement(const sk_obstacle *obstacle, double t, double d[3]) {
  d[0] = d[1] = d[2] = 0.0;
  int n = obstacle->n_motion;
  if (n <= 0) return;
  if (n > SK_OBSTACLE_MOTION_MAX) n = SK_OBSTACLE_MOTION_MAX;
  if (t <= obstacle->motion_t[0]) {
    memcpy(d, obstacle->motion_d[0], 3 * sizeof *d);
    return;
  }
  if (t >= obstacle->motion_t[n - 1]) {
    memcpy(d, obstacle->motion_d[n - 1], 3 * sizeof *d);
    return;
  }
  int k = 0;
  while (k + 1 < n - 1 && obstacle->motion_t[k + 1] <= t) ++k;
  double span = obstacle->motion_t[k + 1] - obstacle->motion_t[k];
  double s = span > 0.0 ? (t - obstacle->motion_t[k]) / span : 1.0;
  for (int i = 0; i < 3; ++i)
    d[i] = (1.0 - s) * obstacle->motion_d[k][i] + s * obstacle->motion_d[k + 1][i];
}

/* Unit tangents with a0 x a1 = n. In 2D a1 = e_z (the surface convention of contact.h), so a0 = (-n_y, n_x). */
static void tangent_frame(const double *n, int dim, double a[2][3]) {
  if (dim == 2) {
    a[0][0] = -n[1];
    a[0][1] = n[0];
    a[0][2] = 0.0;
    a[1][0] = a[1][1] = 0.0;
    a[1][2] = 1.0;
    return;
  }
  /* Start from the coordinate axis least aligned with n. */
  double e[3] = {0, 0, 0};
  int k = 0;
  for (int i = 1; i < 3; ++i)
    if (fabs(n[i]) < fabs(n[k])) k = i;
  e[k] = 1.0;
  double t[3];
  cross3(e, n, t);
  normalise(t, a[0]);
  cross3(n, a[0], a[1]);
}

/* Fills the frame part of the point: orthonormal tangents, identity metric, x,ab = h_ab n (normal coordinates, so
 * the Christoffel symbols vanish at the point). */
static void fill_point(sk_surface_point *point, const double *x, const double *n, double a[2][3], double h[2][2]) {
  memset(point, 0, sizeof *point);
  point->face = -1;
  point->jacobian = 1.0;
  for (int i = 0; i < 3; ++i) {
    point->x[i] = x[i];
    point->n[i] = n[i];
  }
  for (int k = 0; k < 2; ++k) {
    point->m[k][k] = point->m_inv[k][k] = 1.0;
    for (int i = 0; i < 3; ++i) point->a[k][i] = point->a_dual[k][i] = a[k][i];
    for (int l = 0; l < 2; ++l) {
      point->h[k][l] = h[k][l];
      for (int i = 0; i < 3; ++i) point->a_ab[k][l][i] = h[k][l] * n[i];
    }
  }
}

/* Foot point s >= 0 on z = c x^2 of (x0 >= 0, z0): the root of f(s) = 2c^2 s^3 + (1 - 2 c z0) s - x0, which is
 * convex for s > 0 with f(0) = -x0 <= 0, so it has one positive root; Newton from a point where f > 0 decreases
 * monotonically onto it (bisection guards round-off). */
static double parabola_foot(double c, double x0, double z0) {
  const double cubic = 2.0 * c * c, linear = 1.0 - 2.0 * c * z0;
  if (x0 == 0.0) return (linear >= 0.0 || cubic == 0.0) ? 0.0 : sqrt(-linear / cubic);
  double lo = 0.0, hi = fmax(x0, 1e-300);
  while (cubic * hi * hi * hi + linear * hi - x0 <= 0.0) {
    lo = hi;
    hi *= 2.0;
  }
  double s = hi;
  for (int it = 0; it < 100; ++it) {
    double f = cubic * s * s * s + linear * s - x0;
    double df = 3.0 * cubic * s * s + linear;
    if (f > 0.0) hi = s;
    else lo = s;
    double next = df > 0.0 ? s - f / df : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (fabs(next - s) <= 1e-15 * fmax(1.0, fabs(s))) return next;
    s = next;
  }
  return s;
}

sk_status sk_obstacle_project(const sk_obstacle *obstacle, double t, const double *x, int dim,
                              sk_surface_point *point, double *gap) {
  if (!obstacle || !x || !point || !gap || (dim != 2 && dim != 3))
    return sk_error_set(SK_ERR_INPUT, "obstacle projection: missing argument or dimension %d not 2 or 3", dim);
  double d[3], origin[3], r[3];
  sk_obstacle_displacement(obstacle, t, d);
  for (int i = 0; i < 3; ++i) {
    origin[i] = obstacle->point[i] + d[i];
    r[i] = (i < dim ? x[i] : 0.0) - origin[i];
  }
  if (dim == 2) origin[2] = r[2] = 0.0; /* 2D lives in z = 0 whatever the obstacle's z */
  double n[3], a[2][3], h[2][2] = {{0, 0}, {0, 0}}, foot[3];

  switch (obstacle->kind) {
  case SK_OBSTACLE_PLANE: {
    if (!normalise(obstacle->normal, n))
      return sk_error_set(SK_ERR_INPUT, "obstacle %s: the plane normal is zero", obstacle->name);
    *gap = dot3(r, n);
    for (int i = 0; i < 3; ++i) foot[i] = origin[i] + r[i] - *gap * n[i];
    tangent_frame(n, dim, a);
    break;
  }
  case SK_OBSTACLE_SPHERE:
  case SK_OBSTACLE_CYLINDER: {
    if (!(obstacle->radius > 0.0))
      return sk_error_set(SK_ERR_INPUT, "obstacle %s: radius %g must be positive", obstacle->name, obstacle->radius);
    double axis[3] = {0, 0, 1}, radial[3];
    int cylinder = obstacle->kind == SK_OBSTACLE_CYLINDER;
    if (cylinder && !normalise(obstacle->axis, axis))
      return sk_error_set(SK_ERR_INPUT, "obstacle %s: the cylinder axis is zero", obstacle->name);
    double along = cylinder ? dot3(r, axis) : 0.0;
    for (int i = 0; i < 3; ++i) radial[i] = r[i] - along * axis[i];
    double distance = sqrt(dot3(radial, radial));
    if (!normalise(radial, n)) {
      /* On the centre (axis): every direction is closest; pick one deterministically. */
      double e[3] = {0, dim == 2 ? 1.0 : 0.0, dim == 2 ? 0.0 : 1.0};
      double proj = cylinder ? dot3(e, axis) : 0.0;
      for (int i = 0; i < 3; ++i) e[i] -= proj * axis[i];
      if (!normalise(e, n)) {
        double e2[3] = {1, 0, 0};
        proj = dot3(e2, axis);
        for (int i = 0; i < 3; ++i) e2[i] -= proj * axis[i];
        normalise(e2, n);
      }
    }
    *gap = distance - obstacle->radius;
    for (int i = 0; i < 3; ++i) foot[i] = origin[i] + along * axis[i] + obstacle->radius * n[i];
    if (cylinder && dim == 3) {
      cross3(axis, n, a[0]); /* circumferential; a0 x axis = n */
      for (int i = 0; i < 3; ++i) a[1][i] = axis[i];
      h[0][0] = -1.0 / obstacle->radius;
    } else {
      tangent_frame(n, dim, a);
      h[0][0] = -1.0 / obstacle->radius;
      if (dim == 3) h[1][1] = -1.0 / obstacle->radius; /* a 2D circle (or cylinder along e_z) is straight along e_z */
    }
    break;
  }
  case SK_OBSTACLE_PARABOLIC_CYLINDER: {
    /* Local frame: ez = "up", ey = generators, ex = ey x ez. */
    double ez[3], ey[3], ex[3], g[3];
    if (!normalise(obstacle->normal, ez))
      return sk_error_set(SK_ERR_INPUT, "obstacle %s: the parabolic cylinder normal is zero", obstacle->name);
    double along_ez = dot3(obstacle->axis, ez);
    for (int i = 0; i < 3; ++i) g[i] = obstacle->axis[i] - along_ez * ez[i];
    if (!normalise(g, ey))
      return sk_error_set(SK_ERR_INPUT, "obstacle %s: the generator axis must not be parallel to the normal",
                          obstacle->name);
    cross3(ey, ez, ex);
    const double c = obstacle->c;
    double X = dot3(r, ex), Y = dot3(r, ey), Z = dot3(r, ez);
    double s = parabola_foot(c, fabs(X), Z);
    if (X < 0.0) s = -s;
    double slope = 2.0 * c * s, length = sqrt(1.0 + slope * slope);
    for (int i = 0; i < 3; ++i) {
      foot[i] = origin[i] + s * ex[i] + Y * ey[i] + c * s * s * ez[i];
      n[i] = (-slope * ex[i] + ez[i]) / length;
      a[0][i] = (ex[i] + slope * ez[i]) / length;
      a[1][i] = ey[i];
    }
    double diff[3] = {X - s, 0.0, Z - c * s * s};
    *gap = (diff[0] * -slope + diff[2]) / length;
    h[0][0] = 2.0 * c / (length * length * length); /* the curve bends towards n when c > 0 */
    break;
  }
  default: return sk_error_set(SK_ERR_INPUT, "obstacle %s: unknown kind %d", obstacle->name, (int)obstacle->kind);
  }
  fill_point(point, foot, n, a, h);
  return SK_OK;
}
