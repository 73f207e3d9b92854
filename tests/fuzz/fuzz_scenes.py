#!/usr/bin/env python3
"""Mutation fuzzer over the bundled scenes (issue 15): each case takes a scene of scenes/, mutates it (a value made
non-finite, huge, negative, empty or of the wrong type; a key removed, renamed or added; a list element dropped or
doubled; the text truncated or salted with bad bytes; an override through --set), runs `stickslip check` on it and,
for every fifth case, `stickslip run --steps 2 --out DIR`, and fails on:
  - a crash: a signal, an exit status other than 0 or 1, a sanitizer report, "terminate called", ...;
  - a hang: no answer within --timeout seconds;
  - an error without a message (exit 1 and no "stickslip:" line);
  - accepted non-finite input: exit 0 although a number the scene sets was made nan, inf or 1e999;
  - a run reported "ok" whose history.csv holds nan or inf.
The cases are a deterministic function of --seed and the case number; --count and --seconds bound the pass (it stops
starting new cases after --seconds). Every failing case is kept in --keep (scene, command, output) to replay.

  python3 tests/fuzz/fuzz_scenes.py --count 100 --seconds 180          # short pass (CI: ctest fuzz_scenes_short)
  python3 tests/fuzz/fuzz_scenes.py --count 5000 --seconds 7200 --seed 7   # long pass, on demand
"""
import argparse
import copy
import glob
import json
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile
import time

import yaml

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCENES = sorted(glob.glob(os.path.join(ROOT, "scenes", "*.yaml")))

NON_FINITE = [".nan", ".inf", "-.inf", "1e999", "-1e999", ".NaN", "+.Inf"]
ODD_NUMBERS = [0, -0.0, -1, 1e308, -1e308, 1e-308, 5e-324, 2147483648, -2147483649, 1e15, 0.5, 3, 1e6, -1e6, 1e-12]
ODD_VALUES = [None, "", [], {}, "abc", [1, 2, 3], {"a": 1}, True, "∞ ünïcode", "x" * 5000, [[0, 0], [1]], [None]]
CRASH_MARKERS = ["Segmentation", "Aborted", "core dumped", "terminate called", "AddressSanitizer",
                 "runtime error:", "LeakSanitizer", "stack smashing", "double free", "*** Process received signal",
                 "MPI_ABORT", "Bus error", "Floating point exception", "internal error"]

# Limits that keep every case fast; a mutation may override them, as a user could.
FAST = {"max_elements": 200000, "time_limit": 20}


def load(path):
    text = open(path).read().replace("../meshes", os.path.join(ROOT, "meshes"))
    return text, yaml.safe_load(text)


def paths(node, prefix=()):
    """Every (path, value) below node; a path is a tuple of keys and indices."""
    yield prefix, node
    if isinstance(node, dict):
        for k, v in node.items():
            yield from paths(v, prefix + (k,))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from paths(v, prefix + (i,))


def get_parent(tree, path):
    node = tree
    for key in path[:-1]:
        node = node[key]
    return node


def is_number(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool)


class Mutant:
    def __init__(self, scene, text, description, sets=(), non_finite=False):
        self.scene, self.text, self.description = scene, text, description
        self.sets, self.non_finite = list(sets), non_finite


def with_fast_limits(tree):
    if not FAST:
        return tree
    mesh = tree.get("mesh")
    for entry in mesh if isinstance(mesh, list) else [mesh]:
        if isinstance(entry, dict):
            for k, v in FAST.items():
                entry.setdefault(k, v)
    return tree


def dump(tree):
    return yaml.safe_dump(tree, sort_keys=False, allow_unicode=True, width=120)


def set_value(value):
    """A YAML text for --set key=VALUE."""
    if isinstance(value, str) and value in NON_FINITE:
        return value
    return yaml.safe_dump(value, default_flow_style=True, allow_unicode=True).strip().removesuffix("\n...")


