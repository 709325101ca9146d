#include "edges.h"

#include <algorithm>
#include <cmath>

#include "polyaxis/geom2d/clip.h"

namespace polyaxis::lamination::detail {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kMinSampleSpacingMm = 1e-2;  // ring corners closer than this are one sample
// The dense profile: a height every kDenseStepMm, between kMinDenseSteps and kMaxDenseSteps a layer.
// Between two heights a cut may miss a convex profile by its sagitta, r''·step²/8 (a 30 mm ball
// at the jet's limit: 0.01 mm).
constexpr double kDenseStepMm = 0.25;
// Holes with up to this many samples are checked for crossing cuts with an exact O(n²) test; larger
// ones by their orientation alone.
constexpr std::size_t kMaxSimpleCheck = 512;
// Cut slopes below this (0.57°) are vertical: at most 0.06 mm of excess over a 6 mm sheet, and no
// head left turning C about its pole between a vertical wall and the next tilt.
constexpr double kVerticalSlope = 1e-2;
// Ternary steps of the least-excess cut's slope: (2/3)^60 of the jet's range, about 3e-11.
constexpr int kSlopeSearchSteps = 60;
constexpr int kMinDenseSteps = 8;
constexpr int kMaxDenseSteps = 64;

Vec2 unit(Vec2 v) {
  const double l = std::hypot(v.x, v.y);
  return l > 0.0 ? Vec2{v.x / l, v.y / l} : Vec2{0.0, 0.0};
}

// Samples of RING (mm): its corners with the bisector of their edges' right-hand normals, and
// points every SPACING along longer edges with the edge's normal.
std::vector<EdgeSample> ring_samples(const geom2d::Ring& ring, double spacing) {
  std::vector<Vec2> pts;
  for (const auto& q : ring) {
    const Vec2 p{geom2d::to_mm(q.x), geom2d::to_mm(q.y)};
    if (!pts.empty() && std::hypot(p.x - pts.back().x, p.y - pts.back().y) < kMinSampleSpacingMm) continue;
    pts.push_back(p);
  }
  while (pts.size() > 1 && std::hypot(pts.front().x - pts.back().x, pts.front().y - pts.back().y) < kMinSampleSpacingMm) pts.pop_back();
  std::vector<EdgeSample> out;
  const std::size_t n = pts.size();
  if (n < 3) return out;
  auto edge_normal = [&](std::size_t i) {  // of the edge pts[i] → pts[i+1]
    const Vec2 a = pts[i], b = pts[(i + 1) % n];
    return unit(Vec2{b.y - a.y, -(b.x - a.x)});
  };
  auto edge_length = [&](std::size_t i) { return std::hypot(pts[(i + 1) % n].x - pts[i].x, pts[(i + 1) % n].y - pts[i].y); };
  for (std::size_t i = 0; i < n; ++i) {
    // The corner's normal: its edges' normals weighted by their lengths, so that a sliver edge
    // (a section's rounding) does not turn it; the bisector where the two are alike.
    const double lb = edge_length((i + n - 1) % n), la = edge_length(i);
    const Vec2 before = edge_normal((i + n - 1) % n), after = edge_normal(i);
    Vec2 bis = unit(Vec2{lb * before.x + la * after.x, lb * before.y + la * after.y});
    if (bis.x == 0.0 && bis.y == 0.0) bis = after;  // a hairpin: take the edge ahead
    EdgeSample corner;
    corner.p = pts[i];
    corner.n = bis;
    out.push_back(corner);
    const Vec2 a = pts[i], b = pts[(i + 1) % n];
    const double len = std::hypot(b.x - a.x, b.y - a.y);
    const int extra = static_cast<int>(std::ceil(len / spacing)) - 1;
    for (int k = 1; k <= extra; ++k) {
      const double s = static_cast<double>(k) / (extra + 1);
      EdgeSample mid;
      mid.p = {a.x + (b.x - a.x) * s, a.y + (b.y - a.y) * s};
      mid.n = after;
      out.push_back(mid);
    }
  }
  return out;
}

// A sample's profile: at each height the boundary's offset r along n (RayIndex::offset), or none
// where there is no material on the line near the sample (nothing there to keep).
struct Profile {
  std::vector<double> h, r;
  std::vector<bool> found;
};

class LayerEdges {
 public:
  LayerEdges(const EdgeContext& c, double z0, double t) : c_(c), z0_(z0), t_(t) {
    const double sub = c.options.subslice_mm;
    m_ = std::max<std::uint32_t>(1, static_cast<std::uint32_t>(std::ceil(t / sub - 1e-9)));
    tan_limit_ = std::tan(c.options.max_jet_angle_deg * kPi / 180.0);
    z_mid_ = 0.5 * (z0 + std::min(z0 + t, c.stack.max_z()));
    // The coarse profile (the faces and the sub-slices' middles) classifies the edge and places the
    // cuts; the dense one, every t/kDenseSteps at most, keeps them off the part between those.
    std::vector<double> coarse{z0 + kFaceInsetMm};
    for (std::uint32_t k = 0; k < m_; ++k) coarse.push_back(z0 + (k + 0.5) * t / m_);
    coarse.push_back(z0 + t - kFaceInsetMm);
    heights_ = coarse;
    const auto dense = static_cast<int>(std::clamp(std::ceil(t / kDenseStepMm), double(kMinDenseSteps), double(kMaxDenseSteps)));
    for (int i = 1; i < dense; ++i) heights_.push_back(z0 + t * i / dense);
    std::sort(heights_.begin(), heights_.end());
    heights_.erase(std::unique(heights_.begin(), heights_.end()), heights_.end());
    for (double h : coarse) coarse_.push_back(static_cast<std::size_t>(std::lower_bound(heights_.begin(), heights_.end(), h) - heights_.begin()));
    for (double h : heights_) rays_.emplace_back(c.stack.at(h));
  }

