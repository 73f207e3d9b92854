#!/usr/bin/env python3
"""Off-screen pictures of a run's deformed bodies: the outer surface of the meshes in the .pvtu files of a results
folder (results.pvd gives the times; read_vtu joins each one's pieces), coloured by a point field, with the rigid obstacles (obstacles.pvd), rendered
by gnuplot (pm3d, depth-sorted, lit). All instants share one frame: the same axes and colour scale, so that motion
shows. The overview RESULTS/snapshots.png draws them in one picture when the bodies move apart between the instants
(--layout overlay), side by side otherwise (--layout panels); RESULTS/snapshots/step-NNNNNN.png has each instant.
--contact draws the contact surfaces instead (contact.pvd): each slave surface coloured by a contact field
(contact_pressure by default), seen from its master side and framed on the contact zone; in 2D the field along the
surface, one curve per instant. Writes RESULTS/snapshots-contact.png.
Usage: see `scripts/plot-snapshots.sh --help`."""
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
VOLUME_FACES = {12: HEX_FACES, 25: HEX_FACES, 29: HEX_FACES, 10: TET_FACES, 24: TET_FACES}  # hex8/20/27, tet4/10
PLANE_CORNERS = {9: 4, 23: 4, 28: 4, 5: 3, 22: 3}  # quad4/8/9, tri3/6: the cell itself is drawn (faces, 2D models)
LINE_CELLS = {3: 2, 21: 2}  # line2, line3 (by their end points): 2D surfaces and obstacles
NOT_FIELDS = ("Points", "connectivity", "offsets", "types", "cauchy_stress", "body", "rank", "node", "pair", "face",
              "obstacle", "node_id", "cell_id")


def read_collection(folder, name="results.pvd", required=True):
    """(time, .vtu path) of every dataset of a collection, in file order ([] when it is absent and not required)."""
    path = os.path.join(folder, name)
    if not os.path.exists(path):
        if not required:
            return []
        raise SystemExit("plot-snapshots: no %s (was the run made with output.vtu on%s?)" %
                         (path, " and contact pairs" if name == "contact.pvd" else ""))
    entries = re.findall(r'<DataSet[^>]*timestep="([^"]*)"[^>]*file="([^"]*)"', open(path).read())
    if not entries and required:
        raise SystemExit("plot-snapshots: %s lists no datasets" % path)
    return [(float(t), os.path.join(folder, f)) for t, f in entries]


def cells_of(vtu):
    conn = [c[0] for c in vtu["connectivity"]]
    start = 0
    for (end,), (kind,) in zip(vtu["offsets"], vtu["types"]):
        yield kind, conn[start:end]
        start = end


def outer_surface(vtu, by_body=False):
    """Polygons (tuples of point indices) of the boundary: faces that belong to exactly one cell, and the 2D cells;
    by_body: {body index (the cell field `body`): its polygons}."""
    count, first, polygons = {}, {}, []
    owners = [int(b[0]) for b in vtu["body"]] if "body" in vtu else None
    for c, (kind, nodes) in enumerate(cells_of(vtu)):
        owner = owners[c] if owners else 0
        if kind in PLANE_CORNERS:
            polygons.append((owner, tuple(nodes[: PLANE_CORNERS[kind]])))
        for face in VOLUME_FACES.get(kind, ()):
            corners = tuple(nodes[i] for i in face)
            key = tuple(sorted(corners))
            count[key] = count.get(key, 0) + 1
            first.setdefault(key, (owner, corners))
    polygons += [first[key] for key, n in count.items() if n == 1]
    if not by_body:
        return [poly for _, poly in polygons]
    bodies = {}
    for owner, poly in polygons:
        bodies.setdefault(owner, []).append(poly)
    return bodies


def segments(vtu):
    """The line cells (2D surfaces, 2D obstacles) by their end points."""
    return [tuple(nodes[:2]) for kind, nodes in cells_of(vtu) if kind in LINE_CELLS]


def point_fields(vtu):
    return [name for name in vtu if name not in NOT_FIELDS and not name.startswith("cell:")]


