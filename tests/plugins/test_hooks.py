#!/usr/bin/env python3
"""The ABI v2 hooks, each proved by a test plugin (tests/plugins/*.c) through the driver:

  body_free_flight  a body plugin claims a block and integrates it itself (stickslip.bulk, its own integrator):
                    the same history as the core's midpoint rule, and the same invariants
  body_energy       the energy the plugin's integrator reports (ABI 2.5) is history.csv's total_energy; the host's
                    energy of the world state stays in material_total_energy
  body_mpi          the claimed body on 2 ranks = 1 rank (the reported energy summed over ranks)
  body_errors       kinds are checked: a pair plugin named by a body, a body plugin named by a pair
  tied_dual         a tied interface with dual multipliers: condensed on the assembled operator
                    (stickslip.condense) = kept (saddle point), and stickslip.linear's solve_again checked in recover
  tied_dual_mpi     the same on 2 ranks = 1 rank
  reject_once       converged() rejects a converged point once per step: Newton runs again and the step ends with
                    the changed set (= example-spring at the final stiffness)
  reghost_refused   a pair plugin without checkpoint records is refused at the step its master faces must be
                    ghosted again (2 ranks)

Usage: test_hooks.py CASE (the binary from STICKSLIP_BIN, the test plugins from STICKSLIP_PLUGIN_PATH)."""
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "validation"))
from stickslip_results import ROOT, Checks, main, relative_drift, run  # noqa: E402

FLIGHT = "tests/plugins/free-flight-body.yaml"
TIED = "tests/plugins/tied-interface.yaml"
SPRINGS = "tests/plugins/springs.yaml"


def summary(results):
    with open(os.path.join(results.folder, "summary.json")) as f:
        return json.load(f)


def max_difference(a, b, names):
    """The largest |a - b| over rows and columns, relative to each column's largest magnitude (at least 1)."""
    worst, where = 0.0, ""
    for name in names:
        ca, cb = a.column(name), b.column(name)
        scale = max(max(abs(v) for v in ca), 1.0)
        d = max(abs(x - y) for x, y in zip(ca, cb)) / scale
        if d > worst:
            worst, where = d, name
    return worst, where


def body_free_flight(c):
    core, _ = run(FLIGHT)
    plugin, _ = run(FLIGHT, "--set", "bodies.0.plugin=test-midpoint-body")
    names = [n for n in core.rows[0] if n != "wall_seconds"]
    c.check(len(core.rows) == len(plugin.rows) == 41, "41 rows each (%d, %d)" % (len(core.rows), len(plugin.rows)))
    worst, where = max_difference(core, plugin, names)
    print("largest difference plugin vs core midpoint: %.3e (%s)" % (worst, where))
    c.check(worst < 1e-12, "the claimed body's history equals the core's to 1e-12 (%.2e in %s)" % (worst, where))  # measured 1.3e-13
    for results, label in ((core, "core"), (plugin, "plugin")):
        energy = relative_drift(results.column("total_energy"))
        momentum = max(relative_drift(results.column("momentum_" + a), scale=1.0) for a in "xyz")
        angular = max(relative_drift(results.column("angular_momentum_" + a), scale=1.0) for a in "xyz")
        print("%s: energy drift %.2e, momentum %.2e, angular momentum %.2e" % (label, energy, momentum, angular))
        c.check(energy < 1e-12, "%s: energy kept (relative drift %.2e)" % (label, energy))  # measured 2.4e-14
        c.check(momentum < 1e-12 and angular < 1e-12, "%s: momenta kept (%.2e, %.2e)" % (label, momentum, angular))
    c.check(plugin.column("kinetic_energy")[-1] > 0.1, "the body moves")


OFFSET = 7.0  # the test plugin adds it to the strain energy its integrator reports


