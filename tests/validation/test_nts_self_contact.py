"""nts-augmented with self contact and among many bodies.

- nts_ring_crush_self_contact: scenes/ring-crush-2d.yaml with every pair on nts-augmented. The self pair `inner-self`
  holds the gap exactly: one side of the fold carries the constraints (docs/plugins/nts-augmented.md, self contact),
  its nodes stay on the other side's polyline to round-off (<= 1e-9 h) and the pair's largest |g| over its active
  points (history.csv constraint_violation) stays at round-off; the other side's nodes are master nodes, which
  node-to-surface lets enter the slave faces between slave nodes: they do so by less than penalty-nts's bound on the
  same scene (the mean pressure the plates transmit over penalty-nts's computed penalty, tests/validation/
  test_self_contact.py). Without the pair the walls pass through each other by more than ten times that bound.

Penetration is measured on the output geometry: each inner node of one half against the polyline of the other
half's inner nodes at the same x (every output step), both ways."""
import math
import os

from stickslip_results import ROOT, main, read_vtu, run
from stickslip_compare.results import collection
from test_self_contact import E, NU, N_AROUND, R_INNER, R_OUTER, SCENE, without_self_pair


def penetrations(folder):
    """Largest depth of a top-half inner node below the bottom half's inner polyline, and of a bottom-half inner node
    above the top half's, over the output steps."""
    worst = [-math.inf, -math.inf]
    for _, name in collection(folder):
        vtu = read_vtu(os.path.join(folder, name))
        halves = ([], [])
        for p, u in zip(vtu["Points"], vtu["displacement"]):
            X = (p[0] - u[0], p[1] - u[1])
            if abs(math.hypot(*X) - R_INNER) < 1e-6:
                halves[0 if X[1] > 0 else 1].append((p[0], p[1]))
        for side, sign in ((0, 1.0), (1, -1.0)):
            other = sorted(halves[1 - side])
            for x, y in halves[side]:
                for (x0, y0), (x1, y1) in zip(other, other[1:]):
                    if x0 <= x <= x1 and x1 > x0:
                        worst[side] = max(worst[side], sign * (y0 + (x - x0) * (y1 - y0) / (x1 - x0) - y))
    return worst


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


if __name__ == "__main__":
    main([nts_ring_crush_self_contact])