def point_values(vtu, field):
    """One number per point: the field's value, or its magnitude for a vector field."""
    if field not in vtu:
        raise SystemExit("plot-snapshots: no point field '%s' in the .vtu files (they have: %s)" %
                         (field, ", ".join(point_fields(vtu))))
    return [math.sqrt(sum(c * c for c in value)) for value in vtu[field]]


def choose(datasets, count, times):
    """Indices of the instants to draw: the datasets nearest to `times`, or `count` evenly spread ones."""
    if times:
        picked = [min(range(len(datasets)), key=lambda i: abs(datasets[i][0] - t)) for t in times]
    else:
        n, count = len(datasets), min(count, len(datasets))
        picked = [round(k * (n - 1) / max(count - 1, 1)) for k in range(count)]
    return sorted(set(picked))


def write_quads(f, points, polygons, values):
    """gnuplot pm3d input: each polygon as an isolated 2x2 grid (a triangle repeats its last corner)."""
    for poly in polygons:
        a, b, c, d = poly if len(poly) == 4 else (poly[0], poly[1], poly[2], poly[2])
        for row in ((a, b), (d, c)):
            for k in row:
                x = points[k]
                f.write("%.9g %.9g %.9g %.9g\n" % (x[0], x[1], x[2], values[k] if values else 0.0))
            f.write("\n")
        f.write("\n")


def write_segments(f, points, pairs):
    """The segments as polylines: a segment that starts where the last one ended continues it."""
    last = None
    for a, b in pairs:
        if a != last:
            f.write("\n\n%.9g %.9g %.9g\n" % tuple(points[a][:3]) if last is not None else
                    "%.9g %.9g %.9g\n" % tuple(points[a][:3]))
        f.write("%.9g %.9g %.9g\n" % tuple(points[b][:3]))
        last = b


def colour_limits(vmin, vmax):
    """The colour scale of values in [vmin, vmax]: around the value when they are all (nearly) equal."""
    scale = max(abs(vmin), abs(vmax))
    if vmax - vmin > 1e-6 * scale and vmax > vmin:
        return vmin, vmax
    if scale == 0:  # all zero (a magnitude at rest, no contact): the scale from 0
        return 0.0, 1.0
    return vmin - 0.05 * scale, vmax + 0.05 * scale


def field_label(field):
    return "|%s|" % field if field in ("displacement", "velocity") or "traction" in field or "increment" in field \
        else field.replace("_", " ")


class Box:
    """The extent of points."""

    def __init__(self):
        self.lo, self.hi = [math.inf] * 3, [-math.inf] * 3

    def include(self, points, indices):
        for k in indices:
            self.lo = [min(self.lo[i], points[k][i]) for i in range(3)]
            self.hi = [max(self.hi[i], points[k][i]) for i in range(3)]

    def centre(self):
        return [0.5 * (a + b) for a, b in zip(self.lo, self.hi)]

    def size(self):
        return math.sqrt(sum((b - a) ** 2 for a, b in zip(self.lo, self.hi)))


class Frame(Box):
    """One instant: its bodies (or contact surfaces) and obstacles as gnuplot data files, with their extent."""

    def __init__(self, time, name):
        super().__init__()
        self.time, self.name = time, name
        self.parts = {}  # body index -> (data file, Box): each body's surface
        self.obstacle_faces = self.obstacle_under = self.obstacle_lines = None

    def add_part(self, body, path, points, indices):
        box = Box()
        box.include(points, indices)
        self.include(points, indices)
        self.parts[body] = (path, box)


def nearest(datasets, time):
    return min(datasets, key=lambda d: abs(d[0] - time))[1] if datasets else None


def subdivide(points, faces, size):
    """Quadrilaterals cut into pieces no larger than `size` (bilinearly), so that pm3d's depth sorting, which orders
    whole quadrilaterals by their centres, does not draw a large obstacle face over the smaller faces of a body."""
    out_points, out_faces = [], []
    for face in faces:
        corners = [points[k] for k in (face if len(face) == 4 else face + (face[-1],))]
        n = max(1, min(16, math.ceil(max(math.dist(corners[i], corners[(i + 1) % 4]) for i in range(4)) / size)))
        grid = {}
        for i in range(n + 1):
            for j in range(n + 1):
                u, v = i / n, j / n
                grid[i, j] = len(out_points)
                out_points.append([(1 - u) * (1 - v) * a + u * (1 - v) * b + u * v * c + (1 - u) * v * d
                                   for a, b, c, d in zip(*corners)])
        out_faces += [(grid[i, j], grid[i + 1, j], grid[i + 1, j + 1], grid[i, j + 1])
                      for i in range(n) for j in range(n)]
    return out_points, out_faces


