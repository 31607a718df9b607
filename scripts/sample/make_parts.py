#!/usr/bin/python3
"""The hat-rail sample as a multi-part model with NAMED parts, written as Exodus II.

    /usr/bin/python3 scripts/sample/make_parts.py OUT.e FRAME_000.obj FRAME_001.obj ...

Reads the CalculiX hat rail's OBJ frames (the shipped sample: `data/hat-rail/frames.tar.xz`,
made from `rail.frd` by frd_to_obj.py), sorts its shells into the parts a stamped rail is made
of by where each face lies in the first frame (the hat top, its free-meshed patch around the
hole, the two walls and the two flanges), and writes them with netCDF4 as Exodus II element
blocks with names (`eb_names`), ids (`eb_prop1`), nodal displacements DISPL_X/Y/Z per frame
and the frames' times. The result is what a pre-processor would write for this rail, for the
tests of part names (tests/io_exodus_test.cpp, viewer/test/parts_browser.test.mjs).
Needs python3-netcdf4 and python3-numpy (Debian).
"""
import re
import sys

import netCDF4
import numpy as np

# (id, name): Exodus block ids need not be 1..n; names are what the part list shows.
PARTS = [
    (101, "Hat top"),
    (102, "Hat top — hole patch"),
    (201, "Wall left"),
    (202, "Wall right"),
    (301, "Flange left"),
    (302, "Flange right"),
]
LEN_NAME = 33  # Exodus's default name length (32 characters and a NUL)


def read_obj(path):
    """Vertices (n × 3), faces (lists of 0-based corners) and the frame's time note."""
    vertices, faces, time = [], [], None
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                vertices.append([float(x) for x in line.split()[1:4]])
            elif line.startswith("f "):
                faces.append([int(c.split("/")[0]) - 1 for c in line.split()[1:]])
            elif line.startswith("#") and time is None:
                m = re.search(r"time (\S+)", line)
                if m:
                    time = float(m.group(1).rstrip(",;)"))
    return np.array(vertices), faces, time


def char_row(raw):
    """A name as one row of a char[len_name] variable: its UTF-8 bytes, NUL-padded."""
    if len(raw) >= LEN_NAME:
        sys.exit(f"name {raw!r} is longer than {LEN_NAME - 1} bytes")
    return np.frombuffer(raw.ljust(LEN_NAME, b"\0"), dtype="S1")


def part_of(face, xyz):
    """The part a face belongs to, from its centroid in the undeformed rail (mm)."""
    c = xyz[face].mean(axis=0)
    if c[1] > 39.0:  # the hat top, at y = 40
        return 102 if len(face) == 3 else 101
    if c[1] < 1.0:  # the flanges, at y = 0
        return 301 if c[0] < 0 else 302
    return 201 if c[0] < 0 else 202


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    out, frames = sys.argv[1], sys.argv[2:]
    xyz0, faces, _ = read_obj(frames[0])
    blocks = {pid: [f for f in faces if part_of(f, xyz0) == pid] for pid, _ in PARTS}
    for pid, name in PARTS:
        corners = {len(f) for f in blocks[pid]}
        if len(corners) != 1:
            sys.exit(f"part {name}: {sorted(corners)} corners; a block needs one element type")
    n = len(xyz0)
    nc = netCDF4.Dataset(out, "w", format="NETCDF3_64BIT_OFFSET")
    nc.title = "dynpm hat-rail sample, parts by make_parts.py"
    nc.api_version = nc.version = np.float32(8.0)
    nc.floating_point_word_size = np.int32(8)
    nc.file_size = np.int32(1)
    for name, size in [("len_string", 33), ("len_line", 81), ("four", 4), ("len_name", LEN_NAME),
                       ("time_step", None), ("num_dim", 3), ("num_nodes", n),
                       ("num_elem", len(faces)), ("num_el_blk", len(PARTS)),
                       ("num_nod_var", 3)]:
        nc.createDimension(name, size)
    for axis, name in enumerate(["coordx", "coordy", "coordz"]):
        nc.createVariable(name, "f8", ("num_nodes",))[:] = xyz0[:, axis]
    ids = nc.createVariable("eb_prop1", "i4", ("num_el_blk",))
    ids.setncattr("name", "ID")
    ids[:] = [pid for pid, _ in PARTS]
    nc.createVariable("eb_status", "i4", ("num_el_blk",))[:] = 1
    names = nc.createVariable("eb_names", "S1", ("num_el_blk", "len_name"))
    for b, (pid, name) in enumerate(PARTS):
        raw = name.encode("utf-8")
        names[b] = char_row(raw)
        count = len(blocks[pid])
        per = len(blocks[pid][0])
        nc.createDimension(f"num_el_in_blk{b + 1}", count)
        nc.createDimension(f"num_nod_per_el{b + 1}", per)
        connect = nc.createVariable(f"connect{b + 1}", "i4",
                                    (f"num_el_in_blk{b + 1}", f"num_nod_per_el{b + 1}"))
        connect.elem_type = "SHELL4" if per == 4 else "TRISHELL3"
        connect[:] = np.array(blocks[pid]) + 1
    var_names = nc.createVariable("name_nod_var", "S1", ("num_nod_var", "len_name"))
    for k, name in enumerate(["DISPL_X", "DISPL_Y", "DISPL_Z"]):
        var_names[k] = char_row(name.encode())
    times = nc.createVariable("time_whole", "f8", ("time_step",))
    displacement = [nc.createVariable(f"vals_nod_var{k + 1}", "f8", ("time_step", "num_nodes"))
                    for k in range(3)]
    for t, path in enumerate(frames):
        xyz, _, time = read_obj(path)
        if xyz.shape != xyz0.shape:
            sys.exit(f"{path}: {len(xyz)} vertices, the first frame has {n}")
        times[t] = time if time is not None else float(t)
        for k in range(3):
            displacement[k][t, :] = xyz[:, k] - xyz0[:, k]
    nc.close()
    counts = ", ".join(f"{name} {len(blocks[pid])}" for pid, name in PARTS)
    print(f"{out}: {n} nodes, {len(faces)} shells in {len(PARTS)} parts ({counts}), "
          f"{len(frames)} frames")


if __name__ == "__main__":
    main()
