#include "head_material.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/parallel_invoke.h>
#include <numbers>

namespace polyaxis::verify::detail {

std::vector<MaterialSample> prebuilt_material(const machine::PrebuiltBody& body, double radius) {
  std::vector<MaterialSample> out;
  out.reserve(body.surface_mm.size());
  for (std::size_t i = 0; i < body.surface_mm.size(); ++i) {
    const Vec3 c = body.surface_mm[i] - body.normals[i] * (0.5 * radius);
    out.push_back({{static_cast<float>(c.x), static_cast<float>(c.y), static_cast<float>(c.z)}, static_cast<std::uint32_t>(i), kPrebuiltLayer,
                   kPrebuiltLayer});
  }
  return out;
}

namespace {

constexpr std::uint32_t kLeafSize = 8;
// The index is built in parallel down to this depth, for subtrees of more samples than this.
constexpr int kParallelDepth = 6;
constexpr std::uint32_t kParallelCount = 50000;
constexpr double kDegToRad = 3.14159265358979323846 / 180.0;

std::vector<std::array<double, 2>> rect(double h0, double r0, double h1, double r1) { return {{h0, r0}, {h1, r0}, {h1, r1}, {h0, r1}}; }

void split_hr(Vec3 d, Vec3 axis, double& h, double& r) {
  h = core::dot(d, axis);
  const Vec3 side = d - axis * h;
  r = std::sqrt(core::dot(side, side));
}

}  // namespace

HeadProfile::HeadProfile(const machine::BuildModel& model) {
  std::vector<std::vector<std::array<double, 2>>> polys;
  const machine::NozzleModel& n = model.nozzle;
  const double hc = n.cone_height_mm;
  polys.push_back({{0.0, 0.0}, {hc, 0.0}, {hc, hc * std::tan(n.tip_half_angle_deg * kDegToRad)}});
  if (n.cylinder_height_mm > 0.0) polys.push_back(rect(hc, 0.0, hc + n.cylinder_height_mm, n.cylinder_radius_mm));
  for (const machine::HeadBox& b : model.head_boxes) {
    // The box turning about the axis sweeps the annulus between its nearest and farthest points.
    const double nx = std::clamp(0.0, b.min_mm[0], b.max_mm[0]), ny = std::clamp(0.0, b.min_mm[1], b.max_mm[1]);
    double far = 0.0;
    for (const double x : {b.min_mm[0], b.max_mm[0]}) {
      for (const double y : {b.min_mm[1], b.max_mm[1]}) far = std::max(far, std::hypot(x, y));
    }
    polys.push_back(rect(b.min_mm[2], std::hypot(nx, ny), b.max_mm[2], far));
  }
  for (const auto& poly : polys) {
    Piece piece;
    piece.h_min = piece.h_max = poly.front()[0];
    for (const auto& v : poly) piece.h_min = std::min(piece.h_min, v[0]), piece.h_max = std::max(piece.h_max, v[0]);
    std::vector<Edge>& edges = piece.edges;
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const auto& a = poly[i];
      const auto& b = poly[(i + 1) % poly.size()];
      const double ex = b[0] - a[0], ey = b[1] - a[1];
      const double len = std::sqrt(ex * ex + ey * ey);
      if (len == 0.0) continue;  // a degenerate box side
      edges.push_back({a[0], a[1], ex, ey, ey / len, -ex / len, 1.0 / (len * len)});
    }
    if (!edges.empty()) pieces_.push_back(std::move(piece));
  }
}

