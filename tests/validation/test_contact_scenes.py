"""Validation of the contact scenes with the baseline plugin penalty-nts: Hertz 2D/3D against the closed forms of
docs/validation.md, the contact patch test, stick/slip of a block on a plane, momentum of the Franke-Hesch-Betsch
two-element impact, frame indifference and MPI equality. Usage: python3 test_contact_scenes.py CASE (CASES at the
bottom); exit code 0 when every check holds. Measured numbers are quoted in each check's docstring."""
import json
import math
import tempfile

from stickslip_results import Checks, run, main

NU = 0.3


def e_star(E1, E2, nu1=NU, nu2=NU):
    return 1.0 / ((1 - nu1 ** 2) / E1 + (1 - nu2 ** 2) / E2)


def fit_hertz_profile(points):
    """Least squares of p^2 = p0^2 (1 - r^2/a^2) (linear in r^2) over the active points [(r, p)]: (a, p0)."""
    sel = [(r * r, p * p) for r, p in points]
    n = len(sel)
    sx = sum(s[0] for s in sel)
    sy = sum(s[1] for s in sel)
    sxx = sum(s[0] ** 2 for s in sel)
    sxy = sum(s[0] * s[1] for s in sel)
    slope = (n * sxy - sx * sy) / (n * sxx - sx * sx)
    intercept = (sy - slope * sx) / n
    return math.sqrt(intercept / -slope), math.sqrt(intercept)


def reference_points(results, radial):
    """Contact points of the last step at their reference positions (Hertz theory is linear, the contact surface
    itself shrinks by ~(1 - 2 nu)(1 + nu) p/E = 3 % in x here): nodes and Gauss points alike (contact.csv's
    reference_x/_y/_z). Returns [(r, p, gap, node)], node -1 for a Gauss point. With the plugin's own contact state:
    a multiplier method closes an active point's gap up to round-off (+-1e-19 with nts-augmented and mortar-dual),
    whose sign must not decide whether the fit of hertz_profile.profile_errors (gap <= 0) takes the point; a
    penalty's active points have gap < 0 anyway."""
    out = []
    for p in results.contact_points():
        X = [p["reference_" + c] for c in "xyz"]
        r = math.hypot(X[0], X[1]) if radial else X[0]
        gap = min(p["gap"], 0.0) if p["state"] > 0 else p["gap"]
        out.append((r, p["pressure"], gap, int(p["node"])))
    return sorted(out)


def johnson_load(delta, E, Es, R=1.0, nu=NU):
    """Line load P of a cylinder whose centre approaches a rigid flat by delta (Johnson, Contact Mechanics 5.36):
    delta = 2 P (1 - nu^2)/(pi E) (ln(4 R / a) - 1/2), a = sqrt(4 P R / (pi E*)); solved by bisection."""
    def f(P):
        a = math.sqrt(4 * P * R / (math.pi * Es))
        return 2 * P * (1 - nu ** 2) / (math.pi * E) * (math.log(4 * R / a) - 0.5) - delta
    lo, hi = 1e-12, math.pi * Es * R / 4  # f increases on (0, hi]: a = R at hi
    for _ in range(300):
        mid = 0.5 * (lo + hi)
        if f(mid) > 0:
            hi = mid
        else:
            lo = mid
    return lo


def hertz_2d_errors(refine):
    results, _ = run("scenes/hertz-2d.yaml", "--set", "mesh.parameters.refine=%g" % refine, "--set", "output.vtu_every=4")
    E1, E2, d = 1000.0, 1.0e6, 0.016
    Es = e_star(E1, E2)
    last = results.rows[-1]
    P = 2 * abs(last["reaction_top_y"])
    a_exact = math.sqrt(4 * P / (math.pi * Es))
    p0_exact = 2 * P / (math.pi * a_exact)
    pts = reference_points(results, radial=False)
    active = [(r, p) for r, p, g, n in pts if p > 0]
    a_fit, p0_fit = fit_hertz_profile(active)
    # approach of the cylinder centre relative to its contact point: d minus the bottom node's displacement (the stiff
    # block's own compression and the penalty penetration, together 2e-5 = 0.13 % of d)
    bottom = [n for r, p, g, n in pts if abs(r) < 1e-12][0]
    delta = d + results.last_vtu()["displacement"][bottom][1]
    P_johnson = johnson_load(delta, E1, Es)
    return {
        "P": P, "a": (a_fit - a_exact) / a_exact, "p0": (p0_fit - p0_exact) / p0_exact,
        "p0_node": (pts[0][1] - p0_exact) / p0_exact, "P_delta": (P - P_johnson) / P_johnson,
        "balance": abs(2 * last["contact_force_y"] - P) / P, "active": len(active),
        "a_exact": a_exact, "p0_exact": p0_exact, "points": pts, "results": results,
    }


