#!/usr/bin/python3
"""Build at scale (issue 20): tiled CalculiX crash boxes written as Exodus II, and their timings.

  bench/scale_inputs.py write OUT_DIR [--sizes 1M:25,1M:100,5M:25,5M:50] [--crashbox DIR]
  bench/scale_inputs.py run OUT_DIR --dynpm PATH [--sizes …] [--runs 2] [--threads N]

`write` tiles the real crash-box run of ../shared/data/crashbox-s (3,003 nodes, 2,937 S4 shells,
26 frames) into a grid of parts, each a little rotated so that no two are copies in space, until
the vertex count is reached, and writes crashbox_<V>x<S>.exo (Exodus II, netCDF 64-bit offset,
float32 values: coordinates plus nodal DISPL_X/Y/Z). S steps are spread over the run; a step
between two frames is their linear interpolation. OUT_DIR must lie outside the repository: the
data is made here, never committed.

`run` times `dynpm info`, `dynpm build --key-steps auto:3` and `--key-steps all` on each input
with /usr/bin/time (wall and CPU seconds, peak RSS), `--runs` times each (the median is shown),
and prints the load average and a markdown table with the ratio build / info in CPU time
(issue 20: auto:3 at 1 M × 25 within 4×).
Needs Debian's python3-netcdf4 and python3-numpy (hence /usr/bin/python3).
"""
import argparse
import math
import os
import statistics
import subprocess
import sys
import tempfile

import netCDF4
import numpy as np

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_CRASHBOX = os.path.join(os.path.dirname(REPO), "shared", "data", "crashbox-s", "obj")


def parse_sizes(text):
    sizes = []
    for item in text.split(","):
        vertices, steps = item.split(":")
        scale = {"M": 1_000_000, "k": 1_000}.get(vertices[-1], 1)
        count = float(vertices[:-1]) if scale > 1 else float(vertices)
        sizes.append((item, int(count * scale), int(steps)))
    return sizes


def file_name(label, steps):
    return "crashbox_%sx%d.exo" % (label.split(":")[0], steps)


def read_obj_frames(folder):
    """Positions of every frame_NNN.obj (float32, #V × 3) and the 1-based quads of the first."""
    names = sorted(n for n in os.listdir(folder) if n.startswith("frame_") and n.endswith(".obj"))
    frames, faces = [], []
    for i, name in enumerate(names):
        xyz = []
        with open(os.path.join(folder, name)) as f:
            for line in f:
                if line.startswith("v "):
                    xyz.append([float(w) for w in line.split()[1:4]])
                elif i == 0 and line.startswith("f "):
                    faces.append([int(w.split("/")[0]) for w in line.split()[1:]])
        frames.append(np.asarray(xyz, dtype=np.float64))
    if any(len(f) != 4 for f in faces):
        sys.exit("%s: expected quads only" % folder)
    return frames, np.asarray(faces, dtype=np.int32)


def step_positions(frames, steps, s):
    """Step s of `steps` spread over the run, interpolated between its two nearest frames."""
    u = s * (len(frames) - 1) / max(steps - 1, 1)
    a = int(math.floor(u))
    b = min(a + 1, len(frames) - 1)
    w = u - a
    return frames[a] * (1 - w) + frames[b] * w


