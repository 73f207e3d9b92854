/* Shared helpers of the mortar-dual tests: face descriptors on the core's shape functions, a deterministic random
 * generator, and a finite-difference check of any fwd-valued function of a vector of local unknowns. */
#ifndef MORTAR_TEST_SUPPORT_H
#define MORTAR_TEST_SUPPORT_H

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "kernel.h"
#include "sk_test.h"
#include "stickslip/fe.h"

static mortar_face_type ft_line2, ft_line3, ft_tri3, ft_quad4, ft_quad8, ft_quad9, ft_tri6;

static inline void test_face_types(void) {
  mortar_face_type_init(&ft_line2, SK_LINE2, sk_elem_shape, sk_elem_shape_hessian);
  mortar_face_type_init(&ft_line3, SK_LINE3, sk_elem_shape, sk_elem_shape_hessian);
  mortar_face_type_init(&ft_tri3, SK_TRI3, sk_elem_shape, sk_elem_shape_hessian);
  mortar_face_type_init(&ft_quad4, SK_QUAD4, sk_elem_shape, sk_elem_shape_hessian);
  mortar_face_type_init(&ft_quad8, SK_QUAD8, sk_elem_shape, sk_elem_shape_hessian);
  mortar_face_type_init(&ft_quad9, SK_QUAD9, sk_elem_shape, sk_elem_shape_hessian);
  mortar_face_type_init(&ft_tri6, SK_TRI6, sk_elem_shape, sk_elem_shape_hessian);
}

static unsigned long long test_rng_state = 88172645463325252ull;
static inline double test_rand(void) { /* uniform in [-1, 1] */
  test_rng_state ^= test_rng_state << 13;
  test_rng_state ^= test_rng_state >> 7;
  test_rng_state ^= test_rng_state << 17;
  return 2.0 * (double)(test_rng_state >> 11) / 9007199254740992.0 - 1.0;
}

enum { TEST_MAX_OUT = 171 }; /* a QUAD9 pair: D, M (9 x 9 each) and 9 gaps */

/* A function of n local unknowns u with m fwd outputs (derivatives seeded when `derivatives`). */
typedef int (*test_fwd_fn)(void *ctx, const double *u, int derivatives, fwd *out);

/* Central differences of every output against its derivative; returns max |FD - derivative| relative to
 * max(1, max |derivative|); prints it with `label`. */
static inline double test_fd_check(const char *label, test_fwd_fn f, void *ctx, const double *u0, int n, int m,
                                   double h) {
  fwd y[TEST_MAX_OUT], yp[TEST_MAX_OUT], ym[TEST_MAX_OUT];
  double u[FWD_MAX];
  memcpy(u, u0, sizeof(double) * (size_t)n);
  if (f(ctx, u, 1, y) != 0) {
    printf("  %s: evaluation failed\n", label);
    return INFINITY;
  }
  double err = 0.0, scale = 1.0;
  for (int k = 0; k < n; ++k) {
    u[k] = u0[k] + h;
    const int sp = f(ctx, u, 0, yp);
    u[k] = u0[k] - h;
    const int sm = f(ctx, u, 0, ym);
    u[k] = u0[k];
    if (sp != 0 || sm != 0) return INFINITY;
    for (int i = 0; i < m; ++i) {
      const double fd = (yp[i].v - ym[i].v) / (2.0 * h);
      const double an = k < y[i].n ? y[i].d[k] : 0.0;
      err = fmax(err, fabs(fd - an));
      scale = fmax(scale, fabs(an));
    }
  }
  printf("  %s: |derivative - FD| = %.2e (scale %.2e)\n", label, err / scale, scale);
  return err / scale;
}

#endif
