"""Tables (CSV, Markdown), Pareto fronts and gnuplot figures of run records: what `stickslip compare` writes, and the
project's benchmark harness (tests/bench/harness/report.py) too. A record is a dict with a `label`, `status` and
numbers such as `cpu_seconds` and `error`."""
import math
import os
import subprocess
import tempfile


def ok(record):
    e = record.get("error")
    return record.get("status") == "ok" and isinstance(e, (int, float)) and math.isfinite(e) and e > 0


def pareto(records, x="cpu_seconds", y="error"):
    """The records no other record beats in both x and y (smaller is better), ordered by x."""
    front, best = [], math.inf
    for r in sorted((r for r in records if ok(r)), key=lambda r: (r[x], r[y])):
        if r[y] < best:
            front.append(r)
            best = r[y]
    return front


def cell(v):
    """A CSV cell: empty for None, 6 significant digits for floats."""
    if v is None:
        return ""
    if isinstance(v, float):
        return "%.6g" % v
    return v


def plot(path, title, xlabel, ylabel, records, x="cpu_seconds", y="error"):
    """Log-log y against x: one colour per label (faint points = all its runs, line = its Pareto runs), the Pareto
    front over all labels as a thick grey line."""
    labels = sorted({r["label"] for r in records if ok(r)})
    if not labels:
        return False
    work = tempfile.mkdtemp(prefix="stickslip-plot-")
    plots = []
    front = pareto(records, x, y)
    front_file = os.path.join(work, "front.dat")
    with open(front_file, "w") as f:
        for r in front:
            f.write("%.8g %.8g\n" % (r[x], r[y]))
    plots.append("'%s' using 1:2 with lines lw 9 lc rgb '#c8c8c8' title 'Pareto front (all)'" % front_file)
    for i, label in enumerate(labels, start=1):
        mine = [r for r in records if r["label"] == label and ok(r)]
        all_file = os.path.join(work, "all-%d.dat" % i)
        own_file = os.path.join(work, "front-%d.dat" % i)
        with open(all_file, "w") as f:
            for r in mine:
                f.write("%.8g %.8g\n" % (r[x], r[y]))
        with open(own_file, "w") as f:
            for r in pareto(mine, x, y):
                f.write("%.8g %.8g\n" % (r[x], r[y]))
        plots.append("'%s' using 1:2 with points pt %d ps 0.8 lc %d notitle" % (all_file, 4 + 2 * (i % 5), i))
        plots.append("'%s' using 1:2 with linespoints pt %d ps 1.3 lw 2 lc %d title '%s'"
                     % (own_file, 5 + 2 * (i % 5), i, label))
    script = "\n".join([
        "set terminal pngcairo size 900,620 font ',11' noenhanced", "set output '%s'" % path,
        "set title '%s'" % title.replace("'", "''"), "set xlabel '%s'" % xlabel, "set ylabel '%s'" % ylabel,
        "set logscale xy", "set grid", "set key outside right top", "set format y '%.0e'",
        "plot " + ", \\\n  ".join(plots), ""])
    subprocess.run(["gnuplot"], input=script, text=True, check=True)
    return True


def markdown_table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(lines)


def fmt(v, spec="%.3g"):
    if v is None or v == "":
        return "–"
    if isinstance(v, float) and not math.isfinite(v):
        return "–"
    if isinstance(v, int) and not isinstance(v, bool) and spec == "%.3g":
        return str(v)
    return spec % v if isinstance(v, (int, float)) else str(v)
