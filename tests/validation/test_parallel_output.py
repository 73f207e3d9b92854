"""The bodies' VTU output in pieces, one per rank (issue 33, docs/user-guide.md "Result files").

- `parallel_output_pieces`: a 3D block pressed onto a rigid plane and pushed obliquely with Coulomb friction
  (scenes/mortar-block-on-plane-3d.yaml with penalty-nts) on 1 and 2 ranks. Each output step is a .pvtu that lists one
  piece per rank, and results.pvd lists the .pvtu files; the .pvtu's PPointData/PCellData name the arrays of every
  piece in order with their components, and each piece's arrays have its NumberOfPoints/NumberOfCells entries; every
  cell is in exactly one piece, the piece of the rank that owns it; a node that two pieces share has the same values in
  both; and the fields per mesh node id (displacement, velocity, the contact fields) and per cell id (stress) on 2
  ranks equal those on 1 rank to 1e-10 of their size (the largest entry over the output steps).
Usage: python3 test_parallel_output.py CASE; exit code 0 when every check holds."""
import os
import re
import sys
import xml.etree.ElementTree as ElementTree

from stickslip_results import main, run

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "tools"))
from stickslip_compare.results import _read_piece, collection, pvtu_pieces, read_vtu  # noqa: E402

SCENE = "scenes/mortar-block-on-plane-3d.yaml"
SETS = ["--set", "contact.0.plugin=penalty-nts", "--set", "contact.0.strategy=none", "--replace",
        "contact.0.parameters={penalty: 1.0e6, penalty_tangential: 1.0e6, mu: 0.3}", "--steps", "20", "--set",
        "output.vtu_every=10"]
FIELDS = ("displacement", "velocity", "contact_pressure", "contact_gap", "contact_state", "contact_normal_traction",
          "contact_tangential_traction", "contact_normal_force", "contact_slip_increment", "contact_slip")


def header(path):
    """The XML of a .vtu or .pvtu without its appended data."""
    text = open(path, "rb").read().split(b"<AppendedData")[0].decode("latin-1")
    return ElementTree.fromstring(text if text.rstrip().endswith("</VTKFile>") else text + "</VTKFile>")


def arrays_of(element):
    return [(a.get("Name"), a.get("NumberOfComponents")) for a in element] if element is not None else []


def check_pvtu(c, folder, pvtu, ranks):
    """The .pvtu's lists against its pieces; every cell in one piece, its rank's; shared nodes equal."""
    root = header(os.path.join(folder, pvtu))
    grid = root.find("PUnstructuredGrid")
    c.check(root.get("type") == "PUnstructuredGrid" and grid is not None, "%s is a PUnstructuredGrid" % pvtu)
    sources = [p.get("Source") for p in grid.findall("Piece")]
    c.check(len(sources) == ranks and all(os.path.exists(os.path.join(folder, s)) for s in sources),
            "%s lists %d pieces that exist: %s" % (pvtu, ranks, sources))
    parallel_points = arrays_of(grid.find("PPointData"))
    parallel_cells = arrays_of(grid.find("PCellData"))
    c.check(arrays_of(grid.find("PPoints")) == [("Points", "3")], "%s: PPoints is one 3-component array" % pvtu)
    cells_seen, nodes_seen = {}, {}
    for rank, source in enumerate(sources):
        piece = header(os.path.join(folder, source)).find("UnstructuredGrid/Piece")
        c.check(arrays_of(piece.find("PointData")) == parallel_points and
                arrays_of(piece.find("CellData")) == parallel_cells,
                "%s: its point and cell arrays are the .pvtu's (%s)" % (source, [n for n, _ in parallel_points]))
        arrays, _ = _read_piece(os.path.join(folder, source))
        n_points, n_cells = int(piece.get("NumberOfPoints")), int(piece.get("NumberOfCells"))
        c.check(all(len(arrays[n]) == n_points for n, _ in parallel_points) and len(arrays["Points"]) == n_points and
                all(len(arrays[n]) == n_cells for n, _ in parallel_cells) and len(arrays["offsets"]) == n_cells,
                "%s: %d points, %d cells in every array" % (source, n_points, n_cells))
        c.check(n_cells > 0 and all(r == (rank,) for r in arrays["rank"]), "%s: only rank %d's cells" % (source, rank))
        for (cell,) in arrays["cell_id"]:
            cells_seen[cell] = cells_seen.get(cell, 0) + 1
        for k, (node,) in enumerate(arrays["node_id"]):
            values = tuple(arrays[n][k] for n, _ in parallel_points)
            if node in nodes_seen and nodes_seen[node] != values:
                c.check(False, "%s: node %d differs from another piece's" % (source, node))
            nodes_seen[node] = values
    c.check(sorted(cells_seen) == list(range(len(cells_seen))) and set(cells_seen.values()) == {1},
            "%s: every cell (%d) in exactly one piece" % (pvtu, len(cells_seen)))


def size_of(arrays, name):
    return max([abs(x) for v in arrays[name] for x in v] + [1e-300])


def parallel_output_pieces(c):
    runs = {}
    for ranks in (1, 2):
        results, _ = run(SCENE, *SETS, np=ranks)
        c.check(results.summary["ranks"] == ranks, "the run used %d rank(s)" % ranks)
        datasets = collection(results.folder)
        c.check(len(datasets) == 3 and all(re.fullmatch(r"step-\d{6}\.pvtu", f) for _, f in datasets),
                "%d rank(s): results.pvd lists a .pvtu per output step (steps 0, 10, 20): %s" %
                (ranks, [f for _, f in datasets]))
        for _, pvtu in datasets:
            check_pvtu(c, results.folder, pvtu, ranks)
        runs[ranks] = results
    steps = [(pvtu, read_vtu(os.path.join(runs[1].folder, pvtu)), read_vtu(os.path.join(runs[2].folder, pvtu)))
             for _, pvtu in collection(runs[1].folder)]
    names = FIELDS + ("Points", "cauchy_stress")
    for pvtu, one, two in steps:
        c.check(all(n in one and n in two for n in names), "%s: %s are written" % (pvtu, ", ".join(names)))
    # each field's size over the run: a field that is round-off at one step (the tangential ones before the push)
    # is compared at the scale it has when it matters
    sizes = {n: max(size_of(one, n) for _, one, _ in steps) for n in names}
    for pvtu, one, two in steps:
        c.check(len(one["node_id"]) == len(two["node_id"]) and one["connectivity"] == two["connectivity"],
                "%s: the same nodes and cells on 1 and 2 ranks" % pvtu)
        for name in names:
            diff = max(abs(x - y) for u, v in zip(one[name], two[name]) for x, y in zip(u, v)) / sizes[name]
            c.check(diff <= 1e-10, "%s: `%s` on 2 ranks equals 1 rank's to %.1e of its size %.3g" %
                    (pvtu, name, diff, sizes[name]))
    last = read_vtu(os.path.join(runs[2].folder, collection(runs[2].folder)[-1][1]))
    c.check(max(abs(v[0]) for v in last["contact_pressure"]) > 0 and max(abs(v[0]) for v in last["contact_slip"]) > 0,
            "the last step has contact pressure and slip (the comparison covers contact fields that are not zero)")
    pieces = pvtu_pieces(os.path.join(runs[2].folder, collection(runs[2].folder)[-1][1]))
    sizes = [len(_read_piece(p)[0]["offsets"]) for p in pieces]
    c.check(all(s < len(last["offsets"]) for s in sizes), "each rank's piece holds part of the cells: %s of %d" %
            (sizes, len(last["offsets"])))


CASES = [parallel_output_pieces]

if __name__ == "__main__":
    main(CASES)
