"""The chart of where each formulation breaks, from the case tables of docs/stability.md (the page's own numbers):
for every case (### section of "The cases") and formulation (the plugin before the strategy), the share of its runs
that converged. Writes docs/data/stability-breaks.csv and docs/img/stability-breaks.png (gnuplot).
Usage: python3 tests/bench/stability_chart.py"""
import csv
import os
import re
import subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PAGE = os.path.join(ROOT, "docs", "stability.md")
DATA = os.path.join(ROOT, "docs", "data", "stability-breaks.csv")
IMAGE = os.path.join(ROOT, "docs", "img", "stability-breaks.png")


def case_runs():
    """{(case title, plugin): [converged?, ...]} from the tables under '## The cases'."""
    runs, case, header = {}, None, None
    text = open(PAGE, encoding="utf-8").read()
    cases = text[text.index("\n## The cases"):]
    for line in cases.split("\n"):
        if line.startswith("## ") and not line.startswith("## The cases"):
            break
        if line.startswith("### "):
            case, header = line[4:].strip(), None
            continue
        if not line.startswith("|") or case is None:
            continue
        cells = [cell.strip() for cell in line.strip().strip("|").split("|")]
        if header is None:
            header = cells
        elif not all(re.fullmatch(r":?-+:?", cell) for cell in cells) and "converged" in header:
            plugin = cells[0].split("/")[0]
            converged = cells[header.index("converged")].startswith("yes")
            runs.setdefault((case, plugin), []).append(converged)
    return runs


def main():
    runs = case_runs()
    cases = list(dict.fromkeys(case for case, _ in runs))
    plugins = sorted({plugin for _, plugin in runs})
    with open(DATA, "w", newline="") as f:
        out = csv.writer(f)
        out.writerow(["case", "formulation", "runs", "converged", "share"])
        for case in cases:
            for plugin in plugins:
                done = runs.get((case, plugin))
                if done:
                    out.writerow([case, plugin, len(done), sum(done), "%.3f" % (sum(done) / len(done))])
    # One cell per (case, formulation) at x = formulation, y = case: green = every run converged, red = none,
    # blank = not declared; the label is "converged/runs".
    present = [(i, j, runs[(case, plugin)]) for i, case in enumerate(cases) for j, plugin in enumerate(plugins)
               if (case, plugin) in runs]
    cells = "\n".join("%d %d 0.5 0.5 %.3f" % (j, i, sum(done) / len(done)) for i, j, done in present)
    labels = "\n".join('%d %d "%d/%d"' % (j, i, sum(done), len(done)) for i, j, done in present)
    ytics = ", ".join('"%s" %d' % (c.replace('"', "'"), i) for i, c in enumerate(cases))
    xtics = ", ".join('"%s" %d' % (p, j) for j, p in enumerate(plugins))
    script = """set terminal pngcairo size 1500,%d font ",10"
set output "%s"
set title "Where each formulation breaks: converged runs / runs per stress case (docs/stability.md)"
set xrange [-0.5:%f]
set yrange [%f:-0.5]
set xtics (%s) rotate by 20 right
set ytics (%s)
set cbrange [0:1]
set cblabel "share of runs converged"
set palette defined (0 "#c0392b", 0.5 "#f1c40f", 1 "#27ae60")
set tics nomirror
unset key
$cells << EOD
%s
EOD
$labels << EOD
%s
EOD
plot $cells using 1:2:3:4:5 with boxxyerror lc palette fs solid 1.0 noborder, \\
     $labels using 1:2:3 with labels
""" % (200 + 26 * len(cases), IMAGE, len(plugins) - 0.5, len(cases) - 0.5, xtics, ytics, cells, labels)
    subprocess.run(["gnuplot"], input=script, text=True, check=True)
    print("wrote %s and %s (%d cases, %d formulations)" % (os.path.relpath(DATA, ROOT), os.path.relpath(IMAGE, ROOT),
                                                           len(cases), len(plugins)))


if __name__ == "__main__":
    main()
