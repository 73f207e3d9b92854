"""The lagged LU (`solver.linear.solver: gmres-lu`) against MUMPS factorising at every Newton iteration, on the Hertz
ladder: Newton iterations, numeric factorisations, GMRES iterations, CPU time of the whole run (user + system, one
process, one BLAS thread) and how far the contact force of gmres-lu lies from MUMPS's (docs/linear-solvers.md,
"Lagged LU"; docs/hertz.md). With --nullspace it compares GMRES + MueLu with the rigid-body near-nullspace against
the translations only instead (docs/linear-solvers.md, "Near-nullspace"). --solvers A,B,... compares those linear solvers (e.g. mumps,gmres-lu,gmres-muelu,auto).

Usage: python3 tests/bench/hertz/bench_lagged_lu.py [--nullspace | --solvers A,B,...] ELEMENT:REFINE[,REFINE...] ...
       [--set KEY=VALUE ...]
e.g.   python3 tests/bench/hertz/bench_lagged_lu.py quad4:1,2,3 tet4:2 tet10:1
Prints one markdown table row per run."""
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from hertz_cases import ELEMENTS, run_timed  # noqa: E402

# label -> scene settings; the first is the reference of the contact-force column
LAGGED = {"mumps": ["solver.linear.solver=mumps"], "gmres-lu": ["solver.linear.solver=gmres-lu"]}
NULLSPACE = {"muelu rigid-body": ["solver.linear.solver=gmres-muelu", "solver.linear.nullspace=rigid-body"],
             "muelu translations": ["solver.linear.solver=gmres-muelu", "solver.linear.nullspace=translations"]}


def main(argv):
    extra, cases, variants = [], [], LAGGED
    args = iter(argv)
    for arg in args:
        if arg == "--nullspace":
            variants = NULLSPACE
        elif arg == "--solvers":
            variants = {name: ["solver.linear.solver=" + name] for name in next(args).split(",")}
        elif arg == "--set":
            extra.append(next(args))
        else:
            element, refines = arg.split(":")
            cases += [(element, float(r)) for r in refines.split(",")]
    print("| element | refine | unknowns | solver | Newton | factorisations | GMRES iterations | CPU [s] | "
          "solve wall [s] | contact force vs the first |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for element, refine in cases:
        dim, scene, sets = ELEMENTS[element]
        runs = {}
        for label, solver_sets in variants.items():
            out = os.path.join(tempfile.mkdtemp(prefix="stickslip-bench-lagged-"), "results")
            run_sets = list(sets) + ["mesh.parameters.refine=%g" % refine, "output.vtu_every=0"] + solver_sets + extra
            runs[label] = run_timed(scene, run_sets, out)
        reference = next(iter(runs.values()))[0]
        key = "contact_force_z" if dim == 3 else "contact_force_y"
        scale = max(abs(r[key]) for r in reference.rows)
        for solver in variants:
            results, cpu, _ = runs[solver]
            s = results.summary
            difference = max(abs(x[key] - y[key]) for x, y in zip(results.rows, reference.rows)) / scale
            print("| %s | %g | %d | %s | %d | %d | %d | %.1f | %.1f | %.1e |" % (
                element, refine, s["unknowns"], solver, s["newton_iterations"], s["linear_factorisations"],
                s["krylov_iterations"], cpu, s["solve_seconds"], difference), flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
