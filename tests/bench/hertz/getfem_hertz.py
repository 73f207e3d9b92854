"""GetFEM 5.4 solution of the project's Hertz scenes (scenes/hertz-2d.yaml, hertz-3d.yaml), for bench_getfem.py.

  /usr/bin/python3 tests/bench/hertz/getfem_hertz.py ELEMENT REFINE OUT.json [--r R] [--max-res RES]

Runs under a Python that has getfem (Debian: `apt-get install python3-getfem`, GetFEM 5.4.2). The problem is the
scene's, read from its YAML: the same gmsh mesh (the scene's .geo with its mesh parameters, REFINE and the order of
ELEMENT, meshed by the gmsh command line into .msh 2.2; each body imported as its own GetFEM mesh, since one GetFEM
mesh would merge the two bodies' coincident nodes at the first contact point), the same materials (small-strain
isotropic linear elasticity, plane strain in 2D), the same boundary conditions (a fixed group by elimination, a
single prescribed component as a normal Dirichlet condition with multipliers on the flat group), the same load
steps, frictionless contact of the scene's slave group on its master group by GetFEM's nodal contact brick between
non-matching meshes (Alart-Curnier augmented Lagrangian, small sliding, one nodal force per slave node), Newton with
MUMPS until |F|_1 / L <= --max-res after an iteration (md.solve's Newton_with_step_control in GetFEM 5.4: L the
bricks' norm of the external data; no update test). It writes JSON: the cost (unknowns, Newton iterations per step, phase times), the top reaction (the load),
the sum of the contact forces, and the slave nodes' reference positions, pressures and gaps, from which
bench_getfem.py computes the project's errors (hertz_profile.py). Pressures from the nodal forces f_k: p_k = f_k /
w_k with w_k = the integral of the node's shape function over the slave faces, the lumped recovery penalty-nts
reports; on TRI6 slave faces (corner weights 0) penalty-nts's recovery in the modified basis, p = T^T f / T^T w
with the corner's shape function N_c + alpha (N_m1 + N_m2) and the edge node's (1 - 2 alpha) N_m, alpha = 1/5, an
open corner reporting it only when its edge neighbours carry force (docs/plugins/penalty-nts.md, "Quadratic
faces"); `--recovery consistent` solves M p = f instead (M the slave
faces' mass matrix)."""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np
import yaml

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(HERE)))
# element label -> (dimension, scene, --set overrides): the same table the stickslip runs use
sys.path.insert(0, HERE)
from hertz_cases import ELEMENTS  # noqa: E402


def scene_setup(element, refine):
    """The scene (parsed YAML) with the element's overrides: (scene, scene directory, mesh parameters, order)."""
    dim, scene_path, sets = ELEMENTS[element]
    path = os.path.join(ROOT, scene_path)
    with open(path) as f:
        scene = yaml.safe_load(f)
    params = dict(scene["mesh"].get("parameters", {}))
    order = int(scene["mesh"].get("order", 1))
    for s in list(sets) + ["mesh.parameters.refine=%g" % refine]:
        name, _, value = s.partition("=")
        if name.startswith("mesh.parameters."):
            params[name[len("mesh.parameters."):]] = float(value)
        elif name == "mesh.order":
            order = int(value)
        else:
            raise SystemExit("getfem_hertz.py: override '%s' not understood" % s)
    return dim, scene, os.path.dirname(path), params, order


# ---- mesh ---------------------------------------------------------------------------------------------------------
def gmsh_mesh(geo, params, dim, order, work):
    """Meshes the .geo with the parameters assigned before its DefineConstant (as stickslip does) into .msh 2.2."""
    wrapper = os.path.join(work, "mesh.geo")
    with open(wrapper, "w") as f:
        for name, value in params.items():
            f.write("%s = %.17g;\n" % (name, value))
        f.write('Include "%s";\n' % os.path.abspath(geo))
    out = os.path.join(work, "mesh.msh")
    command = ["gmsh", wrapper, "-%d" % dim, "-format", "msh22", "-o", out]
    if order > 1:
        command += ["-order", str(order)]
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return out


