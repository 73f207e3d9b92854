"""What a run writes and says (issues 15 and 16): the columns of contact.csv and what they mean, cut steps back on
the schedule, a step that cannot be solved naming what failed where. Usage: python3 test_run_results.py CASE."""
import math
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "validation"))
from stickslip_results import read_vtu  # noqa: E402
from cli_case import BLOCK, CONTACT, ROOT, main, read_history, read_summary, read_table, replace  # noqa: E402


def schedule_after_cut(c):
    """Issue 16: the compressed block (neo-Hooke, 40 % compression) with Newton limited to 3 iterations cuts the
    steps of dt = 0.1 (each needs 4) into 8 sub-steps at first; every scheduled time n dt must still have its row,
    exactly at n dt (computed, not summed), with substep 0, the sub-steps numbered in between, and a VTU at every
    second scheduled time (vtu_every 2) — not at every second sub-step."""
    scene = replace(replace(BLOCK, "[0, 0, -10]", "[0, 0, -400]"), "model: hooke", "model: neo-hooke-ciarlet")
    c.run_scene(scene, "--set", "time.dt=0.1", "--set", "solver.newton.max_iterations=3", "--set",
                "output.vtu_every=2")
    c.check(c.proc.returncode == 0, "the run succeeds")
    summary = read_summary(c.out)
    rows = read_history(c.out)
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


def contact_points(c, scene, *args):
    c.run("run", os.path.join(ROOT, "scenes", scene), "--out", c.out, "--quiet", *args)
    c.check(c.proc.returncode == 0, "%s runs" % scene)
    points = read_table(os.path.join(c.out, "contact.csv"))
    c.check(len(points) > 0, "contact.csv has rows")
    last = max(p["step"] for p in points) if points else 0
    return [p for p in points if p["step"] == last]  # the last output step


def contact_columns(c):
    """Issue 16: contact.csv carries reference and current positions, gap, normal and tangential traction, state and
    the multiplier. Their meaning: for nodes, reference = the mesh position and current - reference = the node's
    displacement in the last VTU; a Gauss point (covariant STS) has its own reference position on the reference
    surface; the multiplier is there where the formulation has one (mortar: z_n, the pressure) and NaN otherwise."""
    points = contact_points(c, "block-on-plane.yaml", "--steps", "5", "--set", "output.vtu_every=5")
    displacement = read_vtu(os.path.join(c.out, "step-000005.pvtu"))["displacement"]
    for p in points:
        u = displacement[int(p["node"])]
        c.check(abs(p["reference_y"]) == 0 and 0 <= p["reference_x"] <= 1 and p["reference_z"] == 0,
                "penalty-nts node %d: the reference position lies on the block's base y = 0" % p["node"])
        c.check(abs(p["x"] - p["reference_x"] - u[0]) < 1e-15 and abs(p["y"] - p["reference_y"] - u[1]) < 1e-15,
                "node %d: current - reference = its displacement in the VTU" % p["node"])
        c.check(math.isnan(p["multiplier"]), "penalty has no multiplier: NaN")
        c.check(p["pressure"] > 0 and p["state"] == 1 and p["gap"] < 0, "pressed: pressure > 0, stick, penetrating")
    c.check(len({p["reference_x"] for p in points}) == 9, "the 9 base nodes, each once")
    points = contact_points(c, "mortar-patch-test-2d.yaml")
    for p in points:
        # pressure is per reference area (z_n A_current / A_reference); the patch test's interface widens by 0.39 %
        ratio = p["pressure"] / p["multiplier"] if p["multiplier"] > 0 else 0.0
        c.check(abs(ratio - 1.0039) < 1e-3, "mortar node %d: pressure = multiplier z_n x A/A0 (ratio %.6f)"
                % (p["node"], ratio))
        c.check(p["reference_y"] == 0 and p["y"] < 0, "mortar node %d: reference on the interface y = 0, current "
                "below it" % p["node"])
    points = contact_points(c, "ks-block-a.yaml", "--steps", "1")
    c.check(all(p["node"] == -1 for p in points), "covariant STS writes Gauss points")
    # the base is fixed: current = reference up to the round-off of the active points' own interpolation (4e-15)
    c.check(all(p["reference_y"] == 0 and abs(p["x"] - p["reference_x"]) < 1e-13 and abs(p["y"]) < 1e-13 and
                abs(p["z"] - p["reference_z"]) < 1e-13 for p in points),
            "covariant Gauss points: reference on the fixed base's top y = 0, equal to the current position")
    c.check(len({(p["reference_x"], p["reference_z"]) for p in points}) == len(points), "every Gauss point once")


