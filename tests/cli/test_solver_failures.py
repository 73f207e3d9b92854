"""Failures a shorter step cannot cure end or adapt the run without cutting the step (issue 8):
- roundoff_floor: tolerances below the residual's round-off floor (1e-30): Newton accepts each step there, once its
  corrections are at round-off, with a warning that prints the numbers in %g (not `||F|| = 0.000000`); no step is
  cut, the run ends, and summary.json counts the steps (issue 31; before, every step was cut until the run failed);
- iterative_fallback: a Krylov solver the scene chose that misses its tolerance is replaced by the direct solver for
  the rest of the run (one message, no step cut, summary.json records it), and the run ends as with `direct`;
- iterative_equals_direct: a contact run whose systems keep their multiplier rows (scenes/two-elements.yaml,
  nts-augmented `augmented`, the first 25 midpoint steps: contact in steps 13-21) gives with GMRES + MueLu and GMRES + SGS (multiplier rows through
  their Schur complement) and GMRES + the lagged MUMPS factorisation (gmres-lu) the contact forces of MUMPS, to the
  linear and Newton tolerances;
- muelu_nullspace: `solver.linear.nullspace` reaches MueLu: on the quad9 Hertz mesh (refine 0.5), GMRES + MueLu with the
  rigid-body modes and with the translations only take different GMRES iterations (measured 432 and 451) and give
  the same contact force to the Newton tolerance; `check --explain` prints the choice;
- line_search_choice: the backtracking line search runs a punch pressed and dragged with friction (nts-augmented,
  tests/bench/line-search/punch-2d.yaml) to the end, where the full step fails in step 1; the default
  (full-step-then-backtrack) runs it too, solving the steps whose full-step Newton fails again with backtracking
  (counted in summary.json) without a step cut; where the full step converges the default is the full step (two-elements,
  25 midpoint steps: the history of `full-step`, digit for digit) (docs/linear-solvers.md, "Line search");
- backtrack_switch_count: summary.json's `newton_backtrack_switches` counts the solves whose full step made no
  progress and went on with backtracking (docs/stability.md, finding 28), as many as `--verbose` reports, and the
  run's last line says so only when there were any: wedge-slides-2d with mortar-dual switches, with the explicit
  `full-step` or with penalty-nts it never does.
Usage: python3 test_solver_failures.py CASE."""
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cli_case import CONTACT, CRASH_MARKERS, ROOT, main, read_history, read_summary  # noqa: E402


def roundoff_floor(c):
    scene = c.write(CONTACT)
    proc = c.run("run", scene, "--quiet", "--out", c.out, "--set", "solver.newton.tolerance=1e-30",
                 "--set", "solver.newton.absolute_tolerance=1e-30")
    c.check(proc.returncode == 0, "exit 0: the run ends")
    c.check(not any(m in proc.stdout + proc.stderr for m in CRASH_MARKERS), "no crash marker")
    warnings = re.findall(r"warning: step \d+ \(t = [0-9.]+\): Newton accepted at the round-off floor in iteration "
                          r"\d+: \|\|F\|\| = \d\.\d+e-1\d \(\d\.\d+e-1\d before\) with Newton corrections at round-off "
                          r"\(\|\|dx\|\| = \d\.\d+e-1\d <= \d\.\d+e-1\d\), above the absolute tolerance 1e-30", proc.stderr)
    c.check(len(warnings) == 2, "one warning per step, the numbers in %%g (got %d)" % len(warnings))
    c.check("0.000000" not in proc.stderr, "no %f-formatted zero")
    s = read_summary(c.out)
    c.check(s["status"] == "ok" and s["step_cuts"] == 0 and s["steps"] == 2,
            "summary.json: ok, 2 steps, no cut (got %s, %s, %s)" % (s["status"], s["steps"], s["step_cuts"]))
    c.check(s["roundoff_floor_steps"] == 2, "summary.json counts the steps accepted at the floor (got %s)"
            % s["roundoff_floor_steps"])
    c.check(s["newton_iterations"] <= 8, "at most two iterations at the floor per step (measured 6 in all, got %s)"
            % s["newton_iterations"])


def iterative_fallback(c):
    scene = c.write(CONTACT)
    direct_out = os.path.join(c.dir, "direct")
    proc = c.run("run", scene, "--quiet", "--out", c.out, "--set", "solver.linear.solver=gmres-sgs",
                 "--set", "solver.linear.max_iterations=2")
    c.check(proc.returncode == 0, "exit 0: the run finishes")
    c.check(len(re.findall("replaced by direct", proc.stderr)) == 1 and "gmres-sgs: no convergence" in proc.stderr,
            "one message naming the failed solver and its replacement")
    s = read_summary(c.out)
    c.check(s["step_cuts"] == 0 and s["linear_solver_replaced_by_direct"] == 1,
            "summary.json: 0 step cuts, linear_solver_replaced_by_direct = 1")
    c.run("run", scene, "--quiet", "--out", direct_out, "--set", "solver.linear.solver=direct")
    a, b = read_history(c.out), read_history(direct_out)
    worst = max(abs(float(x[k]) - float(y[k])) for x, y in zip(a, b) for k in ("contact_force_z",))
    scale = max(abs(float(x["contact_force_z"])) for x in b)
    c.check(len(a) == len(b) and worst <= 1e-10 * scale,
            "the contact force equals the direct run's to %.1e relative" % (worst / scale))


