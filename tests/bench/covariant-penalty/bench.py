"""covariant-penalty benchmark (not a ctest test): Newton iterations and run time per tangent variant and step size on
the large-step examples of Konyukhov & Schweizerhof (6.1 run B, 6.2, 6.3), and run time against error on the Hertz
sphere beside the other plugins. Writes tests/bench/covariant-penalty/{tangents,hertz}.csv and the plots
docs/img/covariant-{tangents,hertz}.png (gnuplot).

  python3 tests/bench/covariant-penalty/bench.py tangents   # about 10 min on 2 quiet cores
  python3 tests/bench/covariant-penalty/bench.py hertz
  python3 tests/bench/covariant-penalty/bench.py plot       # the plots from the CSV files alone (both)

Needs STICKSLIP_BIN or build/bin/stickslip. Times are wall and CPU (user + system) seconds of the driver; on a
loaded machine the CPU time is the steadier of the two."""
import csv
import os
import resource
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(HERE)))
sys.path.insert(0, os.path.join(ROOT, "tests", "validation"))
sys.path.insert(0, HERE)
import paths  # noqa: E402
from stickslip_results import Results  # noqa: E402

BIN = os.environ.get("STICKSLIP_BIN", os.path.join(ROOT, "build", "bin", "stickslip"))
TANGENTS = ("full", "no-curvature", "main-only")


def timed_run(scene, args):
    """Runs the driver; returns (Results or None, wall seconds, CPU seconds, stderr)."""
    out = os.path.join(tempfile.mkdtemp(prefix="stickslip-bench-cp-"), "results")
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.time()
    proc = subprocess.run([BIN, "run", os.path.join(ROOT, scene), "--out", out, "--quiet", *args],
                          capture_output=True, text=True)
    wall = time.time() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    ok = proc.returncode == 0 and os.path.exists(os.path.join(out, "history.csv"))
    return (Results(out) if ok else None), wall, cpu, proc.stderr


def history_args(index, points):
    return ["--set", "boundary.%d.history=%s" % (index, paths.fmt(points))]


def example_args(example, steps):
    """The --set arguments that run an example's large-step phase in `steps` steps over the paper's distance."""
    if example == "block-b":   # 0.24 sideways after one pressing step
        return ["--set", "time.end=%d" % (1 + steps), "--set", "boundary.2.history=[[0, 0], [1, 0], [%d, 1]]" % (1 + steps)]
    if example == "parabolic":  # u = 0.8 along (116) after 7 pressing steps
        hx, hz = paths.parabolic(steps, 0.8 / steps)
        return ["--set", "time.end=%d" % (7 + steps)] + history_args(2, hx) + history_args(3, hz)
    if example == "spiral":     # x = 0.2 along (127) after one pressing step
        hx, hy, hz = paths.spiral(steps, 0.2 / steps)
        return (["--set", "time.end=%d" % (1 + steps)] + history_args(0, hx) + history_args(1, hy) +
                history_args(2, hz))
    raise ValueError(example)


EXAMPLES = {"block-b": ("scenes/ks-block-b.yaml", 1, (10, 20, 40)),
            "parabolic": ("scenes/ks-parabolic.yaml", 7, (10, 20, 40)),
            "spiral": ("scenes/ks-spiral.yaml", 1, (10, 20, 40))}


def tangents():
    rows = []
    for example, (scene, press, step_counts) in EXAMPLES.items():
        for steps in step_counts:
            for form in ("exact", "paper") if steps == 20 else ("exact",):  # the paper form at the paper's steps
                for tangent in TANGENTS:
                    args = example_args(example, steps) + [
                        "--set", "contact.0.parameters.tangent=%s" % tangent,
                        "--set", "contact.0.parameters.tangent_form=%s" % form]
                    results, wall, cpu, err = timed_run(scene, args)
                    if results is None:
                        row = [example, steps, form, tangent, "failed", "", "", wall, cpu]
                        print("%-9s %3d steps %-5s %-12s failed: %s" % (example, steps, form, tangent,
                                                                       err.strip().splitlines()[-1:]))
                    else:
                        its = [int(r["newton_iterations"]) for r in results.rows if r["step"] > press]
                        done = results.summary.get("steps", len(results.rows) - 1)
                        row = [example, steps, form, tangent, sum(its), max(its), done, wall, cpu]
                        print("%-9s %3d steps %-5s %-12s %4d iterations (max %2d per step, %d steps done), "
                              "%.1f s wall, %.1f s CPU" % (example, steps, form, tangent, sum(its), max(its), done,
                                                           wall, cpu))
                    rows.append(row)
    with open(os.path.join(HERE, "tangents.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["example", "steps", "form", "tangent", "iterations", "max_per_step", "steps_done",
                    "wall_seconds", "cpu_seconds"])
        w.writerows(rows)


