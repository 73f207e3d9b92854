"""Self contact (a pair whose slave and master are the same surface; penalty-nts), on scenes/ring-crush-2d.yaml: a
thin ring (radii 0.9 and 1, E 1e4, nu 0.3) crushed between two plates until its inner surface folds onto itself.

- ring_crush_self_contact: with the pair `inner-self`, the inner surface's top half penetrates its bottom half by no
  more than the penalty's order (the mean pressure the plates transmit, |F_top| over the flattened length pi r_mid,
  over the computed penalty 10 E*/h of the inner surface); without the pair (the same scene, the pair deleted) the
  walls pass through each other by more than ten times that, so the pair is what holds them apart.
- tube_crush_self_contact: the same in 3D on scenes/tube-crush-3d.yaml (a thin tube, radii 0.9 and 1, flattened by a
  plate onto a floor until its inner wall meets itself), run coarser for CI (half the length, 2 element layers along
  it, dt 0.04): with the pair `inner-self` the top wall's inner surface enters the bottom wall's by no more than the
  penalty's order (|F_plate| over the flattened area pi r_mid L, over the computed penalty 10 E*/h); without the
  pair the walls pass through each other by more than ten times that.
- tube_crush_nts_self_contact: the tube with nts-augmented on every pair, coarser still (24 faces around, one layer
  of 0.125 along, dt 0.1: every node lies on a free end, level with the border of the faces it meets, and the walls
  close within a step): the slave side of the fold stays on the other wall, so both halves of the inner wall enter
  each other by no more than round-off (<= 1e-12; before nodes beyond the master's border kept their face within
  master_extension they passed through by 2.5e-2); without the pair the walls pass through each other by more than
  ten times penalty-nts's bound.
- bodies_self_matches_explicit: the ring crush with one `bodies: [ring]` entry with `self: true` (the ring's whole
  boundary against both plates and against itself, mu 0.3 for all) and with the same three pairs written out (slave
  `boundary`, the mesh group of the whole boundary; the self pair last) give the same history to round-off, and the
  self pair holds the walls apart (they touch: more active points than the plates alone make).
- self_contact_refused: a plugin without the self-contact capability (example-spring, for the self pair) is refused
  at `check`, naming the plugins that can (mortar-dual, nts-augmented, penalty-nts).

Penetration is measured on the output geometry: each inner node of the top half against the polyline of the bottom
half's inner nodes at the same x, in the same cross-section (same reference z) in 3D (every output step)."""
import csv
import math
import os
import subprocess
import tempfile

from stickslip_results import ROOT, main, read_vtu, run
from stickslip_compare.results import collection
from test_many_bodies import write as write_scene

SCENE = os.path.join(ROOT, "scenes", "ring-crush-2d.yaml")
R_INNER, R_OUTER, E, NU, N_AROUND = 0.9, 1.0, 1.0e4, 0.3, 96
TUBE = os.path.join(ROOT, "scenes", "tube-crush-3d.yaml")
# the CI version of the tube: half its length, 2 layers along it (faces 0.125 long, as in the scene), dt 0.04
TUBE_LENGTH, TUBE_LAYERS, TUBE_AROUND = 0.25, 2, 48
TUBE_CI = ["--set", "mesh.parameters.length=%g" % TUBE_LENGTH, "--set", "mesh.parameters.n_length=%d" % TUBE_LAYERS,
           "--set", "time.dt=0.04"]


def penetrations(folder):
    """Largest depth of a top-half inner node below the bottom half's inner surface, and of a bottom-half inner node
    above the top half's, over the output steps: in each cross-section (nodes of one reference z; the only one in
    2D), against the other half's polyline at the same x."""
    worst = [-math.inf, -math.inf]
    for _, name in collection(folder):
        vtu = read_vtu(os.path.join(folder, name))
        sections = {}
        for p, u in zip(vtu["Points"], vtu["displacement"]):
            X = (p[0] - u[0], p[1] - u[1])
            if abs(math.hypot(*X) - R_INNER) < 1e-6:
                halves = sections.setdefault(round(p[2] - u[2], 9), ([], []))
                halves[0 if X[1] > 0 else 1].append((p[0], p[1]))
        for halves in sections.values():
            for side, sign in ((0, 1.0), (1, -1.0)):
                other = sorted(halves[1 - side])
                for x, y in halves[side]:
                    for (x0, y0), (x1, y1) in zip(other, other[1:]):
                        if x0 <= x <= x1 and x1 > x0:
                            worst[side] = max(worst[side], sign * (y0 + (x - x0) * (y1 - y0) / (x1 - x0) - y))
    return worst


def inner_penetration(folder):
    """Largest depth of a top-half inner node below the bottom half's inner surface (penetrations)."""
    return penetrations(folder)[0]


