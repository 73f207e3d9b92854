/* Rigid obstacles: gap, foot point and normal against closed forms, orthonormal right-handed frames, curvature
 * (Weingarten by finite differences), the parabolic-cylinder foot point (orthogonality and a dense-sampling
 * minimum), d gap / d x = n by finite differences, prescribed motion and errors. */
#include <string.h>

#include "contact_test_util.h"
#include "sk_test.h"

static double dot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void check_frame(const sk_surface_point *p, int dim) {
  SK_CHECK_CLOSE(dot(p->n, p->n), 1.0, 1e-14);
  for (int k = 0; k < 2; ++k) {
    SK_CHECK_CLOSE(dot(p->a[k], p->n), 0.0, 1e-13);
    for (int l = 0; l < 2; ++l) {
      SK_CHECK_CLOSE(dot(p->a[k], p->a[l]), k == l ? 1.0 : 0.0, 1e-13);
      SK_CHECK_CLOSE(p->m[k][l], k == l ? 1.0 : 0.0, 0);
    }
  }
  double c[3] = {p->a[0][1] * p->a[1][2] - p->a[0][2] * p->a[1][1], p->a[0][2] * p->a[1][0] - p->a[0][0] * p->a[1][2],
                 p->a[0][0] * p->a[1][1] - p->a[0][1] * p->a[1][0]};
  for (int i = 0; i < 3; ++i) SK_CHECK_CLOSE(c[i], p->n[i], 1e-13);
  if (dim == 2) {
    SK_CHECK(p->a[1][2] == 1.0 && p->n[2] == 0.0 && p->x[2] == 0.0);
  }
}

/* d gap / d x = n; and for a point on the surface, moving along a_k moves n by -h_kl a_l (orthonormal frame). */
static void check_derivatives(const sk_obstacle *o, const double *x, int dim) {
  sk_surface_point p, pp, pm;
  double gap, gp, gm, h = 1e-6;
  SK_CHECK(sk_obstacle_project(o, 0.0, x, dim, &p, &gap) == SK_OK);
  check_frame(&p, dim);
  for (int i = 0; i < dim; ++i) {
    double xp[3] = {x[0], x[1], dim == 3 ? x[2] : 0}, xm[3] = {x[0], x[1], dim == 3 ? x[2] : 0};
    xp[i] += h, xm[i] -= h;
    sk_obstacle_project(o, 0.0, xp, dim, &pp, &gp);
    sk_obstacle_project(o, 0.0, xm, dim, &pm, &gm);
    SK_CHECK_CLOSE((gp - gm) / (2 * h), p.n[i], 1e-7);
  }
  /* Foot point: x - gap n. */
  for (int i = 0; i < dim; ++i) SK_CHECK_CLOSE(p.x[i], x[i] - gap * p.n[i], 1e-12);
  /* Weingarten at the foot: n(foot + h a_k) - n(foot - h a_k) ~ -2 h h_kl a_l */
  for (int k = 0; k < dim - 1; ++k) {
    double xp[3], xm[3];
    for (int i = 0; i < 3; ++i) xp[i] = p.x[i] + h * p.a[k][i], xm[i] = p.x[i] - h * p.a[k][i];
    sk_obstacle_project(o, 0.0, xp, dim, &pp, &gp);
    sk_obstacle_project(o, 0.0, xm, dim, &pm, &gm);
    for (int l = 0; l < 2; ++l) {
      double dn[3];
      for (int i = 0; i < 3; ++i) dn[i] = (pp.n[i] - pm.n[i]) / (2 * h);
      SK_CHECK_CLOSE(-dot(dn, p.a[l]), p.h[k][l], 1e-6);
    }
  }
}

static void plane(void) {
  sk_obstacle o = {.kind = SK_OBSTACLE_PLANE, .name = "floor", .point = {1, 2, 3}, .normal = {0, 0, 2}};
  double x[3] = {4, -1, 3.5}, gap;
  sk_surface_point p;
  SK_CHECK(sk_obstacle_project(&o, 0.0, x, 3, &p, &gap) == SK_OK);
  SK_CHECK_CLOSE(gap, 0.5, 1e-14);
  SK_CHECK_CLOSE(p.n[2], 1.0, 1e-14);
  SK_CHECK_CLOSE(p.x[2], 3.0, 1e-14);
  SK_CHECK(p.h[0][0] == 0.0 && p.h[1][1] == 0.0 && p.face == -1);
  double tilted_n[3] = {1, -2, 2};
  memcpy(o.normal, tilted_n, sizeof tilted_n);
  check_derivatives(&o, x, 3);
  SK_CHECK(sk_obstacle_project(&o, 0.0, x, 3, &p, &gap) == SK_OK);
  SK_CHECK_CLOSE(gap, (3 * 1 - 3 * -2 + 0.5 * 2) / 3.0, 1e-14);
  /* 2D: the plane is a line; a[1] = e_z */
  sk_obstacle line = {.kind = SK_OBSTACLE_PLANE, .name = "line", .point = {0, 1, 0}, .normal = {0.6, 0.8, 0}};
  double y[2] = {1, 2};
  check_derivatives(&line, y, 2);
  SK_CHECK(sk_obstacle_project(&line, 0.0, y, 2, &p, &gap) == SK_OK);
  SK_CHECK_CLOSE(gap, 0.6 + 0.8, 1e-14);
}

