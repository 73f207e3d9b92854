"""Checkpoint and restart (docs/user-guide.md, "Checkpoints and restart"): a run stopped at a checkpoint and
continued with `--restart` equals the uninterrupted run — every history column to 1e-12 of its scale (column_scale)
on the same number of ranks, Newton iteration counts included; to 1e-10 on another — and contact.csv likewise (its
rows before the checkpoint carried over, the slip each point accumulated continued) — with a friction scene (nts-augmented on two hex8, deformable master, Coulomb
mu = 0.5: committed facets, tractions and multipliers; penalty-nts on a block pressed and dragged over a plane:
friction anchors) and a body-plugin scene (corotational, which runs on one rank: its rotation, co-rotated velocities
and contact sets). Direct solver KLU2 throughout (it factorises on rank 0): an iterative solver reproduces a run only
to its tolerance, and MUMPS on two ranks does not repeat itself to the last bit (two uninterrupted 2-rank runs of the
block differ by 1e-11 in the contact force and by 3 Newton iterations in step 30, measured 2026-11-28).
Also: a partial or damaged checkpoint and a changed scene are refused with the file named."""
import os
import shutil
import subprocess
import tempfile

from stickslip_results import ROOT, Results, main

BIN = os.environ.get("STICKSLIP_BIN", os.path.join(ROOT, "build", "bin", "stickslip"))
DIRECT = ["--set", "solver.linear.solver=klu2"]

TWO_ELEMENTS = ("scenes/two-elements.yaml", ["--set", "time.end=8"] + DIRECT, 40, 22)     # contact from step 15
BLOCK = ("scenes/block-on-plane.yaml", ["--set", "time.end=1.6"] + DIRECT, 32, 24)        # drag from step 21
BALL = ("scenes/corot-ball-on-plane-friction.yaml", [], 30, 17)                           # impact around step 12
# penalty-nts with friction anchors on 2 ranks: its master faces are ghosted again at step 6, contact from step 11
RING = ("scenes/ring-on-block.yaml", ["--set", "time.dt=0.05", "--set", "contact.0.parameters.mu=0.3"] + DIRECT, 20, 14)


def stickslip(args, np=1, expect_ok=True):
    command = [BIN, *args]
    if np > 1:
        command = [os.environ.get("STICKSLIP_MPIEXEC", "mpirun"), "--allow-run-as-root", "--oversubscribe", "-np",
                   str(np), *command]
    proc = subprocess.run(command, capture_output=True, text=True, cwd=ROOT)
    if expect_ok and proc.returncode != 0:
        raise AssertionError("failed (%d): %s\n%s" % (proc.returncode, " ".join(command), proc.stderr))
    return proc


def straight(case, np, folder):
    scene, args, steps, _ = case
    stickslip(["run", scene, "--out", os.path.join(folder, "straight"), "--quiet", "--steps", str(steps), *args], np)
    return Results(os.path.join(folder, "straight"))


def interrupted(case, np, folder):
    """The run stopped after the checkpoint step (a checkpoint every `at` steps); the checkpoint folder."""
    scene, args, _, at = case
    checkpoint = os.path.join(folder, "checkpoint")
    stickslip(["run", scene, "--out", os.path.join(folder, "first"), "--quiet", "--steps", str(at),
               "--checkpoint-every", str(at), "--checkpoint", checkpoint, *args], np)
    return checkpoint


def restarted(case, checkpoint, np, folder, name):
    _, _, steps, at = case
    out = os.path.join(folder, name)
    stickslip(["run", "--restart", checkpoint, "--out", out, "--quiet", "--steps", str(steps - at)], np)
    return Results(out)


def column_scale(a, name):
    """What a difference in a column is measured against: its largest |value|; for a vector's component (momentum_x,
    contact_force_y, ...) the largest |value| of the vector's three components (a component that is zero in the
    scene, e.g. momentum_x of the two hex8, holds round-off of 1e-14 that two rank counts do not share); for
    constraint_violation, a length, 1 (the scenes' bodies are of unit size; it holds round-off of 1e-16)."""
    if name == "constraint_violation":
        return 1.0
    names = [name[:-1] + c for c in "xyz"] if name[-2:] in ("_x", "_y", "_z") else [name]
    return max(max(max(abs(v) for v in a.column(n)) for n in names if n in a.rows[0]), 1e-300)


