"""Newton iterations on the Hertz ladder per Newton setting (docs/hertz.md, "Newton iterations"): per run the
iterations of each step, their sum, the load (4 |reaction_top_z| in 3D, 2 |reaction_top_y| in 2D) and the L2 profile
error (hertz_profile.py), for the scene's penalty and the default penalty (`contact.0.parameters={area_weighted: 1}`,
what a scene without a penalty gets), with the scene's four load steps and loaded in one step (`time.dt=1`).

Usage: python3 tests/bench/hertz/bench_newton.py [ELEMENT:REFINE[,REFINE...] ...]
e.g.   python3 tests/bench/hertz/bench_newton.py tet4:1,2 tet10:1 quad4:2 quad9:1   (the default ladder)
Prints one markdown table row per run and setting."""
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from hertz_cases import run_case  # noqa: E402
from stickslip_results import Results  # noqa: E402

# label -> scene settings; the first is the default of quasi-static steps
SETTINGS = {
    "default": [],
    "predicted_update=false": ["solver.newton.predicted_update=false"],
    "previous-increment": ["solver.newton.predictor=previous-increment"],
}
PENALTIES = {"scene": [], "default": ["contact.0.parameters={area_weighted: 1}"]}
LADDER = [("tet4", 1.0), ("tet4", 2.0), ("tet10", 1.0), ("quad4", 2.0), ("quad9", 1.0)]


def main(argv):
    cases = [(spec.split(":")[0], float(r)) for spec in argv for r in spec.split(":")[1].split(",")] or LADDER
    print("| element | refine | penalty | steps | setting | Newton per step | Newton | load | L2 profile |")
    print("|---|---|---|---|---|---|---|---|---|")
    for element, refine in cases:
        for penalty, penalty_sets in PENALTIES.items():
            for dt in ("0.25", "1"):
                for label, sets in SETTINGS.items():
                    out = os.path.join(tempfile.mkdtemp(prefix="stickslip-bench-newton-"), "results")
                    row, _ = run_case(element, "penalty-nts", refine, keep=out,
                                      extra_sets=sets + penalty_sets + ["time.dt=" + dt])
                    steps = [r["newton_iterations"] for r in Results(out).rows[1:]]
                    print("| %s | %g | %s | %d | %s | %s | %d | %.8g | %.6f |" % (
                        element, refine, penalty, round(1 / float(dt)), label, ", ".join("%d" % s for s in steps),
                        row["newton"], row["load"], row["l2"]), flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
