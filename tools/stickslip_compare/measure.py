"""Runs one `stickslip` command as a child process and measures what it cost: CPU time and peak RSS (os.wait4: the
child and the gmsh/MPI processes it waited for), wall time, the counters of its summary.json. Shared by
`stickslip compare` and the project's benchmark harness (tests/bench/harness/runner.py)."""
import os
import signal
import subprocess
import time

from .results import Results

# summary.json's counters that a comparison or benchmark record keeps
SUMMARY_KEYS = ("status", "message", "steps", "final_time", "newton_iterations", "linear_solves", "step_cuts",
                "active_set_loops", "dofs", "unknowns", "linear_system_size", "wall_seconds", "assembly_seconds",
                "contact_seconds", "solve_seconds", "linear_solver", "plugin", "strategy")


def run_measured(cmd, stderr_path, timeout):
    """Runs cmd (stdout discarded, stderr to stderr_path) in its own process group; returns {"exit", "timed_out",
    "cpu_seconds", "max_rss_mb", "wall_seconds_outside", "load_average"}. Past `timeout` seconds the group gets
    SIGTERM."""
    load = os.getloadavg()[0]
    start = time.monotonic()
    with open(stderr_path, "w") as err:
        proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=err, start_new_session=True)
        status, usage, timed_out = wait_with_usage(proc, timeout)
    return {"exit": status, "timed_out": timed_out, "cpu_seconds": usage.ru_utime + usage.ru_stime,
            "max_rss_mb": usage.ru_maxrss / 1024.0, "wall_seconds_outside": time.monotonic() - start,
            "load_average": [load, os.getloadavg()[0]]}


def wait_with_usage(proc, timeout):
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


def read_results(folder):
    """The run's results, or None; a failed run's are in FOLDER.incomplete once the driver keeps unfinished runs
    apart."""
    if not os.path.exists(os.path.join(folder, "summary.json")) and os.path.isdir(folder + ".incomplete"):
        folder += ".incomplete"
    if os.path.exists(os.path.join(folder, "history.csv")) and os.path.exists(os.path.join(folder, "summary.json")):
        return Results(folder)
    return None


def summary_fields(results):
    """summary.json's counters (SUMMARY_KEYS) of a finished run."""
    return {k: results.summary.get(k) for k in SUMMARY_KEYS if k in results.summary}


def add_outcome(record, results_dir, stderr_path):
    """Adds what a finished child left to its record: summary.json's counters, or (no results) status timeout or
    no-results with the end of its stderr as the message. Returns the Results or None."""
    results = read_results(results_dir)
    if results is not None:
        record.update(summary_fields(results))
    else:
        record["status"] = "timeout" if record["timed_out"] else "no-results"
        with open(stderr_path) as f:
            record["message"] = f.read()[-500:].strip()
    return results
