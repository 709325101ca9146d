// libFuzzer target: the OBJ reader on arbitrary text. Invariants as for STL.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "raw_mesh_invariants.h"

#include "polyaxis/io/obj.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace polyaxis;
  io::ReadOptions options;
  options.max_triangles = 100000;
  auto r = io::read_obj(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.obj", options);
  if (!r) return 0;
  fuzz::check_raw_mesh(r.value().mesh);
  return 0;
}
