#!/usr/bin/python3
"""Side-by-side benchmark of animated-mesh file formats: dynpm's .dpm, OpenMesh's progressive
mesh (.pm, one per frame), gltfpack's morph targets and Draco (one .drc per frame), built from
the same OBJ frames (docs/peers.md, "File formats").

For every input (a directory holding frame_*.obj, or obj/frame_*.obj) and every format it
prints bytes per vertex per step (whole file / (vertices x steps)), split into positions and
everything else where the format lets us tell, the max position error measured here against the
original frames (decoded output, vertices matched by position, in units of the bounding-box
diagonal over all steps), the encode time and, for the progressive formats, vertex splits per
second. dynpm's numbers come from its command line only (`dynpm build/info/extract --json`,
`navigator_bench`), never from parsing the file, so the script outlives format changes.

Example (docs/peers.md):
  /usr/bin/python3 bench/peers/format_bench.py --workdir build/peers/formats \\
      --dynpm build/release/cli/dynpm --navigator-bench build/release/bench/navigator_bench
"""

import argparse
import datetime
import glob
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.dirname(HERE))
import format_io as fio  # noqa: E402
from simplify_bench import last_json, machine_info  # noqa: E402

SHARED = os.path.normpath(os.path.join(ROOT, "..", "shared", "data"))
DEFAULT_INPUTS = [os.path.join(SHARED, n, "obj")
                  for n in ("crashbox-s", "crashbox-mixed-5k", "crashbox-fields")]
DEFAULT_BOUND = 2.0 ** -18  # dynpm build's default --position-error (diagonals)
PACKAGES = ["libopenmesh-dev", "gltfpack", "draco"]


def log(*a):
    print(*a, file=sys.stderr, flush=True)


def run(argv, what):
    """Runs argv; returns (stdout, wall seconds); exits with the tool's message on failure."""
    t0 = time.monotonic()
    p = subprocess.run(argv, capture_output=True, text=True, stdin=subprocess.DEVNULL)
    wall = time.monotonic() - t0
    if p.returncode != 0:
        last = (p.stderr.strip().splitlines() or p.stdout.strip().splitlines() or [""])[-1]
        sys.exit("format_bench: %s failed (rc %d): %s\n  command: %s"
                 % (what, p.returncode, last[:300], " ".join(argv)))
    return p.stdout, wall


def json_of(text, key, what):
    d = last_json(text, key)
    if d is None:
        sys.exit("format_bench: %s printed no JSON with %r" % (what, key))
    return d


def error_of(original, decoded, same_order, same_index=False):
    """fio.max_error, warning when some original vertices were matched by no decoded one."""
    err, unmatched = fio.max_error(original, decoded, same_order, same_index)
    if unmatched:
        log("  warning: %d original vertices matched by no decoded vertex" % unmatched)
    return err, unmatched


def frame_files(path):
    for pattern in ("frame_*.obj", os.path.join("obj", "frame_*.obj")):
        files = glob.glob(os.path.join(path, pattern))
        if files:
            return sorted(files, key=lambda f: int(re.findall(r"\d+", os.path.basename(f))[-1]))
    sys.exit("format_bench: no frame_*.obj in %s" % path)


class Input:
    """The original frames: positions per frame, faces of frame 0 (same in every frame)."""

    def __init__(self, path, max_frames):
        self.files = frame_files(path)[:max_frames or None]
        self.name = os.path.relpath(path, SHARED) if path.startswith(SHARED) else path
        self.frames, self.faces = [], None
        for f in self.files:
            verts, faces = fio.read_obj(f, self.faces is None)
            self.frames.append(verts)
            self.faces = self.faces if self.faces is not None else faces
        self.V, self.T = len(self.frames[0]), len(self.frames)
        self.tris = fio.triangulate(self.frames[0], self.faces)

    def per_vs(self, nbytes):
        """Bytes per vertex per step."""
        return nbytes / (self.V * self.T)


def row(fmt, setting, total, pos=None, rest=None, err=None, enc=None, runs=None, splits=None,
        note=""):
    return {"format": fmt, "setting": setting, "bytes": total, "pos_bytes": pos,
            "rest_bytes": rest, "max_error": err, "encode_s": enc, "runs": runs,
            "splits_per_s": splits, "note": note}


