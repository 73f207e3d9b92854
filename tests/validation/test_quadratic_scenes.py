"""Validation of second-order elements from a scene (mesh.order: 2) with the baseline plugin penalty-nts: the 3D
contact patch test on quadratic faces, Hertz 2D and 3D refinement with quadratic elements, the VTU cells of a
quadratic run and the scene errors of the mesh keys. Usage: python3 test_quadratic_scenes.py CASE (CASES at the
bottom); exit code 0 when every check holds. Measured numbers are quoted in each check's docstring; the benchmarks
against unknowns and time are in docs/hertz.md."""
import math

from hertz_profile import hertz_reference, profile_errors
from stickslip_results import Checks, main, run
from test_contact_scenes import reference_points

PATCH = "scenes/patch-test-3d.yaml"
ORDER2 = ("--set", "mesh.order=2")
TETS = ("--set", "mesh.parameters.hexes=0")


def patch_test_3d(c):
    """Two stacked boxes, non-matching meshes (4 x 4 against 5 x 5 cells), uniform pressure p = 10. The total force is
    exact for every element type; the nodal pressures of one-pass NTS are not. Measured max deviation from p over the
    slave nodes in contact: hex8 15.3 %, hex27 27.8 %, tet4 19.6 %, tet10 17.6 %. On tet10, 8 of the 157 TRI6 slave
    nodes (all corners) open by up to 8.8e-5 (the edge nodes penetrate about 2e-6): a corner whose consistent load
    would be tensile separates (docs/plugins/penalty-nts.md). hex20 slaves (QUAD8) are refused with a message."""
    cases = (("hex8", (), 0.16, 0), ("hex27", ORDER2, 0.29, 0), ("tet4", TETS, 0.20, 0),
             ("tet10", TETS + ORDER2, 0.18, 8))
    for name, args, bound, open_expected in cases:
        results, _ = run(PATCH, *args)
        last = results.rows[-1]
        c.check(abs(last["contact_force_z"] - 10.0) <= 1e-9 * 10,
                "%s: total contact force %.15g = p * area" % (name, last["contact_force_z"]))
        c.check(abs(last["reaction_base_z"] - 10.0) <= 1e-9 * 10,
                "%s: base reaction %.15g = p * area" % (name, last["reaction_base_z"]))
        points = results.contact_points()
        touching = [q for q in points if q["state"] != 0]
        opened = [q for q in points if q["state"] == 0]
        deviation = max(abs(q["pressure"] - 10.0) for q in touching) / 10.0
        print("%s: %d slave nodes, %d open (largest gap %.2e), pressures %.4f ... %.4f, max deviation %.2f %%"
              % (name, len(points), len(opened), max([q["gap"] for q in opened] or [0.0]),
                 min(q["pressure"] for q in touching), max(q["pressure"] for q in touching), 100 * deviation))
        c.check(deviation <= bound, "%s: NTS patch-test error %.2f %% <= %g %%" % (name, 100 * deviation, 100 * bound))
        c.check(len(opened) == open_expected, "%s: %d open slave nodes (measured %d)" % (name, len(opened),
                                                                                       open_expected))
        c.check(all(q["gap"] < 1e-4 for q in opened), "%s: open nodes stay within 1e-4 of the master" % name)
    _, proc = run(PATCH, *ORDER2, "--set", "mesh.serendipity=true", expect_ok=False)
    c.check(proc.returncode != 0 and "QUAD8" in proc.stderr and "hex27" in proc.stderr,
            "hex20 (QUAD8 slave faces) refused, naming the way out: %s" % proc.stderr.strip().splitlines()[-1])


def hertz_errors(dim, scene, *args):
    results, _ = run(scene, *args, "--set", "output.vtu_every=4")
    _, a, p0 = hertz_reference(dim, results)
    errors = profile_errors(reference_points(results, radial=dim == 3), a, p0)
    errors["unknowns"] = results.summary["unknowns"]
    return errors


