#!/usr/bin/env python3
"""mortar-dual's scaling study (issue 9): strategy saddle-point vs condensed x direct (MUMPS) vs GMRES + MueLu, on
Hertz 3D (scenes/mortar-hertz-3d.yaml, the whole run: 4 steps) and the 3D ironing (scenes/mortar-ironing-3d.yaml,
the first 2 press steps at dt = 0.05) at growing refinement. Each run goes through the shared runner
(tests/bench/harness/runner.py: CPU time and peak RSS of the child by os.wait4, the counters of summary.json; a
finished run is reused unless --fresh; results/bench/mortar-scaling/<scene>/). Writes
results/bench/mortar-scaling/scaling.csv and one .dat per curve, prints the table and the fitted exponents of CPU
time per Newton iteration against dofs (least squares on the log-log points of each curve).

CPU time per Newton iteration against dofs (least squares on the log-log points of each curve).

CPU time per Newton iteration = the child's CPU seconds x (assembly + contact + solve wall seconds) / (wall seconds
of the run) / Newton iterations: the CPU share of the Newton phases, without mesh generation and set-up.

  python3 tests/bench/mortar-dual/scaling.py [--fresh] [--quick] [--solver=NAME] [hertz-3d] [ironing-3d]

--solver=NAME runs only that linear solver's configurations; the others' finished runs are reported, the missing
ones left out of the table.
  gnuplot tests/bench/mortar-dual/scaling.gp      # -> docs/img/mortar-dual-scaling.png"""
import csv
import json
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "harness"))
import declarations as dec  # noqa: E402
import runner  # noqa: E402

GROUP = "mortar-scaling"
STUDIES = {
    "hertz-3d": ("scenes/mortar-hertz-3d.yaml", ("mesh.parameters.refine",), (0.7, 1.0, 1.5, 2.0), ()),
    # refine 0.6 .. 1.25 keep the indenter's 7 cells along y off the block's 8 (no slave edge on a master edge)
    "ironing-3d": ("scenes/mortar-ironing-3d.yaml", ("mesh.0.parameters.refine", "mesh.1.parameters.refine"),
                   (0.6, 0.75, 1.0, 1.25), ("--steps", "2", "--set", "time.dt=0.05")),
}
STRATEGIES = ("saddle-point", "condensed")
SOLVERS = ("direct", "gmres-muelu")
TIMEOUT = 900.0
FIELDS = ("study", "strategy", "solver", "refine", "status", "dofs", "linear_system_size", "newton_iterations",
          "step_cuts", "cpu_seconds", "cpu_per_iteration", "solve_wall_per_iteration", "max_rss_mb",
          "linear_solvers_used", "replaced_by_direct", "message")


def runs(study, quick):
    scene, keys, levels, extra = STUDIES[study]
    for refine in levels[:2] if quick else levels:
        for strategy in STRATEGIES:
            for solver in SOLVERS:
                args = ["--set", "contact.0.strategy=%s" % strategy, "--set", "solver.linear.solver=%s" % solver]
                for k in keys:
                    args += ["--set", "%s=%g" % (k, refine)]
                yield dec.Run(study, "mortar-dual", strategy, solver, {"refine": refine}, [*args, *extra],
                              "mortar-dual/%s/%s" % (strategy, solver), scene)


def row_of(run, record):
    summary = {}
    path = os.path.join(record["folder"], "results", "summary.json")
    if not os.path.exists(path):
        path = os.path.join(record["folder"], "results.incomplete", "summary.json")
    if os.path.exists(path):
        with open(path) as f:
            summary = json.load(f)
    its = record.get("newton_iterations") or 0
    phases = sum(record.get(k) or 0.0 for k in ("assembly_seconds", "contact_seconds", "solve_seconds"))
    wall = record.get("wall_seconds") or 0.0
    ok = record.get("status") == "ok"
    return {
        "study": run.bench, "strategy": run.strategy, "solver": run.solver, "refine": run.values["refine"],
        "status": record.get("status"), "dofs": record.get("dofs"),
        "linear_system_size": record.get("linear_system_size"), "newton_iterations": its,
        "step_cuts": record.get("step_cuts"), "cpu_seconds": round(record["cpu_seconds"], 3),
        "cpu_per_iteration": round(record["cpu_seconds"] * phases / wall / its, 4) if ok and its and wall else "",
        "solve_wall_per_iteration": round((record.get("solve_seconds") or 0.0) / its, 4) if ok and its else "",
        "max_rss_mb": round(record["max_rss_mb"], 1),
        "linear_solvers_used": summary.get("linear_solvers_used", ""),
        "replaced_by_direct": summary.get("linear_solver_replaced_by_direct", ""),
        "message": (record.get("message") or summary.get("message") or "")[:300].replace("\n", " "),
    }


