# mortar-dual scenes (test_mortar_scenes.py): patch tests 2D/3D, Hammer's benchmark, block on a plane, 1 vs 2 ranks.
stickslip_scene_tests(test_mortar_scenes.py mortar_patch_test_2d mortar_patch_test_3d mortar_hammer_benchmark
                      mortar_hammer_benchmark_friction mortar_block_on_plane mortar_mpi)
set_tests_properties(validation_mortar_mpi PROPERTIES LABELS "validation;mpi" PROCESSORS 2)
