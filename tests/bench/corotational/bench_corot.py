#!/usr/bin/env python3
"""Delta t sweeps of the co-rotational schemes (Models 1 and 2) against the core's nonlinear SVK midpoint scheme with
penalty contact, on Hauret et al.'s ball examples, all through the driver (docs/plugins/corotational.md §10). Writes
CSV files next to this script and the plot docs/img/corot-bench.png (gnuplot).

    python3 tests/bench/corotational/bench_corot.py [--stickslip PATH] [--quick]

CPU seconds are user + system time of each run (getrusage); `stepping_cpu` subtracts the least CPU of three one-step
runs of the same scheme (meshing, MPI and Trilinos start-up: about 0.3 s, measured).
"""
import argparse
import csv
import math
import os
import re
import resource
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "tests", "validation"))
import stickslip_results  # noqa: E402  (read_vtu)


def run_cpu(cmd, **kwargs):
    """Runs cmd; returns (completed process, CPU seconds of the child)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    proc = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, **kwargs)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return proc, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def history_iterations(rows):
    return sum(int(float(r["newton_iterations"])) for r in rows)


LINE = re.compile(r"^corotational: step (\d+) t (\S+) theta (\S+) w (\S+) E (\S+)")


def corot(stickslip, scene, model, dt, end, sets):
    """A co-rotational run through the driver: (ok, rows of step/t/theta/w/E from the plugin's --verbose lines, cpu)."""
    with tempfile.TemporaryDirectory() as out:
        cmd = [stickslip, "run", scene, "--out", out, "--verbose", "--set", f"time.dt={dt!r}", "--set",
               f"time.end={end!r}", "--set", "time.max_cuts=0", "--set", "output.vtu_every=0", "--set",
               f"bodies.0.parameters.model={model}"]
        for s in sets:
            cmd += ["--set", s]
        proc, cpu = run_cpu(cmd)
        history = os.path.join(out, "history.csv")
        newton = history_iterations(csv.DictReader(open(history))) if os.path.exists(history) else float("nan")
    rows = []
    for line in proc.stderr.splitlines():
        m = LINE.match(line)
        if m:
            rows.append({k: float(m.group(i + 1)) for i, k in enumerate(("step", "t", "theta", "w", "E"))})
    ok = proc.returncode == 0 and rows and abs(rows[-1]["t"] - end) < 1e-9 * max(1.0, end)
    return ok, rows, cpu, newton


def vtu_mesh(vtu):
    """Points (x, y), displacements and quad cells of a stickslip .vtu (read_vtu's arrays)."""
    points = [p[:2] for p in vtu["Points"]]
    disp = [d[:2] for d in vtu["displacement"]]
    conn = [c[0] for c in vtu["connectivity"]]
    offsets = [0] + [o[0] for o in vtu["offsets"]]
    cells = [conn[offsets[i]:offsets[i + 1]] for i in range(len(offsets) - 1)]
    return points, disp, cells


def tisserand_angle(points, X_ref, cells):
    """Sec. 6.2: theta with sum_a m_a (R^T phi_a) . Pi x_a = 0 (2D, lumped masses from the quad areas):
    tan theta = sum m phi . Pi x / sum m phi . x, phi and x about their centres of mass."""
    mass = [0.0] * len(points)
    for c in cells:
        xs = [X_ref[k] for k in c]
        area = 0.5 * abs(sum(xs[i][0] * xs[(i + 1) % len(xs)][1] - xs[(i + 1) % len(xs)][0] * xs[i][1]
                             for i in range(len(xs))))
        for k in c:
            mass[k] += area / len(c)
    m = sum(mass)
    cx = [sum(mass[k] * X_ref[k][i] for k in range(len(points))) / m for i in range(2)]
    cp = [sum(mass[k] * points[k][i] for k in range(len(points))) / m for i in range(2)]
    num = den = 0.0
    for k in range(len(points)):
        x = (X_ref[k][0] - cx[0], X_ref[k][1] - cx[1])
        p = (points[k][0] - cp[0], points[k][1] - cp[1])
        num += mass[k] * (p[0] * -x[1] + p[1] * x[0])  # phi . Pi x, Pi x = (-x_y, x_x)
        den += mass[k] * (p[0] * x[0] + p[1] * x[1])
    return math.atan2(num, den)


def nonlinear(stickslip, dt, end, sets):
    """The driver's SVK midpoint run of corot-ball-on-plane-nonlinear.yaml with overrides: (ok, history rows,
    theta at the end, cpu)."""
    with tempfile.TemporaryDirectory() as out:
        cmd = [stickslip, "run", "scenes/corot-ball-on-plane-nonlinear.yaml", "--out", out, "--set",
               f"time.dt={dt!r}", "--set", f"time.end={end!r}", "--set", "time.max_cuts=0", "--set",
               "output.vtu_every=0"]
        for s in sets:
            cmd += ["--set", s]
        proc, cpu = run_cpu(cmd)
        if not os.path.exists(os.path.join(out, "history.csv")):
            return False, [], float("nan"), cpu
        res = stickslip_results.Results(out)
        rows = list(csv.DictReader(open(os.path.join(out, "history.csv"))))
        ok = proc.returncode == 0 and abs(float(rows[-1]["time"]) - end) < 1e-9 * max(1.0, end)
        theta = float("nan")
        if ok:
            points, disp, cells = vtu_mesh(res.last_vtu())
            X_ref = [(p[0] - d[0], p[1] - d[1]) for p, d in zip(points, disp)]
            theta = tisserand_angle(points, X_ref, cells)
        return ok, rows, theta, cpu


def unwrap(theta, expected):
    """theta (in (-pi, pi]) moved by multiples of 2 pi next to the expected angle."""
    return theta + 2 * math.pi * round((expected - theta) / (2 * math.pi))


BALL = "scenes/corot-ball-on-plane.yaml"
TWO_PLANES = "scenes/corot-ball-two-planes.yaml"


def setup_cpu(stickslip, scheme):
    """CPU of a one-step run (start-up and meshing), the least of three."""
    best = float("inf")
    for _ in range(3):
        if scheme == "nonlinear":
            cpu = nonlinear(stickslip, 0.002, 0.002, [])[3]
        else:
            cpu = corot(stickslip, BALL, int(scheme[-1]), 0.002, 0.002, [])[2]
        best = min(best, cpu)
    return best


def ball_on_plane(stickslip, dts, end, ref_dt):
    """Sec. 6.3 frictionless: energy and angle errors, Newton iterations and CPU time per scheme and dt. The angle
    error of a scheme is against its own run at ref_dt."""
    rows = []
    for scheme in ("model-1", "model-2", "nonlinear"):
        setup = setup_cpu(stickslip, scheme)
        results = {}
        for dt in [ref_dt] + dts:
            if scheme == "nonlinear":
                ok, hist, theta, cpu = nonlinear(stickslip, dt, end, [])
                E = [float(r["total_energy"]) for r in hist]
                newton = history_iterations(hist)
            else:
                ok, hist, cpu, newton = corot(stickslip, BALL, int(scheme[-1]), dt, end, [])
                E = [r["E"] for r in hist]
                theta = hist[-1]["theta"] if ok else float("nan")
            energy = max(abs(e - E[0]) / E[0] for e in E) if ok else float("nan")
            results[dt] = [ok, theta, energy, newton, cpu]
            print(f"  ball on plane {scheme} dt {dt}: ok {ok}, theta {theta:.10f}, energy {energy:.2e}, "
                  f"cpu {cpu:.2f} s", flush=True)
        theta_ref = unwrap(results[ref_dt][1], 2.0 * end)
        for dt in dts:
            ok, theta, energy, newton, cpu = results[dt]
            error = abs(unwrap(theta, theta_ref) - theta_ref) if ok else float("nan")
            rows.append({"scheme": scheme, "dt": dt, "ok": int(ok), "angle_error": error, "energy_error": energy,
                         "newton_iterations": newton, "cpu_seconds": cpu, "stepping_cpu": max(cpu - setup, 0.0)})
    return rows


def high_spin(stickslip, spins, dts, end):
    """The 6.4 ball (R 1, rho 2) in free flight at theta'_0: does every step converge (no step cut), and how far is
    theta(end) from theta'_0 end (the exact steady rotation)?"""
    rows = []
    for spin in spins:
        for dt in dts:
            for scheme in ("model-1", "model-2", "nonlinear"):
                spin_set = f"bodies.0.angular_velocity=[0,0,{spin!r}]"
                if scheme == "nonlinear":
                    ok, hist, theta, cpu = nonlinear(stickslip, dt, end, [
                        "mesh.parameters.radius=1", "bodies.0.material.density=2", spin_set, "contact=[]"])
                    E = [float(r["total_energy"]) for r in hist]
                else:
                    ok, hist, cpu, _ = corot(stickslip, TWO_PLANES, int(scheme[-1]), dt, end, [spin_set, "contact=[]"])
                    E = [r["E"] for r in hist]
                    theta = hist[-1]["theta"] if ok else float("nan")
                exact = spin * end
                error = abs(unwrap(theta, exact) - exact) if ok else float("nan")
                energy = max(abs(e - E[0]) / E[0] for e in E) if ok and E else float("nan")
                rows.append({"spin": spin, "dt": dt, "scheme": scheme, "ok": int(ok), "angle_error": error,
                             "energy_error": energy, "cpu_seconds": cpu})
                print(f"  spin {spin} dt {dt} {scheme}: ok {ok}, angle error {error:.2e}, energy {energy:.2e}",
                      flush=True)
    return rows


def write_csv(path, rows):
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)


