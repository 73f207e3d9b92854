"""Validation of whole scenes through the driver: invariants of the time schemes, closed-form solutions, MPI
equality. Usage: python3 test_scenes.py CASE (see CASES at the bottom); exit code 0 when every check holds."""
import math
import re

from stickslip_results import Checks, read_vtu, relative_drift, run, main


def vector_drift(rows, prefix, scale=None):
    """Largest change of a 3-vector column group over the run, relative to its initial norm (or `scale`)."""
    initial = [rows[0][prefix + c] for c in "xyz"]
    norm = scale if scale is not None else max(math.sqrt(sum(v * v for v in initial)), 1e-300)
    return max(math.sqrt(sum((row[prefix + c] - initial[i]) ** 2 for i, c in enumerate("xyz"))) for row in rows) / norm


def conservation(c, results, tolerance, energy=True, angular=True):
    rows = results.rows
    if energy:
        drift = relative_drift([r["total_energy"] for r in rows])
        c.check(drift <= tolerance, "total energy constant: relative drift %.2e <= %.0e" % (drift, tolerance))
    # momentum scale: |p| or, for a body at rest overall, total mass x a typical speed would be needed; every scene
    # here moves, so |p0| is the natural scale
    drift = vector_drift(rows, "momentum_")
    c.check(drift <= tolerance, "linear momentum constant: relative drift %.2e <= %.0e" % (drift, tolerance))
    if angular:
        drift = vector_drift(rows, "angular_momentum_")
        c.check(drift <= tolerance, "angular momentum constant: relative drift %.2e <= %.0e" % (drift, tolerance))


def free_flight_blocks_midpoint(c):
    results, _ = run("scenes/free-flight-blocks.yaml")
    conservation(c, results, 1e-10)
    strain = max(results.column("strain_energy"))
    c.check(strain > 1.0, "the spinning block deforms (max strain energy %.3g > 1)" % strain)
    c.check(results.summary["steps"] == 200, "200 steps to t = 2")


def free_flight_blocks_table1(c):
    results, _ = run("scenes/free-flight-blocks.yaml", "--set", "bodies.1.angular_velocity=[0, 0, 0]",
                     "--set", "time.end=0.5")
    first = results.rows[0]
    for name, value in [("total_energy", 5.8), ("momentum_x", 0), ("momentum_y", 100), ("momentum_z", -40),
                        ("angular_momentum_x", -140), ("angular_momentum_y", 0), ("angular_momentum_z", 0)]:
        c.check(abs(first[name] - value) <= 1e-12 * max(1, abs(value)), "Table I: %s = %.15g (expected %g)"
                % (name, first[name], value))
    conservation(c, results, 1e-12)


def free_flight_blocks_backward_euler(c):
    results, _ = run("scenes/free-flight-blocks.yaml", "--set", "time.scheme=backward-euler")
    energy = results.column("total_energy")
    increases = sum(1 for a, b in zip(energy, energy[1:]) if b > a * (1 + 1e-13))
    c.check(increases == 0, "backward Euler never adds energy (%d increases)" % increases)
    loss = (energy[0] - energy[-1]) / energy[0]
    c.check(loss > 1e-3, "backward Euler visibly dissipates: %.3f %% of the energy lost by t = 2" % (100 * loss))
    drift = vector_drift(results.rows, "momentum_")
    c.check(drift <= 1e-10, "backward Euler keeps linear momentum: drift %.2e" % drift)


def free_flight_disk(c):
    results, _ = run("scenes/free-flight-disk.yaml", "--set", "time.end=1")
    conservation(c, results, 1e-10)
    c.check(max(results.column("strain_energy")) > 0.01, "the spinning disk deforms")


def free_flight_torus(c):
    results, _ = run("scenes/free-flight-torus.yaml", "--set", "mesh.parameters.refine=0.25", "--steps", "20")
    conservation(c, results, 1e-10)
    c.check(max(results.column("strain_energy")) > 0, "the spinning torus deforms")


