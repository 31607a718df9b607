#!/usr/bin/env python3
"""The paper's Tables 2 and 3 (Wundrak et al. 2006, §5) on CalculiX animations, with dynpm.

Table 2 form: the two-sided Hausdorff distance (% of the original's bounding-box diagonal) of
the animation simplified to 1, 2, 4 and 11 % of its vertices, at the first, middle and last
step and the max over all steps (key steps: all).
Table 3 form: the mean over all steps of that distance at 1, 4 and 6 % of the vertices for
key steps all, paper (first, last, strongest in between), first only, strongest only, auto:3,
with the simplification time of each.

    python3 scripts/paper_tables.py [--dynpm build/release/cli/dynpm] [--allow-stale]
        FOLDER...   (each holding frame_*.obj)

Refuses to run a binary older than the project's sources (unless --allow-stale).

Standard library only. Prints markdown; every number comes from `dynpm simplify --json` and
`dynpm hausdorff --json` run here.
"""
import argparse
import glob
import json
import os
import subprocess
import sys
import tempfile


ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def stale_sources(binary):
    """The project's C++ sources edited after `binary` was linked: tables from an old binary
    would be reported as today's code."""
    built = os.path.getmtime(binary)
    newer = []
    for folder in ("src", "include", "cli"):
        for base, _, files in os.walk(os.path.join(ROOT, folder)):
            newer += [os.path.relpath(os.path.join(base, f), ROOT) for f in files
                      if f.endswith((".cpp", ".h")) and os.path.getmtime(os.path.join(base, f)) > built]
    return sorted(newer)


def run_json(command):
    out = subprocess.run(command, check=True, capture_output=True, text=True).stdout
    return json.loads(out[out.index("{"):])


def simplify(dynpm, frames, ratio, key_steps, out_dir):
    pattern = os.path.join(out_dir, "s_{:03d}.obj")
    for old in glob.glob(os.path.join(out_dir, "s_*.obj")):
        os.remove(old)
    result = run_json([dynpm, "simplify", frames, "--ratio", str(ratio), "--key-steps", key_steps,
                       "-o", pattern, "--json"])
    return result, os.path.join(out_dir, "s_*.obj")


def hausdorff_per_step(dynpm, frames, simplified):
    result = run_json([dynpm, "hausdorff", frames, simplified, "--json"])
    return result["per_step"]["hausdorff_pct"]


def strongest_step(folder, steps):
    """The step with the largest displacement, from times.csv (max_disp) when present."""
    path = os.path.join(folder, "times.csv")
    if not os.path.exists(path):
        return steps - 1
    rows = [line.strip().split(",") for line in open(path) if line.strip()]
    header, rows = rows[0], rows[1:]
    column = header.index("max_disp")
    return max(range(len(rows)), key=lambda i: float(rows[i][column]))


def table2(dynpm, folder, work):
    frames = os.path.join(folder, "frame_*.obj")
    lines = ["| % of vertices | vertices | t0 [%] | t{m} [%] | t{l} [%] | max over steps [%] |",
             "|---:|---:|---:|---:|---:|---:|"]
    for ratio in (0.01, 0.02, 0.04, 0.11):
        result, simplified = simplify(dynpm, frames, ratio, "all", work)
        per_step = hausdorff_per_step(dynpm, frames, simplified)
        m, last = len(per_step) // 2, len(per_step) - 1
        if lines[0].count("{m}"):
            lines[0] = lines[0].replace("{m}", str(m)).replace("{l}", str(last))
        lines.append(f"| {ratio * 100:g}% | {result['vertices_out']} | {per_step[0]:.3f} | "
                     f"{per_step[m]:.3f} | {per_step[last]:.3f} | {max(per_step):.3f} |")
    return lines


def table3(dynpm, folder, work):
    frames = os.path.join(folder, "frame_*.obj")
    steps = len(glob.glob(frames))
    strongest = strongest_step(folder, steps)
    rules = [("all", "all"), ("paper", "paper"), ("first only", "0"),
             (f"strongest only (t{strongest})", str(strongest)), ("auto:3", "auto:3")]
    lines = ["| key steps | chosen | 1% | 4% | 6% | time 1% [s] | time 4% [s] | time 6% [s] |",
             "|---|---|---:|---:|---:|---:|---:|---:|"]
    for name, rule in rules:
        errors, times, chosen = [], [], ""
        for ratio in (0.01, 0.04, 0.06):
            result, simplified = simplify(dynpm, frames, ratio, rule, work)
            per_step = hausdorff_per_step(dynpm, frames, simplified)
            errors.append(sum(per_step) / len(per_step))
            times.append(result["seconds"])
            chosen = ",".join(str(k) for k in result["key_steps"]) if len(result["key_steps"]) < steps else f"all {steps}"
        lines.append(f"| {name} | {chosen} | " + " | ".join(f"{e:.3f}" for e in errors) + " | " +
                     " | ".join(f"{t:.3f}" for t in times) + " |")
    return lines


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("folders", nargs="+")
    parser.add_argument("--dynpm", default="build/release/cli/dynpm")
    parser.add_argument("--allow-stale", action="store_true",
                        help="run even if sources are newer than the dynpm binary")
    args = parser.parse_args()
    if not os.path.isfile(args.dynpm):
        sys.exit(f"paper_tables.py: {args.dynpm}: no such binary (./dynpm.sh build makes it)")
    newer = stale_sources(args.dynpm)
    if newer and not args.allow_stale:
        sys.exit(f"paper_tables.py: {args.dynpm} is older than {len(newer)} source file(s), e.g. "
                 f"{newer[0]}; rebuild it (./dynpm.sh build) or pass --allow-stale")
    with tempfile.TemporaryDirectory() as work:
        for folder in args.folders:
            name = os.path.basename(os.path.dirname(os.path.abspath(folder.rstrip("/"))))
            steps = len(glob.glob(os.path.join(folder, "frame_*.obj")))
            print(f"### {name} ({steps} steps)\n")
            print("Table 2 form (key steps: all):\n")
            print("\n".join(table2(args.dynpm, folder, work)) + "\n")
            print("Table 3 form (mean over all steps):\n")
            print("\n".join(table3(args.dynpm, folder, work)) + "\n")
            sys.stdout.flush()


if __name__ == "__main__":
    main()
