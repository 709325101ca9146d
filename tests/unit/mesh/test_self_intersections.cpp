// The grid search for self-intersections (parallel, mesh/self_intersections.cpp) against CGAL's
// box_intersection_d over the same exact predicates, on intersecting and clean parts of several
// sizes, tessellations and orientations, and on a part uneven enough for the fallback.
#include <gtest/gtest.h>

#include <cmath>

#include "polyaxis/mesh/repair.h"
#include "polyaxis/mesh/self_intersections.h"
#include "support/meshes.h"

namespace polyaxis::mesh {
namespace {

// RAW turned by DEG about the axis (1, 1, 0)/√2 and moved by SHIFT.
io::RawMesh turned(io::RawMesh raw, double deg, core::Vec3 shift) {
  const double a = deg * M_PI / 180.0, c = std::cos(a), s = std::sin(a);
  const core::Vec3 k = core::normalized(core::Vec3{1, 1, 0});
  for (auto& p : raw.points) {
    const core::Vec3 v{p.x, p.y, p.z};
    const core::Vec3 r = v * c + core::cross(k, v) * s + k * (core::dot(k, v) * (1.0 - c)) + shift;
    p = {static_cast<float>(r.x), static_cast<float>(r.y), static_cast<float>(r.z)};
  }
  return raw;
}

Mesh mesh_of(const io::RawMesh& raw) {
  RepairOptions o;
  o.check_self_intersections = false;
  auto r = repair(raw, o);
  EXPECT_TRUE(r.ok()) << r.error().message;
  return r.value().mesh;
}

TEST(SelfIntersections, GridFindsWhatTheBoxIntersectionFinds) {
  struct Case {
    const char* name;
    io::RawMesh raw;
    bool intersects;
  };
  const std::vector<Case> cases = {
      {"clean torus", test::torus(20, 5, 60, 24), false},
      {"two tori", test::join(test::torus(20, 5, 60, 24), turned(test::torus(18, 4, 47, 19), 37.0, {9, -4, 3})), true},
      {"cube and box", test::join(test::cube(), turned(test::box({5, 5, 5}, {15, 15, 15}), 11.0, {0, 0, 0})), true},
      {"touching cubes", test::join(test::cube(), test::box({10, 0, 0}, {20, 10, 10})), true},
      {"fine torus through a coarse slab", test::join(test::torus(30, 6, 120, 40), turned(test::box({-50, -50, -1}, {50, 50, 1}), 23.0, {1, 2, 0})), true},
      {"frustum and bar", test::join(test::frustum(15, 8, 30, 48), turned(test::bent_bar(25, 4, 120, 40, 16), 5.0, {-20, 3, 10})), true},
      {"far apart", test::join(test::torus(20, 5, 40, 20), turned(test::cube(), 0.0, {100, 0, 0})), false},
  };
  for (const Case& c : cases) {
    const Mesh m = mesh_of(c.raw);
    const auto grid = self_intersecting_faces(m);
    const auto boxes = detail::self_intersecting_faces_by_boxes(m);
    EXPECT_EQ(grid, boxes) << c.name;
    EXPECT_EQ(!grid.empty(), c.intersects) << c.name << ": " << grid.size();
  }
}

// Pairs of faces sharing an edge or a vertex, each with the known answer, including ones whose
// orientation is too close to call in doubles (decided by the exact predicate).
TEST(SelfIntersections, NeighbouringFacesMeetOnlyWhenFoldedOrCrossing) {
  struct Case {
    const char* name;
    std::vector<core::Vec3> points;
    std::vector<Triangle> faces;
    bool intersects;
  };
  // On the tilted plane z = x + 2y, exactly (multiples of 2^-10), where the orientation rounds to
  // -1.1e-8 in doubles; and one ulp off it. Only the exact predicate gets these right.
  const core::Vec3 t0{523.15234375, 734.28125, 1991.71484375}, t1{59.4033203125, 953.595703125, 1966.5947265625},
      t2{510.060546875, 106.1962890625, 722.453125}, t3{321.232421875, 231.8466796875, 784.92578125};
  const core::Vec3 t3_off{t3.x, t3.y, std::nextafter(t3.z, 1e9)};
  std::vector<Case> cases = {
      {"edge, folded flat onto each other", {{0, 0, 0}, {10, 0, 0}, {5, 5, 0}, {4, 3, 0}}, {{0, 1, 2}, {1, 0, 3}}, true},
      {"edge, flat on opposite sides", {{0, 0, 0}, {10, 0, 0}, {5, 5, 0}, {4, -3, 0}}, {{0, 1, 2}, {1, 0, 3}}, false},
      {"edge, a right-angle crease", {{0, 0, 0}, {10, 0, 0}, {5, 5, 0}, {4, 0, 3}}, {{0, 1, 2}, {1, 0, 3}}, false},
      {"edge, folded by 1e-9 off the plane", {{0, 0, 0}, {10, 0, 0}, {5, 5, 0}, {4, 3, 1e-9}}, {{0, 1, 2}, {1, 0, 3}}, false},
      {"edge, folded flat on a tilted plane", {t0, t1, t2, t3}, {{0, 1, 2}, {1, 0, 3}}, true},
      {"edge, folded one ulp off a tilted plane", {t0, t1, t2, t3_off}, {{0, 1, 2}, {1, 0, 3}}, false},
      {"vertex, far edge through the other face", {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {3, 3, -2}, {3, 3, 2}}, {{0, 1, 2}, {0, 3, 4}}, true},
      {"vertex, far edge above the other face", {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {3, 3, 1}, {4, 2, 2}}, {{0, 1, 2}, {0, 3, 4}}, false},
      {"vertex, coplanar and overlapping", {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {8, 1, 0}, {1, 8, 0}}, {{0, 1, 2}, {0, 3, 4}}, true},
      {"vertex, coplanar side by side", {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {-8, 1, 0}, {-1, 8, 0}}, {{0, 1, 2}, {0, 4, 3}}, false},
  };
  // Fans round one vertex whose wedges all turn the same way but wind past a full turn: the second
  // turn lies inside the first, in its plane.
  {
    Case open{"vertex, an open fan wound past a full turn", {{0, 0, 0}}, {}, true};
    for (int i = 0; i <= 5; ++i) {
      const double r = i < 4 ? 10.0 : 8.0, a = M_PI / 2 * i;
      open.points.push_back({r * std::cos(a), r * std::sin(a), 0});
    }
    for (std::uint32_t i = 1; i <= 5; ++i) open.faces.push_back({0, i, i + 1});
    cases.push_back(open);
    Case closed{"vertex, a closed fan wound twice", {{0, 0, 0}}, {}, true};
    for (int i = 0; i < 8; ++i) {
      const double r = i < 4 ? 10.0 : 5.0, a = M_PI / 2 * i;
      closed.points.push_back({r * std::cos(a), r * std::sin(a), 0});
    }
    for (std::uint32_t i = 0; i < 8; ++i) closed.faces.push_back({0, 1 + i, 1 + (i + 1) % 8});
    cases.push_back(closed);
  }
  for (const Case& c : cases) {
    const Mesh m{c.points, c.faces};
    EXPECT_EQ(!self_intersecting_faces(m).empty(), c.intersects) << c.name;
    EXPECT_EQ(!detail::self_intersecting_faces_by_boxes(m).empty(), c.intersects) << c.name;
  }
}

// Faces that only touch, at coordinates no float holds: the grid's boxes (floats) must be rounded
// outwards, or the touching pair is never a candidate.
TEST(SelfIntersections, FacesTouchingAtCoordinatesNoFloatHolds) {
  const double z = 0.1, x = 1.0 / 3.0;
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<core::Vec3> points = {{-5, -5, z}, {5, -5, z}, {0, 5, z}, {x, x, z}, {x + 2, x, z + 4}, {x, x + 2, z + 4}};
    for (auto& p : points) {  // the same pair with the touching plane across each axis
      for (int k = 0; k < axis; ++k) p = {p.z, p.x, p.y};
    }
    const Mesh m{points, {{0, 1, 2}, {3, 4, 5}}};
    EXPECT_EQ(self_intersecting_faces(m).size(), 2u) << axis;
    EXPECT_EQ(detail::self_intersecting_faces_by_boxes(m).size(), 2u) << axis;
  }
}

// Faces sharing no vertex, one a hair above the other's plane or a hair through it: the filter in
// doubles passes over only pairs surely apart, and the exact predicate decides the rest.
TEST(SelfIntersections, FacesAHairApartOrAHairThrough) {
  const double z = 0.1;
  for (const bool through : {false, true}) {
    const double tip = through ? std::nextafter(z, -1.0) : std::nextafter(z, 1.0);
    for (int axis = 0; axis < 3; ++axis) {
      std::vector<core::Vec3> points = {{-5, -5, z}, {5, -5, z}, {0, 5, z}, {0.3, 0.2, tip}, {2.3, 0.2, z + 4}, {0.3, 2.2, z + 3}};
      for (auto& p : points) {
        for (int k = 0; k < axis; ++k) p = {p.z, p.x, p.y};
      }
      const Mesh m{points, {{0, 1, 2}, {3, 4, 5}}};
      EXPECT_EQ(self_intersecting_faces(m).size(), through ? 2u : 0u) << axis << (through ? " through" : " apart");
      EXPECT_EQ(detail::self_intersecting_faces_by_boxes(m).size(), through ? 2u : 0u) << axis;
    }
  }
}

}  // namespace
}  // namespace polyaxis::mesh
