"""Validation of the corotational body plugin (Hauret, Salomon, Weiss & Wohlmuth) through the driver: the paper's
scenes (scenes/corot-*.yaml) against the paper's statements, and the measured causes where we differ
(docs/plugins/corotational.md, "Against the paper"). history.csv's energies are the scheme's (ABI 2.5: the plugin
reports 1/2 s.Ms + 1/2 u.Su); the plugin's per-step --verbose line adds theta, theta', J and the terms of the J balance.
Usage: python3 test_corot_scenes.py CASE (see the cases at the bottom); exit code 0 when every check holds."""
import math
import re

from stickslip_results import Checks, run, main

LINE = re.compile(r"^corotational: step (\d+) t (\S+) theta (\S+) w (\S+) E (\S+) J (\S+) friction (\S+) "
                  r"g/g_ref (\S+) w-updates (\d+) impulse (\S+) defect (\S+) centre (\S+) (\S+) (\S+)")
KEYS = ("step", "t", "theta", "w", "E", "J", "friction", "g", "updates", "impulse", "defect", "x", "y", "z")
TOLERANCE = 1e-12  # the plugin's default rotation tolerance: Model 1's energy error per step <= 4 TOLERANCE E
# The J balance J^{n+1} - J^n = impulse + defect through the driver, relative to J0: it holds to the rotation
# tolerance (2 tol I_e omega_ref) and the Newton residual of the body rows; measured 1.2e-13 ... 5.6e-13 on the balls,
# 2.7e-12 on the torus.
J_BOUND = 1e-11


def steps(proc):
    """The plugin's per-step records (dicts of KEYS)."""
    return [{k: float(v) for k, v in zip(KEYS, m.groups())} for m in map(LINE.match, proc.stderr.splitlines()) if m]


def simulate(c, scene, *args):
    res, proc = run(scene, "--verbose", *args)
    rows = steps(proc)
    c.check(len(rows) == len(res.rows) - 1, "%s: one plugin record per step (%d)" % (scene, len(rows)))
    return res, rows


def energy_balance(c, res, rows, friction, step_bound=4 * TOLERANCE):
    """The scheme's energy (Lemma 2.1): E^{n+1} - E^n = -(friction work of the step) within the rotation tolerance
    (4 tol E0 per step; through the driver Model 2's identity holds to the same bound, measured 1.1e-12 E0), never
    an increase. history.csv carries that energy (ABI 2.5): its total_energy is the plugin's E at every step, and
    total_energy + dissipated_energy stays at its first row's value to the same bound over the run (issue 35, item
    10: it was the host's SVK energy of the world displacement, which drifts by 1.5e-2 on the 6.3 ball). Where the
    Newton tolerance of the body rows rather than the rotation tolerance limits a step, the caller gives step_bound."""
    E0 = res.rows[0]["total_energy"]
    bound = step_bound * E0
    balance = max(abs(b["E"] - a["E"] + b["friction"]) for a, b in zip(rows, rows[1:]))
    c.check(balance <= bound, "energy balance E^{n+1} - E^n + dt sum D s.lambda: %.2e <= %.1e" % (balance, bound))
    increase = max(b["E"] - a["E"] for a, b in zip(rows, rows[1:]))
    c.check(increase <= bound, "the energy never increases: largest step increase %.2e <= %.1e" % (increase, bound))
    same = max(abs(h["total_energy"] - r["E"]) for h, r in zip(res.rows[1:], rows)) / E0
    c.check(same <= 1e-15, "history.csv's total_energy is the scheme's E (%.1e)" % same)
    drift = max(abs(h["total_energy"] + h["dissipated_energy"] - E0) for h in res.rows) / E0
    c.check(drift <= len(rows) * step_bound, "history.csv: total_energy + dissipated_energy constant to %.1e of "
            "E0 = %.6g over %d steps (bound %.1e; material_total_energy moves by %.1e)"
            % (drift, E0, len(rows), len(rows) * step_bound,
               max(abs(h["material_total_energy"] - res.rows[0]["material_total_energy"]) for h in res.rows) / E0))
    if not friction:
        work = max(abs(r["friction"]) for r in rows)
        c.check(work <= 1e-12 * E0, "frictionless: no work on the contact (%.1e of E0)" % (work / E0))
        # dissipated_energy is friction work for every plugin (docs/user-guide.md): without friction it is round-off
        # (measured 6.5e-18 E0 on the 6.3 ball; it was 4.1e-13 while the column also summed the normal work)
        dissipated = max(abs(h["dissipated_energy"]) for h in res.rows) / E0
        c.check(dissipated <= 1e-15, "frictionless: history.csv's dissipated_energy is round-off (%.1e of E0)"
                % dissipated)


