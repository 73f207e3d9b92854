/* The core's contact services as the table plugins receive (plugin.h), shared by the host and by tests' mock hosts. */
#include "stickslip/fe.h"
#include "stickslip/plugin.h"

static const sk_contact_services core_contact_services = {
    .geometry = sk_surface_geometry,
    .nodal_normals = sk_surface_nodal_normals,
    .project = sk_surface_project,
    .search_create = sk_search_create,
    .search_destroy = sk_search_destroy,
    .search_update = sk_search_update,
    .search_query = sk_search_query,
    .obstacle_project = sk_obstacle_project,
    .shape = sk_elem_shape,
    .shape_hessian = sk_elem_shape_hessian,
    .obstacle_displacement = sk_obstacle_displacement,
    .search_rebuild = sk_search_rebuild,
};

const sk_contact_services *sk_core_contact_services(void) { return &core_contact_services; }
