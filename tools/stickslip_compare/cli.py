"""`stickslip compare`: runs variants of one scene (plugins, strategies, penalties, time steps, meshes: any scene key)
and tabulates what each cost and how accurate it was. Usage and every option: `stickslip compare --help`;
docs/user-guide.md ("Comparing formulations and strategies") shows an example."""
import argparse
import csv
import itertools
import os
import shutil
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

from . import errors, report
from .measure import add_outcome, read_results, run_measured

DESCRIPTION = """Runs every combination of the --vary values on SCENE (one `stickslip run` per variant, --jobs at once),
then tabulates per variant: status, steps, Newton iterations, step cuts, CPU and wall time, and the error against a
reference run or a closed form. Writes OUT/compare.csv, OUT/compare.md (also printed) and OUT/compare.png (time
against error, gnuplot: with two or more --vary keys the last one runs along the curves, e.g. one curve per plugin
over the refinements; the grey line is the Pareto front), and each variant's results folder under OUT/runs/.

Every variant is first checked with `stickslip check` (the scene's own key and value checking), so a misspelt key or a
value a plugin refuses stops the comparison before anything runs."""

EPILOG = """error measures:
  With --closed-form hertz:VARS the error is the relative l2 error of the contact pressure against Hertz over the
  contact points with r < 1.25 a, a and p0 from the load the run carries. VARS (comma-separated NAME=VALUE): dim
  (2 or 3), E and nu of the body, E_master of the other body (a rigid one: a large value), R (radius), load_column
  (the history.csv column of the load, e.g. reaction_top_y) and load_factor (what multiplies it into the load: 2 for
  a half model). scenes/hertz-2d.yaml:
    --closed-form hertz:dim=2,E=1000,E_master=1e6,nu=0.3,R=1,load_column=reaction_top_y,load_factor=2
  Otherwise the error is measured against a reference run (--reference, --reference-run; default: the finest
  variant, i.e. the one with the most unknowns, then the most steps, then the last listed) with --error:
    contact-force    max_t |F(t) - F_ref(t)| / max_t |F_ref(t)| of the total contact force (history.csv's
                     contact_force_* columns), the run interpolated linearly at the reference's times (default)
    columns:A,B,...  the same norm over the named history.csv columns (e.g. columns:reaction_top_x,reaction_top_y)
    final-positions  max_i |x_i(T) - x_i,ref(T)| over the nodes at the end time (needs .vtu output; both runs on
                     the same mesh)

examples:
  stickslip compare scenes/hertz-2d.yaml --vary plugin=penalty-nts,nts-augmented \\
      --closed-form hertz:dim=2,E=1000,E_master=1e6,nu=0.3,R=1,load_column=reaction_top_y,load_factor=2
  stickslip compare scenes/mortar-ironing-2d.yaml --vary contact.0.strategy=saddle-point,condensed \\
      --vary time.dt=0.05,0.025 --set time.end=2 --jobs 2 --out ironing-compare
"""


class CompareError(Exception):
    """A usage or input error; the message says what to change."""


def split_values(text):
    """Comma-separated values; commas inside [...] or {...} belong to the value (YAML lists and maps)."""
    values, depth, current = [], 0, ""
    for ch in text:
        if ch in "[{":
            depth += 1
        elif ch in "]}":
            depth -= 1
        if ch == "," and depth == 0:
            values.append(current.strip())
            current = ""
        else:
            current += ch
    values.append(current.strip())
    if any(v == "" for v in values):
        raise CompareError("empty value in '%s'" % text)
    return values


def parse_vary(items):
    """[(key, [values])] in the order given; a key given twice gets the values of both."""
    out = {}
    for item in items:
        if "=" not in item:
            raise CompareError("--vary %s: expected KEY=VALUE,VALUE,... (e.g. contact.0.strategy="
                               "saddle-point,condensed)" % item)
        key, values = item.split("=", 1)
        key = key.strip()
        if not key:
            raise CompareError("--vary %s: no key before '='" % item)
        out.setdefault(key, []).extend(split_values(values))
    return list(out.items())


def short_names(keys):
    """The last component of each key (`refine` for mesh.parameters.refine) unless two keys share it."""
    last = [k.rsplit(".", 1)[-1] for k in keys]
    return [s if last.count(s) == 1 else k for s, k in zip(last, keys)]


def variants(vary, fixed_sets):
    """[{"label", "values": {key: value}, "args": [driver options]}] for every combination of the --vary values."""
    keys = [k for k, _ in vary]
    names = short_names(keys)
    out = []
    for combination in itertools.product(*[values for _, values in vary]) if vary else [()]:
        args = []
        for s in fixed_sets:
            args += ["--set", s]
        for key, value in zip(keys, combination):
            args += ["--plugin", value] if key == "plugin" else ["--set", "%s=%s" % (key, value)]
        label = " ".join("%s=%s" % (n, v) for n, v in zip(names, combination)) or "scene as it is"
        out.append({"label": label, "values": dict(zip(keys, combination)), "args": args})
    return out


