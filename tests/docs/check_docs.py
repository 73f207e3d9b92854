"""Docs against the program: the result columns and scene keys the docs document must be the ones the program
writes and reads. The truth comes from the program and the code, never from a list kept here:
- history.csv and contact.csv: the headers a real run writes (scenes/block-on-plane.yaml has a displacement
  condition, a rigid obstacle and a contact pair, so every column family appears) against the column tables of
  docs/user-guide.md (names, `a_x/_y/_z` groups, `<placeholder>` parts), in both directions and in order;
- the contact fields of the VTU files a real run writes against the field table of docs/user-guide.md, both ways;
- scene keys: `stickslip keys` lists the keys of docs/scene-reference.md and no others (over a few scenes that
  together use every key), every quantity with a unit; every key of the tables of the reference, and every key path
  quoted in the prose of the docs, is set with `stickslip check --set KEY=VALUE` on a valid scene, and the program
  must not call it an unknown key (it reports every key nobody read); and every key that the core reads by name
  (`sk_cfg_*(node, "key", ...)` in core/**/*.c) must be documented in docs/scene-reference.md.
Usage: python3 check_docs.py CASE; exit code 0 when every check holds."""
import os
import re
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "validation"))
from stickslip_results import ROOT, main, run  # noqa: E402

BINARY = os.environ.get("STICKSLIP_BIN", os.path.join(ROOT, "build", "bin", "stickslip"))
BASE_SCENE = "scenes/block-on-plane.yaml"


def markdown_tables(path):
    """(heading path, lead line, rows) of every table in a markdown file: the headings above it (## and ###), the
    last non-empty line before it, and its body rows as lists of cells."""
    tables, headings, lead, rows = [], {}, "", None
    for line in open(path, encoding="utf-8"):
        line = line.rstrip("\n")
        if line.startswith("|"):
            cells = [cell.strip() for cell in line.strip("|").split("|")]
            if rows is None:
                rows = []
                tables.append((dict(headings), lead, rows))
            elif not all(re.fullmatch(r":?-+:?", cell) for cell in cells):
                rows.append(cells)
            continue
        rows = None
        match = re.match(r"(#{2,3}) (.*)", line)
        if match:
            headings[len(match.group(1))] = match.group(2).strip()
            headings.pop(3, None) if len(match.group(1)) == 2 else None
        if line.strip():
            lead = line.strip()
    return tables


def documented_names(cell):
    """The names a first-column cell documents: backticked tokens, `a_x/_y/_z` expanded to a_x, a_y, a_z."""
    names = []
    for token in re.findall(r"`([^`]+)`", cell):
        parts = token.split("/")
        stem = parts[0][: parts[0].rfind("_")]
        names += [parts[0]] + [stem + part for part in parts[1:]]
    return names


def pattern_of(name):
    """A documented column name as a regex: `<...>` stands for any non-empty name."""
    return re.compile("".join("[^,]+" if re.fullmatch(r"<[^>]+>", piece) else re.escape(piece)
                              for piece in re.split(r"(<[^>]+>)", name)) + "$")


def column_table(section):
    """(name, row) of every column the table under `### section` of docs/user-guide.md documents."""
    guide = os.path.join(ROOT, "docs", "user-guide.md")
    for headings, _, rows in markdown_tables(guide):
        if headings.get(3) == section and rows and rows[0]:
            return [(name, k) for k, row in enumerate(rows) for name in documented_names(row[0])]
    raise AssertionError("docs/user-guide.md has no column table under '### %s'" % section)


def compare_columns(c, file_name, written):
    documented = [(name, row, pattern_of(name)) for name, row in column_table(file_name)]
    for name, _, pattern in documented:
        c.check(any(pattern.match(column) for column in written),
                "%s: documented column `%s` is written" % (file_name, name))
    # Order by table row: a row may stand for a repeated group (reaction_<bc>_x/_y/_z once per condition).
    rows = []
    for column in written:
        owners = [row for _, row, pattern in documented if pattern.match(column)]
        c.check(bool(owners), "%s: written column `%s` is documented in docs/user-guide.md" % (file_name, column))
        if owners:
            rows.append(next((row for row in owners if not rows or row >= rows[-1]), owners[0]))
    c.check(rows == sorted(rows), "%s: the columns are written in the documented order" % file_name)


