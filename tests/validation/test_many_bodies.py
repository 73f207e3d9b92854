"""Contact among many bodies (`contact: [{bodies: all | [...], obstacles: [...]}]`, docs/scene-reference.md):

- bodies_all_matches_explicit: four disks colliding in free flight (midpoint, friction). The scene with one
  `bodies: all` entry and the same scene with the six pairs written out (slave and master as the documented rule
  picks them: equal mesh sizes, the body listed first is slave) give the same history to round-off, although the
  created pairs run through the host's broad phase (pair_attempts_apart > 0) and the written ones do not.
- disks_in_box: scenes/disks-in-box-2d.yaml, short: the disks fall on the floor and on each other; no boundary node
  of a disk lies inside its master disk or beyond a wall by more than the penalty's order (the floor impact's
  speed times sqrt(mass / (penalty face size))), checked on the output geometry itself, so that a pair the broad
  phase wrongly kept idle would show.
- tori_on_plane: scenes/tori-on-plane-3d.yaml short (4 steps, 4 elements around each tube) on 1 and 2 ranks: the
  bottom tori rest on the floor and at least two tori touch each other; no point enters beyond the penalty's order
  (a torus of mass m falling at v onto its ring of n_around floor springs eps A, as backward Euler resolves an impact
  shorter than dt: v dt m / (m + n eps A dt^2)); and the two runs agree to 1e-10 of each quantity's scale (reactions,
  contact force, energies) with the same active points."""
import csv
import math
import os
import tempfile

from stickslip_results import ROOT, main, run

DISK = os.path.join(ROOT, "meshes", "disk.geo")
MATERIAL = "{model: neo-hooke-bonet, E: 1.0e4, nu: 0.3, density: 1}"
# two disks moving right meet two moving left, off-centre (sliding with friction), then part
DISKS = [("a", -1.2, 0.0, 2.0), ("b", -1.2, 1.1, 2.0), ("c", 0.0, 0.35, -2.0), ("d", 0.05, 1.5, -2.0)]


def four_disks_scene(contact):
    meshes = "\n".join("  - {file: %s, name: %s, parameters: {radius: 0.5, refine: 0.5, cx: %g, cy: %g}}" %
                       (DISK, name, x, y) for name, x, y, _ in DISKS)
    bodies = "\n".join("  - {name: %s, group: %s.body, material: %s, velocity: [%g, 0, 0]}" % (name, name, MATERIAL, v)
                       for name, _, _, v in DISKS)
    return ("mesh:\n%s\nbodies:\n%s\ncontact:\n%s\ntime: {scheme: midpoint, dt: 0.005, end: 0.4}\n"
            "output: {vtu: false}\n" % (meshes, bodies, contact))


def write(text):
    fd, path = tempfile.mkstemp(suffix=".yaml", prefix="stickslip-many-")
    with os.fdopen(fd, "w") as f:
        f.write(text)
    return path


def bodies_all_matches_explicit(checks):
    created = write(four_disks_scene("  - {name: all, bodies: all, plugin: penalty-nts, parameters: {mu: 0.3}}\n"))
    names = [d[0] for d in DISKS]
    explicit = "".join("  - {name: %s-%s, slave: %s.boundary, master: %s.boundary, plugin: penalty-nts, "
                       "parameters: {mu: 0.3}}\n" % (a, b, a, b)
                       for i, a in enumerate(names) for b in names[i + 1:])
    written = write(four_disks_scene(explicit))
    one, _ = run(created)
    two, _ = run(written)
    checks.check(one.summary["pair_attempts_apart"] > 0 and two.summary["pair_attempts"] == 0,
                 "the created pairs went through the broad phase (%d of %d pair attempts kept idle), the written "
                 "ones did not (%d)" % (one.summary["pair_attempts_apart"], one.summary["pair_attempts"],
                                        two.summary["pair_attempts"]))
    checks.check(max(one.column("active_points")) > 0, "the disks met (up to %d active points)" %
                 max(one.column("active_points")))
    checks.check(len(one.rows) == len(two.rows), "the same steps (%d, %d)" % (len(one.rows), len(two.rows)))
    worst, where = 0.0, ""
    for column in one.rows[0]:
        if column in ("wall_seconds",):
            continue
        a, b = one.column(column), two.column(column)
        scale = max(max(abs(v) for v in a + b), 1e-300)
        diff = max(abs(x - y) for x, y in zip(a, b)) / scale
        if diff > worst:
            worst, where = diff, column
    checks.check(worst <= 1e-9, "every history column agrees to %.2g relative (worst: %s)" % (worst, where or "none"))
    os.remove(created)
    os.remove(written)