def find_binary(given):
    """--binary, STICKSLIP_BIN (set by `stickslip compare`), the driver of this install, or `stickslip` on PATH."""
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))  # <prefix>/share/stickslip/tools
    candidates = [given, os.environ.get("STICKSLIP_BIN"),
                  os.path.normpath(os.path.join(here, "..", "..", "..", "bin", "stickslip")), shutil.which("stickslip")]
    for c in candidates:
        if c and os.path.isfile(c) and os.access(c, os.X_OK):
            return os.path.abspath(c)
    if given:
        raise CompareError("--binary %s: no executable there" % given)
    raise CompareError("no stickslip driver found: run this as `stickslip compare`, or give --binary PATH")


def parse_closed_form(text):
    """'hertz:dim=2,E=1000,...' -> ("hertz_profile", {variables})."""
    name, _, rest = text.partition(":")
    forms = {"hertz": "hertz_profile"}
    if name not in forms:
        raise CompareError("--closed-form %s: unknown closed form '%s' (known: %s)" % (text, name,
                                                                                       ", ".join(sorted(forms))))
    variables = {}
    for item in split_values(rest) if rest else []:
        if "=" not in item:
            raise CompareError("--closed-form %s: expected NAME=VALUE, got '%s'" % (text, item))
        k, v = item.split("=", 1)
        try:
            variables[k.strip()] = float(v)
        except ValueError:
            variables[k.strip()] = v.strip()
    try:
        errors.need_variables(variables, "--closed-form hertz", ("dim", "E", "E_master", "nu", "R", "load_column",
                                                        "load_factor"))
    except errors.ErrorMeasureError as e:
        raise CompareError(str(e) + " (see --help)")
    return forms[name], variables


def reference_measure(error):
    """--error -> (measure name, variables)."""
    if error == "contact-force":
        return "reaction_history", {"columns": ["contact_force_x", "contact_force_y", "contact_force_z"]}
    if error == "final-positions":
        return "final_positions", {}
    if error.startswith("columns:") and error[len("columns:"):]:
        return "reaction_history", {"columns": split_values(error[len("columns:"):])}
    raise CompareError("--error %s: expected contact-force, final-positions or columns:A,B,..." % error)


def check_variant(binary, scene, variant):
    """`stickslip check` with the variant's options: None when fine, else the driver's message."""
    proc = subprocess.run([binary, "check", scene, *variant["args"]], capture_output=True, text=True)
    if proc.returncode != 0:
        return (proc.stderr.strip() or proc.stdout.strip() or "exit %d" % proc.returncode)
    return None


def run_variant(binary, scene, variant, folder, timeout):
    """Runs the variant into folder/results; returns its record (summary counters, cost) and its Results."""
    shutil.rmtree(folder, ignore_errors=True)
    os.makedirs(folder)
    results_dir = os.path.join(folder, "results")
    cmd = [binary, "run", scene, "--out", results_dir, "--quiet", *variant["args"]]
    record = {"label": variant["label"], "values": variant["values"], "folder": folder, "command": cmd}
    record.update(run_measured(cmd, os.path.join(folder, "stderr.txt"), timeout))
    return record, add_outcome(record, results_dir, os.path.join(folder, "stderr.txt"))


def finest(records):
    """The index of the variant with the most unknowns, then the most steps, then the last listed, among those that
    finished."""
    finished = [i for i, r in enumerate(records) if r.get("status") == "ok"]
    if not finished:
        return None
    return max(finished, key=lambda i: (records[i].get("unknowns") or 0, records[i].get("steps") or 0, i))


def pick_reference(spec, records):
    """--reference LABEL or 1-based index -> index."""
    if spec is None:
        return finest(records)
    if spec.isdigit() and 1 <= int(spec) <= len(records):
        return int(spec) - 1
    for i, r in enumerate(records):
        if r["label"] == spec:
            return i
    raise CompareError("--reference %s: no such variant (give its number 1..%d or its label: %s)"
                       % (spec, len(records), "; ".join(r["label"] for r in records)))


def measure_errors(records, results, measure, variables, reference, reference_index):
    for i, (r, res) in enumerate(zip(records, results)):
        if i == reference_index:
            r["error_note"] = "reference"
            continue
        if res is None or r.get("status") != "ok":
            continue
        try:
            r.update({"error": errors.EVALUATORS[measure](res, variables, reference)["error"]})
        except (errors.ErrorMeasureError, ValueError, KeyError, IndexError) as e:
            r["error_note"] = str(e)


