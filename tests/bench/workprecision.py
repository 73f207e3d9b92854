#!/usr/bin/env python3
"""Work-precision benchmarks: every declared plugin x strategy x linear solver on a benchmark scene, swept over mesh
refinement, Delta t and the plugin's own sweeps (penalty); CPU time against error, one plot per benchmark, the table
and the plot in docs/benchmarks.md. Formats and design: docs/benchmarks.md.

  python3 tests/bench/workprecision.py hertz-2d [more benchmarks]   # run (reusing finished runs), plot, write docs
  python3 tests/bench/workprecision.py --all                         # every benchmark
  python3 tests/bench/workprecision.py --list                        # benchmarks, declarations, runs they expand to
  python3 tests/bench/workprecision.py --check [--strict]            # + `stickslip check` of one run per curve
  options: --quick (the benchmarks' quick subsets; docs untouched unless --docs), --fresh (rerun finished runs),
           --plugin NAME (only these plugins; docs untouched unless --docs: the table would lose the others),
           --jobs N (runs at once, default 1), --binary PATH"""
import argparse
import os
import shlex
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "harness"))
import declarations as dec  # noqa: E402
import errors  # noqa: E402
import report  # noqa: E402
import runner  # noqa: E402


def plan(benchmarks, decls, installed, names, only, quick, section="benchmarks"):
    """{bench: (runs, skipped notes)} for the named benchmarks."""
    out = {}
    for name in names:
        bench = benchmarks[name]
        runs, notes = [], []
        for plugin, d in sorted(decls.items()):
            if only and plugin not in only:
                continue
            if (section, name) not in d.entries:
                continue
            if plugin not in installed:
                notes.append("%s: declared, but not built (not listed by `stickslip plugins`)" % plugin)
                continue
            for r in dec.expand(bench, d, section, installed, quick):
                if os.path.exists(os.path.join(dec.ROOT, r.scene)):
                    runs.append(r)
                elif "%s: scene %s is not in the tree" % (r.label, r.scene) not in notes:
                    notes.append("%s: scene %s is not in the tree" % (r.label, r.scene))
        out[name] = (runs, notes)
    return out


def list_plan(benchmarks, planned, check, binary):
    """Prints the runs per benchmark and curve; with check, `stickslip check` of one run per curve. Returns the
    number of failed checks."""
    failed = 0
    for name, (runs, notes) in planned.items():
        bench = benchmarks[name]
        print("%s: %s (%s; error: %s)" % (name, bench.title, bench.scene, bench.error_label))
        labels = {}
        for r in runs:
            labels.setdefault(r.label, []).append(r)
        for label, rs in labels.items():
            print("  %-40s %3d runs" % (label, len(rs)))
        for n in notes:
            print("  skipped: " + n)
        if check:
            seen = set()
            for r in runs:
                if r.label in seen:
                    continue
                seen.add(r.label)
                proc = subprocess.run([binary, "check", os.path.join(dec.ROOT, r.scene), *r.args],
                                      capture_output=True, text=True)
                print("  check %-34s %s" % (r.label, "ok" if proc.returncode == 0 else "FAILED: " +
                                            proc.stderr.strip()[-300:]))
                failed += proc.returncode != 0
    return failed


def run_benchmark(bench, runs, notes, args):
    reference = None
    ref_run = dec.reference_run(bench)
    if ref_run is not None:
        record, reference = runner.execute(ref_run, bench.name, bench.timeout, args.fresh, args.binary)
        if reference is None or record.get("status") != "ok":
            print("%s: the reference run failed: %s" % (bench.name, record.get("message", "")), file=sys.stderr)
            return None
        print("%s: reference %s (%.1f s CPU)" % (bench.name, record["tag"], record["cpu_seconds"]))

    def one(run):
        record, results = runner.execute(run, bench.name, bench.timeout, args.fresh, args.binary)
        if results is not None and record.get("status") == "ok":
            try:
                record.update(errors.evaluate(bench, results, run, reference))
            except (ValueError, KeyError, IndexError, ZeroDivisionError) as e:
                record["status"], record["message"] = "error", "evaluator: %s" % e
            runner.save(record)
        print("  %-40s %-30s %-7s cpu %7.2f s  error %s" % (
            run.label, " ".join("%s=%s" % (k, dec._short(v)) for k, v in run.values.items()),
            record.get("status"), record["cpu_seconds"], report.fmt(record.get("error"))), flush=True)
        return record

    with ThreadPoolExecutor(max_workers=args.jobs) as pool:
        records = list(pool.map(one, runs))
    return records


