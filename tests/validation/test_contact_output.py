"""The contact output means the same for every plugin and follows the run (issue 35, items 3 and 12).

- `contact_output_slide_<plugin>`: a 3D block pressed onto a rigid plane and pushed obliquely
  (scenes/mortar-block-on-plane-3d.yaml, Coulomb mu = 0.3; corotational: its ball on a plane, mu = 0.2): contact.csv
  has the points of every output step (the instants of the .vtu files); at each of them the points' normal_force x
  normal + traction x area sum to history.csv's contact_force, normal_force = pressure x area, |traction| <= mu
  pressure (= when slipping), the friction traction of a slipping point opposes its slip increment, the accumulated
  slip grows by at least the last increment while the point slides and never decreases, and points flip from stick
  to slip; the contact fields of the VTU files are contact.csv's (at the nodes of the bodies, and on the faces of the
  slave surfaces for Gauss points).
- `contact_output_hertz_2d_<plugin>`, `contact_output_hertz_3d_<plugin>`: the Hertz pressure profile read from
  contact.csv's `pressure` against Hertz's closed form, with the error metric of hertz_profile.py (the L2 profile
  error over r < 1.25 a), for every plugin that runs the Hertz scenes. nts-augmented wrote its nodal multiplier (a
  force) there before: L2 0.98 on hertz-2d (0a8b594).
- `contact_output_mpi`: the contact output on 2 ranks equals that on 1 rank.
Usage: python3 test_contact_output.py CASE; exit code 0 when every check holds."""
import math
import os
import re
import sys

from hertz_profile import hertz_reference, profile_errors
from stickslip_results import main, read_vtu, run
from test_contact_scenes import reference_points

SLIDE_3D = "scenes/mortar-block-on-plane-3d.yaml"
# (scene, --set overrides, mu): the block with each pair plugin at its own parameters, the ball for corotational
SLIDES = {
    "penalty-nts": (SLIDE_3D, ["contact.0.plugin=penalty-nts", "contact.0.strategy=none",
                               "contact.0.parameters={penalty: 1.0e6, penalty_tangential: 1.0e6, mu: 0.3}"], 0.3),
    "nts-augmented": (SLIDE_3D, ["contact.0.plugin=nts-augmented", "contact.0.strategy=condensed",
                                 "contact.0.parameters={mu: 0.3, epsilon_t: 1.0e4}"], 0.3),
    "covariant-penalty": (SLIDE_3D, ["contact.0.plugin=covariant-penalty", "contact.0.strategy=none",
                                     "contact.0.parameters={penalty: 1.0e6, penalty_tangential: 1.0e6, mu: 0.3}"],
                          0.3),
    "mortar-dual": (SLIDE_3D, [], 0.3),
    "corotational": ("scenes/corot-ball-on-plane-friction.yaml", [], 0.2),  # lands sliding: no stick to flip from
}
STICKS_FIRST = {SLIDE_3D}


def overrides(sets):
    """Command-line options for KEY=VALUE overrides: a pair's whole parameter map replaces the scene's (--set of a map
    would merge into it), everything else is --set."""
    return [a for s in sets for a in ("--replace" if s.startswith("contact.0.parameters=") else "--set", s)]
VTU_EVERY = 2


def output_steps(results):
    """The steps of the .pvtu files (results.pvd) and of contact.csv."""
    pvd = open(os.path.join(results.folder, "results.pvd")).read()
    vtu = [int(s) for s in re.findall(r'file="step-(\d+)\.pvtu"', pvd)]
    csv = sorted({int(p["step"]) for p in results.contact_table()})
    return vtu, csv


def check_time_series(c, results, plugin):
    vtu, csv = output_steps(results)
    last = int(results.rows[-1]["step"])
    expected = sorted(set(range(0, last + 1, VTU_EVERY)) | {last})
    c.check(vtu == expected, "%s: a .vtu at steps 0, %d, ... and the last (%d): %s" % (plugin, VTU_EVERY, last,
                                                                                   vtu[:6]))
    c.check(csv == vtu, "%s: contact.csv has the points of every output step (%d steps)" % (plugin, len(csv)))
    times = {int(r["step"]): r["time"] for r in results.rows}
    c.check(all(p["time"] == times[int(p["step"])] for p in results.contact_table()),
            "%s: contact.csv's time is history.csv's time of the step" % plugin)


