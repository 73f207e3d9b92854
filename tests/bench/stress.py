#!/usr/bin/env python3
"""Numerical stress suite: every stress case (tests/bench/stress/*.yaml) for every plugin that declares it
(tests/bench/plugins/*.yaml, section `stress`) and, for cases without contact, the core alone. Per run: converged
or not, step cuts, Newton iterations, energy drift, momentum drift, active-set changes; per case and plugin the
largest stable time step of a dt ladder. The table goes into docs/stability.md.

  python3 tests/bench/stress.py                    # the full suite (tests/bench), then docs/stability.md
  python3 tests/bench/stress.py CASE ...           # some cases
  python3 tests/bench/stress.py --short --check    # the CI pass: short variants, fails on a regression
  options: --list, --fresh, --plugin NAME, --jobs N, --binary PATH, --no-ladder
The short pass runs each plugin's default (first) strategy only; the full suite every declared strategy."""
import argparse
import os
import sys
from concurrent.futures import ThreadPoolExecutor

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "harness"))
import declarations as dec  # noqa: E402
import report  # noqa: E402
import runner  # noqa: E402
import stress_metrics  # noqa: E402

CORE = "core"  # label of runs without a plugin (cases with no contact pair)
BOUND_KEYS = {"step_cuts", "newton_iterations", "energy_increase", "energy_step_increase", "flips",
              "flip_reversals", "momentum_drift", "angular_momentum_drift", "energy_drift_per_revolution",
              "angular_momentum_drift_per_revolution", "max_constraint_violation"}


def case_runs(case, decls, installed, only, short, ladder):
    """(runs, notes) of one case: the declared plugins (or the core) over the case's axis, then the dt ladder."""
    runs, notes = [], []
    subset = _short_subset(case) if short else {}
    targets = []
    if case.data.get("core"):
        targets.append(None)
    for plugin, d in sorted(decls.items()):
        if ("stress", case.name) not in d.entries or (only and plugin not in only):
            continue
        if plugin not in installed:
            notes.append("%s: declared, but not built" % plugin)
            continue
        targets.append(d)
    for d in targets:
        runs += _expand(case, d, installed, subset, "", short=short)
        if ladder and "dt_ladder" in case.data and not short:
            lad = case.data["dt_ladder"]
            at = {k: [v] for k, v in (lad.get("at") or {}).items()}
            for factor in lad["factors"]:
                extra = {"time.dt": "$(%r*%s)" % (factor, lad.get("dt", "dt"))}
                for r in _expand(case, d, installed, {**subset, **at}, "ladder", extra):
                    r.values["dt_factor"] = factor
                    runs.append(r)
    return runs, notes


def _short_subset(case):
    return {k: v for k, v in (case.data.get("short") or {}).items()}


def _expand(case, declaration, installed, subset, kind, extra_set=None, short=False):
    saved = dict(case.set)
    if extra_set:
        case.set.update(extra_set)
    try:
        if declaration is None:
            env_runs = dec._sweep_product(case.sweeps, case.variables, subset, case.path)
            runs = []
            for vals, sets in env_runs:
                env = dec.environment(case.variables, vals, case.path)
                overrides = {**dec.substitute(case.set, env, case.path + ": set"), **sets}
                args = []
                for key, value in overrides.items():
                    args += [dec.override_option(value), "%s=%s" % (key, dec.yaml_flow(value))]
                runs.append(dec.Run(case.name, None, None, None, dict(vals), args, CORE, case.scene))
        else:
            runs = dec.expand(case, declaration, "stress", installed, quick=False, subset=subset, short=short)
    finally:
        case.set.clear()
        case.set.update(saved)
    for r in runs:
        r.kind = kind
        if kind:
            r.values = dict(r.values)
        if r.options.get("scheme_energy"):  # the plugin's energy line per step is a --verbose message
            r.args = r.args + ["--verbose"]
    return runs


