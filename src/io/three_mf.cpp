// 3MF reader: 3MF Core Specification 1.2 (3MF Consortium), read through lib3mf 1.8's C API, with
// three checks of our own in front of it, because lib3mf trusts its input more than we may:
//  1. The zip directory is checked with libzip against the decompression caps of
//     core/tolerances.h before anything is inflated (F15 zip bombs).
//  2. Each model part's XML is scanned once for <component> and <triangle> elements: a component
//     cycle is an error naming the objects on it; an index >= the object's vertex count is an error
//     naming the object and triangle (lib3mf would only say "Invalid model node index"); a triangle
//     with a repeated index, which lib3mf refuses as a whole-file error, is cut out of the XML
//     (re-zipped in memory) and reported as a warning, or is an error under options.strict. The
//     scan also refuses more triangle elements than options.max_triangles before lib3mf allocates.
//  3. Build items and components are walked with their 3x4 transforms composed, counting the
//     instanced triangles first (with a cycle and depth check), so options.max_triangles is
//     enforced before our own allocation.
// Every lib3mf handle is owned by a Lib3mfHandle, so each path releases it. lib3mf's C API catches
// its own exceptions; everything of ours is inside one try block.
#include "polyaxis/io/three_mf.h"

#include <fmt/format.h>
#include <zip.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <map>
#include <new>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpedantic"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#include <Model/COM/NMR_DLLInterfaces.h>
#pragma GCC diagnostic pop
#include "polyaxis/io/zip_archive.h"

namespace polyaxis::io {
namespace {

using core::ErrorCode;
using core::make_error;
using core::Vec3;

// A transform whose determinant is below this fraction of the product of its row lengths squashes
// space to (nearly) a plane: |det| / (|r0| |r1| |r2|) is 1 for a rotation and scale-free, so a
// uniform 0.001 scale is fine while a rank-deficient matrix with float noise is not.
constexpr double kSingularTransformRatio = 1e-9;
// Component nesting deeper than this is refused; real files nest two or three levels.
constexpr int kMaxComponentDepth = 64;
// Component instances (paths from an object to its meshes) allowed per object. lib3mf 1.8 walks
// every path while reading (about 50 ns each), so a 1.4 kB file of 40 objects that each use the
// previous one twice would keep it busy for hours; this bounds that walk to about 0.05 s.
constexpr std::uint64_t kMaxComponentInstances = 1'000'000;

constexpr std::string_view kCoreNamespace = "http://schemas.microsoft.com/3dmanufacturing/core/2015/02";

core::Error invalid(std::string message) { return make_error(ErrorCode::kInvalidInput, std::move(message)); }

// ---- zip level (libzip) ------------------------------------------------------------------------

struct ModelPart {
  zip_uint64_t index = 0;
  std::string path;
  std::string xml;
  bool modified = false;
};

bool ends_with_model(std::string_view path) {
  constexpr std::string_view kSuffix = ".model";
  if (path.size() < kSuffix.size()) return false;
  const std::string_view tail = path.substr(path.size() - kSuffix.size());
  return std::equal(tail.begin(), tail.end(), kSuffix.begin(),
                    [](char a, char b) { return std::tolower(static_cast<unsigned char>(a)) == b; });
}

// F15: the archive's directory checked against the caps (io::read_zip), then every *.model part
// read (whose sizes are now known to be bounded).
core::Result<std::vector<ModelPart>> check_and_read_zip(std::string_view data, const std::string& name) {
  auto entries = io::read_zip(data, name, "a 3MF file", ends_with_model);
  if (!entries) return entries.error();
  if (entries.value().empty()) return invalid(fmt::format("{}: no 3D model part (3D/3dmodel.model) in the archive", name));
  std::vector<ModelPart> parts;
  for (io::ZipEntry& e : entries.value()) parts.push_back(ModelPart{e.index, std::move(e.path), std::move(e.bytes), false});
  return parts;
}

// Returns a copy of DATA with the modified PARTS replaced.
core::Result<std::string> rezip(std::string_view data, const std::vector<ModelPart>& parts, const std::string& name) {
  std::vector<std::pair<std::string, std::string>> replaced;
  for (const ModelPart& part : parts) {
    if (part.modified) replaced.emplace_back(part.path, part.xml);
  }
  auto out = io::replace_zip_entries(data, replaced);
  if (!out) {
    return make_error(ErrorCode::kInternal, fmt::format("{}: cannot rewrite the archive without degenerate triangles ({})", name, out.error().message));
  }
  return out;
}

// ---- XML pre-scan ------------------------------------------------------------------------------

// One start tag: its byte range, qualified name and attributes (raw values, entities not decoded;
// only numbers and namespace URIs are read here).
struct Tag {
  std::size_t begin = 0;
  std::size_t end = 0;  // one past '>'
  bool closing = false;
  std::string_view name;
  std::vector<std::pair<std::string_view, std::string_view>> attributes;

