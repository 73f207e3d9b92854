"""The command line's changes to a scene and what they leave behind (issue 31: `--plugin` keeps what the new plugin
takes, `--set` of a map merges; issue 35 items 1, 2, 8: the results' scene.yaml reruns, the plot scripts' files are
the run's, `stickslip keys`). Usage: python3 test_scene_overrides.py CASE."""
import os
import re
import shutil
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cli_case import BIN, CONTACT, MESHES, ROOT, main, read_table, replace  # noqa: E402

# A block pressed onto a deformable block: two meshes, a contact pair with a deformable master. {plugin} and
# {parameters} are the pair's; the rest is what any plugin needs.
TWO_BLOCKS = """\
description: a block pressed onto a deformable block
mesh:
  - name: lower
    file: %s/block.geo
    parameters: {lx: 1, ly: 1, lz: 0.5, x0: 0, y0: 0, z0: -0.5, nx: 2, ny: 2, nz: 1}
  - name: upper
    file: %s/block.geo
    parameters: {lx: 1, ly: 1, lz: 0.5, x0: 0.1, y0: 0.1, z0: 0, nx: 2, ny: 2, nz: 1}
bodies:
  - {name: lower, group: lower.body, material: {model: hooke, E: 1000, nu: 0.3}}
  - {name: upper, group: upper.body, material: {model: hooke, E: 1000, nu: 0.3}}
boundary:
  - {name: base, group: lower.zmin, displacement: [0, 0, 0]}
  - {name: top, group: upper.zmax, displacement: [0.01, 0, -0.01], history: [[0, 0], [1, 1]]}
contact:
  - name: interface
    plugin: {plugin}
    slave: upper.zmin
    master: lower.zmax
{strategy}    parameters: {parameters}
time: {scheme: quasi-static, dt: 0.5, end: 1}
solver:
  linear: {solver: direct}
""".replace("%s", MESHES)

# The same block on a rigid plane.
ON_PLANE = replace(replace(replace(CONTACT, "plugin: penalty-nts", "plugin: {plugin}"),
                           "    parameters: {penalty: 1.0e4}", "{strategy}    parameters: {parameters}"),
                   "displacement: [0, 0, -0.01]", "displacement: [0.01, 0, -0.01], history: [[0, 0], [1, 1]]")

# What a user of each plugin writes: its own parameters (friction where it has it) and, where it has several, a
# strategy other than the default.
NATIVE = {
    "penalty-nts": ("{penalty: 1.0e4, penalty_tangential: 1.0e4, mu: 0.2}", None),
    "nts-augmented": ("{mu: 0.2, epsilon_t: 1.0e4}", "direct"),
    "covariant-penalty": ("{penalty: 1.0e4, penalty_tangential: 1.0e4, mu: 0.2, tangent: full}", None),
    "mortar-dual": ("{mu: 0.2, c_n: 1.0e4}", "condensed"),
    "example-spring": ("{k: 100}", None),
    "corotational": ("{mu: 0.2}", None),
}


def scene_for(base, plugin):
    parameters, strategy = NATIVE[plugin]
    return (base.replace("{plugin}", plugin).replace("{parameters}", parameters)
            .replace("{strategy}", "    strategy: %s\n" % strategy if strategy else ""))


def plugin_tables():
    """{plugin: {"parameters": [(keys, line text, kinds)], "strategies": [...]}} from `stickslip plugins`: the
    parameter lines as the user sees them."""
    out = subprocess.run([BIN, "plugins"], capture_output=True, text=True).stdout
    tables, current = {}, None
    for line in out.splitlines():
        head = re.match(r"^(\S+)  \(ABI", line)
        if head:
            current = tables.setdefault(head.group(1), {"parameters": [], "strategies": []})
        elif current is not None and line.startswith("  strategies:"):
            current["strategies"] = [s.replace(" (default)", "").strip() for s in line.split(":", 1)[1].split(",")]
        elif current is not None and line.startswith("    ") and ":" in line:
            keys, rest = line.strip().split(":", 1)
            scope = re.search(r"\((body|pair)\)$", rest.rstrip())
            kinds = scope.group(1) if scope else "both"
            current["parameters"].append(([k.strip() for k in keys.split(",")], rest, kinds))
    return tables


