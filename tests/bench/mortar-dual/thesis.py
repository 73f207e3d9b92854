#!/usr/bin/env python3
"""Hammer's examples (2012, ch. 8) with mortar-dual, the full runs behind docs/plugins/mortar-dual.md section 11
("Against the paper"): each part runs the thesis's set-up and the variations that locate a difference, and prints the
numbers the table quotes. Finished runs are reused (results/bench/mortar-thesis/<name>/; --fresh to redo).

  python3 tests/bench/mortar-dual/thesis.py --hammer        8.1: full mesh, M and A, mu 0 and 0.3, bases (~15 CPU min)
  python3 tests/bench/mortar-dual/thesis.py --hertz         8.3: the block's height, the thesis's load (~1 CPU min)
  python3 tests/bench/mortar-dual/thesis.py --ring          8.4: the gap and the wall (~1 CPU min)
  python3 tests/bench/mortar-dual/thesis.py --deep-ironing  8.2: M and A at mu 0, M at mu 0.3, refine 1 and 1.5 (hours);
                                                            then gnuplot tests/bench/mortar-dual/deep-ironing.gp"""
import csv
import json
import math
import os
import re
import shutil
import statistics
import subprocess
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "tests", "validation"))
from stickslip_results import Results  # noqa: E402
from test_mortar_thesis import (ellipse_fit, hertz_2d_profile, newton_runs, oscillation,  # noqa: E402
                                HERTZ_2D_F, HERTZ_2D_H)

OUT = os.path.join(os.environ.get("STICKSLIP_BENCH_OUT", os.path.join(ROOT, "results", "bench")), "mortar-thesis")
BINARY = os.environ.get("STICKSLIP_BIN", os.path.join(ROOT, "build", "bin", "stickslip"))
THESIS = ["--set", "contact.0.parameters.integration=concentrated", "--set", "contact.0.parameters.active_set=nested",
          "--set", "contact.0.parameters.basis=dual"]
COARSE = ["--set", "mesh.0.parameters.refine=0.5", "--set", "mesh.1.parameters.refine=0.5"]


def run(name, scene, *args):
    """Runs (or reuses) `stickslip run scene args --verbose` into OUT/name; returns (Results or None, stderr)."""
    folder = os.path.join(OUT, name)
    log = folder + ".log"
    if "--fresh" in sys.argv or not os.path.exists(os.path.join(folder, "summary.json")):
        shutil.rmtree(folder, ignore_errors=True)
        with open(log, "w") as f:
            subprocess.run([BINARY, "run", os.path.join(ROOT, scene), "--out", folder, "--quiet", "--verbose",
                            "--set", "output.vtu_every=0", *args], stderr=f, stdout=subprocess.DEVNULL)
    stderr = open(log).read() if os.path.exists(log) else ""
    results = Results(folder) if os.path.exists(os.path.join(folder, "history.csv")) else None
    return results, stderr


def status(results):
    s = results.summary
    return "%s, %d steps to t = %.4g, %d Newton iterations, %d cuts" % (
        s["status"], s["steps"], results.rows[-1]["time"], s["newton_iterations"], s["step_cuts"])


def by_time(results):
    return {round(row["time"], 6): row for row in results.rows}


# ---- 8.1 the simple benchmark ----------------------------------------------------------------------------------
HAMMER = "scenes/mortar-hammer-benchmark.yaml"


def newton_table(name, results, stderr):
    step_of = {round(row["time"], 6): int(row["step"]) for row in results.rows}
    runs = newton_runs(stderr)
    for n in (10, 17, 40, 57):
        step = step_of.get(round(n / 10, 6))
        print("  %s step %d: %s" % (name, n, " | ".join(" ".join("%.1e" % x for x in r) for r in runs.get(step, []))))


