"""What a plugin cannot run is refused by `check` and by `run` before anything starts (plugin ABI 2.7: capabilities
and sk_plugin.check): one case per refused combination, each asserting that the message names the plugin, the
reason and the plugins on the search path that can run the pair. Contact surfaces glued by shared mesh nodes are
refused with the node count and the fix; separately meshed bodies touching with coincident nodes are not.

  python3 test_capabilities.py CASE"""
import re

from cli_case import CONTACT, MESHES, main, replace, scene_text

PAIR = r"contact pair 'floor'"
ALL_3D = ["covariant-penalty", "mortar-dual", "nts-augmented", "penalty-nts"]


def alternatives(c):
    """{plugin: the strategy the list names for it, or None for its default} from 'Plugins that can: ' in the error
    (empty when none can)."""
    match = re.search(r"Plugins that can: ([^(]+?) \(", c.proc.stderr)
    entries = match.group(1).split(", ") if match else []
    return {e.split(" with strategy: ")[0]: (e.split(" with strategy: ") + [None])[1] for e in entries}


def refused(c, plugin, reason, can, cannot=(), pair=PAIR, itself=None):
    """The run or check failed with one message naming the pair, the plugin, the reason and exactly the plugins of
    `can` among those listed (and none of `cannot`); the refused plugin is listed only with its other strategy
    `itself` when one can run the pair."""
    c.expect_failure(pair, r"plugin '%s' cannot run it: " % re.escape(plugin), reason)
    listed = alternatives(c)
    for name in can:
        c.check(name in listed, "'%s' is listed among the plugins that can (%s)" % (name, listed))
    for name in cannot:
        c.check(name not in listed, "'%s' is not listed (%s)" % (name, listed))
    if itself:
        c.check(listed.get(plugin) == itself, "'%s with strategy: %s' is listed (%s)" % (plugin, itself, listed))
    else:
        c.check(plugin not in listed, "'%s' is not listed (%s)" % (plugin, listed))
    if not can and not itself:
        c.check("No plugin on the search path can run it" in c.proc.stderr, "says that no plugin can")


MIDPOINT = replace(replace(CONTACT, "scheme: quasi-static", "scheme: midpoint"), "nu: 0.3}", "nu: 0.3, density: 1}")


def mortar_midpoint(c):
    # mortar-dual enforces contact at t_(n+1): under the midpoint rule it used to fail in begin_step, after check
    c.run_scene(MIDPOINT, "--plugin", "mortar-dual", command="check")
    refused(c, "mortar-dual", r"scheme 'midpoint' balances forces at t_n \+ 0\.5 dt", ["penalty-nts", "nts-augmented",
                                                                                       "covariant-penalty"])
    # run refuses it before anything starts: no results folder
    c.run_scene(MIDPOINT, "--plugin", "mortar-dual")
    refused(c, "mortar-dual", r"supports quasi-static and backward-euler", ["penalty-nts"])


def mortar_quadratic(c):
    # hex27 (QUAD9 faces: the standard dual basis is admissible) and hex20 (QUAD8: the dual basis of the transformed
    # functions) run; condensed on QUAD8 slave faces is refused (D is not diagonal there)
    c.run_scene(CONTACT, "--plugin", "mortar-dual", "--set", "mesh.order=2", command="check")
    c.check(c.proc.returncode == 0, "mortar-dual takes QUAD9 faces (exit %d)" % c.proc.returncode)
    c.run_scene(CONTACT, "--plugin", "mortar-dual", "--set", "mesh.order=2", "--set", "mesh.serendipity=true",
                command="check")
    c.check(c.proc.returncode == 0, "mortar-dual takes QUAD8 faces (exit %d)" % c.proc.returncode)
    c.run_scene(CONTACT, "--plugin", "mortar-dual", "--set", "mesh.order=2", "--set", "mesh.serendipity=true",
                "--set", "contact.0.strategy=condensed", command="check")
    refused(c, "mortar-dual", r"strategy 'condensed'.*slave surface's QUAD8 faces D = diag\(int Phi_j\) T\^-T is not "
            r"diagonal.*use strategy: saddle-point", [], ["covariant-penalty", "nts-augmented", "penalty-nts"],
            itself="saddle-point")
    # tet10 (TRI6 faces): the same refusal lists mortar-dual with the strategy that runs them, and penalty-nts
    tet10 = replace(replace(CONTACT, "block.geo", "box-tet.geo"), "parameters: {nx: 2, ny: 2, nz: 2}",
                    "parameters: {h: 0.5}\n  order: 2")
    c.run_scene(tet10, "--plugin", "mortar-dual", "--set", "contact.0.strategy=condensed", command="check")
    refused(c, "mortar-dual", r"strategy 'condensed'.*TRI6 faces.*use strategy: saddle-point", ["penalty-nts"],
            ["covariant-penalty", "nts-augmented"], itself="saddle-point")
    c.check(re.search(r"Plugins that can: mortar-dual with strategy: saddle-point, penalty-nts \(", c.proc.stderr)
            is not None, "the list names the setting mortar-dual needs")
    # another plugin refused there names mortar-dual without a setting: its default strategy runs TRI6 faces
    c.run_scene(tet10, "--plugin", "nts-augmented", command="check")
    refused(c, "nts-augmented", r"TRI6 faces", ["penalty-nts", "mortar-dual"], ["covariant-penalty"])
    c.check(alternatives(c).get("mortar-dual", "") is None, "mortar-dual's default needs no setting (%s)"
            % alternatives(c))


