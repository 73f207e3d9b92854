"""stickslip (penalty-nts, the scenes' parameters) against GetFEM 5.4 side by side on the Hertz scenes: the same
mesh, problem and load steps (getfem_hertz.py), the same error metric (tests/validation/hertz_profile.py, fed with
GetFEM's pressures at the slave nodes), runs interleaved (stickslip, GetFEM, stickslip, GetFEM, ...) on one machine.

  python3 tests/bench/hertz/bench_getfem.py run [--repeats N] [--each] [--set KEY=VALUE ...] ELEMENT:REFINE[,REFINE...] ...
                                     runs the cases N times each (default 3), merges them into getfem.csv; --set
                                     runs stickslip with that override as well (rows "stickslip KEY=VALUE"; several
                                     --set together, or with --each one run per --set, all interleaved)
  python3 tests/bench/hertz/bench_getfem.py report
                                     prints the tables and draws docs/img/hertz-getfem.png (bench_hertz.py report
                                     puts the tables into docs/hertz.md)

GetFEM runs under GETFEM_PYTHON (default /usr/bin/python3), which needs the getfem module: Debian's python3-getfem
(`scripts/install-deps.sh --bench-getfem`). Without it `run` says so and exits with status 77 (skipped). Costs are
those of each child process, start to exit (meshing included for both codes): wall seconds and user + system CPU
seconds, with one BLAS/OpenMP thread."""
import json
import os
import statistics
import subprocess
import sys
import tempfile

from hertz_cases import ELEMENTS, HERE, ROOT, run_case, run_child
from hertz_profile import hertz_from_reaction, profile_errors
from stickslip_results import Results

CSV = os.path.join(HERE, "getfem.csv")
FIELDS = ["code", "dim", "element", "refine", "repeat", "unknowns", "newton", "newton_steps", "factorisations", "wall",
          "cpu", "rss_mib", "load", "l2", "l2_core", "a", "p0", "peak", "t_mesh", "t_assembly", "t_contact",
          "t_solve", "force_balance"]
GETFEM_SCRIPT = os.path.join(HERE, "getfem_hertz.py")
SKIPPED = 77
STYLES = {"stickslip": "dt 1 pt 7", "getfem": "dt 2 pt 5"}  # other stickslip settings: dotted


def getfem_python():
    """The Python that runs GetFEM, or None (with the reason printed) when it has no getfem module."""
    python = os.environ.get("GETFEM_PYTHON", "/usr/bin/python3")
    try:
        found = subprocess.run([python, "-c", "import getfem"], capture_output=True).returncode == 0
    except OSError:
        found = False
    if not found:
        print("bench_getfem.py: %s cannot import getfem; install Debian's python3-getfem (scripts/install-deps.sh "
              "--bench-getfem) or set GETFEM_PYTHON to a Python that has it. Skipped." % python)
        return None
    return python


def stickslip_run(element, refine, sets):
    out = os.path.join(tempfile.mkdtemp(prefix="stickslip-bench-getfem-"), "results")
    row, _ = run_case(element, "penalty-nts", refine, keep=out, extra_sets=sets)
    s = Results(out).summary
    return {"unknowns": row["unknowns"], "newton": row["newton"], "newton_steps": "",
            "factorisations": s["linear_factorisations"], "wall": row["process_wall"], "cpu": row["cpu"],
            "rss_mib": row["rss_mib"], "load": row["load"], "l2": row["l2"], "l2_core": row["l2_core"],
            "a": row["a"], "p0": row["p0"], "peak": row["peak"], "t_mesh": "", "t_assembly": s["assembly_seconds"],
            "t_contact": s["contact_seconds"], "t_solve": s["solve_seconds"], "force_balance": ""}