def hertz_2d(c):
    """Cylinder on a stiff block: a, p0 (least-squares fit of p^2 against x^2 over the active nodes) and the load P
    at the prescribed approach (Johnson) against the closed forms, refine 1, 2, 4 (h = 0.02, 0.01, 0.005 at contact).
    Measured (a, p0, P(delta) relative errors): refine 1: -1.64 %, +0.27 %, +0.27 %; refine 2: -0.80 %, +0.23 %,
    +0.045 %; refine 4: -0.43 %, +0.18 %, -0.055 % (P(delta) reaches the level of Hertz's own small-a/R assumptions,
    a/R = 0.1, after refine 2; it is checked to fall from the coarsest level and to be below 0.2 %)."""
    levels = (1, 2, 4)
    errors = [hertz_2d_errors(r) for r in levels]
    for r, e in zip(levels, errors):
        print("refine %g: P = %.6g, a = %.5g (exact %.5g), %d active nodes; errors a %+.3e, p0 %+.3e (peak node %+.3e), "
              "P(delta) %+.3e" % (r, e["P"], e["a_exact"] * (1 + e["a"]), e["a_exact"], e["active"], e["a"], e["p0"],
                                 e["p0_node"], e["P_delta"]))
        c.check(e["balance"] <= 1e-8, "refine %g: contact force = reaction at the top (%.1e)" % (r, e["balance"]))
    for key, bound in (("a", 0.01), ("p0", 0.005)):
        values = [abs(e[key]) for e in errors]
        c.check(all(values[k + 1] < values[k] for k in range(len(values) - 1)),
                "error of %s falls with refinement: %s" % (key, ", ".join("%.3e" % v for v in values)))
        c.check(values[-1] <= bound, "error of %s at refine %g: %.3e <= %g" % (key, levels[-1], values[-1], bound))
    values = [abs(e["P_delta"]) for e in errors]
    c.check(values[-1] < values[0] and values[1] < values[0],
            "error of P(delta) falls from the coarsest level: %s" % ", ".join("%.3e" % v for v in values))
    c.check(values[-1] <= 0.002, "error of P(delta) at refine %g: %.3e <= 0.002" % (levels[-1], values[-1]))
    c.check(abs(errors[-1]["p0_node"]) <= 0.01, "peak nodal pressure within 1 %% of p0: %+.3e" % errors[-1]["p0_node"])


def hertz_2d_rotated(c):
    """Frame indifference: the same problem rigidly rotated by 30 degrees about z (mesh and prescribed displacement).
    The symmetry rollers (u_x = 0) cannot be rotated component-wise, so both runs free them and hold the cylinder top
    in both directions. Measured: pressures equal to 8e-13, gaps to 6e-16 (relative to their maxima), |reactions| to
    1e-11. Inactive points far from the contact may differ in whether a master face lies within the (axis-aligned)
    search boxes: their gap is NaN in one frame and positive in the other; both are inactive."""
    theta, d = math.radians(30), 0.016
    common = ("--set", "boundary.2.displacement=[~, ~]")
    a, _ = run("scenes/hertz-2d.yaml", *common, "--set", "boundary.0.displacement=[0, %r]" % -d)
    b, _ = run("scenes/hertz-2d.yaml", *common,
               "--set", "boundary.0.displacement=[%r, %r]" % (d * math.sin(theta), -d * math.cos(theta)),
               "--set", "mesh.rotate={axis: [0, 0, 1], degrees: 30}")
    for name in ("top", "base"):
        ra = math.hypot(a.rows[-1]["reaction_%s_x" % name], a.rows[-1]["reaction_%s_y" % name])
        rb = math.hypot(b.rows[-1]["reaction_%s_x" % name], b.rows[-1]["reaction_%s_y" % name])
        c.check(abs(ra - rb) <= 1e-8 * ra, "|reaction %s| %.12g vs %.12g rotated (%.1e)" % (name, ra, rb,
                                                                                        abs(ra - rb) / ra))
    pa, pb = a.contact_points(), b.contact_points()
    c.check([p["node"] for p in pa] == [p["node"] for p in pb], "the same slave nodes are reported")
    pmax = max(p["pressure"] for p in pa)
    c.check(pmax > 0 and a.rows[-1]["active_points"] > 0, "contact is active (peak pressure %.4g)" % pmax)
    dp = max(abs(p["pressure"] - q["pressure"]) for p, q in zip(pa, pb)) / pmax
    c.check(dp <= 1e-8, "pressures unchanged by the rotation: %.1e relative" % dp)
    c.check(all(p["state"] == q["state"] for p, q in zip(pa, pb)), "contact states unchanged")
    both = [(p["gap"], q["gap"]) for p, q in zip(pa, pb) if not math.isnan(p["gap"]) and not math.isnan(q["gap"])]
    gmax = max(abs(g) for g, _ in both)
    dg = max(abs(g - h) for g, h in both) / gmax
    c.check(dg <= 1e-8, "gaps unchanged by the rotation: %.1e relative (%d points)" % (dg, len(both)))
    one_sided = [(p["gap"], q["gap"]) for p, q in zip(pa, pb) if math.isnan(p["gap"]) != math.isnan(q["gap"])]
    c.check(all((g if not math.isnan(g) else h) > 0 for g, h in one_sided),
            "points found in only one frame are separated (%d such points)" % len(one_sided))


