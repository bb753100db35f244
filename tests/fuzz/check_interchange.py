#!/usr/bin/env python3
"""Independent check of the interchange writers' output (see write_interchange_samples.cpp):
parses the VTU/PVD files with xml.etree (a VTU's binary arrays with struct and zlib) and the PLY
files by their own rules, and checks the counts and invariants the samples were written with. Exit 1 with a message on the first problem."""
import re
import struct
import sys
import xml.etree.ElementTree as ET
import zlib
from pathlib import Path


def fail(msg):
    print("check_interchange: " + msg)
    sys.exit(1)


def check(cond, msg):
    if not cond:
        fail(msg)


def numbers(text):
    return [float(t) for t in text.split()]


def read_vtu(path):
    """The XML tree of a binary .vtu and a function decoding a DataArray (appended raw data,
    UInt64 headers, little endian, zlib blocks where the file names vtkZLibDataCompressor)."""
    data = path.read_bytes()
    start = data.find(b'<AppendedData encoding="raw">')
    check(start > 0, f"{path}: no raw AppendedData")
    underscore = data.find(b"_", start)
    tail = b"\n  </AppendedData>\n</VTKFile>\n"
    check(data.endswith(tail), f"{path}: does not end with the appended section")
    root = ET.fromstring(data[:underscore] + tail)
    section = data[underscore + 1:len(data) - len(tail)]
    check(root.get("header_type") == "UInt64" and root.get("byte_order") == "LittleEndian", f"{path}: header type")
    compressed = root.get("compressor") == "vtkZLibDataCompressor"
    check(compressed or root.get("compressor") is None, f"{path}: compressor {root.get('compressor')}")
    ends = []

    def decode(array):
        check(array.get("format") == "appended", f"{path}: {array.get('Name')} is not appended")
        at = int(array.get("offset"))
        if not compressed:
            (size,) = struct.unpack_from("<Q", section, at)
            ends.append((at, at + 8 + size))
            raw = section[at + 8:at + 8 + size]
        else:
            blocks, block, last = struct.unpack_from("<3Q", section, at)
            sizes = struct.unpack_from(f"<{blocks}Q", section, at + 24)
            pos, raw = at + 24 + 8 * blocks, b""
            for b, size in enumerate(sizes):
                try:
                    chunk = zlib.decompress(section[pos:pos + size])
                except zlib.error as e:
                    fail(f"{path}: {array.get('Name')} block {b}: {e}")
                check(len(chunk) == (last if b == blocks - 1 and last else block), f"{path}: block {b} size")
                raw, pos = raw + chunk, pos + size
            ends.append((at, pos))
        fmt = {"Float64": "d", "Int32": "i", "Int64": "q", "UInt8": "B"}[array.get("type")]
        return list(struct.unpack(f"<{len(raw) // struct.calcsize(fmt)}{fmt}", raw))

    def arrays_tile():
        # The arrays follow one another from offset 0 to the end of the section.
        spans = sorted(ends)
        check(spans[0][0] == 0 and spans[-1][1] == len(section), f"{path}: the arrays do not fill the section")
        check(all(a[1] == b[0] for a, b in zip(spans, spans[1:])), f"{path}: a gap or overlap between arrays")

    return root, decode, arrays_tile


def check_vtu(path, n_points, n_cells):
    root, decode, arrays_tile = read_vtu(path)
    check(root.tag == "VTKFile" and root.get("type") == "UnstructuredGrid", f"{path}: not an UnstructuredGrid")
    piece = root.find("UnstructuredGrid/Piece")
    check(piece is not None, f"{path}: no Piece")
    check(int(piece.get("NumberOfPoints")) == n_points, f"{path}: NumberOfPoints")
    check(int(piece.get("NumberOfCells")) == n_cells, f"{path}: NumberOfCells")
    pts = decode(piece.find("Points/DataArray"))
    check(len(pts) == 3 * n_points, f"{path}: {len(pts)} point coordinates")
    arrays = {a.get("Name"): a for a in piece.find("Cells").findall("DataArray")}
    conn = decode(arrays["connectivity"])
    offs = decode(arrays["offsets"])
    types = decode(arrays["types"])
    check(len(conn) == 4 * n_cells and all(0 <= c < n_points for c in conn), f"{path}: connectivity")
    check(offs == [4 * (i + 1) for i in range(n_cells)], f"{path}: offsets")
    check(types == [10] * n_cells, f"{path}: types")
    # Every tet has positive volume in the written positions (the samples are not inverted).
    for e in range(n_cells):
        p = [pts[3 * conn[4 * e + k]:3 * conn[4 * e + k] + 3] for k in range(4)]
        a, b, c = ([p[k][i] - p[0][i] for i in range(3)] for k in (1, 2, 3))
        vol6 = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0])
        check(abs(vol6) > 1e-12, f"{path}: tet {e} is flat")
    cd = {a.get("Name"): decode(a) for a in piece.find("CellData").findall("DataArray")}
    check(set(cd) == {"det_F", "inverted"}, f"{path}: cell arrays {sorted(cd)}")
    check(all(len(v) == n_cells for v in cd.values()), f"{path}: cell array lengths")
    check(all((d < 0) == (i == 1) for d, i in zip(cd["det_F"], cd["inverted"])), f"{path}: inverted flags")
    vel = piece.find("PointData/DataArray")
    check(vel.get("Name") == "velocity" and vel.get("NumberOfComponents") == "3", f"{path}: velocity array")
    check(len(decode(vel)) == 3 * n_points, f"{path}: velocity length")
    arrays_tile()