def worst_difference(a, b, with_iterations, scales=None):
    """The largest |a - b| over the rows of both, relative to each column's scale (column_scale; wall time left out,
    and the Newton iteration counts unless with_iterations: on another number of ranks the last bits of the state
    differ, and the block's step 30, where it reaches its stop, takes 9 to 13 iterations to the same converged
    state depending on them — two uninterrupted 2-rank MUMPS runs differ there by 3, measured 2026-11-28)."""
    worst, where = 0.0, None
    for name in a.rows[0]:
        if name == "wall_seconds" or (name == "newton_iterations" and not with_iterations):
            continue
        column_a, column_b = a.column(name), b.column(name)
        scale = (scales or {}).get(name) or column_scale(a, name)
        d = max(abs(x - y) for x, y in zip(column_a, column_b)) / scale
        if d > worst:
            worst, where = d, name
    return worst, where


def compare(checks, label, reference, result, tolerance, with_iterations=True, scales=None):
    checks.check(len(result.rows) == len(reference.rows),
                 "%s: %d history rows, like the uninterrupted run's %d" % (label, len(result.rows), len(reference.rows)))
    checks.check(result.rows[-1]["step"] == reference.rows[-1]["step"], "%s: ends at step %g (%g)" %
                 (label, result.rows[-1]["step"], reference.rows[-1]["step"]))
    worst, where = worst_difference(reference, result, with_iterations, scales)
    checks.check(worst <= tolerance, "%s: every history column equal to %.1e (largest difference %.2e, %s)" %
                 (label, tolerance, worst, where))
    checks.check("restarted_from" in result.summary, "%s: summary.json names the checkpoint" % label)
    # the first run also wrote the points of the step it stopped at (a run's last step is always output), which the
    # uninterrupted run did not: the steps both wrote are compared
    steps = set(r["step"] for r in reference.contact_table())
    worst, where = worst_contact_difference(reference.contact_table(),
                                            [r for r in result.contact_table() if r["step"] in steps])
    checks.check(worst <= tolerance, "%s: contact.csv equal to %.1e, its rows before the checkpoint carried over "
                 "(largest difference %.2e, %s)" % (label, tolerance, worst, where))


def worst_contact_difference(a, b):
    """The largest difference between two contact.csv tables, each column relative to its largest |value| in `a`
    (a missing quantity, NaN, must be missing in both; another number of rows is a difference of infinity)."""
    if len(a) != len(b):
        return float("inf"), "%d rows against %d" % (len(b), len(a))
    worst, where = 0.0, None
    for name in a[0] if a else []:
        scale = max([abs(r[name]) for r in a if r[name] == r[name]] + [1e-300])
        for x, y in zip((r[name] for r in a), (r[name] for r in b)):
            d = (0.0 if (x != x) == (y != y) else float("inf")) if x != x or y != y else abs(x - y) / scale
            if d > worst:
                worst, where = d, name
    return worst, where


def restart_friction_same_ranks(checks):
    for case in (TWO_ELEMENTS, BLOCK):
        for np in (1, 2):
            folder = tempfile.mkdtemp(prefix="stickslip-restart-")
            reference = straight(case, np, folder)
            checks.check(max(reference.column("active_points")) > 0, "%s: contact before and after the checkpoint"
                         % case[0])
            result = restarted(case, interrupted(case, np, folder), np, folder, "again")
            compare(checks, "%s, %d rank(s) -> %d" % (case[0], np, np), reference, result, 1e-12)
            shutil.rmtree(folder)


def restart_friction_other_ranks(checks):
    for case in (TWO_ELEMENTS, BLOCK):
        for written, read in ((2, 1), (1, 2)):
            folder = tempfile.mkdtemp(prefix="stickslip-restart-")
            reference = straight(case, read, folder)
            result = restarted(case, interrupted(case, written, folder), read, folder, "again")
            compare(checks, "%s, %d rank(s) -> %d" % (case[0], written, read), reference, result, 1e-10,
                    with_iterations=False)
            shutil.rmtree(folder)


def restart_reghosted(checks):
    """Master faces ghosted by swept boxes (the default) and ghosted again before the checkpoint: the restart holds
    the faces from the checkpoint's positions, not from the set-up's reference ones (where penalty-nts refused its
    friction anchors on faces the rank did not hold): written and read on 2 ranks (1e-12; measured: equal to the
    bit), written on 1 (1e-10; measured 2.0e-12, reaction_base_y). Labelled long (about 12 s CPU)."""
    for written, read, tolerance in ((2, 2, 1e-12), (1, 2, 1e-10)):
        folder = tempfile.mkdtemp(prefix="stickslip-restart-")
        reference = straight(RING, read, folder)
        checks.check(max(reference.column("active_points")) > 0 and reference.rows[13]["active_points"] > 0,
                     "ring-on-block: in contact at the checkpoint")
        result = restarted(RING, interrupted(RING, written, folder), read, folder, "again")
        # the ring's contact moment is zero by symmetry (round-off of 2e-4 against forces of 2374): measured against
        # the largest contact force times the ring's radius, 100 (1 vs 2 ranks uninterrupted differ by 1.8e-8 in it)
        lever = {"contact_moment_z": 100.0 * max(abs(v) for v in reference.column("contact_force_y"))}
        compare(checks, "ring-on-block, %d rank(s) -> %d" % (written, read), reference, result, tolerance,
                with_iterations=written == read, scales=lever)
        shutil.rmtree(folder)


