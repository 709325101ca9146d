#!/usr/bin/env bash
# Installs the Debian 12 packages polyaxis builds and tests with, only when one is missing, then
# the viewer's npm packages (viewer/package-lock.json) when they are missing or out of date.
# Run as root (or with sudo). Idempotent: a machine that has everything is not touched.
set -euo pipefail
packages=(
  # toolchain
  build-essential cmake pkg-config ccache clang-14 libclang-rt-14-dev
  # libraries (STYLE.md): CGAL, OpenCASCADE, lib3mf, Clipper, oneTBB, JSON, CLI, fmt
  libcgal-dev libgmp-dev libmpfr-dev libboost-dev
  libocct-foundation-dev libocct-modeling-data-dev libocct-modeling-algorithms-dev
  libocct-data-exchange-dev libocct-ocaf-dev libocct-visualization-dev
  lib3mf-dev libzip-dev zlib1g-dev libpolyclipping-dev libtbb-dev nlohmann-json3-dev
  libcli11-dev libfmt-dev libxml2-dev libnest2d-dev libnlopt-cxx-dev
  # tests and benchmarks
  libgtest-dev libgmock-dev libbenchmark-dev
  # the Python module (python/): pybind11 and numpy; its tests and example: pytest and matplotlib
  python3-dev pybind11-dev python3-numpy python3-pytest python3-matplotlib
  # real meshes for the end-to-end plans (OpenCASCADE sample data; LinuxCNC ships machine models)
  occt-misc
  # a real G-code interpreter (rs274) for tests/unit/machine/test_rs274.cpp
  linuxcnc-uspace
  # LinuxCNC's simulator in the loop (tools/linuxcnc-sim): its clock sped up by libfaketime
  libfaketime
  # a real browser for the report viewer's tests (tests/browser)
  chromium
)
# Node.js and npm bundle the viewer; Debian's are used only when the machine has none.
command -v node >/dev/null || packages+=(nodejs)
command -v npm >/dev/null || packages+=(npm)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
else
  echo "install-deps: installing ${missing[*]}"
  sudo_cmd=()
  [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update -q
  "${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
fi
# The viewer's packages (three, esbuild, playwright-core), exactly as locked. npm records what it
# installed in node_modules/.package-lock.json; a newer lock file means they are out of date.
viewer="$(dirname "$0")/../viewer"
if [ ! -f "$viewer/node_modules/.package-lock.json" ] || [ "$viewer/package-lock.json" -nt "$viewer/node_modules/.package-lock.json" ]; then
  echo "install-deps: npm ci in viewer/"
  (cd "$viewer" && npm ci --no-audit --no-fund --loglevel=error)
else
  echo "install-deps: viewer npm packages present"
fi
