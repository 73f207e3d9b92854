#!/usr/bin/env python3
"""mortar-dual's plotted checks (issue 9): the Hertz 2D pressure profile (Hammer's parameters) at refine 1 and 2
against Hertz's p0 sqrt(1 - x^2/b^2) for the load each run carries, plotted against the slave nodes' reference x;
the 2D ironing's reaction history (Yang-Laursen-Meng, mu = 0.5) at refine 0.5, 1 and 2 (its oscillation under
refinement); with --ironing-3d only, the 3D shallow ironing's reaction history at refine 0.5, 0.75 and 1 (dt = 0.01,
five times the scene's, condensed + GMRES/MueLu: about 5 and 21 minutes and over an hour). Writes results/bench/mortar-plots/*.dat and
prints the numbers; then
  gnuplot tests/bench/mortar-dual/plots.gp        -> docs/img/mortar-dual-hertz-2d.png, docs/img/mortar-dual-ironing-2d.png
  gnuplot tests/bench/mortar-dual/ironing-3d.gp   -> docs/img/mortar-dual-ironing-3d.png (after --ironing-3d)

  python3 tests/bench/mortar-dual/plots.py [--ironing | --ironing-3d [--levels 0.5,0.75]]   (the 2D ironing runs
  only, the 3D ones only)"""
import math
import os
import statistics
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "tests", "validation"))
from stickslip_results import run  # noqa: E402
from test_mortar_thesis import hertz_2d_profile  # noqa: E402

OUT = os.path.join(os.environ.get("STICKSLIP_BENCH_OUT", os.path.join(ROOT, "results", "bench")), "mortar-plots")


def hertz():
    if "--ironing" in sys.argv:
        return
    for refine in (1, 2):
        results, _ = run("scenes/mortar-hertz-2d.yaml", "--set", "mesh.parameters.refine=%g" % refine,
                         "--set", "output.vtu_every=0", "--set", "output.contact_csv=true")
        F, b, p0, l2, active = hertz_2d_profile(results)
        print("hertz-2d refine %g: F = %.3f N/mm, b = %.4f mm, p0 = %.2f, l2 error %.2e, %d active nodes"
              % (refine, F, b, p0, l2, len(active)))
        pts = sorted((p["reference_x"], p["pressure"]) for p in results.contact_points() if abs(p["x"]) < 1.5 * b)
        with open(os.path.join(OUT, "hertz-2d-refine%g.dat" % refine), "w") as f:
            f.write("# b %.6f p0 %.6f\n" % (b, p0))
            for x, p in pts:
                f.write("%.8g %.8g %.8g\n" % (x / b, p / p0, math.sqrt(max(1 - x * x / b / b, 0.0))))


def ironing():
    for refine in (0.5, 1, 2):
        results, proc = run("scenes/mortar-ironing-2d.yaml", "--set", "mesh.0.parameters.refine=%g" % refine,
                            "--set", "mesh.1.parameters.refine=%g" % refine, "--set", "output.vtu_every=0",
                            expect_ok=False)
        if proc.returncode != 0:  # a failed run keeps its rows: plotted up to where it stopped
            print("ironing-2d refine %g: FAILED: %s" % (refine, proc.stderr.strip().splitlines()[0][:300]))
        if results is None:
            continue
        rows = results.rows
        with open(os.path.join(OUT, "ironing-2d-refine%g.dat" % refine), "w") as f:
            for r in rows:
                f.write("%.6g %.8g %.8g\n" % (r["time"], -r["reaction_shear_x"], -r["reaction_press_y"]))
        sliding = [-r["reaction_shear_x"] for r in rows if 3.0 <= r["time"] <= 7.5]
        if not sliding:
            continue
        mean = statistics.fmean(sliding)
        print("ironing-2d refine %g: %d steps, %d Newton; sliding (t in [3, 7.5]) F_x mean %.3f, oscillation "
              "(max - min) %.3f = %.1f %% of the mean" % (refine, len(rows) - 1, results.summary["newton_iterations"],
                                                         mean, max(sliding) - min(sliding),
                                                         100 * (max(sliding) - min(sliding)) / abs(mean)))


IRONING_3D_ARGS = ("--set", "time.dt=0.01", "--set", "output.vtu_every=0", "--set", "solver.linear.solver=gmres-muelu")
# refine 0.5 has the block's 4 cells along y under the indenter's 4: the conforming case, which stalled until the
# integration cells' fan was taken about the centre of the polygon's perimeter (docs/plugins/mortar-dual.md, 10)
IRONING_3D_LEVELS = (0.5, 0.75, 1)


def ironing_3d_record(results, refine):
    """Writes the reaction history of one 3D ironing run and prints its drag's mean and oscillation while sliding."""
    rows = results.rows
    with open(os.path.join(OUT, "ironing-3d-refine%g.dat" % refine), "w") as f:
        for r in rows:
            f.write("%.6g %.8g %.8g\n" % (r["time"], -r["reaction_shear_x"], -r["reaction_press_z"]))
    # frictionless: the drag is the ploughing's, small against the press, so both are measured against the press
    drag = [-r["reaction_shear_x"] for r in rows if 1.2 <= r["time"] <= 1.7]
    press = [-r["reaction_press_z"] for r in rows if 1.2 <= r["time"] <= 1.7]
    if press:
        mean = statistics.fmean(press)
        print("ironing-3d refine %g: %d steps, %d Newton; sliding (t in [1.2, 1.7], before the block's end): "
              "press F_z mean %.5g, its oscillation (max - min) %.3f %% of the mean; drag F_x from %.4g to %.4g (%.3f %% of F_z)"
              % (refine, len(rows) - 1, results.summary["newton_iterations"], mean,
                 100 * (max(press) - min(press)) / mean, min(drag), max(drag),
                 100 * (max(drag) - min(drag)) / mean))


def ironing_3d(levels):
    for refine in levels:
        results, proc = run("scenes/mortar-ironing-3d.yaml", "--set", "mesh.0.parameters.refine=%g" % refine,
                            "--set", "mesh.1.parameters.refine=%g" % refine, *IRONING_3D_ARGS, expect_ok=False)
        if proc.returncode != 0:
            print("ironing-3d refine %g: FAILED: %s" % (refine, proc.stderr.strip().splitlines()[0][:300]))
        if results is not None:
            ironing_3d_record(results, refine)


if __name__ == "__main__":
    os.makedirs(OUT, exist_ok=True)
    if "--ironing-3d" in sys.argv:
        # --levels 0.5,1 runs only those (the finest takes over an hour)
        levels = IRONING_3D_LEVELS
        if "--levels" in sys.argv:
            levels = tuple(float(v) for v in sys.argv[sys.argv.index("--levels") + 1].split(","))
        ironing_3d(levels)
    else:
        hertz()
        ironing()