def ghost_nodes(prefix, ranks):
    """The ghost nodes of each rank from the rank statistics (STICKSLIP_RANK_STATS=prefix, core/time/run.c)."""
    return [json.load(open("%s-%04d.json" % (prefix, r)))["nodes_ghost"] for r in range(ranks)]


def hertz_2d_mpi(c):
    """hertz-2d (refine 1) on 1 and 2 ranks: the same reactions and contact force to round-off; on 2 ranks with
    master faces ghosted by swept boxes (the default) and with the master surface replicated
    (STICKSLIP_MASTER_GHOSTING=replicated); the boxes hold fewer ghost nodes on every rank."""
    one, _ = run("scenes/hertz-2d.yaml")
    stats = tempfile.mkdtemp(prefix="stickslip-stats-")
    boxes, _ = run("scenes/hertz-2d.yaml", np=2, env={"STICKSLIP_RANK_STATS": stats + "/boxes"})
    two, _ = run("scenes/hertz-2d.yaml", np=2,
                 env={"STICKSLIP_RANK_STATS": stats + "/replicated", "STICKSLIP_MASTER_GHOSTING": "replicated"})
    for label, other in (("np 1 vs 2, master replicated", two), ("np 1 vs 2, master ghosted by boxes", boxes)):
        c.check(other.summary["ranks"] == 2, "%s: the second run used 2 ranks" % label)
        for name in ("reaction_top_y", "reaction_base_y", "reaction_base_x", "contact_force_y", "strain_energy"):
            a, b = one.column(name), other.column(name)
            scale = max(abs(v) for v in one.column("reaction_top_y")) if name != "strain_energy" else max(a)
            diff = max(abs(x - y) for x, y in zip(a, b)) / scale
            c.check(diff <= 1e-10, "%s: %s equal to %.1e relative" % (label, name, diff))
        c.check(one.column("active_points") == other.column("active_points"), "%s: same active point counts" % label)
    replicated, ghosted = ghost_nodes(stats + "/replicated", 2), ghost_nodes(stats + "/boxes", 2)
    c.check(all(g < r for g, r in zip(ghosted, replicated)),
            "ghost nodes per rank with master faces ghosted by boxes %s, fewer than replicated %s" % (ghosted, replicated))


