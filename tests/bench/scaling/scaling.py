#!/usr/bin/env python3
"""Strong and weak scaling of stickslip over MPI ranks (docs/scaling.md).

Strong scaling runs one fixed scene on each number of ranks; weak scaling runs the two-tori scene with its meshes
refined with the ranks (about the same number of elements per rank). Every run sets STICKSLIP_RANK_STATS, so each
rank reports what it holds, the bytes it sent point to point (ghost exchanges and the linear system's off-rank
entries), its Newton iterations, CPU seconds, peak resident memory and the phases' wall seconds (core/time/run.c).
Writes OUT/scaling.csv (one row per run) and OUT/scaling.png (gnuplot), and prints the table and the fit
M(p) = a + b/p of the largest peak RSS per rank of the strong runs.

Above 2 ranks on a 2-core machine the runs are oversubscribed (--oversubscribe): their wall times are not speed-ups;
memory, bytes and ghost sizes do not depend on it.

Example (a few minutes on 2 cores):
  tests/bench/scaling/scaling.py --out /tmp/scaling
  tests/bench/scaling/scaling.py --strong scenes/two-tori.yaml --strong-set mesh.0.parameters.refine=1 \\
      --strong-set mesh.1.parameters.refine=1 --steps 1 --only strong --out /tmp/full"""
import argparse
import csv
import glob
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
COLUMNS = ["mode", "ranks", "refine", "elements", "unknowns", "steps", "newton_iterations", "wall_seconds",
           "cpu_seconds_max", "cpu_seconds_mean", "peak_rss_mib_max", "peak_rss_mib_mean",
           "bytes_per_rank_per_newton_mean", "bytes_per_rank_per_newton_max", "exchange_bytes_per_newton_mean",
           "linear_system_bytes_per_newton_mean", "owned_nodes_mean", "ghost_nodes_mean",
           "ghost_nodes_max", "ghost_elements_mean", "assembly_share", "contact_share", "solve_share"]


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], epilog=__doc__.split("\n\n", 1)[1],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--ranks", default="1,2,4,8", help="numbers of ranks, comma separated (default 1,2,4,8)")
    p.add_argument("--strong", default="scenes/two-tori.yaml", help="the strong-scaling scene (default two-tori)")
    p.add_argument("--strong-set", action="append", default=None, metavar="KEY=VALUE",
                   help="--set overrides of the strong scene (default: both tori at refine 0.5, 2006 elements)")
    p.add_argument("--weak-refine", default="1:0.25,2:0.36,4:0.52,8:0.73", metavar="P:R,...",
                   help="the two tori's mesh refine per number of ranks for weak scaling (default "
                        "1:0.25,2:0.36,4:0.52,8:0.73: 540, ~1100, ~2200, ~4300 hex8 elements)")
    p.add_argument("--steps", type=int, default=5, help="steps per run (default 5: the tori touch in step 4)")
    p.add_argument("--solver", default="direct", help="solver.linear.solver of every run (default direct: "
                   "the same linear solver on every number of ranks)")
    p.add_argument("--only", choices=("strong", "weak"), help="run one of the two studies")
    p.add_argument("--bin", default=os.path.join(ROOT, "build", "bin", "stickslip"), help="the stickslip binary")
    p.add_argument("--mpirun", default=shutil.which("mpirun") or "mpirun", help="the MPI launcher")
    p.add_argument("--out", required=True, help="folder for scaling.csv and scaling.png")
    p.add_argument("--plot-only", action="store_true", help="re-plot OUT/scaling.csv without running")
    return p.parse_args()


