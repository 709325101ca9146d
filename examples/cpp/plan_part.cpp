// Plans a part with the installed library and writes the same files as `polyaxis plan PART -o OUT`,
// reporting progress through a callback rather than on stderr and using two worker threads.
// Exit codes as the CLI's (docs/api/README.md).
#include <cstdio>
#include <string>

#include "polyaxis/report/plan_job.h"
#include "polyaxis/report/plan_set.h"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: plan_part PART OUT_DIR\n");
    return 2;
  }
  polyaxis::report::PlanRequest request;
  request.part.path = argv[1];
  request.part.repair.check_self_intersections = false;  // as `polyaxis plan`
  request.options.plan.threads = 2;
  std::size_t events = 0;
  request.options.progress = [&events](const polyaxis::core::ProgressEvent& e) {
    if (e.finished) std::fprintf(stderr, "plan_part: %.*s done\n", static_cast<int>(e.stage.size()), e.stage.data());
    ++events;
  };
  auto job = polyaxis::report::run_plan_job(request);
  if (!job) {
    std::fprintf(stderr, "plan_part: %s\n", job.error().message.c_str());
    return static_cast<int>(job.error().code);
  }
  const polyaxis::report::PlanJob& j = *job.value();
  const polyaxis::report::PlanFilesOptions files{argv[2], true, false, 0};
  if (auto s = polyaxis::report::write_plan_files(files, j.set, j.result, j.configs.machine, j.configs.process, j.meta); !s) {
    std::fprintf(stderr, "plan_part: %s\n", s.error().message.c_str());
    return static_cast<int>(s.error().code);
  }
  std::printf("%zu layers, %zu program points, %s, set %s, %zu progress events -> %s/%s\n", j.result.plan.layers.layers.size(),
              j.result.plan.program.size(), j.result.plan.unsupported_area_mm2 == 0.0 ? "support-free" : "not support-free",
              j.set.set_id.c_str(), events, argv[2], j.meta.gcode.c_str());
  return 0;
}