def document(bench, records, notes, args, ref_record):
    value_names = sorted({k for r in records for k in r["values"]})
    csv_path = os.path.join(dec.ROOT, "docs", "data", "wp-%s.csv" % bench.name)
    front = {id(r) for r in report.pareto(records)}
    for r in records:
        r["pareto"] = "yes" if id(r) in front else ""
    report.write_csv(csv_path, records, value_names)
    png = os.path.join(dec.ROOT, "docs", "img", "wp-%s.png" % bench.name)
    report.plot(png, "%s: CPU time against error" % bench.title, "CPU time [s] (user + system of the run)",
                bench.error_label, records)
    rows = []
    for r in sorted(records, key=lambda r: (r["label"], [r["values"].get(k, 0) for k in value_names])):
        rows.append([r["label"], *[report.fmt(r["values"].get(k)) for k in value_names], report.fmt(r.get("dofs")),
                     report.fmt(r.get("steps")), report.fmt(r.get("newton_iterations")),
                     report.fmt(r.get("step_cuts")), report.fmt(r.get("cpu_seconds"), "%.2f"),
                     report.fmt(r.get("wall_seconds"), "%.2f"), report.fmt(r.get("max_rss_mb"), "%.0f"),
                     report.fmt(r.get("error")), "★" if r["pareto"] else "",
                     r.get("status") if r.get("status") == "ok" else "**%s**" % r.get("status")])
    table = report.markdown_table([ "curve", *value_names, "dofs", "steps", "Newton", "cuts", "CPU s", "wall s",
                                    "RSS MB", "error", "front", "status"], rows)
    loads = [l for r in records for l in r.get("load_average", [])]
    command = "python3 tests/bench/workprecision.py %s%s" % (bench.name, " --quick" if args.quick else "")
    text = ["### %s" % bench.title, "",
            "Scene `%s`; error: %s; reference: %s." % (bench.scene, bench.error_label, _reference_text(bench,
                                                                                                   ref_record)),
            "", "```sh\n%s\n```" % command, "", "![%s](img/wp-%s.png)" % (bench.name, bench.name), "", table, ""]
    failed = [r for r in records if r.get("status") != "ok"]
    for r in failed:
        text.append("- `%s` %s: %s — %s" % (r["label"], " ".join("%s=%s" % (k, dec._short(v)) for k, v in
                                                                 r["values"].items()), r.get("status"),
                                            (r.get("message") or "").replace("\n", " ")[:300]))
    for n in notes:
        text.append("- skipped: " + n)
    if loads:
        text.append("")
        text.append("Measured at %s with the load average between %.1f and %.1f on 2 cores (wall times are those "
                    "of a loaded machine; compare CPU times); data: [docs/data/wp-%s.csv](data/wp-%s.csv)."
                    % (report.commits(records), min(loads), max(loads), bench.name, bench.name))
    if bench.notes:
        text += ["", bench.notes.strip()]
    report.replace_section("benchmarks.md", "wp-" + bench.name, "\n".join(text))


def _reference_text(bench, ref_record):
    if not isinstance(bench.reference, dict):
        return str(bench.reference)
    notes = bench.reference.get("notes", "")
    cost = ""
    if ref_record:
        cost = " (`stickslip run %s %s`, %.0f s CPU)" % (bench.scene, shlex.join(ref_record["command"][4:]),
                                                         ref_record["cpu_seconds"])
    return "converged, our own finest run: %s%s" % (notes, cost)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("benchmarks", nargs="*")
    p.add_argument("--all", action="store_true")
    p.add_argument("--list", action="store_true")
    p.add_argument("--check", action="store_true")
    p.add_argument("--strict", action="store_true", help="with --check: exit 1 when a check fails")
    p.add_argument("--quick", action="store_true")
    p.add_argument("--docs", action="store_true")
    p.add_argument("--fresh", action="store_true")
    p.add_argument("--plugin", action="append", default=[])
    p.add_argument("--jobs", type=int, default=1)
    p.add_argument("--binary", default=dec.BIN)
    args = p.parse_args()
    try:
        benchmarks = dec.load_benchmarks()
        decls = dec.load_declarations()
        installed = dec.installed_plugins(args.binary)
        names = list(benchmarks) if args.all or (args.list and not args.benchmarks) or \
            (args.check and not args.benchmarks) else args.benchmarks
        for n in names:
            if n not in benchmarks:
                sys.exit("workprecision: unknown benchmark %r (known: %s)" % (n, ", ".join(benchmarks)))
        for d in decls.values():
            for section, name in d.entries:
                if section == "benchmarks" and name not in benchmarks:
                    raise dec.DeclarationError("%s: benchmarks.%s: no such benchmark (tests/bench/benchmarks/)"
                                               % (d.path, name))
        planned = plan(benchmarks, decls, installed, names, args.plugin, args.quick)
    except dec.DeclarationError as e:
        sys.exit("workprecision: %s" % e)
    undeclared = sorted(set(installed) - set(decls))
    if undeclared:
        print("note: plugins without a declaration in tests/bench/plugins/: %s" % ", ".join(undeclared))
    if args.list or args.check:
        failed = list_plan(benchmarks, planned, args.check, args.binary)
        if args.strict and failed:
            sys.exit("workprecision: %d declaration(s) refused by `stickslip check`" % failed)
        return
    for name, (runs, notes) in planned.items():
        bench = benchmarks[name]
        print("%s: %d runs" % (name, len(runs)), flush=True)
        try:
            records = run_benchmark(bench, runs, notes, args)
        except dec.DeclarationError as e:
            sys.exit("workprecision: %s" % e)
        if records is None:
            continue
        if not (args.quick or args.plugin) or args.docs:
            ref = dec.reference_run(bench)
            ref_record = runner.execute(ref, bench.name, bench.timeout, False, args.binary)[0] if ref else None
            document(bench, records, notes, args, ref_record)


if __name__ == "__main__":
    main()
