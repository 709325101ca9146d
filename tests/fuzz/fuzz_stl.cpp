// libFuzzer target: the STL reader (binary and ASCII) on arbitrary bytes, then repair on
// whatever it accepts. Invariants: a mesh or an error, never a signal; finite points; indices
// in range.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "raw_mesh_invariants.h"

#include "polyaxis/io/stl.h"
#include "polyaxis/mesh/repair.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace polyaxis;
  io::ReadOptions options;
  options.max_triangles = 100000;
  auto r = io::read_stl(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.stl", options);
  if (!r) return 0;
  fuzz::check_raw_mesh(r.value().mesh);
  mesh::RepairOptions repair_options;
  repair_options.check_self_intersections = size < 20000;
  (void)mesh::repair(r.value().mesh, repair_options);
  return 0;
}
