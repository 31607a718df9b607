#!/usr/bin/env python3
"""Which vertices each variant's separate build keeps at a level, and how many a family can share.

A family file has one hierarchy: its level of N vertices is one vertex set for every variant. If
the variants' separate builds keep different vertices at N, a family cannot match each of them
at N; the union of their sets is about the vertex count a family level would need to. This
script builds each input alone and all as a family (default flags), takes every build's level
at --ratio (% of the vertices) and prints the sizes of the sets, their overlaps and union, and
where the vertices only one separate build keeps lie (along the model's longest axis, undeformed).

A level's vertices are matched to the input's nodes through the same file's fully refined step 0
(extract --full comes in the input's order; both hold the same decoded floats).

usage: level_overlap.py --dynpm PATH [--ratio 25] A.frd B.frd [C.frd …]
"""
import argparse
import os
import subprocess
import sys
import tempfile


def run(cmd):
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"failed ({done.returncode}): {' '.join(cmd)}\n{done.stdout}{done.stderr}")


def obj_vertices(path):
    with open(path) as f:
        return [tuple(line.split()[1:4]) for line in f if line.startswith("v ")]


def level_nodes(dynpm, model, ratio, work, variant=None):
    """The input's node indices (0-based, ascending node order) a level of `model` keeps."""
    pick = ["--variant", str(variant)] if variant is not None else []
    full, level = os.path.join(work, "full.obj"), os.path.join(work, "level.obj")
    run([dynpm, "extract", model, "--full", "--step", "0", "-o", full, *pick])
    run([dynpm, "extract", model, "--ratio", str(ratio / 100), "--step", "0", "-o", level, *pick])
    full_xyz = obj_vertices(full)
    index = {}
    for i, xyz in enumerate(full_xyz):
        index.setdefault(xyz, i)
    kept = set()
    for xyz in obj_vertices(level):
        if xyz not in index:
            sys.exit(f"{model}: a level vertex {xyz} is not a vertex of the full mesh")
        kept.add(index[xyz])
    return kept, [tuple(float(c) for c in xyz) for xyz in full_xyz]


def where(nodes, xyz):
    """The 10th, 50th and 90th percentiles of `nodes` along the model's longest axis."""
    if not nodes:
        return "none"
    axis = max(range(3), key=lambda c: max(p[c] for p in xyz) - min(p[c] for p in xyz))
    along = sorted(xyz[i][axis] for i in nodes)
    pick = [along[min(len(along) - 1, int(q * len(along)))] for q in (0.1, 0.5, 0.9)]
    return "%s = %.0f / %.0f / %.0f (10th / 50th / 90th percentile, model %.0f..%.0f)" % (
        "xyz"[axis], *pick, min(p[axis] for p in xyz), max(p[axis] for p in xyz))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--dynpm", required=True)
    ap.add_argument("--ratio", type=float, default=25)
    ap.add_argument("inputs", nargs="+")
    a = ap.parse_args()
    if len(a.inputs) < 2:
        sys.exit("needs two inputs or more")
    with tempfile.TemporaryDirectory(prefix="dynpm-overlap-") as work:
        family = os.path.join(work, "family.dpm")
        run([a.dynpm, "build", "--family", *a.inputs, "-o", family, "--quiet", "--no-thumbnail"])
        separate, xyz = [], None
        for k, path in enumerate(a.inputs):
            out = os.path.join(work, f"v{k}.dpm")
            run([a.dynpm, "build", path, "-o", out, "--quiet", "--no-thumbnail"])
            kept, xyz = level_nodes(a.dynpm, out, a.ratio, work)
            separate.append(kept)
        fam, _ = level_nodes(a.dynpm, family, a.ratio, work, variant=0)
        names = [os.path.basename(p) for p in a.inputs]
        union = set().union(*separate)
        print(f"at {a.ratio:g} % of {len(xyz)} vertices: each separate level keeps "
              f"{', '.join(str(len(s)) for s in separate)}; all of them keep "
              f"{len(set.intersection(*separate))}; their union is {len(union)} "
              f"({100 * len(union) / len(xyz):.1f} % of the vertices)")
        for k, kept in enumerate(separate):
            others = set().union(*(s for j, s in enumerate(separate) if j != k))
            only = kept - others
            print(f"  {names[k]}: {len(only)} kept by its separate build alone, at "
                  f"{where(only, xyz)}; the family's level keeps {len(fam & kept)} of its "
                  f"{len(kept)}")


if __name__ == "__main__":
    main()
