// Kapil, Negi et al., "5-axis slicing methods for additive manufacturing of
// metallic parts", §5-axis slicing, planar: Eq. 1 (t = n × (p_{i+1} − p_i) / |·|), Eq. 2 (the
// facet overhangs when n·k < 0) and Eq. 3 (t = k otherwise). The overhang test takes the
// self-supporting angle into account (toolpath.h) and the tilt is limited to kMaxTiltRad.
#include "overhang.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "polyaxis/toolpath/toolpath.h"

namespace polyaxis::toolpath::detail {
namespace {

// Bound on the grid's cells per axis: keeps the grid's memory linear in the segments even for a
// section with one long and many tiny segments.
constexpr std::int64_t kMaxCellsPerAxis = 1024;

}  // namespace

FacetLocator::FacetLocator(const slicing::SectionContext& ctx, double h, const slicing::Frame& frame,
                           std::span<const std::uint32_t> faces) {
  const mesh::Mesh& m = ctx.mesh();
  // The crossing of edge (a, b), built from its ends in vertex-index order as section.cpp does.
  auto crossing = [&](std::uint32_t a, std::uint32_t b, double& x, double& y) {
    if (a > b) std::swap(a, b);
    const double sa = ctx.height(a), sb = ctx.height(b);
    const double t = (h - sa) / (sb - sa);
    const Vec3 pa = m.vertices[a], pb = m.vertices[b];
    const Vec3 p = pa + (pb - pa) * t - frame.origin;
    x = core::dot(p, frame.u);
    y = core::dot(p, frame.v);
  };
  for (const std::uint32_t f : faces) {
    const auto& tri = m.triangles[f];
    const bool above[3] = {ctx.height(tri[0]) >= h, ctx.height(tri[1]) >= h, ctx.height(tri[2]) >= h};
    if (above[0] == above[1] && above[1] == above[2]) continue;
    // As slicing::section orients it: from the crossing of the above-to-below edge to that of the
    // below-to-above edge, so the solid lies to the left (outer loops counter-clockwise about d).
    Segment s{0, 0, 0, 0, f};
    for (int k = 0; k < 3; ++k) {
      const bool from = above[k], to = above[(k + 1) % 3];
      if (from == to) continue;
      double x = 0.0, y = 0.0;
      crossing(tri[static_cast<std::size_t>(k)], tri[static_cast<std::size_t>((k + 1) % 3)], x, y);
      if (from) {
        s.ax = x;
        s.ay = y;
      } else {
        s.bx = x;
        s.by = y;
      }
    }
    // A plane through a corner gives a point, which has no direction; its neighbours cover it.
    if (s.ax == s.bx && s.ay == s.by) continue;
    segments_.push_back(s);
  }
  if (segments_.empty()) return;
  double x1 = -INFINITY, y1 = -INFINITY;
  x0_ = y0_ = INFINITY;
  for (const Segment& s : segments_) {
    x0_ = std::min({x0_, s.ax, s.bx});
    y0_ = std::min({y0_, s.ay, s.by});
    x1 = std::max({x1, s.ax, s.bx});
    y1 = std::max({y1, s.ay, s.by});
  }
  const double w = x1 - x0_, hgt = y1 - y0_;
  const double n = static_cast<double>(segments_.size());
  // About one segment per cell on average.
  cell_mm_ = std::max({std::sqrt(w * hgt / n), std::max(w, hgt) / static_cast<double>(kMaxCellsPerAxis), 1e-6});
  nx_ = std::min<std::int64_t>(kMaxCellsPerAxis, static_cast<std::int64_t>(w / cell_mm_) + 1);
  ny_ = std::min<std::int64_t>(kMaxCellsPerAxis, static_cast<std::int64_t>(hgt / cell_mm_) + 1);
  auto cell_x = [&](double x) { return std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor((x - x0_) / cell_mm_)), 0, nx_ - 1); };
  auto cell_y = [&](double y) { return std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor((y - y0_) / cell_mm_)), 0, ny_ - 1); };
  start_.assign(static_cast<std::size_t>(nx_ * ny_) + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<std::uint32_t> fill;
    if (pass == 1) {
      for (std::size_t c = 0; c + 1 < start_.size(); ++c) start_[c + 1] += start_[c];
      items_.resize(start_.back());
      fill.assign(start_.begin(), start_.end() - 1);
    }
    for (std::uint32_t i = 0; i < segments_.size(); ++i) {
      const Segment& s = segments_[i];
      const std::int64_t ax = cell_x(std::min(s.ax, s.bx)), bx = cell_x(std::max(s.ax, s.bx));
      const std::int64_t ay = cell_y(std::min(s.ay, s.by)), by = cell_y(std::max(s.ay, s.by));
      for (std::int64_t cy = ay; cy <= by; ++cy) {
        for (std::int64_t cx = ax; cx <= bx; ++cx) {
          const auto c = static_cast<std::size_t>(cy * nx_ + cx);
          if (pass == 0) {
            ++start_[c + 1];
          } else {
            items_[fill[c]++] = i;
          }
        }
      }
    }
  }
}

