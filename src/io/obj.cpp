// Wavefront OBJ: only geometry records matter for a part (`v`, `f`); everything else (vt, vn, g,
// o, usemtl, mtllib, s, l, comments) is skipped. Faces with n > 3 corners are triangulated by
// ear clipping after projecting onto the plane of their Newell normal, so concave n-gons stay
// inside their outline (a fan would not).
#include "polyaxis/io/obj.h"

#include <fmt/format.h>

#include <charconv>
#include <cmath>

#include "sniff.h"

namespace polyaxis::io {
namespace {

using core::ErrorCode;
using core::make_error;
using core::Vec3;

constexpr std::size_t kMaxEarClipCorners = 256;

struct Point2 {
  double x, y;
};

double cross2(Point2 o, Point2 a, Point2 b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); }

bool inside_triangle(Point2 p, Point2 a, Point2 b, Point2 c) {
  return cross2(a, b, p) >= 0 && cross2(b, c, p) >= 0 && cross2(c, a, p) >= 0;
}

// Ear clipping of a simple polygon given by CORNERS (indices into POINTS). Falls back to a fan
// when no ear is found (self-intersecting outline): repair and slicing handle the result.
void triangulate(const std::vector<Vec3>& points, const std::vector<std::uint32_t>& corners, std::vector<Triangle>& out) {
  const std::size_t n = corners.size();
  if (n > kMaxEarClipCorners) {  // ear clipping is O(n^3) at worst: bound the time a file can cost
    for (std::size_t k = 1; k + 1 < n; ++k) out.push_back({corners[0], corners[k], corners[k + 1]});
    return;
  }
  Vec3 normal{};
  for (std::size_t i = 0; i < n; ++i) {  // Newell's method
    const Vec3 a = points[corners[i]];
    const Vec3 b = points[corners[(i + 1) % n]];
    normal = normal + Vec3{(a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y)};
  }
  int drop = 2;  // project away the dominant axis of the normal, keeping orientation
  if (std::fabs(normal.x) >= std::fabs(normal.y) && std::fabs(normal.x) >= std::fabs(normal.z)) drop = 0;
  else if (std::fabs(normal.y) >= std::fabs(normal.z)) drop = 1;
  const double sign = normal[drop] < 0 ? -1.0 : 1.0;
  std::vector<Point2> p2(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 p = points[corners[i]];
    if (drop == 0) p2[i] = {p.y, p.z * sign};
    else if (drop == 1) p2[i] = {p.z, p.x * sign};
    else p2[i] = {p.x, p.y * sign};
  }
  std::vector<std::size_t> ring(n);
  for (std::size_t i = 0; i < n; ++i) ring[i] = i;
  std::size_t guard = 0;
  while (ring.size() > 3 && guard < 2 * n * n) {
    bool clipped = false;
    for (std::size_t k = 0; k < ring.size() && !clipped; ++k, ++guard) {
      const std::size_t ia = ring[(k + ring.size() - 1) % ring.size()], ib = ring[k], ic = ring[(k + 1) % ring.size()];
      if (cross2(p2[ia], p2[ib], p2[ic]) <= 0) continue;  // reflex or flat corner
      bool empty = true;
      for (std::size_t j : ring) {
        if (j == ia || j == ib || j == ic) continue;
        if (inside_triangle(p2[j], p2[ia], p2[ib], p2[ic])) {
          empty = false;
          break;
        }
      }
      if (!empty) continue;
      out.push_back({corners[ia], corners[ib], corners[ic]});
      ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(k));
      clipped = true;
    }
    if (!clipped) break;
  }
  for (std::size_t k = 1; k + 1 < ring.size(); ++k) out.push_back({corners[ring[0]], corners[ring[k]], corners[ring[k + 1]]});
}

bool parse_double(std::string_view word, double& out) {
  if (!word.empty() && word.front() == '+') word.remove_prefix(1);
  const auto [ptr, ec] = std::from_chars(word.data(), word.data() + word.size(), out);
  return ec == std::errc() && ptr == word.data() + word.size();
}