def momentum_balance(c, rows, model):
    """Lemma 2.2 discrete: J^{n+1} - J^n = dt (f - D lambda) . Pi r_h for Model 1. Model 2's lever arm x + T(u) leaves
    Sec. 2.4's defect -w c . Pi (u^{n+1} - u^n): with it the balance holds too, and the defect is what keeps Model 2's
    J from being conserved (Fig. 6.3, middle)."""
    J0 = abs(rows[0]["J"])
    balance = max(abs(b["J"] - a["J"] - b["impulse"] - b["defect"]) for a, b in zip(rows, rows[1:])) / J0
    c.check(balance <= J_BOUND, "J^{n+1} - J^n = impulse%s: %.2e <= %.0e of J0" % (
        " + defect" if model == 2 else "", balance, J_BOUND))
    defect = max(abs(r["defect"]) for r in rows) / J0
    if model == 1:
        c.check(defect == 0.0, "Model 1: no defect")
    else:
        c.check(defect > 1e3 * J_BOUND, "Model 2 does not conserve J: the largest step defect %.2e of J0 is far above "
                "the balance's accuracy" % defect)


def contact_steps(res):
    return [int(r["step"]) for r in res.rows if r["active_points"] > 0]


def episodes(res, column_prefix="reaction_"):
    """Contact episodes [(first step, last step, obstacles touched)] from the per-obstacle reaction columns."""
    names = sorted({k[len(column_prefix):-2] for k in res.rows[0] if k.startswith(column_prefix) and k[-2:] == "_y"})
    out = []
    for r in res.rows[1:]:
        if r["active_points"] == 0:
            continue
        touched = {n for n in names if abs(r[column_prefix + n + "_y"]) > 0}
        step = int(r["step"])
        if out and out[-1][1] == step - 1:
            out[-1] = (out[-1][0], step, out[-1][2] | touched)
        else:
            out.append((step, step, touched))
    return out


def after_contact(iterations, contact):
    return iterations[contact[-1]:]


def ball_on_plane(c, model=1, friction=False, strategy="monolithic"):
    """Sec. 6.3. The gap 0.5 closes at t = 0.0125, inside step 7; the switch (3.5) reads the gap at t_n, so the
    constraint acts from step 8. The paper: one Newton iteration per step before contact, two for most steps after it
    (Fig. 6.5; the scene's predicted_update, see the scene); energy exact (frictionless) or decreasing (friction);
    Model 1's J consistent, Model 2's not; with friction the spin reverses."""
    scene = "scenes/corot-ball-on-plane%s.yaml" % ("-friction" if friction else "")
    res, rows = simulate(c, scene, "--set", "bodies.0.parameters.model=%d" % model, "--set",
                         "bodies.0.strategy=%s" % strategy)
    iterations = [int(r["newton_iterations"]) for r in res.rows[1:]]
    contact = contact_steps(res)
    c.check(contact and contact[0] == 8, "contact from step 8 (the gap closes in step 7): steps %s" % contact)
    c.check(all(i == 1 for i in iterations[:7]),
            "one Newton iteration per step before contact (the paper: 1): %s" % iterations[:7])
    after = after_contact(iterations, contact)
    print("  Newton iterations during contact %s, after %s" % (iterations[7:contact[-1]], after))
    if strategy == "monolithic":
        c.check(after.count(2) > len(after) / 2 and max(after) <= 3,
                "after contact two Newton iterations for most steps (the paper: 2 for most): %d of %d, at most %d"
                % (after.count(2), len(after), max(after)))
    energy_balance(c, res, rows, friction)
    momentum_balance(c, rows, model)
    if friction:
        c.check(rows[-1]["w"] < 0 < rows[0]["w"], "friction reverses the spin: theta' %.4g -> %.4g"
                % (rows[0]["w"], rows[-1]["w"]))
    return res, rows


def corot_ball_on_plane_model1(c):
    ball_on_plane(c, 1)


def corot_ball_on_plane_model2(c):
    ball_on_plane(c, 2)


