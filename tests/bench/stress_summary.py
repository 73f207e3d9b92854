#!/usr/bin/env python3
"""One table of the stress suite's short (CI) pass: every case, value and plugin with its Newton iterations, step
cuts, active-set changes, largest energy gain and CPU time, read from the records the pass left
($STICKSLIP_BENCH_OUT/stress/<case>/<run>/record.json; ctest -L stress writes them under build/stress). It runs
nothing; it writes the section `stress-short-summary` of docs/stability.md.

  (cd build && ctest -L stress) && STICKSLIP_BENCH_OUT=build/stress python3 tests/bench/stress_summary.py"""
import glob
import json
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "harness"))
import report  # noqa: E402
import runner  # noqa: E402
from stress import value_key  # noqa: E402


def main():
    records = []
    for path in sorted(glob.glob(os.path.join(runner.OUT, "stress", "*", "*", "record.json"))):
        with open(path) as f:
            r = json.load(f)
        if not r.get("kind"):  # Δt ladder runs are not part of the short pass
            records.append(r)
    if not records:
        sys.exit("stress_summary: no records under %s (run `ctest -L stress` first)" % os.path.join(runner.OUT,
                                                                                                   "stress"))
    rows = []
    for r in sorted(records, key=lambda r: (r["bench"], r["label"], value_key(r))):
        rows.append([r["bench"], value_key(r) or "–", r["label"],
                     "yes" if r.get("converged") else "**no**", report.fmt(r.get("newton_iterations")),
                     report.fmt(r.get("step_cuts")), report.fmt(r.get("flips"), "%.0f"),
                     report.fmt(r.get("energy_increase"), "%.1e"), report.fmt(r.get("angular_momentum_drift"), "%.1e"),
                     report.fmt(r.get("cpu_seconds"), "%.1f")])
    header = ["case", "value", "formulation", "converged", "Newton", "cuts", "active-set changes", "max E gain",
              "L drift", "CPU s"]
    cpu = {}
    for r in records:
        who = r.get("plugin") if r.get("plugin") not in (None, "none") else "the core alone"
        cpu[who] = cpu.get(who, 0.0) + r.get("cpu_seconds", 0.0)
    text = ["Command: `(cd build && ctest -L stress) && STICKSLIP_BENCH_OUT=build/stress python3 "
            "tests/bench/stress_summary.py`. Measured at %s; CPU seconds of the short runs: %.0f in all (%s), on a "
            "loaded machine." % (report.commits(records), sum(cpu.values()),
                                 ", ".join("%s %.0f" % kv for kv in sorted(cpu.items()))),
            "", report.markdown_table(header, rows)]
    report.replace_section("stability.md", "stress-short-summary", "\n".join(text))
    print("stress_summary: %d runs written to docs/stability.md" % len(rows))


if __name__ == "__main__":
    main()
