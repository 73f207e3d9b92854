"""The reproducers of issue 15 that live in the input: each one, through the driver, must end with exit 1 and one
clear message naming the file, key, parameter, group or element — no crash, no hang, no silently wrong run, no
command run on the user's behalf. Usage: python3 test_hostile_input.py CASE. (The results-folder reproducers are in
test_results_folder.py.)"""
import os
import re
import resource
import signal
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cli_case import BIN, BLOCK, CONTACT, MESHES, ROOT, main, replace, scene_text  # noqa: E402

HERTZ = scene_text("hertz-2d.yaml")
PLUGINS = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(os.environ.get(
    "STICKSLIP_BIN", os.path.join(ROOT, "build", "bin", "stickslip"))))), "lib", "stickslip", "plugins")


def gmsh_exception(c):
    """Item 1: sizes gmsh cannot mesh with used to abort stickslip (an uncaught exception thrown inside OpenMP)."""
    for parameter, shown in [("h_contact=0", "h_contact = 0"), ("h_far=0", "h_far = 0"),
                             ("h_contact=-1", "h_contact = -1"), ("refine=-3", "refine = -3")]:
        c.run_scene(HERTZ, "--set", "mesh.parameters." + parameter, command="check")
        c.expect_failure(r"scene\.yaml:\d+:\d+: mesh .*hertz-2d\.geo: gmsh failed to generate the 1D mesh",
                         r"Wrong mesh element size", re.escape(shown))


def mesh_size_guard(c):
    """Item 2: refine = 1e6 meshed until killed; now refused in seconds, with the limit named and raisable."""
    # CPU seconds of the child, not wall time: a loaded machine stretches the wall clock, not the work done (without
    # the guard gmsh meshed for minutes of CPU until it was killed).
    start = resource.getrusage(resource.RUSAGE_CHILDREN)
    c.run_scene(HERTZ, "--set", "mesh.parameters.refine=1e6", command="check")
    end = resource.getrusage(resource.RUSAGE_CHILDREN)
    spent = (end.ru_utime + end.ru_stime) - (start.ru_utime + start.ru_stime)
    c.expect_failure(r"hertz-2d\.geo: meshing the curves alone asked for the mesh size at", r"mesh\.max_elements = "
                     r"1000000", r"refine = 1e\+06")
    c.check(spent < 30, "refused after %.1f s of CPU" % spent)
    c.run_scene(BLOCK, "--set", "mesh.max_elements=10", command="check")
    c.expect_failure(r"block\.geo: the mesh would have about 27 elements, more than mesh\.max_elements = 10")
    c.run_scene(BLOCK, "--set", "mesh.max_elements=27", command="check")
    c.check(c.proc.returncode == 0, "the limit can be raised")
    c.run_scene(BLOCK, "--set", "mesh.max_elements=0", command="check")
    c.expect_failure(r"max_elements must be at least 1")


