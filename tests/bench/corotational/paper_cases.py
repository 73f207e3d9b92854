#!/usr/bin/env python3
"""The measurements behind the rows of docs/plugins/corotational.md's "Against the paper" table that differ from
Hauret et al., all through the driver:

    python3 tests/bench/corotational/paper_cases.py two-planes     # 6.4: contacts, restitution, Models 1 vs 2 over dt,
                                                                   # the count over meshes
    python3 tests/bench/corotational/paper_cases.py impact-phase   # 6.3: spin after the impact against the touch's
                                                                   # place in the step grid (why the angle error is
                                                                   # not monotone in dt)
    python3 tests/bench/corotational/paper_cases.py ellipse        # 6.4: the ellipse, Models 1 vs 2
    python3 tests/bench/corotational/paper_cases.py friction       # 6.3 with friction (Fig. 6.8): theta' after contact,
                                                                   # Model 1 against the SVK midpoint comparison, over
                                                                   # dt, the plane's place and E

Each prints a table; nothing is written. [--stickslip PATH] selects the binary (default build/bin/stickslip).
"""
import argparse
import csv
import os
import re
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", "..", ".."))
LINE = re.compile(r"^corotational: step (\d+) t (\S+) theta (\S+) w (\S+) E (\S+) J (\S+) friction (\S+) "
                  r"g/g_ref (\S+) w-updates (\d+) impulse (\S+) defect (\S+) centre (\S+) (\S+) (\S+)")
KEYS = ("step", "t", "theta", "w", "E", "J", "friction", "g", "updates", "impulse", "defect", "x", "y", "z")


def simulate(stickslip, scene, *sets):
    """(history rows, plugin records) of one run with --set options."""
    with tempfile.TemporaryDirectory() as out:
        cmd = [stickslip, "run", os.path.join(ROOT, scene), "--out", os.path.join(out, "r"), "--verbose",
               "--set", "output.vtu_every=0"]
        for s in sets:
            cmd += ["--set", s]
        proc = subprocess.run(cmd, capture_output=True, text=True)
        if proc.returncode != 0:
            sys.exit("failed: %s\n%s" % (" ".join(cmd), proc.stderr[-2000:]))
        rows = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(open(os.path.join(out, "r",
                                                                                             "history.csv")))]
    records = [{k: float(v) for k, v in zip(KEYS, m.groups())} for m in map(LINE.match, proc.stderr.splitlines()) if m]
    return rows, records


def contacts(rows):
    """[(t of the first contact step, t of the last, vertical velocity after)] from history.csv."""
    mass = rows[0]["momentum_x"] / 40.0  # V_0 = (40, -40)
    out, start = [], None
    for a, b in zip(rows, rows[1:]):
        if b["active_points"] > 0 and a["active_points"] == 0:
            start = b["time"]
        if b["active_points"] == 0 and a["active_points"] > 0:
            out.append((start, a["time"], b["momentum_y"] / mass))
    return out


def vibration_share(rows, records, t):
    """The share of the scheme's energy not in rigid motion at time t: 1 - (1/2 m V^2 + 1/2 I w^2) / E, with I from
    the steady initial state (its strain energy, 1e-4 of E, counted as rotation)."""
    mass = rows[0]["momentum_x"] / 40.0
    E0 = rows[0]["total_energy"]
    inertia = 2 * (E0 - 0.5 * mass * 3200.0) / 20.0 ** 2
    r = min(records, key=lambda q: abs(q["t"] - t))
    h = min(rows, key=lambda q: abs(q["time"] - t))
    rigid = 0.5 * (h["momentum_x"] ** 2 + h["momentum_y"] ** 2) / mass + 0.5 * inertia * r["w"] ** 2
    return 1 - rigid / r["E"]


def two_planes(stickslip):
    print("6.4 ball between two planes (paper: five contacts, frames t = 0.003, 0.022, 0.041, 0.07, 0.095)")
    print("| dt | model | contacts by t = 0.1 (start, end, v_y after) | vibration share of E after the 1st |")
    print("|---|---|---|---|")
    runs = {}
    for dt in (0.001, 0.0005, 0.00025):
        for model in (1, 2):
            rows, records = simulate(stickslip, "scenes/corot-ball-two-planes.yaml", "time.dt=%r" % dt,
                                     "bodies.0.parameters.model=%d" % model)
            runs[dt, model] = records
            c = contacts(rows)
            share = vibration_share(rows, records, c[0][1] + 0.002)
            print("| %g | %d | %d: %s | %.3f |" % (dt, model, len(c), " ".join("%.4f-%.4f %+.1f" % e for e in c), share))
    print("\nModels 1 vs 2: the largest difference of the centre of mass and of theta' before each contact")
    for dt in (0.001, 0.0005, 0.00025):
        one, two = runs[dt, 1], runs[dt, 2]
        line = []
        for t in (0.02, 0.04, 0.06, 0.08, 0.1):
            pairs = [(a, b) for a, b in zip(one, two) if a["t"] <= t + 1e-12]
            dx = max(max(abs(a["x"] - b["x"]), abs(a["y"] - b["y"])) for a, b in pairs)
            dw = max(abs(a["w"] - b["w"]) for a, b in pairs)
            line.append("t %.2f: %.1e / %.2f" % (t, dx, dw))
        print("dt %g: %s" % (dt, "; ".join(line)))
    print("\nThe mesh (the paper draws its grid, Fig. 6.9, without sizes), dt 0.001, Model 1; the lower gap (the touch's")
    print("place in the step grid) for comparison")
    print("| variation | contacts by t = 0.1 (start, end, v_y after) | vibration share of E after the 1st |")
    print("|---|---|---|")
    for sets in (("mesh.parameters.refine=0.25",), ("mesh.parameters.refine=0.5",), ("mesh.parameters.refine=0.75",),
                 ("mesh.parameters.n=6",),
                 ("mesh.parameters.n=10",), ("mesh.parameters.n=12",), ("mesh.parameters.n_radial=2",),
                 ("mesh.parameters.n_radial=3",), ("mesh.parameters.n_radial=5",), ("mesh.parameters.n_radial=6",),
                 ("contact.0.obstacle.point=[0, -1.08, 0]",), ("contact.0.obstacle.point=[0, -1.12, 0]",)):
        rows, records = simulate(stickslip, "scenes/corot-ball-two-planes.yaml", *sets)
        c = contacts(rows)
        print("| %s | %d: %s | %.3f |" % (" ".join(sets), len(c), " ".join("%.4f-%.4f %+.1f" % e for e in c),
                                         vibration_share(rows, records, c[0][1] + 0.002)))


