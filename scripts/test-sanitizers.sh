#!/usr/bin/env bash
# The unit, command-line and fuzz (short pass) tests under AddressSanitizer + UndefinedBehaviorSanitizer
# (build-asan/). Leak checking is off: gmsh 4.8.4 and Open MPI leak at exit on their own (reported by LeakSanitizer
# inside those libraries).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
BUILD_DIR=build-asan scripts/build.sh -DSTICKSLIP_SANITIZE=ON
export ASAN_OPTIONS=detect_leaks=0:abort_on_error=0 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
cd build-asan
ctest --output-on-failure -j "$(nproc)" -L "unit|cli|fuzz" "$@"
