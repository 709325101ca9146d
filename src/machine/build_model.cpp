#include "polyaxis/machine/build_model.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace polyaxis::machine {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A solid of the head: the hull of two discs about the nozzle axis, S0 and S1 mm up it from the
// tip, of radii R0 and R1.
struct HeadSolid {
  double s0_mm, r0_mm, s1_mm, r1_mm;
};

// The head's solids: the cone (from kTipZoneMm up: the tip itself is the tip's clearance), the
// cylinder, and each head box by the solid it sweeps turning about the axis. At most 2 + boxes.
constexpr double kTipZoneMm = 1.0;

// A solid placed with its tip at TIP along the unit axis A: centre c(λ) = c0 + a·len·λ and radius
// r(λ) = r0 + (r1 − r0)·λ for λ in [0, 1]; U, V span the discs' planes.
struct Frustum {
  Vec3 c0, a, u, v;
  double len, r0, r1;
  Vec3 centre(double l) const { return c0 + a * (len * l); }
  double radius(double l) const { return r0 + (r1 - r0) * l; }
};

double comp(Vec3 p, int i) { return i == 0 ? p.x : p.y; }

// Narrows [LO, HI] to where A + B·λ >= 0.
void keep_where(double a, double b, double& lo, double& hi) {
  if (std::abs(b) < 1e-15) {
    if (a < 0.0) lo = 1.0, hi = 0.0;
    return;
  }
  (b > 0.0 ? lo : hi) = b > 0.0 ? std::max(lo, -a / b) : std::min(hi, -a / b);
}

// The least of G(λ) = A0 + A1·λ − K·√(Q2·λ² + Q1·λ + Q0) on [LO, HI] (G convex, K >= 0), at the
// ends or where G' = 0: 2·A1·√Q = K·(2·Q2·λ + Q1), squared a quadratic in λ.
double convex_min_at(double a0, double a1, double k, double q2, double q1, double q0, double lo, double hi) {
  auto g = [&](double l) { return a0 + a1 * l - k * std::sqrt(std::max(0.0, (q2 * l + q1) * l + q0)); };
  double best_l = lo, best = g(lo);
  auto consider = [&](double l) {
    if (!(l > lo && l < hi)) return;
    const double v = g(l);
    if (v < best) best = v, best_l = l;
  };
  if (hi == lo) return best_l;
  if (k > 0.0) {
    const double c2 = 4.0 * (a1 * a1 * q2 - k * k * q2 * q2), c1 = 4.0 * (a1 * a1 * q1 - k * k * q1 * q2), c0 = 4.0 * a1 * a1 * q0 - k * k * q1 * q1;
    const double scale = std::abs(c2) + std::abs(c1) + std::abs(c0);
    if (std::abs(c2) > 1e-12 * scale) {
      const double disc = c1 * c1 - 4.0 * c2 * c0;
      if (disc >= 0.0) {
        const double sq = std::sqrt(disc), q = -0.5 * (c1 + std::copysign(sq, c1));
        consider(q / c2);
        if (q != 0.0) consider(c0 / q);
      }
    } else if (std::abs(c1) > 1e-12 * scale) {
      consider(-c0 / c1);
    }
  }
  if (g(hi) < best) best_l = hi;
  return best_l;
}