  Layer build() {
    Layer layer;
    layer.z_bottom_mm = z0_;
    layer.thickness_mm = t_;
    layer.subslices = m_;
    layer.excess_mm = std::max(0.0, z0_ + t_ - c_.stack.max_z());
    layer.z_ref_mm = z_mid_;
    for (const auto& poly : c_.stack.at(z_mid_)) {
      Piece piece;
      piece.area_mm2 = geom2d::area_mm2(poly);
      piece.outer = loop(poly.outer, false, layer);
      for (const auto& hole : poly.holes) {
        EdgeLoop l = loop(hole, true, layer);
        if (closes(l)) {
          ++layer.holes_closed;  // kept as material: no straight jet within the limit clears it
        } else {
          piece.holes.push_back(std::move(l));
        }
      }
      if (!piece.outer.samples.empty()) layer.pieces.push_back(std::move(piece));
    }
    return layer;
  }

 private:
  EdgeLoop loop(const geom2d::Ring& ring, bool hole, Layer& layer) {
    EdgeLoop l;
    l.hole = hole;
    l.samples = ring_samples(ring, c_.options.sample_mm);
    for (auto& s : l.samples) {
      fit(s);
      layer.max_gap_mm = std::max(layer.max_gap_mm, s.gap_mm);
      layer.at_jet_limit += s.at_jet_limit ? 1 : 0;
      (s.kind == EdgeKind::kConvex ? layer.convex_samples : s.kind == EdgeKind::kConcave ? layer.concave_samples : layer.straight_samples)++;
    }
    return l;
  }

  // Whether the hole LOOP's kept edge closes somewhere in the layer: a sample's kept edge reaches
  // half the hole's width along its normal (the cut would pass the hole's middle and come out in
  // the material across it), or the ring of its samples moved out by their kept edge stops being a
  // simple clockwise ring at the faces or a sub-slice's middle. The hole narrows below what a line within
  // the jet's limit can follow.
  bool closes(const EdgeLoop& loop) const {
    const std::size_t n = loop.samples.size();
    if (n < 3) return true;
    for (const auto& s : loop.samples) {
      const double width = distance_across(loop, s.p, s.n, kMinSampleSpacingMm);  // to the hole's far side
      for (double h : heights_) {
        if (s.kept_mm(h, z_mid_) >= 0.5 * width) return true;
      }
    }
    for (std::size_t c : coarse_) {
      const double h = heights_[c];
      geom2d::Ring ring;
      ring.reserve(n);
      for (const auto& s : loop.samples) {
        const double r = s.kept_mm(h, z_mid_);
        ring.push_back({geom2d::to_units(s.p.x + s.n.x * r), geom2d::to_units(s.p.y + s.n.y * r)});
      }
      if (geom2d::twice_signed_area(ring) >= 0 || (ring.size() <= kMaxSimpleCheck && !geom2d::is_simple(ring))) return true;
    }
    return false;
  }

  Profile profile(const EdgeSample& s) const {
    Profile pr;
    for (std::size_t j = 0; j < heights_.size(); ++j) {
      const auto t = rays_[j].offset(s.p, s.n);
      pr.h.push_back(heights_[j]);
      pr.found.push_back(t.has_value());
      pr.r.push_back(t.value_or(0.0));
    }
    return pr;
  }

