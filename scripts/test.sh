#!/usr/bin/env bash
# The README's second command (and CI's): install what is missing, fuzz briefly under sanitizers,
# build in Release and run every test with CTest (the last thing it prints is CTest's summary).
set -euo pipefail
cd "$(dirname "$0")/.."
# ccache (when present) keys on paths relative to the checkout, so a fresh clone anywhere reuses
# what an earlier build compiled.
export CCACHE_BASEDIR="$PWD" CCACHE_NOHASHDIR=true
scripts/install-deps.sh
scripts/fuzz.sh "${FUZZ_SECONDS:-20}"
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)"
ctest --test-dir build --output-on-failure -j"$(nproc)"