def spin_rate(res, v0_x, omega0):
    """A run's rotation rate about its centre of mass at the last step, J_c / I: J_c = J - x_c x P, the centre moved
    by the momenta (midpoint rule, mass P_x(0) / v0_x) from the origin, and I = J(0) / omega0 (the run starts as a
    rigid spin omega0 about its centre at the origin)."""
    rows = res.rows
    mass = rows[0]["momentum_x"] / v0_x
    centre = [0.0, 0.0]
    for a, b in zip(rows, rows[1:]):
        for i, key in enumerate(("momentum_x", "momentum_y")):
            centre[i] += b["dt"] * (a[key] + b[key]) / (2 * mass)
    last = rows[-1]
    j_centre = last["angular_momentum_z"] - (centre[0] * last["momentum_y"] - centre[1] * last["momentum_x"])
    return j_centre * omega0 / rows[0]["angular_momentum_z"]


def corot_ball_on_plane_friction_model1(c):
    """Also Fig. 6.8: the paper sees a slightly larger rotation rate after contact with its standard nonlinear scheme
    than with the co-rotational ones. At the paper's dt 0.002 Model 1's rate is one sample of a step function of the
    touch's place in the step grid (the switch (3.5) reads the gap at t_n): -1.086 here, -0.66 ... -1.30 with the plane
    moved by 0.04 ... 0.16, where the comparison scheme (SVK midpoint, penalty-nts friction) stays within -0.855 ...
    -0.871. Both converge as dt -> 0 (Model 1 -0.840, -0.833 at dt 1.25e-4, 6.25e-5; nonlinear -0.897, -0.897), so the
    comparison is made at dt 0.00025, where the plane's place moves Model 1 within -0.848 ... -0.881 and the nonlinear
    within -0.895 ... -0.897 (docs/plugins/corotational.md, Against the paper; paper_cases.py friction)."""
    corot, rows = ball_on_plane(c, 1, True)
    w_scene = spin_rate(corot, 40.0, rows[0]["w"])
    # the two differ by the disk's deformation in I (measured 2.9e-4)
    c.check(abs(w_scene - rows[-1]["w"]) <= 1e-3 * abs(rows[-1]["w"]),
            "the rate from the momenta, %.5f, is Model 1's w %.5f" % (w_scene, rows[-1]["w"]))
    fine = ("--set", "time.dt=0.00025")
    corot, _ = run("scenes/corot-ball-on-plane-friction.yaml", *fine)
    nonlinear, _ = run("scenes/corot-ball-on-plane-nonlinear.yaml", "--set", "contact.0.parameters.mu=0.2", *fine)
    w_corot, w_nonlinear = spin_rate(corot, 40.0, rows[0]["w"]), spin_rate(nonlinear, 40.0, rows[0]["w"])
    excess = w_nonlinear / w_corot - 1
    print("  theta' after contact at dt 0.00025: Model 1 %.4f, nonlinear %.4f (%+.1f %%)"
          % (w_corot, w_nonlinear, 100 * excess))
    # measured -0.8634 and -0.8967: the nonlinear rate 3.9 % larger (1.8 % ... 5.7 % over the plane's places above,
    # 6.7 % at dt 1.25e-4); "slightly larger" read as 1 % ... 10 %
    c.check(w_nonlinear < w_corot < 0 and 0.01 < excess < 0.1,
            "Fig. 6.8: the nonlinear scheme's rate after contact %.4f slightly larger than Model 1's %.4f (%.1f %%)"
            % (w_nonlinear, w_corot, 100 * excess))


def corot_ball_on_plane_friction_model2(c):
    ball_on_plane(c, 2, True)


def corot_ball_on_plane_friction_nested(c):
    """The paper's outer Newton on w (strategy nested: w eliminated, solve_again in recover). Its w update lags the
    host's step by one iteration (docs/plugins/corotational.md §8.3, item 4): 3 iterations after contact, not 2."""
    ball_on_plane(c, 1, True, "nested")


def corot_ball_on_plane_friction_dual(c):
    """Strategy dual: nested, with lambda condensed on the assembled operator by the host (stickslip.condense)."""
    ball_on_plane(c, 1, True, "dual")


