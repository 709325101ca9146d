// STL readers. Binary layout: 80-byte header, uint32 count n, then n records of 50 bytes
// (normal, 3 vertices as float32 little-endian, uint16 attribute). ASCII: solid / facet normal /
// outer loop / vertex ×3 / endloop / endfacet / endsolid, whitespace-separated.
#include "polyaxis/io/stl.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "point_welder.h"
#include "polyaxis/core/progress.h"
#include "sniff.h"

namespace polyaxis::io {
namespace {

using core::ErrorCode;
using core::make_error;
using core::Vec3;

static_assert(std::endian::native == std::endian::little, "STL readers assume a little-endian host");

constexpr std::size_t kHeaderBytes = 84;
constexpr std::size_t kRecordBytes = 50;
constexpr std::string_view kBom = "\xEF\xBB\xBF";

float read_f32(const char* p) {
  std::uint32_t u = 0;
  std::memcpy(&u, p, 4);
  return std::bit_cast<float>(u);
}

std::uint32_t read_u32(const char* p) {
  std::uint32_t u = 0;
  std::memcpy(&u, p, 4);
  return u;
}

bool binary_size_matches(std::size_t size) {
  return size >= kHeaderBytes && (size - kHeaderBytes) % kRecordBytes == 0;
}

bool equals_nocase(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return (x | 0x20) == (y | 0x20);
         });
}

// The body is ASCII STL if, after an optional BOM and whitespace, it says "solid" and the 4 kB
// after the name line hold no NUL (binary floats nearly always do) up to "endsolid", and "facet"
// or "endsolid" appears there. Keywords in any case ("SOLID", as some exporters write them; an
// upper-case file was read as a binary header claiming 538976266 triangles).
bool looks_ascii(std::string_view data) {
  if (data.starts_with(kBom)) data.remove_prefix(kBom.size());
  const auto first = data.find_first_not_of(" \t\r\n");
  if (first == std::string_view::npos) return false;
  data.remove_prefix(first);
  if (data.size() < 5 || !equals_nocase(data.substr(0, 5), "solid")) return false;
  // The name after "solid" is opaque (it may hold any byte, F9): judge the text after it.
  const auto eol = data.find('\n');
  if (eol == std::string_view::npos) return data.size() < 1024;  // "solid name" alone: an empty ASCII file
  data.remove_prefix(eol + 1);
  std::string lowered(data.substr(0, 4096));
  for (char& c : lowered) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  std::string_view head = lowered;
  const auto end = head.find("endsolid");  // its name is opaque too
  if (end != std::string_view::npos) head = head.substr(0, end);
  if (head.find('\0') != std::string_view::npos) return false;
  return end != std::string_view::npos || head.find("facet") != std::string_view::npos;
}

// One chunk of a binary STL welded on its own: its distinct points in first-seen order (with
// their table, kept for the chunks after it) and its triangles in those local indices, or the first
// facet with a non-finite vertex.
struct WeldedChunk {
  std::vector<Vec3> points;
  std::optional<FloatPointWelder> welder;
  std::vector<Triangle> triangles;
  std::vector<std::uint32_t> global;  // local point -> index in the whole mesh
  std::uint64_t nan_normals = 0;
  std::uint64_t bad_facet = std::numeric_limits<std::uint64_t>::max();
  unsigned bad_corner = 0;
};

void weld_chunk(const char* records, std::uint64_t first, std::uint64_t last, WeldedChunk& chunk) {
  const std::uint64_t n = last - first;
  chunk.triangles.resize(n);
  chunk.points.reserve(n / 2 + 16);
  FloatPointWelder& welder = chunk.welder.emplace(chunk.points, n / 2 + 16);
  const char* rec = records + first * kRecordBytes;
  for (std::uint64_t t = 0; t < n; ++t, rec += kRecordBytes) {
    if (!std::isfinite(read_f32(rec)) || !std::isfinite(read_f32(rec + 4)) || !std::isfinite(read_f32(rec + 8))) ++chunk.nan_normals;
    for (unsigned c = 0; c < 3; ++c) {
      const char* v = rec + 12 + 12 * c;
      const float x = read_f32(v), y = read_f32(v + 4), z = read_f32(v + 8);
      if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) {
        chunk.bad_facet = first + t;
        chunk.bad_corner = c;
        return;
      }
      chunk.triangles[t][c] = welder.index_of(x, y, z);
    }
  }
}

