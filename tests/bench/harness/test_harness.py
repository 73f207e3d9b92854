"""Checks of the benchmark harness's own arithmetic (no driver runs): active-set change counting, reversals, Pareto
fronts, expressions and derived variables, YAML flow values, the patch test's error. Usage: python3 tests/bench/harness/test_harness.py"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "validation"))
import declarations as dec  # noqa: E402
import errors  # noqa: E402
import report  # noqa: E402
import stress_metrics as sm  # noqa: E402
from stickslip_results import Checks  # noqa: E402


def row(active, stick=0, slip=0):
    return {"active_points": active, "stick_points": stick, "slip_points": slip}


def main():
    c = Checks("test_harness")
    # state changes between steps: a lower bound on the points that changed state
    c.check(sm.state_changes(row(3, 3, 0), row(3, 2, 1)) == 1, "stick -> slip of one point counts 1")
    c.check(sm.state_changes(row(2), row(1)) == 1, "a frictionless point leaving contact counts 1")
    c.check(sm.state_changes(row(0), row(4, 4, 0)) == 4, "four points entering in stick count 4")
    c.check(sm.state_changes(row(2, 1, 1), row(2, 1, 1)) == 0, "one point in, one out (a swap) is invisible: 0")
    c.check(sm.state_changes(row(2, 0, 0), row(2, 2, 0)) == 2, "frictionless contact -> stick counts per point")
    c.check(sm.reversals([0, 2, 0, 2, 2, 2, 0]) == 2, "0 2 0 2 . . 0: two turn-backs within two steps")
    c.check(sm.reversals([0, 1, 2, 3, 3, 3, 2, 1]) == 0, "a rise, two steps at rest, a fall: no reversal")
    c.check(sm.reversals([0, 1, 2, 3, 3, 2, 1]) == 1, "a rise, one step at rest, a fall: one reversal")
    # a body plugin's own energy line: E after each step plus the friction work so far, against the first row
    log = ("  step 1 newton 1 |F| = 1e-3\nplug: step 1 E 9.5 friction 0.5\nplug: step 2 E 9.0 friction 0.5\n"
           "plug: step 3 E 8.0 friction 0.75\n")
    own = sm.scheme_energy_balance(log, r"plug: step \d+ E (?P<E>\S+) friction (?P<work>\S+)", 10.0)
    c.check(own["energy_increase"] == 0.0 and own["energy_change"] == -0.025,
            "scheme energy: balance 10, 10, 10, 9.75 of 10: gain 0, change -0.025 (%s)" % own)
    own = sm.scheme_energy_balance(log, r"plug: step \d+ E (?P<E>\S+)", 8.0)
    c.check(abs(own["energy_increase"] - 0.1875) < 1e-15, "without work: 9.5 of 8 is a gain of 0.1875")
    c.check(sm.scheme_energy_balance(log, r"other: E (?P<E>\S+)", 1.0) is None, "no matching line: None")
    # Pareto front: no point of it is beaten in both time and error
    recs = [{"status": "ok", "cpu_seconds": t, "error": e} for t, e in ((1, 0.1), (2, 0.05), (3, 0.2), (4, 0.01),
                                                                        (5, 0.01))]
    front = report.pareto(recs)
    c.check([(r["cpu_seconds"], r["error"]) for r in front] == [(1, 0.1), (2, 0.05), (4, 0.01)],
            "Pareto front of five runs: %s" % [(r["cpu_seconds"], r["error"]) for r in front])
    c.check(report.pareto([{"status": "failed", "cpu_seconds": 1, "error": 0.1}]) == [], "failed runs are no front")
    # expressions: arithmetic over variables, nothing else
    c.check(dec.evaluate_expression("1e3*E", {"E": 2.0}, "t") == 2000.0, "1e3*E")
    c.check(dec.evaluate_expression("[0, 0, 6*f]", {"f": 10}, "t") == [0, 0, 60], "a list expression")
    for bad in ("__import__('os')", "E.real", "open('x')", "undefined + 1"):
        try:
            dec.evaluate_expression(bad, {"E": 1.0}, "t")
            c.check(False, "refused: %s" % bad)
        except dec.DeclarationError as e:
            c.check(True, "refused: %s (%s)" % (bad, str(e)[:60]))
    env = dec.environment({"E": 1000, "penalty": "$(factor*E)", "pt": "$penalty"}, {"factor": 0.01}, "t")
    c.check(env["penalty"] == 10.0 and env["pt"] == 10.0, "derived variables: penalty %r, pt %r" % (env["penalty"],
                                                                                                 env["pt"]))
    c.check(dec.substitute({"a": "$(2*x)", "b": "text", "c": ["$x"]}, {"x": 3}, "t") == {"a": 6, "b": "text",
                                                                                        "c": [3]}, "substitute")
    c.check(dec.yaml_flow({"mu": 0.3, "m": None, "v": [1, 2.5], "on": True}) == "{mu: 0.3, m: ~, v: [1, 2.5], on: true}",
            "YAML flow: %s" % dec.yaml_flow({"mu": 0.3, "m": None, "v": [1, 2.5], "on": True}))
    c.check(dec.numeric("1.0e6") == 1.0e6 and dec.numeric("text") == "text", "YAML 1.1 floats without a sign")
    # the patch test asks for a uniform pressure whatever its measure: Cauchy tractions p L0 / L pass, NTS does not
    class Points:
        def __init__(self, pressures):
            self.pressures = pressures

        def contact_points(self):
            return [{"pressure": q, "state": 1, "node": k} for k, q in enumerate(self.pressures)] + [
                {"pressure": 0.0, "state": 0, "node": -1}]  # a point out of contact does not count
    bench = dec.Benchmark.__new__(dec.Benchmark)
    bench.variables = {"pressure": 10}
    cauchy = errors.EVALUATORS["patch_pressure"](Points([10 / 1.0039] * 5), bench.variables)
    c.check(cauchy["error"] < 1e-15 and abs(cauchy["mean"] - 9.96115) < 1e-5,
            "uniform Cauchy tractions 10 / 1.0039 pass: %g" % cauchy["error"])
    nts = errors.EVALUATORS["patch_pressure"](Points([9.23, 10.21, 10.0, 9.9]), bench.variables)
    c.check(abs(nts["error"] - (9.835 - 9.23) / 9.835) < 1e-12, "NTS-like 9.23 ... 10.21: %.4f" % nts["error"])
    # every run of a benchmark has its own folder: labelled variants of one plugin (tet4/tet10) share plugin,
    # strategy, solver and values, and overwrote each other's records before the label joined the tag
    def run(label, options):
        return dec.Run("b", "penalty-nts", None, "direct", {"refine": 1}, [], label, "s.yaml", options)
    tet4, tet10 = run("penalty-nts/tet4", {"label": "penalty-nts/tet4"}), run("penalty-nts/tet10",
                                                                            {"label": "penalty-nts/tet10"})
    c.check(tet4.tag != tet10.tag, "labelled variants, distinct folders: %s, %s" % (tet4.tag, tet10.tag))
    c.check(run("penalty-nts", {}).tag == "penalty-nts-direct-refine1", "an unlabelled run keeps its folder name")
    # `only`: a variant keeps part of the benchmark's sweep
    bench = dec.Benchmark.__new__(dec.Benchmark)
    bench.name, bench.path, bench.scene, bench.set, bench.quick = "b", "b.yaml", "s.yaml", {}, {}
    bench.variables, bench.linear_solvers, bench.pairs = {"E": 1.0}, ["direct"], []
    bench.sweeps = [dec.Sweep("b.yaml", "refine", {"key": "mesh.parameters.refine", "values": [1, 2, 4]})]
    decl = dec.Declaration.__new__(dec.Declaration)
    decl.path, decl.plugin, decl.kind = "p.yaml", "p", "body"
    decl.entries = {("benchmarks", "b"): [{"only": {"refine": [1, 2]}}]}
    kept = [r.values["refine"] for r in dec.expand(bench, decl, "benchmarks", {"p": {}})]
    c.check(kept == [1, 2], "only: {refine: [1, 2]} keeps 1, 2 of 1, 2, 4: %s" % kept)
    decl.entries = {("benchmarks", "b"): [{"only": {"refine": [3]}}]}
    try:
        dec.expand(bench, decl, "benchmarks", {"p": {}})
        c.check(False, "only with a value the sweep lacks is refused")
    except dec.DeclarationError as e:
        c.check(True, "only with a value the sweep lacks is refused (%s)" % str(e)[:70])
    sys.exit(c.finish())


if __name__ == "__main__":
    main()