def without_self_pair(scene=SCENE):
    """A copy of the scene without its pair `inner-self` (the last contact entry, before `time:`)."""
    text = open(scene).read().replace("../meshes", os.path.join(ROOT, "meshes"))
    start = text.index("  - name: inner-self")
    fd, path = tempfile.mkstemp(suffix=".yaml", prefix="stickslip-self-")
    with os.fdopen(fd, "w") as f:
        f.write(text[:start] + text[text.index("time:"):])
    return path


def ring_crush_self_contact(checks):
    with_pair, _ = run(SCENE)
    path = without_self_pair(SCENE)
    without, _ = run(path)
    os.remove(path)
    force = abs(with_pair.rows[-1]["reaction_top_y"])
    h = 2 * R_INNER * math.sin(math.pi / N_AROUND)  # the inner surface's face (chord)
    penalty = 10 * (E / (2 * (1 - NU ** 2))) / h
    bound = force / (math.pi * 0.5 * (R_INNER + R_OUTER)) / penalty
    deep_with, deep_without = inner_penetration(with_pair.folder), inner_penetration(without.folder)
    checks.check(with_pair.rows[-1]["active_points"] > N_AROUND, "the inner surface folded onto itself: %d active "
                 "points at the end (plates and self contact)" % with_pair.rows[-1]["active_points"])
    checks.check(deep_with <= bound, "with self contact the inner surface enters itself by %.3g <= the penalty's "
                 "order %.3g (mean pressure %.4g / penalty %.4g)" % (deep_with, bound, bound * penalty, penalty))
    checks.check(deep_without > 10 * bound, "without it the walls pass through each other: %.3g > 10 x %.3g" %
                 (deep_without, bound))


def self_pair_active(folder, pair=2):
    """Active points of contact pair `pair` (its index in the scene) at the last step, from contact.csv."""
    with open(os.path.join(folder, "contact.csv")) as f:
        rows = [r for r in csv.DictReader(f) if int(r["pair"]) == pair]
    last = max(int(r["step"]) for r in rows)
    return sum(1 for r in rows if int(r["step"]) == last and int(r["state"]) != 0)


def tube_runs(*args, length=TUBE_LENGTH, layers=TUBE_LAYERS, around=TUBE_AROUND):
    """The tube crushed with and without its self pair (args: the size and plugin options of both runs): the two
    results, penalty-nts's penetration bound on it (|F_plate| over the flattened area pi r_mid L, over the computed
    penalty 10 E*/h; h the mean corner-to-corner edge of the inner faces: the chord around and the layer along), h
    and the active points of the pair inner-self at the end."""
    with_pair, _ = run(TUBE, *args)
    path = without_self_pair(TUBE)
    without, _ = run(path, *args)
    os.remove(path)
    force = abs(with_pair.rows[-1]["reaction_plate_y"])
    h = 0.5 * (2 * R_INNER * math.sin(math.pi / around) + length / layers)
    penalty = 10 * (E / (2 * (1 - NU ** 2))) / h
    bound = force / (math.pi * 0.5 * (R_INNER + R_OUTER) * length) / penalty
    return with_pair, without, bound, h, self_pair_active(with_pair.folder)


def check_folded(checks, self_active, layers):
    checks.check(self_active > layers + 1, "the inner wall met itself: %d active points of the pair inner-self at the "
                 "end (more than one line of nodes along the tube)" % self_active)


def tube_crush_self_contact(checks):
    with_pair, without, bound, _, self_active = tube_runs(*TUBE_CI)
    deep_with, deep_without = inner_penetration(with_pair.folder), inner_penetration(without.folder)
    check_folded(checks, self_active, TUBE_LAYERS)
    checks.check(deep_with <= bound, "with self contact the inner wall enters itself by %.3g <= the penalty's "
                 "order %.3g" % (deep_with, bound))
    checks.check(deep_without > 10 * bound, "without it the walls pass through each other: %.3g > 10 x %.3g" %
                 (deep_without, bound))


# nts-augmented's CI size of the tube: 24 faces around, 2 through the wall, one layer of 0.125 along, dt 0.1 (the
# scene's 48 around, 2 layers of 0.125, dt 0.04 take 26 s: docs/plugins/nts-augmented.md)
TUBE_NTS_AROUND = 24
TUBE_NTS = ["--plugin", "nts-augmented", "--set", "mesh.parameters.n_around=%d" % TUBE_NTS_AROUND, "--set",
            "mesh.parameters.n_length=1", "--set", "mesh.parameters.length=0.125", "--set", "time.dt=0.1"]
# The fold's nodes meet node on node, so the halves enter each other by round-off: 4.4e-16 and 2.2e-16 measured
ROUNDOFF_PENETRATION = 1e-12


