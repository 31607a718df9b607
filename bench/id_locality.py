#!/usr/bin/python3
"""How local is a mesher's numbering? (issue 19: the original vertex and face indices are the
largest part of a .dpm's split attributes, about 1 B each per vertex.)

  bench/id_locality.py MESH.obj [MESH.obj …]

Each OBJ is a full FE mesh in its input order (vertex i = the i-th node, faces in element
order, as ../shared/data/*/obj/frame_000.obj). For vertices (over the mesh's edges) and for
faces (over pairs sharing an edge) it prints:
  ±1        the share of adjacent pairs whose indices differ by one;
  50 % / 80 %   how many distinct |differences| cover that share of the pairs (a structured
            patch needs two: 1 and the row width);
  walk      the share of i whose successor i + 1 is adjacent to it (a numbering that walks the
            mesh);
  floor     the mean over items of log2(2|d| + 1) bits, d the difference to the nearest-numbered
            adjacent item of the complete mesh: what an oracle that knew the final neighbours,
            and which of them to use, would still pay (a split knows only its coarse neighbours).
Compare with `tests/split_records_dump`'s "vertex index" and "face index" (B per vertex).
"""
import collections
import math
import sys


def load_obj(path):
    vertex_count, faces = 0, []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                vertex_count += 1
            elif line.startswith("f "):
                faces.append([int(c.split("/")[0]) - 1 for c in line.split()[1:]])
    return vertex_count, faces


def locality(count, pairs):
    """pairs: adjacent (a, b) index pairs, each once."""
    neighbours = [set() for _ in range(count)]
    for a, b in pairs:
        neighbours[a].add(b)
        neighbours[b].add(a)
    gaps = collections.Counter(abs(a - b) for a, b in pairs)
    total = sum(gaps.values())
    covered, distinct, cover = 0, 0, {}
    for _, n in gaps.most_common():
        covered += n
        distinct += 1
        for share in (0.5, 0.8):
            if share not in cover and covered >= share * total:
                cover[share] = distinct
    walk = sum(i + 1 in neighbours[i] for i in range(count - 1)) / max(1, count - 1)
    floor = [math.log2(2 * min(abs(j - i) for j in neighbours[i]) + 1)
             for i in range(count) if neighbours[i]]
    return (f"±1 {gaps[1] / total:.3f}, 50 % / 80 % in {cover[0.5]} / {cover[0.8]} "
            f"differences, walk {walk:.3f}, floor {sum(floor) / len(floor):.2f} bits")


def main(paths):
    for path in paths:
        vertex_count, faces = load_obj(path)
        edges, edge_faces = set(), collections.defaultdict(list)
        for f, corners in enumerate(faces):
            for k, a in enumerate(corners):
                b = corners[(k + 1) % len(corners)]
                edge = (min(a, b), max(a, b))
                edges.add(edge)
                edge_faces[edge].append(f)
        face_pairs = {(min(fs[i], fs[j]), max(fs[i], fs[j]))
                      for fs in edge_faces.values() for i in range(len(fs))
                      for j in range(i + 1, len(fs))}
        print(f"{path}: {vertex_count} vertices, {len(faces)} faces")
        print(f"  vertices: {locality(vertex_count, edges)}")
        print(f"  faces:    {locality(len(faces), face_pairs)}")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    main(sys.argv[1:])