# ------------------------------------------------------------------------------------ dynpm

def dynpm_rows(inp, args, work, bounds):
    rows = []
    one_step = None  # a build of frame 0 alone: what is not a later step's positions
    for label, bound in bounds:
        out = os.path.join(work, "dynpm_%s.dpm" % label)
        extra = [] if bound is None else ["--position-error", "%.6g" % bound]
        times = []
        for _ in range(args.runs):
            text, _wall = run([args.dynpm, "build", *inp.files, "-o", out, "--json", *extra],
                              "dynpm build")
            times.append(json_of(text, "bytes", "dynpm build")["seconds"])
        info = json_of(run([args.dynpm, "info", out, "--json"], "dynpm info")[0], "bytes",
                       "dynpm info")
        total = info["bytes"]
        pos = next((v for k, v in info.items() if re.search(r"position.*bytes|bytes.*position", k)
                    and isinstance(v, (int, float))), None)
        note = "position bound %.3g diag" % (info["position_error"] / info["diagonal"])
        rest = None
        if pos is not None:
            rest = total - pos
            note += "; split from `dynpm info --json`"
        elif inp.T > 1:
            if one_step is None or bound is not None:
                one = os.path.join(work, "dynpm_%s_step0.dpm" % label)
                run([args.dynpm, "build", inp.files[0], "-o", one, "--json", *extra], "dynpm build")
                one_step = json_of(run([args.dynpm, "info", one, "--json"], "dynpm info")[0],
                                   "bytes", "dynpm info")["bytes"]
            later = (total - one_step) / (inp.T - 1)  # one later step's positions
            pos, rest = later * inp.T, total - later * inp.T
            note += ("; positions = (file − 1-step file) / (steps − 1) per step, the rest "
                     "is the 1-step file less one step of those")
        # the error: every step fully refined, in the input's vertex order
        pattern = os.path.join(work, "dynpm_%s_full_{:03d}.obj" % label)
        run([args.dynpm, "extract", out, "--full", "-o", pattern], "dynpm extract")
        decoded = [fio.read_obj(pattern.replace("{:03d}", "%03d" % t), False)[0]
                   for t in range(inp.T)]
        err, _ = error_of(inp.frames, decoded, True, same_index=True)
        splits = None
        if args.navigator_bench:
            nav = json_of(run([args.navigator_bench, out, "9"], "navigator_bench")[0],
                          "splits_per_s", "navigator_bench")
            splits = nav["splits_per_s"]
        rows.append(row("dynpm .dpm", "build" + ("" if bound is None else
                                                 " --position-error %.3g" % bound),
                        total, pos, rest, err, statistics.median(times), args.runs, splits, note))
    return rows


# --------------------------------------------------------------------------------- OpenMesh

def openmesh_rows(inp, args, work):
    tool = os.path.join(args.peers_dir, "peer_openmesh_pm")
    total = enc = 0.0
    worst = 0.0
    replay = None
    for t, f in enumerate(inp.files):
        pm = os.path.join(work, "openmesh_%03d.pm" % t)
        full = os.path.join(work, "openmesh_%03d_full.obj" % t)
        b = json_of(run([tool, "build", f, "-o", pm], "peer_openmesh_pm build")[0], "bytes",
                    "peer_openmesh_pm")
        total += b["bytes"]
        enc += b["seconds"]
        r = json_of(run([tool, "replay", pm, "-o", full, "--repeats", "9" if t == 0 else "1"],
                        "peer_openmesh_pm replay")[0], "splits_per_s", "peer_openmesh_pm")
        replay = replay or r
        worst = max(worst, error_of([inp.frames[t]], [fio.read_obj(full, False)[0]],
                                         False)[0])
    pos = 12 * inp.V * inp.T  # float32 xyz of every vertex, base and detail
    return [row("OpenMesh .pm", "ModQuadric + ModNormalFlipping + ModProgMesh, one file per "
                "frame", total, pos, total - pos, worst, enc, 1, replay["splits_per_s"],
                "%d splits per frame; splits/s: vertex_split replay of frame 0's file"
                % replay["splits"])]


# -------------------------------------------------------------------------------- gltfpack

