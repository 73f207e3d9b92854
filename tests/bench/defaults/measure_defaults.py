#!/usr/bin/env python3
"""The constants of the defaults computed from the scene (docs/scene-reference.md#contact, each plugin page's
"Defaults"), measured: accuracy against Newton iterations over a range of the constant c of each plugin's rule
(penalty = c E*/h, c_n = c E*/h, epsilon_t = c E*/h A), on small scenes a user writes from the scene reference
(tests/scenes-from-reference: no solver section, only mu on the pair) and on the Hertz scenes (closed form) with
linear and quadratic elements. The value a plugin computes by default is read from `stickslip check --explain`; the
sweep gives the key c / c_default times that value.

  python3 tests/bench/defaults/measure_defaults.py                        every case, plugin and constant
  python3 tests/bench/defaults/measure_defaults.py --cases punch-2d --plugins mortar-dual --constants 1,10
  options: --set KEY=VALUE (added to every run, e.g. solver.newton.line_search=backtrack), --key NAME (the swept
  parameter, default the plugin's primary one), --csv FILE (default results.csv here; rows of the same case, plugin,
  key, constant and extra settings are replaced)

Per run: converged to the end or not, steps, step cuts, Newton iterations, CPU seconds (loaded machine: compare
iterations), the deepest penetration at the end over the slave surface's mean edge h (contact.csv gap), the
friction ratio |F_t|/F_n of the last step, and for Hertz the profile errors of tests/validation/hertz_profile.py."""
import argparse
import csv
import json
import math
import os
import re
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(HERE)))
sys.path.insert(0, os.path.join(ROOT, "tests", "validation"))
from hertz_profile import hertz_reference, profile_errors  # noqa: E402
from stickslip_results import Results  # noqa: E402
from test_contact_scenes import reference_points  # noqa: E402

BIN = os.environ.get("STICKSLIP_BIN", os.path.join(ROOT, "build", "bin", "stickslip"))
USER = os.path.join(ROOT, "tests", "scenes-from-reference")
# case -> (scene, --set overrides, normal axis of the contact force, Hertz dimension or 0, the plugins that run it)
CASES = {
    "punch-2d": (os.path.join(USER, "punch-2d.yaml"), [], 1, 0, ["penalty-nts", "nts-augmented", "mortar-dual"]),
    "cube-on-slab-3d": (os.path.join(USER, "cube-on-slab-3d.yaml"), [], 2, 0,
                        ["penalty-nts", "nts-augmented", "covariant-penalty", "mortar-dual"]),
    "half-ball-3d": (os.path.join(USER, "half-ball-3d.yaml"), [], 2, 0,
                     ["penalty-nts", "nts-augmented", "covariant-penalty", "mortar-dual"]),
    "spinning-disk-2d": (os.path.join(USER, "spinning-disk-2d.yaml"), [], 1, 0, ["penalty-nts", "nts-augmented"]),
    "hertz-2d-quad4": ("scenes/hertz-2d.yaml", [], 1, 2, ["penalty-nts", "nts-augmented", "mortar-dual"]),
    "hertz-2d-quad9": ("scenes/hertz-2d.yaml", ["mesh.order=2"], 1, 2, ["penalty-nts"]),
    "hertz-3d-tet4": ("scenes/hertz-3d.yaml", [], 2, 3,
                      ["penalty-nts", "nts-augmented", "covariant-penalty", "mortar-dual"]),
    "hertz-3d-tet10": ("scenes/hertz-3d.yaml", ["mesh.order=2"], 2, 3, ["penalty-nts"]),
    "hertz-3d-hex27": ("scenes/hertz-3d-hex.yaml", ["mesh.order=2"], 2, 3, ["penalty-nts", "covariant-penalty"]),
}
# the parameter each plugin's constant scales, and that constant's default (the plugins' pages)
# (nts-augmented: epsilon_t with friction; frictionless, only c_n is computed and swept)
PRIMARY = {"penalty-nts": ["penalty"], "covariant-penalty": ["penalty"], "mortar-dual": ["c_n"],
           "nts-augmented": ["epsilon_t", "c_n"]}
FIELDS = ["case", "plugin", "key", "constant", "settings", "value", "ok", "final_time", "steps", "step_cuts",
          "newton", "active_set_loops", "cpu", "h", "penetration_h", "friction_ratio", "l2", "a", "p0", "message"]
COMPUTED = re.compile(r"^\s*contact\[0\]\.parameters\.(\w+) = (\S+) \(computed: (.*)\)$")


def scene_path(scene):
    return scene if os.path.isabs(scene) else os.path.join(ROOT, scene)


def base_arguments(case, plugin, extra):
    scene, sets, _, _, _ = CASES[case]
    args = [scene_path(scene), "--plugin", plugin]
    for s in sets + extra:
        args += ["--set", s]
    return args


def mu_of(scene):
    text = open(scene_path(scene)).read()
    match = re.search(r"\bmu:\s*([0-9.eE+-]+)", text)
    return float(match.group(1)) if match else 0.0


