"""Hammer's examples (2012, ch. 8) with mortar-dual, run with the thesis's set-up where it states one (load steps,
Hammer's concentrated integration, his normal fields M and A, his nested active-set loop, the dual basis) and checked
against the thesis's values: 8.1 the simple benchmark (Tables 8.2/8.3, Figs 8.4/8.5, the stick/slip steps), 8.2 the
deep ironing, 8.3 Hertz, 8.4 the elastic ring. Where the thesis omits a dimension it is reconstructed from what the
thesis gives, or chosen and named; every difference to the thesis is explained in docs/plugins/mortar-dual.md,
"Against the paper". Usage: python3 test_mortar_thesis.py CASE; exit code 0 when every check holds."""
import math
import re
import statistics

from stickslip_results import run, main

HAMMER = "scenes/mortar-hammer-benchmark.yaml"
# the thesis's set-up: concentrated integration (6.5.2), the nested loop (Algorithm 1), dual basis (6.15); the coarse
# mesh (block 12 x 8, slab 20 x 6 cells) for CI
THESIS = ("--set", "contact.0.parameters.integration=concentrated", "--set", "contact.0.parameters.active_set=nested",
          "--set", "contact.0.parameters.basis=dual")
COARSE = ("--set", "mesh.0.parameters.refine=0.5", "--set", "mesh.1.parameters.refine=0.5")


def newton_runs(stderr):
    """{step: [[||F|| after iteration 1, 2, ...] per Newton run]} from a --verbose run's stderr."""
    runs = {}
    for line in stderr.splitlines():
        m = re.match(r"\s*step (\d+) newton (\d+) \|F\| = (\S+)", line)
        if m:
            step, k, f = int(m.group(1)), int(m.group(2)), float(m.group(3))
            if k == 1 or step not in runs:
                runs.setdefault(step, []).append([])
            runs[step][-1].append(f)
    return runs


def orders(run_residuals):
    """Convergence orders p = log(r_k+1 / r_k) / log(r_k / r_k-1) over the residuals of one Newton run that lie above
    its round-off floor (ten times its last residual)."""
    floor = 10 * run_residuals[-1]
    r = [x for x in run_residuals if x > floor]
    return [math.log(r[k + 1] / r[k]) / math.log(r[k] / r[k - 1]) for k in range(1, len(r) - 1)]


def by_time(results):
    return {round(row["time"], 6): row for row in results.rows}


def same_curves(c, label, a, b, bound):
    """The reaction histories of two runs at their common times: the largest difference of F_x and F_y against each
    curve's span (max - min), checked against bound."""
    ra, rb = by_time(a), by_time(b)
    common = sorted(set(ra) & set(rb))
    for name in ("reaction_shear_x", "reaction_press_y"):
        values = [ra[t][name] for t in common]
        span = max(values) - min(values)
        diff = max(abs(ra[t][name] - rb[t][name]) for t in common)
        c.check(diff <= bound * span, "%s: %s of M and A differ by %.3g = %.1e of its span %.4g (%d common times)"
                % (label, name, diff, diff / span, span, len(common)))


def path_independent(c, label, results, bound):
    """Hammer 8.1's frictionless path independence: the reactions at t = 7 and 7.5 (moved right and back) against
    those at t = 1 and 0.5 (pressing), relative to the peak F_y, checked against bound."""
    rows = by_time(results)
    scale = max(abs(row["reaction_press_y"]) for row in results.rows)
    for a, b in ((1.0, 7.0), (0.5, 7.5)):
        for name in ("reaction_press_y", "reaction_shear_x"):
            diff = abs(rows[a][name] - rows[b][name]) / scale
            c.check(diff <= bound, "%s: t = %g vs %g: %s equal to %.1e of F_y" % (label, a, b, name, diff))