  // The slope dr/dh of the facet under the profile point at index J: −N_z / (N·n) in the sample's
  // normal plane, the line of V = C × N there.
  std::optional<double> facet_slope(const EdgeSample& s, const Profile& pr, std::size_t j) const {
    if (!pr.found[j]) return std::nullopt;
    const Vec3 hit{s.p.x + s.n.x * pr.r[j], s.p.y + s.n.y * pr.r[j], pr.h[j]};
    const Vec3 normal = c_.surface.nearest(hit).normal;
    const double along = normal.x * s.n.x + normal.y * s.n.y;
    if (along <= 1e-9) return std::nullopt;
    return -normal.z / along;
  }

  // SLOPE within the jet's limit (LIMITED set when it was not), and exactly vertical below
  // kVerticalSlope: a vertical wall's profile carries rounding of 1e-5, and a jet tilted that little
  // in a new direction at every sample would make the head's C spin about its pole.
  double clamp_slope(double slope, bool& limited) const {
    if (std::fabs(slope) < kVerticalSlope) return 0.0;
    if (std::fabs(slope) > tan_limit_) {
      limited = true;
      return std::copysign(tan_limit_, slope);
    }
    return slope;
  }

  // The line through (h, r) with SLOPE, moved out until no profile sample is outside it.
  Cut line_through(double h, double r, double slope, const Profile& pr) const {
    Cut cut{r + slope * (z_mid_ - h), slope};
    double out = 0.0;
    for (std::size_t j = 0; j < pr.h.size(); ++j) {
      if (pr.found[j]) out = std::max(out, pr.r[j] - (cut.r_mid_mm + cut.slope * (pr.h[j] - z_mid_)));
    }
    cut.r_mid_mm += out;
    return cut;
  }

  // The one cut that keeps the least material beyond the profile without leaving a profile point
  // outside it: a line a + s·(h − c) (c the mean height with material) with a ≥ r_j − s·(h_j − c)
  // for every point, whose mean excess over those heights is a − mean(r), so the least a(s) over
  // the slopes the jet reaches. a(s) is the upper envelope of lines in s, convex: a ternary search
  // finds it. On a concave or straight profile this is the chord from bottom to top; at a step it
  // may be vertical or at the jet's limit, whichever keeps less.
  Cut least_excess_line(const Profile& pr, bool& limited) const {
    double c = 0.0;
    int count = 0;
    for (std::size_t j = 0; j < pr.h.size(); ++j) {
      if (pr.found[j]) c += pr.h[j], ++count;
    }
    if (count == 0) return Cut{0.0, 0.0};
    c /= count;
    auto a_of = [&](double slope) {
      double a = -INFINITY;
      for (std::size_t j = 0; j < pr.h.size(); ++j) {
        if (pr.found[j]) a = std::max(a, pr.r[j] - slope * (pr.h[j] - c));
      }
      return a;
    };
    double lo = -tan_limit_, hi = tan_limit_;
    for (int i = 0; i < kSlopeSearchSteps; ++i) {
      const double m1 = lo + (hi - lo) / 3.0, m2 = hi - (hi - lo) / 3.0;
      if (a_of(m1) <= a_of(m2)) {
        hi = m2;
      } else {
        lo = m1;
      }
    }
    double slope = 0.5 * (lo + hi);
    if (std::fabs(slope) > tan_limit_ * (1.0 - 1e-6)) limited = true;
    if (std::fabs(slope) < kVerticalSlope) slope = 0.0;
    return Cut{a_of(slope) + slope * (z_mid_ - c), slope};
  }

  EdgeKind classify(const Profile& pr) const {
    if (std::find(pr.found.begin(), pr.found.end(), false) != pr.found.end()) return EdgeKind::kConcave;  // the material ends or steps: one cut
    bool bulge = false, hollow = false;
    for (std::size_t c = 1; c + 1 < coarse_.size(); ++c) {
      const std::size_t i = coarse_[c - 1], j = coarse_[c], k = coarse_[c + 1];
      const double s = (pr.h[j] - pr.h[i]) / (pr.h[k] - pr.h[i]);
      const double off = pr.r[j] - (pr.r[i] + s * (pr.r[k] - pr.r[i]));
      if (off > kProfileTolMm) bulge = true;
      if (off < -kProfileTolMm) hollow = true;
    }
    if (hollow) return EdgeKind::kConcave;
    return bulge ? EdgeKind::kConvex : EdgeKind::kStraight;
  }

