#!/bin/sh
# Benchmark (c): the two-tori impact, mu = 0.1 and mu = 0.3, both runs at once, then the 4-panel history plots
# (scripts/plot-history.sh) copied to docs/img/nts-tori-mu01.png and docs/img/nts-tori-mu03.png.
#   sh tests/bench/nts-augmented/tori.sh coarse 100   # scenes/two-tori-coarse.yaml (270 hex8 per torus), MUMPS
#   sh tests/bench/nts-augmented/tori.sh fine 30      # scenes/two-tori{,-mu03}.yaml (8024 per torus): hours (docs)
# The full run is 500 steps to t = 5. The script prints wall time, steps, Newton iterations and the time split.
set -e
here=$(cd "$(dirname "$0")" && pwd); root=$(cd "$here/../../.." && pwd)
bin=${STICKSLIP_BIN:-$root/build/bin/stickslip}
out=${NTS_BENCH_OUT:-$root/results/bench-nts-augmented}
size=${1:-coarse}; steps=${2:-100}
if [ "$size" = coarse ]; then
  "$bin" run "$root/scenes/two-tori-coarse.yaml" --steps "$steps" --quiet --set solver.linear.solver=direct \
    --out "$out/$size-mu01" &
  "$bin" run "$root/scenes/two-tori-coarse.yaml" --steps "$steps" --quiet --set solver.linear.solver=direct \
    --set contact.0.parameters.mu=0.3 --out "$out/$size-mu03" &
else
  "$bin" run "$root/scenes/two-tori.yaml" --steps "$steps" --quiet --out "$out/$size-mu01" &
  "$bin" run "$root/scenes/two-tori-mu03.yaml" --steps "$steps" --quiet --out "$out/$size-mu03" &
fi
wait
for mu in 01 03; do
  "$root/scripts/plot-history.sh" "$out/$size-mu$mu" "two tori $size, mu = 0.${mu#0}, first $steps steps"
  cp "$out/$size-mu$mu/history.png" "$root/docs/img/nts-tori-mu$mu.png"
  python3 - "$out/$size-mu$mu/summary.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
print("%s: %s, %d steps to t = %.2f, %d Newton iterations, wall %.1f s (assembly %.1f, contact %.2f, solve %.1f), "
      "linear system %d" % (s["scene"], s["status"], s["steps"], s["final_time"], s["newton_iterations"],
                            s["wall_seconds"], s["assembly_seconds"], s["contact_seconds"], s["solve_seconds"],
                            s["linear_system_size"]))
PY
done
