# nts-augmented on second-order faces (test_nts_quadratic.py): the quad9 contact patch test (matching and non-matching
# interface meshes), the hex27 one and the quad9 Hertz 2D profile error. About 2, 3 and 3.5 s of CPU.
stickslip_scene_tests(test_nts_quadratic.py nts_quad9_patch_2d nts_hex27_patch_3d nts_quad9_hertz_2d)