def master_ghosting_renewed(c):
    """Master faces ghosted by swept boxes (the default) and ghosted again when the contact moves beyond them, on 2
    ranks, against the replicated master surface (STICKSLIP_MASTER_GHOSTING=replicated), direct solver:
    - ring-on-block (20 steps of 0.05): the ring comes down onto block faces beyond its rank's reach at set-up and
      they are ghosted again at step 6 (36 faces; refused there when the faces were set up once); also against the
      run on 1 rank. Measured: forces within 2.3e-12 of the largest contact force (2339), the same active points.
    - slider-2d (dt 0.2 to t = 2.8, mu = 0.3): a block pressed onto a base and dragged across it, ghosted again at
      steps 9, 12 and 14 while it slides, so the penalty-nts instances are re-created with their friction anchors
      from their records. Measured: forces within 1.2e-13 of the largest contact force (21.8) (8.9e-12 in another
      run), dissipated energy within 1.5e-14; its Newton iterations may differ in a step, as they do between 1 and 2
      ranks replicated."""
    ring = ("scenes/ring-on-block.yaml", "--set", "time.dt=0.05")
    slider = ("tests/bench/stress/scenes/slider-2d.yaml", "--set", "time.dt=0.2", "--set", "time.end=2.8")
    forces = {"ring": ("contact_force_x", "contact_force_y", "reaction_ends_x", "reaction_ends_y", "reaction_base_y"),
              "slider": ("contact_force_x", "contact_force_y", "reaction_drag_x", "reaction_fixed_x",
                         "reaction_fixed_y")}
    for name, args, ghosted_at in (("ring", ring, 6), ("slider", slider, 9)):
        boxes, proc = run(*args, "--verbose", np=2)
        replicated, _ = run(*args, np=2, env={"STICKSLIP_MASTER_GHOSTING": "replicated"})
        others = [("boxes vs replicated on 2 ranks", replicated)]
        if name == "ring":
            others.append(("boxes on 2 ranks vs 1 rank", run(*args)[0]))
        c.check(boxes.summary["master_reghosts"] >= 1 and replicated.summary["master_reghosts"] == 0,
                "%s: ghosted again at %d step(s) with boxes, none replicated" % (name, boxes.summary["master_reghosts"]))
        c.check(("step %d: " % ghosted_at) in proc.stderr and "ghosted again" in proc.stderr,
                "%s: the first re-ghosting at step %d (--verbose)" % (name, ghosted_at))
        scale = max(abs(v) for v in replicated.column("contact_force_y"))
        c.check(scale > 0, "%s: in contact (largest contact force %g)" % (name, scale))
        for label, other in others:
            c.check(len(boxes.rows) == len(other.rows), "%s, %s: the same steps" % (name, label))
            for column in forces[name]:
                diff = max(abs(x - y) for x, y in zip(boxes.column(column), other.column(column))) / scale
                c.check(diff <= 1e-10, "%s, %s: %s equal to %.1e of the largest contact force"
                        % (name, label, column, diff))
            if name == "slider":
                a, b = boxes.column("dissipated_energy"), other.column("dissipated_energy")
                diff = max(abs(x - y) for x, y in zip(a, b)) / max(abs(v) for v in b)
                c.check(diff <= 1e-10, "%s, %s: dissipated energy equal to %.1e relative" % (name, label, diff))
            c.check(boxes.column("active_points") == other.column("active_points"),
                    "%s, %s: the same active points" % (name, label))


def hertz_3d_errors(refine):
    results, _ = run("scenes/hertz-3d.yaml", "--set", "mesh.parameters.refine=%g" % refine)
    Es, d = e_star(1000.0, 1.0e6), 0.02
    F = 4 * abs(results.rows[-1]["reaction_top_z"])
    a_exact = (3 * F / (4 * Es)) ** (1.0 / 3.0)
    p0_exact = 3 * F / (2 * math.pi * a_exact ** 2)
    pts = reference_points(results, radial=True)
    active = [(r, p) for r, p, g, n in pts if p > 0]
    a_fit, p0_fit = fit_hertz_profile(active)
    delta = d + results.last_vtu()["displacement"][pts[0][3]][2]
    F_delta = 4.0 / 3.0 * Es * delta ** 1.5
    return {"F": F, "a": (a_fit - a_exact) / a_exact, "p0": (p0_fit - p0_exact) / p0_exact,
            "F_delta": (F - F_delta) / F_delta, "active": len(active), "a_exact": a_exact,
            "balance": abs(4 * results.rows[-1]["contact_force_z"] - F) / F}


def hertz_3d(c):
    """Sphere on a stiff block, quarter model, tet4. The mesh is coarse (h_contact = 0.05 against a = 0.15; refine 2
    costs 17 s and does not improve a and p0 monotonically on these unstructured tets), so a and p0 are checked at one
    level with bounds: measured a -2.3 %, p0 +1.2 % (refine 1), -0.06 % / +2.6 % (refine 1.5), -1.1 % / +3.0 %
    (refine 2). F against the approach of the sphere's centre: +23 % (1), +14 % (1.5), +12 % (2): it falls, towards
    the compression of the whole sphere that Hertz's delta leaves out (order (4/3) a/R); checked to fall from refine
    1 to 1.5 and to be below 25 %."""
    errors = {r: hertz_3d_errors(r) for r in (1, 1.5)}
    for r, e in errors.items():
        print("refine %g: F = %.6g, a = %.4g, %d active nodes; errors a %+.3e, p0 %+.3e, F(delta) %+.3e"
              % (r, e["F"], e["a_exact"], e["active"], e["a"], e["p0"], e["F_delta"]))
        c.check(e["balance"] <= 1e-8, "refine %g: contact force = reaction at the top (%.1e)" % (r, e["balance"]))
        c.check(abs(e["a"]) <= 0.04, "refine %g: contact radius within 4 %%: %+.3e" % (r, e["a"]))
        c.check(abs(e["p0"]) <= 0.04, "refine %g: peak pressure (fit) within 4 %%: %+.3e" % (r, e["p0"]))
        c.check(e["active"] >= 10, "refine %g: %d active nodes" % (r, e["active"]))
    c.check(abs(errors[1.5]["F_delta"]) < abs(errors[1]["F_delta"]) and abs(errors[1.5]["F_delta"]) <= 0.25,
            "F(delta) error falls: %+.3e -> %+.3e (<= 25 %%)" % (errors[1]["F_delta"], errors[1.5]["F_delta"]))