def plugin_points_layouts(c):
    """docs/plugin-abi.md §8: the host completes a plugin's points the same way whatever the plugin knows. The block
    of the contact scene (base 1 x 1 in 2 x 2 quads: tributary areas 1/16, 1/8, 1/4) with the test plugin
    test-points: a point in the 2.4 layout (its struct ends before `forces`, whatever lies beyond) has pressure 2 as
    a traction, area = the node's tributary area, normal_force = 2 x area, no slip; a point with `forces` (0.5 normal,
    0.1 tangential) is divided by the tributary area. Either way the areas sum to the base's area and the normal
    forces to what the plugin reported."""
    for layout in ("24", "forces"):
        scene = replace(replace(CONTACT, "plugin: penalty-nts", "plugin: test-points"), "penalty: 1.0e4",
                        "layout: '%s'" % layout)
        c.run("run", c.write(scene), "--out", c.out, "--quiet", env=FAULT_ENV)
        c.check(c.proc.returncode == 0, "layout %s: the run succeeds (%s)" % (layout, c.proc.stderr.strip()))
        points = contact_table_last(c.out)
        areas = sorted(round(p["area"] * 16, 9) for p in points)  # gmsh places the nodes to ~1e-13
        c.check(areas == [1, 1, 1, 1, 2, 2, 2, 2, 4], "layout %s: the tributary areas x 16: %s" % (layout, areas))
        if layout == "24":
            c.check(all(p["pressure"] == 2 and abs(p["normal_force"] - 2 * p["area"]) < 1e-14 for p in points),
                    "2.4 layout: pressure 2 kept as a traction, normal_force = 2 x area (not the 99 beyond it)")
            c.check(all(math.isnan(p["slip"]) and p["face"] == -1 and math.isnan(p["multiplier"]) for p in points),
                    "2.4 layout: no slip, no face, no multiplier")
        else:
            c.check(all(abs(p["pressure"] - 0.5 / p["area"]) < 1e-12 and p["normal_force"] == 0.5 and
                        abs(p["traction_x"] - 0.1 / p["area"]) < 1e-12 for p in points),
                    "forces: pressure = 0.5 / area, traction_x = 0.1 / area, normal_force = 0.5")
        c.check(abs(sum(p["area"] for p in points) - 1) < 1e-14, "layout %s: the areas sum to the base's" % layout)


def contact_table_last(folder):
    points = read_table(os.path.join(folder, "contact.csv"))
    last = max(p["step"] for p in points)
    return [p for p in points if p["step"] == last]


def diverging_step(c):
    """Issue 15: a step that cannot be solved names the step, the time, the cuts and where the residual is largest
    (node, component, body); exit 1, the results up to the last converged step kept."""
    scene = replace(replace(BLOCK, "[0, 0, -10]", "[0, 0, -400]"), "model: hooke", "model: neo-hooke-ciarlet")
    c.run_scene(scene, "--set", "time.dt=0.1", "--set", "solver.newton.max_iterations=1", "--set", "time.max_cuts=2")
    c.expect_failure(r"step 1 from t = 0: no convergence after 2 step cuts \(dt = 0\.025\)",
                     r"largest residual at node \d+ \([xyz]\) of body 'block': F = ", r"results up to t = 0 \(step 0\) "
                     r"are in .*results \(status \"failed\"\)", out_created=True)


# the contact block of cli_case, its plugin replaced by the test plugin that misbehaves as `fault` says
FAULT_SCENE = replace(replace(CONTACT, "plugin: penalty-nts", "plugin: test-misbehaving"), "penalty: 1.0e4",
                      "fault: 1")
FAULT_ENV = {"STICKSLIP_PLUGIN_PATH": os.environ.get("STICKSLIP_CLI_FAULT_DIR", "")}