// Chunk C's points that an earlier chunk already has: global[i] is set to (chunk << 32 | local
// index) of the first such chunk, packed, or kNew. Read-only lookups, parallel over the points.
constexpr std::uint64_t kNew = std::numeric_limits<std::uint64_t>::max();

std::vector<std::uint64_t> earlier_copies(const std::vector<WeldedChunk>& chunks, std::size_t c) {
  const auto& points = chunks[c].points;
  std::vector<std::uint64_t> found(points.size(), kNew);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 1 << 14), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      const auto x = static_cast<float>(points[i].x), y = static_cast<float>(points[i].y), z = static_cast<float>(points[i].z);
      for (std::size_t j = 0; j < c; ++j) {
        const std::uint32_t k = chunks[j].welder->find(x, y, z);
        if (k != FloatPointWelder::kAbsent) {
          found[i] = static_cast<std::uint64_t>(j) << 32 | k;
          break;
        }
      }
    }
  });
  return found;
}

// Chunks are welded in parallel, then each chunk's points are looked up in the chunks before it,
// so every point gets the index of its first appearance in the file, as one sequential pass would
// give it: the mesh does not depend on the thread count.
core::Result<ReadResult> read_binary(std::string_view data, const std::string& name, const ReadOptions& options,
                                     std::vector<std::string> warnings) {
  const std::uint64_t n = (data.size() - kHeaderBytes) / kRecordBytes;
  const std::uint32_t declared = read_u32(data.data() + 80);
  if (n == 0) return make_error(ErrorCode::kInvalidInput, fmt::format("{}: no geometry (binary STL with 0 triangles)", name));
  if (n > options.max_triangles) {
    return make_error(ErrorCode::kInvalidInput,
                      fmt::format("{}: {} triangles exceeds --max-triangles {}", name, n, options.max_triangles));
  }
  if (declared != n) {
    warnings.push_back(fmt::format("header says {} triangles but the file size holds {}; trusting the size", declared, n));
  }
  constexpr std::uint64_t kMinChunkTriangles = 1 << 16;
  const auto threads = static_cast<std::uint64_t>(std::max(1, tbb::this_task_arena::max_concurrency()));
  const std::size_t count = std::clamp<std::uint64_t>(n / kMinChunkTriangles, 1, threads);
  std::vector<WeldedChunk> chunks(count);  // never resized: each welder refers to its own points
  const char* records = data.data() + kHeaderBytes;
  auto bound = [&](std::uint64_t c) { return n * c / count; };
  core::Progress progress("reading", n);  // triangles
  tbb::parallel_for(std::size_t{0}, count, [&](std::size_t c) { weld_chunk(records, bound(c), bound(c + 1), chunks[c]); });
  std::uint64_t nan_normals = 0;
  for (const WeldedChunk& chunk : chunks) {
    if (chunk.bad_facet != std::numeric_limits<std::uint64_t>::max()) {
      return make_error(ErrorCode::kInvalidInput,
                        fmt::format("{}: facet {} (byte offset {}) has a NaN or infinite vertex", name, chunk.bad_facet,
                                    kHeaderBytes + chunk.bad_facet * kRecordBytes + 12 + 12 * chunk.bad_corner));
    }
    nan_normals += chunk.nan_normals;
  }
  progress.update(n / 2);

  ReadResult result;
  result.format = Format::kStlBinary;
  RawMesh& mesh = result.mesh;
  if (count == 1) {
    mesh.points = std::move(chunks[0].points);
    mesh.triangles = std::move(chunks[0].triangles);
  } else {
    std::size_t distinct = 0;
    for (const WeldedChunk& chunk : chunks) distinct += chunk.points.size();
    mesh.points.reserve(distinct);
    for (std::size_t c = 0; c < count; ++c) {
      const std::vector<std::uint64_t> found = c == 0 ? std::vector<std::uint64_t>(chunks[0].points.size(), kNew) : earlier_copies(chunks, c);
      auto& global = chunks[c].global;
      global.resize(found.size());
      for (std::size_t i = 0; i < found.size(); ++i) {
        if (found[i] == kNew) {
          global[i] = static_cast<std::uint32_t>(mesh.points.size());
          mesh.points.push_back(chunks[c].points[i]);
        } else {
          global[i] = chunks[found[i] >> 32].global[found[i] & 0xffffffffu];
        }
      }
    }
    // The first chunk's points come first and in order (its ids are already global): its faces stay.
    mesh.triangles = std::move(chunks[0].triangles);
    mesh.triangles.resize(n);
    tbb::parallel_for(std::size_t{1}, count, [&](std::size_t c) {
      const auto& local = chunks[c].triangles;
      const auto& global = chunks[c].global;
      for (std::uint64_t t = 0; t < local.size(); ++t) {
        for (std::size_t k = 0; k < 3; ++k) mesh.triangles[bound(c) + t][k] = global[local[t][k]];
      }
    });
  }
  if (nan_normals > 0) warnings.push_back(fmt::format("{} facets had a NaN or infinite normal; normals are recomputed", nan_normals));
  result.warnings = std::move(warnings);
  return result;
}

