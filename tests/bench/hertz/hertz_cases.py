"""Hertz benchmark cases (2D cylinder, 3D sphere) per element type and plugin: one run of the driver with its cost
(unknowns, wall and CPU time, peak memory) and its errors against Hertz's closed forms (tests/validation/
hertz_profile.py defines them)."""
import math
import os
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(HERE)))
sys.path.insert(0, os.path.join(ROOT, "tests", "validation"))
from hertz_profile import PROFILE_RANGE, hertz_reference, profile_errors  # noqa: E402,F401
from stickslip_results import Results  # noqa: E402
from test_contact_scenes import reference_points  # noqa: E402

# element label -> (dimension, scene, --set overrides); quadratic elements are the linear mesh made second order.
ELEMENTS = {
    "tri3": (2, "scenes/hertz-2d.yaml", ["mesh.parameters.quads=0"]),
    "quad4": (2, "scenes/hertz-2d.yaml", []),
    "tri6": (2, "scenes/hertz-2d.yaml", ["mesh.parameters.quads=0", "mesh.order=2"]),
    "quad9": (2, "scenes/hertz-2d.yaml", ["mesh.order=2"]),
    "tet4": (3, "scenes/hertz-3d.yaml", []),
    "tet10": (3, "scenes/hertz-3d.yaml", ["mesh.order=2"]),
    "hex8": (3, "scenes/hertz-3d-hex.yaml", []),
    "hex27": (3, "scenes/hertz-3d-hex.yaml", ["mesh.order=2"]),
}


def driver_command(scene, sets, out):
    """The command line of one quiet run of the driver with --set overrides."""
    binary = os.environ.get("STICKSLIP_BIN", os.path.join(ROOT, "build", "bin", "stickslip"))
    command = [binary, "run", os.path.join(ROOT, scene), "--out", out, "--quiet"]
    for s in sets:  # a map of parameters replaces the scene's (another plugin's) parameters
        command += ["--replace" if s.startswith("contact.0.parameters=") else "--set", s]
    return command


def run_timed(scene, sets, out):
    """Runs the driver (one rank, one thread for BLAS/OpenMP so that CPU time means one core); returns (Results,
    user + system CPU seconds, peak resident memory in MiB) of that child process alone."""
    cpu, rss, _ = run_child(driver_command(scene, sets, out))
    return Results(out), cpu, rss


def run_child(command):
    """Runs a command with one thread for BLAS/OpenMP; returns (user + system CPU seconds, peak resident memory in
    MiB, wall seconds from start to exit) of that child process alone (and the children it waited for)."""
    env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
    start = time.perf_counter()
    proc = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, env=env)
    stderr = proc.stderr.read()
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - start
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode != 0:
        raise RuntimeError("run failed (%d): %s\n%s" % (proc.returncode, " ".join(command), stderr))
    return usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024.0, wall


def run_case(element, plugin, refine, keep=None, extra_sets=()):
    """One benchmark run: a dict of cost and errors, and the profile [(r/a, p/p0)] at reference positions."""
    dim, scene, sets = ELEMENTS[element]
    sets = list(sets) + ["mesh.parameters.refine=%g" % refine, "output.vtu_every=4"]
    if plugin != "penalty-nts":
        sets += ["contact.0.plugin=%s" % plugin, "contact.0.parameters={}"]
    sets += list(extra_sets)  # after the plugin's parameters are cleared, so that they can set them
    out = keep or os.path.join(tempfile.mkdtemp(prefix="stickslip-bench-hertz-"), "results")
    cpu, rss, process_wall = run_child(driver_command(scene, sets, out))
    results = Results(out)
    load, a, p0 = hertz_reference(dim, results)
    points = reference_points(results, radial=dim == 3)
    row = {"dim": dim, "element": element, "plugin": plugin, "refine": refine,
           "unknowns": int(results.summary["unknowns"]), "newton": int(results.summary["newton_iterations"]),
           "wall": results.summary["wall_seconds"], "process_wall": process_wall, "cpu": cpu, "rss_mib": rss,
           "load": load, "a_exact": a}
    row.update(profile_errors(points, a, p0))
    profile = [(r / a, p / p0) for r, p, g, n in points if not math.isnan(g) and r <= 2.0 * a]
    return row, profile
