"""Runs one configuration through the `stickslip` command line and records what it cost: CPU time and peak RSS of
the child (os.wait4), wall time, and the counters of summary.json. A finished record is reused by the next call
unless `fresh` (the results folder and record.json live in results/bench/<bench>/<run tag>/)."""
import json
import os
import shlex
import shutil
import subprocess
import sys

from declarations import BIN, ROOT

sys.path.insert(0, os.path.join(ROOT, "tools"))
from stickslip_compare.measure import add_outcome, read_results, run_measured, summary_fields  # noqa: E402

OUT = os.environ.get("STICKSLIP_BENCH_OUT", os.path.join(ROOT, "results", "bench"))


SOURCES = ("core", "plugins", "driver", "scenes", "meshes")


def source_commit():
    """The commit the measured code is at: the last commit that changed the sources (not docs or tests, so that a
    table does not change its commit with its own docs), `+dirty` when the work tree's sources differ from HEAD."""
    def git(*a):
        return subprocess.run(["git", "-C", ROOT, *a], capture_output=True, text=True)
    last = git("log", "-1", "--format=%h", "HEAD", "--", *SOURCES)
    if last.returncode != 0 or not last.stdout.strip():
        return "unknown"
    dirty = git("diff", "--quiet", "HEAD", "--", *SOURCES).returncode != 0
    return last.stdout.strip() + ("+dirty" if dirty else "")


COMMIT = None


def command(run, folder, binary=BIN):
    return [binary, "run", os.path.join(ROOT, run.scene), "--out", folder, "--quiet", *run.args]


def execute(run, group, timeout, fresh=False, binary=BIN, log=print):
    """Runs `run` into OUT/group/run.tag; returns (record dict, Results or None)."""
    folder = os.path.join(OUT, group, run.tag)
    results_dir = os.path.join(folder, "results")
    record_path = os.path.join(folder, "record.json")
    cmd = command(run, results_dir, binary)
    if not fresh and os.path.exists(record_path):
        with open(record_path) as f:
            record = json.load(f)
        if record.get("command") == cmd[1:]:
            results = read_results(results_dir)
            record.update({"folder": folder, "label": run.label, "values": run.values, "strategy": run.strategy,
                           "solver": run.solver, "plugin": run.plugin})
            if results is not None:  # the evaluators run again: their verdict is not cached
                record.pop("message", None)
                record.update(summary_fields(results))
            return record, results
    shutil.rmtree(folder, ignore_errors=True)
    os.makedirs(folder)
    log("+ " + " ".join(shlex.quote(c) for c in cmd))
    cost = run_measured(cmd, os.path.join(folder, "stderr.txt"), timeout)
    global COMMIT
    if COMMIT is None:
        COMMIT = source_commit()
    record = {
        "bench": run.bench, "plugin": run.plugin, "strategy": run.strategy, "solver": run.solver,
        "label": run.label, "values": run.values, "tag": run.tag, "command": cmd[1:], **cost,
        "folder": folder, "commit": COMMIT,
    }
    results = add_outcome(record, results_dir, os.path.join(folder, "stderr.txt"))
    save(record)
    return record, results


def save(record):
    """Writes the record (with whatever an evaluator added) beside the run's results."""
    with open(os.path.join(record["folder"], "record.json"), "w") as f:
        json.dump(record, f, indent=1)