def exponent(points):
    """Least-squares slope of log y against log x."""
    if len(points) < 2:
        return float("nan")
    lx = [math.log(x) for x, _ in points]
    ly = [math.log(y) for _, y in points]
    mx, my = sum(lx) / len(lx), sum(ly) / len(ly)
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / sum((a - mx) ** 2 for a in lx)


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    fresh, quick = "--fresh" in sys.argv, "--quick" in sys.argv
    only = [a.split("=", 1)[1] for a in sys.argv[1:] if a.startswith("--solver=")]
    studies = args or list(STUDIES)
    rows = []
    for study in studies:
        for run in runs(study, quick):
            group = os.path.join(GROUP, study)
            if only and run.solver not in only and \
                    not os.path.exists(os.path.join(runner.OUT, group, run.tag, "record.json")):
                continue
            record, _ = runner.execute(run, group, TIMEOUT, fresh=fresh and (not only or run.solver in only))
            rows.append(row_of(run, record))
            r = rows[-1]
            print("%s %s/%s refine %g: %s, %s dofs, %s Newton, %.1f CPU s, %s CPU s/iteration, %.0f MB %s"
                  % (study, run.strategy, run.solver, r["refine"], r["status"], r["dofs"], r["newton_iterations"],
                     r["cpu_seconds"], r["cpu_per_iteration"], r["max_rss_mb"], r["linear_solvers_used"]),
                  flush=True)
    out = os.path.join(runner.OUT, GROUP)
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "scaling.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS)
        w.writeheader()
        w.writerows(rows)
    # one data file per curve for gnuplot: dofs, CPU s per Newton iteration
    for study in studies:
        for strategy in STRATEGIES:
            for solver in SOLVERS:
                with open(os.path.join(out, "%s-%s-%s.dat" % (study, strategy, solver)), "w") as f:
                    for r in rows:
                        if (r["study"], r["strategy"], r["solver"]) == (study, strategy, solver) and \
                                r["cpu_per_iteration"] != "" and not r["replaced_by_direct"]:
                            f.write("%s %s\n" % (r["dofs"], r["cpu_per_iteration"]))
    print("\n| scene | strategy | solver | refine | dofs | linear system | Newton | CPU s | CPU s / Newton "
          "iteration | solve wall s / iteration | peak RSS MB | solver used |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        used = r["linear_solvers_used"] + (" (**replaced by direct**)" if r["replaced_by_direct"] else "")
        if r["status"] != "ok":
            used = "**%s**: %s" % (r["status"], r["message"][:160])
        print("| %s | %s | %s | %g | %s | %s | %s | %.1f | %s | %s | %.0f | %s |"
              % (r["study"], r["strategy"], r["solver"], r["refine"], r["dofs"], r["linear_system_size"],
                 r["newton_iterations"], r["cpu_seconds"], r["cpu_per_iteration"], r["solve_wall_per_iteration"],
                 r["max_rss_mb"], used))
    print("\nexponents (CPU s per Newton iteration ~ dofs^k, runs solved by the named solver only):")
    for study in studies:
        for strategy in STRATEGIES:
            for solver in SOLVERS:
                pts = [(r["dofs"], r["cpu_per_iteration"]) for r in rows
                       if (r["study"], r["strategy"], r["solver"]) == (study, strategy, solver)
                       and r["cpu_per_iteration"] != "" and not r["replaced_by_direct"]]
                print("  %s %s/%s: k = %.2f over %d levels" % (study, strategy, solver, exponent(pts), len(pts)))


if __name__ == "__main__":
    main()