def split_msh(path, bodies, dim, work):
    """Writes one .msh 2.2 per body (its volume group and the boundary elements whose nodes are all its nodes);
    returns ({body group: file}, {physical name: tag}, {physical tag: [element's node coordinates]})."""
    lines = open(path).read().split("\n")
    sec = {name: lines.index("$" + name) for name in ("PhysicalNames", "Nodes", "Elements")}
    names = {}
    for line in lines[sec["PhysicalNames"] + 2:lines.index("$EndPhysicalNames")]:
        d, tag, name = line.split(None, 2)
        names[name.strip('"')] = int(tag)
    header = lines[:sec["Nodes"]]
    nodes = lines[sec["Nodes"]:lines.index("$EndNodes") + 1]
    elements = [l.split() for l in lines[sec["Elements"] + 2:lines.index("$EndElements")]]
    files = {}
    for body in bodies:
        tag = names[body]
        volume = [e for e in elements if int(e[3]) == tag]
        body_nodes = set(n for e in volume for n in e[3 + int(e[2]):])
        keep = [e for e in elements if int(e[3]) == tag or
                (int(e[3]) != tag and all(n in body_nodes for n in e[3 + int(e[2]):]) and
                 int(e[3]) not in [names[b] for b in bodies])]
        out = os.path.join(work, "%s.msh" % body)
        with open(out, "w") as f:
            f.write("\n".join(header + nodes + ["$Elements", str(len(keep))] + [" ".join(e) for e in keep] +
                              ["$EndElements", ""]))
        files[body] = out
    coords = {}
    for line in nodes[2:-1]:
        tag, x, y, z = line.split()
        coords[tag] = (float(x), float(y), float(z))
    faces = {}
    for e in elements:
        faces.setdefault(int(e[3]), []).append([coords[n] for n in e[3 + int(e[2]):]])
    return files, names, faces


# ---- model --------------------------------------------------------------------------------------------------------
def history_factor(history, t):
    """The scene's piecewise linear load history at time t."""
    for (t0, v0), (t1, v1) in zip(history, history[1:]):
        if t0 <= t <= t1:
            return v0 + (v1 - v0) * (t - t0) / (t1 - t0)
    return history[-1][1]


def outward_axis(mesh, region):
    """(axis, sign) of the outward unit normal of a flat boundary region along a coordinate axis (else an error)."""
    faces = mesh.region(region)
    normals = mesh.normal_of_faces(faces)
    mean = normals.mean(axis=1)
    axis = int(np.argmax(abs(mean)))
    if not np.allclose(normals, np.outer(np.eye(len(mean))[axis] * np.sign(mean[axis]), np.ones(normals.shape[1])),
                       atol=1e-8):
        raise SystemExit("getfem_hertz.py: a single prescribed component needs a flat group normal to that axis")
    return axis, float(np.sign(mean[axis]))


def modified_basis(faces, X, dim, alpha=0.2):
    """T with N~ = T^T N over TRI6 faces (gmsh order: corners 0-2, edge nodes 3 = (0, 1), 4 = (1, 2), 5 = (2, 0)):
    column k of T holds the coefficients of node k's modified shape function."""
    from scipy.sparse import lil_matrix
    index = {tuple(np.round(X[:, k], 9)): k for k in range(X.shape[1])}
    T = lil_matrix((X.shape[1], X.shape[1]))
    T.setdiag(1.0)
    for face in faces:
        k = [index[tuple(np.round(p[:dim], 9))] for p in face]
        for m, (a, b) in zip(k[3:], ((0, 1), (1, 2), (2, 0))):
            T[m, m] = 1.0 - 2.0 * alpha
            T[m, k[a]] = alpha
            T[m, k[b]] = alpha
    return T.tocsr()


def pressures(mass, force, gap, faces, X, dim, recovery):
    """Nodal pressures from the nodal forces (module docstring); an open TRI6 corner reports its recovered pressure
    only when every edge node next to it carries a force, as penalty-nts does for an exactly closed neighbourhood."""
    weights = np.asarray(mass.sum(axis=1)).ravel()
    if recovery == "consistent":
        from scipy.sparse.linalg import spsolve
        return spsolve(mass.tocsc(), force), recovery
    if dim == 3 and all(len(f) == 6 for f in faces):
        T = modified_basis(faces, X, dim).tocsc()
        p = (T.T @ force) / (T.T @ weights)
        for k in range(len(p)):
            neighbours = [m for m in T.indices[T.indptr[k]:T.indptr[k + 1]] if m != k]
            if gap[k] > 0 and force[k] <= 0 and neighbours and not all(force[m] > 0 for m in neighbours):
                p[k] = 0.0
        return p, "modified basis"
    return force / weights, recovery


