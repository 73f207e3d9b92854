"""The pages against the program and the tree: what README.md and docs/ say must hold on the program as built.
The truth comes from the program (`stickslip plugins`, `stickslip check`) and the tree, never from a list kept here:
- links: every relative link and image of README.md and docs/**/*.md names a file or folder that exists;
- scene_list: README's scene table lists every scenes/*.yaml, each once, and nothing else; every test name or
  pattern in its "checked by" column is a test ctest knows;
- formulation_table: README's formulation table has one row per formulation plugin, and its capability columns
  (dimensions, friction, obstacles, element orders, energy-consistent scheme, multipliers, strategies) say what the
  plugin declares (`stickslip plugins`) or what `stickslip check` accepts (second-order faces);
- face_types: a plugin `stickslip check` lets run QUAD8 (hex20) slave faces has them in README's element orders;
- abi_formulations: plugin-abi.md section 11's dimensions and strategy names of each plugin are the program's;
- strategy_names: every strategy the docs and scene files name (`strategy: X`, `strategy=X`, `plugin/X`) is one its
  plugin accepts, and a deprecated alias (the program warns about it at `check`) appears only where the text says
  it is one;
- commands: every `stickslip run|check|keys|compare SCENE ...` the pages and `stickslip compare --help` show names a
  scene of the tree, and `stickslip check` accepts its overrides (each value of a --vary);
- no_narration: no file of the project (pages, sources, scenes, tests, scripts) narrates how the project was made
  (sessions, work periods, who measured): a measurement states its commit and date.
Usage: python3 check_pages.py CASE; exit code 0 when every check holds."""
import fnmatch
import glob
import os
import re
import shlex
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "validation"))
from stickslip_results import ROOT, main  # noqa: E402
from check_docs import markdown_tables  # noqa: E402

BINARY = os.environ.get("STICKSLIP_BIN", os.path.join(ROOT, "build", "bin", "stickslip"))


def pages():
    """README.md and every markdown page under docs/, as paths relative to ROOT."""
    found = ["README.md"] + sorted(os.path.relpath(p, ROOT)
                                   for p in glob.glob(os.path.join(ROOT, "docs", "**", "*.md"), recursive=True))
    return found


def without_code(text):
    """Markdown text with its fenced code blocks blanked (line numbers kept)."""
    return re.sub(r"```.*?```", lambda m: "\n" * m.group(0).count("\n"), text, flags=re.S)


def anchors(path):
    """The anchors of a markdown page's headings, as GitHub makes them: lower case, punctuation dropped, spaces to
    hyphens, a repeated heading numbered -1, -2, ..."""
    seen, found = {}, set()
    for line in without_code(open(path, encoding="utf-8").read()).split("\n"):
        heading = re.match(r"#{1,6} (.*)", line)
        if heading:
            slug = re.sub(r"[^\w\- ]", "", heading.group(1).strip().lower()).replace(" ", "-")
            found.add(slug if slug not in seen else "%s-%d" % (slug, seen[slug]))
            seen[slug] = seen.get(slug, 0) + 1
    return found


def links(c):
    count = 0
    for page in pages():
        text = without_code(open(os.path.join(ROOT, page), encoding="utf-8").read())
        for number, line in enumerate(text.split("\n"), 1):
            for target in re.findall(r"\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)", line):
                if re.match(r"[a-z]+:", target) or target.startswith("#"):
                    continue  # a web address or an anchor of the same page
                path = os.path.normpath(os.path.join(ROOT, os.path.dirname(page), target.split("#")[0]))
                count += 1
                c.check(os.path.exists(path), "%s:%d: link `%s` resolves" % (page, number, target))
                if "#" in target and path.endswith(".md") and os.path.isfile(path):
                    c.check(target.split("#", 1)[1] in anchors(path), "%s:%d: `%s` is a heading of %s" %
                            (page, number, target, os.path.relpath(path, ROOT)))
    c.check(count > 50, "%d relative links and images checked" % count)


def readme_table(heading):
    """Rows of the first table under `## heading` of README.md."""
    for headings, _, rows in markdown_tables(os.path.join(ROOT, "README.md")):
        if headings.get(2) == heading:
            return rows
    raise AssertionError("README.md has no table under '## %s'" % heading)


