"""Errors of a Hertz run's contact pressure against Hertz's closed forms (docs/validation.md), shared by the validation
tests and tests/bench/hertz. All relative, with the reference a and p0 from the load the run carries (2D:
P = 2 |reaction_top_y|, 3D: F = 4 |reaction_top_z|), so they measure the shape of the pressure distribution, not the
load-approach relation (that is checked in test_contact_scenes.py):
  a     contact half-width / radius of the least-squares fit p^2 = p0^2 (1 - r^2/a^2) over the nodes in contact
        (gap <= 0: on quadratic faces penalty-nts also reports the recovered traction next to the contact zone)
  p0    peak pressure of that fit
  peak  pressure of the node at the centre against p0
  l2    profile error  sqrt(sum (p_i - p_H(r_i))^2 / sum p_H(r_i)^2)  over the slave nodes with r_i < 1.25 a, at their
        reference positions (r = |x| in 2D, sqrt(x^2 + y^2) in 3D)
  l2_core  the same over r_i < 0.8 a, where p_H is smooth: what is left when the edge of the contact zone (infinite
        slope of p_H at r = a, smeared over about one element by any node-to-surface method) is taken out."""
import math

from test_contact_scenes import e_star, fit_hertz_profile

PROFILE_RANGE = 1.25  # the L2 profile error covers r < PROFILE_RANGE * a
CORE_RANGE = 0.8     # ... and l2_core r < CORE_RANGE * a


def hertz_reference(dim, results):
    """(load, a, p0) of Hertz's solution for the load the run carries (docs/validation.md)."""
    last = results.rows[-1]
    return hertz_from_reaction(dim, last["reaction_top_y"] if dim == 2 else last["reaction_top_z"])


def hertz_from_reaction(dim, reaction):
    """(load, a, p0) of Hertz's solution for the reaction at the top of the half (2D) or quarter (3D) model."""
    Es = e_star(1000.0, 1.0e6)
    if dim == 2:
        P = 2 * abs(reaction)
        a = math.sqrt(4 * P / (math.pi * Es))
        return P, a, 2 * P / (math.pi * a)
    F = 4 * abs(reaction)
    a = (3 * F / (4 * Es)) ** (1.0 / 3.0)
    return F, a, 3 * F / (2 * math.pi * a * a)


def profile_errors(points, a, p0):
    """Relative errors of the fit (a, p0), the centre node and the L2 profile; points are [(r, p, gap, node)]."""
    active = [(r, p) for r, p, g, n in points if p > 0 and g <= 0]
    a_fit, p0_fit = fit_hertz_profile(active)
    def l2(limit):
        num = den = 0.0
        for r, p, g, n in points:
            if r < limit * a:
                exact = p0 * math.sqrt(max(0.0, 1.0 - (r / a) ** 2))
                num += (p - exact) ** 2
                den += exact ** 2
        return math.sqrt(num / den)
    return {"a": (a_fit - a) / a, "p0": (p0_fit - p0) / p0, "peak": (points[0][1] - p0) / p0,
            "l2": l2(PROFILE_RANGE), "l2_core": l2(CORE_RANGE), "active": len(active),
            "profile_nodes": sum(1 for r, p, g, n in points if r < PROFILE_RANGE * a)}
