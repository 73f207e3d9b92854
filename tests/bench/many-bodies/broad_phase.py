#!/usr/bin/env python3
"""The host's broad phase over contact pairs created by `bodies: all` (docs/contact-services.md, "Pairs among many
bodies"): its share of a step and its growth with the number of bodies N.

For each N (default 2, 4, 8, 16, 32, 64, 128) the scene is N elastic disks (radius 0.5, 48 quad4 each) on a square-ish grid
in a rigid box (floor and two walls), dropped under gravity for a number of midpoint steps with penalty-nts and
friction: N (N - 1) / 2 disk pairs and 3 N wall pairs, all created by one `bodies: all` entry. Each N runs twice:
with the broad phase, and with it off (STICKSLIP_NO_SKIP=idle-calls, every pair calls its plugin every step), so the
contact seconds show what the broad phase saves (up to --without-up-to bodies: without it every pair searches at
every iterate, which takes long for many bodies). Reads summary.json (broad_phase_seconds, pair_attempts,
pair_attempts_apart, contact_seconds, wall_seconds) and writes OUT/broad-phase.csv and OUT/broad-phase.png, and
prints the exponent p of a least-squares fit time ~ N^p of the broad phase per sweep and per step over N >= 4.

Wall times on a shared machine are noisy: the share and the growth are what matters, not the seconds.
Example: tests/bench/many-bodies/broad_phase.py --out /tmp/broad-phase"""
import argparse
import csv
import json
import math
import os
import subprocess
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
COLUMNS = ["bodies", "pairs", "steps", "newton_iterations", "wall_seconds", "broad_phase_seconds",
           "broad_phase_per_step", "broad_phase_share", "sweeps", "broad_phase_per_sweep", "pair_attempts",
           "pair_attempts_apart", "contact_seconds",
           "contact_seconds_without", "wall_seconds_without"]


def scene(n, steps):
    columns = max(2, math.ceil(math.sqrt(n)))
    width = columns * 1.1 + 0.1
    meshes, bodies = [], []
    for k in range(n):
        row, col = divmod(k, columns)
        x = 0.6 + 1.1 * col + (0.25 if row % 2 else 0.0) * (col < columns - 1)
        y = 0.6 + 1.15 * row
        meshes.append("  - {file: %s/meshes/disk.geo, name: d%d, parameters: {radius: 0.5, refine: 0.5, cx: %g, "
                      "cy: %g}}" % (ROOT, k, x, y))
        bodies.append("  - {name: disk-%d, group: d%d.body, material: {model: neo-hooke-bonet, E: 1.0e4, nu: 0.3, "
                      "density: 1}}" % (k, k))
    return """mesh:
%s
bodies:
%s
body_force: [0, -9.81, 0]
contact:
  - name: all
    bodies: all
    obstacles:
      - {type: plane, name: floor, point: [0, 0, 0], normal: [0, 1, 0]}
      - {type: plane, name: left, point: [0, 0, 0], normal: [1, 0, 0]}
      - {type: plane, name: right, point: [%g, 0, 0], normal: [-1, 0, 0]}
    plugin: penalty-nts
    parameters: {mu: 0.3}
time: {scheme: midpoint, dt: 0.005, end: %g}
output: {vtu: false, contact_csv: false}
""" % ("\n".join(meshes), "\n".join(bodies), width, 0.005 * steps)


def run(binary, path, env=None):
    out = tempfile.mkdtemp(prefix="stickslip-broad-")
    full_env = dict(os.environ)
    full_env.update(env or {})
    subprocess.run([binary, "run", path, "--out", os.path.join(out, "r"), "--quiet"], check=True, env=full_env,
                   capture_output=True)
    with open(os.path.join(out, "r", "summary.json")) as f:
        return json.load(f)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--bodies", default="2,4,8,16,32,64,128")
    p.add_argument("--without-up-to", type=int, default=32, help="largest N also run without the broad phase")
    p.add_argument("--steps", type=int, default=60)
    p.add_argument("--out", required=True)
    p.add_argument("--binary", default=os.path.join(ROOT, "build", "bin", "stickslip"))
    args = p.parse_args()
    os.makedirs(args.out, exist_ok=True)
    rows = []
    for n in [int(v) for v in args.bodies.split(",")]:
        path = os.path.join(args.out, "disks-%d.yaml" % n)
        with open(path, "w") as f:
            f.write(scene(n, args.steps))
        on = run(args.binary, path)
        off = run(args.binary, path, {"STICKSLIP_NO_SKIP": "idle-calls"}) if n <= args.without_up_to else {}
        steps = on["steps"]
        row = {"bodies": n, "pairs": n * (n - 1) // 2 + 3 * n, "steps": steps,
               "newton_iterations": on["newton_iterations"], "wall_seconds": on["wall_seconds"],
               "broad_phase_seconds": on["broad_phase_seconds"],
               "broad_phase_per_step": on["broad_phase_seconds"] / steps,
               "broad_phase_share": on["broad_phase_seconds"] / on["wall_seconds"],
               "sweeps": on["broad_phase_sweeps"],
               "broad_phase_per_sweep": on["broad_phase_seconds"] / max(on["broad_phase_sweeps"], 1),
               "pair_attempts": on["pair_attempts"], "pair_attempts_apart": on["pair_attempts_apart"],
               "contact_seconds": on["contact_seconds"], "contact_seconds_without": off.get("contact_seconds", ""),
               "wall_seconds_without": off.get("wall_seconds", "")}
        rows.append(row)
        print(" ".join("%s=%.4g" % (k, v) if isinstance(v, float) else "%s=%s" % (k, v) for k, v in row.items()),
              flush=True)
    table = os.path.join(args.out, "broad-phase.csv")
    with open(table, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS)
        w.writeheader()
        w.writerows(rows)
    png = os.path.join(args.out, "broad-phase.png")
    subprocess.run(["gnuplot", "-c", os.path.join(os.path.dirname(os.path.abspath(__file__)), "broad-phase.gp"),
                    table, png], check=True)
    for column in ("broad_phase_per_sweep", "broad_phase_per_step"):
        points = [(math.log(r["bodies"]), math.log(r[column])) for r in rows if r["bodies"] >= 4 and r[column] > 0]
        if len(points) >= 2:
            mx, my = sum(x for x, _ in points) / len(points), sum(y for _, y in points) / len(points)
            slope = sum((x - mx) * (y - my) for x, y in points) / sum((x - mx) ** 2 for x, _ in points)
            print("%s ~ N^%.2f (least squares over N = %s)" % (column, slope, ", ".join(
                str(r["bodies"]) for r in rows if r["bodies"] >= 4)))
    print("wrote %s and %s" % (table, png))


if __name__ == "__main__":
    main()
