# Contact work per rank (test_contact_balance.py): summary.json's balance statistics on 1 and 2 ranks.
stickslip_scene_tests(test_contact_balance.py contact_balance)
set_tests_properties(validation_contact_balance PROPERTIES LABELS "validation;mpi" PROCESSORS 2)
