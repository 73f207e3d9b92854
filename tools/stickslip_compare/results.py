"""Reading stickslip result folders: history.csv, summary.json, contact.csv and .vtu point data."""
import csv
import json
import os
import re
import struct


class Results:
    def __init__(self, folder):
        self.folder = folder
        with open(os.path.join(folder, "history.csv")) as f:
            self.rows = [{k: float(v) for k, v in row.items()} for row in csv.DictReader(f)]
        with open(os.path.join(folder, "summary.json")) as f:
            self.summary = json.load(f)

    def column(self, name):
        return [row[name] for row in self.rows]

    def contact_table(self):
        """Every row of contact.csv: the contact points of every output step (columns step and time)."""
        path = os.path.join(self.folder, "contact.csv")
        with open(path) as f:
            return [{k: float(v) for k, v in row.items()} for row in csv.DictReader(f)]

    def contact_points(self, step=None):
        """The contact points of one output step of contact.csv: `step`, or the last one."""
        rows = self.contact_table()
        step = max(r["step"] for r in rows) if step is None and rows else step
        return [r for r in rows if r["step"] == step]

    def last_vtu(self):
        """The bodies at the last output step (results.pvd's last dataset), read_vtu's arrays."""
        return read_vtu(os.path.join(self.folder, collection(self.folder)[-1][1]))


def collection(folder, name="results.pvd"):
    """(time, file relative to the folder) of every dataset of a ParaView collection, in file order."""
    text = open(os.path.join(folder, name)).read()
    return [(float(t), f) for t, f in re.findall(r'<DataSet timestep="([^"]+)"[^>]*file="([^"]+)"', text)]


def read_vtu(path):
    """Point and cell data arrays of a stickslip .vtu (raw appended or inline base64) as lists of tuples, by name; a
    cell array whose name a point array has too (the contact fields of a contact output's pieces) is under
    "cell:NAME". A .pvtu (an output step's bodies or contact surfaces, one piece per rank) is read whole: its pieces
    joined into one grid whose point k is mesh node k (node_id; 0 for a mesh node no element uses) and whose cells
    are in cell_id order, so the arrays are the same whatever the number of ranks."""
    if path.endswith(".pvtu"):
        return read_pvtu(path)
    return _read_piece(path)[0]


def pvtu_pieces(path):
    """The pieces' paths of a .pvtu."""
    text = open(path).read()
    return [os.path.join(os.path.dirname(path), source) for source in re.findall(r'<Piece Source="([^"]+)"', text)]


def read_pvtu(path):
    pieces = [_read_piece(p) for p in pvtu_pieces(path)]
    if not pieces:
        raise ValueError("%s: no pieces" % path)
    cell_names = list(pieces[0][1])
    pieces = [arrays for arrays, _ in pieces]
    point_names = [n for n in pieces[0] if n not in cell_names and n not in ("connectivity", "offsets", "types")]
    n_nodes = 1 + max((int(i[0]) for piece in pieces for i in piece["node_id"]), default=-1)
    merged = {}
    for name in point_names:
        width = next((len(piece[name][0]) for piece in pieces if piece[name]), 1)
        values = [(0.0,) * width] * n_nodes
        for piece in pieces:
            for node, value in zip(piece["node_id"], piece[name]):
                values[int(node[0])] = value
        merged[name] = values
    merged["node_id"] = [(float(k),) for k in range(n_nodes)]
    cells = []
    for piece in pieces:
        start = 0
        for c, ((end,), (kind,)) in enumerate(zip(piece["offsets"], piece["types"])):
            nodes = tuple(int(piece["node_id"][k[0]][0]) for k in piece["connectivity"][start:end])
            cells.append((piece["cell_id"][c][0], kind, nodes, {n: piece[n][c] for n in cell_names}))
            start = end
    cells.sort(key=lambda cell: cell[0])
    merged["connectivity"], merged["offsets"], merged["types"] = [], [], []
    for _, kind, nodes, _ in cells:
        merged["connectivity"].extend((k,) for k in nodes)
        merged["offsets"].append((len(merged["connectivity"]),))
        merged["types"].append((kind,))
    for name in cell_names:
        merged[name] = [cell[3][name] for cell in cells]
    return merged


def _read_piece(path):
    """The arrays of one .vtu (read_vtu) and the names of its cell arrays."""
    data = open(path, "rb").read()
    header_end = data.find(b"<AppendedData")
    text = data[: header_end if header_end >= 0 else len(data)].decode("latin-1")
    arrays = {}
    base = None
    if header_end >= 0:
        base = data.find(b"_", header_end) + 1
    cell_data = (text.find("<CellData"), text.find("</CellData>"))
    cell_names = []
    for match in re.finditer(r'<DataArray([^>]*)>', text):
        attrs = dict(re.findall(r'(\w+)="([^"]*)"', match.group(1)))
        name = attrs.get("Name", "")
        if cell_data[0] <= match.start() < cell_data[1] and name in arrays:
            name = "cell:" + name
        kind = attrs["type"]
        ncomp = int(attrs.get("NumberOfComponents", "1"))
        fmt = {"Float64": "d", "Int32": "i", "Int64": "q", "UInt8": "B"}[kind]
        if attrs.get("format") == "appended":
            start = base + int(attrs["offset"])
            nbytes = struct.unpack("<Q", data[start : start + 8])[0]
            raw = data[start + 8 : start + 8 + nbytes]
        else:
            import base64
            body_start = match.end()
            body_end = text.find("</DataArray>", body_start)
            blob = base64.b64decode(text[body_start:body_end].strip())
            nbytes = struct.unpack("<Q", blob[:8])[0]
            raw = blob[8 : 8 + nbytes]
        values = struct.unpack("<%d%s" % (len(raw) // struct.calcsize(fmt), fmt), raw)
        arrays[name] = [tuple(values[i : i + ncomp]) for i in range(0, len(values), ncomp)]
        if cell_data[0] <= match.start() < cell_data[1]:
            cell_names.append(name)
    return arrays, cell_names
