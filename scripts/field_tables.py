#!/usr/bin/env python3
"""Result fields through the level of detail, measured (docs/RESULTS.md, issue 18's tables).

For each input and field: `dynpm build` with fields in the cost (the default) and with
`--field-weight 0` (geometry only), then `dynpm eval --field` of both at 5 % and 25 % of the
vertices over every step: the field error (% of the field's range; facing, the default, and
beside it the closest point alone and the per-node measure, docs/eval.md), the peak ratio and the
peak gap (how far the largest |value| shown is below the original's, % of the range; the
stored bound is 0.1 %), and the two-sided Hausdorff distance (% of the diagonal). Where the
original passes through itself at some steps, also the field error's max over the other steps.

    python3 scripts/field_tables.py --dynpm build/release/cli/dynpm INPUT:FIELD[,FIELD]...

--with "ARGS" builds the with-fields side with those build flags (e.g. "--field-cost
quadric,scale --field-weight 30"), to compare the field term's forms.

Standard library only. Prints markdown; every number comes from the dynpm runs made here.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

RATIOS = (5, 25)


def run(cmd):
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit("failed: %s\n%s" % (" ".join(cmd), r.stderr))
    return r.stdout


def measure(dynpm, source, fields, weight, work, extra=()):
    """eval's JSON of one build: {ratio: row} with every step's cells."""
    dpm = os.path.join(work, "w%s.dpm" % weight)
    cmd = [dynpm, "build", source, "-o", dpm] + list(extra)
    if weight is not None:
        cmd += ["--field-weight", str(weight)]
    run(cmd)
    out = os.path.join(work, "w%s.json" % weight)
    info = json.loads(run([dynpm, "info", source, "--json"]))
    steps = ",".join(str(t) for t in range(info["steps"]))
    run([dynpm, "eval", source, "--dpm", dpm, "--ratios", ",".join(map(str, RATIOS)),
         "--field", ",".join(fields), "--steps", steps, "--json", out])
    with open(out) as f:
        table = json.load(f)
    return {row["ratio_pct"]: row for row in table["ratios"]}, table.get("self_crossings", [])


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--dynpm", default="build/release/cli/dynpm")
    p.add_argument("--with", dest="with_args", default="",
                   help="build flags of the with-fields side (default: none, the defaults)")
    p.add_argument("inputs", nargs="+", help="INPUT:FIELD[,FIELD]")
    a = p.parse_args()
    for spec in a.inputs:
        source, fields = spec.rsplit(":", 1)
        fields = fields.split(",")
        with tempfile.TemporaryDirectory() as work:
            with_fields, crossings = measure(a.dynpm, source, fields, None, work, a.with_args.split())
            geometry, _ = measure(a.dynpm, source, fields, 0, work)
        name = os.path.basename(source)
        print("\n#### %s\n" % name)
        print("| ratio | field | field error (facing), geometry only → with fields (max over steps) | ratio | "
              "closest point alone | ratio | per node | ratio | "
              "peak ratio (smallest) | peak gap % (largest) | Hausdorff %, geometry only → with fields |")
        print("|---|---|---|---|---|---|---|---|---|---|---|")
        for r in RATIOS:
            g, w = geometry[r]["max"], with_fields[r]["max"]
            for f in fields:
                pairs = []
                for key in ("field_error_pct", "field_error_nearest_pct", "field_error_node_pct"):
                    ge, we = g["fields"][f][key], w["fields"][f][key]
                    if ge is None or we is None:  # the per-node measure of an element field
                        pairs.append("– | –")
                    else:
                        pairs.append("%.3g → %.3g | %.2f" % (ge, we, we / ge if ge > 0 else 0))
                print("| %d %% | %s | %s | %.4f | %.3f | %.3g → %.3g (%+.0f %%) |" % (
                    r, f.replace("|", "\\|"), " | ".join(pairs), w["fields"][f]["peak_ratio"],
                    w["fields"][f]["peak_gap_pct"], g["hausdorff_pct"], w["hausdorff_pct"],
                    100 * (w["hausdorff_pct"] / g["hausdorff_pct"] - 1) if g["hausdorff_pct"] > 0 else 0))
        if crossings:
            print("\nThe original passes through itself at step %s (docs/eval.md, \"Sheets through each "
                  "other\"); the field error's max over the other steps, geometry only → with fields:\n"
                  % ", ".join("%d (%d faces)" % (c["step"], c["faces"]) for c in crossings))
            print("| ratio | field | field error (facing), untangled steps | ratio |")
            print("|---|---|---|---|")
            for r in RATIOS:
                for f in fields:
                    ge = geometry[r]["max"]["fields"][f]["field_error_untangled_pct"]
                    we = with_fields[r]["max"]["fields"][f]["field_error_untangled_pct"]
                    if ge is None or we is None:
                        print("| %d %% | %s | every step crosses | – |" % (r, f.replace("|", "\\|")))
                    else:
                        print("| %d %% | %s | %.3g → %.3g | %.2f |" % (r, f.replace("|", "\\|"), ge, we,
                                                                  we / ge if ge > 0 else 0))
        print("\nEvery step (field error %, geometry only → with fields; peak gap % with fields):\n")
        steps = [c["step"] for c in with_fields[RATIOS[0]]["steps"]]
        print("| field | ratio | " + " | ".join("t=%d" % t for t in steps) + " |")
        print("|---|---|" + "---|" * len(steps))
        for f in fields:
            for r in RATIOS:
                cells = []
                for cg, cw in zip(geometry[r]["steps"], with_fields[r]["steps"]):
                    cells.append("%.2g→%.2g (%.2f)" % (cg["fields"][f]["field_error_pct"],
                                                      cw["fields"][f]["field_error_pct"],
                                                      cw["fields"][f]["peak_gap_pct"]))
                print("| %s | %d %% | %s |" % (f.replace("|", "\\|"), r, " | ".join(cells)))


if __name__ == "__main__":
    main()
