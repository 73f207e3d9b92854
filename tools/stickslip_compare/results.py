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
        files = sorted(p for p in os.listdir(self.folder) if p.startswith("step-") and p.endswith(".vtu"))
        return read_vtu(os.path.join(self.folder, files[-1]))


def read_vtu(path):
    """Point and cell data arrays of a stickslip .vtu (raw appended or inline base64) as lists of tuples, by name; a
    cell array whose name a point array has too (the contact fields of contact-NNNNNN.vtu) is under "cell:NAME"."""
    data = open(path, "rb").read()
    header_end = data.find(b"<AppendedData")
    text = data[: header_end if header_end >= 0 else len(data)].decode("latin-1")
    arrays = {}
    base = None
    if header_end >= 0:
        base = data.find(b"_", header_end) + 1
    cell_data = (text.find("<CellData"), text.find("</CellData>"))
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
    return arrays