FacetLocator::Nearest FacetLocator::nearest(double u, double v) const {
  const std::int64_t cx = std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor((u - x0_) / cell_mm_)), 0, nx_ - 1);
  const std::int64_t cy = std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor((v - y0_) / cell_mm_)), 0, ny_ - 1);
  // Distance from the query to its (clamped) cell: bounds how far rings of cells must be searched.
  const double bx0 = x0_ + static_cast<double>(cx) * cell_mm_, by0 = y0_ + static_cast<double>(cy) * cell_mm_;
  const double dx = std::max({bx0 - u, 0.0, u - (bx0 + cell_mm_)}), dy = std::max({by0 - v, 0.0, v - (by0 + cell_mm_)});
  const double off = std::sqrt(dx * dx + dy * dy);
  double best = std::numeric_limits<double>::infinity();
  std::uint32_t best_i = 0;
  auto visit = [&](std::int64_t x, std::int64_t y) {
    if (x < 0 || y < 0 || x >= nx_ || y >= ny_) return;
    const auto c = static_cast<std::size_t>(y * nx_ + x);
    for (std::uint32_t k = start_[c]; k < start_[c + 1]; ++k) {
      const std::uint32_t i = items_[k];
      const Segment& s = segments_[i];
      const double ex = s.bx - s.ax, ey = s.by - s.ay;
      const double len2 = ex * ex + ey * ey;
      double t = len2 > 0.0 ? ((u - s.ax) * ex + (v - s.ay) * ey) / len2 : 0.0;
      t = std::clamp(t, 0.0, 1.0);
      const double px = s.ax + t * ex - u, py = s.ay + t * ey - v;
      const double d2 = px * px + py * py;
      if (d2 < best || (d2 == best && i < best_i)) {
        best = d2;
        best_i = i;
      }
    }
  };
  const std::int64_t max_r = std::max(nx_, ny_);
  for (std::int64_t r = 0; r <= max_r; ++r) {
    if (r == 0) {
      visit(cx, cy);
    } else {
      for (std::int64_t x = cx - r; x <= cx + r; ++x) {
        visit(x, cy - r);
        visit(x, cy + r);
      }
      for (std::int64_t y = cy - r + 1; y <= cy + r - 1; ++y) {
        visit(cx - r, y);
        visit(cx + r, y);
      }
    }
    // Cells beyond ring r are at least r·cell from the query's cell.
    if (best < std::numeric_limits<double>::infinity() && std::sqrt(best) <= static_cast<double>(r) * cell_mm_ - off) break;
  }
  const Segment& s = segments_[best_i];
  const double len = std::hypot(s.bx - s.ax, s.by - s.ay);
  return {s.face, (s.bx - s.ax) / len, (s.by - s.ay) / len};
}

Vec3 torch_axis(Vec3 n, Vec3 tangent, Vec3 d, double min_dot) {
  if (!(core::dot(n, d) < min_dot)) return d;  // Eq. 3, second case (with the self-supporting angle)
  Vec3 t = core::cross(n, tangent);              // Eq. 1
  const double len = core::norm(t);
  if (!(len > 0.0) || !std::isfinite(len)) return d;
  t = t / len;
  // Up the nozzle means away from the deposited layer: t·d must not be negative.
  if (core::dot(t, d) < 0.0) t = t * -1.0;
  const double c = std::clamp(core::dot(t, d), -1.0, 1.0);
  if (std::acos(c) <= kMaxTiltRad) return t;
  const Vec3 side = core::normalized(t - d * c);
  if (core::norm(side) == 0.0) return d;
  return core::normalized(d * std::cos(kMaxTiltRad) + side * std::sin(kMaxTiltRad));
}

}  // namespace polyaxis::toolpath::detail
