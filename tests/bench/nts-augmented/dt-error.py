#!/usr/bin/env python3
"""Benchmark (b): run time against error for the Table I two-element scene (scenes/two-elements.yaml), midpoint
against backward Euler, over dt. Error: z of node 8 (paper numbering; stickslip node 7) and the max nodal
displacement difference at T = 3.2 (sliding contact) against a run of the same scheme at dt = 0.0004 (the two
schemes converge to different motions: the midpoint impact at t = 2.5 keeps the energy, backward Euler's dissipates;
their dt = 0.0004 runs differ by the "midpoint vs backward Euler" line in the output).
Usage: python3 tests/bench/nts-augmented/dt-error.py   -> tests/bench/nts-augmented/dt-error.csv, docs/img/nts-dt-error.png"""
import math
import os

from common import OUT, ROOT, gnuplot, run, write_csv

SCENE = "scenes/two-elements.yaml"
T = 3.2
DTS = [0.2, 0.1, 0.05, 0.025, 0.0125, 0.00625, 0.003125, 0.0015625]
REF_DT = 0.0004


def final(scheme, dt):
    steps = int(round(T / dt))
    # the reference with KLU: at dt 0.0004 the first touch (t = 2.5, four nodes active with lambda_n = 0) gives a
    # saddle-point matrix whose Schur pivots (~4e-9) sit 1e-18 below its mass pivots (2.7e9), and MUMPS calls it
    # singular (docs/plugins/nts-augmented.md); KLU solves it
    solver = ("--set", "solver.linear.solver=klu") if dt == REF_DT else ()
    r = run(SCENE, "dt-%s-%g" % (scheme, dt), "--set", "time.scheme=" + scheme, "--set", "time.dt=%r" % dt,
            "--set", "time.end=%r" % T, "--set", "output.vtu_every=%d" % steps, *solver)
    if r is None or r.summary["status"] != "ok":
        return None
    vtu = r.last_vtu()
    return vtu["Points"], r.summary


refs = {scheme: final(scheme, REF_DT) for scheme in ("midpoint", "backward-euler")}
rows = []
for scheme in ("midpoint", "backward-euler"):
    ref_points, ref_summary = refs[scheme]
    for dt in DTS:
        out = final(scheme, dt)
        if out is None:
            rows.append([scheme, dt, "nan", "nan", "nan", "nan", "failed"])
            continue
        points, s = out
        ez = abs(points[7][2] - ref_points[7][2])
        ex = max(math.dist(p, q) for p, q in zip(points, ref_points))
        rows.append([scheme, dt, "%.6e" % ez, "%.6e" % ex, "%.6f" % s["wall_seconds"], s["newton_iterations"], "ok"])
csv_path = os.path.join(ROOT, "tests", "bench", "nts-augmented", "dt-error.csv")
write_csv(csv_path, ["scheme", "dt", "error_z8", "error_max_node", "wall_seconds", "newton_iterations", "status"], rows)
for scheme, (points, summary) in refs.items():
    print("reference: %s dt %g, z8(T=%g) = %.12f, %.2f s" % (scheme, REF_DT, T, points[7][2], summary["wall_seconds"]))
a, b = refs["midpoint"][0], refs["backward-euler"][0]
print("midpoint vs backward Euler at dt %g: z8 differs by %.3e, max node by %.3e"
      % (REF_DT, abs(a[7][2] - b[7][2]), max(math.dist(p, q) for p, q in zip(a, b))))
png = os.path.join(ROOT, "docs", "img", "nts-dt-error.png")
gnuplot("""
set terminal pngcairo size 1100,480 font ',10'
set output '%(png)s'
set datafile separator ','
set multiplot layout 1,2 title 'Table I two elements, T = %(T)g: error against the same scheme at dt = %(ref)g'
set logscale xy; set grid; set key bottom right
set xlabel 'dt'; set ylabel 'error'
plot '%(csv)s' u (strcol(1) eq 'midpoint' ? $2 : 1/0):4 w lp pt 7 t 'midpoint, max node', \
     '' u (strcol(1) eq 'midpoint' ? $2 : 1/0):3 w lp pt 6 t 'midpoint, z node 8', \
     '' u (strcol(1) eq 'backward-euler' ? $2 : 1/0):4 w lp pt 5 t 'backward Euler, max node', \
     '' u (strcol(1) eq 'backward-euler' ? $2 : 1/0):3 w lp pt 4 t 'backward Euler, z node 8', \
     x**2 w l dt 2 lc 'gray' t 'dt^2', x w l dt 3 lc 'gray' t 'dt'
set xlabel 'wall time [s]'; set ylabel 'error (max node)'
plot '%(csv)s' u (strcol(1) eq 'midpoint' ? $5 : 1/0):4 w lp pt 7 t 'midpoint', \
     '' u (strcol(1) eq 'backward-euler' ? $5 : 1/0):4 w lp pt 5 t 'backward Euler'
unset multiplot
""" % {"png": png, "csv": csv_path, "T": T, "ref": REF_DT})
print("wrote " + png)
