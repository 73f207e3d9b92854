"""Error measures of a finished run against a closed form or a reference run: each takes (results, variables,
reference) and returns {"error": number, ...details}; `variables` are the numbers the measure needs (a benchmark's
`variables:`, or `stickslip compare --closed-form hertz:E=...`). The norm of each is stated in its docstring and in
docs/benchmarks.md. Shared by `stickslip compare` and the benchmark harness (tests/bench/harness/errors.py)."""
import bisect
import math


class ErrorMeasureError(Exception):
    """A measure that cannot be evaluated as asked (a missing reference or variable); the message says what."""

PROFILE_RANGE = 1.25  # Hertz profile error over r < 1.25 a (as tests/validation's hertz_profile.py)


def contact_pressures(results):
    """The last state's contact points (contact.csv's pressure is a traction for every plugin)."""
    return results.contact_points()


def reference_positions(results, radial):
    """[(r, pressure, gap)] of the last state's contact points at their reference positions: the reference_x/y/z
    columns when contact.csv has them, else current position minus the node's displacement (.vtu), else the current
    position (Gauss-point output without reference coordinates: Hertz's x shrinks by ~3 % there; reported)."""
    points = contact_pressures(results)
    u = None
    out, current_only = [], 0
    for p in points:
        if "reference_x" in p:
            X = [p["reference_x"], p["reference_y"], p["reference_z"]]
        elif p["node"] >= 0:
            if u is None:
                u = results.last_vtu()["displacement"]
            X = [p[c] - u[int(p["node"])][i] for i, c in enumerate("xyz")]
        else:
            X = [p["x"], p["y"], p["z"]]
            current_only += 1
        r = math.hypot(X[0], X[1]) if radial else abs(X[0])
        out.append((r, p["pressure"], p["gap"]))
    return sorted(out), current_only


def hertz_profile(results, variables, reference=None):
    """Relative discrete l2 error of the contact pressure against Hertz, sqrt(sum (p_i - p_H(r_i))^2 / sum
    p_H(r_i)^2) over the slave points with r_i < 1.25 a at their reference positions; a and p0 from the load the run
    carries (2D: P = factor |reaction|, a = sqrt(4PR/(pi E*)), p0 = 2P/(pi a); 3D: a = (3FR/(4E*))^(1/3),
    p0 = 3F/(2 pi a^2)), so the error measures the distribution, not the load-approach relation."""
    v = need_variables(variables, "hertz_profile", ("dim", "E", "E_master", "nu", "R", "load_column", "load_factor"))
    E1, E2, nu, R = v["E"], v["E_master"], v["nu"], v["R"]
    Es = 1.0 / ((1 - nu ** 2) / E1 + (1 - nu ** 2) / E2)
    load = v["load_factor"] * abs(results.rows[-1][v["load_column"]])
    if v["dim"] == 2:
        a = math.sqrt(4 * load * R / (math.pi * Es))
        p0 = 2 * load / (math.pi * a)
    else:
        a = (3 * load * R / (4 * Es)) ** (1.0 / 3.0)
        p0 = 3 * load / (2 * math.pi * a * a)
    points, current_only = reference_positions(results, v["dim"] == 3)
    num = den = 0.0
    count = 0
    for r, p, g in points:
        if r < PROFILE_RANGE * a:
            exact = p0 * math.sqrt(max(0.0, 1.0 - (r / a) ** 2))
            num += (p - exact) ** 2
            den += exact ** 2
            count += 1
    if den == 0:
        raise ValueError("no contact points within 1.25 a = %g" % (PROFILE_RANGE * a))
    return {"error": math.sqrt(num / den), "load": load, "a": a, "p0": p0, "profile_points": count,
            "current_positions": current_only}