def friction_summary(name, results):
    rows = by_time(results)
    fx = [(t, row["reaction_shear_x"], row["reaction_press_y"]) for t, row in sorted(rows.items())]
    right, left = max(fx, key=lambda v: v[1]), min(fx, key=lambda v: v[1])
    full = [t for t, row in sorted(rows.items())
            if row["active_points"] > 0 and row["slip_points"] == row["active_points"]]
    ratio = lambda v: abs(v[1] / v[2]) if v[2] else math.nan  # noqa: E731
    print("  %s: %s; max F_x %.1f at t = %.2f (F_y %.0f, ratio %.4f), min %.1f at t = %.2f (F_y %.0f, ratio %.4f); "
          "full slip first at t = %s moving right, %s moving left"
          % (name, status(results), right[1], right[0], right[2], ratio(right), left[1], left[0], left[2],
             ratio(left), [t for t in full if 1 < t < 4][:1], [t for t in full if 4 < t < 7][:1]))


def hammer():
    print("8.1 frictionless, thesis set-up, full mesh (block 24 x 16, slab 40 x 12):")
    runs = {}
    for normal in ("M", "A"):
        for predictor in ("last-state", "previous-increment"):
            name = "hammer-%s-%s" % (normal, predictor)
            r, err = run(name, HAMMER, *THESIS, "--set", "contact.0.parameters.normal=" + normal,
                         "--set", "solver.newton.predictor=" + predictor)
            runs[name] = r
            print(" %s: %s" % (name, status(r)))
            newton_table(name, r, err)
            rows = by_time(r)
            scale = max(abs(row["reaction_press_y"]) for row in r.rows)
            print("  path independence: t 1 vs 7: F_y %.1e, F_x %.1e of max F_y"
                  % (abs(rows[1.0]["reaction_press_y"] - rows[7.0]["reaction_press_y"]) / scale,
                     abs(rows[1.0]["reaction_shear_x"] - rows[7.0]["reaction_shear_x"]) / scale))
    for predictor in ("last-state", "previous-increment"):
        a, b = by_time(runs["hammer-M-" + predictor]), by_time(runs["hammer-A-" + predictor])
        common = sorted(set(a) & set(b))
        for key in ("reaction_shear_x", "reaction_press_y"):
            values = [a[t][key] for t in common]
            diff = max(abs(a[t][key] - b[t][key]) for t in common)
            print(" M vs A (%s): %s differ by %.3g = %.1e of the span %.4g" % (predictor, key, diff,
                  diff / (max(values) - min(values)), max(values) - min(values)))
    print("8.1 mu = 0.3, thesis set-up:")
    for name, args in (("coarse-dual-M", COARSE + ["--set", "contact.0.parameters.normal=M"]),
                       ("coarse-dual-A", COARSE + ["--set", "contact.0.parameters.normal=A"]),
                       ("coarse-dual-M-slab140", COARSE + ["--set", "contact.0.parameters.normal=M",
                                                           "--set", "mesh.0.parameters.lx=140",
                                                           "--set", "mesh.0.parameters.nx=28"]),
                       ("full-dual-M", ["--set", "contact.0.parameters.normal=M"]),
                       ("full-standard-M", ["--set", "contact.0.parameters.normal=M", "--set",
                                            "contact.0.parameters.basis=standard"])):
        r, err = run("hammer-mu03-" + name, HAMMER, *THESIS, "--set", "contact.0.parameters.mu=0.3", *args)
        friction_summary(name, r)
        if r.summary["status"] != "ok":
            print("   failed: %s" % [l for l in err.splitlines() if l.startswith("stickslip:")][:1])
        newton_table(name, r, err)


# ---- 8.3 Hertz ---------------------------------------------------------------------------------------------------
HERTZ = "scenes/mortar-hertz-2d.yaml"


def hertz():
    print("8.3 Hertz, the approach 0.015 mm: F against the block's size (R = 69.565):")
    for name, args in (("H35", ["--set", "mesh.parameters.H=35"]), ("H70", []),
                       ("H140", ["--set", "mesh.parameters.H=140"]), ("H200", ["--set", "mesh.parameters.H=200"]),
                       ("H242", ["--set", "mesh.parameters.H=%g" % HERTZ_2D_H]),
                       ("H250", ["--set", "mesh.parameters.H=250"]), ("H280", ["--set", "mesh.parameters.H=280"]),
                       ("W280", ["--set", "mesh.parameters.W=280"])):
        r, _ = run("hertz-" + name, HERTZ, *args)
        F, b, p0, l2, _ = hertz_2d_profile(r)
        print("  %s: F = %.2f N/mm (thesis %.2f), b(F) = %.4f, l2 error %.2e" % (name, F, HERTZ_2D_F, b, l2))
    r, _ = run("hertz-thesis-load", HERTZ, "--replace", "boundary.0={name: top, group: cylinder-top, resultant: "
               "[0, %.10g], history: [[0, 0], [1, 1]]}" % (-HERTZ_2D_F / 2), "--set", "output.contact_csv=true")
    p0, b = ellipse_fit(r.contact_points())
    print("  the thesis's load: fitted b = %.5f, p0 = %.3f, centre %.3f"
          % (b, p0, min(r.contact_points(), key=lambda p: abs(p["x"]))["pressure"]))


