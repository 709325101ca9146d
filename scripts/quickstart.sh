#!/usr/bin/env bash
# The README's first command: install what is missing, build in Release, run the main job on an
# example part.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" --target polyaxis
build/apps/polyaxis/polyaxis inspect examples/parts/l_block.stl
