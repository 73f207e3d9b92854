/* penalty-nts: the master face of each slave node (the closest-point projection over its candidates, the
 * master_extension band beyond the border, the hysteresis of the selection within a step). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "penalty_nts.h"

/* Closest point on the polynomial extension of `face` (also beyond its border): Newton on (x_s - x(xi)) . a_a = 0
 * from pt->xi, *pt holding the geometry there. Returns 1 with *pt at the closest point when Newton converged and the
 * point lies within `band` of the face (|xi| <= 1 + 2 band on lines and quads, barycentrics >= -band on
 * triangles), 0 otherwise. Used beyond the master's border with band = master_extension (without it a slave node
 * level with the master's end, a patch test's corner, toggles in and out of contact between Newton iterations)
 * and for the face selected during a step (band SELECT_BAND, see select_face). */
int extend_on_face(const sk_instance *in, int face, const double *xs, const double *xm, double band,
                          sk_surface_point *pt) {
  const sk_view *master = in->master;
  const int pdim = in->dim - 1;
  double xi[2] = {pt->xi[0], pt->xi[1]};
  int converged = 0;
  for (int it = 0; it < 30 && !converged; ++it) {
    double d[3] = {xs[0] - pt->x[0], xs[1] - pt->x[1], xs[2] - pt->x[2]}, r[2] = {0, 0};
    double J[2][2] = {{1.0, 0.0}, {0.0, 1.0}}, Jinv[2][2], step = 0.0;
    for (int a = 0; a < pdim; ++a) {
      r[a] = dot3(d, pt->a[a]);
      for (int b = 0; b < pdim; ++b) J[a][b] = dot3(pt->a[a], pt->a[b]) - dot3(d, pt->a_ab[a][b]);
    }
    if (!cov_invert2(pdim, J, Jinv)) return 0;
    for (int a = 0; a < pdim; ++a) {
      double dxi = 0.0;
      for (int b = 0; b < pdim; ++b) dxi += Jinv[a][b] * r[b];
      xi[a] += dxi;
      step = fmax(step, fabs(dxi));
    }
    in->cs->geometry(master, face, xi, xm, pt);
    converged = step <= 1e-13;
  }
  if (!converged) return 0;
  pt->face = face;
  pt->xi[0] = xi[0];
  pt->xi[1] = xi[1];
  return cand_within_band(master->cell_type, xi, band);
}

/* ---- master face selection --------------------------------------------------------------------------------------- */

/* Hysteresis of the face selection: a selected face is kept while the slave's closest point on its polynomial
 * extension stays within this fraction of the face beyond its edge. */
#define SELECT_BAND 0.1

/* The closest-point projection over the candidates with the master_extension treatment at the master's border:
 * face (-1: none), parameters, and whether the point lies beyond the border and its band. */
static sk_status project_global(const sk_instance *in, const double *xm, const double *xs, int k, int *face,
                                double xi[2], int *beyond) {
  const sk_view *master = in->master;
  *face = -1;
  *beyond = 0;
  xi[0] = xi[1] = 0.0;
  if (in->cand_count[k] == 0) return SK_OK;
  sk_projection proj = {.struct_size = sizeof proj};
  SK_TRY(in->cs->project(master, xm, xs, in->cand.faces + in->cand_start[k], in->cand_count[k], &proj));
  if (proj.face < 0) return SK_OK;
  *face = proj.face;
  xi[0] = proj.xi[0];
  xi[1] = proj.xi[1];
  if (proj.kind != SK_PROJ_OUTSIDE) return SK_OK;
  *beyond = 1;
  if (in->extension > 0.0) {
    sk_surface_point pt = {.struct_size = sizeof pt};
    in->cs->geometry(master, proj.face, proj.xi, xm, &pt);
    pt.xi[0] = proj.xi[0];
    pt.xi[1] = proj.xi[1];
    if (extend_on_face(in, proj.face, xs, xm, in->extension, &pt)) {
      xi[0] = pt.xi[0];
      xi[1] = pt.xi[1];
      *beyond = 0;
    }
  }
  return SK_OK;
}

/* Selects the master face of slave node k at positions q: the closest-point projection, except that a face selected
 * earlier in the step is kept while the slave's closest point on that face's extension stays within SELECT_BAND of
 * it (and the slave has not slid off the master). Called by begin_step (at the predictor, with no earlier face) and
 * by after_iteration at every new iterate; residual and Jacobian only evaluate the selection, so they are smooth
 * functions of q. Without the hysteresis a slave node at a shared master node where the master has a kink jumps
 * between the two faces: the closest point's normal turns from one face's normal to the other's within a fan of
 * width ~ |g| x kink angle (1e-10 in the patch test), where the slave is held by the full penalty stiffness, while
 * outside it only the bodies' stiffness acts, so Newton steps over the fan and back forever. */
sk_status select_face(sk_instance *in, const double *const *x, int k) {
  double xs[3], xi[2];
  int face, beyond;
  slave_position(in, x, k, xs);
  SK_TRY(project_global(in, x[1], xs, k, &face, xi, &beyond));
  int old = in->sel_face[k];
  /* The projection walks across faces from the candidates, so under large sliding it may end on a face whose
   * couplings pattern() did not declare. Such a point stays on its last face's extension until Newton converges;
   * pnts_converged then searches again around the converged point and has the host lay out the pattern again. */
  in->escaped[k] = face >= 0 && !cand_contains(&in->cand, in->cand_start[k], in->cand_count[k], face);
  if (in->escaped[k]) {
    face = old;
    beyond = 0;
    if (old >= 0) {
      xi[0] = in->sel_xi[k][0];
      xi[1] = in->sel_xi[k][1];
      beyond = in->sel_beyond[k];
    }
  }
  if (old >= 0 && old != face && face >= 0 && !beyond) {
    sk_surface_point pt = {.struct_size = sizeof pt};
    in->cs->geometry(in->master, old, in->sel_xi[k], x[1], &pt);
    pt.xi[0] = in->sel_xi[k][0];
    pt.xi[1] = in->sel_xi[k][1];
    if (extend_on_face(in, old, xs, x[1], SELECT_BAND, &pt)) {
      in->sel_xi[k][0] = pt.xi[0];
      in->sel_xi[k][1] = pt.xi[1];
      in->sel_beyond[k] = 0;
      return SK_OK;
    }
  }
  in->sel_face[k] = face;
  in->sel_xi[k][0] = xi[0];
  in->sel_xi[k][1] = xi[1];
  in->sel_beyond[k] = (unsigned char)beyond;
  return SK_OK;
}
