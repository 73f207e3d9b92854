#!/usr/bin/env python3
"""Each skip of issue 14, on and forced off (the test switch STICKSLIP_NO_SKIP=<need>, docs/performance.md).

  skip.py check CASE     (ctest skip_CASE) the same scene with the skip on and off: `run --explain` says which, and
                         every history.csv column agrees to round-off (scaled difference <= TOLERANCE).
                         friction_*: mu = 0 against mu = 1e-300 (the plugins' friction path forced on), FRICTION below.
  skip.py bench [-n N] [CASE...]  the same pairs on larger scenes (all, or the CASEs), N repeats each: the minimum
                         CPU time of the stickslip process
                         (and its children) and the assembly seconds of summary.json; prints the markdown table of
                         docs/performance.md.

Environment: STICKSLIP_BIN (default build/bin/stickslip), SCENES (default the tree's scenes/).
"""
import csv
import json
import os
import resource
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", "..", ".."))
BIN = os.environ.get("STICKSLIP_BIN", os.path.join(ROOT, "build", "bin", "stickslip"))
SCENES = os.environ.get("SCENES", os.path.join(ROOT, "scenes"))

# Differences between skip on and off, each column scaled by the largest value of its kind (energies, forces,
# momenta), measured: see docs/performance.md (largest 1.4e-11). The assertion sits two decades above.
TOLERANCE = 1e-9

HOOKE_BLOCKS = ["--set", "bodies.0.material.model=hooke", "--set", "bodies.1.material.model=hooke"]

# case: (need, scene, extra arguments, the explain line's name)
CASES = {
    "mass": ("mass", "hertz-2d.yaml", []),
    "stiffness_quasistatic": ("stiffness-update", "hertz-2d.yaml", []),
    "stiffness_midpoint": ("stiffness-update", "two-elements-penalty.yaml", HOOKE_BLOCKS),
    # the ring has no candidate face for steps 1-31, touches the block from step 32 (--verbose says both)
    "idle_calls": ("idle-calls", "ring-on-block.yaml", ["--steps", "40", "--verbose"]),
    # the linear solver's set-up (core/solver): forced, every solve sets up as on a new pattern; direct: bitwise
    "symbolic_setup": ("symbolic-setup", "ring-on-block.yaml", ["--steps", "40"]),
    # multiplier plugins (ABI 2.3): the host writes the inactive multipliers' trivial rows itself; nts-augmented has
    # no candidate in steps 1-31, mortar-dual (swept face boxes) in steps 1-20
    "idle_calls_nts_augmented": ("idle-calls", "ring-on-block.yaml",
                                 ["--plugin", "nts-augmented", "--replace", "contact.0.parameters={mu: 0}", "--steps", "40",
                                  "--verbose"]),
    "idle_calls_mortar_dual": ("idle-calls", "ring-on-block.yaml",
                               ["--plugin", "mortar-dual", "--replace", "contact.0.parameters={}", "--verbose"]),
}

# The scene's length scale where the skip changes the linear system (not only skips zeros): mortar-dual's idle rows
# are z = 0 from the host instead of its rotated C = (n.z, t.z) with the D block, so the solver's round-off differs,
# and columns that vanish by symmetry (the ring's contact moment, 6e-5 of force x radius 2.3e5; the constraint
# violation, 2e-15) are round-off themselves. They are measured against force x size and size.
SCENE_SIZE = {"idle_calls_mortar_dual": 100.0}

# The friction skip is the plugins' own branch on mu > 0 (docs/plugin-abi.md, FRICTION), so it has no host switch:
# mu = 1e-300 forces the friction path (anchors, slip history, the tangential trial and return map, tangential
# stiffness) where mu = 0 skips it, and the Coulomb cone is then 1e-300 p_n wide, so the mechanics must agree to
# round-off. Expected to differ: the friction output and, at a new contact, Newton's path (a point starts sticking:
# one more or fewer iteration). The ring touches the block from step 32 (penalty-nts, nts-augmented) or 21 (mortar).
# case: (plugin, parameters with mu = 0, the same with mu = 1e-300)
FRICTION = {
    "friction_penalty_nts": ("penalty-nts", "{penalty: 1.0e5, penalty_tangential: 1.0e5, mu: 0, area_weighted: 1}",
                             "{penalty: 1.0e5, penalty_tangential: 1.0e5, mu: 1.0e-300, area_weighted: 1}"),
    "friction_nts_augmented": ("nts-augmented", "{mu: 0}", "{mu: 1.0e-300, epsilon_t: 1.0e+4}"),
    "friction_mortar_dual": ("mortar-dual", "{mu: 0}", "{mu: 1.0e-300}"),
}
FRICTION_OUTPUT = ("newton_iterations", "stick_points", "slip_points", "dissipated_energy")

