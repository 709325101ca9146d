#include "fidelity.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "polyaxis/geom2d/clip.h"
#include "polyaxis/mesh/mesh.h"
#include "polyaxis/mesh/topology.h"
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

}  // namespace

void measure_fidelity(Plan& plan, double part_volume_mm3) {
  const auto& layers = plan.layers.layers;
  std::map<std::uint32_t, std::size_t> index_of;  // region id -> placed_regions
  for (std::size_t i = 0; i < plan.placed_regions.size(); ++i) index_of[plan.placed_regions[i].id] = i;
  std::vector<mesh::EdgeTopology> topologies(plan.placed_regions.size());
  tbb::parallel_for(std::size_t{0}, topologies.size(), [&](std::size_t i) { topologies[i] = mesh::build_topology(plan.placed_regions[i].mesh); });
  std::vector<LayerFidelity> per(layers.size());
  tbb::enumerable_thread_specific<slicing::SectionScratch> scratch;
  tbb::parallel_for(std::size_t{0}, layers.size(), [&](std::size_t k) {
    const auto it = index_of.find(plan.region_of_layer[k]);
    if (it == index_of.end()) return;
    per[k] = measure_layer(layers[k], plan.placed_regions[it->second].mesh, topologies[it->second], scratch.local());
  });
  plan.fidelity = {};
  for (const LayerFidelity& f : per) plan.fidelity.max_cusp_mm = std::max(plan.fidelity.max_cusp_mm, f.cusp_mm), plan.fidelity.volume_difference_mm3 += f.difference_mm3;
  plan.fidelity.volume_difference_share = part_volume_mm3 > 0.0 ? plan.fidelity.volume_difference_mm3 / part_volume_mm3 : 0.0;
}

}  // namespace polyaxis::planner::detail
