#!/usr/bin/env python3
"""Where a CalculiX shell model's surface passes through itself, per step (docs/eval.md, "The
crash box's floor: sheets through each other").

Step 0 is the undeformed mesh, step k the node coordinates plus the k-th DISP block, as
`dynpm` reads an .frd. Every shell element is split into triangles (a quad into the four
triangles through its centroid, as `eval` samples it); two elements that share no node
intersect when an edge of a triangle of one crosses a triangle of the other. Coplanar
overlaps are not counted (a crash run's sheets are not exactly coplanar). Prints, per step,
the number of intersecting element pairs and the box around them, and with --json the pairs'
midpoints, so that `eval`'s `field_error_at` can be compared against them:

    python3 scripts/self_intersections.py box.frd [--json out.json] [--steps 12,13,14]

Standard library only (a uniform grid as the broad phase).
"""
import argparse
import json
import math
import sys


def read_frd(path):
    """(coords {node: (x,y,z)}, elements [node list], displacements [{node: (dx,dy,dz)}])."""
    coords = {}; elements = []; disps = []
    with open(path) as f:
        lines = f.read().split("\n")
    i = 0
    while i < len(lines):
        l = lines[i]
        if l.startswith("    2C"):
            i += 1
            while not lines[i].startswith(" -3"):
                s = lines[i]
                if s.startswith(" -1"):
                    coords[int(s[3:13])] = (float(s[13:25]), float(s[25:37]), float(s[37:49]))
                i += 1
        elif l.startswith("    3C"):
            i += 1
            while not lines[i].startswith(" -3"):
                if lines[i].startswith(" -2"):
                    elements.append([int(x) for x in lines[i][3:].split()])
                i += 1
        elif l.startswith(" -4  DISP"):
            d = {}; i += 1
            while not lines[i].startswith(" -3"):
                s = lines[i]
                if s.startswith(" -1"):
                    d[int(s[3:13])] = (float(s[13:25]), float(s[25:37]), float(s[37:49]))
                i += 1
            disps.append(d)
        i += 1
    return coords, elements, disps


def sub(a, b): return (a[0] - b[0], a[1] - b[1], a[2] - b[2])
def cross(a, b): return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
def dot(a, b): return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def segment_hits_triangle(p, q, a, b, c):
    """Whether the closed segment pq crosses triangle abc (not coplanar), by signed volumes."""
    n = cross(sub(b, a), sub(c, a))
    dp, dq = dot(sub(p, a), n), dot(sub(q, a), n)
    if (dp > 0 and dq > 0) or (dp < 0 and dq < 0) or (dp == 0 and dq == 0):
        return False
    d = sub(q, p)
    s1 = dot(d, cross(sub(a, p), sub(b, p)))
    s2 = dot(d, cross(sub(b, p), sub(c, p)))
    s3 = dot(d, cross(sub(c, p), sub(a, p)))
    return (s1 >= 0 and s2 >= 0 and s3 >= 0) or (s1 <= 0 and s2 <= 0 and s3 <= 0)


def triangles_intersect(t, u):
    for x, y in ((0, 1), (1, 2), (2, 0)):
        if segment_hits_triangle(t[x], t[y], *u) or segment_hits_triangle(u[x], u[y], *t):
            return True
    return False


def element_triangles(pos, nodes):
    ps = [pos[n] for n in nodes]
    if len(ps) == 3:
        return [tuple(ps)]
    c = tuple(sum(p[k] for p in ps) / len(ps) for k in range(3))
    return [(ps[j], ps[(j + 1) % len(ps)], c) for j in range(len(ps))]


def intersecting_pairs(pos, elements):
    tris = [element_triangles(pos, e) for e in elements]
    boxes = []
    for ts in tris:
        pts = [p for t in ts for p in t]
        boxes.append((tuple(min(p[k] for p in pts) for k in range(3)), tuple(max(p[k] for p in pts) for k in range(3))))
    cell = 2.0 * sum(hi[0] - lo[0] + hi[1] - lo[1] + hi[2] - lo[2] for lo, hi in boxes) / (3 * len(boxes))
    grid = {}
    for e, (lo, hi) in enumerate(boxes):
        r = [range(math.floor(lo[k] / cell), math.floor(hi[k] / cell) + 1) for k in range(3)]
        for i in r[0]:
            for j in r[1]:
                for k in r[2]:
                    grid.setdefault((i, j, k), []).append(e)
    node_sets = [set(e) for e in elements]
    seen = set(); pairs = []
    for members in grid.values():
        for x in range(len(members)):
            a = members[x]
            for b in members[x + 1:]:
                key = (a, b) if a < b else (b, a)
                if key in seen:
                    continue
                seen.add(key)
                la, ha = boxes[a]; lb, hb = boxes[b]
                if any(ha[k] < lb[k] or hb[k] < la[k] for k in range(3)) or node_sets[a] & node_sets[b]:
                    continue
                if any(triangles_intersect(t, u) for t in tris[a] for u in tris[b]):
                    pairs.append(key)
    return pairs


def main():
    p = argparse.ArgumentParser()
    p.add_argument("frd")
    p.add_argument("--steps", help="comma-separated steps (default: every step)")
    p.add_argument("--json", help="write {step: [[x,y,z] midpoint of each intersecting pair]}")
    a = p.parse_args()
    coords, elements, disps = read_frd(a.frd)
    n_steps = 1 + len(disps)
    steps = [int(s) for s in a.steps.split(",")] if a.steps else range(n_steps)
    out = {}
    for t in steps:
        if t >= n_steps:
            sys.exit("%s: no step %d (%d steps)" % (a.frd, t, n_steps))
        d = disps[t - 1] if t > 0 else {}
        pos = {n: tuple(c[k] + d.get(n, (0, 0, 0))[k] for k in range(3)) for n, c in coords.items()}
        pairs = intersecting_pairs(pos, elements)
        mids = []
        for a_, b_ in pairs:
            ns = elements[a_] + elements[b_]
            mids.append([sum(pos[n][k] for n in ns) / len(ns) for k in range(3)])
        out[t] = mids
        if mids:
            lo = [min(m[k] for m in mids) for k in range(3)]; hi = [max(m[k] for m in mids) for k in range(3)]
            where = "x %.1f..%.1f, y %.1f..%.1f, z %.1f..%.1f" % (lo[0], hi[0], lo[1], hi[1], lo[2], hi[2])
        else:
            where = "-"
        print("step %2d: %4d intersecting element pairs, %4d elements; %s" % (
            t, len(pairs), len({e for pr in pairs for e in pr}), where), flush=True)
    if a.json:
        with open(a.json, "w") as f:
            json.dump(out, f)


if __name__ == "__main__":
    main()