def written_headers():
    results, _ = run(BASE_SCENE, "--steps", "2")
    headers = {}
    for name in ("history.csv", "contact.csv"):
        with open(os.path.join(results.folder, name)) as f:
            headers[name] = f.readline().strip().split(",")
    return headers


def history_columns(c):
    compare_columns(c, "history.csv", written_headers()["history.csv"])


def contact_columns(c):
    compare_columns(c, "contact.csv", written_headers()["contact.csv"])


def vtu_arrays(path, section):
    """Names of the DataArrays of a .vtu in <PointData> or <CellData>."""
    text = open(path, "rb").read().split(b"<AppendedData")[0].decode("latin-1")
    start, end = text.find("<%s>" % section), text.find("</%s>" % section)
    return re.findall(r'Name="([^"]+)"', text[start:end]) if start >= 0 else []


def vtu_contact_fields(c):
    """The contact fields of the VTU files (the bodies' pieces step-NNNNNN/rank-RRRR.vtu, the slave surfaces' pieces
    contact-NNNNNN/rank-RRRR.vtu, the
    obstacles') against the field table of docs/user-guide.md, both ways. mortar-dual on the block: a plugin with
    friction and multipliers, so that every optional field is written."""
    results, _ = run(BASE_SCENE, "--steps", "2", "--set", "contact.0.plugin=mortar-dual", "--set",
                     "contact.0.strategy=saddle-point", "--replace", "contact.0.parameters={mu: 0.3}")
    documented = {name for name, _ in column_table("contact.pvd and contact-NNNNNN.pvtu")}
    folder = results.folder
    body = [n for n in vtu_arrays(os.path.join(folder, "step-000002", "rank-0000.vtu"), "PointData")
            if n.startswith("contact_")]
    points = vtu_arrays(os.path.join(folder, "contact-000002", "rank-0000.vtu"), "PointData")
    cells = vtu_arrays(os.path.join(folder, "contact-000002", "rank-0000.vtu"), "CellData")
    for where, names in (("step-000002/rank-0000.vtu point", body), ("contact-000002/rank-0000.vtu point", points),
                         ("contact-000002/rank-0000.vtu cell", cells)):
        for name in names:
            c.check(name in documented, "%s field `%s` is documented in docs/user-guide.md" % (where, name))
    for name in documented:
        c.check(name in points or name in cells, "documented field `%s` is written to the contact pieces" % name)
        c.check(not name.startswith("contact_") or name in body, "documented field `%s` is on the bodies' nodes" % name)
    obstacle = vtu_arrays(os.path.join(folder, "obstacles-000002.vtu"), "CellData")
    c.check(obstacle == ["obstacle"], "obstacles-000002.vtu has the cell field `obstacle` (%s)" % obstacle)


# A value of the documented type for `--set` (any value will do: a key the program knows fails, if at all, on its
# value, and only a key nobody reads is reported as unknown).
SAMPLE_VALUES = [("vec3", "[0, 0, 1]"), ("vecD", "[0, 0]"), ("bool", "true"), ("int", "1"), ("number", "1"),
                 ("string", "x"), ("history", "[[0, 1]]"), ("list", "[]"), ("map", "{}")]