def mortar_hammer_thesis(c):
    """Hammer 8.1, frictionless, with the thesis's set-up (concentrated integration, nested loop, dual basis) and the
    previous increment as Newton's start (the thesis's first energies are those of a linearised step; from the
    prescribed boundary values alone the first iterate shears the block's top row by 67 % and Newton needs one to two
    iterations more: docs, "Against the paper"). Both normal fields, 80 steps.
    - Tables 8.2/8.3: every Newton run at steps 10, 17, 40, 57 takes at most 4 iterations (the thesis's 4; measured
      3, 4, 4, 4 in one run each) at quadratic order: p >= 1.8 wherever three residuals above the round-off floor
      exist (measured 2.1 - 2.2).
    - Fig. 8.4: M and A cannot be told apart: their reactions differ by at most 0.5 % of each curve's span (about a
      line's width in the plot; measured 2e-4 for F_x, 6e-6 for F_y).
    - Path independence ("identical"): step 70 equals step 10, 75 equals 5. With frozen_band 0 (a Gauss point that
      leaves its master face gets the face it now lies over, and Newton runs again) to round-off: measured 1.2e-15
      of F_y (M), 6e-16 (A); checked to 1e-12. The default frozen_band 0.1 keeps a point on its face's extension up to
      5 % of an edge beyond it (the frozen face, H 7.2.3), which is the whole difference at t = 7 (measured: 5.6e-5
      of F_y in F_y, 1.1e-4 in F_x, the band's measured effect, not the thesis's value); checked to 2e-4, so that a
      larger effect of the band shows. The band saves 51 of 383 Newton iterations (13 %).
    - The full mesh's first two steps, where the block meets the slab exactly, without a cut (the nested loop cycled
      there on round-off until a node on the border of two branches kept its own)."""
    results = {}
    for normal in ("M", "A"):
        results[normal], proc = run(HAMMER, *COARSE, *THESIS, "--set", "contact.0.parameters.normal=" + normal,
                                    "--set", "solver.newton.predictor=previous-increment", "--set",
                                    "output.vtu_every=0", "--verbose")
        r = results[normal]
        c.check(r.rows[-1]["time"] >= 8 - 1e-9 and r.summary["step_cuts"] == 0,
                "%s: 80 steps to t = 8 without a cut (%d cuts)" % (normal, r.summary["step_cuts"]))
        step_of = {round(row["time"], 6): int(row["step"]) for row in r.rows}
        runs = newton_runs(proc.stderr)
        measured = []
        for thesis_step in (10, 17, 40, 57):
            for residuals in runs.get(step_of[round(thesis_step / 10, 6)], []):
                p = orders(residuals)
                measured.append((thesis_step, len(residuals), ["%.2f" % x for x in p]))
                c.check(len(residuals) <= 4 and all(x >= 1.8 for x in p),
                        "%s: step %d: a Newton run of %d iterations, orders %s (residuals %s)"
                        % (normal, thesis_step, len(residuals), ["%.2f" % x for x in p],
                           ["%.1e" % x for x in residuals]))
        c.check(sum(len(m[2]) for m in measured) >= 3, "%s: orders measured in %s" % (normal, measured))
        path_independent(c, normal + ", frozen_band 0.1", r, 2e-4)
    same_curves(c, "Fig. 8.4", results["M"], results["A"], 5e-3)
    reselect, _ = run(HAMMER, *COARSE, *THESIS, "--set", "contact.0.parameters.normal=M", "--set",
                      "contact.0.parameters.frozen_band=0", "--set", "solver.newton.predictor=previous-increment",
                      "--set", "output.vtu_every=0")
    path_independent(c, "M, frozen_band 0", reselect, 1e-12)
    # The block meets the slab exactly at the end of step 1 (gap 1 mm, 1 mm per step): on the full mesh the nested loop
    # flipped its 25 touching nodes on the sign of round-off (g = z_n = 0), 10 outer loops per attempt, and the run
    # failed at t = 0.098 after 6 cuts; a node on the border of two branches keeps its own (mortar_ncp_branch_holds).
    full, _ = run(HAMMER, *THESIS, "--set", "contact.0.parameters.normal=M", "--set", "time.end=0.2",
                  "--set", "output.vtu_every=0")
    c.check(full.summary["step_cuts"] == 0 and abs(full.rows[-1]["time"] - 0.2) < 1e-9,
            "full mesh, the first two steps (touching at t = 0.1) without a cut (%d cuts, %d outer loops)"
            % (full.summary["step_cuts"], full.summary["active_set_loops"]))


