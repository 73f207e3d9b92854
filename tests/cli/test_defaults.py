"""Defaults computed from the scene (plugin ABI 2.7, stickslip.scene.v1): `check --explain` and `run --explain` print
each with its value and reason, the value is the plugin's rule on the scene's numbers, a value the scene gives wins,
`stickslip plugins` states the rules, and a scene giving only mu runs with every plugin that takes it.

  python3 test_defaults.py CASE"""
import os
import re

from cli_case import CONTACT, ROOT, main, replace, scene_text

ONLY_MU = replace(CONTACT, "parameters: {penalty: 1.0e4}", "parameters: {mu: 0.3}")
# the block of CONTACT: E 1000, nu 0.3 on a rigid plane; its zmin face is 2 x 2 quad4 of edge 0.5 (9 nodes)
E_STAR = 1000.0 / (1.0 - 0.3 ** 2)
H = 0.5
AREA = 1.0 / 9.0
COMPUTED = re.compile(r"^  contact\[0\]\.parameters\.(\w+) = (\S+) \(computed: (.*)\)$", re.M)
# plugin -> {key: (expected value, a fragment of the reason)}
RULES = {
    "penalty-nts": {"penalty": (10 * E_STAR / H, "10 E*/h; E* = 1099 (slave body 'block' E 1000 nu 0.3; rigid "
                                                 "obstacle 'plane'), h = 0.5 (mean corner-to-corner edge of slave "
                                                 "surface 'zmin', 4 faces of order 1)"),
                    "penalty_tangential": (10 * E_STAR / H, "the normal penalty")},
    "covariant-penalty": {"penalty": (10 * E_STAR / H, "10 E*/h"), "penalty_tangential": (10 * E_STAR / H, "normal")},
    "nts-augmented": {"epsilon_t": (10 * E_STAR / H * AREA, "10 E*/h A"), "c_n": (E_STAR / H * AREA, "1 E*/h A")},
    "mortar-dual": {"c_n": (10 * E_STAR / H, "10 E*/h"), "c_t": (10 * E_STAR / H, "c_n")},
}
# lengths computed from the scene: no master faces against an obstacle; self_exclusion unused on a pair that is not
# self contact; nts-augmented's margin is half the slave surface's mean edge there
RULES["penalty-nts"].update({"search_margin": (0.0, "rigid obstacle has no master faces"),
                             "self_exclusion": (0.0, "unused: the pair is not self contact")})
RULES["covariant-penalty"]["search_margin"] = (0.0, "rigid obstacle has no master faces")
RULES["nts-augmented"].update({"search_margin": (0.5 * H, "half the mean edge of slave surface 'zmin'"),
                               "self_exclusion": (0.0, "unused: the pair is not self contact")})
# mortar-dual against an obstacle searches by the slave's mean edge and integrates at face_gauss's points (its
# segment and cell rules unused); covariant-penalty's Gauss points follow the order of the slave faces
RULES["mortar-dual"].update({"search_margin": (H, "the mean edge of slave surface 'zmin' (a rigid obstacle has no "
                                                  "master faces)"),
                             "self_exclusion": (0.0, "unused: the pair is not self contact"),
                             "transform_alpha": (0.0, "unused: slave surface 'zmin' has no TRI6 or QUAD8 faces"),
                             "segment_gauss": (0.0, "unused: an obstacle pair integrates at face_gauss's points"),
                             "cell_rule": (0.0, "unused: an obstacle pair integrates at face_gauss's points")})