def documented_keys():
    """(key path for --set, table cell) of every key of docs/scene-reference.md. The section of a table gives the
    path prefix ("Top level": none; a section whose top-level type is a list: its first element, `bodies.0.`); a
    table led by "<Name> keys:" holds the keys of the map <name> inside that section's entries."""
    tables = markdown_tables(os.path.join(ROOT, "docs", "scene-reference.md"))
    top_types = {}
    for headings, _, rows in tables:
        if headings.get(2) == "Top level":
            top_types = {documented_names(row[0])[0]: row[1] for row in rows}
    keys = []
    for headings, lead, rows in tables:
        section = headings.get(2, "")
        if headings.get(3) == "Defaults computed from the scene":
            continue  # rows of plugins and their parameters (checked by the plugins), not scene keys
        if section == "Top level":
            prefix = ""
        else:
            prefix = section + (".0." if top_types.get(section, "").startswith("list") else ".")
        sub = re.fullmatch(r"(\w+) keys:", lead)
        if sub:
            prefix += sub.group(1).lower() + "."
        for row in rows:
            for name in documented_names(row[0]):
                keys.append((prefix + name, row))
    return keys


def sample_value(row):
    default = re.fullmatch(r"`([^`]+)`", row[2]) if len(row) > 2 else None
    if default and not default.group(1).startswith("pair-"):
        return default.group(1)
    return next((value for kind, value in SAMPLE_VALUES if row[1].startswith(kind)), "1")


# keys of one mesh in a list of meshes (`mesh.0.order`) are checked on a scene with a mesh list
MESH_LIST_SCENE = "scenes/mortar-patch-test-3d.yaml"


def check_with(settings):
    """`stickslip check BASE_SCENE --set S` for each S (MESH_LIST_SCENE for `mesh.N...`), a few at a time (each is a
    separate program start)."""
    def one(setting):
        scene = MESH_LIST_SCENE if re.match(r"mesh\.\d", setting) else BASE_SCENE
        return subprocess.run([BINARY, "check", os.path.join(ROOT, scene), "--set", setting],
                              capture_output=True, text=True)
    with ThreadPoolExecutor(max_workers=4) as pool:
        return list(pool.map(one, settings))


def scene_keys_documented_exist(c):
    keys = documented_keys()
    c.check(len(keys) > 40, "docs/scene-reference.md documents %d keys" % len(keys))
    runs = check_with(["%s=%s" % (key, sample_value(row)) for key, row in keys])
    for (key, _), proc in zip(keys, runs):
        unknown = "unknown key" in proc.stderr
        c.check(proc.returncode in (0, 1) and not unknown, "scene key `%s` is read by the program%s" %
                (key, "" if not unknown else ": " + proc.stderr.strip()))


def prose_keys():
    """(file, key) of scene key paths quoted in the prose of README.md and docs/**/*.md (`time.dt`,
    `--set contact[0].plugin=...`); file names, wildcards, placeholders (`mesh.N`) and plugin parameters (checked
    by their plugins, which differ per scene) are left out."""
    top = "time|solver|output|mesh|bodies|boundary|contact|description|dimension|body_force"
    files = [os.path.join(ROOT, "README.md")] + [os.path.join(folder, name)
                                                for folder, _, names in os.walk(os.path.join(ROOT, "docs"))
                                                for name in names if name.endswith(".md")]
    found = []  # (file, key), each once
    for path in sorted(files):
        text = re.sub(r"```.*?```", "", open(path, encoding="utf-8").read(), flags=re.S)
        for token in re.findall(r"`([^`]+)`", text):
            token = re.sub(r"^--(set|replace) ", "", token)
            key = re.split(r"[=: ]", token)[0]
            key = re.sub(r"\[(\d+)\]", r".\1", key)
            if (re.match(r"(%s)\." % top, key) and not re.search(r"\.(h|c|csv|md|yaml|vtu|pvd|json|geo|msh)$", key)
                    and "*" not in key and ".parameters." not in key and not re.search(r"\.[A-Z]\b", key)):
                if (os.path.relpath(path, ROOT), key) not in found:
                    found.append((os.path.relpath(path, ROOT), key))
    return found


def scene_keys_in_prose_exist(c):
    found = prose_keys()
    c.check(len(found) >= 10, "%d scene keys quoted in the docs' prose" % len(found))
    for (path, key), proc in zip(found, check_with(["%s=1" % key for _, key in found])):
        c.check(proc.returncode in (0, 1) and "unknown key" not in proc.stderr,
                "%s: `%s` is a scene key the program reads" % (path, key))


