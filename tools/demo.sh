#!/usr/bin/env bash
# The main job on the bundled demo scene (make demo): describe the scene, render
# its frames (a bright LED frame and a dim laser frame) with ground truth, then
# extract, identify and triangulate the stripe of the dim frame, and evaluate the
# measurement against the ground truth (metrics.json, report.html).
set -euo pipefail
lasertwin=$1
out=$2
scene=scenes/demo/scene.json
echo "== lasertwin info $scene"
"$lasertwin" info "$scene"
echo
echo "== lasertwin render $scene --out $out"
rm -rf "$out"
"$lasertwin" render "$scene" --out "$out"
echo
echo "== lasertwin scan $out --method com"
"$lasertwin" scan "$out" --method com
echo
echo "== lasertwin eval $out"
"$lasertwin" eval "$out"
echo
echo "Results in $out/:"
echo "  frames/        camera images (16-bit PNG, raw 10-bit digital numbers)"
echo "  radiance/ gt/  linear radiance and ground truth (EXR), gt/*_centers.csv exact stripe centres"
echo "  centers/       measured stripe centres with their triangulated 3D points (CSV)"
echo "  cloud.ply      the triangulated point cloud"
echo "  metrics.json   measured against ground truth (docs/evaluation.md)"
echo "  report.html    the evaluation as one page: open it in a browser"
echo "  manifest.jsonl scene.json rig.json"