def ctest_names():
    build = os.environ.get("STICKSLIP_BUILD_DIR", os.path.join(ROOT, "build"))
    out = subprocess.run(["ctest", "-N"], cwd=build, capture_output=True, text=True).stdout
    return re.findall(r"Test\s+#\d+: (\S+)", out)


def scene_list(c):
    listed = []
    tests = ctest_names()
    c.check(len(tests) > 100, "ctest -N knows %d tests" % len(tests))
    for row in readme_table("Scenes"):
        listed += re.findall(r"`([^`/]+\.yaml)`", row[0])
        for pattern in re.findall(r"`((?:validation|stress|test|unit|cli|mpi|bench)_[^`\s]*)`", row[-1]):
            c.check(any(fnmatch.fnmatchcase(name, pattern) for name in tests),
                    "README scene table: test `%s` (%s) is one ctest knows" % (pattern, row[0]))
    shipped = sorted(os.path.basename(p) for p in glob.glob(os.path.join(ROOT, "scenes", "*.yaml")))
    for scene in shipped:
        c.check(listed.count(scene) == 1, "scenes/%s is listed once in README's scene table (%d)" %
                (scene, listed.count(scene)))
    for scene in listed:
        c.check(scene in shipped, "README's scene table lists `%s`, which is in scenes/" % scene)


def declared_plugins():
    """{name: {"capabilities": set, "strategies": [names], "required": [parameters]}} from `stickslip plugins`."""
    out = subprocess.run([BINARY, "plugins"], capture_output=True, text=True, check=True).stdout
    plugins, name, section = {}, None, None
    for line in out.split("\n"):
        head = re.match(r"(\S+)\s+\(ABI", line)
        if head:
            name = head.group(1)
            plugins[name] = {"capabilities": set(), "strategies": [], "required": []}
            continue
        field = re.match(r"\s+(capabilities|strategies|parameters):\s*(.*)", line)
        if field:
            section = field.group(1)
            if section == "capabilities":
                plugins[name]["capabilities"] = set(field.group(2).split())
            elif section == "strategies":
                plugins[name]["strategies"] = [s.split()[0] for s in field.group(2).split(",")]
            continue
        if section == "parameters" and re.match(r"\s{4}\S", line) and "[required]" in line:
            plugins[name]["required"] += [p.strip() for p in line.split(":")[0].split(",")]
        if re.match(r"\s{2}\S", line) and not line.startswith("    "):
            section = None
    return plugins


def scene_plugins():
    """{plugin: [scene files using it]} over scenes/*.yaml."""
    import yaml
    used = {}
    for path in sorted(glob.glob(os.path.join(ROOT, "scenes", "*.yaml"))):
        scene = yaml.safe_load(open(path)) or {}
        for entry in (scene.get("contact") or []) + (scene.get("bodies") or []):
            if isinstance(entry, dict) and entry.get("plugin"):
                used.setdefault(entry["plugin"], []).append(path)
    return used


def deprecated_strategies(plugins):
    """{plugin: {alias}}: the strategies `stickslip check` warns about as deprecated on the plugin's first scene."""
    deprecated = {}
    for name, scenes in scene_plugins().items():
        for strategy in plugins.get(name, {}).get("strategies", [])[1:]:
            proc = subprocess.run([BINARY, "check", scenes[0], "--set", "contact.0.strategy=" + strategy],
                                  capture_output=True, text=True)
            if "deprecated" in proc.stdout + proc.stderr:
                deprecated.setdefault(name, set()).add(strategy)
    return deprecated


def second_order_accepted(name, scene):
    """True when `stickslip check` accepts the plugin's scene on second-order elements, False when the plugin
    refuses them (its message says first-order), None when the check fails for another reason."""
    import yaml
    meshes = (yaml.safe_load(open(scene)) or {}).get("mesh")
    keys = ["mesh.%d.order" % k for k in range(len(meshes))] if isinstance(meshes, list) else ["mesh.order"]
    settings = [arg for key in keys for arg in ("--set", key + "=2")]
    proc = subprocess.run([BINARY, "check", scene, *settings], capture_output=True, text=True)
    if proc.returncode == 0:
        return True
    return False if "first-order" in proc.stderr else None


