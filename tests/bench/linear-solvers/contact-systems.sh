#!/bin/sh
# Contact systems benchmark: the linear systems of the two-tori impact (nts-augmented, `reduced`) at four mesh
# refinements, taken from a run at the same physical time (solves 26 and 27: step 10-11, t = 0.1, contact since
# step 5), solved by the bridge's solvers through `solve_dumped` (CPU seconds: set-up + first solve, and a
# re-solve on the kept set-up), plus GMRES + MueLu on the whole system as it ran before the nodal / constraint
# split (`--whole`, the coarsest size only: it fails after 500 iterations).
#
#   sh tests/bench/linear-solvers/contact-systems.sh [build-dir]      (about 15 CPU minutes; MUMPS dominates)
#
# Writes docs/linear-solvers-contact.csv and, with gnuplot, docs/img/linear-solvers-contact.png; prints a
# Markdown table and the fitted exponents of the re-solve time against unknowns.
set -e
here=$(cd "$(dirname "$0")" && pwd); root=$(cd "$here/../../.." && pwd)
build=${1:-$root/build}
cmake --build "$build" --target stickslip solve_dumped >/dev/null
work=${CONTACT_BENCH_DIR:-$(mktemp -d /tmp/stickslip-contact-systems.XXXXXX)}
csv=$root/docs/linear-solvers-contact.csv
echo "dir,index,unknowns,constraints,solver,pattern_cpu,iterations,first_cpu,resolve_iterations,resolve_cpu,residual,difference,failed" >"$csv"
for refine in 0.25 0.5 0.75 1; do
  dir=$work/refine-$refine; mkdir -p "$dir"
  STICKSLIP_DUMP_SYSTEMS=$dir STICKSLIP_DUMP_FIRST=26 STICKSLIP_DUMP_LAST=27 \
    "$build/bin/stickslip" run "$root/scenes/two-tori.yaml" --set mesh.0.parameters.refine=$refine \
    --set mesh.1.parameters.refine=$refine --steps 11 --quiet >/dev/null
  "$build/bench/solve_dumped" --csv "$csv" "$dir" 26,27 mumps gmres-muelu gmres-sgs gmres-ilu || true
  if [ "$refine" = 0.25 ]; then "$build/bench/solve_dumped" --whole --csv "$csv" "$dir" 26 gmres-muelu || true; fi
done
python3 "$here/contact-systems.py" "$csv"
if command -v gnuplot >/dev/null; then
  gnuplot -c "$here/contact-systems.gp" "$csv" "$root/docs/img/linear-solvers-contact.png"
fi
echo "systems: $work"
