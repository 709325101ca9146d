// Centroidal axis (Ruan §3) on the reference parts (parts/README.md) and on parts built here with
// other sizes and arm layouts, so the expectations are not tuned to the reference files.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

#include "polyaxis/analysis/centroidal_axis.h"
#include "polyaxis/io/read_part.h"
#include "polyaxis/mesh/repair.h"
#include "support/meshes.h"
#include "support/repaired.h"

namespace polyaxis::analysis {
namespace {

constexpr double kPi = 3.14159265358979323846;

using polyaxis::test::repaired;

mesh::RepairedMesh part(const std::string& name) {
  auto read = io::read_part(std::string(POLYAXIS_PARTS_DIR) + "/" + name + ".stl");
  EXPECT_TRUE(read.ok()) << name;
  return repaired(std::move(read.value().mesh));
}

CentroidalAxis axis_of(const mesh::RepairedMesh& m, const CentroidalAxisOptions& o = {}) {
  auto r = centroidal_axis(m.mesh, m.topology, o);
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
  return r.ok() ? std::move(r.value()) : CentroidalAxis{};
}

bool same(Vec3 a, Vec3 b) { return core::norm(a - b) < 1e-12; }
const AxisBranch* root_of(const CentroidalAxis& a) {
  const AxisBranch* root = nullptr;
  for (const auto& b : a.branches) {
    if (!b.father) {
      EXPECT_EQ(root, nullptr) << "more than one root branch";
      root = &b;
    }
  }
  return root;
}
std::vector<const AxisBranch*> children_of(const CentroidalAxis& a, const AxisBranch& b) {
  std::vector<const AxisBranch*> out;
  for (auto c : b.children) out.push_back(&a.branches[c]);
  return out;
}
Vec3 mean_position(const CentroidalAxis& a, const AxisBranch& b) {
  Vec3 s{};
  for (auto n : b.nodes) s = s + a.nodes[n].position;
  return b.nodes.empty() ? s : s / static_cast<double>(b.nodes.size());
}
// The link from the father into the branch's first node.
const AxisLink* connecting_link(const CentroidalAxis& a, const AxisBranch& b) {
  for (const auto& l : a.links) {
    if (l.to == b.nodes.front() && a.nodes[l.from].branch != b.id) return &l;
  }
  return nullptr;
}
std::size_t break_count(const CentroidalAxis& a) {
  return static_cast<std::size_t>(std::count_if(a.links.begin(), a.links.end(), [](const AxisLink& l) { return l.is_break; }));
}

// Structure every axis must have: ids in range, each node in its branch once, father/children and
// brothers consistent, every non-root branch linked to its father.
void expect_well_formed(const CentroidalAxis& a, const std::string& what) {
  ASSERT_FALSE(a.branches.empty()) << what;
  std::vector<int> seen(a.nodes.size(), 0);
  for (const auto& b : a.branches) {
    EXPECT_FALSE(b.nodes.empty()) << what << " branch " << b.id;
    for (auto n : b.nodes) {
      ASSERT_LT(n, a.nodes.size()) << what;
      EXPECT_EQ(a.nodes[n].branch, b.id) << what;
      ++seen[n];
    }
    if (b.father) {
      ASSERT_LT(*b.father, a.branches.size()) << what;
      const auto& f = a.branches[*b.father];
      EXPECT_NE(std::find(f.children.begin(), f.children.end(), b.id), f.children.end()) << what;
      const AxisLink* l = b.nodes.empty() ? nullptr : connecting_link(a, b);
      ASSERT_NE(l, nullptr) << what << " branch " << b.id << " has no connecting link";
      EXPECT_EQ(a.nodes[l->from].branch, *b.father) << what;
      EXPECT_EQ(b.brothers.size(), f.children.size() - 1) << what;
    }
    for (auto c : b.children) EXPECT_EQ(a.branches[c].father, std::optional<std::uint32_t>(b.id)) << what;
    const double len = core::norm(b.direction);
    EXPECT_NEAR(len, 1.0, 1e-12) << what;
  }
  for (std::size_t n = 0; n < a.nodes.size(); ++n) {
    EXPECT_EQ(seen[n], 1) << what << " node " << n;
    EXPECT_EQ(a.nodes[n].id, n) << what;
    EXPECT_GT(a.nodes[n].area_mm2, 0.0) << what;
    EXPECT_TRUE(core::is_finite(a.nodes[n].position)) << what;
  }
  for (const auto& l : a.links) {
    EXPECT_LT(l.from, a.nodes.size()) << what;
    EXPECT_LT(l.to, a.nodes.size()) << what;
  }
}

const char* kParts[] = {"l_block", "pen_rack", "two_branches", "hinge", "cyl_walls5", "spiral", "impeller", "dome_sphere"};

TEST(CentroidalAxis, ReferencePartsAreWellFormedAndTimed) {
  const CentroidalAxisOptions defaults;
  for (const char* name : kParts) {
    const auto m = part(name);
    // Timing is printed, never asserted (STYLE.md: tests never assert on time).
    const auto t0 = std::chrono::steady_clock::now();
    auto r = centroidal_axis(m.mesh, m.topology);
    const auto t1 = std::chrono::steady_clock::now();
    ASSERT_TRUE(r.ok()) << name << ": " << r.error().message;
    const CentroidalAxis& a = r.value();
    std::printf("[ timing   ] centroidal axis %-12s %7.2f ms  inc %.3f mm  %zu nodes  %zu branches  %zu breaks\n", name,
                std::chrono::duration<double, std::milli>(t1 - t0).count(), a.increment_mm, a.nodes.size(), a.branches.size(),
                break_count(a));
    expect_well_formed(a, name);
    EXPECT_GE(a.increment_mm, defaults.min_increment_mm) << name;
    EXPECT_LE(a.increment_mm, defaults.max_increment_mm) << name;
    EXPECT_NE(root_of(a), nullptr) << name;
  }
}

TEST(CentroidalAxis, LBlockColumnThenArmTurningToPlusX) {
  const CentroidalAxis a = axis_of(part("l_block"));
  ASSERT_EQ(a.branches.size(), 2u);
  const AxisBranch* root = root_of(a);
  ASSERT_NE(root, nullptr);
  EXPECT_TRUE(same(root->direction, {0, 0, 1}));
  for (auto n : root->nodes) {  // the column's centroids (the arm's root above it included)
    EXPECT_NEAR(a.nodes[n].position.x, 10.0, 0.01);
    EXPECT_NEAR(a.nodes[n].position.y, 10.0, 0.01);
  }
  const auto kids = children_of(a, *root);
  ASSERT_EQ(kids.size(), 1u);
  const AxisBranch& arm = *kids[0];
  EXPECT_TRUE(same(arm.direction, {1, 0, 0}));
  EXPECT_GE(arm.nodes.size(), 5u);
  for (auto n : arm.nodes) {
    EXPECT_NEAR(a.nodes[n].position.z, 50.0, 0.01);
    EXPECT_GE(a.nodes[n].position.x, 20.0);  // the arm beyond the column, not searched twice
  }
  EXPECT_NEAR(a.nodes[arm.nodes.front()].position.x, 20.0, 0.01);  // Eq. 4: ε beyond the column face
  // One break link: the turn from the column into the arm, within the arm's height (z 40–60).
  ASSERT_EQ(break_count(a), 1u);
  const AxisLink* turn = connecting_link(a, arm);
  ASSERT_NE(turn, nullptr);
  EXPECT_TRUE(turn->is_break);
  EXPECT_GE(a.nodes[turn->from].position.z, 40.0);
  EXPECT_LE(a.nodes[turn->from].position.z, 60.0);
}

TEST(CentroidalAxis, PenRackFollowsTheIncline) {
  const CentroidalAxis a = axis_of(part("pen_rack"));
  ASSERT_EQ(a.branches.size(), 1u);  // the sliver poking below the plate is not a branch
  // Links along the bar (plate top z = 6, bar top about 5 + 60 cos 35° = 54).
  Vec3 sum{};
  int count = 0;
  for (const auto& l : a.links) {
    const Vec3 p = a.nodes[l.from].position, q = a.nodes[l.to].position;
    if (p.z < 8.0 || q.z > 48.0) continue;
    sum = sum + core::normalized(q - p);
    ++count;
  }
  ASSERT_GE(count, 4);
  const Vec3 expected{std::sin(35.0 * kPi / 180.0), 0.0, std::cos(35.0 * kPi / 180.0)};
  const double angle_deg = std::acos(std::clamp(core::dot(core::normalized(sum), expected), -1.0, 1.0)) * 180.0 / kPi;
  EXPECT_LT(angle_deg, 5.0);
}

TEST(CentroidalAxis, TwoBranchesSplitNearThirty) {
  const CentroidalAxis a = axis_of(part("two_branches"));
  const AxisBranch* root = root_of(a);
  ASSERT_NE(root, nullptr);
  EXPECT_TRUE(same(root->direction, {0, 0, 1}));
  for (auto n : root->nodes) EXPECT_NEAR(a.nodes[n].position.x, 0.0, 0.05);  // the trunk
  const auto kids = children_of(a, *root);
  ASSERT_EQ(kids.size(), 2u);
  EXPECT_EQ(kids[0]->brothers, std::vector<std::uint32_t>{kids[1]->id});
  EXPECT_EQ(kids[1]->brothers, std::vector<std::uint32_t>{kids[0]->id});
  double end_x[2];
  for (int i = 0; i < 2; ++i) {
    const AxisLink* l = connecting_link(a, *kids[i]);
    ASSERT_NE(l, nullptr);
    EXPECT_NEAR(a.nodes[l->from].position.z, 30.0, 3.0);  // the branch point
    end_x[i] = a.nodes[kids[i]->nodes.back()].position.x;
    EXPECT_GT(std::fabs(end_x[i]), 20.0);  // the arms curve out to |x| ≈ 30
    EXPECT_TRUE(kids[i]->children.empty());
    // Each arm's centroids move away from the trunk monotonically (they follow the curve).
    for (std::size_t k = 1; k < kids[i]->nodes.size(); ++k) {
      EXPECT_GE(std::fabs(a.nodes[kids[i]->nodes[k]].position.x), std::fabs(a.nodes[kids[i]->nodes[k - 1]].position.x) - 1e-6);
    }
  }
  EXPECT_LT(end_x[0] * end_x[1], 0.0);  // one arm each side
}

TEST(CentroidalAxis, HingeLugsAlongYKnucklesDown) {
  const CentroidalAxis a = axis_of(part("hinge"));
  const AxisBranch* root = root_of(a);
  ASSERT_NE(root, nullptr);
  EXPECT_TRUE(same(root->direction, {0, 0, 1}));  // the body is the root: the knuckles merge into it
  for (auto n : root->nodes) {
    EXPECT_GE(a.nodes[n].position.z, -10.0);
    EXPECT_LE(a.nodes[n].position.z, 10.0);
  }
  std::multiset<std::string> dirs;
  for (const AxisBranch* c : children_of(a, *root)) {
    const Vec3 mean = mean_position(a, *c);
    if (same(c->direction, {0, 1, 0})) {
      dirs.insert("+Y");
      EXPECT_GT(mean.y, 15.0);
    } else if (same(c->direction, {0, -1, 0})) {
      dirs.insert("-Y");
      EXPECT_LT(mean.y, -15.0);
    } else if (same(c->direction, {0, 0, -1})) {
      dirs.insert("-Z");
      EXPECT_NEAR(std::fabs(mean.x), 20.0, 0.01);
      EXPECT_LT(mean.z, -10.0);
      // A knuckle grows away from the body: its nodes go down.
      EXPECT_GT(a.nodes[c->nodes.front()].position.z, a.nodes[c->nodes.back()].position.z);
    } else {
      dirs.insert("other");
    }
  }
  EXPECT_EQ(dirs, (std::multiset<std::string>{"+Y", "-Y", "-Z", "-Z"}));
  EXPECT_EQ(a.branches.size(), 5u);
}

TEST(CentroidalAxis, CylinderWithFiveWalls) {
  const CentroidalAxis a = axis_of(part("cyl_walls5"));
  const AxisBranch* root = root_of(a);
  ASSERT_NE(root, nullptr);
  EXPECT_TRUE(same(root->direction, {0, 0, 1}));
  for (auto n : root->nodes) EXPECT_LT(std::hypot(a.nodes[n].position.x, a.nodes[n].position.y), 1.0);
  const auto kids = children_of(a, *root);
  ASSERT_EQ(kids.size(), 5u);
  EXPECT_EQ(a.branches.size(), 6u);
  std::set<int> walls_found;
  for (const AxisBranch* c : kids) {
    // The wall this branch runs along: the polar angle of its centroids.
    const Vec3 mean = mean_position(a, *c);
    double angle = std::atan2(mean.y, mean.x) * 180.0 / kPi;
    if (angle < 0) angle += 360.0;
    int wall = -1;
    for (int i = 0; i < 5; ++i) {
      double d = std::fabs(angle - (18.0 + 72.0 * i));
      d = std::min(d, 360.0 - d);
      if (d < 10.0) wall = i;
    }
    ASSERT_GE(wall, 0) << "branch at " << angle << "°";
    walls_found.insert(wall);
    const double w = (18.0 + 72.0 * wall) * kPi / 180.0;
    const Vec3 radial{std::cos(w), std::sin(w), 0.0};
    // The major axis closest to the wall direction.
    Vec3 best{};
    double best_dot = -2.0;
    for (Vec3 d : {Vec3{1, 0, 0}, Vec3{-1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, -1, 0}}) {
      if (core::dot(d, radial) > best_dot) best_dot = core::dot(d, radial), best = d;
    }
    EXPECT_TRUE(same(c->direction, best)) << "wall " << wall;
    for (auto n : c->nodes) EXPECT_GT(std::hypot(a.nodes[n].position.x, a.nodes[n].position.y), 14.9) << "wall " << wall;
  }
  EXPECT_EQ(walls_found.size(), 5u);
}

// ---- Generated parts: other sizes, other directions, several arms -------------------------------

// Overlapping boxes as one mesh of several closed shells, used as they are: sections take the
// nonzero union of their loops, so the part is the union of the boxes. (Repair is not run: it
// would keep the boxes as separate solids, which is not the part meant here.)
struct Generated {
  mesh::Mesh mesh;
  mesh::EdgeTopology topology;
};
Generated boxes(std::initializer_list<std::pair<Vec3, Vec3>> list) {
  io::RawMesh raw;
  for (const auto& [lo, hi] : list) raw = test::join(std::move(raw), test::box(lo, hi));
  Generated g;
  g.mesh.vertices = raw.points;
  g.mesh.triangles = raw.triangles;
  g.topology = mesh::build_topology(g.mesh);
  return g;
}
CentroidalAxis axis_of(const Generated& g, const CentroidalAxisOptions& o = {}) {
  auto r = centroidal_axis(g.mesh, g.topology, o);
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
  return r.ok() ? std::move(r.value()) : CentroidalAxis{};
}

TEST(CentroidalAxis, GeneratedLWithArmAlongMinusY) {
  // Column 30×25×45, arm 15 mm thick at the top reaching 50 mm along −Y.
  const auto m = boxes({{{0, 0, 0}, {30, 25, 45}}, {{0, -50, 30}, {30, 25, 45}}});
  const CentroidalAxis a = axis_of(m);
  expect_well_formed(a, "L");
  ASSERT_EQ(a.branches.size(), 2u);
  const AxisBranch* root = root_of(a);
  ASSERT_NE(root, nullptr);
  EXPECT_TRUE(same(root->direction, {0, 0, 1}));
  const auto kids = children_of(a, *root);
  ASSERT_EQ(kids.size(), 1u);
  EXPECT_TRUE(same(kids[0]->direction, {0, -1, 0}));
  for (auto n : kids[0]->nodes) {
    EXPECT_NEAR(a.nodes[n].position.z, 37.5, 0.01);
    EXPECT_NEAR(a.nodes[n].position.x, 15.0, 0.01);
    EXPECT_LE(a.nodes[n].position.y, 0.0);
  }
  EXPECT_EQ(break_count(a), 1u);
  EXPECT_TRUE(connecting_link(a, *kids[0])->is_break);
}

TEST(CentroidalAxis, GeneratedTWithTwoArms) {
  const auto m = boxes({{{-10, -10, 0}, {10, 10, 50}}, {{-45, -10, 35}, {45, 10, 50}}});
  const CentroidalAxis a = axis_of(m);
  expect_well_formed(a, "T");
  const AxisBranch* root = root_of(a);
  ASSERT_NE(root, nullptr);
  const auto kids = children_of(a, *root);
  ASSERT_EQ(kids.size(), 2u);
  EXPECT_EQ(a.branches.size(), 3u);
  std::set<double> xs;
  for (const AxisBranch* c : kids) {
    EXPECT_EQ(c->brothers.size(), 1u);
    const Vec3 mean = mean_position(a, *c);
    EXPECT_NEAR(mean.z, 42.5, 0.01);
    EXPECT_TRUE(same(c->direction, mean.x > 0 ? Vec3{1, 0, 0} : Vec3{-1, 0, 0}));
    xs.insert(mean.x > 0 ? 1.0 : -1.0);
  }
  EXPECT_EQ(xs.size(), 2u);
}

TEST(CentroidalAxis, GeneratedColumnWithThreeArmsAtDifferentHeights) {
  // Column 20×20×90; arms +X at z 15–25, −Y at z 40–50, −X at z 65–75.
  const auto m = boxes({{{0, 0, 0}, {20, 20, 90}},
                        {{0, 0, 15}, {50, 20, 25}},
                        {{0, -30, 40}, {20, 20, 50}},
                        {{-35, 0, 65}, {20, 20, 75}}});
  const CentroidalAxis a = axis_of(m);
  const AxisBranch* root = root_of(a);
  ASSERT_NE(root, nullptr);
  EXPECT_TRUE(same(root->direction, {0, 0, 1}));
  for (auto n : root->nodes) EXPECT_NEAR(a.nodes[n].position.x, 10.0, 0.01);
  const auto kids = children_of(a, *root);
  ASSERT_EQ(kids.size(), 3u);
  EXPECT_EQ(a.branches.size(), 4u);
  struct Arm {
    Vec3 direction;
    double z;
  };
  const Arm arms[] = {{{1, 0, 0}, 20.0}, {{0, -1, 0}, 45.0}, {{-1, 0, 0}, 70.0}};
  for (const Arm& arm : arms) {
    const auto it = std::find_if(kids.begin(), kids.end(), [&](const AxisBranch* c) { return same(c->direction, arm.direction); });
    ASSERT_NE(it, kids.end()) << "arm at z " << arm.z;
    EXPECT_NEAR(mean_position(a, **it).z, arm.z, 0.01);
    const AxisLink* l = connecting_link(a, **it);
    ASSERT_NE(l, nullptr);
    EXPECT_NEAR(a.nodes[l->from].position.z, arm.z, 5.0);  // FindConnectingLink: the nearest column node
    EXPECT_TRUE(l->is_break);
  }
  EXPECT_EQ(break_count(a), 3u);
}

TEST(CentroidalAxis, StartDirectionAlongX) {
  // The three-arm column lying on its side: the same part rotated so the column runs along +X.
  const auto m = boxes({{{0, 0, 0}, {90, 20, 20}}, {{15, 0, 0}, {25, 20, 50}}});
  CentroidalAxisOptions o;
  o.start_direction = {1, 0, 0};
  const CentroidalAxis a = axis_of(m, o);
  expect_well_formed(a, "along X");
  const AxisBranch* root = root_of(a);
  ASSERT_NE(root, nullptr);
  EXPECT_TRUE(same(root->direction, {1, 0, 0}));
  const auto kids = children_of(a, *root);
  ASSERT_EQ(kids.size(), 1u);
  EXPECT_TRUE(same(kids[0]->direction, {0, 0, 1}));
  EXPECT_NEAR(mean_position(a, *kids[0]).x, 20.0, 0.01);
}

TEST(CentroidalAxis, IncrementIsClampedToTheOptions) {
  const auto m = part("l_block");
  CentroidalAxisOptions o;
  o.min_increment_mm = o.max_increment_mm = 2.5;
  const CentroidalAxis a = axis_of(m, o);
  EXPECT_DOUBLE_EQ(a.increment_mm, 2.5);
  const AxisBranch* root = root_of(a);
  ASSERT_NE(root, nullptr);
  ASSERT_GE(root->nodes.size(), 2u);
  EXPECT_NEAR(a.nodes[root->nodes[1]].position.z - a.nodes[root->nodes[0]].position.z, 2.5, 1e-9);
}

TEST(CentroidalAxis, IncrementIsTheGapBetweenFlatFeaturesFacingEachOtherHoweverFinelyTessellated) {
  // A spool: flanges 4 mm thick (r 20) on a core r 8, a bore r 3; the flanges' facing sides 3 mm
  // apart. Each flat annulus is a thousand facets at one height at the finest tessellation (the
  // feature search compares only facets near each other across), and the increment is the gap
  // at every tessellation, as the flanges (4 mm) and the core's strip (5 mm) are wider.
  for (const std::uint32_t sides : {24u, 120u, 600u}) {
    const auto m = polyaxis::test::repaired(polyaxis::test::revolve({{20, 0}, {20, 4}, {8, 4}, {8, 7}, {20, 7}, {20, 11}}, sides, 3.0));
    CentroidalAxisOptions o;
    o.max_increment_mm = 10.0;
    EXPECT_NEAR(axis_of(m, o).increment_mm, 3.0, 1e-9) << sides << " sides";
  }
}

TEST(CentroidalAxis, BadOptionsAndOpenMeshesAreErrors) {
  const auto m = part("l_block");
  CentroidalAxisOptions o;
  o.start_direction = {1, 1, 0};
  auto r = centroidal_axis(m.mesh, m.topology, o);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, core::ErrorCode::kUsage);
  o = {};
  o.min_increment_mm = 0.0;
  r = centroidal_axis(m.mesh, m.topology, o);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, core::ErrorCode::kUsage);
  o = {};
  o.max_increment_mm = 0.1;  // below the minimum
  EXPECT_FALSE(centroidal_axis(m.mesh, m.topology, o).ok());

  mesh::Mesh open = m.mesh;
  open.triangles.pop_back();
  const mesh::EdgeTopology t = mesh::build_topology(open);
  r = centroidal_axis(open, t);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, core::ErrorCode::kInvalidInput);
}

TEST(CentroidalAxis, Deterministic) {
  const auto m = part("cyl_walls5");
  const CentroidalAxis a = axis_of(m), b = axis_of(m);
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  for (std::size_t i = 0; i < a.nodes.size(); ++i) EXPECT_TRUE(a.nodes[i].position == b.nodes[i].position);
  ASSERT_EQ(a.links.size(), b.links.size());
  for (std::size_t i = 0; i < a.links.size(); ++i) {
    EXPECT_EQ(a.links[i].from, b.links[i].from);
    EXPECT_EQ(a.links[i].to, b.links[i].to);
    EXPECT_EQ(a.links[i].is_break, b.links[i].is_break);
  }
}

}  // namespace
}  // namespace polyaxis::analysis
