# Contact among many bodies (test_many_bodies.py): pairs created by `bodies: all` against the same pairs written out,
# and the pile of disks in a box (scenes/disks-in-box-2d.yaml, short).
stickslip_scene_tests(test_many_bodies.py bodies_all_matches_explicit disks_in_box)