def nts_curved_obstacle(c):
    text = replace(CONTACT, "obstacle: {type: plane, point: [0, 0, 0], normal: [0, 0, 1]}",
                   "obstacle: {type: sphere, point: [0.5, 0.5, -3], radius: 3}")
    c.run_scene(text, "--plugin", "nts-augmented", command="check")
    refused(c, "nts-augmented", r"plane obstacles only: obstacle 'sphere' is curved",
            ["penalty-nts", "covariant-penalty", "mortar-dual"])


def nts_quadratic(c):
    # hex27 (QUAD9 slave faces) runs; hex20's QUAD8 corners would need tensile nodal forces
    c.run_scene(CONTACT, "--plugin", "nts-augmented", "--set", "mesh.order=2", command="check")
    c.check(c.proc.returncode == 0, "nts-augmented takes QUAD9 slave faces (exit %d)" % c.proc.returncode)
    c.run_scene(CONTACT, "--plugin", "nts-augmented", "--set", "mesh.order=2", "--set", "mesh.serendipity=true",
                command="check")
    refused(c, "nts-augmented", r"slave surface 'zmin' has QUAD8 faces, whose corner nodes' consistent loads under "
            r"a uniform pressure are negative", ["mortar-dual"], ["covariant-penalty", "penalty-nts"])


def covariant_2d(c):
    c.run_scene(scene_text("patch-test-2d.yaml"), "--plugin", "covariant-penalty", command="check")
    refused(c, "covariant-penalty", r"lacks what this scene needs: 2d", ["penalty-nts", "nts-augmented",
                                                                        "mortar-dual"],
            pair=r"contact pair 'interface'")


def serendipity_slave(c):
    # hex20: QUAD8 slave faces, whose corners would need tensile forces at the nodes; of the plugins on the search
    # path only mortar-dual (the dual basis of the transformed functions) takes them
    for plugin in ["covariant-penalty", "penalty-nts"]:
        c.run_scene(CONTACT, "--plugin", plugin, "--set", "mesh.order=2", "--set", "mesh.serendipity=true",
                    command="check")
        refused(c, plugin, r"QUAD8", ["mortar-dual"], ["covariant-penalty", "penalty-nts", "nts-augmented"])


def friction_without_capability(c):
    # example-spring has no friction: mu > 0 is refused (it used to be an unknown key)
    text = replace(CONTACT, "parameters: {penalty: 1.0e4}", "parameters: {k: 100, mu: 0.3}")
    # the plugin named, not --plugin: --plugin drops the parameters the plugin does not list, mu among them
    c.run_scene(text, "--set", "contact.0.plugin=example-spring", command="check")
    refused(c, "example-spring", r"lacks what this scene needs: friction", ALL_3D)


def corotational_pair_off_its_body(c):
    # the corotational pair acts on corotational bodies only; the body here is integrated by the scene's midpoint
    c.run_scene(MIDPOINT, "--plugin", "corotational", command="check")
    refused(c, "corotational", r"corotational bodies only: the body of slave surface 'zmin' is integrated by "
            r"'midpoint'", ["penalty-nts", "nts-augmented"])


COROT = scene_text("corot-ball-on-plane.yaml")


def corotational_moving_plane(c):
    text = replace(COROT, "normal: [0, 1, 0]}", "normal: [0, 1, 0], motion: [[0, 0, 0, 0], [1, 1, 0, 0]]}")
    c.run_scene(text, command="check")
    refused(c, "corotational", r"planes at rest: obstacle 'plane' has a motion", ["penalty-nts", "nts-augmented"],
            ["mortar-dual", "covariant-penalty"])


def corotational_curved_obstacle(c):
    text = replace(COROT, "obstacle: {type: plane, point: [0, -10.5, 0], normal: [0, 1, 0]}",
                   "obstacle: {type: sphere, point: [0, -30.5, 0], radius: 20}")
    c.run_scene(text, command="check")
    refused(c, "corotational", r"rigid planes only \(the master of this pair is a curved obstacle 'sphere'\)",
            ["penalty-nts"], ["nts-augmented", "mortar-dual", "covariant-penalty"])