# what --verbose must print when the skip is taken (a static "skipped" in --explain does not prove it happened)
TAKEN = {"idle-calls": "no candidate: active-set, residual and Jacobian calls skipped"}

# bench: larger variants of the same scenes
BENCH = {
    "mass": ("mass", "hertz-3d.yaml", ["--set", "mesh.parameters.refine=2"], "check"),
    "stiffness_quasistatic": ("stiffness-update", "hertz-3d.yaml", ["--set", "mesh.parameters.refine=2"], "run"),
    "stiffness_midpoint": ("stiffness-update", "two-elements-penalty.yaml", HOOKE_BLOCKS, "run"),
    "idle_calls": ("idle-calls", "ring-on-block.yaml", [], "run"),
    "idle_calls_mortar_dual": ("idle-calls", "ring-on-block.yaml",
                               ["--plugin", "mortar-dual", "--replace", "contact.0.parameters={}"], "run"),
    "symbolic_setup": ("symbolic-setup", "hertz-3d.yaml", ["--set", "mesh.parameters.refine=2"], "run"),
    "symbolic_setup_muelu": ("symbolic-setup", "hertz-3d.yaml",
                             ["--set", "mesh.parameters.refine=2", "--set", "solver.linear.solver=gmres-muelu"], "run"),
}


