#include "part_options.h"

#include <fmt/format.h>

#include <chrono>
#include <cmath>

namespace polyaxis::app {

// CLI11's number checks let "nan" through (P5): refuse non-finite numbers here.
const CLI::Validator kFinite(
    [](std::string& text) -> std::string {
      try {
        std::size_t used = 0;
        const double v = std::stod(text, &used);
        if (used == text.size() && std::isfinite(v)) return {};
      } catch (const std::exception&) {
      }
      return "must be a finite number, not '" + text + "'";
    },
    "FINITE");

const CLI::Validator kFinitePositive(
    [](std::string& text) -> std::string {
      try {
        std::size_t used = 0;
        const double v = std::stod(text, &used);
        if (used == text.size() && std::isfinite(v) && v > 0.0) return {};
      } catch (const std::exception&) {
      }
      return "must be a finite positive number, not '" + text + "'";
    },
    "POSITIVE");

namespace {

}  // namespace

void add_part_options(CLI::App& command, PartOptions& options) {
  command.add_option("PART", options.path, "Part file: STL (binary or ASCII), OBJ, 3MF, STEP or IGES")->required();
  command.add_option("--scale", options.scale, "Multiply coordinates by this factor (e.g. 1000 for metres, 25.4 for inches)")
      ->check(kFinitePositive);
  command.add_option("--merge-mm", options.repair.merge_mm, "Merge vertices closer than this, mm")
      ->capture_default_str()->check(kFinite & CLI::Range(0.0, 1.0));
  command.add_option("--max-hole-edges", options.repair.max_hole_edges, "Fill holes with at most this many edges")
      ->capture_default_str();
  command.add_flag("--allow-open", options.repair.allow_open, "Keep larger holes open instead of refusing the part");
  CLI::Option* strict =
      command.add_flag("--strict", options.repair.strict, "Refuse self-intersecting parts and dropped 3MF triangles (runs the self-intersection check)");
  command.add_flag("!--no-self-intersections", options.repair.check_self_intersections,
                   "Skip the self-intersection check (the slowest part of repair)")
      ->excludes(strict);
  command.add_option("--max-triangles", options.read.max_triangles, "Refuse files with more triangles than this")
      ->capture_default_str()->check(CLI::PositiveNumber);
  command.add_option("--chordal-mm", options.read.chordal_mm, "STEP/IGES tessellation: largest chord deviation, mm")
      ->capture_default_str()->check(kFinitePositive & CLI::Range(1e-6, 10.0));
}

core::Result<LoadedPart> load_part(const PartOptions& options) {
  LoadedPart part;
  io::ReadOptions read = options.read;
  read.strict = options.repair.strict;
  const auto t0 = std::chrono::steady_clock::now();
  auto loaded = io::read_part(options.path, read);
  if (!loaded) return loaded.error();
  io::ReadResult& result = loaded.value();
  part.format = result.format;
  part.warnings = std::move(result.warnings);
  if (options.scale != 1.0) {
    for (auto& p : result.mesh.points) p = p * options.scale;
  }
  const auto t1 = std::chrono::steady_clock::now();
  mesh::RepairOptions repair = options.repair;
  // --strict refuses self-intersections, so it needs them found, whatever the command's default.
  if (repair.strict) repair.check_self_intersections = true;
  auto repaired = mesh::repair(std::move(result.mesh), repair);
  if (!repaired) {
    core::Error e = repaired.error();
    e.message = fmt::format("{}: {}", options.path, e.message);
    return e;
  }
  part.repaired = std::move(repaired.value());
  const auto t2 = std::chrono::steady_clock::now();
  for (auto& line : part.repaired.report.lines()) part.warnings.push_back(line);
  for (auto& line : part.repaired.warnings) part.warnings.push_back(line);
  part.read_s = std::chrono::duration<double>(t1 - t0).count();
  part.repair_s = std::chrono::duration<double>(t2 - t1).count();
  return part;
}

core::Result<double> parse_number(const std::string& text, const std::string& what) {
  try {
    std::size_t used = 0;
    const double v = std::stod(text, &used);
    if (used == text.size() && std::isfinite(v)) return v;
  } catch (const std::exception&) {
  }
  return core::make_error(core::ErrorCode::kUsage, fmt::format("{}: '{}' is not a finite number", what, text));
}

}  // namespace polyaxis::app
