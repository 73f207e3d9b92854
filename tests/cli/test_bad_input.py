"""Bad input through the driver: each case writes a small broken scene (or command line) into a temporary folder and
checks that stickslip fails cleanly — exit code 1 (not a signal), one clear message on stderr naming the culprit
(file:line, key, group, ...), no traceback or crash, and no results folder. Usage: python3 test_bad_input.py CASE."""
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cli_case import BLOCK, CONTACT, MESHES, PLUGIN_DIR, ROOT, main, read_summary, replace  # noqa: E402


# ---- cases -----------------------------------------------------------------------------------------------------------

def malformed_yaml(c):
    c.run_scene(replace(BLOCK, "  dt: 0.25\n", "  dt: [0.25\n"))
    c.expect_failure(r"scene\.yaml:\d+:\d+:", r"scene\.yaml:2[2-4]:")  # the line of the broken flow sequence


def unknown_key(c):
    c.run_scene(replace(BLOCK, "density: 1", "densty: 1"))
    c.expect_failure(r"scene\.yaml:14:\d+", r"unknown key 'bodies\[0\]\.material\.densty'", r"did you mean 'density'")


def misspelt_required_key(c):
    """A required key misspelt is reported as missing at the line of the misspelling, which it names."""
    c.run_scene(replace(BLOCK, "scheme:", "shceme:"))
    c.expect_failure(r"scene\.yaml:\d+:\d+: missing key 'time\.scheme' \('time\.shceme' is there: a misspelling\?\)")


def missing_mesh_file(c):
    c.run_scene(replace(BLOCK, "block.geo", "no-such-block.geo"))
    c.expect_failure(r"scene\.yaml:\d+", r"no-such-block\.geo", r"(cannot open|No such file)")


def unknown_mesh_parameter(c):
    c.run_scene(replace(BLOCK, "nz: 3", "nzz: 3"))
    c.expect_failure(r"scene\.yaml:\d+", r"unknown parameter 'nzz'", r"nx, ny, nz")


def missing_group(c):
    c.run_scene(replace(BLOCK, "group: zmin", "group: zbottom"))
    c.expect_failure(r"scene\.yaml:\d+", r"boundary\[2\]\.group", r"no physical group 'zbottom'", r"zmin", r"body")


def material_nu(c):
    c.run_scene(replace(BLOCK, "nu: 0.3", "nu: 0.6"))
    c.expect_failure(r"scene\.yaml:14:\d+", r"body 'block'", r"nu = 0\.6", r"0\.5")


def material_E(c):
    c.run_scene(replace(BLOCK, "E: 1000", "E: -1"))
    c.expect_failure(r"scene\.yaml:14:\d+", r"body 'block'", r"E = -1", r"> 0")


def negative_dt(c):
    c.run_scene(replace(BLOCK, "dt: 0.25", "dt: -0.25"))
    c.expect_failure(r"scene\.yaml:\d+", r"time\.dt", r"positive")


def unknown_scheme(c):
    c.run_scene(replace(BLOCK, "scheme: quasi-static", "scheme: leapfrog"))
    c.expect_failure(r"scene\.yaml:\d+", r"time\.scheme", r"leapfrog", r"quasi-static", r"backward-euler",
                     r"midpoint")


def plugin_without_contact(c):
    """--plugin on a scene without contact pairs would silently change nothing: refused, for run and check."""
    for command in ("run", "check"):
        c.run_scene(BLOCK, "--plugin", "penalty-nts", command=command)
        c.expect_failure(r"--plugin penalty-nts", r"scene\.yaml has no contact pairs")


def mesh_order(c):
    """mesh.order out of range, and serendipity without order 2, name the key."""
    c.run_scene(replace(BLOCK, "  file: ", "  order: 3\n  file: "))
    c.expect_failure(r"scene\.yaml:\d+", r"key 'mesh\.order'", r"1 or 2")
    c.run_scene(replace(BLOCK, "  file: ", "  serendipity: true\n  file: "))
    c.expect_failure(r"scene\.yaml:\d+", r"key 'mesh\.serendipity'", r"order: 2")


def old_minor_plugin(c):
    """A plugin built for ABI 2.0 is not attached to second-order faces (it predates their element types); on a
    first-order mesh the host gets past that check (the test plugin then fails in create, on purpose)."""
    env = {"STICKSLIP_PLUGIN_PATH": os.environ["STICKSLIP_CLI_MINOR0_DIR"]}
    scene = replace(replace(CONTACT, "plugin: penalty-nts", "plugin: old-minor"), "  file: ",
                    "  order: 2\n  serendipity: true\n  file: ")  # hex20: QUAD8 faces (quad9 is an ABI 2.0 type)
    c.run_scene(scene, command="check", env=env)
    c.expect_failure(r"old-minor", r"ABI 2\.0", r"'zmin' \(quad8 cells\)", r"rebuild it against ABI 2\.\d+")
    c.run_scene(replace(CONTACT, "plugin: penalty-nts", "plugin: old-minor"), command="check", env=env)
    c.check(c.proc.returncode != 0 and "predates" not in c.proc.stderr, "first-order faces pass the ABI check")


