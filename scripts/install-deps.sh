#!/usr/bin/env bash
# Installs the Debian packages linx needs to build and test, only those missing.
# Usage: scripts/install-deps.sh [--peers]   (--peers adds ODE, Bullet, MuJoCo, DART and Simbody for bench/)
# clang builds the fuzz harnesses (scripts/fuzz.sh), curl tests the viewer server.
# Pictures (docs/visualization.md): povray renders frames, ffmpeg makes videos, gnuplot plots,
# cpp-httplib serves the viewer, whose page is bundled by npm (three.js) at build time and tested
# in Chromium. Node.js and npm come from Debian unless the machine already has them.
# Python (docs/python.md): pybind11 builds the module for Debian's python3 with numpy; pytest,
# dask.distributed and matplotlib run its tests, sweeps and examples; venv for installing it.
set -euo pipefail

packages=(build-essential cmake ninja-build pkg-config libeigen3-dev nlohmann-json3-dev libcli11-dev
          libfmt-dev libgtest-dev libgmock-dev libbenchmark-dev libqhull-dev
          libtinyobjloader-dev liburdfdom-dev libtinyxml2-dev zlib1g-dev libmujoco-dev libmujoco-samples
          povray ffmpeg gnuplot-nox fonts-dejavu-core libpng-dev libcpp-httplib-dev chromium curl clang
          python3-dev pybind11-dev python3-numpy python3-pytest python3-distributed python3-matplotlib
          python3-venv)
if ! command -v npm >/dev/null || ! command -v node >/dev/null; then packages+=(nodejs npm); fi
if [[ "${1:-}" == "--peers" ]]; then packages+=(libode-dev libbullet-dev libmujoco-dev libdart-dev libsimbody-dev); fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [[ ${#missing[@]} -eq 0 ]]; then exit 0; fi

echo "linx: installing ${missing[*]}" >&2
sudo=()
if [[ $(id -u) -ne 0 ]]; then sudo=(sudo); fi
"${sudo[@]}" apt-get update -qq
DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