def compressed_block(c):
    """Hooke block on rollers under pressure p: u_z(top) = -p/E, u_x(x=1) = nu p/E, at every node, exactly."""
    for refine in (1, 2):
        results, _ = run("scenes/compressed-block.yaml", "--set", "mesh.parameters.refine=%d" % refine)
        vtu = results.last_vtu()
        p, E, nu = 10.0, 1000.0, 0.3
        error = 0.0
        # reference position = current - displacement
        for x, u in zip(vtu["Points"], vtu["displacement"]):
            X = [x[i] - u[i] for i in range(3)]
            exact = [nu * p / E * X[0], nu * p / E * X[1], -p / E * X[2]]
            error = max(error, max(abs(u[i] - exact[i]) for i in range(3)))
        c.check(error <= 1e-12, "refine %d: uniaxial displacement field exact to %.2e <= 1e-12" % (refine, error))
        reaction = results.rows[-1]["reaction_base_z"]
        c.check(abs(reaction - p) <= 1e-9 * p, "refine %d: base reaction %.15g equals p*A = 10" % (refine, reaction))
        stress = vtu["cauchy_stress"]
        worst = max(abs(s[8] + p) for s in stress)
        c.check(worst <= 1e-9, "refine %d: sigma_zz = -p in every element (worst error %.2e)" % (refine, worst))
        # "gmres-muelu + mumps (step 1), gmres-sgs (steps 2-4)": the solvers that ran, over ranges covering every step
        used = results.summary["linear_solvers_used"]
        ranges = re.findall(r"([a-z0-9-]+(?: \+ [a-z0-9-]+)*) \(steps? (\d+)(?:-(\d+))?\)(?:, |$)", used)
        covered = [n for _, first, last in ranges for n in range(int(first), int(last or first) + 1)]
        known = {"mumps", "klu", "klu2", "gmres-muelu", "gmres-ilu", "gmres-sgs", "gmres-jacobi", "gmres-lu", "cg-muelu"}
        names = {n for solvers, _, _ in ranges for n in solvers.split(" + ")}
        c.check(covered == list(range(1, len(results.rows))) and names <= known,
                "refine %d: summary.json names the solvers that ran over each step range: %s" % (refine, used))
    results, _ = run("scenes/compressed-block.yaml", "--set", "solver.linear.solver=gmres-ilu")
    used = results.summary["linear_solvers_used"]
    c.check(used == "gmres-ilu (steps 1-4)", "a chosen iterative solver is reported as used: %s" % used)


def compressed_block_neo_hooke(c):
    """Neo-Hooke approaches the small-strain answer as p/E -> 0: the error of u_z(top) falls like (p/E)^2."""
    errors = []
    for p in (10.0, 5.0, 2.5):
        results, _ = run("scenes/compressed-block.yaml", "--set", "bodies.0.material.model=neo-hooke-bonet",
                         "--set", "boundary.3.traction=[0, 0, %g]" % -p)
        vtu = results.last_vtu()
        top = min(u[2] for u in vtu["displacement"])
        errors.append(abs(top - (-p / 1000.0)))
    ratios = [errors[i] / errors[i + 1] for i in range(2)]
    c.check(all(3.5 < r < 4.5 for r in ratios), "error falls like (p/E)^2: ratios %s" % ratios)


def uniaxial_stretches(law, E, nu, p):
    """Closed-form finite-strain answer of the compressed block for a Neo-Hooke law: F = diag(b, b, a) with
    S = mu (I - C^-1) + q(J) C^-1, q = lambda ln J (bonet) or lambda/2 (J^2 - 1) (ciarlet). Free sides give S_xx = 0:
    mu (b^2 - 1) + q = 0; the dead load p per reference area gives P_zz = a S_zz = -p: mu (a^2 - 1) + q = -p a.
    Solved by Newton on (a, b) with the exact Jacobian."""
    lam, mu = E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))
    a, b = 1 - p / E, 1 + nu * p / E
    for _ in range(50):
        J = a * b * b
        q, dq_dJ = (lam * math.log(J), lam / J) if law == "bonet" else (0.5 * lam * (J * J - 1), lam * J)
        r = (mu * (b * b - 1) + q, mu * (a * a - 1) + q + p * a)
        j11, j12 = dq_dJ * b * b, 2 * mu * b + dq_dJ * 2 * a * b
        j21, j22 = 2 * mu * a + dq_dJ * b * b + p, dq_dJ * 2 * a * b
        det = j11 * j22 - j12 * j21
        a, b = a - (j22 * r[0] - j12 * r[1]) / det, b - (j11 * r[1] - j21 * r[0]) / det
    return a, b


