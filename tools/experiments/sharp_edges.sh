#!/usr/bin/env bash
# Extraction at sharp edges (docs/experiments.md): renders the sharp-edge part
# (scenes/sharp_edges), scans it with maximum search, centre of mass and
# Steger's method, and compares each with the exact stripe centres, separately
# near edges and on smooth surface.
#
#   tools/experiments/sharp_edges.sh [OUT_DIR]     (default: out/experiments/sharp_edges)
#
# Needs build/bin/lasertwin and build/bin/exp_edges (LT_BIN overrides the folder).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
bin=${LT_BIN:-$root/build/bin}
out=${1:-out/experiments/sharp_edges}
run="$out/run"
mkdir -p "$out"
"$bin/lasertwin" render "$root/scenes/sharp_edges/scene.json" --out "$run" --resume --quiet
methods=(max com steger)
for m in "${methods[@]}"; do
  # Steger's filter scale from the stripe's width here (FWHM about 3 px), not the width it measures
  # on each frame by default (5 px before StegerDefaults.WidthIsMeasuredOnTheFrame).
  extra=()
  if [ "$m" = steger ]; then extra=(--width 3); fi
  "$bin/lasertwin" scan "$run" --method "$m" "${extra[@]}" --quiet
  rm -rf "$run/centers_$m"
  cp -r "$run/centers" "$run/centers_$m"
done
"$bin/exp_edges" "$out" "$run" "${methods[@]}"
