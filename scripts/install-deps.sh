#!/usr/bin/env bash
# Installs the Debian 12 packages polyaxis builds and tests with, only when one is missing.
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
  libcli11-dev libfmt-dev
  # tests and benchmarks
  libgtest-dev libgmock-dev libbenchmark-dev
  # a real G-code interpreter (rs274) for tests/unit/machine/test_rs274.cpp
  linuxcnc-uspace
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
sudo_cmd=()
[ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -q
"${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