// The lowest point of the solid F within the vertical plane where coordinate I (0: x, 1: y) is
// VAL, if its other coordinate lies in [LO, HI]; +inf otherwise. Each disc meets the plane in a
// chord whose lower end is the disc's lowest point there; over the discs that height is convex
// (the section of a convex solid) and of the form of convex_min_at.
double lowest_on_face(const Frustum& f, int i, double val, double lo, double hi) {
  const int j = 1 - i;
  const double gx = comp(f.u, i), gy = comp(f.v, i), gn = std::sqrt(gx * gx + gy * gy);
  const double inf = std::numeric_limits<double>::infinity();
  if (gn < 1e-9) {  // the discs are parallel to the plane: the one in it, whole
    const double l = (val - comp(f.c0, i)) / (comp(f.a, i) * f.len);
    if (!(l >= 0.0 && l <= 1.0)) return inf;
    const Vec3 c = f.centre(l);
    return comp(c, j) >= lo && comp(c, j) <= hi ? c.z - f.radius(l) : inf;
  }
  // e(λ): the plane's offset from the centre along the discs' own direction of coordinate I.
  const double e0 = val - comp(f.c0, i), e1 = -comp(f.a, i) * f.len;
  double l_lo = 0.0, l_hi = 1.0;
  keep_where(f.r0 * gn - e0, (f.r1 - f.r0) * gn - e1, l_lo, l_hi);
  keep_where(f.r0 * gn + e0, (f.r1 - f.r0) * gn + e1, l_lo, l_hi);
  if (l_lo > l_hi) return inf;
  const double ux = gx / gn, uy = gy / gn;         // ĝ in the discs' (u, v) plane
  const double along = ux * f.u.z + uy * f.v.z;    // ĝ·h
  const double across = -uy * f.u.z + ux * f.v.z;  // ĝ⊥·h
  // G(λ) = c(λ).z + (e/|g|)·along − |across|·√(r² − (e/|g|)²), with e/|g| = F0 + F1·λ.
  const double f0 = e0 / gn, f1 = e1 / gn, dr = f.r1 - f.r0;
  const double l = convex_min_at(f.c0.z + f0 * along, f.a.z * f.len + f1 * along, std::abs(across), dr * dr - f1 * f1,
                                 2.0 * (f.r0 * dr - f0 * f1), f.r0 * f.r0 - f0 * f0, l_lo, l_hi);
  const double e = e0 + e1 * l, r = f.radius(l);
  const double t = -std::copysign(std::sqrt(std::max(0.0, r * r - (e / gn) * (e / gn))), across);
  const double alpha = (e / gn) * ux - t * uy, beta = (e / gn) * uy + t * ux;
  const Vec3 p = f.centre(l) + f.u * alpha + f.v * beta;
  return comp(p, j) >= lo - 1e-9 && comp(p, j) <= hi + 1e-9 ? p.z : inf;
}

// The lowest point of the solid F on the vertical line through (X, Y); +inf where it misses.
double lowest_on_line(const Frustum& f, double x, double y) {
  const double inf = std::numeric_limits<double>::infinity();
  const Vec3 a = f.a;
  const double dx0 = x - f.c0.x, dy0 = y - f.c0.y;
  if (std::abs(a.z) < 1e-7) {  // the discs are vertical: the line lies in one of them
    const double l = (a.x * dx0 + a.y * dy0) / f.len;
    if (!(l >= 0.0 && l <= 1.0)) return inf;
    const Vec3 c = f.centre(l);
    const double h = std::sqrt((x - c.x) * (x - c.x) + (y - c.y) * (y - c.y)), r = f.radius(l);
    return h <= r ? c.z - std::sqrt(r * r - h * h) : inf;
  }
  // The line meets disc λ's plane at q(λ); d(λ) = q − c(λ) = D0 + D1·λ, inside where |d| <= r(λ).
  const Vec3 d0{dx0, dy0, -(a.x * dx0 + a.y * dy0) / a.z};
  const Vec3 d1{-a.x * f.len, -a.y * f.len, f.len * (a.x * a.x + a.y * a.y) / a.z};
  const double dr = f.r1 - f.r0;
  const double qa = core::dot(d1, d1) - dr * dr, qb = 2.0 * (core::dot(d0, d1) - f.r0 * dr), qc = core::dot(d0, d0) - f.r0 * f.r0;
  auto inside = [&](double l) { return (qa * l + qb) * l + qc <= 1e-9 * (1.0 + core::dot(d0, d0) + f.r1 * f.r1 + core::dot(d1, d1)); };
  auto z_at = [&](double l) { return f.c0.z + a.z * f.len * l + d0.z + d1.z * l; };
  // The inside is an interval (a convex solid) and the height is linear along it: its least is at
  // an end, which is 0, 1 or a root.
  double candidates[4] = {0.0, 1.0, -1.0, -1.0};
  if (std::abs(qa) > 1e-15) {
    const double disc = qb * qb - 4.0 * qa * qc;
    if (disc >= 0.0) {
      const double s = std::sqrt(disc), q = -0.5 * (qb + std::copysign(s, qb));
      candidates[2] = q / qa;
      if (q != 0.0) candidates[3] = qc / q;
    }
  } else if (std::abs(qb) > 1e-15) {
    candidates[2] = -qc / qb;
  }
  double best = inf;
  for (double l : candidates) {
    l = std::clamp(l, 0.0, 1.0);
    if (inside(l)) best = std::min(best, z_at(l));
  }
  return best;
}

