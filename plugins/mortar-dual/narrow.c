/* mortar-dual: the kernel and the evaluation compiled a second time with 36 derivative slots and faces of at most 4
 * nodes (fwd.h, kernel.h), for pairs of first-order faces (and LINE3 in 2D): with the 81 slots of a QUAD9 pair every
 * fwd is 2.2 times as large, and first-order runs paid for the copies (docs/plugins/mortar-dual.md section 9.3). The
 * arithmetic is the same (every loop runs over the slots in use), so the results are the same to the bit. The plugin
 * calls mortar_narrow_evaluate for such pairs (inst->narrow); the other functions of this copy are renamed here so
 * that both copies link into one module, and only the evaluation's tree calls them. */
#define MORTAR_NARROW 1

/* kernel.h, kernel_internal.h */
#define mortar_add_point mortar_narrow_add_point
#define mortar_add_point_shapes mortar_narrow_add_point_shapes
#define mortar_along mortar_narrow_along
#define mortar_along_fwd mortar_narrow_along_fwd
#define mortar_closest_fwd mortar_narrow_closest_fwd
#define mortar_basis_coefficients mortar_narrow_basis_coefficients
#define mortar_face_exact_order mortar_narrow_face_exact_order
#define mortar_face_normal mortar_narrow_face_normal
#define mortar_face_normal_at_node mortar_narrow_face_normal_at_node
#define mortar_face_point mortar_narrow_face_point
#define mortar_face_rule mortar_narrow_face_rule
#define mortar_face_type_init mortar_narrow_face_type_init
#define mortar_face_values mortar_narrow_face_values
#define mortar_gauss_legendre mortar_narrow_gauss_legendre
#define mortar_implicit mortar_narrow_implicit
#define mortar_integrals_zero mortar_narrow_integrals_zero
#define mortar_ncp_places mortar_narrow_ncp_places
#define mortar_normalize mortar_narrow_normalize
#define mortar_obstacle_points mortar_narrow_obstacle_points
#define mortar_pair_forces mortar_narrow_pair_forces
#define mortar_pair_set mortar_narrow_pair_set
#define mortar_pair_weighted_positions mortar_narrow_pair_weighted_positions
#define mortar_points mortar_narrow_points
#define mortar_project_point mortar_narrow_project_point
#define mortar_segments_2d mortar_narrow_segments_2d
#define mortar_segments_3d mortar_narrow_segments_3d
#define mortar_shape mortar_narrow_shape
#define mortar_slave_integrals mortar_narrow_slave_integrals
#define mortar_slave_normal mortar_narrow_slave_normal
#define mortar_solve_small mortar_narrow_solve_small
#define mortar_tangents mortar_narrow_tangents
#define mortar_transform mortar_narrow_transform
#define mortar_transform_values mortar_narrow_transform_values
#define mortar_triangle_rule mortar_narrow_triangle_rule
#define mortar_values mortar_narrow_values
/* mortar.h: assemble.c, cache.c */
#define mortar_compute_normals mortar_narrow_compute_normals
#define mortar_pair_reaches mortar_narrow_pair_reaches
#define mortar_evaluate mortar_narrow_evaluate
#define mortar_cache_size mortar_narrow_cache_size
#define mortar_cache_begin mortar_narrow_cache_begin
#define mortar_cache_end mortar_narrow_cache_end
#define mortar_cache_put mortar_narrow_cache_put
#define mortar_cache_get mortar_narrow_cache_get

#include "basis.c"
#include "integrate.c"
#include "projection.c"
#include "clip.c"
#include "assemble.c"
#include "cache.c"
