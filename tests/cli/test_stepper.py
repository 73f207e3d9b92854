"""The stepper as a user sees it (issues 15 and 16): cut steps come back onto the schedule, a step that cannot be
solved names what failed where. Usage: python3 test_stepper.py CASE."""
import json
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from test_bad_input import BLOCK, Case, replace  # noqa: E402


def read_csv(path):
    with open(path) as f:
        names = f.readline().strip().split(",")
        return [dict(zip(names, map(float, line.split(",")))) for line in f if line.strip()]


def schedule_after_cut(c):
    """Issue 16: the compressed block (neo-Hooke, 40 % compression) with Newton limited to 3 iterations cuts the
    steps of dt = 0.1 (each needs 4) into 8 sub-steps at first; every scheduled time n dt must still have its row,
    exactly at n dt (computed, not summed), with substep 0, the sub-steps numbered in between, and a VTU at every
    second scheduled time (vtu_every 2) — not at every second sub-step."""
    scene = replace(replace(BLOCK, "[0, 0, -10]", "[0, 0, -400]"), "model: hooke", "model: neo-hooke-ciarlet")
    c.run_scene(scene, "--set", "time.dt=0.1", "--set", "solver.newton.max_iterations=3", "--set",
                "output.vtu_every=2")
    c.check(c.proc.returncode == 0, "the run succeeds")
    summary = json.load(open(os.path.join(c.out, "summary.json")))
    rows = read_csv(os.path.join(c.out, "history.csv"))
    c.check(summary["step_cuts"] > 0, "steps were cut (%d cuts)" % summary["step_cuts"])
    on_schedule = [r["time"] for r in rows if r["substep"] == 0]
    c.check(on_schedule == [n * 0.1 for n in range(11)], "every scheduled time n dt has its row, exactly: %s"
            % on_schedule)
    c.check(len(rows) > 11, "there are sub-steps (%d rows)" % len(rows))
    expected, previous = 0, 0.0
    for r in rows[1:]:
        expected = 0 if r["substep"] == 0 else expected + 1
        c.check(r["substep"] == expected, "sub-steps are numbered 1, 2, ... since the last scheduled time (t = %r)"
                % r["time"])
        c.check(r["time"] > previous and (r["substep"] == 0 or round(r["time"] / 0.1, 9) % 1 != 0),
                "a sub-step lies strictly between scheduled times (t = %r)" % r["time"])
        previous = r["time"]
    pvd = open(os.path.join(c.out, "results.pvd")).read()
    times = [float(t) for t in re.findall(r'timestep="([^"]+)"', pvd)]
    c.check(times == [n * 0.1 for n in range(0, 11, 2)], "VTUs at every second scheduled time: %s" % times)


CASES = {f.__name__: f for f in [schedule_after_cut]}

if __name__ == "__main__":
    if len(sys.argv) != 2 or sys.argv[1] not in CASES:
        print("usage: test_stepper.py CASE\ncases: " + " ".join(CASES))
        sys.exit(2)
    case = Case(sys.argv[1])
    CASES[sys.argv[1]](case)
    sys.exit(case.finish())