def pair_keys(table):
    return {k for keys, _, kinds in table["parameters"] if kinds != "body" for k in keys}


def native_keys(plugin):
    return re.findall(r"(\w+):", NATIVE[plugin][0])


def checks(argument_lists):
    """`stickslip check ARGS` for each list of arguments, a few at a time (each is a program start that mostly
    waits for meshes and libraries)."""
    def one(args):
        return subprocess.run([BIN, "check", *args], capture_output=True, text=True, timeout=120)
    with ThreadPoolExecutor(max_workers=4) as pool:
        return list(pool.map(one, argument_lists))


def plugin_switch(c, base, label):
    """Every ordered pair (A, B) of plugins that both accept the scene: A's scene with --plugin B checks, or fails
    only on a parameter B's table marks as required that A's scene does not give; either way one warning names
    exactly A's parameters (and strategy) that B does not take, and none of A's is called unknown."""
    tables = plugin_tables()
    accepting = []
    scenes = {p: c.write(scene_for(base, p), "%s-%s.yaml" % (label, p)) for p in sorted(NATIVE)}
    for plugin, proc in zip(sorted(NATIVE), checks([[scenes[p]] for p in sorted(NATIVE)])):
        if proc.returncode != 0:
            c.check("lacks what this scene needs" in proc.stderr, "%s refuses the %s scene only for a capability it "
                    "lacks (%s)" % (plugin, label, proc.stderr.strip()))
            continue
        accepting.append(plugin)
    c.check(len(accepting) >= 3, "%s: %d plugins accept the scene (%s)" % (label, len(accepting), accepting))
    pairs = [(a, b) for a in accepting for b in accepting if a != b]
    for (a, b), proc in zip(pairs, checks([[scenes[a], "--plugin", b] for a, b in pairs])):
        c.proc = proc
        print("$ stickslip check %s-%s.yaml --plugin %s\nexit %d\nstdout: %s\nstderr: %s" % (
            label, a, b, proc.returncode, proc.stdout.strip(), proc.stderr.strip()))
        c.no_crash()
        strategy = NATIVE[a][1]
        dropped = ["strategy (%s)" % strategy] if strategy and strategy not in tables[b]["strategies"] else []
        dropped += [k for k in native_keys(a) if k not in pair_keys(tables[b])]
        warnings = [line for line in c.proc.stderr.splitlines() if line.startswith("warning: --plugin")]
        if dropped:
            expected = ", ".join("contact[0]." + ("parameters." + k if "strategy" not in k else k)
                                 for k in dropped)
            c.check(len(warnings) == 1 and warnings[0].endswith(": " + expected),
                    "%s -> %s: one warning naming %s" % (a, b, expected))
        else:
            c.check(not warnings, "%s -> %s: nothing dropped, no warning" % (a, b))
        c.check("unknown key" not in c.proc.stderr,
                "%s -> %s: none of %s's parameters is an unknown key" % (a, b, a))
        kept = [k for k in native_keys(a) if k in pair_keys(tables[b])]
        required = [k for keys, text, kinds in tables[b]["parameters"] if kinds != "body" and "required" in text
                    for k in keys if k not in kept]
        if c.proc.returncode == 0:
            c.check(re.search(r"pair 'interface|pair 'floor'", c.proc.stdout) is not None and
                    ("plugin %s," % b) in c.proc.stdout, "%s -> %s: check passes with %s" % (a, b, b))
        else:
            missing = re.search(r"missing key 'contact\[0\]\.parameters\.(\w+)'", c.proc.stderr)
            c.check(missing is not None and missing.group(1) in required,
                    "%s -> %s: fails only on a parameter %s requires (%s)" % (a, b, b, c.proc.stderr.strip()))