  std::optional<std::string_view> attribute(std::string_view key) const {
    for (const auto& [k, v] : attributes) {
      if (k == key) return v;
    }
    return std::nullopt;
  }
};

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

// A minimal, non-validating tag scanner: lib3mf remains the parser; this only has to find the
// core-namespace object/vertex/triangle start tags the way lib3mf will see them, and to stop
// (returning false) on anything it does not understand.
class TagScanner {
 public:
  explicit TagScanner(std::string_view xml) : xml_(xml) {}

  // Next start or end tag; false at the end or on malformed markup.
  bool next(Tag& tag) {
    for (;;) {
      const std::size_t open = xml_.find('<', pos_);
      if (open == std::string_view::npos) return false;
      const std::string_view rest = xml_.substr(open);
      if (rest.starts_with("<!--")) {
        if (!skip_past(open, "-->")) return false;
        continue;
      }
      if (rest.starts_with("<![CDATA[")) {
        if (!skip_past(open, "]]>")) return false;
        continue;
      }
      if (rest.starts_with("<?")) {
        if (!skip_past(open, "?>")) return false;
        continue;
      }
      if (rest.starts_with("<!")) return false;  // DOCTYPE: not in 3MF; let lib3mf decide
      return parse_tag(open, tag);
    }
  }

 private:
  bool skip_past(std::size_t from, std::string_view terminator) {
    const std::size_t at = xml_.find(terminator, from);
    if (at == std::string_view::npos) return false;
    pos_ = at + terminator.size();
    return true;
  }

  bool parse_tag(std::size_t open, Tag& tag) {
    tag = Tag{};
    tag.begin = open;
    std::size_t p = open + 1;
    if (p < xml_.size() && xml_[p] == '/') {
      tag.closing = true;
      ++p;
    }
    const std::size_t name_begin = p;
    while (p < xml_.size() && !is_space(xml_[p]) && xml_[p] != '>' && xml_[p] != '/') ++p;
    tag.name = xml_.substr(name_begin, p - name_begin);
    if (tag.name.empty()) return false;
    for (;;) {
      while (p < xml_.size() && is_space(xml_[p])) ++p;
      if (p >= xml_.size()) return false;
      if (xml_[p] == '>') {
        tag.end = p + 1;
        break;
      }
      if (xml_[p] == '/') {
        if (p + 1 >= xml_.size() || xml_[p + 1] != '>') return false;
        tag.end = p + 2;
        break;
      }
      const std::size_t key_begin = p;
      while (p < xml_.size() && !is_space(xml_[p]) && xml_[p] != '=' && xml_[p] != '>' && xml_[p] != '/') ++p;
      const std::string_view key = xml_.substr(key_begin, p - key_begin);
      while (p < xml_.size() && is_space(xml_[p])) ++p;
      if (key.empty() || p >= xml_.size() || xml_[p] != '=') return false;
      ++p;
      while (p < xml_.size() && is_space(xml_[p])) ++p;
      if (p >= xml_.size() || (xml_[p] != '"' && xml_[p] != '\'')) return false;
      const char quote = xml_[p++];
      const std::size_t close = xml_.find(quote, p);
      if (close == std::string_view::npos) return false;
      tag.attributes.emplace_back(key, xml_.substr(p, close - p));
      p = close + 1;
    }
    pos_ = tag.end;
    return true;
  }

