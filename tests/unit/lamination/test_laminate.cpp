// Sloped-edge lamination (lamination.h): layers from the stock, cuts that follow the part without
// gouging it, convex edges cut once per sub-slice, concave ones once, and less deviation than
// vertical edges at the same layers. Parts are made here (solids of revolution with convex and
// concave edges, a tube, a neck, a box) besides the reference dome.
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

// The part's own section at H, cut here with every face as a candidate (not the lamination's stack).
std::vector<geom2d::Polygon> part_section(const mesh::Mesh& m, double h) {
  slicing::SectionContext ctx(m, {0, 0, 1});
  std::vector<std::uint32_t> all(m.triangles.size());
  for (std::uint32_t f = 0; f < all.size(); ++f) all[f] = f;
  slicing::SectionScratch scratch;
  return slicing::section(ctx, h, slicing::plane_frame({0, 0, 1}, h), all, scratch).polygons;
}

std::vector<geom2d::Polygon> kept(const Layer& layer, double h) {
  std::vector<geom2d::Ring> rings;
  for (const auto& piece : layer.pieces) {
    for (const auto& p : kept_section(layer, piece, h)) {
      const auto r = geom2d::rings_of({p});
      rings.insert(rings.end(), r.begin(), r.end());
    }
  }
  return geom2d::union_rings(rings, geom2d::FillRule::kNonZero);
}

// A sphere of radius R on a 2 mm base disc: convex flanks all the way up.
mesh::Mesh ball(double r, std::uint32_t n) {
  std::vector<std::array<double, 2>> profile;
  for (int k = 0; k <= 40; ++k) {
    const double a = -kPi / 2 + kPi * k / 40.0;
    profile.push_back({std::max(r * std::cos(a), 0.5), r + r * std::sin(a)});
  }
  return test::repaired(test::revolve(profile, n)).mesh;
}

// A spool: radius 20 at both ends narrowing to WAIST in the middle along a parabola (concave edges).
mesh::Mesh spool(double waist, double h, std::uint32_t n, double bore = 0.0) {
  std::vector<std::array<double, 2>> profile;
  for (int k = 0; k <= 48; ++k) {
    const double z = h * k / 48.0, s = (z - h / 2) / (h / 2);
    profile.push_back({waist + (20.0 - waist) * s * s, z});
  }
  return test::repaired(test::revolve(profile, n, bore)).mesh;
}

struct Checked {
  std::uint32_t convex = 0, concave = 0, straight = 0;
};

// What every lamination must hold, whatever the part: the stock, a stack without gaps from the
// part's bottom over its top, no gouge at any height (the part's section inside the kept one), and
// less deviation than vertical edges.
Checked check_lamination(const mesh::Mesh& m, const LaminateOptions& o, const Lamination& l, const char* name) {
  Checked c;
  core::Box3 box;
  for (const auto& v : m.vertices) box.add(v);
  EXPECT_FALSE(l.layers.empty());
  double z = box.min.z;
  for (const auto& layer : l.layers) {
    EXPECT_NE(std::find(o.sheets_mm.begin(), o.sheets_mm.end(), layer.thickness_mm), o.sheets_mm.end()) << name << " layer " << layer.index;
    EXPECT_NEAR(layer.z_bottom_mm, z, 1e-9) << name;
    z += layer.thickness_mm;
    c.convex += layer.convex_samples, c.concave += layer.concave_samples, c.straight += layer.straight_samples;
    for (int j = 0; j < 7; ++j) {
      const double h = layer.z_bottom_mm + (j + 0.5) * layer.thickness_mm / 7.0;
      if (h >= box.max.z) continue;
      const auto part = part_section(m, h);
      const double gouged = geom2d::area_mm2(geom2d::difference_rings(geom2d::rings_of(part), geom2d::rings_of(kept(layer, h))));
      // A sample's edge is straight between samples ≤ sample_mm apart: allow the chord's sliver.
      EXPECT_LE(gouged, 0.01 * geom2d::area_mm2(part) + 0.05) << name << " layer " << layer.index << " h " << h;
    }
  }
  EXPECT_GE(z, box.max.z - 1e-9) << name;
  EXPECT_LT(z - box.max.z, *std::min_element(o.sheets_mm.begin(), o.sheets_mm.end()) + 1e-9) << name;
  EXPECT_LT(l.sloped_deviation_mm3, l.stepped_deviation_mm3) << name;
  std::printf("%s: %zu layers, sloped %.1f mm3 vs stepped %.1f mm3 (part %.0f mm3); samples convex %u concave %u straight %u\n", name,
              l.layers.size(), l.sloped_deviation_mm3, l.stepped_deviation_mm3, l.part_volume_mm3, c.convex, c.concave, c.straight);
  return c;
}

