#!/usr/bin/env bash
# Makes BUILD/venv: a virtual environment of Debian's python3 (its numpy, dask and matplotlib
# through --system-site-packages) with the linx package of BUILD installed in it, wheel-free, by
# `cmake --install BUILD --component python`. Then `BUILD/venv/bin/python3 -c "import linx"`, or
# `. BUILD/venv/bin/activate` and plain `python3`. Usage: scripts/python-venv.sh [BUILD]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
python=$(sed -n 's/^Python_EXECUTABLE:[A-Z]*=//p' "$build/CMakeCache.txt")
if [[ ! -x "$build/venv/bin/python3" ]]; then
  "${python:-/usr/bin/python3}" -m venv --system-site-packages "$build/venv"
fi
cmake --install "$build" --component python --prefix "$(realpath "$build")/venv" >/dev/null
"$build/venv/bin/python3" -c "import linx" # fails loudly if the package does not import