  std::string_view xml_;
  std::size_t pos_ = 0;
};

// A vertex coordinate (3MF ST_Number: an optional sign, digits, an optional fraction and
// exponent); none when TEXT is missing, empty, not a number or not finite. lib3mf reads "abc" and
// "" as 0 with a warning, which changes the part (a cube of 8000 mm³ came out 5333).
std::optional<double> parse_coordinate(std::optional<std::string_view> text) {
  if (!text) return std::nullopt;
  std::string_view s = *text;
  while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty() || !(std::isdigit(static_cast<unsigned char>(s.front())) || s.front() == '-' || s.front() == '.')) return std::nullopt;
  double value = 0.0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (ec != std::errc() || ptr != s.data() + s.size() || !std::isfinite(value)) return std::nullopt;
  return value;
}

std::optional<std::uint64_t> parse_index(std::optional<std::string_view> text) {
  if (!text) return std::nullopt;
  std::string_view s = *text;
  while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
  if (s.empty() || s.size() > 18) return std::nullopt;
  std::uint64_t value = 0;
  for (const char c : s) {
    if (c < '0' || c > '9') return std::nullopt;
    value = value * 10 + static_cast<std::uint64_t>(c - '0');
  }
  return value;
}

// Component graph of one model part: object id -> ids of the objects its components use.
using ComponentGraph = std::map<std::string, std::vector<std::string>, std::less<>>;

// A cycle in the component graph, as "a -> b -> a", if there is one. Iterative depth-first
// search, so a long chain cannot overflow the stack.
std::optional<std::string> find_cycle(const ComponentGraph& children) {
  enum class Mark { kNew, kOnPath, kDone };
  std::map<std::string_view, Mark> marks;
  for (const auto& [root, unused] : children) {
    if (marks[root] != Mark::kNew) continue;
    std::vector<std::pair<std::string_view, std::size_t>> path{{root, 0}};  // node, next child
    marks[root] = Mark::kOnPath;
    while (!path.empty()) {
      auto& [node, next] = path.back();
      const auto it = children.find(node);
      if (it == children.end() || next >= it->second.size()) {
        marks[node] = Mark::kDone;
        path.pop_back();
        continue;
      }
      const std::string_view child = it->second[next++];
      Mark& mark = marks[child];
      if (mark == Mark::kOnPath) {
        std::string text;
        auto from = std::find_if(path.begin(), path.end(), [&](const auto& e) { return e.first == child; });
        for (; from != path.end(); ++from) text += fmt::format("{} -> ", from->first);
        return text + std::string(child);
      }
      if (mark == Mark::kNew) {
        mark = Mark::kOnPath;
        path.emplace_back(child, 0);
      }
    }
  }
  return std::nullopt;
}

// Counts component instances below each object (memoised, so linear in the graph) and says why
// the graph is refused: nesting deeper than kMaxComponentDepth or more than
// kMaxComponentInstances instances. The graph must be acyclic (find_cycle first).
class ExpansionCheck {
 public:
  explicit ExpansionCheck(const ComponentGraph& children) : children_(children) {}

  // Checks every object, then the sum over the build items ITEMS (lib3mf walks each item's tree).
  std::optional<std::string> run(const std::vector<std::string>& items) {
    for (const auto& entry : children_) {
      visit(entry.first, 0);
      if (why_) return why_;
    }
    std::uint64_t total = 0;
    for (const std::string& item : items) {
      total += visit(item, 0);
      if (why_) return why_;
      if (total > kMaxComponentInstances) {
        return fmt::format("build items expand to more than {} component instances", kMaxComponentInstances);
      }
    }
    return why_;
  }

 private:
  std::uint64_t visit(std::string_view id, int depth) {
    if (why_) return 0;
    if (const auto it = instances_.find(id); it != instances_.end()) return it->second;
    if (depth > kMaxComponentDepth) {
      why_ = fmt::format("components nest deeper than {} levels (at object {})", kMaxComponentDepth, id);
      return 0;
    }
    std::uint64_t total = 1;
    if (const auto it = children_.find(id); it != children_.end()) {
      for (const std::string& child : it->second) {
        total += std::min(visit(child, depth + 1), kMaxComponentInstances + 1);
        if (why_) return 0;
        if (total > kMaxComponentInstances) {
          why_ = fmt::format("object {} expands to more than {} component instances", id, kMaxComponentInstances);
          return 0;
        }
      }
    }
    instances_.emplace(id, total);
    return total;
  }

