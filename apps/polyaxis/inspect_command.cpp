// polyaxis inspect PART [--json]: what the part is, what repair did, and whether it is a solid.
// The JSON schema is documented in docs/inspect.md.
#include <fmt/format.h>

#include <cmath>
#include <cstdio>

#include "commands.h"
#include "part_options.h"
#include "polyaxis/mesh/properties.h"
#include "polyaxis/report/analyze.h"

namespace polyaxis::app {
namespace {

struct InspectOptions {
  PartOptions part;
  bool json = false;
  double self_supporting_deg = core::kDefaultSelfSupportingDeg;
};

constexpr double kPi = 3.14159265358979323846;

int run_inspect(const InspectOptions& options) {
  auto loaded = load_part(options.part);
  if (!loaded) return report_error(loaded.error());
  const LoadedPart& part = loaded.value();
  const mesh::Mesh& m = part.repaired.mesh;
  const mesh::RepairReport& r = part.repaired.report;
  const core::Box3 box = mesh::bounding_box(m);
  const report::SolidMeasure measure = report::solid_measure(part.repaired);
  const double volume = measure.volume_mm3, area = measure.area_mm2;
  const double overhang = mesh::overhang_area(m, {0, 0, 1}, options.self_supporting_deg * kPi / 180.0);
  std::size_t cavities = 0;
  for (const auto& s : part.repaired.shells) cavities += s.cavity ? 1 : 0;

  for (const auto& w : part.warnings) std::fprintf(stderr, "polyaxis: warning: %s\n", w.c_str());
  if (!part.warnings.empty()) std::fprintf(stderr, "polyaxis: %zu warnings\n", part.warnings.size());

  if (options.json) {
    std::printf("%s\n", report::inspect_json(part, options.part.path, options.self_supporting_deg,
                                             options.part.repair.check_self_intersections).c_str());
    return 0;
  }
  std::printf("file          %s\n", options.part.path.c_str());
  std::printf("format        %s\n", std::string(io::format_name(part.format)).c_str());
  std::printf("triangles     %zu\n", m.triangles.size());
  std::printf("vertices      %zu\n", m.vertices.size());
  std::printf("bbox min      %.4f %.4f %.4f\n", box.min.x, box.min.y, box.min.z);
  std::printf("bbox max      %.4f %.4f %.4f\n", box.max.x, box.max.y, box.max.z);
  std::printf("volume        %.3f mm3%s\n", volume, measure.united ? " (the overlapping bodies united)" : "");
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