def plot(bop_csv, spin_csv, png):
    script = f"""
set datafile separator ','
set terminal pngcairo size 1500,480 font ',10'
set output '{png}'
set multiplot layout 1,3
set logscale xy
set grid
set key bottom right
set title 'Ball on plane (6.3): angle error at t = 0.06 vs CPU time'
set xlabel 'CPU seconds of the time stepping (loaded machine)'
set ylabel '|theta - theta(dt = ref)|'
plot '< grep model-1 {bop_csv}' using 8:4 with linespoints title 'co-rotational Model 1', \
     '< grep model-2 {bop_csv}' using 8:4 with linespoints title 'Model 2', \
     '< grep nonlinear {bop_csv}' using 8:4 with linespoints title 'nonlinear SVK midpoint + penalty'
set title 'Ball on plane: energy error over the run'
set xlabel 'dt'
set ylabel 'max |E - E_0| / E_0'
set key center right
set yrange [1e-16:1]
plot '< grep model-1 {bop_csv}' using 2:5 with linespoints title 'Model 1', \
     '< grep model-2 {bop_csv}' using 2:5 with linespoints title 'Model 2', \
     '< grep nonlinear {bop_csv}' using 2:5 with linespoints title 'nonlinear'
unset yrange
set title "Free spin, theta'_0 = 200 (6.4 ball): angle error at t = 0.2"
set xlabel 'dt'
set ylabel '|theta - theta_0 t| (errors of exactly 0 not drawn)'
set key center right
set yrange [1e-16:10]
plot '< grep "^200" {spin_csv} | grep model-1' using 2:5 with linespoints title 'Model 1', \
     '< grep "^200" {spin_csv} | grep model-2' using 2:5 with linespoints title 'Model 2', \
     '< grep "^200" {spin_csv} | grep nonlinear' using 2:5 with linespoints title 'nonlinear'
unset multiplot
"""
    subprocess.run(["gnuplot"], input=script, text=True, check=True, cwd=ROOT)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--stickslip", default=os.path.join(ROOT, "build", "bin", "stickslip"))
    parser.add_argument("--quick", action="store_true", help="fewer dt (a smoke run)")
    parser.add_argument("--plot-only", action="store_true", help="redraw the plot from the CSV files")
    args = parser.parse_args()
    if args.plot_only:
        plot(os.path.join(HERE, "ball-on-plane.csv"), os.path.join(HERE, "high-spin.csv"),
             os.path.join(ROOT, "docs", "img", "corot-bench.png"))
        return
    args.stickslip = os.path.abspath(args.stickslip)
    dts = [0.004, 0.002, 0.001] if args.quick else [0.008, 0.004, 0.002, 0.001, 0.0005]
    bop = ball_on_plane(args.stickslip, dts, 0.064, 0.00025 if not args.quick else 0.0005)
    bop_csv = os.path.join(HERE, "ball-on-plane.csv")
    write_csv(bop_csv, bop)
    spin_dts = [0.001, 0.01] if args.quick else [0.0005, 0.001, 0.002, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2]
    spin = high_spin(args.stickslip, [20.0, 200.0], spin_dts, 0.2)
    spin_csv = os.path.join(HERE, "high-spin.csv")
    write_csv(spin_csv, spin)
    plot(bop_csv, spin_csv, os.path.join(ROOT, "docs", "img", "corot-bench.png"))


if __name__ == "__main__":
    main()