def run(command, scene, args, out, forced):
    env = dict(os.environ)
    env["STICKSLIP_NO_SKIP"] = forced
    cmd = [BIN, command, os.path.join(SCENES, scene), "--explain"] + args
    if command == "run":
        cmd += ["--quiet", "--out", out]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    proc = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=600)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode != 0:
        sys.exit(f"{' '.join(cmd)} (STICKSLIP_NO_SKIP={forced}) failed:\n{proc.stdout}{proc.stderr}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return proc.stdout + proc.stderr, cpu


def explain_line(stdout, need):
    for line in stdout.splitlines():
        words = line.split()
        if len(words) >= 2 and words[0] == need and words[1] in ("computed", "skipped:"):
            return line.strip()
    sys.exit(f"--explain printed no summary line for '{need}':\n{stdout}")


def history(out):
    with open(os.path.join(out, "history.csv")) as f:
        rows = list(csv.reader(f))
    return rows[0], [[float(v) for v in row] for row in rows[1:]]


def compare(out_on, out_off, size=0.0, ignore=()):
    head, on = history(out_on)
    head_off, off = history(out_off)
    if head != head_off or len(on) != len(off):
        sys.exit(f"different histories: {len(on)} vs {len(off)} rows")
    # each column against the largest value of its kind (a strain energy of 1e-33 in a rigid motion is measured
    # against the kinetic energy, not against itself)
    def kind(name):
        for word in ("energy", "angular_momentum", "momentum", "force", "reaction", "moment", "points"):
            if word in name:
                return word
        return name

    scales = {}
    for k, name in enumerate(head):
        largest = max(max(abs(r[k]) for r in on), max(abs(r[k]) for r in off))
        scales[kind(name)] = max(scales.get(kind(name), 0.0), largest)
    if size > 0.0:
        forces = max(scales.get("force", 0.0), scales.get("reaction", 0.0))
        scales["moment"] = max(scales.get("moment", 0.0), forces * size)
        scales["constraint_violation"] = max(scales.get("constraint_violation", 0.0), size)
    worst, where = 0.0, ""
    for k, name in enumerate(head):
        scale = scales[kind(name)]
        if name == "wall_seconds" or name in ignore or scale == 0.0:
            continue
        for r_on, r_off in zip(on, off):
            d = abs(r_on[k] - r_off[k]) / scale
            if d > worst:
                worst, where = d, f"{name} at t = {r_on[0]:g}"
    return worst, where, len(on) - 1


def check(case):
    need, scene, args = CASES[case]
    with tempfile.TemporaryDirectory() as tmp:
        on_out, off_out = os.path.join(tmp, "on"), os.path.join(tmp, "off")
        text_on, _ = run("run", scene, args, on_out, "")
        text_off, _ = run("run", scene, args, off_out, need)
        line_on, line_off = explain_line(text_on, need), explain_line(text_off, need)
        if "skipped" not in line_on:
            sys.exit(f"{scene}: the skip of '{need}' is not taken: {line_on}")
        if "STICKSLIP_NO_SKIP" not in line_off:
            sys.exit(f"{scene}: STICKSLIP_NO_SKIP={need} did not force it: {line_off}")
        if need in TAKEN and TAKEN[need] not in text_on:
            sys.exit(f"{scene}: the skip of '{need}' was not taken (--verbose did not say '{TAKEN[need]}')")
        if need in TAKEN and TAKEN[need] in text_off:
            sys.exit(f"{scene}: the skip of '{need}' was taken although STICKSLIP_NO_SKIP={need}")
        worst, where, steps = compare(on_out, off_out, SCENE_SIZE.get(case, 0.0))
    print(f"{case}: {scene} {' '.join(args)}: {steps} steps, skip on vs off: max scaled difference "
          f"{worst:.2e} ({where or 'all equal'})")
    if worst > TOLERANCE:
        sys.exit(f"FAIL: {worst:.2e} > {TOLERANCE:g}")


def friction(case):
    plugin, frictionless, forced = FRICTION[case]
    args = ["--plugin", plugin, "--steps", "50"]
    with tempfile.TemporaryDirectory() as tmp:
        on_out, off_out = os.path.join(tmp, "on"), os.path.join(tmp, "off")
        text_on, _ = run("run", "ring-on-block.yaml", args + ["--replace", f"contact.0.parameters={frictionless}"], on_out,
                         "")
        text_off, _ = run("run", "ring-on-block.yaml", args + ["--replace", f"contact.0.parameters={forced}"], off_out, "")
        line_on, line_off = explain_line(text_on, "friction"), explain_line(text_off, "friction")
        if "skipped" not in line_on or "computed" not in line_off:
            sys.exit(f"--explain does not say friction is skipped at mu = 0 and computed at mu = 1e-300: "
                     f"{line_on} / {line_off}")
        head, rows = history(off_out)
        if max(r[head.index("stick_points")] + r[head.index("slip_points")] for r in rows) == 0 and \
                max(r[head.index("dissipated_energy")] for r in rows) == 0.0:
            sys.exit(f"{plugin}: mu = 1e-300 reported no stick, no slip and no dissipation: the friction path did "
                     f"not run")
        worst, where, steps = compare(on_out, off_out, 100.0, FRICTION_OUTPUT)
    print(f"{case}: ring-on-block.yaml, {plugin}, {steps} steps, mu = 0 (skipped) vs 1e-300 (friction path): max "
          f"scaled difference {worst:.2e} ({where or 'all equal'})")
    if worst > TOLERANCE:
        sys.exit(f"FAIL: {worst:.2e} > {TOLERANCE:g}")


def mesh_cache():
    """The mesh cache (STICKSLIP_MESH_CACHE): off vs cold vs warm give the same results; a warm run reads the entry
    (its file is not replaced); another parameter is another entry; a damaged entry is replaced; two runs racing on
    an empty cache both succeed and leave one whole entry and no temporary file."""
    scene, args = "hertz-2d.yaml", ["--steps", "2"]
    with tempfile.TemporaryDirectory() as tmp:
        folder = os.path.join(tmp, "cache")

        said = {}

        def go(name, cache, extra=()):
            os.environ["STICKSLIP_MESH_CACHE"] = cache
            out = os.path.join(tmp, name)
            said[name] = run("run", scene, args + list(extra), out, "")[0]
            return out

        def explains(name, words):
            lines = [line for line in said[name].splitlines() if "hertz-2d.geo:" in line]
            if len(lines) != 1 or words not in lines[0]:
                sys.exit(f"--explain of the {name} run does not say '{words}' about the mesh cache: {lines}")

        def entries():
            return sorted(f for f in os.listdir(folder)) if os.path.isdir(folder) else []

        reference = go("off", "off")
        if entries():
            sys.exit("STICKSLIP_MESH_CACHE=off wrote to the cache")
        cold = go("cold", folder)
        if len(entries()) != 1:
            sys.exit(f"a cold run left {entries()} in the cache")
        entry = os.path.join(folder, entries()[0])
        inode = os.stat(entry).st_ino
        warm = go("warm", folder)
        if os.stat(entry).st_ino != inode:
            sys.exit("the warm run regenerated the mesh instead of reading the cache")
        explains("off", "not cached (STICKSLIP_MESH_CACHE=off)")
        explains("cold", "miss: meshed by gmsh")
        explains("warm", "hit: read from the cache")
        key = entries()[0][:-len(".mesh")]
        if f"key {key}" not in said["warm"] or f"entry {entry}" not in said["warm"]:
            sys.exit(f"--explain of the warm run does not name the key {key} and the entry {entry}")
        for out in (cold, warm):
            worst, where, _ = compare(reference, out)
            if worst != 0.0:
                sys.exit(f"a mesh from the cache changed the results: {worst:.2e} ({where})")
        go("other", folder, ["--set", "mesh.parameters.h_far=0.25"])
        if len(entries()) != 2:
            sys.exit(f"another parameter did not make another entry: {entries()}")
        size = os.path.getsize(entry)
        with open(entry, "r+b") as f:
            f.truncate(size // 2)
        damaged = go("damaged", folder)
        explains("damaged", "miss: meshed by gmsh")
        if os.path.getsize(entry) != size or compare(reference, damaged)[0] != 0.0:
            sys.exit("a damaged entry was not replaced by a good one")
        for name in entries():
            os.unlink(os.path.join(folder, name))
        env = dict(os.environ, STICKSLIP_MESH_CACHE=folder)
        procs = [subprocess.Popen([BIN, "check", os.path.join(SCENES, scene)], env=env, stdout=subprocess.DEVNULL,
                                  stderr=subprocess.PIPE, text=True) for _ in range(2)]
        for proc in procs:
            _, err = proc.communicate(timeout=300)
            if proc.returncode != 0:
                sys.exit(f"a concurrent run failed: {err}")
        if len(entries()) != 1 or not entries()[0].endswith(".mesh"):
            sys.exit(f"two concurrent runs left {entries()}")
    print("mesh_cache: off, cold, warm and repaired runs agree exactly; warm runs read the entry; concurrent runs "
          "leave one entry")


def bench(repeats, only):
    print("| skip | scene | command | CPU s, skip off | CPU s, skip on | assembly s off → on | max difference |")
    print("|---|---|---|---|---|---|---|")
    for case, (need, scene, args, command) in BENCH.items():
        if only and case not in only:
            continue
        cpu = {"off": [], "on": []}
        assembly = {"off": [], "on": []}
        with tempfile.TemporaryDirectory() as tmp:
            for _ in range(repeats):
                for mode, forced in (("off", need), ("on", "")):
                    out = os.path.join(tmp, mode)
                    _, seconds = run(command, scene, args, out, forced)
                    cpu[mode].append(seconds)
                    if command == "run":
                        with open(os.path.join(out, "summary.json")) as f:
                            assembly[mode].append(json.load(f)["assembly_seconds"])
            diff = (f"{compare(os.path.join(tmp, 'on'), os.path.join(tmp, 'off'), SCENE_SIZE.get(case, 0.0))[0]:.1e}"
                    if command == "run" else "—")
        asm = f"{min(assembly['off']):.2f} → {min(assembly['on']):.2f}" if command == "run" else "—"
        print(f"| {need} | {scene} {' '.join(a for a in args if a != '--set')} | {command} | {min(cpu['off']):.2f} | "
              f"{min(cpu['on']):.2f} | {asm} | {diff} |")
    if only and "mesh_cache" not in only:
        return
    # the mesh cache: off (gmsh every time) against a warm cache, `check` (set-up only), CPU with gmsh's child
    scene, args = "hertz-3d.yaml", ["--set", "mesh.parameters.refine=2"]
    cpu = {"off": [], "on": []}
    with tempfile.TemporaryDirectory() as tmp:
        saved = os.environ.get("STICKSLIP_MESH_CACHE")
        for mode, cache in (("on", os.path.join(tmp, "cache")), ("off", "off"), ("on", os.path.join(tmp, "cache"))):
            os.environ["STICKSLIP_MESH_CACHE"] = cache
            for _ in range(repeats):
                cpu[mode].append(run("check", scene, args, tmp, "")[1])
        if saved is None:
            del os.environ["STICKSLIP_MESH_CACHE"]
        else:
            os.environ["STICKSLIP_MESH_CACHE"] = saved
    cpu["on"] = cpu["on"][repeats:]  # the first pass filled the cache
    print(f"| mesh cache | {scene} mesh.parameters.refine=2 | check | {min(cpu['off']):.2f} | {min(cpu['on']):.2f} | "
          f"— | identical (skip_mesh_cache) |")


def invariants():
    """--quiet without --out: nobody reads the energies and momenta, so they are not computed (--explain says so);
    the run takes the same steps and Newton iterations as with them forced (STICKSLIP_NO_SKIP=invariants), and with
    --out (where history.csv needs them) they are computed."""
    scene = os.path.join(SCENES, "two-elements-penalty.yaml")
    said = {}
    for mode, forced in (("on", ""), ("off", "invariants")):
        env = dict(os.environ, STICKSLIP_NO_SKIP=forced)
        proc = subprocess.run([BIN, "run", scene, "--quiet", "--explain"], env=env, capture_output=True, text=True,
                              timeout=300)
        if proc.returncode != 0:
            sys.exit(f"run failed ({mode}):\n{proc.stdout}{proc.stderr}")
        said[mode] = proc.stdout
    if "invariants       skipped" not in said["on"] or "invariants       skipped" in said["off"]:
        sys.exit(f"--explain does not say the invariants are skipped (only) when not forced:\n{said['on']}")
    def solve(text):  # "N steps to t = T, I Newton iterations, L linear solves" without the timings
        return [line.split(" s (")[0].rsplit(",", 1)[0] for line in text.splitlines() if "Newton iterations" in line]
    if not solve(said["on"]) or solve(said["on"]) != solve(said["off"]):
        sys.exit(f"the run differs with the invariants skipped: {solve(said['on'])} vs {solve(said['off'])}")
    with tempfile.TemporaryDirectory() as tmp:
        text, _ = run("run", "two-elements-penalty.yaml", [], os.path.join(tmp, "out"), "")
        if "invariants       skipped" in text:
            sys.exit("with --out the invariants are skipped")
        head, rows = history(os.path.join(tmp, "out"))
        if max(abs(r[head.index("total_energy")]) for r in rows) == 0.0:
            sys.exit("with --out history.csv has no energies")
    print(f"invariants: skipped without an audience, same solve ({solve(said['on'])[0]}); computed with --out")


def main():
    if len(sys.argv) >= 3 and sys.argv[1] == "check" and sys.argv[2] in CASES:
        check(sys.argv[2])
    elif len(sys.argv) >= 3 and sys.argv[1] == "check" and sys.argv[2] in FRICTION:
        friction(sys.argv[2])
    elif len(sys.argv) >= 3 and sys.argv[1] == "check" and sys.argv[2] == "mesh_cache":
        mesh_cache()
    elif len(sys.argv) >= 3 and sys.argv[1] == "check" and sys.argv[2] == "invariants":
        invariants()
    elif len(sys.argv) >= 2 and sys.argv[1] == "bench":
        with_n = len(sys.argv) >= 4 and sys.argv[2] == "-n"
        repeats = int(sys.argv[3]) if with_n else 3
        bench(repeats, sys.argv[4 if with_n else 2:])
    else:
        sys.exit(f"usage: skip.py check {{{','.join(list(CASES) + list(FRICTION))},mesh_cache,invariants}} | "
                 "skip.py bench [-n N] [CASE...]")


if __name__ == "__main__":
    main()
