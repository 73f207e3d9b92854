"""Hertz benchmarks (not ctest tests): error against unknowns and CPU time for linear and quadratic elements, 2D
(tri3, quad4, tri6, quad9; scenes/hertz-2d.yaml) and 3D (tet4, tet10 on scenes/hertz-3d.yaml; hex8, hex27 on
scenes/hertz-3d-hex.yaml), with the plugins that run them. Errors and costs: hertz_cases.py.

  python3 tests/bench/hertz/bench_hertz.py run 3d [--plugin NAME] [ELEMENT[:REFINE,...] ...]
                                                      runs cases, merges them into results.csv
  python3 tests/bench/hertz/bench_hertz.py report                           plots + docs/hertz.md from the CSV files

The side-by-side runs against GetFEM (getfem.csv) are bench_getfem.py's; `report` puts their tables in too.

`run 2d` / `run 3d` without elements runs the default levels (LEVELS below); `--plugin` runs the cases with another
formulation than penalty-nts, given its defaults only; `cmake --build build --target bench-hertz` runs everything
(penalty-nts) and reports. Needs STICKSLIP_BIN or build/bin/stickslip; gnuplot for the plots."""
import csv
import math
import os
import subprocess
import sys

from hertz_cases import ELEMENTS, HERE, PROFILE_RANGE, ROOT, run_case

RESULTS = os.path.join(HERE, "results.csv")
PROFILES = os.path.join(HERE, "profiles.csv")
FIELDS = ["dim", "element", "plugin", "refine", "unknowns", "newton", "wall", "cpu", "rss_mib", "load", "a_exact",
          "a", "p0", "peak", "l2", "l2_core", "active", "profile_nodes"]
PLUGIN = "penalty-nts"  # the plugin that runs every element type, and the profiles' plot
# line style per plugin in the error plots (colour: the element)
PLUGIN_STYLES = {"penalty-nts": "dt 1 pt 7", "nts-augmented": "dt 2 pt 5", "mortar-dual": "dt 3 pt 9",
                 "covariant-penalty": "dt 4 pt 13"}
LEVELS = {
    "tri3": [1, 2, 3, 4, 6], "quad4": [1, 2, 3, 4, 6], "tri6": [0.5, 1, 1.5, 2, 3], "quad9": [0.5, 1, 1.5, 2, 3],
    "tet4": [1, 1.5, 2, 2.5, 3, 3.5], "tet10": [0.75, 1, 1.25, 1.5, 2], "hex8": [1, 1.5, 2, 2.5, 3],
    "hex27": [0.75, 1, 1.25, 1.5],
}
COLOURS = {"tri3": "#1f77b4", "quad4": "#2ca02c", "tri6": "#d62728", "quad9": "#9467bd", "tet4": "#1f77b4",
           "hex8": "#2ca02c", "tet10": "#d62728", "hex27": "#9467bd"}


def read_csv(path):
    if not os.path.exists(path):
        return []
    with open(path) as f:
        return list(csv.DictReader(f))


def key(row):
    return (row["element"], row["plugin"], "%g" % float(row["refine"]))


def merge(path, fields, new_rows, replaced_keys):
    """Rewrites a CSV with the rows of replaced_keys taken from new_rows, other rows kept; sorted."""
    rows = [r for r in read_csv(path) if key(r) not in replaced_keys] + new_rows
    rows.sort(key=lambda r: (int(r["dim"]) if "dim" in r else 0, r["element"], r["plugin"], float(r["refine"])))
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=fields, extrasaction="ignore")
        writer.writeheader()
        for r in rows:
            writer.writerow(r)


def parse_cases(dim, specs):
    cases = []
    for element, (d, _, _) in ELEMENTS.items():
        if d == dim and not specs:
            cases += [(element, r) for r in LEVELS[element]]
    for spec in specs:
        element, _, levels = spec.partition(":")
        if element not in ELEMENTS or ELEMENTS[element][0] != dim:
            sys.exit("unknown %dD element '%s' (known: %s)" % (dim, element, ", ".join(
                e for e, v in ELEMENTS.items() if v[0] == dim)))
        cases += [(element, float(r)) for r in (levels.split(",") if levels else LEVELS[element])]
    return cases


