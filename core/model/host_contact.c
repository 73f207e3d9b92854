/* The contact services of the plugin ABI (plugin.h: sk_contact_services) over views: each call runs the core's
 * function on the view's surface in view numbering, and writes only within the struct_size of the caller's struct
 * (an older plugin's smaller sk_surface_point / sk_projection). */
#include <string.h>

#include "host.h"
#include "stickslip/fe.h"

static const sk_surface *surface_of(const sk_view *view) { return &sk_view_data_of(view)->local; }

/* Runs `fill` into the caller's struct, or into a full-size copy when the caller's is smaller. */
#define FILL_SIZED(type, out, call_on)                                   \
  do {                                                                   \
    const uint32_t size_ = (out)->struct_size;                           \
    if (size_ >= sizeof(type)) {                                         \
      call_on(out);                                                      \
      (out)->struct_size = size_;                                        \
    } else {                                                             \
      type full_;                                                        \
      call_on(&full_);                                                   \
      if (size_ > sizeof(uint32_t))                                      \
        memcpy((char *)(out) + sizeof(uint32_t), (const char *)&full_ + sizeof(uint32_t), size_ - sizeof(uint32_t)); \
    }                                                                    \
  } while (0)

static void geometry(const sk_view *surface, int face, const double xi[2], const double *x, sk_surface_point *point) {
#define CALL(p) sk_surface_geometry(surface_of(surface), face, xi, x, p)
  FILL_SIZED(sk_surface_point, point, CALL);
#undef CALL
}

static void nodal_normals(const sk_view *surface, const double *x, double *normals) {
  sk_surface_nodal_normals(surface_of(surface), x, normals);
}

static sk_status project(const sk_view *surface, const double *x, const double *point, const int *candidates,
                         int n_candidates, sk_projection *projection) {
  sk_status status = SK_OK;
#define CALL(p) status = sk_surface_project(surface_of(surface), x, point, candidates, n_candidates, p)
  FILL_SIZED(sk_projection, projection, CALL);
#undef CALL
  return status;
}

static sk_status search_create(const sk_view *surface, sk_search **search) {
  return sk_search_create(surface_of(surface), search);
}

static sk_status obstacle_project(const sk_obstacle *obstacle, double t, const double *point, int dim,
                                  sk_surface_point *closest, double *gap) {
  sk_status status = SK_OK;
#define CALL(p) status = sk_obstacle_project(obstacle, t, point, dim, p, gap)
  FILL_SIZED(sk_surface_point, closest, CALL);
#undef CALL
  return status;
}

const sk_contact_services sk_host_contact_table = {
    SK_TABLE_HEADER(sk_contact_services),
    .geometry = geometry,
    .nodal_normals = nodal_normals,
    .project = project,
    .search_create = search_create,
    .search_destroy = sk_search_destroy,
    .search_update = sk_search_update,
    .search_query = sk_search_query,
    .search_rebuild = sk_search_rebuild,
    .obstacle_project = obstacle_project,
    .obstacle_displacement = sk_obstacle_displacement,
    .shape = sk_elem_shape,
    .shape_hessian = sk_elem_shape_hessian,
    .quadrature = sk_face_quadrature,
};

