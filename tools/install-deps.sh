#!/usr/bin/env bash
# Installs, with apt-get, the Debian 12 packages lasertwin needs that are missing.
# Idempotent; prints nothing when everything is already there. Run as root
# (or with sudo available).
set -euo pipefail

packages=(
  cmake g++ make ninja-build pkg-config git
  libembree-dev          # ray tracing kernels (Embree 3)
  libopenimageio-dev     # PNG/TIFF/EXR reading and writing
  libopenexr-dev
  libtinygltf-dev        # glTF 2.0 parsing
  libglm-dev
  libeigen3-dev          # linear algebra, poses
  libtbb-dev             # parallel loops
  libgtest-dev libgmock-dev
  libbenchmark-dev       # Google Benchmark
  nlohmann-json3-dev     # JSON
  libcli11-dev           # command-line parsing
  python3 python3-jsonschema  # validates the scene JSON Schema in a test
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null; then SUDO="sudo"; else
    echo "install-deps: missing packages (${missing[*]}) and not root; run as root" >&2
    exit 1
  fi
fi
echo "install-deps: installing ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq >/dev/null
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
