#!/usr/bin/env python3
"""Newton's line search as the default: every candidate over the shipped scenes (scenes/*.yaml, long ones capped),
the user-like scenes of tests/bench/line-search/ (each with every contact plugin that accepts it) and the stress
suite's short pass (tests/bench/stress.py --short). Per run and candidate: converged or not, Newton iterations,
step cuts. A candidate is applied the way a default is: only to runs whose scene and options do not choose
solver.newton.line_search themselves (the others run once, as they are). The tables go into docs/linear-solvers.md.

  python3 tests/bench/line_search.py                 # every group, every candidate
  python3 tests/bench/line_search.py --group user     # shipped | user | stress
  options: --candidates full-step,backtrack,...  --only REGEX (runs whose name matches)  --jobs N  --fresh
           --docs (write the tables)"""
import argparse
import os
import re
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor

import yaml

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "harness"))
sys.path.insert(0, HERE)
import declarations as dec  # noqa: E402
import report  # noqa: E402
import runner  # noqa: E402
import stress  # noqa: E402

CANDIDATES = ["full-step", "backtrack", "polynomial"]
KEY = "solver.newton.line_search"
TIMEOUT = 3600

# Shipped scenes that run long: the first steps only (contact included), or a coarser mesh of the same scene.
SHIPPED_CAPS = {
    "corot-ellipse-two-planes": ["--steps", "200"],
    "mortar-ironing-3d": ["--steps", "60"],
    "two-tori-coarse": ["--steps", "100"],
    "two-tori-mu03": ["--steps", "100", "--set", "mesh.0.parameters.refine=0.25",
                      "--set", "mesh.1.parameters.refine=0.25"],
}
SHIPPED_SKIP = {"two-tori": "the full tori of two-tori-coarse (refine 1, 76k unknowns: about 1 s CPU per Newton "
                            "iteration); two-tori-coarse and two-tori-mu03 at refine 0.25 stand for it"}

# The user-like scenes with each plugin: the parameters a plugin needs until it computes its own defaults
# (mortar-dual needs none: its c_n falls back to 1 with a warning, which is what a user gets).
USER_PARAMETERS = {
    "penalty-nts": {"mu": 0.3, "penalty": 1.0e5, "penalty_tangential": 1.0e5},
    "covariant-penalty": {"mu": 0.3, "penalty": 1.0e5},
    "nts-augmented": {"mu": 0.3, "epsilon_t": 1.0e5},
    "mortar-dual": {"mu": 0.3},
}


class TaggedRun(dec.Run):
    """A run with its own results folder name (one per scene, plugin and candidate)."""

    def __init__(self, tag, *a):
        super().__init__(*a)
        self._tag = tag

    @property
    def tag(self):
        return self._tag


class Job:
    def __init__(self, group, name, plugin, scene, args, chooses):
        self.group, self.name, self.plugin, self.scene, self.args = group, name, plugin, scene, args
        self.chooses = chooses  # the scene or its options set the line search: run once, as it is

    def run_for(self, candidate):
        args = list(self.args)
        if not self.chooses:
            args += ["--set", "%s=%s" % (KEY, candidate)]
        tag = re.sub(r"[^A-Za-z0-9.+_-]+", "_", "%s-%s-%s" % (self.name, self.plugin or "core",
                                                              "own" if self.chooses else candidate))
        return TaggedRun(tag, "line-search", self.plugin, None, None, {}, args, self.name, self.scene)


def scene_chooses(scene_path, args):
    if any(a.startswith(KEY + "=") for a in args):
        return True
    with open(os.path.join(dec.ROOT, scene_path)) as f:
        data = yaml.safe_load(f)
    return KEY.split(".")[-1] in (((data or {}).get("solver") or {}).get("newton") or {})


def shipped_jobs():
    jobs = []
    for name in sorted(os.listdir(os.path.join(dec.ROOT, "scenes"))):
        stem = name[:-5]
        if not name.endswith(".yaml") or stem in SHIPPED_SKIP:
            continue
        scene = os.path.join("scenes", name)
        args = SHIPPED_CAPS.get(stem, [])
        with open(os.path.join(dec.ROOT, scene)) as f:
            pairs = yaml.safe_load(f).get("contact") or []
        plugin = pairs[0]["plugin"] if pairs else None
        jobs.append(Job("shipped", stem, plugin, scene, args, scene_chooses(scene, args)))
    return jobs


