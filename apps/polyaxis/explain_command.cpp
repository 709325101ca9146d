// polyaxis explain PLAN.json (--layer R2L5 | --region 3 | --point N) [--json]: why the plan is as
// it is, from plan.json alone (report/explain.h).
#include <fmt/format.h>

#include <cstdio>

#include "commands.h"
#include "polyaxis/io/text_file.h"
#include "polyaxis/report/explain.h"
#include "polyaxis/report/plan_view.h"

namespace polyaxis::app {
namespace {

constexpr std::uint64_t kMaxPlanBytes = 4ull << 30;

struct ExplainOptions {
  std::string plan_path;
  std::string layer;
  std::optional<std::uint32_t> region;
  std::optional<std::uint64_t> point;
  bool json = false;
};

int run_explain(const ExplainOptions& o) {
  const int asked = (o.layer.empty() ? 0 : 1) + (o.region ? 1 : 0) + (o.point ? 1 : 0);
  if (asked != 1) {
    return report_error(core::make_error(core::ErrorCode::kUsage, "explain: give exactly one of --layer R<region>L<n>, --region ID or --point N"));
  }
  auto text = io::read_text_file(o.plan_path, kMaxPlanBytes);
  if (!text) return report_error(text.error());
  auto view = report::read_plan_view(text.value(), o.plan_path);
  if (!view) return report_error(view.error());
  if (view.value().rules.empty()) {
    return report_error(core::make_error(core::ErrorCode::kInvalidInput,
                                         fmt::format("{}: written before plans recorded their rules: plan the part again to explain it", o.plan_path)));
  }
  core::Result<report::Explanation> answer = core::make_error(core::ErrorCode::kInternal, "no question");
  if (!o.layer.empty()) {
    auto k = report::find_layer(view.value(), o.layer);
    if (!k) return report_error(k.error());
    answer = report::explain_layer(view.value(), k.value());
  } else if (o.region) {
    answer = report::explain_region(view.value(), *o.region);
  } else {
    answer = report::explain_point(view.value(), *o.point);
  }
  if (!answer) return report_error(answer.error());
  const std::string& out = o.json ? answer.value().json : answer.value().text;
  std::fwrite(out.data(), 1, out.size(), stdout);
  return 0;
}

}  // namespace

Runner add_explain_command(CLI::App& app) {
  auto o = std::make_shared<ExplainOptions>();
  CLI::App* cmd = app.add_subcommand("explain", "Why a plan is as it is: a layer's place in the order, a region's direction, a point's clearance");
  cmd->add_option("plan", o->plan_path, "plan.json written by polyaxis plan")->required();
  cmd->add_option("--layer", o->layer, "A layer: R<region>L<n> (the region's n-th layer, from 1) or its build position");
  cmd->add_option("--region", o->region, "A region id");
  cmd->add_option("--point", o->point, "A program point (index into plan.json's program)");
  cmd->add_flag("--json", o->json, "The answer as one JSON object");
  return [o] { return run_explain(*o); };
}

}  // namespace polyaxis::app
