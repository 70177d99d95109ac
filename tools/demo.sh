#!/usr/bin/env bash
# The main job on the bundled demo scene (make demo).
set -euo pipefail
lasertwin=$1
out=$2
scene=scenes/demo/scene.json
echo "== lasertwin info $scene"
"$lasertwin" info "$scene"
