/* The rigid obstacles as surfaces (obstacles-NNNNNN.vtu): each obstacle is a parametric patch, tessellated once over
 * the region of the mesh in a grid of quadrilaterals (3D) or a polyline (2D), and moved by its prescribed motion at
 * each output. Only a picture: the contact itself uses the exact shapes (core/contact/obstacle.c). */
#define _GNU_SOURCE
#include "obstacle_output.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "stickslip/contact.h"
#include "stickslip/output.h"

struct sk_obstacle_output {
  int n_obstacles, dim;
  const sk_obstacle **obstacle;
  int n_points, n_cells, cap_points, cap_cells;
  double *points;         /* at the obstacle's reference position (no motion) */
  int *point_obstacle;
  sk_elem_type *types;
  int *offsets, *conn;
  double *cell_obstacle;
};

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* The range of (corner - origin) . direction over the 8 corners of the box [lo, hi]. */
static void box_range(const double lo[3], const double hi[3], const double *origin, const double *direction,
                      double range[2]) {
  range[0] = HUGE_VAL;
  range[1] = -HUGE_VAL;
  for (int c = 0; c < 8; ++c) {
    double corner[3];
    for (int i = 0; i < 3; ++i) corner[i] = ((c >> i) & 1 ? hi[i] : lo[i]) - origin[i];
    const double s = dot3(corner, direction);
    range[0] = fmin(range[0], s);
    range[1] = fmax(range[1], s);
  }
}

/* A patch x(u, v) = origin + u e_u + v e_v + w(u) e_w over [u0, u1] x [v0, v1] on an nu x nv grid (nv = 0: the curve
 * at v = 0), where w(u) = c u^2 (planes: c = 0), or a surface of revolution when radius > 0: x = origin + v e_v +
 * radius (cos u e_u + sin u e_w) (v0 = v1: the circle). */
typedef struct {
  double origin[3], e_u[3], e_v[3], e_w[3];
  double u[2], v[2], c, radius;
  int nu, nv, sphere;
} patch;

static void patch_point(const patch *p, double u, double v, double *x) {
  for (int i = 0; i < 3; ++i) {
    if (p->sphere) /* u: longitude, v: polar angle */
      x[i] = p->origin[i] + p->radius * (sin(v) * (cos(u) * p->e_u[i] + sin(u) * p->e_w[i]) + cos(v) * p->e_v[i]);
    else if (p->radius > 0.0)
      x[i] = p->origin[i] + v * p->e_v[i] + p->radius * (cos(u) * p->e_u[i] + sin(u) * p->e_w[i]);
    else
      x[i] = p->origin[i] + u * p->e_u[i] + v * p->e_v[i] + p->c * u * u * p->e_w[i];
  }
}

static int grow(sk_obstacle_output *o, int points, int cells) {
  if (o->n_points + points > o->cap_points) {
    const int cap = o->n_points + points + 1024;
    double *x = realloc(o->points, sizeof(double) * 3 * (size_t)cap);
    if (x) o->points = x;
    int *owner = x ? realloc(o->point_obstacle, sizeof(int) * (size_t)cap) : NULL;
    if (!owner) return 0;
    o->point_obstacle = owner;
    o->cap_points = cap;
  }
  if (o->n_cells + cells > o->cap_cells) {
    const int cap = o->n_cells + cells + 1024;
    sk_elem_type *types = realloc(o->types, sizeof(sk_elem_type) * (size_t)cap);
    if (types) o->types = types;
    int *offsets = types ? realloc(o->offsets, sizeof(int) * ((size_t)cap + 1)) : NULL;
    if (offsets) o->offsets = offsets;
    int *conn = offsets ? realloc(o->conn, sizeof(int) * 4 * (size_t)cap) : NULL;
    if (conn) o->conn = conn;
    double *owner = conn ? realloc(o->cell_obstacle, sizeof(double) * (size_t)cap) : NULL;
    if (!owner) return 0;
    o->cell_obstacle = owner;
    o->cap_cells = cap;
  }
  return 1;
}

