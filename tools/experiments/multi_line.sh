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
  # Steger's filter scale from the stripe's width here (FWHM about 3 px), not the width it measures
  # on each frame by default (5 px before StegerDefaults.WidthIsMeasuredOnTheFrame).
  extra=()
  if [ "$m" = steger ]; then extra=(--width 3); fi
  # The thesis's setup: its edge chains need every stripe to cross the searched
  # region from its start edge, so search the columns where the stripes lie on
  # the part (x within +-18 mm at 80 mm), not the dark print bed beside it. The
  # part's steps move a stripe by up to 9 px between neighbouring columns: link
  # across such jumps. (The whole frame: docs/experiments.md.)
  "$bin/lasertwin" scan "$run" --method "$m" "${extra[@]}" --roi 110,0,420,512 --link-distance 10 --quiet
  rm -rf "$run/centers_$m"
  cp -r "$run/centers" "$run/centers_$m"
done
"$bin/exp_multiline" "$out" "$run" "${methods[@]}" --lines 110,529
