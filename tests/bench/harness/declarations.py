"""Benchmark definitions (tests/bench/benchmarks/*.yaml), stress cases (tests/bench/stress/*.yaml) and plugin
declarations (tests/bench/plugins/*.yaml): loading, checking and expanding them into runs. docs/benchmarks.md
describes the three formats. Nothing here knows a plugin: a run is a scene file plus command-line options."""
import ast
import itertools
import math
import os
import re
import subprocess

import yaml

BENCH = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ROOT = os.path.dirname(os.path.dirname(BENCH))
BIN = os.environ.get("STICKSLIP_BIN", os.path.join(ROOT, "build", "bin", "stickslip"))


class DeclarationError(Exception):
    """A malformed benchmark, stress case or declaration; the message names the file and key."""


def numeric(value):
    """PyYAML reads 1.0e6 (no sign in the exponent, YAML 1.1) as a string: such strings become floats."""
    if isinstance(value, str):
        try:
            return float(value)
        except ValueError:
            return value
    return value


def load_yaml(path):
    with open(path) as f:
        try:
            data = yaml.safe_load(f)
        except yaml.YAMLError as e:
            raise DeclarationError("%s: %s" % (path, str(e).replace("\n", " ")))
    if not isinstance(data, dict):
        raise DeclarationError("%s: expected a map at the top level" % path)
    return data


def _check_keys(path, where, data, allowed):
    unknown = sorted(set(data) - set(allowed))
    if unknown:
        raise DeclarationError("%s: %s: unknown key(s) %s (known: %s)" % (path, where, ", ".join(unknown),
                                                                          ", ".join(sorted(allowed))))


# --- expressions: "$name" and "$(expression)" over numeric variables ------------------------------------------------

_ALLOWED_NODES = (ast.Expression, ast.BinOp, ast.UnaryOp, ast.Constant, ast.Name, ast.Load, ast.Add, ast.Sub,
                  ast.Mult, ast.Div, ast.Pow, ast.USub, ast.UAdd, ast.Call, ast.List, ast.Tuple)
_FUNCTIONS = {"sqrt": math.sqrt, "min": min, "max": max}


def evaluate_expression(text, variables, where):
    """Arithmetic over the variables (+ - * / **, sqrt, min, max); anything else is an error naming `where`."""
    try:
        tree = ast.parse(str(text).strip(), mode="eval")
    except SyntaxError as e:
        raise DeclarationError("%s: cannot parse expression %r (%s)" % (where, text, e.msg))
    for node in ast.walk(tree):
        if not isinstance(node, _ALLOWED_NODES):
            raise DeclarationError("%s: %r: only arithmetic is allowed in expressions" % (where, text))
        if isinstance(node, ast.Call) and not (isinstance(node.func, ast.Name) and node.func.id in _FUNCTIONS):
            raise DeclarationError("%s: %r: unknown function" % (where, text))
        if isinstance(node, ast.Name) and node.id not in variables and node.id not in _FUNCTIONS:
            raise DeclarationError("%s: %r: unknown variable %r (known: %s)" % (where, text, node.id,
                                                                             ", ".join(sorted(variables))))
    return eval(compile(tree, where, "eval"), {"__builtins__": {}}, {**_FUNCTIONS, **variables})


def substitute(value, variables, where):
    """Replaces "$name" and "$(expr)" strings (also inside lists and maps); other values are returned as they are."""
    if isinstance(value, dict):
        return {k: substitute(v, variables, "%s.%s" % (where, k)) for k, v in value.items()}
    if isinstance(value, list):
        return [substitute(v, variables, "%s[%d]" % (where, i)) for i, v in enumerate(value)]
    if isinstance(value, str) and value.startswith("$"):
        body = value[1:]
        if body.startswith("(") and body.endswith(")"):
            body = body[1:-1]
        return evaluate_expression(body, variables, where)
    return value


def environment(variables, values, where):
    """Variables and swept values; a variable written "$(expression)" is derived from the others (e.g. a penalty
    from a swept factor and E), evaluated once the swept values are known."""
    env = {**variables, **values}
    for _ in range(3):  # derived variables may use derived variables
        pending = {k: v for k, v in env.items() if isinstance(v, str) and v.startswith("$")}
        if not pending:
            return env
        for k, v in pending.items():
            try:
                env[k] = substitute(v, {n: x for n, x in env.items() if n not in pending}, "%s: %s" % (where, k))
            except DeclarationError:
                continue
    raise DeclarationError("%s: cannot evaluate the variables %s" % (where, ", ".join(sorted(pending))))


def sweep_value(value, variables, where):
    """A sweep value: a number, or an expression string such as "1e3*E"."""
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return value
    if isinstance(value, str):
        return evaluate_expression(value[1:] if value.startswith("$") else value, variables, where)
    raise DeclarationError("%s: sweep value %r must be a number or an expression" % (where, value))