static sk_status add_patch(sk_obstacle_output *o, int index, const patch *p) {
  const int rows = p->nv > 0 ? p->nv + 1 : 1, columns = p->nu + 1;
  if (!grow(o, rows * columns, p->nu * (p->nv > 0 ? p->nv : 1)))
    return sk_error_set(SK_ERR_NOMEM, "out of memory for the obstacles' output");
  const int first = o->n_points;
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < columns; ++i) {
      const double u = p->u[0] + (p->u[1] - p->u[0]) * i / p->nu;
      const double v = p->nv > 0 ? p->v[0] + (p->v[1] - p->v[0]) * j / p->nv : p->v[0];
      patch_point(p, u, v, o->points + 3 * (size_t)o->n_points);
      o->point_obstacle[o->n_points++] = index;
    }
  if (o->n_cells == 0) o->offsets[0] = 0;
  for (int j = 0; j < (p->nv > 0 ? p->nv : 1); ++j)
    for (int i = 0; i < p->nu; ++i) {
      const int c = o->n_cells++, at = o->offsets[c], corner = first + j * columns + i;
      o->cell_obstacle[c] = index;
      if (p->nv > 0) {
        o->types[c] = SK_QUAD4;
        const int quad[4] = {corner, corner + 1, corner + columns + 1, corner + columns};
        memcpy(o->conn + at, quad, sizeof quad);
        o->offsets[c + 1] = at + 4;
      } else {
        o->types[c] = SK_LINE2;
        o->conn[at] = corner;
        o->conn[at + 1] = corner + 1;
        o->offsets[c + 1] = at + 2;
      }
    }
  return SK_OK;
}

/* The patch of one obstacle over the box [lo, hi] (the mesh's region). Its frame is the one the contact sees: the
 * obstacle's closest point to its own `point` (a plane's tangents and normal; a cylinder's radial normal, tangent and
 * axis, the point lying on the axis; a parabolic cylinder's x, generator and "up" directions at its vertex). */
static sk_status tessellate(sk_obstacle_output *o, int index, const sk_obstacle *ob, const double lo[3],
                            const double hi[3]) {
  const int dim = o->dim;
  patch p = {.nu = 24, .nv = dim == 3 ? 12 : 0};
  memcpy(p.origin, ob->point, sizeof p.origin);
  if (dim == 2) p.origin[2] = 0.0;
  const double t0 = ob->n_motion > 0 ? ob->motion_t[0] : 0.0;
  double d[3], at[3], gap;
  sk_obstacle_displacement(ob, t0, d);
  for (int i = 0; i < 3; ++i) at[i] = p.origin[i] + d[i];
  sk_surface_point frame;
  SK_TRY(sk_obstacle_project(ob, t0, at, dim, &frame, &gap));
  switch (ob->kind) {
  case SK_OBSTACLE_PLANE:
    memcpy(p.e_u, frame.a[0], sizeof p.e_u);
    box_range(lo, hi, p.origin, p.e_u, p.u);
    if (dim == 3) {
      memcpy(p.e_v, frame.a[1], sizeof p.e_v);
      box_range(lo, hi, p.origin, p.e_v, p.v);
    }
    p.nu = dim == 2 ? 24 : 12;
    break;
  case SK_OBSTACLE_SPHERE:
  case SK_OBSTACLE_CYLINDER: {
    const double ex[3] = {1, 0, 0}, ey[3] = {0, 1, 0}, ez[3] = {0, 0, 1};
    p.radius = ob->radius;
    p.u[1] = 2.0 * M_PI;
    p.nu = 48;
    if (ob->kind == SK_OBSTACLE_CYLINDER && dim == 3) { /* around the axis a[1] */
      memcpy(p.e_u, frame.n, sizeof p.e_u);
      memcpy(p.e_w, frame.a[0], sizeof p.e_w);
      memcpy(p.e_v, frame.a[1], sizeof p.e_v);
      box_range(lo, hi, p.origin, p.e_v, p.v);
      p.nv = 8;
    } else { /* a sphere (longitude u about e_z, polar angle v), or the circle of 2D in z = 0 */
      memcpy(p.e_u, ex, sizeof ex);
      memcpy(p.e_w, ey, sizeof ey);
      memcpy(p.e_v, ez, sizeof ez);
      p.sphere = dim == 3;
      p.v[1] = dim == 3 ? M_PI : 0.0;
      p.nv = dim == 3 ? 24 : 0;
    }
    break;
  }
  case SK_OBSTACLE_PARABOLIC_CYLINDER:
    memcpy(p.e_u, frame.a[0], sizeof p.e_u);
    memcpy(p.e_v, frame.a[1], sizeof p.e_v);
    memcpy(p.e_w, frame.n, sizeof p.e_w);
    p.c = ob->c;
    box_range(lo, hi, p.origin, p.e_u, p.u);
    if (dim == 3) box_range(lo, hi, p.origin, p.e_v, p.v);
    p.nu = 32;
    p.nv = dim == 3 ? 8 : 0;
    break;
  default: return SK_OK;
  }
  return add_patch(o, index, &p);
}

