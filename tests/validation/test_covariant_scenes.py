"""Validation of covariant-penalty against Konyukhov & Schweizerhof (2005) through the driver: the paper's examples as
scenes (scenes/ks-*.yaml), checked against the paper's own numbers where this code reproduces them (Table 3's and
Table 5's iterations per sliding step, Table 4's per step, 6.2's contact loss, the frictionless pressure of
6.1, the estimate (110), the claim of Fig. 7, 6.2's rigid-body estimate); frame indifference and rank independence
of a whole run. The rows that are not reproduced, with their causes and the commands that show them:
docs/plugins/covariant-penalty.md, "Against the paper".
Iterations are our Newton iterations per load step (history.csv); the paper's are FEAP's, with a criterion it does not
state; tests/bench/covariant-penalty/iterations.py counts a run both ways (docs §9).
Usage: python3 test_covariant_scenes.py CASE; exit code 0 when every check holds."""
import json
import math
import os
import sys

import yaml

from stickslip_results import ROOT, Results, run, main

sys.path.insert(0, os.path.join(ROOT, "tests", "bench", "covariant-penalty"))
import paths  # noqa: E402

MU = 0.3


def iterations(results, first_step=1):
    """Newton iterations of each step from first_step on (history.csv, step 0 is the initial state)."""
    return [int(r["newton_iterations"]) for r in results.rows if r["step"] >= first_step]


def run_variant(scene, tangent, *args, form="exact"):
    results, _ = run(scene, "--set", "contact.0.parameters.tangent=%s" % tangent,
                     "--set", "contact.0.parameters.tangent_form=%s" % form, *args)
    return results


def bottom_lag(folder, step, applied):
    """u_x - u_applied of the block's bottom nodes (reference y = 0, z = 0; the clamped base's do not move) at a
    step, ordered by x: the paper's Fig. 7."""
    from stickslip_results import read_vtu
    a = read_vtu(os.path.join(folder, "step-%06d.pvtu" % step))
    rows = sorted((x - d[0], d[0] - applied) for (x, y, z), d in zip(a["Points"], a["displacement"])
                  if abs(y - d[1]) < 1e-9 and abs(z - d[2]) < 1e-9 and d != (0.0, 0.0, 0.0))
    return [lag for _, lag in rows]