  const ComponentGraph& children_;
  std::map<std::string_view, std::uint64_t> instances_;
  std::optional<std::string> why_;
};

struct ScanTotals {
  std::uint64_t triangle_elements = 0;
};

// Checks the triangles of one model part (see the file comment) and cuts degenerate ones out of
// PART.xml. Appends warnings; returns an Error for out-of-range indices, for degenerate triangles
// under STRICT, and when more than MAX_TRIANGLES triangle elements are present in all parts.
core::Status scan_model_part(ModelPart& part, const std::string& name, const ReadOptions& options, ScanTotals& totals,
                             std::vector<std::string>& warnings) {
  TagScanner scanner(part.xml);
  Tag tag;
  // The core namespace's prefix, from the root element's declarations ("" for the default one).
  std::optional<std::string> prefix;
  if (!scanner.next(tag) || tag.closing) return {};
  for (const auto& [key, value] : tag.attributes) {
    if (value != kCoreNamespace) continue;
    if (key == "xmlns") prefix = "";
    if (key.starts_with("xmlns:")) prefix = std::string(key.substr(6)) + ":";
  }
  if (!prefix) return {};  // not a core model part; lib3mf reports what is wrong with it
  const std::string object_name = *prefix + "object";
  const std::string vertex_name = *prefix + "vertex";
  const std::string triangle_name = *prefix + "triangle";
  const std::string component_name = *prefix + "component";
  const std::string item_name = *prefix + "item";

  std::string object_id = "?";
  std::uint64_t vertex_count = 0;
  std::uint64_t triangle_index = 0;
  std::uint64_t dropped_in_object = 0;
  std::string first_dropped;
  std::vector<std::pair<std::size_t, std::size_t>> cuts;
  ComponentGraph children;
  std::vector<std::string> items;  // object ids of the build items in this part

  const auto flush_object_warning = [&] {
    if (dropped_in_object == 0) return;
    warnings.push_back(fmt::format("{}: {}: object {}: dropped {} degenerate triangle{} (repeated vertex index; "
                                   "first: {})",
                                   name, part.path, object_id, dropped_in_object, dropped_in_object == 1 ? "" : "s",
                                   first_dropped));
    dropped_in_object = 0;
  };

  while (scanner.next(tag)) {
    if (tag.closing) continue;
    if (tag.name == object_name) {
      flush_object_warning();
      object_id = std::string(tag.attribute("id").value_or("?"));
      vertex_count = 0;
      triangle_index = 0;
    } else if (tag.name == component_name || tag.name == item_name) {
      // A reference into another part (production extension p:path) is outside this graph.
      const bool other_part = std::any_of(tag.attributes.begin(), tag.attributes.end(),
                                          [](const auto& kv) { return kv.first.ends_with(":path"); });
      if (const auto target = tag.attribute("objectid"); target && !other_part) {
        if (tag.name == item_name) {
          items.emplace_back(*target);
        } else {
          children[object_id].emplace_back(*target);
        }
      }
    } else if (tag.name == vertex_name) {
      for (const char* axis : {"x", "y", "z"}) {
        if (!parse_coordinate(tag.attribute(axis))) {
          return invalid(fmt::format("{}: {}: object {}, vertex {}: coordinate {}=\"{:.40}\" is not a finite number", name, part.path,
                                     object_id, vertex_count, axis, std::string(tag.attribute(axis).value_or("(missing)"))));
        }
      }
      ++vertex_count;
    } else if (tag.name == triangle_name) {
      if (++totals.triangle_elements > options.max_triangles) {
        return invalid(fmt::format("{}: more than {} triangles; exceeds --max-triangles", name, options.max_triangles));
      }
      const std::array<std::optional<std::uint64_t>, 3> v = {
          parse_index(tag.attribute("v1")), parse_index(tag.attribute("v2")), parse_index(tag.attribute("v3"))};
      if (v[0] && v[1] && v[2]) {
        for (int k = 0; k < 3; ++k) {
          if (*v[k] >= vertex_count) {
            return invalid(fmt::format("{}: {}: object {}, triangle {}: vertex index v{}={} >= vertex count {}", name,
                                       part.path, object_id, triangle_index, k + 1, *v[k], vertex_count));
          }
        }
        if (*v[0] == *v[1] || *v[0] == *v[2] || *v[1] == *v[2]) {
          if (options.strict) {
            return invalid(fmt::format("{}: {}: object {}, triangle {} is degenerate (vertices {} {} {}); refused "
                                       "under --strict",
                                       name, part.path, object_id, triangle_index, *v[0], *v[1], *v[2]));
          }
          if (dropped_in_object == 0) {
            first_dropped = fmt::format("triangle {}, vertices {} {} {}", triangle_index, *v[0], *v[1], *v[2]);
          }
          ++dropped_in_object;
          cuts.emplace_back(tag.begin, tag.end);
        }
      }
      ++triangle_index;
    }
  }
  flush_object_warning();
  if (auto cycle = find_cycle(children)) {
    return invalid(fmt::format("{}: {}: component cycle: object {}", name, part.path, *cycle));
  }
  if (auto why = ExpansionCheck(children).run(items)) return invalid(fmt::format("{}: {}: {}", name, part.path, *why));

  if (!cuts.empty()) {
    std::string kept;
    kept.reserve(part.xml.size());
    std::size_t from = 0;
    for (const auto& [begin, end] : cuts) {
      kept.append(part.xml, from, begin - from);
      from = end;
    }
    kept.append(part.xml, from, std::string::npos);
    part.xml = std::move(kept);
    part.modified = true;
  }
  return {};
}

// ---- lib3mf level ------------------------------------------------------------------------------

// Owns one lib3mf handle (every object lib3mf hands out is a new reference).
class Lib3mfHandle {
 public:
  Lib3mfHandle() = default;
  Lib3mfHandle(const Lib3mfHandle&) = delete;
  Lib3mfHandle& operator=(const Lib3mfHandle&) = delete;
  ~Lib3mfHandle() {
    if (handle_ != nullptr) NMR::lib3mf_release(handle_);
  }
  NMR::PLib3MFBase* get() const { return handle_; }
  // For an _Outptr_ argument; releases what was held before.
  NMR::PLib3MFBase** out() {
    if (handle_ != nullptr) NMR::lib3mf_release(handle_);
    handle_ = nullptr;
    return &handle_;
  }

