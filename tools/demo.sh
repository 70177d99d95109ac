#!/usr/bin/env bash
# The main job on the bundled demo scene (make demo): describe the scene, render
# its frames (a bright LED frame and a dim laser frame) with ground truth, and
# extract the stripe from the dim frame.
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
dim=$(grep -l . "$out"/manifest.jsonl >/dev/null && python3 -c "
import json,sys
for line in open('$out/manifest.jsonl'):
    j = json.loads(line)
    if j['shutter']['laser_on']:
        print(j['files']['image'], j['gt_axis'], j['bit_depth']); break
")
read -r image axis bits <<<"$dim"
echo "== lasertwin extract $out/$image --method com --axis $axis"
"$lasertwin" extract "$out/$image" --method com --axis "$axis" --threshold $(( (1 << bits) / 10 )) \
  --out "$out/centers_com.csv"
echo
echo "results in $out/: frames/ (camera images), radiance/ and gt/ (EXR), gt/*_centers.csv (exact"
echo "stripe centres), manifest.jsonl, scene.json; stripe centres found by centre of mass in"
echo "$out/centers_com.csv"
