#!/usr/bin/env bash
# Peak resident memory per rank against the number of ranks (docs/design.md, "Memory per rank"): runs a scene for a
# few steps at 1, 2 and 4 ranks under /usr/bin/time -v and prints, per rank count, the largest and the mean peak RSS
# of the ranks, and (memory_per_rank.py) the fit M(p) = a + b/p extrapolated to 256 ranks.
# Usage: tests/bench/memory/memory_per_rank.sh [SCENE] [STEPS] [BIN]   (defaults: scenes/two-tori.yaml 1 build/bin/stickslip)
set -euo pipefail
cd "$(dirname "$0")/../../.."
scene=${1:-scenes/two-tori.yaml}
steps=${2:-1}
bin=${3:-build/bin/stickslip}
out=$(mktemp -d)
for np in 1 2 4; do
  OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 \
    mpirun --allow-run-as-root --oversubscribe -np "$np" \
    sh -c "/usr/bin/time -v $bin run $scene --steps $steps --quiet --out $out/run-$np 2> $out/time-$np-\$OMPI_COMM_WORLD_RANK.txt"
done
python3 "$(dirname "$0")/memory_per_rank.py" "$out"
rm -rf "$out"
