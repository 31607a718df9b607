#!/usr/bin/env python3
"""Single-word corruptions of an Exodus file, each run through `dynpm info`; counts the runs
that ended by a signal (a crash). Issue 16 found SIGSEGVs inside libhdf5 this way on
vtkdata_biplane_rms_pressure_bs.exo (netCDF-4), bytes 7,780 to 11,860.

  fuzz/exodus_word_flips.py DYNPM FILE [--start 7780 --end 11860 --step 4 --keep DIR]

Every aligned 32-bit word in [start, end) is replaced in turn by each of a few values
(all ones, zero, its bytes inverted, a large count); --keep copies the crashing files to DIR."""
import argparse, concurrent.futures, os, shutil, signal, subprocess, sys, tempfile

VALUES = [b"\xff\xff\xff\xff", b"\x00\x00\x00\x00", None, b"\x00\x00\x00\x7f"]  # None: invert


def run(dynpm, data, offset, value, tmp):
    word = bytes(b ^ 0xFF for b in data[offset:offset + 4]) if value is None else value
    path = os.path.join(tmp, f"flip-{offset}-{VALUES.index(value)}.exo")
    with open(path, "wb") as f:
        f.write(data[:offset] + word + data[offset + 4:])
    try:
        p = subprocess.run([dynpm, "info", path], stdout=subprocess.DEVNULL,
                           stderr=subprocess.PIPE, timeout=120)
        rc, err = p.returncode, p.stderr.decode(errors="replace")
    except subprocess.TimeoutExpired:
        rc, err = "timeout", ""
    return path, rc, err


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("dynpm")
    ap.add_argument("file")
    ap.add_argument("--start", type=int, default=7780)
    ap.add_argument("--end", type=int, default=11860)
    ap.add_argument("--step", type=int, default=4)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--keep")
    a = ap.parse_args()
    data = open(a.file, "rb").read()
    counts = {"ok": 0, "error": 0, "signal": 0, "timeout": 0}
    with tempfile.TemporaryDirectory() as tmp, \
            concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
        jobs = [pool.submit(run, a.dynpm, data, o, v, tmp)
                for o in range(a.start, min(a.end, len(data) - 3), a.step) for v in VALUES]
        for job in concurrent.futures.as_completed(jobs):
            path, rc, err = job.result()
            if rc == "timeout":
                counts["timeout"] += 1
            elif rc < 0:
                counts["signal"] += 1
                print(f"{os.path.basename(path)}: {signal.Signals(-rc).name}", flush=True)
                if a.keep:
                    os.makedirs(a.keep, exist_ok=True)
                    shutil.copy(path, a.keep)
            else:
                counts["ok" if rc == 0 else "error"] += 1
    print(" ".join(f"{k} {v}" for k, v in counts.items()), f"of {len(jobs)}")
    return 1 if counts["signal"] or counts["timeout"] else 0


if __name__ == "__main__":
    sys.exit(main())
