#include "polyaxis/mesh/load_part.h"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <cstdint>

namespace polyaxis::mesh {
namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// Scales and repairs MESH into PART; NAME prefixes repair's errors.
core::Status scale_and_repair(io::RawMesh mesh, const LoadOptions& options, const std::string& name, LoadedPart& part) {
  if (!std::isfinite(options.scale) || options.scale <= 0.0) {
    return core::make_error(core::ErrorCode::kUsage, fmt::format("scale: {} is not a finite positive number", options.scale));
  }
  if (options.scale != 1.0) {
    for (auto& p : mesh.points) p = p * options.scale;
  }
  const auto t = Clock::now();
  RepairOptions repair = options.repair;
  // strict refuses self-intersections, so it needs them found, whatever the caller's default.
  if (repair.strict) repair.check_self_intersections = true;
  auto repaired = mesh::repair(std::move(mesh), repair);
  if (!repaired) {
    core::Error e = repaired.error();
    e.message = fmt::format("{}: {}", name, e.message);
    return e;
  }
  part.repaired = std::move(repaired.value());
  part.repair_s = since(t);
  for (auto& line : part.repaired.report.lines()) part.warnings.push_back(line);
  for (auto& line : part.repaired.warnings) part.warnings.push_back(line);
  return {};
}

}  // namespace

core::Result<LoadedPart> load_part(const LoadOptions& options) {
  LoadedPart part;
  io::ReadOptions read = options.read;
  read.strict = options.repair.strict;
  const auto t = Clock::now();
  auto loaded = io::read_part(options.path, read);
  if (!loaded) return loaded.error();
  io::ReadResult& result = loaded.value();
  part.format = result.format;
  part.warnings = std::move(result.warnings);
  part.read_s = since(t);
  if (auto s = scale_and_repair(std::move(result.mesh), options, options.path, part); !s) return s.error();
  return part;
}

core::Result<LoadedPart> load_part(io::RawMesh mesh, const LoadOptions& options, const std::string& name) {
  for (std::size_t i = 0; i < mesh.points.size(); ++i) {
    const Vec3& p = mesh.points[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      return core::make_error(core::ErrorCode::kInvalidInput, fmt::format("{}: vertex {} is not finite", name, i));
    }
  }
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    for (const std::uint32_t v : mesh.triangles[f]) {
      if (v >= mesh.points.size()) {
        return core::make_error(core::ErrorCode::kInvalidInput,
                                fmt::format("{}: triangle {} names vertex {} of {}", name, f, v, mesh.points.size()));
      }
    }
  }
  LoadedPart part;
  if (auto s = scale_and_repair(std::move(mesh), options, name, part); !s) return s.error();
  return part;
}

}  // namespace polyaxis::mesh
