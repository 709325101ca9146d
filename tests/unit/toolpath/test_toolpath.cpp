// Toolpath properties: perimeters at their offsets, fill inside and spaced by a bead, thin
// features reported, seams spread, tool axes unit and tilted only over overhangs (Kapil Eq. 1-3),
// output independent of the thread count.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "polyaxis/geom2d/clip.h"
#include "polyaxis/io/read_part.h"
#include "polyaxis/mesh/repair.h"
#include "polyaxis/slicing/slice.h"
#include "polyaxis/toolpath/toolpath.h"
#include "support/meshes.h"

namespace polyaxis::toolpath {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Coordinates pass through the 1 nm grid (and, for the fill, one rotation rounded to it): a few
// nm of slack on lengths, and the matching slack on areas of rings tens of mm long.
constexpr double kLengthTol = 1e-5;
constexpr double kAreaTol = 1e-3;

mesh::Mesh repaired(io::RawMesh raw) {
  mesh::RepairOptions o;
  o.check_self_intersections = false;
  auto r = mesh::repair(std::move(raw), o);
  EXPECT_TRUE(r.ok());
  return r.value().mesh;
}

// A frustum around Z: an N-gon of radius R0 at z = 0 widening to R1 at z = H.
io::RawMesh frustum(double r0, double r1, double h, std::uint32_t n) {
  io::RawMesh m;
  for (std::uint32_t i = 0; i < n; ++i) {
    const double a = 2.0 * kPi * i / n;
    m.points.push_back({r0 * std::cos(a), r0 * std::sin(a), 0.0});
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    const double a = 2.0 * kPi * i / n;
    m.points.push_back({r1 * std::cos(a), r1 * std::sin(a), h});
  }
  m.points.push_back({0, 0, 0});
  m.points.push_back({0, 0, h});
  const std::uint32_t cb = 2 * n, ct = 2 * n + 1;
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t j = (i + 1) % n;
    m.triangles.push_back({cb, j, i});
    m.triangles.push_back({ct, n + i, n + j});
    m.triangles.push_back({i, j, n + j});
    m.triangles.push_back({i, n + j, n + i});
  }
  return m;
}

slicing::SliceResult sliced(const mesh::Mesh& m, double layer_mm) {
  slicing::SliceOptions o;
  o.layer_mm = layer_mm;
  auto r = slicing::slice(m, o);
  EXPECT_TRUE(r.ok());
  return r.value();
}

std::vector<LayerToolpaths> plan(const mesh::Mesh& m, const slicing::SliceResult& s, const ToolpathOptions& o) {
  auto r = make_toolpaths(m, s, o);
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
  return r.ok() ? r.value() : std::vector<LayerToolpaths>{};
}

std::vector<const Path*> of_kind(const LayerToolpaths& l, PathKind kind) {
  std::vector<const Path*> out;
  for (const Path& p : l.paths) {
    if (p.kind == kind) out.push_back(&p);
  }
  return out;
}

// Shoelace area of a closed path's XY projection (the paths repeat their first point).
double xy_area(const Path& p) {
  double a2 = 0.0;
  for (std::size_t i = 0; i + 1 < p.points.size(); ++i) {
    const Vec3 a = p.points[i].position_mm, b = p.points[i + 1].position_mm;
    a2 += a.x * b.y - b.x * a.y;
  }
  return a2 / 2.0;
}

double tilt_rad(const PathPoint& q, Vec3 d) { return std::acos(std::clamp(core::dot(q.tool_axis, d), -1.0, 1.0)); }

void expect_unit_axes(const std::vector<LayerToolpaths>& layers) {
  for (const auto& l : layers) {
    for (const Path& p : l.paths) {
      for (const PathPoint& q : p.points) ASSERT_NEAR(core::norm(q.tool_axis), 1.0, 1e-12) << "layer " << l.layer;
    }
  }
}

bool same(const std::vector<LayerToolpaths>& a, const std::vector<LayerToolpaths>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const auto &x = a[i], &y = b[i];
    if (x.layer != y.layer || x.paths.size() != y.paths.size() || x.thin.size() != y.thin.size() ||
        x.deposit_length_mm != y.deposit_length_mm || x.travel_length_mm != y.travel_length_mm) {
      return false;
    }
    for (std::size_t j = 0; j < x.paths.size(); ++j) {
      const Path &p = x.paths[j], &q = y.paths[j];
      if (p.kind != q.kind || p.perimeter_index != q.perimeter_index || p.surface_contour != q.surface_contour ||
          p.points.size() != q.points.size()) {
        return false;
      }
      for (std::size_t k = 0; k < p.points.size(); ++k) {
        if (!(p.points[k].position_mm == q.points[k].position_mm) || !(p.points[k].tool_axis == q.points[k].tool_axis) ||
            p.points[k].deposit != q.points[k].deposit) {
          return false;
        }
      }
    }
    for (std::size_t j = 0; j < x.thin.size(); ++j) {
      if (!(x.thin[j].where_mm == y.thin[j].where_mm) || x.thin[j].area_mm2 != y.thin[j].area_mm2) return false;
    }
  }
  return true;
}

TEST(Toolpath, BoxPerimetersAtTheirOffsets) {
  const mesh::Mesh box = repaired(test::box({0, 0, 0}, {40, 30, 10}));
  const auto layers = plan(box, sliced(box, 1.0), ToolpathOptions{});
  ASSERT_EQ(layers.size(), 10u);
  for (const auto& l : layers) {
    EXPECT_TRUE(l.thin.empty());
    const auto perimeters = of_kind(l, PathKind::kPerimeter);
    ASSERT_EQ(perimeters.size(), 2u) << "layer " << l.layer;
    for (const Path* p : perimeters) {
      EXPECT_EQ(p->points.front().position_mm, p->points.back().position_mm);
      EXPECT_FALSE(p->points.front().deposit);
      EXPECT_TRUE(p->points.back().deposit);
      const double off = 1.0 + 2.0 * p->perimeter_index;  // half a bead, then a bead each
      EXPECT_NEAR(xy_area(*p), (40 - 2 * off) * (30 - 2 * off), kAreaTol) << "layer " << l.layer;
      EXPECT_EQ(p->surface_contour, p->perimeter_index == 0);
      for (const PathPoint& q : p->points) EXPECT_NEAR(q.position_mm.z, l.layer + 0.5, 1e-9);
    }
    // Execution order: outermost perimeter, inner perimeter, fill; travels between.
    std::vector<PathKind> kinds;
    for (const Path& p : l.paths) kinds.push_back(p.kind);
    ASSERT_GE(kinds.size(), 5u);
    EXPECT_EQ(l.paths[0].perimeter_index, 0u);
    EXPECT_EQ(kinds[0], PathKind::kPerimeter);
    EXPECT_EQ(kinds[1], PathKind::kTravel);
    EXPECT_EQ(kinds[2], PathKind::kPerimeter);
    EXPECT_EQ(kinds[3], PathKind::kTravel);
    EXPECT_EQ(kinds.back(), PathKind::kFill);
    for (const Path* t : of_kind(l, PathKind::kTravel)) {
      for (const PathPoint& q : t->points) EXPECT_FALSE(q.deposit);
    }
    // Deposited: both perimeters (2·(38+28) + 2·(34+24)) and the fill.
    EXPECT_GT(l.deposit_length_mm, 248.0);
    EXPECT_GT(l.travel_length_mm, 0.0);
  }
  expect_unit_axes(layers);
}