def run_case(args, mode, ranks, refine, sets):
    """One run under mpirun; its row from the ranks' statistics."""
    work = tempfile.mkdtemp(prefix="stickslip-scaling-")
    command = [args.bin, "run", os.path.join(ROOT, args.strong if mode == "strong" else "scenes/two-tori.yaml"),
               "--quiet", "--steps", str(args.steps), "--set", "solver.linear.solver=" + args.solver]
    for s in sets:
        command += ["--set", s]
    # one rank under mpirun too: every run starts the same way
    command = [args.mpirun, "--allow-run-as-root", "--oversubscribe", "-np", str(ranks)] + command
    env = dict(os.environ, STICKSLIP_RANK_STATS=os.path.join(work, "rank"), OMPI_ALLOW_RUN_AS_ROOT="1",
               OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    start = time.monotonic()
    proc = subprocess.run(command, env=env, capture_output=True, text=True)
    wall = time.monotonic() - start
    stats = [json.load(open(p)) for p in sorted(glob.glob(os.path.join(work, "rank-*.json")))]
    shutil.rmtree(work, ignore_errors=True)
    if proc.returncode != 0 or len(stats) != ranks:
        sys.exit("scaling: %s failed (exit %d, %d rank reports):\n%s" % (" ".join(command), proc.returncode,
                                                                           len(stats), proc.stderr[-2000:]))
    mean = lambda key: sum(s[key] for s in stats) / len(stats)  # noqa: E731
    newton = max(stats[0]["newton_iterations"], 1)
    sent = [(s["exchange_bytes_sent"] + s["linear_system_bytes_sent"]) / newton for s in stats]
    root = stats[0]
    return {
        "mode": mode, "ranks": ranks, "refine": refine, "elements": sum(s["elements_owned"] for s in stats),
        "unknowns": sum(s["unknowns_owned"] for s in stats), "steps": root["steps"],
        "newton_iterations": root["newton_iterations"], "wall_seconds": round(wall, 2),
        "cpu_seconds_max": round(max(s["cpu_seconds"] for s in stats), 2),
        "cpu_seconds_mean": round(mean("cpu_seconds"), 2),
        "peak_rss_mib_max": round(max(s["peak_rss_kib"] for s in stats) / 1024, 1),
        "peak_rss_mib_mean": round(mean("peak_rss_kib") / 1024, 1),
        "bytes_per_rank_per_newton_mean": round(sum(sent) / len(sent)),
        "bytes_per_rank_per_newton_max": round(max(sent)),
        "exchange_bytes_per_newton_mean": round(mean("exchange_bytes_sent") / newton),
        "linear_system_bytes_per_newton_mean": round(mean("linear_system_bytes_sent") / newton),
        "owned_nodes_mean": round(mean("nodes_owned"), 1), "ghost_nodes_mean": round(mean("nodes_ghost"), 1),
        "ghost_nodes_max": max(s["nodes_ghost"] for s in stats),
        "ghost_elements_mean": round(mean("elements_held") - mean("elements_owned"), 1),
        "assembly_share": round(root["assembly_seconds"] / max(root["wall_seconds"], 1e-9), 3),
        "contact_share": round(root["contact_seconds"] / max(root["wall_seconds"], 1e-9), 3),
        "solve_share": round(root["solve_seconds"] / max(root["wall_seconds"], 1e-9), 3),
    }


def fit(rows):
    """Least squares of the largest peak RSS per rank to a + b/p over the rows."""
    xs, ys = [1.0 / int(r["ranks"]) for r in rows], [float(r["peak_rss_mib_max"]) for r in rows]
    if len(xs) < 2:
        return None
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    b = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)
    return my - b * mx, b


