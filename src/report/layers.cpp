#include "polyaxis/report/layers.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <nlohmann/json.hpp>
#include <tbb/parallel_for.h>
#include <tbb/parallel_pipeline.h>

namespace polyaxis::report {
namespace {

using nlohmann::ordered_json;

// Coordinates are exact multiples of 1 nm: printed with 6 decimals, by hand, two digits at a time
// (this is the hot loop of writing layers.json).
constexpr char kDigitPairs[] =
    "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
    "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
    "8081828384858687888990919293949596979899";

// Writes UNITS (nm) as mm with 6 decimals at P; the end. At most kNumberChars characters.
constexpr std::size_t kNumberChars = 22;
char* write_mm(char* p, std::int64_t units) {
  if (units < 0) *p++ = '-';
  std::uint64_t a = units < 0 ? static_cast<std::uint64_t>(-(units + 1)) + 1 : static_cast<std::uint64_t>(units);
  std::uint64_t whole = a / 1000000, fraction = a % 1000000;
  char buf[24];
  char* q = buf + sizeof buf;
  while (whole >= 100) {
    q -= 2;
    std::memcpy(q, kDigitPairs + 2 * (whole % 100), 2);
    whole /= 100;
  }
  if (whole >= 10) {
    q -= 2;
    std::memcpy(q, kDigitPairs + 2 * whole, 2);
  } else {
    *--q = static_cast<char>('0' + whole);
  }
  const auto n = static_cast<std::size_t>(buf + sizeof buf - q);
  std::memcpy(p, q, n);
  p += n;
  *p++ = '.';
  for (int k = 2; k >= 0; --k) {
    std::memcpy(p + 2 * k, kDigitPairs + 2 * (fraction % 100), 2);
    fraction /= 100;
  }
  return p + 6;
}

// A ring as [[x,y],...]: written in place into room reserved for its longest form.
void append_ring(std::string& out, const geom2d::Ring& ring) {
  const std::size_t at = out.size();
  out.resize(at + 2 + ring.size() * (2 * kNumberChars + 4));
  char* const start = out.data() + at;
  char* p = start;
  *p++ = '[';
  for (std::size_t i = 0; i < ring.size(); ++i) {
    if (i) *p++ = ',';
    *p++ = '[';
    p = write_mm(p, ring[i].x);
    *p++ = ',';
    p = write_mm(p, ring[i].y);
    *p++ = ']';
  }
  *p++ = ']';
  out.resize(at + static_cast<std::size_t>(p - start));
}

std::string vec(core::Vec3 v) { return fmt::format("[{:.9g},{:.9g},{:.9g}]", v.x, v.y, v.z); }

ordered_json summary(const slicing::SliceResult& r, const LayersMeta& meta) {
  double tmin = std::numeric_limits<double>::infinity(), tmax = 0.0;
  for (const auto& l : r.layers) tmin = std::min(tmin, l.thickness_range().first), tmax = std::max(tmax, l.thickness_range().second);
  ordered_json j;
  j["part"] = meta.part;
  j["direction"] = {core::normalized(meta.options.direction).x, core::normalized(meta.options.direction).y,
                    core::normalized(meta.options.direction).z};
  j["mode"] = meta.options.tilted ? "tilted" : meta.options.adaptive ? "adaptive" : "uniform";
  j["layers"] = r.layers.size();
  j["total_area_mm2"] = r.total_area_mm2;
  j["volume_estimate_mm3"] = r.volume_estimate_mm3;
  j["min_thickness_mm"] = r.layers.empty() ? 0.0 : tmin;
  j["max_thickness_mm"] = tmax;
  j["open_chains"] = r.open_chains;
  j["limit_violations"] = r.limit_violations;
  return j;
}

// Bytes of a layer's head and of a point in layer_json (room for its longest form): reserved at
// once, the string is not copied as it grows.
constexpr std::size_t kLayerHeadBytes = 1024;
constexpr std::size_t kPointBytes = 2 * kNumberChars + 4;

std::string layer_json(const slicing::Layer& l) {
  std::string out;
  std::size_t points = 0;
  for (const geom2d::Polygon& p : l.polygons) {
    points += p.outer.size();
    for (const geom2d::Ring& h : p.holes) points += h.size();
  }
  out.reserve(kLayerHeadBytes + kPointBytes * points);
  fmt::format_to(std::back_inserter(out),
                 "{{\"index\":{},\"origin\":{},\"normal\":{},\"u\":{},\"v\":{},\"height_mm\":{:.9g},\"thickness_mm\":{:.9g},"
                 "\"thickness_range_mm\":[{:.9g},{:.9g}],\"below_mm\":{:.9g},\"above_mm\":{:.9g},\"area_mm2\":{:.9g},\"polygons\":[",
                 l.index, vec(l.frame.origin), vec(l.frame.d), vec(l.frame.u), vec(l.frame.v), l.height_mm, l.thickness_mm(),
                 l.thickness_range().first, l.thickness_range().second, l.below_mm, l.above_mm, l.area_mm2);
  for (std::size_t p = 0; p < l.polygons.size(); ++p) {
    if (p) out += ',';
    out += "{\"outer\":";
    append_ring(out, l.polygons[p].outer);
    out += ",\"holes\":[";
    for (std::size_t h = 0; h < l.polygons[p].holes.size(); ++h) {
      if (h) out += ',';
      append_ring(out, l.polygons[p].holes[h]);
    }
    out += "]}";
  }
  out += "]}";
  return out;
}

}  // namespace

std::string slice_summary_json(const slicing::SliceResult& result, const LayersMeta& meta) { return summary(result, meta).dump(2); }

namespace {

std::string layers_head(const slicing::SliceResult& result, const LayersMeta& meta) {
  return "{\"summary\":" + summary(result, meta).dump() + ",\n\"layers\":[\n";
}
constexpr std::string_view kLayersTail = "\n]}\n";

// Layers formatted together (in parallel with other blocks), and blocks in flight at once.
constexpr std::size_t kBlockLayers = 16;
constexpr std::size_t kBlocksInFlight = 8;

// The layers of block B, each after ",\n" but the part's first.
std::string layers_block(const slicing::SliceResult& result, std::size_t b) {
  std::string out;
  for (std::size_t k = b * kBlockLayers; k < std::min(result.layers.size(), (b + 1) * kBlockLayers); ++k) {
    if (k) out += ",\n";
    out += layer_json(result.layers[k]);
  }
  return out;
}

}  // namespace

std::string layers_json(const slicing::SliceResult& result, const LayersMeta& meta) {
  // Blocks are formatted in parallel into their own strings, then joined in order: the bytes do
  // not depend on the thread count.
  const std::size_t blocks = (result.layers.size() + kBlockLayers - 1) / kBlockLayers;
  std::vector<std::string> parts(blocks);
  tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) { parts[b] = layers_block(result, b); });
  std::string out = layers_head(result, meta);
  std::size_t total = out.size() + kLayersTail.size();
  for (const auto& p : parts) total += p.size();
  out.reserve(total);
  for (const std::string& p : parts) out += p;
  out += kLayersTail;
  return out;
}

