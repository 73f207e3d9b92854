"""What every CLI test script shares: where the binary and the scenes are, a test case (a temporary folder, the
runs, the checks and their verdict), readers for a results folder, and the command-line entry `main(CASES)`."""
import csv
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BIN = os.environ.get("STICKSLIP_BIN", os.path.join(ROOT, "build", "bin", "stickslip"))
PLUGIN_DIR = os.environ.get("STICKSLIP_CLI_PLUGIN_DIR", os.path.join(ROOT, "build", "tests", "cli-plugins"))
MESHES = os.path.join(ROOT, "meshes")

# Crash / internal-error markers that must never reach the user.
CRASH_MARKERS = ["Traceback", "Segmentation", "Aborted", "core dumped", "terminate called", "AddressSanitizer",
                 "internal error", "MPI_ABORT", "*** Process received signal"]


def scene_text(name):
    """A scene of scenes/ with its mesh paths made absolute (the copy lives in a temporary folder)."""
    with open(os.path.join(ROOT, "scenes", name)) as f:
        return f.read().replace("../meshes", MESHES)


BLOCK = scene_text("compressed-block.yaml")

CONTACT = """\
description: a block pressed onto a rigid floor (penalty contact)
mesh:
  file: %s/block.geo
  parameters: {nx: 2, ny: 2, nz: 2}
bodies:
  - {name: block, group: body, material: {model: hooke, E: 1000, nu: 0.3}}
boundary:
  - {name: top, group: zmax, displacement: [0, 0, -0.01]}
contact:
  - name: floor
    plugin: penalty-nts
    slave: zmin
    obstacle: {type: plane, point: [0, 0, 0], normal: [0, 0, 1]}
    parameters: {penalty: 1.0e4}
time: {scheme: quasi-static, dt: 0.5, end: 1}
""" % MESHES


def replace(text, old, new):
    assert old in text, "test setup: %r not in the scene" % old
    return text.replace(old, new, 1)


class Case:
    def __init__(self, name):
        self.name = name
        self.dir = tempfile.mkdtemp(prefix="stickslip-cli-")
        self.out = os.path.join(self.dir, "results")
        self.failures = []

    def write(self, text, name="scene.yaml"):
        path = os.path.join(self.dir, name)
        with open(path, "w") as f:
            f.write(text)
        return path

    def run(self, *args, env=None, timeout=60):
        full_env = dict(os.environ)
        full_env.pop("STICKSLIP_PLUGIN_PATH", None)
        full_env.update(env or {})
        proc = subprocess.run([BIN, *args], capture_output=True, text=True, env=full_env, timeout=timeout,
                              cwd=self.dir)
        self.proc = proc
        print("$ stickslip %s\nexit %d\nstdout: %s\nstderr: %s" % (" ".join(args), proc.returncode,
                                                                    proc.stdout.strip(), proc.stderr.strip()))
        return proc

    def check(self, condition, message):
        print(("ok: " if condition else "FAILED: ") + message)
        if not condition:
            self.failures.append(message)

    def no_crash(self):
        p = self.proc
        self.check(p.returncode >= 0, "not killed by a signal (exit %d)" % p.returncode)
        for marker in CRASH_MARKERS:
            self.check(marker not in p.stderr and marker not in p.stdout, "no '%s' in the output" % marker)

    def expect_failure(self, *patterns, out_created=False):
        """exit 1, one error line on stderr matching every regex in `patterns`, no crash, no results folder."""
        p = self.proc
        self.no_crash()
        self.check(p.returncode == 1, "exit code 1 (got %d)" % p.returncode)
        lines = [line for line in p.stderr.splitlines() if line.strip() and not line.startswith("warning:")]
        self.check(len(lines) == 1 if not out_created else len(lines) >= 1,
                   "one error message on stderr (got %d lines)" % len(lines))
        for pattern in patterns:
            self.check(re.search(pattern, p.stderr) is not None, "stderr matches /%s/" % pattern)
        if not out_created:
            self.check(not os.path.exists(self.out), "the --out folder was not created")

    def run_scene(self, text, *args, command="run", env=None):
        path = self.write(text)
        extra = ["--out", self.out, "--quiet"] if command == "run" else []
        return self.run(command, path, *extra, *args, env=env)

    def finish(self):
        shutil.rmtree(self.dir, ignore_errors=True)
        print("%s: %d failed" % (self.name, len(self.failures)))
        return 1 if self.failures else 0


def signal_run(c, args, out, rows, sig):
    """Starts `stickslip run ARGS --out OUT` in the case's folder, sends `sig` once its staging folder's history.csv
    has `rows` lines (or the run ended); returns (process, stderr)."""
    env = dict(os.environ)
    env.pop("STICKSLIP_PLUGIN_PATH", None)
    proc = subprocess.Popen([BIN, "run", *args, "--out", out], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, env=env, cwd=c.dir)
    history = os.path.join(out + ".partial-%d" % proc.pid, "history.csv")
    deadline = time.time() + 60
    while time.time() < deadline and proc.poll() is None:
        if os.path.exists(history) and open(history).read().count("\n") >= rows:
            break
        time.sleep(0.02)
    c.check(proc.poll() is None, "the run was still running when signalled")
    proc.send_signal(sig)
    _, stderr = proc.communicate(timeout=60)
    print("exit %d\nstderr: %s" % (proc.returncode, stderr))
    return proc, stderr


def read_summary(folder):
    """summary.json of a results folder."""
    with open(os.path.join(folder, "summary.json")) as f:
        return json.load(f)


def read_table(path):
    """A CSV written by stickslip (history.csv, contact.csv): one dict of floats per row."""
    with open(path) as f:
        return [{k: float(v) for k, v in row.items()} for row in csv.DictReader(f)]


def read_history(folder):
    return read_table(os.path.join(folder, "history.csv"))


def main(cases):
    """Runs the case named on the command line: python3 SCRIPT CASE."""
    script = os.path.basename(sys.argv[0])
    if len(sys.argv) != 2 or sys.argv[1] not in cases:
        print("usage: %s CASE\ncases: %s" % (script, " ".join(cases)))
        sys.exit(2)
    case = Case(sys.argv[1])
    cases[sys.argv[1]](case)
    sys.exit(case.finish())
