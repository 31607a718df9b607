"""Mesh I/O and error measurement for bench/peers/format_bench.py (docs/peers.md).

Pure Python (no numpy): OBJ frames in and out, a glTF writer with one morph target per later
frame, a glTF/GLB reader that undoes KHR_mesh_quantization, and the max position error of a
decoded animation against the original frames (in units of the bounding-box diagonal over all
frames), with the decoded vertices matched to the original ones by position (peers reorder).
"""

import array
import base64
import json
import math
import struct


def read_obj(path, want_faces=True):
    """Positions [(x, y, z)] and faces [[i, ...]] (0-based) of an OBJ file."""
    verts, faces = [], []
    with open(path, encoding="utf-8", errors="replace") as f:
        for line in f:
            if line.startswith("v "):
                p = line.split()
                verts.append((float(p[1]), float(p[2]), float(p[3])))
            elif want_faces and line.startswith("f "):
                face = []
                for c in line.split()[1:]:
                    i = int(c.split("/")[0])
                    face.append(i - 1 if i > 0 else len(verts) + i)
                faces.append(face)
    return verts, faces


def write_obj(path, verts, faces):
    with open(path, "w") as f:
        f.writelines("v %.9g %.9g %.9g\n" % v for v in verts)
        f.writelines("f " + " ".join(str(i + 1) for i in face) + "\n" for face in faces)


def triangulate(verts, faces):
    """Triangles, quads split along their shorter diagonal as bench/peers/obj_io.h does."""
    def d2(a, b):
        return sum((verts[a][k] - verts[b][k]) ** 2 for k in range(3))

    tris = []
    for f in faces:
        if len(f) == 4:
            a, b, c, d = f
            if d2(a, c) <= d2(b, d):
                tris += [(a, b, c), (a, c, d)]
            else:
                tris += [(a, b, d), (b, c, d)]
        else:
            tris += [(f[0], f[k], f[k + 1]) for k in range(1, len(f) - 1)]
    return tris


def bbox_diagonal(frames):
    lo = [math.inf] * 3
    hi = [-math.inf] * 3
    for frame in frames:
        for v in frame:
            for k in range(3):
                lo[k] = min(lo[k], v[k])
                hi[k] = max(hi[k], v[k])
    return math.dist(lo, hi)


# ---------------------------------------------------------------- glTF with morph targets

def write_morph_gltf(path, frames, tris):
    """One mesh: frame 0 as POSITION, frame t > 0 as morph target t-1 (deltas), float32,
    uint32 indices; the buffer embedded as a data: URI (gltfpack reads it)."""
    base = frames[0]
    blobs, views, accessors = [], [], []

    def add(data, target, comp, count, kind, minmax=None):
        offset = sum(len(b) for b in blobs)
        blobs.append(data + b"\0" * (-len(data) % 4))
        views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(data)})
        if target:
            views[-1]["target"] = target
        acc = {"bufferView": len(views) - 1, "componentType": comp, "count": count, "type": kind}
        if minmax:
            acc["min"], acc["max"] = minmax
        accessors.append(acc)
        return len(accessors) - 1

    def vec3(vs):
        flat = array.array("f", (c for v in vs for c in v))
        f32 = [tuple(flat[3 * i:3 * i + 3]) for i in range(len(vs))]
        mm = ([min(v[k] for v in f32) for k in range(3)], [max(v[k] for v in f32) for k in range(3)])
        return flat.tobytes(), mm

    data, mm = vec3(base)
    pos = add(data, 34962, 5126, len(base), "VEC3", mm)
    idx = add(array.array("I", (i for t in tris for i in t)).tobytes(), 34963, 5125,
              3 * len(tris), "SCALAR")
    targets = []
    for frame in frames[1:]:
        data, mm = vec3([tuple(frame[i][k] - base[i][k] for k in range(3))
                         for i in range(len(base))])
        targets.append({"POSITION": add(data, 34962, 5126, len(base), "VEC3", mm)})
    buf = b"".join(blobs)
    prim = {"attributes": {"POSITION": pos}, "indices": idx, "mode": 4}
    if targets:
        prim["targets"] = targets
    doc = {
        "asset": {"version": "2.0", "generator": "dynpm bench/peers/format_io.py"},
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [prim], "weights": [0.0] * len(targets)}],
        "buffers": [{"byteLength": len(buf),
                     "uri": "data:application/octet-stream;base64," +
                            base64.b64encode(buf).decode()}],
        "bufferViews": views, "accessors": accessors,
    }
    with open(path, "w") as f:
        json.dump(doc, f)


