#include "polyaxis/report/analyze.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <numbers>

#include "polyaxis/mesh/properties.h"

namespace polyaxis::report {
namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

nlohmann::json vec_json(core::Vec3 v) { return nlohmann::json::array({v.x, v.y, v.z}); }

double radians(double deg) { return deg * std::numbers::pi / 180.0; }

}  // namespace

core::Result<PartAnalysis> analyze_part(const mesh::RepairedMesh& part, const AnalyzeOptions& o) {
  if (!(o.self_supporting_deg >= 0.0 && o.self_supporting_deg <= 89.0)) {
    return core::make_error(core::ErrorCode::kUsage, "self_supporting_deg: must be in [0, 89] degrees");
  }
  if (!(o.break_angle_deg >= 1.0 && o.break_angle_deg <= 179.0)) {
    return core::make_error(core::ErrorCode::kUsage, "break_angle_deg: must be in [1, 179] degrees");
  }
  if (!(o.voxel_mm >= 0.0 && o.voxel_mm <= 1000.0)) return core::make_error(core::ErrorCode::kUsage, "voxel_mm: must be in [0, 1000] mm");
  PartAnalysis out;
  auto root_dir = analysis::root_direction(part.mesh, o.root_base, {0, 0, 1});
  if (!root_dir) return root_dir.error();
  out.root_direction = root_dir.value();

  auto t = Clock::now();
  out.overhang = analysis::overhang_map(part.mesh, part.topology, out.root_direction, radians(o.self_supporting_deg));
  out.times.overhang_s = since(t);

  // A solid the cuts can take: the part, or its overlapping bodies united; a surface that crosses
  // itself otherwise is refused (CGAL's cuts are undefined on it). The axis is the solid's.
  std::optional<mesh::RepairedMesh> united;
  std::size_t crossing = 0;
  auto solid = analysis::cuttable_solid(part, united, crossing);
  if (!solid) return solid.error();

  t = Clock::now();
  analysis::CentroidalAxisOptions axis_options;
  axis_options.start_direction = analysis::nearest_major_direction(out.root_direction);
  axis_options.break_angle_deg = o.break_angle_deg;
  auto axis = analysis::centroidal_axis(solid.value()->mesh, solid.value()->topology, axis_options);
  if (!axis) return axis.error();
  out.axis = std::move(axis.value());
  out.times.axis_s = since(t);

  if (o.skeleton) {
    t = Clock::now();
    analysis::SkeletonOptions so;
    so.field.voxel_mm = o.voxel_mm;
    auto sk = analysis::skeleton(part.mesh, so);
    if (!sk) return sk.error();
    out.skeleton = std::move(sk.value());
    out.times.skeleton_s = since(t);
  }

  t = Clock::now();
  analysis::DecomposeOptions dopt;
  dopt.root_direction = out.root_direction;
  dopt.root_base = o.root_base;
  dopt.self_supporting_deg = o.self_supporting_deg;
  auto tree = analysis::decompose(solid.value()->mesh, out.axis, dopt);
  if (!tree) return tree.error();
  out.tree = std::move(tree.value());
  out.times.decompose_s = since(t);
  return out;
}

SolidMeasure solid_measure(const mesh::RepairedMesh& part) {
  SolidMeasure out;
  if (!part.self_intersecting.empty()) {
    if (const auto united = mesh::unite_overlapping_shells(part); united && united->self_intersecting.size() < part.self_intersecting.size()) {
      out.united = true;
      for (const auto& s : united->shells) out.volume_mm3 += s.volume_mm3, out.area_mm2 += s.area_mm2;
      return out;
    }
  }
  for (const auto& s : part.shells) out.volume_mm3 += s.volume_mm3, out.area_mm2 += s.area_mm2;  // repair measured every shell already
  return out;
}

std::string inspect_json(const mesh::LoadedPart& part, const std::string& path, double self_supporting_deg, bool checked) {
  const mesh::Mesh& m = part.repaired.mesh;
  const mesh::RepairReport& r = part.repaired.report;
  const core::Box3 box = mesh::bounding_box(m);
  const SolidMeasure measure = solid_measure(part.repaired);
  const double volume = measure.volume_mm3, area = measure.area_mm2;
  const double overhang = mesh::overhang_area(m, {0, 0, 1}, radians(self_supporting_deg));
  std::size_t cavities = 0;
  for (const auto& s : part.repaired.shells) cavities += s.cavity ? 1 : 0;
  nlohmann::json j;
  j["file"] = path;
  j["format"] = io::format_name(part.format);
  j["triangles"] = m.triangles.size();
  j["vertices"] = m.vertices.size();
  j["bbox"] = {{"min", vec_json(box.min)}, {"max", vec_json(box.max)}, {"size", vec_json(box.size())}};
  j["volume_mm3"] = volume;
  j["area_mm2"] = area;
  j["bodies_united"] = measure.united;
  j["shells"] = part.repaired.shells.size();
  j["cavities"] = cavities;
  nlohmann::json shells = nlohmann::json::array();
  for (const auto& s : part.repaired.shells) {
    shells.push_back({{"faces", s.face_count}, {"volume_mm3", s.volume_mm3}, {"area_mm2", s.area_mm2}, {"cavity", s.cavity}});
  }
  j["shell_list"] = shells;
  j["watertight"] = part.repaired.watertight;
  j["manifold"] = part.repaired.manifold;
  j["outward"] = volume > 0.0;
  j["self_intersecting_faces"] = r.self_intersecting_faces;
  j["self_intersections_checked"] = checked;
  j["repairs"] = {{"merged_vertices", r.merged_vertices},
                  {"unused_vertices", r.unused_vertices},
                  {"flipped_caps", r.flipped_caps},
                  {"degenerate_faces", r.degenerate_faces},
                  {"duplicate_faces", r.duplicate_faces},
                  {"nonmanifold_edges", r.nonmanifold_edges},
                  {"split_vertices", r.split_vertices},
                  {"flipped_faces", r.flipped_faces},
                  {"inverted_shells", r.inverted_shells},
                  {"holes_filled", r.holes_filled},
                  {"hole_faces_added", r.hole_faces_added},
                  {"open_holes", r.open_holes},
                  {"interior_shells_removed", r.interior_shells_removed}};
  j["overhang_direction"] = {0.0, 0.0, 1.0};
  j["self_supporting_deg"] = self_supporting_deg;
  j["overhang_area_mm2"] = overhang;
  j["warnings"] = part.warnings;
  j["timings_s"] = {{"read", part.read_s}, {"repair", part.repair_s}};
  return j.dump(2);
}

}  // namespace polyaxis::report
