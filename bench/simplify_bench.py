#!/usr/bin/python3
"""Side-by-side benchmark of mesh simplifiers (dynpm and its peers, docs/peers.md).

Every simplifier is a command template. It is run as-is (no shell) after substituting
{input}, {output}, {target} (vertex count) and {ratio} (target / input vertices), and must
write the simplified mesh to {output} (OBJ, quads allowed) and print one JSON object on
stdout (one line, or pretty-printed at the end of the output) with at least

    {"vertices_out": int, "faces_out": int, "seconds": float}

("seconds" = simplification only, no file I/O). Optional keys: "peer", "input",
"vertices_in", "faces_in", "target_vertices", "peak_rss_mb" (if missing, the runner polls
the child's VmHWM every 5 ms: it can miss a peak in the last few ms and sees only that
process, not its children), plus any extra keys (kept in --json-out).

The Hausdorff command template gets {a} (the input, reference of the % diagonal) and {b} (the
simplified output) and must print a JSON line with "hausdorff_pct".

Each (input, target, peer) is run --runs times: median seconds, max peak RSS; the Hausdorff
distance is measured on the last run's output. Prints one markdown table (with the machine
and the command) on stdout; progress goes to stderr.

Example:
  /usr/bin/python3 bench/simplify_bench.py \\
      --dynpm-cmd "build/release/cli/dynpm simplify {input} -o {output} --vertices {target} --json" \\
      --hausdorff-cmd "build/release/cli/dynpm hausdorff {a} {b} --json"
"""

import argparse
import datetime
import json
import os
import platform
import re
import shlex
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = os.path.normpath(os.path.join(ROOT, "..", "shared", "data"))  # ../shared beside the project

DEFAULT_INPUTS = [
    os.path.join(SHARED, "meshes", "bunny.obj"),
    os.path.join(SHARED, "meshes", "dragon.obj"),
    os.path.join(SHARED, "crashbox-s", "obj", "frame_000.obj"),
    os.path.join(SHARED, "crashbox-s", "obj", "frame_025.obj"),
]

# name -> template; {peers_dir} is replaced by --peers-dir first.
PEERS = {
    "meshoptimizer": "{peers_dir}/peer_meshopt {input} -o {output} --vertices {target}",
    "openmesh": "{peers_dir}/peer_openmesh {input} -o {output} --vertices {target}",
    "cgal": "{peers_dir}/peer_cgal {input} -o {output} --vertices {target}",
    "cgal-lt": "{peers_dir}/peer_cgal_lt {input} -o {output} --vertices {target}",
    "meshlab": "/usr/bin/python3 " + os.path.join(ROOT, "bench", "peers", "peer_meshlab.py")
               + " {input} -o {output} --vertices {target}",
}
DEFAULT_HAUSDORFF = "{peers_dir}/hausdorff_cgal {a} {b} --json"


def log(*a):
    print(*a, file=sys.stderr, flush=True)


def count_obj(path):
    """(vertices, faces, quads) of an OBJ file."""
    v = f = q = 0
    with open(path, "rb") as fh:
        for line in fh:
            if line.startswith(b"v "):
                v += 1
            elif line.startswith(b"f "):
                f += 1
                if len(line.split()) == 5:
                    q += 1
    return v, f, q


def expand(template, values):
    """Splits a template like a shell would, then substitutes {key} in every word."""
    words = shlex.split(template)
    out = []
    for w in words:
        for k, val in values.items():
            w = w.replace("{" + k + "}", str(val))
        out.append(w)
    return out


def vm_hwm_kb(pid):
    """VmHWM (peak RSS, KiB) of a running process, 0 if unreadable."""
    try:
        with open("/proc/%d/status" % pid) as f:
            for line in f:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1])
    except (OSError, ValueError):
        pass
    return 0


def run_cmd(argv, timeout):
    """Runs argv; returns (rc, stdout, stderr, wall seconds, child peak RSS in MB).

    The RSS is the child's VmHWM polled every 5 ms (the last value before it exits), or wait4's
    ru_maxrss if never read (that one can include this Python's pages: Linux keeps the pre-exec
    high-water mark)."""
    t0 = time.monotonic()
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        try:
            p = subprocess.Popen(argv, stdout=out, stderr=err, stdin=subprocess.DEVNULL)
        except OSError as e:
            return 127, "", str(e), 0.0, 0.0
        deadline = t0 + timeout
        hwm_kb = 0
        while True:
            pid, status, ru = os.wait4(p.pid, os.WNOHANG)
            if pid:
                break
            hwm_kb = max(hwm_kb, vm_hwm_kb(p.pid))
            if time.monotonic() > deadline:
                p.kill()
                pid, status, ru = os.wait4(p.pid, 0)
                p.returncode = -9
                return -9, "", "timeout after %gs" % timeout, time.monotonic() - t0, ru.ru_maxrss / 1024
            time.sleep(0.005)
        p.returncode = os.waitstatus_to_exitcode(status)
        wall = time.monotonic() - t0
        out.seek(0)
        err.seek(0)
        rss_kb = hwm_kb if hwm_kb else ru.ru_maxrss
        return (p.returncode, out.read().decode(errors="replace"), err.read().decode(errors="replace"),
                wall, rss_kb / 1024)