bool HeadProfile::may_touch(Vec3 lo, Vec3 hi, Vec3 c, double rho, Vec3 tip, Vec3 axis, double reach) const {
  // The box's extent along the axis, from the tip.
  const double a[3] = {axis.x, axis.y, axis.z}, l[3] = {lo.x, lo.y, lo.z}, u[3] = {hi.x, hi.y, hi.z};
  double h_lo = -core::dot(tip, axis), h_hi = h_lo;
  for (int k = 0; k < 3; ++k) h_lo += a[k] * (a[k] > 0.0 ? l[k] : u[k]), h_hi += a[k] * (a[k] > 0.0 ? u[k] : l[k]);
  double h = 0.0, r = 0.0;
  split_hr(c - tip, axis, h, r);
  for (const Piece& piece : pieces_) {
    if (h_hi < piece.h_min - reach || h_lo > piece.h_max + reach) continue;
    double m = -std::numeric_limits<double>::infinity();
    for (const Edge& e : piece.edges) m = std::max(m, (h - e.ax) * e.nx + (r - e.ay) * e.ny);
    if (m - rho <= reach) return true;
  }
  return false;
}

double HeadProfile::distance(Vec3 d, Vec3 axis) const {
  double h = 0.0, r = 0.0;
  split_hr(d, axis, h, r);
  double best = std::numeric_limits<double>::infinity();
  for (const Piece& p : pieces_) {
    const std::vector<Edge>& piece = p.edges;
    // Signed distance to the convex piece: the largest edge-line distance inside, else the
    // distance to the nearest edge.
    double max_edge = -std::numeric_limits<double>::infinity(), nearest2 = std::numeric_limits<double>::infinity();
    bool inside = true;
    for (const Edge& e : piece) {
      const double px = h - e.ax, py = r - e.ay;
      const double s = px * e.nx + py * e.ny;
      max_edge = std::max(max_edge, s);
      if (s > 0.0) {
        inside = false;
        const double t = std::clamp((px * e.ex + py * e.ey) * e.inv_len2, 0.0, 1.0);
        const double qx = px - t * e.ex, qy = py - t * e.ey;
        nearest2 = std::min(nearest2, qx * qx + qy * qy);
      }
    }
    best = std::min(best, inside ? max_edge : std::sqrt(nearest2));
  }
  return best;
}

MaterialIndex::MaterialIndex(std::vector<MaterialSample> samples, double prebuilt_ignore_mm)
    : samples_(std::move(samples)), prebuilt_ignore_mm_(prebuilt_ignore_mm) {
  has_prebuilt_ = std::any_of(samples_.begin(), samples_.end(), [](const MaterialSample& s) { return s.layer == kPrebuiltLayer; });
  if (samples_.empty()) return;
  const auto n = static_cast<std::uint32_t>(samples_.size());
  nodes_.resize(subtree_nodes(n));
  std::array<float, 3> lo = samples_.front().position, hi = lo;
  for (const MaterialSample& s : samples_) {
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], s.position[k]), hi[k] = std::max(hi[k], s.position[k]);
  }
  build(0, 0, n, 0, lo, hi);
}

std::uint32_t MaterialIndex::subtree_nodes(std::uint32_t count) {
  // Filled before the build (read only while it runs in parallel): counts at one depth differ by
  // at most one, so there are two a level.
  if (const auto it = subtree_sizes_.find(count); it != subtree_sizes_.end()) return it->second;
  const std::uint32_t half = count / 2;
  const std::uint32_t size = count <= kLeafSize ? 1 : 1 + subtree_nodes(half) + subtree_nodes(count - half);
  subtree_sizes_.emplace(count, size);
  return size;
}

