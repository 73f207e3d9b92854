# nts-augmented with self contact (test_nts_self_contact.py): the thin ring crushed until its inner surface touches
# itself, with and without the self pair; the ten-disk pile (energy never created, momentum balance).
stickslip_scene_tests(test_nts_self_contact.py nts_ring_crush_self_contact nts_disk_pile_energy)
