// polyaxis: a thin command line over libpolyaxis.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <vector>

#include "commands.h"
#include "huge_pages.h"
#include "polyaxis/core/check.h"
#include "polyaxis/core/progress.h"

namespace polyaxis::app {

int report_error(const core::Error& error) {
  std::fprintf(stderr, "polyaxis: error: %s\n", error.message.c_str());
  return static_cast<int>(error.code);
}

// A command's exit code, or 6 when what it wrote to stdout did not all get there (a full disk, a
// closed pipe: catalogue O5), so that `polyaxis inspect X --json >/dev/full` does not pass as done.
int with_stdout_checked(int code) {
  const bool failed = std::fflush(stdout) != 0 || std::ferror(stdout) != 0;
  if (!failed) return code;
  std::fprintf(stderr, "polyaxis: error: writing to standard output failed: %s\n", std::strerror(errno));
  return code != 0 ? code : static_cast<int>(core::ErrorCode::kOutput);
}

}  // namespace polyaxis::app

int main(int argc, char** argv) {
  using namespace polyaxis;
  app::use_huge_pages(argv);
  CLI::App app{"polyaxis: process planner for multi-axis layered manufacturing"};
  app.require_subcommand(1);
  app.fallthrough();  // --quiet works before or after the subcommand
  app.set_version_flag("--version", "polyaxis 0.1.0");
  bool quiet = false;
  app.add_flag("-q,--quiet", quiet, "No progress output on stderr");
  const app::Runner inspect = app::add_inspect_command(app);
  const app::Runner slice = app::add_slice_command(app);
  const app::Runner plan = app::add_plan_command(app);
  const app::Runner simulate = app::add_simulate_command(app);
  const app::Runner analyze = app::add_analyze_command(app);
  const app::Runner view = app::add_view_command(app);
  const app::Runner explain = app::add_explain_command(app);
  const app::Runner laminate = app::add_laminate_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  core::set_progress_mode(quiet ? core::ProgressMode::kQuiet : core::ProgressMode::kAuto);
  try {
    using app::with_stdout_checked;
    if (app.got_subcommand("inspect")) return with_stdout_checked(inspect());
    if (app.got_subcommand("slice")) return with_stdout_checked(slice());
    if (app.got_subcommand("plan")) return with_stdout_checked(plan());
    if (app.got_subcommand("simulate")) return with_stdout_checked(simulate());
    if (app.got_subcommand("analyze")) return with_stdout_checked(analyze());
    if (app.got_subcommand("view")) return with_stdout_checked(view());
    if (app.got_subcommand("explain")) return with_stdout_checked(explain());
    if (app.got_subcommand("laminate")) return with_stdout_checked(laminate());
    return 2;
  } catch (const core::InvariantError& e) {
    std::fprintf(stderr, "polyaxis: internal error: %s\n", e.what());
    return 1;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "polyaxis: internal error: out of memory\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "polyaxis: internal error: %s\n", e.what());
    return 1;
  }
}
