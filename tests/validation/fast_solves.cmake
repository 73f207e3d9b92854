# The iterative linear path on a contact run (issue 8): GMRES + MueLu / SGS against MUMPS on the coarse two-tori,
# 12 steps (~10 s).
stickslip_scene_tests(test_fast_solves.py two_tori_coarse_iterative_vs_direct)
# MUMPS's iterative refinement on a saddle point with changed contact rows: two elements to t = 6 (~5 s).
stickslip_scene_tests(test_fast_solves.py direct_solve_refinement)
# solver.pattern_margin: fewer pattern rebuilds, the same history (coarse two-tori, 60 steps: margin 0 and 1 on one
# rank, margin 1 on two; ~15 s).
stickslip_scene_tests(test_fast_solves.py pattern_margin_same_history)
set_tests_properties(validation_pattern_margin_same_history PROPERTIES LABELS "validation;mpi" PROCESSORS 2)
# gmres-lu (the lagged LU) against MUMPS on 2D Hertz: the same forces and profile, fewer factorisations (~2 s).
stickslip_scene_tests(test_fast_solves.py hertz_2d_lagged_lu)
# GMRES + MueLu on 4 ranks through a recomputed preconditioner, against MUMPS on one rank (corner-contact, 2 steps;
# ~2 s CPU).
stickslip_scene_tests(test_fast_solves.py muelu_four_ranks)
set_tests_properties(validation_muelu_four_ranks PROPERTIES LABELS "validation;mpi" PROCESSORS 2)