def unknown_plugin(c):
    c.run_scene(replace(CONTACT, "plugin: penalty-nts", "plugin: mortar-magic"))
    c.expect_failure(r"scene\.yaml:\d+", r"contact pair 'floor'", r"unknown plugin 'mortar-magic'",
                     r"available: .*penalty-nts", r"nts-augmented")


def unknown_linear_solver(c):
    c.run_scene(BLOCK, "--set", "solver.linear.solver=superlu")
    c.expect_failure(r"solver\.linear\.solver", r"superlu", r"direct", r"gmres-muelu", r"gmres-ilu", r"auto")


def section_not_a_map(c):
    c.run_scene(BLOCK, "--set", "solver=3")
    c.expect_failure(r"--set solver", r"key 'solver'", r"expects a map")
    c.run_scene(BLOCK, "--set", "time=3")
    c.expect_failure(r"--set time", r"'time' should be a map")


def bad_set(c):
    c.run_scene(BLOCK, "--set", "time.dt")
    c.expect_failure(r"--set expects key\.path=value", r"time\.dt")
    c.run_scene(BLOCK, "--set", "time..dt=3")
    c.expect_failure(r"--set", r"time\.\.dt", r"empty part")


def unknown_option(c):
    c.run_scene(BLOCK, "--frobnicate")
    c.expect_failure(r"unknown option '--frobnicate'", r"--help")
    c.run("run", os.path.join(ROOT, "scenes", "compressed-block.yaml"), "--steps", "zero", "--out", c.out)
    c.expect_failure(r"--steps expects a positive integer", r"zero")


def missing_scene(c):
    c.run("run", os.path.join(c.dir, "nowhere.yaml"), "--out", c.out)
    c.expect_failure(r"nowhere\.yaml", r"(cannot open|No such file)")
    c.run("run", "--out", c.out)
    c.expect_failure(r"which scene")


def conflicting_displacements(c):
    """Two displacement conditions on dofs they share must agree at every time (else the list order decides)."""
    c.run_scene(replace(BLOCK, "displacement: [0, ~, ~]}", "displacement: [0, ~, 0.01], history: [[0, 0], [1, 1]]}"))
    c.expect_failure(r"scene\.yaml:18:\d+: boundary 'base' and boundary 'roller-x' \(.*scene\.yaml:16:\d+\)",
                     r"different z displacements", r"0 against 0\.01 at t = 1", r"free the component in one of them")
    c.run_scene(replace(BLOCK, "displacement: [0, ~, ~]}", "displacement: [0, ~, 0]}"), command="check")
    c.check(c.proc.returncode == 0, "conditions that agree on their shared edge are accepted")


def check_good(c):
    c.run_scene(BLOCK, command="check")
    c.no_crash()
    c.check(c.proc.returncode == 0, "check of a good scene exits 0")
    c.check(re.search(r"ok — 3D, 64 nodes, 27 elements", c.proc.stdout) is not None, "check reports the model")
    c.check(not os.path.exists(c.out), "check writes no results")
    c.run_scene(CONTACT, command="check")
    c.check(c.proc.returncode == 0, "check of a contact scene exits 0")
    c.check("pair 'floor': plugin penalty-nts" in c.proc.stdout, "check lists the contact pair")


def check_bad(c):
    c.run_scene(replace(BLOCK, "nu: 0.3", "nu: 0.6"), command="check")
    c.expect_failure(r"scene\.yaml:14:\d+", r"nu = 0\.6")


def plugins_list(c):
    c.run("plugins")
    c.no_crash()
    c.check(c.proc.returncode == 0, "plugins exits 0")
    for name in ["penalty-nts", "nts-augmented"]:
        c.check(re.search(r"^%s  \(ABI 2\.\d+\)" % name, c.proc.stdout, re.M) is not None, "lists %s" % name)
    c.check("attaches to:  pair" in c.proc.stdout, "shows what plugins attach to")
    c.check("capabilities:" in c.proc.stdout and "strategies:" in c.proc.stdout, "shows capabilities and strategies")
    c.check("penalty:" in c.proc.stdout, "shows penalty-nts's parameters")


def bad_abi_plugin(c):
    library = os.path.join(PLUGIN_DIR, "libstickslip-bad-abi.so")
    c.check(os.path.exists(library), "test plugin built: %s" % library)
    env = {"STICKSLIP_PLUGIN_PATH": PLUGIN_DIR}
    # listing: a warning about the broken library, the good plugins still listed
    c.run("plugins", env=env)
    c.no_crash()
    c.check(c.proc.returncode == 0, "plugins still exits 0")
    c.check(re.search(r"warning: .*libstickslip-bad-abi\.so.*ABI version 1;.*port it", c.proc.stderr) is not None,
            "plugins warns about the ABI version 1 library")
    c.check("penalty-nts" in c.proc.stdout, "the good plugins are still listed")
    # requesting it: a clear failure naming the ABI mismatch
    c.run_scene(replace(CONTACT, "plugin: penalty-nts", "plugin: bad-abi"), env=env)
    c.expect_failure(r"scene\.yaml:\d+", r"bad-abi", r"ABI version 1;")
    # other plugins keep working with the broken library on the path
    c.run_scene(CONTACT, command="check", env=env)
    c.check(c.proc.returncode == 0, "a scene using penalty-nts still checks with the broken library present")


