#!/usr/bin/env bash
# One browser test (CTest): plan PART with the polyaxis CLI (extra plan options after the part), or
# rewrite the page with `polyaxis view`, then open the report.html in headless Chromium through
# viewer/test/browser_test.mjs (no console error, a drawn canvas, the layer slider changes the
# picture) and keep the screenshot in ARTIFACTS.
# Usage: run_browser_test.sh CLI NODE VIEWER_DIR ARTIFACTS NAME PART [plan options...]
set -euo pipefail
cli=$1 node=$2 viewer=$3 artifacts=$4 name=$5 part=$6
shift 6
out="$artifacts/$name"
rm -rf "$out"
mkdir -p "$out"
"$cli" --quiet plan "$part" -o "$out" "$@"
test -s "$out/report.html"
"$node" "$viewer/test/browser_test.mjs" "$out/report.html" --screenshot "$artifacts/$name.png"
# The same page from plan.json alone (`polyaxis view`) must pass too.
"$cli" view "$out/plan.json" -o "$out/view.html"
"$node" "$viewer/test/browser_test.mjs" "$out/view.html"