def body_energy(c):
    """The test plugin's integrator reports its Hooke energy plus OFFSET: every row's total_energy is the core's
    total plus OFFSET (the reported energy replaced the host's for body a), and material_total_energy, the host's
    energy of the world state, is the core's total."""
    core, _ = run(FLIGHT, "--set", "time.end=0.1")
    plugin, _ = run(FLIGHT, "--set", "bodies.0.plugin=test-midpoint-body", "--set", "time.end=0.1",
                    "--set", "bodies.0.parameters.energy_offset=%g" % OFFSET)
    scale = max(core.column("total_energy"))
    c.check(len(core.rows) == len(plugin.rows) == 11, "11 rows each")
    shift = max(abs(p["total_energy"] - q["total_energy"] - OFFSET) for p, q in zip(plugin.rows, core.rows)) / scale
    c.check(shift < 1e-12, "total_energy = the core's + the reported offset %g, from row 0 on (%.1e)" % (OFFSET, shift))
    strain = max(abs(p["strain_energy"] - q["strain_energy"] - OFFSET) for p, q in zip(plugin.rows, core.rows)) / scale
    kinetic = max(abs(p["kinetic_energy"] - q["kinetic_energy"]) for p, q in zip(plugin.rows, core.rows)) / scale
    c.check(strain < 1e-12 and kinetic < 1e-12, "the offset is in strain_energy (%.1e), kinetic_energy is the core's "
            "(%.1e)" % (strain, kinetic))
    material = max(abs(p["material_total_energy"] - q["total_energy"]) for p, q in zip(plugin.rows, core.rows)) / scale
    same = max(abs(q["material_total_energy"] - q["total_energy"]) for q in core.rows) / scale
    c.check(material < 1e-12 and same == 0.0, "material_total_energy is the host's energy of the world state: the "
            "core's total (%.1e); without a reporting plugin it is total_energy (%.1e)" % (material, same))


def body_mpi(c):
    """The claimed body on 2 ranks: the plugin sees owned + ghosted views, the host completes the partial sums (of the
    residual and of the energy its integrator reports)."""
    one, _ = run(FLIGHT, "--set", "bodies.0.plugin=test-midpoint-body", "--set", "time.end=0.1",
                 "--set", "bodies.0.parameters.energy_offset=%g" % OFFSET)
    two, _ = run(FLIGHT, "--set", "bodies.0.plugin=test-midpoint-body", "--set", "time.end=0.1",
                 "--set", "bodies.0.parameters.energy_offset=%g" % OFFSET, np=2)
    names = [n for n in one.rows[0] if n != "wall_seconds"]
    worst, where = max_difference(one, two, names)
    print("body plugin, 2 ranks vs 1: %.3e (%s)" % (worst, where))
    c.check(worst < 1e-12, "2 ranks = 1 rank (%.2e in %s)" % (worst, where))
    c.check(summary(two)["ranks"] == 2, "ran on 2 ranks")


def body_errors(c):
    _, proc = run(FLIGHT, "--set", "bodies.1.plugin=penalty-nts", expect_ok=False)
    c.check(proc.returncode != 0 and "does not attach to a body" in proc.stderr,
            "a pair plugin named by a body is refused: " + proc.stderr.strip()[-160:])
    _, proc = run(TIED, "--set", "contact.0.plugin=test-midpoint-body", expect_ok=False)
    c.check(proc.returncode != 0 and "does not attach to a contact pair" in proc.stderr,
            "a body plugin named by a pair is refused: " + proc.stderr.strip()[-160:])


def displacements(results):
    return results.last_vtu()["displacement"]


def compare_runs(c, a, b, label):
    ua, ub = displacements(a), displacements(b)
    scale = max(max(abs(x) for u in ua for x in u), 1e-300)
    d = max(abs(x - y) for u, v in zip(ua, ub) for x, y in zip(u, v))
    print("%s: largest displacement difference %.3e (|u| %.3e)" % (label, d, scale))
    c.check(d <= 1e-13 * scale, "%s: displacements equal to 1e-13 (%.2e relative)" % (label, d / scale))  # measured 1.1e-15
    fa, fb = a.column("contact_force_y")[-1], b.column("contact_force_y")[-1]
    c.check(abs(fa - fb) <= 1e-13 * abs(fa) and abs(fa) > 1.0,
            "%s: the interface force (from the multipliers) equal: %.12g vs %.12g" % (label, fa, fb))
    return d / scale


def tied_dual(c):
    saddle, _ = run(TIED)
    dual, _ = run(TIED, "--set", "contact.0.strategy=dual")
    compare_runs(c, saddle, dual, "dual vs saddle point")
    s, d = summary(saddle), summary(dual)
    print("linear system: saddle point %d, dual %d (unknowns %d)" % (s["linear_system_size"],
                                                                     d["linear_system_size"], d["unknowns"]))
    c.check(d["linear_system_size"] == d["dofs"] and s["linear_system_size"] == s["unknowns"] > s["dofs"],
            "dual solves the displacement-only system, saddle point all unknowns")
    # the load is carried through the glue: the upper block's shear moves its bottom
    c.check(abs(dual.column("contact_force_x")[-1] + 3.0) < 1e-9,
            "the glue carries the applied shear (force %.12g)" % dual.column("contact_force_x")[-1])