def line_search_choice(c):
    punch = os.path.join(ROOT, "tests", "bench", "line-search", "punch-2d.yaml")
    args = ("--quiet", "--plugin", "nts-augmented", "--set", "contact.0.parameters={mu: 0.3, epsilon_t: 1.0e+5}")
    full_out = os.path.join(c.dir, "full-step")
    c.run("run", punch, *args, "--out", c.out, "--set", "solver.newton.line_search=backtrack")
    c.run("run", punch, *args, "--out", full_out, "--set", "solver.newton.line_search=full-step")
    s, full = read_summary(c.out), read_summary(full_out)
    c.check(s["status"] == "ok" and s["final_time"] == 2,
            "backtrack: the punch runs to t = 2 (got %s at t = %s)" % (s["status"], s["final_time"]))
    c.check(full["status"] == "failed", "with the full step it fails (got %s)" % full["status"])
    c.run("check", punch, "--explain")
    c.check(re.search(r"line_search +full-step-then-backtrack: full Newton steps; a step whose Newton fails is solved "
                      r"again", c.proc.stdout) is not None, "check --explain prints the default line search")
    default_out = os.path.join(c.dir, "default")
    c.run("run", punch, *args, "--out", default_out)
    d = read_summary(default_out)
    c.check(d["status"] == "ok" and d["final_time"] == 2,
            "default: the punch runs to t = 2 (got %s at t = %s)" % (d["status"], d["final_time"]))
    # the full step stalls in step 1 (it fails there alone, above): it goes on with backtracking in the same solve
    # (docs/stability.md, finding 28) instead of a retry of the step. Measured: 144 Newton iterations, no retry, no
    # cut; at 71eff4f, before that, the step's retry with backtracking: 175 iterations, 1 retry (rescued), no cut.
    c.check(d.get("backtrack_retries", 0) == 0 and d["step_cuts"] == 0 and d["newton_iterations"] <= 150,
            "default: the stalled full step goes on with backtracking, no retry, no step cut, <= 150 Newton "
            "iterations (retries %s, cuts %s, iterations %s)" % (d.get("backtrack_retries"), d["step_cuts"],
                                                                 d["newton_iterations"]))
    print("punch-2d nts-augmented: backtrack %d iterations / %d cuts; default %d / %d (%d retries)" % (
        s["newton_iterations"], s["step_cuts"], d["newton_iterations"], d["step_cuts"], d["backtrack_retries"]))
    scene = os.path.join(ROOT, "scenes", "two-elements.yaml")
    dynamic_full = os.path.join(c.dir, "dynamic-full-step")
    dynamic_default = os.path.join(c.dir, "dynamic-default")
    c.run("run", scene, "--quiet", "--steps", "25", "--out", dynamic_default)
    c.run("run", scene, "--quiet", "--steps", "25", "--out", dynamic_full, "--set", "solver.newton.line_search=full-step")
    def history(folder):  # every column but the wall clock
        return [{k: v for k, v in row.items() if k != "wall_seconds"} for row in read_history(folder)]
    a, b = history(dynamic_default), history(dynamic_full)
    c.check(len(a) == 26 and a == b, "default: the full step's history, digit for digit")


def iterative_equals_direct(c):
    scene = os.path.join(ROOT, "scenes", "two-elements.yaml")
    common = ("--quiet", "--steps", "25", "--set", "contact.0.strategy=augmented")
    runs = {}
    # (solver, inexact Newton, bound): exact Krylov solves to linear.tolerance 1e-10 (measured: MueLu 2.2e-14,
    # SGS 1.7e-14 relative), and the default inexact solves (measured: MueLu 3.5e-13); Newton's update test
    # confirms convergence with one more solve, which brings both to round-off
    # gmres-lu (the lagged MUMPS factorisation as preconditioner, inexact): measured 5.1e-14
    cases = [("direct", "false", 0.0), ("gmres-muelu", "false", 1e-13), ("gmres-sgs", "false", 1e-13),
             ("gmres-muelu", "true", 1e-12), ("gmres-lu", "true", 1e-12)]
    for solver, inexact, bound in cases:
        out = os.path.join(c.dir, "%s-%s" % (solver, inexact))
        proc = c.run("run", scene, *common, "--out", out, "--set", "solver.linear.solver=" + solver,
                     "--set", "solver.newton.inexact=" + inexact)
        c.check(proc.returncode == 0, "%s (inexact %s): exit 0" % (solver, inexact))
        runs[(solver, inexact)] = (read_history(out), read_summary(out))
    ref, ref_summary = runs[("direct", "false")]
    c.check(ref_summary["unknowns"] > ref_summary["dofs"] and ref_summary["linear_system_size"] == ref_summary["unknowns"],
            "the systems keep multiplier rows (%d unknowns, %d displacements)" % (ref_summary["unknowns"], ref_summary["dofs"]))
    c.check(sum(1 for r in ref if float(r["active_points"]) > 0) >= 5, "contact is active in several steps")
    keys = ("contact_force_x", "contact_force_y")
    scale = max(abs(float(r[k])) for r in ref for k in keys)
    for solver, inexact, bound in cases[1:]:
        rows, s = runs[(solver, inexact)]
        worst = max(abs(float(x[k]) - float(y[k])) for x, y in zip(rows, ref) for k in keys)
        c.check(s["linear_solver_replaced_by_direct"] == 0, "%s (inexact %s) solved every system itself" % (solver, inexact))
        c.check(len(rows) == len(ref) and worst <= bound * scale,
                "%s (inexact %s): contact forces equal MUMPS's to %.1e relative (bound %.0e)"
                % (solver, inexact, worst / scale, bound))


