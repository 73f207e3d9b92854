# Contact among many bodies (test_many_bodies.py): pairs created by `bodies: all` against the same pairs written out,
# and the pile of disks in a box (scenes/disks-in-box-2d.yaml, short).
stickslip_scene_tests(test_many_bodies.py bodies_all_matches_explicit disks_in_box)
# Eight coarse tori dropped onto a floor (scenes/tori-on-plane-3d.yaml, short) on 1 and 2 ranks.
stickslip_scene_tests(test_many_bodies.py tori_on_plane)
set_tests_properties(validation_tori_on_plane PROPERTIES LABELS "validation;mpi" PROCESSORS 2)