void MaterialIndex::build(std::uint32_t id, std::uint32_t first, std::uint32_t count, int depth, std::array<float, 3> lo,
                          std::array<float, 3> hi) {
  Node node;
  if (count <= kLeafSize) {
    node.lo = {std::numeric_limits<float>::max(), std::numeric_limits<float>::max(), std::numeric_limits<float>::max()};
    node.hi = {-std::numeric_limits<float>::max(), -std::numeric_limits<float>::max(), -std::numeric_limits<float>::max()};
    node.min_stamp = std::numeric_limits<std::uint32_t>::max();
    for (std::uint32_t i = first; i < first + count; ++i) {
      for (int k = 0; k < 3; ++k) node.lo[k] = std::min(node.lo[k], samples_[i].position[k]), node.hi[k] = std::max(node.hi[k], samples_[i].position[k]);
      node.min_stamp = std::min(node.min_stamp, samples_[i].stamp);
    }
    node.first = first, node.count = count;
    nodes_[id] = finish(node);
    return;
  }
  int axis = 0;
  for (int k = 1; k < 3; ++k) {
    if (hi[k] - lo[k] > hi[axis] - lo[axis]) axis = k;
  }
  const std::uint32_t half = count / 2;
  std::nth_element(samples_.begin() + first, samples_.begin() + first + half, samples_.begin() + first + count,
                   [axis](const MaterialSample& a, const MaterialSample& b) { return a.position[axis] < b.position[axis]; });
  // Preorder layout: the left subtree follows its parent, the right one follows the left.
  node.left = id + 1;
  node.right = id + 1 + subtree_nodes(half);
  const float cut = samples_[first + half].position[axis];  // no sample on the left above it, none on the right below
  std::array<float, 3> left_hi = hi, right_lo = lo;
  left_hi[axis] = cut, right_lo[axis] = cut;
  auto left = [&] { build(node.left, first, half, depth + 1, lo, left_hi); };
  auto right = [&] { build(node.right, first + half, count - half, depth + 1, right_lo, hi); };
  // The subtrees own disjoint samples and nodes: the top levels are built side by side.
  if (depth < kParallelDepth && count > kParallelCount) {
    tbb::parallel_invoke(left, right);
  } else {
    left(), right();
  }
  const Node& l = nodes_[node.left];
  const Node& r = nodes_[node.right];
  for (int k = 0; k < 3; ++k) node.lo[k] = std::min(l.lo[k], r.lo[k]), node.hi[k] = std::max(l.hi[k], r.hi[k]);
  node.min_stamp = std::min(l.min_stamp, r.min_stamp);
  nodes_[id] = finish(node);
}

MaterialIndex::Node MaterialIndex::finish(Node node) {
  double d2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    node.centre[k] = 0.5f * (node.lo[k] + node.hi[k]);
    // The ball about the rounded centre holds both corners.
    const double e = std::max(static_cast<double>(node.hi[k]) - node.centre[k], static_cast<double>(node.centre[k]) - node.lo[k]);
    d2 += e * e;
  }
  node.rho = std::nextafter(static_cast<float>(std::sqrt(d2)), std::numeric_limits<float>::infinity());
  return node;
}

std::optional<MaterialHit> MaterialIndex::deepest(const HeadProfile& head, Vec3 tip, Vec3 axis, std::uint32_t before, double radius_mm,
                                                  double ignore_mm, double margin_mm, double turn_rad, bool any) const {
  std::optional<MaterialHit> best;
  if (nodes_.empty()) return best;
  const double prebuilt_mm = std::min(ignore_mm, prebuilt_ignore_mm_), near_mm = has_prebuilt_ ? prebuilt_mm : ignore_mm;
  std::uint32_t stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[stack[--top]];
    if (n.min_stamp >= before) continue;
    const Vec3 lo{n.lo[0], n.lo[1], n.lo[2]}, hi{n.hi[0], n.hi[1], n.hi[2]};
    const Vec3 c{n.centre[0], n.centre[1], n.centre[2]};
    const double rho = n.rho;
    const double dc = core::norm(c - tip);
    if (dc + rho <= near_mm) continue;  // all of it beside the tip
    const double reach = radius_mm + margin_mm + turn_rad * (dc + rho);
    if (!head.may_touch(lo, hi, c, rho, tip, axis, reach)) continue;
    if (n.count == 0) {
      if (top + 2 > 64) continue;  // cannot happen: the tree is balanced (depth ≤ 2·log2 n)
      stack[top++] = n.left;
      stack[top++] = n.right;
      continue;
    }
    for (std::uint32_t i = n.first; i < n.first + n.count; ++i) {
      const MaterialSample& s = samples_[i];
      if (s.stamp >= before) continue;
      const Vec3 p{s.position[0], s.position[1], s.position[2]};
      const double d = core::norm(p - tip);
      if (d <= (s.layer == kPrebuiltLayer ? prebuilt_mm : ignore_mm)) continue;
      const double sd = head.distance(p - tip, axis);
      if (sd > radius_mm + margin_mm + turn_rad * d) continue;
      const double depth = radius_mm - sd;
      if (!best || depth > best->depth_mm) best = MaterialHit{i, depth};
      if (any) return best;
    }
  }
  return best;
}

