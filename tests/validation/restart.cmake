# Checkpoint and restart (test_restart.py): same and other rank counts, friction and body-plugin scenes, refusals.
stickslip_scene_tests(test_restart.py restart_friction_same_ranks restart_friction_other_ranks restart_body_plugin
                      restart_refusals restart_reghosted)
set_tests_properties(validation_restart_friction_same_ranks validation_restart_friction_other_ranks
                     validation_restart_reghosted PROPERTIES LABELS "validation;mpi" PROCESSORS 2)