def mortar_hammer_thesis_friction(c):
    """Hammer 8.1 with mu = 0.3 and the thesis's set-up, both normal fields, 80 steps (the reversal at step 40 is cut:
    the nested loop's frozen slip branch meets a slip that turns, docs, "Against the paper").
    - Stick while pressing (every node at t = 1); full slip first at step 17 (the thesis's "at time step 17 ... we
      change from stick to slip", measured: t = 1.7 with either field, refine 0.5 and 1).
    - After the reversal the nodes stick again and slip again moving left (thesis: from step 57; measured 52 here,
      54 on a slab of 140 instead of 200: the step depends on the unstated dimensions, docs).
    - F_x changes sign with the direction; its largest magnitude moving right exceeds that moving left (thesis:
      1440.56 and 1389.06 N, for its own dimensions; measured 2570 and 2507 N).
    - Fig. 8.5: M and A cannot be told apart: reactions differ by at most 0.5 % of each curve's span (measured 3e-4)."""
    results = {}
    for normal in ("M", "A"):
        results[normal], _ = run(HAMMER, *COARSE, *THESIS, "--set", "contact.0.parameters.normal=" + normal,
                                 "--set", "contact.0.parameters.mu=0.3", "--set", "output.vtu_every=0")
        r = results[normal]
        rows = by_time(r)
        c.check(r.rows[-1]["time"] >= 8 - 1e-9, "%s: 80 steps to t = 8" % normal)
        c.check(rows[1.0]["stick_points"] == rows[1.0]["active_points"] > 0,
                "%s: t = 1: all %d active nodes stick" % (normal, rows[1.0]["active_points"]))
        full = [t for t, row in sorted(rows.items()) if row["active_points"] > 0 and
                row["slip_points"] == row["active_points"]]
        right = min(t for t in full if 1.0 < t < 4.0)
        c.check(abs(right - 1.7) < 1e-9, "%s: full slip first at t = %g (thesis: step 17)" % (normal, right))
        c.check(rows[4.5]["stick_points"] > rows[4.5]["slip_points"], "%s: t = 4.5, after the reversal: %d stick, "
                "%d slip" % (normal, rows[4.5]["stick_points"], rows[4.5]["slip_points"]))
        left = [t for t in full if 4.5 < t < 7.0]
        c.check(bool(left), "%s: full slip again moving left from t = %s (thesis: step 57)"
                % (normal, left[0] if left else None))
        fx = r.column("reaction_shear_x")
        c.check(max(fx) > 0 > min(fx) and max(fx) > -min(fx),
                "%s: F_x %.1f moving right, %.1f moving left (thesis: 1440.56, 1389.06 for its dimensions)"
                % (normal, max(fx), min(fx)))
    same_curves(c, "Fig. 8.5", results["M"], results["A"], 5e-3)


HERTZ_2D = "scenes/mortar-hertz-2d.yaml"
HERTZ_2D_R = 69.565  # the scene's R: reconstructed from the thesis's F and b (the scene's header)
HERTZ_2D_F, HERTZ_2D_B = 206.44549, 0.5781716  # Hammer 2012, 8.3: the reaction at the approach 0.015 mm, and b(F)
# the block's height (width 140) reconstructed from the thesis's F: 200/242/250/280 mm give F = 211.28/206.41/205.51/
# 202.3 N/mm at the approach 0.015 mm (tests/bench/mortar-dual/thesis.py --hertz); 1 mm of height moves F by 0.06 %
HERTZ_2D_H = 242


def hertz_2d_profile(results, E=96000.0, nu=0.35, R=HERTZ_2D_R):
    """F (both halves), the Hertz half-width b and peak p0 for that load (thesis 8.1-8.4), the relative l2 error of
    the slave pressures against p0 sqrt(1 - x^2/b^2) over |x| < 1.25 b, and the active points."""
    F = 2 * abs(results.rows[-1]["reaction_top_y"])
    delta = (1 - nu * nu) / (E * math.pi)
    b = 2 * math.sqrt(F * 2 * delta * R)
    p0 = 2 * F / (math.pi * b)
    points = [p for p in results.contact_points() if abs(p["x"]) < 1.25 * b]
    exact = [p0 * math.sqrt(max(1 - p["x"] ** 2 / b ** 2, 0.0)) for p in points]
    l2 = math.sqrt(sum((p["pressure"] - e) ** 2 for p, e in zip(points, exact)) / sum(e * e for e in exact))
    active = [p for p in results.contact_points() if p["state"] > 0]
    return F, b, p0, l2, active


