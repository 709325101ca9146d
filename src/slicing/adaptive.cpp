// Adaptive layer thickness. From the bottom, each layer takes the largest admissible thickness
// t in [ΔL_min, ΔL_max] (snapped to the grid or the stock of thicknesses) for which every limit
// given holds between the section at its bottom S_b and the section at its top S_t:
//
// - cusp height (Dolenc & Mäkelä): t · max |n·d| over the facets crossing the layer ≤ cusp.
//   Facets within 1° of flat (|n·d| > cos 1°) are left out: a flat facet makes no staircase, and
//   counting it would force the minimum thickness on every layer that touches a horizontal face.
// - volumetric difference (Ruan 2006, §4.2.2, Eq. 9: VolDiff ≤ VolDiff_pre). We take
//       VolDiff = A(S_b Δ S_t) · t / (max(A(S_b), A(S_t)) · t) = A(S_b Δ S_t) / max(A(S_b), A(S_t)),
//   the volume of the staircase error band (the symmetric difference swept through the layer)
//   relative to the volume of the larger of the two prisms the layer lies between. Ruan leaves the
//   normalisation open; this one is dimensionless (one VolDiff_pre fits parts of any size),
//   bounded by 2, and zero exactly when the sections coincide.
// - area deviation (Hayasi & Asiabanpour 2012, §3-1): |A(S_t) − A(S_b)| / A(S_b) ≤ limit.
// - overhang (Kapil et al., Fig. 4): S_t − offset(S_b, t·tan α_max) is empty (up to
//   kOverhangAreaMm2 of snapping noise): no point of the upper section stands further out than
//   the lower one grown by what the material can bridge.
//
// Layers end on flat faces: when a horizontal facet (within 1°) lies less than the chosen
// thickness above the layer's bottom, and at least ΔL_min above it, the layer stops there, so
// steps in the part (a plate under a bar, a shoulder) are reproduced exactly; a layer that would
// stop just short of a flat (by less than ΔL_min) is shortened so that the next one can end on it.
//
// The largest admissible t is found by bisection over the candidate thicknesses (limits grow
// with t for the shapes a layer spans). Each accepted layer's record holds its mid-plane section,
// so Σ area × t is the midpoint rule for the volume.
#include "adaptive.h"

#include <algorithm>
#include <cmath>

#include "polyaxis/core/progress.h"
#include "polyaxis/geom2d/clip.h"

namespace polyaxis::slicing::detail {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kOverhangAreaMm2 = 1e-3;   // snapping noise in the overhang difference
const double kFlatCos = std::cos(1.0 * kPi / 180.0);

// Faces whose height range meets [lo, hi], kept as the window moves up.
class FaceWindow {
 public:
  explicit FaceWindow(const SectionContext& ctx) : ctx_(ctx) {
    by_min_.resize(ctx.mesh().triangles.size());
    for (std::uint32_t f = 0; f < by_min_.size(); ++f) by_min_[f] = f;
    std::sort(by_min_.begin(), by_min_.end(), [&](std::uint32_t a, std::uint32_t b) {
      return ctx.face_min(a) != ctx.face_min(b) ? ctx.face_min(a) < ctx.face_min(b) : a < b;
    });
  }
  // Faces with face_min <= hi and face_max >= lo; lo never decreases between calls.
  const std::vector<std::uint32_t>& span(double lo, double hi) {
    while (next_ < by_min_.size() && ctx_.face_min(by_min_[next_]) <= hi) active_.push_back(by_min_[next_++]);
    std::erase_if(active_, [&](std::uint32_t f) { return ctx_.face_max(f) < lo; });
    std::sort(active_.begin(), active_.end());  // face order: deterministic sections
    return active_;
  }