def viewer(view):
    """The unit vector from the scene towards the viewer of gnuplot's `set view rot_x, rot_z`."""
    a, b = math.radians(view[0]), math.radians(view[1])
    return [math.sin(a) * math.sin(b), -math.sin(a) * math.cos(b), math.cos(a)]


def flat_normal(points, faces):
    """The unit normal of faces that lie in one plane, or None."""
    corners = [points[k] for face in faces for k in face]
    origin, normal = corners[0], None
    for face in faces:
        a, b, c = (points[k] for k in face[:3])
        u, v = [b[i] - a[i] for i in range(3)], [c[i] - a[i] for i in range(3)]
        n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
        length = math.sqrt(sum(x * x for x in n))
        if length > 0:
            normal = [x / length for x in n]
            break
    if normal is None:
        return None
    size = max(math.dist(origin, p) for p in corners) or 1.0
    flat = all(abs(sum((p[i] - origin[i]) * normal[i] for i in range(3))) <= 1e-9 * size for p in corners)
    return normal if flat else None


def add_obstacles(frame, obstacles, tmp, face_size, view):
    """The obstacles' .vtu nearest to the frame's time as data files: lines (2D); faces (3D, cut to the bodies' face
    size); a flat obstacle whose bodies' side faces the viewer (a floor seen from above) lies behind them all and is
    drawn first, beneath the depth-sorted faces."""
    path = nearest(obstacles, frame.time)
    if not path:
        return
    vtu = read_vtu(path)
    points, lines = vtu["Points"], segments(vtu)
    owner = [int(v[0]) for v in vtu.get("cell:obstacle", vtu.get("obstacle", []))]
    by_obstacle = {}
    for (kind, nodes), k in zip(cells_of(vtu), owner):
        if kind in PLANE_CORNERS:
            by_obstacle.setdefault(k, []).append(tuple(nodes[: PLANE_CORNERS[kind]]))
    eye, centre = viewer(view), frame.centre()
    for k, faces in by_obstacle.items():
        normal = flat_normal(points, faces)
        behind = False
        if normal is not None:  # the bodies' side of the plane, and whether the viewer is on it too
            side = sum((centre[i] - points[faces[0][0]][i]) * normal[i] for i in range(3))
            behind = side * sum(eye[i] * normal[i] for i in range(3)) > 0
        attribute = "obstacle_under" if behind else "obstacle_faces"
        name = os.path.join(tmp, "%s-obstacle-%d.dat" % (frame.name, k))
        with open(name, "w") as f:
            write_quads(f, *subdivide(points, faces, face_size), None)
        setattr(frame, attribute, (getattr(frame, attribute) or []) + [name])
    if lines:
        frame.obstacle_lines = os.path.join(tmp, frame.name + "-obstacle-lines.dat")
        with open(frame.obstacle_lines, "w") as f:
            write_segments(f, points, lines)


