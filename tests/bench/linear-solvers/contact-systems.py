"""Table and fitted exponents of docs/linear-solvers-contact.csv (contact-systems.sh).
   python3 tests/bench/linear-solvers/contact-systems.py docs/linear-solvers-contact.csv"""
import csv
import math
import sys

rows = list(csv.DictReader(open(sys.argv[1] if len(sys.argv) > 1 else "docs/linear-solvers-contact.csv")))
print("| unknowns | constraint rows | solver | GMRES iterations | set-up + solve [s CPU] | re-solve [s CPU] | "
      "difference from MUMPS |")
print("|---:|---:|:--|---:|---:|---:|---:|")
for r in rows:
    failed = r["failed"] == "1"
    print("| %s | %s | %s | %s | %s | %s | %s |" % (
        r["unknowns"], r["constraints"], r["solver"], r["iterations"] if not failed else "%s (failed)" % r["iterations"],
        r["first_cpu"] if not failed else "–", r["resolve_cpu"] if not failed else "–",
        r["difference"] if not failed and r["solver"] != "mumps" else "–"))
print()
for solver in sorted({r["solver"] for r in rows if r["failed"] == "0"}):
    points = {}
    for r in rows:  # mean over the systems of one size
        if r["solver"] == solver and r["failed"] == "0":
            points.setdefault(int(r["unknowns"]), []).append(float(r["resolve_cpu"]))
    pts = [(math.log(n), math.log(sum(t) / len(t))) for n, t in points.items() if min(t) > 0]
    if len(pts) < 3:
        continue
    mx = sum(p[0] for p in pts) / len(pts)
    my = sum(p[1] for p in pts) / len(pts)
    slope = sum((p[0] - mx) * (p[1] - my) for p in pts) / sum((p[0] - mx) ** 2 for p in pts)
    print("%s: re-solve CPU time ~ unknowns^%.2f (%d sizes)" % (solver, slope, len(pts)))
