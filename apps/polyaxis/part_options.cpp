#include "part_options.h"

#include <fmt/format.h>

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
