"""Scenes a user writes from docs/scene-reference.md alone (tests/scenes-from-reference: no `solver` section, only
`mu` on the pair) with every plugin on the search path: `check` accepts the scene, or refuses it naming the reason
and the plugins that can — never a missing key —, and every plugin that accepts it runs it to the end.

  python3 test_scenes_from_reference.py CASE      (CASE: punch_2d, cube_on_slab_3d, half_ball_3d, spinning_disk_2d)"""
import math
import os
import re

from cli_case import ROOT, main, read_history, read_summary

SCENES = os.path.join(ROOT, "tests", "scenes-from-reference")
# Each scene's needs decide which plugins run it; a change in what a plugin accepts shows here.
CAN = {
    "punch-2d": {"penalty-nts", "nts-augmented", "mortar-dual"},
    "cube-on-slab-3d": {"penalty-nts", "nts-augmented", "covariant-penalty", "mortar-dual"},
    "half-ball-3d": {"penalty-nts", "nts-augmented", "covariant-penalty", "mortar-dual"},
    "spinning-disk-2d": {"penalty-nts", "nts-augmented"},
}
MU = 0.3
# The scenes start with the bodies touching at zero gap and friction: a full Newton step (the default) stalls at
# ||F||/||F0|| ~ 0.1 in step 1 for most of these pairs (punch, cube, and nts-augmented on the half ball) whatever the
# step size, and the backtracking line search solves them (docs/linear-solvers.md, "Line search": it is not the
# default because it fails other cases the full step runs).
RUN = ["--set", "solver.newton.line_search=backtrack", "--set", "output.vtu_every=0"]
REFUSED = re.compile(r"contact pair '\w+': plugin '([\w-]+)' cannot run it: (.+)\. Plugins that can: ([\w, -]+) \(")


def plugins_on_the_path(c):
    """The contact formulations on the search path: example-spring, a teaching example, is left out (`--plugin
    example-spring` drops the `mu` it does not know, with a warning, and then runs any pair frictionless)."""
    c.run("plugins")
    return [p for p in re.findall(r"^([\w-]+)  \(ABI", c.proc.stdout, re.M) if p != "example-spring"]


def checked(c, scene):
    """{plugin: accepted?} from `check --explain` with every plugin on the search path."""
    accepted = {}
    for plugin in plugins_on_the_path(c):
        c.run("check", scene, "--plugin", plugin, "--explain")
        c.no_crash()
        out = c.proc.stdout + c.proc.stderr
        c.check("missing key" not in out, "%s: no missing key" % plugin)
        if c.proc.returncode == 0:
            accepted[plugin] = True
            c.check("(computed: " in c.proc.stdout, "%s: --explain prints the parameters computed from the scene"
                    % plugin)
            continue
        accepted[plugin] = False
        refusal = REFUSED.search(c.proc.stderr)
        c.check(c.proc.returncode == 1 and refusal is not None,
                "%s: refused by check with the reason and the plugins that can (exit %d)" % (plugin, c.proc.returncode))
        if refusal:
            accepted.setdefault("can, as %s says" % plugin, set(refusal.group(3).split(", ")))
    return accepted


def coulomb_on_the_plane(c, history, plugin):
    """On the rigid plane the normal is fixed: the total tangential force stays within mu times the normal one and
    reaches it while the ball slides (the drag's last steps)."""
    ratios = []
    for row in history:
        normal = abs(row["contact_force_z"])
        if normal > 0:
            ratios.append(math.hypot(row["contact_force_x"], row["contact_force_y"]) / normal)
    c.check(bool(ratios) and max(ratios) <= MU * (1 + 1e-4), "%s: |F_t| <= mu F_n (max %.6f)" % (
        plugin, max(ratios or [0])))
    c.check(bool(ratios) and ratios[-1] >= 0.99 * MU, "%s: sliding at the end, |F_t| / F_n = %.6f" % (
        plugin, ratios[-1] if ratios else 0))


def runs(c, name):
    scene = os.path.join(SCENES, name + ".yaml")
    accepted = checked(c, scene)
    runnable = {p for p, ok in accepted.items() if ok is True}
    c.check(runnable == CAN[name], "check accepts exactly %s (got %s)" % (sorted(CAN[name]), sorted(runnable)))
    for key, named in accepted.items():
        if key.startswith("can, as "):
            c.check(named == runnable, "%s the plugins that can are those check accepts (%s)" % (key, sorted(named)))
    for plugin in sorted(runnable):
        out = os.path.join(c.dir, plugin)
        # a few CPU seconds (mortar-dual on the half ball: 18), minutes of wall time on a loaded machine
        c.run("run", scene, "--plugin", plugin, "--out", out, "--quiet", *RUN, timeout=240)
        c.no_crash()
        summary = read_summary(out) if os.path.exists(os.path.join(out, "summary.json")) else {}
        print("%s %s: status %s, t %s, steps %s, Newton iterations %s, step cuts %s" % (
            name, plugin, summary.get("status"), summary.get("final_time"), summary.get("steps"),
            summary.get("newton_iterations"), summary.get("step_cuts")))
        c.check(c.proc.returncode == 0 and summary.get("status") == "ok", "%s runs to the end (exit %d)" % (
            plugin, c.proc.returncode))
        if name == "half-ball-3d" and summary.get("status") == "ok":
            coulomb_on_the_plane(c, read_history(out), plugin)


def punch_2d(c):
    runs(c, "punch-2d")


def cube_on_slab_3d(c):
    runs(c, "cube-on-slab-3d")


def half_ball_3d(c):
    runs(c, "half-ball-3d")


def spinning_disk_2d(c):
    runs(c, "spinning-disk-2d")


if __name__ == "__main__":
    main({f.__name__: f for f in [punch_2d, cube_on_slab_3d, half_ball_3d, spinning_disk_2d]})
