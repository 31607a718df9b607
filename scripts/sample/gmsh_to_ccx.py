#!/usr/bin/env python3
"""Turn gmsh's Abaqus-style .inp export of rail.geo into a CalculiX mesh include.

Standard library only.  Keeps the 2-D surface elements (gmsh writes them as
CPS3/CPS4) and writes them as shell elements S3/S4, numbered 1..N in gmsh's
order; drops the T3D2 line elements gmsh writes for the physical curves; keeps
the node sets ROOT and TIP.  All shells are re-oriented so that neighbouring
elements agree (every interior edge is walked in opposite directions by its two
elements) and the normal of the hat top points to +y.

usage: gmsh_to_ccx.py GMSH.inp OUT_MESH.inp
"""
import sys
from collections import deque

SHELL_TYPES = {"CPS3": "S3", "CPS4": "S4", "S3": "S3", "S4": "S4",
               "CPE3": "S3", "CPE4": "S4", "S3R": "S3", "S4R": "S4"}
SKIP_TYPES = {"T3D2", "T2D2", "B31", "B21"}


def die(msg):
    sys.exit("gmsh_to_ccx.py: error: " + msg)


def keyword_params(line):
    parts = [p.strip() for p in line.split(",")]
    params = {}
    for p in parts[1:]:
        if "=" in p:
            k, v = p.split("=", 1)
            params[k.strip().upper()] = v.strip()
        elif p:
            params[p.upper()] = ""
    return parts[0].upper(), params


def read_gmsh_inp(path):
    nodes, elems, nsets = {}, [], {}
    mode, etype, setname = None, None, None
    with open(path) as f:
        for lineno, raw in enumerate(f, 1):
            line = raw.strip()
            if not line or line.startswith("**"):
                continue
            if line.startswith("*"):
                kw, params = keyword_params(line)
                mode = None
                if kw == "*NODE":
                    mode = "node"
                elif kw == "*ELEMENT":
                    t = params.get("TYPE", "").upper()
                    if t in SHELL_TYPES:
                        mode, etype = "elem", SHELL_TYPES[t]
                    elif t in SKIP_TYPES:
                        mode = "skip"
                    else:
                        die("%s:%d: unsupported element type %r" % (path, lineno, t))
                elif kw == "*NSET":
                    setname = params.get("NSET", "").upper()
                    if not setname:
                        die("%s:%d: *NSET without NSET=" % (path, lineno))
                    mode = "nset"
                    nsets.setdefault(setname, [])
                continue
            try:
                vals = [v for v in line.replace(",", " ").split()]
                if mode == "node":
                    if len(vals) < 4:
                        raise ValueError("node line needs id, x, y, z")
                    nodes[int(vals[0])] = tuple(float(v) for v in vals[1:4])
                elif mode == "elem":
                    ids = [int(v) for v in vals]
                    need = 4 if etype == "S3" else 5
                    if len(ids) != need:
                        raise ValueError("%s element needs %d numbers" % (etype, need))
                    elems.append((etype, ids[1:]))
                elif mode == "nset":
                    nsets[setname].extend(int(v) for v in vals)
            except ValueError as e:
                die("%s:%d: %s: %r" % (path, lineno, e, line))
    return nodes, elems, nsets


