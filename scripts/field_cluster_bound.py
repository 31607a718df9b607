#!/usr/bin/env python3
"""How small the per-node field error of a level can be, from the field alone (docs/simplify.md,
"The jump allowance"): a level with k vertices groups the original nodes into k connected
clusters (a vertex stands for the nodes collapsed into it), and with the max aggregate each
cluster's nodes are shown its largest value, so the per-node error is at least each cluster's
range (largest − smallest value, over every step, since one hierarchy serves all steps).

Two numbers per field and ratio, in % of the field's range over the steps:
- the bottleneck: the largest edge difference that must be merged to reach k clusters (Kruskal,
  an edge weighing its largest difference over the steps) — no grouping does better;
- greedy: the largest cluster range of a grouping made by merging, always, the two neighbouring
  clusters whose union has the smallest range — a grouping that exists, so a level whose node
  error is this is possible as far as the field is concerned (the geometry is not looked at).
The geometry-only build's per-node error is in docs/eval.md.

    python3 scripts/field_cluster_bound.py box.frd [--ratios 5,25]

Standard library only.
"""
import argparse
import heapq
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from field_edge_jumps import read_frd  # noqa: E402


def scaled_steps(blocks, names, nodes):
    """Per node, its values over the steps of every named field, in % of each field's range."""
    per_node = {n: [] for n in nodes}
    for name in names:
        steps = [v for n, v in blocks if n == name]
        lo = min(min(v.values()) for v in steps); hi = max(max(v.values()) for v in steps)
        for v in steps:
            for n in nodes: per_node[n].append((v[n] - lo) / (hi - lo) * 100)
    return per_node


def bottleneck(edges, values, nodes, k):
    weight = lambda a, b: max(abs(x - y) for x, y in zip(values[a], values[b]))
    parent = {n: n for n in nodes}
    def root(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]; x = parent[x]
        return x
    clusters, worst = len(nodes), 0.0
    for w, a, b in sorted((weight(a, b), a, b) for a, b in edges):
        if clusters <= k: break
        ra, rb = root(a), root(b)
        if ra != rb: parent[ra] = rb; clusters -= 1; worst = w
    return worst


def greedy(edges, values, nodes, k):
    lo = {n: list(values[n]) for n in nodes}; hi = {n: list(values[n]) for n in nodes}
    near = {n: set() for n in nodes}
    for a, b in edges: near[a].add(b); near[b].add(a)
    union = lambda a, b: max(max(h1, h2) - min(l1, l2) for l1, h1, l2, h2 in zip(lo[a], hi[a], lo[b], hi[b]))
    heap = [(union(a, b), a, b) for a, b in edges]; heapq.heapify(heap)
    alive, worst = set(nodes), 0.0
    while len(alive) > k and heap:
        c, a, b = heapq.heappop(heap)
        if a not in alive or b not in alive: continue
        if c != union(a, b): heapq.heappush(heap, (union(a, b), a, b)); continue  # stale
        worst = max(worst, c)
        lo[a] = [min(x, y) for x, y in zip(lo[a], lo[b])]; hi[a] = [max(x, y) for x, y in zip(hi[a], hi[b])]
        alive.discard(b)
        for x in near.pop(b):
            if x != a: near[x].discard(b); near[x].add(a); near[a].add(x)
        near[a].discard(b)
        for x in near[a]: heapq.heappush(heap, (union(a, x), a, x))
    return worst


def main():
    p = argparse.ArgumentParser()
    p.add_argument("frd")
    p.add_argument("--ratios", default="5,25")
    a = p.parse_args()
    edges, blocks = read_frd(a.frd)
    nodes = sorted({n for e in edges for n in e})
    print("| fields | ratio | clusters | bottleneck % | greedy grouping % |")
    print("|---|---|---:|---:|---:|")
    for names in (("S_MISES",), ("PEEQ",), ("S_MISES", "PEEQ")):
        values = scaled_steps(blocks, names, nodes)
        for r in (float(x) for x in a.ratios.split(",")):
            k = max(1, round(r / 100 * len(nodes)))
            print("| %s | %g %% | %d | %.1f | %.1f |" % (" + ".join(names), r, k,
                  bottleneck(edges, values, nodes, k), greedy(edges, values, nodes, k)))


if __name__ == "__main__":
    main()
