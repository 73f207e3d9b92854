"""history.csv's external_work: the work of the loads (body force, tractions, resultants), checked against the energy
balance of the implicit midpoint scheme, which with hyperelastic bodies and no contact or moving supports keeps
E_n - E_0 = W_n to round-off (M (v_n+1 - v_n) / dt + f_int = f_ext at the midpoint, times u_n+1 - u_n = dt v_n+1/2;
the internal force is the scheme's discrete gradient of the strain energy). A wrong load time (t_n+1 instead of the
midpoint), a missing load or a load counted twice breaks the balance by the order of the load's work.

- external_work_traction_body_force: scenes/cantilever-2d.yaml made dynamic (midpoint, neo-Hooke), its end traction
  ramped to 2 over half the run, with a body force.
- external_work_resultant_current_area: scenes/compressed-block.yaml made dynamic, its top loaded by a follower
  resultant over the current area (non-conservative: only the work at the scheme's configuration balances), with a
  body force; the same on 2 ranks gives the same column.
- external_work_restart: the cantilever's run restarted from a checkpoint at step 8 continues the column: equal to the
  uninterrupted run's (the checkpoint carries the work done before it).
- external_work_corotational_at_rest: the co-rotational ball of Hauret et al. 6.3 at rest, dropped onto its plane by a
  body force and a traction ramp on its rim (frictionless; the traction at the body plugin's force time): E - E0 = W to round-off (a body without rotation: the scheme's load work dt f . s is the
  world work). A body at rest once gave the rotation row the scale 0/0 (a NaN residual at step 1).
- external_work_corotational_spinning: the same ball spinning in free flight under a body force: the scheme rotates the
  loads to the midpoint (f = R_m^T f_W), so its load work differs from the world work by O(dt^2): halving dt divides
  max |E - E0 - W| by 4 (docs/plugins/corotational.md, discrete energy).

The disk pile (test_nts_self_contact.py nts_disk_pile_energy) checks the column against the work of gravity computed
from the momenta."""
import tempfile

from stickslip_results import main, run
from test_restart import interrupted, restarted, straight

CANTILEVER = ["--set", "time.scheme=midpoint", "--set", "time.dt=0.5", "--set", "time.end=10",
              "--set", "boundary.1.traction=[0,-2]", "--set", "boundary.1.history=[[0,0],[5,1]]",
              "--set", "body_force=[0.02,-0.05,0]", "--set", "bodies.0.material.model=neo-hooke-bonet",
              "--set", "output.vtu_every=0"]
BLOCK = ["--set", "time.scheme=midpoint", "--set", "time.dt=0.05", "--set", "time.end=0.6",
         "--replace", "boundary.3={name: load, group: zmax, resultant: [30, 20, -400], area: current, "
         "history: [[0, 0], [0.5, 1]]}", "--set", "bodies.0.material.model=neo-hooke-bonet",
         "--set", "body_force=[1,0,-5]", "--set", "output.vtu_every=0"]


def balance(rows):
    """Largest |E_n - E_0 - W_n| and the scale max(|E| + |W|) over the rows."""
    e0 = rows[0]["total_energy"]
    scale = max(abs(r["total_energy"]) + abs(r["external_work"]) for r in rows)
    return max(abs(r["total_energy"] - e0 - r["external_work"]) for r in rows), scale


def external_work_traction_body_force(checks):
    results, _ = run("scenes/cantilever-2d.yaml", *CANTILEVER)
    rows = results.rows
    error, scale = balance(rows)
    checks.check(rows[-1]["time"] == 10 and rows[-1]["external_work"] > 0.1 * scale, "20 steps; the loads did work "
                 "%.4g (scale %.4g)" % (rows[-1]["external_work"], scale))
    checks.check(error <= 2e-14 * scale, "E - E0 = external_work at every step to %.3g (<= 2e-14 x %.3g)"
                 % (error, scale))