def corot_newton_vs_nonlinear(c):
    """Fig. 6.5: co-rotational against the nonlinear SVK midpoint scheme. The paper: before contact 1 against 3, after
    it 2 for most steps against 3 or 4; during contact the linearised-r scheme (Model 2) needs fewer than Model 1.
    Before contact the comparison scheme takes 2, not 3 (the scene's predictor and tolerance: the first solve reaches
    the residual's round-off, 1.8e-8 from 7e-3): printed, not asserted (docs/plugins/corotational.md, Against the
    paper)."""
    corot, _ = simulate(c, "scenes/corot-ball-on-plane.yaml")
    linear_r, _ = simulate(c, "scenes/corot-ball-on-plane.yaml", "--set", "bodies.0.parameters.model=2")
    nonlinear, _ = run("scenes/corot-ball-on-plane-nonlinear.yaml")
    a, m2, b = ([int(r["newton_iterations"]) for r in x.rows[1:]] for x in (corot, linear_r, nonlinear))
    contact = contact_steps(corot)
    last = contact[-1]
    print("  co-rotational %s (total %d), linearised r %s (%d), nonlinear %s (%d)"
          % (a, sum(a), m2, sum(m2), b, sum(b)))
    c.check(max(a[:7]) == 1 and max(m2[:7]) == 1, "before contact: co-rotational 1 (the paper: 1): %s, %s"
            % (a[:7], m2[:7]))
    c.check(min(b[last:]) >= 3 and max(b[last:]) <= 4, "after contact: nonlinear 3 or 4 (the paper: 3 or 4): %s"
            % b[last:])
    c.check(a[last:].count(2) > len(a[last:]) / 2, "after contact: co-rotational 2 for most steps (the paper): %s"
            % a[last:])
    during = slice(contact[0] - 1, last)
    c.check(sum(m2[during]) < sum(a[during]), "during contact the linearised-r scheme needs fewer iterations (the "
            "paper: 'performs much better'): %d < %d" % (sum(m2[during]), sum(a[during])))


def restitution(c, dt):
    """The vertical velocity after the ball's first impact on the lower plane over the one before it."""
    res, _ = run("scenes/corot-ball-two-planes.yaml", "--set", "time.dt=%r" % dt, "--set", "time.end=0.012",
                 "--set", "output.vtu_every=0")
    before, after = res.rows[0]["momentum_y"], res.rows[-1]["momentum_y"]
    c.check(res.rows[-1]["active_points"] == 0 and after > 0, "dt %g: the ball left the lower plane by t = 0.012" % dt)
    return -after / before


def corot_ball_two_planes(c):
    """Sec. 6.4 at the paper's data (dt 0.001, Model 1): the ball meets both planes in turn, from step 4 (the gap 0.1
    closes at t = 0.0025); friction turns the spin around; energy and J balances. The paper shows five contacts by
    its last frame (t = 0.095); at dt 0.001 we count four by t = 0.1 (printed). The cause, asserted below: the first
    impact, resolved by the switch (3.5) a step after the touch, leaves part of the vertical momentum in the disk's
    vibrations, less as dt falls (restitution measured 0.80, 0.93, 0.97 at dt 0.001, 0.0005, 0.00025; five contacts
    by t = 0.1 at 0.0005, six at 0.00025; the rigid ball would have seven). The count at dt 0.001 hangs on the mesh,
    which the paper does not give (its Fig. 6.9 only draws it): of ten O-grids (refine 0.25 ... 0.75, n 6 ... 12,
    n_radial 2 ... 6) two give the paper's five contacts by t = 0.1, and n_radial 2 (32 rim nodes, 2 element rows in
    the rim patches) also its frame times t = 0.07 and 0.095 (contacts from t = 0.004, 0.027, 0.049, 0.071, 0.095),
    asserted below: the paper's count is reached on a mesh the paper may have used, not a property of dt 0.001."""
    res, rows = simulate(c, "scenes/corot-ball-two-planes.yaml")
    touches = episodes(res)
    print("  contact episodes (first step, last step, planes): %s" % touches)
    c.check(touches and touches[0][0] == 4 and touches[0][2] == {"lower"},
            "the first contact, on the lower plane, acts from step 4 (gap 0.1 / 40 = 0.0025)")
    c.check(all(len(e[2]) == 1 for e in touches) and all(a[2] != b[2] for a, b in zip(touches, touches[1:])),
            "the contacts alternate between the planes: %s" % [sorted(e[2])[0] for e in touches])
    energy_balance(c, res, rows, True)
    momentum_balance(c, rows, 1)
    c.check(min(r["w"] for r in rows) < 0, "friction turns the spin around: min theta' %.3g" % min(r["w"] for r in rows))
    e = [restitution(c, dt) for dt in (0.001, 0.0005, 0.00025)]
    c.check(e[0] < e[1] < e[2] < 1, "the first impact's vertical restitution rises towards the rigid ball's 1 as dt "
            "falls: %.3f, %.3f, %.3f at dt 0.001, 0.0005, 0.00025" % tuple(e))
    coarse, _ = run("scenes/corot-ball-two-planes.yaml", "--set", "mesh.parameters.n_radial=2", "--set",
                    "output.vtu_every=0")
    five = episodes(coarse)
    print("  n_radial 2: contact episodes %s" % five)
    # the paper's frames t = 0.003, 0.022, 0.041, 0.07, 0.095 are not the contacts' first steps; the count and the
    # alternation are its statement ("all five contacts"), asserted exactly
    c.check(len(five) == 5 and all(len(e[2]) == 1 for e in five)
            and all(a[2] != b[2] for a, b in zip(five, five[1:])),
            "with 2 element rows in the rim patches (n_radial 2) the paper's five contacts by t = 0.1, alternating: %s"
            % [sorted(e[2])[0] for e in five])


