"""Shared helpers of the nts-augmented benchmarks: run the driver, read results, write CSV, call gnuplot."""
import csv
import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(HERE)))
sys.path.insert(0, os.path.join(ROOT, "tests", "validation"))
from stickslip_results import Results  # noqa: E402

BIN = os.environ.get("STICKSLIP_BIN", os.path.join(ROOT, "build", "bin", "stickslip"))
OUT = os.environ.get("NTS_BENCH_OUT", os.path.join(ROOT, "results", "bench-nts-augmented"))


def run(scene, tag, *args):
    """Runs the driver on scene with args into OUT/tag; returns Results (status may be 'failed')."""
    folder = os.path.join(OUT, tag)
    command = [BIN, "run", os.path.join(ROOT, scene), "--out", folder, "--quiet", *args]
    print("+ " + " ".join(command), flush=True)
    proc = subprocess.run(command, capture_output=True, text=True)
    if proc.returncode != 0:
        print(proc.stderr[-2000:], file=sys.stderr)
    return Results(folder) if os.path.exists(os.path.join(folder, "history.csv")) else None


def write_csv(path, header, rows):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        w.writerows(rows)
    print("wrote " + path)


def gnuplot(script):
    subprocess.run(["gnuplot"], input=script, text=True, check=True)