static void sphere_and_cylinder(void) {
  sk_obstacle sphere = {.kind = SK_OBSTACLE_SPHERE, .name = "ball", .point = {1, 0, -1}, .radius = 2};
  double x[3] = {2, 2, 1}, gap;
  sk_surface_point p;
  SK_CHECK(sk_obstacle_project(&sphere, 0.0, x, 3, &p, &gap) == SK_OK);
  SK_CHECK_CLOSE(gap, 3.0 - 2.0, 1e-14);
  SK_CHECK_CLOSE(p.n[0], 1 / 3.0, 1e-14);
  SK_CHECK_CLOSE(p.h[0][0], -0.5, 1e-14);
  SK_CHECK_CLOSE(p.h[1][1], -0.5, 1e-14);
  check_derivatives(&sphere, x, 3);
  double inside[3] = {1.5, 0.5, -0.5};
  check_derivatives(&sphere, inside, 3);
  SK_CHECK(sk_obstacle_project(&sphere, 0.0, inside, 3, &p, &gap) == SK_OK);
  SK_CHECK_CLOSE(gap, sqrt(0.75) - 2.0, 1e-14);
  /* Circle in 2D. */
  double y[2] = {4, 4};
  check_derivatives(&sphere, y, 2);
  SK_CHECK(sk_obstacle_project(&sphere, 0.0, y, 2, &p, &gap) == SK_OK);
  SK_CHECK_CLOSE(gap, 5.0 - 2.0, 1e-14);
  SK_CHECK(p.h[1][1] == 0.0);
  /* At the centre: a deterministic normal, no NaN. */
  double centre[3] = {1, 0, -1};
  SK_CHECK(sk_obstacle_project(&sphere, 0.0, centre, 3, &p, &gap) == SK_OK);
  SK_CHECK_CLOSE(gap, -2.0, 1e-14);
  SK_CHECK_CLOSE(dot(p.n, p.n), 1.0, 1e-14);

  sk_obstacle cylinder = {.kind = SK_OBSTACLE_CYLINDER, .name = "roller", .point = {0, 0, 0}, .axis = {0, 1, 1},
                          .radius = 1};
  double z[3] = {2, 5, 1};
  SK_CHECK(sk_obstacle_project(&cylinder, 0.0, z, 3, &p, &gap) == SK_OK);
  /* distance from the axis (0, 1, 1)/sqrt 2: |z|^2 - (z.u)^2 = 30 - 18 = 12 */
  SK_CHECK_CLOSE(gap, sqrt(12.0) - 1.0, 1e-14);
  SK_CHECK_CLOSE(p.h[0][0], -1.0, 1e-14);
  SK_CHECK(p.h[1][1] == 0.0);
  check_derivatives(&cylinder, z, 3);
  /* In 2D with axis e_z: a circle. */
  sk_obstacle disc = {.kind = SK_OBSTACLE_CYLINDER, .name = "disc", .point = {0, 0, 0}, .axis = {0, 0, 1},
                      .radius = 1};
  double w[2] = {0.3, -1.5};
  check_derivatives(&disc, w, 2);
}