def plugin_switch_deformable(c):
    plugin_switch(c, TWO_BLOCKS, "two-blocks")


def plugin_switch_obstacle(c):
    plugin_switch(c, ON_PLANE, "on-plane")


def plugin_switch_runs(c):
    """A penalty-nts scene run with --plugin mortar-dual: the parameters mortar-dual takes (mu) are kept, the rest
    dropped; it runs to the end; a parameter given on the command line is never dropped (a misspelt one is an error);
    a pair whose file already names the plugin keeps everything (its misspelt key is still an error)."""
    scene = c.write(scene_for(TWO_BLOCKS, "penalty-nts"))
    # the default line search (the full step first): with backtracking alone mortar-dual stops at step 8 of these two
    # blocks (||F|| grows from 0.09 to 903 in 25 iterations; docs/linear-solvers.md, "Line search")
    c.run("run", scene, "--plugin", "mortar-dual", "--set", "contact.0.parameters.c_n=1e4", "--out", c.out, "--quiet")
    c.check(c.proc.returncode == 0, "runs to the end")
    if c.proc.returncode != 0:
        return
    c.check("dropped what mortar-dual does not take, its defaults apply: contact[0].parameters.penalty, "
            "contact[0].parameters.penalty_tangential" in c.proc.stderr, "the warning names the dropped keys")
    saved = open(os.path.join(c.out, "scene.yaml")).read()
    c.check(re.search(r"plugin: mortar-dual\n", saved) and "penalty" not in saved.split("contact:")[1]
            and re.search(r"mu: 0\.2", saved) and re.search(r"c_n: 1e4", saved),
            "the results' scene.yaml has mortar-dual with mu kept and c_n set")
    c.run("check", scene, "--plugin", "mortar-dual", "--set", "contact.0.parameters.c_m=1e4")
    c.expect_failure(r"--set contact\.0\.parameters\.c_m: unknown key 'contact\[0\]\.parameters\.c_m'",
                     out_created=True)
    c.run("check", c.write(scene_for(TWO_BLOCKS, "penalty-nts").replace("mu: 0.2", "mu: 0.2, penalti: 3"), "typo.yaml"),
          "--plugin", "penalty-nts")
    c.expect_failure(r"unknown key 'contact\[0\]\.parameters\.penalti'", out_created=True)
    # a plugin name set on the command line is not the file's: --plugin still drops what it does not take
    c.run("check", scene, "--set", "contact.0.plugin=mortar-dual", "--plugin", "mortar-dual")
    c.check(c.proc.returncode == 0 and "dropped what mortar-dual does not take" in c.proc.stderr,
            "--set contact.0.plugin=mortar-dual --plugin mortar-dual drops penalty-nts's parameters")
    c.run("check", scene, "--plugin", "no-such-plugin")
    c.expect_failure(r"--plugin no-such-plugin: unknown plugin 'no-such-plugin'", out_created=True)


