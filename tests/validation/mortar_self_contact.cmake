# mortar-dual self contact (test_mortar_self_contact.py): the thin ring crushed until its inner surface touches
# itself, the self pair run by mortar-dual (dynamic slave/master sides), with and without the pair; condensed against
# saddle-point; the thin tube flattened until its inner wall meets itself (3D, quad4 faces, a short tube; and on quad9
# faces, labelled long: about 35 s CPU); the ring with friction on the self pair.
stickslip_scene_tests(test_mortar_self_contact.py mortar_ring_crush_self_contact mortar_self_contact_condensed
  mortar_tube_crush_self_contact mortar_tube_crush_self_contact_quad9 mortar_ring_crush_self_friction)
set_property(TEST validation_mortar_tube_crush_self_contact_quad9 APPEND PROPERTY LABELS long)
