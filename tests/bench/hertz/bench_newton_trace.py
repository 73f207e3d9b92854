"""Where the Newton iterations of a Hertz run go (docs/hertz.md, "Newton iterations and linear solvers"): one run with
`--verbose` and NOX's own output (`solver.newton.verbose=true`), read back per load step and iteration: ||F|| after
the iteration, the line search's step length, ||s|| (the step taken), and penalty-nts's active set there (nodes in
contact, entered, left, changed master face). Per step it splits the iterations into those up to the last change of
the set ("set settling"), those with the set settled until ||F|| passes the run's residual tests, and the confirming
ones after (the update test on the step taken), and gives where two other tests would have stopped:
- "residual": the run's own residual tests alone (||F|| <= max(absolute, relative ||F0||)), no update test;
- "GetFEM": the test of GetFEM 5.4's md.solve (Newton_with_step_control), ||F|| / L <= 1e-8 after an iteration,
  no update test: GetFEM takes 1-norms and L the bricks' norm of the external data, which grows with the prescribed
  displacement (its noisy output: ||F0|| / L = 1, 1/2, 1/3, 1/4 in the scenes' four steps); here 2-norms and
  L = n ||F0|| in the n-th Newton solve (one per step when no step is cut).

Usage: python3 tests/bench/hertz/bench_newton_trace.py ELEMENT:REFINE [--set key=value ...] [--replace key=value ...]
                                                      [--table]
e.g.   python3 tests/bench/hertz/bench_newton_trace.py tet10:1
Prints every iteration, then one summary row per step (--table: the summary rows only, as markdown)."""
import argparse
import os
import re
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from hertz_cases import ELEMENTS, ROOT, driver_command  # noqa: E402

GETFEM_TOLERANCE = 1e-8
NOX_STEP = re.compile(r"^\|\|F\|\| = (\S+)\s+step = (\S+)\s+dx = (\S+)")
NOX_RESIDUAL = re.compile(r"F-Norm = \S+ < (\S+)\s*$")
NOX_UPDATE = re.compile(r"\) <= (\S+)\s*$")
ACTIVE = re.compile(r"active set: (\d+) slave nodes in contact, (\d+) entered, (\d+) left, (\d+) changed")
NEWTON = re.compile(r"^\s*step (\d+) newton (\d+) ")


def trace(element, refine, sets, replaces=()):
    """Runs the case; returns a list of steps, each a list of iterations (dicts); iteration 0 is the predictor."""
    _, scene, element_sets = ELEMENTS[element]
    out = tempfile.mkdtemp(prefix="stickslip-bench-trace-")
    command = driver_command(scene, element_sets + ["mesh.parameters.refine=%g" % refine,
                                                    "solver.newton.verbose=true"] + list(sets), out)
    command = ["stdbuf", "-oL", "-eL"] + [c for c in command if c != "--quiet"] + ["--verbose"]
    for r in replaces:
        command += ["--replace", r]
    env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
    proc = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env, cwd=ROOT)
    if proc.returncode != 0:
        raise SystemExit("bench_newton_trace.py: the run failed (exit %d): %s\n%s"
                         % (proc.returncode, " ".join(command[3:]), "\n".join(proc.stdout.splitlines()[-5:])))
    text = proc.stdout
    steps, current, pending_set, bounds = [], None, None, {}
    for line in text.splitlines():
        m = ACTIVE.search(line)
        if m:
            pending_set = [int(v) for v in m.groups()]
            continue
        m = NOX_RESIDUAL.search(line)
        if m:  # the absolute test comes first, then the relative one
            bounds.setdefault("residual", []).append(float(m.group(1)))
            continue
        m = NOX_UPDATE.search(line)
        if m:
            bounds["update"] = float(m.group(1))
            continue
        m = NOX_STEP.match(line.strip())
        if m:
            norm_f, length, s = (float(v) for v in m.groups())
            if length == 0.0 and s == 0.0:  # Step 0: a new Newton solve (a new load step or an outer loop)
                current = []
                steps.append(current)
                tolerance = max(bounds["residual"][-2:])  # max(absolute, relative ||F0||): fixed for the solve
            # the last iteration's tests are printed after it: its update bound is taken as the one before
            update = bounds.get("update", current[-1]["update"] if current else 0.0)
            current.append({"F": norm_f, "step": length, "s": s, "set": pending_set, "tol": tolerance,
                            "update": update})
            bounds = {}
            continue
    return steps, " ".join(command[3:])


