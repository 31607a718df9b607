#!/usr/bin/env python3
"""Render OBJ frames side by side into a PNG (standard library only).

A small z-buffer rasteriser: orthographic view from above the -x side, flat
two-sided shading (outer side blue-grey, inner side sand), element edges
drawn dark.  All panels share one scale so deformations compare directly.

usage: render_png.py OUT.png FRAME.obj [FRAME.obj ...]
"""
import math
import struct
import sys
import zlib

W, H = 640, 400          # one panel
CAM = (-0.75, 0.55, -0.38)
LIGHT = (-0.4, 0.8, -0.45)


def norm(v):
    n = math.sqrt(sum(c * c for c in v)) or 1.0
    return tuple(c / n for c in v)


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def read_obj(path):
    v, f = [], []
    with open(path) as fh:
        for line in fh:
            if line.startswith("v "):
                v.append(tuple(float(t) for t in line.split()[1:4]))
            elif line.startswith("f "):
                f.append([int(t.split("/")[0]) - 1 for t in line.split()[1:]])
    return v, f


def main(argv):
    if len(argv) < 3:
        sys.exit(__doc__.strip().splitlines()[-1])
    out, paths = argv[1], argv[2:]
    fwd = norm(tuple(-c for c in CAM))
    right = norm(cross(fwd, (0.0, 1.0, 0.0)))
    up = cross(right, fwd)
    light = norm(LIGHT)
    meshes = []
    for p in paths:
        v, f = read_obj(p)
        s = [(dot(p3, right), dot(p3, up), dot(p3, fwd)) for p3 in v]
        meshes.append((v, f, s))
    xs = [q[0] for _, _, s in meshes for q in s]
    ys = [q[1] for _, _, s in meshes for q in s]
    scale = 0.9 * min(W / (max(xs) - min(xs)), H / (max(ys) - min(ys)))
    cx, cy = (max(xs) + min(xs)) / 2, (max(ys) + min(ys)) / 2
    NW = W * len(meshes)
    img = bytearray([245, 245, 245] * NW * H)
    for k, (v, f, s) in enumerate(meshes):
        ox = k * W
        zbuf = [float("inf")] * (W * H)
        P = [(W / 2 + (q[0] - cx) * scale, H / 2 - (q[1] - cy) * scale, q[2]) for q in s]
        for face in f:
            a, b, c = (v[face[0]], v[face[1]], v[face[2 if len(face) == 3 else 2]])
            n = norm(cross(tuple(b[i] - a[i] for i in range(3)), tuple(c[i] - a[i] for i in range(3))))
            if len(face) == 4:
                d = v[face[3]]
                n = norm(cross(tuple(c[i] - a[i] for i in range(3)), tuple(d[i] - b[i] for i in range(3))))
            front = dot(n, fwd) < 0
            lam = abs(dot(n, light))
            base = (120, 150, 190) if front else (205, 180, 120)
            col = tuple(int(bc * (0.35 + 0.65 * lam)) for bc in base)
            tris = [(0, 1, 2)] if len(face) == 3 else [(0, 1, 2), (0, 2, 3)]
            for t in tris:
                # real element edges of this triangle: opposite vertex index -> is real
                if len(face) == 3:
                    real = (True, True, True)
                elif t == (0, 1, 2):
                    real = (True, False, True)   # edge 0-2 (diagonal) is opposite vertex 1
                else:
                    real = (True, True, False)   # edge 0-2 (diagonal) is opposite vertex 3
                p0, p1, p2 = P[face[t[0]]], P[face[t[1]]], P[face[t[2]]]
                area = (p1[0] - p0[0]) * (p2[1] - p0[1]) - (p2[0] - p0[0]) * (p1[1] - p0[1])
                if abs(area) < 1e-9:
                    continue
                # distance scale of each barycentric coordinate (height over opposite edge)
                hs = []
                for (qa, qb) in ((p1, p2), (p2, p0), (p0, p1)):
                    el = math.hypot(qb[0] - qa[0], qb[1] - qa[1]) or 1e-9
                    hs.append(abs(area) / el)
                x0 = max(int(min(p0[0], p1[0], p2[0])), 0)
                x1 = min(int(max(p0[0], p1[0], p2[0])) + 1, W - 1)
                y0 = max(int(min(p0[1], p1[1], p2[1])), 0)
                y1 = min(int(max(p0[1], p1[1], p2[1])) + 1, H - 1)
                for y in range(y0, y1 + 1):
                    py = y + 0.5
                    for x in range(x0, x1 + 1):
                        px = x + 0.5
                        w0 = ((p1[0] - px) * (p2[1] - py) - (p2[0] - px) * (p1[1] - py)) / area
                        w1 = ((p2[0] - px) * (p0[1] - py) - (p0[0] - px) * (p2[1] - py)) / area
                        w2 = 1.0 - w0 - w1
                        if w0 < 0 or w1 < 0 or w2 < 0:
                            continue
                        z = w0 * p0[2] + w1 * p1[2] + w2 * p2[2]
                        zi = y * W + x
                        if z >= zbuf[zi]:
                            continue
                        zbuf[zi] = z
                        edge = ((real[0] and w0 * hs[0] < 0.7) or (real[1] and w1 * hs[1] < 0.7)
                                or (real[2] and w2 * hs[2] < 0.7))
                        o = 3 * (y * NW + ox + x)
                        img[o:o + 3] = bytes((40, 40, 50)) if edge else bytes(col)
    raw = b"".join(b"\x00" + bytes(img[3 * y * NW:3 * (y + 1) * NW]) for y in range(H))

    def chunk(tag, data):
        return (struct.pack(">I", len(data)) + tag + data
                + struct.pack(">I", zlib.crc32(tag + data) & 0xffffffff))
    png = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", NW, H, 8, 2, 0, 0, 0))
           + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))
    with open(out, "wb") as fh:
        fh.write(png)


if __name__ == "__main__":
    main(sys.argv)
