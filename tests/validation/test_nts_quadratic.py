"""nts-augmented on second-order faces (2D: curved LINE3 faces of quad9 meshes; 3D: QUAD9 faces of hex27 meshes;
every face node a slave point with its own multiplier, the mid-side and centre nodes included). Usage: python3
test_nts_quadratic.py CASE (CASES at the bottom).

- nts_quad9_patch_2d: scenes/patch-test-2d.yaml on quad9 (mesh.order 2), frictionless. With matching interface
  meshes (4 against 4 elements) every slave node sits on a master node and the nodal pressures are p = 10 to the
  Newton tolerance; with the scene's non-matching meshes (5 upper against 4 lower) the total force is exact and the
  nodal pressures are not uniform, as for every one-pass node-to-surface formulation (penalty-nts on the same quad9
  mesh deviates by the same 14.2 %; on quad4 both deviate by 7.7 %).
- nts_hex27_patch_3d: scenes/patch-test-3d.yaml on hex27 (QUAD9 slave and master faces, 5 x 5 against 4 x 4
  elements), frictionless, in the scene's two steps: the total force is exact, all 121 slave nodes touch, and the
  nodal pressures deviate from p as penalty-nts's do on the same mesh (27.8 %). The first step leaves the 13 slave
  nodes on the two free border edges 3e-5 ... 6e-5 beyond the master's border (the upper block's edge expands more
  under the non-uniform nodal loads); they keep their faces through master_extension (without it they were released
  in the second step; docs/plugins/nts-augmented.md, "Quadratic faces").
- nts_quad9_hertz_2d: scenes/hertz-2d.yaml on quad9, refine 1, frictionless, only the plugin's defaults: the L2
  profile error against Hertz (the metric of docs/hertz.md). penalty-nts on the same mesh: 0.0096.

The measured numbers, with their commands, are in docs/plugins/nts-augmented.md, "Quadratic faces"."""
from hertz_profile import hertz_reference, profile_errors
from stickslip_results import main, run
from test_contact_scenes import reference_points

NTS = ("--plugin", "nts-augmented", "--replace", "contact.0.parameters={}")
ORDER2 = ("--set", "mesh.order=2")
P = 10.0


def patch_run(c, label, *args):
    results, _ = run("scenes/patch-test-2d.yaml", *NTS, *ORDER2, *args)
    last = results.rows[-1]
    c.check(results.summary["status"] == "ok" and abs(last["contact_force_y"] - P) <= 1e-12 * P
            and abs(last["reaction_base_y"] - P) <= 1e-12 * P, "%s: contact force %.15g = base reaction %.15g = "
            "p * width" % (label, last["contact_force_y"], last["reaction_base_y"]))
    c.check(last["constraint_violation"] <= 1e-14, "%s: max |Phi| %.1e" % (label, last["constraint_violation"]))
    points = results.contact_points()
    c.check(all(q["state"] == 1 for q in points), "%s: all %d slave nodes in contact" % (label, len(points)))
    deviation = max(abs(q["pressure"] - P) for q in points) / P
    print("%s: %d slave nodes, pressures %.12g ... %.12g, max deviation %.3e"
          % (label, len(points), min(q["pressure"] for q in points), max(q["pressure"] for q in points), deviation))
    return len(points), deviation


def nts_quad9_patch_2d(c):
    """Measured: matching meshes 9 slave nodes (5 corners, 4 mid-side), deviation 2.3e-11 (the Newton tolerance);
    non-matching 11 slave nodes, 14.16 % (penalty-nts 14.16 %), refine 2 14.23 % (penalty-nts 14.22 %)."""
    n, deviation = patch_run(c, "quad9, matching meshes", "--set", "mesh.parameters.nx_upper=4")
    c.check(n == 9 and deviation <= 1e-10, "matching meshes: nodal pressures = p to %.1e over %d nodes (<= 1e-10)"
            % (deviation, n))
    n, deviation = patch_run(c, "quad9, non-matching meshes")
    c.check(n == 11 and deviation <= 0.145, "non-matching meshes: one-pass NTS deviation %.2f %% <= 14.5 %%"
            % (100 * deviation))


def nts_hex27_patch_3d(c):
    """Measured: 121 slave nodes (25 corners, 60 edge, 36 centre nodes), all in contact, deviation 27.78 %
    (penalty-nts 27.77 %), max |Phi| 3.9e-18."""
    results, _ = run("scenes/patch-test-3d.yaml", *NTS, *ORDER2)
    last = results.rows[-1]
    c.check(results.summary["status"] == "ok" and abs(last["contact_force_z"] - P) <= 1e-12 * P
            and abs(last["reaction_base_z"] - P) <= 1e-12 * P, "contact force %.15g = base reaction %.15g = p * area"
            % (last["contact_force_z"], last["reaction_base_z"]))
    c.check(last["constraint_violation"] <= 1e-14, "max |Phi| %.1e" % last["constraint_violation"])
    points = results.contact_points()
    c.check(len(points) == 121 and all(q["state"] == 1 for q in points),
            "all %d slave nodes of the QUAD9 faces in contact" % len(points))
    deviation = max(abs(q["pressure"] - P) for q in points) / P
    c.check(deviation <= 0.285, "one-pass NTS deviation %.2f %% <= 28.5 %% (penalty-nts on this mesh: 27.77 %%)"
            % (100 * deviation))


def nts_quad9_hertz_2d(c):
    """Measured at refine 1: 11 503 unknowns, L2 profile 0.0091, a +0.54 %, p0 +0.27 % over the 11 active nodes
    (penalty-nts: 0.0096, a +0.59 %, p0 +0.23 %; mortar-dual: 0.0090, a +0.54 %, p0 +0.27 %). The fit's a and p0 were
    -0.18 % and +0.42 % when it took an active node only where the sign of its round-off gap (+-1e-19) was negative:
    5 of the 11 nodes, 7 when the Newton iterations stopped one earlier (a +0.62 %); reference_points now takes them
    all from the plugin's contact state, so the bound on a sits at the value of the whole active set."""
    results, _ = run("scenes/hertz-2d.yaml", *NTS, *ORDER2, "--set", "output.vtu_every=4")
    last = results.rows[-1]
    c.check(results.summary["status"] == "ok" and last["constraint_violation"] <= 1e-13,
            "max |Phi| %.1e" % last["constraint_violation"])
    _, a, p0 = hertz_reference(2, results)
    e = profile_errors(reference_points(results, radial=False), a, p0)
    print("quad9 refine 1: %d unknowns, %d nodes in r < 1.25 a, L2 profile %.4f, a %+.3e, p0 %+.3e"
          % (results.summary["unknowns"], e["profile_nodes"], e["l2"], e["a"], e["p0"]))
    c.check(e["l2"] <= 0.0095, "L2 profile error %.4f <= 0.0095 (penalty-nts on this mesh: 0.0096)" % e["l2"])
    c.check(abs(e["a"]) <= 0.006 and abs(e["p0"]) <= 0.005, "fit errors a %+.2e (<= 0.6 %%), p0 %+.2e (<= 0.5 %%)"
            % (e["a"], e["p0"]))


if __name__ == "__main__":
    main([nts_quad9_patch_2d, nts_hex27_patch_3d, nts_quad9_hertz_2d])