def corotational_spin_off_axis(c):
    # the co-rotational body spins about its plugin's axis: another spin was refused only at the first step
    text = replace(scene_text("corot-torus-on-plane.yaml"), "angular_velocity: [0, 0, 20]",
                   "angular_velocity: [0, 5, 20]")
    c.run_scene(text, command="check")
    c.expect_failure(r"body 'torus'", r"corotational", r"angular_velocity \(0, 5, 20\) is not along the plugin's "
                     r"axis \(0, 0, 1\)")


def accepted_combination(c):
    # the same scenes with a plugin that can: check passes and names the plugin
    c.run_scene(MIDPOINT, "--plugin", "nts-augmented", "--replace", "contact.0.parameters={}", command="check")
    c.no_crash()
    c.check(c.proc.returncode == 0, "nts-augmented runs the midpoint scene (exit %d)" % c.proc.returncode)
    c.run_scene(CONTACT, "--set", "mesh.order=2", command="check")
    c.check(c.proc.returncode == 0, "penalty-nts takes hex27's QUAD9 faces (exit %d)" % c.proc.returncode)


GLUED_GEO = """\
// two squares meshed as one: the edge y = 1 is both bodies' (their nodes there are shared: the gmsh trap)
h = 0.25;
Point(1) = {0, 0, 0, h}; Point(2) = {1, 0, 0, h}; Point(3) = {1, 1, 0, h}; Point(4) = {0, 1, 0, h};
Point(5) = {1, 2, 0, h}; Point(6) = {0, 2, 0, h};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Line(5) = {3, 5}; Line(6) = {5, 6}; Line(7) = {6, 4};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Curve Loop(2) = {-3, 5, 6, 7}; Plane Surface(2) = {2};
Physical Surface("lower") = {1};
Physical Surface("upper") = {2};
Physical Curve("lower-top") = {3};
Physical Curve("upper-bottom") = {3};
Physical Curve("lower-bottom") = {1};
Physical Curve("upper-top") = {6};
"""

GLUED = """\
mesh: {file: glued.geo}
bodies:
  - {name: lower, group: lower, material: {model: hooke, E: 1000, nu: 0.3}}
  - {name: upper, group: upper, material: {model: hooke, E: 1000, nu: 0.3}}
boundary:
  - {name: base, group: lower-bottom, displacement: [0, 0]}
  - {name: top, group: upper-top, displacement: [0.1, -0.01]}
contact:
  - {name: interface, plugin: penalty-nts, slave: upper-bottom, master: lower-top, parameters: {mu: 0.3}}
time: {scheme: quasi-static, dt: 0.5, end: 1}
"""

SEPARATE = """\
mesh:
  - {name: lower, file: %s/patch-test-2d.geo, parameters: {nx_lower: 4, nx_upper: 4}}
bodies:
  - {name: lower, group: lower.lower, material: {model: hooke, E: 1000, nu: 0.3}}
  - {name: upper, group: lower.upper, material: {model: hooke, E: 1000, nu: 0.3}}
boundary:
  - {name: base, group: lower.lower-bottom, displacement: [0, 0]}
  - {name: top, group: lower.upper-top, displacement: [0, -0.01]}
contact:
  - {name: interface, plugin: penalty-nts, slave: lower.upper-bottom, master: lower.lower-top}
time: {scheme: quasi-static, dt: 0.5, end: 1}
""" % MESHES


def glued_interface(c):
    c.write(GLUED_GEO, "glued.geo")
    for command in ["check", "run"]:
        c.run_scene(GLUED, command=command)
        c.expect_failure(r"contact pair 'interface'", r"slave surface 'upper-bottom' and the master surface "
                         r"'lower-top' share 5 of their 5 and 5 mesh nodes", r"meshed as one",
                         r"Mesh the bodies separately", r"`mesh` list")
    # the same interface meshed as two bodies whose interface nodes coincide (matching meshes, nodes not shared)
    # is legitimate initial touching: check passes and the run presses the upper block down through contact
    c.run_scene(SEPARATE)
    c.no_crash()
    c.check(c.proc.returncode == 0, "matching but separate interface nodes run (exit %d)" % c.proc.returncode)


if __name__ == "__main__":
    main({f.__name__: f for f in [mortar_midpoint, mortar_quadratic, nts_curved_obstacle, nts_quadratic, covariant_2d,
                                  serendipity_slave, friction_without_capability, corotational_pair_off_its_body,
                                  corotational_moving_plane, corotational_curved_obstacle, corotational_spin_off_axis,
                                  accepted_combination,
                                  glued_interface]})