def mutate(rng, scene_path):
    text, tree = load(scene_path)
    name = os.path.basename(scene_path)
    all_paths = [p for p, _ in paths(tree) if p]
    numbers = [p for p, v in paths(tree) if p and is_number(v)]
    kind = rng.choice(["non_finite", "non_finite", "odd_number", "odd_value", "delete", "rename", "add_key",
                       "list", "swap", "set_non_finite", "set_odd", "text"])
    tree = copy.deepcopy(tree)
    if kind in ("non_finite", "set_non_finite") and numbers:
        path = rng.choice(numbers)
        value = rng.choice(NON_FINITE)
        if kind == "set_non_finite":
            key = ".".join(str(k) for k in path)
            return Mutant(name, dump(with_fast_limits(tree)), "--set %s=%s" % (key, value),
                          ["%s=%s" % (key, value)], non_finite=True)
        get_parent(tree, path)[path[-1]] = "@@%s@@" % value  # placed unquoted below
        out = dump(with_fast_limits(tree))
        for placeholder in ("'@@%s@@'" % value, "\"@@%s@@\"" % value, "@@%s@@" % value):
            out = out.replace(placeholder, value)
        return Mutant(name, out, "%s = %s" % (".".join(map(str, path)), value), non_finite=True)
    if kind == "odd_number" and numbers:
        path = rng.choice(numbers)
        value = rng.choice(ODD_NUMBERS)
        get_parent(tree, path)[path[-1]] = value
        return Mutant(name, dump(with_fast_limits(tree)), "%s = %r" % (".".join(map(str, path)), value))
    if kind in ("odd_value", "set_odd"):
        path = rng.choice(all_paths)
        value = rng.choice(ODD_VALUES)
        if kind == "set_odd":
            key = ".".join(str(k) for k in path)
            return Mutant(name, dump(with_fast_limits(tree)), "--set %s=%s" % (key, set_value(value)),
                          ["%s=%s" % (key, set_value(value))])
        get_parent(tree, path)[path[-1]] = value
        return Mutant(name, dump(with_fast_limits(tree)), "%s = %r" % (".".join(map(str, path)), value)[:200])
    if kind == "delete":
        path = rng.choice(all_paths)
        del get_parent(tree, path)[path[-1]]
        return Mutant(name, dump(with_fast_limits(tree)), "delete %s" % ".".join(map(str, path)))
    if kind == "rename":
        keyed = [p for p in all_paths if isinstance(p[-1], str)]
        path = rng.choice(keyed)
        parent = get_parent(tree, path)
        parent[path[-1] + rng.choice(["_", "s", "x"])] = parent.pop(path[-1])
        return Mutant(name, dump(with_fast_limits(tree)), "rename %s" % ".".join(map(str, path)))
    if kind == "add_key":
        maps = [p for p, v in paths(tree) if isinstance(v, dict)]
        path = rng.choice(maps)
        node = tree
        for key in path:
            node = node[key]
        node[rng.choice(["extra", "mu", "refine", "dt", "parameters"])] = rng.choice(ODD_VALUES + ODD_NUMBERS)
        return Mutant(name, dump(with_fast_limits(tree)), "add a key under %s" % ".".join(map(str, path)))
    if kind == "list":
        lists = [p for p, v in paths(tree) if isinstance(v, list) and v]
        if lists:
            path = rng.choice(lists)
            node = tree
            for key in path:
                node = node[key]
            if rng.random() < 0.5:
                node.pop(rng.randrange(len(node)))
                what = "drop"
            else:
                node.append(copy.deepcopy(rng.choice(node)))
                what = "double"
            return Mutant(name, dump(with_fast_limits(tree)), "%s an element of %s" % (what, ".".join(map(str, path))))
    if kind == "swap" and len(all_paths) > 1:
        a, b = rng.sample(all_paths, 2)
        if a[:len(b)] != b and b[:len(a)] != a:
            pa, pb = get_parent(tree, a), get_parent(tree, b)
            pa[a[-1]], pb[b[-1]] = pb[b[-1]], pa[a[-1]]
            return Mutant(name, dump(with_fast_limits(tree)), "swap %s and %s" % (".".join(map(str, a)),
                                                                                   ".".join(map(str, b))))
    # text-level: the parser's side
    lines = text.splitlines(True)
    op = rng.choice(["truncate", "drop_line", "double_line", "bytes", "indent"])
    if op == "truncate":
        cut = rng.randrange(len(text))
        return Mutant(name, text[:cut], "truncated at byte %d" % cut)
    i = rng.randrange(len(lines))
    if op == "drop_line":
        del lines[i]
    elif op == "double_line":
        lines.insert(i, lines[i])
    elif op == "bytes":
        junk = rng.choice(["\t", "\ufeff", "\x00", "\x7f", "\ud7ff", ": : :", "&a *a", "{[", "- - -", "\u2028"])
        pos = rng.randrange(len(lines[i]) + 1)
        lines[i] = lines[i][:pos] + junk + lines[i][pos:]
    else:
        lines[i] = rng.choice(["", " ", "   ", "\t"]) + lines[i]
    return Mutant(name, "".join(lines), "%s at line %d" % (op, i + 1))


def run(binary, args, timeout, cwd):
    env = dict(os.environ)
    env.pop("STICKSLIP_PLUGIN_PATH", None)
    start = time.time()
    try:
        proc = subprocess.run([binary] + args, capture_output=True, timeout=timeout, cwd=cwd, env=env)
        out = proc.stdout.decode("utf-8", "replace") + proc.stderr.decode("utf-8", "replace")
        return proc.returncode, proc.stderr.decode("utf-8", "replace"), out, time.time() - start
    except OSError as e:  # the binary itself is missing or being rebuilt: not a finding
        sys.exit("fuzz_scenes: cannot run %s: %s" % (binary, e))
    except subprocess.TimeoutExpired as e:
        # the child and its gmsh helper are killed by subprocess; the helper also dies with its parent
        out = (e.stdout or b"").decode("utf-8", "replace") + (e.stderr or b"").decode("utf-8", "replace")
        return None, out, out, time.time() - start


