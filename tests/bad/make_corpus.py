#!/usr/bin/env python3
"""Writes the bad-input corpus (tests/bad/): small files, each broken in one way.

Run from anywhere: python3 tests/bad/make_corpus.py DYNPM  (the dynpm binary builds the .dpm
cases). The files are committed; this script says how each was made and remakes them.
expected.txt says what dynpm must answer for each.
"""
import math
import os
import shutil
import struct
import subprocess
import sys
import tempfile
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))

# A 2 x 2 grid of unit quads in z = 0:  6---7---8
#                                       | 2 | 3 |
#                                       3---4---5
#                                       | 0 | 1 |
#                                       0---1---2
GRID_V = [(float(i), float(j), 0.0) for j in range(3) for i in range(3)]
GRID_F = [(0, 1, 4, 3), (1, 2, 5, 4), (3, 4, 7, 6), (4, 5, 8, 7)]


def write(name, data):
    path = os.path.join(HERE, name)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "wb") as f:
        f.write(data.encode() if isinstance(data, str) else data)


def obj(vertices, faces, comment="a 2 x 2 quad grid"):
    s = f"# {comment}\n"
    s += "".join(f"v {x:g} {y:g} {z:g}\n" for x, y, z in vertices)
    s += "".join("f " + " ".join(str(c + 1) for c in f) + "\n" for f in faces)
    return s


def binary_ply(vertices, faces):
    head = ("ply\nformat binary_little_endian 1.0\ncomment the 2 x 2 quad grid\n"
            f"element vertex {len(vertices)}\nproperty float x\nproperty float y\n"
            f"property float z\nelement face {len(faces)}\n"
            "property list uchar int vertex_indices\nend_header\n").encode()
    body = b"".join(struct.pack("<3f", *v) for v in vertices)
    body += b"".join(struct.pack("<B", len(f)) + struct.pack(f"<{len(f)}i", *f) for f in faces)
    return head + body


def binary_vtk(vertices, faces):
    s = (b"# vtk DataFile Version 3.0\nthe 2 x 2 quad grid\nBINARY\nDATASET POLYDATA\n"
         + f"POINTS {len(vertices)} float\n".encode())
    s += b"".join(struct.pack(">3f", *v) for v in vertices)
    size = sum(len(f) + 1 for f in faces)
    s += f"\nPOLYGONS {len(faces)} {size}\n".encode()
    s += b"".join(struct.pack(f">{len(f) + 1}i", len(f), *f) for f in faces)
    return s + b"\n"


def ascii_ply(vertices, faces, element_face=None, extra_header=""):
    """Ascii PLY of the grid; element_face replaces the face count's text."""
    return ("ply\nformat ascii 1.0\n" + extra_header
            + f"element vertex {len(vertices)}\nproperty float x\nproperty float y\n"
            f"property float z\nelement face {element_face or len(faces)}\n"
            "property list uchar int vertex_indices\nend_header\n"
            + "".join(f"{x:g} {y:g} {z:g}\n" for x, y, z in vertices)
            + "".join(f"{len(f)} " + " ".join(map(str, f)) + "\n" for f in faces))


def ascii_vtk(coordinates, faces, keyword="POLYGONS"):
    """Legacy ascii VTK of the grid; coordinates are the points' text, one 'x y z' per point."""
    size = sum(len(f) + 1 for f in faces)
    return ("# vtk DataFile Version 3.0\nthe 2 x 2 quad grid\nASCII\nDATASET POLYDATA\n"
            f"POINTS {len(coordinates)} float\n" + "".join(c + "\n" for c in coordinates)
            + f"{keyword} {len(faces)} {size}\n"
            + "".join(f"{len(f)} " + " ".join(map(str, f)) + "\n" for f in faces))


def ascii_vtu(coordinates, faces):
    """VTK XML UnstructuredGrid, ascii DataArrays; coordinates as text, one 'x y z' each."""
    offsets, at = [], 0
    for f in faces:
        at += len(f)
        offsets.append(at)
    return ('<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="1.0">\n'
            f'<UnstructuredGrid><Piece NumberOfPoints="{len(coordinates)}" '
            f'NumberOfCells="{len(faces)}">\n<Points>\n'
            '<DataArray type="Float32" NumberOfComponents="3" format="ascii">\n'
            + "\n".join(coordinates) + "\n</DataArray>\n</Points>\n<Cells>\n"
            '<DataArray type="Int32" Name="connectivity" format="ascii">\n'
            + " ".join(str(c) for f in faces for c in f) + "\n</DataArray>\n"
            '<DataArray type="Int32" Name="offsets" format="ascii">\n'
            + " ".join(map(str, offsets)) + "\n</DataArray>\n"
            '<DataArray type="UInt8" Name="types" format="ascii">\n'
            + " ".join("9" if len(f) == 4 else "5" for f in faces) + "\n</DataArray>\n"
            "</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n")


