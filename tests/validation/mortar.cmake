# mortar-dual scenes (test_mortar_scenes.py): patch tests 2D/3D, 2D with quad9/tri6 (LINE3 faces), 3D on hex27 (QUAD9
# faces), hex20 (QUAD8 faces) and tet10 (TRI6 faces), Hertz 2D quad9, the quad9 ring on a block with friction, the
# refusal of condensed on tri6 and quad8 slave faces, Hammer's
# benchmark (segments: path independence), block on a rigid plane (2D, 3D), 1 vs 2 ranks, Hertz 3D, 2D ironing
# (shortened), 3D ironing condensed with GMRES + MueLu against MUMPS and on conforming meshes, large sliding at large
# steps (tests/bench/stress/scenes/slider-2d.yaml, shortened).
stickslip_scene_tests(test_mortar_scenes.py mortar_patch_test_2d mortar_patch_test_2d_quadratic mortar_hertz_2d_quadratic
                      mortar_ring_on_block_quad9 mortar_quadratic_3d_refused mortar_patch_test_3d
                      mortar_patch_test_3d_quad9 mortar_patch_test_3d_quad8 mortar_patch_test_3d_tri6
                      mortar_hammer_benchmark
                      mortar_block_on_plane mortar_mpi mortar_hertz_3d mortar_ironing_2d
                      mortar_condensed mortar_condensed_krylov mortar_large_sliding mortar_obstacle_3d
                      mortar_obstacle_3d_quad9
                      mortar_ironing_3d_conforming)
# Hammer's examples with his set-up, against the thesis (test_mortar_thesis.py; docs/plugins/mortar-dual.md, "Against
# the paper"): the simple benchmark frictionless (Tables 8.2/8.3, Fig. 8.4) and with friction (Fig. 8.5), Hertz, the
# elastic ring, the deep ironing (its press and the start of the ironing; with friction to t = 3 at two refinements,
# about 35 s CPU: labelled long, tests/validation/CMakeLists.txt).
stickslip_scene_tests(test_mortar_thesis.py mortar_hammer_thesis mortar_hammer_thesis_friction mortar_hertz_2d
                      mortar_ring mortar_deep_ironing mortar_deep_ironing_refinement)
set_tests_properties(validation_mortar_mpi PROPERTIES LABELS "validation;mpi" PROCESSORS 2)