def getfem_run(python, element, refine):
    """One GetFEM run, checked: its contact force must balance the load (else the run is refused)."""
    out = os.path.join(tempfile.mkdtemp(prefix="stickslip-bench-getfem-"), "getfem.json")
    cpu, rss, wall = run_child([python, GETFEM_SCRIPT, element, "%g" % refine, out])
    with open(out) as f:
        g = json.load(f)
    reaction = g["reactions"]["top"]
    balance = abs(g["contact_force"] - reaction) / reaction
    if balance > 1e-6:
        raise RuntimeError("GetFEM %s refine %g: contact force %g against the load %g" % (
            element, refine, g["contact_force"], reaction))
    load, a, p0 = hertz_from_reaction(g["dim"], reaction)
    errors = profile_errors(sorted(tuple(p) for p in g["points"]), a, p0)
    return {"unknowns": g["displacement_unknowns"], "newton": sum(g["newton"]),
            "newton_steps": " ".join(str(n) for n in g["newton"]), "factorisations": sum(g["newton"]), "wall": wall,
            "cpu": cpu, "rss_mib": rss, "load": load, "l2": errors["l2"], "l2_core": errors["l2_core"],
            "a": errors["a"], "p0": errors["p0"], "peak": errors["peak"], "t_mesh": g["phases"]["mesh"],
            "t_assembly": g["phases"]["setup"], "t_contact": "", "t_solve": g["phases"]["solve"],
            "force_balance": balance}


def read_rows():
    if not os.path.exists(CSV):
        return []
    import csv
    with open(CSV) as f:
        return list(csv.DictReader(f))


def write_rows(rows):
    import csv
    rows.sort(key=lambda r: (int(r["dim"]), r["element"], float(r["refine"]), r["code"], int(r["repeat"])))
    with open(CSV, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=FIELDS, extrasaction="ignore")
        writer.writeheader()
        writer.writerows(rows)


def parse_cases(specs):
    cases = []
    for spec in specs:
        element, _, levels = spec.partition(":")
        if element not in ELEMENTS or not levels:
            sys.exit("bench_getfem.py: cases are ELEMENT:REFINE[,REFINE...] with ELEMENT one of %s, not '%s'"
                     % (", ".join(ELEMENTS), spec))
        try:
            cases += [(element, float(r)) for r in levels.split(",")]
        except ValueError:
            sys.exit("bench_getfem.py: '%s': refine levels must be numbers" % spec)
    return cases


def run(args):
    repeats, sets, each = 3, [], False
    while args[:1] in (["--repeats"], ["--set"], ["--each"]):
        if args[0] == "--each":
            each, args = True, args[1:]
            continue
        if len(args) < 2:
            sys.exit("bench_getfem.py: %s needs a value" % args[0])
        if args[0] == "--set":
            if "=" not in args[1]:
                sys.exit("bench_getfem.py: --set takes KEY=VALUE, not '%s'" % args[1])
            sets.append(args[1])
        elif not args[1].isdigit() or int(args[1]) < 1:
            sys.exit("bench_getfem.py: --repeats takes a positive integer")
        else:
            repeats = int(args[1])
        args = args[2:]
    variants = [[s] for s in sets] if each else [sets] if sets else []
    codes = ["stickslip"] + [" ".join(["stickslip"] + v) for v in variants] + ["getfem"]
    variant_sets = {" ".join(["stickslip"] + v): v for v in variants}
    cases = parse_cases(args)
    if not cases:
        sys.exit(__doc__)
    python = getfem_python()
    if python is None:
        sys.exit(SKIPPED)
    for element, refine in cases:
        for repeat in range(repeats):
            new = []
            for code in codes:  # interleaved: the codes see the same machine load
                row = (getfem_run(python, element, refine) if code == "getfem" else
                       stickslip_run(element, refine, variant_sets.get(code, [])))
                row.update({"code": code, "dim": ELEMENTS[element][0], "element": element, "refine": "%g" % refine,
                            "repeat": repeat})
                print("%-9s %-6s refine %-5g #%d %7d unknowns  Newton %3d  wall %7.2f s  cpu %7.2f s  l2 %.4f  "
                      "load %.5f" % (code, element, refine, repeat, row["unknowns"], row["newton"], row["wall"],
                                     row["cpu"], row["l2"], row["load"]), flush=True)
                new.append({k: ("%.6g" % v if isinstance(v, float) else v) for k, v in row.items()})
            keys = {(r["code"], r["element"], r["refine"], str(r["repeat"])) for r in new}
            write_rows([r for r in read_rows() if (r["code"], r["element"], r["refine"], r["repeat"]) not in keys]
                       + new)


# ---- report ------------------------------------------------------------------------------------------------------
def levels(rows):
    """{(dim, element, refine, code): [rows of its repeats]}."""
    out = {}
    for r in rows:
        out.setdefault((int(r["dim"]), r["element"], float(r["refine"]), r["code"]), []).append(r)
    return out


def median(runs, field):
    return statistics.median(float(r[field]) for r in runs)


