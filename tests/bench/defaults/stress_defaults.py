#!/usr/bin/env python3
"""The stress suite (tests/bench/stress.py, docs/stability.md) with the defaults computed from the scene: each short run
of a contact plugin once as its declaration sets it (the tuned penalty, epsilon_t or c_n) and once with those keys
removed, so that the plugin computes them (docs/scene-reference.md#contact). Per pair of runs: converged or not,
step cuts, Newton iterations, energy gain, and the computed values. The table goes into the plugins' "Defaults".

  python3 tests/bench/defaults/stress_defaults.py [CASE ...] [--plugin NAME] [--set KEY=VALUE] [--csv FILE]
Results are cached under results/bench/stress-defaults (STICKSLIP_BENCH_OUT) like the stress suite's."""
import argparse
import csv
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
BENCH = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(BENCH, "harness"))
sys.path.insert(0, BENCH)
import declarations as dec  # noqa: E402
import stress  # noqa: E402

# the parameters whose defaults the scene gives (the rest of a declaration's parameters stay)
COMPUTED_KEYS = {"penalty", "penalty_tangential", "epsilon_t", "c_n", "c_t"}
PLUGINS = {"penalty-nts", "covariant-penalty", "nts-augmented", "mortar-dual"}
FIELDS = ["case", "plugin", "values", "parameters", "settings", "converged", "step_cuts", "newton_iterations",
          "energy_increase", "computed"]


def with_defaults(run):
    """A copy of `run` whose contact parameters keep only the keys that are not computed from the scene."""
    args = list(run.args)
    for i, a in enumerate(args):
        if a.startswith("contact.0.parameters="):
            entries = re.findall(r"(\w+): ([^,}]+)", a.split("=", 1)[1])
            kept = ", ".join("%s: %s" % (k, v) for k, v in entries if k not in COMPUTED_KEYS)
            args[i] = "contact.0.parameters={%s}" % kept
    out = dec.Run(run.bench, run.plugin, run.strategy, run.solver, dict(run.values), args, run.label + "/defaults",
                  run.scene, run.options)
    out.values["parameters"] = "defaults"
    return out


def parameters_of(run):
    for a in run.args:
        if a.startswith("contact.0.parameters="):
            return a.split("=", 1)[1]
    return ""


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("cases", nargs="*")
    p.add_argument("--plugin", action="append", default=[])
    p.add_argument("--set", action="append", default=[])
    p.add_argument("--csv", default=os.path.join(HERE, "stress.csv"))
    p.add_argument("--binary", default=dec.BIN)
    args = p.parse_args()
    args.fresh = False
    cases = dec.load_benchmarks("stress", kind="stress")
    decls = dec.load_declarations()
    installed = dec.installed_plugins(args.binary)
    rows = []
    for name in args.cases or list(cases):
        case = cases[name]
        runs, _ = stress.case_runs(case, decls, installed, args.plugin, True, False)
        for run in runs:
            if run.plugin not in PLUGINS:
                continue
            for extra in args.set:
                run.args += ["--set", extra]
            for variant in (run, with_defaults(run)):
                record = stress.measure(case, variant, args)
                computed = ""
                err = os.path.join(record["folder"], "stderr.txt")
                row = {"case": name, "plugin": run.plugin, "values": stress.value_key(record),
                       "parameters": parameters_of(variant), "settings": " ".join(args.set),
                       "converged": int(bool(record.get("converged"))), "step_cuts": record.get("step_cuts"),
                       "newton_iterations": record.get("newton_iterations"),
                       "energy_increase": record.get("energy_increase"), "computed": computed}
                if variant is not run and os.path.exists(err):
                    row["computed"] = explain(variant, args.binary)
                rows.append(row)
                print("%-18s %-17s %-22s %-60s %-4s cuts %-3s newton %-5s E+ %s" % (
                    name, run.plugin, row["values"], row["parameters"][:60], "ok" if row["converged"] else "FAIL",
                    row["step_cuts"], row["newton_iterations"], row["energy_increase"]), flush=True)
    with open(args.csv, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=FIELDS)
        writer.writeheader()
        writer.writerows(rows)


def explain(run, binary):
    """The computed values of `run`, "key=value; ..." from `stickslip check --explain`."""
    import subprocess
    scene = os.path.join(dec.ROOT, run.scene) if not os.path.isabs(run.scene) else run.scene
    proc = subprocess.run([binary, "check", scene] + run.args + ["--explain"], capture_output=True, text=True)
    found = re.findall(r"parameters\.(\w+) = (\S+) \(computed: (?!unused:)", proc.stdout)  # not the unused ones (0)
    return "; ".join("%s=%s" % kv for kv in found)


if __name__ == "__main__":
    main()