def gltfpack_rows(inp, args, work):
    src = os.path.join(work, "morph.gltf")
    fio.write_morph_gltf(src, inp.frames, inp.tris)
    rows = []
    for bits in args.gltfpack_bits:
        plain = os.path.join(work, "gltfpack_vp%d.glb" % bits)
        packed = os.path.join(work, "gltfpack_vp%d_cc.glb" % bits)
        vp = ["-vp", str(bits)]
        times = {"": [], "-cc": []}
        for _ in range(args.runs):
            times[""].append(run(["gltfpack", "-i", src, "-o", plain, *vp], "gltfpack")[1])
            times["-cc"].append(run(["gltfpack", "-i", src, "-o", packed, "-cc", *vp],
                                    "gltfpack -cc")[1])
        err, _ = error_of(inp.frames, fio.read_morph_glb(plain), True)
        # -cc codes the same quantized values losslessly unless a bufferView has a filter
        doc_p, _ = fio.read_glb(plain)
        doc_c, _ = fio.read_glb(packed)
        filters = [v["extensions"]["EXT_meshopt_compression"].get("filter") for v in
                   doc_c["bufferViews"] if "EXT_meshopt_compression" in v.get("extensions", {})]
        same = doc_c["accessors"] == doc_p["accessors"] and not any(
            f and f != "NONE" for f in filters)
        for label, path, doc in (("", plain, doc_p), ("-cc", packed, doc_c)):
            total = os.path.getsize(path)
            pos = sum(fio.view_bytes(doc, v) for v in fio.position_views(doc))
            setting = " ".join(x for x in ("-vp %d" % bits + (" (default)" if bits == 14 else
                                                              ""), label) if x)
            rows.append(row("gltfpack morph targets", setting, total, pos, total - pos,
                            err if (label == "" or same) else None,
                            statistics.median(times[label]), args.runs, None,
                            "wall time of the process (reads a %.1f MB .gltf)"
                            % (os.path.getsize(src) / 1e6)))
    return rows


# ----------------------------------------------------------------------------------- Draco

def draco_rows(inp, args, work):
    rows = []
    for bits in args.draco_bits:
        total = enc = worst = 0.0
        for t, f in enumerate(inp.files):
            drc = os.path.join(work, "draco_qp%d_%03d.drc" % (bits, t))
            dec = os.path.join(work, "draco_qp%d_%03d.obj" % (bits, t))
            text, _ = run(["draco_encoder", "-i", f, "-o", drc, "-qp", str(bits),
                           "-cl", str(args.draco_cl)], "draco_encoder")
            m = re.search(r"\((\d+) ms to encode\)", text)
            enc += int(m.group(1)) / 1000 if m else 0.0
            total += os.path.getsize(drc)
            run(["draco_decoder", "-i", drc, "-o", dec], "draco_decoder")
            worst = max(worst, error_of([inp.frames[t]], [fio.read_obj(dec, False)[0]],
                                             False)[0])
        rows.append(row("Draco .drc", "-qp %d -cl %d, one file per frame" % (bits, args.draco_cl),
                        total, None, None, worst, enc, 1, None,
                        "encode: draco_encoder's own ms, summed over the frames"))
    return rows


# ------------------------------------------------------------------------------------ table

def fmt(v, spec):
    return "—" if v is None else spec % v


