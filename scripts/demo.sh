#!/usr/bin/env bash
# Installs what is missing, builds linx and runs the demo scene: a planar slider-crank driven by
# a hinge motor. It ends with a picture of the last frame (POV-Ray) and prints its path. It also
# builds the Python package into build/venv (scripts/python-venv.sh).
# Usage: scripts/demo.sh [SCENE.json] [OUT_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."

scene=${1:-examples/slider_crank.json}
out=${2:-out/$(basename "$scene" .json)}

scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DLINX_BUILD_TESTS=OFF >/dev/null
cmake --build build --target linx_cli linx_python
scripts/python-venv.sh build
build/linx run "$scene" --out "$out"
picture=$(build/linx render "$out" --frame last)
echo "demo: $scene simulated; trajectory in $out/bodies.csv, joints in $out/joints.csv, energies in $out/world.csv"
echo "demo: more pictures: build/linx render $out (a video), build/linx plot $out, build/linx view $out"
echo "demo: Python: build/venv/bin/python3 -c 'import linx' (or . build/venv/bin/activate; docs/python.md)"
echo "demo: picture of the last frame: $picture"