TABLE = [("#", "index", "%d"), ("variant", "label", "%s"), ("status", "status", "%s"), ("steps", "steps", "%d"),
         ("Newton its", "newton_iterations", "%d"), ("cuts", "step_cuts", "%d"), ("unknowns", "unknowns", "%d"),
         ("CPU s", "cpu_seconds", "%.3g"), ("wall s", "wall_seconds_outside", "%.3g"), ("error", "error", "%.3e")]


def curve_label(record):
    """The plot's curve of a variant: with two or more --vary keys, the last one runs along each curve (e.g. the
    refinement along one curve per plugin); with one, every variant is its own point."""
    keys = list(record["values"])
    if len(keys) < 2:
        return record["label"]
    names = short_names(keys)
    return " ".join("%s=%s" % (n, record["values"][k]) for n, k in zip(names[:-1], keys[:-1]))


def write_outputs(out, records, scene, error_label, time_key):
    with open(os.path.join(out, "compare.csv"), "w", newline="") as f:
        w = csv.writer(f)
        keys = list(records[0]["values"]) if records else []
        w.writerow(["index", "label", *keys, "status", "steps", "newton_iterations", "step_cuts", "unknowns",
                    "cpu_seconds", "wall_seconds_outside", "wall_seconds", "max_rss_mb", "error", "error_note",
                    "folder"])
        for r in records:
            w.writerow([r["index"], r["label"], *[r["values"][k] for k in keys],
                        *[report.cell(r.get(c)) for c in ("status", "steps", "newton_iterations", "step_cuts",
                                                           "unknowns", "cpu_seconds", "wall_seconds_outside",
                                                           "wall_seconds", "max_rss_mb",
                                                           "error", "error_note")], r["folder"]])
    rows = []
    for r in records:
        row = [report.fmt(r.get(key), spec) for _, key, spec in TABLE]
        if r.get("error_note") == "reference":
            row[-1] = "reference"
        rows.append(row)
    table = report.markdown_table([h for h, _, _ in TABLE], rows)
    notes = ["- %d: %s" % (r["index"], r["error_note"] if r.get("status") == "ok" else
                           (r.get("message") or r.get("status")).splitlines()[-1])
             for r in records if (r.get("error_note") not in (None, "reference")) or r.get("status") != "ok"]
    text = "Scene `%s`, error: %s.\n\n%s\n" % (scene, error_label, table)
    if notes:
        text += "\n" + "\n".join(notes) + "\n"
    with open(os.path.join(out, "compare.md"), "w") as f:
        f.write(text)
    plotted = report.plot(os.path.join(out, "compare.png"), "%s: time against error" % os.path.basename(scene),
                          "CPU seconds" if time_key == "cpu_seconds" else "wall seconds", error_label,
                          [dict(r, label=curve_label(r)) for r in records], x=time_key, y="error")
    return text, plotted


def parse_arguments(argv):
    p = argparse.ArgumentParser(prog="stickslip compare", description=DESCRIPTION, epilog=EPILOG,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("scene", metavar="SCENE.yaml", help="the scene every variant starts from")
    p.add_argument("--vary", action="append", default=[], metavar="KEY=V1,V2,...",
                   help="a scene key (as for `stickslip run --set`, e.g. contact.0.plugin, "
                        "contact.0.strategy, time.dt, mesh.parameters.refine) and the values to try; "
                        "repeat for more keys: every combination runs. The key `plugin` means `stickslip run --plugin` "
                        "(every pair; the scene's parameters kept where the plugin has them). Commas inside [...] or "
                        "{...} belong to the value")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="an override for every variant (as `stickslip run --set`)")
    ref = p.add_mutually_exclusive_group()
    ref.add_argument("--reference", metavar="VARIANT",
                     help="the variant the others are measured against: its number (1 = first, as in the table) or "
                          "its label (default: the finest variant, see below)")
    ref.add_argument("--reference-run", metavar="DIR",
                     help="a results folder of an earlier `stickslip run --out DIR` as the reference")
    ref.add_argument("--closed-form", metavar="NAME:VARS",
                     help="measure the error against a closed form instead of a run: hertz:VARS (see below)")
    p.add_argument("--error", default="contact-force", metavar="MEASURE",
                   help="the error against a reference run: contact-force (default), final-positions or "
                        "columns:A,B,... (see below)")
    p.add_argument("--jobs", type=int, default=1, metavar="N", help="variants run at once (default 1)")
    p.add_argument("--out", metavar="DIR",
                   help="where the table, the plot and the runs go (default: compare-<scene name>); replaced")
    p.add_argument("--time", choices=("cpu", "wall"), default="cpu",
                   help="the time axis of the plot: the CPU time of the whole `stickslip run` process (meshing and "
                        "child processes included; default) or its wall time (both measured from outside; with "
                        "--jobs above 1 or on a busy machine wall times include waiting)")
    p.add_argument("--timeout", type=float, default=3600.0, metavar="SECONDS",
                   help="a variant running longer is stopped and reported as timeout (default 3600)")
    p.add_argument("--binary", metavar="PATH", help="the stickslip driver to run (default: the one running this)")
    p.add_argument("--no-check", action="store_true",
                   help="skip the `stickslip check` of every variant before the runs")
    return p.parse_args(argv)