_COMP = {5120: ("b", 127.0), 5121: ("B", 255.0), 5122: ("h", 32767.0), 5123: ("H", 65535.0),
         5125: ("I", None), 5126: ("f", None)}


def read_glb(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:4] != b"glTF":
        raise ValueError("%s: not a GLB file" % path)
    doc, binary, pos = None, b"", 12
    while pos < len(data):
        length, kind = struct.unpack_from("<II", data, pos)
        chunk = data[pos + 8:pos + 8 + length]
        if kind == 0x4E4F534A:
            doc = json.loads(chunk)
        elif kind == 0x004E4942:
            binary = chunk
        pos += 8 + length
    return doc, binary


def position_views(doc):
    """The bufferViews holding POSITION data (base and morph targets)."""
    views = set()
    for mesh in doc.get("meshes", []):
        for prim in mesh["primitives"]:
            for attrs in [prim["attributes"]] + prim.get("targets", []):
                if "POSITION" in attrs:
                    views.add(doc["accessors"][attrs["POSITION"]]["bufferView"])
    return sorted(views)


def view_bytes(doc, index):
    """Bytes a bufferView takes in the file (its compressed size under EXT_meshopt_compression)."""
    view = doc["bufferViews"][index]
    ext = view.get("extensions", {}).get("EXT_meshopt_compression")
    return ext["byteLength"] if ext else view["byteLength"]


def _accessor(doc, binary, index):
    acc = doc["accessors"][index]
    if "extensions" in doc.get("bufferViews", [{}])[acc["bufferView"]]:
        raise ValueError("compressed buffer view (decode with gltfpack -noq first)")
    view = doc["bufferViews"][acc["bufferView"]]
    code, norm = _COMP[acc["componentType"]]
    n = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}[acc["type"]]
    size = struct.calcsize("<" + code)
    stride = view.get("byteStride", n * size)
    base = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
    out = []
    for i in range(acc["count"]):
        vals = struct.unpack_from("<%d%s" % (n, code), binary, base + i * stride)
        if acc.get("normalized") and norm:
            vals = tuple(max(v / norm, -1.0) for v in vals)
        out.append(vals if n > 1 else vals[0])
    return out


def _node_transform(node):
    """(scale, translation) of a node: gltfpack's dequantization is a scale and a shift."""
    if "matrix" in node:
        m = node["matrix"]
        if any(abs(m[i]) > 0 for i in (1, 2, 3, 4, 6, 7, 8, 9, 11)) or m[15] != 1:
            raise ValueError("node matrix is not a scale + translation")
        return (m[0], m[5], m[10]), (m[12], m[13], m[14])
    if any(abs(r) > 1e-12 for r in node.get("rotation", [0, 0, 0, 1])[:3]):
        raise ValueError("node rotation is not supported")
    return tuple(node.get("scale", [1, 1, 1])), tuple(node.get("translation", [0, 0, 0]))