def run(dim, specs):
    plugin = PLUGIN
    if len(specs) >= 2 and specs[0] == "--plugin":
        plugin, specs = specs[1], specs[2:]
        if plugin not in PLUGIN_STYLES:
            sys.exit("unknown plugin '%s' (known: %s)" % (plugin, ", ".join(PLUGIN_STYLES)))
    for element, refine in parse_cases(dim, specs):
        row, profile = run_case(element, plugin, refine)
        print("%-17s %-6s refine %-5g %7d unknowns  cpu %8.1f s  wall %8.1f s  %6.0f MiB  l2 %.4f  a %+.4f  p0 %+.4f  "
              "peak %+.4f" % (plugin, element, refine, row["unknowns"], row["cpu"], row["wall"], row["rss_mib"], row["l2"],
                              row["a"], row["p0"], row["peak"]), flush=True)
        done = {key({k: str(v) for k, v in row.items()})}
        merge(RESULTS, FIELDS, [{k: ("%.6g" % v if isinstance(v, float) else v) for k, v in row.items()}], done)
        merge(PROFILES, ["element", "plugin", "refine", "r_over_a", "p_over_p0"],
              [{"element": element, "plugin": plugin, "refine": "%g" % refine, "r_over_a": "%.6g" % r,
                "p_over_p0": "%.6g" % p} for r, p in profile], done)


# ---- report ------------------------------------------------------------------------------------------------------
def gnuplot(script):
    subprocess.run(["gnuplot"], input=script, text=True, check=True)


def series_file(rows, element, plugin, columns, path):
    with open(path, "w") as f:
        for r in sorted((r for r in rows if r["element"] == element and r["plugin"] == plugin),
                        key=lambda r: int(r["unknowns"])):
            f.write(" ".join(r[c] for c in columns) + "\n")


def plot_errors(dim, rows, work):
    curves = [(e, p) for e, v in ELEMENTS.items() for p in PLUGIN_STYLES
              if v[0] == dim and any(r["element"] == e and r["plugin"] == p for r in rows)]
    for e, p in curves:
        series_file(rows, e, p, ["unknowns", "cpu", "l2", "l2_core", "a", "p0"], os.path.join(work, "%s-%s.dat" % (e, p)))
    png = os.path.join(ROOT, "docs", "img", "hertz-%dd-errors.png" % dim)
    panels = [("l2", 3, "L2 profile error (r < 1.25 a)"), ("l2_core", 4, "L2 profile error, core (r < 0.8 a)"),
              ("a", 5, "|error of a|"), ("p0", 6, "|error of p0 (fit)|")]
    lines = ["set terminal pngcairo size 1800,900 font ',11'", "set output '%s'" % png, "set multiplot layout 2,4 "
             "title 'hertz-%dd: errors against unknowns (top) and CPU time (bottom); colour: element, line: plugin'" % dim,
             "set logscale xy", "set grid", "set format y '%.0e'"]
    for xcol, xlabel in ((1, "unknowns"), (2, "CPU time [s] (one core)")):
        for _, col, title in panels:
            plots = ["'%s' using %d:(abs($%d)) with linespoints lw 2 %s lc rgb '%s' title '%s%s'"
                     % (os.path.join(work, "%s-%s.dat" % (e, p)), xcol, col, PLUGIN_STYLES[p], COLOURS[e], e,
                        "" if p == PLUGIN else " " + p) for e, p in curves]
            # one legend, in the first panel's empty upper right corner (the curves fall from the upper left)
            key = ("set key top right font ',8' samplen 2 spacing 0.85" if (xcol, col) == (1, panels[0][1])
                   else "unset key")
            lines += [key, "set xlabel '%s'" % xlabel, "set title '%s'" % title, "plot " + ", ".join(plots)]
    lines += ["unset multiplot", ""]
    gnuplot("\n".join(lines))
    return png


