"""Tables, CSV, Pareto fronts and gnuplot figures from run records, and the generated sections of docs pages
(between `<!-- begin NAME -->` and `<!-- end NAME -->` markers; the text around them is written by hand)."""
import csv
import math
import os
import subprocess
import tempfile

from declarations import ROOT


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


def write_csv(path, records, value_names):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    columns = ["label", "plugin", "strategy", "solver", *value_names, "status", "dofs", "linear_system_size", "steps",
               "newton_iterations", "step_cuts", "cpu_seconds", "wall_seconds", "max_rss_mb", "error", "pareto", "commit"]
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(columns)
        for r in records:
            w.writerow([_cell(r.get(c) if c not in value_names else r["values"].get(c)) for c in columns])


def commits(records):
    """Which commits the runs were measured at, with their counts (records older than the field say so)."""
    count = {}
    for r in records:
        c = r.get("commit", "a commit before records kept it")
        count[c] = count.get(c, 0) + 1
    return ", ".join("%s (%d runs)" % (c, n) for c, n in sorted(count.items()))


def _cell(v):
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


def replace_section(doc, name, text):
    """Writes text between the markers of section `name` in docs/<doc>; appends the section when it is new."""
    path = os.path.join(ROOT, "docs", doc)
    begin, end = "<!-- begin %s -->" % name, "<!-- end %s -->" % name
    with open(path) as f:
        content = f.read()
    block = "%s\n%s\n%s" % (begin, text.strip("\n"), end)
    if begin in content and end in content:
        head, rest = content.split(begin, 1)
        content = head + block + rest.split(end, 1)[1]
    else:
        content = content.rstrip("\n") + "\n\n" + block + "\n"
    with open(path, "w") as f:
        f.write(content)