def check_pvd(path):
    root = ET.parse(path).getroot()
    check(root.get("type") == "Collection", f"{path}: not a Collection")
    sets = root.findall("Collection/DataSet")
    check(len(sets) == 2, f"{path}: {len(sets)} DataSets")
    times = [float(s.get("timestep")) for s in sets]
    check(times == sorted(times), f"{path}: times not sorted")
    for s in sets:
        check((path.parent / s.get("file")).is_file(), f"{path}: {s.get('file')} missing")
        check_vtu(path.parent / s.get("file"), 12, 12)


def check_ply(path, n_vertices, n_faces):
    data = path.read_bytes()
    end = data.find(b"end_header\n")
    check(end > 0, f"{path}: no end_header")
    header = data[:end].decode("ascii").splitlines()
    check(header[0] == "ply", f"{path}: no magic")
    fmt = header[1].split()[1]
    check(f"element vertex {n_vertices}" in header and f"element face {n_faces}" in header, f"{path}: counts")
    body = data[end + len(b"end_header\n"):]
    if fmt == "binary_little_endian":
        check(len(body) == 24 * n_vertices + 13 * n_faces, f"{path}: body is {len(body)} bytes")
        xyz = struct.unpack_from(f"<{3 * n_vertices}d", body)
        faces = [struct.unpack_from("<Biii", body, 24 * n_vertices + 13 * f) for f in range(n_faces)]
    else:
        check(fmt == "ascii", f"{path}: format {fmt}")
        rows = [r.split() for r in body.decode("ascii").splitlines()]
        check(len(rows) == n_vertices + n_faces, f"{path}: {len(rows)} body lines")
        xyz = [float(v) for r in rows[:n_vertices] for v in r]
        faces = [tuple(int(v) for v in r) for r in rows[n_vertices:]]
    check(len(xyz) == 3 * n_vertices, f"{path}: coordinates")
    check(all(f[0] == 3 and all(0 <= i < n_vertices for i in f[1:]) for f in faces), f"{path}: faces")


def check_usda(path, n_points, n_faces, n_frames):
    text = path.read_text()
    check(text.startswith("#usda 1.0\n"), f"{path}: header")
    depth = {"(": 0, "[": 0, "{": 0}
    pairs = {")": "(", "]": "[", "}": "{"}
    for ch in re.sub(r'"[^"]*"', '""', text):
        if ch in depth:
            depth[ch] += 1
        elif ch in pairs:
            depth[pairs[ch]] -= 1
            check(depth[pairs[ch]] >= 0, f"{path}: unbalanced {ch}")
    check(all(v == 0 for v in depth.values()), f"{path}: unbalanced brackets")
    for key, want in (("upAxis", '"Y"'), ("metersPerUnit", "1"), ("timeCodesPerSecond", "30"),
                      ("startTimeCode", "0"), ("endTimeCode", str(n_frames - 1))):
        check(re.search(rf"^\s*{key} = {re.escape(want)}$", text, re.M), f"{path}: {key} != {want}")
    idx = re.search(r"int\[\] faceVertexIndices = \[([^\]]*)\]", text).group(1)
    check(len(idx.split(",")) == 3 * n_faces, f"{path}: faceVertexIndices")
    samples = re.search(r"points\.timeSamples = \{(.*?)\n\s*\}", text, re.S).group(1)
    frames = re.findall(r"^\s*(\d+): \[(.*)\],$", samples, re.M)
    check(len(frames) == n_frames, f"{path}: {len(frames)} point samples")
    for f, pts in frames:
        tuples = re.findall(r"\(([^)]*)\)", pts)
        check(len(tuples) == n_points, f"{path}: frame {f} has {len(tuples)} points")
        for t in tuples:
            [float(v) for v in t.split(",")]


def main():
    d = Path(sys.argv[1])
    check_ply(d / "sample_binary.ply", 6, 4)
    check_ply(d / "sample_ascii.ply", 6, 4)
    check_pvd(d / "sample.pvd")
    check_usda(d / "sample.usda", 6, 4, 3)
    print("check_interchange: PLY x2, PVD + 2 VTU, USDA all pass")


if __name__ == "__main__":
    main()
