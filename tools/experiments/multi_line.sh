#!/usr/bin/env bash
# Multi-line scan (docs/experiments.md): renders the sharp-edge part under a
# 5-sheet laser (scenes/multi_line), scans it with multi-maximum centre of mass
# and Steger's method (plane identification numbers the stripes), and compares
# plane numbers and 3D points with the exact stripe centres.
#
#   tools/experiments/multi_line.sh [OUT_DIR]     (default: out/experiments/multi_line)
#
# Needs build/bin/lasertwin and build/bin/exp_multiline (LT_BIN overrides the folder).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
bin=${LT_BIN:-$root/build/bin}
out=${1:-out/experiments/multi_line}
run="$out/run"
mkdir -p "$out"
"$bin/lasertwin" render "$root/scenes/multi_line/scene.json" --out "$run" --resume --quiet
methods=(multicom steger)
for m in "${methods[@]}"; do
  "$bin/lasertwin" scan "$run" --method "$m" --quiet
  rm -rf "$run/centers_$m"
  cp -r "$run/centers" "$run/centers_$m"
done
"$bin/exp_multiline" "$out" "$run" "${methods[@]}"