def patch_test_2d(c):
    """Taylor-Papadopoulos patch test with one-pass NTS: the total force is exact, the nodal pressures are not.
    Measured max relative deviation from p = 10: 7.66 % (refine 1, 9.23 ... 10.21), 7.51 % (refine 2). Refine 3 and 4
    (15 vs 12, 20 vs 16 elements) put slave nodes exactly over master nodes, where the master kinks under load; they
    converge since penalty-nts keeps a step's master face selection with hysteresis (docs/plugins/penalty-nts.md)."""
    p = 10.0
    for refine in (1, 2, 3, 4):
        results, _ = run("scenes/patch-test-2d.yaml", "--set", "mesh.parameters.refine=%d" % refine)
        last = results.rows[-1]
        c.check(abs(last["contact_force_y"] - p) <= 1e-10 * p,
                "refine %d: total contact force %.15g = p * width" % (refine, last["contact_force_y"]))
        c.check(abs(last["reaction_base_y"] - p) <= 1e-10 * p,
                "refine %d: base reaction %.15g = p * width" % (refine, last["reaction_base_y"]))
        pressures = [q["pressure"] for q in results.contact_points()]
        c.check(all(q["state"] == 1 for q in results.contact_points()), "refine %d: every slave node in contact" % refine)
        deviation = max(abs(q - p) for q in pressures) / p
        print("refine %d: nodal pressures %.4f ... %.4f, max relative deviation %.3e" % (refine, min(pressures),
                                                                                         max(pressures), deviation))
        c.check(deviation <= 0.10, "refine %d: NTS patch-test error %.2f %% <= 10 %%" % (refine, 100 * deviation))


def block_on_plane(c):
    """Stick, then slip at F_t/F_n = mu. Measured: 9 stick points to t = 1.2 (F_t/F_n = 0.153), partial slip from
    t = 1.25, full slip from t = 1.5 with F_t/F_n = 0.3 to ~1e-15, F_n = 9.99."""
    results, _ = run("scenes/block-on-plane.yaml")
    mu = 0.3
    rows = results.rows[1:]
    press = [r for r in rows if r["time"] <= 1.0 + 1e-12]
    early = [r for r in rows if 1.0 < r["time"] <= 1.2 + 1e-12]
    c.check(all(r["stick_points"] > 0 and r["slip_points"] == 0 for r in press + early),
            "pressing and the first sideways steps stick (%d steps, no slip points)" % len(press + early))
    c.check(all(abs(r["reaction_shear_x"]) < mu * abs(r["reaction_press_y"]) for r in press + early),
            "while sticking |F_t| < mu F_n (largest ratio %.4f)"
            % max(abs(r["reaction_shear_x"]) / abs(r["reaction_press_y"]) for r in press + early))
    c.check(max(abs(r["reaction_shear_x"]) for r in early) > 0.1, "the stuck block carries a tangential load")
    slip = [r for r in rows if r["slip_points"] == r["active_points"] and r["active_points"] > 0]
    c.check(len(slip) >= 10, "the whole base slides in %d steps" % len(slip))
    worst = max(abs(abs(r["reaction_shear_x"] / r["reaction_press_y"]) - mu) for r in slip)
    c.check(worst <= 1e-3, "in full slip F_t/F_n = mu to %.1e (<= 1e-3)" % worst)
    c.check(slip[-1]["time"] == rows[-1]["time"], "it slides to the end")
    balance = max(abs(r["contact_force_x"] + r["reaction_shear_x"]) + abs(r["contact_force_y"] + r["reaction_press_y"])
                  for r in rows)
    c.check(balance <= 1e-8, "contact force = -(reaction at the top) (%.1e)" % balance)
    c.check(results.rows[-1]["dissipated_energy"] > 0, "slip dissipates energy")