TEST(Toolpath, BoxZigzagFillInsideTheInnermostPerimeterSpacedByABead) {
  const mesh::Mesh box = repaired(test::box({0, 0, 0}, {40, 30, 10}));
  const auto layers = plan(box, sliced(box, 1.0), ToolpathOptions{});
  ASSERT_EQ(layers.size(), 10u);
  for (const auto& l : layers) {
    const auto fill = of_kind(l, PathKind::kFill);
    ASSERT_EQ(fill.size(), 1u) << "a convex island fills in one zigzag, layer " << l.layer;
    // The innermost perimeter runs at 3 mm from the sides, its bead to 4 mm: fill stays in
    // [4, 36] × [4, 26] and its lines lie half a bead further in.
    std::set<long> lines;  // line positions across the scan direction, in µm
    const bool along_x = l.layer % 2 == 0;  // fill_angle 0, +90° on odd layers
    const auto& pts = fill.front()->points;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const Vec3 p = pts[i].position_mm;
      EXPECT_GE(p.x, 4.0 - kLengthTol);
      EXPECT_LE(p.x, 36.0 + kLengthTol);
      EXPECT_GE(p.y, 4.0 - kLengthTol);
      EXPECT_LE(p.y, 26.0 + kLengthTol);
      if (i == 0) continue;
      const Vec3 step = p - pts[i - 1].position_mm;
      const double along = std::fabs(along_x ? step.x : step.y), across = std::fabs(along_x ? step.y : step.x);
      if (along > 1.0) {
        EXPECT_LT(across, kLengthTol) << "scan lines follow the layer's fill angle, layer " << l.layer;
        lines.insert(std::lround((along_x ? p.y : p.x) * 1000.0));
      }
    }
    ASSERT_EQ(lines.size(), along_x ? 11u : 16u) << "layer " << l.layer;
    EXPECT_EQ(*lines.begin(), 5000);
    long previous = -1;
    for (long y : lines) {
      if (previous >= 0) {
        EXPECT_EQ(y - previous, 2000) << "layer " << l.layer;
      }
      previous = y;
    }
  }
}

TEST(Toolpath, FrameWithAHolePerimetersBothBoundariesAndFillsAroundTheHole) {
  // A 40 mm square with a 16 mm square hole, built from four overlapping bars (the slicer unions them).
  io::RawMesh frame = test::box({0, 0, 0}, {40, 12, 3});
  frame = test::join(frame, test::box({0, 28, 0}, {40, 40, 3}));
  frame = test::join(frame, test::box({0, 6, 0}, {12, 34, 3}));
  frame = test::join(frame, test::box({28, 6, 0}, {40, 34, 3}));
  const mesh::Mesh m = repaired(frame);
  const auto layers = plan(m, sliced(m, 1.0), ToolpathOptions{});
  ASSERT_EQ(layers.size(), 3u);
  for (const auto& l : layers) {
    EXPECT_TRUE(l.thin.empty());
    const auto perimeters = of_kind(l, PathKind::kPerimeter);
    ASSERT_EQ(perimeters.size(), 4u);
    for (const Path* p : perimeters) {
      const double off = 1.0 + 2.0 * p->perimeter_index;
      const bool outer = xy_area(*p) > 0.0;  // outer rings counter-clockwise, holes clockwise
      EXPECT_EQ(p->surface_contour, p->perimeter_index == 0) << "the hole's outermost perimeter lays the part's surface too";
      EXPECT_NEAR(std::fabs(xy_area(*p)), outer ? (40 - 2 * off) * (40 - 2 * off) : (16 + 2 * off) * (16 + 2 * off), kAreaTol);
    }
    const auto fill = of_kind(l, PathKind::kFill);
    ASSERT_FALSE(fill.empty());
    for (const Path* p : fill) {
      for (const PathPoint& q : p->points) {
        const Vec3 a = q.position_mm;
        EXPECT_TRUE(a.x >= 4.0 - kLengthTol && a.x <= 36.0 + kLengthTol && a.y >= 4.0 - kLengthTol && a.y <= 36.0 + kLengthTol);
        EXPECT_FALSE(a.x > 8.0 + kLengthTol && a.x < 32.0 - kLengthTol && a.y > 8.0 + kLengthTol && a.y < 32.0 - kLengthTol)
            << "fill point (" << a.x << ", " << a.y << ") inside the hole's perimeters, layer " << l.layer;
      }
    }
  }
}

TEST(Toolpath, ContourFillContinuesTheOffsetsUntilEmpty) {
  const mesh::Mesh box = repaired(test::box({0, 0, 0}, {40, 30, 4}));
  ToolpathOptions o;
  o.fill = ToolpathOptions::kContour;
  const auto layers = plan(box, sliced(box, 1.0), o);
  for (const auto& l : layers) {
    const auto fill = of_kind(l, PathKind::kFill);
    ASSERT_EQ(fill.size(), 5u);  // offsets 5, 7, 9, 11, 13 mm; at 15 mm the 30 mm side closes
    for (const Path* p : fill) {
      const double off = 1.0 + 2.0 * p->perimeter_index;
      EXPECT_NEAR(xy_area(*p), (40 - 2 * off) * (30 - 2 * off), kAreaTol);
      EXPECT_FALSE(p->surface_contour);
    }
  }
}

TEST(Toolpath, OverlapBringsBeadsCloser) {
  const mesh::Mesh box = repaired(test::box({0, 0, 0}, {40, 30, 2}));
  ToolpathOptions o;
  o.overlap = 0.25;
  o.perimeters = 3;
  const auto layers = plan(box, sliced(box, 1.0), o);
  for (const auto& l : layers) {
    for (const Path* p : of_kind(l, PathKind::kPerimeter)) {
      const double off = 1.0 + 1.5 * p->perimeter_index;
      EXPECT_NEAR(xy_area(*p), (40 - 2 * off) * (30 - 2 * off), kAreaTol);
    }
  }
}