def ellipse_fit(points):
    """Least-squares fit of p^2 = p0^2 (1 - x^2 / b^2) (linear in x^2) to the active nodes but the outermost (whose
    support straddles the contact edge): (p0, b) measured from the pressures alone."""
    active = [p for p in points if p["state"] > 0]
    edge = max(abs(p["x"]) for p in active)
    inner = [(p["x"] ** 2, p["pressure"] ** 2) for p in active if abs(p["x"]) < edge - 1e-12]
    n, sx, sy = len(inner), sum(x for x, _ in inner), sum(y for _, y in inner)
    sxx, sxy = sum(x * x for x, _ in inner), sum(x * y for x, y in inner)
    slope = (n * sxy - sx * sy) / (n * sxx - sx * sx)
    intercept = (sy - slope * sx) / n
    return math.sqrt(intercept), math.sqrt(-intercept / slope)


def mortar_hertz_2d(c):
    """Hammer's Hertz line contact (E = 96 GPa, nu = 0.35, R = 69.565 mm reconstructed from the thesis's F and b),
    h = 0.05 mm at the contact.
    1. The thesis's set-up, the top lowered by 0.015 mm: the pressure profile against Hertz for the load the run
    carries (the thesis's Fig. 8.14 check). Measured (refine 1): F = 236.95 N/mm, b = 0.6194, l2 error 5.0e-3 (3.7e-3
    at R = 70: the error is dominated by the node whose support straddles the contact edge, x = 0.5941, and moves
    with b against the nodes), peak (nominal) pressure 243.38 against p0 = 243.53 (0.06 %), the contact edge between
    two nodes around b. The thesis's F = 206.45 at this
    approach depends on the block's size, which the thesis does not state (block height 35/70/140/280 mm: F =
    254.8/236.9/220.3/202.3; docs/plugins/mortar-dual.md, "Against the paper"): 2b reconstructs the height from it.
    2. The thesis's load F = 206.44549 N/mm as a resultant on the top: the Hertz ellipse fitted to the nodal
    pressures gives the thesis's half-width and peak, b = 0.5781716 mm and p0 = 2F/(pi b) = 227.315 N/mm^2.
    Measured b = 0.57855 (+0.065 %), the centre node's pressure 227.295 (-0.009 %), the fit's p0 226.97 (-0.15 %).
    Tolerances: b to 0.2 % (a twentieth of the node spacing 0.0495 mm), the centre pressure to 0.05 % and the
    edge between the last active and the first free node (the discretisation: 11 nodes across b).
    2b. The approach 0.015 mm on a block of the reconstructed height 242 mm: measured F = 206.413 (-0.016 %), fitted
    b = 0.57847 (+0.051 %), centre 227.296 (-0.008 %); the same tolerances."""
    results, _ = run(HERTZ_2D, "--set", "output.vtu_every=0")
    F, b, p0, l2, active = hertz_2d_profile(results)
    peak = max(p["pressure"] for p in active)
    edge = max(abs(p["x"]) for p in active)
    free = min(abs(p["x"]) for p in results.contact_points() if p["state"] == 0)
    print("Hertz 2D, approach 0.015 mm: F = %.4f (thesis %.4f for its own block), b = %.5f, p0 = %.3f, peak %.3f, "
          "l2 error %.3e, active to x = %.4f" % (F, HERTZ_2D_F, b, p0, peak, l2, edge))
    c.check(l2 <= 6e-3, "pressure profile: relative l2 error %.2e <= 6e-3" % l2)
    c.check(abs(peak - p0) <= 2e-3 * p0, "peak pressure %.3f against p0 = %.3f" % (peak, p0))
    c.check(b - 0.05 < edge < b < free, "contact edge between the nodes %.4f and %.4f around b = %.4f"
            % (edge, free, b))
    loaded, _ = run(HERTZ_2D, "--set", "output.vtu_every=0",
                    "--replace", "boundary.0={name: top, group: cylinder-top, resultant: [0, %.10g], history: [[0, 0], "
                    "[1, 1]]}" % (-HERTZ_2D_F / 2))
    F = 2 * abs(loaded.rows[-1]["contact_force_y"])  # a prescribed load has no reaction column
    points = loaded.contact_points()
    p0_fit, b_fit = ellipse_fit(points)
    p0_thesis = 2 * HERTZ_2D_F / (math.pi * HERTZ_2D_B)
    centre = min(points, key=lambda p: abs(p["x"]))["pressure"]
    edge = max(abs(p["x"]) for p in points if p["state"] > 0)
    free = min(abs(p["x"]) for p in points if p["state"] == 0)
    print("Hertz 2D, the thesis's load F = %.5f: fitted b = %.5f (thesis %.7f), p0 %.3f, centre %.3f (thesis p0 "
          "%.3f), active to %.4f, free from %.4f" % (F, b_fit, HERTZ_2D_B, p0_fit, centre, p0_thesis, edge, free))
    c.check(abs(F - HERTZ_2D_F) <= 1e-9 * HERTZ_2D_F, "the contact carries the thesis's load (%.8f)" % F)
    c.check(abs(b_fit - HERTZ_2D_B) <= 2e-3 * HERTZ_2D_B,
            "half-width %.5f against the thesis's %.5f" % (b_fit, HERTZ_2D_B))
    c.check(abs(centre - p0_thesis) <= 5e-4 * p0_thesis, "centre pressure %.3f against the thesis's p0 = %.3f"
            % (centre, p0_thesis))
    c.check(edge < HERTZ_2D_B < free, "the thesis's b = %.4f between the last active node %.4f and the first free %.4f"
            % (HERTZ_2D_B, edge, free))
    # 2b. The thesis's own loading (the approach 0.015 mm) with the block's height reconstructed from its F: the force
    # holds the reconstruction (no check of the thesis: H comes from F; within 0.1 %, the 1 mm resolution of H being
    # 0.06 %), the profile is the thesis's Fig. 8.14 in its set-up: b and p0 as in 2.
    rebuilt, _ = run(HERTZ_2D, "--set", "output.vtu_every=0", "--set", "mesh.parameters.H=%g" % HERTZ_2D_H)
    F = 2 * abs(rebuilt.rows[-1]["reaction_top_y"])
    points = rebuilt.contact_points()
    p0_fit, b_fit = ellipse_fit(points)
    centre = min(points, key=lambda p: abs(p["x"]))["pressure"]
    print("Hertz 2D, the block's height %g (reconstructed): F = %.4f (thesis %.5f), fitted b = %.5f, centre %.3f"
          % (HERTZ_2D_H, F, HERTZ_2D_F, b_fit, centre))
    c.check(abs(F - HERTZ_2D_F) <= 1e-3 * HERTZ_2D_F, "height %g: F = %.4f, the thesis's %.4f (the reconstruction)"
            % (HERTZ_2D_H, F, HERTZ_2D_F))
    c.check(abs(b_fit - HERTZ_2D_B) <= 2e-3 * HERTZ_2D_B, "height %g: half-width %.5f against the thesis's %.5f"
            % (HERTZ_2D_H, b_fit, HERTZ_2D_B))
    c.check(abs(centre - p0_thesis) <= 5e-4 * p0_thesis, "height %g: centre pressure %.3f against the thesis's p0 = "
            "%.3f" % (HERTZ_2D_H, centre, p0_thesis))
    # 3. The thesis's normal fields M and A (concentrated integration) cannot be told apart in Fig. 8.14: here the
    # master is flat, so they coincide; measured: nodal pressures equal to 1.6e-8 of the peak, both within 0.19 % of
    # the segment-based ones.
    fields = {}
    for normal in ("A", "M"):
        fields[normal], _ = run(HERTZ_2D, "--set", "output.vtu_every=0", "--set", "output.contact_csv=true",
                                "--set", "contact.0.parameters.integration=concentrated",
                                "--set", "contact.0.parameters.normal=" + normal)
    pa, pm = (sorted(fields[n].contact_points(), key=lambda p: p["x"]) for n in ("A", "M"))
    top = max(p["pressure"] for p in pa)
    diff = max(abs(p["pressure"] - q["pressure"]) for p, q in zip(pa, pm)) / top
    c.check(len(pa) == len(pm) and diff <= 1e-7,
            "normal fields M and A: nodal pressures equal to %.1e of the peak" % diff)


