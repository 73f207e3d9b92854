"""What the command line says, said consistently (issue 35, item 9): a failed or interrupted run does not say "done";
a bad plugin parameter and a bad `--set` value are reported where they were given, naming the pair once; every
option is in the usage line; --quiet keeps warnings and drops information; the plot scripts answer --help.
Usage: python3 test_consistency.py CASE."""
import os
import re
import signal
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cli_case import BLOCK, CONTACT, ROOT, main, read_summary, replace, signal_run  # noqa: E402

DISK = os.path.join(ROOT, "scenes", "free-flight-disk.yaml")


def stopped_runs_say_so(c):
    """The progress line's last words: "failed after N steps" for a failed run, "interrupted after N steps" for a
    run stopped by Ctrl-C, "done, N steps" only for one that finished."""
    failing = replace(replace(BLOCK, "model: hooke", "model: neo-hooke"), "[0, 0, -10]", "[0, 0, -1.0e5]")
    # the full Newton step (named: backtracking converges this load) inverts elements
    c.run("run", c.write(failing), "--set", "time.max_cuts=2", "--set", "solver.newton.line_search=full-step")
    c.check(c.proc.returncode == 1, "the run fails")
    c.check(re.search(r"scene\.yaml: failed after 0 steps, ", c.proc.stderr) is not None, "it says it failed")
    c.check("done" not in c.proc.stderr, "it does not say done")
    c.run("run", c.write(BLOCK))
    c.check(c.proc.returncode == 0 and re.search(r"scene\.yaml: done, 4 steps in ", c.proc.stderr) is not None,
            "a finished run says done, 4 steps")
    out = os.path.join(c.dir, "disk")
    proc, stderr = signal_run(c, [DISK], out, 4, signal.SIGINT)
    match = re.search(r"free-flight-disk\.yaml: interrupted after (\d+) steps, ", stderr)
    c.check(proc.returncode == 130 and match is not None, "it says it was interrupted")
    c.check("done" not in stderr, "it does not say done")
    summary = os.path.join(out, "summary.json")
    c.check(match is not None and os.path.exists(summary) and
            '"steps": %s,' % match.group(1) in open(summary).read(), "after as many steps as summary.json says")


def plugin_parameter_errors(c):
    """A bad plugin parameter is reported at its file:line:column (or its --set), naming the pair once."""
    c.run_scene(replace(CONTACT, "{penalty: 1.0e4}", "{penalty: -1.0e4}"), command="check")
    c.expect_failure(r"^stickslip: \S*scene\.yaml:14:27: contact pair 'floor' \(plugin penalty-nts\): "
                     r"parameter 'penalty' must be a finite number > 0")
    c.check(c.proc.stderr.count("floor") == 1, "the pair is named once")
    c.run_scene(CONTACT, "--set", "contact.0.parameters.penalty=0", command="check")
    c.expect_failure(r"^stickslip: --set contact\.0\.parameters\.penalty: contact pair 'floor' "
                     r"\(plugin penalty-nts\): ")
    c.run_scene(replace(CONTACT, "{penalty: 1.0e4}", "{penalty: stiff}"), command="check")
    c.expect_failure(r"^stickslip: \S*scene\.yaml:14:27: contact pair 'floor' \(plugin penalty-nts\): key "
                     r"'contact\[0\]\.parameters\.penalty' expects a number, got 'stiff'")


def set_value_positions(c):
    """A bad material value is reported where it was given: `--set bodies.0.material.E`, or its line and column."""
    c.run_scene(BLOCK, "--set", "bodies.0.material.E=-5", command="check")
    c.expect_failure(r"^stickslip: --set bodies\.0\.material\.E: body 'block': material: Young's modulus E = -5")
    c.run_scene(BLOCK, "--set", "bodies.0.material={nu: 0.7}", command="check")
    c.expect_failure(r"^stickslip: --set bodies\.0\.material: body 'block': material: Poisson's ratio nu = 0\.7")
    c.run_scene(replace(BLOCK, "nu: 0.3", "nu: 0.6"), command="check")
    c.expect_failure(r"^stickslip: \S*scene\.yaml:14:\d+: body 'block': material: Poisson's ratio nu = 0\.6")
    position = re.search(r"scene\.yaml:14:(\d+):", c.proc.stderr)
    column = int(position.group(1)) if position else 0
    line = BLOCK.splitlines()[13]
    c.check(line[column - 1:column + 2] == "0.3", "at the column of nu's value (%d in %r)" % (column, line))


