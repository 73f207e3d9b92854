"""Contact work per rank (summary.json's contact_seconds_rank_* / contact_imbalance_* / contact_active_rank_*, and
`--verbose`'s per-step line; docs/user-guide.md, summary.json): on scenes/corner-contact.yaml, whose contact sits at
one corner of a slab, the active slave points per rank add up to history.csv's active_points at the peak step, the
time statistics are ordered (min <= mean <= max, 1 <= mean imbalance <= worst), and on one rank every statistic is
the run's own contact_seconds (imbalance exactly 1). A direct solver (MUMPS): both runs take the same active set."""
import re

from stickslip_results import main, run

SCENE = "scenes/corner-contact.yaml"
# a coarser slab (12 x 12 x 2 instead of 24 x 24 x 4): the contact stays at the corner, the run takes seconds
ARGS = ["--steps", "3", "--set", "solver.linear.solver=direct", "--set", "mesh.0.parameters.nx=12", "--set",
        "mesh.0.parameters.ny=12", "--set", "mesh.0.parameters.nz=2"]


def peak_active(results, step):
    return next(row["active_points"] for row in results.rows if int(row["step"]) == step and int(row["substep"]) == 0)


def contact_balance(checks):
    one, _ = run(SCENE, *ARGS)
    s = one.summary
    for key in ("contact_seconds_rank_min", "contact_seconds_rank_mean", "contact_seconds_rank_max"):
        checks.check(s[key] == s["contact_seconds"], "1 rank: %s = %g is the run's contact_seconds %g" %
                     (key, s[key], s["contact_seconds"]))
    checks.check(s["contact_imbalance_mean"] == 1 and s["contact_imbalance_worst"] == 1,
                 "1 rank: imbalance mean %g, worst %g are 1" % (s["contact_imbalance_mean"], s["contact_imbalance_worst"]))
    active = peak_active(one, s["contact_active_peak_step"])
    checks.check(active > 0 and s["contact_active_rank_min"] == s["contact_active_rank_max"] == active,
                 "1 rank: active points per rank %g / %g = history's %g at the peak step %d" %
                 (s["contact_active_rank_min"], s["contact_active_rank_max"], active, s["contact_active_peak_step"]))

    two, proc = run(SCENE, *ARGS, "--verbose", np=2)
    s = two.summary
    ranks = s["ranks"]
    checks.check(ranks == 2, "2 ranks ran (%d)" % ranks)
    lo, mean, hi = (s["contact_seconds_rank_" + k] for k in ("min", "mean", "max"))
    checks.check(0 <= lo <= mean <= hi <= s["wall_seconds"], "2 ranks: contact seconds per rank %g <= %g <= %g <= wall %g"
                 % (lo, mean, hi, s["wall_seconds"]))
    checks.check(1 <= s["contact_imbalance_mean"] <= s["contact_imbalance_worst"] <= ranks,
                 "2 ranks: 1 <= imbalance mean %g <= worst %g <= ranks" % (s["contact_imbalance_mean"],
                                                                          s["contact_imbalance_worst"]))
    step = s["contact_active_peak_step"]
    total = peak_active(two, step)
    checks.check(abs(s["contact_active_rank_mean"] * ranks - total) < 1e-9 and
                 s["contact_active_rank_min"] <= s["contact_active_rank_mean"] <= s["contact_active_rank_max"],
                 "2 ranks: active points per rank %g / %g / %g add up to history's %g at step %d" %
                 (s["contact_active_rank_min"], s["contact_active_rank_mean"], s["contact_active_rank_max"], total, step))
    checks.check(total == active, "2 ranks: the same active points as on 1 rank (%g, %g)" % (total, active))
    lines = re.findall(r"^step (\d+) contact balance over 2 ranks: .*max/mean ([0-9.]+)\), active slave points "
                       r"([0-9.]+) / ([0-9.e+-]+) / ([0-9.]+)$", proc.stderr, re.M)
    checks.check([int(m[0]) for m in lines] == [1, 2, 3], "--verbose: one balance line per step (%s)" %
                 [m[0] for m in lines])
    checks.check(all(float(m[2]) + float(m[4]) == peak_active(two, int(m[0])) for m in lines),
                 "--verbose: the two ranks' active points add up to history's at every step")


if __name__ == "__main__":
    main([contact_balance])
