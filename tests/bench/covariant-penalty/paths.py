"""Prescribed paths of the Konyukhov-Schweizerhof examples as scene histories (piecewise linear, at most 64 points):
prints the `history:` lists that scenes/ks-parabolic*.yaml and scenes/ks-spiral.yaml carry, so a changed path is
regenerated rather than edited by hand.

  python3 tests/bench/covariant-penalty/paths.py parabolic STEPS DU     # 6.2, Eq. (116): 7 pressing steps, then
                                                                        # STEPS steps of DU along the parabola
  python3 tests/bench/covariant-penalty/paths.py spiral STEPS [V]       # 6.3, Eq. (127): 1 pressing step, then STEPS
                                                                        # steps of v t (v = 1e-2, the paper's)
"""
import sys


def fmt(points):
    return "[" + ", ".join("[%.10g, %.10g]" % p for p in points) + "]"


def parabolic(steps, du, c=0.03, h=-0.007, press_steps=7):
    """Top of the block: pressed by h in press_steps steps (t = 1 .. 7), then moved along (116),
    r = (u (1 - 2 c h), 0, h + c u^2 (1 - 2 c h)), u = du (t - 7). With more than 56 steps the quadratic z is
    sampled at 56 points (linear in between; error c (du steps / 56)^2 / 8)."""
    s = 1.0 - 2.0 * c * h
    x = [(0, 0.0), (press_steps, 0.0)]
    z = [(0, 0.0), (press_steps, h)]
    samples = min(steps, 56)
    for k in range(1, samples + 1):
        t = press_steps + steps * k / samples
        u = du * steps * k / samples
        x.append((t, u * s))
        z.append((t, h + c * u * u * s))
    return x, z


def spiral(steps, v=1e-2, total=1000, length=20.0, c=0.05, h=-0.01):
    """Cut faces of the semi-cylinder: pressed by h in step 1, then (127) with t the step count after it:
    r = (v t (1 - 2 c h), length (v t) / (v_paper total), h + c (1 - 2 c h) (v t)^2): the paper's path, v t the
    distance along x, so another v walks the same path in other steps (y = 20 t/T with v = 1e-2, T = 1000). Exact at
    every step for steps <= 62."""
    s = 1.0 - 2.0 * c * h
    x, y, z = [(0, 0.0), (1, 0.0)], [(0, 0.0), (1, 0.0)], [(0, 0.0), (1, h)]
    samples = min(steps, 62)
    for k in range(1, samples + 1):
        t = steps * k / samples
        x.append((1 + t, v * t * s))
        y.append((1 + t, length * v * t / (1e-2 * total)))
        z.append((1 + t, h + c * s * (v * t) ** 2))
    return x, y, z


if __name__ == "__main__":
    if len(sys.argv) >= 4 and sys.argv[1] == "parabolic":
        hx, hz = parabolic(int(sys.argv[2]), float(sys.argv[3]))
        print("x:", fmt(hx))
        print("z:", fmt(hz))
    elif len(sys.argv) >= 3 and sys.argv[1] == "spiral":
        hx, hy, hz = spiral(int(sys.argv[2]), float(sys.argv[3]) if len(sys.argv) > 3 else 1e-2)
        print("x:", fmt(hx))
        print("y:", fmt(hy))
        print("z:", fmt(hz))
    else:
        sys.exit(__doc__)