TEST(Toolpath, ThinWallIsReportedNotDropped) {
  // 0.8 mm: less than half the 2 mm bead, so not even gap fill lays it.
  const mesh::Mesh wall = repaired(test::box({0, 0, 0}, {40, 0.8, 3}));
  const auto layers = plan(wall, sliced(wall, 1.0), ToolpathOptions{});
  ASSERT_EQ(layers.size(), 3u);
  for (const auto& l : layers) {
    EXPECT_TRUE(l.paths.empty());
    ASSERT_EQ(l.thin.size(), 1u);
    EXPECT_EQ(l.thin[0].layer, l.layer);
    EXPECT_NEAR(l.thin[0].area_mm2, 32.0, kAreaTol);
    EXPECT_NEAR(l.thin[0].where_mm.x, 20.0, 1e-6);
    EXPECT_NEAR(l.thin[0].where_mm.y, 0.4, 1e-6);
    EXPECT_NEAR(l.thin[0].where_mm.z, l.layer + 0.5, 1e-9);
    EXPECT_FALSE(l.thin[0].what.empty());
  }
}

TEST(Toolpath, ThinFinOnABlockIsReported) {
  // A 0.8 mm fin from x = 20 to 40 on a 20 mm block: the block gets perimeters, the fin is reported.
  const mesh::Mesh part = repaired(test::join(test::box({0, 0, 0}, {20, 20, 2}), test::box({15, 9.6, 0}, {40, 10.4, 2})));
  const auto layers = plan(part, sliced(part, 1.0), ToolpathOptions{});
  ASSERT_EQ(layers.size(), 2u);
  for (const auto& l : layers) {
    EXPECT_EQ(of_kind(l, PathKind::kPerimeter).size(), 2u);
    ASSERT_EQ(l.thin.size(), 1u);
    EXPECT_NEAR(l.thin[0].area_mm2, 16.0, 0.01);  // 20 × 0.8 mm, less the 1 µm slack
    EXPECT_NEAR(l.thin[0].where_mm.x, 30.0, 0.01);
  }
}

// The gap-fill paths of a layer.
std::vector<const Path*> gap_fill_of(const LayerToolpaths& l) {
  std::vector<const Path*> out;
  for (const Path& p : l.paths) {
    if (p.gap_fill) out.push_back(&p);
  }
  return out;
}

double path_length(const Path& p) {
  double l = 0.0;
  for (std::size_t i = 1; i < p.points.size(); ++i) l += core::norm(p.points[i].position_mm - p.points[i - 1].position_mm);
  return l;
}

// Blocks of widths that are no whole number of beads, turned about Z: the beads of each layer
// (perimeters and fill, swept a bead wide) cover its section but for the perimeters' rounded
// corners. Fill lines laid from one side a bead apart left a strip up to a bead wide bare along
// the far perimeter, under which the read-back found beads of the next layer over nothing.
TEST(Toolpath, ZigzagFillSpreadsItsLinesSoNoStripIsLeftBareAlongThePerimeters) {
  for (const double width : {7.3, 9.1, 12.45, 17.0, 23.7}) {
    for (const double turn_deg : {0.0, 23.0, 90.0}) {
      for (const double overlap : {0.0, 0.25}) {
        // Lines oblique to the sides at no overlap leave slivers in the zigzag's acute turns (the
        // beads only touch there): that case is left out.
        if (turn_deg == 23.0 && overlap == 0.0) continue;
        io::RawMesh raw = test::box({-15, -width / 2.0, 0}, {15, width / 2.0, 2});
        const double c = std::cos(turn_deg * kPi / 180.0), s = std::sin(turn_deg * kPi / 180.0);
        for (core::Vec3& p : raw.points) p = {c * p.x - s * p.y, s * p.x + c * p.y, p.z};
        const mesh::Mesh block = repaired(std::move(raw));
        ToolpathOptions o;
        o.overlap = overlap;
        const auto sections = sliced(block, 1.0);
        const auto layers = plan(block, sections, o);
        ASSERT_EQ(layers.size(), sections.layers.size());
        for (std::size_t k = 0; k < layers.size(); ++k) {
          std::vector<geom2d::Ring> beads;
          for (const Path& path : layers[k].paths) {
            geom2d::Ring line;
            for (const PathPoint& q : path.points) line.push_back({geom2d::to_units(q.position_mm.x), geom2d::to_units(q.position_mm.y)});
            beads.push_back(std::move(line));
          }
          const auto covered = geom2d::sweep_open(beads, o.bead_width_mm / 2.0);
          const double bare = geom2d::area_mm2(geom2d::difference_rings(geom2d::rings_of(sections.layers[k].polygons), geom2d::rings_of(covered)));
          // Each perimeter's round bead leaves its four square corners outside it bare: (1 - pi/4)(w/2)^2
          // each (a hair more on the polygonal arcs, within kAreaTol).
          const double corners = 4.0 * o.perimeters * (1.0 - kPi / 4.0) * o.bead_width_mm * o.bead_width_mm / 4.0;
          EXPECT_LE(bare, corners + kAreaTol) << width << " mm wide, turned " << turn_deg << " deg, overlap " << overlap << ", layer " << k;
        }
      }
    }
  }
}

TEST(Toolpath, WallsAndFinsBetweenHalfABeadAndABeadGetOneBeadAlongTheirMiddle) {
  // Widths of 1.1–1.9 mm with a 2 mm bead, at several lengths and turns about Z: one open fill
  // path along the middle, on the layer, laid (deposit after its first point), nothing reported.
  for (const double width : {1.1, 1.5, 1.9}) {
    for (const double length : {6.0, 40.0}) {
      const mesh::Mesh wall = repaired(test::box({0, 0, 0}, {length, width, 3}));
      const auto layers = plan(wall, sliced(wall, 1.0), ToolpathOptions{});
      ASSERT_EQ(layers.size(), 3u);
      for (const auto& l : layers) {
        EXPECT_TRUE(l.thin.empty()) << width << " " << length;
        const auto gap = gap_fill_of(l);
        ASSERT_EQ(gap.size(), 1u) << width << " " << length;
        EXPECT_EQ(gap[0]->kind, PathKind::kFill);
        EXPECT_FALSE(gap[0]->points.front().deposit);
        EXPECT_TRUE(gap[0]->points.back().deposit);
        for (const PathPoint& q : gap[0]->points) {
          EXPECT_NEAR(q.position_mm.y, width / 2.0, 1e-5);
          EXPECT_NEAR(q.position_mm.z, l.layer + 0.5, 1e-9);
        }
        // The skeleton's spine: from half the width in from one end to half the width from the other.
        EXPECT_NEAR(path_length(*gap[0]), length - width, 1e-4) << width << " " << length;
      }
    }
  }
  // The fin on a block: laid along its middle from the block's perimeter bead to the fin's end.
  const mesh::Mesh part = repaired(test::join(test::box({0, 0, 0}, {20, 20, 2}), test::box({15, 9.3, 0}, {40, 10.7, 2})));
  for (const auto& l : plan(part, sliced(part, 1.0), ToolpathOptions{})) {
    EXPECT_TRUE(l.thin.empty());
    const auto gap = gap_fill_of(l);
    ASSERT_EQ(gap.size(), 1u);
    double x1 = 0.0;
    for (const PathPoint& q : gap[0]->points) {
      EXPECT_NEAR(q.position_mm.y, 10.0, 1e-5);
      x1 = std::max(x1, q.position_mm.x);
    }
    EXPECT_NEAR(x1, 40.0 - 0.7, 1e-4);
  }
  ToolpathOptions off;
  off.gap_fill = false;
  const mesh::Mesh wall = repaired(test::box({0, 0, 0}, {40, 1.5, 3}));
  for (const auto& l : plan(wall, sliced(wall, 1.0), off)) {
    EXPECT_TRUE(l.paths.empty());
    EXPECT_EQ(l.thin.size(), 1u);
  }
}

