#include "polyaxis/lamination/nest.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <polyclipping/clipper.hpp>

#include "libnest2d_bridge.h"
#include "polyaxis/geom2d/clip.h"

namespace polyaxis::lamination {
namespace {

// libnest2d's placer leaves pieces touching to within its optimiser's tolerance (seen: 0.013 mm
// into each other): the outlines are grown by this share of the spacing more, doubled on each
// retry while the exact check still finds two pieces too close.
constexpr double kSlackShareOfSpacing = 0.02;
constexpr int kSlackRetries = 4;
constexpr double kPi = 3.14159265358979323846;

// Directions of the nesting outlines' sides: every 5°, a multiple of four so that a quarter turn
// maps the outline onto itself.
constexpr int kOutlineSides = 72;

// The outline libnest2d nests for RING grown by GROW_MM: the intersection of the half-planes
// x·u ≤ max(p·u over RING) + GROW_MM for kOutlineSides directions u, which is exactly the 72-sided
// polygon circumscribing the ring's convex hull grown by GROW_MM (the support function of a disc
// sum is the sum), so it contains that growth and exceeds it by at most (R + GROW)·(sec 2.5° − 1),
// 0.1 % of the piece's size. Convex with few sides: libnest2d's convex no-fit polygons need both
// (they came out overlapping for a 1024-gon). Corners are rounded outwards to whole units.
geom2d::Ring nesting_outline(const geom2d::Ring& ring, double grow_mm) {
  std::array<double, kOutlineSides> support{};
  std::array<double, kOutlineSides> ux{}, uy{};
  for (int j = 0; j < kOutlineSides; ++j) {
    const double a = 2.0 * kPi * j / kOutlineSides;
    ux[static_cast<std::size_t>(j)] = std::cos(a), uy[static_cast<std::size_t>(j)] = std::sin(a);
    double h = -INFINITY;
    for (const auto& p : ring) h = std::max(h, geom2d::to_mm(p.x) * std::cos(a) + geom2d::to_mm(p.y) * std::sin(a));
    support[static_cast<std::size_t>(j)] = h + grow_mm;
  }
  geom2d::Ring out;
  for (std::size_t j = 0; j < kOutlineSides; ++j) {
    const std::size_t k = (j + 1) % kOutlineSides;
    // The corner where side j meets side k.
    const double det = ux[j] * uy[k] - uy[j] * ux[k];
    const double x = (support[j] * uy[k] - uy[j] * support[k]) / det, y = (ux[j] * support[k] - support[j] * ux[k]) / det;
    out.push_back({static_cast<std::int64_t>(std::llround(x * geom2d::kUnitsPerMm + (x > 0 ? 1.0 : -1.0))),
                   static_cast<std::int64_t>(std::llround(y * geom2d::kUnitsPerMm + (y > 0 ? 1.0 : -1.0)))});
  }
  return out;
}

ClipperLib::Paths round_grown(const geom2d::Ring& ring, double grow_mm) {
  ClipperLib::Path path;
  for (const auto& p : ring) path.push_back({p.x, p.y});
  ClipperLib::ClipperOffset offset;
  offset.AddPath(path, ClipperLib::jtRound, ClipperLib::etClosedPolygon);
  ClipperLib::Paths out;
  offset.Execute(out, geom2d::kUnitsPerMm * grow_mm);
  return out;
}

double area_of(const ClipperLib::Paths& paths) {
  double a = 0.0;
  for (const auto& p : paths) a += ClipperLib::Area(p);
  return a / (geom2d::kUnitsPerMm * geom2d::kUnitsPerMm);
}

// Exact check (integer booleans): on each sheet the placed outlines grown by just under half the
// spacing neither overlap nor leave the sheet shrunk by as much.
core::Status check(const std::vector<geom2d::Ring>& outlines, const std::vector<Placement>& placements, const NestOptions& o) {
  const double half = 0.5 * o.spacing_mm * (1.0 - 1e-6);
  std::vector<ClipperLib::Paths> placed(outlines.size());
  // Each grown outline's box: pairs whose boxes are apart, and outlines whose box is inside the
  // sheet, need no boolean.
  std::vector<std::array<ClipperLib::cInt, 4>> boxes(outlines.size());
  for (std::size_t i = 0; i < outlines.size(); ++i) {
    placed[i] = round_grown(place(placements[i], outlines[i]), half);
    auto& b = boxes[i];
    b = {std::numeric_limits<ClipperLib::cInt>::max(), std::numeric_limits<ClipperLib::cInt>::max(), std::numeric_limits<ClipperLib::cInt>::min(),
         std::numeric_limits<ClipperLib::cInt>::min()};
    for (const auto& path : placed[i]) {
      for (const auto& q : path) b = {std::min(b[0], q.X), std::min(b[1], q.Y), std::max(b[2], q.X), std::max(b[3], q.Y)};
    }
  }
  const ClipperLib::Path inner{{geom2d::to_units(half), geom2d::to_units(half)},
                               {geom2d::to_units(o.sheet_w_mm - half), geom2d::to_units(half)},
                               {geom2d::to_units(o.sheet_w_mm - half), geom2d::to_units(o.sheet_h_mm - half)},
                               {geom2d::to_units(half), geom2d::to_units(o.sheet_h_mm - half)}};
  for (std::size_t i = 0; i < outlines.size(); ++i) {
    const auto& bi = boxes[i];
    const bool inside_sheet = bi[0] >= inner[0].X && bi[1] >= inner[0].Y && bi[2] <= inner[2].X && bi[3] <= inner[2].Y;
    if (!inside_sheet) {
      ClipperLib::Clipper outside;
      outside.AddPaths(placed[i], ClipperLib::ptSubject, true);
      outside.AddPath(inner, ClipperLib::ptClip, true);
      ClipperLib::Paths off;
      outside.Execute(ClipperLib::ctDifference, off, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
      if (area_of(off) > 0.0) return core::make_error(core::ErrorCode::kInternal, fmt::format("nesting: piece {} is placed off its sheet", i));
    }
    for (std::size_t j = i + 1; j < outlines.size(); ++j) {
      if (placements[i].sheet != placements[j].sheet) continue;
      const auto& bj = boxes[j];
      if (bi[2] < bj[0] || bj[2] < bi[0] || bi[3] < bj[1] || bj[3] < bi[1]) continue;  // boxes apart
      ClipperLib::Clipper both;
      both.AddPaths(placed[i], ClipperLib::ptSubject, true);
      both.AddPaths(placed[j], ClipperLib::ptClip, true);
      ClipperLib::Paths common;
      both.Execute(ClipperLib::ctIntersection, common, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
      if (area_of(common) > 0.0) {
        return core::make_error(core::ErrorCode::kInternal, fmt::format("nesting: pieces {} and {} are placed closer than the spacing ({} mm² of their grown outlines overlap; {} {} {} / {} {} {})", i, j, area_of(common), placements[i].rotation_deg, placements[i].dx_mm, placements[i].dy_mm, placements[j].rotation_deg, placements[j].dx_mm, placements[j].dy_mm));
      }
    }
  }
  return {};
}

// One run of the placer with the outlines' hulls grown by half the spacing plus SLACK_MM.
core::Result<std::vector<Placement>> nest_once(const std::vector<geom2d::Ring>& outlines, const NestOptions& o, double slack_mm) {
  const double half = 0.5 * o.spacing_mm + slack_mm;
  std::vector<std::vector<detail::BridgePoint>> rings;
  for (const auto& outline : outlines) {
    std::vector<detail::BridgePoint> r;
    // libnest2d's clipper backend finds no-fit polygons of convex shapes only (nesting_outline).
    for (const auto& p : nesting_outline(outline, half)) r.push_back({p.x, p.y});
    rings.push_back(std::move(r));
  }
  const auto raw = detail::nest_rings(rings, geom2d::to_units(half), geom2d::to_units(half), geom2d::to_units(o.sheet_w_mm - half),
                                    geom2d::to_units(o.sheet_h_mm - half));
  std::vector<Placement> placements;
  for (std::size_t i = 0; i < raw.size(); ++i) {
    if (raw[i].bin < 0) {
      return core::make_error(core::ErrorCode::kInfeasible,
                              fmt::format("piece {} fits no {}x{} mm sheet with {} mm spacing at any quarter turn", i, o.sheet_w_mm, o.sheet_h_mm, o.spacing_mm));
    }
    Placement p;
    p.sheet = static_cast<std::uint32_t>(raw[i].bin);
    p.rotation_deg = 90.0 * std::round(raw[i].rotation_rad / (kPi / 2));
    p.rotation_deg = std::fmod(std::fmod(p.rotation_deg, 360.0) + 360.0, 360.0);
    p.dx_mm = geom2d::to_mm(raw[i].dx);
    p.dy_mm = geom2d::to_mm(raw[i].dy);
    placements.push_back(p);
  }
  return placements;
}

}  // namespace

void place(const Placement& pl, double x, double y, double& out_x, double& out_y) {
  const double a = pl.rotation_deg * kPi / 180.0;
  // Quarter turns exactly: no rounding in cos/sin of 90° multiples.
  const int q = static_cast<int>(std::lround(pl.rotation_deg / 90.0)) & 3;
  const bool quarter = std::fabs(pl.rotation_deg - 90.0 * std::round(pl.rotation_deg / 90.0)) < 1e-12;
  const double c = quarter ? (q == 0 ? 1.0 : q == 2 ? -1.0 : 0.0) : std::cos(a);
  const double s = quarter ? (q == 1 ? 1.0 : q == 3 ? -1.0 : 0.0) : std::sin(a);
  out_x = c * x - s * y + pl.dx_mm;
  out_y = s * x + c * y + pl.dy_mm;
}

geom2d::Ring place(const Placement& pl, const geom2d::Ring& ring) {
  geom2d::Ring out;
  out.reserve(ring.size());
  for (const auto& p : ring) {
    double x = 0, y = 0;
    place(pl, geom2d::to_mm(p.x), geom2d::to_mm(p.y), x, y);
    out.push_back({geom2d::to_units(x), geom2d::to_units(y)});
  }
  return out;
}

core::Result<std::vector<Placement>> nest(const std::vector<geom2d::Ring>& outlines, const NestOptions& o) {
  if (!(o.sheet_w_mm > 0.0 && o.sheet_h_mm > 0.0 && o.sheet_w_mm <= 1e5 && o.sheet_h_mm <= 1e5)) {
    return core::make_error(core::ErrorCode::kUsage, fmt::format("--sheet-size {}x{}: each side must be in (0, 100000] mm", o.sheet_w_mm, o.sheet_h_mm));
  }
  if (!(o.spacing_mm > 0.0 && 2.0 * o.spacing_mm < std::min(o.sheet_w_mm, o.sheet_h_mm))) {
    return core::make_error(core::ErrorCode::kUsage, fmt::format("nesting spacing {} mm must be above 0 and leave room on the sheet", o.spacing_mm));
  }
  core::Error last;
  for (int attempt = 0; attempt < kSlackRetries; ++attempt) {
    const double slack = kSlackShareOfSpacing * o.spacing_mm * std::pow(2.0, attempt);
    auto placed = nest_once(outlines, o, slack);
    if (!placed) return placed.error();
    auto s = check(outlines, placed.value(), o);
    if (s) return placed;
    last = s.error();
  }
  return last;
}


}  // namespace polyaxis::lamination