def ks_block_b(c):
    """6.1 run B, Table 3: 20 sliding steps of 12e-3 after the pressing step (eps 2.1e5). The paper: full tangent
    4, 6, 5, then 3 iterations per step (66); main part only 5, 6, 5, then 4 (84).
    Measured (our criterion): full 7, 4, then 3 per step except 4 in the three steps in which base points come into
    contact at the block's leading edge (the base is 1 longer than the block; with a base as long as the block, none
    enters and the total is 66: docs, "Against the paper"), 68 in all; main-only 96, 4-5 per step: its linear
    convergence (rate 2e-3 ... 2e-2, the rotational part's weight channel missing) leaves its 4th iterate at
    |F| = 4e-8 ... 3e-7, above our 1e-8 (not reproduced: docs). Fig. 7: the bottom's lag behind the applied
    displacement, u - u_applied, at u = 0.012, 0.048 and 0.120 (measured: -8.06e-3 ... -5.16e-3, changing by at most
    1.0e-4 between the three states, 1.7 % of its mean, while u grows tenfold)."""
    full, _ = run("scenes/ks-block-b.yaml", "--set", "output.vtu_every=1")
    main_only = run_variant("scenes/ks-block-b.yaml", "main-only")
    counts = {"full": iterations(full, 2), "main-only": iterations(main_only, 2)}
    for name, res in (("full", full), ("main-only", main_only)):
        ratios = [r["reaction_drag_x"] / r["reaction_press_y"] for r in res.rows if r["step"] >= 2]
        worst = max(ratios, key=lambda x: abs(x + MU))
        c.check(len(ratios) == 20 and abs(worst + MU) <= 1e-4,
                "%s: 20 sliding steps, F_x/F_y = -0.3 after each (worst %+.6f)" % (name, worst))
        print("6.1 run B, %s: %d iterations over the sliding steps: %s" % (name, sum(counts[name]), counts[name]))
    steady = counts["full"][3:]
    # the paper: 3 per step in steps 4-20; each step in which a base point enters contact at the leading edge takes a
    # 4th (3 such steps measured)
    c.check(sorted(steady)[len(steady) // 2] == 3 and steady.count(3) >= len(steady) - 3 and max(steady) <= 4,
            "full: steps 4-20 take the paper's 3 iterations, 4 in at most 3 steps (%s)" % steady)
    c.check(abs(sum(counts["full"]) - 66) <= 3, "full: %d iterations over the 20 steps, the paper's 66 plus at most the "
            "3 leading-edge steps" % sum(counts["full"]))
    c.check(all(m > f for m, f in zip(counts["main-only"][3:], steady) if f == 3),
            "main-only takes more iterations than full in every steady step (the paper: 4 against 3)")
    lags = [bottom_lag(full.folder, 1 + k, 0.012 * k) for k in (1, 4, 10)]
    mean = sum(lags[0]) / len(lags[0])
    change = max(abs(a - b) for i in range(3) for j in range(i) for a, b in zip(lags[i], lags[j]))
    print("Fig. 7: u - u_applied of the bottom in [%.3e, %.3e] at u = 0.012; largest change to u = 0.048, 0.120: "
          "%.2e" % (min(lags[0]), max(lags[0]), change))
    c.check(len(lags[0]) == 41 and change <= 0.02 * abs(mean),
            "Fig. 7: the relative displacements hardly change in large sliding (by %.2e, %.1f %% of the lag %.3e)"
            % (change, 100 * change / abs(mean), mean))


def critical_drag(scene):
    """The estimate (110) of the drag at which sliding sets in, u_cr = 2 mu h / (1 - nu), from a 6.1 scene's own
    values: mu of the contact, nu of the block, h the pressing displacement of the block's top."""
    with open(os.path.join(ROOT, scene)) as f:
        d = yaml.safe_load(f)
    mu = d["contact"][0]["parameters"]["mu"]
    nu = next(b for b in d["bodies"] if b["name"] == "block")["material"]["nu"]
    h = abs(next(b for b in d["boundary"] if b["name"] == "press")["displacement"][1])
    return 2 * mu * h / (1 - nu)


def frictionless_pressure(c):
    """6.1's pressing without friction and without the top's x-hold: the block in uniaxial stress on the rigid base,
    p = E |v| / (b + E / eps_N) = 29.3413 (the penalty spring in series with the block). Measured F_y / (a c) =
    29.34138 (2.3e-6 above: the base's Gauss points within master_extension beyond the block's ends carry some
    pressure); with the x-hold (the scene as it stands) 30.84, the block's top cannot expand."""
    E, v, b, eps, area = 2.1e4, 7.0e-3, 5.0, 2.1e6, 20.0 * 0.5
    expected = E * v / (b + E / eps)
    res, _ = run("scenes/ks-block-a.yaml", "--set", "time.end=1", "--set", "contact.0.parameters.mu=0",
                 "--set", "boundary.2.displacement=[~, ~, ~]")
    p = -res.rows[-1]["reaction_press_y"] / area
    print("frictionless pressing, top free in x: p = %.6f, E|v|/(b + E/eps_N) = %.6f" % (p, expected))
    c.check(abs(p - expected) <= 1e-5 * expected, "p = F_y / (a c) = %.5f is E|v|/(b + E/eps_N) = %.5f to 1e-5"
            % (p, expected))


def ks_block_a(c):
    """6.1 run A (steps of 2.5e-4, eps 2.1e6) to u = 9e-3, and the frictionless pressing. The estimate (110),
    u_cr = 2 mu |v| / (1 - nu), from the scene's values is the paper's 6.0e-3; the paper's claim that it estimates
    the onset of sliding from below holds: the total |F_x/F_y| (reactions at the top) reaches mu to 1 % at u = 8.0e-3
    and to 2 % at the paper's 7.5e-3, the plotted state (Fig. 6) at which the paper sees it at mu, and no point sticks from u = 8.25e-3 (the paper: 11.0e-3). Those two are not reproduced with
    the block's faces z = 0, c free as here (held in z, the full sliding is: ks_block_a_plane_strain; docs, "Against
    the paper"); checked here: (110) from the scene file's mu, h, nu against the paper's 6.0e-3, |F_x/F_y| <= mu, the
    order u_cr < onset <= all sliding, and that the pressing leaves points sticking."""
    frictionless_pressure(c)
    u_cr = critical_drag("scenes/ks-block-a.yaml")
    c.check(abs(u_cr - 6.0e-3) <= 1e-15, "(110) from the scene's mu, h, nu: u_cr = %.4e, the paper's 6.0e-3" % u_cr)
    results = run_variant("scenes/ks-block-a.yaml", "full", "--set", "time.end=37")
    onset = full = None
    for r in results.rows:
        k = int(r["step"]) - 1
        if k <= 0:
            continue
        ratio = abs(r["reaction_drag_x"] / r["reaction_press_y"])
        if onset is None and ratio >= 0.99 * MU:
            onset = k * 2.5e-4
        if full is None and r["stick_points"] == 0 and r["slip_points"] > 0:
            full = k * 2.5e-4
    print("run A: |F_x/F_y| within 1 %% of mu from u = %s, no point sticks from u = %s (the paper: 7.5e-3, 11.0e-3; "
          "(110): %.1e)" % (onset, full, u_cr))
    c.check(onset is not None and full is not None and u_cr < onset <= full,
            "u_cr %.2e < onset %s <= all sliding %s" % (u_cr, onset, full))
    # Fig. 6 at the paper's plotted states (u = 6.0, 7.5, 9.0e-3; its onset 7.5e-3 is the first plotted state at mu):
    # measured |F_x/F_y| = 0.2677 (0.89 mu), 0.2939 (0.98 mu), 0.3000 at bb687e1, 2026-11-30
    at = {int(r["step"]) - 1: abs(r["reaction_drag_x"] / r["reaction_press_y"]) for r in results.rows if r["step"] >= 2}
    c.check(at[24] < 0.95 * MU and at[30] >= 0.97 * MU and abs(at[36] - MU) <= 1e-4 * MU,
            "Fig. 6: |F_x/F_y| at u = 6.0, 7.5, 9.0e-3: %.4f, %.4f, %.4f (the paper: below mu, at mu from 7.5e-3)"
            % (at[24], at[30], at[36]))
    worst = max(abs(r["reaction_drag_x"] / r["reaction_press_y"]) for r in results.rows if r["step"] >= 1)
    c.check(worst <= MU + 1e-6, "|F_x/F_y| <= mu throughout (max %.7f)" % worst)
    first = results.rows[1]
    c.check(first["stick_points"] > 0, "pressing: %d points stick, %d slide" % (first["stick_points"],
                                                                                first["slip_points"]))


def ks_block_a_plane_strain(c):
    """6.1 run A with the block's faces z = 0, c held in z (plane strain, the assumption of the estimate (110); the
    paper does not state what holds them), to u = 1.1e-2. The paper: the block slides at the full lower boundary when
    u reaches 11.0e-3, read at the states it plots (Fig. 5: 9.0, 10.0, 11.0, 12.0e-3), so its value is known to lie in
    (10.0e-3, 11.0e-3]: asserted there, one plotted interval (four of our load steps of 2.5e-4). Measured: no point
    sticks from u = 1.025e-2 (step 42). Its onset (|F_x/F_y| at mu, 1.0e-2 against the paper's 7.5e-3) is not
    reproduced (docs, "Against the paper")."""
    with open(os.path.join(ROOT, "scenes/ks-block-a.yaml")) as f:
        boundary = yaml.safe_load(f)["boundary"]
    boundary.append({"name": "sides", "group": "block-sides", "displacement": [None, None, 0]})
    results, _ = run("scenes/ks-block-a.yaml", "--set", "time.end=45", "--set", "boundary=" + json.dumps(boundary))
    c.check(results.summary["status"] == "ok" and len(results.rows) == 46, "45 steps done, to u = 1.1e-2")
    full = next(((int(r["step"]) - 1) * 2.5e-4 for r in results.rows
                 if r["step"] >= 2 and r["stick_points"] == 0 and r["slip_points"] > 0), None)
    print("run A held in z: no point sticks from u = %s (the paper: 11.0e-3, its previous plotted state 10.0e-3)"
          % full)
    c.check(full is not None and 10.0e-3 < full <= 11.0e-3 + 1e-12,
            "Fig. 5: all sliding from u = %s, in the paper's (10.0e-3, 11.0e-3]" % full)


def ks_parabolic(c):
    """6.2: the 7 pressing steps (Fig. 9) and the first 8 of Table 4's 20 sliding steps of 4e-2, full tangent. The
    paper's full tangent: 6, 5, 5, then 4 per step (steps 4-18). Measured: 7, 7, 5, then 4, 4, 4, 4, 5 (over all 20:
    4 in 12 of the steps 4-20, 5 in the others, 92 against 86: docs). Fig. 9's stick zone |x| < ~3 with sliding
    outside is not reproduced (after the pressing every node sticks, with any of the variants docs,
    "Against the paper", lists); checked here is the rigid-body estimate the paper states beside it, which holds for
    a block without Poisson expansion (nu = 0): sliding where tan(alpha) = 0.06 |x| >= mu, i.e. only the end nodes
    |x| = 5, where tan(alpha) = mu (|t|/(mu p) = 1.00 there, 0.39 at |x| = 3)."""
    results = run_variant("scenes/ks-parabolic.yaml", "full", "--set", "time.end=15")
    its = iterations(results)
    c.check(results.summary["status"] == "ok" and len(its) == 15, "15 steps done")
    sliding = its[7:]
    print("6.2, full: pressing %s, sliding %s (the paper: 6, 5, 5, then 4)" % (its[:7], sliding))
    c.check(sliding[3:].count(4) >= len(sliding[3:]) - 1 and max(sliding[3:]) <= 5,
            "steps 4-8 take the paper's 4 iterations, at most one 5 (%s)" % sliding[3:])
    rigid, _ = run("scenes/ks-parabolic.yaml", "--set", "time.end=7", "--set", "bodies.0.material.nu=0")
    pts = [p for p in rigid.contact_points() if p["state"] != 0]
    slipping = [abs(p["reference_x"]) for p in pts if p["state"] == 2]
    print("6.2 pressed, nu = 0: %d of %d nodes slip, at |x| = %s" % (len(slipping), len(pts), sorted(set(slipping))))
    c.check(len(pts) == 123 and len(slipping) == 6 and all(abs(x - 5.0) < 1e-9 for x in slipping),
            "pressed, nu = 0: the rigid estimate, the 6 end nodes |x| = 5 (tan(alpha) = mu) slide, no other")


def ks_parabolic_contact_loss(c):
    """6.2, Fig. 12: "the zone without contact is detected as a zone with zero normal nodal forces f_n = 0 starting at
    a loading with u >= 1.52e-2", on the equidistant path (116) after the 7 pressing steps. The paper gives no penalty
    for 6.2; with eps_N = eps_T = 2.1e4 (= E) the end column of base nodes (x = -5, 3 nodes) loses contact first at
    the paper's step (Delta u = 2.5e-5, 640 steps) exactly at u = 1.52e-2 (measured at 2f6c26c, 2026-11-29); the
    scene's 2.1e5 at 1.09e-2, 6.3e4 at 1.3e-2 (docs, "Against the paper"). Here with steps of 5e-4 (32 steps,
    20 times the paper's): every node in contact to u = 1.50e-2, the 3 end nodes lost in the step to 1.55e-2, the one
    that holds the paper's 1.52e-2 (the bound: that step). About 25 s CPU: labelled long."""
    du, steps = 5e-4, 32
    hx, hz = paths.parabolic(steps, du)
    res, _ = run("scenes/ks-parabolic.yaml", "--set", "time.end=%d" % (7 + steps),
                 "--set", "boundary.2.history=%s" % paths.fmt(hx), "--set", "boundary.3.history=%s" % paths.fmt(hz),
                 "--set", "contact.0.parameters.penalty=2.1e4",
                 "--set", "contact.0.parameters.penalty_tangential=2.1e4")
    c.check(res.summary["status"] == "ok" and len(res.rows) == 8 + steps, "%d steps done" % (7 + steps))
    active = [(round((r["step"] - 7) * du, 7), int(r["active_points"])) for r in res.rows if r["step"] > 7]
    lost = [u for u, n in active if n < 123]
    print("6.2, eps 2.1e4: active points %s" % [(u, n) for u, n in active if u >= 1.4e-2])
    c.check(bool(lost) and lost[0] - du < 1.52e-2 <= lost[0],
            "first contact loss in the step to u = %s, which holds the paper's 1.52e-2" % (lost[0] if lost else None))
    c.check(all(n == 123 for u, n in active if u < 1.52e-2), "every base node in contact before")
    c.check(dict(active).get(lost[0] if lost else 0) == 120, "the end column (3 nodes) first")


def ks_parabolic_table4_penalty_e(c):
    """6.2, Table 4, case 1 (full tangent) with eps_N = eps_T = 2.1e4 (= E), the penalty that gives Fig. 12's contact
    loss at the paper's u (ks_parabolic_contact_loss; the paper gives none for 6.2, the scene uses 2.1e5). The paper:
    6, 5, 5, then 4 (steps 4-18), 5, 5: 86. Measured at 2f6c26c (2026-11-29): 6, 5, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4,
    4, 4, 5, 4, 4, 4, 5: 86 (with the scene's 2.1e5: 7, 7, 5, then 4-5, 92). Checked: the paper's 6 and 5 in the first
    two steps, the paper's 4 or 5 in every later step, at most three 5s as in the paper, the total the paper's 86 to
    2 (the count's round-off: the line search's choices move single steps by one). About 25 s CPU: labelled long."""
    res = run_variant("scenes/ks-parabolic.yaml", "full", "--set", "contact.0.parameters.penalty=2.1e4",
                      "--set", "contact.0.parameters.penalty_tangential=2.1e4")
    its = iterations(res)
    c.check(res.summary["status"] == "ok" and len(its) == 27, "27 steps done")
    sliding = its[7:]
    print("6.2, eps 2.1e4, full: pressing %s, sliding %s, %d (the paper: 6, 5, 5, then 4, 5, 5: 86)"
          % (its[:7], sliding, sum(sliding)))
    c.check(sliding[:2] == [6, 5], "steps 1-2 take the paper's 6 and 5 (%s)" % sliding[:2])
    c.check(set(sliding[2:]) <= {4, 5} and sliding[2:].count(5) <= 3,
            "steps 3-20 take 4 or 5, at most three 5s (the paper: steps 3, 19, 20): %s" % sliding[2:])
    c.check(abs(sum(sliding) - 86) <= 2, "%d iterations, the paper's 86 to 2" % sum(sliding))


def ks_parabolic_small_steps(c):
    """6.2, the text after Table 4: "during the analysis of the threshold value before full sliding the number of
    equilibrium iterations remains the same for each case due to a small load step". After the 7 pressing steps, 10
    steps of the paper's du = 2.5e-5 along (116) with the full tangent and without the curvature part. Measured at
    3b8a645, 2026-11-28 (again at bb687e1, 2026-11-30): 2 per step each (main-only 3: the rotational part's weight
    channel, docs, "Against the paper"). Checked: full and no-curvature equal in every small step."""
    hx, hz = paths.parabolic(10, 2.5e-5)
    sets = ("--set", "time.end=17", "--set", "boundary.2.history=%s" % paths.fmt(hx),
            "--set", "boundary.3.history=%s" % paths.fmt(hz))
    counts = {v: iterations(run_variant("scenes/ks-parabolic.yaml", v, *sets))[7:] for v in ("full", "no-curvature")}
    print("6.2, 10 steps of 2.5e-5: full %s, no-curvature %s" % (counts["full"], counts["no-curvature"]))
    c.check(len(counts["full"]) == 10 and counts["full"] == counts["no-curvature"],
            "the same count in every small step (the paper): full %s, no-curvature %s"
            % (counts["full"], counts["no-curvature"]))


# The compression held at the pressing force of eps 2.1e4 (the reaction after the 7 pressing steps): the top moves
# along (116) in x, in z a resultant, as the paper describes its path ("approximately constant compression")
CONSTANT_COMPRESSION_E = "boundary.3={name: top-z, group: block.top, resultant: [0, 0, -286.2223387], " \
                         "history: [[0, 0], [7, 1]]}"


def ks_parabolic_table4_main_only(c):
    """6.2, Table 4, case 3 (main part only): the paper 6 ... 10 per step, 156 over the 20 sliding steps. With eps_N
    = eps_T = 2.1e4 (the penalty at which full takes the paper's 86: ks_parabolic_table4_penalty_e), the compression
    held at the pressing force, counted by FEAP's energy test (the paper's program; tests/bench/covariant-penalty/
    iterations.py), whose tolerance the paper does not state. Measured at bb687e1, 2026-11-30: at 1e-12 9, 5, 5, 6, 6,
    6, 5, 5, 6, 6, 6, 6, 7, 9, 10, 8, 8, 8, 9, 12: 142; at 1e-14 165 (full 82 and 88 there, the paper's 86). On the
    top translated along (116) the compression grows (contact force 286 -> 2182, contact 123 -> 45 slave nodes) and
    main-only takes 191 at 1e-12, 24 in the last step (docs, "Against the paper"). Checked: the paper's 156 between
    the counts at 1e-12 and 1e-14. About 40 s CPU: labelled long."""
    import iterations as feap  # tests/bench/covariant-penalty/iterations.py
    res, proc = run("scenes/ks-parabolic.yaml", "--verbose", "--replace", CONSTANT_COMPRESSION_E,
                    "--set", "contact.0.parameters.tangent=main-only",
                    "--set", "contact.0.parameters.penalty=2.1e4",
                    "--set", "contact.0.parameters.penalty_tangential=2.1e4", "--set", "solver.newton.max_iterations=60")
    steps = feap.histories(proc.stderr)
    counts = {tol: [feap.energy_count(steps[s], tol) for s in sorted(steps)][7:] for tol in (1e-12, 1e-14)}
    c.check(res.summary["status"] == "ok" and all(len(n) == 20 and None not in n for n in counts.values()),
            "20 sliding steps done and counted (%s)" % counts[1e-12])
    loose, tight = (sum(n for n in counts[tol] if n is not None) for tol in (1e-12, 1e-14))
    print("6.2, eps 2.1e4, constant compression, main only, FEAP's test at 1e-12: %s, %d; at 1e-14: %d (the paper: "
          "6 ... 10, 156)" % (counts[1e-12], loose, tight))
    c.check(loose <= 156 <= tight, "the paper's 156 between FEAP's counts at 1e-12 (%d) and 1e-14 (%d)" % (loose, tight))


def ks_spiral(c):
    """6.3, Table 5: pressing and the first 20 spiral steps. Case 1 (without the curvature part; STAS has none, so the
    full tangent): the paper 9, 8, 5, then 4 per step (90); ours 7, 5, then 3-4 (76): at most the paper's 4 from step
    4 on (with eps 2.1e6 instead of the scene's 2.1e5, 4 in 16 of steps 4-20 and 89 in all: docs). Case 2 (only the main matrix): the paper 10, then 13 per step (254); the printed main matrix
    (tangent_form: paper) takes 14, then 13 in every step (261): the paper's 13 in steps 2-18 (its 12 and 11 in steps
    19, 20 are 13 here). The exact form's main part converges in 4-5 per step: it differentiates the ray through the
    obstacle's normal, which the printed n (x) n does not (docs)."""
    full = run_variant("scenes/ks-spiral.yaml", "full")
    main_only = run_variant("scenes/ks-spiral.yaml", "main-only", form="paper")
    case1, case2 = iterations(full, 2), iterations(main_only, 2)
    for name, res in (("case 1", full), ("case 2", main_only)):
        c.check(res.summary["status"] == "ok" and len(res.rows) == 22, "%s: 21 steps done" % name)
    print("6.3, case 1 (full, exact): %d %s; case 2 (main, paper form): %d %s" % (sum(case1), case1, sum(case2), case2))
    c.check(max(case1[3:]) <= 4, "case 1: steps 4-20 take at most the paper's 4 iterations (%s)" % case1[3:])
    c.check(case2[1:18].count(13) == 17, "case 2: steps 2-18 take the paper's 13 iterations each (%s)" % case2[1:18])
    c.check(abs(sum(case2) - 254) <= 0.03 * 254, "case 2: %d iterations over the 20 steps, the paper's 254 to 3 %% "
            "(its first step, 10, is 14 here)" % sum(case2))


def rotation(axis, degrees):
    n = math.sqrt(sum(a * a for a in axis))
    k = [a / n for a in axis]
    th = math.radians(degrees)
    cs, sn = math.cos(th), math.sin(th)

    def apply(v):
        kv = sum(a * b for a, b in zip(k, v))
        kxv = [k[1] * v[2] - k[2] * v[1], k[2] * v[0] - k[0] * v[2], k[0] * v[1] - k[1] * v[0]]
        return [v[i] * cs + kxv[i] * sn + k[i] * kv * (1 - cs) for i in range(3)]
    return k, apply


def ks_spiral_rotated(c):
    """Frame indifference of a whole run: 6.3 with the mesh, the obstacle and the prescribed path rotated by 40 degrees
    about (1, 2, 3). Measured: the contact force of every step is the rotated one to 8e-10 (|F| = 1.2, the level of the
    Newton tolerance), the reactions likewise; the per-step iteration counts differ by one here and there (round-off
    changes the line search's choices), totals 159 and 155."""
    axis, R = rotation([1, 2, 3], 40.0)
    hx, hy, hz = paths.spiral(20)
    moved = [R([a[1], b[1], d[1]]) for a, b, d in zip(hx, hy, hz)]
    vec = lambda v: "[%s]" % ", ".join("%.17g" % x for x in v)
    args = ["--set", "mesh.rotate={axis: %s, degrees: 40}" % vec(axis),
            "--set", "contact.0.obstacle.normal=%s" % vec(R([0, 0, 1])),
            "--set", "contact.0.obstacle.axis=%s" % vec(R([0, 1, 0]))]
    for i in range(3):
        args += ["--set", "boundary.%d.history=%s" % (i, paths.fmt([(a[0], m[i]) for a, m in zip(hx, moved)]))]
    plain, _ = run("scenes/ks-spiral.yaml")
    turned, _ = run("scenes/ks-spiral.yaml", *args)
    worst, scale = 0.0, 0.0
    for a, b in zip(plain.rows[1:], turned.rows[1:]):
        F = [a["contact_force_%s" % k] for k in "xyz"]
        G = [b["contact_force_%s" % k] for k in "xyz"]
        worst = max(worst, max(abs(p - q) for p, q in zip(R(F), G)))
        scale = max(scale, max(abs(v) for v in F))
    c.check(len(plain.rows) == len(turned.rows) == 22, "both runs reach step 21")
    c.check(worst <= 1e-8 * scale, "contact forces rotate with the frame: max |R F - F'| = %.2e of |F| %.3e"
            % (worst, scale))
    totals = [sum(iterations(r)) for r in (plain, turned)]
    c.check(abs(totals[0] - totals[1]) <= 0.05 * totals[0], "Newton iterations %d and %d (within 5 %%)" % tuple(totals))


def ks_spiral_mpi(c):
    """6.3 on 1 and 2 ranks (each rank owns its faces' Gauss points): the same contact forces, reactions and contact
    point counts at every step. Measured: forces equal to 1.3e-13 (|F| = 1.2); the Newton iteration counts of single
    steps differ by one (the parallel sums' round-off changes the line search's choices). Newton stops once its
    predicted update is below update_tolerance (1e-8: forces then differ by up to 2.7e-9 between the two runs, the
    stopping point, not the parallel sums); 1e-13 makes both runs take the last quadratic step."""
    tight = ("--set", "solver.newton.update_tolerance=1e-13")
    one, _ = run("scenes/ks-spiral.yaml", *tight)
    two, _ = run("scenes/ks-spiral.yaml", *tight, np=2)
    c.check(two.summary["ranks"] == 2 and len(one.rows) == len(two.rows) == 22, "2 ranks, 21 steps each")
    keys = ("contact_force_x", "contact_force_y", "contact_force_z", "reaction_cut-x_x", "reaction_cut-y_y",
            "reaction_cut-z_z")
    scale = max(abs(r[k]) for r in one.rows for k in keys)
    worst = max(abs(a[k] - b[k]) for a, b in zip(one.rows, two.rows) for k in keys)
    c.check(worst <= 1e-10 * scale, "np 1 vs 2: forces and reactions equal to %.1e relative" % (worst / scale))
    for k in ("active_points", "stick_points", "slip_points"):
        c.check(one.column(k) == two.column(k), "np 1 vs 2: the same %s at every step" % k)


CASES = [ks_block_b, ks_block_a, ks_block_a_plane_strain, ks_parabolic, ks_parabolic_contact_loss,
         ks_parabolic_table4_penalty_e, ks_parabolic_table4_main_only, ks_parabolic_small_steps,
         ks_spiral, ks_spiral_rotated, ks_spiral_mpi]

if __name__ == "__main__":
    main(CASES)
