"""What the stress suite measures in a finished run (history.csv and summary.json only): convergence, step cuts,
Newton iterations, energy drift, momentum drift, active-set changes and whether contact was found at all.
docs/stability.md defines each quantity; every one is computed here and nowhere else."""
import math

# Columns that, once the driver writes them, replace the lower bound computed from the counts (docs/stability.md,
# "Active-set changes"): points whose state differs from the previous converged step, and state changes between
# Newton iterates within the step.
EXACT_CHANGES = "active_set_changes"
NEWTON_CHANGES = "newton_active_set_changes"


# every key metrics() may write (a reused record drops them before they are computed again)
METRIC_KEYS = ("converged", "steps", "step_cuts", "newton_iterations", "final_time", "energy_increase",
               "energy_change", "energy_step_increase", "energy_drift_per_revolution", "momentum_drift",
               "angular_momentum_drift", "angular_momentum_drift_per_revolution", "revolutions", "flips_exact",
               "flips", "flips_max_step", "flip_reversals", "newton_flips", "contact_steps", "max_active",
               "max_constraint_violation", "input_error")


def state_changes(prev, row):
    """Lower bound on the contact points whose state (inactive / frictionless contact / stick / slip) changed between
    two rows: half the sum of the count changes of the four states (each change moves one point between two)."""
    da = row["active_points"] - prev["active_points"]
    dst = row["stick_points"] - prev["stick_points"]
    dsl = row["slip_points"] - prev["slip_points"]
    return (abs(da) + abs(da - dst - dsl) + abs(dst) + abs(dsl)) / 2.0


def _vector(row, prefix):
    return [row[prefix + c] for c in "xyz"]


def _norm(v):
    return math.sqrt(sum(x * x for x in v))


def _drift(rows, prefix, scale):
    """max_t |v(t) - v(0)| / scale, None without a scale (a body at rest)."""
    if not scale > 0.0:
        return None
    v0 = _vector(rows[0], prefix)
    return max(math.dist(_vector(r, prefix), v0) for r in rows) / scale


def metrics(results, closed, revolutions=None, length=1.0):
    """The stress quantities of one run (see docs/stability.md); the energy balance only for closed systems (no
    loads, supports or moving obstacles do work on them). Momentum drifts are relative to |p(0)| and to
    max(|L(0)|, |p(0)| length): a body falling along an axis through the origin has L(0) = 0 to round-off."""
    rows, s = results.rows, results.summary
    out = {"converged": s.get("status") == "ok", "steps": s.get("steps"), "step_cuts": s.get("step_cuts"),
           "newton_iterations": s.get("newton_iterations"), "final_time": s.get("final_time")}
    if closed:
        out.update(energy_balance(rows, revolutions))
    p0, L0 = _vector(rows[0], "momentum_"), _vector(rows[0], "angular_momentum_")
    L_scale = max(_norm(L0), _norm(p0) * length)
    out["momentum_drift"] = _drift(rows, "momentum_", _norm(p0))
    out["angular_momentum_drift"] = _drift(rows, "angular_momentum_", L_scale)
    if revolutions:
        out["revolutions"] = revolutions
    if revolutions and out["angular_momentum_drift"] is not None:
        final = math.dist(_vector(rows[-1], "angular_momentum_"), L0) / L_scale
        out["angular_momentum_drift_per_revolution"] = final / revolutions
    if EXACT_CHANGES in rows[0]:
        changes = [r[EXACT_CHANGES] for r in rows[1:]]
        out["flips_exact"] = True
    else:
        changes = [state_changes(a, b) for a, b in zip(rows, rows[1:])]
        out["flips_exact"] = False
    out["flips"] = sum(changes)
    out["flips_max_step"] = max(changes or [0])
    out["flip_reversals"] = reversals([r["active_points"] for r in rows])
    if NEWTON_CHANGES in rows[0]:
        out["newton_flips"] = sum(r[NEWTON_CHANGES] for r in rows[1:])
    out["contact_steps"] = sum(1 for r in rows[1:] if r["active_points"] > 0)
    out["max_active"] = max(r["active_points"] for r in rows)
    out["max_constraint_violation"] = max(r["constraint_violation"] for r in rows)
    return out


def energy_balance(rows, revolutions=None):
    """Kinetic + strain energy (+ contact energy where the driver includes it in total_energy) plus what friction
    dissipated, relative to its initial value: the largest gain over the run, the largest gain in one step and the
    change at the end (and per revolution)."""
    balance = [r["total_energy"] + r.get("dissipated_energy", 0.0) for r in rows]
    scale = abs(balance[0]) if balance[0] != 0 else max(abs(b) for b in balance) or 1.0
    out = {"energy_increase": max(b - balance[0] for b in balance) / scale,
           "energy_change": (balance[-1] - balance[0]) / scale,
           "energy_step_increase": max([b - a for a, b in zip(balance, balance[1:])] or [0.0]) / scale}
    if revolutions:
        out["energy_drift_per_revolution"] = abs(out["energy_change"]) / revolutions
    return out


def scheme_energy_balance(log_text, pattern, initial_energy, revolutions=None):
    """energy_balance of a body plugin's own energy: history.csv's strain energy is the host's material energy of the
    world displacement, not the scheme's (a co-rotational scheme conserves 1/2 s.M s + 1/2 u.S u, not the SVK energy).
    `pattern` matches the plugin's line per converged step in the --verbose log, with the named groups E (the scheme's
    energy after the step) and optionally work (the energy friction dissipated in the step). initial_energy is
    history.csv's first row (the scene's rigid motion, undeformed: the scheme's energy there as well). None when no
    line matched."""
    import re
    rows, dissipated = [{"total_energy": initial_energy}], 0.0
    for m in re.finditer(pattern, log_text, re.MULTILINE):
        dissipated += float(m.group("work")) if "work" in m.groupdict() else 0.0
        rows.append({"total_energy": float(m.group("E")), "dissipated_energy": dissipated})
    return energy_balance(rows, revolutions) if len(rows) > 1 else None


def reversals(counts):
    """Steps at which the number of active points turns back (grew, then shrank, or the reverse) within two steps:
    chattering in time shows up as many of these."""
    n, last = 0, None  # last: (index, sign) of the last nonzero change
    for i in range(1, len(counts)):
        d = counts[i] - counts[i - 1]
        if d == 0:
            continue
        sign = 1 if d > 0 else -1
        if last is not None and sign != last[1] and i - last[0] <= 2:
            n += 1
        last = (i, sign)
    return n