BelowTheTip::BelowTheTip(std::vector<std::array<float, 3>> axes, const std::vector<MaterialSample>& material, const machine::BuildModel& model,
                         double radius, double ignore)
    : radius_(radius), ignore_(ignore) {
  const machine::NozzleModel& n = model.nozzle;
  cone_rad_ = n.tip_half_angle_deg * kDegToRad;
  above_cone_mm_ = n.cone_height_mm;  // where the cylinder starts
  for (const machine::HeadBox& b : model.head_boxes) {
    if (b.min_mm[2] < 0.0) return;  // a box below the tip: no shortcut
    above_cone_mm_ = std::min(above_cone_mm_, b.min_mm[2]);
  }
  // Every head point is within this of the tip.
  extent_ = n.cone_height_mm + n.cylinder_height_mm + std::max(n.cylinder_radius_mm, n.cone_height_mm * std::tan(cone_rad_));
  for (const machine::HeadBox& b : model.head_boxes) {
    for (const double x : {b.min_mm[0], b.max_mm[0]}) {
      for (const double y : {b.min_mm[1], b.max_mm[1]}) {
        for (const double z : {b.min_mm[2], b.max_mm[2]}) extent_ = std::max(extent_, std::sqrt(x * x + y * y + z * z));
      }
    }
  }
  for (const auto& axis : axes) {
    Track t;
    t.axis = axis;
    t.highest.resize(material.size() + 1);
    t.highest[0] = -INFINITY;
    const Vec3 a{axis[0], axis[1], axis[2]};
    for (std::size_t i = 0; i < material.size(); ++i) {
      const Vec3 p{material[i].position[0], material[i].position[1], material[i].position[2]};
      t.highest[i + 1] = std::max(t.highest[i], core::dot(p, a));
    }
    tracks_.push_back(std::move(t));
  }
}

bool BelowTheTip::clear(const std::array<float, 3>& tip, const std::array<float, 3>& axis, std::uint32_t before, double margin_mm,
                        double turn_rad) const {
  for (const Track& t : tracks_) {
    if (t.axis != axis || before >= t.highest.size()) continue;
    const Vec3 a{axis[0], axis[1], axis[2]}, p{tip[0], tip[1], tip[2]};
    const double h = t.highest[before] - core::dot(p, a);
    if (h >= ignore_) return false;
    // Above the cone: the cylinder and the boxes start above_cone_mm_ up the axis. A ball that can
    // come within its reach of the head is at most R from the tip, R = extent + radius + margin +
    // turn·R: the turn's reach is taken there.
    if (turn_rad >= 1.0) return false;
    const double far = (extent_ + radius_ + margin_mm) / (1.0 - turn_rad);
    if (above_cone_mm_ - h <= radius_ + margin_mm + turn_rad * far) return false;
    // The cone's side: a point R ≥ ignore from the tip at elevation φ from the plane is R·cos(φ + θ)
    // from the cone's side (R from its apex once φ < −θ); at most h up, φ ≤ φ_h with sin φ_h =
    // max(h, 0) / ignore. Its reach grows by the turn times R, slower than that distance.
    const double phi = std::asin(std::max(h, 0.0) / ignore_);
    const double c = std::cos(phi + cone_rad_);
    return phi + cone_rad_ < 0.5 * std::numbers::pi && c > turn_rad && ignore_ * (c - turn_rad) > radius_ + margin_mm;
  }
  return false;
}

}  // namespace polyaxis::verify::detail
