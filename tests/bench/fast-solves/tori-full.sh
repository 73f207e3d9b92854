#!/bin/sh
# Benchmark (issue 8): the full two-tori impact (scenes/two-tori.yaml: 2 x 8024 hex8, 72 216 dofs, nts-augmented
# condensed, midpoint, dt = 0.01), 500 steps to t = 5, for mu = 0.1 and mu = 0.3, with the default solver settings
# (`auto`: it measures its candidates and keeps the cheapest, see docs/linear-solvers.md).
#
#   sh tests/bench/fast-solves/tori-full.sh                  # 500 steps, 1 rank, both mu, one after the other
#   sh tests/bench/fast-solves/tori-full.sh 500 2            # the same on 2 ranks (mpirun -np 2)
#   sh tests/bench/fast-solves/tori-full.sh 40 1 0.3         # the first 40 steps, mu = 0.3 only
#
# For each run it prints the wall time, the CPU time of all ranks (user + sys, /usr/bin/time), steps, Newton
# iterations and linear solves and the program's own split (assembly, contact, solve), and writes the 4-panel history
# plot (scripts/plot-history.sh) to docs/img/fast-solves-tori-mu01.png / -mu03.png. Results: results/bench-fast-solves
# (FAST_SOLVES_OUT overrides). The goal of issue 8 is <= 10 minutes wall per 500-step run on an idle 2-core machine.
set -e
here=$(cd "$(dirname "$0")" && pwd); root=$(cd "$here/../../.." && pwd)
bin=${STICKSLIP_BIN:-$root/build/bin/stickslip}
out=${FAST_SOLVES_OUT:-$root/results/bench-fast-solves}
steps=${1:-500}; ranks=${2:-1}; mus=${3:-"0.1 0.3"}
[ -x "$bin" ] || { echo "tori-full.sh: no $bin (build first: scripts/build.sh)" >&2; exit 1; }
command -v /usr/bin/time >/dev/null 2>&1 || { echo "tori-full.sh: /usr/bin/time is needed (apt-get install time)" >&2; exit 1; }
launch=""
if [ "$ranks" -gt 1 ]; then
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
  launch="mpirun -np $ranks"
fi
# 500 or more: run to the scene's end (t = 5); a cut step adds sub-steps, so --steps 500 would stop short of it
step_limit="--steps $steps"; [ "$steps" -ge 500 ] && step_limit=""
mkdir -p "$out"
for mu in $mus; do
  tag=mu$(echo "$mu" | tr -d .)           # 0.1 -> mu01
  dir="$out/$tag-np$ranks"
  rm -rf "$dir"
  echo "two-tori full, mu = $mu, $steps steps, $ranks rank(s): $dir" >&2
  # shellcheck disable=SC2086
  /usr/bin/time -f "%e %U %S" -o "$dir.time" $launch "$bin" run "$root/scenes/two-tori.yaml" --quiet \
    $step_limit --set "contact.0.parameters.mu=$mu" --out "$dir"
  "$root/scripts/plot-history.sh" "$dir" "two tori (2 x 8024 hex8), mu = $mu, $steps steps, $ranks rank(s)" >/dev/null
  mkdir -p "$root/docs/img"
  cp "$dir/history.png" "$root/docs/img/fast-solves-tori-$tag.png"
  python3 - "$dir" "$mu" "$ranks" <<'PY'
import csv, json, sys
d, mu, ranks = sys.argv[1], sys.argv[2], sys.argv[3]
s = json.load(open(d + "/summary.json"))
wall, user, system = (float(v) for v in open(d + ".time").read().split()[-3:])
rows = list(csv.DictReader(open(d + "/history.csv")))
e0 = float(rows[0]["total_energy"])
rise = max(float(b["total_energy"]) - float(a["total_energy"]) for a, b in zip(rows, rows[1:]))
l0 = [float(rows[0]["angular_momentum_" + c]) for c in "xyz"]
drift = max(sum((float(r["angular_momentum_" + c]) - l0[i]) ** 2 for i, c in enumerate("xyz")) ** 0.5
            for r in rows) / sum(v * v for v in l0) ** 0.5
n = max(s["newton_iterations"], 1)
print("mu = %s, %s rank(s): %s, %d steps to t = %.2f, %d Newton iterations (%.2f per step), %d linear solves (%s)"
      % (mu, ranks, s["status"], s["steps"], s["final_time"], s["newton_iterations"],
         s["newton_iterations"] / max(s["steps"], 1), s["linear_solves"], s["linear_solvers_used"]))
print("  wall %.1f s, CPU %.1f s (user %.1f + sys %.1f, all ranks): %.3f s CPU per Newton iteration; program's own "
      "split (wall): assembly %.1f, contact %.2f, solve %.1f" % (wall, user + system, user, system,
                                                                  (user + system) / n, s["assembly_seconds"],
                                                                  s["contact_seconds"], s["solve_seconds"]))
print("  total energy: largest step increase %.2e of E0 = %.6g (lost %.4f %%); angular momentum drift %.2e relative"
      % (rise / e0, e0, 100 * (e0 - float(rows[-1]["total_energy"])) / e0, drift))
PY
done