 private:
  NMR::PLib3MFBase* handle_ = nullptr;
};

std::string last_error(NMR::PLib3MFBase* instance) {
  ::DWORD code = 0;
  ::LPCSTR message = nullptr;
  if (instance == nullptr || NMR::lib3mf_getlasterror(instance, &code, &message) != LIB3MF_OK) return "unknown error";
  return fmt::format("{} (lib3mf error 0x{:X})", message != nullptr ? message : "unknown error", code);
}

// A 3x4 affine transform: p' = L p + t, rows of L in m[r][0..2], t in m[r][3].
struct Affine {
  std::array<std::array<double, 4>, 3> m{{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}}};

  static Affine from(const NMR::MODELTRANSFORM& t) {
    Affine a;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 4; ++c) a.m[r][c] = static_cast<double>(t.m_fFields[r][c]);
    }
    return a;
  }
  Vec3 apply(Vec3 p) const {
    return {m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3],
            m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
            m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]};
  }
  // this ∘ inner: first INNER, then this.
  Affine compose(const Affine& inner) const {
    Affine out;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 4; ++c) {
        double s = c == 3 ? m[r][3] : 0.0;
        for (int k = 0; k < 3; ++k) s += m[r][k] * inner.m[k][c];
        out.m[r][c] = s;
      }
    }
    return out;
  }
  Affine scaled(double s) const {
    Affine out = *this;
    for (auto& row : out.m) {
      for (double& v : row) v *= s;
    }
    return out;
  }
  bool singular() const {
    for (const auto& row : m) {
      for (const double v : row) {
        if (!std::isfinite(v)) return true;
      }
    }
    const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                       m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                       m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    double rows = 1.0;
    for (const auto& row : m) rows *= std::sqrt(row[0] * row[0] + row[1] * row[1] + row[2] * row[2]);
    return !std::isfinite(det) || !(rows > 0.0) || !(std::fabs(det) > kSingularTransformRatio * rows);
  }
};

double unit_to_mm(::DWORD unit) {
  switch (unit) {
    case NMR::MODELUNIT_MICROMETER: return 0.001;
    case NMR::MODELUNIT_CENTIMETER: return 10.0;
    case NMR::MODELUNIT_INCH: return 25.4;
    case NMR::MODELUNIT_FOOT: return 304.8;
    case NMR::MODELUNIT_METER: return 1000.0;
    default: return 1.0;
  }
}

std::uint64_t saturating_add(std::uint64_t a, std::uint64_t b) {
  return a > std::numeric_limits<std::uint64_t>::max() - b ? std::numeric_limits<std::uint64_t>::max() : a + b;
}

// Walks objects by resource id: counts instanced triangles, then emits transformed geometry.
class ModelWalker {
 public:
  ModelWalker(NMR::PLib3MFModel* model, const std::string& name, ReadResult& out)
      : model_(model), name_(name), out_(out) {}

