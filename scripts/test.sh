#!/usr/bin/env bash
# The whole test suite on a fresh machine: installs the dependencies, builds, runs ctest (unit, validation, MPI and
# command-line tests) except the label "long" (the longest validation runs). Extra arguments go to ctest instead of that
# default (e.g. -R mesh, -L unit, -L long; no label filter: -LE none).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
cd build
if [ $# -eq 0 ]; then set -- -LE long; fi
ctest --output-on-failure -j "$(nproc)" "$@"