def muelu_nullspace(c):
    scene = os.path.join(ROOT, "scenes", "hertz-2d.yaml")
    common = ("--quiet", "--set", "mesh.order=2", "--set", "mesh.parameters.refine=0.5",
              "--set", "solver.linear.solver=gmres-muelu")
    runs = {}
    for nullspace in ("rigid-body", "translations"):
        explain = c.run("check", scene, "--explain", *common[1:], "--set", "solver.linear.nullspace=" + nullspace)
        c.check(re.search(r"nullspace\s+%s:" % nullspace, explain.stdout) is not None,
                "check --explain prints nullspace %s" % nullspace)
        out = os.path.join(c.dir, nullspace)
        proc = c.run("run", scene, *common, "--out", out, "--set", "solver.linear.nullspace=" + nullspace)
        c.check(proc.returncode == 0, "%s: exit 0" % nullspace)
        runs[nullspace] = (read_history(out), read_summary(out))
    (rigid, rigid_summary), (translations, translations_summary) = runs["rigid-body"], runs["translations"]
    c.check(rigid_summary["krylov_iterations"] != translations_summary["krylov_iterations"],
            "the nullspace reaches MueLu: %d against %d GMRES iterations"
            % (rigid_summary["krylov_iterations"], translations_summary["krylov_iterations"]))
    key = "contact_force_y"
    scale = max(abs(float(r[key])) for r in rigid)
    worst = max(abs(float(x[key]) - float(y[key])) for x, y in zip(rigid, translations))
    # measured 2.6e-12: the two runs stop at different Newton iterates within the tolerance
    c.check(len(rigid) == len(translations) and worst <= 1e-10 * scale,
            "the same contact force: %.1e relative" % (worst / scale))


SWITCHED = re.compile(r"Newton iterations \((\d+) solves? switched to backtracking\)")


def backtrack_switch_count(c):
    wedge = os.path.join(ROOT, "tests", "scenes-from-reference", "wedge-slides-2d.yaml")
    base = ("--set", "output.vtu_every=0", "--out")
    # mortar-dual: c_t s outweighs the friction bound and the slip direction cycles under the full step (finding 28);
    # measured: 1 switch in 50 steps, 122 Newton iterations, no retry (0.15 s)
    c.run("run", wedge, "--plugin", "mortar-dual", "--verbose", *base, c.out)
    s = read_summary(c.out)
    said = c.proc.stderr.count("no progress under the full step: Newton went on with backtracking")
    switches = s.get("newton_backtrack_switches")
    c.check(s["status"] == "ok" and switches is not None and switches > 0 and switches == said,
            "mortar-dual: summary.json counts the switches --verbose reports (%s, %d reported)" % (switches, said))
    line = SWITCHED.search(c.proc.stdout)
    c.check(line is not None and int(line.group(1)) == switches,
            "mortar-dual: the last line gives the count (%s)" % (line.group(0) if line else c.proc.stdout[-300:]))
    # never with the explicit full step (no switch there), nor where the full step converges (penalty-nts)
    for label, args in (("full-step", ("--plugin", "mortar-dual", "--set", "solver.newton.line_search=full-step")),
                         ("penalty-nts", ("--plugin", "penalty-nts"))):
        out = os.path.join(c.dir, label)
        c.run("run", wedge, "--quiet", *args, *base, out)
        s = read_summary(out)
        c.check(s["status"] == "ok" and s.get("newton_backtrack_switches") == 0,
                "%s: no switch (%s)" % (label, s.get("newton_backtrack_switches")))
        c.check("switched to backtracking" not in c.proc.stdout and "Newton iterations, " in c.proc.stdout,
                "%s: the last line has no count (%s)" % (label, c.proc.stdout.strip()[-200:]))


CASES = {f.__name__: f for f in [roundoff_floor, iterative_fallback, iterative_equals_direct, muelu_nullspace,
                                 line_search_choice, backtrack_switch_count]}

if __name__ == "__main__":
    main(CASES)
