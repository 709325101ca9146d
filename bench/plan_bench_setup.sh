# Sourced by run_plan_bench.sh and run_report_bench.sh: from the repository root, installs
# hyperfine if missing, builds the CLI and the mesh generator in Release, makes the ~82k and ~1.3M
# triangle meshes when absent, and sets $cli and a scratch directory $out removed on exit.
command -v hyperfine >/dev/null || { apt-get update -q && apt-get install -y -q --no-install-recommends hyperfine; }
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" --target polyaxis polyaxis-cad-import make_bench_mesh >/dev/null
mkdir -p bench/data
[ -f bench/data/bumpy_82k.stl ] || build/bench/make_bench_mesh 6 bench/data/bumpy_82k.stl >/dev/null
[ -f bench/data/bumpy_1.3m.stl ] || build/bench/make_bench_mesh 8 bench/data/bumpy_1.3m.stl >/dev/null
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
cli=build/apps/polyaxis/polyaxis