 private:
  const SectionContext& ctx_;
  std::vector<std::uint32_t> by_min_;
  std::size_t next_ = 0;
  std::vector<std::uint32_t> active_;
};



// Candidate thicknesses, ascending.
std::vector<double> candidates(const SliceOptions& o) {
  std::vector<double> c;
  if (!o.thickness_stock_mm.empty()) {
    for (double t : o.thickness_stock_mm) {
      if (t >= o.min_mm && t <= o.max_mm) c.push_back(t);
    }
  } else if (o.snap_mm > 0.0) {
    for (double k = std::ceil(o.min_mm / o.snap_mm - 1e-9); k * o.snap_mm <= o.max_mm * (1 + 1e-12) && c.size() < 100000; ++k) {
      c.push_back(k * o.snap_mm);
    }
  } else {
    constexpr int kSteps = 64;  // bisection resolution: (max − min)/64
    for (int i = 0; i <= kSteps; ++i) c.push_back(o.min_mm + (o.max_mm - o.min_mm) * i / kSteps);
  }
  std::sort(c.begin(), c.end());
  c.erase(std::unique(c.begin(), c.end()), c.end());
  if (c.empty()) c.push_back(o.min_mm);
  return c;
}

}  // namespace

core::Result<SliceResult> slice_adaptive(const SectionContext& ctx, const SliceOptions& o) {
  const mesh::Mesh& m = ctx.mesh();
  const std::vector<double> ts = candidates(o);
  const double t_max = ts.back();
  FaceWindow window(ctx);
  SectionScratch scratch;
  SliceResult result;
  const double top = ctx.max_height();
  double h = ctx.min_height();
  const double tan_a = o.limits.overhang_deg ? std::tan(*o.limits.overhang_deg * kPi / 180.0) : 0.0;
  core::Progress progress("slicing", 0);
  std::vector<double> flats;  // heights of flat facets, ascending
  for (std::uint32_t f = 0; f < m.triangles.size(); ++f) {
    const Vec3 n = core::normalized(mesh::face_area_vector(m, f));
    if (std::fabs(core::dot(n, ctx.direction())) > kFlatCos) flats.push_back((ctx.face_min(f) + ctx.face_max(f)) / 2.0);
  }
  std::sort(flats.begin(), flats.end());
  flats.erase(std::unique(flats.begin(), flats.end()), flats.end());

  auto cut = [&](double at, const std::vector<std::uint32_t>& faces) {
    return section(ctx, at, plane_frame(ctx.direction(), at), faces, scratch);
  };
  // The bottom section of the first layer: just above the lowest point (the tie rule puts the
  // plane through the lowest vertex below everything, which would be empty).
  const std::vector<std::uint32_t>* faces = &window.span(h, h + t_max);
  SectionResult bottom = cut(h + 1e-9 * std::max(1.0, std::fabs(h)), *faces);

  auto admissible = [&](double t, const std::vector<std::uint32_t>& span_faces, const SectionResult& b) {
    if (o.limits.cusp_mm) {
      double steep = 0.0;
      for (auto f : span_faces) {
        if (ctx.face_max(f) < h || ctx.face_min(f) > h + t) continue;
        const Vec3 n = core::normalized(mesh::face_area_vector(m, f));
        const double c = std::fabs(core::dot(n, ctx.direction()));
        if (c < kFlatCos) steep = std::max(steep, c);
      }
      if (t * steep > *o.limits.cusp_mm) return false;
    }
    if (!o.limits.voldiff && !o.limits.area_deviation && !o.limits.overhang_deg) return true;
    const double at = std::min(h + t, top - 1e-9 * std::max(1.0, std::fabs(top)));
    const SectionResult s = cut(at, span_faces);
    const double ab = b.area_mm2, at_area = s.area_mm2;
    if (o.limits.voldiff) {
      const auto band = geom2d::xor_rings(geom2d::rings_of(b.polygons), geom2d::rings_of(s.polygons));
      const double denom = std::max(ab, at_area);
      if (denom > 0.0 && geom2d::area_mm2(band) / denom > *o.limits.voldiff) return false;
    }
    if (o.limits.area_deviation) {  // from an empty bottom (a part starting at a point) any area is infinite deviation
      if (ab == 0.0 ? at_area > 0.0 : std::fabs(at_area - ab) / ab > *o.limits.area_deviation) return false;
    }
    if (o.limits.overhang_deg) {
      const double grow = std::max(t * tan_a, o.limits.overhang_step_mm.value_or(0.0));
      const auto grown = geom2d::offset(b.polygons, grow);
      const auto beyond = geom2d::difference_rings(geom2d::rings_of(s.polygons), geom2d::rings_of(grown));
      if (geom2d::area_mm2(beyond) > kOverhangAreaMm2) return false;
    }
    return true;
  };
  // Whether the section T above the bottom lies within the bottom section: nothing to hold up.
  auto narrows = [&](double t, const std::vector<std::uint32_t>& span_faces, const SectionResult& b) {
    const double at = std::min(h + t, top - 1e-9 * std::max(1.0, std::fabs(top)));
    const SectionResult s = cut(at, span_faces);
    return geom2d::area_mm2(geom2d::difference_rings(geom2d::rings_of(s.polygons), geom2d::rings_of(b.polygons))) <= kOverhangAreaMm2;
  };

  while (h < top) {
    faces = &window.span(h, h + t_max);
    // Bisection for the largest admissible candidate; the smallest is taken when none is.
    std::size_t lo = 0, hi = ts.size() - 1;
    std::size_t best = 0;
    bool any = admissible(ts[0], *faces, bottom);
    if (any) {
      if (admissible(ts[hi], *faces, bottom)) {
        best = hi;
      } else {
        while (hi - lo > 1) {
          const std::size_t mid = (lo + hi) / 2;
          (admissible(ts[mid], *faces, bottom) ? lo : hi) = mid;
        }
        best = lo;
      }
    } else {
      ++result.limit_violations;
    }
    // The last layer ends at the top: Σ area × t stays equal to the volume.
    double t = std::min(ts[best], top - h);
    const auto flat = std::upper_bound(flats.begin(), flats.end(), h + 0.5 * o.min_mm);
    if (flat != flats.end() && *flat < h + t && *flat - h >= o.min_mm * (1.0 - 1e-9)) {
      t = *flat - h;
    } else if (flat != flats.end() && *flat < h + t + o.min_mm && *flat - h - o.min_mm >= o.min_mm * (1.0 - 1e-9)) {
      t = *flat - h - o.min_mm;  // leave exactly ΔL_min for the next layer to end on the flat
    }
    // A remainder thinner than ΔL_min above this layer would be a layer the process cannot lay:
    // this one takes it, or the rest is split in two equal layers, where that stays within ΔL_max
    // and the limits. Where neither meets the limits but the part narrows there (a dome's top,
    // where the cusp limit binds), the range wins over the limits: this layer takes the rest, or
    // the two share it, counted in limit_violations. A top that still overhangs keeps its thin
    // layer rather than a thick one the layer below cannot hold.
    if (const double rest = top - (h + t); rest > 0.0 && rest < o.min_mm * (1.0 - 1e-9)) {
      const double half = 0.5 * (top - h);
      const bool whole_fits = t + rest <= o.max_mm * (1.0 + 1e-9);
      const bool halves_fit = half >= o.min_mm * (1.0 - 1e-9) && half <= o.max_mm * (1.0 + 1e-9);
      if (whole_fits && admissible(t + rest, *faces, bottom)) {
        t += rest;
      } else if (halves_fit && admissible(half, *faces, bottom)) {
        t = half;
      } else if ((whole_fits || halves_fit) && narrows(whole_fits ? t + rest : half, *faces, bottom)) {
        t = whole_fits ? t + rest : half;
        ++result.limit_violations;
      }
    }
    Layer layer;
    layer.index = static_cast<std::uint32_t>(result.layers.size());
    layer.height_mm = h + t / 2.0;
    layer.frame = plane_frame(ctx.direction(), layer.height_mm);
    layer.below_mm = layer.above_mm = t / 2.0;
    SectionResult mid = section(ctx, layer.height_mm, layer.frame, *faces, scratch);
    result.open_chains += mid.open_chains;
    layer.polygons = std::move(mid.polygons);
    layer.area_mm2 = mid.area_mm2;
    const double next = h + t;
    if (next < top) {
      faces = &window.span(next, next + t_max);
      bottom = cut(next, *faces);
    }
    if (!layer.polygons.empty()) result.layers.push_back(std::move(layer));
    h = next;
    progress.update(result.layers.size());
  }
  for (std::uint32_t k = 0; k < result.layers.size(); ++k) {
    result.layers[k].index = k;
    result.total_area_mm2 += result.layers[k].area_mm2;
    result.volume_estimate_mm3 += result.layers[k].area_mm2 * result.layers[k].thickness_mm();
  }
  return result;
}

}  // namespace polyaxis::slicing::detail