def judge(rc, stderr, output, mutant, history=None):
    """The reasons this outcome is a failure (empty: fine)."""
    problems = []
    if rc is None:
        return ["hang: no answer within the timeout"]
    if rc == 127 and "error while loading shared libraries" in output:
        sys.exit("fuzz_scenes: the stickslip build is broken or being rebuilt:\n" + output)
    if rc not in (0, 1):
        problems.append("crash: exit status %d" % rc)
    for marker in CRASH_MARKERS:
        if marker in output:
            problems.append("crash marker '%s'" % marker)
    if rc == 1 and not re.search(r"^stickslip[: ]", stderr, re.M):
        problems.append("error without a message")
    if rc == 0 and mutant.non_finite:
        problems.append("accepted non-finite input (%s)" % mutant.description)
    if rc == 0 and history and re.search(r"(^|,)(-?nan|-?inf)(,|$)", history, re.M | re.I):
        problems.append("run reported ok with nan/inf in history.csv")
    return problems


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--bin", default=os.environ.get("STICKSLIP_BIN", os.path.join(ROOT, "build", "bin",
                                                                                     "stickslip")))
    parser.add_argument("--seed", type=int, default=15)
    parser.add_argument("--count", type=int, default=100)
    parser.add_argument("--seconds", type=float, default=240, help="stop starting new cases after this")
    parser.add_argument("--timeout", type=float, default=60, help="a case taking longer is a hang")
    parser.add_argument("--run-every", type=int, default=5, help="also `run --steps 2` every N-th case")
    parser.add_argument("--keep", default=os.path.join(tempfile.gettempdir(), "stickslip-fuzz-failures"))
    parser.add_argument("--no-limits", action="store_true",
                        help="do not add mesh.max_elements/time_limit (for builds that lack these keys)")
    args = parser.parse_args()
    if args.no_limits:
        FAST.clear()

    start = time.time()
    work = tempfile.mkdtemp(prefix="stickslip-fuzz-")
    failures, done, runs, exits = [], 0, 0, {}
    for case in range(args.count):
        if time.time() - start > args.seconds:
            break
        rng = random.Random(args.seed * 1000003 + case)
        mutant = mutate(rng, SCENES[rng.randrange(len(SCENES))])
        folder = os.path.join(work, "case-%d" % case)
        os.makedirs(folder)
        scene = os.path.join(folder, "scene.yaml")
        with open(scene, "w", encoding="utf-8", errors="surrogatepass") as f:
            f.write(mutant.text)
        sets = sum((["--set", s] for s in mutant.sets), [])
        commands = [["check", scene] + sets]
        if case % args.run_every == 0:
            commands.append(["run", scene, "--steps", "2", "--quiet", "--out", os.path.join(folder, "out")] + sets)
        for command in commands:
            rc, stderr, output, spent = run(args.bin, command, args.timeout, folder)
            history_path = os.path.join(folder, "out", "history.csv")
            history = open(history_path).read() if command[0] == "run" and os.path.exists(history_path) else None
            problems = judge(rc, stderr, output, mutant, history)
            exits[rc] = exits.get(rc, 0) + 1
            runs += command[0] == "run"
            if problems:
                keep = os.path.join(args.keep, "seed-%d-case-%d" % (args.seed, case))
                shutil.rmtree(keep, ignore_errors=True)
                shutil.copytree(folder, keep)
                with open(os.path.join(keep, "report.txt"), "w") as f:
                    f.write("mutation: %s (from %s)\ncommand: stickslip %s\nproblems: %s\n\n%s" % (
                        mutant.description, mutant.scene, " ".join(command), "; ".join(problems), output))
                failures.append((case, mutant, command, problems, keep))
                print("FAIL case %d (%s, %s): %s\n  kept in %s\n  %s" % (case, mutant.scene, mutant.description,
                      "; ".join(problems), keep, output.strip()[-600:].replace("\n", "\n  ")), flush=True)
        shutil.rmtree(folder, ignore_errors=True)
        done += 1
        if done % 50 == 0:
            print("fuzz_scenes: %d cases, %d failing, %.0f s" % (done, len(failures), time.time() - start), flush=True)
    shutil.rmtree(work, ignore_errors=True)
    print("fuzz_scenes: seed %d, %d cases (%d with run) in %.0f s, exit statuses %s, %d failing" % (
        args.seed, done, runs, time.time() - start, json.dumps({str(k): v for k, v in sorted(
            exits.items(), key=lambda kv: str(kv[0]))}), len(failures)))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