def set_merges(c):
    """--set of a map merges into the scene's map (the scene reference's own example kept the line search out of
    the scene before); --replace replaces it; both are shown with their origin by `keys`."""
    scene = c.write(CONTACT + "solver:\n  newton: {line_search: polynomial, tolerance: 1.0e-11}\n")
    c.run("keys", scene, "--set", "solver.newton={max_iterations: 40}")
    c.check(c.proc.returncode == 0, "keys exits 0")
    rows = {line.split()[0]: line for line in c.proc.stdout.splitlines() if line and not line.startswith("#")}
    c.check(re.search(r"polynomial .*scene\.yaml:\d+:\d+", rows.get("solver.newton.line_search", "")) is not None,
            "--set merged: the scene's line search stays (%s)" % rows.get("solver.newton.line_search"))
    c.check(re.search(r"1\.0e-11 .*scene\.yaml:\d+:\d+", rows.get("solver.newton.tolerance", "")) is not None,
            "--set merged: the scene's tolerance stays")
    c.check(re.search(r"40 .*--set solver\.newton", rows.get("solver.newton.max_iterations", "")) is not None,
            "--set merged: max_iterations from --set solver.newton")
    c.run("keys", scene, "--replace", "solver.newton={max_iterations: 40}")
    rows = {line.split()[0]: line for line in c.proc.stdout.splitlines() if line and not line.startswith("#")}
    c.check(re.search(r"full-step-then-backtrack .*default", rows.get("solver.newton.line_search", "")) is not None,
            "--replace: the scene's line search is gone (the default applies)")
    c.check(re.search(r"40 .*--replace solver\.newton", rows.get("solver.newton.max_iterations", "")) is not None,
            "--replace: max_iterations from --replace solver.newton")
    # a bad key or value in a merged map is reported at the --set that brought it
    c.run("check", scene, "--set", "solver.newton={max_iteration: 40}")
    c.expect_failure(r"--set solver\.newton: unknown key 'solver\.newton\.max_iteration' \(did you mean "
                     r"'max_iterations'\?\)")
    c.run("check", scene, "--set", "solver.newton={max_iterations: many}")
    c.expect_failure(r"--set solver\.newton: key 'solver\.newton\.max_iterations' expects an integer, got 'many'")


def results_scene_reruns(c):
    """Item 1: the results' scene.yaml is the effective scene — the overrides applied and named in its header, mesh
    paths that resolve from anywhere: checked and run from another folder, it gives the same history."""
    project = os.path.join(c.dir, "project")
    os.makedirs(os.path.join(project, "scenes"))
    shutil.copytree(MESHES, os.path.join(project, "meshes"))
    with open(os.path.join(project, "scenes", "blocks.yaml"), "w") as f:
        f.write(scene_for(TWO_BLOCKS, "penalty-nts").replace(MESHES, "../meshes"))
    first = subprocess.run([BIN, "run", "scenes/blocks.yaml", "--out", "results/blocks", "--quiet",
                            "--plugin", "mortar-dual", "--set", "time.dt=0.25", "--set",
                            "solver.newton={max_iterations: 30}", "--replace", "contact.0.parameters.mu=0.1",
                            "--set", "contact.0.parameters.c_n=1e4"],
                           cwd=project, capture_output=True, text=True)
    print(first.stderr)
    c.check(first.returncode == 0, "the run with overrides succeeds")
    saved = os.path.join(project, "results", "blocks", "scene.yaml")
    if first.returncode != 0:
        return
    text = open(saved).read()
    header = [line for line in text.splitlines() if line.startswith("#")]
    print("\n".join(header))
    c.check(any(os.path.join(project, "scenes", "blocks.yaml") in line for line in header),
            "the header names the scene file (absolute)")
    c.check(any("--set time.dt=0.25 --set 'solver.newton={max_iterations: 30}' --replace contact.0.parameters.mu=0.1 "
                "--set contact.0.parameters.c_n=1e4 --plugin mortar-dual" in line for line in header),
            "the header lists the overrides as typed")
    c.check(any("dropped by --plugin" in line and "contact[0].parameters.penalty" in line for line in header),
            "the header names what --plugin dropped")
    c.check(os.path.join(project, "meshes", "block.geo") in text, "mesh paths are absolute")
    elsewhere = os.path.join(c.dir, "elsewhere")
    os.makedirs(elsewhere)
    relative = os.path.relpath(saved, elsewhere)
    c.proc = subprocess.run([BIN, "check", relative], cwd=elsewhere, capture_output=True, text=True)
    print(c.proc.stdout, c.proc.stderr)
    c.check(c.proc.returncode == 0 and "plugin mortar-dual" in c.proc.stdout, "check of the saved scene passes from "
            "another folder, with mortar-dual")
    folder = os.path.dirname(relative)
    given_folder = subprocess.run([BIN, "check", folder], cwd=elsewhere, capture_output=True, text=True)
    print(given_folder.stderr)
    c.check(given_folder.returncode == 1 and "its effective scene is %s" % relative in given_folder.stderr,
            "the results folder given as the scene: the message names its scene.yaml")
    c.proc = subprocess.run([BIN, "run", relative, "--out", "again", "--quiet"], cwd=elsewhere, capture_output=True,
                            text=True)
    print(c.proc.stderr)
    c.check(c.proc.returncode == 0, "the saved scene runs from another folder")
    if c.proc.returncode == 0:
        before = read_table(os.path.join(project, "results", "blocks", "history.csv"))
        after = read_table(os.path.join(elsewhere, "again", "history.csv"))
        differ = [(k, a["time"], a[k], b[k]) for a, b in zip(before, after) for k in a
                  if k != "wall_seconds" and a[k] != b[k]]
        print("differ:", differ[:10])
        same = len(before) == len(after) >= 5 and not differ
        c.check(same, "the same history, every column but wall_seconds (%d and %d rows)" % (len(before), len(after)))
        again = open(os.path.join(elsewhere, "again", "scene.yaml")).read()
        c.check(re.search(r"# scene: .*results/blocks/scene\.yaml\n# overrides: none\n", again) is not None and
                "#   scene: %s" % os.path.join(project, "scenes", "blocks.yaml") in again and
                "#   overrides: --set time.dt=0.25" in again,
                "the rerun's header names the saved scene and passes on that scene's own header")


