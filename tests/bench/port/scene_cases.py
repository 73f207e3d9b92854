#!/usr/bin/env python3
"""Runs every bundled scene (and the strategy, scheme, friction and MPI variants the validation tests use) with one
stickslip binary, or compares two such result folders: the before/after check of a refactoring that must not change
results (the ABI v2 port, issue 7).

  scene_cases.py run BIN OUTDIR [CASE...]     run the cases (all when none named) into OUTDIR/<case>/
  scene_cases.py compare OLD NEW              per case: the largest difference of every history.csv and contact.csv
                                              column (wall_seconds excluded), absolute and relative to the column's
                                              largest magnitude; exit 1 if a case is missing or a row count differs

Environment: STICKSLIP_MPIEXEC (default mpiexec) for the 2-rank cases."""
import csv
import os
import subprocess
import sys
import time

# name: (scene, extra arguments, ranks). Long scenes are cut with --steps; the validation tests run the same ones.
CASES = {
    "block_on_plane": ("scenes/block-on-plane.yaml", [], 1),
    "cantilever_2d": ("scenes/cantilever-2d.yaml", [], 1),
    "compressed_block": ("scenes/compressed-block.yaml", [], 1),
    "free_flight_blocks": ("scenes/free-flight-blocks.yaml", [], 1),
    "free_flight_blocks_be": ("scenes/free-flight-blocks.yaml", ["--set", "time.scheme=backward-euler"], 1),
    "free_flight_disk": ("scenes/free-flight-disk.yaml", [], 1),
    "free_flight_torus": ("scenes/free-flight-torus.yaml", ["--steps", "20"], 1),
    "free_flight_torus_np2": ("scenes/free-flight-torus.yaml",
                              ["--set", "mesh.parameters.refine=0.25", "--steps", "5"], 2),
    "hertz_2d": ("scenes/hertz-2d.yaml", [], 1),
    "hertz_2d_np2": ("scenes/hertz-2d.yaml", [], 2),
    "hertz_3d": ("scenes/hertz-3d.yaml", [], 1),
    "patch_test_2d": ("scenes/patch-test-2d.yaml", [], 1),
    "patch_test_2d_refine3": ("scenes/patch-test-2d.yaml", ["--set", "mesh.parameters.refine=3"], 1),
    "two_elements_penalty": ("scenes/two-elements-penalty.yaml", [], 1),
    "two_elements_penalty_mu": ("scenes/two-elements-penalty.yaml",
                                ["--set", "contact.0.parameters.mu=0.3",
                                 "--set", "contact.0.parameters.penalty_tangential=1000"], 1),
    "two_elements": ("scenes/two-elements.yaml", [], 1),
    "two_elements_none": ("scenes/two-elements.yaml", ["--set", "contact.0.strategy=none"], 1),
    "two_elements_direct": ("scenes/two-elements.yaml",
                            ["--set", "contact.0.strategy=direct", "--set", "time.dt=0.005",
                             "--set", "time.end=3.5"], 1),
    "two_elements_be": ("scenes/two-elements.yaml", ["--set", "time.scheme=backward-euler"], 1),
    "two_tori_coarse": ("scenes/two-tori-coarse.yaml", [], 1),
    "two_tori_coarse_np2": ("scenes/two-tori-coarse.yaml", ["--steps", "30"], 2),
    "two_tori_mu03": ("scenes/two-tori-mu03.yaml", ["--steps", "8"], 1),
    "two_tori": ("scenes/two-tori.yaml", ["--steps", "8"], 1),
}


def run(binary, outdir, names):
    for name in names:
        scene, args, ranks = CASES[name]
        target = os.path.join(outdir, name)
        cmd = [binary, "run", scene, "--out", target] + args
        if ranks > 1:
            cmd = [os.environ.get("STICKSLIP_MPIEXEC", "mpiexec"), "--allow-run-as-root", "--oversubscribe", "-np",
                   str(ranks)] + cmd
        start = time.time()
        proc = subprocess.run(cmd, capture_output=True, text=True)
        print("%-26s %6.1f s  exit %d  %s" % (name, time.time() - start, proc.returncode, " ".join(cmd)), flush=True)
        if proc.returncode != 0:
            print(proc.stderr[-2000:])


def read(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    return rows[0], [[float(v) for v in r] for r in rows[1:]]


def group_of(name):
    """Columns of one vector share a scale: momentum_x/_y/_z, contact_force_*, reaction_<bc>_*, normal_*, ..."""
    for suffix in ("_x", "_y", "_z"):
        if name.endswith(suffix):
            return name[: -len(suffix)]
    return {"x": "position", "y": "position", "z": "position"}.get(name, name)


def compare_file(old, new):
    """The largest absolute difference over the columns both files have (wall_seconds aside), and relative to the
    largest magnitude of the column's vector (momentum_y against the whole momentum, so that a component that is
    zero up to round-off does not count as a relative change of 1). A column the old file has and the new one lacks
    is a failure."""
    names, a = read(old)
    names_b, b = read(new)
    missing = [n for n in names if n not in names_b]
    if missing:
        return None, "columns missing: %s" % missing
    if len(a) != len(b):
        return None, "%d rows vs %d" % (len(a), len(b))
    scales = {}
    for j, name in enumerate(names):
        m = max([abs(r[j]) for r in a if r[j] == r[j]] + [0.0])
        scales[group_of(name)] = max(scales.get(group_of(name), 1e-300), m)
    worst_abs, worst_rel, where = 0.0, 0.0, ""
    for j, name in enumerate(names):
        # constraint_violation is the solver's residual of the constraints (noise at the Newton tolerance): it enters
        # the absolute maximum only
        if name in ("wall_seconds",):
            continue
        jb = names_b.index(name)
        scale = scales[group_of(name)] if name != "constraint_violation" else float("inf")
        for ra, rb in zip(a, b):
            d = 0.0 if ra[j] != ra[j] and rb[jb] != rb[jb] else abs(ra[j] - rb[jb])  # NaN on both sides: equal
            worst_abs = max(worst_abs, d)
            if d != d or d / scale > worst_rel:  # a NaN on one side only counts as a difference
                worst_rel, where = d / scale, name
    return (worst_abs, worst_rel, where, len(a)), ""


def compare(old, new):
    failed = False
    for name in CASES:
        line = "%-26s" % name
        for file in ("history.csv", "contact.csv"):
            a, b = os.path.join(old, name, file), os.path.join(new, name, file)
            if not os.path.exists(a) and not os.path.exists(b):
                continue
            if not (os.path.exists(a) and os.path.exists(b)):
                line += "  %s: missing" % file
                failed = True
                continue
            result, why = compare_file(a, b)
            if result is None:
                line += "  %s: %s" % (file, why)
                failed = True
            else:
                line += "  %s: %d rows, max |d| %.2e, rel %.2e (%s)" % ((file,) + (result[3], result[0], result[1],
                                                                                   result[2] or "-"))
        print(line)
    return 1 if failed else 0


if __name__ == "__main__":
    if len(sys.argv) >= 4 and sys.argv[1] == "run":
        run(sys.argv[2], sys.argv[3], sys.argv[4:] or list(CASES))
    elif len(sys.argv) == 4 and sys.argv[1] == "compare":
        sys.exit(compare(sys.argv[2], sys.argv[3]))
    else:
        print(__doc__)
        sys.exit(2)
