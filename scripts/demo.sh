#!/usr/bin/env bash
# The main job on a fresh machine: installs the dependencies, builds, runs the bundled default scene and plots its
# energy/momentum history. Usage: scripts/demo.sh [SCENE.yaml] [extra `stickslip run` arguments]
set -euo pipefail
cd "$(dirname "$0")/.."
scene=${1:-scenes/two-tori-coarse.yaml}
shift || true
scripts/install-deps.sh
scripts/build.sh
name=$(basename "$scene" .yaml)
out=results/$name
mkdir -p results
build/bin/stickslip run "$scene" --out "$out" "$@"
scripts/plot-history.sh "$out" "$name"
echo "results: $out/ (history.csv, summary.json, results.pvd for ParaView)"
echo "plot:    $out/history.png"