  // Triangles of object ID with all its components expanded (saturating). Detects cycles.
  core::Result<std::uint64_t> count(::DWORD id, int depth) {
    if (const auto it = counts_.find(id); it != counts_.end()) return it->second;
    if (depth > kMaxComponentDepth) {
      return invalid(fmt::format("{}: components nest deeper than {} levels at object {}", name_, kMaxComponentDepth, id));
    }
    if (!on_path_.insert(id).second) {
      return invalid(fmt::format("{}: component cycle: object {} contains itself", name_, id));
    }
    std::uint64_t total = 0;
    Lib3mfHandle mesh;
    Lib3mfHandle components;
    if (get_mesh(id, mesh)) {
      ::DWORD n = 0;
      if (NMR::lib3mf_meshobject_gettrianglecount(mesh.get(), &n) != LIB3MF_OK) return lib_error("triangle count", id);
      total = n;
    } else if (get_components(id, components)) {
      ::DWORD n = 0;
      if (NMR::lib3mf_componentsobject_getcomponentcount(components.get(), &n) != LIB3MF_OK) {
        return lib_error("component count", id);
      }
      for (::DWORD i = 0; i < n; ++i) {
        auto child = component(components.get(), id, i);
        if (!child) return child.error();
        auto child_count = count(child.value().first, depth + 1);
        if (!child_count) return child_count.error();
        total = saturating_add(total, child_count.value());
      }
    } else {
      return invalid(fmt::format("{}: object {} is neither a mesh nor a components object", name_, id));
    }
    on_path_.erase(id);
    counts_[id] = total;
    return total;
  }

  // Appends object ID's geometry under TRANSFORM (object space -> millimetres in build space).
  core::Status emit(::DWORD id, const Affine& transform, int depth) {
    if (depth > kMaxComponentDepth) return invalid(fmt::format("{}: components nest too deep at object {}", name_, id));
    Lib3mfHandle mesh;
    Lib3mfHandle components;
    if (get_mesh(id, mesh)) return emit_mesh(mesh.get(), id, transform);
    if (!get_components(id, components)) {
      return invalid(fmt::format("{}: object {} is neither a mesh nor a components object", name_, id));
    }
    ::DWORD n = 0;
    if (NMR::lib3mf_componentsobject_getcomponentcount(components.get(), &n) != LIB3MF_OK) {
      return lib_error("component count", id);
    }
    for (::DWORD i = 0; i < n; ++i) {
      auto child = component(components.get(), id, i);
      if (!child) return child.error();
      if (const core::Status s = emit(child.value().first, transform.compose(child.value().second), depth + 1); !s) {
        return s;
      }
    }
    return {};
  }

 private:
  // lib3mf quirk: the *byid getters return success with a null handle when ID is an object of the
  // other kind, so the handle itself must be checked.
  bool get_mesh(::DWORD id, Lib3mfHandle& mesh) const {
    return NMR::lib3mf_model_getmeshobjectbyid(model_, id, mesh.out()) == LIB3MF_OK && mesh.get() != nullptr;
  }
  bool get_components(::DWORD id, Lib3mfHandle& components) const {
    return NMR::lib3mf_model_getcomponentsobjectbyid(model_, id, components.out()) == LIB3MF_OK &&
           components.get() != nullptr;
  }

  core::Error lib_error(const char* what, ::DWORD id) const {
    return invalid(fmt::format("{}: object {}: cannot read its {} ({})", name_, id, what, last_error(model_)));
  }

  // Component I of components object ID: the referenced object id and its transform.
  core::Result<std::pair<::DWORD, Affine>> component(NMR::PLib3MFModelComponentsObject* components, ::DWORD id,
                                                        ::DWORD i) {
    Lib3mfHandle handle;
    ::DWORD child = 0;
    NMR::MODELTRANSFORM t{};
    if (NMR::lib3mf_componentsobject_getcomponent(components, i, handle.out()) != LIB3MF_OK ||
        NMR::lib3mf_component_getobjectresourceid(handle.get(), &child) != LIB3MF_OK ||
        NMR::lib3mf_component_gettransform(handle.get(), &t) != LIB3MF_OK) {
      return invalid(fmt::format("{}: object {}: cannot read component {} ({})", name_, id, i, last_error(components)));
    }
    const Affine a = Affine::from(t);
    if (a.singular()) {
      return invalid(fmt::format("{}: object {}, component {} (object {}): singular transform", name_, id, i, child));
    }
    return std::pair{child, a};
  }