RING = "scenes/mortar-ring.yaml"


def mortar_ring(c):
    """Hammer 8.4, the elastic ring, 30 steps. Frictionless: the ring snaps through at step 23 (t = 0.767) in the
    thesis, the reaction falls sharply after it. The scene's gap is reconstructed from that time (the scene's header:
    the snap comes 43.1 below first contact whatever the wall), so the step checks the snap deflection against the
    one measured at a 17.5 gap; one step's tolerance (the peak is resolved to the step; measured t = 0.7583 after a
    cut, step 22.75). Measured: peak 604.7, falling to 149.4 (25 %) by t = 1.
    mu = 0.5 (backtracking line search: without it the stick/slip set cycled at t = 0.59 and the step was cut to
    1e-6): the thesis's "no decrease in stiffness": the reaction rises in every step, 30 steps without a cut,
    measured to 1582.4 at t = 1, above the frictionless peak (compared with this run's, not a number)."""
    results, _ = run(RING, "--set", "output.vtu_every=0")
    reaction = results.column("reaction_base_y")
    peak = max(range(len(reaction)), key=lambda i: reaction[i])
    t_peak = results.rows[peak]["time"]
    print("frictionless: peak %.1f at t = %.4f (step %.2f of 30; thesis 23), final %.1f"
          % (reaction[peak], t_peak, 30 * t_peak, reaction[-1]))
    c.check(abs(30 * t_peak - 23) <= 1 + 1e-9, "the reaction peaks at step %.2f of 30 (thesis: 23)" % (30 * t_peak))
    c.check(reaction[-1] < 0.5 * reaction[peak],
            "the reaction falls from %.1f to %.1f after the snap" % (reaction[peak], reaction[-1]))
    friction, _ = run(RING, "--set", "output.vtu_every=0", "--set", "contact.0.parameters.mu=0.5",
                      "--set", "solver.newton.line_search=backtrack")
    held = friction.column("reaction_base_y")
    noise = 1e-9 * max(held)  # before contact the reaction is round-off of either sign
    falls = [(friction.rows[i + 1]["time"], a, b) for i, (a, b) in enumerate(zip(held, held[1:])) if b < a - noise]
    print("mu = 0.5: %d steps, final reaction %.1f, %d stick / %d slip" % (len(held) - 1, held[-1],
          friction.rows[-1]["stick_points"], friction.rows[-1]["slip_points"]))
    c.check(not falls, "mu = 0.5: the reaction never falls (no snap-through): %s" % falls[:3])
    c.check(len(held) == 31, "mu = 0.5: 30 steps without a cut (%d)" % (len(held) - 1))
    c.check(held[-1] > reaction[peak], "mu = 0.5: final reaction %.1f above the frictionless peak %.1f"
            % (held[-1], reaction[peak]))


