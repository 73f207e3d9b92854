"""Self contact in mortar-dual (docs/plugins/mortar-dual.md section 3.6: the surface split into a slave and a master
side per step), on scenes/ring-crush-2d.yaml with its self pair `inner-self` run by mortar-dual (the plates stay
penalty-nts): a thin ring (radii 0.9 and 1, E 1e4, nu 0.3) crushed between two plates until its inner surface folds
onto itself.

- mortar_ring_crush_self_contact: with the self pair the inner surface's halves enter each other by at most 1.5e-4
  (measured 1.07e-4, the deepest of either half into the other over the run: the mortar constraint holds the
  weighted gap, the pointwise penetration left is the interpolation's; penalty-nts's self pair on the same scene
  1.56e-3); the slave side holds one half's nodes in contact (45 of 96 measured), the other half is its master;
  without the pair the walls pass through each other by more than 100 times the bound (0.052).
- mortar_self_contact_condensed: strategy `condensed` on the self pair (the nodes on no master-side face condensed,
  the others kept) gives the saddle-point result: the plates' reactions equal to 1e-12, the same Newton iterations.

Penetration is measured on the output geometry: each inner node of one half (by reference y) against the polyline
of the other half's inner nodes at the same x, every output step."""
import os

from stickslip_results import main, run
from test_self_contact import SCENE, penetrations, without_self_pair

MORTAR_SELF = ("--set", "contact.2.plugin=mortar-dual")


def self_points(result):
    """Active points of the self pair (contact.csv pair 2) at the last step."""
    return sum(1 for r in result.contact_points() if r["pair"] == 2 and r["state"] != 0)


def mortar_ring_crush_self_contact(checks):
    with_pair, _ = run(SCENE, *MORTAR_SELF)
    path = without_self_pair()
    without, _ = run(path)
    os.remove(path)
    deep_with, deep_without = max(penetrations(with_pair.folder)), max(penetrations(without.folder))
    active = self_points(with_pair)
    checks.check(with_pair.rows[-1]["time"] == 1.0, "the crush ran to t = 1 (t = %g)" % with_pair.rows[-1]["time"])
    checks.check(30 <= active <= 60, "one half of the inner surface (96 nodes) is the slave side in contact at the "
                 "end: %d active nodes of the self pair" % active)
    checks.check(deep_with <= 1.5e-4, "with mortar self contact the inner surface enters itself by %.3g <= 1.5e-4 "
                 "(measured 1.07e-4)" % deep_with)
    checks.check(deep_without > 100 * 1.5e-4, "without the self pair the walls pass through each other: %.3g > "
                 "1.5e-2" % deep_without)


def mortar_self_contact_condensed(checks):
    saddle, _ = run(SCENE, *MORTAR_SELF)
    condensed, _ = run(SCENE, *MORTAR_SELF, "--set", "contact.2.strategy=condensed")
    for key in ("reaction_top_y", "reaction_floor_y"):
        a, b = saddle.rows[-1][key], condensed.rows[-1][key]
        checks.check(abs(a - b) <= 1e-12 * abs(a), "%s: condensed %.15g = saddle-point %.15g" % (key, b, a))
    iterations = [sum(r["newton_iterations"] for r in res.rows) for res in (saddle, condensed)]
    checks.check(iterations[0] == iterations[1], "the same Newton iterations: %d and %d" % tuple(iterations))
    checks.check(self_points(saddle) == self_points(condensed) > 0, "the same active nodes of the self pair: %d, %d" %
                 (self_points(saddle), self_points(condensed)))


if __name__ == "__main__":
    main([mortar_ring_crush_self_contact, mortar_self_contact_condensed])
