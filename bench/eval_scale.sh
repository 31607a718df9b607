#!/bin/sh
# dynpm eval at scale (issue 18): a 1 M-vertex × 25-step animated plate, simplified by
# `dynpm build`, then measured at two ratios over every step, with time and peak memory from
# /usr/bin/time -v. The data is generated here (eval_bench --write-plate), never committed.
#
#   bench/eval_scale.sh BUILD_DIR WORK_DIR [extra eval flags…]
#
# BUILD_DIR holds dynpm and bench/eval_bench (a Release build with -DDYNPM_BUILD_BENCH=ON).
set -eu
build=$1 work=$2
shift 2
mkdir -p "$work/plate"
if [ ! -f "$work/plate/frame_024.ply" ]; then
  "$build/bench/eval_bench" --write-plate "$work/plate" --size 1000 --steps 25
fi
if [ ! -f "$work/plate.dpm" ]; then
  /usr/bin/time -f 'build: %e s, peak %M kB' \
    "$build/cli/dynpm" build "$work/plate/frame_*.ply" -o "$work/plate.dpm" --key-steps auto:3
fi
/usr/bin/time -v "$build/cli/dynpm" eval "$work/plate/frame_*.ply" --dpm "$work/plate.dpm" \
  --ratios 5,25 --json "$work/eval.json" "$@" 2> "$work/time.txt"
grep -E 'Elapsed|Maximum resident|User time|System time' "$work/time.txt"
