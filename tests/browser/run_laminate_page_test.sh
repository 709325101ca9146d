#!/usr/bin/env bash
# The lamination report in a real browser (CTest): laminate PART with the polyaxis CLI (extra options
# after the part), then open report.html in headless Chromium through viewer/test/laminate_page_test.mjs
# and keep the screenshot in ARTIFACTS.
# Usage: run_laminate_page_test.sh CLI NODE VIEWER_DIR ARTIFACTS NAME PART [laminate options...]
set -euo pipefail
cli=$1 node=$2 viewer=$3 artifacts=$4 name=$5 part=$6
shift 6
out="$artifacts/$name"
rm -rf "$out"
mkdir -p "$out"
"$cli" --quiet laminate "$part" -o "$out" "$@"
sheets=$(ls "$out"/sheet_*.ngc | wc -l)
"$node" "$viewer/test/laminate_page_test.mjs" "$out/report.html" "$sheets" --screenshot "$artifacts/$name.png"
