# Self contact (test_self_contact.py): the thin ring crushed until its inner surface touches itself, with and
# without the self pair; the thin tube (tube-crush-3d.yaml, coarser) flattened likewise; plugins without the
# capability refused at check; `bodies: [ring]` with `self: true` against the same pairs written out.
stickslip_scene_tests(test_self_contact.py ring_crush_self_contact tube_crush_self_contact
  tube_crush_nts_self_contact
  bodies_self_matches_explicit self_contact_refused)