def plotted_folder_reruns(c):
    """Item 2: after plot-history.sh and plot-snapshots.sh (with and without --contact) a run into the same folder
    replaces it (their files are the run's); a file of the user's in the folder or in snapshots/ still stops it and
    is kept."""
    scene = c.write(scene_for(ON_PLANE, "penalty-nts"))
    scripts = os.path.join(ROOT, "scripts")
    for attempt in ("plotted", "user file", "user file in snapshots"):
        if os.path.exists(c.out):
            shutil.rmtree(c.out)
        c.run("run", scene, "--out", c.out, "--quiet")
        c.check(c.proc.returncode == 0, "the run succeeds")
        for script, *options in (("plot-history.sh",), ("plot-snapshots.sh",), ("plot-snapshots.sh", "--contact")):
            p = subprocess.run([os.path.join(scripts, script), c.out, *options], capture_output=True, text=True)
            c.check(p.returncode == 0, "%s %s succeeds (%s)" % (script, " ".join(options), p.stderr.strip()[-200:]))
        c.check(os.path.exists(os.path.join(c.out, "history.png")) and
                os.path.exists(os.path.join(c.out, "snapshots-contact.png")) and
                os.path.isdir(os.path.join(c.out, "snapshots")), "the plots are in the folder")
        mine = {"plotted": None, "user file": "notes.txt", "user file in snapshots": "snapshots/mine.txt"}[attempt]
        if mine:
            with open(os.path.join(c.out, mine), "w") as f:
                f.write("mine\n")
        c.run("run", scene, "--out", c.out, "--quiet")
        if mine is None:
            c.check(c.proc.returncode == 0, "a plotted folder is replaced by the next run")
            c.check(not os.path.exists(os.path.join(c.out, "history.png")), "with the plots of the run it replaced")
        else:
            c.expect_failure(r"refusing to replace '.*results': it holds '%s', which stickslip did not write" % mine,
                             out_created=True)
            c.check(os.path.exists(os.path.join(c.out, mine)), "%s is kept" % mine)