def orient(nodes, elems):
    """Flip elements so that shared edges are walked in opposite directions."""
    edge_users = {}
    for i, (_, conn) in enumerate(elems):
        n = len(conn)
        for k in range(n):
            a, b = conn[k], conn[(k + 1) % n]
            edge_users.setdefault((min(a, b), max(a, b)), []).append(i)
    for e, users in edge_users.items():
        if len(users) > 2:
            die("non-manifold edge %s used by %d elements" % (e, len(users)))

    def directed(conn):
        n = len(conn)
        return {(conn[k], conn[(k + 1) % n]) for k in range(n)}

    conns = [list(c) for _, c in elems]
    done = [False] * len(elems)
    components = 0
    for seed in range(len(elems)):
        if done[seed]:
            continue
        components += 1
        done[seed] = True
        queue = deque([seed])
        while queue:
            i = queue.popleft()
            d = directed(conns[i])
            n = len(conns[i])
            for k in range(n):
                a, b = conns[i][k], conns[i][(k + 1) % n]
                for j in edge_users[(min(a, b), max(a, b))]:
                    if j == i:
                        continue
                    same = (a, b) in directed(conns[j])
                    if not done[j]:
                        if same:
                            conns[j] = conns[j][::-1]
                        done[j] = True
                        queue.append(j)
                    elif same:
                        die("mesh is not orientable (element %d vs %d)" % (i + 1, j + 1))
    if components != 1:
        die("expected one connected shell, found %d pieces" % components)

    # global sign: the element with the highest centroid (on the hat top)
    # should have its normal pointing to +y
    def centroid_y(c):
        return sum(nodes[n][1] for n in c) / len(c)
    top = max(range(len(conns)), key=lambda i: centroid_y(conns[i]))
    p = [nodes[n] for n in conns[top]]
    u = [p[1][k] - p[0][k] for k in range(3)]
    v = [p[2][k] - p[0][k] for k in range(3)]
    ny = u[2] * v[0] - u[0] * v[2]
    if ny < 0:
        conns = [c[::-1] for c in conns]
    return [(t, c) for (t, _), c in zip(elems, conns)]


def write(path, nodes, elems, nsets):
    used = sorted({n for _, c in elems for n in c})
    missing = [n for n in used if n not in nodes]
    if missing:
        die("elements use undefined nodes, e.g. %d" % missing[0])
    for name in ("ROOT", "TIP"):
        if not nsets.get(name):
            die("node set %s missing or empty (physical curve in rail.geo?)" % name)
    usedset = set(used)
    with open(path, "w") as f:
        f.write("** shell mesh of rail.geo, written by gmsh_to_ccx.py\n")
        f.write("** %d nodes, %d S4, %d S3\n" % (
            len(used), sum(t == "S4" for t, _ in elems), sum(t == "S3" for t, _ in elems)))
        f.write("*NODE, NSET=NALL\n")
        for n in used:
            x, y, z = nodes[n]
            f.write("%d, %.9g, %.9g, %.9g\n" % (n, x, y, z))
        # one *ELEMENT block per run of equal type, numbering 1..N in gmsh order
        eid, k = 0, 0
        while k < len(elems):
            t = elems[k][0]
            name = "EQUAD" if t == "S4" else "ETRI"
            f.write("*ELEMENT, TYPE=%s, ELSET=%s\n" % (t, name))
            while k < len(elems) and elems[k][0] == t:
                eid += 1
                f.write("%d, %s\n" % (eid, ", ".join(str(n) for n in elems[k][1])))
                k += 1
        f.write("*ELSET, ELSET=EALL\nEQUAD, ETRI\n")
        for name in ("ROOT", "TIP"):
            ids = sorted(set(nsets[name]) & usedset)
            f.write("*NSET, NSET=%s\n" % name)
            for i in range(0, len(ids), 10):
                f.write(", ".join(str(n) for n in ids[i:i + 10]) + "\n")
    return len(used)


def main(argv):
    if len(argv) != 3:
        sys.exit(__doc__.strip().splitlines()[-1])
    nodes, elems, nsets = read_gmsh_inp(argv[1])
    if not elems:
        die("no CPS3/CPS4 surface elements in %s" % argv[1])
    if not any(t == "S3" for t, _ in elems):
        die("no triangles: the free-meshed patch in rail.geo is missing")
    elems = orient(nodes, elems)
    nn = write(argv[2], nodes, elems, nsets)
    print("gmsh_to_ccx.py: %d nodes, %d S4, %d S3 -> %s" % (
        nn, sum(t == "S4" for t, _ in elems), sum(t == "S3" for t, _ in elems), argv[2]))


if __name__ == "__main__":
    main(sys.argv)