def table(dim, rows):
    """Median over the repeats; ratio = stickslip / GetFEM at the same mesh."""
    by = levels(rows)
    out = ["| element | refine | code | unknowns | Newton (per step) | factorisations | wall [s] | CPU [s] | "
           "assembly / contact / solve [s] | L2 profile | L2 core | load | wall ratio | CPU ratio |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    order = [e for e, v in ELEMENTS.items() if v[0] == dim]
    keys = [k for k in by if k[0] == dim]
    for d, element, refine, code in sorted(keys, key=lambda k: (order.index(k[1]), k[2], k[3] == "getfem", k[3])):
        runs = by[(d, element, refine, code)]
        other = by.get((d, element, refine, "getfem"))
        ratio = lambda f: "%.2f" % (median(runs, f) / median(other, f)) if code != "getfem" and other else ""
        phases = ("%.2f / %.2f / %.2f" % tuple(median(runs, "t_" + p) for p in ("assembly", "contact", "solve"))
                  if code != "getfem" else "mesh %.2f, set-up %.2f, Newton %.2f" % (
                      median(runs, "t_mesh"), median(runs, "t_assembly"), median(runs, "t_solve")))
        newton = runs[0]["newton"] + (" (%s)" % runs[0]["newton_steps"].replace(" ", ", ")
                                      if runs[0]["newton_steps"] else "")
        out.append("| %s | %g | %s | %s | %s | %s | %.2f (%.2f–%.2f) | %.2f | %s | %.4f | %.4f | %.4f | %s | %s |" % (
            element, refine, "GetFEM nodal" if code == "getfem" else "stickslip penalty-nts" + code[len("stickslip"):],
            runs[0]["unknowns"],
            newton, runs[0]["factorisations"], median(runs, "wall"), min(float(r["wall"]) for r in runs),
            max(float(r["wall"]) for r in runs), median(runs, "cpu"), phases, median(runs, "l2"),
            median(runs, "l2_core"), median(runs, "load"), ratio("wall"), ratio("cpu")))
    return "\n".join(out)


def plot(rows, work):
    """Work-precision: L2 profile error against wall and CPU seconds (medians), 2D above, 3D below."""
    from bench_hertz import COLOURS, gnuplot
    by = levels(rows)
    curves = sorted({(k[0], k[1], k[3]) for k in by})
    for dim, element, code in curves:
        with open(os.path.join(work, "%s-%s.dat" % (element, code.replace(" ", "_"))), "w") as f:
            for key in sorted(k for k in by if k[:2] == (dim, element) and k[3] == code):
                runs = by[key]
                f.write("%g %g %g\n" % (median(runs, "wall"), median(runs, "cpu"), median(runs, "l2")))
    png = os.path.join(ROOT, "docs", "img", "hertz-getfem.png")
    lines = ["set terminal pngcairo size 1400,1000 font ',11'", "set output '%s'" % png,
             "set multiplot layout 2,2 title 'Hertz: L2 profile error against cost, stickslip penalty-nts (solid; "
             "dotted: other settings) and GetFEM nodal contact (dashed); medians of interleaved runs'",
             "set logscale xy", "set grid", "set key top right font ',9'", "set ylabel 'L2 profile error'"]
    for dim in (2, 3):
        for col, label in ((1, "wall"), (2, "CPU (user + system)")):
            plots = ["'%s' using %d:3 with linespoints lw 2 %s lc rgb '%s' title '%s %s'" % (
                os.path.join(work, "%s-%s.dat" % (e, c.replace(" ", "_"))), col, STYLES.get(c, "dt 3 pt 9"),
                COLOURS[e], e, "GetFEM" if c == "getfem" else c) for d, e, c in curves if d == dim]
            if plots:
                lines += ["set title '%dD'" % dim, "set xlabel '%s seconds per run'" % label,
                          "plot " + ", ".join(plots)]
    gnuplot("\n".join(lines + ["unset multiplot", ""]))
    return png


def report():
    rows = read_rows()
    if not rows:
        return {}
    plot(rows, tempfile.mkdtemp(prefix="stickslip-bench-getfem-plot-"))
    return {dim: table(dim, rows) for dim in (2, 3) if any(int(r["dim"]) == dim for r in rows)}


def main():
    if len(sys.argv) >= 2 and sys.argv[1] == "run":
        run(sys.argv[2:])
    elif sys.argv[1:] == ["report"]:
        for dim, text in report().items():
            print("%dD\n%s\n" % (dim, text))
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main()