def table(inputs, results):
    lines = ["| input | V | steps | format | setting | file bytes | B/vertex/step | positions "
             "B/v/step | rest B/v/step | max error (diag) | encode s | runs | splits/s | notes |",
             "|---|---:|---:|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
    for inp in inputs:
        for r in results[inp.name]:
            lines.append("| %s | %s | %d | %s | %s | %s | %.2f | %s | %s | %s | %s | %s | %s | %s |"
                         % (inp.name, "{:,}".format(inp.V), inp.T, r["format"], r["setting"],
                            "{:,}".format(int(r["bytes"])), inp.per_vs(r["bytes"]),
                            fmt(r["pos_bytes"] and inp.per_vs(r["pos_bytes"]), "%.2f"),
                            fmt(r["rest_bytes"] and inp.per_vs(r["rest_bytes"]), "%.2f"),
                            fmt(r["max_error"], "%.2e"), fmt(r["encode_s"], "%.3g"),
                            fmt(r["runs"], "%d"),
                            fmt(r["splits_per_s"] and r["splits_per_s"] / 1e6, "%.2f M"),
                            r["note"]))
    return lines


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--inputs", nargs="+", default=DEFAULT_INPUTS,
                    help="directories holding frame_*.obj (or obj/frame_*.obj)")
    ap.add_argument("--max-frames", type=int, default=0, help="use the first N frames only")
    ap.add_argument("--formats", default="dynpm,openmesh,gltfpack,draco")
    ap.add_argument("--runs", type=int, default=3, help="runs of dynpm build and gltfpack")
    ap.add_argument("--dynpm", default=os.path.join(ROOT, "build", "release", "cli", "dynpm"))
    ap.add_argument("--navigator-bench", default=None,
                    help="build/…/bench/navigator_bench, for dynpm's splits/s")
    ap.add_argument("--peers-dir", default=os.path.join(ROOT, "build", "peers"))
    ap.add_argument("--draco-bits", default="18,14")
    ap.add_argument("--draco-cl", type=int, default=7, help="draco_encoder -cl (default 7)")
    ap.add_argument("--gltfpack-bits", default="14,16")
    ap.add_argument("--no-matched-bound", action="store_true",
                    help="skip the dynpm build at gltfpack -vp 14's measured error")
    ap.add_argument("--workdir", default=os.path.join(ROOT, "build", "peers", "formats"))
    ap.add_argument("--out", help="also write the table (markdown) here")
    ap.add_argument("--json-out", help="also write every row as JSON here")
    args = ap.parse_args()
    args.draco_bits = [int(b) for b in args.draco_bits.split(",")]
    args.gltfpack_bits = [int(b) for b in args.gltfpack_bits.split(",")]
    formats = args.formats.split(",")
    for tool in (["gltfpack"] if "gltfpack" in formats else []) + (
            ["draco_encoder", "draco_decoder"] if "draco" in formats else []):
        if not shutil.which(tool):
            sys.exit("format_bench: %s not found (apt-get install gltfpack draco)" % tool)

    started = datetime.datetime.now(datetime.timezone.utc)
    inputs, results = [], {}
    for path in args.inputs:
        inp = Input(path, args.max_frames)
        work = os.path.join(args.workdir, re.sub(r"[^A-Za-z0-9_.-]+", "_", inp.name))
        os.makedirs(work, exist_ok=True)
        log("%s: %d vertices, %d steps" % (inp.name, inp.V, inp.T))
        rows = []
        if "gltfpack" in formats:
            log("  gltfpack")
            rows += gltfpack_rows(inp, args, work)
        if "dynpm" in formats:
            log("  dynpm")
            bounds = [("default", None)]
            matched = [r["max_error"] for r in rows if r["setting"].startswith("-vp 14")]
            if matched and matched[0] and not args.no_matched_bound:
                bounds.append(("gltfpack14", matched[0]))
            rows = dynpm_rows(inp, args, work, bounds) + rows
        if "openmesh" in formats:
            log("  openmesh")
            rows += openmesh_rows(inp, args, work)
        if "draco" in formats:
            log("  draco")
            rows += draco_rows(inp, args, work)
        inputs.append(inp)
        results[inp.name] = rows

    info = machine_info()
    pkgs = subprocess.run(["dpkg-query", "-W", "-f", "${Package} ${Version}, ", *PACKAGES],
                          capture_output=True, text=True).stdout.strip().rstrip(",")
    lines = table(inputs, results) + [
        "",
        "Machine: %d cores, CPU \"%s\", %s RAM, %s. Packages: %s." % (
            info["nproc"], info["cpu_model"], info["memory"], info["os"], pkgs),
        "Run: %s → %s UTC, load average %.2f at the end (1 min)." % (
            started.strftime("%Y-%m-%d %H:%M"),
            datetime.datetime.now(datetime.timezone.utc).strftime("%H:%M"), os.getloadavg()[0]),
        "Command: `%s`" % " ".join([os.path.relpath(sys.argv[0], ROOT)] + sys.argv[1:]),
    ]
    text = "\n".join(lines)
    print(text)
    if args.out:
        with open(args.out, "w") as f:
            f.write(text + "\n")
    if args.json_out:
        with open(args.json_out, "w") as f:
            json.dump({"machine": info, "packages": pkgs, "inputs": [
                {"input": i.name, "vertices": i.V, "steps": i.T, "rows": results[i.name]}
                for i in inputs]}, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