// A bar LENGTH × WIDTH × 2 mm centred on the origin, turned TURN_DEG about Z.
mesh::Mesh turned_bar(double length, double width, double turn_deg) {
  io::RawMesh bar = test::box({-length / 2.0, -width / 2.0, 0}, {length / 2.0, width / 2.0, 2});
  const double c = std::cos(turn_deg * kPi / 180.0), s = std::sin(turn_deg * kPi / 180.0);
  for (auto& p : bar.points) p = {c * p[0] - s * p[1], s * p[0] + c * p[1], p[2]};
  return repaired(std::move(bar));
}

TEST(Toolpath, AnInteriorNarrowerThanTheLineSpacingGetsOneBeadAlongItsMiddleAtAnyTurn) {
  // Bars a few beads wide (bead 0.9 mm, two perimeters: 3.6 mm of perimeter beads) leave an
  // interior of 0.2–0.8 mm. Turned about Z by any angle, on layers whose fill turns by 90° from one
  // to the next, each layer's fill is one bead along the bar's middle (a zigzag would cross the
  // strip in short strokes, or run beside it and leave it bare).
  ToolpathOptions o;
  o.bead_width_mm = 0.9;
  o.perimeters = 2;
  constexpr double kLength = 40.0;
  for (const double width : {4.1, 4.3, 4.4}) {
    for (const double turn_deg : {0.0, 6.0, 30.0, 45.0, 84.0, 90.0}) {
      const double c = std::cos(turn_deg * kPi / 180.0), s = std::sin(turn_deg * kPi / 180.0);
      const mesh::Mesh part = turned_bar(kLength, width, turn_deg);
      const auto layers = plan(part, sliced(part, 0.5), o);
      ASSERT_EQ(layers.size(), 4u);
      for (const auto& l : layers) {
        const auto fill = of_kind(l, PathKind::kFill);
        ASSERT_EQ(fill.size(), 1u) << width << " " << turn_deg << " layer " << l.layer;
        EXPECT_FALSE(fill[0]->gap_fill);
        for (const PathPoint& q : fill[0]->points) {
          const double across = -s * q.position_mm.x + c * q.position_mm.y;  // from the bar's middle
          EXPECT_NEAR(across, 0.0, 1e-5) << width << " " << turn_deg;
        }
        // The skeleton's spine of the interior: its length less the interior's width.
        const double interior = width - 4.0 * o.bead_width_mm;
        EXPECT_NEAR(path_length(*fill[0]), kLength - 4.0 * o.bead_width_mm - interior, 1e-3) << width << " " << turn_deg;
      }
    }
  }
}

TEST(Toolpath, AGapBetweenPerimetersGetsOneBeadAlongItsMiddle) {
  // Bars between two and three beads wide (bead 0.9 mm, two perimeters asked): the second
  // perimeter does not fit, and the first leaves a gap of 0.5–0.85 mm between its sides. Turned
  // about Z, every layer lays one gap-fill bead along the bar's middle, a whole spine long, and
  // reports nothing; the bead rests on the one below (each layer's line over the last).
  ToolpathOptions o;
  o.bead_width_mm = 0.9;
  o.perimeters = 2;
  constexpr double kLength = 30.0;
  for (const double width : {2.3, 2.55, 2.65}) {
    for (const double turn_deg : {0.0, 17.0, 90.0}) {
      const double c = std::cos(turn_deg * kPi / 180.0), s = std::sin(turn_deg * kPi / 180.0);
      const mesh::Mesh part = turned_bar(kLength, width, turn_deg);
      const auto layers = plan(part, sliced(part, 0.5), o);
      ASSERT_EQ(layers.size(), 4u);
      for (const auto& l : layers) {
        EXPECT_TRUE(l.thin.empty()) << width << " " << turn_deg;
        EXPECT_EQ(of_kind(l, PathKind::kPerimeter).size(), 1u);
        const auto gap = gap_fill_of(l);
        ASSERT_EQ(gap.size(), 1u) << width << " " << turn_deg << " layer " << l.layer;
        EXPECT_TRUE(gap[0]->points.back().deposit);
        for (const PathPoint& q : gap[0]->points) {
          EXPECT_NEAR(-s * q.position_mm.x + c * q.position_mm.y, 0.0, 1e-5) << width << " " << turn_deg;
        }
        // The gap is the bar less a bead from each side; its spine is its length less its width.
        const double gap_width = width - 2.0 * o.bead_width_mm;
        EXPECT_NEAR(path_length(*gap[0]), kLength - 2.0 * o.bead_width_mm - gap_width, 1e-3) << width << " " << turn_deg;
      }
    }
  }
  // Narrower than a gap-fill bead may be (0.2 mm): the beads' spread; nothing laid or reported.
  const mesh::Mesh narrow = repaired(test::box({0, 0, 0}, {kLength, 2.0, 2}));
  for (const auto& l : plan(narrow, sliced(narrow, 0.5), o)) {
    EXPECT_TRUE(l.thin.empty());
    EXPECT_TRUE(gap_fill_of(l).empty());
  }
  // A tongue 2.55 mm wide on a block: both perimeters run round the block, the first alone down
  // the tongue, and the gap it leaves there gets one bead from the block's second perimeter's bead
  // to the tongue's end (each end half the gap's width in).
  const mesh::Mesh tongue = repaired(test::join(test::box({0, 0, 0}, {12, 12, 2}), test::box({11, 4.725, 0}, {40, 7.275, 2})));
  for (const auto& l : plan(tongue, sliced(tongue, 0.5), o)) {
    EXPECT_TRUE(l.thin.empty());
    const auto gap = gap_fill_of(l);
    ASSERT_EQ(gap.size(), 1u);
    double x0 = INFINITY, x1 = -INFINITY;
    for (const PathPoint& q : gap[0]->points) {
      EXPECT_NEAR(q.position_mm.y, 6.0, 1e-5);
      x0 = std::min(x0, q.position_mm.x), x1 = std::max(x1, q.position_mm.x);
    }
    EXPECT_NEAR(x1, 40.0 - 0.9 - 0.375, 1e-3);
    EXPECT_NEAR(x0, 12.0 - 0.9 + 0.375, 2e-3);  // the second perimeter's bead ends 0.9 inside the block (+1 µm slack)
  }
}