def compressed_block_finite_strain(c):
    """Both Neo-Hooke laws at 20 % compression reproduce their own closed-form homogeneous answer at every node
    (hex8 holds a linear field exactly), the two answers differ, and Newton converges quadratically (4 iterations a
    step measured; a Bonet volumetric tangent under the Ciarlet stress took 8-11)."""
    E, nu, p = 1000.0, 0.3, 200.0
    tops = {}
    for law in ("bonet", "ciarlet"):
        results, _ = run("scenes/compressed-block.yaml", "--set", "bodies.0.material.model=neo-hooke-" + law,
                         "--set", "boundary.3.traction=[0, 0, %g]" % -p)
        a, b = uniaxial_stretches(law, E, nu, p)
        tops[law] = a - 1
        vtu = results.last_vtu()
        error = 0.0
        for x, u in zip(vtu["Points"], vtu["displacement"]):
            X = [x[i] - u[i] for i in range(3)]
            exact = [(b - 1) * X[0], (b - 1) * X[1], (a - 1) * X[2]]
            error = max(error, max(abs(u[i] - exact[i]) for i in range(3)))
        c.check(error <= 1e-14, "neo-hooke-%s: u = (b-1, b-1, a-1) X with a = %.10f, b = %.10f at every node "
                "(error %.1e <= 1e-14)" % (law, a, b, error))
        iterations = max(results.column("newton_iterations"))
        c.check(iterations <= 5, "neo-hooke-%s: at most %d <= 5 Newton iterations a step" % (law, iterations))
    # the scene name of the first releases keeps meaning Bonet's law
    results, _ = run("scenes/compressed-block.yaml", "--set", "bodies.0.material.model=neo-hooke",
                     "--set", "boundary.3.traction=[0, 0, %g]" % -p)
    top = min(u[2] for u in results.last_vtu()["displacement"])
    c.check(abs(top - tops["bonet"]) <= 1e-14, "`neo-hooke` is neo-hooke-bonet: top %.10f" % top)
    difference = abs(tops["bonet"] - tops["ciarlet"])
    c.check(difference > 1e-3, "the laws differ at 20 %% strain: top displacements %.6f and %.6f" %
            (tops["bonet"], tops["ciarlet"]))


def mpi_free_flight_torus(c):
    """1 and 2 ranks give the same history and displacements to round-off (METIS partition, distributed solve)."""
    args = ("--set", "mesh.parameters.refine=0.25", "--steps", "5", "--set", "solver.linear.solver=direct")
    one, _ = run("scenes/free-flight-torus.yaml", *args)
    two, _ = run("scenes/free-flight-torus.yaml", *args, np=2)
    c.check(two.summary["ranks"] == 2, "the second run used 2 ranks")
    energy_scale = max(one.column("total_energy"))
    for name in ("total_energy", "strain_energy", "angular_momentum_z", "momentum_x"):
        a, b = one.column(name), two.column(name)
        # energies on the scale of the total energy (strain energy starts at zero)
        scale = energy_scale if name.endswith("energy") else max(abs(v) for v in a)
        diff = max(abs(x - y) for x, y in zip(a, b)) / scale
        c.check(diff <= 1e-11, "np 1 vs 2: %s equal to %.2e relative" % (name, diff))
    last_one, last_two = one.last_vtu(), two.last_vtu()
    for name in ("displacement", "velocity"):  # the 2-rank pieces joined by node id (a node on both: its owner's)
        ua, ub = last_one[name], last_two[name]
        scale = max(max(abs(v) for v in u) for u in ua)
        diff = max(max(abs(x - y) for x, y in zip(p, q)) for p, q in zip(ua, ub)) / scale
        c.check(diff <= 1e-11, "np 1 vs 2: %s equal to %.2e relative" % (name, diff))


def cantilever_tip(refine, order):
    results, _ = run("scenes/cantilever-2d.yaml", "--set", "mesh.parameters.refine=%d" % refine,
                     "--set", "mesh.parameters.order=%d" % order)
    return min(u[1] for u in results.last_vtu()["displacement"])


def cantilever_convergence(c):
    """Quad4 tip deflection converges at O(h^2) to the converged (quad9) answer, which matches beam theory."""
    E, nu, P, L, h = 1000.0, 0.3, 0.01, 10.0, 1.0
    E_plane = E / (1 - nu * nu)
    G = E / (2 * (1 + nu))
    beam = -(P * L ** 3 / (3 * E_plane * h ** 3 / 12) + P * L / (5.0 / 6.0 * G * h))
    reference = cantilever_tip(4, 2)
    c.check(abs(reference - beam) / abs(beam) < 5e-3,
            "quad9 (refine 4) tip %.6g within 0.5 %% of Timoshenko beam theory %.6g" % (reference, beam))
    errors = [abs(cantilever_tip(r, 1) - reference) for r in (1, 2, 4)]
    ratios = [errors[i] / errors[i + 1] for i in range(2)]
    c.check(all(3.0 < q < 5.0 for q in ratios), "quad4 error falls like h^2: errors %s, ratios %s" % (
        ["%.3g" % e for e in errors], ["%.2f" % q for q in ratios]))


if __name__ == "__main__":
    main([free_flight_blocks_midpoint, free_flight_blocks_table1, free_flight_blocks_backward_euler,
          free_flight_disk, free_flight_torus, compressed_block, compressed_block_neo_hooke,
          compressed_block_finite_strain, mpi_free_flight_torus, cantilever_convergence])