def mortar_deep_ironing(c):
    """Hammer 8.2, the deep ironing (scenes/mortar-deep-ironing.yaml: Table 8.4's data, the rounded block pressed 30
    mm into the soft slab, dimensions chosen), frictionless, the press and the first 3 mm of the ironing (to t = 1.1)
    with both normal fields, concentrated integration. The thesis: "the differences between mortar and averaged
    non-mortar normals are really small", the vertical reactions with no big difference, the horizontal ones
    oscillating with either (Figs 8.9, 8.10: "only a few time steps where the red mortar side normal method is
    visible behind the averaged normal method"). Measured: F_y of M and A within 7.7e-5 of its span (3450 N), F_x
    within 1.5 % of its span (45 N, 2e-4 of F_y); checked to 1e-3 and 3 %. The whole runs (220 mm right, 110 back,
    mu = 0 and 0.3, refinement): docs/plugins/mortar-dual.md, "Against the paper"."""
    results = {}
    for normal in ("M", "A"):
        results[normal], _ = run("scenes/mortar-deep-ironing.yaml", "--set", "time.end=1.1",
                                 "--set", "output.vtu_every=0", "--set", "contact.0.parameters.normal=" + normal)
        r = results[normal]
        c.check(abs(r.rows[-1]["time"] - 1.1) < 1e-9, "%s: pressed 30 mm and ironed 3 mm (t = %g)"
                % (normal, r.rows[-1]["time"]))
        press = by_time(r)[1.0]
        print("%s: at the full depth (t = 1) F_y = %.1f, F_x = %.1f, %d active nodes"
              % (normal, press["reaction_press_y"], press["reaction_iron_x"], press["active_points"]))
    ra, rb = by_time(results["M"]), by_time(results["A"])
    common = sorted(set(ra) & set(rb))
    for name, bound in (("reaction_press_y", 1e-3), ("reaction_iron_x", 3e-2)):
        values = [ra[t][name] for t in common]
        span = max(values) - min(values)
        diff = max(abs(ra[t][name] - rb[t][name]) for t in common)
        c.check(diff <= bound * span, "Figs 8.9/8.10: %s of M and A differ by %.3g = %.1e of its span %.4g (%d common "
                "times)" % (name, diff, diff / span, span, len(common)))


