# Second-order elements from a scene (mesh.order: 2) with penalty-nts (test_quadratic_scenes.py): the 3D contact patch
# test on hex8/hex27/tet4/tet10 (and the hex20 refusal), Hertz 3D refinement with tet10, Hertz 2D with quad9/tri6,
# tet10 on 1 and 2 ranks, the VTU cells of a tet10 run and the mesh-key errors, the resultant load on hex27/hex20
# (reactions = -R, reference area = traction, 1 vs 2 ranks), the refusals of plugins without second-order faces. About 60 s of CPU in total.
stickslip_scene_tests(test_quadratic_scenes.py patch_test_3d hertz_3d_quadratic hertz_2d_quadratic quadratic_output
                      hertz_3d_quadratic_mpi resultant_load resultant_load_mpi quadratic_refusals)
set_tests_properties(validation_hertz_3d_quadratic_mpi validation_resultant_load_mpi PROPERTIES LABELS "validation;mpi"
                     PROCESSORS 2)
