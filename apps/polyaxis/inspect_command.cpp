// polyaxis inspect PART [--json]: what the part is, what repair did, and whether it is a solid.
// The JSON schema is documented in docs/inspect.md.
#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "part_options.h"
#include "polyaxis/mesh/properties.h"

namespace polyaxis::app {
namespace {

struct InspectOptions {
  PartOptions part;
  bool json = false;
  double self_supporting_deg = core::kDefaultSelfSupportingDeg;
};

constexpr double kPi = 3.14159265358979323846;

nlohmann::json vec_json(core::Vec3 v) { return nlohmann::json::array({v.x, v.y, v.z}); }

int run_inspect(const InspectOptions& options) {
  auto loaded = load_part(options.part);
  if (!loaded) return report_error(loaded.error());
  const LoadedPart& part = loaded.value();
  const mesh::Mesh& m = part.repaired.mesh;
  const mesh::RepairReport& r = part.repaired.report;
  const core::Box3 box = mesh::bounding_box(m);
  double volume = 0.0, area = 0.0;  // repair measured every shell already
  for (const auto& s : part.repaired.shells) volume += s.volume_mm3, area += s.area_mm2;
  const double overhang = mesh::overhang_area(m, {0, 0, 1}, options.self_supporting_deg * kPi / 180.0);
  std::size_t cavities = 0;
  for (const auto& s : part.repaired.shells) cavities += s.cavity ? 1 : 0;

  for (const auto& w : part.warnings) std::fprintf(stderr, "polyaxis: warning: %s\n", w.c_str());
  if (!part.warnings.empty()) std::fprintf(stderr, "polyaxis: %zu warnings\n", part.warnings.size());

  if (options.json) {
    nlohmann::json j;
    j["file"] = options.part.path;
    j["format"] = io::format_name(part.format);
    j["triangles"] = m.triangles.size();
    j["vertices"] = m.vertices.size();
    j["bbox"] = {{"min", vec_json(box.min)}, {"max", vec_json(box.max)}, {"size", vec_json(box.size())}};
    j["volume_mm3"] = volume;
    j["area_mm2"] = area;
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
    j["self_intersections_checked"] = options.part.repair.check_self_intersections;
    j["repairs"] = {{"merged_vertices", r.merged_vertices},
                    {"unused_vertices", r.unused_vertices},
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
    j["self_supporting_deg"] = options.self_supporting_deg;
    j["overhang_area_mm2"] = overhang;
    j["warnings"] = part.warnings;
    j["timings_s"] = {{"read", part.read_s}, {"repair", part.repair_s}};
    std::printf("%s\n", j.dump(2).c_str());
    return 0;
  }
  std::printf("file          %s\n", options.part.path.c_str());
  std::printf("format        %s\n", std::string(io::format_name(part.format)).c_str());
  std::printf("triangles     %zu\n", m.triangles.size());
  std::printf("vertices      %zu\n", m.vertices.size());
  std::printf("bbox min      %.4f %.4f %.4f\n", box.min.x, box.min.y, box.min.z);
  std::printf("bbox max      %.4f %.4f %.4f\n", box.max.x, box.max.y, box.max.z);
  std::printf("volume        %.3f mm3\n", volume);
  std::printf("area          %.3f mm2\n", area);
  std::printf("shells        %zu (%zu cavities)\n", part.repaired.shells.size(), cavities);
  std::printf("watertight    %s\n", part.repaired.watertight ? "yes" : "no");
  std::printf("manifold      %s\n", part.repaired.manifold ? "yes" : "no");
  if (options.part.repair.check_self_intersections) {
    std::printf("self-intersecting faces  %llu\n", static_cast<unsigned long long>(r.self_intersecting_faces));
  }
  std::printf("overhang (+Z, %.0f deg)  %.3f mm2\n", options.self_supporting_deg, overhang);
  const auto lines = r.lines();
  std::printf("repairs       %s\n", lines.empty() ? "none" : "");
  for (const auto& line : lines) std::printf("  %s\n", line.c_str());
  return 0;
}

}  // namespace

Runner add_inspect_command(CLI::App& app) {
  auto options = std::make_shared<InspectOptions>();
  CLI::App* cmd = app.add_subcommand("inspect", "Read and repair a part; report its geometry and what was repaired");
  add_part_options(*cmd, options->part);
  cmd->add_flag("--json", options->json, "Print one JSON object (schema: docs/inspect.md)");
  cmd->add_option("--self-supporting-deg", options->self_supporting_deg, "Self-supporting angle from vertical, degrees")
      ->capture_default_str()->check(kFinite & CLI::Range(0.0, 90.0));
  return [options] { return run_inspect(*options); };
}

}  // namespace polyaxis::app
