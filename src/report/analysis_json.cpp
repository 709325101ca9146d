#include "polyaxis/report/analysis_json.h"

#include <nlohmann/json.hpp>

namespace polyaxis::report {
namespace {

using nlohmann::ordered_json;

ordered_json vec(core::Vec3 v) { return ordered_json::array({v.x, v.y, v.z}); }

ordered_json points(const std::vector<core::Vec3>& ps) {
  ordered_json out = ordered_json::array();
  for (const core::Vec3& p : ps) out.push_back(vec(p));
  return out;
}

}  // namespace

std::string analysis_json(const std::string& part, const analysis::OverhangMap& overhang, const analysis::CentroidalAxis& axis,
                          const std::optional<analysis::SkeletonGraph>& skeleton, const analysis::RegionTree& tree,
                          const AnalysisTimes& times) {
  ordered_json j;
  j["part"] = part;
  j["build_direction"] = vec(overhang.build_direction);
  j["overhang_area_mm2"] = overhang.area_mm2;
  ordered_json patches = ordered_json::array();
  for (const auto& p : overhang.patches) {
    patches.push_back({{"facets", p.facets.size()}, {"area_mm2", p.area_mm2}, {"centroid", vec(p.centroid)}, {"normal", vec(p.mean_normal)},
                       {"lowest_mm", p.lowest_mm}, {"highest_mm", p.highest_mm}});
  }
  j["overhang_patches"] = patches;
  ordered_json nodes = ordered_json::array(), links = ordered_json::array(), branches = ordered_json::array();
  for (const auto& n : axis.nodes) {
    nodes.push_back({{"id", n.id}, {"position", vec(n.position)}, {"direction", vec(n.direction)}, {"area_mm2", n.area_mm2}, {"branch", n.branch}});
  }
  for (const auto& l : axis.links) links.push_back({{"from", l.from}, {"to", l.to}, {"break", l.is_break}});
  for (const auto& b : axis.branches) {
    branches.push_back({{"id", b.id}, {"direction", vec(b.direction)}, {"father", b.father ? ordered_json(*b.father) : ordered_json()},
                        {"children", b.children}, {"brothers", b.brothers}});
  }
  j["centroidal_axis"] = {{"increment_mm", axis.increment_mm}, {"nodes", nodes}, {"links", links}, {"branches", branches}};
  if (skeleton) {
    ordered_json sn = ordered_json::array(), se = ordered_json::array();
    for (const auto& n : skeleton->nodes) {
      sn.push_back({{"id", n.id}, {"position", vec(n.position)}, {"radius_mm", n.radius_mm}, {"degree", n.degree}});
    }
    for (const auto& e : skeleton->edges) {
      se.push_back({{"from", e.from}, {"to", e.to}, {"length_mm", e.length_mm}, {"direction", vec(e.direction)}});
    }
    j["skeleton"] = {{"voxel_mm", skeleton->voxel_mm}, {"nodes", sn}, {"edges", se}};
  } else {
    j["skeleton"] = nullptr;
  }
  ordered_json regions = ordered_json::array();
  for (const auto& r : tree.regions) {
    regions.push_back({{"id", r.id},
                       {"parent", r.parent ? ordered_json(*r.parent) : ordered_json()},
                       {"build_direction", vec(r.build_direction)},
                       {"base_point", vec(r.base_point)},
                       {"base_normal", vec(r.base_normal)},
                       {"volume_mm3", r.volume_mm3},
                       {"support_free", r.support_free},
                       {"unsupported_area_mm2", r.unsupported_area_mm2},
                       {"mid_air_starts", points(r.mid_air_starts)},
                       {"rule", r.rule},
                       {"rests_on", r.rests_on},
                       {"stl", "region_" + std::to_string(r.id) + ".stl"}});
  }
  j["regions"] = regions;
  ordered_json faces = ordered_json::array();
  for (const auto& f : tree.faces) {
    faces.push_back({{"id", f.id}, {"normal", vec(f.normal)}, {"point", vec(f.point)}, {"area_mm2", f.area_mm2}, {"facets", f.facets}});
  }
  j["faces"] = faces;
  j["timings_s"] = {{"overhang", times.overhang_s}, {"centroidal_axis", times.axis_s}, {"skeleton", times.skeleton_s}, {"decompose", times.decompose_s}};
  return j.dump(2) + "\n";
}

}  // namespace polyaxis::report