std::string_view next_word(std::string_view& line) {
  std::size_t i = 0;
  while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
  std::size_t j = i;
  while (j < line.size() && line[j] != ' ' && line[j] != '\t') ++j;
  const std::string_view w = line.substr(i, j - i);
  line.remove_prefix(j);
  return w;
}

}  // namespace

core::Result<ReadResult> read_obj(std::string_view data, const std::string& name, const ReadOptions& options) {
  if (const auto compressed = compression_of(data)) {
    return make_error(ErrorCode::kInvalidInput, fmt::format("{}: compressed input ({}); decompress first", name, *compressed));
  }
  if (data.starts_with("\xEF\xBB\xBF")) data.remove_prefix(3);
  ReadResult result;
  result.format = Format::kObj;
  RawMesh& mesh = result.mesh;
  std::vector<std::uint32_t> corners;
  std::uint64_t ngons = 0;
  std::size_t line_no = 0;
  std::size_t pos = 0;
  while (pos < data.size()) {
    std::size_t end = data.find('\n', pos);
    if (end == std::string_view::npos) end = data.size();
    std::string_view line = data.substr(pos, end - pos);
    pos = end + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    const std::string_view kind = next_word(line);
    if (kind == "v") {
      Vec3 p;
      for (int i = 0; i < 3; ++i) {
        const std::string_view w = next_word(line);
        if (!parse_double(w, p[i])) {
          return make_error(ErrorCode::kInvalidInput, fmt::format("{}: line {}: bad vertex coordinate '{:.40}'", name, line_no, w));
        }
      }
      if (!core::is_finite(p)) {
        return make_error(ErrorCode::kInvalidInput, fmt::format("{}: line {}: NaN or infinite vertex {}", name, line_no, mesh.points.size() + 1));
      }
      if (mesh.points.size() >= 3 * options.max_triangles + 3) {
        return make_error(ErrorCode::kInvalidInput, fmt::format("{}: line {}: too many vertices for --max-triangles {}", name, line_no, options.max_triangles));
      }
      mesh.points.push_back(p);
    } else if (kind == "f") {
      corners.clear();
      while (true) {
        std::string_view w = next_word(line);
        if (w.empty()) break;
        w = w.substr(0, w.find('/'));
        long long index = 0;
        const auto [ptr, ec] = std::from_chars(w.data(), w.data() + w.size(), index);
        if (ec != std::errc() || ptr != w.data() + w.size()) {
          return make_error(ErrorCode::kInvalidInput, fmt::format("{}: line {}: bad face index '{:.40}'", name, line_no, w));
        }
        const auto count = static_cast<long long>(mesh.points.size());
        const long long resolved = index < 0 ? count + index : index - 1;  // OBJ is 1-based; -1 = last
        if (index == 0 || resolved < 0 || resolved >= count) {
          return make_error(ErrorCode::kInvalidInput,
                            fmt::format("{}: line {}: face index {} out of range (1..{} or -1..-{})", name, line_no, index, count, count));
        }
        corners.push_back(static_cast<std::uint32_t>(resolved));
      }
      if (corners.size() < 3) {
        return make_error(ErrorCode::kInvalidInput, fmt::format("{}: line {}: face with {} corners", name, line_no, corners.size()));
      }
      if (corners.size() == 3) {
        mesh.triangles.push_back({corners[0], corners[1], corners[2]});
      } else {
        ++ngons;
        triangulate(mesh.points, corners, mesh.triangles);
      }
      if (mesh.triangles.size() > options.max_triangles) {
        return make_error(ErrorCode::kInvalidInput, fmt::format("{}: line {}: more than {} triangles exceeds --max-triangles", name, line_no, options.max_triangles));
      }
    }
  }
  if (mesh.triangles.empty()) return make_error(ErrorCode::kInvalidInput, fmt::format("{}: no geometry (no faces)", name));
  if (ngons > 0) result.warnings.push_back(fmt::format("triangulated {} faces with more than 3 corners", ngons));
  return result;
}

}  // namespace polyaxis::io
