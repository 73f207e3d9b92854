"""The plotting scripts on real results: scripts/plot-snapshots.sh draws the outer surface of the bodies with colours
that follow the field, and reports bad input clearly; scripts/plot-history.sh draws history.csv.
Usage: python3 test_plot_scripts.py CASE; exit code 0 when every check holds."""
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


def plot_snapshots(c):
    """Compressed block (3x3x3 hex8, 5 states): 54 outer faces; the first state (u = 0) is one colour, the last
    spans the palette from the fixed base (blue) to the pressed top (red)."""
    results, _ = run("scenes/compressed-block.yaml")
    folder = results.folder
    proc = script("plot-snapshots.sh", folder, "--size", "300x200")
    c.check(proc.returncode == 0, "plot-snapshots exits 0 (%s)" % proc.stderr.strip())
    c.check("54 surface faces" in proc.stdout, "the 54 outer faces of the 3x3x3 block are drawn: %s" % proc.stdout)
    c.check("t = 0, 0.25, 0.75, 1" in proc.stdout, "4 instants evenly spread over the 5 states")
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


def plot_history(c):
    results, _ = run("scenes/compressed-block.yaml")
    proc = script("plot-history.sh", results.folder)
    c.check(proc.returncode == 0, "plot-history exits 0 (%s)" % proc.stderr.strip())
    width, height, _ = read_png(os.path.join(results.folder, "history.png"))
    c.check((width, height) == (1400, 900), "history.png is 1400 x 900 (%d x %d)" % (width, height))


if __name__ == "__main__":
    main([plot_snapshots, plot_snapshots_bad_input, plot_history])