def second_order_by_dimension(name, scenes):
    """{'2D' / '3D': second_order_accepted} on the plugin's first scene of each dimension its scene names tell
    (-2d / -3d); {'': ...} on its first scene when no name tells a dimension."""
    found = {}
    for path in scenes:
        for tag in ("2d", "3d"):
            if "-%s" % tag in os.path.basename(path) and tag.upper() not in found:
                found[tag.upper()] = path
    if not found:
        found[""] = scenes[0]
    return {dim: second_order_accepted(name, path) for dim, path in found.items()}


def yes(cell):
    return cell.strip().lower().startswith("yes")


def formulation_table(c):
    plugins = declared_plugins()
    deprecated = deprecated_strategies(plugins)
    scenes = scene_plugins()
    rows = readme_table("Choosing a formulation")
    header = [h.lower() for h in readme_table_header("Choosing a formulation")]
    col = {key: next(i for i, h in enumerate(header) if h.startswith(key))
           for key in ("formulation", "dimensions", "friction", "obstacles", "element orders", "energy",
                       "multipliers", "strategies")}
    listed = []
    for row in rows:
        name = re.findall(r"`([^`]+)`", row[col["formulation"]])[0]
        listed.append(name)
        if name not in plugins:
            c.check(False, "README formulation `%s` is a plugin `stickslip plugins` lists" % name)
            continue
        caps = plugins[name]["capabilities"]
        dims = {d.lower() for d in re.findall(r"[23]D", row[col["dimensions"]])}
        c.check(dims == caps & {"2d", "3d"}, "%s: dimensions %s are the declared %s" %
                (name, sorted(dims), sorted(caps & {"2d", "3d"})))
        for key, capability in (("friction", "friction"), ("energy", "energy-momentum"),
                                ("multipliers", "multipliers")):
            c.check(yes(row[col[key]]) == (capability in caps), "%s: column '%s' (%s) agrees with capability %s" %
                    (name, key, row[col[key]], capability))
        obstacles = row[col["obstacles"]].lower()
        c.check(("rigid" in obstacles) == ("rigid-obstacle" in caps),
                "%s: obstacles column names rigid obstacles iff it declares rigid-obstacle" % name)
        c.check(("deformable" in obstacles) == ("deformable-master" in caps),
                "%s: obstacles column names deformable bodies iff it declares deformable-master" % name)
        named = re.findall(r"`([^`]+)`", row[col["strategies"]])
        current = [s for s in plugins[name]["strategies"] if s not in deprecated.get(name, set())]
        c.check(named == current, "%s: strategies %s are the program's (%s, deprecated aliases left out)" %
                (name, named, current))
        cell = row[col["element orders"]]
        orders = re.findall(r"\b[12]\b", cell)  # not the 2 of "2D"
        if name in scenes:
            accepted = second_order_by_dimension(name, scenes[name])
            c.check(None not in accepted.values(), "%s: `check --set mesh.order=2` on its scenes tells the element "
                    "orders (%s)" % (name, accepted))
            if None not in accepted.values():
                c.check(orders == (["1", "2"] if any(accepted.values()) else ["1"]),
                        "%s: element orders %s (second order %s)" % (name, orders, accepted))
                partial = [dim for dim, ok in accepted.items() if ok] if not all(accepted.values()) else []
                c.check(all(dim in cell for dim in partial), "%s: element orders '%s' name where second order runs "
                        "(%s)" % (name, cell, ", ".join(partial)))
    formulations = sorted(n for n in plugins if not n.startswith("example-"))
    c.check(sorted(listed) == formulations, "README's formulation table lists %s; the program has %s" %
            (sorted(listed), formulations))


QUAD8_SCENE = """\
mesh: {file: %s, parameters: {nx: 1, ny: 1, nz: 1}, order: 2, serendipity: true}
bodies: [{name: block, group: body, material: {model: svk, E: 1000, nu: 0.3}}]
boundary: [{name: top, group: zmax, displacement: [0, 0, -0.01]}]
contact: [{name: floor, plugin: penalty-nts, slave: zmin, obstacle: {type: plane}}]
time: {scheme: quasi-static, dt: 1, end: 1}
"""