def report(label, e):
    print("%s: %d unknowns, %d nodes in r < 1.25 a, L2 profile %.4f, a %+.3e, p0 %+.3e, centre %+.3e"
          % (label, e["unknowns"], e["profile_nodes"], e["l2"], e["a"], e["p0"], e["peak"]))


def hertz_3d_quadratic(c):
    """Sphere on a stiff block with tet10 (the tet4 mesh of hertz-3d.yaml made second order): refine 0.75 and 1.
    Measured L2 profile errors 0.052 (4.2k unknowns) and 0.034 (8.9k); the tet4 mesh of refine 1 gives 0.135 at 1.5k
    unknowns and tet4 needs refine 1.5 (3.6k unknowns) for 0.063. Fit errors at refine 1: a -0.82 %, p0 -0.88 %,
    centre node -1.4 %."""
    coarse = hertz_errors(3, "scenes/hertz-3d.yaml", *ORDER2, "--set", "mesh.parameters.refine=0.75")
    fine = hertz_errors(3, "scenes/hertz-3d.yaml", *ORDER2)
    linear = hertz_errors(3, "scenes/hertz-3d.yaml")
    report("tet10 refine 0.75", coarse)
    report("tet10 refine 1", fine)
    report("tet4 refine 1", linear)
    c.check(fine["l2"] < coarse["l2"], "tet10: L2 profile error falls with refinement: %.4f -> %.4f"
            % (coarse["l2"], fine["l2"]))
    c.check(fine["l2"] <= 0.04, "tet10 refine 1: L2 profile error %.4f <= 0.04" % fine["l2"])
    c.check(fine["l2"] < linear["l2"] / 3, "tet10 on the tet4 mesh: %.4f < tet4's %.4f / 3" % (fine["l2"],
                                                                                             linear["l2"]))
    for key, bound in (("a", 0.012), ("p0", 0.012), ("peak", 0.02)):
        c.check(abs(fine[key]) <= bound, "tet10 refine 1: error of %s %+.3e within %g" % (key, fine[key], bound))


def hertz_2d_quadratic(c):
    """Cylinder on a stiff block with quad9 and tri6 (the quad4 / triangle meshes of hertz-2d.yaml made second
    order), refine 0.5, 1, 2: the L2 profile error falls from the coarsest level. The measured errors per level are
    docs/hertz.md's second-order table."""
    for name, args in (("quad9", ORDER2), ("tri6", ORDER2 + ("--set", "mesh.parameters.quads=0"))):
        errors = []
        for refine in (0.5, 1, 2):
            e = hertz_errors(2, "scenes/hertz-2d.yaml", *args, "--set", "mesh.parameters.refine=%g" % refine)
            report("%s refine %g" % (name, refine), e)
            errors.append(e)
        values = [e["l2"] for e in errors]
        c.check(values[2] < values[0] and values[1] < values[0],
                "%s: L2 profile error falls from the coarsest level: %s" % (name, ", ".join("%.4f" % v
                                                                                         for v in values)))


def hertz_3d_quadratic_mpi(c):
    """tet10 hertz-3d (refine 0.75) on 1 and 2 ranks: METIS partitions quadratic elements by their corners, and
    penalty-nts' TRI6 pressure recovery combines nodes that different ranks own. Measured: reactions and contact force
    equal to 1e-14, nodal pressures to 1e-11 (of p0 = 100)."""
    args = ORDER2 + ("--set", "mesh.parameters.refine=0.75")
    one, _ = run("scenes/hertz-3d.yaml", *args)
    two, _ = run("scenes/hertz-3d.yaml", *args, np=2)
    c.check(two.summary["ranks"] == 2, "the second run used 2 ranks")
    for name in ("reaction_top_z", "contact_force_z", "strain_energy"):
        a, b = one.rows[-1][name], two.rows[-1][name]
        c.check(abs(a - b) <= 1e-10 * abs(a), "np 1 vs 2: %s %.15g vs %.15g" % (name, a, b))
    pa = {q["node"]: q["pressure"] for q in one.contact_points()}
    pb = {q["node"]: q["pressure"] for q in two.contact_points()}
    c.check(sorted(pa) == sorted(pb), "the same %d slave nodes are reported" % len(pa))
    worst = max(abs(pa[k] - pb.get(k, math.inf)) for k in pa)
    c.check(worst <= 1e-8, "np 1 vs 2: nodal pressures equal to %.1e" % worst)


