"""The plotting scripts on real results: scripts/plot-snapshots.sh draws the outer surface of the bodies with colours
that follow the field, on axes common to every instant (motion shows; one picture when the bodies move apart), with
the rigid obstacles, and the contact surfaces with --contact; it reports bad input clearly. scripts/plot-history.sh
draws history.csv with the panels that fit the kind of run (quasi-static, dynamic, frictional). Both answer --help.
Usage: python3 test_plot_scripts.py CASE; exit code 0 when every check holds."""
import math
import os
import struct
import subprocess
import sys
import tempfile
import zlib

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "validation"))
from stickslip_results import ROOT, main, run  # noqa: E402


def read_png(path):
    """(width, height, rows of (r, g, b)) of an 8-bit RGB or RGBA, non-interlaced PNG (what pngcairo writes)."""
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "%s is not a PNG" % path
    pos, idat, width = 8, b"", 0
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", body)
            assert depth == 8 and colour in (2, 6) and interlace == 0, "unsupported PNG layout in %s" % path
            channels = 3 if colour == 2 else 4
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    raw, stride, rows, previous = zlib.decompress(idat), width * channels, [], bytearray(width * channels)
    for y in range(height):
        line = raw[y * (stride + 1):(y + 1) * (stride + 1)]
        kind, row = line[0], bytearray(line[1:])
        for i in range(stride):  # undo the PNG filter of this row
            left = row[i - channels] if i >= channels else 0
            up, corner = previous[i], previous[i - channels] if i >= channels else 0
            if kind == 1:
                row[i] = (row[i] + left) & 255
            elif kind == 2:
                row[i] = (row[i] + up) & 255
            elif kind == 3:
                row[i] = (row[i] + (left + up) // 2) & 255
            elif kind == 4:
                p = left + up - corner
                pa, pb, pc = abs(p - left), abs(p - up), abs(p - corner)
                row[i] = (row[i] + (left if pa <= pb and pa <= pc else up if pb <= pc else corner)) & 255
        rows.append([tuple(row[x * channels:x * channels + 3]) for x in range(width)])
        previous = row
    return width, height, rows


def colour_counts(path):
    """Pixels of the palette's ends where the bodies are drawn (the left 80 %; the colour bar is right of it):
    (saturated, reddish (high values), bluish (low values))."""
    width, _, rows = read_png(path)
    saturated = reddish = bluish = 0
    for row in rows:
        for r, g, b in row[:int(0.8 * width)]:
            if max(r, g, b) - min(r, g, b) > 60:
                saturated += 1
                reddish += r > b + 60
                bluish += b > r + 60
    return saturated, reddish, bluish


def script(name, *args):
    return subprocess.run([os.path.join(ROOT, "scripts", name), *args], capture_output=True, text=True)


def pixels(path, test):
    """The pixels of the left 78 % of a picture (the colour bar starts at 80 %) for which test(r, g, b) holds."""
    width, _, rows = read_png(path)
    return [(x, y) for y, row in enumerate(rows) for x, (r, g, b) in enumerate(row[:int(0.78 * width)])
            if test(r, g, b)]


def saturated(r, g, b):
    return max(r, g, b) - min(r, g, b) > 60


def centroid(points):
    return (sum(p[0] for p in points) / len(points), sum(p[1] for p in points) / len(points))


def plot_snapshots(c):
    """Compressed block (3x3x3 hex8, 5 states): 54 outer faces; the first state (u = 0) is one colour, the last
    spans the palette from the fixed base (blue) to the pressed top (red)."""
    results, _ = run("scenes/compressed-block.yaml")
    folder = results.folder
    proc = script("plot-snapshots.sh", folder, "--size", "300x200")
    c.check(proc.returncode == 0, "plot-snapshots exits 0 (%s)" % proc.stderr.strip())
    c.check("54 surface faces" in proc.stdout, "the 54 outer faces of the 3x3x3 block are drawn: %s" % proc.stdout)
    c.check("t = 0, 0.25, 0.75, 1" in proc.stdout, "4 instants evenly spread over the 5 states")
    c.check("; panels" in proc.stdout, "the block stays in place: the instants side by side (%s)" % proc.stdout.strip())
    pictures = sorted(os.listdir(os.path.join(folder, "snapshots")))
    c.check(pictures == ["step-000000.png", "step-000001.png", "step-000003.png", "step-000004.png"],
            "one picture per instant: %s" % pictures)
    width, height, _ = read_png(os.path.join(folder, "snapshots.png"))
    c.check((width, height) == (600, 400), "the overview holds 2 x 2 pictures of 300 x 200 (%d x %d)" % (width, height))
    first = colour_counts(os.path.join(folder, "snapshots", "step-000000.png"))
    last = colour_counts(os.path.join(folder, "snapshots", "step-000004.png"))
    c.check(first[0] > 0.05 * 300 * 200, "the block covers %d of 60000 pixels in colour" % first[0])
    c.check(first[1] == 0, "u = 0 at t = 0: no pixel at the high (red) end of the scale (%d)" % first[1])
    c.check(last[1] > 100 and last[2] > 100, "t = 1: the pressed top in red (%d pixels), the base in blue (%d)"
            % (last[1], last[2]))


def plot_snapshots_bad_input(c):
    empty = tempfile.mkdtemp(prefix="stickslip-test-")
    proc = script("plot-snapshots.sh", empty)
    c.check(proc.returncode == 1 and "no %s/results.pvd" % empty in proc.stderr,
            "a folder without results.pvd: exit 1 and a message naming the file (%s)" % proc.stderr.strip())
    results, _ = run("scenes/compressed-block.yaml", "--steps", "1")
    proc = script("plot-snapshots.sh", results.folder, "--field", "pressure")
    c.check(proc.returncode == 1 and "no point field 'pressure'" in proc.stderr and "displacement" in proc.stderr,
            "an unknown field: exit 1, the fields the files have are listed (%s)" % proc.stderr.strip())
    proc = script("plot-snapshots.sh", results.folder, "--count", "0")
    c.check(proc.returncode == 2 and "--count" in proc.stderr, "--count 0 is refused")
    proc = script("plot-snapshots.sh", results.folder, "--contact")
    c.check(proc.returncode == 1 and "contact.pvd" in proc.stderr and "contact pairs" in proc.stderr,
            "--contact on a run without contact: exit 1, the missing contact.pvd named (%s)" % proc.stderr.strip())
    for name in ("plot-snapshots.sh", "plot-history.sh"):
        proc = script(name, "--help")
        c.check(proc.returncode == 0 and "usage: %s" % name in proc.stdout and "RESULTS" in proc.stdout,
                "%s --help: exit 0, the usage and what it draws" % name)


def plot_snapshots_motion(c):
    """The two-element impact (the upper block falls obliquely onto the lower one): the instants share one frame, so
    the falling block is drawn at different places in the pictures of the instants, and the overview draws every
    instant in one picture (the block moves by more than a third of its size)."""
    results, _ = run("scenes/two-elements.yaml")
    proc = script("plot-snapshots.sh", results.folder, "--size", "600x400")
    c.check(proc.returncode == 0 and "; overlay" in proc.stdout,
            "one picture of every instant (%s)" % proc.stdout.strip())
    width, height, _ = read_png(os.path.join(results.folder, "snapshots.png"))
    c.check((width, height) == (600, 400), "the overview is one picture of 600 x 400 (%d x %d)" % (width, height))
    pictures = sorted(os.listdir(os.path.join(results.folder, "snapshots")))
    first, last = (centroid(pixels(os.path.join(results.folder, "snapshots", p), saturated))
                   for p in (pictures[0], pictures[-1]))
    shift = math.dist(first, last)  # of both blocks' pixels: the lower block stays nearly in place
    c.check(shift > 15, "the bodies' pictures at t = 0 and t = 20 lie %.0f pixels apart on the common axes" % shift)


def grey(r, g, b):  # the lit floor; text is drawn black (its edges grey: a few hundred pixels at most)
    return max(r, g, b) - min(r, g, b) < 8 and 60 < r < 235


def plot_snapshots_obstacles(c):
    """Rigid obstacles are drawn: the plane under the 2D block as a dark line, under the 3D block as a grey floor;
    --no-obstacles leaves them out. --contact draws the 3D block's contact face coloured by the pressure."""
    two, _ = run("scenes/block-on-plane.yaml", "--set", "time.end=0.5", "--set", "output.vtu_every=5")
    proc = script("plot-snapshots.sh", two.folder, "--size", "300x200", "--count", "1")
    c.check(proc.returncode == 0 and "1 obstacle(s) drawn" in proc.stdout, "2D: the plane is drawn (%s)"
            % proc.stdout.strip())
    picture = os.path.join(two.folder, "snapshots.png")

    def beside_the_block():  # dark pixels left and right of the block, at the height of its base
        block = pixels(picture, saturated)
        left, right, base = min(x for x, _ in block), max(x for x, _ in block), max(y for _, y in block)
        return [(x, y) for x, y in pixels(picture, lambda r, g, b: max(r, g, b) < 90)
                if (x < left - 2 or x > right + 2) and abs(y - base) <= 3]
    line = beside_the_block()
    c.check(len(line) > 40, "2D: %d dark pixels of the plane beside the block's base" % len(line))
    script("plot-snapshots.sh", two.folder, "--size", "300x200", "--count", "1", "--no-obstacles")
    c.check(not beside_the_block(), "2D: --no-obstacles leaves the plane out")
    three, _ = run("scenes/mortar-block-on-plane-3d.yaml", "--set", "time.end=0.3", "--set", "output.vtu_every=1")
    proc = script("plot-snapshots.sh", three.folder, "--size", "300x200", "--count", "1")
    picture = os.path.join(three.folder, "snapshots.png")
    floor = len(pixels(picture, grey))
    c.check(proc.returncode == 0 and floor > 3000,
            "3D: %d grey pixels of the floor (%s)" % (floor, proc.stdout.strip()))
    script("plot-snapshots.sh", three.folder, "--size", "300x200", "--count", "1", "--no-obstacles")
    rest = len(pixels(picture, grey))
    c.check(rest < floor / 5, "3D: --no-obstacles leaves the floor out (%d grey pixels left)" % rest)
    proc = script("plot-snapshots.sh", three.folder, "--contact", "--size", "300x200", "--count", "1")
    c.check(proc.returncode == 0 and "contact pressure of the contact surfaces" in proc.stdout,
            "3D --contact: %s" % proc.stdout.strip())
    contact = os.path.join(three.folder, "snapshots-contact.png")
    c.check(len(pixels(contact, saturated)) > 2000, "3D --contact: the contact face is drawn in colour")


def plot_snapshots_contact_2d(c):
    """hertz-2d --contact: the pressure along the contact surface, one curve per instant with contact."""
    results, _ = run("scenes/hertz-2d.yaml", "--set", "output.vtu_every=2")
    proc = script("plot-snapshots.sh", results.folder, "--contact", "--size", "600x400")
    c.check(proc.returncode == 0 and "at t = 0.5, 1" in proc.stdout,
            "the instants with contact (%s)" % proc.stdout.strip())
    width, height, _ = read_png(os.path.join(results.folder, "snapshots-contact.png"))
    c.check((width, height) == (600, 400), "snapshots-contact.png is 600 x 400 (%d x %d)" % (width, height))


# Each kind of run gets its panels: (scene, run arguments, kind, panels, picture size).
HISTORY_CASES = {
    "force_driven": ("scenes/compressed-block.yaml", [], "quasi-static", "load-displacement, energy, Newton iterations",
                     (1400, 520)),  # three panels in a row
    "quasi_static_contact": ("scenes/hertz-2d.yaml", [], "quasi-static, contact",
                             "load-displacement, energy, contact forces, Newton iterations", (1400, 900)),
    "quasi_static_friction": ("scenes/block-on-plane.yaml", ["--set", "time.end=1.5"], "quasi-static, friction",
                              "load-displacement, energy, contact forces, friction ratio", (1400, 900)),
    "dynamic": ("scenes/free-flight-blocks.yaml", ["--set", "time.end=0.5"], "dynamic",
                "energy, conservation, linear momentum, Newton iterations", (1400, 900)),
    "dynamic_friction": ("scenes/two-elements.yaml", [], "dynamic, friction",
                         "energy, conservation, linear momentum, contact forces", (1400, 900)),
    # frictionless; its contact reports a dissipation of round-off size (1e-13 of the energy)
    "dynamic_contact": ("scenes/corot-ball-on-plane.yaml", [], "dynamic, contact",
                        "energy, conservation, linear momentum, contact forces", (1400, 900)),
}


def plot_history_case(name):
    def case(c):
        scene, args, kind, panels, size = HISTORY_CASES[name]
        results, _ = run(scene, *args)
        proc = script("plot-history.sh", results.folder)
        c.check(proc.returncode == 0, "%s: plot-history exits 0 (%s)" % (scene, proc.stderr.strip()))
        c.check("(%s): %s" % (kind, panels) in proc.stdout, "%s: %s run, panels %s (%s)" % (scene, kind, panels,
                                                                                           proc.stdout.strip()))
        width, height, _ = read_png(os.path.join(results.folder, "history.png"))
        c.check((width, height) == size, "%s: history.png is %d x %d (%d x %d)" % (scene, *size, width, height))
    case.__name__ = "plot_history_" + name
    return case


if __name__ == "__main__":
    main([plot_snapshots, plot_snapshots_bad_input, plot_snapshots_motion, plot_snapshots_obstacles,
          plot_snapshots_contact_2d] + [plot_history_case(name) for name in HISTORY_CASES])
