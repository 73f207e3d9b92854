# covariant-penalty (Konyukhov & Schweizerhof 2005): the paper's examples 6.1-6.3 through the driver
# (scenes/ks-*.yaml) against the paper's values (docs/plugins/covariant-penalty.md, "Against the paper"). Each case
# runs one to three scenes (ks_parabolic: 15 steps of the hex27 mesh and a 7-step pressing; ks_block_b: two
# 21-step runs), tens of seconds each. Labelled long (tests/validation/CMakeLists.txt): ks_parabolic_contact_loss
# (39 steps) and ks_parabolic_table4_penalty_e (27 steps), about 25 s CPU each, and ks_parabolic_table4_main_only
# (27 steps, linear convergence), about 40 s CPU, and ks_parabolic_small_steps (two 17-step runs), about 14 s CPU.
stickslip_scene_tests(test_covariant_scenes.py ks_block_b ks_block_a ks_block_a_plane_strain ks_parabolic ks_spiral
                      ks_spiral_rotated ks_spiral_mpi ks_parabolic_contact_loss ks_parabolic_table4_penalty_e
                      ks_parabolic_table4_main_only ks_parabolic_small_steps)
set_tests_properties(validation_ks_spiral_mpi PROPERTIES LABELS "validation;mpi" PROCESSORS 2)