sk_status sk_obstacle_output_open(const sk_model *model, sk_obstacle_output **out) {
  sk_obstacle_output *o = calloc(1, sizeof *o);
  *out = o;
  if (!o || !(o->obstacle = calloc((size_t)model->n_pairs + 1, sizeof *o->obstacle)))
    return sk_error_set(SK_ERR_NOMEM, "out of memory for the obstacles' output");
  o->dim = model->dim;
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  for (int i = 0; i < model->dim; ++i) {
    lo[i] = HUGE_VAL;
    hi[i] = -HUGE_VAL;
    for (int a = 0; a < model->n_nodes; ++a) {
      lo[i] = fmin(lo[i], model->X[a * model->dim + i]);
      hi[i] = fmax(hi[i], model->X[a * model->dim + i]);
    }
  }
  /* the whole mesh's box: each rank holds its part of the nodes */
  MPI_Allreduce(MPI_IN_PLACE, lo, 3, MPI_DOUBLE, MPI_MIN, model->comm);
  MPI_Allreduce(MPI_IN_PLACE, hi, 3, MPI_DOUBLE, MPI_MAX, model->comm);
  double diagonal = 0.0;
  for (int i = 0; i < 3; ++i) diagonal += (hi[i] - lo[i]) * (hi[i] - lo[i]);
  for (int i = 0; i < model->dim; ++i) { /* widened, so that the obstacle reaches beyond the bodies */
    lo[i] -= 0.25 * sqrt(diagonal);
    hi[i] += 0.25 * sqrt(diagonal);
  }
  for (int k = 0; k < model->n_pairs; ++k) {
    if (!model->pairs[k].has_obstacle || model->pairs[k].obstacle_column != o->n_obstacles) continue;
    o->obstacle[o->n_obstacles] = &model->pairs[k].obstacle;
    SK_TRY(tessellate(o, o->n_obstacles, &model->pairs[k].obstacle, lo, hi));
    o->n_obstacles++;
  }
  return SK_OK;
}

int sk_obstacle_output_count(const sk_obstacle_output *obstacles) { return obstacles ? obstacles->n_obstacles : 0; }

sk_status sk_obstacle_output_write(const sk_obstacle_output *o, double t, const char *path) {
  double *x = malloc(sizeof(double) * 3 * ((size_t)o->n_points + 1));
  if (!x) return sk_error_set(SK_ERR_NOMEM, "out of memory for the obstacles' output");
  double d[3];
  for (int a = 0; a < o->n_points; ++a) {
    sk_obstacle_displacement(o->obstacle[o->point_obstacle[a]], t, d);
    for (int i = 0; i < 3; ++i) x[3 * a + i] = o->points[3 * a + i] + (i < o->dim ? d[i] : 0.0);
  }
  const sk_vtu_field cell_fields[] = {{"obstacle", 1, o->cell_obstacle}};
  const sk_status status =
      sk_vtu_write(path, o->n_points, x, o->n_cells, o->types, o->offsets, o->conn, 0, NULL, 1, cell_fields);
  free(x);
  return status;
}

void sk_obstacle_output_free(sk_obstacle_output *o) {
  if (!o) return;
  free(o->obstacle);
  free(o->points);
  free(o->point_obstacle);
  free(o->types);
  free(o->offsets);
  free(o->conn);
  free(o->cell_obstacle);
  free(o);
}
