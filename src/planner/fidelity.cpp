#include "fidelity.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>

#include "polyaxis/geom2d/clip.h"
#include "polyaxis/mesh/distance.h"
#include "polyaxis/mesh/mesh.h"
#include "polyaxis/mesh/topology.h"
#include "polyaxis/slicing/conformal.h"
#include "polyaxis/slicing/section.h"

namespace polyaxis::planner::detail {
namespace {

constexpr double kPi = 3.14159265358979323846;
const double kFlatCos = std::cos(1.0 * kPi / 180.0);  // as the adaptive slicer

struct LayerFidelity {
  double cusp_mm = 0.0, difference_mm3 = 0.0;
};

LayerFidelity measure_layer(const slicing::Layer& layer, const mesh::Mesh& region, const mesh::EdgeTopology& topology,
                            slicing::SectionScratch& scratch) {
  LayerFidelity out;
  const slicing::SectionContext ctx(region, layer.frame.d, &topology);
  const double h = layer.height_mm, lo = h - layer.below_mm, hi = h + layer.above_mm;
  const double t = layer.thickness_range().second;
  std::vector<std::uint32_t> faces;
  for (std::uint32_t f = 0; f < region.triangles.size(); ++f) {
    if (ctx.face_max(f) < lo || ctx.face_min(f) > hi) continue;
    faces.push_back(f);
    const double c = std::fabs(core::dot(core::normalized(mesh::face_area_vector(region, f)), layer.frame.d));
    if (c < kFlatCos) out.cusp_mm = std::max(out.cusp_mm, t * c);
  }
  for (const auto& [at, half] : {std::pair{h - layer.below_mm / 2.0, layer.below_mm}, std::pair{h + layer.above_mm / 2.0, layer.above_mm}}) {
    const slicing::SectionResult s = slicing::section(ctx, at, slicing::plane_frame(layer.frame.d, at), faces, scratch);
    const auto band = geom2d::xor_rings(geom2d::rings_of(s.polygons), geom2d::rings_of(layer.polygons));
    out.difference_mm3 += geom2d::area_mm2(band) * half;
  }
  return out;
}

// What the fidelity of a region's conformal layers is measured on: the region refined as the
// slicer refines it, and the distance from the base at its corners.
struct ConformalRegion {
  mesh::Mesh fine;
  std::unique_ptr<slicing::SectionContext> field;
};

// As measure_layer, for a conformal layer: the band of levels [level − t/2, level + t/2] around its
// mid-surface, each half at its middle level, the sections projected along d (so the volume is
// the projected area times the thickness along the gradient); the staircase of a facet is
// t·|n·g|, g the gradient at the facet's centroid.
LayerFidelity measure_conformal_layer(const slicing::Layer& layer, const ConformalRegion& region, const mesh::SurfaceDistance& base,
                                      slicing::SectionScratch& scratch) {
  LayerFidelity out;
  const slicing::SectionContext& ctx = *region.field;
  const double level = layer.conformal->level_mm, t = layer.thickness_range().second;
  const double lo = level - t / 2.0, hi = level + t / 2.0;
  std::vector<std::uint32_t> faces;
  for (std::uint32_t f = 0; f < region.fine.triangles.size(); ++f) {
    if (ctx.face_max(f) < lo || ctx.face_min(f) > hi) continue;
    faces.push_back(f);
    const Vec3 centroid = (region.fine.corner(f, 0) + region.fine.corner(f, 1) + region.fine.corner(f, 2)) / 3.0;
    const mesh::Nearest n = base.nearest(centroid);
    const Vec3 g = core::normalized(centroid - n.point);
    const double c = std::fabs(core::dot(core::normalized(mesh::face_area_vector(region.fine, f)), g));
    // A facet all but parallel to the levels makes a step no taller than its own span of levels.
    if (c < kFlatCos) out.cusp_mm = std::max(out.cusp_mm, std::min(t * c, ctx.face_max(f) - ctx.face_min(f)));
  }
  const slicing::Frame plane = slicing::plane_frame(layer.frame.d, 0.0);  // the polygons' (u, v): frames along d share them
  for (const double at : {level - t / 4.0, level + t / 4.0}) {
    const slicing::SectionResult s = slicing::section(ctx, at, plane, faces, scratch);
    const auto band = geom2d::xor_rings(geom2d::rings_of(s.polygons), geom2d::rings_of(layer.polygons));
    out.difference_mm3 += geom2d::area_mm2(band) * t / 2.0;
  }
  return out;
}

}  // namespace

void measure_fidelity(Plan& plan, double part_volume_mm3, double conformal_edge_mm) {
  const auto& layers = plan.layers.layers;
  std::map<std::uint32_t, std::size_t> index_of;  // region id -> placed_regions
  for (std::size_t i = 0; i < plan.placed_regions.size(); ++i) index_of[plan.placed_regions[i].id] = i;
  std::vector<mesh::EdgeTopology> topologies(plan.placed_regions.size());
  tbb::parallel_for(std::size_t{0}, topologies.size(), [&](std::size_t i) { topologies[i] = mesh::build_topology(plan.placed_regions[i].mesh); });
  const mesh::SurfaceDistance* base = plan.layers.conformal_base.get();
  std::vector<ConformalRegion> conformal(plan.placed_regions.size());
  for (std::size_t i = 0; i < plan.placed_regions.size(); ++i) {
    if (base == nullptr || plan.placed_regions[i].layers != slicing::LayerStrategy::kConformal) continue;
    ConformalRegion& c = conformal[i];
    auto fine = slicing::refined_for_levels(plan.placed_regions[i].mesh, *base, conformal_edge_mm);
    if (!fine) continue;  // the slicer refined it, so this does not happen; measured as planar then
    c.fine = std::move(*fine);
    std::vector<double> field(c.fine.vertices.size());
    tbb::parallel_for(std::size_t{0}, field.size(), [&](std::size_t v) { field[v] = base->nearest(c.fine.vertices[v]).signed_mm; });
    c.field = std::make_unique<slicing::SectionContext>(c.fine, plan.placed_regions[i].direction, std::move(field));
    c.field->set_field_at([base](Vec3 p) { return base->nearest(p).signed_mm; });  // as the slicer's contours
  }
  std::vector<LayerFidelity> per(layers.size());
  tbb::enumerable_thread_specific<slicing::SectionScratch> scratch;
  tbb::parallel_for(std::size_t{0}, layers.size(), [&](std::size_t k) {
    const auto it = index_of.find(plan.region_of_layer[k]);
    if (it == index_of.end()) return;
    if (layers[k].conformal && conformal[it->second].field) {
      per[k] = measure_conformal_layer(layers[k], conformal[it->second], *base, scratch.local());
    } else {
      per[k] = measure_layer(layers[k], plan.placed_regions[it->second].mesh, topologies[it->second], scratch.local());
    }
  });
  plan.fidelity = {};
  for (const LayerFidelity& f : per) plan.fidelity.max_cusp_mm = std::max(plan.fidelity.max_cusp_mm, f.cusp_mm), plan.fidelity.volume_difference_mm3 += f.difference_mm3;
  plan.fidelity.volume_difference_share = part_volume_mm3 > 0.0 ? plan.fidelity.volume_difference_mm3 / part_volume_mm3 : 0.0;
}

}  // namespace polyaxis::planner::detail
