// polyaxis analyze PART [-o DIR] [--json]: overhang map, centroidal axis, distance-field skeleton
// and the region tree; writes DIR/analysis.json and DIR/region_<id>.stl (schema: docs/analyze.md).
#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "commands.h"
#include "root_base_option.h"
#include "part_options.h"
#include "polyaxis/io/stl_writer.h"
#include "polyaxis/io/write_file.h"
#include "polyaxis/report/analyze.h"

namespace polyaxis::app {
namespace {

struct AnalyzeOptions {
  PartOptions part;
  std::string out_dir = "analysis";
  bool json = false;
  bool skeleton = true;
  double self_supporting_deg = core::kDefaultSelfSupportingDeg;
  double voxel_mm = 0.0;
  double break_angle_deg = 30.0;
  std::string root_base;
};

int run_analyze(const AnalyzeOptions& o) {
  auto loaded = load_part(o.part);
  if (!loaded) return report_error(loaded.error());
  for (const auto& w : loaded.value().warnings) std::fprintf(stderr, "polyaxis: warning: %s\n", w.c_str());
  const mesh::RepairedMesh& part = loaded.value().repaired;
  auto root_base = parse_root_base(o.root_base);
  if (!root_base) return report_error(root_base.error());
  report::AnalyzeOptions options;
  options.root_base = root_base.value();
  options.skeleton = o.skeleton;
  options.voxel_mm = o.voxel_mm;
  options.self_supporting_deg = o.self_supporting_deg;
  options.break_angle_deg = o.break_angle_deg;
  auto analyzed = report::analyze_part(part, options);
  if (!analyzed) return report_error(analyzed.error());
  const report::PartAnalysis& a = analyzed.value();
  const analysis::OverhangMap& overhang = a.overhang;
  const analysis::RegionTree& tree = a.tree;

  std::error_code ec;
  std::filesystem::create_directories(o.out_dir, ec);
  if (ec) return report_error(core::make_error(core::ErrorCode::kOutput, fmt::format("{}: cannot create: {}", o.out_dir, ec.message())));
  for (const analysis::Region& r : tree.regions) {
    const std::string bytes = io::binary_stl(io::RawMesh{r.mesh.vertices, r.mesh.triangles}, fmt::format("polyaxis region {}", r.id));
    if (auto s = io::write_file_atomic(fmt::format("{}/region_{}.stl", o.out_dir, r.id), bytes, io::Durability::kAtomic); !s) {
      return report_error(s.error());
    }
  }
  const std::string text = report::analysis_json(o.part.path, overhang, a.axis, a.skeleton, tree, a.times);
  if (auto s = io::write_file_atomic(o.out_dir + "/analysis.json", text, io::Durability::kAtomic); !s) return report_error(s.error());
  if (o.json) {
    std::fputs(text.c_str(), stdout);
  } else {
    std::size_t breaks = 0, unsupported = 0;
    for (const auto& l : a.axis.links) breaks += l.is_break ? 1 : 0;
    for (const auto& r : tree.regions) unsupported += r.support_free ? 0 : 1;
    std::printf("overhang %.1f mm2 in %zu patches; centroidal axis %zu nodes, %zu branches, %zu break links; %zu regions (%zu not "
                "support-free) -> %s/analysis.json\n",
                overhang.area_mm2, overhang.patches.size(), a.axis.nodes.size(), a.axis.branches.size(), breaks,
                tree.regions.size(), unsupported, o.out_dir.c_str());
  }
  return 0;
}

}  // namespace

Runner add_analyze_command(CLI::App& app) {
  auto o = std::make_shared<AnalyzeOptions>();
  o->part.repair.check_self_intersections = false;
  CLI::App* cmd = app.add_subcommand("analyze", "Overhangs, centroidal axis, skeleton and the region tree of a part");
  add_part_options(*cmd, o->part);
  cmd->add_option("-o,--out", o->out_dir, "Output directory")->capture_default_str();
  add_root_base_option(*cmd, o->root_base);
  cmd->add_flag("--json", o->json, "Print analysis.json instead of one line");
  cmd->add_flag("!--no-skeleton", o->skeleton, "Skip the distance-field skeleton");
  cmd->add_option("--voxel-mm", o->voxel_mm, "Skeleton grid resolution, mm (0: the part's size / 64)")->check(kFinite & CLI::Range(0.0, 1000.0));
  cmd->add_option("--self-supporting-deg", o->self_supporting_deg, "Self-supporting angle from vertical, degrees")
      ->capture_default_str()->check(kFinite & CLI::Range(0.0, 89.0));
  cmd->add_option("--break-angle-deg", o->break_angle_deg, "Centroidal-axis links turning more than this are break links")
      ->capture_default_str()->check(kFinite & CLI::Range(1.0, 179.0));
  return [o] { return run_analyze(*o); };
}

}  // namespace polyaxis::app