def two_elements(c, *args):
    results, proc = run("scenes/two-elements-penalty.yaml", *args)
    rows = results.rows
    first = rows[0]
    for name, value in (("momentum_x", 0.0), ("momentum_y", 100.0), ("momentum_z", -40.0)):
        c.check(abs(first[name] - value) <= 1e-12 * 100, "Table I: initial %s = %.15g" % (name, first[name]))
    scale = math.sqrt(100.0 ** 2 + 40.0 ** 2)
    drift = max(math.sqrt(sum((r["momentum_" + k] - first["momentum_" + k]) ** 2 for k in "xyz")) for r in rows)
    c.check(drift <= 1e-10 * scale, "linear momentum [0, 100, -40] constant through contact: %.1e relative"
            % (drift / scale))
    contact = [r for r in rows if r["active_points"] > 0 and abs(r["contact_force_z"]) > 0]
    c.check(len(contact) > 0, "contact forces present in %d steps (peak %.4g)"
            % (len(contact), max([abs(r["contact_force_z"]) for r in contact] or [0])))
    c.check(results.summary["final_time"] >= 6 - 1e-9, "the run reaches t = 6")
    c.check("not energy-consistent" in proc.stderr, "the driver warns that energy is not conserved")
    return results


def two_elements_penalty(c):
    """Frictionless. Measured: momentum drift 4e-16 relative; contact t = 2.5 ... 4.0 (4 points, peak force 56);
    energy 5.8 -> 5.74 (not conserved, as expected)."""
    two_elements(c)


def two_elements_penalty_friction(c):
    """mu = 0.3, eps_T = 1e4: momentum still exact (equal and opposite tangential forces)."""
    results = two_elements(c, "--set", "contact.0.parameters.mu=0.3", "--set",
                           "contact.0.parameters.penalty_tangential=1e4")
    c.check(max(r["stick_points"] + r["slip_points"] for r in results.rows) > 0, "frictional points recorded")


def newton_predicted_update(c):
    """`solver.newton.predicted_update: true` accepts the Newton update predicted from the residual's decrease
    (docs/hertz.md, "Newton iterations"; off by default): on the 3D Hertz tet4, refine 1, with the default penalty (a
    user's scene sets none), 14 Newton iterations (5, 3, 3, 3) against 17 (5, 4, 4, 4) with the default confirming
    solve, and the same load: |reaction_top_z| 1.20066870003 both, relative difference 9.6e-15 measured (bound 1e-12:
    the accepted iterates differ by the last iteration's correction, whose residual is already at round-off; the
    absolute tolerance 1e-9 would allow 1e-9). The counts are checked to +-1: a confirming iteration saved or not
    depends on where ||F|| lands against the tolerances, which another BLAS or MUMPS build can move by one."""
    default_penalty = ("--replace", "contact.0.parameters={area_weighted: 1}")
    runs = {}
    for label, extra in (("predicted", ("--set", "solver.newton.predicted_update=true")), ("default", ())):
        results, _ = run("scenes/hertz-3d.yaml", *default_penalty, *extra)
        runs[label] = (int(results.summary["newton_iterations"]), abs(results.rows[-1]["reaction_top_z"]))
        print("%s: %d Newton iterations (%s), |reaction_top_z| = %.15g" % (
            label, runs[label][0], ", ".join("%d" % r["newton_iterations"] for r in results.rows[1:]), runs[label][1]))
    new, old = runs["predicted"], runs["default"]
    c.check(abs(new[0] - 14) <= 1 and abs(old[0] - 17) <= 1,
            "Newton iterations %d (predicted update) and %d (default, confirming solve): measured 14 and 17, +-1" % (
                new[0], old[0]))
    c.check(new[0] < old[0], "the predicted update takes fewer iterations: %d < %d" % (new[0], old[0]))
    difference = abs(new[1] - old[1]) / old[1]
    c.check(difference <= 1e-12, "the same load to the Newton tolerance: %.1e relative <= 1e-12" % difference)

if __name__ == "__main__":
    main([hertz_2d, hertz_2d_rotated, hertz_2d_mpi, master_ghosting_renewed, hertz_3d, patch_test_2d, block_on_plane,
          two_elements_penalty, two_elements_penalty_friction, newton_predicted_update])
