# The short pass of the numerical stress suite (tests/bench/stress.py, docs/stability.md): one test per case in
# tests/bench/stress/, every declared plugin's default strategy on the case's short values, run afresh. A test fails
# on a divergence, a refused input, or a quantity beyond its bound (energy gain, active-set changes, Newton
# iterations, step cuts). About 3 minutes in all on 2 idle cores; label "stress".
# The harness's declarations are checked too (bench_declarations: every benchmark and stress declaration parses,
# names existing plugins, strategies and benchmarks, and `stickslip check` accepts one run of each).
file(GLOB stress_case_files ${CMAKE_SOURCE_DIR}/tests/bench/stress/*.yaml)
set(stress_environment "STICKSLIP_BIN=$<TARGET_FILE:stickslip>;STICKSLIP_BENCH_OUT=${CMAKE_BINARY_DIR}/stress")
foreach(case_file ${stress_case_files})
  get_filename_component(case ${case_file} NAME_WE)
  add_test(NAME stress_${case}
           COMMAND ${Python3_EXECUTABLE} ${CMAKE_SOURCE_DIR}/tests/bench/stress.py --short --check --fresh ${case})
  set_tests_properties(stress_${case} PROPERTIES LABELS "stress" ENVIRONMENT "${stress_environment}")
endforeach()
add_test(NAME bench_declarations
         COMMAND ${Python3_EXECUTABLE} ${CMAKE_SOURCE_DIR}/tests/bench/workprecision.py --check --strict)
set_tests_properties(bench_declarations PROPERTIES LABELS "stress" ENVIRONMENT "${stress_environment}")
add_test(NAME bench_harness COMMAND ${Python3_EXECUTABLE} ${CMAKE_SOURCE_DIR}/tests/bench/harness/test_harness.py)
set_tests_properties(bench_harness PROPERTIES LABELS "stress")