def override_option(value):
    """`--replace` for a map (a benchmark's `parameters` or `set` value is the whole map, as declared), `--set`
    otherwise (`--set` would merge a map into the scene's)."""
    return "--replace" if isinstance(value, dict) else "--set"


def yaml_flow(value):
    """A value as a YAML flow scalar or collection for `--set key=value`."""
    if value is None:
        return "~"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, dict):
        return "{" + ", ".join("%s: %s" % (k, yaml_flow(v)) for k, v in value.items()) + "}"
    if isinstance(value, list):
        return "[" + ", ".join(yaml_flow(v) for v in value) + "]"
    return str(value)


# --- benchmark definitions and stress cases ------------------------------------------------------------------------

BENCHMARK_KEYS = {"scene", "title", "error", "error_label", "reference", "pairs", "variables", "sweeps", "quick",
                  "linear_solvers", "set", "timeout", "notes", "plot"}
STRESS_KEYS = (BENCHMARK_KEYS - {"error", "error_label", "reference", "quick"}) | {"short", "dt_ladder", "expect",
                                                                                  "core", "revolutions", "closed",
                                                                                  "bounds"}
SWEEP_KEYS = {"key", "set", "values"}


class Sweep:
    """One swept variable: its values and the overrides it makes (`key: K` is short for `set: {K: $name}`)."""

    def __init__(self, path, name, data):
        where = "%s: sweeps.%s" % (path, name)
        if isinstance(data, list):
            data = {"values": data}
        if not isinstance(data, dict) or "values" not in data:
            raise DeclarationError("%s: give `values` (and `key` or `set`)" % where)
        _check_keys(path, "sweeps." + name, data, SWEEP_KEYS)
        self.name = name
        self.values = list(data["values"])
        if not self.values:
            raise DeclarationError("%s: no values" % where)
        self.set = dict(data.get("set") or {})
        if "key" in data:
            self.set[data["key"]] = "$" + name
        self.where = where


class Benchmark:
    def __init__(self, path, kind="benchmark"):
        data = load_yaml(path)
        self.path = path
        self.name = os.path.splitext(os.path.basename(path))[0]
        _check_keys(path, kind, data, BENCHMARK_KEYS if kind == "benchmark" else STRESS_KEYS)
        for key in ("scene", "title"):
            if key not in data:
                raise DeclarationError("%s: missing `%s`" % (path, key))
        self.data = data
        self.scene = data["scene"]
        self.title = data["title"]
        self.error = data.get("error")
        if kind == "benchmark" and not self.error:
            raise DeclarationError("%s: missing `error` (an evaluator in tests/bench/harness/errors.py)" % path)
        self.error_label = data.get("error_label", self.error)
        self.reference = data.get("reference", "analytical")
        self.pairs = data.get("pairs", "all")
        self.variables = {k: numeric(v) for k, v in (data.get("variables") or {}).items()}
        self.sweeps = [Sweep(path, n, d) for n, d in (data.get("sweeps") or {}).items()]
        self.quick = dict(data.get("quick") or data.get("short") or {})
        for name in self.quick:
            if name not in [s.name for s in self.sweeps]:
                raise DeclarationError("%s: quick.%s: not a sweep" % (path, name))
        self.linear_solvers = list(data.get("linear_solvers") or ["direct"])
        self.set = dict(data.get("set") or {})
        self.timeout = float(data.get("timeout", 1800))
        self.notes = data.get("notes", "")


def benchmark_files(folder):
    folder = os.path.join(BENCH, folder)
    return sorted(os.path.join(folder, f) for f in os.listdir(folder) if f.endswith(".yaml"))


def load_benchmarks(folder="benchmarks", kind="benchmark"):
    return {b.name: b for b in (Benchmark(p, kind) for p in benchmark_files(folder))}


# --- plugin declarations -------------------------------------------------------------------------------------------

ENTRY_KEYS = {"parameters", "set", "sweep", "strategies", "linear_solvers", "scene", "label", "strategy_key", "notes",
              "bounds", "expect_failure", "short", "scheme_energy", "only"}
DECLARATION_KEYS = ENTRY_KEYS | {"plugin", "kind", "benchmarks", "stress"}