def patch_pressure(results, variables=None, reference=None):
    """Largest relative deviation of the contact pressure from uniform over the slave points in contact,
    max_i |p_i - mean p| / mean p (max norm). Uniformity is what the patch test asks; the level depends on the
    measure a plugin reports: the load p is nominal, so a Cauchy traction on the interface, which the lateral
    (Poisson) expansion widens by 0.39 % at p = 10, E = 1000, is p L0 / L = 9.961 (mortar-dual), while a force per
    reference area is p (penalty-nts). The mean is reported beside it."""
    pressures = [q["pressure"] for q in contact_pressures(results) if q["state"] > 0]
    if not pressures:
        raise ValueError("no contact point in contact")
    mean = sum(pressures) / len(pressures)
    worst = max(abs(q - mean) for q in pressures) / abs(mean)
    return {"error": worst, "points": len(pressures), "mean": mean, "min": min(pressures), "max": max(pressures)}


def _interpolate(times, values, t):
    i = bisect.bisect_left(times, t)
    if i < len(times) and abs(times[i] - t) <= 1e-12 * max(1.0, abs(t)):
        return values[i]
    if i == 0 or i >= len(times):
        return values[min(max(i, 0), len(values) - 1)]
    w = (t - times[i - 1]) / (times[i] - times[i - 1])
    return (1 - w) * values[i - 1] + w * values[i]


def reaction_history(results, variables, reference):
    """max_t |R_h(t) - R_ref(t)| / max_t |R_ref(t)| over the reference's (finer) time points: the support reaction
    vector (the columns listed in the benchmark's `variables.columns`), the run's history interpolated linearly
    between its steps, so that a coarse step is charged for what it misses between its points. A run that did not
    reach the end time is an error (its history is incomplete)."""
    if reference is None:
        raise ErrorMeasureError("reaction_history needs a reference run")
    columns = need_variables(variables, "reaction_history", ("columns",))["columns"]
    missing = [c for c in columns if c not in reference.rows[0] or c not in results.rows[0]]
    if missing:
        raise ErrorMeasureError("reaction_history: history.csv has no column %s" % ", ".join(missing))
    t_ref = reference.column("time")
    ref = [reference.column(c) for c in columns]
    scale = max(math.sqrt(sum(col[i] ** 2 for col in ref)) for i in range(len(t_ref)))
    if abs(results.rows[-1]["time"] - t_ref[-1]) > 1e-9 * max(1.0, t_ref[-1]):
        raise ValueError("the run ended at t = %g before the reference's %g" % (results.rows[-1]["time"], t_ref[-1]))
    times = results.column("time")
    mine = [results.column(c) for c in columns]
    worst, at = 0.0, 0.0
    for i, t in enumerate(t_ref):
        d = math.sqrt(sum((_interpolate(times, col, t) - rcol[i]) ** 2 for col, rcol in zip(mine, ref)))
        if d > worst:
            worst, at = d, t
    return {"error": worst / scale, "at_time": at, "scale": scale}


def final_positions(results, variables, reference):
    """max_i |x_i(T) - x_i,ref(T)| / length: the largest nodal position difference at the end time T against the
    converged reference (the deformed positions of the last .vtu; length = `variables.length`)."""
    if reference is None:
        raise ErrorMeasureError("final_positions needs a reference run")
    T = reference.rows[-1]["time"]
    if abs(results.rows[-1]["time"] - T) > 1e-9 * max(1.0, T):
        raise ValueError("the run ended at t = %g, the reference at %g" % (results.rows[-1]["time"], T))
    a, b = results.last_vtu()["Points"], reference.last_vtu()["Points"]
    if len(a) != len(b):
        raise ValueError("%d nodes against the reference's %d" % (len(a), len(b)))
    worst = max(math.dist(p, q) for p, q in zip(a, b))
    return {"error": worst / (variables or {}).get("length", 1.0)}


EVALUATORS = {f.__name__: f for f in (hertz_profile, patch_pressure, reaction_history, final_positions)}


def need_variables(variables, measure, names):
    missing = [n for n in names if n not in (variables or {})]
    if missing:
        raise ErrorMeasureError("%s needs the variable(s) %s" % (measure, ", ".join(missing)))
    return variables
