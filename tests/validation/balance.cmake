# Contact work per rank (test_contact_balance.py): summary.json's balance statistics on 1 and 2 ranks.
stickslip_scene_tests(test_contact_balance.py contact_balance)
set_tests_properties(validation_contact_balance PROPERTIES LABELS "validation;mpi" PROCESSORS 2)
# The contact partition (contact_balance.rebalance: on) equal to the bulk partition on 1, 2 and 4 ranks, with
# penalty-nts (friction) and nts-augmented (extras), restarted on 2 ranks from a checkpoint written on 4, and
# rebalanced between steps, and restarted with the rebalanced partition; the 4-rank runs are cases of their own (each case <= 5 s CPU).
set(partition_cases contact_partition contact_partition_4 contact_partition_extras contact_partition_extras_4
    contact_partition_restart contact_partition_rebalanced contact_partition_rebalanced_4
    contact_partition_rebalanced_extras contact_partition_restart_rebalanced)
stickslip_scene_tests(test_contact_balance.py ${partition_cases})
foreach(case ${partition_cases})
  set_tests_properties(validation_${case} PROPERTIES LABELS "validation;mpi" PROCESSORS 2)
endforeach()
# mortar-dual on 4 ranks (its averaged normals need the slave view's second layer of faces): about 5 s CPU, labelled
# long in CMakeLists.txt.
stickslip_scene_tests(test_contact_balance.py contact_partition_mortar)
set_tests_properties(validation_contact_partition_mortar PROPERTIES LABELS "validation;mpi" PROCESSORS 2)
# mortar-dual with the bulk partition on 8 ranks (the slave view's second layer of faces ghosted by the host): about
# 25 s CPU, labelled long in CMakeLists.txt.
stickslip_scene_tests(test_contact_balance.py bulk_partition_mortar_8)
set_tests_properties(validation_bulk_partition_mortar_8 PROPERTIES LABELS "validation;mpi" PROCESSORS 2)
# A restart equal to the uninterrupted run to the bit (1 rank, about 3 s CPU).
stickslip_scene_tests(test_contact_balance.py restart_to_the_bit)