def boundary_loops(vtu):
    """Each body's boundary (edges used by one cell) as a list of edges (point index pairs), by body id."""
    conn, offsets, bodies = vtu["connectivity"], vtu["offsets"], vtu["body"]
    edges, start = {}, 0
    for c, (end,) in enumerate(offsets):
        nodes = [int(k[0]) for k in conn[start:end]][:4]
        for i in range(len(nodes)):
            key = tuple(sorted((nodes[i], nodes[(i + 1) % len(nodes)])))
            edges.setdefault((int(bodies[c][0]), key), 0)
            edges[(int(bodies[c][0]), key)] += 1
        start = end
    loops = {}
    for (body, key), count in edges.items():
        if count == 1:
            loops.setdefault(body, []).append(key)
    return loops


def inside(point, edges, x):
    """Winding test of point against a closed polygon given by its edges, and the distance to it."""
    px, py = point
    crossings, distance = 0, math.inf
    for i, j in edges:
        (ax, ay), (bx, by) = x[i], x[j]
        if (ay > py) != (by > py) and px < ax + (py - ay) * (bx - ax) / (by - ay):
            crossings += 1
        dx, dy = bx - ax, by - ay
        t = max(0.0, min(1.0, ((px - ax) * dx + (py - ay) * dy) / (dx * dx + dy * dy)))
        distance = min(distance, math.hypot(px - ax - t * dx, py - ay - t * dy))
    return crossings % 2 == 1, distance


def disks_in_box(checks):
    results, _ = run("scenes/disks-in-box-2d.yaml", "--set", "time.end=0.5", "--set", "output.vtu_every=10")
    s = results.summary
    checks.check(s["pair_attempts_apart"] > 0.3 * s["pair_attempts"],
                 "the broad phase kept %d of %d disk-disk pair attempts idle" % (s["pair_attempts_apart"],
                                                                                 s["pair_attempts"]))
    # the penalty's order: the bottom disks hit the floor at v = sqrt(2 g d), d = 0.1 their initial height above it;
    # a disk of mass m stopped by one slave node's spring eps h (eps = 10 E*/h, E* = E / (1 - nu^2) against a rigid
    # wall; h its rim face) enters by v sqrt(m / (eps h)), which falls as eps^(-1/2) as the penalty grows
    h = 2 * 0.5 * math.sin(math.pi / 16)
    penalty = 10 * 1.0e4 / (1 - 0.3 ** 2) / h
    bound = math.sqrt(2 * 9.81 * 0.1) * math.sqrt(math.pi * 0.25 / (penalty * h))
    deepest = max(results.column("constraint_violation"))
    checks.check(0 < deepest <= bound, "largest penetration the plugin reports %.3g <= the penalty's order %.3g" %
                 (deepest, bound))
    checks.check(min(results.column("reaction_floor_y")) < 0 and results.rows[-1]["reaction_floor_y"] < 0,
                 "the floor carries the pile (its reaction at the end %.3g)" % results.rows[-1]["reaction_floor_y"])
    from stickslip_results import read_vtu
    from stickslip_compare.results import collection
    # node-to-segment keeps slave nodes out of master faces (a master node may cut a slave face's chord by up to the
    # faceting's sagitta): the slave of two equal disks is the one listed first (lower body index); every disk is
    # slave against the walls
    worst = 0.0
    for _, name in collection(results.folder):
        vtu = read_vtu(os.path.join(results.folder, name))
        x = [(p[0], p[1]) for p in vtu["Points"]]
        loops = boundary_loops(vtu)
        for body, edges in loops.items():
            nodes = {k for e in edges for k in e}
            for other, other_edges in loops.items():
                if other <= body:
                    continue
                for node in nodes:
                    is_in, depth = inside(x[node], other_edges, x)
                    if is_in:
                        worst = max(worst, depth)
            for node in nodes:
                worst = max(worst, -x[node][1], -x[node][0], x[node][0] - 3.3)
    checks.check(worst <= bound, "no slave node lies inside its master disk or beyond a wall by more than the "
                 "penalty's order: deepest %.3g <= %.3g (every output step)" % (worst, bound))