class Declaration:
    def __init__(self, path):
        data = load_yaml(path)
        _check_keys(path, "declaration", data, DECLARATION_KEYS)
        if "plugin" not in data:
            raise DeclarationError("%s: missing `plugin`" % path)
        self.path = path
        self.plugin = data["plugin"]
        self.kind = data.get("kind", "pair")
        if self.kind not in ("pair", "body"):
            raise DeclarationError("%s: kind: %r is neither 'pair' nor 'body'" % (path, self.kind))
        self.defaults = {k: data[k] for k in ENTRY_KEYS if k in data}
        self.entries = {}
        for section in ("benchmarks", "stress"):
            entries = data.get(section) or {}
            if not isinstance(entries, dict):
                raise DeclarationError("%s: %s: expected a map name -> entry" % (path, section))
            for name, entry in entries.items():
                # one entry, or a list of variants (each its own curve: give each a distinct `label`)
                variants = entry if isinstance(entry, list) else [entry or {}]
                out = []
                for i, variant in enumerate(variants):
                    where = "%s.%s" % (section, name) + ("[%d]" % i if isinstance(entry, list) else "")
                    if not isinstance(variant, dict):
                        raise DeclarationError("%s: %s: expected a map" % (path, where))
                    _check_keys(path, where, variant, ENTRY_KEYS)
                    # the top-level keys are defaults of the benchmark entries; stress entries stand alone (a
                    # stress case fixes what the benchmarks sweep)
                    out.append({**self.defaults, **variant} if section == "benchmarks" else dict(variant))
                if len(out) > 1 and len({v.get("label") for v in out}) < len(out):
                    raise DeclarationError("%s: %s.%s: variants need distinct labels" % (path, section, name))
                self.entries[(section, name)] = out


def load_declarations():
    folder = os.path.join(BENCH, "plugins")
    out = {}
    for f in sorted(os.listdir(folder)):
        if f.endswith(".yaml"):
            d = Declaration(os.path.join(folder, f))
            if d.plugin in out:
                raise DeclarationError("%s: plugin %s is also declared in %s" % (d.path, d.plugin,
                                                                                  out[d.plugin].path))
            out[d.plugin] = d
    return out


def installed_plugins(binary=BIN):
    """{name: {"strategies": [...], "capabilities": [...]}} from `stickslip plugins` (the listing users read)."""
    if not (os.path.isfile(binary) and os.access(binary, os.X_OK)):
        raise DeclarationError("no stickslip driver at %s: build it (scripts/build.sh), or name one with --binary "
                               "or STICKSLIP_BIN" % binary)
    proc = subprocess.run([binary, "plugins"], capture_output=True, text=True)
    plugins, current = {}, None
    for line in proc.stdout.splitlines():
        m = re.match(r"^(\S+)\s+\(ABI", line)
        if m:
            current = plugins.setdefault(m.group(1), {"strategies": [], "capabilities": []})
            continue
        m = re.match(r"^\s+(strategies|capabilities):\s+(.*)$", line)
        if current is not None and m:
            if m.group(1) == "strategies":
                current["strategies"] = [s.replace("(default)", "").strip() for s in m.group(2).split(",")]
            else:
                current["capabilities"] = m.group(2).split()
    return plugins


# --- expansion into runs -------------------------------------------------------------------------------------------

class Run:
    """One configuration: the options of `stickslip run` and the values that identify it in tables and plots."""

    def __init__(self, bench, plugin, strategy, solver, values, args, label, scene, options=None):
        self.bench, self.plugin, self.strategy, self.solver = bench, plugin, strategy, solver
        self.options = options or {}  # declaration keys the evaluators read
        self.values = values          # swept variable -> value
        self.args = args              # --plugin/--set options
        self.label = label            # the curve this run belongs to
        self.scene = scene

    @property
    def tag(self):
        # a labelled variant (penalty-nts/tet10, mortar-dual/standard) has its own folder: the variants of one
        # plugin share plugin, strategy, solver and values, and would overwrite each other's runs
        parts = [self.options.get("label") or self.plugin or self.label, self.strategy or "", self.solver or ""]
        parts += ["%s%s" % (k, _short(v)) for k, v in sorted(self.values.items())]
        return re.sub(r"[^A-Za-z0-9.+_-]+", "_", "-".join(p for p in parts if p))


def _short(v):
    return ("%.4g" % v) if isinstance(v, float) else str(v)


def _pair_indices(bench, scene_path):
    if bench.pairs != "all":
        return list(bench.pairs)
    if not os.path.exists(os.path.join(ROOT, scene_path)):
        return []  # the caller reports the missing scene
    with open(os.path.join(ROOT, scene_path)) as f:
        scene = yaml.safe_load(f)
    return list(range(len(scene.get("contact") or [])))


def _sweep_product(sweeps, variables, subset, where):
    """[(values dict, overrides dict)] over the product of the sweeps (subset: name -> values to keep)."""
    axes = []
    for s in sweeps:
        values = subset.get(s.name, s.values)
        axes.append([(s, sweep_value(v, variables, "%s.values" % s.where)) for v in values])
    out = []
    for combo in itertools.product(*axes):
        vals = {s.name: v for s, v in combo}
        env = environment(variables, vals, where)
        sets = {}
        for s, _ in combo:
            sets.update(substitute(s.set, env, s.where))
        out.append((vals, sets))
    return out