def both_models(c, scene, end, *args):
    """Models 1 and 2 on a frictional scene to t = end, each with its energy and J balances: [(res, rows)] * 2."""
    runs = [simulate(c, scene, "--set", "time.end=%r" % end, "--set", "bodies.0.parameters.model=%d" % m, *args)
            for m in (1, 2)]
    for m, (res, rows) in zip((1, 2), runs):
        energy_balance(c, res, rows, True)
        momentum_balance(c, rows, m)
    return runs


def corot_ball_two_planes_models(c):
    """Figs. 6.11, 6.12: Models 1 and 2 on the ball between two planes, both energy-consistent (balances), identical
    while the ball spins freely (both keep the steady spin exactly), and close after the first impact. At dt 0.001 they
    part at the second contact (theta' 1.4 against 7.9 at t = 0.028); at dt 0.0005 they agree through the third
    (measured in docs/plugins/corotational.md, Against the paper): the difference of the lever arms is the co-rotated
    vibration u - T(u), which the impact's resolution sets. The centres' difference is first order in dt (below)."""
    (_, one), (_, two) = both_models(c, "scenes/corot-ball-two-planes.yaml", 0.024)
    free = [k for k, r in enumerate(one) if r["t"] <= 0.003 + 1e-12]
    d_free = max(max(abs(one[k][q] - two[k][q]) for q in ("theta", "x", "y")) for k in free)
    c.check(d_free <= 1e-12, "before the first contact Models 1 and 2 coincide (steady spin): %.1e" % d_free)
    dw = max(abs(a["w"] - b["w"]) / abs(a["w"]) for a, b in zip(one, two) if a["t"] >= 0.008)
    dx = max(max(abs(a["x"] - b["x"]), abs(a["y"] - b["y"])) for a, b in zip(one, two))
    print("  after the first impact: theta' differs by %.2e relative, the centre by %.2e (radius 1)" % (dw, dx))
    c.check(dw <= 0.02 and dx <= 1e-3, "similar after the first impact (the paper: similar results, small differences "
            "in the translation): theta' within 2 %% (%.2e), centre within 1e-3 of the radius (%.1e)" % (dw, dx))
    # The translation's difference is the discretisation's: to t = 0.02 (before the second contact) it halves with
    # dt (measured 2.48e-4, 1.23e-4, 6.2e-5 at dt 0.001, 0.0005, 0.00025), while theta' keeps 1.0 - 1.3 %.
    (_, one_half), (_, two_half) = both_models(c, "scenes/corot-ball-two-planes.yaml", 0.02, "--set", "time.dt=0.0005")

    def centre_gap(a_rows, b_rows):
        return max(max(abs(a["x"] - b["x"]), abs(a["y"] - b["y"])) for a, b in zip(a_rows, b_rows) if a["t"] <= 0.02)
    coarse, fine = centre_gap(one, two), centre_gap(one_half, two_half)
    c.check(fine <= 0.6 * coarse, "the models' centres differ by %.3e at dt 0.001 and %.3e at 0.0005 to t = 0.02: a "
            "first-order discretisation difference (ratio %.2f <= 0.6)" % (coarse, fine, fine / coarse))


