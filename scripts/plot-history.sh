#!/usr/bin/env bash
# The history of a run (history.csv) as panels that fit the run, drawn by gnuplot into RESULTS/history.png:
# quasi-static runs get load-displacement, contact forces, energy (and dissipation with friction) and Newton iterations;
# dynamic runs energies, their conservation (with the dissipation under friction), momenta and contact forces.
# Usage: scripts/plot-history.sh RESULTS [title] [--size WxH]        (--help says which panels fit which run)
set -euo pipefail
command -v gnuplot >/dev/null || { echo "plot-history: gnuplot is not installed (scripts/install-deps.sh)" >&2; exit 1; }
command -v python3 >/dev/null || { echo "plot-history: python3 is not installed (scripts/install-deps.sh)" >&2; exit 1; }
exec python3 "$(dirname "$0")/plot_history.py" "$@"
