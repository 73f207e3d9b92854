/* Self contact in the node-to-surface plugins (self_contact.h). */
#include "self_contact.h"

#include <math.h>
#include <stdio.h>

#include "defaults.h"

sk_status self_contact_exclusion(const sk_host_api *api, sk_host *host, const sk_view *surface, double *out) {
  const int dim = surface->dim;
  double largest = 0.0;
  for (int f = 0; f < surface->n_cells; ++f) {
    const int32_t *c = surface->conn + (size_t)f * surface->nen;
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL}, diag2 = 0.0;
    for (int I = 0; I < surface->nen; ++I)
      for (int i = 0; i < dim; ++i) {
        lo[i] = fmin(lo[i], surface->X[c[I] * dim + i]);
        hi[i] = fmax(hi[i], surface->X[c[I] * dim + i]);
      }
    for (int i = 0; i < dim; ++i) diag2 += (hi[i] - lo[i]) * (hi[i] - lo[i]);
    largest = fmax(largest, sqrt(diag2));
  }
  char why[300];
  snprintf(why, sizeof why, "the largest face of surface '%s' (diagonal of its reference box): the faces at the node "
           "and their neighbours", surface->name);
  return sk_defaults_param(api, host, sk_defaults_scene(api, host), "self_exclusion", largest, why, out);
}

void self_contact_exclusion_unused(const sk_host_api *api, sk_host *host) {
  /* not read: a pair that is not self contact refuses the key as unknown */
  sk_defaults_unused(api, host, "self_exclusion", "unused: the pair is not self contact (its master is not its slave)");
}

/* A body's boundary is closed and its normals point out of the material, so the faces a point can meet face it:
 * one-sided normals suffice. A face it lies behind in the reference configuration has the body's material in
 * between (e.g. the other side of a thin wall); the undeformed body does not penetrate itself, so the point reaches
 * such a face only through a face in front of it. */
int self_contact_filter(const sk_contact_services *cs, const sk_view *surface, const double *X, double exclusion,
                        int *faces, int count, sk_status *status) {
  const int dim = surface->dim;
  int kept = 0;
  *status = SK_OK;
  for (int c = 0; c < count; ++c) {
    const int f = faces[c];
    const int32_t *conn = surface->conn + (size_t)f * surface->nen;
    int near = 0;
    for (int a = 0; a < surface->nen && !near; ++a) {
      double d2 = 0.0;
      for (int i = 0; i < dim; ++i) {
        const double d = surface->X[conn[a] * dim + i] - X[i];
        d2 += d * d;
      }
      near = d2 <= exclusion * exclusion;
    }
    if (near) continue;
    sk_projection proj = {.struct_size = sizeof proj};
    const sk_status st = cs->project(surface, surface->X, X, &f, 1, &proj);
    if (st != SK_OK && st != SK_ERR_DIVERGED) {
      *status = st;
      return -1;
    }
    if (proj.face >= 0 && proj.gap < 0.0) continue;
    faces[kept++] = f;
  }
  return kept;
}