def restart_body_plugin(checks):
    folder = tempfile.mkdtemp(prefix="stickslip-restart-")
    reference = straight(BALL, 1, folder)
    checks.check(max(reference.column("active_points")) > 0, "the ball is in contact after the checkpoint")
    result = restarted(BALL, interrupted(BALL, 1, folder), 1, folder, "again")
    compare(checks, "corotational ball, 1 rank", reference, result, 1e-12)
    shutil.rmtree(folder)


def restart_refusals(checks):
    folder = tempfile.mkdtemp(prefix="stickslip-restart-")
    scene, args, _, _ = BLOCK
    checkpoint = os.path.join(folder, "checkpoint")
    stickslip(["run", scene, "--quiet", "--steps", "3", "--checkpoint-every", "3", "--checkpoint", checkpoint, *args])
    step = os.path.join(checkpoint, "step-00000003")
    checks.check(os.path.exists(os.path.join(step, "state-0000.bin")), "the checkpoint's step folder is complete")
    # a truncated state file
    damaged = os.path.join(folder, "damaged")
    shutil.copytree(step, damaged)
    path = os.path.join(damaged, "state-0000.bin")
    with open(path, "rb+") as f:
        f.truncate(os.path.getsize(path) - 20)
    proc = stickslip(["run", "--restart", damaged, "--quiet"], expect_ok=False)
    checks.check(proc.returncode != 0 and "state-0000.bin" in proc.stderr and "truncated" in proc.stderr,
                 "a truncated state file is refused, named: " + proc.stderr.strip().splitlines()[-1])
    # a missing state file
    os.remove(path)
    proc = stickslip(["run", "--restart", damaged, "--quiet"], expect_ok=False)
    checks.check(proc.returncode != 0 and "state-0000.bin is missing" in proc.stderr,
                 "a missing state file is refused: " + proc.stderr.strip().splitlines()[-1])
    # a partial checkpoint (its writing interrupted): no `latest`, only a .partial folder
    partial = os.path.join(folder, "partial")
    os.makedirs(os.path.join(partial, ".partial-step-00000003-1234"))
    proc = stickslip(["run", "--restart", partial, "--quiet"], expect_ok=False)
    checks.check(proc.returncode != 0 and "no complete checkpoint" in proc.stderr,
                 "a partial checkpoint is refused: " + proc.stderr.strip().splitlines()[-1])
    # the scene changed since the checkpoint: the hash of its file differs from the recorded one
    proc = stickslip(["run", "--restart", checkpoint, "--steps", "1", "--quiet"])
    checks.check(proc.returncode == 0, "the unchanged scene restarts")
    with open(os.path.join(step, "checkpoint.yaml")) as f:
        description = f.read()
    with open(os.path.join(step, "checkpoint.yaml"), "w") as f:
        f.write(description.replace('scene_hash: "', 'scene_hash: "f'))
    proc = stickslip(["run", "--restart", checkpoint, "--quiet"], expect_ok=False)
    checks.check(proc.returncode != 0 and "changed since the checkpoint" in proc.stderr,
                 "a scene changed since the checkpoint is refused: " + proc.stderr.strip().splitlines()[-1])
    # --restart takes no scene; a checkpoint folder that is not stickslip's is refused
    proc = stickslip(["run", scene, "--restart", checkpoint], expect_ok=False)
    checks.check(proc.returncode != 0 and "give no SCENE" in proc.stderr, "--restart with a scene is refused")
    foreign = os.path.join(folder, "foreign")
    os.makedirs(foreign)
    open(os.path.join(foreign, "notes.txt"), "w").close()
    proc = stickslip(["run", scene, "--quiet", "--steps", "1", "--checkpoint-every", "1", "--checkpoint", foreign, *args],
                     expect_ok=False)
    checks.check(proc.returncode != 0 and "notes.txt" in proc.stderr and os.path.exists(os.path.join(foreign, "notes.txt")),
                 "a checkpoint folder holding someone's file is refused and the file kept")
    shutil.rmtree(folder)


if __name__ == "__main__":
    main([restart_reghosted, restart_friction_same_ranks, restart_friction_other_ranks, restart_body_plugin,
          restart_refusals])
