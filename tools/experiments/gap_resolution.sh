#!/usr/bin/env bash
# Gap resolution experiment (docs/experiments.md, "Gap resolution"): renders the
# slot test part from 2, 3.5 and 5 inches (scenes/gap_resolution), scans each run
# and measures the slot widths against the part's geometry.
#
#   tools/experiments/gap_resolution.sh [OUT_DIR]     (default: out/experiments/gap_resolution)
#
# Needs build/bin/lasertwin and build/bin/exp_gap (LT_BIN overrides the folder).
# An interrupted run resumes where it stopped.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
bin=${LT_BIN:-$root/build/bin}
out=${1:-out/experiments/gap_resolution}
mkdir -p "$out"
runs=()
for d in 2in 3.5in 5in; do
  run="$out/run_$d"
  "$bin/lasertwin" render "$root/scenes/gap_resolution/gap_$d.json" --out "$run" --resume --quiet
  "$bin/lasertwin" scan "$run" --quiet
  runs+=("$d=$run")
done
"$bin/exp_gap" "$out" "$root/scenes/demo/test_part.glb" "${runs[@]}"
