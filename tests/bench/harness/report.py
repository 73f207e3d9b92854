"""Tables, CSV, Pareto fronts and gnuplot figures from run records, and the generated sections of docs pages
(between `<!-- begin NAME -->` and `<!-- end NAME -->` markers; the text around them is written by hand)."""
import csv
import os
import sys

from declarations import ROOT

sys.path.insert(0, os.path.join(ROOT, "tools"))
from stickslip_compare.report import cell, fmt, markdown_table, ok, pareto, plot  # noqa: E402,F401  (shared)


def write_csv(path, records, value_names):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    columns = ["label", "plugin", "strategy", "solver", *value_names, "status", "dofs", "linear_system_size", "steps",
               "newton_iterations", "step_cuts", "cpu_seconds", "wall_seconds", "max_rss_mb", "error", "pareto", "commit"]
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(columns)
        for r in records:
            w.writerow([cell(r.get(c) if c not in value_names else r["values"].get(c)) for c in columns])


def commits(records):
    """Which commits the runs were measured at, with their counts (records older than the field say so)."""
    count = {}
    for r in records:
        c = r.get("commit", "a commit before records kept it")
        count[c] = count.get(c, 0) + 1
    return ", ".join("%s (%d runs)" % (c, n) for c, n in sorted(count.items()))


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
