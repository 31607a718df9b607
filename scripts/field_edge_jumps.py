#!/usr/bin/env python3
"""The largest difference of S_MISES and PEEQ across one mesh edge of a CalculiX .frd (ASCII), per
step, in % of the field's range over the steps (docs/eval.md, "What the field error is made of").
A half-edge collapse merges two neighbours, so at a level where such an edge is gone the per-node
error is at least this. Standard library only.

    python3 scripts/field_edge_jumps.py box.frd
"""
import math
import sys


def read_frd(path):
    """(edges, blocks): the element edges as sorted node pairs, and per result block in file order
    (name, {node: value}) for S_MISES (from the stress tensor) and PEEQ."""
    lines = open(path).read().split("\n")
    edges = set(); blocks = []; i = 0
    while i < len(lines):
        l = lines[i]
        if l.startswith("    3C"):
            i += 1
            while not lines[i].startswith(" -3"):
                if lines[i].startswith(" -2"):
                    ns = [int(x) for x in lines[i][3:].split()]
                    for a, b in zip(ns, ns[1:] + ns[:1]): edges.add((min(a, b), max(a, b)))
                i += 1
        elif l.startswith(" -4  STRESS") or l.startswith(" -4  PE"):
            name = "S_MISES" if "STRESS" in l else "PEEQ"
            vals = {}; i += 1
            while not lines[i].startswith(" -3"):
                s = lines[i]
                if s.startswith(" -1"):
                    nid = int(s[3:13]); v = [float(s[13 + 12 * k: 25 + 12 * k]) for k in range((len(s) - 13) // 12)]
                    if name == "PEEQ": vals[nid] = v[0]
                    else:
                        sx, sy, sz, sxy, syz, szx = v[:6]
                        vals[nid] = math.sqrt(0.5 * ((sx - sy) ** 2 + (sy - sz) ** 2 + (sz - sx) ** 2) + 3 * (sxy ** 2 + syz ** 2 + szx ** 2))
                i += 1
            blocks.append((name, vals))
        i += 1
    return edges, blocks


def main():
    edges, blocks = read_frd(sys.argv[1])
    for name in ("S_MISES", "PEEQ"):
        steps = [v for n, v in blocks if n == name]
        lo = min(min(v.values()) for v in steps); hi = max(max(v.values()) for v in steps)
        worst = [max(abs(v[a] - v[b]) for a, b in edges) / (hi - lo) * 100 for v in steps]
        print(name, "range %.4g..%.4g" % (lo, hi), "largest difference across an edge, %% of range, per step: %s; max %.1f" % (" ".join("%.0f" % w for w in worst), max(worst)))


if __name__ == "__main__":
    main()