def read_morph_glb(path):
    """Frames [[(x, y, z)]] of every primitive's base + each morph target (all targets applied
    one at a time), vertices of all primitives concatenated in file order, node transforms
    applied. gltfpack keeps one node per mesh here."""
    doc, binary = read_glb(path)
    nodes = doc.get("nodes", [])
    parent = {c: i for i, n in enumerate(nodes) for c in n.get("children", [])}
    frames = None
    for index, node in enumerate(nodes):
        if "mesh" not in node:
            continue
        s, t = _node_transform(node)
        up = index
        while up in parent:  # world = parent's scale and shift after the node's own
            up = parent[up]
            ps, pt = _node_transform(nodes[up])
            s = tuple(ps[k] * s[k] for k in range(3))
            t = tuple(ps[k] * t[k] + pt[k] for k in range(3))
        for prim in doc["meshes"][node["mesh"]]["primitives"]:
            base = _accessor(doc, binary, prim["attributes"]["POSITION"])
            deltas = [_accessor(doc, binary, tg["POSITION"]) for tg in prim.get("targets", [])]
            cur = [base] + [[tuple(b[k] + d[k] for k in range(3)) for b, d in zip(base, dl)]
                            for dl in deltas]
            cur = [[tuple(v[k] * s[k] + t[k] for k in range(3)) for v in f] for f in cur]
            frames = cur if frames is None else [a + b for a, b in zip(frames, cur)]
    if frames is None:
        raise ValueError("%s: no mesh" % path)
    return frames


# ---------------------------------------------------------------- error measurement

def max_error(original, decoded, same_order_every_frame, same_index=False):
    """Largest distance between a decoded vertex and its original, over all frames, divided by
    the diagonal of the original's bounding box over all frames. Decoded vertex i is matched to
    the nearest original vertex at frame 0 (grid search; ties broken by the whole trajectory)
    if same_order_every_frame, else frame by frame; to original vertex i if same_index.
    Returns (error, count of original vertices no decoded one was matched to)."""
    if len(original) != len(decoded):
        raise ValueError("%d decoded frames for %d original ones" % (len(decoded), len(original)))
    diag = bbox_diagonal(original)
    worst, extra = 0.0, 0
    if same_index:
        if any(len(fo) != len(fd) for fo, fd in zip(original, decoded)):
            raise ValueError("decoded vertex count differs from the original's")
        for fo, fd in zip(original, decoded):
            worst = max(worst, max(math.dist(a, b) for a, b in zip(fo, fd)))
    elif same_order_every_frame:
        match = _nearest(original[0], decoded[0], diag, original, decoded)
        extra = abs(len(original[0]) - len(set(match)))
        for fo, fd in zip(original, decoded):
            for i, j in enumerate(match):
                worst = max(worst, math.dist(fd[i], fo[j]))
    else:
        for fo, fd in zip(original, decoded):
            match = _nearest(fo, fd, diag)
            extra = max(extra, abs(len(fo) - len(set(match))))
            for i, j in enumerate(match):
                worst = max(worst, math.dist(fd[i], fo[j]))
    return worst / diag, extra


def _nearest(orig, dec, diag, orig_frames=None, dec_frames=None):
    cell = diag * 2.0 ** -10
    grid = {}
    for j, v in enumerate(orig):
        grid.setdefault(tuple(int(math.floor(c / cell)) for c in v), []).append(j)
    match = []
    for i, v in enumerate(dec):
        key = tuple(int(math.floor(c / cell)) for c in v)
        best, best_d, r = None, math.inf, 1
        while best is None and r <= 64:
            cands = [j for dx in range(-r, r + 1) for dy in range(-r, r + 1)
                     for dz in range(-r, r + 1)
                     for j in grid.get((key[0] + dx, key[1] + dy, key[2] + dz), ())]
            for j in cands:
                if orig_frames is None:
                    d = math.dist(v, orig[j])
                else:  # coincident at frame 0 (e.g. two sides of a crack): the whole path
                    d = sum(math.dist(fd[i], fo[j]) for fo, fd in zip(orig_frames, dec_frames))
                if d < best_d:
                    best, best_d = j, d
            r *= 4
        if best is None:
            raise ValueError("decoded vertex %d has no original within %g" % (i, 64 * cell))
        match.append(best)
    return match
