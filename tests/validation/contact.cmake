# Contact scenes with the baseline plugin penalty-nts (test_contact_scenes.py): Hertz 2D/3D, patch test, block on a
# plane with friction, two-element impact, frame indifference, MPI. About 80 s in total on 2 cores.
stickslip_scene_tests(test_contact_scenes.py hertz_2d hertz_2d_rotated hertz_3d patch_test_2d block_on_plane
                      two_elements_penalty two_elements_penalty_friction hertz_2d_mpi
                      master_ghosting_renewed newton_predicted_update)
set_tests_properties(validation_hertz_2d_mpi validation_master_ghosting_renewed PROPERTIES LABELS "validation;mpi"
                     PROCESSORS 2)