// A forward-only tokenizer that counts lines, for error messages.
class Tokens {
 public:
  explicit Tokens(std::string_view text) : text_(text) {}

  std::string_view next() {
    skip_space();
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !is_space(text_[pos_])) ++pos_;
    return text_.substr(start, pos_ - start);
  }
  void skip_line() {
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
  }
  bool at_end() {
    skip_space();
    return pos_ >= text_.size();
  }
  std::size_t line() const { return line_; }
  std::size_t position() const { return pos_; }

 private:
  static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }
  void skip_space() {
    while (pos_ < text_.size() && is_space(text_[pos_])) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
  }
  std::string_view text_;
  std::size_t pos_ = 0;
  std::size_t line_ = 1;
};

bool parse_double(std::string_view word, double& out) {
  if (!word.empty() && word.front() == '+') word.remove_prefix(1);
  const auto [ptr, ec] = std::from_chars(word.data(), word.data() + word.size(), out);
  return ec == std::errc() && ptr == word.data() + word.size();
}

core::Result<ReadResult> read_ascii(std::string_view data, const std::string& name, const ReadOptions& options,
                                    std::vector<std::string> warnings) {
  if (data.starts_with(kBom)) data.remove_prefix(kBom.size());
  ReadResult result;
  result.format = Format::kStlAscii;
  RawMesh& mesh = result.mesh;
  // An ASCII facet takes at least ~100 bytes: a capacity hint that cannot be inflated by a header.
  PointWelder welder(mesh.points, std::min<std::size_t>(data.size() / 200, 1u << 24));
  Tokens tok(data);
  std::uint64_t facet = 0;
  std::uint64_t nan_normals = 0;
  auto cut = [&](std::string_view expected, std::string_view got) {
    if (got.empty()) {
      return make_error(ErrorCode::kInvalidInput, fmt::format("{}: ASCII STL ends inside facet {} at line {} (expected '{}')",
                                                              name, facet, tok.line(), expected));
    }
    return make_error(ErrorCode::kInvalidInput, fmt::format("{}: line {}: expected '{}' in facet {}, found '{:.40}'",
                                                            name, tok.line(), expected, facet, got));
  };
  auto expect = [&](std::string_view word) -> core::Status {
    const std::string_view got = tok.next();
    if (!equals_nocase(got, word)) return cut(word, got);
    return {};
  };
  bool in_solid = false;
  core::Progress progress("reading", data.size());  // bytes
  std::uint64_t facets_read = 0;
  while (!tok.at_end()) {
    if ((++facets_read & 0xffff) == 0) progress.update(tok.position());
    const std::string_view word = tok.next();
    if (equals_nocase(word, "solid")) {
      tok.skip_line();  // the name: opaque bytes (F9)
      in_solid = true;
      continue;
    }
    if (equals_nocase(word, "endsolid")) {
      tok.skip_line();
      in_solid = false;
      continue;
    }
    if (!equals_nocase(word, "facet")) {
      return make_error(ErrorCode::kInvalidInput,
                        fmt::format("{}: line {}: expected 'facet' or 'endsolid', found '{:.40}'", name, tok.line(), word));
    }
    if (!in_solid) {
      return make_error(ErrorCode::kInvalidInput, fmt::format("{}: line {}: 'facet' outside 'solid'", name, tok.line()));
    }
    if (facet >= options.max_triangles) {
      return make_error(ErrorCode::kInvalidInput,
                        fmt::format("{}: more than {} triangles exceeds --max-triangles", name, options.max_triangles));
    }
    if (auto s = expect("normal"); !s) return s.error();
    bool normal_ok = true;
    for (int i = 0; i < 3; ++i) {
      const std::string_view w = tok.next();
      double v = 0;
      if (!parse_double(w, v)) return cut("a number", w);
      normal_ok = normal_ok && std::isfinite(v);
    }
    if (!normal_ok) ++nan_normals;
    if (auto s = expect("outer"); !s) return s.error();
    if (auto s = expect("loop"); !s) return s.error();
    Triangle tri{};
    for (int c = 0; c < 3; ++c) {
      if (auto s = expect("vertex"); !s) return s.error();
      Vec3 p;
      for (int i = 0; i < 3; ++i) {
        const std::string_view w = tok.next();
        if (!parse_double(w, p[i])) return cut("a number", w);
      }
      if (!core::is_finite(p)) {
        return make_error(ErrorCode::kInvalidInput,
                          fmt::format("{}: line {}: facet {} has a NaN or infinite vertex", name, tok.line(), facet));
      }
      tri[static_cast<std::size_t>(c)] = welder.index_of(p);
    }
    if (auto s = expect("endloop"); !s) return s.error();
    if (auto s = expect("endfacet"); !s) return s.error();
    mesh.triangles.push_back(tri);
    ++facet;
  }
  if (mesh.triangles.empty()) return make_error(ErrorCode::kInvalidInput, fmt::format("{}: no geometry (ASCII STL without facets)", name));
  if (nan_normals > 0) warnings.push_back(fmt::format("{} facets had a NaN or infinite normal; normals are recomputed", nan_normals));
  result.warnings = std::move(warnings);
  return result;
}

}  // namespace

