#!/usr/bin/env python3
"""Writes a CalculiX deck for a second load case on crashbox-s's own mesh, and runs ccx.

The family file (docs/family.md) needs variants of ONE mesh: same node and element ids. The
crash box of ../shared/data/crashbox-s was made by gmsh + ccx, but its deck is not kept; its .frd
holds the mesh (the node block 2C and the S4 element block 3C), which is all a new deck needs.
This one clamps the bottom ring (z = 0) like the original and pushes the top ring (z = 250 mm)
30 mm sideways in x, free along the tube's axis (a cantilever bend instead of the axial crush),
with 12 output times: another load, another step count.

usage: make_crashbox_variant.py CRASHBOX.frd[.gz] OUTDIR   -> OUTDIR/crashbox-bent.frd
needs: ccx (Debian: calculix-ccx)
"""
import gzip
import os
import subprocess
import sys


def read_mesh(path):
    opener = gzip.open if path.endswith(".gz") else open
    nodes, elements = [], []
    block = None
    with opener(path, "rt") as f:
        lines = iter(f)
        for line in lines:
            if line.startswith("    2C"):
                block = "nodes"
                continue
            if line.startswith("    3C"):
                block = "elements"
                continue
            if line.startswith(" -3"):
                if block == "elements":
                    break
                block = None
                continue
            if block == "nodes" and line.startswith(" -1"):
                nodes.append((int(line[3:13]), float(line[13:25]), float(line[25:37]),
                              float(line[37:49])))
            elif block == "elements" and line.startswith(" -1"):
                number, kind = int(line[3:13]), int(line[13:18])
                if kind != 9:
                    sys.exit(f"{path}: element {number}: type {kind}, expected 9 (S4)")
                corners = next(lines)
                elements.append((number, [int(c) for c in corners[3:].split()]))
    if not nodes or not elements:
        sys.exit(f"{path}: no node or element block")
    return nodes, elements


def write_deck(nodes, elements, deck):
    z = [n[3] for n in nodes]
    bottom = [n[0] for n in nodes if abs(n[3] - min(z)) < 1e-6]
    top = [n[0] for n in nodes if abs(n[3] - max(z)) < 1e-6]
    out = ["*HEADING", "crashbox-s mesh, bent: top ring pushed 30 mm in x",
           "*NODE, NSET=NALL"]
    out += [f"{n}, {x:.6g}, {y:.6g}, {zz:.6g}" for n, x, y, zz in nodes]
    out.append("*ELEMENT, TYPE=S4, ELSET=EALL")
    out += [f"{e}, " + ", ".join(str(c) for c in corners) for e, corners in elements]
    for name, ids in (("BOTTOM", bottom), ("TOP", top)):
        out.append(f"*NSET, NSET={name}")
        out += [", ".join(str(i) for i in ids[k:k + 12]) for k in range(0, len(ids), 12)]
    out += ["*MATERIAL, NAME=STEEL", "*ELASTIC", "210000., 0.3", "*PLASTIC", "250., 0.0",
            "300., 0.05", "380., 0.20", "450., 1.00", "*DENSITY", "7.85E-9",
            "*SHELL SECTION, ELSET=EALL, MATERIAL=STEEL", "1.5",
            "*TIME POINTS, NAME=TOUT, GENERATE", "1., 12., 1.",
            "*STEP, NLGEOM, INC=1000", "*CONTROLS, PARAMETERS=TIME INCREMENTATION",
            "8, 12, 9, 30, 10, 4, 12, 8", "*STATIC", "0.5, 12., 1.E-4, 1.", "*BOUNDARY",
            "BOTTOM, 1, 3, 0.", "TOP, 1, 1, 30.", "TOP, 2, 2, 0.",
            "*NODE FILE, OUTPUT=2D, TIME POINTS=TOUT", "U", "*END STEP", ""]
    with open(deck, "w") as f:
        f.write("\n".join(out))


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    source, outdir = sys.argv[1], sys.argv[2]
    os.makedirs(outdir, exist_ok=True)
    nodes, elements = read_mesh(source)
    write_deck(nodes, elements, os.path.join(outdir, "crashbox-bent.inp"))
    env = dict(os.environ, OMP_NUM_THREADS="1")
    with open(os.path.join(outdir, "ccx.log"), "w") as log:
        run = subprocess.run(["ccx", "-i", "crashbox-bent"], cwd=outdir, stdout=log,
                             stderr=subprocess.STDOUT, env=env)
    text = open(os.path.join(outdir, "ccx.log")).read()
    if run.returncode != 0 or "*ERROR" in text or "Job finished" not in text:
        sys.exit(f"ccx failed (see {outdir}/ccx.log)")
    print(os.path.join(outdir, "crashbox-bent.frd"))


if __name__ == "__main__":
    main()
