#include "sections.h"

#include <algorithm>
#include <cmath>

#include "polyaxis/slicing/layer.h"

namespace polyaxis::lamination::detail {
namespace {

constexpr std::size_t kMaxBins = 4096;
constexpr double kMinCellMm = 0.05;

}  // namespace

SectionStack::SectionStack(const mesh::Mesh& mesh) : context_(mesh, Vec3{0, 0, 1}) {
  const double span = std::max(context_.max_height() - context_.min_height(), 1e-9);
  const std::size_t nbins = std::clamp<std::size_t>(mesh.triangles.size() / 8 + 1, 1, kMaxBins);
  bin_mm_ = span / static_cast<double>(nbins);
  bins_.resize(nbins);
  for (std::uint32_t f = 0; f < mesh.triangles.size(); ++f) {
    const auto lo = static_cast<std::size_t>(std::clamp((context_.face_min(f) - context_.min_height()) / bin_mm_, 0.0, double(nbins - 1)));
    const auto hi = static_cast<std::size_t>(std::clamp((context_.face_max(f) - context_.min_height()) / bin_mm_, 0.0, double(nbins - 1)));
    for (std::size_t b = lo; b <= hi; ++b) bins_[b].push_back(f);
  }
}

std::vector<geom2d::Polygon> SectionStack::at(double h) const {
  if (h < context_.min_height() || h > context_.max_height()) return {};
  const auto b = static_cast<std::size_t>(
      std::clamp((h - context_.min_height()) / bin_mm_, 0.0, static_cast<double>(bins_.size() - 1)));
  slicing::SectionScratch scratch;
  auto result = slicing::section(context_, h, slicing::plane_frame(Vec3{0, 0, 1}, h), bins_[b], scratch);
  return std::move(result.polygons);
}

RayIndex::RayIndex(const std::vector<geom2d::Polygon>& polygons) {
  auto add_ring = [&](const geom2d::Ring& ring) {
    for (std::size_t i = 0; i < ring.size(); ++i) {
      const auto& a = ring[i];
      const auto& b = ring[(i + 1) % ring.size()];
      segments_.push_back({{geom2d::to_mm(a.x), geom2d::to_mm(a.y)}, {geom2d::to_mm(b.x), geom2d::to_mm(b.y)}});
    }
  };
  for (const auto& poly : polygons) {
    add_ring(poly.outer);
    for (const auto& hole : poly.holes) add_ring(hole);
  }
  if (segments_.empty()) return;
  double x1 = -INFINITY, y1 = -INFINITY, total = 0.0;
  x0_ = y0_ = INFINITY;
  for (const auto& s : segments_) {
    x0_ = std::min({x0_, s.a.x, s.b.x}), y0_ = std::min({y0_, s.a.y, s.b.y});
    x1 = std::max({x1, s.a.x, s.b.x}), y1 = std::max({y1, s.a.y, s.b.y});
    total += std::hypot(s.b.x - s.a.x, s.b.y - s.a.y);
  }
  // Cells of about four mean segment lengths, at most ~4 segments' worth of cells per segment.
  cell_ = std::max(kMinCellMm, 4.0 * total / static_cast<double>(segments_.size()));
  const double cells_needed = (x1 - x0_) * (y1 - y0_) / (cell_ * cell_);
  if (cells_needed > 4.0 * static_cast<double>(segments_.size()) + 64.0) {
    cell_ *= std::sqrt(cells_needed / (4.0 * static_cast<double>(segments_.size()) + 64.0));
  }
  nx_ = static_cast<int>((x1 - x0_) / cell_) + 1;
  ny_ = static_cast<int>((y1 - y0_) / cell_) + 1;
  std::vector<std::vector<std::uint32_t>> grid(static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_));
  for (std::uint32_t i = 0; i < segments_.size(); ++i) {
    const auto& s = segments_[i];
    const int cx0 = static_cast<int>((std::min(s.a.x, s.b.x) - x0_) / cell_), cx1 = static_cast<int>((std::max(s.a.x, s.b.x) - x0_) / cell_);
    const int cy0 = static_cast<int>((std::min(s.a.y, s.b.y) - y0_) / cell_), cy1 = static_cast<int>((std::max(s.a.y, s.b.y) - y0_) / cell_);
    for (int cy = cy0; cy <= std::min(cy1, ny_ - 1); ++cy) {
      for (int cx = cx0; cx <= std::min(cx1, nx_ - 1); ++cx) grid[static_cast<std::size_t>(cy) * static_cast<std::size_t>(nx_) + static_cast<std::size_t>(cx)].push_back(i);
    }
  }
  start_.assign(grid.size() + 1, 0);
  for (std::size_t c = 0; c < grid.size(); ++c) start_[c + 1] = start_[c] + static_cast<std::uint32_t>(grid[c].size());
  cells_.reserve(start_.back());
  for (const auto& g : grid) cells_.insert(cells_.end(), g.begin(), g.end());
}

std::optional<double> RayIndex::crossing(Vec2 p, Vec2 n, double reach) const {
  if (segments_.empty()) return std::nullopt;
  const Vec2 a{p.x - n.x * reach, p.y - n.y * reach}, b{p.x + n.x * reach, p.y + n.y * reach};
  const int cx0 = std::max(0, static_cast<int>(std::floor((std::min(a.x, b.x) - x0_) / cell_)));
  const int cx1 = std::min(nx_ - 1, static_cast<int>(std::floor((std::max(a.x, b.x) - x0_) / cell_)));
  const int cy0 = std::max(0, static_cast<int>(std::floor((std::min(a.y, b.y) - y0_) / cell_)));
  const int cy1 = std::min(ny_ - 1, static_cast<int>(std::floor((std::max(a.y, b.y) - y0_) / cell_)));
  std::optional<double> best;
  for (int cy = cy0; cy <= cy1; ++cy) {
    for (int cx = cx0; cx <= cx1; ++cx) {
      const std::size_t c = static_cast<std::size_t>(cy) * static_cast<std::size_t>(nx_) + static_cast<std::size_t>(cx);
      for (std::uint32_t k = start_[c]; k < start_[c + 1]; ++k) {
        const Segment& s = segments_[cells_[k]];
        const Vec2 e{s.b.x - s.a.x, s.b.y - s.a.y};
        // Right-hand normal (e.y, -e.x) points out of the material: keep segments facing +n.
        const double facing = e.y * n.x - e.x * n.y;
        if (facing <= 0.0) continue;
        // p + t·n = a + u·e  →  solve by 2-D cross products.
        const double denom = n.x * e.y - n.y * e.x;  // = facing
        const Vec2 w{s.a.x - p.x, s.a.y - p.y};
        const double t = (w.x * e.y - w.y * e.x) / denom;
        const double u = (w.x * n.y - w.y * n.x) / denom;
        if (u < 0.0 || u > 1.0 || std::fabs(t) > reach) continue;
        if (!best || std::fabs(t) < std::fabs(*best) || (std::fabs(t) == std::fabs(*best) && t > *best)) best = t;
      }
    }
  }
  return best;
}

bool RayIndex::inside(Vec2 p) const {
  int winding = 0;
  for (const auto& s : segments_) {
    const double cross = (s.b.x - s.a.x) * (p.y - s.a.y) - (p.x - s.a.x) * (s.b.y - s.a.y);
    if (s.a.y <= p.y) {
      if (s.b.y > p.y && cross > 0) ++winding;
    } else if (s.b.y <= p.y && cross < 0) {
      --winding;
    }
  }
  return winding != 0;
}

}  // namespace polyaxis::lamination::detail
