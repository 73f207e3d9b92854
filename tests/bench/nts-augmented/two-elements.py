#!/usr/bin/env python3
"""Benchmark: the strategies of nts-augmented on Table I (scenes/two-elements.yaml: midpoint, mu 0.5, epsilon_t 1e4):
Newton iterations, linear system size, invariants and the difference of each strategy's history to condensed;
then the scene's default run (dt 0.2, T 20: Fig. 8) and backward Euler at dt 0.005 (Fig. 7's setting), condensed
against direct-endpoint. Usage: python3 tests/bench/nts-augmented/two-elements.py -> table on stdout"""
import math

from common import run

SCENE = "scenes/two-elements.yaml"
STRATEGIES = ("condensed", "augmented", "paper-reduced", "direct", "direct-endpoint")
COLUMNS = ("total_energy", "kinetic_energy", "dissipated_energy", "contact_force_y", "contact_force_z",
           "angular_momentum_x")


def drift(rows, prefix):
    ref = [rows[0][prefix + c] for c in "xyz"]
    norm = math.sqrt(sum(v * v for v in ref))
    return max(math.sqrt(sum((r[prefix + c] - ref[i]) ** 2 for i, c in enumerate("xyz"))) for r in rows) / norm


def difference(a, b):
    """max over COLUMNS of max_t |a - b| relative to the column's largest magnitude (energies: to E0)."""
    worst = 0.0
    for name in COLUMNS:
        x, y = a.column(name), b.column(name)
        if len(x) != len(y):
            return float("inf")
        scale = a.rows[0]["total_energy"] if name.endswith("energy") else max(max(abs(v) for v in x), 1e-300)
        worst = max(worst, max(abs(p - q) for p, q in zip(x, y)) / scale)
    return worst


def table(title, args, strategies):
    print("\n%s: %s" % (title, " ".join(args)))
    print("| strategy | steps | Newton iterations | linear system | E end | dissipated | p, L drift | max \\|Phi\\| "
          "| history vs condensed | wall s |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    ref = None
    for s in strategies:
        r = run(SCENE, "two-elements-%s-%s" % (title.replace(" ", "-"), s), *args, "--set", "contact.0.strategy=" + s)
        ref = ref or r
        print("| %s | %d | %d | %d | %.6f | %.4f | %.0e, %.0e | %.0e | %s | %.2f |" % (
            s, r.summary["steps"], r.summary["newton_iterations"], r.summary["linear_system_size"],
            r.rows[-1]["total_energy"], r.rows[-1]["dissipated_energy"], drift(r.rows, "momentum_"),
            drift(r.rows, "angular_momentum_"), max(x["constraint_violation"] for x in r.rows),
            "-" if r is ref else "%.1e" % difference(ref, r), r.summary["wall_seconds"]), flush=True)


table("midpoint dt 0.05 T 6", ("--set", "time.dt=0.05", "--set", "time.end=6"), STRATEGIES)
table("midpoint dt 0.2 T 20", (), ("condensed",))
table("backward Euler dt 0.005 T 6", ("--set", "time.dt=0.005", "--set", "time.end=6",
                                       "--set", "time.scheme=backward-euler"), ("condensed", "direct-endpoint"))