core::Status write_layers_json(io::AtomicFile& file, const slicing::SliceResult& result, const LayersMeta& meta) {
  core::Status status = file.write(layers_head(result, meta));
  const std::size_t blocks = (result.layers.size() + kBlockLayers - 1) / kBlockLayers;
  std::size_t next = 0;
  // Blocks are made side by side and written in order as they come: the bytes of layers_json.
  tbb::parallel_pipeline(kBlocksInFlight,
                         tbb::make_filter<void, std::size_t>(tbb::filter_mode::serial_in_order,
                                                             [&](tbb::flow_control& fc) -> std::size_t {
                                                               if (next == blocks || !status) {
                                                                 fc.stop();
                                                                 return 0;
                                                               }
                                                               return next++;
                                                             }) &
                             tbb::make_filter<std::size_t, std::string>(tbb::filter_mode::parallel,
                                                                        [&](std::size_t b) { return layers_block(result, b); }) &
                             tbb::make_filter<std::string, void>(tbb::filter_mode::serial_in_order, [&](const std::string& bytes) {
                               if (status) status = file.write(bytes);
                             }));
  if (!status) return status;
  return file.write(kLayersTail);
}

std::string layer_svg(const slicing::Layer& layer, const toolpath::LayerToolpaths* paths) {
  std::int64_t x0 = std::numeric_limits<std::int64_t>::max(), y0 = x0, x1 = std::numeric_limits<std::int64_t>::min(), y1 = x1;
  for (const auto& p : layer.polygons) {
    for (const auto& q : p.outer) x0 = std::min(x0, q.x), y0 = std::min(y0, q.y), x1 = std::max(x1, q.x), y1 = std::max(y1, q.y);
  }
  if (layer.polygons.empty()) x0 = y0 = x1 = y1 = 0;
  const double margin = 1.0;
  const double w = geom2d::to_mm(x1 - x0) + 2 * margin, h = geom2d::to_mm(y1 - y0) + 2 * margin;
  std::string out = fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{:.3f}mm\" height=\"{:.3f}mm\" viewBox=\"{:.6f} {:.6f} {:.6f} {:.6f}\">\n"
      "<title>layer {} at {:.4f} mm, {:.4f} mm thick, {:.3f} mm2</title>\n"
      "<g transform=\"scale(1,-1)\" fill=\"#4a90d9\" fill-opacity=\"0.6\" stroke=\"#1f3f66\" stroke-width=\"0.1\" fill-rule=\"evenodd\">\n",
      w, h, geom2d::to_mm(x0) - margin, -geom2d::to_mm(y1) - margin, w, h, layer.index, layer.height_mm, layer.thickness_mm(),
      layer.area_mm2);
  for (const auto& p : layer.polygons) {
    out += "<path d=\"";
    auto ring = [&](const geom2d::Ring& r) {
      for (std::size_t i = 0; i < r.size(); ++i) {
        fmt::format_to(std::back_inserter(out), "{}{:.6f} {:.6f} ", i ? "L" : "M", geom2d::to_mm(r[i].x), geom2d::to_mm(r[i].y));
      }
      out += "Z ";
    };
    ring(p.outer);
    for (const auto& hole : p.holes) ring(hole);
    out += "\"/>\n";
  }
  out += "</g>\n";
  if (paths != nullptr) {
    // Paths in the layer's (u, v) frame: perimeters dark red, fill orange, travel dashed grey; a
    // dot at each closed path's seam (its first point).
    auto uv = [&](core::Vec3 p) {
      const core::Vec3 rel = p - layer.frame.origin;
      return std::pair{core::dot(rel, layer.frame.u), core::dot(rel, layer.frame.v)};
    };
    out += "<g transform=\"scale(1,-1)\" fill=\"none\" stroke-width=\"0.15\" stroke-linejoin=\"round\">\n";
    for (const toolpath::Path& path : paths->paths) {
      if (path.points.size() < 2) continue;
      const char* style = path.kind == toolpath::PathKind::kPerimeter ? "stroke=\"#8b1a1a\""
                          : path.kind == toolpath::PathKind::kFill    ? "stroke=\"#e08a00\""
                                                                      : "stroke=\"#888\" stroke-dasharray=\"0.5 0.5\"";
      fmt::format_to(std::back_inserter(out), "<polyline {} points=\"", style);
      for (const toolpath::PathPoint& p : path.points) {
        const auto [u, v] = uv(p.position_mm);
        fmt::format_to(std::back_inserter(out), "{:.4f},{:.4f} ", u, v);
      }
      out += "\"/>\n";
    }
    for (const toolpath::Path& path : paths->paths) {
      const bool closed = path.points.size() > 2 && path.kind != toolpath::PathKind::kTravel &&
                          core::norm(path.points.front().position_mm - path.points.back().position_mm) < 1e-9;
      if (!closed) continue;
      const auto [u, v] = uv(path.points.front().position_mm);
      fmt::format_to(std::back_inserter(out), "<circle class=\"seam\" cx=\"{:.4f}\" cy=\"{:.4f}\" r=\"0.3\" fill=\"#0a7d2c\"/>\n", u, v);
    }
    out += "</g>\n";
  }
  out += "</svg>\n";
  return out;
}

}  // namespace polyaxis::report