def scene_keys_read_are_documented(c):
    reference = open(os.path.join(ROOT, "docs", "scene-reference.md"), encoding="utf-8").read()
    reference = re.sub(r"```.*?```", "", reference, flags=re.S)  # examples are no documentation of a key
    backticked = " ".join(re.findall(r"`([^`]+)`", reference))
    read = set()
    for folder, _, files in os.walk(os.path.join(ROOT, "core")):
        for name in files:
            # config.c is the reader itself; restart.c reads a checkpoint's own checkpoint.yaml, not a scene
            if name.endswith(".c") and name not in ("config.c", "restart.c"):
                text = open(os.path.join(folder, name), encoding="utf-8").read()
                read |= set(re.findall(r"\bsk_cfg_\w+\(\s*\w+\s*,\s*\"(\w+)\"", text))
    c.check(len(read) > 30, "the core reads %d scene keys by name" % len(read))
    for key in sorted(read):
        c.check(re.search(r"\b%s\b" % re.escape(key), backticked) is not None,
                "scene key `%s` (read in core/) is documented in docs/scene-reference.md" % key)


# Scenes whose keys together reach every documented key: an obstacle and histories; a resultant with `area`, a
# rotated mesh and tractions; a mesh list, a deformable master and a strategy; a body plugin.
KEY_SCENES = [
    (BASE_SCENE,),
    ("scenes/compressed-block.yaml", "--replace", "boundary.3={name: load, group: zmax, resultant: [0, 0, -1], "
     "area: current}", "--set", "mesh.rotate={axis: [0, 0, 1], degrees: 10}"),
    ("scenes/mortar-patch-test-3d.yaml",),
    ("scenes/corot-ball-on-plane.yaml",),
    ("scenes/disks-in-box-2d.yaml",),
]


def listed_keys():
    """Key paths `stickslip keys` prints for KEY_SCENES, without indices, and the lines printing them."""
    keys = {}
    for scene, *args in KEY_SCENES:
        proc = subprocess.run([BINARY, "keys", os.path.join(ROOT, scene), *args], capture_output=True, text=True)
        if proc.returncode != 0:
            raise AssertionError("stickslip keys %s failed: %s" % (scene, proc.stderr))
        for line in proc.stdout.splitlines()[3:]:  # two comment lines and the column heads
            keys.setdefault(re.sub(r"\[\d+\]", "", line.split()[0]), line)
    return keys


def keys_listed_are_documented(c):
    """`stickslip keys` and docs/scene-reference.md name the same keys: every key listed is documented (or lies in a
    documented map: a plugin's or a mesh script's `parameters`, `rotate`), every documented key is listed; and
    every quantity listed has a unit."""
    listed = listed_keys()
    documented = {re.sub(r"\.0(?=\.|$)", "", key) for key, _ in documented_keys()}
    c.check(len(listed) > 60, "stickslip keys lists %d keys over %d scenes" % (len(listed), len(KEY_SCENES)))

    def under(key, names):
        parts = key.split(".")
        return any(".".join(parts[:n]) in names for n in range(1, len(parts) + 1))
    for key in sorted(listed):
        c.check(under(key, documented), "listed key `%s` is documented in docs/scene-reference.md" % key)
    for key in sorted(documented):
        c.check(key in listed or any(k.startswith(key + ".") for k in listed),
                "documented key `%s` is listed by stickslip keys" % key)
    unitless = [line for line in listed.values() if re.search(r"\s\?\s", line)]
    c.check(not unitless, "every quantity has a unit (%s)" % unitless)


if __name__ == "__main__":
    main([history_columns, contact_columns, vtu_contact_fields, scene_keys_documented_exist, scene_keys_in_prose_exist,
          scene_keys_read_are_documented, keys_listed_are_documented])
