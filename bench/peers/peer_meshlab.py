#!/usr/bin/python3
"""Peer driver: MeshLab 2020.09 (Debian package meshlab) quadric edge collapse, via meshlabserver.

    peer_meshlab.py INPUT.obj -o OUTPUT.obj --vertices N

Same contract as the C++ drivers (driver_common.h): writes OUTPUT.obj, prints one JSON line.

meshlabserver needs an OpenGL context even without a window, so the driver starts its own
Xvfb (package xvfb) and stops it at the end. MeshLab's OBJ importer aborts on our inputs (an
assertion in vcglib's import_obj.h), so the driver hands it a binary PLY instead: the OBJ is
read and quads are split along the shorter diagonal exactly as obj_io.h does.

Filter "Simplification: Quadric Edge Collapse Decimation" with every parameter set
explicitly (see MLX below): QualityThr 0.3, PreserveBoundary false, BoundaryWeight 1,
PreserveNormal false, PreserveTopology false, OptimalPlacement true, PlanarQuadric false,
PlanarWeight 0.001, QualityWeight false, AutoClean true, Selected false.

MeshLab targets a FACE count: the driver searches the face target (secant steps, each a
meshlabserver run) until the output has within 0.5 % of the requested vertices; the face target
found is cached beside the output (OUTPUT.obj.meshlab-faces) so that repeated runs of the
same cell do not search again. meshlabserver reports no filter time, so
"seconds" = wall time of the final run - wall time of a run that only loads and saves the same
mesh (an estimate of the filter time without I/O and start-up); both walls are reported.
"peak_rss_mb" is meshlabserver's own peak (VmHWM polled every 2 ms while it runs; it includes
MeshLab's Qt/GL start-up).
"""

import array
import json
import os
import struct
import subprocess
import sys
import tempfile
import time

PEER = "meshlab"

MLX = """<!DOCTYPE FilterScript>
<FilterScript>
 <filter name="Simplification: Quadric Edge Collapse Decimation">
  <Param type="RichInt" value="{faces}" name="TargetFaceNum"/>
  <Param type="RichFloat" value="0" name="TargetPerc"/>
  <Param type="RichFloat" value="0.3" name="QualityThr"/>
  <Param type="RichBool" value="false" name="PreserveBoundary"/>
  <Param type="RichFloat" value="1" name="BoundaryWeight"/>
  <Param type="RichBool" value="false" name="PreserveNormal"/>
  <Param type="RichBool" value="false" name="PreserveTopology"/>
  <Param type="RichBool" value="true" name="OptimalPlacement"/>
  <Param type="RichBool" value="false" name="PlanarQuadric"/>
  <Param type="RichFloat" value="0.001" name="PlanarWeight"/>
  <Param type="RichBool" value="false" name="QualityWeight"/>
  <Param type="RichBool" value="true" name="AutoClean"/>
  <Param type="RichBool" value="false" name="Selected"/>
 </filter>
</FilterScript>
"""


def die(msg, code=1):
    print("%s: %s" % (PEER, msg), file=sys.stderr)
    sys.exit(code)


def parse_args(argv):
    inp = out = None
    n = 0
    i = 1
    while i < len(argv):
        a = argv[i]
        if a in ("-o", "--output") and i + 1 < len(argv):
            out = argv[i + 1]
            i += 1
        elif a in ("--vertices", "-n") and i + 1 < len(argv):
            n = int(argv[i + 1])
            i += 1
        elif not a.startswith("-") and inp is None:
            inp = a
        else:
            die("unknown argument %r" % a, 2)
        i += 1
    if not inp or not out or n <= 0:
        die("usage: peer_meshlab.py INPUT.obj -o OUTPUT.obj --vertices N", 2)
    return inp, out, n


def read_obj(path):
    """(vertices [x,y,z...] flat list, triangles flat list, faces in file); quads split on the shorter diagonal."""
    V = []
    T = []
    nf = 0
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                s = line.split()
                V.append((float(s[1]), float(s[2]), float(s[3])))
            elif line.startswith("f "):
                idx = []
                for w in line.split()[1:]:
                    k = int(w.split("/")[0])
                    idx.append(k - 1 if k > 0 else len(V) + k)
                nf += 1
                if len(idx) == 3:
                    T.extend(idx)
                elif len(idx) == 4:
                    a, b, c, d = (V[k] for k in idx)
                    ac = sum((a[j] - c[j]) ** 2 for j in range(3))
                    bd = sum((b[j] - d[j]) ** 2 for j in range(3))
                    i0, i1, i2, i3 = idx
                    T.extend((i0, i1, i2, i0, i2, i3) if ac <= bd else (i0, i1, i3, i1, i2, i3))
                else:
                    for k in range(1, len(idx) - 1):
                        T.extend((idx[0], idx[k], idx[k + 1]))
    return V, T, nf


