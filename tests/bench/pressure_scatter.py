#!/usr/bin/env python3
"""Why covariant-penalty's Hertz 3D error grows with the penalty: splits the benchmark's pressure error into a
smooth part and a scatter part, with the largest penetration, for the sts variant at 1, 2 and 3 Gauss points per
face direction and the nts variant, at each penalty.

  python3 tests/bench/pressure_scatter.py [--refine 1] [--penalties 1e5 1e6 1e7]

The error is the benchmark's (tests/bench/harness/errors.py, hertz_profile: relative l2 over the contact points with
r < 1.25 a). Smooth part: the points' pressures averaged in 8 radial bins over r < 1.25 a, each bin mean against Hertz
at the bin's mean radius; scatter: the points' deviation from their bin mean; both relative to the same norm of the
Hertz pressure. Over-penetration would show in the smooth part and fall with the penalty; an under-integrated
contact integral would change with the Gauss points; an over-constrained point-wise penalty shows as scatter that
grows with the penalty. Runs go to results/bench/pressure-scatter/ (reused when present)."""
import argparse
import math
import os
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "harness"))
import declarations as dec  # noqa: E402
import errors  # noqa: E402
from runner import OUT  # noqa: E402
from stickslip_results import Results  # noqa: E402

BINS = 8


def split_error(results, bench):
    e = errors.hertz_profile(results, bench, None, None)
    a, p0 = e["a"], e["p0"]
    points, _ = errors.reference_positions(results, True)
    inside = [(r, p, g) for r, p, g in points if r < errors.PROFILE_RANGE * a]
    bins = {}
    for r, p, _ in inside:
        bins.setdefault(min(int(r / (errors.PROFILE_RANGE * a) * BINS), BINS - 1), []).append((r, p))
    smooth = scatter = norm = 0.0
    for members in bins.values():
        r_mean = sum(r for r, _ in members) / len(members)
        p_mean = sum(p for _, p in members) / len(members)
        for r, p in members:
            smooth += (p_mean - p0 * math.sqrt(max(0.0, 1 - (r_mean / a) ** 2))) ** 2
            scatter += (p - p_mean) ** 2
            norm += (p0 * math.sqrt(max(0.0, 1 - (r / a) ** 2))) ** 2
    penetration = max((-g for _, _, g in inside if g == g), default=float("nan"))
    return e, math.sqrt(smooth / norm), math.sqrt(scatter / norm), penetration


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--refine", default="1")
    p.add_argument("--penalties", nargs="+", default=["1e5", "1e6", "1e7"])
    p.add_argument("--binary", default=dec.BIN)
    args = p.parse_args()
    bench = dec.load_benchmarks()["hertz-3d"]
    print("| penalty | variant | points | error | smooth | scatter | max penetration |")
    print("|---|---|---|---|---|---|---|")
    for penalty in args.penalties:
        for variant, gauss in (("sts", 1), ("sts", 2), ("sts", 3), ("nts", 0)):
            folder = os.path.join(OUT, "pressure-scatter", "refine%s-penalty%s-%s%s" % (
                args.refine, penalty, variant, gauss or ""))
            params = "{penalty: %s, penalty_tangential: %s, mu: 0, variant: %s%s}" % (
                penalty, penalty, variant, ", gauss_points: %d" % gauss if gauss else "")
            if not os.path.exists(os.path.join(folder, "summary.json")):
                subprocess.run([args.binary, "run", os.path.join(dec.ROOT, "scenes", "hertz-3d.yaml"), "--out", folder,
                                "--quiet", "--plugin", "covariant-penalty", "--set", "output.vtu_every=0",
                                "--set", "mesh.parameters.refine=" + args.refine, "--replace", "contact.0.parameters=" +
                                params, "--set", "solver.linear.solver=direct"], check=True)
            e, smooth, scatter, penetration = split_error(Results(folder), bench)
            print("| %s | %s | %d | %.3f | %.3f | %.3f | %.2e |" % (
                penalty, variant + (" %d Gauss" % gauss if gauss else ""), e["profile_points"], e["error"], smooth,
                scatter, penetration), flush=True)


if __name__ == "__main__":
    main()