def tube_crush_nts_self_contact(checks):
    with_pair, without, bound, _, self_active = tube_runs(*TUBE_NTS, length=0.125, layers=1, around=TUBE_NTS_AROUND)
    deep_with, deep_without = penetrations(with_pair.folder), inner_penetration(without.folder)
    check_folded(checks, self_active, 1)
    checks.check(max(deep_with) <= ROUNDOFF_PENETRATION, "nts-augmented holds the gap of the self pair exactly: the "
                 "inner wall's halves enter each other by %.3g and %.3g <= %g" % (tuple(deep_with) +
                                                                                  (ROUNDOFF_PENETRATION,)))
    checks.check(deep_without > 10 * bound, "without the pair the walls pass through each other: %.3g > 10 x "
                 "penalty-nts's bound %.3g" % (deep_without, bound))


RING_MESH = """mesh:
  file: %s
  parameters: {r_inner: 0.9, r_outer: 1.0, n_around: 96, n_wall: 2}
bodies:
  - {name: ring, group: body, material: {model: neo-hooke-bonet, E: 1.0e4, nu: 0.3, density: 1}}
""" % os.path.join(ROOT, "meshes", "ring.geo")
FLOOR = "{type: plane, name: floor, point: [0, -1, 0], normal: [0, 1, 0]}"
TOP = "{type: plane, name: top, point: [0, 1, 0], normal: [0, -1, 0], motion: [[0, 0, 0, 0], [1, 0, -1.84, 0]]}"
RING_TIME = "time: {scheme: backward-euler, dt: 0.01, end: 1}\noutput: {vtu: false}\n"


def bodies_self_matches_explicit(checks):
    created = write_scene(RING_MESH + "contact:\n  - {name: all, bodies: [ring], self: true, obstacles: [%s, %s], "
                          "plugin: penalty-nts, parameters: {mu: 0.3}}\n" % (FLOOR, TOP) + RING_TIME)
    written = write_scene(RING_MESH + "contact:\n" + "".join(
        "  - {name: %s, slave: boundary, %s, plugin: penalty-nts, parameters: {mu: 0.3}}\n" % (name, other)
        for name, other in (("floor", "obstacle: " + FLOOR), ("top", "obstacle: " + TOP),
                            ("self", "master: boundary"))) + RING_TIME)
    one, _ = run(created)
    two, _ = run(written)
    os.remove(created)
    os.remove(written)
    checks.check(len(one.rows) == len(two.rows), "the same steps (%d, %d)" % (len(one.rows), len(two.rows)))
    # The surfaces' nodes come in another order (the mesh group's, the boundary's), so sums differ by round-off:
    # each column is compared against its quantity's scale over the run, a vector's component against the vector's
    # largest component (momentum_x, zero by symmetry, against momentum_y), a moment against its force times the
    # ring's radius.
    peak = {c: max(max(abs(v) for v in one.column(c) + two.column(c)), 1e-300) for c in one.rows[0]}

    def scale(column):
        family = column.rstrip("xyz").rstrip("_") if column[-2:] in ("_x", "_y", "_z") else column
        value = max(peak[c] for c in peak if c.startswith(family + "_") or c == column)
        if family in ("angular_momentum", "contact_moment"):
            value = max(value, R_OUTER * scale("momentum_x" if family == "angular_momentum" else "contact_force_x"))
        return value

    worst, where = 0.0, ""
    for column in one.rows[0]:
        if column == "wall_seconds":
            continue
        diff = max(abs(x - y) for x, y in zip(one.column(column), two.column(column))) / scale(column)
        if diff > worst:
            worst, where = diff, column
    checks.check(worst <= 1e-9, "every history column agrees to %.2g of its quantity's scale (worst: %s)" %
                 (worst, where or "none"))
    # the plates alone touch the outer surface along two flat strips; the fold adds the inner surface's nodes
    checks.check(one.rows[-1]["active_points"] > N_AROUND, "the created self pair is at work: %d active points at "
                 "the end" % one.rows[-1]["active_points"])


def self_contact_refused(checks):
    binary = os.environ.get("STICKSLIP_BIN", os.path.join(ROOT, "build", "bin", "stickslip"))
    # the self pair (contact entry 2) given to a plugin that lacks only the self-contact capability
    proc = subprocess.run([binary, "check", SCENE, "--set", "contact.2.plugin=example-spring"], capture_output=True,
                          text=True)
    checks.check(proc.returncode == 1 and "contact pair 'inner-self'" in proc.stderr and "lacks what this scene needs: "
                 "self-contact" in proc.stderr and "Plugins that can: mortar-dual, nts-augmented, penalty-nts" in
                 proc.stderr, "example-spring is refused at check for the self pair, naming mortar-dual, nts-augmented "
                 "and penalty-nts: %s" % proc.stderr.strip()[-200:])


if __name__ == "__main__":
    main([ring_crush_self_contact, tube_crush_self_contact, tube_crush_nts_self_contact, bodies_self_matches_explicit,
          self_contact_refused])