// The lowest point of the solid F over the plate's rectangle (exact: the solid's lowest point when
// it lies over the plate, else the least over the rectangle's four sides and four corners, where
// the lowest point of the solid's part over the rectangle must then lie); +inf where none is over it.
double lowest_over_plate(const Frustum& f, const SubstratePlate& p, double bx0, double by0, double bx1, double by1) {
  const double s = std::sqrt(std::max(0.0, 1.0 - f.a.z * f.a.z));
  const Vec3 down = s > 1e-12 ? (f.a * f.a.z - Vec3{0, 0, 1}) / s : Vec3{};
  double low = std::numeric_limits<double>::infinity();
  Vec3 lowest;
  for (const double l : {0.0, 1.0}) {
    const Vec3 q = f.centre(l) + down * f.radius(l);
    if (q.z < low) low = q.z, lowest = q;
  }
  if (lowest.x >= p.x_min_mm && lowest.x <= p.x_max_mm && lowest.y >= p.y_min_mm && lowest.y <= p.y_max_mm) return low;
  // Only the sides and corners within the solid's box [BX0, BX1] × [BY0, BY1] can meet it.
  double best = std::numeric_limits<double>::infinity();
  const bool ys = by1 >= p.y_min_mm && by0 <= p.y_max_mm, xs = bx1 >= p.x_min_mm && bx0 <= p.x_max_mm;
  for (const double x : {p.x_min_mm, p.x_max_mm}) {
    if (ys && x >= bx0 && x <= bx1) best = std::min(best, lowest_on_face(f, 0, x, p.y_min_mm, p.y_max_mm));
  }
  for (const double y : {p.y_min_mm, p.y_max_mm}) {
    if (xs && y >= by0 && y <= by1) best = std::min(best, lowest_on_face(f, 1, y, p.x_min_mm, p.x_max_mm));
  }
  for (const double x : {p.x_min_mm, p.x_max_mm}) {
    for (const double y : {p.y_min_mm, p.y_max_mm}) {
      if (x >= bx0 && x <= bx1 && y >= by0 && y <= by1) best = std::min(best, lowest_on_line(f, x, y));
    }
  }
  return best;
}

// The table's top under a disc centred at (X, Y) of radius R when the disc overlaps the table, else
// none (−inf).
double table_under(const BuildModel& m, double x, double y, double r) {
  const double dx = x - m.table_centre_mm.x, dy = y - m.table_centre_mm.y, reach = m.table_radius_mm + r;
  if (dx * dx + dy * dy <= reach * reach) return m.table_top_z_mm();
  return -std::numeric_limits<double>::infinity();
}

