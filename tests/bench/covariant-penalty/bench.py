"""covariant-penalty benchmark (not a ctest test): Newton iterations and run time per tangent variant and step size on
the large-step examples of Konyukhov & Schweizerhof (6.1 run B, 6.2, 6.3). Writes tests/bench/covariant-penalty/
tangents.csv (not committed) and the plot docs/img/covariant-tangents.png (gnuplot). Run time against error beside the
other plugins is the work-precision harness's (tests/bench/plugins/covariant-penalty.yaml:
python3 tests/bench/workprecision.py hertz-3d).

  python3 tests/bench/covariant-penalty/bench.py tangents   # about 10 min on 2 quiet cores
  python3 tests/bench/covariant-penalty/bench.py tangents EXAMPLE[:STEPS,...] ...   # some examples / step counts,
                                                             # e.g. spiral:20 parabolic (block-b, parabolic, spiral)
  python3 tests/bench/covariant-penalty/bench.py plot       # the plot from the CSV file alone

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


CSV_HEADER = ["example", "steps", "form", "tangent", "iterations", "max_per_step", "steps_done", "wall_seconds",
              "cpu_seconds"]


def store_row(row):
    """Writes one run into tangents.csv as soon as it is measured (a run of the same example, steps, form and tangent
    is replaced), so an interrupted benchmark keeps what it measured."""
    path = os.path.join(HERE, "tangents.csv")
    rows = []
    if os.path.exists(path):
        with open(path) as f:
            rows = [r for r in csv.reader(f)][1:]
    rows = [r for r in rows if r[:4] != [str(v) for v in row[:4]]] + [row]
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(CSV_HEADER)
        w.writerows(rows)


def selection(args):
    """{example: step counts} from arguments EXAMPLE[:STEPS,...]; all examples and step counts without arguments."""
    if not args:
        return {name: steps for name, (_, _, steps) in EXAMPLES.items()}
    chosen = {}
    for arg in args:
        name, _, counts = arg.partition(":")
        if name not in EXAMPLES:
            sys.exit("unknown example %r (known: %s)" % (name, ", ".join(EXAMPLES)))
        chosen[name] = tuple(int(c) for c in counts.split(",")) if counts else EXAMPLES[name][2]
    return chosen


def tangents(args=()):
    for example, step_counts in selection(args).items():
        scene, press, _ = EXAMPLES[example]
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
                    store_row(row)


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
            if not curves:  # an example not measured yet keeps its panel, saying so
                lines += ["set label 1 'not measured' at graph 0.5, 0.5 center", "plot [10:40] [0:1] 2 notitle",
                          "unset label 1"]
                continue
            lines.append("plot " + ", \\\n  ".join("'%s' using 1:%d with linespoints dt %d lw 2 title '%s'" %
                                                   (p, column, dash, t) for p, t, dash in curves))
    lines.append("unset multiplot")
    subprocess.run(["gnuplot"], input="\n".join(lines) + "\n", text=True, check=True)
    print("wrote", png)


if __name__ == "__main__":
    what = sys.argv[1] if len(sys.argv) > 1 else "tangents"
    if what == "tangents":
        tangents(sys.argv[2:])
        plot()
    elif what == "plot":
        plot()
    else:
        sys.exit(__doc__)