  core::Status emit_mesh(NMR::PLib3MFModelMeshObject* mesh, ::DWORD id, const Affine& transform) {
    ::DWORD vertex_count = 0;
    ::DWORD triangle_count = 0;
    if (NMR::lib3mf_meshobject_getvertexcount(mesh, &vertex_count) != LIB3MF_OK ||
        NMR::lib3mf_meshobject_gettrianglecount(mesh, &triangle_count) != LIB3MF_OK) {
      return lib_error("counts", id);
    }
    if (triangle_count == 0) return {};
    std::vector<NMR::MODELMESHVERTEX> vertices(vertex_count);
    std::vector<NMR::MODELMESHTRIANGLE> triangles(triangle_count);
    ::DWORD got = 0;
    if (vertex_count > 0 &&
        (NMR::lib3mf_meshobject_getvertices(mesh, vertices.data(), vertex_count, &got) != LIB3MF_OK ||
         got != vertex_count)) {
      return lib_error("vertices", id);
    }
    if (NMR::lib3mf_meshobject_gettriangleindices(mesh, triangles.data(), triangle_count, &got) != LIB3MF_OK ||
        got != triangle_count) {
      return lib_error("triangles", id);
    }
    // Only referenced vertices are emitted, so points stay bounded by 3 x triangles.
    constexpr std::uint32_t kUnused = std::numeric_limits<std::uint32_t>::max();
    std::vector<std::uint32_t> remap(vertex_count, kUnused);
    for (::DWORD t = 0; t < triangle_count; ++t) {
      Triangle out{};
      for (int k = 0; k < 3; ++k) {
        const ::DWORD v = triangles[t].m_nIndices[k];
        if (v >= vertex_count) {
          return invalid(fmt::format("{}: object {}, triangle {}: vertex index {} >= vertex count {}", name_, id, t, v,
                                     vertex_count));
        }
        if (remap[v] == kUnused) {
          if (out_.mesh.points.size() >= kUnused) {
            return invalid(fmt::format("{}: more than 2^32-1 vertices after expanding components", name_));
          }
          const auto& f = vertices[v].m_fPosition;
          const Vec3 p = transform.apply({static_cast<double>(f[0]), static_cast<double>(f[1]),
                                          static_cast<double>(f[2])});
          if (!core::is_finite(p)) {
            return invalid(fmt::format("{}: object {}, vertex {}: non-finite coordinate after transform", name_, id, v));
          }
          remap[v] = static_cast<std::uint32_t>(out_.mesh.points.size());
          out_.mesh.points.push_back(p);
        }
        out[static_cast<std::size_t>(k)] = remap[v];
      }
      if (out[0] == out[1] || out[0] == out[2] || out[1] == out[2]) continue;  // lib3mf refuses these already
      out_.mesh.triangles.push_back(out);
    }
    return {};
  }

  NMR::PLib3MFModel* model_;
  const std::string& name_;
  ReadResult& out_;
  std::map<::DWORD, std::uint64_t> counts_;
  std::set<::DWORD> on_path_;
};

struct BuildItem {
  ::DWORD object_id = 0;
  Affine transform;
};