TEST(Toolpath, AChannelBranchingOffAnotherGetsItsOwnBead) {
  // Walls 2.55 mm thick (bead 0.9 mm, two perimeters asked) leave a 0.75 mm channel between the
  // first perimeter's sides. Where one wall branches off another the channels branch too, and the
  // branch that the first centre line does not follow gets a bead of its own, to its end: a T (the
  // skeleton's side branch) and a square tube with a fin (a loop round the tube's channel, with the
  // fin's channel off it), each turned about Z. Nothing is reported thin.
  ToolpathOptions o;
  o.bead_width_mm = 0.9;
  o.perimeters = 2;
  const double end_in = 0.9 + 0.375 + 0.05;  // a branch's bead ends a bead and half the channel in, and a little slack
  struct Case {
    const char* name;
    std::vector<std::pair<Vec3, Vec3>> boxes;
    std::vector<Vec3> ends;  // the channels' ends, each reached by a gap-fill point
  };
  const std::vector<Case> cases = {
      {"T", {{{0, 0, 0}, {30, 2.55, 2}}, {{13.725, 1, 0}, {16.275, 14, 2}}}, {{0, 1.275, 0}, {30, 1.275, 0}, {15, 14, 0}}},
      {"tube with a fin",
       {{{0, 0, 0}, {20, 2.55, 2}}, {{0, 17.45, 0}, {20, 20, 2}}, {{0, 0, 0}, {2.55, 20, 2}}, {{17.45, 0, 0}, {20, 20, 2}},
        {{19, 8.725, 0}, {32, 11.275, 2}}},
       {{32, 10, 0}}}};
  for (const Case& k : cases) {
    for (const double turn_deg : {0.0, 23.0}) {
      const double c = std::cos(turn_deg * kPi / 180.0), s = std::sin(turn_deg * kPi / 180.0);
      auto turned = [&](Vec3 p) { return Vec3{c * p.x - s * p.y, s * p.x + c * p.y, p.z}; };
      io::RawMesh raw;
      for (const auto& [lo, hi] : k.boxes) raw = test::join(raw, test::box(lo, hi));
      for (auto& p : raw.points) {
        const Vec3 q = turned({p[0], p[1], p[2]});
        p = {q.x, q.y, q.z};
      }
      const mesh::Mesh part = repaired(std::move(raw));
      const auto layers = plan(part, sliced(part, 0.5), o);
      ASSERT_EQ(layers.size(), 4u) << k.name;
      for (const auto& l : layers) {
        EXPECT_TRUE(l.thin.empty()) << k.name << " " << turn_deg << " layer " << l.layer << ": " << l.thin.size() << " thin regions";
        const auto gap = gap_fill_of(l);
        for (const Vec3& end : k.ends) {
          double nearest = INFINITY;
          for (const Path* p : gap) {
            for (const PathPoint& q : p->points) {
              nearest = std::min(nearest, std::hypot(q.position_mm.x - turned(end).x, q.position_mm.y - turned(end).y));
            }
          }
          EXPECT_LE(nearest, end_in) << k.name << " " << turn_deg << " layer " << l.layer << " end (" << end.x << ", " << end.y << ")";
        }
      }
    }
  }
}

// A round tube (radii R_OUT, R_IN, N sides) LENGTH long, turned LEAN_DEG about Y from standing
// upright (its horizontal sections are elliptic annuli, their walls 1/cos(LEAN_DEG) thicker along X).
mesh::Mesh leaning_tube(double r_out, double r_in, double length, double lean_deg, std::uint32_t n) {
  io::RawMesh m;
  const double c = std::cos(lean_deg * kPi / 180.0), s = std::sin(lean_deg * kPi / 180.0);
  for (const double z : {0.0, length}) {
    for (const double r : {r_out, r_in}) {
      for (std::uint32_t i = 0; i < n; ++i) {
        const double a = 2.0 * kPi * i / n, x = r * std::cos(a);
        m.points.push_back({c * x + s * z, r * std::sin(a), -s * x + c * z});
      }
    }
  }
  auto at = [&](std::uint32_t level, std::uint32_t ring, std::uint32_t i) { return (2 * level + ring) * n + i % n; };
  for (std::uint32_t i = 0; i < n; ++i) {
    m.triangles.push_back({at(0, 0, i), at(0, 0, i + 1), at(1, 0, i + 1)});  // outer wall
    m.triangles.push_back({at(0, 0, i), at(1, 0, i + 1), at(1, 0, i)});
    m.triangles.push_back({at(0, 1, i), at(1, 1, i + 1), at(0, 1, i + 1)});  // inner wall, facing the axis
    m.triangles.push_back({at(0, 1, i), at(1, 1, i), at(1, 1, i + 1)});
    m.triangles.push_back({at(0, 0, i), at(0, 1, i + 1), at(0, 0, i + 1)});  // bottom
    m.triangles.push_back({at(0, 0, i), at(0, 1, i), at(0, 1, i + 1)});
    m.triangles.push_back({at(1, 0, i), at(1, 0, i + 1), at(1, 1, i + 1)});  // top
    m.triangles.push_back({at(1, 0, i), at(1, 1, i + 1), at(1, 1, i)});
  }
  return repaired(std::move(m));
}

TEST(Toolpath, AGapBetweenPerimetersNarrowingToTheBeadsSpreadIsNotReported) {
  // A tube with 2.2 mm walls leaning 30° (bead 0.9 mm, two perimeters): where its sections are
  // whole annuli their walls are 2.54 mm thick front and back and 2.2 mm at the sides, so the first
  // perimeter's sides leave a channel 0.74 mm wide front and back that narrows to 0.4 mm at the
  // sides, less than a gap-fill bead (half a bead): the beads' spread there, as in a wall that
  // thin all round. The channel gets its beads front and back, and no thin region is reported there.
  ToolpathOptions o;
  o.bead_width_mm = 0.9;
  o.perimeters = 2;
  o.max_step_mm = 0.45;  // each layer's channel is 0.29 mm from the one below
  for (const std::uint32_t sides : {96u, 61u}) {
    const mesh::Mesh tube = leaning_tube(8.0, 5.8, 20.0, 30.0, sides);
    const auto s = sliced(tube, 0.5);
    const auto layers = plan(tube, s, o);
    ASSERT_EQ(layers.size(), s.layers.size());
    double lowest = INFINITY;
    for (const Vec3& v : tube.vertices) lowest = std::min(lowest, v.z);
    std::size_t whole = 0;
    for (std::size_t k = 0; k < layers.size(); ++k) {
      const double z = s.layers[k].frame.origin.z - lowest;
      if (z < 8.0 + 0.5 || z > 20.0 * std::cos(kPi / 6.0) - 0.5) continue;  // a whole annulus: from 2·8·sin 30° up to 20·cos 30°
      ++whole;
      EXPECT_TRUE(layers[k].thin.empty()) << sides << " sides, layer " << k << ": " << layers[k].thin.size() << " thin regions";
      EXPECT_EQ(gap_fill_of(layers[k]).size(), 2u) << sides << " sides, layer " << k;
    }
    EXPECT_GE(whole, 15u);
  }
}