def measure(case, run, args):
    record, results = runner.execute(run, "stress/" + case.name, case.timeout, args.fresh, args.binary)
    record["kind"] = getattr(run, "kind", "")
    record["bounds"] = run.options.get("bounds") or {}  # the declaration's, read by the CI check
    record["expect_failure"] = run.options.get("expect_failure") or {}
    for k in stress_metrics.METRIC_KEYS:
        record.pop(k, None)
    if results is not None:
        env = dec.environment(case.variables, run.values, case.path)
        revs = case.data.get("revolutions")
        revs = dec.sweep_value(revs, env, case.path + ": revolutions") if revs is not None else None
        record.update(stress_metrics.metrics(results, bool(case.data.get("closed")), revs,
                                             float(env.get("length", 1.0))))
        pattern = run.options.get("scheme_energy")
        if pattern and case.data.get("closed"):
            with open(os.path.join(record["folder"], "stderr.txt")) as f:
                own = stress_metrics.scheme_energy_balance(f.read(), pattern, results.rows[0]["total_energy"], revs)
            if own is None:  # the declaration's pattern does not fit the plugin's log: a broken declaration
                record["converged"], record["input_error"] = False, True
                record["message"] = "scheme_energy: no line of stderr.txt matches %r" % pattern
            else:
                record.update(own)
                record["energy_source"] = "scheme"
    else:  # the driver refused the input (no results): a broken case or declaration, never a finding
        record["converged"], record["input_error"] = False, True
    runner.save(record)
    return record


def value_key(record):
    return " ".join("%s=%s" % (k, dec._short(v)) for k, v in sorted(record["values"].items()) if k != "dt_factor")


def bounds_for(case, decls, record):
    """The bounds a run must keep: the case's `expect` (any formulation) and the declaration's `bounds` (its own
    measurements; for runs of the core alone, the case's `bounds`), each either for `all` runs or for one value of
    the axis ("name=value")."""
    out, expected_failure = {}, None
    sources = [case.data.get("expect") or {}]
    if record["plugin"] is None:  # the core alone: the case's own bounds
        sources.append(case.data.get("bounds") or {})
    else:
        sources.append(record.get("bounds") or {})
        expected_failure = (record.get("expect_failure") or {}).get(value_key(record))
    for src in sources:
        for key in ("all", value_key(record)):
            for k, v in (src.get(key) or {}).items():
                if k not in BOUND_KEYS:
                    raise dec.DeclarationError("%s: bounds: unknown quantity %r (known: %s)" % (
                        case.path, k, ", ".join(sorted(BOUND_KEYS))))
                out[k] = dec.numeric(v)
    return out, expected_failure


def check(case, decls, records):
    """Regression check of the short pass: every failure message, [] when all hold."""
    failures = []
    for r in records:
        if r.get("kind"):
            continue
        name = "%s %s [%s]" % (case.name, value_key(r), r["label"])
        bounds, expected_failure = bounds_for(case, decls, r)
        if r.get("input_error"):
            failures.append("%s: the driver refused the input: %s" % (name, (r.get("message") or "")[:300]))
            continue
        if not r.get("converged"):
            if expected_failure:
                print("  expected failure: %s (%s)" % (name, expected_failure))
            else:
                failures.append("%s: did not converge (%s)" % (name, (r.get("message") or r.get("status") or "")
                                                              [:300]))
            continue
        if expected_failure:
            print("  NOTE: %s now converges; it is listed as an expected failure (%s)" % (name, expected_failure))
        for key, bound in sorted(bounds.items()):
            value = r.get(key)
            if value is None:
                continue
            if value > bound:
                failures.append("%s: %s = %.4g > %.4g" % (name, key, value, bound))
            else:
                print("  ok: %s: %s = %.4g <= %.4g" % (name, key, value, bound))
    return failures