TORI = "scenes/tori-on-plane-3d.yaml"
# the CI version: 4 elements around each tube (the scene's 8 halved: its top and bottom rings of nodes stay)
TORI_CI = ["--set", "time.end=0.04", "--set", "output.vtu_every=4"] + [
    a for k in range(8) for a in ("--set", "mesh.%d.parameters.n_tube=4" % k)]
# pair indices of the `bodies: all` entry: torus i (1-based) meets tori i+1..8, then the floor
FLOOR_PAIRS = {7, 14, 20, 25, 29, 32, 34, 35}
BOTTOM_ON_FLOOR = {7, 14, 20, 25}


def tori_on_plane(checks):
    one, _ = run(TORI, *TORI_CI)
    two, _ = run(TORI, *TORI_CI, np=2)
    checks.check(two.summary["ranks"] == 2, "the second run used 2 ranks")
    with open(os.path.join(one.folder, "contact.csv")) as f:
        points = [r for r in csv.DictReader(f) if int(r["state"]) != 0]
    last = max(int(r["step"]) for r in points)
    active = {int(r["pair"]) for r in points if int(r["step"]) == last}
    checks.check(BOTTOM_ON_FLOOR <= active, "the four bottom tori rest on the floor (active pairs %s)" % sorted(active))
    checks.check(len(active - FLOOR_PAIRS) >= 2, "tori touch each other: %d torus-torus pairs active at the end" %
                 len(active - FLOOR_PAIRS))
    # the penalty's order: a bottom torus (R 3, tube radii 1 and 0.8, density 1) falls 0.02 at 1 onto its ring of
    # n_around = 16 nodes, each a spring eps A (eps = 10 E*/h against the rigid floor, E* = E / (1 - nu^2), h the
    # mean edge 1.222 that --explain prints; A the nodes' mean tributary area from contact.csv)
    mass = 2 * math.pi * 3 * math.pi * (1 - 0.8 ** 2)
    v = math.sqrt(1 + 2 * 9.81 * 0.02)
    eps = 10 * 1.0e4 / (1 - 0.3 ** 2) / 1.222
    floor = [float(r["area"]) for r in points if int(r["pair"]) == 7]
    k, dt = 16 * eps * sum(floor) / len(floor), 0.01
    bound = v * dt * mass / (mass + k * dt * dt)
    deepest = max(-float(r["gap"]) for r in points)
    checks.check(0 < deepest <= bound, "deepest point %.3g <= the penalty's order %.3g (every pair, every output "
                 "step)" % (deepest, bound))
    worst, where = 0.0, ""
    for column in ("reaction_floor_x", "reaction_floor_y", "reaction_floor_z", "contact_force_z", "kinetic_energy",
                   "strain_energy"):
        family = "reaction_floor_z" if "floor" in column or "force" in column else column
        scale = max(abs(x) for x in one.column(family))
        diff = max(abs(x - y) for x, y in zip(one.column(column), two.column(column))) / scale
        if diff > worst:
            worst, where = diff, column
    checks.check(worst <= 1e-10, "1 and 2 ranks agree to %.1e of each quantity's scale (worst: %s)" % (worst, where))
    checks.check(one.column("active_points") == two.column("active_points"), "the same active points on 1 and 2 "
                 "ranks (%s)" % one.column("active_points"))


if __name__ == "__main__":
    main([bodies_all_matches_explicit, disks_in_box, tori_on_plane])