def impact_phase(stickslip):
    print("6.3 ball, frictionless: theta' after the impact (t = 0.06) against where the touch falls in the step grid.")
    print("The plane moved down by d: the touch at t = (0.5 + d)/40; the exact spin after the impact hardly changes")
    print("| d | touch t | dt 0.001: theta'(0.06), first contact step | dt 0.00025 |")
    print("|---|---|---|---|")
    for d in (0.0, 0.01, 0.02, 0.03, 0.04, 0.05, 0.06, 0.07):
        cells = []
        for dt in (0.001, 0.00025):
            rows, records = simulate(stickslip, "scenes/corot-ball-on-plane.yaml", "time.dt=%r" % dt,
                                     "contact.0.obstacle.point=[0, %r, 0]" % (-10.5 - d))
            first = next(r["time"] for r in rows if r["active_points"] > 0)
            cells.append("%.5f, ends %.5f" % (records[-1]["w"], first))
        print("| %.2f | %.6f | %s | %s |" % (d, (0.5 + d) / 40, cells[0], cells[1]))


def ellipse(stickslip):
    print("6.4 ellipse (semi-axes 0.6 x 1, ours): contacts and the centre difference Models 1 - 2")
    for dt in (0.001, 0.0005):
        runs = {}
        for model in (1, 2):
            rows, records = simulate(stickslip, "scenes/corot-ellipse-two-planes.yaml", "time.dt=%r" % dt,
                                     "time.end=0.15", "bodies.0.parameters.model=%d" % model)
            runs[model] = records
            print("dt %g model %d: contacts %s" % (dt, model, " ".join("%.4f-%.4f %+.1f" % e for e in contacts(rows))))
        one, two = runs[1], runs[2]
        print("  centre difference at t = 0.01 ... 0.15: %s" % " ".join(
            "%.1e" % max(abs(a["x"] - b["x"]), abs(a["y"] - b["y"])) for a, b in zip(one, two)
            if abs(a["t"] * 100 - round(a["t"] * 100)) < 1e-9))


def spin_after(rows):
    """(theta' about the centre of mass at the last row, angular impulse per tangential impulse): J_c = J - x_c x P
    with the centre moved by the momenta from the origin (mass P_x(0) / 40), I = J(0) / 2 (theta'_0 = 2)."""
    mass, centre = rows[0]["momentum_x"] / 40.0, [0.0, 0.0]
    for a, b in zip(rows, rows[1:]):
        for i, key in enumerate(("momentum_x", "momentum_y")):
            centre[i] += (b["time"] - a["time"]) * (a[key] + b[key]) / (2 * mass)
    last = rows[-1]
    j_centre = last["angular_momentum_z"] - (centre[0] * last["momentum_y"] - centre[1] * last["momentum_x"])
    j0 = rows[0]["angular_momentum_z"]
    return 2 * j_centre / j0, (j_centre - j0) / (last["momentum_x"] - rows[0]["momentum_x"])


def friction(stickslip):
    print("6.3 ball with friction 0.2 (Fig. 6.8): theta' after contact (t = 0.06) and the angular impulse per")
    print("tangential impulse, Model 1 against the SVK midpoint comparison (penalty-nts friction)")
    print("| variant | Model 1 | nonlinear |")
    print("|---|---|---|")
    schemes = (("scenes/corot-ball-on-plane-friction.yaml",),
               ("scenes/corot-ball-on-plane-nonlinear.yaml", "contact.0.parameters.mu=0.2"))
    variants = [("dt %g" % dt, ("time.dt=%r" % dt,)) for dt in (0.002, 0.001, 0.0005, 0.00025, 0.000125, 0.0000625)]
    variants += [("dt %g, plane moved by %.2f" % (dt, d), ("time.dt=%r" % dt, "contact.0.obstacle.point=[0, %r, 0]"
                                                            % (-10.5 - d)))
                 for dt in (0.002, 0.00025) for d in (0.04, 0.08, 0.12, 0.16)]
    variants += [("E x %d" % f, ("bodies.0.material.E=%r" % (1.62e7 * f),)) for f in (10, 100)]
    for name, sets in variants:
        cells = []
        for scheme in schemes:
            rows, _ = simulate(stickslip, scheme[0], *(scheme[1:] + sets))
            cells.append("%.4f, %.3f" % spin_after(rows))
        print("| %s | %s | %s |" % (name, cells[0], cells[1]))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("case", choices=("two-planes", "impact-phase", "ellipse", "friction"))
    parser.add_argument("--stickslip", default=os.path.join(ROOT, "build", "bin", "stickslip"))
    args = parser.parse_args()
    {"two-planes": two_planes, "impact-phase": impact_phase, "ellipse": ellipse,
     "friction": friction}[args.case](args.stickslip)


if __name__ == "__main__":
    main()
