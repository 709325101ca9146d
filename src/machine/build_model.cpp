#include "polyaxis/machine/build_model.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace polyaxis::machine {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A circle of the head: centre S mm up the axis from the tip, radius R mm, about the axis.
struct HeadCircle {
  double s_mm, r_mm;
};

// The surface under a disc centred at (X, Y) of radius R: the plate's top when the disc overlaps
// the plate's rectangle, the table's top when it overlaps the table, else none (−inf).
double surface_under(const BuildModel& m, double x, double y, double r) {
  const SubstratePlate& p = m.substrate;
  const double dx = std::max({p.x_min_mm - x, 0.0, x - p.x_max_mm}), dy = std::max({p.y_min_mm - y, 0.0, y - p.y_max_mm});
  if (dx * dx + dy * dy <= r * r) return p.top_z_mm;
  if (std::hypot(x - m.table_centre_mm.x, y - m.table_centre_mm.y) <= m.table_radius_mm + r) return m.table_top_z_mm();
  return -std::numeric_limits<double>::infinity();
}

}  // namespace

BuildModel make_build_model(const MachineConfig& machine, const process::ProcessConfig& process, double x0, double y0, double x1, double y1) {
  BuildModel m;
  m.nozzle = machine.nozzle;
  m.head_boxes = machine.head_boxes;
  m.table_radius_mm = machine.table.radius_mm;
  m.table_centre_mm = turns_table(machine.kind) ? Vec3{machine.pivot.x_rot_point_mm, machine.pivot.y_rot_point_mm, 0.0}
                                                    : work_centre_mm(machine);
  const auto& s = process.substrate;
  const double cx = (x0 + x1) * 0.5, cy = (y0 + y1) * 0.5;
  const double hx = s.size_x_mm > 0.0 ? s.size_x_mm * 0.5 : (x1 - x0) * 0.5 + s.margin_mm;
  const double hy = s.size_y_mm > 0.0 ? s.size_y_mm * 0.5 : (y1 - y0) * 0.5 + s.margin_mm;
  m.substrate = {cx - hx, cy - hy, cx + hx, cy + hy, 0.0, s.thickness_mm};
  return m;
}

bool add_prebuilt(PrebuiltBody& body, const std::vector<Vec3>& vertices, const std::vector<std::array<std::uint32_t, 3>>& triangles,
                  double spacing_mm, std::size_t max_samples) {
  if (!(spacing_mm > 0.0) || !std::isfinite(spacing_mm)) return true;  // no samples rather than no end
  // Every piece has an area of at most √3/4 · spacing² and about half a sample: at least
  // area / spacing² samples, refused before any is made.
  double total_area = 0.0;
  for (const auto& t : triangles) {
    const double a = core::norm(core::cross(vertices[t[1]] - vertices[t[0]], vertices[t[2]] - vertices[t[0]]));
    if (std::isfinite(a)) total_area += 0.5 * a;
  }
  if (total_area / (spacing_mm * spacing_mm) > static_cast<double>(max_samples)) return false;
  const std::size_t first = body.surface_mm.size();
  auto undo = [&] {
    body.surface_mm.resize(first), body.normals.resize(first);
    return false;
  };
  std::vector<std::array<double, 3>> corners;  // of one triangle's pieces
  for (const auto& t : triangles) {
    const Vec3 a = vertices[t[0]], b = vertices[t[1]], c = vertices[t[2]];
    const Vec3 area = core::cross(b - a, c - a);
    if (!(core::norm(area) > 0.0) || !std::isfinite(core::norm(area))) continue;  // degenerate or not finite
    const Vec3 n = core::normalized(area);
    // Split at the longest edge's middle until every edge is within SPACING: each corner of the
    // pieces is a sample (a sliver gives points along its length only).
    std::vector<std::array<Vec3, 3>> todo{{a, b, c}};
    while (!todo.empty()) {
      // A triangle's pieces have about six corners for each sample they leave once shared corners
      // are merged: a bound that keeps the corners of one giant triangle within 2 × MAX_SAMPLES.
      if (body.surface_mm.size() - first + corners.size() / 3 > max_samples) return undo();
      const auto [p, q, r] = todo.back();
      todo.pop_back();
      const double pq = core::norm(q - p), qr = core::norm(r - q), rp = core::norm(p - r);
      const double longest = std::max({pq, qr, rp});
      if (longest <= spacing_mm) {
        for (const Vec3& x : {p, q, r}) corners.push_back({x.x, x.y, x.z});
        continue;
      }
      if (longest == pq) {
        const Vec3 m = (p + q) * 0.5;
        todo.push_back({p, m, r}), todo.push_back({m, q, r});
      } else if (longest == qr) {
        const Vec3 m = (q + r) * 0.5;
        todo.push_back({p, q, m}), todo.push_back({p, m, r});
      } else {
        const Vec3 m = (r + p) * 0.5;
        todo.push_back({p, q, m}), todo.push_back({m, q, r});
      }
    }
    // A corner shared by the triangle's pieces around it is kept once (the triangle's edges and
    // corners are sampled again by its neighbours: points the same spacing apart, a few more).
    std::sort(corners.begin(), corners.end());
    corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
    for (const auto& x : corners) body.surface_mm.push_back({x[0], x[1], x[2]}), body.normals.push_back(n);
    corners.clear();
    if (body.surface_mm.size() - first > max_samples) return undo();
  }
  body.spacing_mm = body.spacing_mm > 0.0 ? std::min(body.spacing_mm, spacing_mm) : spacing_mm;
  return true;
}

double tip_clearance_mm(const BuildModel& m, Vec3 tip) { return tip.z - surface_under(m, tip.x, tip.y, 0.0); }

double head_clearance_mm(const BuildModel& m, Vec3 tip, Vec3 axis) {
  const Vec3 a = core::normalized(axis);
  const NozzleModel& n = m.nozzle;
  HeadCircle circles[8];
  int count = 0;
  const double cone_top_r = n.cone_height_mm * std::tan(n.tip_half_angle_deg * kPi / 180.0);
  circles[count++] = {n.cone_height_mm, std::max(cone_top_r, n.cylinder_radius_mm)};
  circles[count++] = {n.cone_height_mm + n.cylinder_height_mm, n.cylinder_radius_mm};
  double clearance = std::numeric_limits<double>::infinity();
  auto visit = [&](HeadCircle c) {
    const Vec3 centre = tip + a * c.s_mm;
    // The circle's lowest point drops sin(tilt)·r below its centre.
    const double drop = c.r_mm * std::sqrt(std::max(0.0, 1.0 - a.z * a.z));
    clearance = std::min(clearance, centre.z - drop - surface_under(m, centre.x, centre.y, c.r_mm));
  };
  for (int k = 0; k < count; ++k) visit(circles[k]);
  for (const HeadBox& b : m.head_boxes) {
    double r = 0.0;
    for (const double x : {b.min_mm[0], b.max_mm[0]}) {
      for (const double y : {b.min_mm[1], b.max_mm[1]}) r = std::max(r, std::hypot(x, y));
    }
    visit({b.min_mm[2], r});
    visit({b.max_mm[2], r});
  }
  return clearance;
}

}  // namespace polyaxis::machine