RULES["covariant-penalty"]["gauss_points"] = (2.0, "first-order slave faces of surface 'zmin'")
# pairs with a deformable master (scenes/patch-test-*.yaml, frictionless: the tangential parameters unused): the
# 2D one's master lower-top has 4 line2 edges of 0.25, the 3D one's 4 x 4 quad4 of edge 0.25 (diagonal 0.3536)
PAIR_SCENES = [
    ("patch-test-2d.yaml", "mortar-dual", {
        "segment_gauss": (3.0, "line2 faces on both sides"), "cell_rule": (0.0, "unused: a 2D pair"),
        "search_margin": (0.25, "the mean edge of master surface 'lower-top'"),
        "c_t": (0.0, "unused: the pair is frictionless (mu 0)")}),
    ("patch-test-3d.yaml", "mortar-dual", {
        "cell_rule": (6.0, "exact on parallelograms"), "segment_gauss": (0.0, "unused: a 3D pair"),
        "search_margin": (0.25, "the mean edge of master surface 'lower-top'")}),
    ("patch-test-3d.yaml", "covariant-penalty", {
        "gauss_points": (2.0, "first-order slave faces of surface 'upper-bottom'"),
        "search_margin": (0.125 * 2 ** 0.5, "half the mean face size of master surface 'lower-top'"),
        "penalty_tangential": (0.0, "unused: the pair is frictionless (mu 0)")}),
    ("patch-test-3d.yaml", "penalty-nts", {}), ("patch-test-3d.yaml", "nts-augmented", {
        "epsilon_t": (0.0, "unused: the pair is frictionless (mu 0)")}),
]


def computed(c):
    return {m.group(1): (float(m.group(2)), m.group(3)) for m in COMPUTED.finditer(c.proc.stdout)}


def explain_defaults(c):
    for plugin, rules in RULES.items():
        c.run_scene(ONLY_MU, "--plugin", plugin, "--explain", command="check")
        c.no_crash()
        c.check(c.proc.returncode == 0, "%s: check passes with only mu (exit %d)" % (plugin, c.proc.returncode))
        got = computed(c)
        c.check(set(got) == set(rules), "%s: computes %s (got %s)" % (plugin, sorted(rules), sorted(got)))
        for key, (value, reason) in rules.items():
            if key in got:
                c.check(abs(got[key][0] - value) <= 1e-5 * value, "%s: %s = %g, the rule gives %g" % (
                    plugin, key, got[key][0], value))
                c.check(reason in got[key][1], "%s: %s's reason has '%s' (%s)" % (plugin, key, reason, got[key][1]))


def second_order_faces(c):
    # the order of the slave faces sets penalty-nts' constant: 300 E*/h on QUAD9 (h still the corner-to-corner edge)
    c.run_scene(ONLY_MU, "--set", "mesh.order=2", "--explain", command="check")
    c.no_crash()
    got = computed(c).get("penalty")
    c.check(got is not None and abs(got[0] - 300 * E_STAR / H) <= 1e-5 * 300 * E_STAR / H and "300 E*/h" in got[1],
            "second-order faces: penalty = 300 E*/h = %g (got %s)" % (300 * E_STAR / H, got))


def given_value_wins(c):
    c.run_scene(replace(ONLY_MU, "{mu: 0.3}", "{mu: 0.3, penalty: 123}"), "--explain", command="check")
    got = computed(c)
    c.check("penalty" not in got, "a penalty the scene gives is not computed")
    c.check(got.get("penalty_tangential", (0,))[0] == 123, "the tangential penalty follows the given one (%s)" % got)
    # frictionless: the tangential penalty is unused and reported so (0), not computed from the normal one
    c.run_scene(replace(ONLY_MU, "{mu: 0.3}", "{}"), "--explain", command="check")
    got = computed(c)
    c.check(set(got) == {"penalty", "penalty_tangential", "search_margin", "self_exclusion"},
            "frictionless: the penalty, the lengths and the unused tangential penalty are reported (%s)" % got)
    c.check(got.get("penalty_tangential") == (0.0, "unused: the pair is frictionless (mu 0)"),
            "frictionless: the tangential penalty is unused (%s)" % (got.get("penalty_tangential"),))