def render(panels, bounds, limits, args, png, columns, title):
    """One gnuplot run: each panel in a multiplot with `columns` columns, shared ranges and colour scale. A panel is a
    list of draws (frame, the bodies of it to draw, the body to put its time above or None); a panel of one draw has
    its time in its corner."""
    rows = (len(panels) + columns - 1) // columns
    lo, hi = bounds
    pad = 0.02 * max(hi[i] - lo[i] for i in range(3)) or 1.0
    ranges = "\n".join("set %srange [%.9g:%.9g]" % (axis, lo[i] - pad, hi[i] + pad) for i, axis in enumerate("xyz"))
    script = [
        'set terminal pngcairo size %d,%d noenhanced rounded font ",11"' % (args.size[0] * columns,
                                                                            args.size[1] * rows),
        'set output "%s"' % png,
        "set view %g,%g,%g" % (args.view[0], args.view[1], args.zoom), "set view equal xyz", ranges,
        "unset border", "unset tics", "set cbtics", "unset key", "unset xlabel", "unset ylabel", "unset zlabel",
        "set pm3d depthorder corners2color mean border lc rgb '#303030' lw 0.5",
        "set pm3d lighting primary 0.55 specular 0.15",
        "set palette rgb 33,13,10", "set style textbox opaque noborder margins 2,1",
        "set cbrange [%.9g:%.9g]" % limits,
        'set cblabel "%s"' % field_label(args.field),
        'set multiplot title "%s"' % title if title else "set multiplot",
    ]
    # Each panel: the bodies on the left 80 % of its cell, its colour bar in the rest (a multiplot layout would put
    # the bar over the bodies), the times as labels; the top 6 % of the picture is left to the title.
    top = 0.94 if title else 1.0
    cell_w, cell_h = 1.0 / columns, top / rows
    for k, frames in enumerate(panels):
        x0, y0 = (k % columns) * cell_w, top - (k // columns + 1) * cell_h
        script += ["set origin %.4f,%.4f" % (x0, y0), "set size %.4f,%.4f" % (0.8 * cell_w, cell_h),
                   "set colorbox vertical user origin %.4f,%.4f size %.4f,%.4f" %
                   (x0 + 0.8 * cell_w, y0 + 0.2 * cell_h, 0.02 * cell_w, 0.6 * cell_h), "unset label"]
        draws = frames
        if len(draws) == 1:  # the time in the cell's top left corner
            script.append('set label 1 "t = %.4g" at screen %.4f,%.4f left front' % (
                draws[0][0].time, x0 + 0.02 * cell_w, y0 + 0.93 * cell_h))
        else:  # each instant's time above the body that moves most
            for j, (frame, _, body) in enumerate(draws):
                if body is None:
                    continue
                box = frame.parts[body][1]
                c = box.centre()
                at = (c[0], box.hi[1] + 3 * pad, 0.0) if args.view[0] == 0 else (c[0], c[1], box.hi[2] + 3 * pad)
                script.append('set label %d "t = %.4g" at %.9g,%.9g,%.9g center front boxed' % (
                    (j + 1, frame.time) + at))
        # the obstacles: of every frame of a panel of one instant, of the last one in an overlay
        carriers = [draws[0][0]] if len(draws) == 1 else [draws[-1][0]]
        obstacle = 'using 1:2:3 with pm3d fillcolor rgb "#c8c8c8"'
        under = ['"%s" %s' % (name, obstacle) for frame in carriers for name in frame.obstacle_under or []]
        if under:  # a separate plot, drawn first at the same place: the bodies and their labels come over it
            script.append("splot " + ", ".join(under))
        plots = ['"%s" %s' % (name, obstacle) for frame in carriers for name in frame.obstacle_faces or []]
        plots += ['"%s" using 1:2:3:4 with pm3d' % frame.parts[b][0] for frame, bodies, _ in draws for b in bodies]
        plots += ['"%s" using 1:2:3 with lines lc rgb "#404040" lw 3' % frame.obstacle_lines  # over the surfaces
                  for frame in carriers if frame.obstacle_lines]
        script.append("splot " + ", ".join(plots))
    script.append("unset multiplot")
    proc = subprocess.run(["gnuplot"], input="\n".join(script) + "\n", text=True, capture_output=True)
    if proc.returncode != 0:
        raise SystemExit("plot-snapshots: gnuplot failed:\n" + proc.stderr)


def moved(a, b, fraction):
    """1 when a body's surface (box b) lies more than `fraction` of its size away from where it was (box a)."""
    return math.dist(a.centre(), b.centre()) > fraction * min(a.size(), b.size())


def overlay(frames):
    """The draws of one picture of every instant: each body at the first instant, then whenever it has moved on by
    more than a tenth of its size since the copy drawn last (the final state replacing the last copy drawn before
    it), so that copies do not lie on top of each other; the times above the body that moves most."""
    bodies = list(frames[0].parts)
    drawn = {}
    for b in bodies:
        shown = [0]
        for i in range(1, len(frames)):
            if moved(frames[shown[-1]].parts[b][1], frames[i].parts[b][1], 0.1):
                shown.append(i)
        shown[-1] = len(frames) - 1
        drawn[b] = shown
    mover = max(bodies, key=lambda b: math.dist(frames[0].parts[b][1].centre(), frames[-1].parts[b][1].centre()))
    return [(frame, [b for b in bodies if i in drawn[b]], mover if i in drawn[mover] else None)
            for i, frame in enumerate(frames) if any(i in drawn[b] for b in bodies)]


def apart(frames):
    """1 when a body moves by more than a third of its size between the first and the last instant (an overlay shows
    the motion), 0 when they all stay in place (an overlay would hide the earlier instants)."""
    return len(frames) > 1 and any(moved(frames[0].parts[b][1], frames[-1].parts[b][1], 1 / 3) for b in frames[0].parts)


def snapshot_frames(args, chosen, obstacles, tmp):
    """The bodies of each chosen instant: (frames, colour limits, polygon count)."""
    bodies, frames, vmin, vmax = None, [], math.inf, -math.inf
    for time, path in chosen:
        vtu = read_vtu(path)
        bodies = bodies or outer_surface(vtu, by_body=True)  # the mesh is the same in every file of a run
        points, values = vtu["Points"], point_values(vtu, args.field)
        frame = Frame(time, os.path.splitext(os.path.basename(path))[0])
        for body, polygons in bodies.items():
            used = {k for poly in polygons for k in poly}
            vmin, vmax = min([vmin] + [values[k] for k in used]), max([vmax] + [values[k] for k in used])
            surface = os.path.join(tmp, "%s-body-%d.dat" % (frame.name, body))
            with open(surface, "w") as f:
                write_quads(f, points, polygons, values)
            frame.add_part(body, surface, points, used)
        frames.append(frame)
    polygons = [poly for group in bodies.values() for poly in group]
    if args.view is None:  # a 2D model (all z = 0) is seen from above
        flat = all(f.hi[2] - f.lo[2] <= 1e-12 * max(f.hi[0] - f.lo[0], f.hi[1] - f.lo[1]) for f in frames)
        args.view = [0.0, 0.0] if flat else [62.0, 20.0]
    edges = sorted(math.dist(points[p[i]], points[p[i - 1]]) for p in polygons for i in range(len(p)))
    for frame in frames if obstacles else []:
        add_obstacles(frame, obstacles, tmp, max(0.5 * edges[len(edges) // 2], 1e-12), args.view)
    return frames, colour_limits(vmin, vmax), len(polygons)


def overall_bounds(frames, obstacles_too):
    lo, hi = [math.inf] * 3, [-math.inf] * 3
    for frame in frames:
        lo = [min(a, b) for a, b in zip(lo, frame.lo)]
        hi = [max(a, b) for a, b in zip(hi, frame.hi)]
    if obstacles_too:  # the obstacles within reach of the bodies (they extend beyond them)
        size = max(b - a for a, b in zip(lo, hi))
        lo = [a - 0.15 * size if b - a > 0 or i < 2 else a for i, (a, b) in enumerate(zip(lo, hi))]
        hi = [b + 0.15 * size if b - a > 0 or i < 2 else b for i, (a, b) in enumerate(zip(lo, hi))]
    return lo, hi


def bodies(args):
    datasets = read_collection(args.results)
    obstacles = [] if args.no_obstacles else read_collection(args.results, "obstacles.pvd", required=False)
    chosen = [datasets[i] for i in choose(datasets, args.count, args.times)]
    out_dir = os.path.join(args.results, "snapshots")
    os.makedirs(out_dir, exist_ok=True)
    for old in os.listdir(out_dir):  # pictures of an earlier choice of instants would mix with these
        if re.fullmatch(r"step-\d+\.png", old):
            os.remove(os.path.join(out_dir, old))
    with tempfile.TemporaryDirectory(prefix="stickslip-snapshots-") as tmp:
        zoom = args.zoom
        args.zoom = zoom or 1.8
        frames, limits, n_polygons = snapshot_frames(args, chosen, obstacles, tmp)
        bounds = overall_bounds(frames, bool(obstacles))
        whole = [[(frame, list(frame.parts), None)] for frame in frames]
        for frame, panel in zip(frames, whole):
            render([panel], bounds, limits, args, os.path.join(out_dir, frame.name + ".png"), 1, None)
        layout = args.layout if args.layout != "auto" else ("overlay" if apart(frames) else "panels")
        overview = os.path.join(args.results, "snapshots.png")
        if layout == "overlay":
            args.zoom = zoom or 1.4  # the bodies of every instant in one frame: the box is larger
            render([overlay(frames)], bounds, limits, args, overview, 1, "%s: t = %s" % (
                args.title, ", ".join("%.4g" % f.time for f in frames)))
        else:
            render(whole, bounds, limits, args, overview, min(len(frames), 2), args.title)
    print("plot-snapshots: %s (t = %s; %d surface faces; %s%s; one picture per instant in %s/)" %
          (overview, ", ".join("%.4g" % f.time for f in frames), n_polygons, layout,
           ", %d obstacle(s) drawn" % obstacle_count(obstacles) if obstacles else "", out_dir))
    return ["snapshots.png", "snapshots"] + ["snapshots/%s.png" % f.name for f in frames]


def obstacle_count(obstacles):
    vtu = read_vtu(obstacles[0][1])
    return len({int(v[0]) for v in vtu.get("cell:obstacle", vtu.get("obstacle", []))})


def contact_view_2d(args, chosen, png):
    """2D: the contact field along each slave surface, one curve per instant, against the coordinate along which the
    surface extends most."""
    with tempfile.TemporaryDirectory(prefix="stickslip-contact-") as tmp:
        files, spread = [], [0.0, 0.0]
        for time, path in chosen:
            vtu = read_vtu(path)
            points = vtu["Points"]
            for i in range(2):
                spread[i] = max(spread[i], max(p[i] for p in points) - min(p[i] for p in points))
            files.append((time, vtu, os.path.join(tmp, "t%d.dat" % len(files))))
        axis = 0 if spread[0] >= spread[1] else 1
        for time, vtu, path in files:
            values = point_values(vtu, args.field)
            with open(path, "w") as f:
                for k in sorted(range(len(values)), key=lambda k: vtu["Points"][k][axis]):
                    f.write("%.9g %.9g\n" % (vtu["Points"][k][axis], values[k]))
        script = ['set terminal pngcairo size %d,%d noenhanced font ",11"' % tuple(args.size),
                  'set output "%s"' % png, 'set title "%s: %s along the contact surface"' % (
                      args.title, field_label(args.field)), "set grid", "set key below horizontal",
                  'set xlabel "%s (current position)"' % "xy"[axis], 'set ylabel "%s"' % field_label(args.field),
                  "plot " + ", ".join('"%s" using 1:2 with linespoints lw 2 pt 7 ps 0.6 title "t = %.4g"' % (p, t)
                                      for t, _, p in files)]
        proc = subprocess.run(["gnuplot"], input="\n".join(script) + "\n", text=True, capture_output=True)
        if proc.returncode != 0:
            raise SystemExit("plot-snapshots: gnuplot failed:\n" + proc.stderr)


def contact_view_3d(args, chosen, png):
    """3D: each instant's slave surfaces coloured by the field, seen along the mean normal of the contact zone from
    the master's side, framed on the points where the field is not zero (the whole surface when it is zero)."""
    with tempfile.TemporaryDirectory(prefix="stickslip-contact-") as tmp:
        frames, vmin, vmax, normal = [], math.inf, -math.inf, [0.0, 0.0, 0.0]
        zone = []
        for time, path in chosen:
            vtu = read_vtu(path)
            points, values, faces = vtu["Points"], point_values(vtu, args.field), outer_surface(vtu)
            frame = Frame(time, "contact-%d" % len(frames))
            active = [k for k in range(len(points)) if values[k] != 0]
            if active:
                zone_box = Box()
                zone_box.include(points, active)
                zone.append(zone_box)
            for k in active:  # contact_normal_traction is pressure x normal: their sum points along the zone's normal
                for i in range(3):
                    normal[i] += vtu["contact_normal_traction"][k][i] if "contact_normal_traction" in vtu else 0.0
            vmin, vmax = min([vmin] + values), max([vmax] + values)
            surface = os.path.join(tmp, frame.name + ".dat")
            with open(surface, "w") as f:
                write_quads(f, points, faces, values)
            frame.add_part(0, surface, points, range(len(points)))
            frames.append(frame)
        length = math.sqrt(sum(v * v for v in normal))
        n = [v / length for v in normal] if length > 0 else [0.0, 0.0, 1.0]
        if args.view is None:  # look against the normal (towards the slave from the master's side)
            rot_x = math.degrees(math.acos(max(-1.0, min(1.0, -n[2]))))
            rot_z = (math.degrees(math.atan2(-n[0], n[1])) if math.hypot(n[0], n[1]) > 1e-12 else 0.0) % 360
            args.view = [rot_x, rot_z]
        lo, hi = overall_bounds(zone or frames, False)  # the contact zones, or the whole surfaces without contact
        size = max(b - a for a, b in zip(lo, hi)) or 1.0
        lo, hi = [a - 0.2 * size for a in lo], [b + 0.2 * size for b in hi]
        args.zoom = args.zoom or 1.4
        render([[(f, [0], None)] for f in frames], (lo, hi), colour_limits(vmin, vmax), args, png,
               min(len(frames), 2), "%s: %s on the contact surfaces" % (args.title, field_label(args.field)))


def contact(args):
    datasets = read_collection(args.results, "contact.pvd")
    if args.field == "displacement":
        args.field = "contact_pressure"
    if not args.times:  # the instants with contact (all when there is none)
        touching = [d for d in datasets if any(v != 0 for v in point_values(read_vtu(d[1]), args.field))]
        datasets = touching or datasets
    chosen = [datasets[i] for i in choose(datasets, args.count, args.times)]
    png = os.path.join(args.results, "snapshots-contact.png")
    if segments(read_vtu(chosen[0][1])):  # line faces: a 2D model
        contact_view_2d(args, chosen, png)
    else:
        contact_view_3d(args, chosen, png)
    print("plot-snapshots: %s (%s of the contact surfaces at t = %s)" % (
        png, field_label(args.field), ", ".join("%.4g" % t for t, _ in chosen)))
    return ["snapshots-contact.png"]


def main():
    parser = argparse.ArgumentParser(prog="plot-snapshots.sh", description="\n".join(__doc__.split("\n")[:-1]),
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("results", help="a results folder written by `stickslip run --out`")
    parser.add_argument("--field", default="displacement",
                        help="point field to colour by (magnitude of vectors): displacement (default), velocity, "
                             "contact_pressure, contact_gap, contact_state, contact_slip, ...; with --contact "
                             "contact_pressure (default) or another contact field")
    parser.add_argument("--count", type=int, default=4, help="instants evenly spread over the run (default 4)")
    parser.add_argument("--times", type=lambda s: [float(t) for t in s.split(",")],
                        help="comma-separated times; the nearest written instants are drawn")
    parser.add_argument("--layout", choices=("auto", "overlay", "panels"), default="auto",
                        help="the overview: every instant in one picture (overlay), side by side (panels), or overlay "
                             "when the bodies move by more than a third of their size (auto, the default)")
    parser.add_argument("--contact", action="store_true",
                        help="the contact surfaces coloured by a contact field instead of the bodies "
                             "(snapshots-contact.png)")
    parser.add_argument("--no-obstacles", action="store_true", help="leave the rigid obstacles out")
    parser.add_argument("--view", type=lambda s: [float(v) for v in s.split(",")],
                        help="gnuplot view angles ROT_X,ROT_Z in degrees (default 62,20; 0,0 for 2D models; with "
                             "--contact along the contact normal)")
    parser.add_argument("--zoom", type=float,
                        help="gnuplot view scale: larger draws the bodies larger (default 1.8; 1.4 for an overlay and "
                             "with --contact)")
    parser.add_argument("--size", type=lambda s: [int(v) for v in s.split("x")], default=[900, 560],
                        help="pixels of one picture, WxH (default 900x560)")
    parser.add_argument("--title", default=None, help="title of the overview (default: the folder name)")
    args = parser.parse_args()
    if args.count < 1:
        parser.error("--count must be >= 1")
    args.title = args.title or os.path.basename(os.path.normpath(args.results))
    written = contact(args) if args.contact else bodies(args)
    # the pictures are the run's: the next run into the folder replaces them with it
    subprocess.run([os.path.join(os.path.dirname(os.path.abspath(__file__)), "claim-results-files.sh"), args.results]
                   + written, check=True)


if __name__ == "__main__":
    main()
