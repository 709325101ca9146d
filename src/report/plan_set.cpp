#include "polyaxis/report/plan_set.h"

#include <fmt/format.h>

#include <tbb/parallel_invoke.h>

#include <filesystem>
#include <optional>

#include "polyaxis/core/progress.h"
#include "polyaxis/io/output_set.h"
#include "polyaxis/post/toolpath_3mf.h"
#include "polyaxis/post/traori.h"
#include "polyaxis/report/layers.h"
#include "polyaxis/report/plan_view.h"
#include "polyaxis/report/report_html.h"
#include "polyaxis/verify/playback.h"

namespace polyaxis::report {
namespace {

// The output set's id: a hash of the program and the report (without the id), so that identical
// runs give identical files and any two different sets differ.
std::string set_id(std::string_view gcode, std::string_view report) {
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a, 64 bits
  for (const std::string_view part : {gcode, report}) {
    for (const char c : part) h = (h ^ static_cast<unsigned char>(c)) * 1099511628211ull;
  }
  return fmt::format("{:016x}", h);
}

}  // namespace

PlanMeta plan_meta(const planner::PlanPartResult& job, const machine::MachineConfig& machine,
                   const process::ProcessConfig& process, const std::string& part_path, double read_s, double repair_s) {
  const std::string stem = std::filesystem::path(part_path).stem().string();
  PlanMeta meta{part_path, machine.name, process.name, stem + std::string(post::program_extension(machine)), read_s, repair_s,
                job.gcode_s, job.simulate_s, job.verify_s, "", "", ""};
  meta.strategy = planner::strategy_name(job.strategy_used);
  meta.choose_s = job.choose_s;
  meta.choice = job.choice;
  if (machine.robot) meta.robot = &job.gcode_stats;
  return meta;
}

core::Result<PlanSet> make_plan_set(const planner::PlanPartResult& job, const machine::MachineConfig& machine, PlanMeta& meta) {
  PlanSet set;
  meta.set_id = "";
  set.set_id = set_id(job.gcode, report_json(job.plan, job.simulation, meta, &job.check));
  meta.set_id = set.set_id;
  auto stamped = post::with_set_id(machine, job.gcode, meta.set_id);
  if (!stamped) return stamped.error();
  set.gcode = std::move(stamped.value());
  set.report_json = report_json(job.plan, job.simulation, meta, &job.check);
  return set;
}

core::Status write_plan_files(const PlanFilesOptions& o, const PlanSet& plan_set, const planner::PlanPartResult& job,
                              const machine::MachineConfig& machine, const process::ProcessConfig& process, const PlanMeta& meta) {
  auto set = io::OutputSet::open(o.out_dir);
  if (!set) return set.error();
  const planner::Plan& plan = job.plan;
  const std::size_t files = 4 + (o.html ? 1 : 0) + (o.svg ? plan.layers.layers.size() : 0);
  core::Progress progress("writing", files);
  std::size_t written = 0;
  std::uint64_t total = 0;
  auto add = [&](const std::string& name, std::string_view bytes, io::Durability durability) -> core::Status {
    total += bytes.size();
    if (o.max_output_bytes != 0 && total > o.max_output_bytes) {
      return core::make_error(core::ErrorCode::kOutput, fmt::format("{}/{}: the output exceeds --max-output-bytes {} ({} bytes so far); "
                                                                    "nothing of this run was written",
                                                                    o.out_dir, name, o.max_output_bytes, total));
    }
    auto s = set.value().add(name, bytes, durability);
    if (s) progress.update(++written);
    return s;
  };
  PlanView view = make_plan_view(plan, machine, process, job.axis ? &*job.axis : nullptr, meta.part, plan_set.report_json, &job.check);
  // plan.json leaves out the machine playback of report.html (the program as its controller reads
  // it): plan.json is made on one side, the playback and then report.html on the other. The
  // playback is a member plan_view_json does not read.
  std::string plan_json, html;
  std::optional<core::Error> html_error;
  const auto scope = core::ProgressScope::current();  // each side may run on a worker thread
  tbb::parallel_invoke(
      [&] {
        const core::ProgressScope inner(scope);
        plan_json = plan_view_json(view);
      },
      [&] {
        const core::ProgressScope inner(scope);
        if (!o.html) return;
        auto frames = verify::playback_frames(machine, process, job.gcode);
        if (!frames) return html_error.emplace(frames.error()), void();
        view.playback = ViewPlayback{machine, std::move(frames.value())};
        html = report_html(view, viewer_bundle());
      });
  if (html_error) return *html_error;
  if (auto s = add("plan.json", plan_json, io::Durability::kAtomic); !s) return s;
  if (auto s = add("report.json", plan_set.report_json, io::Durability::kAtomic); !s) return s;
  if (auto s = add("timings.json", timings_json(plan, meta), io::Durability::kAtomic); !s) return s;
  if (o.html) {
    if (auto s = add("report.html", html, io::Durability::kAtomic); !s) return s;
  }
  if (o.svg) {
    for (std::size_t k = 0; k < plan.layers.layers.size(); ++k) {
      const std::string name = fmt::format("layer_{:05d}.svg", plan.layers.layers[k].index);
      if (auto s = add(name, layer_svg(plan.layers.layers[k], &plan.toolpaths[k]), io::Durability::kAtomic); !s) return s;
    }
  }
  // The machine program last: moved into place after everything it belongs with.
  if (auto s = add(meta.gcode, plan_set.gcode, io::Durability::kSynced); !s) return s;
  return set.value().commit();
}

}  // namespace polyaxis::report