core::Result<ReadResult> read_3mf_unguarded(std::string_view data, const std::string& name,
                                            const ReadOptions& options) {
  ReadResult result;
  result.format = Format::k3mf;

  auto parts_or = check_and_read_zip(data, name);
  if (!parts_or) return parts_or.error();
  std::vector<ModelPart>& parts = parts_or.value();
  ScanTotals totals;
  bool modified = false;
  for (ModelPart& part : parts) {
    if (const core::Status s = scan_model_part(part, name, options, totals, result.warnings); !s) return s.error();
    modified = modified || part.modified;
  }
  std::string rewritten;
  if (modified) {
    auto rezipped = rezip(data, parts, name);
    if (!rezipped) return rezipped.error();
    rewritten = std::move(rezipped.value());
    data = rewritten;
  }
  parts.clear();

  Lib3mfHandle model;
  if (NMR::lib3mf_createmodel(model.out()) != LIB3MF_OK || model.get() == nullptr) {
    return make_error(ErrorCode::kInternal, fmt::format("{}: lib3mf cannot create a model", name));
  }
  Lib3mfHandle reader;
  if (NMR::lib3mf_model_queryreader(model.get(), "3mf", reader.out()) != LIB3MF_OK || reader.get() == nullptr) {
    return make_error(ErrorCode::kInternal, fmt::format("{}: lib3mf has no 3MF reader", name));
  }
  // lib3mf takes a non-const pointer but only reads the buffer.
  auto* bytes = reinterpret_cast<::BYTE*>(const_cast<char*>(data.data()));
  if (NMR::lib3mf_reader_readfrombuffer(reader.get(), bytes, data.size()) != LIB3MF_OK) {
    return invalid(fmt::format("{}: not a valid 3MF model: {}", name, last_error(reader.get())));
  }
  ::DWORD warning_count = 0;
  if (NMR::lib3mf_reader_getwarningcount(reader.get(), &warning_count) == LIB3MF_OK) {
    for (::DWORD i = 0; i < std::min<::DWORD>(warning_count, 100); ++i) {
      std::array<char, 512> text{};
      ::DWORD code = 0;
      ::ULONG needed = 0;
      if (NMR::lib3mf_reader_getwarningutf8(reader.get(), i, &code, text.data(), static_cast<::ULONG>(text.size()), &needed) == LIB3MF_OK) {
        text.back() = '\0';
        result.warnings.push_back(fmt::format("{}: lib3mf: {} (0x{:X})", name, text.data(), code));
      }
    }
  }

  ::DWORD unit = NMR::MODELUNIT_MILLIMETER;
  NMR::lib3mf_model_getunit(model.get(), &unit);
  const double mm_per_unit = unit_to_mm(unit);

  std::vector<BuildItem> items;
  {
    Lib3mfHandle iterator;
    if (NMR::lib3mf_model_getbuilditems(model.get(), iterator.out()) != LIB3MF_OK) {
      return invalid(fmt::format("{}: cannot list build items ({})", name, last_error(model.get())));
    }
    ::BOOL has_next = 0;
    while (NMR::lib3mf_builditemiterator_movenext(iterator.get(), &has_next) == LIB3MF_OK && has_next) {
      Lib3mfHandle item;
      BuildItem build;
      NMR::MODELTRANSFORM t{};
      if (NMR::lib3mf_builditemiterator_getcurrent(iterator.get(), item.out()) != LIB3MF_OK ||
          NMR::lib3mf_builditem_getobjectresourceid(item.get(), &build.object_id) != LIB3MF_OK ||
          NMR::lib3mf_builditem_getobjecttransform(item.get(), &t) != LIB3MF_OK) {
        return invalid(fmt::format("{}: cannot read build item {} ({})", name, items.size(), last_error(model.get())));
      }
      build.transform = Affine::from(t);
      if (build.transform.singular()) {
        return invalid(fmt::format("{}: build item {} (object {}): singular transform", name, items.size(),
                                   build.object_id));
      }
      items.push_back(build);
    }
  }
  if (items.empty()) return invalid(fmt::format("{}: no build item; nothing to make", name));

  ModelWalker walker(model.get(), name, result);
  std::uint64_t total = 0;
  for (const BuildItem& item : items) {
    auto n = walker.count(item.object_id, 0);
    if (!n) return n.error();
    total = saturating_add(total, n.value());
  }
  if (total > options.max_triangles) {
    return invalid(fmt::format("{}: {} triangles after expanding build items and components; exceeds --max-triangles {}",
                               name, total, options.max_triangles));
  }
  if (total == 0) return invalid(fmt::format("{}: no geometry (build items hold no triangle)", name));
  result.mesh.triangles.reserve(static_cast<std::size_t>(total));

  // Build space is in the model's unit; scaling last turns it into millimetres.
  const Affine to_mm = Affine{}.scaled(mm_per_unit);
  for (const BuildItem& item : items) {
    if (const core::Status s = walker.emit(item.object_id, to_mm.compose(item.transform), 0); !s) return s.error();
  }
  if (result.mesh.triangles.empty()) return invalid(fmt::format("{}: no geometry", name));
  return result;
}

}  // namespace

core::Result<ReadResult> read_3mf(std::string_view data, const std::string& name, const ReadOptions& options) {
  try {
    return read_3mf_unguarded(data, name, options);
  } catch (const std::bad_alloc&) {
    return invalid(fmt::format("{}: out of memory while reading the 3MF model", name));
  } catch (const std::exception& e) {
    return invalid(fmt::format("{}: 3MF reader failed: {}", name, e.what()));
  } catch (...) {
    return invalid(fmt::format("{}: 3MF reader failed with an unknown exception", name));
  }
}

}  // namespace polyaxis::io