TEST(Toolpath, GapFillIsLaidOnlyOverTheBeadsOfTheLayerBelow) {
  // A wall 0.8 mm thick (too thin to lay) under 1.5 mm (gap fill): nothing is laid over the unlaid
  // layers, so the upper part is reported too. The other way up, the lower part is laid and the
  // upper reported.
  const mesh::Mesh thin_under = repaired(test::join(test::box({0, 0.35, 0}, {30, 1.15, 2}), test::box({0, 0, 1.5}, {30, 1.5, 4})));
  const auto up = plan(thin_under, sliced(thin_under, 0.5), ToolpathOptions{});
  ASSERT_EQ(up.size(), 8u);
  for (const auto& l : up) {
    EXPECT_TRUE(l.paths.empty()) << l.layer;
    EXPECT_EQ(l.thin.size(), 1u) << l.layer;
  }
  const mesh::Mesh wide_under = repaired(test::join(test::box({0, 0, 0}, {30, 1.5, 2}), test::box({0, 0.35, 1.5}, {30, 1.15, 4})));
  const auto down = plan(wide_under, sliced(wide_under, 0.5), ToolpathOptions{});
  ASSERT_EQ(down.size(), 8u);
  for (const auto& l : down) {
    const bool wide = l.layer < 4;
    EXPECT_EQ(gap_fill_of(l).size(), wide ? 1u : 0u) << l.layer;
    EXPECT_EQ(l.thin.size(), wide ? 0u : 1u) << l.layer;
  }
  // A wall that narrows from 1.5 to 0.8 mm midway along its length, under a wall 1.5 mm all along:
  // the lower layers' line stops where the wall narrows, and each layer above reaches at most
  // t·tan α (0.5 mm · tan 30°) beyond the line below it.
  io::RawMesh stepped = test::join(test::box({0, 0, 0}, {15, 1.5, 2}), test::box({14, 0.35, 0}, {30, 1.15, 2}));
  stepped = test::join(stepped, test::box({0, 0, 1.5}, {30, 1.5, 4}));
  const auto mixed = plan(repaired(stepped), sliced(repaired(stepped), 0.5), ToolpathOptions{});
  ASSERT_EQ(mixed.size(), 8u);
  double below_x1 = 0.0;
  for (const auto& l : mixed) {
    const auto gap = gap_fill_of(l);
    ASSERT_EQ(gap.size(), 1u) << l.layer;
    double x1 = 0.0;
    for (const PathPoint& q : gap[0]->points) x1 = std::max(x1, q.position_mm.x);
    if (l.layer < 4) {
      EXPECT_LT(x1, 15.5) << l.layer;
    } else {
      EXPECT_GT(x1, below_x1 + 0.1) << l.layer;  // the wider part above leans out as far as it may
    }
    if (l.layer > 0) {
      EXPECT_LE(x1, below_x1 + 0.5 * std::tan(30.0 * kPi / 180.0) + 1e-3) << l.layer;
    }
    below_x1 = x1;
  }
}

TEST(Toolpath, GapFillStepsAsFarAsTheMaxStepLetsAWallLean) {
  // Walls 1.5 mm thick (gap fill, bead 2 mm) leaning so that each 1 mm layer steps 0.7 or 0.9 mm,
  // more than t·tan α (0.58 mm) and at most half a bead: with max_step_mm (as the planner sets it
  // from the process) every layer is laid, each line within max_step_mm of the one below; without
  // it only the first layer is, and the rest are reported.
  for (const double shift : {0.7, 0.9}) {
    const double h = 5.0;
    const mesh::Mesh wall = repaired(test::prism_xz({{0, 0}, {1.5, 0}, {1.5 + shift * h, h}, {shift * h, h}}, 30.0));
    ToolpathOptions o;
    o.max_step_mm = 1.0;
    const auto laid = plan(wall, sliced(wall, 1.0), o);
    ASSERT_EQ(laid.size(), 5u);
    double below_x = 0.0;
    for (const auto& l : laid) {
      EXPECT_TRUE(l.thin.empty()) << shift << " layer " << l.layer;
      const auto gap = gap_fill_of(l);
      ASSERT_EQ(gap.size(), 1u) << shift << " layer " << l.layer;
      const double x = gap[0]->points.front().position_mm.x;
      EXPECT_NEAR(x, shift * (l.layer + 0.5) + 0.75, 1e-3) << shift << " layer " << l.layer;
      if (l.layer > 0) {
        EXPECT_LE(x - below_x, o.max_step_mm + 1e-6);
      }
      below_x = x;
    }
    for (const auto& l : plan(wall, sliced(wall, 1.0), ToolpathOptions{})) {
      EXPECT_EQ(gap_fill_of(l).size(), l.layer == 0 ? 1u : 0u) << shift << " layer " << l.layer;
    }
  }
  ToolpathOptions bad;
  bad.max_step_mm = -1.0;
  const mesh::Mesh box = repaired(test::box({0, 0, 0}, {10, 10, 2}));
  EXPECT_FALSE(make_toolpaths(box, sliced(box, 1.0), bad).ok());
}

// Every pair of consecutive points of PATHS at least the program's resolution apart (0.1 µm: the
// G-code's words), else the G-code gets a block where the tip stays and the tool turns in place.
void expect_distinct_points(const std::vector<LayerToolpaths>& layers, const std::string& what) {
  std::size_t near = 0, points = 0;
  for (const LayerToolpaths& l : layers) {
    for (const Path& p : l.paths) {
      points += p.points.size();
      for (std::size_t i = 1; i < p.points.size(); ++i) near += core::norm(p.points[i].position_mm - p.points[i - 1].position_mm) < 1e-4;
    }
  }
  EXPECT_GT(points, 0u) << what;
  EXPECT_EQ(near, 0u) << what << ": " << near << " of " << points << " path points within 0.1 um of the one before";
}

