#!/usr/bin/env python3
"""A family file against separate builds (docs/family.md): size and each variant's error.

For two or more variants of one mesh (uncompressed inputs dynpm reads, e.g. CalculiX .frd):
  - builds each alone and all with --family (the same flags otherwise),
  - builds the first input's step 0 alone (converted to PLY, float32 exact), the size that the
    family saves per extra variant when the undeformed step is shared,
  - prints the family's size against the sum of the separate files and against
    (sum - (variants - 1) x step 0 alone): the issue's target is <= 1.05x the latter,
  - runs 'dynpm eval' at --ratios (default 5,25) for each variant, of the family (--variant)
    and of its separate build, over every step, and prints the Hausdorff distance (max over the
    steps) in the input's units and the family's / separate ratio (target within 10 %).
Distances are compared in absolute units: a family's bounding box (and so the diagonal eval
states percentages of) is the box of every variant.

usage: family_bench.py --dynpm PATH [--ratios 5,25] [--json OUT] A.frd B.frd [C.frd …]
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile


def run(cmd):
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"failed ({done.returncode}): {' '.join(cmd)}\n{done.stdout}{done.stderr}")
    return done.stdout


def hausdorff(dynpm, original, model, ratios, work, variant=None):
    out = os.path.join(work, "eval.json")
    cmd = [dynpm, "eval", original, "--dpm", model, "--ratios", ratios, "--steps", "every:1",
           "--json", out, "--quiet"]
    if variant is not None:
        cmd += ["--variant", str(variant)]
    run(cmd)
    with open(out) as f:
        result = json.load(f)
    diagonal = result["model_diagonal"]
    return {r["ratio_pct"]: r["max"]["hausdorff_pct"] * diagonal / 100 for r in result["ratios"]}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--dynpm", required=True)
    ap.add_argument("--ratios", default="5,25")
    ap.add_argument("--json")
    ap.add_argument("inputs", nargs="+")
    a = ap.parse_args()
    if len(a.inputs) < 2:
        sys.exit("needs two inputs or more")
    with tempfile.TemporaryDirectory(prefix="dynpm-family-") as work:
        family = os.path.join(work, "family.dpm")
        run([a.dynpm, "build", "--family", *a.inputs, "-o", family, "--quiet", "--no-thumbnail"])
        separate = []
        for k, path in enumerate(a.inputs):
            out = os.path.join(work, f"v{k}.dpm")
            run([a.dynpm, "build", path, "-o", out, "--quiet", "--no-thumbnail"])
            separate.append(out)
        run([a.dynpm, "convert", a.inputs[0], "-o", os.path.join(work, "s_{:03d}.ply"), "--quiet"])
        step0 = os.path.join(work, "step0.dpm")
        run([a.dynpm, "build", os.path.join(work, "s_000.ply"), "-o", step0, "--quiet", "--no-thumbnail"])
        size = {"family": os.path.getsize(family), "step0_alone": os.path.getsize(step0),
                "separate": [os.path.getsize(p) for p in separate]}
        total = sum(size["separate"])
        shared = total - (len(a.inputs) - 1) * size["step0_alone"]
        print(f"family {size['family']} bytes; separate {' + '.join(map(str, size['separate']))}"
              f" = {total} ({size['family'] / total:.3f}x); step 0 alone {size['step0_alone']};"
              f" separate - shared step 0 = {shared} ({size['family'] / shared:.3f}x, target"
              f" <= 1.05x)")
        rows = []
        for k, path in enumerate(a.inputs):
            fam = hausdorff(a.dynpm, path, family, a.ratios, work, variant=k)
            own = hausdorff(a.dynpm, path, separate[k], a.ratios, work)
            for ratio in sorted(own):
                ratio_of = fam[ratio] / own[ratio] if own[ratio] > 0 else float("nan")
                rows.append({"variant": k, "input": os.path.basename(path), "ratio_pct": ratio,
                             "family": fam[ratio], "separate": own[ratio], "ratio": ratio_of})
                print(f"variant {k} {os.path.basename(path)} at {ratio:g} %: Hausdorff "
                      f"{fam[ratio]:.4g} (family) vs {own[ratio]:.4g} (separate): "
                      f"{ratio_of:.3f}x (target <= 1.10x)")
        if a.json:
            with open(a.json, "w") as f:
                json.dump({"size": size, "hausdorff": rows}, f, indent=1)


if __name__ == "__main__":
    main()
