#!/usr/bin/env python3
"""Splits the slave's contact force of a finished 2D mortar-dual run into the sum of the nodal normal forces and
the sum of the nodal tangential forces (contact.csv of the last state): |F_x| / |F_y| of the total may exceed mu
while every slipping node holds |t_j| = mu p_j exactly, because the nodal normals tilt (docs/plugins/mortar-dual.md,
section 10). Usage: coulomb_resultant.py RESULTS_DIR (written by `stickslip run ... --set output.contact_csv=true
--out RESULTS_DIR`)."""
import csv
import math
import os
import sys


def main(directory):
    rows = list(csv.DictReader(open(os.path.join(directory, "contact.csv"))))
    last = max(int(p["step"]) for p in rows)
    points = [p for p in rows if int(p["step"]) == last]  # contact.csv has every output step: the last state
    normal, tangential, worst = [0.0, 0.0], [0.0, 0.0], 0.0
    for p in points:
        pressure, area = float(p["pressure"]), float(p["area"])
        t = (float(p["traction_x"]), float(p["traction_y"]))
        if int(p["state"]) == 2 and pressure > 0:
            worst = max(worst, math.hypot(*t) / pressure)
        for i, axis in enumerate("xy"):
            normal[i] += float(p["normal_force"]) * float(p["normal_" + axis])
            tangential[i] += area * t[i]
    total = [normal[i] + tangential[i] for i in range(2)]
    print("slipping nodes: max |t_j| / p_j = %.6f" % worst)
    print("sum of normal forces (%.3f, %.3f), of tangential forces (%.3f, %.3f)" % (*normal, *tangential))
    print("|sum tangential| / |sum normal| = %.6f" % (math.hypot(*tangential) / math.hypot(*normal)))
    print("total (%.3f, %.3f): |F_x| / |F_y| = %.6f" % (*total, abs(total[0] / total[1])))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