TEST(Toolpath, NoPathPointFallsWithinTheProgramsResolutionOfTheOneBefore) {
  // A star whose reflex corners the inward offsets round off, stood along Y, sliced across.
  std::vector<std::array<double, 2>> star;
  for (int k = 0; k < 14; ++k) {
    const double a = 2.0 * kPi * k / 14.0 + 0.11, r = k % 2 == 0 ? 12.0 : 5.5;
    star.push_back({r * std::cos(a), 10.0 + r * std::sin(a)});
  }
  const mesh::Mesh prism = repaired(test::prism_xz(star, 3.0));
  slicing::SliceOptions across;
  across.layer_mm = 0.7;
  across.direction = {0, 1, 0};
  const auto star_layers = slicing::slice(prism, across);
  ASSERT_TRUE(star_layers.ok());
  // A round bar bent through a quarter turn (a torus' sector), and a reference part built of them.
  const mesh::Mesh bent = repaired(test::bent_bar(20.0, 5.0, 90.0, 64, 32));
  auto read = io::read_part(std::string(POLYAXIS_PARTS_DIR) + "/two_branches.stl");
  ASSERT_TRUE(read.ok());
  const mesh::Mesh two_branches = repaired(std::move(read.value().mesh));
  for (auto fill : {ToolpathOptions::kZigzag, ToolpathOptions::kContour}) {
    ToolpathOptions o;
    o.fill = fill;
    expect_distinct_points(plan(prism, star_layers.value(), o), "star");
    expect_distinct_points(plan(bent, sliced(bent, 0.6), o), "bent bar");
    expect_distinct_points(plan(two_branches, sliced(two_branches, 0.6), o), "two_branches");
  }
}

TEST(Toolpath, SeamsMoveFromLayerToLayer) {
  const mesh::Mesh box = repaired(test::box({0, 0, 0}, {40, 30, 20}));
  const auto layers = plan(box, sliced(box, 1.0), ToolpathOptions{});
  ASSERT_EQ(layers.size(), 20u);
  for (std::size_t k = 0; k + 1 < layers.size(); ++k) {
    const Vec3 a = layers[k].paths.front().points.front().position_mm, b = layers[k + 1].paths.front().points.front().position_mm;
    EXPECT_FALSE(a.x == b.x && a.y == b.y) << "layers " << k << " and " << k + 1 << " share a seam";
  }
}

TEST(Toolpath, VerticalWallsKeepTheBuildDirection) {
  const mesh::Mesh box = repaired(test::box({0, 0, 0}, {40, 30, 10}));
  for (const auto& l : plan(box, sliced(box, 1.0), ToolpathOptions{})) {
    for (const Path& p : l.paths) {
      for (const PathPoint& q : p.points) EXPECT_EQ(q.tool_axis, (Vec3{0, 0, 1}));
    }
  }
}

constexpr std::uint32_t kFrustumSides = 64;

// The angle from vertical of the side facets of frustum(10, R1, 10, kFrustumSides): the flat
// sides lie at cos(π/N) times the corner radius.
double frustum_wall_rad(double r1) { return std::atan((r1 - 10.0) * std::cos(kPi / kFrustumSides) / 10.0); }

// Outer-contour points of a frustum widening upwards: every move over an overhanging wall is
// tilted by the wall angle (up to the limit), outwards and up; everything else keeps d.
void expect_frustum_tilt(double r1, double expected_tilt_rad, const ToolpathOptions& o) {
  const mesh::Mesh m = repaired(frustum(10.0, r1, 10.0, kFrustumSides));
  const auto layers = plan(m, sliced(m, 1.0), o);
  ASSERT_EQ(layers.size(), 10u);
  expect_unit_axes(layers);
  const Vec3 d{0, 0, 1};
  std::size_t tilted = 0;
  for (const auto& l : layers) {
    for (const Path& p : l.paths) {
      for (std::size_t i = 0; i < p.points.size(); ++i) {
        const PathPoint& q = p.points[i];
        if (p.kind == PathKind::kTravel) continue;  // takes the axes of the paths it joins
        if (!p.surface_contour) {
          EXPECT_EQ(q.tool_axis, d);
          continue;
        }
        EXPECT_GT(core::dot(q.tool_axis, d), 0.0);
        EXPECT_LE(tilt_rad(q, d), kMaxTiltRad + 1e-12);
        EXPECT_NEAR(tilt_rad(q, d), expected_tilt_rad, 1e-6) << "layer " << l.layer;
        const Vec3 radial{q.position_mm.x, q.position_mm.y, 0.0};
        if (expected_tilt_rad > 0.0) {
          EXPECT_GT(core::dot(q.tool_axis, radial), 0.0) << "the torch leans outwards, along the wall";
          ++tilted;
        }
      }
    }
  }
  if (expected_tilt_rad > 0.0) {
    EXPECT_GT(tilted, 0u);
  }
}

TEST(Toolpath, OverhangingFrustumTiltsOuterContoursByTheWallAngle) {
  expect_frustum_tilt(20.0, frustum_wall_rad(20.0), ToolpathOptions{});  // wall ≈ 45° from vertical
}

TEST(Toolpath, SteepOverhangTiltIsLimited) {
  expect_frustum_tilt(40.0, kMaxTiltRad, ToolpathOptions{});  // wall atan(3) ≈ 71.6° from vertical
}

TEST(Toolpath, SelfSupportingWallIsNotTilted) {
  const double r1 = 10.0 + 10.0 * std::tan(20.0 * kPi / 180.0);  // wall 20° from vertical
  expect_frustum_tilt(r1, 0.0, ToolpathOptions{});
  ToolpathOptions kapil;  // α = 0: Kapil's Eq. 2 as printed, every downward facet overhangs
  kapil.self_supporting_deg = 0.0;
  expect_frustum_tilt(r1, frustum_wall_rad(r1), kapil);
  ToolpathOptions off;
  off.tilt_on_overhang = false;
  expect_frustum_tilt(20.0, 0.0, off);
}

// A cylinder of radius R_OUT around a bore narrowing upwards from R0 at z = 0 to R1 at z = H
// (N-gons): the bore's wall leans inwards and overhangs, as a bottle's shoulder or a dome closing
// in does from inside.
io::RawMesh closing_bore(double r_out, double r0, double r1, double h, std::uint32_t n) {
  io::RawMesh m;
  for (const auto& [r, z] : std::vector<std::array<double, 2>>{{r_out, 0.0}, {r_out, h}, {r0, 0.0}, {r1, h}}) {
    for (std::uint32_t i = 0; i < n; ++i) m.points.push_back({r * std::cos(2.0 * kPi * i / n), r * std::sin(2.0 * kPi * i / n), z});
  }
  const std::uint32_t ob = 0, ot = n, ib = 2 * n, it = 3 * n;
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t j = (i + 1) % n;
    m.triangles.push_back({ob + i, ob + j, ot + j});  // the outer wall, outwards
    m.triangles.push_back({ob + i, ot + j, ot + i});
    m.triangles.push_back({ib + i, it + j, ib + j});  // the bore's wall, towards the axis
    m.triangles.push_back({ib + i, it + i, it + j});
    m.triangles.push_back({ob + i, ib + j, ob + j});  // the bottom ring, down
    m.triangles.push_back({ob + i, ib + i, ib + j});
    m.triangles.push_back({ot + i, ot + j, it + j});  // the top ring, up
    m.triangles.push_back({ot + i, it + j, it + i});
  }
  return m;
}

