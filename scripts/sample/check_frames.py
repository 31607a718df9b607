#!/usr/bin/env python3
"""Check an OBJ sequence written by frd_to_obj.py.  Standard library only.

Checks: frame_000.obj ... are consecutive and at least MIN_FRAMES (default 26);
every frame has the same vertex count and byte-identical face lines; frame 0
equals the undeformed geometry (max_disp 0); times and max_disp in times.csv
never decrease and agree with the OBJ coordinates.  Prints one summary line:
  frames=N nodes=N quads=N triangles=N max_disp=X final_time=T

usage: check_frames.py DIR [MIN_FRAMES]
"""
import csv
import glob
import math
import os
import sys


def die(msg):
    sys.exit("check_frames.py: FAILED: " + msg)


def read_obj(path):
    verts, faces = [], []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                verts.append(tuple(float(t) for t in line.split()[1:4]))
            elif line.startswith("f "):
                faces.append(line)
            elif line.startswith("#") or not line.strip():
                continue
            else:
                die("%s: unexpected line %r" % (path, line[:40]))
    return verts, faces


def main(argv):
    if len(argv) not in (2, 3):
        sys.exit(__doc__.strip().splitlines()[-1])
    d = argv[1]
    min_frames = int(argv[2]) if len(argv) == 3 else 26
    files = sorted(glob.glob(os.path.join(d, "frame_*.obj")))
    if len(files) < min_frames:
        die("%d frames, expected at least %d" % (len(files), min_frames))
    for i, p in enumerate(files):
        if int(os.path.basename(p)[6:-4]) != i:
            die("frame numbers are not consecutive at %s" % p)
    with open(os.path.join(d, "times.csv")) as f:
        rows = list(csv.DictReader(f))
    if len(rows) != len(files):
        die("times.csv has %d rows for %d frames" % (len(rows), len(files)))
    v0, f0 = read_obj(files[0])
    nq = sum(1 for l in f0 if len(l.split()) == 5)
    nt = sum(1 for l in f0 if len(l.split()) == 4)
    if nq + nt != len(f0):
        die("faces other than quads and triangles in frame 0")
    used = {int(t) for l in f0 for t in l.split()[1:]}
    if min(used) < 1 or max(used) > len(v0) or len(used) != len(v0):
        die("faces do not use exactly the vertices 1..%d" % len(v0))
    prev_t, prev_m = -1.0, -1.0
    for i, p in enumerate(files):
        v, fl = read_obj(p)
        if len(v) != len(v0):
            die("%s has %d vertices, frame 0 has %d" % (p, len(v), len(v0)))
        if fl != f0:
            die("%s: face lines differ from frame 0" % p)
        m = max(math.dist(a, b) for a, b in zip(v, v0))
        row = rows[i]
        if int(row["frame"]) != i:
            die("times.csv row %d has frame %s" % (i, row["frame"]))
        t, md = float(row["time"]), float(row["max_disp"])
        if abs(m - md) > 1e-3 * max(1.0, md) + 1e-4:
            die("%s: max displacement from coordinates %.4g != times.csv %.4g" % (p, m, md))
        if t < prev_t or md < prev_m:
            die("time or max_disp decreases at frame %d" % i)
        prev_t, prev_m = t, md
    if float(rows[0]["max_disp"]) != 0.0:
        die("frame 0 is not undeformed")
    print("frames=%d nodes=%d quads=%d triangles=%d max_disp=%s final_time=%s"
          % (len(files), len(v0), nq, nt, rows[-1]["max_disp"], rows[-1]["time"]))


if __name__ == "__main__":
    main(sys.argv)
