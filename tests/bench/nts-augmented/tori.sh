#!/bin/sh
# Benchmark (c): the two-tori impact at full resolution (scenes/two-tori.yaml, mu = 0.1; scenes/two-tori-mu03.yaml,
# mu = 0.3; 8024 hex8 per torus, 72216 dofs), truncated to STEPS steps (default 30; the full run is 500 steps),
# then the 4-panel history plots (scripts/plot-history.sh) copied to docs/img/nts-tori-mu01.png / nts-tori-mu03.png
# and a one-line summary per run (wall time, steps, Newton iterations, assembly/contact/solve seconds).
# Usage: sh tests/bench/nts-augmented/tori.sh [STEPS]
set -e
here=$(cd "$(dirname "$0")" && pwd); root=$(cd "$here/../../.." && pwd)
bin=${STICKSLIP_BIN:-$root/build/bin/stickslip}
out=${NTS_BENCH_OUT:-$root/results/bench-nts-augmented}
steps=${1:-30}
for case in "two-tori mu01" "two-tori-mu03 mu03"; do
  set -- $case
  "$bin" run "$root/scenes/$1.yaml" --steps "$steps" --quiet --out "$out/tori-$2" &
done
wait
for mu in mu01 mu03; do
  "$root/scripts/plot-history.sh" "$out/tori-$mu"
  cp "$out/tori-$mu/history.png" "$root/docs/img/nts-tori-$mu.png"
  python3 - "$out/tori-$mu/summary.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
print("%s: %s, %d steps to t = %.2f, %d Newton iterations, wall %.0f s (assembly %.0f, contact %.1f, solve %.0f), "
      "linear system %d" % (s["scene"], s["status"], s["steps"], s["final_time"], s["newton_iterations"],
                            s["wall_seconds"], s["assembly_seconds"], s["contact_seconds"], s["solve_seconds"],
                            s["linear_system_size"]))
PY
done