def computed_defaults(case, plugin, extra):
    """{key: (value, reason)} the plugin computes for the case with only mu given."""
    scene = CASES[case][0]
    args = base_arguments(case, plugin, extra) + ["--replace", "contact.0.parameters={mu: %g}" % mu_of(scene),
                                                  "--explain"]
    proc = subprocess.run([BIN, "check"] + args, capture_output=True, text=True)
    if proc.returncode != 0:
        raise RuntimeError("check failed: %s\n%s" % (" ".join(args), proc.stderr))
    out = {}
    for line in proc.stdout.splitlines():
        match = COMPUTED.match(line)
        if match and not match.group(3).startswith("unused:"):  # a parameter the pair does not use is reported as 0
            out[match.group(1)] = (float(match.group(2)), match.group(3))
    return out


def default_constant(reason):
    """The c of a reason "c E*/h ..."."""
    return float(reason.split()[0])


def run(case, plugin, keys, constant, extra):
    """One run with the first of `keys` the plugin computes set to constant / its default constant times its value."""
    scene, _, axis, hertz, _ = CASES[case]
    defaults = computed_defaults(case, plugin, extra)
    key = next((k for k in keys if k in defaults), None)
    if key is None:
        raise RuntimeError("%s computes none of %s for %s" % (plugin, keys, case))
    value, reason = defaults[key]
    value *= constant / default_constant(reason)
    h = float(re.search(r"h = (\S+) \(mean", reason).group(1))
    params = "{mu: %g, %s: %.10g}" % (mu_of(scene), key, value)
    out = os.path.join(tempfile.mkdtemp(prefix="stickslip-defaults-"), "results")
    command = [BIN, "run"] + base_arguments(case, plugin, extra) + [
        "--replace", "contact.0.parameters=" + params, "--out", out, "--quiet", "--set", "output.vtu_every=0"]
    env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
    proc = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, env=env)
    _, status, usage = os.wait4(proc.pid, 0)
    stderr = proc.stderr.read()
    row = {"case": case, "plugin": plugin, "key": key, "constant": constant, "settings": " ".join(extra),
           "value": "%.6g" % value, "cpu": "%.2f" % (usage.ru_utime + usage.ru_stime), "h": "%.4g" % h}
    summary_path = os.path.join(out, "summary.json")
    if not os.path.exists(summary_path):
        row.update(ok=0, message=stderr.strip().splitlines()[-1] if stderr.strip() else "no summary")
        return row
    summary = json.load(open(summary_path))
    row.update(ok=int(summary["status"] == "ok"), final_time="%.4g" % summary["final_time"], steps=summary["steps"],
               step_cuts=summary["step_cuts"], newton=summary["newton_iterations"],
               active_set_loops=summary.get("active_set_loops", 0),
               message=summary.get("message", "")[:160])
    if summary["status"] != "ok":
        return row
    results = Results(out)
    points = results.contact_points()
    depth = max([-p["gap"] for p in points if p["state"] > 0 and not math.isnan(p["gap"])] or [0.0])
    row["penetration_h"] = "%.3g" % (depth / h)
    last = results.rows[-1]
    force = [last["contact_force_%s" % c] for c in "xyz"]
    normal = abs(force[axis])
    tangential = math.sqrt(sum(f * f for i, f in enumerate(force) if i != axis))
    row["friction_ratio"] = "%.4g" % (tangential / normal) if normal > 0 else ""
    if hertz:  # vtu_every 0 writes the last state, whose displacements give the reference positions
        load, a, p0 = hertz_reference(hertz, results)
        errors = profile_errors(reference_points(results, radial=hertz == 3), a, p0)
        row.update(l2="%.4f" % errors["l2"], a="%+.4f" % errors["a"], p0="%+.4f" % errors["p0"])
    return row


def merge(path, rows):
    def identity(r):
        return (r["case"], r["plugin"], r["key"], "%g" % float(r["constant"]), r.get("settings", ""))
    old = []
    if os.path.exists(path):
        with open(path) as f:
            old = list(csv.DictReader(f))
    done = {identity(r) for r in rows}
    kept = [r for r in old if identity(r) not in done] + rows
    kept.sort(key=lambda r: (r["case"], r["plugin"], r["key"], r.get("settings", ""), float(r["constant"])))
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=FIELDS, extrasaction="ignore")
        writer.writeheader()
        writer.writerows(kept)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cases", default=",".join(CASES))
    parser.add_argument("--plugins", default="")
    parser.add_argument("--constants", default="1,3,10,30,100,300,1000")
    parser.add_argument("--key", default="")
    parser.add_argument("--set", action="append", default=[])
    parser.add_argument("--csv", default=os.path.join(HERE, "results.csv"))
    args = parser.parse_args()
    for case in args.cases.split(","):
        for plugin in CASES[case][4]:
            if args.plugins and plugin not in args.plugins.split(","):
                continue
            keys = [args.key] if args.key else PRIMARY[plugin]
            rows = []
            for constant in [float(c) for c in args.constants.split(",")]:
                row = run(case, plugin, keys, constant, args.set)
                rows.append(row)
                print("%-16s %-17s %-9s c %-6g ok %s  steps %-4s cuts %-3s newton %-5s pen/h %-9s Ft/Fn %-7s l2 %-7s %s"
                      % (case, plugin, row["key"], constant, row["ok"], row.get("steps", ""), row.get("step_cuts", ""),
                         row.get("newton", ""), row.get("penetration_h", ""), row.get("friction_ratio", ""),
                         row.get("l2", ""), row.get("message", "")[:60] if not row["ok"] else ""), flush=True)
            merge(args.csv, rows)


if __name__ == "__main__":
    main()
