/* mortar-dual kernel: helpers shared by the kernel's files (not part of the kernel's interface). */
#ifndef MORTAR_KERNEL_INTERNAL_H
#define MORTAR_KERNEL_INTERNAL_H

#include "kernel.h"

/* A (n x n, row-major, overwritten) X = B (n x nrhs, overwritten with X); partial pivoting. -1 if singular. */
int mortar_solve_small(int n, double *A, double *B, int nrhs);
/* Implicit function theorem for m <= 3 unknowns y of r(y, u) = 0: r evaluated with its seeds at fixed y, J = dr/dy.
 * out = y with derivatives -J^-1 dr/du. */
int mortar_implicit(int m, const double *J, const fwd *r, const double *y, fwd *out);
/* x(xi), a_alpha(xi) and a_alpha,beta of a face at plain parameters: values only (local Newton iterations). */
void mortar_face_values(const mortar_face_type *ft, fwd x[][3], const double *xi, double pos[3], double a[2][3],
                        double aa[2][2][3]);
/* The values of dim fwd entries (zero-padded to 3). */
void mortar_values(int dim, const fwd *x, double *v);
/* x2(xi) = x1 + t d on the master face (Newton on values; xi, t in: start, out: root). 0 or -1. */
int mortar_along(const mortar_face_type *mt, fwd xm[][3], int dim, const fwd *x1, const fwd *d, double xi[2],
                 double *t);
/* The same with derivatives (xi0 in: start, out: root). */
int mortar_along_fwd(const mortar_face_type *mt, fwd xm[][3], int dim, const fwd *x1, const fwd *d, double xi0[2],
                     fwd xi[2], fwd *t);
/* The closest point of the master face to x1 with derivatives (xi0 in: start, out: root). 0 or -1. */
int mortar_closest_fwd(const mortar_face_type *mt, fwd xm[][3], int dim, const fwd *x1, double xi0[2], fwd xi[2]);
/* A local Newton iteration on face parameters (and a distance along a normal) is done: its step (max norm) at the
 * round-off of the unknowns' size, or below 1e-9 of it and no longer halving (the round-off floor: the parameters of
 * a short face carry its distance from the origin over its length times the coordinates' round-off; an absolute
 * 1e-14 failed the projections of points 5 to 15 faces beyond theirs, 100 mm from the origin over 1 to 2 mm faces, in
 * the deep ironing at refine 2). `previous` is the last step (INFINITY at the first). */
static inline int mortar_newton_done(double step, double previous, double size) {
  return step <= 1e-14 * (1.0 + size) || (step <= 1e-9 * (1.0 + size) && step > 0.5 * previous);
}
/* Outward unit normal of a face from its tangents. */
void mortar_face_normal(int dim, int pdim, fwd a[2][3], fwd n[3]);
/* Interpolated (unnormalised) slave normal sum_k N_k n_k. */
void mortar_slave_normal(const mortar_pair *p, const fwd *N, fwd n[3]);
/* Adds one integration point with slave/master parameters (xi2 NULL: obstacle), weight and normal gap. */
void mortar_add_point(const mortar_pair *p, const mortar_basis_coeffs *A, mortar_basis basis, const fwd *xi1,
                      const fwd *xi2, fwd weight, fwd g, mortar_integrals *I);
/* The same with the shape functions already evaluated there (N2 NULL: obstacle). */
void mortar_add_point_shapes(const mortar_pair *p, const mortar_basis_coeffs *A, mortar_basis basis, const fwd *N1,
                             const fwd *N2, const fwd *weight, const fwd *g, mortar_integrals *I);

#endif