TEST(Laminate, DomeSphereFollowsTheDomeAndItsDishBetterThanSteps) {
  const mesh::Mesh m = read_reference("dome_sphere.stl");
  LaminateOptions o;
  o.sheets_mm = {1, 2, 3, 6};
  o.max_jet_angle_deg = 60.0;
  auto r = laminate(m, o);
  ASSERT_TRUE(r.ok()) << r.error().message;
  const auto c = check_lamination(m, o, r.value(), "dome_sphere");
  EXPECT_GT(c.convex, 0u);
  // Hayasi's figure for his part: several times less deviation than stair steps.
  EXPECT_LT(3.0 * r.value().sloped_deviation_mm3, r.value().stepped_deviation_mm3);
}

TEST(Laminate, ConeEdgesAreOneStraightCutAtTheConesAngle) {
  // A frustum r 30 → 15 over 30 mm: the wall leans 26.57° in; 96 sides.
  const mesh::Mesh m = test::repaired(test::frustum(30.0, 15.0, 30.0, 96)).mesh;
  LaminateOptions o;
  o.sheets_mm = {2, 5};
  auto r = laminate(m, o);
  ASSERT_TRUE(r.ok()) << r.error().message;
  const auto c = check_lamination(m, o, r.value(), "frustum");
  EXPECT_EQ(c.convex, 0u);
  for (const auto& layer : r.value().layers) {
    EXPECT_EQ(layer.thickness_mm, 5.0);  // a straight wall meets any deviation at the thickest sheet
    for (const auto& s : layer.pieces.at(0).outer.samples) {
      ASSERT_EQ(s.cuts.size(), 1u);
      EXPECT_NEAR(s.cuts[0].slope, -0.5, 1e-3);  // 15 mm in over 30 mm up
      EXPECT_LT(s.gap_mm, 0.01);
    }
  }
  EXPECT_LT(r.value().sloped_deviation_mm3, 0.02 * r.value().stepped_deviation_mm3);
}

TEST(Laminate, ConvexEdgesAreCutOncePerSubslice) {
  const mesh::Mesh m = ball(20.0, 128);
  LaminateOptions o;
  o.sheets_mm = {1, 3, 6};
  o.max_jet_angle_deg = 70.0;
  o.area_deviation = 0.2;
  auto r = laminate(m, o);
  ASSERT_TRUE(r.ok()) << r.error().message;
  const auto c = check_lamination(m, o, r.value(), "ball");
  EXPECT_GT(c.convex, 0u);
  EXPECT_EQ(c.concave, 0u);
  bool multi = false;
  for (const auto& layer : r.value().layers) {
    for (const auto& s : layer.pieces.empty() ? std::vector<EdgeSample>{} : layer.pieces[0].outer.samples) {
      if (s.kind != EdgeKind::kConvex) continue;
      EXPECT_EQ(s.cuts.size(), layer.subslices);
      multi = multi || s.cuts.size() > 1;
      // Each cut leans more than the one below it: the flank turns inwards going up.
      for (std::size_t k = 1; k < s.cuts.size(); ++k) EXPECT_LE(s.cuts[k].slope, s.cuts[k - 1].slope + 1e-9);
    }
  }
  EXPECT_TRUE(multi);
}

TEST(Laminate, ConcaveNeckIsCutOnceAndATubeKeepsItsBore) {
  for (double bore : {0.0, 6.0}) {
    const mesh::Mesh m = spool(10.0, 36.0, 96, bore);
    LaminateOptions o;
    o.sheets_mm = {2, 6};
    o.area_deviation = 0.3;
    auto r = laminate(m, o);
    ASSERT_TRUE(r.ok()) << r.error().message;
    const auto c = check_lamination(m, o, r.value(), bore > 0 ? "spool with bore" : "spool");
    EXPECT_GT(c.concave, 0u);
    for (const auto& layer : r.value().layers) {
      for (const auto& piece : layer.pieces) {
        EXPECT_EQ(piece.holes.size(), bore > 0 ? 1u : 0u);
        for (const auto& s : piece.outer.samples) {
          if (s.kind == EdgeKind::kConcave) {
            EXPECT_EQ(s.cuts.size(), 1u);
          }
        }
      }
    }
  }
}

