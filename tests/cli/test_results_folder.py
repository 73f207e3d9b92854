"""The results folder under hostile conditions (issue 15, items 5, 6, 7, 10; docs/user-guide.md, "The results
folder"): a full disk, a failed run after a good one, foreign files in --out, `--out .`, a run killed with SIGKILL.
Each case checks the exit code, the message (where the results are, exactly) and what is on disk afterwards.
Usage: python3 test_results_folder.py CASE."""
import glob
import os
import re
import shutil
import signal
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cli_case import BIN, BLOCK, CONTACT, ROOT, main, read_summary, replace, signal_run  # noqa: E402

DISK = os.path.join(ROOT, "scenes", "free-flight-disk.yaml")


def failing(text):
    """The compressed block with a load that inverts an element at step 1: a run that fails with 0 steps."""
    text = replace(text, "model: hooke", "model: neo-hooke")
    return replace(text, "[0, 0, -10]", "[0, 0, -1.0e5]")


def good_run(c, out):
    c.run("run", c.write(BLOCK, "good.yaml"), "--out", out, "--quiet")
    c.check(c.proc.returncode == 0, "the good run succeeds")
    return open(os.path.join(out, "history.csv")).read()


def failed_run_keeps_results(c):
    """Item 5: a run that fails (0 steps) next to finished results goes to DIR.incomplete; DIR is kept."""
    before = good_run(c, c.out)
    c.run("run", c.write(failing(BLOCK)), "--out", c.out, "--quiet", "--set", "time.max_cuts=2", "--set",
          "solver.newton.line_search=full-step")  # named: backtracking converges this load
    c.expect_failure(r"no convergence", r"results up to t = 0 \(step 0\) are in .*results\.incomplete",
                     r"the results already in .*results were kept", out_created=True)
    c.check(open(os.path.join(c.out, "history.csv")).read() == before, "the good results are untouched")
    c.check(read_summary(c.out)["status"] == "ok", "summary.json of DIR still says ok")
    c.check(read_summary(c.out + ".incomplete")["status"] == "failed", "DIR.incomplete holds the failed run")
    c.check(not glob.glob(c.out + ".partial-*"), "no staging folder left")
    # the next good run replaces DIR, DIR.incomplete stays for the user
    good_run(c, c.out)
    c.check(os.path.isdir(c.out + ".incomplete"), "DIR.incomplete is left to the user")


def foreign_files(c):
    """Item 6: a folder is not stickslip's because its summary.json says "stickslip"; nothing of it is deleted."""
    os.makedirs(c.out)
    with open(os.path.join(c.out, "summary.json"), "w") as f:
        f.write("stickslip\n")
    with open(os.path.join(c.out, "thesis.tex"), "w") as f:
        f.write("precious\n")
    c.run_scene(BLOCK)
    c.expect_failure(r"refusing to replace '.*results': it holds 'summary.json', 'thesis.tex', which stickslip did not "
                     r"write \(it is not a stickslip results folder\)", r"no results were written; .*results is "
                     r"unchanged", out_created=True)
    c.check(open(os.path.join(c.out, "thesis.tex")).read() == "precious\n", "thesis.tex is still there")
    c.check(not glob.glob(c.out + ".partial-*"), "no staging folder left")
    # a file added to a real results folder is not deleted either
    shutil.rmtree(c.out)
    good_run(c, c.out)
    with open(os.path.join(c.out, "notes.txt"), "w") as f:
        f.write("mine\n")
    c.run_scene(BLOCK)
    c.expect_failure(r"it holds 'notes.txt', which stickslip did not write", out_created=True)
    c.check(os.path.exists(os.path.join(c.out, "notes.txt")), "notes.txt is still there")


def out_dot(c):
    """Item 10: `--out .` replaced the current folder (and staged into `..partial-PID`); now a clear refusal."""
    here = os.path.join(c.dir, "here")
    os.makedirs(here)
    scene = c.write(BLOCK)
    proc = subprocess.run([BIN, "run", scene, "--out", ".", "--quiet"], capture_output=True, text=True, cwd=here,
                          timeout=60)
    c.proc = proc
    print("$ (in here/) stickslip run scene.yaml --out .\nexit %d\nstderr: %s" % (proc.returncode, proc.stderr))
    c.expect_failure(r"--out '\.' is the current directory or contains it", r"e\.g\. --out results", out_created=True)
    c.check(os.listdir(here) == [], "the current folder is untouched")
    c.check(not [n for n in os.listdir(c.dir) if "partial" in n], "no staging folder anywhere")