def expand(bench, declaration, section, plugins, quick=False, subset=None, short=False):
    """The runs of one plugin on one benchmark (or stress case), over the variants of its entry; [] when the plugin
    does not declare it. short (the stress suite's short pass): the default strategy only, and no variant that says
    `short: false`."""
    runs = []
    for entry in declaration.entries.get((section, bench.name), []):
        if not (short and entry.get("short") is False):
            runs += _expand_variant(bench, declaration, section, plugins, quick, subset, short, entry)
    return runs


def _expand_variant(bench, declaration, section, plugins, quick, subset, short, entry):
    where = "%s: %s.%s" % (declaration.path, section, bench.name)
    scene = entry.get("scene", bench.scene)
    listed = plugins.get(declaration.plugin, {}).get("strategies") or [None]
    strategies = entry.get("strategies", listed)
    if short:
        strategies = strategies[:1]
    solvers = entry.get("linear_solvers", bench.linear_solvers)
    own = [Sweep(declaration.path, n, d) for n, d in (entry.get("sweep") or {}).items()]
    if subset is None:
        subset = bench.quick if quick else {}
        if quick:  # a quick run keeps the first value of the declaration's own sweeps
            subset = {**subset, **{s.name: s.values[:1] for s in own}}
    only = entry.get("only") or {}  # a costly variant runs part of the benchmark's sweep: name -> values kept
    for name, values in only.items():
        known = {s.name: s.values for s in bench.sweeps}
        if name not in known or not isinstance(values, list) or any(v not in known[name] for v in values):
            raise DeclarationError("%s.only.%s: must list values of the benchmark's sweep %r (%s)" % (
                where, name, name, known.get(name, "no such sweep")))
        subset = {**subset, name: [v for v in subset.get(name, values) if v in values]}
    runs = []
    pairs = _pair_indices(bench, scene) if declaration.kind == "pair" else []
    for strategy in strategies:
        for solver in solvers:
            for bvals, bsets in _sweep_product(bench.sweeps, bench.variables, subset, bench.path):
                env = environment(bench.variables, bvals, bench.path)
                for pvals, psets in _sweep_product(own, env, subset, where):
                    env2 = environment(bench.variables, {**bvals, **pvals}, where)
                    overrides = {**substitute(bench.set, env2, bench.path + ": set"), **bsets, **psets}
                    args = []
                    if declaration.kind == "pair":
                        args += ["--plugin", declaration.plugin]
                        for n in pairs:
                            if "parameters" in entry:
                                overrides["contact.%d.parameters" % n] = substitute(entry["parameters"], env2,
                                                                                  where + ".parameters")
                            if strategy:
                                overrides["contact.%d.strategy" % n] = strategy
                    elif strategy and "strategy_key" in entry:
                        overrides[entry["strategy_key"]] = strategy
                    overrides.update(substitute(entry.get("set") or {}, env2, where + ".set"))
                    overrides["solver.linear.solver"] = solver
                    for key, value in overrides.items():
                        args += [override_option(value), "%s=%s" % (key, yaml_flow(value))]
                    label = entry.get("label") or "/".join(
                        p for p in (declaration.plugin, strategy if len(strategies) > 1 else None,
                                    solver if len(solvers) > 1 else None) if p)
                    runs.append(Run(bench.name, declaration.plugin, strategy, solver, {**bvals, **pvals}, args,
                                    label, scene, entry))
    return runs


def reference_run(bench):
    """The reference configuration of a benchmark with `reference: {converged: ...}`, or None (analytical)."""
    ref = bench.reference
    if not isinstance(ref, dict):
        return None
    _check_keys(bench.path, "reference", ref, {"plugin", "strategy", "parameters", "set", "label", "notes"})
    overrides = dict(substitute(bench.set, bench.variables, bench.path + ": set"))
    args = []
    if "plugin" in ref:
        args += ["--plugin", ref["plugin"]]
        for n in _pair_indices(bench, bench.scene):
            if "parameters" in ref:
                overrides["contact.%d.parameters" % n] = substitute(ref["parameters"], bench.variables,
                                                                  bench.path + ": reference.parameters")
            if "strategy" in ref:
                overrides["contact.%d.strategy" % n] = ref["strategy"]
    overrides.update(substitute(ref.get("set") or {}, bench.variables, bench.path + ": reference.set"))
    for key, value in overrides.items():
        args += [override_option(value), "%s=%s" % (key, yaml_flow(value))]
    return Run(bench.name, None, ref.get("strategy"), None, {}, args, "reference", bench.scene)