def solve(element, refine, r_factor, max_res, recovery):
    import getfem as gf
    gf.util_trace_level(0)
    gf.util_warning_level(0)
    clock = {"start": time.perf_counter()}
    dim, scene, scene_dir, params, order = scene_setup(element, refine)
    bodies = [b["group"] for b in scene["bodies"]]
    work = tempfile.mkdtemp(prefix="stickslip-bench-getfem-")
    msh = gmsh_mesh(os.path.join(scene_dir, scene["mesh"]["file"]), params, dim, order, work)
    files, tags, faces = split_msh(msh, bodies, dim, work)
    md = gf.Model("real")
    body = {}
    for b, spec in zip(bodies, scene["bodies"]):
        mat = spec["material"]
        if mat["model"] != "hooke":
            raise SystemExit("getfem_hertz.py: material %s not modelled (hooke only)" % mat["model"])
        m = gf.Mesh("import", "gmsh", files[b])
        mf = gf.MeshFem(m, dim)
        mf.set_classical_fem(order)
        mim = gf.MeshIm(m, 2 * order)
        name = b.replace("-", "_")  # GetFEM's variable names take no '-'
        u = "u_" + name
        md.add_fem_variable(u, mf)
        E, nu = float(mat["E"]), float(mat["nu"])
        md.add_initialized_data("lambda_" + name, [E * nu / ((1 + nu) * (1 - 2 * nu))])
        md.add_initialized_data("mu_" + name, [E / (2 * (1 + nu))])
        md.add_isotropic_linearized_elasticity_brick(mim, u, "lambda_" + name, "mu_" + name)
        body[b] = {"mesh": m, "mf": mf, "mim": mim, "u": u, "E": E, "regions": set(m.regions())}
    clock["mesh"] = time.perf_counter()

    # boundary conditions: one per body that holds the group
    loaded = []  # the prescribed single components
    for bc in scene["boundary"]:
        tag = tags[bc["group"]]
        values = bc["displacement"]
        history = bc.get("history", [[0, 1], [1, 1]])
        given = [c for c, v in enumerate(values) if v is not None]
        for b, info in body.items():
            if tag not in info["regions"]:
                continue
            if len(given) == dim and all(float(v) == 0 for v in values):
                md.add_Dirichlet_condition_with_simplification(info["u"], tag)
            elif len(given) == 1:
                axis, sign = outward_axis(info["mesh"], tag)
                if axis != given[0]:
                    raise SystemExit("getfem_hertz.py: group %s: prescribed component %d is not its normal"
                                     % (bc["group"], given[0]))
                data = "g_%s_%s" % (bc["name"].replace("-", "_"), b.replace("-", "_"))
                md.add_initialized_data(data, [0.0])
                mfm = gf.MeshFem(info["mesh"], 1)
                mfm.set_classical_fem(order)
                brick = md.add_normal_Dirichlet_condition_with_multipliers(info["mim"], info["u"], mfm, tag, data)
                loaded.append({"data": data, "value": float(values[given[0]]), "sign": sign, "history": history,
                               "multiplier": md.mult_varname_Dirichlet(brick), "region": tag, "body": b,
                               "name": bc["name"]})
            else:
                raise SystemExit("getfem_hertz.py: boundary %s not modelled" % bc["name"])

    # contact: the scene's first pair, frictionless
    pair = scene["contact"][0]
    slave_tag, master_tag = tags[pair["slave"]], tags[pair["master"]]
    sb = next(b for b, i in body.items() if slave_tag in i["regions"])
    mb = next(b for b, i in body.items() if master_tag in i["regions"])
    s, m = body[sb], body[mb]
    slave_dofs = [d for d in s["mf"].basic_dof_on_region(slave_tag) if d % dim == 0]  # GetFEM's contact node order
    h = float(params.get("h_contact", 1.0)) / float(params.get("refine", 1.0))
    r = r_factor * s["E"] * (h if dim == 3 else 1.0)  # a force per length: E in 2D (per unit depth), E h in 3D
    md.add_initialized_data("r", [r])
    md.add_nodal_contact_between_nonmatching_meshes_brick(s["mim"], m["mim"], s["u"], m["u"], "lambda_n", "r",
                                                          slave_tag, master_tag, 1, 0, 1)
    clock["setup"] = time.perf_counter()

    # quasi-static steps
    t, dt, end = 0.0, float(scene["time"]["dt"]), float(scene["time"]["end"])
    newton, step_seconds = [], []
    while t < end - 1e-12:
        t = min(end, t + dt)
        for bc in loaded:
            md.set_variable(bc["data"], [bc["sign"] * bc["value"] * history_factor(bc["history"], t)])
        t0 = time.perf_counter()
        nbit, converged = md.solve("max_res", max_res, "max_iter", 50, "lsolver", "mumps",
                                   *(["noisy"] if os.environ.get("GETFEM_HERTZ_NOISY") else []))
        step_seconds.append(time.perf_counter() - t0)
        if not converged:
            raise SystemExit("getfem_hertz.py: Newton did not converge at t = %g (%d iterations)" % (t, nbit))
        newton.append(int(nbit))
    clock["solve"] = time.perf_counter()

    # reactions of the loaded groups: the integral of the multiplier (a force along the outward normal)
    reactions = {bc["name"]: abs(float(gf.asm_generic(body[bc["body"]]["mim"], 0, bc["multiplier"], bc["region"], md)))
                 for bc in loaded if bc["value"] != 0.0}
    u_s = md.variable(s["u"])
    u_m = md.variable(m["u"])
    lam = md.variable("lambda_n")
    # nodal positions and pressures of the slave nodes
    mfp = gf.MeshFem(s["mesh"], 1)
    mfp.set_classical_fem(order)
    nodes = [d // dim for d in slave_dofs]
    X = mfp.basic_dof_nodes(nodes)
    assert np.array_equal(X, s["mf"].basic_dof_nodes(slave_dofs)), "scalar and vector dofs differ"
    M = gf.asm_mass_matrix(s["mim"], mfp, mfp, slave_tag)
    M.to_csc()
    from scipy.sparse import csc_matrix
    jc, ir = M.csc_ind()
    n_all = mfp.nbdof()
    full = csc_matrix((M.csc_val(), ir, jc), shape=(n_all, n_all))[nodes, :][:, nodes]
    force = -lam  # GetFEM's nodal normal forces are <= 0 in compression
    # gap along the master's outward normal (a flat master: the scenes' block top)
    axis, sign = outward_axis(m["mesh"], master_tag)
    plane = float(np.mean(m["mesh"].pts(m["mesh"].pid_in_regions(master_tag))[axis]))
    inside = X.copy()
    inside[axis, :] = plane - sign * 1e-9
    us = gf.compute_interpolate_on(s["mf"], u_s, X)
    um = gf.compute_interpolate_on(m["mf"], u_m, inside)
    gap = sign * ((X[axis] + us[axis]) - (plane + um[axis]))
    pressure, recovery = pressures(full, force, gap, faces[slave_tag], X, dim, recovery)
    radial = X[:axis]
    rs = np.sqrt((radial ** 2).sum(axis=0)) if dim == 3 else np.abs(X[0])
    return {
        "element": element, "refine": refine, "dim": dim, "order": order, "r": r, "max_res": max_res,
        "unknowns": int(md.nbdof()), "displacement_unknowns": int(sum(body[b]["mf"].nbdof() for b in bodies)),
        "slave_nodes": len(nodes), "newton": newton, "step_seconds": step_seconds,
        "phases": {"mesh": clock["mesh"] - clock["start"], "setup": clock["setup"] - clock["mesh"],
                   "solve": clock["solve"] - clock["setup"], "total": time.perf_counter() - clock["start"]},
        "reactions": reactions, "contact_force": float(force.sum()), "recovery": recovery,
        "points": [[float(r_), float(p), float(g), int(n)] for r_, p, g, n in zip(rs, pressure, gap, nodes)],
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("element", choices=sorted(ELEMENTS))
    parser.add_argument("refine", type=float)
    parser.add_argument("out")
    parser.add_argument("--r", type=float, default=1.0, help="augmentation parameter in units of E (2D), E h (3D)")
    parser.add_argument("--max-res", type=float, default=1e-8,
                        help="Newton's tolerance on |F|_1 / L, GetFEM's max_res (L its external load norm; its floor: "
                        "2e-9 on quad9 refine 1.6)")
    parser.add_argument("--recovery", choices=("lumped", "consistent"), default="lumped",
                        help="pressure from the nodal forces: lumped (modified basis on TRI6) or consistent")
    args = parser.parse_args()
    try:
        import getfem  # noqa: F401
    except ImportError:
        sys.exit("getfem_hertz.py: this Python (%s) has no getfem module; install python3-getfem (Debian) and run "
                 "it with /usr/bin/python3" % sys.executable)
    result = solve(args.element, args.refine, args.r, args.max_res, args.recovery)
    with open(args.out, "w") as f:
        json.dump(result, f)


if __name__ == "__main__":
    main()