def plot():
    """docs/img/covariant-tangents.png: iterations per large step against the step count, per example, variant and
    form; CPU seconds beside."""
    data = {}
    with open(os.path.join(HERE, "tangents.csv")) as f:
        for r in csv.DictReader(f):
            if r["iterations"] == "failed":
                continue
            key = (r["example"], r["form"], r["tangent"])
            data.setdefault(key, []).append((int(r["steps"]), int(r["iterations"]) / int(r["steps"]),
                                             float(r["cpu_seconds"])))
    work = tempfile.mkdtemp(prefix="stickslip-bench-cp-plot-")
    panels = []
    for example in EXAMPLES:
        curves = []
        for form in ("exact", "paper"):
            for tangent in TANGENTS:
                pts = sorted(data.get((example, form, tangent), []))
                if not pts:
                    continue
                path = os.path.join(work, "%s-%s-%s.dat" % (example, form, tangent))
                with open(path, "w") as f:
                    for steps, per_step, cpu in pts:
                        f.write("%d %.6g %.6g\n" % (steps, per_step, cpu))
                dash = 1 if form == "exact" else 2
                curves.append((path, "%s %s" % (tangent, form), dash))
        panels.append((example, curves))
    png = os.path.join(ROOT, "docs", "img", "covariant-tangents.png")
    lines = ["set terminal pngcairo size 1400,820 font ',10' dashed", "set output '%s'" % png,
             "set multiplot layout 2,3 title 'covariant-penalty: Newton iterations per step and CPU time "
             "against the number of steps over the same path'", "set grid", "set key top right font ',8'",
             "set logscale x 2", "set xtics (10, 20, 40)"]
    for column, label in ((2, "iterations per step"), (3, "CPU seconds (whole run)")):
        for example, curves in panels:
            lines += ["set title '%s'" % example, "set xlabel 'steps'", "set ylabel '%s'" % label]
            lines.append("plot " + ", \\\n  ".join("'%s' using 1:%d with linespoints dt %d lw 2 title '%s'" %
                                                   (p, column, dash, t) for p, t, dash in curves))
    lines.append("unset multiplot")
    subprocess.run(["gnuplot"], input="\n".join(lines) + "\n", text=True, check=True)
    print("wrote", png)


# ---- Hertz: run time against error beside the other plugins ------------------------------------------------------
HERTZ_PLUGINS = (
    ("penalty-nts", []),
    ("covariant-penalty nts", ["--plugin", "covariant-penalty", "--set", "contact.0.parameters.variant=nts"]),
    ("covariant-penalty sts", ["--plugin", "covariant-penalty", "--set", "contact.0.parameters.variant=sts"]),
    ("nts-augmented", ["--plugin", "nts-augmented", "--set", "contact.0.parameters={}"]),
)


