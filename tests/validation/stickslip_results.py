"""Reading stickslip result folders in tests: history.csv, summary.json, contact.csv and .vtu point data."""
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tools"))
from stickslip_compare.results import Results, read_vtu  # noqa: E402,F401  (the one reader, shared with the compare tool)


def run(scene, *args, np=1, expect_ok=True, out=None, env=None):
    """Runs `stickslip run scene --out DIR args...` (under mpirun for np > 1), with `env` added to the environment;
    returns (Results or None, stderr)."""
    binary = os.environ.get("STICKSLIP_BIN", os.path.join(ROOT, "build", "bin", "stickslip"))
    out = out or tempfile.mkdtemp(prefix="stickslip-test-")
    target = os.path.join(out, "results")
    command = [binary, "run", os.path.join(ROOT, scene), "--out", target, "--quiet", *args]
    if np > 1:
        mpiexec = os.environ.get("STICKSLIP_MPIEXEC", "mpirun")
        command = [mpiexec, "--allow-run-as-root", "--oversubscribe", "-np", str(np), *command]
    proc = subprocess.run(command, capture_output=True, text=True, env=dict(os.environ, **(env or {})))
    if expect_ok and proc.returncode != 0:
        raise AssertionError("run failed (%d): %s\n%s" % (proc.returncode, " ".join(command), proc.stderr))
    results = Results(target) if os.path.exists(os.path.join(target, "history.csv")) else None
    return results, proc


def relative_drift(values, scale=None):
    """max |v - v0| / scale (scale defaults to max(|v0|, 1e-300))."""
    v0 = values[0]
    scale = scale if scale is not None else max(abs(v0), 1e-300)
    return max(abs(v - v0) for v in values) / scale


class Checks:
    """Collects failures so one run reports every broken check; exit code 1 if any failed."""

    def __init__(self, name):
        self.name = name
        self.failures = []
        self.count = 0

    def check(self, condition, message):
        self.count += 1
        if not condition:
            self.failures.append(message)
            print("FAILED: " + message)
        else:
            print("ok: " + message)

    def finish(self):
        print("%s: %d checks, %d failed" % (self.name, self.count, len(self.failures)))
        return 1 if self.failures else 0


def main(cases):
    """Runs the case named on the command line: python3 SCRIPT CASE; exit code 0 when every check held."""
    import sys
    names = {f.__name__: f for f in cases}
    if len(sys.argv) != 2 or sys.argv[1] not in names:
        print("usage: %s CASE\ncases: %s" % (os.path.basename(sys.argv[0]), " ".join(names)))
        sys.exit(2)
    checks = Checks(sys.argv[1])
    names[sys.argv[1]](checks)
    sys.exit(checks.finish())
