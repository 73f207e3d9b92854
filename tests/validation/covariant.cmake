# covariant-penalty (Konyukhov & Schweizerhof 2005): the paper's examples 6.1-6.3 through the driver
# (scenes/ks-*.yaml). CPU time on 2 cores: ks_parabolic ~45 s (three variants on the paper's hex27 mesh), the others
# 5-25 s each.
stickslip_scene_tests(test_covariant_scenes.py ks_block_b ks_block_a ks_parabolic ks_spiral ks_spiral_rotated
                      ks_spiral_mpi)
set_tests_properties(validation_ks_spiral_mpi PROPERTIES LABELS "validation;mpi" PROCESSORS 2)