def hertz_errors(results):
    """scenes/hertz-3d.yaml (quarter model, d = 0.02): the force F = 4 |reaction_top_z| against Hertz's at the approach
    of the sphere's lowest point (F(delta), Johnson/Hertz: F = 4/3 E* R^1/2 delta^3/2, delta = d + u_z of the sphere's
    node at the origin), and the contact radius from the outermost active point (its current position) against
    a = (3 F R / (4 E*))^(1/3). Both measures read the same for node and Gauss-point plugins."""
    import math
    nu, E1, E2, d = 0.3, 1000.0, 1.0e6, 0.02
    Es = 1.0 / ((1 - nu ** 2) / E1 + (1 - nu ** 2) / E2)
    F = 4 * abs(results.rows[-1]["reaction_top_z"])
    vtu = results.last_vtu()
    # the sphere's node at the origin: of the two coincident nodes there, the one that moved down
    uz = min(u[2] for x, u in zip(vtu["points"], vtu["displacement"])
             if math.sqrt(sum((xi - ui) ** 2 for xi, ui in zip(x, u))) < 1e-9)
    delta = d + uz
    F_delta = 4.0 / 3.0 * Es * delta ** 1.5
    a_exact = (3 * F / (4 * Es)) ** (1.0 / 3.0)
    active = [p for p in results.contact_points() if p["state"] > 0 and p["pressure"] > 0]
    a = max(math.hypot(p["x"], p["y"]) for p in active) if active else 0.0
    return (F - F_delta) / F_delta, (a - a_exact) / a_exact, len(active)


def hertz():
    rows = []
    for refine in (1, 1.5):
        for name, args in HERTZ_PLUGINS:
            results, wall, cpu, err = timed_run("scenes/hertz-3d.yaml", args + [
                "--set", "mesh.parameters.refine=%g" % refine, "--set", "output.vtu_every=0"])
            if results is None:
                print("%-22s refine %g failed: %s" % (name, refine, err.strip().splitlines()[-1:]))
                rows.append([name, refine, "failed", "", "", "", wall, cpu])
                continue
            e_F, e_a, n = hertz_errors(results)
            its = sum(int(r["newton_iterations"]) for r in results.rows)
            print("%-22s refine %g: F(delta) %+.3e, a (outermost active point) %+.3e, %d active points, %d "
                  "iterations, %.1f s wall, %.1f s CPU" % (name, refine, e_F, e_a, n, its, wall, cpu))
            rows.append([name, refine, "%.6e" % e_F, "%.6e" % e_a, n, its, wall, cpu])
    with open(os.path.join(HERE, "hertz.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["plugin", "refine", "error_F_delta", "error_a", "active_points", "iterations", "wall_seconds",
                    "cpu_seconds"])
        w.writerows(rows)


def plot_hertz():
    """docs/img/covariant-hertz.png: |error of F(delta)| against CPU seconds, one curve per plugin (refine 1, 1.5)."""
    data = {}
    with open(os.path.join(HERE, "hertz.csv")) as f:
        for r in csv.DictReader(f):
            if r["error_F_delta"] != "failed":
                data.setdefault(r["plugin"], []).append((float(r["cpu_seconds"]), abs(float(r["error_F_delta"])),
                                                         r["refine"]))
    work = tempfile.mkdtemp(prefix="stickslip-bench-cp-hertz-")
    curves = []
    for name, pts in data.items():
        path = os.path.join(work, name.replace(" ", "-") + ".dat")
        with open(path, "w") as f:
            for cpu, err, refine in sorted(pts):
                f.write("%.6g %.6g %s\n" % (cpu, err, refine))
        curves.append((path, name))
    png = os.path.join(ROOT, "docs", "img", "covariant-hertz.png")
    lines = ["set terminal pngcairo size 900,560 font ',11'", "set output '%s'" % png,
             "set title 'hertz-3d (tet4, TRI3 faces): error of F(delta) against run time, refine 1 and 1.5'",
             "set xlabel 'CPU seconds'", "set ylabel '|F - F_Hertz(delta)| / F_Hertz(delta)'", "set logscale xy",
             "set grid", "set key top right",
             "plot " + ", \\\n  ".join("'%s' using 1:2 with linespoints pt 7 lw 2 title '%s'" % c for c in curves)]
    subprocess.run(["gnuplot"], input="\n".join(lines) + "\n", text=True, check=True)
    print("wrote", png)


if __name__ == "__main__":
    what = sys.argv[1] if len(sys.argv) > 1 else "tangents"
    if what == "tangents":
        tangents()
        plot()
    elif what == "plot":
        plot()
        plot_hertz()
    elif what == "hertz":
        hertz()
        plot_hertz()
    else:
        sys.exit(__doc__)