def main(argv=None):
    args = parse_arguments(sys.argv[1:] if argv is None else argv)
    try:
        return compare(args)
    except CompareError as e:
        print("stickslip compare: %s" % e, file=sys.stderr)
        return 2


def compare(args):
    scene = os.path.abspath(args.scene)
    if not os.path.isfile(scene):
        raise CompareError("%s: no such scene file" % args.scene)
    if args.jobs < 1:
        raise CompareError("--jobs %d: give 1 or more" % args.jobs)
    binary = find_binary(args.binary)
    for s in args.set:
        if "=" not in s:
            raise CompareError("--set %s: expected KEY=VALUE" % s)
    runs = variants(parse_vary(args.vary), args.set)
    if args.closed_form:
        measure, variables = parse_closed_form(args.closed_form)
        error_label = "relative l2 error of the contact pressure against Hertz, r < 1.25 a"
    else:
        measure, variables = reference_measure(args.error)
        error_label = {"final_positions": "max nodal position difference at the end against the reference"}.get(
            measure, "max_t |F - F_ref| / max_t |F_ref|, F = (%s)" % ", ".join(variables.get("columns", [])))
    reference_run = None
    if args.reference_run:
        reference_run = read_results(args.reference_run)
        if reference_run is None:
            raise CompareError("--reference-run %s: no history.csv and summary.json there" % args.reference_run)
    out = os.path.abspath(args.out or "compare-%s" % os.path.splitext(os.path.basename(scene))[0])

    with ThreadPoolExecutor(max_workers=args.jobs) as pool:
        if not args.no_check:
            problems = list(pool.map(lambda v: check_variant(binary, scene, v), runs))
            bad = [(i, m) for i, m in enumerate(problems) if m]
            if bad:
                raise CompareError("\n".join("variant %d (%s) is refused by `stickslip check`:\n  %s"
                                             % (i + 1, runs[i]["label"], m.replace("\n", "\n  ")) for i, m in bad))
        shutil.rmtree(os.path.join(out, "runs"), ignore_errors=True)
        os.makedirs(out, exist_ok=True)
        print("stickslip compare: %d variant(s) of %s, %d at once, into %s" % (len(runs), args.scene, args.jobs, out),
              flush=True)

        def one(i):
            record, results = run_variant(binary, scene, runs[i], os.path.join(out, "runs", "%02d" % (i + 1)),
                                          args.timeout)
            print("  %2d/%d %-40s %s, %s steps, %s Newton iterations, %.2f s CPU"
                  % (i + 1, len(runs), runs[i]["label"], record.get("status"), record.get("steps", "–"),
                     record.get("newton_iterations", "–"), record["cpu_seconds"]), flush=True)
            return record, results
        done = list(pool.map(one, range(len(runs))))
    records = [r for r, _ in done]
    results = [res for _, res in done]
    for i, r in enumerate(records):
        r["index"] = i + 1

    reference_index = None
    if args.closed_form:
        reference = None
    elif reference_run is not None:
        reference = reference_run
    else:
        reference_index = pick_reference(args.reference, records)
        if reference_index is None or results[reference_index] is None or \
                records[reference_index].get("status") != "ok":
            reference = None
            for r in records:
                r["error_note"] = "no reference: the reference variant did not finish"
            reference_index = None
        else:
            reference = results[reference_index]
            error_label += " (reference: variant %d, %s)" % (reference_index + 1, records[reference_index]["label"])
    if args.closed_form or reference is not None:
        measure_errors(records, results, measure, variables, reference, reference_index)

    text, plotted = write_outputs(out, records, args.scene, error_label,
                                  "cpu_seconds" if args.time == "cpu" else "wall_seconds_outside")
    print()
    print(text)
    print("written: %s%s" % (", ".join(os.path.join(out, f) for f in ("compare.csv", "compare.md")),
                             ", " + os.path.join(out, "compare.png") if plotted else
                             " (no plot: no variant has an error to plot)"))
    return 0 if any(r.get("status") == "ok" for r in records) else 1
