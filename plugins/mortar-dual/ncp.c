/* mortar-dual kernel: the nonlinear complementarity functions of normal contact and Coulomb friction and their
 * semismooth derivatives (see kernel.h). Derivative columns: [z_n, z_t1, z_t2, g, s1, s2]. */
#include <math.h>
#include <string.h>

#include "kernel.h"

enum { COL_ZN = 0, COL_ZT = 1, COL_G = 3, COL_S = 4 };

void mortar_ncp_eval(int n_t, double z_n, const double *z_t, double g, const double *s, const mortar_ncp_params *prm,
                     int force_state, mortar_ncp *out) {
  mortar_ncp_eval_dir(n_t, z_n, z_t, g, s, prm, force_state, NULL, out);
}

void mortar_ncp_eval_dir(int n_t, double z_n, const double *z_t, double g, const double *s,
                         const mortar_ncp_params *prm, int force_state, const double *slip_dir, mortar_ncp *out) {
  memset(out, 0, sizeof *out);
  const double zeta = z_n - prm->c_n * g; /* > 0: the normal condition is active */
  int state;
  double v[2] = {0.0, 0.0}, vlen = 0.0;
  for (int a = 0; a < n_t; ++a) {
    v[a] = z_t[a] + prm->c_t * s[a];
    vlen += v[a] * v[a];
  }
  vlen = sqrt(vlen);
  const double radius = prm->mu * (zeta > 0.0 ? zeta : 0.0);
  if (force_state >= 0) {
    state = force_state;
    /* a slip branch without a slip direction is a stick; friction-free contact has no stick */
    if (state == MORTAR_SLIP && prm->mu > 0.0 && !(vlen > 0.0) && !slip_dir) state = MORTAR_STICK;
  } else if (zeta < 0.0) {
    /* zeta = 0 (touching, no pressure yet: the first step of bodies that start in contact) counts as active, so
     * that a body held only by the contact is not left floating by its first Newton step */
    state = MORTAR_INACTIVE;
  } else if (prm->mu > 0.0 && vlen <= radius) {
    state = MORTAR_STICK;
  } else {
    state = MORTAR_SLIP;
  }
  if (prm->mu <= 0.0 && state == MORTAR_STICK) state = MORTAR_SLIP;
  out->state = state;

  /* normal row: inactive C_N = z_n, active C_N = c_n g */
  if (state == MORTAR_INACTIVE) {
    out->C[0] = z_n;
    out->dC[0][COL_ZN] = 1.0;
  } else {
    out->C[0] = prm->c_n * g;
    out->dC[0][COL_G] = prm->c_n;
  }
  /* tangential rows */
  for (int a = 0; a < n_t; ++a) {
    double *row = out->dC[1 + a];
    if (state == MORTAR_INACTIVE || prm->mu <= 0.0) {
      out->C[1 + a] = z_t[a];
      row[COL_ZT + a] = 1.0;
    } else if (state == MORTAR_STICK) {
      out->C[1 + a] = -prm->c_t * s[a];
      row[COL_S + a] = -prm->c_t;
    } else if (slip_dir) {
      /* the nested loop's slip with the direction frozen for the Newton run: C_T = z_t - r d, r = mu (z_n - c_n g) */
      out->C[1 + a] = z_t[a] - prm->mu * zeta * slip_dir[a];
      row[COL_ZT + a] = 1.0;
      row[COL_ZN] = -prm->mu * slip_dir[a];
      row[COL_G] = prm->mu * prm->c_n * slip_dir[a];
    } else {
      /* C_T = z_t - r v/|v|, r = mu (z_n - c_n g), v = z_t + c_t s */
      const double r = prm->mu * zeta, vh = v[a] / vlen;
      out->C[1 + a] = z_t[a] - r * vh;
      row[COL_ZN] = -prm->mu * vh;
      row[COL_G] = prm->mu * prm->c_n * vh;
      for (int b = 0; b < n_t; ++b) {
        const double dvh = ((a == b ? 1.0 : 0.0) - vh * v[b] / vlen) / vlen; /* d (v_a/|v|) / d v_b */
        row[COL_ZT + b] = (a == b ? 1.0 : 0.0) - r * dvh;
        row[COL_S + b] = -r * dvh * prm->c_t;
      }
    }
  }
}

int mortar_ncp_branch_holds(int n_t, double z_n, const double *z_t, double g, const double *s,
                            const mortar_ncp_params *prm, int state, const double *slip_dir, double tol) {
  const double zeta = z_n - prm->c_n * g;
  if (state == MORTAR_INACTIVE) return zeta < tol;
  if (zeta < -tol) return 0;
  if (prm->mu <= 0.0) return 1; /* frictionless contact: any active branch */
  double vlen = 0.0, along = 0.0;
  for (int a = 0; a < n_t; ++a) {
    const double v = z_t[a] + prm->c_t * s[a];
    vlen += v * v;
    if (slip_dir) along += v * slip_dir[a];
  }
  vlen = sqrt(vlen);
  const double radius = prm->mu * (zeta > 0.0 ? zeta : 0.0);
  if (state == MORTAR_STICK) return vlen <= radius + tol;
  /* a frozen slip direction holds while the trial traction exceeds the radius along it (the slip has not turned) */
  return slip_dir ? along >= radius - tol && vlen - along <= tol + 1e-8 * vlen : vlen >= radius - tol;
}
