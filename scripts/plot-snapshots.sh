#!/usr/bin/env bash
# Pictures of the deformed bodies at a few instants, without ParaView or a display: the outer surface of the meshes in
# RESULTS/step-*.pvtu (their pieces joined) coloured by a point field (displacement magnitude by default, or
# contact_pressure, ...), with the rigid obstacles, rendered off screen by gnuplot. All instants share one frame (axes
# and colour scale): RESULTS/snapshots.png draws them in one picture when the bodies move apart, side by side otherwise;
# RESULTS/snapshots/step-NNNNNN.png has one per instant. --contact draws the contact surfaces coloured by the contact
# pressure (RESULTS/snapshots-contact.png).
# Usage: scripts/plot-snapshots.sh RESULTS [--field NAME] [--count N | --times t1,t2,...] [--layout auto|overlay|panels]
#        [--contact] [--no-obstacles] [--view ROT_X,ROT_Z] [--zoom Z] [--size WxH] [--title TEXT]   (--help)
set -euo pipefail
command -v gnuplot >/dev/null || { echo "plot-snapshots: gnuplot is not installed (scripts/install-deps.sh)" >&2; exit 1; }
command -v python3 >/dev/null || { echo "plot-snapshots: python3 is not installed (scripts/install-deps.sh)" >&2; exit 1; }
exec python3 "$(dirname "$0")/plot_snapshots.py" "$@"