def check_forces(c, results, plugin, mu):
    """At every output step: the points' forces sum to the resultant, pressure x area = normal force, Coulomb."""
    rows = {int(r["step"]): r for r in results.rows}
    worst_sum = worst_area = worst_coulomb = worst_cone = 0.0
    for step in sorted({int(p["step"]) for p in results.contact_table()}):
        points = results.contact_points(step)
        active = [p for p in points if p["state"] > 0]
        force = [sum(p["normal_force"] * p["normal_" + k] + p["traction_" + k] * p["area"] for p in active)
                 for k in "xyz"]
        resultant = [rows[step]["contact_force_" + k] for k in "xyz"]
        scale = max(abs(f) for f in resultant)
        if scale > 0:
            worst_sum = max(worst_sum, max(abs(f - r) for f, r in zip(force, resultant)) / scale)
        for p in active:
            worst_area = max(worst_area, abs(p["normal_force"] - p["pressure"] * p["area"]) /
                             max(abs(p["normal_force"]), 1e-300))
            tangential = math.sqrt(sum(p["traction_" + k] ** 2 for k in "xyz"))
            worst_coulomb = max(worst_coulomb, (tangential - mu * p["pressure"]) / max(p["pressure"], 1e-300))
            if p["state"] == 2:
                worst_cone = max(worst_cone, abs(tangential - mu * p["pressure"]) / p["pressure"])
    c.check(worst_sum <= 1e-12, "%s: normal_force x normal + traction x area of the points sum to history.csv's "
            "contact_force at every output step (%.1e relative)" % (plugin, worst_sum))
    c.check(worst_area <= 1e-14, "%s: normal_force = pressure x area (%.1e)" % (plugin, worst_area))
    c.check(worst_coulomb <= 1e-9, "%s: |traction| <= mu pressure at every point in contact (largest excess %.1e of "
            "the pressure)" % (plugin, worst_coulomb))
    c.check(worst_cone <= 1e-9, "%s: |traction| = mu pressure at every slipping point (%.1e)" % (plugin, worst_cone))


def check_slip(c, results, plugin, sticks_first):
    """Slip against the traction while slipping, accumulated slip growing, stick flipping to slip."""
    by_point = {}
    for p in results.contact_table():
        key = (p["pair"], p["node"], p["face"], p["reference_x"], p["reference_y"], p["reference_z"])
        by_point.setdefault(key, []).append(p)
    dissipative = slipping = grows = flips = 0
    worst_order = 0.0
    for history in by_point.values():
        history.sort(key=lambda p: p["step"])
        for before, now in zip(history, history[1:]):
            increment = math.sqrt(sum(now["slip_increment_" + k] ** 2 for k in "xyz"))
            worst_order = max(worst_order, before["slip"] - now["slip"])
            if now["state"] == 2:
                slipping += 1
                dissipative += sum(now["traction_" + k] * now["slip_increment_" + k] for k in "xyz") < 0
                grows += increment > 0 and now["slip"] - before["slip"] >= increment * (1 - 1e-12)
            flips += before["state"] == 1 and now["state"] == 2
    c.check(slipping > 0, "%s: points slip (%d point-steps)" % (plugin, slipping))
    c.check(dissipative == slipping, "%s: the traction of every slipping point opposes its slip increment "
            "(traction . slip_increment < 0: %d of %d)" % (plugin, dissipative, slipping))
    c.check(grows == slipping, "%s: the accumulated slip of a slipping point grows by at least its last increment "
            "(%d of %d)" % (plugin, grows, slipping))
    c.check(worst_order == 0.0, "%s: the accumulated slip never decreases" % plugin)
    if sticks_first:
        c.check(flips > 0, "%s: points flip from stick to slip (%d)" % (plugin, flips))
    stuck = [p for p in results.contact_table() if p["state"] == 1]
    c.check(all(not math.isnan(p["slip"]) for p in stuck), "%s: sticking points report their slip too" % plugin)


def close(a, b, scale):
    return abs(a - b) <= 1e-12 * scale


