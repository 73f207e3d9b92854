#!/usr/bin/env python3
"""Off-screen pictures of a run's deformed bodies: the outer surface of the meshes in the .vtu files of a results
folder (results.pvd gives the times), coloured by a point field, rendered by gnuplot (pm3d, depth-sorted, lit).
Usage: see `scripts/plot-snapshots.sh --help`. Writes RESULTS/snapshots/step-NNNNNN.png for each chosen instant and
RESULTS/snapshots.png with all of them side by side, on one frame and one colour scale."""
import argparse
import math
import os
import re
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "tests", "validation"))
from stickslip_results import read_vtu  # noqa: E402  (the one reader of stickslip's .vtu files)

# Faces of the VTK cell types stickslip writes, by local corner indices (mid-side and centre nodes of the quadratic
# types are not drawn: the picture shows each face as its corner polygon). Faces are oriented outwards.
HEX_FACES = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
TET_FACES = [(0, 2, 1), (0, 1, 3), (1, 2, 3), (0, 3, 2)]
VOLUME_FACES = {12: HEX_FACES, 29: HEX_FACES, 10: TET_FACES}  # hex8, hex27, tet4
PLANE_CORNERS = {9: 4, 28: 4, 5: 3}  # quad4, quad9, tri3: the cell itself is drawn (2D models)


def read_collection(folder):
    """(time, .vtu path) of every dataset in results.pvd, in file order."""
    path = os.path.join(folder, "results.pvd")
    if not os.path.exists(path):
        raise SystemExit("plot-snapshots: no %s (was the run made with output.vtu on?)" % path)
    entries = re.findall(r'<DataSet[^>]*timestep="([^"]*)"[^>]*file="([^"]*)"', open(path).read())
    if not entries:
        raise SystemExit("plot-snapshots: %s lists no datasets" % path)
    return [(float(t), os.path.join(folder, f)) for t, f in entries]


def outer_surface(vtu):
    """Polygons (tuples of point indices) of the boundary: faces that belong to exactly one cell."""
    conn = [c[0] for c in vtu["connectivity"]]
    offsets = [o[0] for o in vtu["offsets"]]
    types = [t[0] for t in vtu["types"]]
    count, first = {}, {}
    polygons = []
    start = 0
    for end, kind in zip(offsets, types):
        nodes = conn[start:end]
        start = end
        if kind in PLANE_CORNERS:
            polygons.append(tuple(nodes[: PLANE_CORNERS[kind]]))
        for face in VOLUME_FACES.get(kind, ()):
            corners = tuple(nodes[i] for i in face)
            key = tuple(sorted(corners))
            count[key] = count.get(key, 0) + 1
            first.setdefault(key, corners)
    polygons += [first[key] for key, n in count.items() if n == 1]
    return polygons


def point_values(vtu, field):
    """One number per point: the field's value, or its magnitude for a vector field."""
    if field not in vtu:
        point_fields = [name for name in vtu if name not in
                        ("Points", "connectivity", "offsets", "types", "cauchy_stress", "body", "rank")]
        raise SystemExit("plot-snapshots: no point field '%s' in the .vtu files (they have: %s)" %
                         (field, ", ".join(point_fields)))
    return [math.sqrt(sum(c * c for c in value)) for value in vtu[field]]


def choose(datasets, count, times):
    """Indices of the instants to draw: the datasets nearest to `times`, or `count` evenly spread ones."""
    if times:
        picked = [min(range(len(datasets)), key=lambda i: abs(datasets[i][0] - t)) for t in times]
    else:
        n, count = len(datasets), min(count, len(datasets))
        picked = [round(k * (n - 1) / max(count - 1, 1)) for k in range(count)]
    return sorted(set(picked))


def write_quads(path, points, polygons, values):
    """gnuplot pm3d input: each polygon as an isolated 2x2 grid (a triangle repeats its last corner)."""
    with open(path, "w") as f:
        for poly in polygons:
            a, b, c, d = poly if len(poly) == 4 else (poly[0], poly[1], poly[2], poly[2])
            for row in ((a, b), (d, c)):
                for k in row:
                    x = points[k]
                    f.write("%.9g %.9g %.9g %.9g\n" % (x[0], x[1], x[2], values[k]))
                f.write("\n")
            f.write("\n")


def field_label(field):
    return "|%s|" % field if field in ("displacement", "velocity") else field.replace("_", " ")


