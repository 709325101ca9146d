#!/usr/bin/env bash
# Builds the libFuzzer targets with clang-14 (ASan + UBSan), replays every committed corpus input
# (-runs=0), then fuzzes each target for FUZZ_SECONDS (default 20). New crashes land in
# build-fuzz/crashes/. Usage: scripts/fuzz.sh [seconds]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-${FUZZ_SECONDS:-20}}
if ! command -v clang++-14 >/dev/null; then
  echo "fuzz: clang++-14 not installed; skipping (apt-get install clang-14 libclang-rt-14-dev)" >&2
  exit 0
fi
jobs=$(nproc)
cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++-14 \
  -DPOLYAXIS_BUILD_FUZZ=ON -DPOLYAXIS_BUILD_TESTS=OFF -DPOLYAXIS_BUILD_BENCH=OFF -DPOLYAXIS_PYTHON=OFF \
  -DCMAKE_POSITION_INDEPENDENT_CODE=OFF >/dev/null
cmake --build build-fuzz -j"$jobs" --target fuzz_stl fuzz_obj fuzz_3mf fuzz_repair fuzz_plan_json fuzz_config fuzz_gcode fuzz_toolpath_3mf
mkdir -p build-fuzz/crashes
# lib3mf 1.8.1 leaks a few bytes per package inside libzip (see tests/fuzz/fuzz_3mf.cpp).
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
for name in stl obj 3mf repair plan_json config gcode toolpath_3mf; do
  bin=build-fuzz/tests/fuzz/fuzz_$name
  extra=(-artifact_prefix=build-fuzz/crashes/"$name"-)
  export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
  if [ "$name" = 3mf ]; then extra+=(-detect_leaks=0); export ASAN_OPTIONS=detect_leaks=0:abort_on_error=1; fi
  work=build-fuzz/corpus-$name
  mkdir -p "$work"
  echo "fuzz_$name: replaying tests/fuzz/corpus/$name"
  "$bin" "${extra[@]}" -rss_limit_mb=2560 -timeout=60 -runs=0 tests/fuzz/corpus/$name
  echo "fuzz_$name: fuzzing for ${seconds}s"
  set -o pipefail
  "$bin" "${extra[@]}" -rss_limit_mb=2560 -timeout=60 -max_total_time="$seconds" -print_final_stats=0 \
    "$work" tests/fuzz/corpus/$name 2>&1 | tail -n 3
done
echo "fuzz: all targets replayed their corpora and ran ${seconds}s without a finding"