def check_vtu_fields(c, results, plugin):
    """The last output step's VTU fields against contact.csv."""
    points = results.contact_points()
    step = int(points[0]["step"])
    body = read_vtu(os.path.join(results.folder, "step-%06d.pvtu" % step))
    surface = read_vtu(os.path.join(results.folder, "contact-%06d.pvtu" % step))
    names = ("contact_pressure", "contact_gap", "contact_state", "contact_normal_traction",
             "contact_tangential_traction", "contact_normal_force", "contact_slip_increment", "contact_slip")
    c.check(all(n in body for n in names) and all(n in surface for n in names),
            "%s: the bodies' and the slave surfaces' VTU carry %s" % (plugin, ", ".join(names)))
    scale = max(p["pressure"] for p in points)
    nodes = [p for p in points if p["node"] >= 0]
    bad = 0
    for p in nodes:
        n = int(p["node"])
        bad += not close(body["contact_pressure"][n][0], p["pressure"], scale)
        bad += not close(body["contact_state"][n][0], p["state"], 1)
        bad += not all(close(body["contact_normal_traction"][n][i], p["pressure"] * p["normal_" + k], scale)
                       for i, k in enumerate("xyz"))
        bad += not all(close(body["contact_tangential_traction"][n][i], p["traction_" + k], scale)
                       for i, k in enumerate("xyz"))
        bad += not all(close(body["contact_slip_increment"][n][i], p["slip_increment_" + k], 1)
                       for i, k in enumerate("xyz"))
    c.check(bad == 0, "%s: the bodies' VTU fields at the %d node points are contact.csv's (%d differ)"
            % (plugin, len(nodes), bad))
    if nodes:
        # the pieces joined by read_vtu: point k is mesh node k, which the point field `node` names too
        c.check(all(int(surface["node"][int(p["node"])][0]) == int(p["node"]) and
                    close(surface["contact_pressure"][int(p["node"])][0], p["pressure"], scale) for p in nodes),
                "%s: contact-%06d.pvtu's point field contact_pressure is contact.csv's" % (plugin, step))
        return
    # Gauss points: each face's cell value is the mean of its points weighted by their measure
    faces = {}
    for p in points:
        faces.setdefault((int(p["pair"]), int(p["face"])), []).append(p)
    cells = {(int(surface["pair"][k][0]), int(surface["face"][k][0])): k for k in range(len(surface["pair"]))}
    bad = 0
    for key, members in faces.items():
        mean = sum(p["pressure"] * p["area"] for p in members) / sum(p["area"] for p in members)
        bad += not close(surface["cell:contact_pressure"][cells[key]][0], mean, scale)
    c.check(bad == 0, "%s: the %d faces of contact-%06d.pvtu carry the area-weighted means of their Gauss points' "
            "pressures (%d differ)" % (plugin, len(faces), step, bad))


def slide(plugin):
    def case(c):
        scene, sets, mu = SLIDES[plugin]
        args = overrides(sets + ["output.vtu_every=%d" % VTU_EVERY])
        results, _ = run(scene, *args)
        c.check(results.summary["status"] == "ok", "%s: the run succeeds" % plugin)
        check_time_series(c, results, plugin)
        check_forces(c, results, plugin, mu)
        check_slip(c, results, plugin, scene in STICKS_FIRST)
        check_vtu_fields(c, results, plugin)
    case.__name__ = "contact_output_slide_" + plugin.replace("-", "_")
    return case