def capability_mismatch(c):
    # the co-rotational schemes are dynamic only: a quasi-static scene is refused before any work
    c.run_scene(replace(CONTACT, "parameters: {penalty: 1.0e4}", "parameters: {mu: 0.1}"), "--plugin", "corotational")
    c.expect_failure(r"scene\.yaml:\d+", r"contact pair 'floor'", r"corotational", r"lacks", r"quasi-static")


def unknown_strategy(c):
    c.run_scene(replace(CONTACT, "parameters: {penalty: 1.0e4}", "parameters: {penalty: 1.0e4}\n    strategy: reduced"))
    c.expect_failure(r"scene\.yaml:\d+", r"penalty-nts", r"no strategy 'reduced'", r"offers: none")


def inverted_element(c):
    text = replace(BLOCK, "model: hooke", "model: neo-hooke")
    text = replace(text, "[0, 0, -10]", "[0, 0, -1.0e5]")
    # the full Newton step (named: backtracking converges this load) inverts elements
    c.run_scene(text, "--set", "time.max_cuts=3", "--set", "solver.newton.line_search=full-step")
    c.expect_failure(r"step cuts", r"(inverted|no convergence)", out_created=True)
    summary = os.path.join(c.out, "summary.json")
    c.check(os.path.exists(summary), "the run had started: summary.json written")
    if os.path.exists(summary):
        data = read_summary(c.out)
        c.check(data.get("status") == "failed", "summary.json status 'failed' (got %r)" % data.get("status"))
        c.check("step cuts" in data.get("message", ""), "summary.json carries the message")
        c.check(os.path.exists(os.path.join(c.out, "history.csv")), "history.csv written (initial row)")


def inverted_by_prescribed_displacement(c):
    """A top pushed through the block by a prescribed displacement against a frictionless multiplier contact (which
    holds the base): the elements invert at the first Newton point. The message names the body and the element once
    (it said "body 'block': body 'block', element 0: ..."), exit 1, and the results up to the last converged step."""
    text = replace(CONTACT, "displacement: [0, 0, -0.01]}", "displacement: [0, 0, -1.2], history: [[0, 0], [0.5, 0], "
                   "[1, 1]]}")
    text = replace(text, "plugin: penalty-nts", "plugin: nts-augmented")
    text = replace(replace(text, "parameters: {penalty: 1.0e4}", "parameters: {mu: 0}"), "model: hooke", "model: svk")
    c.run_scene(text, "--set", "time.max_cuts=2")
    c.expect_failure(r"step \d+ from t = ", r"body 'block', element \d+: hex8 element inverted: det F = ",
                     out_created=True)
    c.check(c.proc.stderr.count("body 'block'") == 1, "the body named once (stderr: %r)" % c.proc.stderr)
    c.check(os.path.exists(os.path.join(c.out, "history.csv")) and read_summary(c.out).get("status") == "failed",
            "results up to the last converged step, status failed")


SPINNING = """\
description: a spinning block integrated by a body plugin
mesh:
  file: %s/block.geo
  parameters: {nx: 2, ny: 2, nz: 2}
bodies:
  - name: block
    group: body
    material: {model: svk, E: 1000, nu: 0.3, density: 1}
    angular_velocity: [0, 3, 0]
    plugin: corotational
time: {scheme: midpoint, dt: 0.01, end: 0.02}
""" % MESHES


def body_plugin_refusal_position(c):
    """A body plugin that refuses the body (the spin is not about its default axis e_z) is reported at the body's
    `plugin` key, file:line:col, also when the body gives no `parameters` (the plugin's message has no position)."""
    c.run_scene(SPINNING, command="check")
    c.expect_failure(r"scene\.yaml:10:\d+: body 'block' \(plugin corotational\)", r"angular_velocity")
    c.run_scene(replace(SPINNING, "plugin: corotational", "plugin: corotational\n    parameters: {model: 1}"),
                command="check")
    c.expect_failure(r"scene\.yaml:11:\d+: body 'block' \(plugin corotational\)", r"angular_velocity")


CASES = {f.__name__: f for f in [
    malformed_yaml, unknown_key, misspelt_required_key, missing_mesh_file, unknown_mesh_parameter, missing_group,
    material_nu, material_E, negative_dt, unknown_scheme, unknown_plugin, unknown_linear_solver, section_not_a_map,
    bad_set, unknown_option, missing_scene, check_good, check_bad, plugins_list, bad_abi_plugin,
    capability_mismatch, unknown_strategy, inverted_element, plugin_without_contact, mesh_order, old_minor_plugin,
    conflicting_displacements, body_plugin_refusal_position,
    inverted_by_prescribed_displacement]}

if __name__ == "__main__":
    main(CASES)
