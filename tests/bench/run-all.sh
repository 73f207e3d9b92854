#!/usr/bin/env bash
# Every benchmark figure and table of docs/benchmarks.md and docs/stability.md, from scratch: the work-precision
# runs of every declared plugin on every benchmark, the condensation table, then the full stress suite.
#   tests/bench/run-all.sh [--jobs N]       (default 1 job: CPU times are cleanest on an otherwise idle machine)
# Needs build/bin/stickslip (scripts/build.sh) or STICKSLIP_BIN. Results go to results/bench/ (not committed);
# docs/benchmarks.md, docs/stability.md, docs/img/wp-*.png and docs/data/wp-*.csv are rewritten.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
jobs=1
[ "${1:-}" = "--jobs" ] && jobs=${2:?--jobs N}
start=$(date +%s)
python3 "$here/workprecision.py" --all --fresh --jobs "$jobs"
python3 "$here/condensation.py"
python3 "$here/stress.py" --fresh --jobs "$jobs"
echo "run-all: $(( ($(date +%s) - start) / 60 )) minutes"