// The surface under the point (X, Y): the plate's top over its rectangle, else the table's.
double surface_under(const BuildModel& m, double x, double y) {
  const SubstratePlate& p = m.substrate;
  if (x >= p.x_min_mm && x <= p.x_max_mm && y >= p.y_min_mm && y <= p.y_max_mm) return p.top_z_mm;
  return table_under(m, x, y, 0.0);
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

double tip_clearance_mm(const BuildModel& m, Vec3 tip) { return tip.z - surface_under(m, tip.x, tip.y); }

double head_clearance_mm(const BuildModel& m, Vec3 tip, Vec3 axis, double exact_below_mm) {
  const Vec3 a = core::normalized(axis);
  const NozzleModel& n = m.nozzle;
  const double tan_half = std::tan(n.tip_half_angle_deg * kPi / 180.0);
  const double tip_zone = std::min(kTipZoneMm, n.cone_height_mm);
  HeadSolid solids[2] = {{tip_zone, tip_zone * tan_half, n.cone_height_mm, n.cone_height_mm * tan_half},
                         {n.cone_height_mm, n.cylinder_radius_mm, n.cone_height_mm + n.cylinder_height_mm, n.cylinder_radius_mm}};
  // The discs' planes: U and V perpendicular to the axis.
  const Vec3 helper = std::abs(a.z) < 0.9 ? Vec3{0, 0, 1} : Vec3{1, 0, 0};
  const Vec3 u = core::normalized(core::cross(a, helper)), v = core::cross(a, u);
  const double side = std::sqrt(std::max(0.0, 1.0 - a.z * a.z));
  const SubstratePlate& p = m.substrate;
  // Every solid below lies within its widest radius of the axis, between its lowest and highest
  // point along it: its lowest point is no lower than that span's lower end less the widest
  // radius times the axis's slope. Above the highest surface by at least EXACT_BELOW_MM, that
  // bound is the answer (most calls: the head well above the plate), and no solid is visited.
  {
    double r_max = std::max(n.cone_height_mm * tan_half, n.cylinder_radius_mm), low = std::min(tip_zone * a.z, n.cone_height_mm * a.z);
    low = std::min(low, (n.cone_height_mm + n.cylinder_height_mm) * a.z);
    for (const HeadBox& b : m.head_boxes) {
      for (const double x : {b.min_mm[0], b.max_mm[0]}) {
        for (const double y : {b.min_mm[1], b.max_mm[1]}) r_max = std::max(r_max, std::hypot(x, y));
      }
      low = std::min({low, b.min_mm[2] * a.z, b.max_mm[2] * a.z});
    }
    const double bound = tip.z + low - r_max * side - std::max(p.top_z_mm, m.table_top_z_mm());
    if (bound >= exact_below_mm) return bound;
  }
  double clearance = std::numeric_limits<double>::infinity();
  auto visit = [&](HeadSolid h) {
    if (h.s1_mm <= h.s0_mm) h.s1_mm = h.s0_mm + 1e-6;  // a flat box: its disc
    const Frustum f{tip + a * h.s0_mm, a, u, v, h.s1_mm - h.s0_mm, h.r0_mm, h.r1_mm};
    // Against the table: the solid's lowest point, wherever a disc overlaps the table.
    for (const double l : {0.0, 1.0}) {
      const Vec3 c = f.centre(l);
      clearance = std::min(clearance, c.z - f.radius(l) * side - table_under(m, c.x, c.y, f.radius(l)));
    }
    // Against the plate: the lowest point of the solid's part over it, where its box meets the plate.
    double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
    for (const double l : {0.0, 1.0}) {
      const Vec3 c = f.centre(l);
      const double r = f.radius(l);
      x0 = std::min(x0, c.x - r), x1 = std::max(x1, c.x + r), y0 = std::min(y0, c.y - r), y1 = std::max(y1, c.y + r);
    }
    if (x1 < p.x_min_mm || x0 > p.x_max_mm || y1 < p.y_min_mm || y0 > p.y_max_mm) return;
    // The solid's lowest point bounds its part over the plate from below: enough where that is
    // already no nearer than asked for exactly.
    const double bound = std::min(f.c0.z - f.r0 * side, f.centre(1.0).z - f.r1 * side) - p.top_z_mm;
    if (bound >= exact_below_mm || bound >= clearance) {
      clearance = std::min(clearance, bound);
      return;
    }
    clearance = std::min(clearance, lowest_over_plate(f, p, x0, y0, x1, y1) - p.top_z_mm);
  };
  for (const HeadSolid& h : solids) visit(h);
  for (const HeadBox& b : m.head_boxes) {
    double r = 0.0;
    for (const double x : {b.min_mm[0], b.max_mm[0]}) {
      for (const double y : {b.min_mm[1], b.max_mm[1]}) r = std::max(r, std::hypot(x, y));
    }
    visit({b.min_mm[2], r, b.max_mm[2], r});
  }
  return clearance;
}

}  // namespace polyaxis::machine