def run_explain(c):
    # run --explain prints the same lines before the run, and the run with the computed values converges
    c.run_scene(ONLY_MU, "--explain")
    c.no_crash()
    c.check(c.proc.returncode == 0, "the run with only mu converges (exit %d)" % c.proc.returncode)
    c.check("penalty" in computed(c), "run --explain prints the computed penalty")


def plugins_state_rules(c):
    c.run("plugins")
    c.check(c.proc.returncode == 0, "plugins exits 0")
    for plugin, key in [("penalty-nts", "penalty"), ("covariant-penalty", "penalty"), ("nts-augmented", "epsilon_t"),
                        ("mortar-dual", "c_n")]:
        block = c.proc.stdout.split("\n%s  (ABI" % plugin)[1].split("\n\n")[0]
        line = [l for l in block.splitlines() if l.strip().startswith(key + ":")]
        c.check(bool(line) and "computed from the scene:" in line[0], "%s lists %s as computed from the scene: %s" % (
            plugin, key, line))


def only_mu_runs(c):
    # the block pressed on the plane with only mu, two steps, with every contact plugin that takes a 3D obstacle and
    # no solver section: friction with the full Newton step alone stalls in nts-augmented at its default epsilon_t
    # (docs/plugins/nts-augmented.md#defaults); the default line search solves such a step again with backtracking
    for plugin in RULES:
        c.run_scene(ONLY_MU, "--plugin", plugin)
        c.no_crash()
        c.check(c.proc.returncode == 0, "%s runs with only mu (exit %d)" % (plugin, c.proc.returncode))


def explain_newton_defaults(c):
    # solver.newton.predicted_update: off by default (the confirming solve) for every scheme and plugin; a given value
    # wins; --explain prints it with the predictor
    lines = {}
    for label, scene, extra in (("quasi-static", ONLY_MU, ()),
                                ("backward-euler", ONLY_MU, ("--set", "time.scheme=backward-euler", "--set",
                                                             "bodies.0.material.density=1")),
                                ("given", ONLY_MU, ("--set", "solver.newton.predicted_update=true")),
                                ("multipliers", ONLY_MU, ("--plugin", "nts-augmented"))):
        c.run_scene(scene, *extra, "--explain", command="check")
        c.no_crash()
        lines[label] = [l.strip() for l in c.proc.stdout.splitlines() if l.strip().startswith("predicted_update")]
        c.check(any(l.strip().startswith("predictor") for l in c.proc.stdout.splitlines()),
                "%s: --explain prints the predictor" % label)
    for label in ("quasi-static", "backward-euler", "multipliers"):
        c.check(lines[label] and lines[label][0].split()[1] == "false:",
                "%s: predicted_update false by default (%s)" % (label, lines[label]))
    c.check(lines["given"] and lines["given"][0].split()[1] == "true:",
            "quasi-static with predicted_update=true given: true (%s)" % lines["given"])

def reference_keys():
    """Every key of docs/scene-reference.md's key tables, as `keys` spells it for the first body, boundary condition
    and contact pair."""
    prefixes = {"Top level": "", "mesh": "mesh.", "bodies": "bodies[0].", "boundary": "boundary[0].",
                "contact": "contact[0].", "time": "time.", "solver": "solver.", "output": "output.",
                "contact_balance": "contact_balance."}
    keys, prefix = [], None
    with open(os.path.join(ROOT, "docs", "scene-reference.md")) as f:
        for line in f:
            if line.startswith("## "):
                prefix = prefixes.get(line[3:].strip())
            elif line.startswith("### "):
                prefix = None  # the subsections' tables are not keys (plugins, rules)
            elif line.startswith("Obstacle keys:") and prefix == "contact[0].":
                prefix = "contact[0].obstacle."
            elif prefix is not None:
                match = re.match(r"^\| `([\w.]+)` \|", line)
                if match:
                    keys.append(prefix + match.group(1))
    return keys