def corot_ellipse_two_planes(c):
    """The ellipse (semi-axes 0.6 x 1, ours: the paper gives none): Models 1 and 2 coincide while it spins freely, then
    part for good, the paper's 'a small difference amplifies and a completely different behaviour occurs' (the paper
    sees it after the third and fourth contacts, we after the second: docs/plugins/corotational.md, Against the
    paper); both keep their energy balance."""
    (res1, one), (_, two) = both_models(c, "scenes/corot-ellipse-two-planes.yaml", 0.1)
    touches = episodes(res1)
    print("  Model 1 contact episodes: %s" % touches)
    c.check(touches and touches[0][0] == 4, "the first contact acts from step 4 (the ball's gap 0.1)")

    def gap(t):
        k = min(range(len(one)), key=lambda i: abs(one[i]["t"] - t))
        return max(abs(one[k]["x"] - two[k]["x"]), abs(one[k]["y"] - two[k]["y"]))
    early, late = max(gap(t) for t in (0.001, 0.002, 0.003)), gap(0.1)
    print("  centre difference Model 1 - Model 2: %.1e (free flight), %.1e (t = 0.02), %.1e (t = 0.1)"
          % (early, gap(0.02), late))
    c.check(early <= 1e-12 and late >= 1e-2, "the models coincide in free flight (%.1e) and end apart (%.2e at t = 0.1)"
            % (early, late))


def corot_torus_on_plane(c):
    """Sec. 6.5, 3D, frictionless, to t = 0.25: the plane at 9 from the centre, the outer radius 8, V_y = -10: the
    touch at t = 0.1 acts from the step after it (the switch reads the gap at t_n; the rim is a polygon), energy and J
    balances, one iteration per step before contact."""
    res, rows = simulate(c, "scenes/corot-torus-on-plane.yaml", "--set", "time.end=0.25")
    iterations = [int(r["newton_iterations"]) for r in res.rows[1:]]
    contact = contact_steps(res)
    c.check(contact and 10 <= contact[0] - 1 <= 11, "the contact acts from t_n = %.2f (touch at t = 0.1, one step of "
            "resolution), ends at t = %.2f" % ((contact[0] - 1) * 0.01, contact[-1] * 0.01))
    c.check(all(i == 1 for i in iterations[:contact[0] - 1]),
            "one iteration per step before contact: %s" % iterations[:contact[0] - 1])
    # in 3D contact a step may stop with its body rows' residual near the absolute tolerance 1e-5 (which allows
    # dt 1e-5 |s|_2 / E0 ~ 3e-10 of E0) rather than at round-off: measured 4.4e-12 of E0 at step 21 (|g| 2.5e-15 g_ref)
    energy_balance(c, res, rows, False, step_bound=2e-11)
    momentum_balance(c, rows, 1)


def corot_free_flight_momentum(c):
    """The 6.3 ball in free flight (5 steps before the contact): the world linear momentum keeps its length to round-off
    but turns, each step by w dt - 2 atan(w dt / 2) (~ (w dt)^3 / 12): the frame turns by w dt (theta^{n+1} = theta^n
    + dt w), the co-rotated velocity s by the midpoint rule's Cayley angle 2 atan(w dt / 2) (docs/plugins/
    corotational.md, "Linear momentum"). Measured: the length to 7e-16, the angle to 1.4e-7 of the prediction."""
    res, rows = simulate(c, "scenes/corot-ball-on-plane.yaml", "--steps", "5")
    c.check(not contact_steps(res), "free flight: no contact in the 5 steps")
    p0 = (res.rows[0]["momentum_x"], res.rows[0]["momentum_y"])
    predicted, dt = 0.0, 0.002
    for row, record in zip(res.rows[1:], rows):
        predicted += record["w"] * dt - 2 * math.atan(record["w"] * dt / 2)
        p = (row["momentum_x"], row["momentum_y"])
        turn = math.atan2(p[1], p[0]) - math.atan2(p0[1], p0[0])
        c.check(abs(math.hypot(*p) / math.hypot(*p0) - 1) < 1e-14, "step %d: |p| kept (%.2e)" % (
            record["step"], math.hypot(*p) / math.hypot(*p0) - 1))
        c.check(predicted > 1e-9 and abs(turn / predicted - 1) < 1e-6, "step %d: p turned by %.6e, w dt - 2 atan(w dt "
                "/ 2) summed %.6e" % (record["step"], turn, predicted))


if __name__ == "__main__":
    main([corot_ball_on_plane_model1, corot_ball_on_plane_model2, corot_ball_on_plane_friction_model1,
          corot_ball_on_plane_friction_model2, corot_ball_on_plane_friction_nested, corot_ball_on_plane_friction_dual,
          corot_newton_vs_nonlinear, corot_ball_two_planes, corot_ball_two_planes_models, corot_ellipse_two_planes,
          corot_torus_on_plane, corot_free_flight_momentum])
