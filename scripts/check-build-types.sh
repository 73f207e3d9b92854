#!/usr/bin/env bash
# Compiles everything (library, plugins, driver, tests) under the CMake build types users pick, with warnings as
# errors, so that -Wall -Wextra stays clean where the optimiser differs from the developers' RelWithDebInfo (GCC's
# maybe-uninitialized analysis depends on inlining: -O3 finds what -O2 -g does not). Compile only, no tests run.
# Build trees: build-check/<type>. Usage: scripts/check-build-types.sh [TYPE...]   (default: Release Debug)
set -euo pipefail
cd "$(dirname "$0")/.."
types=("$@")
[ ${#types[@]} -gt 0 ] || types=(Release Debug)
for type in "${types[@]}"; do
  dir=build-check/$type
  mkdir -p "$dir"
  start=$SECONDS
  cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE="$type" -DSTICKSLIP_WERROR=ON >"$dir.configure.log" 2>&1 || {
    cat "$dir.configure.log"
    exit 1
  }
  if ! cmake --build "$dir" -j "$(nproc)" >"$dir.build.log" 2>&1; then
    grep -E "error|warning" "$dir.build.log" | grep -v "^\[" || tail -30 "$dir.build.log"
    echo "check-build-types: $type build failed (log: $dir.build.log)" >&2
    exit 1
  fi
  echo "check-build-types: $type compiles warning-free ($((SECONDS - start)) s)"
done