def misbehaving_plugin(c):
    """Issue 15, items 4, 11, 15: a plugin's NaN or negative report, a residual row beyond the unknowns, an error
    without a message and 2e9 extra unknowns each end the run with one message naming the pair and what is wrong
    (no step cut, no nan in history.csv, no crash, no OOM kill)."""
    env = FAULT_ENV
    expected = {1: r"report: force\[1\] = nan is not a number",
                2: r"report: negative point counts \(active -3, stick 0, slip 0\)",
                3: r"residual entry in row 88, beyond the 81 unknowns",
                4: r"plugin 'test-misbehaving' failed in residual\(\) with status 6 \(SK_ERR_INTERNAL\) and gave "
                   r"no message",
                5: r"2000000081 unknowns \(81 displacement dofs, 2000000000 extra unknowns of contact pair 'floor'\) "
                   r"need 225 GB for the work vectors alone, more than this machine's"}
    for fault, pattern in expected.items():
        out = os.path.join(c.dir, "out-%d" % fault)
        c.run("run", c.write(FAULT_SCENE), "--out", out, "--quiet", "--set", "contact.0.parameters.fault=%d" % fault,
              env=env)
        c.no_crash()
        c.check(c.proc.returncode == 1, "fault %d: exit 1" % fault)
        c.check(re.search(r"^stickslip: .*scene\.yaml: (contact pair 'floor': )?" + pattern, c.proc.stderr, re.M)
                is not None, "fault %d: one message naming the pair and the fault" % fault)
        c.check(c.proc.stderr.count("floor") == 1, "fault %d: said once" % fault)
        summary = read_summary(out)
        c.check(summary["status"] == "failed" and summary["step_cuts"] == 0, "fault %d: failed, not cut" % fault)
        history = open(os.path.join(out, "history.csv")).read()
        c.check("nan" not in history and "inf" not in history, "fault %d: no nan in history.csv" % fault)


def smallest_step(c):
    """A step that keeps failing after good sub-steps (test fault 6: every other attempt fails) must not halve dt on
    and on: dt stops at time.dt / 2^max_cuts and a failure there ends the run, with a message that says so. Before,
    cuts alternating with good sub-steps never counted max_cuts in a row and dt shrank towards zero."""
    # the full step named: fault 6 fails every other attempt, so the default's retry of a failed step (with
    # backtracking) would succeed and no step would be cut; this case is about the cuts
    c.run("run", c.write(FAULT_SCENE), "--out", c.out, "--quiet", "--set", "contact.0.parameters.fault=6",
          "--set", "time.max_cuts=4", "--set", "solver.newton.line_search=full-step", env=FAULT_ENV)
    c.expect_failure(r"no convergence at the smallest step time\.dt / 2\^4 \(dt = 0\.0312\): .*test fault 6",
                     out_created=True)
    rows = read_history(c.out)
    smallest = min(r["dt"] for r in rows[1:]) if len(rows) > 1 else 0.0
    c.check(len(rows) > 1 and smallest >= 0.5 / 16 * (1 - 1e-12), "no step shorter than dt / 2^4 (smallest %g)"
            % smallest)
    summary = read_summary(c.out)
    c.check(summary["step_cuts"] == 5, "4 halvings, each followed by a good sub-step, and the failure at dt / 2^4 "
            "(got %d)" % summary["step_cuts"])


def verbose_active_set(c):
    """Issue 36: with --verbose penalty-nts prints its active set at every new Newton point (the predictor, then each
    iterate; bench_newton_trace.py reads it): within a step the count follows from the last one and the nodes that
    entered and left, at a step's first point every node in contact counts as entered, a step prints one line more
    than it takes Newton iterations (full steps, no line-search trial points), and its last line's count is the step's
    active_points in history.csv. The 2D Hertz at refine 0.5: 4 steps, 15 Newton iterations, 2 to 3 nodes in
    contact (measured), about 0.3 s."""
    c.run("run", os.path.join(ROOT, "scenes", "hertz-2d.yaml"), "--out", c.out, "--verbose", "--set",
          "mesh.parameters.refine=0.5")
    c.check(c.proc.returncode == 0, "the run succeeds")
    active = re.compile(r"penalty-nts: active set: (\d+) slave nodes in contact, (\d+) entered, (\d+) left, "
                        r"(\d+) changed master face")
    newton = re.compile(r"^\s*step (\d+) newton (\d+) ")
    steps, pending = {}, []  # step -> its points' [in contact, entered, left, faces]; the iterations it printed
    iterations = {}
    for line in c.proc.stderr.splitlines():
        m = active.search(line)
        if m:
            pending.append([int(v) for v in m.groups()])
            continue
        m = newton.match(line)
        if m:  # the points printed since the last iteration line belong to this iteration's step
            step = int(m.group(1))
            steps.setdefault(step, []).extend(pending)
            pending = []
            iterations[step] = int(m.group(2))
    rows = read_history(c.out)[1:]
    c.check(len(rows) == 4 and sorted(steps) == [1, 2, 3, 4], "4 steps, each with its points (%d rows, steps %s)"
            % (len(rows), sorted(steps)))
    for r in rows:
        points = steps.get(int(r["step"]), [])
        c.check(len(points) == r["newton_iterations"] + 1 == iterations.get(int(r["step"]), -1) + 1,
                "step %d: one point per Newton iteration and the predictor (%d points, %d iterations)"
                % (r["step"], len(points), r["newton_iterations"]))
        if not points:
            continue
        c.check(points[0][0] == points[0][1] and points[0][2] == 0,
                "step %d: at the first point every node in contact counts as entered (%s)" % (r["step"], points[0]))
        c.check(all(b[0] == a[0] + b[1] - b[2] for a, b in zip(points, points[1:])),
                "step %d: in contact = before + entered - left at every point (%s)" % (r["step"], points))
        c.check(points[-1][0] == r["active_points"] > 0, "step %d: the last point's %d nodes in contact are "
                "history.csv's active_points (%d)" % (r["step"], points[-1][0], r["active_points"]))


