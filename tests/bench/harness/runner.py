"""Runs one configuration through the `stickslip` command line and records what it cost: CPU time and peak RSS of
the child (os.wait4), wall time, and the counters of summary.json. A finished record is reused by the next call
unless `fresh` (the results folder and record.json live in results/bench/<bench>/<run tag>/)."""
import json
import os
import shlex
import shutil
import signal
import subprocess
import sys
import time

from declarations import BIN, ROOT

sys.path.insert(0, os.path.join(ROOT, "tests", "validation"))
from stickslip_results import Results  # noqa: E402

OUT = os.environ.get("STICKSLIP_BENCH_OUT", os.path.join(ROOT, "results", "bench"))
SUMMARY_KEYS = ("status", "message", "steps", "final_time", "newton_iterations", "linear_solves", "step_cuts",
                "active_set_loops", "dofs", "unknowns", "linear_system_size", "wall_seconds", "assembly_seconds",
                "contact_seconds", "solve_seconds", "linear_solver", "plugin", "strategy")


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
            results = _results(results_dir)
            record.update({"folder": folder, "label": run.label, "values": run.values, "strategy": run.strategy,
                           "solver": run.solver, "plugin": run.plugin})
            if results is not None:  # the evaluators run again: their verdict is not cached
                record.pop("message", None)
                record.update({k: results.summary.get(k) for k in SUMMARY_KEYS if k in results.summary})
            return record, results
    shutil.rmtree(folder, ignore_errors=True)
    os.makedirs(folder)
    log("+ " + " ".join(shlex.quote(c) for c in cmd))
    load = os.getloadavg()[0]
    start = time.monotonic()
    with open(os.path.join(folder, "stderr.txt"), "w") as err:
        proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=err, start_new_session=True)
        status, usage, timed_out = _wait(proc, timeout)
    wall = time.monotonic() - start
    global COMMIT
    if COMMIT is None:
        COMMIT = source_commit()
    record = {
        "bench": run.bench, "plugin": run.plugin, "strategy": run.strategy, "solver": run.solver,
        "label": run.label, "values": run.values, "tag": run.tag, "command": cmd[1:],
        "exit": status, "timed_out": timed_out, "cpu_seconds": usage.ru_utime + usage.ru_stime,
        "max_rss_mb": usage.ru_maxrss / 1024.0, "wall_seconds_outside": wall,
        "load_average": [load, os.getloadavg()[0]], "folder": folder, "commit": COMMIT,
    }
    results = _results(results_dir)
    if results is not None:
        record.update({k: results.summary.get(k) for k in SUMMARY_KEYS if k in results.summary})
    else:
        record["status"] = "timeout" if timed_out else "no-results"
        with open(os.path.join(folder, "stderr.txt")) as f:
            record["message"] = f.read()[-500:].strip()
    save(record)
    return record, results


def save(record):
    """Writes the record (with whatever an evaluator added) beside the run's results."""
    with open(os.path.join(record["folder"], "record.json"), "w") as f:
        json.dump(record, f, indent=1)


def _wait(proc, timeout):
    """Waits for the child with os.wait4 (its rusage: CPU and peak RSS, gmsh and MPI children included)."""
    deadline = time.monotonic() + timeout
    while True:
        pid, status, usage = os.wait4(proc.pid, os.WNOHANG)
        if pid == proc.pid:
            proc.returncode = os.waitstatus_to_exitcode(status)
            return proc.returncode, usage, False
        if time.monotonic() > deadline:
            os.killpg(proc.pid, signal.SIGTERM)
            pid, status, usage = os.wait4(proc.pid, 0)
            proc.returncode = os.waitstatus_to_exitcode(status)
            return proc.returncode, usage, True
        time.sleep(0.05)


def _results(folder):
    """The run's results; a failed run's are in FOLDER.incomplete once the driver keeps unfinished runs apart."""
    if not os.path.exists(os.path.join(folder, "summary.json")) and os.path.isdir(folder + ".incomplete"):
        folder += ".incomplete"
    if os.path.exists(os.path.join(folder, "history.csv")) and os.path.exists(os.path.join(folder, "summary.json")):
        return Results(folder)
    return None