def last_json(text, key):
    """The last JSON object on stdout holding `key`: a single line, or a pretty-printed
    object running to the end of the output (e.g. dynpm's --json)."""
    lines = text.strip().splitlines()
    for i in range(len(lines) - 1, -1, -1):
        if not lines[i].lstrip().startswith("{"):
            continue
        for chunk in (lines[i], "\n".join(lines[i:])):
            try:
                d = json.loads(chunk)
            except ValueError:
                continue
            if isinstance(d, dict) and key in d:
                return d
    return None


def failure(rc, err, what):
    last = (err.strip().splitlines() or [""])[-1][:200]
    if rc == 0:
        return "no JSON with %s on stdout" % what
    return "failed (rc %d): %s" % (rc, last)


def machine_info():
    model = "unknown"
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    model = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    mem = ""
    try:
        with open("/proc/meminfo") as f:
            kb = int(re.search(r"MemTotal:\s+(\d+)", f.read()).group(1))
            mem = "%.1f GiB" % (kb / 1024 / 1024)
    except (OSError, AttributeError):
        pass
    distro = ""
    try:
        with open("/etc/os-release") as f:
            m = re.search(r'PRETTY_NAME="([^"]*)"', f.read())
            distro = m.group(1) if m else ""
    except OSError:
        pass
    pkgs = ""
    try:
        pkgs = subprocess.run(
            ["dpkg-query", "-W", "-f", "${Package} ${Version}, ",
             "libmeshoptimizer-dev", "libopenmesh-dev", "libcgal-dev", "g++"],
            capture_output=True, text=True).stdout.strip().rstrip(",")
    except OSError:
        pass
    return {
        "nproc": os.cpu_count(),
        "cpu_model": model,
        "memory": mem,
        "os": distro,
        "kernel": platform.release(),
        "packages": pkgs,
        "python": platform.python_version(),
    }


def parse_kv(items, conv):
    out = []
    for it in items or []:
        k, _, v = it.partition("=")
        if not _:
            sys.exit("expected PATTERN=VALUE, got %r" % it)
        out.append((k, conv(v)))
    return out


def match_override(path, overrides, default):
    for pat, val in overrides:
        if pat in path:
            return val
    return default


def fmt_int(n):
    return "{:,}".format(n) if isinstance(n, int) else str(n)


def fmt_secs(s):
    if s is None:
        return "—"
    return "%.4f" % s if s < 0.1 else ("%.3f" % s if s < 10 else "%.2f" % s)


