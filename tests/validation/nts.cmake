# nts-augmented (Franke, Hesch & Betsch 2013) through the driver: the Table I two-element scene with every strategy,
# the coarse two-tori impact (every strategy for 8 steps, ~30 s; two_tori_coarse_full: the 500 steps, ~100 s), and
# the 2D / rigid-obstacle scenes of penalty-nts (patch test, Hertz 2D, block on a plane) with this plugin's multipliers,
# and the stress slider (tests/bench/stress, to t = 2.5) against penalty-nts: the normal force under large sliding.
stickslip_scene_tests(test_nts_scenes.py
  two_elements_midpoint two_elements_dt02 two_elements_strategies two_elements_direct_vs_reduced
  two_elements_euler_damping
  two_elements_newton_quadratic two_tori_coarse two_tori_coarse_friction two_tori_coarse_full two_tori_paper_start
  nts_patch_test_2d nts_hertz_2d nts_block_on_plane
  nts_slider_2d nts_slider_3d)
set_tests_properties(validation_two_tori_coarse_full PROPERTIES TIMEOUT 900)