def oscillation(times, values, window=20.0 / 30.0):
    """Root mean square of the values about their moving mean over `window` (20 mm of travel: five slab cells at
    refine 1), and that mean's average: the facets' ripple without the slow trend."""
    dev = []
    for t, v in zip(times, values):
        near = [w for s, w in zip(times, values) if abs(s - t) <= window / 2]
        dev.append(v - statistics.fmean(near))
    return math.sqrt(statistics.fmean(d * d for d in dev)), statistics.fmean(values)


def mortar_deep_ironing_refinement(c):
    """Hammer 8.2 with friction (mu = 0.3, Figs 8.10-8.12): "the oscillation significantly decreases with mesh
    refinement". The press and the ironing to t = 3 (60 mm) at refine 0.75 and 1 (both meshes; coarser ones invert an
    element of the soft slab), the ripple of F_x about its 20 mm moving mean over t in [2.3, 3], where every active
    node slides (from t = 2.07 and 2.13). Measured at bb687e1, 2026-11-30: 28.7 N and 15.4 N (6.7 N at refine 1.5,
    not run here: 158 s CPU to t = 4), a ratio of 0.54. Checked: the finer mesh's ripple at most 0.7 of the coarser's,
    both meshes in full slip over the window. About 35 s CPU: labelled long."""
    ripple = {}
    for refine in (0.75, 1):
        r, _ = run("scenes/mortar-deep-ironing.yaml", "--set", "contact.0.parameters.mu=0.3", "--set", "time.end=3",
                   "--set", "output.vtu_every=0", "--set", "mesh.0.parameters.refine=%g" % refine,
                   "--set", "mesh.1.parameters.refine=%g" % refine)
        window = [row for row in r.rows if 2.3 <= row["time"] <= 3.0 + 1e-9]
        c.check(abs(r.rows[-1]["time"] - 3.0) < 1e-9 and len(window) >= 8
                and all(row["slip_points"] == row["active_points"] > 0 for row in window),
                "refine %g: ironed to t = 3, full slip over t in [2.3, 3] (%d steps)" % (refine, len(window)))
        ripple[refine] = oscillation([row["time"] for row in window], [row["reaction_iron_x"] for row in window])[0]
    print("ripple of F_x over t in [2.3, 3]: refine 0.75 %.2f N, refine 1 %.2f N" % (ripple[0.75], ripple[1]))
    c.check(ripple[1] <= 0.7 * ripple[0.75], "Fig. 8.12: the ripple falls under refinement, %.2f -> %.2f N (ratio %.2f)"
            % (ripple[0.75], ripple[1], ripple[1] / ripple[0.75]))


if __name__ == "__main__":
    main([mortar_hammer_thesis, mortar_hammer_thesis_friction, mortar_hertz_2d, mortar_ring, mortar_deep_ironing,
          mortar_deep_ironing_refinement])