# the contact block (1 x 1 x 1, 2 x 2 x 2 hex8, neo-Hooke: slave faces of mean edge H = 0.5) crushed to 20 % of its
# height against the floor with the default penalty 10 E*/h: the floor takes pressures above E*; measured penetration
# 0.061 (12 % of H) at step 3 (t = 0.75, 5 % at step 2), 0.13 (26 %) at t = 1
DEEP = replace(replace(replace(CONTACT, "parameters: {penalty: 1.0e4}", "parameters: {}"), "[0, 0, -0.01]",
                       "[0, 0, -0.8], history: [[0, 0], [1, 1]]"), "model: hooke", "model: neo-hooke-bonet")
DEEP_H = 0.5
WARNING = re.compile(r"warning: contact pair 'floor' \(plugin penalty-nts\): at step (\d+) \(t = [\d.]+\) the "
                     r"slave surface 'zmin' penetrates [\d.]+, (\d+) % of its faces' mean edge 0\.5 \(more than "
                     r"10 %\).*Raise the pair's penalty.*nts-augmented, mortar-dual")


def deep_penetration(c):
    """A penalty pair penetrating more than 10 % of its slave faces' mean edge is warned about once (stderr, naming the
    pair, the step and what to do) and recorded in summary.json; a stiff enough penalty or a multiplier plugin is
    not."""
    c.run_scene(DEEP, "--set", "time.dt=0.25")
    c.no_crash()
    summary = read_summary(c.out)
    rows = read_history(c.out)
    deepest = max(r["constraint_violation"] for r in rows)
    warnings = WARNING.findall(c.proc.stderr)
    print("stderr: %s\nconstraint_violation max %g, summary %s / %s" % (
        c.proc.stderr.strip(), deepest, summary.get("penetration_ratio_max"), summary.get("penetration_warning")))
    c.check(c.proc.returncode == 0 and len(warnings) == 1, "one warning, the run goes on (exit %d, %d warnings)" %
            (c.proc.returncode, len(warnings)))
    if warnings:
        step = int(warnings[0][0])
        first = [r for r in rows if r["constraint_violation"] > 0.1 * DEEP_H]
        c.check(first and first[0]["step"] == step, "the warning names the first step above 10 %% (%d)" % step)
    c.check(abs(summary.get("penetration_ratio_max", 0) - deepest / DEEP_H) <= 1e-12 * deepest / DEEP_H and
            deepest / DEEP_H > 0.1, "summary.json: the largest penetration / h is history.csv's (%g)" %
            (deepest / DEEP_H))
    c.check(str(summary.get("penetration_warning", "")).startswith("contact pair 'floor': penetration "),
            "summary.json names the pair (%s)" % summary.get("penetration_warning"))
    # 100 times the default penalty keeps the penetration at a few % of h; nts-augmented has no penalty at all
    for label, extra in (("stiff penalty", ("--set", "contact.0.parameters.penalty=2.2e6")),
                         ("nts-augmented", ("--plugin", "nts-augmented"))):
        c.run_scene(DEEP, "--set", "time.dt=0.25", *extra)
        summary = read_summary(c.out)
        c.check(c.proc.returncode == 0 and "penetrates" not in c.proc.stderr and
                summary.get("penetration_warning") == "none" and summary.get("penetration_ratio_max", 1) < 0.1,
                "%s: no warning (exit %d, ratio %s)" % (label, c.proc.returncode, summary.get("penetration_ratio_max")))


CASES = {f.__name__: f for f in [contact_columns, schedule_after_cut, diverging_step, misbehaving_plugin,
                                 smallest_step, plugin_points_layouts, verbose_active_set, deep_penetration]}

if __name__ == "__main__":
    main(CASES)