# Keys the scene cannot have together with those it has: the pair has an obstacle (not `master`, nor `bodies:` with
# its `obstacles` and `self`), the boundary condition a displacement (not a traction or resultant with its `area`),
# the body no body plugin (whose `strategy` and `parameters` need one).
EXCLUSIVE = {"contact[0].master", "contact[0].bodies", "contact[0].obstacles", "contact[0].self",
             "boundary[0].traction", "boundary[0].resultant", "boundary[0].area", "bodies[0].strategy",
             "bodies[0].parameters"}
KEY_LINE = re.compile(r"^([\w.\[\]]+)  +(\S.*?)  +(?:\S.*?  +)?(default|computed from the scene: |[^ ]*\.yaml:\d+:\d+)",
                      re.M)


# a plugin parameter's value in the listing: a number, or one word of its choices in parentheses ("(dual)"); a rule
# in words ("(the mean master edge length)", "(3; 5 with line3 faces)") is not a value
PARAMETER_VALUE = re.compile(r"^(-?\d+(\.\d*)?(e[+-]?\d+)?|\([\w-]+\))$")


def number(text):
    try:
        return float(text)
    except ValueError:
        return None


def explain_every_key(c):
    # every key of the scene reference appears in --explain with its value and where it came from (given, default,
    # computed from the scene), and every plugin parameter of the pair as a number (or a choice), the one in use for
    # this pair: against an obstacle for every plugin, and on the pairs with a master of PAIR_SCENES
    keys = reference_keys()
    c.check(len(keys) > 60, "the scene reference lists %d keys" % len(keys))
    runs = [("obstacle", ONLY_MU, plugin, RULES[plugin]) for plugin in RULES]
    runs += [(name, scene_text(name), plugin, rules) for name, plugin, rules in PAIR_SCENES]
    for name, scene, plugin, rules in runs:
        c.run_scene(scene, "--plugin", plugin, "--explain", command="check")
        c.no_crash()
        c.check(c.proc.returncode == 0, "%s on %s: check passes (exit %d)" % (plugin, name, c.proc.returncode))
        lines = {m.group(1): (m.group(2), m.group(3)) for m in KEY_LINE.finditer(c.proc.stdout)}
        if plugin == "penalty-nts" and name == "obstacle":
            for key in keys:
                if key in EXCLUSIVE:
                    continue
                c.check(key in lines or any(k.startswith(key + ".") or k.startswith(key + "[") for k in lines),
                        "%s: --explain prints %s with its value and origin" % (plugin, key))
            for key in ("time.max_cuts", "output.vtu", "output.vtu_every", "output.contact_csv"):
                c.check(lines.get(key, ("", ""))[1] == "default", "%s is a default (%s)" % (key, lines.get(key)))
        params = {k: v for k, v in lines.items() if k.startswith("contact[0].parameters.")}
        c.check(len(params) > 3, "%s on %s: its parameters are printed (%d)" % (plugin, name, len(params)))
        for key, (value, origin) in params.items():
            c.check(PARAMETER_VALUE.match(value) is not None, "%s on %s: %s is printed as a number or a choice, not "
                    "a rule (%s; %s)" % (plugin, name, key, value, origin))
        reasons = computed(c)
        for key, (value, reason) in rules.items():
            got = params.get("contact[0].parameters." + key)
            got_value = number(got[0]) if got else None
            c.check(got is not None and got[1] == "computed from the scene: " and got_value is not None and
                    abs(got_value - value) <= 1e-5 * value, "%s on %s: %s printed as the number in use %g (%s)" % (
                        plugin, name, key, value, got))
            c.check(reason in reasons.get(key, (0, ""))[1], "%s on %s: %s's reason has '%s' (%s)" % (
                plugin, name, key, reason, reasons.get(key)))


if __name__ == "__main__":
    main({f.__name__: f for f in [explain_defaults, second_order_faces, given_value_wins, run_explain,
                                  plugins_state_rules, only_mu_runs, explain_newton_defaults, explain_every_key]})