def write_ply(path, V, T):
    with open(path, "wb") as f:
        f.write(("ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\nproperty float y\n"
                 "property float z\nelement face %d\nproperty list uchar int vertex_indices\nend_header\n"
                 % (len(V), len(T) // 3)).encode())
        f.write(array.array("f", [c for v in V for c in v]).tobytes())
        rec = struct.Struct("<Biii")
        buf = bytearray()
        for k in range(0, len(T), 3):
            buf += rec.pack(3, T[k], T[k + 1], T[k + 2])
        f.write(buf)


PLY_TYPES = {"char": "b", "int8": "b", "uchar": "B", "uint8": "B", "short": "h", "int16": "h",
             "ushort": "H", "uint16": "H", "int": "i", "int32": "i", "uint": "I", "uint32": "I",
             "float": "f", "float32": "f", "double": "d", "float64": "d"}


def read_ply(path):
    """Vertices and triangles of a binary little-endian or ASCII PLY (the subset MeshLab writes)."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header") + len(b"end_header")
    end = data.index(b"\n", end) + 1
    header = data[:end].decode().splitlines()
    fmt = None
    elements = []
    for line in header:
        w = line.split()
        if not w:
            continue
        if w[0] == "format":
            fmt = w[1]
        elif w[0] == "element":
            elements.append((w[1], int(w[2]), []))
        elif w[0] == "property":
            elements[-1][2].append(w[1:])
    V, T = [], []
    if fmt == "ascii":
        toks = data[end:].split()
        p = 0
        for name, count, props in elements:
            for _ in range(count):
                vals = []
                for pr in props:
                    if pr[0] == "list":
                        n = int(toks[p]); p += 1
                        vals.append([int(t) for t in toks[p:p + n]]); p += n
                    else:
                        vals.append(float(toks[p])); p += 1
                if name == "vertex":
                    V.append(tuple(vals[:3]))
                elif name == "face":
                    lst = next(v for v in vals if isinstance(v, list))
                    for k in range(1, len(lst) - 1):
                        T.extend((lst[0], lst[k], lst[k + 1]))
        return V, T
    if fmt != "binary_little_endian":
        die("unsupported PLY format %s" % fmt)
    p = end
    for name, count, props in elements:
        if all(pr[0] != "list" for pr in props):
            st = struct.Struct("<" + "".join(PLY_TYPES[pr[0]] for pr in props))
            names = [pr[1] for pr in props]
            ix, iy, iz = (names.index(c) for c in "xyz") if name == "vertex" else (0, 0, 0)
            for rec in st.iter_unpack(data[p:p + st.size * count]):
                if name == "vertex":
                    V.append((rec[ix], rec[iy], rec[iz]))
            p += st.size * count
        else:
            for _ in range(count):
                lst = None
                for pr in props:
                    if pr[0] == "list":
                        cnt_t, item_t = PLY_TYPES[pr[1]], PLY_TYPES[pr[2]]
                        (n,) = struct.unpack_from("<" + cnt_t, data, p)
                        p += struct.calcsize(cnt_t)
                        vals = struct.unpack_from("<%d%s" % (n, item_t), data, p)
                        p += n * struct.calcsize(item_t)
                        if lst is None:
                            lst = vals
                    else:
                        p += struct.calcsize(PLY_TYPES[pr[0]])
                if name == "face" and lst:
                    for k in range(1, len(lst) - 1):
                        T.extend((lst[0], lst[k], lst[k + 1]))
    return V, T


def start_xvfb():
    r, w = os.pipe()
    p = subprocess.Popen(["Xvfb", "-displayfd", str(w), "-screen", "0", "320x240x24", "-nolisten", "tcp"],
                         pass_fds=(w,), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    os.close(w)
    buf = b""
    deadline = time.monotonic() + 30
    while not buf.endswith(b"\n") and time.monotonic() < deadline:
        chunk = os.read(r, 16)
        if not chunk:
            break
        buf += chunk
    os.close(r)
    if not buf.strip():
        p.kill()
        p.wait()
        die("Xvfb did not start (apt-get install xvfb)")
    return p, ":" + buf.decode().strip()


def vm_hwm_kb(pid):
    """Peak RSS of a running process (VmHWM); unlike wait4's ru_maxrss it does not include the
    pages of the forking Python process."""
    try:
        with open("/proc/%d/status" % pid) as f:
            for line in f:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1])
    except (OSError, ValueError):
        pass
    return 0


def run_meshlab(env, args):
    """Runs meshlabserver; returns (wall seconds, peak RSS MB, stdout+stderr)."""
    with tempfile.TemporaryFile() as log:
        t0 = time.monotonic()
        p = subprocess.Popen(["meshlabserver"] + args, env=env, stdout=log, stderr=subprocess.STDOUT,
                             stdin=subprocess.DEVNULL)
        hwm_kb = 0
        while True:
            pid, status, _ = os.wait4(p.pid, os.WNOHANG)
            if pid:
                break
            hwm_kb = max(hwm_kb, vm_hwm_kb(p.pid))
            time.sleep(0.002)
        wall = time.monotonic() - t0
        p.returncode = os.waitstatus_to_exitcode(status)
        log.seek(0)
        text = log.read().decode(errors="replace")
    if p.returncode != 0:
        die("meshlabserver failed (rc %d): %s" % (p.returncode, text.strip().splitlines()[-1:]))
    return wall, hwm_kb / 1024, text


def main():
    inp, out, target = parse_args(sys.argv)
    V, T, faces_in = read_obj(inp)
    tmp = tempfile.TemporaryDirectory(prefix="peer_meshlab_")
    src = os.path.join(tmp.name, "in.ply")
    dst = os.path.join(tmp.name, "out.ply")
    mlx = os.path.join(tmp.name, "qec.mlx")
    write_ply(src, V, T)
    xvfb, display = start_xvfb()
    env = dict(os.environ, DISPLAY=display, QT_QPA_PLATFORM="xcb")
    try:
        cache = out + ".meshlab-faces"
        nt = len(T) // 3
        faces = None
        try:
            with open(cache) as f:
                c = json.load(f)
            if c.get("input") == os.path.abspath(inp) and c.get("target") == target:
                faces = int(c["faces"])
        except (OSError, ValueError, KeyError):
            pass
        calls = 0
        search_wall = 0.0
        tol = max(1.0, 0.005 * target)
        best = None  # (|dv|, faces, wall, rss, V, T)
        if faces is None:
            faces = max(1, round(nt * target / len(V)))
            lo, hi = 0, nt
            while calls < 12:
                with open(mlx, "w") as f:
                    f.write(MLX.format(faces=faces))
                wall, rss, _ = run_meshlab(env, ["-i", src, "-o", dst, "-s", mlx])
                calls += 1
                search_wall += wall
                oV, oT = read_ply(dst)
                used = len(set(oT))
                d = abs(used - target)
                if best is None or d < best[0]:
                    best = (d, faces, wall, rss, oV, oT)
                if d <= tol:
                    break
                if used > target:
                    hi = faces
                else:
                    lo = faces
                nxt = round(faces * target / max(1, used))
                if nxt <= lo or nxt >= hi:
                    nxt = (lo + hi) // 2
                if nxt == faces or hi - lo <= 1:
                    break
                faces = nxt
            faces = best[1]
            with open(cache, "w") as f:
                json.dump({"input": os.path.abspath(inp), "target": target, "faces": faces}, f)
        # Timed run at the chosen face target, then the load+save-only baseline.
        with open(mlx, "w") as f:
            f.write(MLX.format(faces=faces))
        wall, rss, _ = run_meshlab(env, ["-i", src, "-o", dst, "-s", mlx])
        oV, oT = read_ply(dst)
        base_wall, base_rss, _ = run_meshlab(env, ["-i", src, "-o", os.path.join(tmp.name, "copy.ply")])
    finally:
        xvfb.terminate()
        xvfb.wait()

    # Compact and write the OBJ.
    remap = {}
    outV = []
    outT = []
    for k in oT:
        if k not in remap:
            remap[k] = len(outV)
            outV.append(oV[k])
        outT.append(remap[k])
    with open(out, "w") as f:
        f.write("# %d vertices, %d triangles\n" % (len(outV), len(outT) // 3))
        f.write("".join("v %.9g %.9g %.9g\n" % v for v in outV))
        f.write("".join("f %d %d %d\n" % (outT[k] + 1, outT[k + 1] + 1, outT[k + 2] + 1) for k in range(0, len(outT), 3)))
    tmp.cleanup()

    print(json.dumps({
        "peer": PEER, "input": inp, "vertices_in": len(V), "faces_in": faces_in, "target_vertices": target,
        "vertices_out": len(outV), "faces_out": len(outT) // 3, "seconds": max(0.0, wall - base_wall),
        "peak_rss_mb": rss, "triangles_in": nt, "seconds_wall_with_io": wall, "seconds_wall_io_only": base_wall,
        "peak_rss_mb_io_only": base_rss, "target_faces": faces, "search_calls": calls,
        "search_seconds": search_wall, "seconds_estimated": True, "version": "MeshLab 2020.09 (meshlabserver)"}))
    sys.stdout.flush()


if __name__ == "__main__":
    main()
