#!/usr/bin/env bash
# The main job on a fresh machine: installs the dependencies, builds, runs the bundled default scene, plots its
# history and draws the deformed bodies at four instants.
# Usage: scripts/demo.sh [SCENE.yaml] [extra `stickslip run` arguments]
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
echo "results: $out/ (history.csv, summary.json, contact.csv over time; results.pvd, contact.pvd for ParaView)"
echo "plot:    $out/history.png (the panels that fit the run)"
if [ -f "$out/results.pvd" ]; then # unless the scene turned output.vtu off
  scripts/plot-snapshots.sh "$out" --title "$name: |displacement|"
  echo "bodies:  $out/snapshots.png (more: scripts/plot-snapshots.sh $out --field contact_pressure, --contact, --help)"
fi
