"""`contact: [{bodies: ...}]` through the driver: `check --explain` lists the pairs it creates and which the broad
phase keeps idle at the start; each mistake (an unknown body, a body listed twice, one body and no obstacle, a pair
given twice) fails cleanly with a message naming the key and the fix; `self: true` adds each listed body's self
pair, listed too, and refused for a plugin without self contact. Usage: python3 test_many_bodies.py CASE."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cli_case import MESHES, main, replace  # noqa: E402

# three disks side by side, the middle one touching neither (0.1 apart), the third far away
SCENE = """\
mesh:
  - {file: %(m)s/disk.geo, name: a, parameters: {radius: 0.5, refine: 0.5, cx: 0, cy: 0}}
  - {file: %(m)s/disk.geo, name: b, parameters: {radius: 0.5, refine: 1, cx: 1.1, cy: 0}}
  - {file: %(m)s/disk.geo, name: c, parameters: {radius: 0.5, refine: 0.5, cx: 6, cy: 0}}
bodies:
  - {name: left, group: a.body, material: {model: hooke, E: 1000, nu: 0.3, density: 1}}
  - {name: middle, group: b.body, material: {model: hooke, E: 1000, nu: 0.3, density: 1}}
  - {name: right, group: c.body, material: {model: hooke, E: 1000, nu: 0.3, density: 1}}
contact:
  - name: all
    bodies: all
    obstacles: [{type: plane, name: floor, point: [0, -0.6, 0], normal: [0, 1, 0]}]
    plugin: penalty-nts
time: {scheme: backward-euler, dt: 0.01, end: 0.02}
""" % {"m": MESHES}


def explain_lists_pairs(c):
    c.run_scene(SCENE, "--explain", command="check")
    c.check(c.proc.returncode == 0, "check exits 0")
    out = c.proc.stdout
    c.check("contact pairs created by `bodies:` (6;" in out, "--explain counts the 6 pairs (3 between bodies, 3 "
            "against the floor)")
    # the finer mesh (middle: refine 1) is slave against left; left and right are equal: the one listed first
    c.check("'all:middle/left': slave middle-boundary" in out, "the finer mesh is slave (middle against left)")
    c.check("'all:left/right': slave left-boundary" in out, "equal meshes: the body listed first is slave")
    c.check("'all:middle/left': slave middle-boundary (32 faces), master left-boundary (16 faces): near at the start"
            in out, "the touching-close pair is near at the start")
    c.check("'all:left/right': slave left-boundary (16 faces), master right-boundary (16 faces): apart at the start: "
            "idle" in out, "the far pair is idle at the start")
    c.check("'all:left/floor': slave left-boundary (16 faces), master floor: an obstacle: no broad phase" in out,
            "obstacle pairs are listed")


def refused(c, old, new, *patterns):
    """`check` of the scene with `old` replaced by `new` fails cleanly with a message matching every pattern."""
    c.run_scene(replace(SCENE, old, new), command="check")
    c.expect_failure(*patterns)


def unknown_body(c):
    refused(c, "bodies: all", "bodies: [left, centre]",
            r"scene\.yaml:\d+:\d+: unknown body 'centre' \(the scene's bodies: left, middle, right\)")


def body_listed_twice(c):
    refused(c, "bodies: all", "bodies: [left, middle, left]",
            r"scene\.yaml:\d+:\d+: key 'contact\[0\]\.bodies\[2\]': body 'left' is listed twice")


def one_body(c):
    refused(c, "bodies: all\n    obstacles: [{type: plane, name: floor, point: [0, -0.6, 0], normal: [0, 1, 0]}]",
            "bodies: [left]", r"scene\.yaml:\d+:\d+: `bodies` gives 1 body, no `obstacles` and no `self: true`: no pair "
            r"to create")


def not_a_body_list(c):
    refused(c, "bodies: all", "bodies: every", r"scene\.yaml:\d+:\d+: .*expects `all` or a list of body names")


def pair_given_twice(c):
    refused(c, "time:", "  - {name: extra, plugin: penalty-nts, slave: a.boundary, master: c.boundary}\ntime:",
            r"contact pair 'extra' puts bodies 'left' and 'right' in contact, and so does pair 'all:left/right'",
            r"given once")


def bodies_with_slave(c):
    refused(c, "bodies: all", "bodies: all\n    slave: a.boundary",
            r"scene\.yaml:\d+:\d+: `slave` does not go with `bodies`")


def obstacles_without_bodies(c):
    refused(c, "bodies: all", "slave: a.boundary\n    master: b.boundary", r"scene\.yaml:\d+:\d+: .*goes with `bodies`")


def self_pairs_listed(c):
    c.run_scene(replace(SCENE, "bodies: all", "bodies: all\n    self: true"), "--explain", command="check")
    out = c.proc.stdout
    c.check(c.proc.returncode == 0, "check exits 0")
    c.check("contact pairs created by `bodies:` (9;" in out, "--explain counts 9 pairs (3 between bodies, 3 against "
            "the floor, 3 self pairs)")
    for body, faces in (("left", 16), ("middle", 32), ("right", 16)):
        c.check("'all:%s/self': slave %s-boundary (%d faces), master %s-boundary: self contact: no broad phase" %
                (body, body, faces, body) in out, "the self pair of %s is listed" % body)
    c.run_scene(replace(SCENE, "bodies: all", "bodies: [middle]\n    self: true"), command="check")
    c.check(c.proc.returncode == 0, "one body with `self: true` and no other pair is enough")


def self_refused(c):
    # example-spring meets bodies and obstacles in 2D but declares no self contact: the created self pair is refused
    refused(c, "bodies: all\n    obstacles: [{type: plane, name: floor, point: [0, -0.6, 0], normal: [0, 1, 0]}]\n"
            "    plugin: penalty-nts", "bodies: all\n    self: true\n    plugin: example-spring",
            r"scene\.yaml:\d+:\d+: contact pair 'all:left/self': plugin 'example-spring' cannot run it: it lacks what "
            r"this scene needs: self-contact\. Plugins that can: .*penalty-nts")


def self_given_twice(c):
    scene = replace(SCENE, "bodies: all", "bodies: all\n    self: true")
    c.run_scene(replace(scene, "time:", "  - {name: extra, plugin: penalty-nts, slave: b.boundary, master: b.boundary}"
                        "\ntime:"), command="check")
    c.expect_failure(r"contact pair 'extra' puts body 'middle' in contact with itself, and so does pair "
                     r"'all:middle/self' \(.*scene\.yaml:\d+:\d+\): a body's self contact is given once")


def self_without_bodies(c):
    refused(c, "bodies: all\n    obstacles: [{type: plane, name: floor, point: [0, -0.6, 0], normal: [0, 1, 0]}]",
            "slave: a.boundary\n    master: a.boundary\n    self: true", r"scene\.yaml:\d+:\d+: .*'contact\[0\]\.self': "
            r"goes with `bodies`.*a single self pair gives `master` equal to `slave`")


CASES = {f.__name__: f for f in [explain_lists_pairs, unknown_body, body_listed_twice, one_body, not_a_body_list,
                                 pair_given_twice, bodies_with_slave, obstacles_without_bodies, self_pairs_listed,
                                 self_refused, self_given_twice, self_without_bodies]}

if __name__ == "__main__":
    main(CASES)
