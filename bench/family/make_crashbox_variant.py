#!/usr/bin/env python3
"""Writes a CalculiX deck for a second load case on a crash box's own mesh, and runs ccx.

The family file (docs/family.md) needs variants of ONE mesh: same node and element ids. The
crash boxes of ../shared/data (crashbox-s, crashbox-fields) were made by gmsh + ccx, but their
decks are not kept; their .frd holds the mesh (the node block 2C and the element block 3C: S4
quads, and S3 triangles in crashbox-fields), which is all a new deck needs.
On crashbox-s (clamped bottom ring z = 0, the top ring z = 250 mm moved, like the original):
  bent  30 mm sideways in x, free along the tube's axis (a cantilever bend instead of the axial
        crush), 12 output times: another kind of load, another step count;
  deep  75 mm down the axis, held in x and y like the original's 60 mm crush, 15 output times:
        the same kind of load with another magnitude, as a DOE over the crush depth would run;
  short 4.8 mm down the axis, held like deep, 8 output times: the crush stopped as the first
        fold forms (the original reaches 4.8 mm at its 2nd output time).
On crashbox-fields (both rings clamped, as the original, whose strip of the y = +30 face at
z = 115 … 135 mm is pushed 100 mm per time unit in −y; results U, S, PEEQ and ERR at the shell
nodes, as the original's):
  side  the same strip of the x = +30 face pushed 2 mm in −x, 2 output times of 1 mm: the
        three-point bend turned a quarter, a short run (a 20 mm push ran 0.14 mm a minute of
        wall time at load 14, where ccx got a fifth of a core: hours).

usage: make_crashbox_variant.py CRASHBOX.frd[.gz] OUTDIR [bent|deep|short|side]
       -> OUTDIR/crashbox-LOAD.frd (bent when no load is given; side is made for crashbox-fields)
needs: ccx (Debian: calculix-ccx)
"""
import gzip
import os
import subprocess
import sys


# CalculiX's .frd element types: 9 a 4-node shell (S4), 7 a 3-node one (S3).
FRD_SHELLS = {9: "S4", 7: "S3"}


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
                if kind not in FRD_SHELLS:
                    sys.exit(f"{path}: element {number}: type {kind}, expected 9 (S4) or 7 (S3)")
                corners = next(lines)
                elements.append((number, FRD_SHELLS[kind], [int(c) for c in corners[3:].split()]))
    if not nodes or not elements:
        sys.exit(f"{path}: no node or element block")
    return nodes, elements


# Per load: the mesh (s: crashbox-s, fields: crashbox-fields), heading, output times,
# *CONTROLS time incrementation (the 6th number: an increment that converges in fewer iterations,
# twice, lets the next grow; the crush yields and folds from 0.3 mm on, where every increment
# takes 4 to 5), *STATIC line (initial, period, min, max increment) and the moved nodes' boundary
# conditions (TOP: the top ring; SIDE: the pushed strip). The bent deck is the one
# crashbox-bent.frd.gz was computed from.
LOADS = {
    "bent": ("s", "crashbox-s mesh, bent: top ring pushed 30 mm in x", 12,
             "8, 12, 9, 30, 10, 4, 12, 8", "0.5, 12., 1.E-4, 1.", ["TOP, 1, 1, 30.", "TOP, 2, 2, 0."]),
    "deep": ("s", "crashbox-s mesh, deep crush: top ring pushed 75 mm down", 15,
             "8, 12, 9, 30, 10, 6, 12, 8", "0.02, 15., 1.E-5, 0.25",
             ["TOP, 1, 2, 0.", "TOP, 3, 3, -75."]),
    "short": ("s", "crashbox-s mesh, short crush: top ring pushed 4.8 mm down", 8,
              "8, 12, 9, 30, 10, 6, 12, 8", "0.1, 8., 1.E-5, 0.5",
              ["TOP, 1, 2, 0.", "TOP, 3, 3, -4.8"]),
    "side": ("fields", "crashbox-fields mesh, side: the x = +30 strip at z 115-135 pushed 2 mm in -x",
             2, "8, 12, 9, 30, 10, 6, 12, 8", "0.05, 2., 1.E-5, 0.25", ["SIDE, 1, 1, -2."]),
}
# The clamped rings and the results written: crashbox-s's crush clamps the bottom and writes U;
# crashbox-fields clamps both rings and writes U, S, PEEQ and ERR (its fields, named as the
# original's, so that the two are variants of one mesh with the same fields).
MESHES = {
    "s": (["BOTTOM"], []),
    "fields": (["BOTTOM", "TOP"], ["*EL FILE, OUTPUT=2D, TIME POINTS=TOUT", "S, PEEQ, ERR"]),
}


