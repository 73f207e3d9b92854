"""Newton iterations per load step of a run, counted two ways: ours (the scene's criterion: the residual test and the
update test, history.csv's newton_iterations) and the paper's way. Konyukhov & Schweizerhof computed with FEAP,
whose Newton loop stops after the iteration whose energy norm |du_k . R_(k-1)| falls below tol times that of the
first iteration of the step; the paper does not state tol. `stickslip run --verbose` prints both norms per iteration
(`step N newton k |F| = .. |dx.F| = ..`), so one run gives the count under any energy tolerance up to our own stopping
point; where our Newton stopped first, the next iteration's energy is estimated as |J^-1| |F_k|^2 with |J^-1| from
the last iteration (|dx_k . F_(k-1)| / |F_(k-1)|^2), which tells whether FEAP would take exactly one iteration more
(it is then orders of magnitude below the threshold: our last iterate sits at the residual's round-off).

  python3 tests/bench/covariant-penalty/iterations.py SCENE [--set ...]   # per-step counts, ours and FEAP's at
                                                                          # energy tolerances 1e-16 ... 1e-10
"""
import os
import re
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(HERE)))
BIN = os.environ.get("STICKSLIP_BIN", os.path.join(ROOT, "build", "bin", "stickslip"))

LINE = re.compile(r"step (\d+) newton (\d+) \|F\| = ([0-9.eE+-]+) \|dx\.F\| = ([0-9.eE+-]+)")


def histories(stderr):
    """{step: [(|F_k|, |dx_k . F_(k-1)|), k = 1, 2, ...]} of the last Newton run of each step (a step cut or an outer
    active-set loop starts a new run at k = 1)."""
    steps = {}
    for m in LINE.finditer(stderr):
        step, k = int(m.group(1)), int(m.group(2))
        if k <= 1 or step not in steps:
            steps[step] = []
        steps[step].append((float(m.group(3)), float(m.group(4))))
    return steps


def energy_count(history, tol):
    """The iteration at which FEAP's energy test |dx_k . F_(k-1)| <= tol |dx_1 . F_0| first holds: k within the
    history; len + 1 when the estimate of the next iteration's energy meets it; None when it cannot be told."""
    first = history[0][1]
    for k, (_, energy) in enumerate(history, 1):
        if energy <= tol * first:
            return k
    if len(history) >= 2:
        f_prev, f_last = history[-2][0], history[-1][0]
        # |dx_k| ~ |dx_k . F_(k-1)| / |F_(k-1)| (a Newton step is nearly along F), |J^-1| ~ |dx_k| / |F_(k-1)|
        inverse = history[-1][1] / (f_prev * f_prev)
        if inverse * f_last * f_last <= tol * first:
            return len(history) + 1
    return None


def run(scene, *args):
    """Runs a scene with --verbose; returns (return code, {step: history}, stderr)."""
    proc = subprocess.run([BIN, "run", os.path.join(ROOT, scene), "--quiet", "--verbose", *args], capture_output=True,
                          text=True)
    return proc.returncode, histories(proc.stderr), proc.stderr


def main(argv):
    if not argv:
        sys.exit(__doc__)
    code, steps, stderr = run(argv[0], *argv[1:])
    if code != 0:
        print(stderr.strip().splitlines()[-1])
    order = sorted(steps)
    ours = [len(steps[s]) for s in order]
    print("%-10s %5d  %s" % ("ours", sum(ours), " ".join("%d" % n for n in ours)))
    for tol in (1e-16, 1e-14, 1e-12, 1e-10):
        counts = [energy_count(steps[s], tol) for s in order]
        known = [n for n in counts if n is not None]
        print("%-10s %5s  %s" % ("FEAP %.0e" % tol, sum(known) if len(known) == len(counts) else "-",
                                 " ".join("%s" % (n if n is not None else "?") for n in counts)))


if __name__ == "__main__":
    main(sys.argv[1:])
