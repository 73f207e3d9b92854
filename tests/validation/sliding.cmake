# Large sliding within one step (test_large_sliding.py): slave points that slide beyond their candidate faces, for
# the plugins that search again at the converged point (penalty-nts, covariant-penalty). About 10-20 s each on 2 cores.
stickslip_scene_tests(test_large_sliding.py large_sliding_penalty_nts_2d large_sliding_penalty_nts_3d
                      large_sliding_covariant_sts large_sliding_covariant_nts)