def frd(steps, node_x=None, time_text=None):
    """CalculiX .frd (ascii, short format): the grid as nodes 1-9 and S4 elements 1-4.
    node_x: {node index: 12-column text} replaces x coordinates; time_text: step 1's time."""
    e12 = lambda v: f"{v:12.5E}"
    s = "    1C\n    1UUSER\n"
    s += "    2C" + " " * 18 + f"{len(GRID_V):12d}" + " " * 37 + "0\n"
    for n, (x, y, z) in enumerate(GRID_V):
        xt = (node_x or {}).get(n, e12(x))
        s += f" -1{n + 1:5d}" + xt + e12(y) + e12(z) + "\n"
    s += " -3\n"
    s += "    3C" + " " * 18 + f"{len(GRID_F):12d}" + " " * 37 + "0\n"
    for e, f in enumerate(GRID_F):
        s += f" -1{e + 1:5d}{9:5d}{0:5d}{1:5d}\n -2" + "".join(f"{c + 1:5d}" for c in f) + "\n"
    s += " -3\n"
    for step in range(1, steps + 1):
        t = time_text if time_text and step == 1 else e12(0.5 * step)
        s += (f"  100CL  1{step:2d}" + t + f"{len(GRID_V):12d}" + " " * 20
              + f"{0:2d}{step:5d}" + " " * 10 + " 0\n")
        s += " -4  DISP        4    1\n"
        for c, name in enumerate(["D1", "D2", "D3"]):
            s += f" -5  {name:<8s}{1:5d}{2:5d}{c + 1:5d}{0:5d}\n"
        s += " -5  ALL         1    2    0    0    1ALL\n"
        for n in range(len(GRID_V)):
            s += f" -1{n + 1:5d}" + e12(0.0) + e12(0.0) + e12(0.1 * step * n) + "\n"
        s += " -3\n"
    return s + " 9999\n"


def zstd_zeros(n):
    """A zstd frame (RFC 8878) of n zero bytes made of RLE blocks, with its content size."""
    frame = struct.pack("<IBB", 0xFD2FB528, 0xC0, (17 - 10) << 3)  # 8-byte size, 128 KiB window
    frame += struct.pack("<Q", n)
    while n > 0:
        size = min(n, 1 << 17)
        n -= size
        header = (size << 3) | (1 << 1) | (1 if n == 0 else 0)  # RLE block, last?
        frame += struct.pack("<I", header)[:3] + b"\0"
    return frame


def chunk(tag, flags, raw, stored):
    """A .dpm chunk (docs/FORMAT.md): tag, flags, sizes, CRC-32 of the stored bytes, payload."""
    return tag + struct.pack("<IIIII", flags, len(stored), raw, zlib.crc32(stored), 0) + stored