core::Result<ReadResult> read_stl(std::string_view data, const std::string& name, const ReadOptions& options) {
  std::vector<std::string> warnings;
  if (data.size() < kHeaderBytes && !looks_ascii(data)) {
    if (data.empty()) return make_error(ErrorCode::kInvalidInput, fmt::format("{}: empty file, no geometry", name));
    return make_error(ErrorCode::kInvalidInput,
                      fmt::format("{}: truncated: expected at least {} bytes, got {}", name, kHeaderBytes, data.size()));
  }
  // Size invariant first (F4: a binary header may say "solid"); a declared count that also matches
  // makes it certain.
  if (data.size() >= kHeaderBytes) {
    const std::uint64_t declared = read_u32(data.data() + 80);
    if (kHeaderBytes + declared * kRecordBytes == data.size()) return read_binary(data, name, options, std::move(warnings));
  }
  if (looks_ascii(data)) return read_ascii(data, name, options, std::move(warnings));
  if (const auto compressed = compression_of(data)) {
    return make_error(ErrorCode::kInvalidInput, fmt::format("{}: compressed input ({}); decompress first", name, *compressed));
  }
  if (data.starts_with(kBom) && binary_size_matches(data.size() - kBom.size())) {
    warnings.push_back("skipped a UTF-8 byte-order mark before binary data");
    data.remove_prefix(kBom.size());
  }
  if (binary_size_matches(data.size())) return read_binary(data, name, options, std::move(warnings));
  const std::uint64_t declared = read_u32(data.data() + 80);
  if (declared > options.max_triangles) {
    return make_error(ErrorCode::kInvalidInput,
                      fmt::format("{}: header claims {} triangles, exceeds --max-triangles {}", name, declared, options.max_triangles));
  }
  return make_error(ErrorCode::kInvalidInput,
                    fmt::format("{}: truncated: expected {} bytes, got {}", name, kHeaderBytes + declared * kRecordBytes, data.size()));
}

}  // namespace polyaxis::io
