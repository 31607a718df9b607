#!/bin/sh
# What a .dpm's split records and attributes cost, part by part (issue 19 item 1: ≤ 4 B per
# vertex for everything that is not a position): builds the shared CalculiX crash boxes and the
# hat rail at the default bound (key steps all), and, when given, more inputs (a tiled set of
# bench/scale_inputs.py write, built with --key-steps auto:3), then prints
# tests/split_records_dump's groups as a markdown table, the parts of each below it, and the
# whole file in bytes per vertex per step. Inputs are unpacked and built in WORK_DIR.
#
#   bench/record_parts.sh BUILD_DIR WORK_DIR [EXTRA_INPUT…]
#
# BUILD_DIR holds cli/dynpm and tests/split_records_dump (a build with -DDYNPM_BUILD_TESTS=ON).
set -eu
build=$1 work=$2
shift 2
here=$(cd "$(dirname "$0")/.." && pwd)
data="$here/../shared/data"
mkdir -p "$work"

echo "| input | vertices × steps | records + attributes, B/vertex | parent | wings | moved | errors | vertex ids | face ids | whole file, B/vertex/step |"
echo "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|"
parts=""
measure() {  # name, input, build flags…
  name=$1 input=$2
  shift 2
  "$build/cli/dynpm" build "$input" -o "$work/$name.dpm" --quiet "$@" > /dev/null
  out=$("$build/tests/split_records_dump" "$work/$name.dpm")
  vertices=$(echo "$out" | sed -n 's/.*: V \([0-9]*\), splits.*/\1/p')
  steps=$(echo "$out" | sed -n 's/.*, steps \([0-9]*\)$/\1/p')
  total=$(echo "$out" | sed -n 's/^B\/vertex  range-coded: .* total \([0-9.]*\)$/\1/p')
  groups=$(echo "$out" | sed -n 's/^groups B\/vertex: //p' |
    sed 's/parent \(.*\) wings \(.*\) moved \(.*\) errors \(.*\) vertex ids \(.*\) face ids \(.*\)/\1 | \2 | \3 | \4 | \5 | \6/')
  size=$(wc -c < "$work/$name.dpm")
  whole=$(awk "BEGIN { printf \"%.3f\", $size / ($vertices * $steps) }")
  echo "| $name | $vertices × $steps | $total | $groups | $whole |"
  parts="$parts
$name: $(echo "$out" | sed -n 's/^parts B\/vertex: //p')"
}

for box in crashbox-s crashbox-mixed-5k crashbox-fields; do
  [ -f "$work/$box.frd" ] || gunzip -c "$data/$box/$box.frd.gz" > "$work/$box.frd"
  measure "$box" "$work/$box.frd"
done
[ -f "$work/rail.frd" ] || gunzip -c "$here/data/hat-rail/rail.frd.gz" > "$work/rail.frd"
measure hat-rail "$work/rail.frd"
for input in "$@"; do
  measure "$(basename "$input" | sed 's/\.[^.]*$//')" "$input" --key-steps auto:3
done
echo "$parts"