def full_disk(c):
    """Item 5 and 10 on a full disk: a tmpfs of 512 kB holds one result; filled up, the next run fails to write,
    says so, says no results were written and that DIR is unchanged, leaves DIR as it was and no staging folder.
    Needs a tmpfs mount: as root, or in a user namespace (unshare -rm); skipped with the reason otherwise."""
    mount = os.path.join(c.dir, "disk")
    os.makedirs(mount)
    scene = c.write(BLOCK)
    script = """
set -e
mount -t tmpfs -o size=512k tmpfs "$DISK"
"$BIN" run "$SCENE" --out "$DISK/out" --quiet
cp -r "$DISK/out" "$DISK/../before"
# leave about 12 kB free: the next run cannot write its files
dd if=/dev/zero of="$DISK/filler" bs=4k count=$(( $(stat -f -c %a "$DISK") - 3 )) 2>/dev/null || true
set +e
"$BIN" run "$SCENE" --out "$DISK/out" --quiet --set time.dt=0.125
echo "second-exit=$?"
ls -a "$DISK" > "$DISK/../listing"
diff -r "$DISK/out" "$DISK/../before" > "$DISK/../diff" 2>&1; echo "diff-exit=$?" >> "$DISK/../diff"
umount "$DISK"
"""
    env = dict(os.environ, DISK=mount, BIN=BIN, SCENE=scene)
    env.pop("STICKSLIP_PLUGIN_PATH", None)
    attempts = [["unshare", "-m", "sh", "-c", script]] if os.geteuid() == 0 else []
    attempts.append(["unshare", "-rm", "sh", "-c", script])
    proc = None
    for command in attempts:
        try:
            proc = subprocess.run(command, capture_output=True, text=True, env=env, timeout=120)
        except FileNotFoundError:
            continue
        if "second-exit=" in proc.stdout:
            break
    if proc is None or "second-exit=" not in proc.stdout:
        print("SKIPPED: cannot mount a tmpfs here (needs root or unprivileged user namespaces): %s"
              % (proc.stderr.strip() if proc else "unshare not found"))
        return
    print(proc.stdout, proc.stderr)
    c.check("second-exit=1" in proc.stdout, "the run on the full disk exits 1")
    c.check("No space left on device" in proc.stderr, "the message names the write error")
    c.check("no results were written;" in proc.stderr and "out is unchanged" in proc.stderr,
            "the message says nothing was written and DIR is unchanged")
    c.check("are in" not in proc.stderr, "no claim that results are somewhere")
    listing = open(os.path.join(c.dir, "listing")).read().split()
    c.check(not [n for n in listing if "partial" in n or "incomplete" in n], "no staging or incomplete folder: %s"
            % listing)
    c.check("diff-exit=0" in open(os.path.join(c.dir, "diff")).read(), "DIR holds exactly the first run's files")
    for marker in ["Segmentation", "Aborted", "terminate called", "AddressSanitizer"]:
        c.check(marker not in proc.stderr, "no '%s'" % marker)


def killed_run(c):
    """Item 7 (SIGKILL): a run killed mid-way leaves DIR as it was and its staging folder with the rows written
    so far; the next run into DIR names that folder (it is not deleted)."""
    good_run(c, c.out)
    before = open(os.path.join(c.out, "history.csv")).read()
    proc, _ = signal_run(c, [DISK, "--quiet"], c.out, 5, signal.SIGKILL)
    staging = c.out + ".partial-%d" % proc.pid
    history = os.path.join(staging, "history.csv")
    c.check(proc.returncode == -signal.SIGKILL, "killed by SIGKILL")
    c.check(open(os.path.join(c.out, "history.csv")).read() == before, "DIR is untouched by the killed run")
    rows = open(history).read().count("\n") if os.path.exists(history) else 0
    c.check(rows >= 5, "the staging folder keeps the rows written before the kill (%d lines)" % rows)
    c.run_scene(BLOCK)
    c.check(c.proc.returncode == 0, "the next run succeeds")
    c.check(("note: %s holds the unfinished results of process %d" % (staging, proc.pid)) in c.proc.stderr,
            "the next run names the killed run's staging folder")
    c.check(os.path.exists(history), "and leaves it in place")


