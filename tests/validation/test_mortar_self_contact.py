"""Self contact in mortar-dual (docs/plugins/mortar-dual.md section 3.6: the surface split into a slave and a master
side per step), on scenes/ring-crush-2d.yaml with its self pair `inner-self` run by mortar-dual (the plates stay
penalty-nts): a thin ring (radii 0.9 and 1, E 1e4, nu 0.3) crushed between two plates until its inner surface folds
onto itself.

- mortar_ring_crush_self_contact: with the self pair the inner surface's halves enter each other by at most 3e-7
  (measured 1.08e-7, the deepest of either half into the other over the run: the mortar constraint holds the
  weighted gap, the pointwise penetration left is the interpolation's; penalty-nts's self pair on the same scene
  1.56e-3); the slave side holds one half's nodes in contact (45 of 96 measured), the other half is its master;
  without the pair the walls pass through each other by more than 1.5e-2 (0.052).
- mortar_self_contact_condensed: strategy `condensed` on the self pair (the nodes on no master-side face condensed,
  the others kept) gives the saddle-point result: the plates' reactions equal to 1e-12, the same Newton iterations.

- mortar_tube_crush_self_contact: the same in 3D on scenes/tube-crush-3d.yaml (a thin hex8 tube, radii 0.9 and 1,
  flattened by a plate onto a floor until its inner wall meets itself), its self pair `inner-self` by mortar-dual on
  quad4 faces, at a CI size: one layer of elements along a tube 0.125 long (48 around), 10 steps of 0.1. With the pair
  the walls enter each other by at most 3e-8 (measured 1.0e-8: the constraint holds the facing walls' weighted gap,
  the one layer's nodes face each other) and one half's nodes are the slave side in contact (42 of the 96 inner nodes
  measured); without it they pass through each other by 0.063. The full scene (4 layers, 50 steps) and the pair at
  the penalty test's CI size are measured in docs/plugins/mortar-dual.md section 3.6.

- mortar_tube_crush_self_contact_quad9 (long: about 35 s CPU): the same tube on hex27 (`mesh.order: 2`, QUAD9 faces
  of the standard dual basis): it runs to t = 1, the walls enter each other by at most 6e-6 (measured 4.57e-6,
  facing walls beside the fold, where the nodes' polyline the check measures against cuts the curved faces) and
  129 of the 288 inner nodes are the slave side in contact.

- mortar_ring_crush_self_friction: the ring crush with mu 0.3 on the self pair (each step's sides get their D^n,
  M^n at the step's start): it runs to t = 1, the halves enter each other by at most 6e-5 (measured 4.07e-5), the
  slave side holds 30-60 nodes in contact (45 measured), every active node's tangential traction is within the
  Coulomb disc (|t_t| <= mu p) and friction carries load (the largest |t_t| / (mu p) 0.23 measured, > 0.1 asserted;
  0 without friction).

Penetration is measured on the output geometry: each inner node of one half (by reference y) against the polyline
of the other half's inner nodes at the same x (in 3D in each cross-section), every output step (the helpers of
test_self_contact.py)."""
import math
import os

from stickslip_results import main, run
from test_self_contact import SCENE, TUBE, penetrations, self_pair_active, without_self_pair

MORTAR_SELF = ("--set", "contact.2.plugin=mortar-dual")
# the tube at its smallest: one element layer along 0.125 (the scene's layer), 10 steps
TUBE_SMALL = ("--set", "mesh.parameters.length=0.125", "--set", "mesh.parameters.n_length=1", "--set", "time.dt=0.1",
              "--set", "output.vtu_every=1")


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
    checks.check(deep_with <= 3e-7, "with mortar self contact the inner surface enters itself by %.3g <= 3e-7 "
                 "(measured 1.08e-7)" % deep_with)
    checks.check(deep_without > 1.5e-2, "without the self pair the walls pass through each other: %.3g > 1.5e-2 "
                 "(measured 0.052)" % deep_without)


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


def mortar_tube_crush_self_contact(checks):
    with_pair, _ = run(TUBE, *MORTAR_SELF, *TUBE_SMALL)
    path = without_self_pair(TUBE)
    without, _ = run(path, *TUBE_SMALL)
    os.remove(path)
    deep_with, deep_without = max(penetrations(with_pair.folder)), max(penetrations(without.folder))
    active = self_pair_active(with_pair.folder)
    checks.check(with_pair.rows[-1]["time"] == 1.0, "the crush ran to t = 1 (t = %g)" % with_pair.rows[-1]["time"])
    checks.check(38 <= active <= 46, "one half of the inner wall is the slave side in contact at the end: %d active "
                 "nodes of the self pair (measured 42)" % active)
    checks.check(deep_with <= 3e-8, "with mortar self contact the inner wall enters itself by %.3g <= 3e-8 (measured "
                 "1.0e-8)" % deep_with)
    checks.check(deep_without > 0.05, "without the self pair the walls pass through each other: %.3g > 0.05 "
                 "(measured 0.063)" % deep_without)


def mortar_tube_crush_self_contact_quad9(checks):
    with_pair, _ = run(TUBE, *MORTAR_SELF, *TUBE_SMALL, "--set", "mesh.order=2")
    deep = max(penetrations(with_pair.folder))
    active = self_pair_active(with_pair.folder)
    checks.check(with_pair.rows[-1]["time"] == 1.0, "the crush ran to t = 1 (t = %g)" % with_pair.rows[-1]["time"])
    checks.check(116 <= active <= 142, "one half of the inner wall is the slave side in contact at the end: %d active "
                 "nodes of the self pair (measured 129 of the 288 inner nodes)" % active)
    checks.check(deep <= 6e-6, "with mortar self contact on QUAD9 faces the inner wall enters itself by %.3g <= 6e-6 "
                 "(measured 4.57e-6, facing walls beside the fold: the nodes' polyline against curved faces)" % deep)


def mortar_ring_crush_self_friction(checks):
    mu = 0.3
    result, _ = run(SCENE, *MORTAR_SELF, "--set", "contact.2.parameters.mu=%g" % mu)
    deep = max(penetrations(result.folder))
    last = [r for r in result.contact_points() if r["pair"] == 2 and r["state"] != 0]
    ratios = []
    for r in last:
        t = [r["traction_" + c] for c in "xyz"]
        n = [r["normal_" + c] for c in "xyz"]
        tn = sum(a * b for a, b in zip(t, n))
        ratios.append(math.sqrt(max(0.0, sum(a * a for a in t) - tn * tn)) / (mu * r["pressure"]))
    checks.check(result.rows[-1]["time"] == 1.0, "the crush ran to t = 1 (t = %g)" % result.rows[-1]["time"])
    checks.check(30 <= len(last) <= 60, "one half in contact at the end: %d active nodes of the self pair (measured "
                 "45)" % len(last))
    checks.check(deep <= 6e-5, "with friction on the self pair the inner surface enters itself by %.3g <= 6e-5 "
                 "(measured 4.07e-5)" % deep)
    checks.check(max(ratios) <= 1.0 + 1e-9, "every active node within the Coulomb disc: |t_t| / (mu p) <= %.6f" %
                 max(ratios))
    checks.check(max(ratios) > 0.1, "friction carries load on the self pair: the largest |t_t| / (mu p) is %.3f "
                 "(measured 0.23)" % max(ratios))


if __name__ == "__main__":
    main([mortar_ring_crush_self_contact, mortar_self_contact_condensed, mortar_tube_crush_self_contact,
          mortar_tube_crush_self_contact_quad9, mortar_ring_crush_self_friction])