def tile(xyz, tiles):
    """Every tile's copy of one tube: rotated by 0.1 rad per tile about z, on a 120 mm grid."""
    columns = math.ceil(math.sqrt(tiles))
    t = np.arange(tiles)
    c, s = np.cos(0.1 * t)[:, None], np.sin(0.1 * t)[:, None]
    dx, dy = ((t % columns) * 120.0)[:, None], ((t // columns) * 120.0)[:, None]
    x, y, z = xyz[:, 0][None, :], xyz[:, 1][None, :], xyz[:, 2][None, :]
    out = np.empty((tiles, xyz.shape[0], 3), dtype=np.float64)
    out[:, :, 0] = c * x - s * y + dx
    out[:, :, 1] = s * x + c * y + dy
    out[:, :, 2] = np.broadcast_to(z, (tiles, xyz.shape[0]))
    return out.reshape(-1, 3)


def write_exodus(path, frames, faces, tiles, steps):
    n_one = frames[0].shape[0]
    nodes = n_one * tiles
    base = tile(frames[0], tiles)
    tmp = path + ".part"
    nc = netCDF4.Dataset(tmp, "w", format="NETCDF3_64BIT_OFFSET")
    nc.api_version = np.float32(5.0)
    nc.version = np.float32(5.0)
    nc.floating_point_word_size = np.int32(4)
    nc.file_size = np.int32(1)
    nc.title = "crash box tiled %d times, %d steps (bench/scale_inputs.py)" % (tiles, steps)
    for name, size in [("len_string", 33), ("len_name", 33), ("len_line", 81), ("four", 4),
                       ("num_dim", 3), ("num_nodes", nodes), ("num_elem", len(faces) * tiles),
                       ("num_el_blk", 1), ("num_el_in_blk1", len(faces) * tiles),
                       ("num_nod_per_el1", 4), ("num_nod_var", 3), ("time_step", None)]:
        nc.createDimension(name, size)
    for axis, name in enumerate(["coordx", "coordy", "coordz"]):
        v = nc.createVariable(name, "f4", ("num_nodes",))
        v[:] = base[:, axis].astype(np.float32)
    prop = nc.createVariable("eb_prop1", "i4", ("num_el_blk",))
    prop.setncattr("name", "ID")
    prop[:] = [1]
    nc.createVariable("eb_status", "i4", ("num_el_blk",))[:] = [1]
    connect = nc.createVariable("connect1", "i4", ("num_el_in_blk1", "num_nod_per_el1"))
    connect.elem_type = "SHELL4"
    offsets = (np.arange(tiles, dtype=np.int32) * n_one)[:, None, None]
    connect[:] = (faces[None, :, :] + offsets).reshape(-1, 4)
    names = nc.createVariable("name_nod_var", "S1", ("num_nod_var", "len_name"))
    names[:] = netCDF4.stringtochar(np.array(["DISPL_X", "DISPL_Y", "DISPL_Z"], dtype="S33"))
    times = nc.createVariable("time_whole", "f4", ("time_step",))
    values = [nc.createVariable("vals_nod_var%d" % (k + 1), "f4", ("time_step", "num_nodes"))
              for k in range(3)]
    for s in range(steps):
        moved = tile(step_positions(frames, steps, s), tiles) - base
        times[s] = float(s)
        for k in range(3):
            values[k][s, :] = moved[:, k].astype(np.float32)
    nc.close()
    os.replace(tmp, path)
    return nodes


def outside_repo(folder):
    real = os.path.realpath(folder)
    return not (real == REPO or real.startswith(REPO + os.sep))


def write(args):
    if not outside_repo(args.out_dir):
        sys.exit("%s: inside the repository; give a folder outside it" % args.out_dir)
    os.makedirs(args.out_dir, exist_ok=True)
    frames, faces = read_obj_frames(args.crashbox)
    for label, vertices, steps in parse_sizes(args.sizes):
        path = os.path.join(args.out_dir, file_name(label, steps))
        if os.path.exists(path):
            print("have  %s" % path)
            continue
        tiles = math.ceil(vertices / frames[0].shape[0])
        nodes = write_exodus(path, frames, faces, tiles, steps)
        print("wrote %s: %d nodes, %d shells, %d steps, %.0f MB" %
              (path, nodes, len(faces) * tiles, steps, os.path.getsize(path) / 1e6))


def timed(command):
    """Wall seconds, CPU seconds (user + sys) and peak RSS in MB of one run (GNU time)."""
    with tempfile.NamedTemporaryFile("r", suffix=".time") as report:
        done = subprocess.run(["/usr/bin/time", "-f", "%e %U %S %M", "-o", report.name] + command,
                              stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        if done.returncode != 0:
            sys.exit("%s failed:\n%s" % (" ".join(command), done.stderr))
        wall, user, system, kb = report.read().split()[-4:]
    return float(wall), float(user) + float(system), float(kb) / 1024


def median_of(runs, command):
    """The median of each measure over `runs` runs (a loaded machine: CPU is the steadier one)."""
    results = [timed(command) for _ in range(runs)]
    return tuple(statistics.median(r[k] for r in results) for k in range(3))


def load_text():
    return "%.1f / %.1f / %.1f" % os.getloadavg()


def run(args):
    rows = []
    threads = ["--threads", str(args.threads)] if args.threads else []
    load_before = load_text()
    for label, _, steps in parse_sizes(args.sizes):
        path = os.path.join(args.out_dir, file_name(label, steps))
        if not os.path.exists(path):
            sys.exit("%s: missing; run 'write' first" % path)
        out = os.path.join(args.out_dir, "bench.dpm")
        info = median_of(args.runs, [args.dynpm, "info", path])
        auto = median_of(args.runs, [args.dynpm, "build", path, "-o", out, "--key-steps",
                                     "auto:3"] + threads)
        every = median_of(args.runs, [args.dynpm, "build", path, "-o", out, "--key-steps",
                                      "all"] + threads)
        os.remove(out)
        rows.append((label.replace(":", " × "), info, auto, every))
        print("done  %s" % path, file=sys.stderr)
    print("Wall / CPU (user + sys) seconds, medians of %d runs; load average (1 / 5 / 15 min) "
          "%s before, %s after." % (args.runs, load_before, load_text()))
    print()
    print("| input | `info` | build auto:3 | build all | peak memory auto:3 / all | "
          "auto:3 / info, CPU |")
    print("|---|---:|---:|---:|---:|---:|")
    for name, info, auto, every in rows:
        print("| %s | %.1f / %.1f s | %.1f / %.1f s | %.1f / %.1f s | %.2f / %.2f GB | %.1f× |" %
              (name, info[0], info[1], auto[0], auto[1], every[0], every[1], auto[2] / 1024,
               every[2] / 1024, auto[1] / info[1]))


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="verb", required=True)
    w = sub.add_parser("write", help="write the tiled Exodus inputs")
    w.add_argument("out_dir")
    w.add_argument("--sizes", default="1M:25,1M:100,5M:25,5M:50")
    w.add_argument("--crashbox", default=DEFAULT_CRASHBOX, help="the crashbox-s OBJ frames")
    r = sub.add_parser("run", help="time info and build on each input")
    r.add_argument("out_dir")
    r.add_argument("--dynpm", required=True)
    r.add_argument("--sizes", default="1M:25,1M:100,5M:25,5M:50")
    r.add_argument("--runs", type=int, default=2)
    r.add_argument("--threads", type=int, default=0, help="passed to build (0: its default)")
    args = parser.parse_args()
    write(args) if args.verb == "write" else run(args)


if __name__ == "__main__":
    main()
