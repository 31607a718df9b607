#!/usr/bin/env python3
"""Writes fuzz/corpus/dpm/small_grid_family.dpm: a family file small enough for the fuzzers and
the decoders' conformance test. Two variants of one 6 x 6 quad grid as OBJ sequences sharing the
flat step 0: 'wave' (3 steps) and 'bulge' (4 steps).

usage: make_small_grid_family.py DYNPM OUT.dpm
"""
import math
import os
import subprocess
import sys
import tempfile

N = 6


def write_sequence(folder, steps, height):
    os.makedirs(folder)
    for t in range(steps):
        with open(os.path.join(folder, f"frame_{t:03d}.obj"), "w") as f:
            for j in range(N + 1):
                for i in range(N + 1):
                    x, y = i / N, j / N
                    f.write(f"v {x:.6f} {y:.6f} {0.0 if t == 0 else t * height(x, y):.6f}\n")
            for j in range(N):
                for i in range(N):
                    a = j * (N + 1) + i + 1
                    f.write(f"f {a} {a + 1} {a + N + 2} {a + N + 1}\n")


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    dynpm, out = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    with tempfile.TemporaryDirectory() as work:
        write_sequence(os.path.join(work, "wave"), 3, lambda x, y: 0.3 * math.sin(3 * x + y))
        write_sequence(os.path.join(work, "bulge"), 4, lambda x, y: 0.5 * (x * (1 - x) + y * (1 - y)))
        subprocess.run([dynpm, "build", "--family", "wave/frame_*.obj", "bulge/frame_*.obj", "--no-thumbnail", "-o",
                        out, "--quiet"], cwd=work, check=True)


if __name__ == "__main__":
    main()