def usage_lists_options(c):
    """`stickslip COMMAND --help`: the usage line names every option the help explains, and the other way round."""
    for command in ("run", "check", "keys"):
        c.run(command, "--help")
        c.check(c.proc.returncode == 0, "%s --help exits 0" % command)
        text = c.proc.stdout
        usage = text.split("\n\n")[0]
        described = set(re.findall(r"^  (--[a-z-]+)", text, re.M))
        in_usage = set(re.findall(r"\[(--[a-z-]+)", usage))
        c.check(described and described == in_usage, "%s: usage %s, described %s" % (command, sorted(in_usage),
                                                                                   sorted(described)))
    c.run("run", "--help")
    c.check("[--explain]" in c.proc.stdout.split("\n\n")[0], "run's usage has --explain")


def command_line_mistakes(c):
    """A mistyped command or option gets one line in one form, "stickslip COMMAND: what is wrong; see stickslip
    COMMAND --help", exit 1, and the likely intent: the closest option or command, the command an option belongs to,
    the value an option lacks. `--name=value` is `--name value`; `stickslip help COMMAND` is `COMMAND --help`."""
    block = c.write(BLOCK)
    mistakes = [
        (["chek", block], r"^stickslip: unknown command 'chek' \(did you mean 'check'\?\); see stickslip --help$"),
        (["--verison"], r"^stickslip: unknown command '--verison' \(did you mean '--version'\?\)"),
        (["frobnicate"], r"^stickslip: unknown command 'frobnicate' \(commands: run, check, keys, plugins, compare\)"),
        (["run", block, "--stepz", "2"], r"^stickslip run: unknown option '--stepz' \(did you mean '--steps'\?\); "
                                         r"see stickslip run --help$"),
        (["run", block, "--plugn=mortar-dual"], r"^stickslip run: unknown option '--plugn=mortar-dual' \(did you "
                                                r"mean '--plugin'\?\)"),
        (["check", block, "--out", "r"], r"^stickslip check: --out is an option of stickslip run, not of stickslip "
                                         r"check; see stickslip check --help$"),
        (["keys", block, "--explain"], r"^stickslip keys: --explain is an option of stickslip run"),
        (["run", block, "--steps"], r"^stickslip run: --steps needs a value \(--steps N\)"),
        (["run", block, "--plugin", "--quiet"], r"^stickslip run: --plugin needs a value \(--plugin NAME\)"),
        (["run", block, "--quiet=yes"], r"^stickslip run: --quiet takes no value, got '--quiet=yes'"),
        (["run", block, "--steps=-3"], r"^stickslip run: --steps expects a positive integer, got '-3'"),
        (["run", block, block], r"^stickslip run: a second scene '.*scene\.yaml' after '.*scene\.yaml'"),
        (["check"], r"^stickslip check: which scene\? \(stickslip check SCENE\.yaml\); see stickslip check --help$"),
        (["plugins", "--all"], r"^stickslip plugins: unexpected argument '--all'; see stickslip plugins --help$"),
        # `--replace contact.0.parameters={mu: 0.1}` without quotes: the shell splits it in two
        (["check", block, "--replace", "bodies.0.material={E:", "3}"],
         r"^stickslip check: '3}' after --replace 'bodies\.0\.material=\{E:': a value with spaces needs quotes "
         r"\(--replace 'key=\{a: 1, b: 2\}'\)"),
        (["check", block, "--set", "bodies.1.material.E=3"],
         r"^stickslip: --set bodies\.1\.material\.E: index 1 is out of range: 'bodies' \(.*scene\.yaml:\d+:\d+\) has "
         r"1 entry \(0 to 0\)$"),
    ]
    for args, pattern in mistakes:
        c.run(*args)
        c.expect_failure(pattern)
        c.check(not c.proc.stdout, "nothing on stdout")
    c.run("run", block, "--steps=2", "--out=%s" % c.out, "--set=time.dt=0.25", "--quiet")
    c.check(c.proc.returncode == 0, "--name=value options run")
    if c.proc.returncode == 0:
        c.check(read_summary(c.out)["steps"] == 2, "--steps=2 stops after 2 steps")
        saved = open(os.path.join(c.out, "scene.yaml")).read()
        c.check("# overrides: --set time.dt=0.25 (applied below)\n" in saved, "--set=... is recorded as --set")
        c.check("# run with --steps 2: it stopped there; `stickslip run scene.yaml` runs to time.end" in saved,
                "the saved scene's header says the run was cut short by --steps")
    for args, usage in ((["help", "run"], "usage: stickslip run SCENE.yaml"),
                        (["plugins", "--help"], "usage: stickslip plugins"),
                        (["help", "keys"], "usage: stickslip keys SCENE.yaml"), (["--help"], "usage: stickslip <command>"),
                        (["help"], "usage: stickslip <command>"), (["check", "-h"], "usage: stickslip check SCENE.yaml")):
        c.run(*args)
        c.check(c.proc.returncode == 0 and usage in c.proc.stdout and not c.proc.stderr,
                "stickslip %s: exit 0, the usage on stdout" % " ".join(args))