def keys_listing(c):
    """Item 8: `stickslip keys` lists every key the scene is read with — given (with file:line:col or --set) or
    default — with its unit, and each pair's plugin parameters with their declared defaults; --plugin switches
    them."""
    scene = c.write(scene_for(ON_PLANE, "penalty-nts"))
    c.run("keys", scene, "--set", "time.dt=0.25")
    c.no_crash()
    c.check(c.proc.returncode == 0, "keys exits 0")
    rows = {}
    for line in c.proc.stdout.splitlines():
        if line and not line.startswith("#") and not line.startswith("key "):
            rows[line.split()[0]] = line
    expect = {
        "time.dt": r"0\.25 +time +--set time\.dt",
        "time.end": r"1 +time +.*scene\.yaml:\d+:\d+",
        "time.start": r"0 +time +default",
        "time.max_cuts": r"6 +default",
        "bodies[0].material.E": r"1000 +force/area +.*scene\.yaml:\d+:\d+",
        "bodies[0].material.density": r"0 +mass/volume +default",
        "dimension": r"\(from the mesh: 3\) +default",
        "solver.newton.tolerance": r"1e-10 +1 \(relative\) +default",
        "solver.linear.solver": r"auto +default",
        "output.vtu_every": r"10 +default",
        "contact[0].obstacle.type": r"plane +.*scene\.yaml",
        "contact[0].obstacle.radius": r"0 +length +default",
        "contact[0].parameters.penalty": r"1\.0e4 +.*scene\.yaml:\d+:\d+; penalty-nts: normal penalty",
        "contact[0].parameters.master_extension": r"0\.1 +default; penalty-nts:",
        "contact[0].strategy": r"none +default",
        "boundary[0].history": r"\[\[0, 0\], \[1, 1\]\] +\[time, factor\]",
    }
    for key, pattern in expect.items():
        c.check(re.search(pattern, rows.get(key, "")) is not None, "%s: /%s/ (%s)" % (key, pattern, rows.get(key)))
    c.check(not [line for line in rows.values() if re.search(r"  \?  ", line)], "every quantity has a unit")
    header = next(line for line in c.proc.stdout.splitlines() if line.startswith("key "))
    origin_column = header.index("origin")
    c.check(rows["time.end"].index("scene.yaml") - len(c.dir) - 1 == origin_column and
            rows["time.start"].index("default") == origin_column, "origins start in the origin column")
    # Every origin starts in the origin column, or two spaces after a longer value that took the unit's room: the
    # rule holds whatever the paths in the value column (a checkout's location changes their length).
    misplaced = []
    for key, line in rows.items():
        found = re.search(r"  (default|computed from the scene|\S*scene\.yaml:\d+:\d+|--set )", line[len(key):])
        if found is None:
            misplaced.append(key)
            continue
        start = len(key) + found.start(1)
        before = len(line[:start].rstrip())
        if start != (origin_column if before <= origin_column - 2 else before + 2):
            misplaced.append(key)
    c.check(not misplaced, "origins in the origin column or two spaces after a longer value (%s)" % misplaced[:5])
    c.check(re.search(r"^bodies\[0\]\.plugin +\(none: the core integrates the body\) {2,}default$",
                      rows.get("bodies[0].plugin", "")) is not None, "a value longer than its column is printed whole")
    c.run("keys", scene, "--plugin", "mortar-dual")
    c.check(c.proc.returncode == 0 and "contact[0].parameters.c_n" in c.proc.stdout and
            "parameters.penalty " not in c.proc.stdout, "with --plugin mortar-dual: mortar-dual's parameters")
    c.run("keys", "--plugin", "corotational")  # a plugin alone: its table, per kind of attachment
    c.check(c.proc.returncode == 0 and re.search(r"^pair\.parameters\.mu +0 +default; corotational:", c.proc.stdout,
                                                 re.M) is not None and
            re.search(r"^body\.parameters\.axis_z +1 +default", c.proc.stdout, re.M) is not None,
            "keys --plugin corotational lists its pair and body parameters with their defaults")
    c.run("keys", c.write(replace(scene_for(ON_PLANE, "penalty-nts"), "dt: 0.5", "dt: -1"), "bad.yaml"))
    c.expect_failure(r"bad\.yaml:\d+:\d+: key 'time\.dt': must be positive")


CASES = {f.__name__: f for f in [plugin_switch_deformable, plugin_switch_obstacle, plugin_switch_runs, set_merges,
                                 results_scene_reruns, plotted_folder_reruns, keys_listing]}

if __name__ == "__main__":
    main(CASES)
