"""nts-augmented with self contact and among many bodies.

- nts_ring_crush_self_contact: scenes/ring-crush-2d.yaml with every pair on nts-augmented. The self pair `inner-self`
  holds the gap exactly: one side of the fold carries the constraints (docs/plugins/nts-augmented.md, self contact),
  its nodes stay on the other side's polyline to round-off (<= 1e-9 h) and the pair's largest |g| over its active
  points (history.csv constraint_violation) stays at round-off; the other side's nodes are master nodes, which
  node-to-surface lets enter the slave faces between slave nodes: they do so by less than penalty-nts's bound on the
  same scene (the mean pressure the plates transmit over penalty-nts's computed penalty, tests/validation/
  test_self_contact.py). Without the pair the walls pass through each other by more than ten times that bound.

- nts_disk_pile_energy: scenes/disks-in-box-2d.yaml (ten disks dropped into a rigid box, midpoint, mu 0.3, one
  `bodies: all` entry) with nts-augmented, its first 100 steps (t = 0.5: the bottom row lands, the upper rows hit it;
  disk-disk contacts in steps where the floor carries nothing). Energy is never created over the run: at every step
  E_n + D_n <= E_0 + W_n + round-off, with E = total_energy, D = dissipated_energy and W_n the work of gravity,
  g dt (P_y,n + P_y,n+1) / 2 summed (under the midpoint rule M (u_n+1 - u_n) = dt M v_n+1/2, and the body force's
  load vector is M g). The difference is the energy the friction law stores (psi >= 0, not in total_energy) and
  loses at activations; step by step it cannot be asserted with friction, because psi is released in stick. The
  momenta: the box exerts forces on the pile (reaction_<obstacle> is the force the obstacle receives), so the pile's
  momentum changes per step by dt (M g - sum of the box's reactions), to round-off: the disk-disk contacts, internal
  forces, create none.

Penetration is measured on the output geometry: each inner node of one half against the polyline of the other
half's inner nodes at the same x (every output step), both ways."""
import math
import os

from stickslip_results import main, run
from test_self_contact import E, NU, N_AROUND, R_INNER, R_OUTER, SCENE, penetrations, without_self_pair


def nts_ring_crush_self_contact(checks):
    with_pair, _ = run(SCENE, "--plugin", "nts-augmented")
    path = without_self_pair()
    without, _ = run(path, "--plugin", "nts-augmented")
    os.remove(path)
    force = abs(with_pair.rows[-1]["reaction_top_y"])
    h = 2 * R_INNER * math.sin(math.pi / N_AROUND)  # the inner surface's face (chord)
    penalty = 10 * (E / (2 * (1 - NU ** 2))) / h  # penalty-nts's computed penalty on this surface
    bound = force / (math.pi * 0.5 * (R_INNER + R_OUTER)) / penalty
    slave_side, master_side = sorted(penetrations(with_pair.folder))
    deep_without = max(penetrations(without.folder))
    violation = max(row["constraint_violation"] for row in with_pair.rows)
    checks.check(with_pair.rows[-1]["active_points"] > N_AROUND, "the inner surface folded onto itself: %d active "
                 "points at the end (plates and self contact)" % with_pair.rows[-1]["active_points"])
    checks.check(slave_side <= 1e-9 * h, "the slave side's nodes stay on the other wall: penetration %.3g <= 1e-9 h"
                 % slave_side)
    checks.check(violation <= 1e-9 * h, "largest |gap| of an active point %.3g <= 1e-9 h" % violation)
    checks.check(0.0 < master_side <= bound, "the master side's nodes enter the slave faces by %.3g <= penalty-nts's "
                 "bound %.3g" % (master_side, bound))
    checks.check(deep_without > 10 * bound, "without the pair the walls pass through each other: %.3g > 10 x %.3g" %
                 (deep_without, bound))


def gravity_work(rows, g):
    """W_n: the work of the body force g (y) up to each row, from the momentum under the midpoint rule."""
    work = [0.0]
    for a, b in zip(rows, rows[1:]):
        work.append(work[-1] + g * b["dt"] * 0.5 * (a["momentum_y"] + b["momentum_y"]))
    return work


def nts_disk_pile_energy(checks):
    results, _ = run("scenes/disks-in-box-2d.yaml", "--plugin", "nts-augmented", "--steps", "100")
    rows = results.rows
    g = -9.81
    mass = (rows[1]["momentum_y"] - rows[0]["momentum_y"]) / (rows[1]["dt"] * g)  # the first step is free fall
    work = gravity_work(rows, g)
    scale = max(abs(r["total_energy"]) + abs(w) for r, w in zip(rows, work))
    excess = [r["total_energy"] + r["dissipated_energy"] - rows[0]["total_energy"] - w for r, w in zip(rows, work)]
    walls = ("floor", "left", "right")
    imbalance, impulse = 0.0, 0.0
    for a, b in zip(rows, rows[1:]):
        for axis, load in (("x", 0.0), ("y", mass * g)):
            change = b["momentum_" + axis] - a["momentum_" + axis]
            box = sum(b["reaction_%s_%s" % (w, axis)] for w in walls)
            imbalance = max(imbalance, abs(change - b["dt"] * (load - box)))
            impulse = max(impulse, abs(change))
    between_disks = sum(1 for r in rows if r["active_points"] > 0 and all(r["reaction_%s_%s" % (w, axis)] == 0.0
                                                                              for w in walls for axis in "xy"))
    checks.check(rows[-1]["step"] == 100 and between_disks >= 3, "100 steps; %d steps with contacts between disks "
                 "only (the box carries nothing)" % between_disks)
    checks.check(max(excess) <= 1e-12 * scale, "E + D never exceeds E_0 + W: largest excess %.3g <= 1e-12 x %.3g; "
                 "at the end E + D = E_0 + W %+.4g (friction's stored energy and activation losses)"
                 % (max(excess), scale, excess[-1]))
    checks.check(imbalance <= 1e-12 * impulse, "momentum change per step = dt (M g - box reactions) to %.3g (largest "
                 "change %.3g, M = %.6g)" % (imbalance, impulse, mass))
    column = max(abs(r["external_work"] - w) for r, w in zip(rows, work))
    checks.check(column <= 1e-12 * scale, "history.csv's external_work is W_n to %.3g (<= 1e-12 x %.3g)"
                 % (column, scale))


if __name__ == "__main__":
    main([nts_ring_crush_self_contact, nts_disk_pile_energy])
