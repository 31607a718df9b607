#!/usr/bin/env bash
# 'dynpm batch --slurm' on a real Slurm: a one-node cluster on this machine
# (scripts/slurm/local_cluster.sh), three real CalculiX variants submitted as a job array and the
# catalogue job after it; checks the three .dpm files, their logs and index.json, then submits the
# same batch again (every task must skip its up-to-date file). The cluster is stopped on any exit.
# Usage: slurm_batch.sh DYNPM SOURCE_DIR SHARED_DATA. Exit 77 (skipped) only when the cluster's
# daemons cannot start, and then not where DYNPM_REQUIRE_THIRD_PARTY=1 (the project's test run).
set -euo pipefail
dynpm="$1" source_dir="$2" shared="$3"
cluster="$source_dir/scripts/slurm/local_cluster.sh"
work="$(mktemp -d "${TMPDIR:-/tmp}/dynpm-slurm-test-XXXXXX")"
export DYNPM_SLURM_DIR="$work/cluster"
cleanup() {
  "$cluster" stop || echo "slurm_batch: stopping the cluster failed" >&2
  rm -rf "$work"
}
trap cleanup EXIT
fail() {
  echo "slurm_batch: FAILED: $*" >&2
  for f in "$work"/out/logs/*; do [ -f "$f" ] && { echo "== $f" >&2; tail -n 5 "$f" >&2; }; done
  exit 1
}

if ! "$cluster" start >"$work/start.txt" 2>&1; then
  cat "$work/start.txt" >&2
  [ "${DYNPM_REQUIRE_THIRD_PARTY:-}" = "1" ] && fail "the local Slurm cluster did not start"
  echo "slurm_batch: SKIPPED: the local Slurm cluster's daemons could not start (above)" >&2
  exit 77
fi
export SLURM_CONF="$DYNPM_SLURM_DIR/slurm.conf"

# Three variants, one with a space in its folder's name (the scripts must quote it).
mkdir -p "$work/runs/set A"
zcat "$shared/crashbox-s/crashbox-s.frd.gz" >"$work/runs/set A/crashbox-s.frd"
zcat "$shared/crashbox-mixed-5k/crashbox-mixed-5k.frd.gz" >"$work/runs/set A/mixed.frd"
zcat "$shared/crashbox-fields/crashbox-fields.frd.gz" >"$work/runs/fields.frd"
printf '# three CalculiX runs\nset A/*.frd\n\nfields.frd\n' >"$work/runs/list.txt"

# Waits until none of the jobs is queued or running (at most $2 s).
wait_for_jobs() {
  local ids="$1" limit="$2" waited=0
  while [ -n "$(squeue -h -j "$ids" -o %i 2>/dev/null)" ]; do
    [ "$waited" -ge "$limit" ] && fail "jobs $ids still queued after $limit s: $(squeue)"
    sleep 1
    waited=$((waited + 1))
  done
}

submit() {
  "$dynpm" batch "$work/runs/list.txt" --out "$work/out" --slurm --time 00:05:00 \
    --max-running 2 --key-steps paper >"$work/submitted.txt" || fail "dynpm batch --slurm"
  cat "$work/submitted.txt"
  array=$(sed -n 's/^array job \([0-9]*\): 3 builds$/\1/p' "$work/submitted.txt")
  catalogue=$(sed -n 's/^catalogue job \([0-9]*\): .*/\1/p' "$work/submitted.txt")
  [ -n "$array" ] && [ -n "$catalogue" ] || fail "no job ids in: $(cat "$work/submitted.txt")"
  wait_for_jobs "$array,$catalogue" 90
}

submit
for name in crashbox-s mixed fields; do
  [ -f "$work/out/$name.dpm" ] || fail "no $name.dpm"
  grep -q "built" "$work/out/logs/slurm-${array}_"*.out || fail "no task says 'built'"
done
# The builds' vertices, as dynpm info reads them back, and the index's.
python3 - "$work/out" "$dynpm" <<'PY' || fail "index.json"
import json, subprocess, sys
out, dynpm = sys.argv[1], sys.argv[2]
index = json.load(open(out + "/index.json"))
assert index["format"] == "dynpm-catalogue" and index["problems"] == [], index
entries = {e["name"]: e for e in index["entries"]}
assert sorted(entries) == ["crashbox-s", "fields", "mixed"], sorted(entries)
expected = {"crashbox-s": (3003, 26, "crashbox-s.frd"), "mixed": (4929, 41, "mixed.frd"),
            "fields": (5658, 15, "fields.frd")}
for name, (vertices, steps, source) in expected.items():
    e = entries[name]
    info = json.loads(subprocess.run([dynpm, "info", out + "/" + e["path"], "--json"],
                                     check=True, capture_output=True, text=True).stdout)
    assert e["vertices"] == vertices == info["vertices"], (name, e["vertices"], info["vertices"])
    assert e["steps"] == steps == info["steps"], (name, e["steps"])
    assert e["source"] == source and e["bytes"] == info["bytes"], (name, e)
fields = {f["name"] for f in entries["fields"]["fields"]}
assert fields and not entries["crashbox-s"]["fields"], fields
print("index.json: 3 entries, fields of fields.dpm:", sorted(fields))
PY

# Idempotent by task id: the same batch again skips every variant and leaves the files alone.
before=$(stat -c %Y "$work"/out/*.dpm)
rm -f "$work"/out/logs/slurm-*.out
submit
[ "$(grep -l "skipped" "$work/out/logs/slurm-${array}_"*.out | wc -l)" = 3 ] ||
  fail "a second submission rebuilt a variant"
[ "$before" = "$(stat -c %Y "$work"/out/*.dpm)" ] || fail "a second submission changed a .dpm"
[ -f "$work/out/index.json" ] || fail "no index.json after the second submission"
echo "slurm_batch: 3 variants built by a Slurm job array, catalogue written, resubmission skipped"
