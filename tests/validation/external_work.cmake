# history.csv's external_work against the midpoint scheme's energy balance (test_external_work.py).
stickslip_scene_tests(test_external_work.py external_work_traction_body_force external_work_resultant_current_area
                      external_work_restart
                      external_work_corotational_at_rest external_work_corotational_spinning)
set_tests_properties(validation_external_work_resultant_current_area PROPERTIES LABELS "validation;mpi" PROCESSORS 2)