def plot(out, rows):
    data = os.path.join(out, "scaling.dat")
    with open(data, "w") as f:
        for mode in ("strong", "weak"):
            f.write("# %s\n" % mode)
            for r in rows:
                if r["mode"] == mode:
                    f.write("%s %s %s %s %s %s %s %s %s\n" % (
                        r["ranks"], r["wall_seconds"], r["cpu_seconds_max"], r["peak_rss_mib_max"],
                        r["bytes_per_rank_per_newton_mean"], r["ghost_nodes_mean"], r["owned_nodes_mean"],
                        r["exchange_bytes_per_newton_mean"], r["linear_system_bytes_per_newton_mean"]))
            f.write("\n\n")
    script = """
set terminal pngcairo size 1200,900 font ",11"
set output "%s"
set multiplot layout 2,2 title "stickslip scaling (two tori; oversubscribed above 2 ranks on 2 cores)"
set logscale x 2
set xlabel "ranks"
set key top left
set grid
set title "wall and CPU seconds (largest rank)"
plot "%s" index 0 using 1:2 with linespoints title "strong: wall", "" index 0 using 1:3 with linespoints title "strong: CPU", \\
     "" index 1 using 1:2 with linespoints title "weak: wall", "" index 1 using 1:3 with linespoints title "weak: CPU"
set title "peak RSS per rank (largest), MiB"
set yrange [0:*]
plot "%s" index 0 using 1:4 with linespoints title "strong", "" index 1 using 1:4 with linespoints title "weak"
set title "bytes sent per rank per Newton iteration (mean; none on 1 rank)"
set logscale y
set yrange [*:*]
plot "%s" index 0 using 1:5 with linespoints title "strong: all", \
     "" index 0 using 1:8 with linespoints dashtype 2 title "strong: ghost exchanges", \
     "" index 0 using 1:9 with linespoints dashtype 3 title "strong: linear system", \
     "" index 1 using 1:5 with linespoints title "weak: all", \
     "" index 1 using 1:8 with linespoints dashtype 2 title "weak: ghost exchanges", \
     "" index 1 using 1:9 with linespoints dashtype 3 title "weak: linear system"
unset logscale y
set title "ghost nodes per rank / owned nodes per rank (mean)"
set yrange [0:*]
plot "%s" index 0 using 1:($6/$7) with linespoints title "strong", "" index 1 using 1:($6/$7) with linespoints title "weak"
unset multiplot
""" % (os.path.join(out, "scaling.png"), data, data, data, data)
    proc = subprocess.run(["gnuplot"], input=script, capture_output=True, text=True)
    if proc.returncode != 0:
        print("scaling: gnuplot failed, no plot: %s" % proc.stderr.strip(), file=sys.stderr)


def print_table(rows):
    short = ["mode", "ranks", "refine", "elements", "newton_iterations", "wall_seconds", "cpu_seconds_max",
             "peak_rss_mib_max", "bytes_per_rank_per_newton_mean", "exchange_bytes_per_newton_mean",
             "linear_system_bytes_per_newton_mean", "ghost_nodes_mean", "ghost_elements_mean",
             "assembly_share", "contact_share", "solve_share"]
    print(" ".join("%s" % c for c in short))
    for r in rows:
        print(" ".join(str(r[c]) for c in short))
    strong = [r for r in rows if r["mode"] == "strong"]
    ab = fit(strong)
    if ab:
        print("strong: largest peak RSS per rank fits M(p) = %.1f + %.1f / p MiB" % ab)
    weak = sorted((r for r in rows if r["mode"] == "weak"), key=lambda r: int(r["ranks"]))
    if len(weak) > 1:
        print("weak: peak RSS per rank at %s ranks / at %s: %.2f" % (
            weak[-1]["ranks"], weak[0]["ranks"], float(weak[-1]["peak_rss_mib_max"]) / float(weak[0]["peak_rss_mib_max"])))


def main():
    args = parse_args()
    os.makedirs(args.out, exist_ok=True)
    table = os.path.join(args.out, "scaling.csv")
    if args.plot_only:
        rows = list(csv.DictReader(open(table)))
    else:
        ranks = [int(p) for p in args.ranks.split(",")]
        refine = {int(p): r for p, r in (item.split(":") for item in args.weak_refine.split(","))}
        strong_sets = args.strong_set if args.strong_set is not None else [
            "mesh.0.parameters.refine=0.5", "mesh.1.parameters.refine=0.5"]
        rows = []
        for mode in ("strong", "weak"):
            if args.only and args.only != mode:
                continue
            for p in ranks:
                if mode == "weak" and p not in refine:
                    sys.exit("scaling: --weak-refine has no refine for %d ranks" % p)
                sets = strong_sets if mode == "strong" else [
                    "mesh.0.parameters.refine=" + refine[p], "mesh.1.parameters.refine=" + refine[p]]
                label = ",".join(s.split("=", 1)[1] for s in sets if "refine" in s)
                print("scaling: %s, %d rank(s), %s" % (mode, p, " ".join(sets)), file=sys.stderr, flush=True)
                rows.append(run_case(args, mode, p, label.split(",")[0] if label else "", sets))
                with open(table, "w", newline="") as f:  # complete after every run
                    w = csv.DictWriter(f, fieldnames=COLUMNS)
                    w.writeheader()
                    w.writerows(rows)
    print_table(rows)
    plot(args.out, rows)
    print("scaling: %s, %s" % (table, os.path.join(args.out, "scaling.png")))


if __name__ == "__main__":
    main()