def write_deck(nodes, elements, load, deck):
    mesh, heading, outputs, controls, static, moved = LOADS[load]
    clamped, element_output = MESHES[mesh]
    z = [n[3] for n in nodes]
    sets = {
        "BOTTOM": [n[0] for n in nodes if abs(n[3] - min(z)) < 1e-6],
        "TOP": [n[0] for n in nodes if abs(n[3] - max(z)) < 1e-6],
        # The x = +30 face's strip, |y| <= 25 (the flat, not the corner radii), z 115 ... 135.
        "SIDE": [n[0] for n in nodes if abs(n[1] - 30) < 1e-6 and abs(n[2]) <= 25 + 1e-6
                 and 115 <= n[3] <= 135.5],
    }
    out = ["*HEADING", heading, "*NODE, NSET=NALL"]
    out += [f"{n}, {x:.6g}, {y:.6g}, {zz:.6g}" for n, x, y, zz in nodes]
    for kind in ("S4", "S3"):
        of_kind = [(e, corners) for e, k, corners in elements if k == kind]
        if of_kind:
            out.append(f"*ELEMENT, TYPE={kind}, ELSET=EALL")
            out += [f"{e}, " + ", ".join(str(c) for c in corners) for e, corners in of_kind]
    for name in clamped + sorted({bc.split(",")[0] for bc in moved}):
        ids = sets[name]
        if not ids:
            sys.exit(f"no node in {name}: is this the mesh the load is made for?")
        out.append(f"*NSET, NSET={name}")
        out += [", ".join(str(i) for i in ids[k:k + 12]) for k in range(0, len(ids), 12)]
    out += ["*MATERIAL, NAME=STEEL", "*ELASTIC", "210000., 0.3", "*PLASTIC", "250., 0.0",
            "300., 0.05", "380., 0.20", "450., 1.00", "*DENSITY", "7.85E-9",
            "*SHELL SECTION, ELSET=EALL, MATERIAL=STEEL", "1.5",
            "*TIME POINTS, NAME=TOUT, GENERATE", f"1., {outputs}., 1.",
            "*STEP, NLGEOM, INC=1000", "*CONTROLS, PARAMETERS=TIME INCREMENTATION",
            controls, "*STATIC", static, "*BOUNDARY"]
    out += [f"{name}, 1, 3, 0." for name in clamped] + moved
    out += ["*NODE FILE, OUTPUT=2D, TIME POINTS=TOUT", "U"] + element_output
    out += ["*END STEP", ""]
    with open(deck, "w") as f:
        f.write("\n".join(out))


def main():
    if len(sys.argv) not in (3, 4) or (len(sys.argv) == 4 and sys.argv[3] not in LOADS):
        sys.exit(__doc__)
    source, outdir = sys.argv[1], sys.argv[2]
    load = sys.argv[3] if len(sys.argv) == 4 else "bent"
    job = f"crashbox-{load}"
    os.makedirs(outdir, exist_ok=True)
    nodes, elements = read_mesh(source)
    write_deck(nodes, elements, load, os.path.join(outdir, job + ".inp"))
    env = dict(os.environ, OMP_NUM_THREADS="1")
    with open(os.path.join(outdir, "ccx.log"), "w") as log:
        run = subprocess.run(["ccx", "-i", job], cwd=outdir, stdout=log,
                             stderr=subprocess.STDOUT, env=env)
    text = open(os.path.join(outdir, "ccx.log")).read()
    if run.returncode != 0 or "*ERROR" in text or "Job finished" not in text:
        sys.exit(f"ccx failed (see {outdir}/ccx.log)")
    print(os.path.join(outdir, job + ".frd"))


if __name__ == "__main__":
    main()