def summary(its, solve):
    """Counts of the solve-th Newton solve (its[0] the predictor): iterations, set changes, tail, where other tests
    stop."""
    n = len(its) - 1
    changes = sum(1 for k in range(1, n + 1) if its[k]["set"] and (its[k]["set"][1] or its[k]["set"][2]
                                                                     or its[k]["set"][3]))
    residual_stop = next((k for k in range(1, n + 1) if its[k]["F"] <= its[k]["tol"]), n)
    load = solve * its[0]["F"]
    getfem_stop = next((k for k in range(1, n + 1) if its[k]["F"] <= GETFEM_TOLERANCE * load), n)
    last_change = max([k for k in range(1, n + 1) if its[k]["set"] and (its[k]["set"][1] or its[k]["set"][2]
                                                                         or its[k]["set"][3])], default=0)
    return {"newton": n, "set_changes": changes, "settled_from": last_change + 1, "residual": residual_stop,
            "getfem": getfem_stop, "active": its[-1]["set"][0] if its[-1]["set"] else -1,
            "cut": sum(1 for it in its[1:] if it["step"] != 1.0)}


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("case", help="ELEMENT:REFINE, e.g. tet10:1")
    parser.add_argument("--set", action="append", default=[], help="a scene override, as the driver's --set")
    parser.add_argument("--replace", action="append", default=[], help="a scene override, as the driver's --replace")
    parser.add_argument("--table", action="store_true", help="the summary rows only")
    args = parser.parse_args(argv)
    element, refine = args.case.split(":")
    steps, command = trace(element, float(refine), args.set, args.replace)
    if not args.table:
        print(command)
        for n, its in enumerate(steps, 1):
            for k, it in enumerate(its):
                act = "%d in contact, +%d -%d, %d faces" % tuple(it["set"]) if it["set"] else "-"
                print("solve %d it %d  ||F|| %.3e  step %.3g  ||s|| %.3e  (residual tol %.3g, update tol %.3g)  %s"
                      % (n, k, it["F"], it["step"], it["s"], it["tol"], it["update"], act))
    print("| case | step | Newton | ‖F‖ after each iteration | set changed at | in contact | set settling | settled, "
          "‖F‖ above the tests | confirming | residual tests alone | GetFEM's test | step lengths < 1 |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    totals = [0] * 6
    for n, its in enumerate(steps, 1):
        s = summary(its, n)
        changed = [str(k) for k in range(1, len(its)) if its[k]["set"] and any(its[k]["set"][1:])]
        parts = (s["settled_from"] - 1, s["residual"] - s["settled_from"] + 1, s["newton"] - s["residual"],
                 s["newton"], s["residual"], s["getfem"])
        totals = [a + b for a, b in zip(totals, parts)]
        print("| %s | %d | %d | %s | %s | %d | %d | %d | %d | %d | %d | %d |" % (
            args.case, n, s["newton"], ", ".join("%.1e" % it["F"] for it in its[1:]), ", ".join(changed) or "–",
            s["active"], parts[0], parts[1], parts[2], s["residual"], s["getfem"], s["cut"]))
    print("| %s | all | %d | | | | %d | %d | %d | %d | %d | |" % (args.case, totals[3], totals[0], totals[1], totals[2],
                                                                 totals[4], totals[5]))

if __name__ == "__main__":
    main(sys.argv[1:])
