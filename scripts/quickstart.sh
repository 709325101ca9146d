#!/usr/bin/env bash
# The README's first command: install what is missing, build in Release, run the main job on an
# example part.
set -euo pipefail
cd "$(dirname "$0")/.."
# ccache (when present) keys on paths relative to the checkout, so a fresh clone anywhere reuses
# what an earlier build compiled.
export CCACHE_BASEDIR="$PWD" CCACHE_NOHASHDIR=true
scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" --target polyaxis polyaxis-cad-import
build/apps/polyaxis/polyaxis plan examples/parts/impeller.stl -o out/impeller
