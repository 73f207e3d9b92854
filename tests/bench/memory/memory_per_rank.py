#!/usr/bin/env python3
"""Reads the /usr/bin/time -v reports of memory_per_rank.sh (time-NP-RANK.txt) and prints the peak RSS per rank
against the number of ranks, the least-squares fit of the largest rank's peak to M(p) = a + b/p (a: what every rank
holds whatever p, b: what is divided over the ranks) and its value at 256 ranks."""
import glob
import os
import re
import sys


def peak_kb(path):
    with open(path) as f:
        match = re.search(r"Maximum resident set size \(kbytes\): (\d+)", f.read())
    return int(match.group(1)) if match else None


folder = sys.argv[1]
rows = []
for np in (1, 2, 4):
    peaks = [peak_kb(p) for p in sorted(glob.glob(os.path.join(folder, "time-%d-*.txt" % np)))]
    peaks = [p for p in peaks if p]
    if not peaks:
        continue
    rows.append((np, max(peaks) / 1024.0, sum(peaks) / len(peaks) / 1024.0))
print("ranks  largest peak RSS per rank (MiB)  mean (MiB)  all ranks (MiB)")
for np, largest, mean in rows:
    print("%5d  %31.1f  %10.1f  %15.1f" % (np, largest, mean, mean * np))
if len(rows) >= 2:
    # least squares for largest = a + b / p
    xs = [1.0 / r[0] for r in rows]
    ys = [r[1] for r in rows]
    n = len(xs)
    mx, my = sum(xs) / n, sum(ys) / n
    b = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)
    a = my - b * mx
    print("fit: M(p) = %.1f + %.1f / p MiB  ->  M(256) = %.1f MiB per rank, %.1f GiB over 256 ranks"
          % (a, b, a + b / 256, 256 * (a + b / 256) / 1024))
