// The contract every reader's RawMesh keeps (io/raw_mesh.h), checked by the fuzz targets: every
// point finite, every index below the point count. A breach aborts, which libFuzzer reports.
#pragma once

#include <cstdlib>

#include "polyaxis/core/vec3.h"
#include "polyaxis/io/raw_mesh.h"

namespace polyaxis::fuzz {

inline void check_raw_mesh(const io::RawMesh& m) {
  for (const auto& p : m.points) {
    if (!core::is_finite(p)) std::abort();
  }
  for (const auto& t : m.triangles) {
    for (auto v : t) {
      if (v >= m.points.size()) std::abort();
    }
  }
}

}  // namespace polyaxis::fuzz