def quadratic_output(c):
    """A tet10 run writes tet10 cells (VTK type 24, 10 nodes each, one point per node); mesh keys with bad values are
    refused naming the key."""
    results, proc = run("scenes/hertz-3d.yaml", *ORDER2, "--set", "time.end=0.25")
    arrays = results.last_vtu()
    types = {t[0] for t in arrays["types"]}
    offsets = [o[0] for o in arrays["offsets"]]
    c.check(types == {24}, "every cell is a VTK quadratic tetra (24): %s" % sorted(types))
    c.check(all(b - a == 10 for a, b in zip([0] + offsets, offsets)), "every cell has 10 nodes")
    c.check(len(arrays["Points"]) == results.summary["dofs"] // 3, "points = nodes (%d)" % len(arrays["Points"]))
    for key, value, needle in (("mesh.order", "3", "mesh.order"), ("mesh.serendipity", "true", "order: 2")):
        _, bad = run("scenes/hertz-3d.yaml", "--set", "%s=%s" % (key, value), expect_ok=False)
        c.check(bad.returncode != 0 and needle in bad.stderr,
                "--set %s=%s refused: %s" % (key, value, bad.stderr.strip().splitlines()[-1]))


BLOCK = "scenes/compressed-block.yaml"
RESULTANT = (3.0, -2.0, -100.0)  # a 10 % compression with some shear: the top stretches by about 3 %


def resultant_runs(*args, area="reference", np=1, law="neo-hooke-bonet"):
    load = "{name: load, group: zmax, resultant: [%g, %g, %g], area: %s, history: [[0, 0], [1, 1]]}" % (
        RESULTANT + (area,))
    return run(BLOCK, "--replace", "mesh.parameters={nx: 2, ny: 2, nz: 2}", "--replace", "boundary.3=" + load, "--set",
               "bodies.0.material.model=" + law, "--set", "output.vtu_every=4", *args, np=np)[0]


def reaction_balance(c, results, label):
    """Sum of the reactions of the three roller conditions + history(t) R = 0 at every step."""
    worst = 0.0
    for row in results.rows:
        for i, axis in enumerate("xyz"):
            total = sum(row["reaction_%s_%s" % (name, axis)] for name in ("roller-x", "roller-y", "base"))
            worst = max(worst, abs(total + row["time"] * RESULTANT[i]))
    c.check(worst <= 1e-12 * abs(RESULTANT[2]), "%s: reactions = -R(t) to %.1e (R = %s)" % (label, worst, RESULTANT))


def resultant_load(c):
    """boundary `resultant`: the compressed block (rollers) under R = (3, -2, -100) on its top, ramped over 4 steps,
    neo-Hooke, second-order hex27 (QUAD9 top faces) and hex20 (QUAD8: negative corner weights), over the reference and
    the current area. The reactions equal -R(t) at every step (measured <= 6e-14 against 100); over the reference area
    the run equals the one with the uniform traction R / A (A = 1) to round-off; over the current area the top
    (stretched sideways by nu) carries the same total force spread differently (displacements differ from the
    reference-area run by 0.36 % of the largest, hex27), and Newton still converges quadratically: 4 iterations per
    step for both areas (the current area's Jacobian is exact, test_resultant)."""
    for label, args in (("hex27", ("--set", "mesh.order=2")),
                        ("hex20", ("--set", "mesh.order=2", "--set", "mesh.serendipity=true"))):
        for area in ("reference", "current"):
            results = resultant_runs(*args, area=area)
            reaction_balance(c, results, "%s, %s area" % (label, area))
            if area == "reference":
                traction = run(BLOCK, "--replace", "mesh.parameters={nx: 2, ny: 2, nz: 2}", "--set",
                               "bodies.0.material.model=neo-hooke-bonet", "--set", "output.vtu_every=0", "--replace",
                               "boundary.3={name: load, group: zmax, traction: [%g, %g, %g], "
                               "history: [[0, 0], [1, 1]]}" % RESULTANT, *args)[0]
                names = [k for k in results.rows[-1] if k.startswith("reaction_")]
                worst = max(abs(results.rows[-1][k] - traction.rows[-1][k]) for k in names)
                c.check(worst <= 1e-12 * abs(RESULTANT[2]), "%s: resultant over the reference area = traction R / A "
                        "(reactions equal to %.1e)" % (label, worst))
                reference = results.last_vtu()["displacement"]
            else:
                current = results.last_vtu()["displacement"]
                change = max(abs(a - b) for u, v in zip(reference, current) for a, b in zip(u, v))
                largest = max(abs(a) for u in reference for a in u)
                c.check(0.002 <= change / largest <= 0.006, "%s: the current area changes the displacements by "
                        "%.2f %% of the largest (measured 0.36 %% on hex27)" % (label, 100 * change / largest))
            iterations = results.summary["newton_iterations"] / results.summary["steps"]
            print("%s, %s area: %.1f Newton iterations per step" % (label, area, iterations))
            c.check(iterations <= 4, "%s, %s area: %.1f Newton iterations per step (measured 4)" % (label, area,
                                                                                              iterations))


def resultant_load_mpi(c):
    """The resultant over the current area on 2 ranks equals the 1-rank run (reactions to 1e-10)."""
    one = resultant_runs("--set", "mesh.order=2", area="current")
    two = resultant_runs("--set", "mesh.order=2", area="current", np=2)
    reaction_balance(c, two, "hex27, current area, 2 ranks")
    names = [k for k in one.rows[-1] if k.startswith("reaction_")]
    worst = max(abs(one.rows[-1][k] - two.rows[-1][k]) for k in names)
    c.check(worst <= 1e-10, "np 1 vs 2: reactions equal to %.1e" % worst)


def quadratic_refusals(c):
    """Plugins that cannot take second-order faces refuse them at check, naming the pair, the surface, its faces
    and the plugins that can (hertz-3d with mesh.order 2: TRI6 faces on both surfaces); none runs with a silently wrong result.
    mortar-dual takes TRI6 faces (the dual basis of the transformed functions, saddle point only:
    validation_mortar_quadratic_3d_refused and validation_mortar_patch_test_3d_tri6)."""
    import os
    import subprocess
    from stickslip_results import ROOT
    binary = os.environ.get("STICKSLIP_BIN", os.path.join(ROOT, "build", "bin", "stickslip"))
    for plugin, needle in (("nts-augmented", "TRI6 faces, whose corner nodes' consistent loads"),
                           ("covariant-penalty", "(not TRI6 or QUAD8)")):
        proc = subprocess.run([binary, "check", os.path.join(ROOT, "scenes/hertz-3d.yaml"), "--plugin", plugin,
                               "--set", "mesh.order=2", "--replace", "contact.0.parameters={}"],
                              capture_output=True, text=True)
        message = proc.stderr.strip().splitlines()[-1] if proc.stderr.strip() else ""
        c.check(proc.returncode == 1 and needle in message and "slave surface 'sphere-contact' has" in message
                and ("second-order faces" in message or "TRI6 faces" in message) and "Plugins that can: " in message,
                "%s refuses TRI6 faces: %s" % (plugin, message))


if __name__ == "__main__":
    main([patch_test_3d, hertz_3d_quadratic, hertz_2d_quadratic, hertz_3d_quadratic_mpi, quadratic_output,
          resultant_load, resultant_load_mpi, quadratic_refusals])