static void parabolic(void) {
  /* z = c x^2 in the frame origin (1, 1, 0), up = e_z, generators along e_y. */
  sk_obstacle o = {.kind = SK_OBSTACLE_PARABOLIC_CYLINDER, .name = "parabola", .point = {1, 1, 0},
                   .normal = {0, 0, 1}, .axis = {0, 1, 0}, .c = 0.5};
  unsigned long long seed = 3;
  for (int trial = 0; trial < 60; ++trial) {
    /* Include points high above the vertex (several foot candidates) and points on the axis. */
    double X = trial % 10 == 0 ? 0.0 : -3 + 6 * test_random(&seed), Z = -2 + 6 * test_random(&seed);
    double x[3] = {1 + X, 1 + 2 * test_random(&seed), Z}, gap;
    sk_surface_point p;
    SK_CHECK(sk_obstacle_project(&o, 0.0, x, 3, &p, &gap) == SK_OK);
    /* on the surface, and x - foot is normal to it */
    double fx = p.x[0] - 1, fz = p.x[2];
    SK_CHECK_CLOSE(fz, 0.5 * fx * fx, 1e-12);
    double r[3] = {x[0] - p.x[0], x[1] - p.x[1], x[2] - p.x[2]};
    SK_CHECK_CLOSE(dot(r, p.a[0]), 0.0, 1e-11);
    SK_CHECK_CLOSE(dot(r, p.a[1]), 0.0, 1e-12);
    /* the global minimum: no sampled point of the curve is closer */
    double best = INFINITY;
    for (int k = -4000; k <= 4000; ++k) {
      double s = k * 1e-3, dx = X - s, dz = Z - 0.5 * s * s;
      best = fmin(best, sqrt(dx * dx + dz * dz));
    }
    SK_CHECK(fabs(gap) <= best + 1e-9);
    SK_CHECK(fabs(gap) >= best - 1e-5);
    /* above the surface: positive gap (material below) */
    SK_CHECK((Z > 0.5 * X * X) == (gap > 0));
    if (fabs(X) > 1e-3 && fabs(gap) > 1e-3) check_derivatives(&o, x, 3);
  }
  /* Curvature at the vertex: 2c, positive (the surface bends towards n). */
  double above[3] = {1, 0, 0.1}, gap;
  sk_surface_point p;
  SK_CHECK(sk_obstacle_project(&o, 0.0, above, 3, &p, &gap) == SK_OK);
  SK_CHECK_CLOSE(p.h[0][0], 1.0, 1e-14);
  SK_CHECK_CLOSE(gap, 0.1, 1e-14);
  /* Tilted frame and 2D use (up = e_y, generators e_z). */
  sk_obstacle o2 = {.kind = SK_OBSTACLE_PARABOLIC_CYLINDER, .name = "p2", .point = {0, -1, 0}, .normal = {0, 1, 0},
                    .axis = {0, 0, 1}, .c = 0.05};
  double y[2] = {2.5, 0.2};
  check_derivatives(&o2, y, 2);
  SK_CHECK(sk_obstacle_project(&o2, 0.0, y, 2, &p, &gap) == SK_OK);
  SK_CHECK_CLOSE(p.x[1] + 1, 0.05 * p.x[0] * p.x[0], 1e-12);
}

static void motion(void) {
  sk_obstacle o = {.kind = SK_OBSTACLE_PLANE, .name = "press", .point = {0, 0, 1}, .normal = {0, 0, -1},
                   .n_motion = 3, .motion_t = {1, 2, 4}, .motion_d = {{0, 0, 0}, {0, 0, -0.5}, {1, 0, -0.5}}};
  double d[3];
  sk_obstacle_displacement(&o, 0.0, d);
  SK_CHECK(d[0] == 0 && d[2] == 0);
  sk_obstacle_displacement(&o, 1.5, d);
  SK_CHECK_CLOSE(d[2], -0.25, 1e-15);
  sk_obstacle_displacement(&o, 3.0, d);
  SK_CHECK_CLOSE(d[0], 0.5, 1e-15);
  SK_CHECK_CLOSE(d[2], -0.5, 1e-15);
  sk_obstacle_displacement(&o, 9.0, d);
  SK_CHECK(d[0] == 1.0 && d[2] == -0.5);
  double x[3] = {0, 0, 0}, gap;
  sk_surface_point p;
  SK_CHECK(sk_obstacle_project(&o, 1.5, x, 3, &p, &gap) == SK_OK);
  SK_CHECK_CLOSE(gap, 0.75, 1e-15); /* plane at z = 0.75, material above, x below it */
  sk_obstacle still = {.kind = SK_OBSTACLE_PLANE, .name = "still", .normal = {0, 0, 1}};
  sk_obstacle_displacement(&still, 5.0, d);
  SK_CHECK(d[0] == 0 && d[1] == 0 && d[2] == 0);
}

static void errors(void) {
  sk_obstacle o = {.kind = SK_OBSTACLE_SPHERE, .name = "broken-ball", .radius = 0};
  double x[3] = {1, 1, 1}, gap;
  sk_surface_point p;
  SK_CHECK(sk_obstacle_project(&o, 0.0, x, 3, &p, &gap) == SK_ERR_INPUT);
  SK_CHECK(strstr(sk_error_message(), "broken-ball") != NULL);
  sk_obstacle q = {.kind = SK_OBSTACLE_PLANE, .name = "no-normal"};
  SK_CHECK(sk_obstacle_project(&q, 0.0, x, 3, &p, &gap) == SK_ERR_INPUT);
  SK_CHECK(strstr(sk_error_message(), "no-normal") != NULL);
  sk_obstacle r = {.kind = SK_OBSTACLE_PARABOLIC_CYLINDER, .name = "bad-axis", .normal = {0, 0, 1},
                   .axis = {0, 0, 2}, .c = 1};
  SK_CHECK(sk_obstacle_project(&r, 0.0, x, 3, &p, &gap) == SK_ERR_INPUT);
  SK_CHECK(sk_obstacle_project(&r, 0.0, x, 4, &p, &gap) == SK_ERR_INPUT);
}

int main(void) {
  plane();
  sphere_and_cylinder();
  parabolic();
  motion();
  errors();
  return sk_test_finish("test_contact_obstacle");
}
