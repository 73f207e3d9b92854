#!/usr/bin/env bash
# Pictures of the deformed bodies at a few instants, without ParaView or a display: the outer surface of the meshes in
# RESULTS/*.vtu coloured by a point field (displacement magnitude by default, or contact_pressure, ...), rendered off
# screen by gnuplot. Writes RESULTS/snapshots.png (all instants on one frame and colour scale) and
# RESULTS/snapshots/step-NNNNNN.png (one per instant).
# Usage: scripts/plot-snapshots.sh RESULTS [--field NAME] [--count N | --times t1,t2,...] [--view ROT_X,ROT_Z]
#        [--size WxH] [--title TEXT]        (--help lists them)
set -euo pipefail
command -v gnuplot >/dev/null || { echo "plot-snapshots: gnuplot is not installed (scripts/install-deps.sh)" >&2; exit 1; }
command -v python3 >/dev/null || { echo "plot-snapshots: python3 is not installed (scripts/install-deps.sh)" >&2; exit 1; }
exec python3 "$(dirname "$0")/plot_snapshots.py" "$@"