def main():
    dynpm = sys.argv[1] if len(sys.argv) > 1 else None

    write("empty.obj", "")
    write("comments-only.obj", "# a mesh file with nothing in it\n\n# time 0\n")
    write("directory.obj/.gitkeep", "")  # a folder named like a mesh file

    ply = binary_ply(GRID_V, GRID_F)
    header_end = ply.index(b"end_header\n") + len(b"end_header\n")
    # Cut in the middle of the third face record (each face: 1 + 4 * 4 = 17 bytes).
    write("truncated-binary.ply", ply[:header_end + 9 * 12 + 2 * 17 + 7])
    vtk = binary_vtk(GRID_V, GRID_F)
    points = vtk.index(b"float\n") + len(b"float\n")
    write("truncated-binary.vtk", vtk[:points + 5 * 12 + 4])  # inside vertex 5 of 9
    full = frd(2)
    second = full.index("  100CL  1 2")
    write("truncated.frd", full[:second + (full.index(" -3\n", second) - second) // 2])
    write("cut-after-a-step.frd", full[:second])  # ends after step 1's block, no ' 9999'

    write("nan.obj", obj([(math.nan, 0, 0) if i == 4 else v for i, v in enumerate(GRID_V)],
                         GRID_F))
    write("infinite.obj", obj([(1e39, 1, 0) if i == 4 else v for i, v in enumerate(GRID_V)],
                              GRID_F))
    write("nan-binary.ply",
          binary_ply([(0.0, math.nan, 0.0) if i == 4 else v for i, v in enumerate(GRID_V)],
                     GRID_F))

    write("repeated-index.obj", obj(GRID_V, GRID_F[:3] + [(4, 5, 5, 7)]))
    write("out-of-range.obj", obj(GRID_V, GRID_F[:3] + [(4, 5, 9, 7)]))
    write("out-of-range-binary.ply", binary_ply(GRID_V, GRID_F[:3] + [(4, 5, 9, 7)]))

    # Sequences: step 2 (the third file) breaks the first file's mesh.
    nan_step = [(x, y, 0.2) for x, y, _ in GRID_V]
    nan_step[7] = (1.0, 2.0, math.nan)
    for name, bad in [("seq-vertex-count", obj(GRID_V + [(3.0, 3.0, 0.0)], GRID_F)),
                      ("seq-faces", obj(GRID_V, GRID_F[:3] + [(4, 5, 8, 6)])),
                      ("seq-nan", obj(nan_step, GRID_F))]:
        for t in range(3):
            moved = [(x, y, 0.1 * t) for x, y, _ in GRID_V]
            write(f"{name}/frame_{t}.obj", bad if t == 2 else obj(moved, GRID_F))
    # Broken faces in every file and a NaN in step 2: the build reads the steps while it checks
    # the faces, and must still name the faces.
    repeated = GRID_F[:3] + [(4, 5, 5, 7)]
    for t in range(3):
        moved = [(x, y, 0.1 * t) for x, y, _ in GRID_V]
        write(f"seq-nan-bad-faces/frame_{t}.obj", obj(nan_step if t == 2 else moved, repeated))

    # A triangle whose corners lie on one line and a quad folded onto a segment.
    # The grid and a triangle on its right edge whose third corner lies on that edge: 5-2-9 has
    # its corners on the line x = 2 (a sliver, as where a mesher collapsed an element).
    write("zero-area.obj", obj(GRID_V + [(2.0, 0.5, 0.0)], GRID_F + [(5, 2, 9)],
                               "a triangle of zero area"))

    # Five quads on the edge (0, 1): fins of a T-joint gone wild, a non-manifold edge.
    fins = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0)]
    fin_faces = []
    for k in range(5):
        a = 2 * math.pi * k / 5
        dx, dz = round(math.cos(a), 6), round(math.sin(a), 6)
        fins += [(1.0, dx, dz), (0.0, dx, dz)]
        fin_faces.append((0, 1, 2 + 2 * k, 3 + 2 * k))
    write("five-faces-on-an-edge.obj", obj(fins, fin_faces, "five quads share the edge 1-2"))

    # Numbers: one rule for every text reader (a whole token; integers within their type;
    # beyond the double range ±inf, as 1e39 is beyond the float range).
    faces_ply = GRID_F
    write("count-with-junk.ply", ascii_ply(GRID_V, faces_ply, element_face="2x"))
    write("junk-after-number.obj",
          obj(GRID_V, GRID_F).replace("v 1 1 0\n", "v 1 1 0x\n"))
    grid_text = [f"{x:g} {y:g} {z:g}" for x, y, z in GRID_V]
    huge = grid_text[:4] + ["1e400 1 0"] + grid_text[5:]
    write("overflow.obj", obj(GRID_V, GRID_F).replace("v 1 1 0\n", "v 1e400 1 0\n"))
    write("overflow.vtk", ascii_vtk(huge, GRID_F))
    write("overflow.vtu", ascii_vtu(huge, GRID_F))
    write("overflow.frd", frd(1, node_x={4: "      1E+400"}))
    # Times must be finite.
    write("time-nan.obj", obj(GRID_V, GRID_F, "time nan"))
    write("time-nan.frd", frd(2, time_text="         NaN"))
    write("pvd-timestep-nan/step_0.vtu", ascii_vtu(grid_text, GRID_F))
    write("pvd-timestep-nan/step_1.vtu", ascii_vtu(grid_text, GRID_F))
    write("pvd-timestep-nan/run.pvd",
          '<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n<Collection>\n'
          '<DataSet timestep="0" file="step_0.vtu"/>\n'
          '<DataSet timestep="nan" file="step_1.vtu"/>\n</Collection>\n</VTKFile>\n')
    # Bytes from the file in messages: escaped, and at most 80 of them.
    write("escape-in-header.ply",
          ascii_ply(GRID_V, GRID_F, extra_header="\x1b]0;owned\x07\x1b[2J\n"))
    write("nul-in-keyword.vtk", ascii_vtk(grid_text, GRID_F, keyword="POLY\0GONS"))
    # A field name is file text too: 'dynpm info' prints it escaped.
    write("escape-in-field-name.vtk",
          ascii_vtk(grid_text, GRID_F) + "POINT_DATA 9\nSCALARS \x1b[2Jred float 1\n"
          "LOOKUP_TABLE default\n" + "".join(f"{i}\n" for i in range(9)))
    write("long-statement.obj",
          obj(GRID_V, GRID_F) + "x" * 4096 + " a statement 4 KB long\n")

    # .dpm: built from the grid, then broken.
    if dynpm:
        tmp = tempfile.mkdtemp()
        try:
            src = os.path.join(tmp, "grid.obj")
            with open(src, "w") as f:
                f.write(obj(GRID_V, GRID_F))
            out = os.path.join(tmp, "grid.dpm")
            # No thumbnail: the files stay small, as they were before the build drew one.
            subprocess.run([dynpm, "build", src, "--no-thumbnail", "-o", out], check=True,
                           stdout=subprocess.DEVNULL)
            data = open(out, "rb").read()
        finally:
            shutil.rmtree(tmp)
        base = data.index(b"BASE")
        write("truncated-base.dpm", data[:base + 30])  # inside the base mesh chunk
        splt = data.index(b"SPLT")
        write("truncated-splits.dpm", data[:splt + 30])  # a prefix: the base mesh, no splits
        write("wrong-magic.dpm", b"\x89DPN" + data[4:])
        write("wrong-version.dpm", data[:8] + struct.pack("<I", 8) + data[12:])
        # A decompression bomb: the grid's HEAD, then a BASE chunk whose zstd frame really holds
        # 2^31 zero bytes (16384 RLE blocks of 128 KiB, 4 bytes each: 64 KiB for 2 GiB).
        head_end = base  # the BASE chunk starts where HEAD ends
        write("bomb-base.dpm", data[:head_end] + chunk(b"BASE", 1, 2**31, zstd_zeros(2**31)))
        # HEAD's base_error a NaN (8 counts, the box, quant_step and max_error before it; the
        # checksum made again): the split errors' grid starts there (docs/FORMAT.md "Split
        # records"), so both readers refuse it where HEAD is read.
        head = data.index(b"HEAD")
        payload = bytearray(data[head + 24:base])
        payload[96:104] = struct.pack("<d", math.nan)
        write("base-error-nan.dpm", data[:head] + chunk(b"HEAD", 0, len(payload), bytes(payload))
              + data[base:])
        # base_error finite but above 2^1023: no power of two is ≥ it, and the split errors' grid
        # (its P) looped forever in both readers (docs/RELIABILITY.md finding 8); refused in HEAD.
        payload[96:104] = struct.pack("<d", 1.6e308)
        write("base-error-huge.dpm", data[:head] + chunk(b"HEAD", 0, len(payload), bytes(payload))
              + data[base:])
        # HEAD claims 30 million vertices and faces (the counts kept consistent, the checksum
        # made again) for a file of a few hundred bytes: both readers must size what they keep by
        # the splits that arrive, not by the claim (at 300 million it took 3.6 GB and 10 s in C++,
        # 7.9 GB and 29 s in dpm.js), and refuse the file where it ends.
        claim = bytearray(data[head + 24:base])
        base_vertices = struct.unpack_from("<I", claim, 8)[0]
        struct.pack_into("<II", claim, 0, 30_000_000, 30_000_000)
        struct.pack_into("<I", claim, 16, 30_000_000 - base_vertices)
        write("claims-30m-vertices.dpm",
              data[:head] + chunk(b"HEAD", 0, len(claim), bytes(claim)) + data[base:])

    # d3plot-like garbage: named like an LS-DYNA result, 4 KB of noise.
    noise = bytearray()
    x = 12345
    for _ in range(4096):
        x = (1103515245 * x + 12345) % 2**31
        noise.append(x >> 23)
    write("d3plot-garbage/d3plot", bytes(noise))


if __name__ == "__main__":
    main()