TEST(Laminate, ThinnerSheetsWhereTheShapeChangesFast) {
  // The ball's flat-ish top and bottom change area fast: thin sheets there, thick ones on the flanks.
  const mesh::Mesh m = ball(25.0, 96);
  LaminateOptions o;
  o.sheets_mm = {1, 2, 4, 8};
  o.area_deviation = 0.05;
  auto r = laminate(m, o);
  ASSERT_TRUE(r.ok()) << r.error().message;
  check_lamination(m, o, r.value(), "ball 25");
  const auto& layers = r.value().layers;
  double thickest = 0.0;
  for (const auto& l : layers) thickest = std::max(thickest, l.thickness_mm);
  EXPECT_GT(thickest, layers.front().thickness_mm);
  EXPECT_GT(thickest, layers.back().thickness_mm);
  // A tighter deviation never takes thicker sheets.
  o.area_deviation = 0.01;
  auto tight = laminate(m, o);
  ASSERT_TRUE(tight.ok());
  EXPECT_GE(tight.value().layers.size(), layers.size());
}

TEST(Laminate, CuspLimitsTheGapBetweenCutAndPart) {
  const mesh::Mesh m = ball(20.0, 96);
  LaminateOptions o;
  o.sheets_mm = {1, 2, 4, 8};
  o.area_deviation = 1.0;
  o.max_jet_angle_deg = 80.0;
  o.cusp_mm = 0.05;
  auto r = laminate(m, o);
  ASSERT_TRUE(r.ok());
  for (const auto& l : r.value().layers) {
    if (l.thickness_mm > 1.0) {
      EXPECT_LE(l.max_gap_mm, 0.05) << l.index;
    }
  }
}

TEST(Laminate, SteeperThanTheJetIsCutAtTheLimit) {
  const mesh::Mesh m = test::repaired(test::frustum(30.0, 5.0, 10.0, 64)).mesh;  // 68° off vertical
  LaminateOptions o;
  o.sheets_mm = {5};
  o.max_jet_angle_deg = 45.0;
  auto r = laminate(m, o);
  ASSERT_TRUE(r.ok());
  std::uint32_t limited = 0;
  for (const auto& l : r.value().layers) {
    limited += l.at_jet_limit;
    for (const auto& p : l.pieces) {
      for (const auto& s : p.outer.samples) {
        for (const auto& cut : s.cuts) EXPECT_LE(std::fabs(cut.slope), 1.0 + 1e-9);
      }
    }
  }
  EXPECT_GT(limited, 0u);
}

TEST(Laminate, BadOptionsAreUsageErrors) {
  const mesh::Mesh m = test::repaired(test::cube(10.0)).mesh;
  for (const std::vector<double>& sheets : {std::vector<double>{}, {0.0}, {-1.0}, {NAN}, {2e3}}) {
    LaminateOptions o;
    o.sheets_mm = sheets;
    auto r = laminate(m, o);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, core::ErrorCode::kUsage);
  }
  LaminateOptions o;
  o.sheets_mm = {1};
  o.max_jet_angle_deg = 95.0;
  EXPECT_EQ(laminate(m, o).error().code, core::ErrorCode::kUsage);
}

TEST(Laminate, SameResultAtAnyThreadCount) {
  const mesh::Mesh m = read_reference("dome_sphere.stl");
  LaminateOptions o;
  o.sheets_mm = {1, 2, 3, 6};
  o.threads = 1;
  auto a = laminate(m, o);
  o.threads = 2;
  auto b = laminate(m, o);
  ASSERT_TRUE(a.ok() && b.ok());
  ASSERT_EQ(a.value().layers.size(), b.value().layers.size());
  EXPECT_EQ(a.value().sloped_deviation_mm3, b.value().sloped_deviation_mm3);
  for (std::size_t i = 0; i < a.value().layers.size(); ++i) EXPECT_EQ(a.value().layers[i].thickness_mm, b.value().layers[i].thickness_mm);
}

}  // namespace
}  // namespace polyaxis::lamination
