"""Self contact (a pair whose slave and master are the same surface; penalty-nts), on scenes/ring-crush-2d.yaml: a
thin ring (radii 0.9 and 1, E 1e4, nu 0.3) crushed between two plates until its inner surface folds onto itself.

- ring_crush_self_contact: with the pair `inner-self`, the inner surface's top half penetrates its bottom half by no
  more than the penalty's order (the mean pressure the plates transmit, |F_top| over the flattened length pi r_mid,
  over the computed penalty 10 E*/h of the inner surface); without the pair (the same scene, the pair deleted) the
  walls pass through each other by more than ten times that, so the pair is what holds them apart.
- self_contact_refused: a plugin without the self-contact capability is refused at `check`, naming mortar-dual and
  penalty-nts.

Penetration is measured on the output geometry: each inner node of the top half against the polyline of the bottom
half's inner nodes at the same x (every output step)."""
import math
import os
import subprocess
import tempfile

from stickslip_results import ROOT, main, read_vtu, run
from stickslip_compare.results import collection

SCENE = os.path.join(ROOT, "scenes", "ring-crush-2d.yaml")
R_INNER, R_OUTER, E, NU, N_AROUND = 0.9, 1.0, 1.0e4, 0.3, 96


def inner_penetration(folder):
    """Largest depth of a top-half inner node below the bottom half's inner surface, over the output steps."""
    worst = -math.inf
    for _, name in collection(folder):
        vtu = read_vtu(os.path.join(folder, name))
        top, bottom = [], []
        for p, u in zip(vtu["Points"], vtu["displacement"]):
            X = (p[0] - u[0], p[1] - u[1])
            if abs(math.hypot(*X) - R_INNER) < 1e-6:
                (top if X[1] > 0 else bottom).append((p[0], p[1]))
        bottom.sort()
        for x, y in top:
            for (x0, y0), (x1, y1) in zip(bottom, bottom[1:]):
                if x0 <= x <= x1 and x1 > x0:
                    worst = max(worst, y0 + (x - x0) * (y1 - y0) / (x1 - x0) - y)
    return worst


def without_self_pair():
    text = open(SCENE).read().replace("../meshes", os.path.join(ROOT, "meshes"))
    start = text.index("  - name: inner-self")
    fd, path = tempfile.mkstemp(suffix=".yaml", prefix="stickslip-ring-")
    with os.fdopen(fd, "w") as f:
        f.write(text[:start] + text[text.index("time:"):])
    return path


def ring_crush_self_contact(checks):
    with_pair, _ = run(SCENE)
    path = without_self_pair()
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


def self_contact_refused(checks):
    binary = os.environ.get("STICKSLIP_BIN", os.path.join(ROOT, "build", "bin", "stickslip"))
    for plugin in ("nts-augmented",):
        proc = subprocess.run([binary, "check", SCENE, "--plugin", plugin], capture_output=True, text=True)
        checks.check(proc.returncode == 1 and "contact pair 'inner-self'" in proc.stderr and "self-contact" in
                     proc.stderr and "Plugins that can: mortar-dual, penalty-nts" in proc.stderr,
                     "%s is refused at check for the self pair, naming mortar-dual and penalty-nts: %s" % (plugin,
                                                                                       proc.stderr.strip()[-200:]))


if __name__ == "__main__":
    main([ring_crush_self_contact, self_contact_refused])