def face_types(c):
    """README's element orders of a plugin that `stickslip check` lets run QUAD8 (hex20) slave faces (one hex20 on a
    rigid plane, the plugin's default strategy) name quad8, and do not say it cannot."""
    import tempfile
    rows = readme_table("Choosing a formulation")
    header = [h.lower() for h in readme_table_header("Choosing a formulation")]
    name_col, orders_col = header.index("formulation (plugin)"), next(
        i for i, h in enumerate(header) if h.startswith("element orders"))
    with tempfile.TemporaryDirectory() as folder:
        scene = os.path.join(folder, "quad8.yaml")
        with open(scene, "w") as f:
            f.write(QUAD8_SCENE % os.path.join(ROOT, "meshes", "block.geo"))
        for row in rows:
            name, cell = re.findall(r"`([^`]+)`", row[name_col])[0], row[orders_col].lower()
            proc = subprocess.run([BINARY, "check", scene, "--plugin", name], capture_output=True, text=True)
            runs = proc.returncode == 0 and "quad8 faces" in proc.stdout
            print("%s: QUAD8 slave faces %s" % (name, "accepted" if runs else "refused: " + proc.stderr.strip()[:160]))
            if runs:
                c.check("quad8" in cell and "not quad8" not in cell, "%s: `check` accepts QUAD8 (hex20) slave "
                        "faces, so README's element orders '%s' name quad8 as run" % (name, cell))


def readme_table_header(heading):
    """Header cells of the first table under `## heading` of README.md."""
    current = None
    for line in open(os.path.join(ROOT, "README.md"), encoding="utf-8"):
        match = re.match(r"## (.*)", line)
        if match:
            current = match.group(1).strip()
        elif current == heading and line.startswith("|"):
            return [cell.strip() for cell in line.strip().strip("|").split("|")]
    raise AssertionError("README.md has no table under '## %s'" % heading)


def abi_formulations(c):
    """plugin-abi.md section 11: each `### 11.N ... (`plugins/NAME`...)` section's **Capabilities** dimensions and
    **Strategies** names against the program."""
    plugins = declared_plugins()
    deprecated = deprecated_strategies(plugins)
    text = open(os.path.join(ROOT, "docs", "plugin-abi.md"), encoding="utf-8").read()
    sections = re.findall(r"^### 11\.\d+ [^\n]*?`plugins/([\w-]+)`[^\n]*\n(.*?)(?=^###? |\Z)", text, flags=re.S | re.M)
    c.check(len(sections) >= 5, "plugin-abi.md section 11 describes %d plugins" % len(sections))
    for name, body in sections:
        caps = plugins.get(name, {}).get("capabilities", set())
        c.check(name in plugins, "plugin-abi.md 11: `%s` is a plugin the program lists" % name)
        declared = re.search(r"\*\*Capabilities\*\*(.*?)\.\s", body, flags=re.S)
        c.check(declared is not None, "plugin-abi.md 11 (%s) states its capabilities" % name)
        if declared:
            dims = set(re.findall(r"\b([23]d)\b", declared.group(1)))
            c.check(dims == caps & {"2d", "3d"}, "plugin-abi.md 11 (%s): dimensions %s are the declared %s" %
                    (name, sorted(dims), sorted(caps & {"2d", "3d"})))
        strategies = re.search(r"\*\*Strategies\*\*(.*?)(?:\.\s|;)", body, flags=re.S)
        c.check(strategies is not None, "plugin-abi.md 11 (%s) names its strategies" % name)
        if strategies:
            named = re.findall(r"`([^`]+)`", re.sub(r"\([^)]*\)", "", strategies.group(1)))
            current = [s for s in plugins.get(name, {}).get("strategies", []) if s not in deprecated.get(name, set())]
            c.check(sorted(named) == sorted(current), "plugin-abi.md 11 (%s): strategies %s are the program's %s" %
                    (name, named, current))