def accepts(scene, plugin, args):
    proc = subprocess.run([dec.BIN, "check", os.path.join(dec.ROOT, scene), *args], capture_output=True, text=True)
    return proc.returncode == 0


def user_jobs():
    jobs = []
    folder = os.path.join("tests", "bench", "line-search")
    for name in sorted(os.listdir(os.path.join(dec.ROOT, folder))):
        if not name.endswith(".yaml"):
            continue
        scene = os.path.join(folder, name)
        for plugin, params in USER_PARAMETERS.items():
            args = ["--plugin", plugin, "--set", "contact.0.parameters=%s" % dec.yaml_flow(params)]
            if accepts(scene, plugin, args):
                jobs.append(Job("user", name[:-5], plugin, scene, args, scene_chooses(scene, args)))
    return jobs


def stress_jobs():
    jobs = []
    decls, installed = dec.load_declarations(), dec.installed_plugins()
    for case in dec.load_benchmarks("stress", kind="stress").values():
        runs, _ = stress.case_runs(case, decls, installed, [], True, False)
        for r in runs:
            name = "%s %s" % (case.name, stress.value_key({"values": r.values}))
            jobs.append(Job("stress", name.strip(), r.plugin, r.scene, r.args, scene_chooses(r.scene, r.args)))
    return jobs


GROUPS = {"shipped": shipped_jobs, "user": user_jobs, "stress": stress_jobs}


def execute(job, candidate, fresh):
    record, _ = runner.execute(job.run_for(candidate), "line-search/" + job.group, TIMEOUT, fresh)
    return record


def cell(record):
    if record is None:
        return "–"
    if record.get("status") != "ok":
        return "**failed** t = %s" % report.fmt(record.get("final_time"), "%.3g")
    return "%s / %s" % (record.get("newton_iterations"), record.get("step_cuts"))


def table(jobs, candidates, results):
    rows, totals = [], {c: [0, 0, 0] for c in candidates}  # iterations, cuts, failures over the runs all converged
    for job in jobs:
        recs = {c: results.get((job.name, job.plugin, "own" if job.chooses else c)) for c in candidates}
        row = [job.name, job.plugin or "core", "scene's own" if job.chooses else "–"]
        row += [cell(recs[c]) for c in candidates]
        rows.append(row)
        all_ok = all(r and r.get("status") == "ok" for r in recs.values())
        for c, r in recs.items():
            if r and r.get("status") != "ok":
                totals[c][2] += 1
            elif all_ok:
                totals[c][0] += r["newton_iterations"]
                totals[c][1] += r["step_cuts"]
    rows.append(["**all**", "", "", *["%d / %d, %d failed" % tuple(totals[c]) for c in candidates]])
    header = ["run", "plugin", "line search"] + candidates
    return report.markdown_table(header, rows)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--group", action="append", choices=sorted(GROUPS))
    ap.add_argument("--candidates", default=",".join(CANDIDATES))
    ap.add_argument("--only", help="a regular expression: only the runs whose name matches it")
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--fresh", action="store_true")
    ap.add_argument("--docs", action="store_true")
    args = ap.parse_args()
    candidates = args.candidates.split(",")
    for group in args.group or sorted(GROUPS):
        jobs = [job for job in GROUPS[group]() if not args.only or re.search(args.only, job.name)]
        work = sorted({(job, "own" if job.chooses else c) for job in jobs for c in candidates},
                      key=lambda w: (w[0].name, w[1]))
        results = {}

        def one(w):
            job, c = w
            record = execute(job, c, args.fresh)
            results[(job.name, job.plugin, c)] = record
            print("%-8s %-40s %-18s %-12s %s" % (group, job.name, job.plugin or "core", c, cell(record)), flush=True)

        with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
            list(pool.map(one, work))
        text = table(jobs, candidates, results)
        print(text)
        if args.docs:
            commits = sorted({r.get("commit", "?") for r in results.values() if r})
            only = " --only '%s'" % args.only if args.only else ""
            head = ("Command: `python3 tests/bench/line_search.py --group %s%s --docs`. Measured at %s, %s; cells: "
                    "Newton iterations / step cuts over the whole run." % (group, only, ", ".join(commits),
                                                                          time.strftime("%Y-%m-%d")))
            report.replace_section("linear-solvers.md", "line-search-" + group, head + "\n\n" + text)


if __name__ == "__main__":
    main()
