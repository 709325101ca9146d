// libFuzzer target: the OBJ reader on arbitrary text. Invariants as for STL.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "polyaxis/core/vec3.h"
#include "polyaxis/io/obj.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace polyaxis;
  io::ReadOptions options;
  options.max_triangles = 100000;
  auto r = io::read_obj(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.obj", options);
  if (!r) return 0;
  const io::RawMesh& m = r.value().mesh;
  for (const auto& p : m.points) {
    if (!core::is_finite(p)) std::abort();
  }
  for (const auto& t : m.triangles) {
    for (auto v : t) {
      if (v >= m.points.size()) std::abort();
    }
  }
  return 0;
}
