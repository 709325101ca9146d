#include "polyaxis/lamination/nest.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include <polyclipping/clipper.hpp>

#include "libnest2d_bridge.h"
#include "polyaxis/geom2d/clip.h"

namespace polyaxis::lamination {
namespace {

constexpr double kCleanShareOfSpacing = 0.01;  // cleaning tolerance of the grown outlines
// libnest2d's placer leaves pieces touching to within its optimiser's tolerance (seen: 0.013 mm
// into each other): the outlines are grown by this share of the spacing more, doubled on each
// retry while the exact check still finds two pieces too close.
constexpr double kSlackShareOfSpacing = 0.02;
constexpr int kSlackRetries = 4;
constexpr double kPi = 3.14159265358979323846;

// The convex hull of RING (Andrew's monotone chain, exact orientation), counter-clockwise.
geom2d::Ring hull(geom2d::Ring pts) {
  std::sort(pts.begin(), pts.end(), [](const geom2d::Point& a, const geom2d::Point& b) { return a.x != b.x ? a.x < b.x : a.y < b.y; });
  pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
  if (pts.size() < 3) return pts;
  geom2d::Ring h(2 * pts.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    while (k >= 2 && geom2d::orientation(h[k - 2], h[k - 1], pts[i]) <= 0) --k;
    h[k++] = pts[i];
  }
  for (std::size_t i = pts.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && geom2d::orientation(h[k - 2], h[k - 1], pts[i]) <= 0) --k;
    h[k++] = pts[i];
  }
  h.resize(k - 1);
  return h;
}

// OUTLINE grown by GROW_MM with round joins, then cleaned within CLEAN_MM. Both the arcs' chords
// (arc tolerance CLEAN_MM) and the cleaning may cut up to CLEAN_MM inwards, so the ring is grown
// by twice that more first and stays outside the exact growth.
geom2d::Ring grown(const geom2d::Ring& outline, double grow_mm, double clean_mm) {
  ClipperLib::Path path;
  for (const auto& p : outline) path.push_back({p.x, p.y});
  ClipperLib::ClipperOffset offset(2.0, geom2d::kUnitsPerMm * clean_mm);
  offset.AddPath(path, ClipperLib::jtRound, ClipperLib::etClosedPolygon);
  ClipperLib::Paths out;
  offset.Execute(out, geom2d::kUnitsPerMm * (grow_mm + 2.0 * clean_mm));
  geom2d::Ring best;
  double best_area = 0.0;
  for (auto& p : out) {
    ClipperLib::CleanPolygon(p, geom2d::kUnitsPerMm * clean_mm);
    const double a = ClipperLib::Area(p);
    if (a > best_area) {
      best_area = a;
      best.clear();
      for (const auto& q : p) best.push_back({q.X, q.Y});
    }
  }
  return best;
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
  for (std::size_t i = 0; i < outlines.size(); ++i) placed[i] = round_grown(place(placements[i], outlines[i]), half);
  const ClipperLib::Path inner{{geom2d::to_units(half), geom2d::to_units(half)},
                               {geom2d::to_units(o.sheet_w_mm - half), geom2d::to_units(half)},
                               {geom2d::to_units(o.sheet_w_mm - half), geom2d::to_units(o.sheet_h_mm - half)},
                               {geom2d::to_units(half), geom2d::to_units(o.sheet_h_mm - half)}};
  for (std::size_t i = 0; i < outlines.size(); ++i) {
    ClipperLib::Clipper outside;
    outside.AddPaths(placed[i], ClipperLib::ptSubject, true);
    outside.AddPath(inner, ClipperLib::ptClip, true);
    ClipperLib::Paths off;
    outside.Execute(ClipperLib::ctDifference, off, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
    if (area_of(off) > 0.0) return core::make_error(core::ErrorCode::kInternal, fmt::format("nesting: piece {} is placed off its sheet", i));
    for (std::size_t j = i + 1; j < outlines.size(); ++j) {
      if (placements[i].sheet != placements[j].sheet) continue;
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
  const double clean = kCleanShareOfSpacing * o.spacing_mm;
  std::vector<std::vector<detail::BridgePoint>> rings;
  for (const auto& outline : outlines) {
    std::vector<detail::BridgePoint> r;
    // libnest2d's clipper backend finds no-fit polygons of convex shapes only: nest the hull.
    for (const auto& p : hull(grown(hull(outline), half, clean))) r.push_back({p.x, p.y});
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
