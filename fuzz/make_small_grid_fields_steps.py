#!/usr/bin/env python3
"""Writes fuzz/corpus/dpm/small_grid_fields_steps.dpm: a file with result fields over several
steps, small enough for the dpm fuzzer and the decoders' conformance mutants. A 6 x 6 quad grid
as a legacy VTK sequence of 4 steps: a node field 'strain' that spreads over the grid (its
sections after step 0 take the ring's median change, docs/FORMAT.md "Fields") and an element
field 'stress' (its sections take the heir's change).

usage: make_small_grid_fields_steps.py DYNPM OUT.dpm
"""
import math
import os
import subprocess
import sys
import tempfile

N = 6
STEPS = 4


def write_step(path, t):
    points = [(i / N, j / N) for j in range(N + 1) for i in range(N + 1)]
    quads = [(j * (N + 1) + i, j * (N + 1) + i + 1, (j + 1) * (N + 1) + i + 1, (j + 1) * (N + 1) + i)
             for j in range(N) for i in range(N)]
    lines = ["# vtk DataFile Version 3.0", "grid", "ASCII", "DATASET POLYDATA",
             f"POINTS {len(points)} float"]
    lines += [f"{x:.6f} {y:.6f} {t * 0.3 * math.sin(3 * x + y):.6f}" for x, y in points]
    lines += [f"POLYGONS {len(quads)} {5 * len(quads)}"] + ["4 %d %d %d %d" % q for q in quads]
    lines += [f"POINT_DATA {len(points)}", "SCALARS strain float 1", "LOOKUP_TABLE default"]
    lines += [f"{max(0.0, t * (x * y - 0.2)):.6f}" for x, y in points]
    lines += [f"CELL_DATA {len(quads)}", "SCALARS stress float 1", "LOOKUP_TABLE default"]
    lines += [f"{t * 10 * math.cos(k % N + 0.5 * (k // N)):.5f}" for k in range(len(quads))]
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    dynpm, out = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    with tempfile.TemporaryDirectory() as work:
        for t in range(STEPS):
            write_step(os.path.join(work, f"frame_{t:03d}.vtk"), t)
        build = [dynpm, "build", "frame_*.vtk", "--no-thumbnail", "--quiet", "-o", out]
        subprocess.run(build, cwd=work, check=True)


if __name__ == "__main__":
    main()