def tied_dual_mpi(c):
    for strategy in ("dual", "saddle-point"):
        one, _ = run(TIED, "--set", "contact.0.strategy=" + strategy)
        two, _ = run(TIED, "--set", "contact.0.strategy=" + strategy, np=2)
        compare_runs(c, one, two, strategy + ": 2 ranks vs 1")
        c.check(summary(two)["ranks"] == 2, "ran on 2 ranks")


def reghost_refused(c):
    """ring-on-block on 2 ranks with test-reject-once, which keeps no checkpoint records: when the ring's master faces
    must be ghosted again (step 7 here; 3.3 s CPU) the pair cannot be re-created, and the step is refused naming the
    pair, the plugin and STICKSLIP_MASTER_GHOSTING=replicated, the results so far kept."""
    results, proc = run("scenes/ring-on-block.yaml", "--set", "time.dt=0.05", "--set", "time.end=0.4", "--plugin",
                        "test-reject-once", "--replace", "contact.0.parameters={k_first: 1, k_final: 2}", np=2,
                        expect_ok=False)
    c.check(proc.returncode != 0, "the run stops (exit %d)" % proc.returncode)
    message = proc.stderr.strip().splitlines()[0] if proc.stderr.strip() else "(no message)"
    c.check("contact pair 'ring': at step 7" in proc.stderr and "test-reject-once" in proc.stderr and
            "STICKSLIP_MASTER_GHOSTING=replicated" in proc.stderr, "the refusal names pair, step, plugin and "
            "variable: " + message[:240])
    c.check(results is not None and summary(results)["status"] == "failed" and int(results.rows[-1]["step"]) == 6,
            "the results up to step 6 are kept, status failed")


def reject_once(c):
    rejecting, _ = run(SPRINGS)
    reference, _ = run(SPRINGS, "--set", "contact.0.plugin=example-spring", "--replace", "contact.0.parameters={k: 5}")
    names = ["contact_force_x", "contact_force_y", "reaction_pull_x", "reaction_pull_y", "strain_energy"]
    worst, where = max_difference(rejecting, reference, names)
    print("reject-once vs example-spring at k_final: %.3e (%s)" % (worst, where))
    c.check(worst < 1e-13, "the step ends with the changed set: equal to k = k_final (%.2e)" % worst)  # measured 8e-15
    r, s = summary(rejecting), summary(reference)
    print("active-set loops %d over %d steps; Newton iterations %d vs %d" % (
        r["active_set_loops"], r["steps"], r["newton_iterations"], s["newton_iterations"]))
    c.check(r["active_set_loops"] == r["steps"] == 4, "one rejection per step")
    c.check(s["active_set_loops"] == 0, "example-spring never rejects")
    c.check(r["newton_iterations"] > s["newton_iterations"], "the re-solves cost Newton iterations")


def partition_refused(c):
    """contact_balance.rebalance: on (core/model/contact_partition.h) with a pair whose plugin keeps no checkpoint
    records (test-reject-once) and a self-contact pair (ring-crush-2d's inner-self): `check --explain` says they keep
    the bulk partition and why, and gives the other pairs (obstacles) the contact partition; a value other than off
    or on is refused naming the key. `check` only, 1 rank."""
    binary = os.environ.get("STICKSLIP_BIN", os.path.join(ROOT, "build", "bin", "stickslip"))

    def check(scene, *args):
        return subprocess.run([binary, "check", os.path.join(ROOT, scene), *args], capture_output=True, text=True)
    on = ("--set", "contact_balance.rebalance=on")
    proc = check("scenes/ring-on-block.yaml", "--explain", "--plugin", "test-reject-once", "--replace",
                 "contact.0.parameters={k_first: 1, k_final: 2}", *on)
    c.check(proc.returncode == 0 and "contact pair ring: keeps the bulk partition (its plugin keeps no records" in
            proc.stdout, "a plugin without records keeps the bulk partition (--explain)")
    proc = check("scenes/ring-crush-2d.yaml", "--explain", *on)
    c.check("contact pair inner-self: keeps the bulk partition (self contact" in proc.stdout,
            "a self-contact pair keeps the bulk partition (--explain)")
    c.check("contact pair floor: 96 to 96 slave nodes" in proc.stdout, "an obstacle pair takes the contact partition")
    proc = check("scenes/ring-crush-2d.yaml", "--set", "contact_balance.rebalance=yes")
    c.check(proc.returncode != 0 and "contact_balance.rebalance" in proc.stderr and "'off', 'on'" in proc.stderr,
            "rebalance=yes refused naming the key: " + proc.stderr.strip()[:160])


if __name__ == "__main__":
    main([body_free_flight, body_energy, body_mpi, body_errors, tied_dual, tied_dual_mpi, reject_once,
          reghost_refused, partition_refused])