def interrupted_run(c):
    """Item 7 (SIGINT, SIGTERM): the stepper stops between two steps; the results up to the last converged step are
    written complete (summary.json "interrupted", its step count = the history rows), the exit code is 128 + the
    signal, the message says where the results are, and no staging folder is left."""
    for sig, code, name in [(signal.SIGINT, 130, r"SIGINT \(Ctrl-C\)"), (signal.SIGTERM, 143, "SIGTERM")]:
        out = os.path.join(c.dir, "out-%d" % code)
        proc, stderr = signal_run(c, [DISK, "--quiet"], out, 4, sig)
        c.check(proc.returncode == code, "exit %d after %s (got %d)" % (code, sig.name, proc.returncode))
        match = re.search(r"interrupted by %s after step (\d+) \(t = ([^)]+)\)" % name, stderr)
        c.check(match is not None, "the message names the signal, the step and the time")
        c.check(re.search(r"results up to t = .* \(step \d+\) are in .*out-%d \(status \"interrupted\"\)" % code,
                          stderr) is not None, "the message says where the results are")
        for marker in ["Segmentation", "Aborted", "AddressSanitizer", "MPI_ABORT"]:
            c.check(marker not in stderr, "no '%s'" % marker)
        summary = read_summary(out)
        rows = open(os.path.join(out, "history.csv")).read().strip().split("\n")[1:]
        c.check(summary["status"] == "interrupted", "summary.json says interrupted")
        c.check(match is not None and summary["steps"] == int(match.group(1)) == len(rows) - 1,
                "summary.json, the message and history.csv agree on the last step (%d rows)" % len(rows))
        c.check(summary["steps"] >= 3, "it stopped after the steps it had done, not at once")
        c.check(os.path.exists(os.path.join(out, "results.pvd")), "results.pvd is there")
        last_picture = "step-%06d.pvtu" % summary["steps"]
        c.check(os.path.exists(os.path.join(out, last_picture)) and
                last_picture in open(os.path.join(out, "results.pvd")).read(),
                "the last converged step has a picture, listed in results.pvd (%s; vtu_every 20)" % last_picture)
        c.check(not glob.glob(out + ".partial-*"), "no staging folder left")


def results_line_names_files(c):
    """The run's last line names the files it wrote into --out: with a contact pair on a rigid plane contact.csv, and
    with VTU output contact.pvd and obstacles.pvd; without VTU output no .pvd (it said "(history.csv, summary.json,
    results.pvd)" whatever was written)."""
    scene = c.write(CONTACT)
    for vtu, expected in (("true", ["history.csv", "contact.csv", "summary.json", "scene.yaml", "results.pvd",
                                    "contact.pvd", "obstacles.pvd"]),
                          ("false", ["history.csv", "contact.csv", "summary.json", "scene.yaml"])):
        out = os.path.join(c.dir, "out-" + vtu)
        c.run("run", scene, "--out", out, "--quiet", "--set", "output.vtu=" + vtu)
        line = re.search(r"^results: .*$", c.proc.stdout, re.M)
        named = re.findall(r"[\w-]+\.(?:csv|json|yaml|pvd)", line.group(0).partition("(")[2]) if line else []
        c.check(c.proc.returncode == 0 and named == expected, "output.vtu %s: the results line names %s (got %r)" % (
            vtu, expected, line.group(0) if line else None))
        c.check(all(os.path.exists(os.path.join(out, name)) for name in named), "each file named is there")


CASES = {f.__name__: f for f in [failed_run_keeps_results, foreign_files, out_dot, full_disk, killed_run,
                                 interrupted_run, results_line_names_files]}

if __name__ == "__main__":
    main(CASES)
