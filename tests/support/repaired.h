// Repair as `polyaxis analyze` and `plan` do before geometry reasoning (no self-intersection pass),
// for tests that build their parts.
#pragma once

#include <gtest/gtest.h>

#include "polyaxis/io/raw_mesh.h"
#include "polyaxis/mesh/repair.h"

namespace polyaxis::test {

inline mesh::RepairedMesh repaired(io::RawMesh raw) {
  mesh::RepairOptions o;
  o.check_self_intersections = false;
  auto r = mesh::repair(std::move(raw), o);
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
  return std::move(r.value());
}

}  // namespace polyaxis::test
