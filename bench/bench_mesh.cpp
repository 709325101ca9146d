// Read + repair + check of binary STL tori (bench/run_mesh_bench.sh makes them and compares
// with admesh). Benchmarks take the file from POLYAXIS_BENCH_DIR (default bench/data).
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <string>

#include "polyaxis/io/read_part.h"
#include "polyaxis/mesh/repair.h"

namespace {

std::string data_file(const char* name) {
  const char* dir = std::getenv("POLYAXIS_BENCH_DIR");
  return std::string(dir ? dir : "bench/data") + "/" + name;
}

void read_only(benchmark::State& state, const char* name) {
  const std::string path = data_file(name);
  for (auto _ : state) {
    auto r = polyaxis::io::read_part(path);
    if (!r) {
      state.SkipWithError(r.error().message.c_str());
      return;
    }
    benchmark::DoNotOptimize(r.value().mesh.triangles.data());
  }
}

void read_repair(benchmark::State& state, const char* name, bool self_intersections) {
  const std::string path = data_file(name);
  polyaxis::mesh::RepairOptions options;
  options.check_self_intersections = self_intersections;
  for (auto _ : state) {
    auto r = polyaxis::io::read_part(path);
    if (!r) {
      state.SkipWithError(r.error().message.c_str());
      return;
    }
    auto m = polyaxis::mesh::repair(std::move(r.value().mesh), options);
    if (!m || !m.value().watertight) {
      state.SkipWithError("repair failed");
      return;
    }
    benchmark::DoNotOptimize(m.value().mesh.triangles.data());
  }
}

}  // namespace

BENCHMARK_CAPTURE(read_only, torus_100k, "torus_100k.stl")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(read_only, torus_1m, "torus_1m.stl")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(read_only, torus_4m, "torus_4m.stl")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(read_repair, torus_100k, "torus_100k.stl", false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(read_repair, torus_1m, "torus_1m.stl", false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(read_repair, torus_4m, "torus_4m.stl", false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(read_repair, torus_100k_selfint, "torus_100k.stl", true)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(read_repair, torus_1m_selfint, "torus_1m.stl", true)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