def plot_profiles(dim, rows, profiles, work, target):
    """Pressure profiles at reference positions: per element the run with the unknowns closest to `target`."""
    png = os.path.join(ROOT, "docs", "img", "hertz-%dd-profiles.png" % dim)
    plots = ["(x < 1 ? sqrt(1 - x*x) : 0) with lines lw 2 lc rgb 'black' title 'Hertz'"]
    chosen = []
    for e, v in ELEMENTS.items():
        candidates = [r for r in rows if r["element"] == e and r["plugin"] == PLUGIN]
        if v[0] != dim or not candidates:
            continue
        best = min(candidates, key=lambda r: abs(math.log(int(r["unknowns"]) / target)))
        chosen.append(best)
        path = os.path.join(work, "profile-%s.dat" % e)
        with open(path, "w") as f:
            for p in profiles:
                if key(p) == key(best):
                    f.write("%s %s\n" % (p["r_over_a"], p["p_over_p0"]))
        plots.append("'%s' using 1:2 with points pt 7 ps 0.8 lc rgb '%s' title '%s, %s unknowns'"
                     % (path, COLOURS[e], e, best["unknowns"]))
    gnuplot("\n".join([
        "set terminal pngcairo size 1000,620 font ',11'", "set output '%s'" % png,
        "set title 'hertz-%dd (%s): nodal contact pressure at reference positions'" % (dim, PLUGIN),
        "set xlabel '%s / a (a from the load of each run)'" % ("x" if dim == 2 else "r"), "set ylabel 'p / p0'",
        "set xrange [0:1.6]", "set yrange [-0.05:1.15]", "set samples 400", "set grid", "set key top right",
        "plot " + ", \\\n  ".join(plots), ""]))
    return png, chosen


def table(dim, rows):
    out = ["| element | plugin | refine | unknowns | Newton | CPU [s] | wall [s] | peak memory [MiB] | nodes r < %g a | "
           "L2 profile | L2 core | a | p0 (fit) | p at centre |" % PROFILE_RANGE,
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    order = [e for e, v in ELEMENTS.items() if v[0] == dim]
    for r in sorted((r for r in rows if int(r["dim"]) == dim),
                    key=lambda r: (order.index(r["element"]), list(PLUGIN_STYLES).index(r["plugin"]),
                                   float(r["refine"]))):
        out.append("| %s | %s | %s | %s | %s | %.1f | %.1f | %.0f | %s | %.4f | %.4f | %+.2f %% | %+.2f %% | %+.2f %% |" % (
            r["element"], r["plugin"], r["refine"], r["unknowns"], r["newton"], float(r["cpu"]), float(r["wall"]),
            float(r["rss_mib"]), r["profile_nodes"], float(r["l2"]), float(r.get("l2_core") or "nan"),
            100 * float(r["a"]), 100 * float(r["p0"]), 100 * float(r["peak"])))
    return "\n".join(out)


def report():
    import tempfile
    rows, profiles = read_csv(RESULTS), read_csv(PROFILES)
    work = tempfile.mkdtemp(prefix="stickslip-bench-hertz-plot-")
    sections = {}
    for dim, target in ((2, 3000), (3, 10000)):
        dim_rows = [r for r in rows if int(r["dim"]) == dim]
        if not dim_rows:
            continue
        plot_errors(dim, dim_rows, work)
        plot_profiles(dim, dim_rows, profiles, work, target)
        sections[dim] = table(dim, rows)
    template = open(os.path.join(HERE, "hertz.md.in")).read()
    text = template.replace("@TABLE_2D@", sections.get(2, "(not run)"))
    text = text.replace("@TABLE_3D@", sections.get(3, "(not run)"))
    from bench_getfem import report as getfem_report  # the side-by-side runs of getfem.csv
    getfem = getfem_report()
    for dim in (2, 3):
        text = text.replace("@GETFEM_%dD@" % dim, getfem.get(dim, "(not run)"))
    with open(os.path.join(ROOT, "docs", "hertz.md"), "w") as f:
        f.write(text)
    print("wrote docs/hertz.md, docs/img/hertz-{2d,3d}-{errors,profiles}.png and docs/img/hertz-getfem.png")


def main():
    if len(sys.argv) >= 3 and sys.argv[1] == "run" and sys.argv[2] in ("2d", "3d"):
        run(int(sys.argv[2][0]), sys.argv[3:])
    elif len(sys.argv) == 2 and sys.argv[1] == "report":
        report()
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main()
