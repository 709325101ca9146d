#!/usr/bin/env bash
# The installed package, as a user on a fresh machine gets it (ctest: package_install):
#   1. `cmake --install` the build into a throw-away prefix;
#   2. build examples/cpp against it with find_package(polyaxis) and run it on a reference part;
#      its program must be the installed CLI's, byte for byte;
#   3. `import polyaxis` in Debian's python3 from the prefix, and run examples/python there;
#   4. a library-only configure (-DPOLYAXIS_VIEWER=OFF) needs no Node.js and bundles no viewer.
# Usage: run_package_test.sh BUILD_DIR SOURCE_DIR PYTHON
set -euo pipefail
build=$(cd "$1" && pwd) source=$(cd "$2" && pwd) python=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
prefix=$work/prefix

echo "== install into $prefix"
cmake --install "$build" --prefix "$prefix" >"$work/install.log"
for f in bin/polyaxis bin/polyaxis-cad-import lib/libpolyaxis.so include/polyaxis/report/plan_job.h \
         lib/cmake/polyaxis/polyaxisConfig.cmake lib/cmake/polyaxis/polyaxisTargets.cmake share/polyaxis/machines/ded5_ac.json; do
  [ -e "$prefix/$f" ] || { echo "missing from the install: $f"; exit 1; }
done

echo "== examples/cpp against the installed package"
cmake -S "$source/examples/cpp" -B "$work/example" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release >"$work/example.log"
cmake --build "$work/example" -j2 >>"$work/example.log"
# Nothing of the build tree may be needed: the example links libpolyaxis.so from the prefix.
# (ldd's output is taken whole: grep -q stopping early would break ldd's pipe under pipefail.)
libs=$(ldd "$work/example/plan_part")
if grep -q "$build" <<<"$libs"; then echo "plan_part links the build tree"; exit 1; fi
grep -q "$prefix/lib/libpolyaxis.so" <<<"$libs" || { echo "plan_part does not link the installed libpolyaxis:"; echo "$libs"; exit 1; }
part=$source/examples/parts/l_block.stl
(cd "$work" && "$work/example/plan_part" "$part" "$work/lib-out" | tee "$work/example.out")
grep -q "progress events" "$work/example.out"
"$prefix/bin/polyaxis" plan "$part" -o "$work/cli-out" --no-html -q >/dev/null
cmp "$work/lib-out/l_block.ngc" "$work/cli-out/l_block.ngc"
cmp "$work/lib-out/report.json" "$work/cli-out/report.json"

echo "== python: import polyaxis from the prefix"
site=$(find "$prefix" -type d -name dist-packages -print -quit)
[ -f "$site/polyaxis/__init__.py" ] || { echo "no polyaxis package under $prefix"; exit 1; }
PYTHONPATH=$site "$python" -c "import polyaxis, sys; assert polyaxis.__file__.startswith('$prefix'), polyaxis.__file__; print('import polyaxis:', polyaxis.__file__)"
# A STEP part (OpenCASCADE's sample, occt-misc) through the CAD importer installed beside the module.
step=/usr/share/opencascade/data/step/screw.step
if [ -f "$step" ]; then
  PYTHONPATH=$site "$python" -c "import polyaxis; p = polyaxis.read_part('$step'); assert p.format == 'step' and len(p.triangles) > 100, p"
fi
(cd "$work" && PYTHONPATH=$site MPLCONFIGDIR=$work/mpl "$python" "$source/examples/python/plan_and_plot.py" "$source/examples/parts/pen_rack.stl" "$work/py-out")
for f in layers.png tilt.png pen_rack.ngc report.json plan.json report.html; do
  [ -s "$work/py-out/$f" ] || { echo "examples/python wrote no $f"; exit 1; }
done
"$prefix/bin/polyaxis" plan "$source/examples/parts/pen_rack.stl" -o "$work/cli-pen" --no-html -q >/dev/null
cmp "$work/py-out/pen_rack.ngc" "$work/cli-pen/pen_rack.ngc"

echo "== a library-only configure needs no Node.js"
cmake -S "$source" -B "$work/libonly" -DPOLYAXIS_VIEWER=OFF -DPOLYAXIS_PYTHON=OFF -DPOLYAXIS_BUILD_TESTS=OFF \
      -DPOLYAXIS_BUILD_BENCH=OFF -DNODE_PROGRAM=/nonexistent/node >"$work/libonly.log"
if grep -rq "build.mjs\|/nonexistent/node" "$work/libonly/src/CMakeFiles" "$work/libonly/src/Makefile"; then
  echo "the library-only build still runs Node.js"; exit 1
fi
grep -rq "viewer_absent.js" "$work/libonly/src/CMakeFiles" || { echo "the library-only build does not embed viewer_absent.js"; exit 1; }
echo "package test passed"
