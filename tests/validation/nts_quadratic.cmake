# nts-augmented on second-order faces (test_nts_quadratic.py): the quad9 contact patch test (matching and non-matching
# interface meshes) and the quad9 Hertz 2D profile error. About 2 and 3.5 s of CPU.
stickslip_scene_tests(test_nts_quadratic.py nts_quad9_patch_2d nts_quad9_hertz_2d)