def suggest_bounds(case, records):
    """Bounds just above the measured values of the short runs, per plugin (printed for a maintainer to review
    and copy into the declaration; never written automatically)."""
    import math
    by_label = {}
    for r in records:
        if r.get("kind") or not r.get("converged"):
            continue
        b = {"newton_iterations": int(math.ceil(1.1 * r["newton_iterations"])) + 2, "step_cuts": r["step_cuts"],
             "flips": int(math.ceil(1.1 * r["flips"])) + 2}
        if r.get("energy_increase") is not None:
            b["energy_increase"] = float("%.1g" % max(2 * r["energy_increase"], 1e-12))
        by_label.setdefault(r["plugin"] or CORE, {})[value_key(r)] = b
    for plugin, values in by_label.items():
        print("  # %s, %s (measured %s)" % (case.name, plugin, __import__("time").strftime("%Y-%m-%d")))
        print("  %s: {bounds: {%s}}" % (case.name, ", ".join("%s: {%s}" % (k, ", ".join(
            "%s: %s" % kv for kv in v.items())) for k, v in values.items())))


def largest_stable(case, records):
    """Per label: the largest dt factor of the ladder that converged within the case's energy bound."""
    limit = (case.data.get("expect") or {}).get("all", {}).get("energy_increase")
    out = {}
    for r in records:
        if r.get("kind") != "ladder":
            continue
        stable = r.get("converged") and (limit is None or r.get("energy_increase", 0) <= float(limit))
        best = out.setdefault(r["label"], None)
        if stable and (best is None or r["values"]["dt_factor"] > best):
            out[r["label"]] = r["values"]["dt_factor"]
    return out