def quiet_keeps_warnings(c):
    """--quiet drops the progress line and information (the auto linear solver's decisions), keeps warnings."""
    scene = c.write(replace(replace(CONTACT, "scheme: quasi-static", "scheme: midpoint"),
                            "material: {model: hooke, E: 1000, nu: 0.3}",
                            "material: {model: hooke, E: 1000, nu: 0.3, density: 1}"))
    c.run("run", scene)
    c.check(c.proc.returncode == 0, "the run succeeds")
    c.check("linear solver (auto):" in c.proc.stderr, "without --quiet: the auto solver's decision is shown")
    warning = "warning: contact pair 'floor': plugin 'penalty-nts' is not energy-consistent with the midpoint scheme"
    c.check(warning in c.proc.stderr, "without --quiet: the warning")
    c.run("run", scene, "--quiet")
    c.check(c.proc.returncode == 0, "the quiet run succeeds")
    c.check("linear solver (auto)" not in c.proc.stderr and "done," not in c.proc.stderr,
            "--quiet: no information, no progress")
    c.check(warning in c.proc.stderr, "--quiet: the warning stays")


def plot_scripts_help(c):
    """The plot scripts answer --help (plot-history.sh took it for a results folder) and refuse a missing one."""
    for script in ("plot-history.sh", "plot-snapshots.sh", "claim-results-files.sh"):
        p = subprocess.run([os.path.join(ROOT, "scripts", script), "--help"], capture_output=True, text=True)
        print("$ %s --help\nexit %d\n%s%s" % (script, p.returncode, p.stdout, p.stderr))
        c.check(p.returncode == 0 and re.search(r"usage", p.stdout, re.I) is not None and not p.stderr,
                "%s --help: exit 0 and the usage on stdout" % script)
    p = subprocess.run([os.path.join(ROOT, "scripts", "plot-history.sh")], capture_output=True, text=True)
    c.check(p.returncode == 2 and re.search(r"usage: plot-history\.sh .*results", p.stderr) is not None,
            "plot-history.sh without a folder: exit 2 and the usage")


CASES = {f.__name__: f for f in [stopped_runs_say_so, plugin_parameter_errors, set_value_positions,
                                 usage_lists_options, command_line_mistakes, quiet_keeps_warnings,
                                 plot_scripts_help]}

if __name__ == "__main__":
    main(CASES)
