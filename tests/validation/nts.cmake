# nts-augmented (Franke, Hesch & Betsch 2013): Table I two-element scene and the coarse two-tori impact, through
# the driver (scenes/two-elements.yaml, scenes/two-tori-coarse.yaml). Each case runs in a few seconds, except
# two_tori_coarse_full (the full 500 coarse steps, ~100 s).
stickslip_scene_tests(test_nts_scenes.py
  two_elements_midpoint two_elements_dt02 two_elements_none_vs_reduced two_elements_direct_vs_reduced
  two_elements_newton_quadratic two_tori_coarse two_tori_coarse_full)
set_tests_properties(validation_two_tori_coarse_full PROPERTIES TIMEOUT 900)