  // Fits the sample's cuts to its profile. No cut leaves a present profile point outside it (no
  // gouge): a line whose slope the jet cannot reach is cut at the limit and moved out, keeping
  // excess material instead.
  void fit(EdgeSample& s) const {
    const Profile pr = profile(s);
    bool limited = false;
    s.kind = m_ > 1 ? classify(pr) : EdgeKind::kStraight;
    if (s.kind == EdgeKind::kConvex) {
      for (std::uint32_t k = 0; k < m_; ++k) {
        const std::size_t j = coarse_[k + 1];  // the sub-slice's middle
        double slope = 0.0;
        if (auto f = facet_slope(s, pr, j)) {
          slope = *f;
        } else {  // no facet under it: the chord of its neighbours
          slope = (pr.r[j + 1] - pr.r[j - 1]) / (pr.h[j + 1] - pr.h[j - 1]);
        }
        s.cuts.push_back(line_through(pr.h[j], pr.r[j], clamp_slope(slope, limited), pr));
      }
    } else {
      s.cuts.push_back(least_excess_line(pr, limited));
    }
    s.at_jet_limit = limited;
    for (std::size_t j = 0; j < pr.h.size(); ++j) {
      if (pr.found[j]) s.gap_mm = std::max(s.gap_mm, s.kept_mm(pr.h[j], z_mid_) - pr.r[j]);
    }
    hayasi_angles(s);
  }

  // Hayasi Eq. 1 for the first cut's vector V = (n·slope, 1) (up along the surface).
  static void hayasi_angles(EdgeSample& s) {
    const double slope = s.cuts.front().slope;
    const Vec3 v = core::normalized(Vec3{s.n.x * slope, s.n.y * slope, 1.0});
    s.hayasi_a_deg = 180.0 - std::acos(std::clamp(v.z, -1.0, 1.0)) * 180.0 / kPi;
    const double hx = std::fabs(slope) > 1e-12 ? v.x : s.n.x, hy = std::fabs(slope) > 1e-12 ? v.y : s.n.y;
    const double c = std::acos(std::clamp(hx / std::max(std::hypot(hx, hy), 1e-300), -1.0, 1.0)) * 180.0 / kPi;
    s.hayasi_c_deg = hy < 0.0 ? -c : c;
  }

  const EdgeContext& c_;
  double z0_, t_, z_mid_ = 0.0, tan_limit_ = 1.0;
  std::uint32_t m_ = 1;
  std::vector<double> heights_;
  std::vector<std::size_t> coarse_;  // indices into heights_ of the faces and the sub-slices' middles
  std::vector<RayIndex> rays_;
};

}  // namespace

Layer build_layer(const EdgeContext& context, double z0, double t) { return LayerEdges(context, z0, t).build(); }

double distance_across(const EdgeLoop& loop, Vec2 p, Vec2 n, double min_mm) {
  double nearest = INFINITY;
  const std::size_t count = loop.samples.size();
  for (std::size_t i = 0; i < count; ++i) {
    const Vec2 a = loop.samples[i].p, b = loop.samples[(i + 1) % count].p;
    const Vec2 e{b.x - a.x, b.y - a.y}, w{a.x - p.x, a.y - p.y};
    const double denom = n.x * e.y - n.y * e.x;
    if (std::fabs(denom) < 1e-15) continue;
    const double t = (w.x * e.y - w.y * e.x) / denom, u = (w.x * n.y - w.y * n.x) / denom;
    if (u >= 0.0 && u <= 1.0 && t > min_mm) nearest = std::min(nearest, t);
  }
  return nearest;
}

}  // namespace polyaxis::lamination::detail

namespace polyaxis::lamination {

double EdgeSample::kept_mm(double h, double z_mid) const {
  double r = INFINITY;
  for (const auto& c : cuts) r = std::min(r, c.r_mid_mm + c.slope * (h - z_mid));
  return r;
}

int EdgeLoop::passes() const {
  std::size_t p = 1;
  for (const auto& s : samples) p = std::max(p, s.cuts.size());
  return static_cast<int>(p);
}

std::vector<geom2d::Polygon> kept_section(const Layer& layer, const Piece& piece, double h, double offset_mm) {
  std::vector<geom2d::Ring> rings;
  auto add = [&](const EdgeLoop& loop) {
    geom2d::Ring ring;
    ring.reserve(loop.samples.size());
    for (const auto& s : loop.samples) {
      double r = INFINITY;
      for (const auto& c : s.cuts) r = std::min(r, c.r_mid_mm + c.slope * (h - layer.z_ref_mm) + offset_mm * std::sqrt(1.0 + c.slope * c.slope));
      ring.push_back({geom2d::to_units(s.p.x + s.n.x * r), geom2d::to_units(s.p.y + s.n.y * r)});
    }
    rings.push_back(std::move(ring));
  };
  add(piece.outer);
  for (const auto& hole : piece.holes) add(hole);
  return geom2d::union_rings(rings, geom2d::FillRule::kNonZero);
}

}  // namespace polyaxis::lamination
