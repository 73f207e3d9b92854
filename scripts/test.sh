#!/usr/bin/env bash
# The whole test suite on a fresh machine: installs the dependencies, builds, runs ctest (unit, validation, MPI and
# command-line tests). Extra arguments go to ctest (e.g. -R mesh, -L unit).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
cd build
ctest --output-on-failure -j "$(nproc)" "$@"
