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
  core::Box3 box;
  for (const auto& v : mesh.vertices) box.add(v);
  diagonal_mm_ = box.empty() ? 0.0 : core::norm(box.max - box.min);
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

std::optional<RayIndex::Hit> RayIndex::first_hit(Vec2 p, Vec2 d) const {
  if (segments_.empty()) return std::nullopt;
  // The part of the line inside the grid's box.
  const double lo[2] = {x0_, y0_}, hi[2] = {x0_ + nx_ * cell_, y0_ + ny_ * cell_}, pp[2] = {p.x, p.y}, dd[2] = {d.x, d.y};
  double t0 = -kOnBoundaryMm, t1 = INFINITY;
  for (int k = 0; k < 2; ++k) {
    if (std::fabs(dd[k]) < 1e-300) {
      if (pp[k] < lo[k] || pp[k] > hi[k]) return std::nullopt;
      continue;
    }
    double a = (lo[k] - pp[k]) / dd[k], b = (hi[k] - pp[k]) / dd[k];
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a), t1 = std::min(t1, b);
  }
  if (t0 > t1) return std::nullopt;
  const double qx = p.x + d.x * t0, qy = p.y + d.y * t0;
  int cx = std::clamp(static_cast<int>(std::floor((qx - x0_) / cell_)), 0, nx_ - 1);
  int cy = std::clamp(static_cast<int>(std::floor((qy - y0_) / cell_)), 0, ny_ - 1);
  const int sx = d.x > 0 ? 1 : -1, sy = d.y > 0 ? 1 : -1;
  const bool flat_x = std::fabs(d.x) < 1e-300, flat_y = std::fabs(d.y) < 1e-300;
  double tx = flat_x ? INFINITY : (x0_ + (cx + (d.x > 0 ? 1 : 0)) * cell_ - p.x) / d.x;
  double ty = flat_y ? INFINITY : (y0_ + (cy + (d.y > 0 ? 1 : 0)) * cell_ - p.y) / d.y;
  const double dtx = flat_x ? INFINITY : cell_ / std::fabs(d.x), dty = flat_y ? INFINITY : cell_ / std::fabs(d.y);
  std::optional<Hit> best;
  while (cx >= 0 && cx < nx_ && cy >= 0 && cy < ny_) {
    const std::size_t c = static_cast<std::size_t>(cy) * static_cast<std::size_t>(nx_) + static_cast<std::size_t>(cx);
    for (std::uint32_t k = start_[c]; k < start_[c + 1]; ++k) {
      const Segment& s = segments_[cells_[k]];
      const Vec2 e{s.b.x - s.a.x, s.b.y - s.a.y};
      const double denom = d.x * e.y - d.y * e.x;  // > 0: the outward normal (e.y, −e.x) points along d
      if (denom == 0.0) continue;
      const Vec2 w{s.a.x - p.x, s.a.y - p.y};
      const double t = (w.x * e.y - w.y * e.x) / denom, u = (w.x * d.y - w.y * d.x) / denom;
      if (u < 0.0 || u > 1.0 || t < -kOnBoundaryMm) continue;
      if (!best || t < best->t) best = Hit{t, denom > 0.0};
    }
    const double t_exit = std::min(tx, ty);
    if ((best && best->t <= t_exit) || t_exit > t1) break;
    if (tx < ty) {
      cx += sx, tx += dtx;
    } else {
      cy += sy, ty += dty;
    }
  }
  return best;
}

std::optional<double> RayIndex::offset(Vec2 p, Vec2 n) const {
  const auto ahead = first_hit(p, n);
  if (ahead && ahead->leaves) return ahead->t;  // in the material: it reaches the first exit
  const auto behind = first_hit(p, Vec2{-n.x, -n.y});
  if (behind && !behind->leaves) return -behind->t;  // the material lies behind, its edge there
  return std::nullopt;
}

}  // namespace polyaxis::lamination::detail