def render(frames, bounds, limits, args, png, columns):
    """One gnuplot run: every frame in a multiplot with `columns` columns, shared ranges and colour scale."""
    rows = (len(frames) + columns - 1) // columns
    lo, hi = bounds
    pad = 0.02 * max(hi[i] - lo[i] for i in range(3)) or 1.0
    ranges = "\n".join("set %srange [%.9g:%.9g]" % (axis, lo[i] - pad, hi[i] + pad) for i, axis in enumerate("xyz"))
    script = [
        'set terminal pngcairo size %d,%d noenhanced font ",11"' % (args.size[0] * columns, args.size[1] * rows),
        'set output "%s"' % png,
        "set view %g,%g,%g" % (args.view[0], args.view[1], args.zoom), "set view equal xyz", ranges,
        "unset border", "unset tics", "set cbtics", "unset key", "unset xlabel", "unset ylabel", "unset zlabel",
        "set pm3d depthorder corners2color mean border lc rgb '#303030' lw 0.5",
        "set pm3d lighting primary 0.55 specular 0.15",
        "set palette rgb 33,13,10",
        "set cbrange [%.9g:%.9g]" % limits,
        'set cblabel "%s"' % field_label(args.field),
        "set multiplot title \"%s\"" % args.title if len(frames) > 1 else "set multiplot",
    ]
    # Each panel: the bodies on the left 80 % of its cell, its colour bar and labels in the rest (a multiplot
    # layout would put the bar over the bodies), the time in the cell's top left corner (a title would sit under
    # the enlarged bodies); the top 6 % of the picture is left to the overview's title.
    top = 0.94 if len(frames) > 1 else 1.0
    cell_w, cell_h = 1.0 / columns, top / rows
    for k, (time, data) in enumerate(frames):
        x0, y0 = (k % columns) * cell_w, top - (k // columns + 1) * cell_h
        script += ["set origin %.4f,%.4f" % (x0, y0), "set size %.4f,%.4f" % (0.8 * cell_w, cell_h),
                   "set colorbox vertical user origin %.4f,%.4f size %.4f,%.4f" %
                   (x0 + 0.8 * cell_w, y0 + 0.2 * cell_h, 0.02 * cell_w, 0.6 * cell_h),
                   'set label 1 "t = %.4g" at screen %.4f,%.4f left front' % (time, x0 + 0.02 * cell_w,
                                                                             y0 + 0.93 * cell_h),
                   'splot "%s" using 1:2:3:4 with pm3d' % data]
    script.append("unset multiplot")
    proc = subprocess.run(["gnuplot"], input="\n".join(script) + "\n", text=True, capture_output=True)
    if proc.returncode != 0:
        raise SystemExit("plot-snapshots: gnuplot failed:\n" + proc.stderr)


def main():
    parser = argparse.ArgumentParser(prog="plot-snapshots.sh", description=__doc__.split("\n")[0])
    parser.add_argument("results", help="a results folder written by `stickslip run --out`")
    parser.add_argument("--field", default="displacement",
                        help="point field to colour by (magnitude of vectors): displacement (default), velocity, "
                             "contact_pressure, contact_gap, contact_state")
    parser.add_argument("--count", type=int, default=4, help="instants evenly spread over the run (default 4)")
    parser.add_argument("--times", type=lambda s: [float(t) for t in s.split(",")],
                        help="comma-separated times; the nearest written instants are drawn")
    parser.add_argument("--view", type=lambda s: [float(v) for v in s.split(",")],
                        help="gnuplot view angles ROT_X,ROT_Z in degrees (default 62,20; 0,0 for 2D models)")
    parser.add_argument("--zoom", type=float, default=1.8,
                        help="gnuplot view scale: larger draws the bodies larger (default 1.8)")
    parser.add_argument("--size", type=lambda s: [int(v) for v in s.split("x")], default=[900, 560],
                        help="pixels of one picture, WxH (default 900x560)")
    parser.add_argument("--title", default=None, help="title of the overview (default: the folder name)")
    args = parser.parse_args()
    if args.count < 1:
        parser.error("--count must be >= 1")
    args.title = args.title or os.path.basename(os.path.normpath(args.results))
    datasets = read_collection(args.results)
    chosen = [datasets[i] for i in choose(datasets, args.count, args.times)]

    out_dir = os.path.join(args.results, "snapshots")
    os.makedirs(out_dir, exist_ok=True)
    for old in os.listdir(out_dir):  # pictures of an earlier choice of instants would mix with these
        if re.fullmatch(r"step-\d+\.png", old):
            os.remove(os.path.join(out_dir, old))
    polygons = None
    frames, lo, hi, vmin, vmax = [], [math.inf] * 3, [-math.inf] * 3, math.inf, -math.inf
    with tempfile.TemporaryDirectory(prefix="stickslip-snapshots-") as tmp:
        for time, path in chosen:
            vtu = read_vtu(path)
            polygons = polygons or outer_surface(vtu)  # the mesh is the same in every file of a run
            points, values = vtu["Points"], point_values(vtu, args.field)
            used = {k for poly in polygons for k in poly}
            for k in used:
                lo = [min(lo[i], points[k][i]) for i in range(3)]
                hi = [max(hi[i], points[k][i]) for i in range(3)]
                vmin, vmax = min(vmin, values[k]), max(vmax, values[k])
            data = os.path.join(tmp, os.path.basename(path) + ".dat")
            write_quads(data, points, polygons, values)
            frames.append((time, data, os.path.splitext(os.path.basename(path))[0]))
        limits = (vmin, vmax if vmax > vmin else vmin + 1.0)
        if args.view is None:  # a 2D model (all z = 0) is seen from above
            args.view = [0.0, 0.0] if hi[2] - lo[2] <= 1e-12 * max(hi[0] - lo[0], hi[1] - lo[1]) else [62.0, 20.0]
        for time, data, name in frames:
            render([(time, data)], (lo, hi), limits, args, os.path.join(out_dir, name + ".png"), 1)
        overview = os.path.join(args.results, "snapshots.png")
        render([(t, d) for t, d, _ in frames], (lo, hi), limits, args, overview, min(len(frames), 2))
    print("plot-snapshots: %s (t = %s; %d surface faces; one picture per instant in %s/)" %
          (overview, ", ".join("%.4g" % f[0] for f in frames), len(polygons), out_dir))


if __name__ == "__main__":
    main()