TEST(Toolpath, AnOverhangingHoleWallTiltsTheHoleContourInwards) {
  // Kapil's Eq. 1-3 hold on every contour of the part's surface, a hole's as well as the outer one.
  constexpr std::uint32_t kSides = 64;
  for (const auto& [r0, r1] : std::vector<std::array<double, 2>>{{20.0, 8.0}, {14.0, 6.0}}) {
    const double wall = std::atan((r0 - r1) * std::cos(kPi / kSides) / 10.0);  // from vertical: 50°, 38.7°
    const mesh::Mesh m = repaired(closing_bore(25.0, r0, r1, 10.0, kSides));
    const auto layers = plan(m, sliced(m, 1.0), ToolpathOptions{});
    ASSERT_EQ(layers.size(), 10u);
    expect_unit_axes(layers);
    const Vec3 d{0, 0, 1};
    std::size_t tilted = 0;
    for (const auto& l : layers) {
      for (const Path& p : l.paths) {
        if (p.kind == PathKind::kTravel) continue;
        for (const PathPoint& q : p.points) {
          const Vec3 radial{q.position_mm.x, q.position_mm.y, 0.0};
          const bool on_bore = p.surface_contour && core::norm(radial) < 0.5 * (r0 + 25.0);
          if (!on_bore) {
            EXPECT_EQ(q.tool_axis, d) << "the outer wall stands upright; inner perimeters and fill keep d";
            continue;
          }
          EXPECT_NEAR(tilt_rad(q, d), std::min(wall, kMaxTiltRad), 1e-6) << "layer " << l.layer;
          EXPECT_LT(core::dot(q.tool_axis, radial), 0.0) << "the torch leans inwards, along the bore's wall";
          ++tilted;
        }
      }
    }
    EXPECT_GT(tilted, 0u);
  }
}

TEST(Toolpath, SameOutputAtAnyThreadCount) {
  const mesh::Mesh m = repaired(frustum(10.0, 20.0, 30.0, 48));
  const auto s = sliced(m, 0.5);
  ToolpathOptions one, two;
  one.threads = 1;
  two.threads = 2;
  one.fill_angle_deg = two.fill_angle_deg = 30.0;
  const auto a = plan(m, s, one), b = plan(m, s, two);
  ASSERT_EQ(a.size(), s.layers.size());
  EXPECT_TRUE(same(a, b));
}

TEST(Toolpath, RejectsBadOptions) {
  const mesh::Mesh box = repaired(test::cube());
  const auto s = sliced(box, 1.0);
  ToolpathOptions o;
  o.bead_width_mm = 0.0;
  EXPECT_FALSE(make_toolpaths(box, s, o).ok());
  o = {};
  o.overlap = 1.0;
  EXPECT_FALSE(make_toolpaths(box, s, o).ok());
  o = {};
  o.self_supporting_deg = 90.0;
  EXPECT_FALSE(make_toolpaths(box, s, o).ok());
  o = {};
  o.perimeters = -1;
  auto r = make_toolpaths(box, s, o);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, core::ErrorCode::kUsage);
}

// Even-odd point-in-polygon test in the layer's (u, v) frame.
bool inside(const slicing::Layer& layer, Vec3 p) {
  const Vec3 q = p - layer.frame.origin;
  const double u = core::dot(q, layer.frame.u), v = core::dot(q, layer.frame.v);
  bool in = false;
  for (const auto& poly : layer.polygons) {
    std::vector<const geom2d::Ring*> rings{&poly.outer};
    for (const auto& h : poly.holes) rings.push_back(&h);
    for (const geom2d::Ring* r : rings) {
      for (std::size_t i = 0, j = r->size() - 1; i < r->size(); j = i++) {
        const double xi = geom2d::to_mm((*r)[i].x), yi = geom2d::to_mm((*r)[i].y);
        const double xj = geom2d::to_mm((*r)[j].x), yj = geom2d::to_mm((*r)[j].y);
        if ((yi > v) != (yj > v) && u < (xj - xi) * (v - yi) / (yj - yi) + xi) in = !in;
      }
    }
  }
  return in;
}

TEST(Toolpath, ReferencePartsDepositInsideTheirSectionsWithValidAxes) {
  for (const char* name : {"cyl_walls5", "dome_sphere", "hinge", "l_block", "pen_rack", "spiral", "two_branches"}) {
    auto read = io::read_part(std::string(POLYAXIS_PARTS_DIR) + "/" + name + ".stl");
    ASSERT_TRUE(read.ok()) << name;
    const mesh::Mesh m = repaired(std::move(read.value().mesh));
    const auto s = sliced(m, 1.0);
    for (auto fill : {ToolpathOptions::kZigzag, ToolpathOptions::kContour}) {
      ToolpathOptions o;
      o.fill = fill;
      o.fill_angle_deg = 17.0;
      const auto layers = plan(m, s, o);
      ASSERT_EQ(layers.size(), s.layers.size());
      expect_unit_axes(layers);
      for (std::size_t k = 0; k < layers.size(); ++k) {
        const Vec3 d = s.layers[k].frame.d;
        for (const Path& p : layers[k].paths) {
          for (const PathPoint& q : p.points) {
            EXPECT_GT(core::dot(q.tool_axis, d), 0.0);
            EXPECT_LE(tilt_rad(q, d), kMaxTiltRad + 1e-12);
            if (p.kind != PathKind::kTravel) {
              EXPECT_TRUE(inside(s.layers[k], q.position_mm)) << name << " layer " << k;
            }
          }
        }
      }
    }
  }
}

TEST(Toolpath, ImpellerBladeTipsAreTilted) {
  auto read = io::read_part(std::string(POLYAXIS_PARTS_DIR) + "/impeller.stl");
  ASSERT_TRUE(read.ok());
  const mesh::Mesh m = repaired(std::move(read.value().mesh));
  const auto s = sliced(m, 1.0);
  ToolpathOptions one, two;
  one.threads = 1;
  two.threads = 2;
  const auto layers = plan(m, s, two);
  ASSERT_EQ(layers.size(), s.layers.size());
  expect_unit_axes(layers);
  const Vec3 d{0, 0, 1};
  std::size_t tilted = 0, outer = 0;
  for (const auto& l : layers) {
    for (const Path& p : l.paths) {
      for (const PathPoint& q : p.points) {
        EXPECT_GT(core::dot(q.tool_axis, d), 0.0);
        EXPECT_LE(tilt_rad(q, d), kMaxTiltRad + 1e-12);
        if (p.kind == PathKind::kTravel) continue;  // takes the axes of the paths it joins
        if (!p.surface_contour) {
          EXPECT_EQ(q.tool_axis, d);
          continue;
        }
        ++outer;
        if (tilt_rad(q, d) > 1e-9) ++tilted;
      }
    }
  }
  EXPECT_GT(tilted, 0u) << "the blade tips overhang ~40°";
  EXPECT_LT(tilted, outer) << "the hub (16° from vertical) is self-supporting";
  EXPECT_TRUE(same(layers, plan(m, s, one)));
}

}  // namespace
}  // namespace polyaxis::toolpath