# The Hertz cases: (dimension, scene, plugin, --set overrides, the largest L2 profile error accepted). The bounds sit
# just above the errors measured at refine 1 (the errors of the coarse meshes, the same for every plugin that reports
# nodes: 2D 0.0293 penalty-nts, 0.0299 nts-augmented, 0.0296 mortar-dual; 3D 0.135 for penalty-nts, nts-augmented,
# covariant-penalty's nts and mortar-dual; measured at 84c0f8e, 2026-11-28).
# covariant-penalty's sts reports its Gauss points, whose pressures scatter on the faceted sphere: 0.195 at penalty 1e5
# (0.632 at the scene's 1e7, where the over-constrained Gauss points lock: docs/benchmarks.md has both).
DEFAULTS = ["contact.0.parameters={}"]
HERTZ = {
    "hertz_2d_penalty_nts": (2, "scenes/hertz-2d.yaml", [], 0.031),
    "hertz_2d_nts_augmented": (2, "scenes/hertz-2d.yaml", ["contact.0.plugin=nts-augmented"] + DEFAULTS, 0.031),
    "hertz_2d_mortar_dual": (2, "scenes/hertz-2d.yaml", ["contact.0.plugin=mortar-dual"] + DEFAULTS, 0.031),
    "hertz_3d_penalty_nts": (3, "scenes/hertz-3d.yaml", [], 0.14),
    "hertz_3d_nts_augmented": (3, "scenes/hertz-3d.yaml", ["contact.0.plugin=nts-augmented"] + DEFAULTS, 0.14),
    "hertz_3d_covariant_nts": (3, "scenes/hertz-3d.yaml", ["contact.0.plugin=covariant-penalty",
                                                          "contact.0.parameters={penalty: 1.0e7, variant: nts}"],
                               0.14),
    "hertz_3d_covariant_sts": (3, "scenes/hertz-3d.yaml", ["contact.0.plugin=covariant-penalty",
                                                          "contact.0.parameters={penalty: 1.0e5, variant: sts}"],
                               0.21),
}  # mortar-dual's 3D profile from contact.csv: validation_mortar_hertz_3d (l2 0.151 <= 0.16, scenes/mortar-hertz-3d)


def hertz(name):
    def case(c):
        dim, scene, sets, bound = HERTZ[name]
        results, _ = run(scene, *overrides(sets))
        load, a, p0 = hertz_reference(dim, results)
        errors = profile_errors(reference_points(results, radial=dim == 3), a, p0)
        print("%s: load %.6g, a %.5g, p0 %.5g; errors %s" % (name, load, a, p0, ", ".join(
            "%s %.4g" % (k, v) for k, v in errors.items())))
        c.check(errors["l2"] <= bound, "%s: L2 error of the pressure profile from contact.csv against Hertz %.4f <= %g"
                % (name, errors["l2"], bound))
        last = results.contact_points()
        total = sum(p["normal_force"] for p in last)
        normal = abs(results.rows[-1]["contact_force_y" if dim == 2 else "contact_force_z"])
        c.check(abs(total - normal) <= 1e-3 * normal, "%s: the normal forces sum to the contact force %.6g (%.6g)"
                % (name, normal, total))
    case.__name__ = "contact_output_" + name
    return case


def contact_output_mpi(c):
    """The block slide with penalty-nts on 1 and 2 ranks: the same contact.csv and contact fields to round-off."""
    scene, sets, _ = SLIDES["penalty-nts"]
    args = overrides(sets + ["output.vtu_every=10"])
    one, _ = run(scene, *args)
    two, _ = run(scene, *args, np=2)
    c.check(two.summary["ranks"] == 2, "the second run used 2 ranks")
    key = lambda p: (p["step"], p["node"])  # noqa: E731
    a, b = sorted(one.contact_table(), key=key), sorted(two.contact_table(), key=key)
    c.check([key(p) for p in a] == [key(p) for p in b], "the same points at the same steps (%d rows)" % len(a))
    scale = max(p["pressure"] for p in a)
    worst = max(abs(p[k] - q[k]) for p, q in zip(a, b) for k in ("pressure", "normal_force", "traction_x", "slip"))
    c.check(worst <= 1e-9 * scale, "contact.csv equal to %.1e" % worst)
    for name in ("step-000030.pvtu", "contact-000030.pvtu"):
        va, vb = read_vtu(os.path.join(one.folder, name)), read_vtu(os.path.join(two.folder, name))
        diff = max(abs(x - y) for f in ("contact_pressure", "contact_tangential_traction", "contact_slip")
                   for u, v in zip(va[f], vb[f]) for x, y in zip(u, v))
        c.check(diff <= 1e-9 * scale, "%s: the contact fields equal to %.1e" % (name, diff))


CASES = [slide(p) for p in SLIDES] + [hertz(n) for n in HERTZ] + [contact_output_mpi]

if __name__ == "__main__":
    main(CASES)