def broken_plugin_files(c):
    """Item 3: a truncated .so in the plugin path gave a bus error in `plugins` and in `check` of every scene."""
    folder = os.path.join(c.dir, "plugins")
    os.makedirs(folder)
    good = os.path.join(PLUGINS, "libstickslip-penalty-nts.so")
    c.check(os.path.exists(good), "a real plugin to truncate: %s" % good)
    data = open(good, "rb").read()
    for size, name in [(len(data) // 2, "half"), (len(data) - 1, "short"), (64, "header")]:
        with open(os.path.join(folder, "libstickslip-%s.so" % name), "wb") as f:
            f.write(data[:size])
    with open(os.path.join(folder, "libstickslip-junk.so"), "w") as f:
        f.write("not a library\n")
    os.mkfifo(os.path.join(folder, "libstickslip-fifo.so"))
    env = {"STICKSLIP_PLUGIN_PATH": folder}
    c.run("plugins", env=env)
    c.no_crash()
    c.check(c.proc.returncode == 0, "plugins exits 0")
    for name in ["half", "short", "header"]:
        c.check(re.search(r"warning: plugin library .*libstickslip-%s\.so is truncated" % name, c.proc.stderr)
                is not None, "a warning names the truncated %s library" % name)
    c.check("libstickslip-junk.so is not an ELF shared library" in c.proc.stderr, "a warning names the junk file")
    c.check("libstickslip-fifo.so is not a regular file" in c.proc.stderr, "a warning names the FIFO")
    c.check("penalty-nts" in c.proc.stdout, "the good plugins are listed")
    c.run_scene(CONTACT, command="check", env=env)
    c.check(c.proc.returncode == 0 and c.proc.stderr == "", "a scene using penalty-nts checks, without a word about "
                                                            "the broken files (they are not opened)")
    c.run_scene(replace(CONTACT, "plugin: penalty-nts", "plugin: half"), command="check", env=env)
    c.expect_failure(r"scene\.yaml:\d+:\d+: contact pair 'floor': plugin 'half' cannot be used: plugin library "
                     r".*libstickslip-half\.so is truncated", r"Rebuild or reinstall it")


def empty_sections(c):
    """Item 8: an empty or null section said `configuration: missing key 'model'`, with no file, line or path."""
    for key, path, missing in [("bodies.0.material", r"bodies\[0\]\.material", "model"), ("time", "time", "scheme"),
                               ("boundary.0", r"boundary\[0\]", "group"), ("mesh.rotate", r"mesh\.rotate", "axis")]:
        c.run_scene(BLOCK, "--set", key + "=~", command="check")
        c.expect_failure(r"--set %s: '%s' is empty; missing key '%s\.%s'" % (re.escape(key), path, path, missing))
    c.run_scene(replace(CONTACT, "obstacle: {type: plane, point: [0, 0, 0], normal: [0, 0, 1]}", "obstacle:"),
                command="check")
    c.expect_failure(r"scene\.yaml:\d+:5: 'contact\[0\]\.obstacle' is empty; missing key 'contact\[0\]\.obstacle\.type'")
    c.run_scene(replace(BLOCK, "material: {model: hooke, E: 1000, nu: 0.3, density: 1}", "material: null"),
                command="check")
    c.expect_failure(r"scene\.yaml:\d+:5: 'bodies\[0\]\.material' is empty; missing key")


def non_finite(c):
    """Item 12: nan/inf were accepted by check (and time.end=.inf ran 0 steps, reporting ok)."""
    cases = [
        (BLOCK, "time.end=.inf", r"key 'time\.end' expects a finite number, got '\.inf'"),
        (BLOCK, "time.dt=.nan", r"key 'time\.dt' expects a finite number"),
        (BLOCK, "bodies.0.velocity=[0, .nan, 0]", r"key 'bodies\[0\]\.velocity\[1\]' expects a finite number"),
        (BLOCK, "boundary.0.displacement=[.inf, ~, ~]", r"key 'boundary\[0\]\.displacement\[0\]' expects a finite"),
        (BLOCK, "boundary.3.history=[[0, 0], [1, .nan]]", r"key 'boundary\[3\]\.history\[1\]\[1\]' expects a finite"),
        (BLOCK, "body_force=[0, 0, -.inf]", r"key 'body_force\[2\]' expects a finite number"),
        (BLOCK, "solver.newton.tolerance=.nan", r"key 'solver\.newton\.tolerance' expects a finite number"),
        (BLOCK, "mesh.parameters.nx=.inf", r"key 'mesh\.parameters\.nx' expects a finite number"),
        (BLOCK, "bodies.0.material.E=1e999", r"key 'bodies\[0\]\.material\.E' expects a finite number, got '1e999'"),
        (CONTACT, "contact.0.obstacle.point=[0, 0, .nan]", r"key 'contact\[0\]\.obstacle\.point\[2\]' expects a finite"),
        (CONTACT, "contact.0.parameters.penalty=.inf", r"key 'contact\[0\]\.parameters\.penalty' expects a finite"),
        (BLOCK, "time.dt=1e-300", r"key 'time\.dt': is too small to advance the time"),
    ]
    for scene, assignment, message in cases:
        c.run_scene(scene, "--set", assignment, command="check")
        c.expect_failure(message)
    c.run_scene(BLOCK, "--set", "time.end=.inf")
    c.expect_failure(r"time\.end")


def write_msh(c, name, node9, elements):
    """A .msh with the nodes of a unit cube (1-8), node 9 and the given $Elements lines."""
    text = ("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n3\n3 1 \"block\"\n3 2 \"other\"\n2 3 \"bottom\"\n"
            "$EndPhysicalNames\n$Nodes\n9\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 0 0 1\n6 1 0 1\n7 1 1 1\n8 0 1 1\n"
            "9 %s\n$EndNodes\n$Elements\n%d\n%s$EndElements\n" % (node9, elements.count("\n"), elements))
    return c.write(text, name)


def msh_scene(path, bodies):
    return ("mesh: {file: %s}\nbodies:\n%s\ntime: {scheme: quasi-static, dt: 1, end: 1}\n" % (path, bodies))


def geometry_errors(c):
    """Item 9: a non-finite coordinate or an inverted element said "hex8 element: reference Jacobian det J = nan"
    with no file, body or element."""
    body = "  - {name: cube, group: block, material: {model: hooke, E: 1, nu: 0.3}}"
    path = write_msh(c, "nan.msh", "nan 0 0", "1 5 2 1 1 1 2 3 4 5 6 7 8\n2 15 2 2 9 9\n")
    c.run_scene(msh_scene(path, body), command="check")
    c.expect_failure(r"scene\.yaml:1:7: mesh .*nan\.msh: node \d+ has a non-finite coordinate")
    path = write_msh(c, "twisted.msh", "2 2 2", "1 5 2 1 1 1 2 4 3 5 6 7 8\n")
    c.run_scene(msh_scene(path, body), command="check")
    c.expect_failure(r"mesh .*twisted\.msh: physical group 'block', element 0 \(of 1; first node at \(0, 0, 0\)\): "
                     r"inverted \(twisted\) at corner")


def shared_group(c):
    """Item 13: two bodies on the same physical group counted every element twice (double stiffness, exit 0)."""
    text = scene_text("free-flight-blocks.yaml")
    c.run_scene(text, "--set", "bodies.1.group=upper", command="check")
    c.expect_failure(r"scene\.yaml:\d+:\d+: body 'upper' and body 'lower' both use physical group 'upper'",
                     r"would count twice")
    path = write_msh(c, "overlap.msh", "2 2 2", "1 5 2 1 1 1 2 3 4 5 6 7 8\n2 5 2 2 2 2 3 4 1 6 7 8 5\n")
    bodies = ("  - {name: a, group: block, material: {model: hooke, E: 1, nu: 0.3}}\n"
              "  - {name: b, group: other, material: {model: hooke, E: 1, nu: 0.3}}")
    c.run_scene(msh_scene(path, bodies), command="check")
    c.expect_failure(r"overlap\.msh: physical group 'other', element 0", r"body 'a' and body 'b' overlap")


def collapsed_element(c):
    """Item 14: a hex with a repeated node was accepted (the initial energy changed from 5.8 to 4.35)."""
    path = write_msh(c, "collapsed.msh", "2 2 2", "1 5 2 1 1 1 2 3 3 5 6 7 8\n")
    body = "  - {name: cube, group: block, material: {model: hooke, E: 1, nu: 0.3}}"
    c.run_scene(msh_scene(path, body), command="check")
    c.expect_failure(r"scene\.yaml:1:7: mesh .*collapsed\.msh: physical group 'block', element 0",
                     r"its nodes 2 and 3 are the same node \(a collapsed element\)")


def system_call(c):
    """Item 16: `stickslip check` ran the shell commands of a .geo file's SystemCall."""
    marker = os.path.join(c.dir, "pwned")
    geo = open(os.path.join(MESHES, "block.geo")).read()
    c.write('// a scene shared by someone else\nInclude "block.geo";\nSystemCall "touch %s";\n' % marker, "evil.geo")
    c.write(geo, "block.geo")
    text = replace(BLOCK, os.path.join(MESHES, "block.geo"), "evil.geo")
    c.run_scene(text, command="check")
    c.expect_failure(r"scene\.yaml:\d+:\d+: mesh script .*evil\.geo:3: 'SystemCall' runs a shell command",
                     r"--trust-scripts")
    c.check(not os.path.exists(marker), "the command did not run")
    c.run_scene(text, "--trust-scripts", command="check")
    c.check(c.proc.returncode == 0 and os.path.exists(marker), "with --trust-scripts it runs")


def special_files(c):
    """Item 17: a FIFO or /dev/zero as the scene, a .geo that loops forever, a very fine h_contact: hung until
    killed."""
    fifo = os.path.join(c.dir, "fifo.yaml")
    os.mkfifo(fifo)
    for path, what in [(fifo, r"is a FIFO \(named pipe\), not a regular file"),
                       ("/dev/zero", r"'/dev/zero' is a character device"), (c.dir, r"is a directory")]:
        start = time.time()
        c.run("check", path)
        c.expect_failure(r"scene file '.*' " + what if path != "/dev/zero" else what)
        c.check(time.time() - start < 20, "answered at once")
    c.write("For i In {1:1e15}\n  x = i;\nEndFor\n", "loop.geo")
    start = time.time()
    c.run_scene(replace(BLOCK, os.path.join(MESHES, "block.geo"), "loop.geo").replace(
        "  parameters: {nx: 3, ny: 3, nz: 3}\n", "  time_limit: 2\n"), command="check")
    c.expect_failure(r"loop\.geo: gmsh did not finish within 2 s while evaluating the script", r"mesh\.time_limit")
    c.check(time.time() - start < 20, "stopped at the time limit")
    c.run_scene(HERTZ, "--set", "mesh.parameters.h_contact=1e-9", command="check")
    c.expect_failure(r"hertz-2d\.geo: .*mesh\.max_elements = 1000000", r"h_contact = 1e-09")


def interrupt_while_meshing(c):
    """Item 7 (before the run): SIGINT or SIGTERM while gmsh works ends stickslip at once with a message and the
    shell's exit code, stops the mesh generator, and writes nothing."""
    c.write("For i In {1:1e15}\n  x = i;\nEndFor\n", "loop.geo")
    scene = c.write(replace(BLOCK, os.path.join(MESHES, "block.geo"), "loop.geo").replace(
        "  parameters: {nx: 3, ny: 3, nz: 3}\n", ""))
    env = dict(os.environ)
    env.pop("STICKSLIP_PLUGIN_PATH", None)
    for sig, code, name in [(signal.SIGINT, 130, "SIGINT"), (signal.SIGTERM, 143, "SIGTERM")]:
        proc = subprocess.Popen([BIN, "run", scene, "--out", c.out, "--quiet"], stdout=subprocess.PIPE,
                                stderr=subprocess.PIPE, text=True, env=env, cwd=c.dir)
        # wait for the mesh generator: a child process named like its parent (MPI starts another, orted)
        deadline, child = time.time() + 60, ""
        while time.time() < deadline and proc.poll() is None and not child:
            child = subprocess.run(["pgrep", "-x", "-P", str(proc.pid), "stickslip"], capture_output=True,
                                   text=True).stdout.strip()
            time.sleep(0.05)
        c.check(child != "", "the mesh generator started")
        proc.send_signal(sig)
        try:
            out, err = proc.communicate(timeout=30)
        except subprocess.TimeoutExpired:
            proc.kill()
            out, err = proc.communicate()
        print("$ stickslip run (%s while gmsh runs)\nexit %d\nstderr: %s" % (name, proc.returncode, err))
        c.check(proc.returncode == code, "exit %d after %s (got %d)" % (code, name, proc.returncode))
        c.check(re.search(r"loop\.geo: interrupted by %s.* while (evaluating the script|loading gmsh|starting gmsh)" % name, err)
                is not None, "the message says what was interrupted")
        c.check(not os.path.exists(c.out), "nothing written")
        c.check(child == "" or not os.path.exists("/proc/" + child.split()[0]), "no mesh generator left behind")


CASES = {f.__name__: f for f in [gmsh_exception, mesh_size_guard, broken_plugin_files, empty_sections, non_finite,
                                 geometry_errors, shared_group, collapsed_element, system_call, special_files,
                                 interrupt_while_meshing]}

if __name__ == "__main__":
    main(CASES)
