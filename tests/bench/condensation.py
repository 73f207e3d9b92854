#!/usr/bin/env python3
"""Condensation strategies side by side: for every plugin with more than one strategy, on every benchmark it runs,
the system sizes, Newton iterations, CPU time per Newton iteration and peak memory of each strategy at the same
configurations (the benchmark's finest level at which every strategy of the plugin finished). Reads the records
of tests/bench/workprecision.py (run it first; nothing is run here) and writes the table into docs/benchmarks.md.

  python3 tests/bench/condensation.py [BENCHMARK ...]"""
import json
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "harness"))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import declarations as dec  # noqa: E402
import report  # noqa: E402
import runner  # noqa: E402
import workprecision  # noqa: E402


def records_of(runs):
    """The finished records of the planned runs (stale results of older declarations are not read)."""
    out = []
    for run in runs:
        path = os.path.join(runner.OUT, run.bench, run.tag, "record.json")
        if os.path.exists(path):
            with open(path) as f:
                out.append(json.load(f))
    return out


def key(values):
    return tuple(sorted(values.items()))


def compare(records):
    """{plugin: (values, {(strategy, solver): record})} at the costliest configuration all strategies finished."""
    out = {}
    for plugin in sorted({r["plugin"] for r in records}):
        mine = [r for r in records if r["plugin"] == plugin]
        variants = sorted({(r["strategy"], r["solver"]) for r in mine})
        if len({v[0] for v in variants}) < 2:
            continue
        by_config = {}
        for r in mine:
            by_config.setdefault(key(r["values"]), {})[(r["strategy"], r["solver"])] = r
        complete = [(vals, rs) for vals, rs in by_config.items()
                    if len(rs) == len(variants) and all(x.get("status") == "ok" for x in rs.values())]
        if not complete:
            continue
        vals, rs = max(complete, key=lambda c: max(x.get("dofs") or 0 for x in c[1].values()) * 1e6 +
                       max(x.get("newton_iterations") or 0 for x in c[1].values()))
        out[plugin] = (dict(vals), rs)
    return out


def main():
    benchmarks = dec.load_benchmarks()
    names = sys.argv[1:] or list(benchmarks)
    planned = workprecision.plan(benchmarks, dec.load_declarations(), dec.installed_plugins(), names, [], False)
    lines = []
    for name in names:
        found = compare(records_of(planned[name][0]))
        for plugin, (values, rs) in found.items():
            rows = []
            for (strategy, solver), r in sorted(rs.items()):
                its = r.get("newton_iterations") or 0
                rows.append([strategy, solver, report.fmt(r.get("dofs")), report.fmt(r.get("unknowns")),
                             report.fmt(r.get("linear_system_size")), report.fmt(its),
                             report.fmt(r.get("step_cuts")), report.fmt(r["cpu_seconds"], "%.2f"),
                             report.fmt(1000 * r["cpu_seconds"] / its if its else None, "%.1f"),
                             report.fmt(1000 * ((r.get("solve_seconds") or 0) + (r.get("assembly_seconds") or 0) +
                                                (r.get("contact_seconds") or 0)) / its if its else None, "%.1f"),
                             report.fmt(r.get("max_rss_mb"), "%.0f"), report.fmt(r.get("error"))])
            lines += ["#### %s on %s (%s)" % (plugin, name, ", ".join("%s = %s" % (k, dec._short(v))
                                                                      for k, v in sorted(values.items()))), "",
                      report.markdown_table(["strategy", "linear solver", "dofs", "unknowns", "linear system",
                                             "Newton", "cuts", "CPU s", "CPU ms / iteration (run total)",
                                             "assembly + solve ms / iteration (wall)", "RSS MB", "error"], rows), ""]
    if not lines:
        sys.exit("condensation: no plugin with two strategies has finished runs; run tests/bench/workprecision.py")
    text = ["Command: `python3 tests/bench/condensation.py` (from the records of `workprecision.py`).", ""] + lines
    report.replace_section("benchmarks.md", "condensation", "\n".join(text))
    print("\n".join(text))


if __name__ == "__main__":
    main()