# ---- 8.4 the ring ------------------------------------------------------------------------------------------------
RING = "scenes/mortar-ring.yaml"


def ring():
    print("8.4 ring, frictionless: the snap-through (the reaction's peak) against the gap and the wall:")
    for name, args in (("gap10-wall5", []), ("gap17.5-wall5", ["--set", "mesh.1.parameters.cy=120"]),
                       ("gap17.5-wall4", ["--set", "mesh.1.parameters.cy=120", "--set", "mesh.1.parameters.t=4"]),
                       ("gap17.5-wall6", ["--set", "mesh.1.parameters.cy=120", "--set", "mesh.1.parameters.t=6"])):
        r, _ = run("ring-" + name, RING, *args)
        reaction = r.column("reaction_base_y")
        i = max(range(len(reaction)), key=lambda k: reaction[k])
        t = r.rows[i]["time"]
        gap = float(re.search(r"gap([\d.]+)", name).group(1))
        print("  %s: peak %.1f at t = %.4f (step %.2f of 30), %.1f below first contact; final %.1f; %s"
              % (name, reaction[i], t, 30 * t, 70 * t - gap, reaction[-1], status(r)))


# ---- 8.2 the deep ironing ----------------------------------------------------------------------------------------
DEEP = "scenes/mortar-deep-ironing.yaml"
DEEP_RUNS = (("M-mu0", []), ("A-mu0", ["--set", "contact.0.parameters.normal=A"]),
             ("M-mu0.3", ["--set", "contact.0.parameters.mu=0.3"]),
             ("M-mu0.3-refine1.5", ["--set", "contact.0.parameters.mu=0.3", "--set", "mesh.0.parameters.refine=1.5",
                                    "--set", "mesh.1.parameters.refine=1.5"]))


def deep_ironing():
    os.makedirs(OUT, exist_ok=True)
    print("8.2 deep ironing (2 mm of travel per step; ironing windows: right t in [3, 8], left t in [9.5, 12]):")
    for name, args in DEEP_RUNS:
        r, err = run("deep-" + name, DEEP, *args)
        if r is None:
            print("  %s: no results" % name)
            continue
        with open(os.path.join(OUT, "deep-%s.dat" % name), "w") as f:
            for row in r.rows:
                f.write("%.6g %.8g %.8g\n" % (row["time"], row["reaction_iron_x"], row["reaction_press_y"]))
        line = "  %s: %s" % (name, status(r))
        if r.summary["status"] != "ok":
            line += " (%s)" % [l for l in err.splitlines() if l.startswith("stickslip:")][:1]
        print(line)
        for label, lo, hi in (("right", 3.0, 8.0), ("left", 9.5, 12.0)):
            window = [row for row in r.rows if lo <= row["time"] <= hi]
            if len(window) < 10:
                continue
            times = [row["time"] for row in window]
            rms, mean = oscillation(times, [row["reaction_iron_x"] for row in window])
            fy = statistics.fmean(-row["reaction_press_y"] for row in window)
            print("    ironing %s: F_x mean %.1f, ripple (rms about the 20 mm mean) %.2f = %.2f %% of F_y %.1f"
                  % (label, mean, rms, 100 * rms / fy, fy))


if __name__ == "__main__":
    os.makedirs(OUT, exist_ok=True)
    parts = {"--hammer": hammer, "--hertz": hertz, "--ring": ring, "--deep-ironing": deep_ironing}
    chosen = [f for flag, f in parts.items() if flag in sys.argv] or [hammer, hertz, ring]
    for part in chosen:
        part()
