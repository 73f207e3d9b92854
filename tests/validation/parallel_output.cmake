# The bodies' VTU in pieces, one per rank, 1 against 2 ranks (issue 33; test_parallel_output.py).
stickslip_scene_tests(test_parallel_output.py parallel_output_pieces)
set_tests_properties(validation_parallel_output_pieces PROPERTIES LABELS "validation;mpi" PROCESSORS 2)