def strategy_mentions(path):
    """(line number, line, strategy) of every strategy a page or scene file names: `strategy: X`, `strategy=X|Y`
    (in a page: inside a code span), "strategy `X`", "`X` strategy". (A `plugin/label` in a table may name a
    benchmark variant, not a strategy.)"""
    found = []
    markdown = path.endswith(".md")
    for number, line in enumerate(open(path, encoding="utf-8").read().split("\n"), 1):
        settings = "\n".join(re.findall(r"`([^`]+)`", line)) if markdown else line
        names = [m.group(1) for m in re.finditer(r"strategy[ ]*[=:][ ]*([a-z][\w-]*(?:\|[a-z][\w-]*)*)", settings)]
        names += [a or b for a, b in re.findall(r"strategy `([a-z][\w-]*)`|`([a-z][\w-]*)` strategy", line)]
        found += [(number, line, strategy) for name in names for strategy in name.split("|")]
    return found


def strategy_names(c):
    plugins = declared_plugins()
    deprecated = deprecated_strategies(plugins)
    every = {s for p in plugins.values() for s in p["strategies"]}
    files = pages() + sorted(os.path.relpath(p, ROOT) for p in glob.glob(os.path.join(ROOT, "scenes", "*.yaml")))
    uses = scene_plugins()
    count = 0
    for relative in files:
        path = os.path.join(ROOT, relative)
        # The plugin a page or scene is about: a plugin page's own name, or the one plugin a scene uses.
        own = os.path.splitext(os.path.basename(relative))[0] if "/plugins/" in "/" + relative else None
        if relative.startswith("scenes/"):
            owners = [name for name, scenes in uses.items() if path in scenes]
            own = owners[0] if len(owners) == 1 else None
        for number, line, strategy in strategy_mentions(path):
            plugin = own
            count += 1
            accepted = plugins[plugin]["strategies"] if plugin in plugins else every
            c.check(strategy in accepted, "%s:%d: strategy `%s` is one %s accepts (%s)" %
                    (relative, number, strategy, plugin or "a plugin", ", ".join(sorted(accepted))))
            if strategy in deprecated.get(plugin, set()):
                c.check(re.search(r"deprecat|alias", line, flags=re.I) is not None,
                        "%s:%d: `%s` is a deprecated alias of %s: use its current name" %
                        (relative, number, strategy, plugin))
    c.check(count > 20, "%d strategy names checked" % count)


COMMAND = re.compile(r"(?:^|[\s`(])(?:\S*/)?stickslip (run|check|keys|compare) ((?:scenes|tests)/[\w./-]+\.yaml)(.*)")


def command_lines(text):
    """(line number, command, scene, arguments) of every `stickslip run|check|keys|compare SCENE ...` of a text:
    in code blocks (a line continued with a backslash joined to the next) and in inline code spans."""
    joined, number = [], 1
    for line in text.split("\n"):
        if joined and joined[-1][1].endswith("\\"):
            joined[-1] = (joined[-1][0], joined[-1][1][:-1] + " " + line)
        else:
            joined.append((number, line))
        number += 1
    found = []
    for number, line in joined:
        for span in re.findall(r"`([^`]*stickslip [^`]*)`", line) or [line]:
            match = COMMAND.search(span)
            if match:
                rest = re.split(r"\s(?:#|&&|\||;|>)", match.group(3).replace("\\|", "|"))[0]
                found.append((number, match.group(1), match.group(2), rest))
    return found


def check_arguments(command, arguments):
    """The `stickslip check` argument lists a command's overrides come to: run/check/keys keep their --plugin, --set
    and --replace; compare gives one list per value of each --vary (with its --set). None when the command line has a
    placeholder (SCENE, $p, ..., <x>) or cannot be split."""
    if re.search(r"\$|\.\.\.|…|<[a-z]|=[A-Z]\b|\b[A-Z]{3,}\b", arguments):
        return None
    try:
        words = shlex.split(arguments)
    except ValueError:
        return None
    fixed, vary, i = [], [], 0
    while i < len(words):
        word, value = words[i], words[i + 1] if i + 1 < len(words) else None
        if word in ("--set", "--replace", "--plugin") and value is not None:
            fixed += [word, value]
            i += 2
        elif word == "--vary" and value is not None and command == "compare":
            key, values = value.split("=", 1)
            vary.append([(key, v) for v in re.split(r",(?![^\[{]*[\]}])", values)])
            i += 2
        else:
            i += 1
    if not vary:
        return [fixed]
    return [fixed + (["--plugin", v] if k == "plugin" else ["--set", "%s=%s" % (k, v)])
            for options in vary for k, v in options]


