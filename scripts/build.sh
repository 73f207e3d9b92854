#!/usr/bin/env bash
# Configures and builds stickslip into build/ (Release with debug info, warnings as errors: the developers' and
# CI's build). Idempotent. Usage: scripts/build.sh [extra cmake arguments]
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${BUILD_DIR:-build}
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSTICKSLIP_WERROR=ON "$@" >"$BUILD_DIR.configure.log" 2>&1 || {
  cat "$BUILD_DIR.configure.log"
  exit 1
}
cmake --build "$BUILD_DIR" -j "$(nproc)" 2>&1 | grep -E "error|warning|Error" || true
cmake --build "$BUILD_DIR" -j "$(nproc)" >/dev/null
echo "build: $BUILD_DIR/bin/stickslip"
