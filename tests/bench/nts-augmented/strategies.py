#!/usr/bin/env python3
"""Benchmark (a): the strategies of nts-augmented on the two-tori impact (scenes/two-tori-coarse.yaml: refine 0.25,
270 hex8 per torus; refine 0.5, 1020 hex8 per torus), per linear solver option (direct = MUMPS; auto). Truncated
runs: the first STEPS steps (contact from step 5). Reports linear system size, Newton iterations per step, time per
Newton iteration, wall time.
Usage: python3 tests/bench/nts-augmented/strategies.py [STEPS [REFINES [SOLVERS]]]
  e.g. strategies.py 12 0.25,0.5 direct,auto   (default: 12 0.25 direct)
  -> tests/bench/nts-augmented/strategies.csv, table on stdout"""
import os
import sys

from common import ROOT, run, write_csv

STEPS = int(sys.argv[1]) if len(sys.argv) > 1 else 12
REFINES = [float(r) for r in (sys.argv[2] if len(sys.argv) > 2 else "0.25").split(",")]
SOLVERS = (sys.argv[3] if len(sys.argv) > 3 else "direct").split(",")
STRATEGIES = ("condensed", "augmented", "paper-reduced", "direct", "direct-endpoint")
rows = []
for refine in REFINES:
    for solver in SOLVERS:
        for strategy in STRATEGIES:
            tag = "strategies-r%g-%s-%s" % (refine, solver, strategy)
            r = run("scenes/two-tori-coarse.yaml", tag, "--steps", str(STEPS),
                    "--set", "mesh.0.parameters.refine=%g" % refine, "--set", "mesh.1.parameters.refine=%g" % refine,
                    "--set", "solver.linear.solver=" + solver, "--set", "contact.0.strategy=" + strategy)
            if r is None:
                rows.append([refine, solver, strategy, "", "", "", "", "", "", "", "failed"])
                continue
            s = r.summary
            its = s["newton_iterations"]
            active = max(row["active_points"] for row in r.rows)
            rows.append([refine, solver, strategy, s["dofs"], s["linear_system_size"], s["steps"], its,
                         "%.2f" % (its / max(s["steps"], 1)), "%.4f" % (s["wall_seconds"] / max(its, 1)),
                         "%.2f" % s["wall_seconds"], "%.2f/%.2f/%.2f" % (s["assembly_seconds"], s["contact_seconds"],
                                                                        s["solve_seconds"]),
                         int(active), s["status"]])
header = ["refine", "linear_solver", "strategy", "dofs", "linear_system_size", "steps", "newton_iterations",
          "iterations_per_step", "seconds_per_iteration", "wall_seconds", "assembly/contact/solve_seconds",
          "max_active", "status"]
write_csv(os.path.join(ROOT, "tests", "bench", "nts-augmented", "strategies.csv"), header, rows)
print("| " + " | ".join(header) + " |")
print("|" + "---|" * len(header))
for row in rows:
    print("| " + " | ".join(str(v) for v in row) + " |")