def external_work_resultant_current_area(checks):
    one, _ = run("scenes/compressed-block.yaml", *BLOCK)
    two, _ = run("scenes/compressed-block.yaml", *BLOCK, np=2)
    error, scale = balance(one.rows)
    checks.check(one.rows[-1]["time"] == 0.6 and one.rows[-1]["external_work"] > 0.1 * scale, "to t = 0.6; the loads "
                 "did work %.4g (scale %.4g)" % (one.rows[-1]["external_work"], scale))
    checks.check(error <= 1e-15 * scale, "E - E0 = external_work at every step to %.3g (<= 1e-15 x %.3g)"
                 % (error, scale))
    ranks = max(abs(a["external_work"] - b["external_work"]) for a, b in zip(one.rows, two.rows))
    checks.check(len(one.rows) == len(two.rows) and ranks <= 2e-15 * scale, "2 ranks: the same %d rows, external_work "
                 "to %.3g (<= 2e-15 x %.3g)" % (len(two.rows), ranks, scale))


COROT = ["--set", "output.vtu_every=0", "--quiet"]


def external_work_corotational_at_rest(checks):
    results, _ = run("scenes/corot-ball-on-plane.yaml", *COROT, "--set", "body_force=[0,-5000,0]", "--replace",
                     "boundary=[{name: push, group: boundary, traction: [0, -100000], history: [[0, 0], [0.06, 1]]}]",
                     "--set", "bodies.0.angular_velocity=[0,0,0]", "--set", "bodies.0.velocity=[0,0,0]")
    rows = results.rows
    error, scale = balance(rows)
    checks.check(rows[-1]["time"] == 0.06 and max(r["contact_force_y"] for r in rows) > 0, "to t = 0.06, dropped onto "
                 "the plane (largest contact force %.4g)" % max(r["contact_force_y"] for r in rows))
    checks.check(error <= 1e-14 * scale, "E - E0 = external_work at every step to %.3g (<= 1e-14 x %.3g)"
                 % (error, scale))


def external_work_corotational_spinning(checks):
    errors = []
    for dt in (0.002, 0.001):
        results, _ = run("scenes/corot-ball-on-plane.yaml", *COROT, "--set", "body_force=[3000,-5000,0]",
                         "--set", "contact.0.obstacle.point=[0,-1000,0]", "--set", "time.dt=%g" % dt)
        error, scale = balance(results.rows)
        errors.append(error / scale)
    checks.check(1e-8 < errors[0] < 1e-5, "dt 0.002: max |E - E0 - W| = %.3g of the scale (the scheme's O(dt^2))"
                 % errors[0])
    ratio = errors[0] / errors[1]
    checks.check(abs(ratio - 4) <= 0.01, "halving dt divides it by %.4f (4 +- 0.01: second order)" % ratio)


def external_work_restart(checks):
    case = ("scenes/cantilever-2d.yaml", CANTILEVER, 16, 8)
    folder = tempfile.mkdtemp(prefix="stickslip-work-")
    reference = straight(case, 1, folder)
    result = restarted(case, interrupted(case, 1, folder), 1, folder, "restarted")
    difference = max(abs(a["external_work"] - b["external_work"]) for a, b in zip(reference.rows, result.rows))
    scale = max(abs(r["external_work"]) for r in reference.rows)
    checks.check(len(result.rows) == len(reference.rows) == 17 and result.rows[8]["external_work"] > 0,
                 "17 rows in both runs, work done before the checkpoint (%.4g)" % result.rows[8]["external_work"])
    checks.check(difference <= 1e-15 * scale, "the restarted run's external_work is the uninterrupted run's to %.3g "
                 "(<= 1e-15 x %.3g)" % (difference, scale))


if __name__ == "__main__":
    main([external_work_traction_body_force, external_work_resultant_current_area, external_work_restart,
          external_work_corotational_at_rest, external_work_corotational_spinning])