def commands(c):
    """Every `stickslip run|check|keys|compare` command line of the pages and of `stickslip compare --help` names a
    scene of the tree, and `stickslip check` accepts its overrides (each value of a --vary)."""
    texts = [(page, open(os.path.join(ROOT, page), encoding="utf-8").read()) for page in pages()]
    texts.append(("stickslip compare --help", subprocess.run([BINARY, "compare", "--help"], capture_output=True,
                                                              text=True, check=True).stdout))
    checks = []
    for name, text in texts:
        for number, command, scene, arguments in command_lines(text):
            if re.search(r"/[A-Z]+\.yaml$", scene):
                continue  # a placeholder: scenes/SCENE.yaml
            where = "%s:%d" % (name, number)
            c.check(os.path.isfile(os.path.join(ROOT, scene)), "%s: `stickslip %s %s`: the scene exists" %
                    (where, command, scene))
            lists = check_arguments(command, arguments)
            if lists is not None and os.path.isfile(os.path.join(ROOT, scene)):
                checks += [(where, scene, options) for options in lists]
    unique = sorted({(scene, tuple(options)): where for where, scene, options in checks}.items())

    def one(item):
        (scene, options), _ = item
        return subprocess.run([BINARY, "check", scene] + list(options), cwd=ROOT, capture_output=True, text=True)
    with ThreadPoolExecutor(max_workers=2) as pool:
        results = list(pool.map(one, unique))
    for ((scene, options), where), proc in zip(unique, results):
        message = (proc.stderr.strip().split("\n") or [""])[-1]
        c.check(proc.returncode == 0, "%s: `stickslip check %s %s` is accepted%s" %
                (where, scene, " ".join(shlex.quote(o) for o in options), "" if proc.returncode == 0 else
                 ": " + message))
    c.check(len(unique) >= 20, "%d command lines checked" % len(unique))


# Words that narrate the making of the project rather than describe it.
# ("session" stays where it names a thing: Open MPI's session directory and base, a session id, statistics.)
NARRATION = re.compile(r"\bsessions?\b(?! ?-?(?:stat|start|id\b|dir|base))|\bwork periods?\b|\bengineers?\b|"
                       r"\bcoordinator\b|\bthis round\b|\bwe measured\b|\bthe brief\b|"
                       r"shared/notes|shared/seeds|/work/shared|\.\./shared", re.I)


def tracked_files():
    """Every file of the project outside the pages: git's list where the tree is a clone, else the source folders."""
    proc = subprocess.run(["git", "-C", ROOT, "ls-files"], capture_output=True, text=True)
    if proc.returncode == 0 and proc.stdout.strip():
        listed = proc.stdout.split("\n")
    else:
        listed = [os.path.relpath(p, ROOT) for folder in ("cmake", "core", "driver", "meshes", "plugins", "scenes",
                                                          "scripts", "tests", "tools", ".ci")
                  for p in glob.glob(os.path.join(ROOT, folder, "**", "*"), recursive=True)]
        listed += ["CMakeLists.txt"]
    return sorted(set(f for f in listed if f and not f.startswith("build") and os.path.isfile(os.path.join(ROOT, f)))
                  - set(pages()))


def no_narration(c):
    files = pages() + tracked_files()
    count = 0
    for relative in files:
        if relative == os.path.relpath(os.path.abspath(__file__), ROOT):
            continue  # the pattern itself
        try:
            lines = open(os.path.join(ROOT, relative), encoding="utf-8").read().split("\n")
        except UnicodeDecodeError:
            continue
        count += 1
        for number, line in enumerate(lines, 1):
            match = NARRATION.search(line)
            c.check(match is None, "%s:%d narrates how the project was made (`%s`): state the commit and date" %
                    (relative, number, match.group(0) if match else ""))
    c.check(count > 100, "%d files read" % count)


if __name__ == "__main__":
    main([links, scene_list, formulation_table, face_types, abi_formulations, strategy_names, commands,
          no_narration])