def notes_for(res):
    d = res["json"]
    first = res["json_first"]
    n = []
    if d.get("seconds_estimated"):
        n.append("seconds ≈ wall %s − load/save-only wall %s (last run)" % (
            fmt_secs(d.get("seconds_wall_with_io")), fmt_secs(d.get("seconds_wall_io_only"))))
    if first.get("search_calls"):
        what = "face" if "target_faces" in first else "index"
        n.append("%s-target search: %d call%s, %s s" % (
            what, first["search_calls"], "" if first["search_calls"] == 1 else "s",
            fmt_secs(first.get("search_seconds"))))
    if d.get("stalled"):
        n.append("stopped short of target")
    if d.get("faces_rejected"):
        n.append("%d faces rejected" % d["faces_rejected"])
    if d.get("vertices_duplicated"):
        n.append("%d vertices duplicated (non-manifold)" % d["vertices_duplicated"])
    if len(set(res["vertices_out_all"])) > 1:
        n.append("V out varies: %s" % sorted(set(res["vertices_out_all"])))
    if res.get("rss_from_wait4"):
        n.append("RSS polled by the runner")
    if res.get("error"):
        n.append(res["error"])
    return "; ".join(n)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--inputs", nargs="+", default=DEFAULT_INPUTS, help="OBJ inputs")
    ap.add_argument("--targets", default="25,5,1", help="target vertex counts in %% of the input's (default 25,5,1)")
    ap.add_argument("--input-targets", action="append", metavar="PATTERN=LIST",
                    help="targets for inputs whose path contains PATTERN, e.g. dragon=25")
    ap.add_argument("--runs", type=int, default=3, help="runs per (input, target, peer) (default 3)")
    ap.add_argument("--input-runs", action="append", metavar="PATTERN=N",
                    help="runs for inputs whose path contains PATTERN, e.g. dragon=1")
    ap.add_argument("--peers-dir", default=os.path.join(ROOT, "build", "peers"), help="where the peer drivers are")
    default_peers = [p for p in PEERS if p != "meshlab" or (shutil.which("meshlabserver") and shutil.which("Xvfb"))]
    ap.add_argument("--peers", default=",".join(default_peers),
                    help="built-in peers to run (default: %(default)s; meshlab only if meshlabserver and Xvfb exist)")
    ap.add_argument("--peer-cmd", action="append", metavar="NAME=TEMPLATE", help="an extra simplifier")
    ap.add_argument("--dynpm-cmd", metavar="TEMPLATE", help="dynpm's simplifier (same as --peer-cmd dynpm=TEMPLATE)")
    ap.add_argument("--hausdorff-cmd", default=DEFAULT_HAUSDORFF, metavar="TEMPLATE",
                    help="Hausdorff tool: {a} input, {b} output; prints JSON with hausdorff_pct (default: %(default)s)")
    ap.add_argument("--no-hausdorff", action="store_true")
    ap.add_argument("--workdir", help="keep outputs here (default: a temporary directory, removed)")
    ap.add_argument("--timeout", type=float, default=1800, help="seconds per command (default 1800)")
    ap.add_argument("--out", help="also write the markdown here")
    ap.add_argument("--json-out", help="write all raw results here (JSON)")
    args = ap.parse_args()

    peers = []
    for name in [p for p in args.peers.split(",") if p]:
        if name not in PEERS:
            sys.exit("unknown peer %r (known: %s)" % (name, ", ".join(PEERS)))
        peers.append((name, PEERS[name].replace("{peers_dir}", args.peers_dir)))
    for name, tmpl in parse_kv(args.peer_cmd, str):
        peers.append((name, tmpl))
    if args.dynpm_cmd:
        peers.append(("dynpm", args.dynpm_cmd))
    hcmd = args.hausdorff_cmd.replace("{peers_dir}", args.peers_dir)

    targets = [float(t) for t in args.targets.split(",")]
    tgt_over = parse_kv(args.input_targets, lambda v: [float(t) for t in v.split(",")])
    runs_over = parse_kv(args.input_runs, int)

    tmp = None
    if args.workdir:
        workdir = args.workdir
        os.makedirs(workdir, exist_ok=True)
    else:
        tmp = tempfile.TemporaryDirectory(prefix="simplify_bench_")
        workdir = tmp.name

    info = machine_info()
    info["loadavg_start"] = os.getloadavg()
    started = datetime.datetime.now().astimezone()
    cmdline = " ".join(shlex.quote(a) for a in ["/usr/bin/python3", os.path.relpath(__file__, os.getcwd())] + sys.argv[1:])

    results = []
    for inp in args.inputs:
        vin, fin, qin = count_obj(inp)
        runs = match_override(inp, runs_over, args.runs)
        for pct in match_override(inp, tgt_over, targets):
            target = max(3, int(round(vin * pct / 100.0)))
            for name, tmpl in peers:
                stem = "%s__%s__%g__%s.obj" % (os.path.splitext(os.path.basename(inp))[0],
                                              os.path.basename(os.path.dirname(inp)), pct, name)
                outp = os.path.join(workdir, stem)
                values = {"input": inp, "output": outp, "target": target, "ratio": "%.6g" % (target / vin)}
                argv = expand(tmpl, values)
                res = {"peer": name, "input": inp, "vertices_in": vin, "faces_in": fin, "quads_in": qin,
                       "target_pct": pct, "target_vertices": target, "runs_requested": runs,
                       "seconds_all": [], "rss_all": [], "vertices_out_all": [], "command": argv}
                for r in range(runs):
                    log("[%s] %s %g%% (%d) run %d/%d" % (name, os.path.basename(inp), pct, target, r + 1, runs))
                    rc, out, err, wall, rss = run_cmd(argv, args.timeout)
                    d = last_json(out, "vertices_out") if rc == 0 else None
                    if d is None or not os.path.exists(outp):
                        res["error"] = (failure(rc, err, "vertices_out") if d is None
                                        else "no output file %s" % outp)
                        log("  " + res["error"])
                        break
                    res["json"] = d
                    res.setdefault("json_first", d)
                    res["seconds_all"].append(float(d["seconds"]))
                    # The command's own figure wins over the polled one.
                    res["rss_all"].append(float(d["peak_rss_mb"]) if "peak_rss_mb" in d else rss)
                    res["rss_from_wait4"] = "peak_rss_mb" not in d
                    res["vertices_out_all"].append(int(d["vertices_out"]))
                    res["wall_all"] = res.get("wall_all", []) + [wall]
                if res["seconds_all"]:
                    d = res["json"]
                    res["runs"] = len(res["seconds_all"])
                    res["seconds"] = statistics.median(res["seconds_all"])
                    res["peak_rss_mb"] = max(res["rss_all"])
                    res["vertices_out"] = int(d["vertices_out"])
                    res["faces_out"] = int(d["faces_out"])
                    if not args.no_hausdorff:
                        hargv = expand(hcmd, {"a": inp, "b": outp, "input": inp, "output": outp})
                        log("  hausdorff: " + " ".join(hargv))
                        rc, out, err, wall, _ = run_cmd(hargv, args.timeout)
                        h = last_json(out, "hausdorff_pct") if rc == 0 else None
                        if h is None:
                            res["hausdorff_error"] = failure(rc, err, "hausdorff_pct")
                            log("  hausdorff failed: " + res["hausdorff_error"])
                        else:
                            res["hausdorff_pct"] = float(h["hausdorff_pct"])
                            res["hausdorff_json"] = h
                results.append(res)

    info["loadavg_end"] = os.getloadavg()
    finished = datetime.datetime.now().astimezone()

    lines = []
    lines.append("Machine: %d cores (`nproc`), CPU model \"%s\", %s RAM, %s, kernel %s." % (
        info["nproc"], info["cpu_model"], info["memory"], info["os"], info["kernel"]))
    lines.append("Packages: %s." % info["packages"])
    lines.append("Run: %s → %s, load average %.2f at start, %.2f at end (1 min)." % (
        started.strftime("%Y-%m-%d %H:%M %Z"), finished.strftime("%H:%M"),
        info["loadavg_start"][0], info["loadavg_end"][0]))
    lines.append("")
    lines.append("Command: `%s`" % cmdline)
    lines.append("Hausdorff: `%s`" % ("(not measured)" if args.no_hausdorff else hcmd))
    lines.append("")
    lines.append("| input | V in | F in | target | peer | V out | F out | seconds (median) | runs | peak RSS MB (max) | Hausdorff % diag | notes |")
    lines.append("|---|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---|")
    for r in results:
        name = os.path.relpath(r["input"], SHARED) if r["input"].startswith(SHARED) else r["input"]
        fin = fmt_int(r["faces_in"]) + (" quads" if r["quads_in"] == r["faces_in"] else
                                        (" (%s quads)" % fmt_int(r["quads_in"]) if r["quads_in"] else " tris"))
        if "seconds" in r:
            h = "%.3f" % r["hausdorff_pct"] if "hausdorff_pct" in r else "—"
            spread = ""
            if len(r["seconds_all"]) > 1:
                spread = " (%s–%s)" % (fmt_secs(min(r["seconds_all"])), fmt_secs(max(r["seconds_all"])))
            lines.append("| %s | %s | %s | %g%% (%s) | %s | %s | %s | %s%s | %d | %.1f | %s | %s |" % (
                name, fmt_int(r["vertices_in"]), fin, r["target_pct"], fmt_int(r["target_vertices"]), r["peer"],
                fmt_int(r["vertices_out"]), fmt_int(r["faces_out"]),
                ("≈" if r["json"].get("seconds_estimated") else "") + fmt_secs(r["seconds"]), spread, r["runs"],
                r["peak_rss_mb"], h, notes_for(r) + ("; hausdorff " + r["hausdorff_error"] if "hausdorff_error" in r else "")))
        else:
            lines.append("| %s | %s | %s | %g%% (%s) | %s | — | — | — | 0 | — | — | %s |" % (
                name, fmt_int(r["vertices_in"]), fin, r["target_pct"], fmt_int(r["target_vertices"]), r["peer"],
                r.get("error", "")))
    md = "\n".join(lines) + "\n"
    sys.stdout.write(md)
    if args.out:
        with open(args.out, "w") as f:
            f.write(md)
    if args.json_out:
        with open(args.json_out, "w") as f:
            json.dump({"machine": info, "command": cmdline, "started": started.isoformat(),
                       "finished": finished.isoformat(), "results": results}, f, indent=1)
    if tmp:
        tmp.cleanup()
    return 0 if all("seconds" in r for r in results) else 1


if __name__ == "__main__":
    sys.exit(main())