def document(case, records, notes, ladder, short=False):
    rows = []
    for r in sorted((r for r in records if not r.get("kind")),
                    key=lambda r: (r["label"], [v for k, v in sorted(r["values"].items())])):
        converged = "yes" if r.get("converged") else "**input error**" if r.get("input_error") else "**no**"
        rows.append([r["label"], value_key(r) or "–", converged,
                     report.fmt(r.get("steps")), report.fmt(r.get("step_cuts")), report.fmt(r.get("newton_iterations")),
                     report.fmt(r.get("energy_increase"), "%.1e"), report.fmt(r.get("energy_change"), "%+.1e"),
                     report.fmt(r.get("angular_momentum_drift"), "%.1e"),
                     "%s / %s / %s" % (report.fmt(r.get("flips"), "%.0f"), report.fmt(r.get("flips_max_step"), "%.0f"),
                                       report.fmt(r.get("flip_reversals"), "%.0f")),
                     report.fmt(r.get("contact_steps"), "%d"), report.fmt(r.get("cpu_seconds"), "%.1f")])
    header = ["formulation", "value", "converged", "steps", "cuts", "Newton", "max E gain", "E change", "L drift",
              "active-set changes / max per step / reversals", "contact steps", "CPU s"]
    text = ["### %s" % case.title, "", "`%s`; %s" % (case.scene, case.data.get("notes", "").strip()), "",
            "```sh\npython3 tests/bench/stress.py %s\n```" % case.name, "", report.markdown_table(header, rows)]
    if case.data.get("revolutions"):
        text.append("")
        for r in records:
            if r.get("energy_drift_per_revolution") is not None and not r.get("kind"):
                text.append("- %s, %s: %.0f revolutions, energy drift %.2e per revolution, angular momentum %s per "
                            "revolution" % (r["label"], value_key(r), r["revolutions"],
                                            r["energy_drift_per_revolution"],
                                            report.fmt(r.get("angular_momentum_drift_per_revolution"), "%.2e")))
    failed = [r for r in records if not r.get("converged")]
    if failed:
        text.append("")
        for r in failed:
            text.append("- did not converge: %s %s%s — %s" % (
                r["label"], value_key(r), " (dt x%g)" % r["values"]["dt_factor"] if r.get("kind") else "",
                (r.get("message") or r.get("status") or "").replace("\n", " ")[:240]))
    stable = largest_stable(case, records)
    if stable:
        text.append("")
        lad = case.data["dt_ladder"]
        text.append("Largest stable Δt (ladder %s × the default, at %s): %s." % (
            ", ".join("%g" % f for f in lad["factors"]), ", ".join("%s = %s" % kv for kv in
                                                                 (lad.get("at") or {}).items()) or "the default",
            "; ".join("%s ×%s" % (k, "%g" % v if v else "none") for k, v in sorted(stable.items()))))
    for n in notes:
        text.append("- skipped: " + n)
    if short:
        text += ["", "The short (CI) pass only, the plugins' default strategies (`python3 tests/bench/stress.py --short "
                 "--docs %s`); the full sweep has not been run with mortar-dual yet." % case.name]
    text += ["", "Measured at %s (CPU times of a loaded machine)." % report.commits(records)]
    report.replace_section("stability.md", "stress-" + case.name, "\n".join(text))


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("cases", nargs="*")
    p.add_argument("--short", action="store_true")
    p.add_argument("--check", action="store_true")
    p.add_argument("--list", action="store_true")
    p.add_argument("--fresh", action="store_true")
    p.add_argument("--no-ladder", action="store_true")
    p.add_argument("--docs", action="store_true")
    p.add_argument("--suggest-bounds", action="store_true")
    p.add_argument("--plugin", action="append", default=[])
    p.add_argument("--jobs", type=int, default=1)
    p.add_argument("--binary", default=dec.BIN)
    args = p.parse_args()
    try:
        cases = dec.load_benchmarks("stress", kind="stress")
        decls = dec.load_declarations()
        installed = dec.installed_plugins(args.binary)
        for d in decls.values():
            for section, name in d.entries:
                if section == "stress" and name not in cases:
                    raise dec.DeclarationError("%s: stress.%s: no such case (tests/bench/stress/)" % (d.path, name))
        names = args.cases or list(cases)
        for n in names:
            if n not in cases:
                sys.exit("stress: unknown case %r (known: %s)" % (n, ", ".join(cases)))
        planned = {n: case_runs(cases[n], decls, installed, args.plugin, args.short, not args.no_ladder)
                   for n in names}
    except dec.DeclarationError as e:
        sys.exit("stress: %s" % e)
    if args.list:
        for n, (runs, notes) in planned.items():
            labels = {}
            for r in runs:
                labels[r.label] = labels.get(r.label, 0) + 1
            print("%s: %s — %s" % (n, cases[n].title, ", ".join("%s %d runs" % kv for kv in labels.items())))
            for note in notes:
                print("  skipped: " + note)
        return
    all_failures = []
    for n, (runs, notes) in planned.items():
        case = cases[n]
        print("%s: %d runs" % (n, len(runs)), flush=True)
        with ThreadPoolExecutor(max_workers=args.jobs) as pool:
            records = list(pool.map(lambda r: measure(case, r, args), runs))
        for r in records:
            print("  %-28s %-26s %-4s cuts %-3s newton %-5s E+ %-9s flips %-5s cpu %.1f s" % (
                r["label"], value_key(r) + (" dt x%g" % r["values"]["dt_factor"] if r.get("kind") else ""),
                "ok" if r.get("converged") else "FAIL", r.get("step_cuts"), r.get("newton_iterations"),
                report.fmt(r.get("energy_increase"), "%.1e"), report.fmt(r.get("flips"), "%.0f"),
                r["cpu_seconds"]), flush=True)
        if args.suggest_bounds:
            suggest_bounds(case, records)
        if args.check:
            try:
                failures = check(case, decls, records)
            except dec.DeclarationError as e:
                sys.exit("stress: %s" % e)
            all_failures += failures
            for f in failures:
                print("REGRESSION: " + f)
        if not args.short or args.docs:
            document(case, records, notes, not args.no_ladder, args.short)
    if args.check:
        print("stress: %d regression(s)" % len(all_failures))
        sys.exit(1 if all_failures else 0)


if __name__ == "__main__":
    main()
