#include "polyaxis/post/toolpath_3mf.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "polyaxis/io/zip_archive.h"
#include "polyaxis/machine/kinematics.h"
#include "polyaxis/mesh/mesh.h"
#include "post/toolpath_3mf_frame.h"
#include "post/tool_space.h"

namespace polyaxis::post {
namespace {

using core::ErrorCode;
using core::make_error;
using core::Vec3;
using machine::MachinePose;
using detail::Quaternion;

constexpr std::string_view kModelPath = "3D/3dmodel.model";
constexpr std::string_view kSetPlaceholder = "0000000000000000";  // with_set_id writes the set id here

// A pose as written: the tip in device units (0.1 µm) and the frame.
struct Pose {
  std::array<std::int32_t, 3> tip{};
  Quaternion q;
};
struct Travel {
  Pose pose;
  double speed_mm_s = 0.0;  // 0: at the machine's rapid rates (the first move, turns in place)
};
struct Segment {
  std::vector<Travel> jump;    // polyaxis's route to the segment's first pose (pa:jump)
  std::vector<Pose> poses;     // the bead run, from where the process switched on
  std::vector<double> feeds;   // the tip's feed on the move ending at each pose (feeds[0] unused)
};
struct Layer {
  std::uint32_t layer = 0, region = 0;
  std::vector<Segment> segments;
  std::vector<Travel> trailing;  // travel after the last segment (the end of the program)
};

// FNV-1a, 64 bits.
std::uint64_t fnv(std::uint64_t h, std::string_view s) {
  for (const char c : s) h = (h ^ static_cast<unsigned char>(c)) * 1099511628211ull;
  return h;
}

// A name-based UUID (RFC 9562 version 8: our own hash) from the program's hash and a role, so
// the same program gives the same package.
std::string uuid_of(std::uint64_t content, std::string_view role) {
  const std::uint64_t a = fnv(content ^ 0x9e3779b97f4a7c15ull, role), b = fnv(a ^ 0xc2b2ae3d27d4eb4full, role);
  const std::uint64_t hi = (a & 0xffffffffffff0fffull) | 0x8000ull, lo = (b & 0x3fffffffffffffffull) | 0x8000000000000000ull;
  return fmt::format("{:08x}-{:04x}-{:04x}-{:04x}-{:012x}", hi >> 32, (hi >> 16) & 0xffff, hi & 0xffff, lo >> 48, lo & 0xffffffffffffull);
}

// Text for an XML attribute or element.
std::string xml_text(std::string_view s) {
  std::string out;
  for (const char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += static_cast<unsigned char>(c) < 0x20 || c == 0x7f ? '?' : c;
    }
  }
  return out;
}

class Toolpath3mf final : public detail::ToolSpaceDialect {
 public:
  Toolpath3mf(const machine::MachineConfig& m, const process::ProcessConfig& p, const GcodeOptions& o) : m_(m), p_(p), o_(o) {}

  core::Result<MachinePose> pose_of(const ProgramPoint& pt, const MachinePose* previous) override {
    // The inverse kinematics of the pose as the package holds it: the tip to 0.1 µm, as the
    // tool-space loop measures it (detail::written_tip), so feeds and read-back agree.
    auto tip = device_tip(pt.tip_part_mm);
    if (!tip) return tip.error();
    return machine::inverse(m_, tip_mm(tip.value()), detail::written_vector(pt.tool_axis_part), previous);
  }

  void header() override {}

  void comment(const ProgramPoint& pt) override {
    if (!layers_.empty() && layers_.back().layer == pt.layer && layers_.back().region == pt.region) return;
    close_segment();
    layers_.push_back(Layer{pt.layer, pt.region, {}, {}});
  }

  core::Status block(detail::BlockKind kind, const ProgramPoint& pt, const MachinePose&, double feed_mm_s, const ProgramPoint*) override {
    auto tip = device_tip(pt.tip_part_mm);
    if (!tip) return tip.error();
    frame_ = kind == detail::BlockKind::kFirst ? detail::frame_from_z(detail::written_vector(pt.tool_axis_part))
                                               : detail::carry_frame(frame_, detail::written_vector(pt.tool_axis_part));
    const Pose pose{tip.value(), frame_};
    for (const std::int32_t v : pose.tip) hash_ = fnv(hash_, std::string_view(reinterpret_cast<const char*>(&v), sizeof v));
    ++poses_;
    if (kind == detail::BlockKind::kFeed && on_) {
      if (layers_.empty()) layers_.push_back(Layer{pt.layer, pt.region, {}, {}});
      if (!open_) {
        Segment s;
        s.jump = std::move(jump_);
        jump_.clear();
        s.poses = {current_};
        s.feeds = {0.0};
        layers_.back().segments.push_back(std::move(s));
        open_ = true;
      }
      Segment& s = layers_.back().segments.back();
      s.poses.push_back(pose);
      s.feeds.push_back(feed_mm_s);
      if (o_.stats != nullptr) ++o_.stats->feed_blocks;
    } else {
      jump_.push_back(Travel{pose, kind == detail::BlockKind::kFeed ? feed_mm_s : 0.0});
    }
    current_ = pose;
    return {};
  }

  void switch_process(bool on) override {
    if (!on) close_segment();
    on_ = on;
  }

  void footer(std::uint64_t) override {
    close_segment();
    if (layers_.empty()) layers_.push_back(Layer{});
    layers_.back().trailing = std::move(jump_);
  }

  // About what the package's XML holds so far (for max_output_bytes, which the zip only lowers).
  std::size_t size() const override { return poses_ * 110; }

  core::Result<std::string> package() const;

 private:
  void close_segment() {
    if (open_ && layers_.back().segments.back().poses.size() < 2) layers_.back().segments.pop_back();
    open_ = false;
  }

  core::Result<std::array<std::int32_t, 3>> device_tip(Vec3 p) const {
    std::array<std::int32_t, 3> out{};
    const double c[3] = {p.x, p.y, p.z};
    for (int k = 0; k < 3; ++k) {
      const double v = std::round(c[k] * 1e4);  // as detail::written_tip rounds: 1e4 units of kToolpathUnitMm a mm
      if (!(std::abs(v) <= static_cast<double>(std::numeric_limits<std::int32_t>::max()))) {
        return make_error(ErrorCode::kInfeasible, fmt::format("the tip ({:.4f}, {:.4f}, {:.4f}) mm is beyond the ±214 m that the 3MF toolpath's "
                                                              "32-bit coordinates hold at 0.1 µm",
                                                              p.x, p.y, p.z));
      }
      out[static_cast<std::size_t>(k)] = static_cast<std::int32_t>(v);
    }
    return out;
  }
  static Vec3 tip_mm(const std::array<std::int32_t, 3>& t) {
    return Vec3{t[0] * kToolpathUnitMm, t[1] * kToolpathUnitMm, t[2] * kToolpathUnitMm};
  }

  std::string model_xml(std::string_view profile_xml) const;
  std::string layer_xml(const Layer& layer, double fmin, double fmax) const;

  const machine::MachineConfig& m_;
  const process::ProcessConfig& p_;
  const GcodeOptions& o_;
  std::vector<Layer> layers_;
  std::vector<Travel> jump_;
  Pose current_;
  Quaternion frame_;
  bool on_ = false, open_ = false;
  std::uint64_t hash_ = 1469598103934665603ull, poses_ = 0;
};

void append_pose(std::string& out, const Pose& p) {
  fmt::format_to(std::back_inserter(out), "x=\"{}\" y=\"{}\" z=\"{}\" i=\"{:.9f}\" j=\"{:.9f}\" k=\"{:.9f}\" w=\"{:.9f}\"", p.tip[0], p.tip[1], p.tip[2],
                 p.q.i, p.q.j, p.q.k, p.q.w);
}

void append_jump(std::string& out, std::size_t before, const std::vector<Travel>& jump) {
  if (jump.empty()) return;
  fmt::format_to(std::back_inserter(out), "<pa:jump segment=\"{}\">", before);
  for (const Travel& t : jump) {
    out += "<pa:pose ";
    append_pose(out, t.pose);
    if (t.speed_mm_s > 0.0) fmt::format_to(std::back_inserter(out), " speed=\"{:.6f}\"", t.speed_mm_s);
    out += "/>";
  }
  out += "</pa:jump>\n";
}

std::string Toolpath3mf::layer_xml(const Layer& layer, double fmin, double fmax) const {
  std::string out = fmt::format("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<layer xmlns=\"{}\" xmlns:pa=\"{}\">\n", kToolpathNamespace,
                                kPolyaxisNamespace);
  fmt::format_to(std::back_inserter(out), "<parts><part id=\"1\" uuid=\"{}\"/></parts>\n<profiles><profile id=\"1\" uuid=\"{}\"/></profiles>\n",
                 uuid_of(hash_, "item"), uuid_of(hash_, "profile deposit"));
  fmt::format_to(std::back_inserter(out), "<data>\n<pa:layer index=\"{}\" region=\"{}\"/>\n", layer.layer, layer.region);
  for (std::size_t s = 0; s < layer.segments.size(); ++s) append_jump(out, s, layer.segments[s].jump);
  append_jump(out, layer.segments.size(), layer.trailing);
  out += "</data>\n<segments>\n";
  for (const Segment& s : layer.segments) {
    out += "<segment type=\"polyline6d\" profileid=\"1\" partid=\"1\">\n";
    for (std::size_t k = 0; k < s.poses.size(); ++k) {
      out += "<point6d ";
      append_pose(out, s.poses[k]);
      if (k > 0 && fmax > fmin && s.feeds[k] < fmax) fmt::format_to(std::back_inserter(out), " f=\"{:.9f}\"", (s.feeds[k] - fmin) / (fmax - fmin));
      out += "/>\n";
    }
    out += "</segment>\n";
  }
  out += "</segments>\n</layer>\n";
  return out;
}

std::string Toolpath3mf::model_xml(std::string_view profile_xml) const {
  std::string out = fmt::format(
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      "<model unit=\"millimeter\" xml:lang=\"en-US\" xmlns=\"http://schemas.microsoft.com/3dmanufacturing/core/2015/02\" "
      "xmlns:p=\"http://schemas.microsoft.com/3dmanufacturing/production/2015/06\" xmlns:tp=\"{}\" xmlns:pa=\"{}\" requiredextensions=\"p tp\">\n"
      "<metadata name=\"Application\">polyaxis</metadata>\n<metadata name=\"pa:machine\">{}</metadata>\n"
      "<metadata name=\"pa:process\">{}</metadata>\n<metadata name=\"pa:set\">{}</metadata>\n<resources>\n"
      "<tp:toolpathresource id=\"1\" uuid=\"{}\" unitfactor=\"{}\" toolpathtype=\"6axis\">\n{}<tp:toolpathlayers>\n",
      kToolpathNamespace, kPolyaxisNamespace, xml_text(m_.name), xml_text(p_.name), kSetPlaceholder, uuid_of(hash_, "toolpath"), fmt::format("{:.10g}", kToolpathUnitMm),
      profile_xml);
  for (std::size_t k = 0; k < layers_.size(); ++k) {
    fmt::format_to(std::back_inserter(out), "<tp:toolpathlayer path=\"/Toolpath/Layers/layer{:05d}.xml\"/>\n", k + 1);
  }
  fmt::format_to(std::back_inserter(out), "</tp:toolpathlayers>\n</tp:toolpathresource>\n<object id=\"2\" type=\"model\" p:UUID=\"{}\">\n<mesh>\n<vertices>\n",
                 uuid_of(hash_, "object"));
  for (const Vec3& v : o_.part->vertices) fmt::format_to(std::back_inserter(out), "<vertex x=\"{}\" y=\"{}\" z=\"{}\"/>\n", v.x, v.y, v.z);
  out += "</vertices>\n<triangles>\n";
  for (const auto& t : o_.part->triangles) fmt::format_to(std::back_inserter(out), "<triangle v1=\"{}\" v2=\"{}\" v3=\"{}\"/>\n", t[0], t[1], t[2]);
  fmt::format_to(std::back_inserter(out),
                 "</triangles>\n</mesh>\n</object>\n</resources>\n<build p:UUID=\"{}\" tp:toolpathid=\"1\">\n"
                 "<item objectid=\"2\" p:UUID=\"{}\"/>\n</build>\n</model>\n",
                 uuid_of(hash_, "build"), uuid_of(hash_, "item"));
  return out;
}

core::Result<std::string> Toolpath3mf::package() const {
  double fmin = INFINITY, fmax = 0.0;
  for (const Layer& l : layers_) {
    for (const Segment& s : l.segments) {
      for (std::size_t k = 1; k < s.feeds.size(); ++k) fmin = std::min(fmin, s.feeds[k]), fmax = std::max(fmax, s.feeds[k]);
    }
  }
  if (!(fmax > 0.0)) fmin = fmax = p_.deposit_feed_mm_s;  // nothing deposited: the process's feed
  std::string profile = fmt::format(
      "<tp:toolpathprofiles>\n<tp:toolpathprofile uuid=\"{}\" name=\"deposit\" depositionspeed=\"{:.6f}\" beadwidth=\"{}\" beadheight=\"{}\"",
      uuid_of(hash_, "profile deposit"), fmax, p_.bead_width_mm, p_.layer_mm);
  if (p_.dwell_on_s > 0.0) profile += fmt::format(" prewaittime=\"{:.0f}\"", p_.dwell_on_s * 1e6);
  profile += ">";
  if (fmax > fmin) {
    profile += fmt::format("<tp:modifier attribute=\"depositionspeed\" type=\"constant\" factor=\"f\" minvalue=\"{:.6f}\" maxvalue=\"{:.6f}\"/>", fmin, fmax);
  }
  profile += "</tp:toolpathprofile>\n</tp:toolpathprofiles>\n";
  std::vector<std::pair<std::string, std::string>> entries;
  entries.emplace_back("[Content_Types].xml",
                       "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<Types xmlns=\"http://schemas.openxmlformats.org/package/2006/content-types\">"
                       "<Default Extension=\"rels\" ContentType=\"application/vnd.openxmlformats-package.relationships+xml\"/>"
                       "<Default Extension=\"model\" ContentType=\"application/vnd.ms-package.3dmanufacturing-3dmodel+xml\"/>"
                       "<Default Extension=\"xml\" ContentType=\"application/xml\"/></Types>\n");
  entries.emplace_back("_rels/.rels",
                       "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<Relationships xmlns=\"http://schemas.openxmlformats.org/package/2006/relationships\">"
                       "<Relationship Target=\"/3D/3dmodel.model\" Id=\"rel0\" Type=\"http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel\"/>"
                       "</Relationships>\n");
  entries.emplace_back(std::string(kModelPath), model_xml(profile));
  std::string rels = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<Relationships xmlns=\"http://schemas.openxmlformats.org/package/2006/relationships\">\n";
  for (std::size_t k = 0; k < layers_.size(); ++k) {
    fmt::format_to(std::back_inserter(rels), "<Relationship Target=\"/Toolpath/Layers/layer{:05d}.xml\" Id=\"layer{}\" Type=\"{}\"/>\n", k + 1, k + 1,
                   kToolpathLayerRelationship);
  }
  rels += "</Relationships>\n";
  entries.emplace_back("3D/_rels/3dmodel.model.rels", std::move(rels));
  for (std::size_t k = 0; k < layers_.size(); ++k) {
    entries.emplace_back(fmt::format("Toolpath/Layers/layer{:05d}.xml", k + 1), layer_xml(layers_[k], fmin, fmax));
  }
  return io::write_zip(entries);
}

}  // namespace

core::Result<std::string> write_toolpath_3mf(const machine::MachineConfig& machine, const process::ProcessConfig& process,
                                             std::span<const ProgramPoint> points, const GcodeOptions& options) {
  if (points.empty()) return make_error(ErrorCode::kInfeasible, "no program points to write");
  if (options.part == nullptr) return make_error(ErrorCode::kUsage, "the 3MF toolpath carries the part: give the part's mesh (GcodeOptions::part)");
  Toolpath3mf w(machine, process, options);
  if (auto st = detail::write_tool_space(machine, points, options, w); !st) return st.error();
  auto package = w.package();
  if (package && options.max_output_bytes != 0 && package.value().size() > options.max_output_bytes) {
    return make_error(ErrorCode::kOutput, fmt::format("the program exceeds {} bytes", options.max_output_bytes));
  }
  return package;
}

core::Result<std::string> stamp_toolpath_3mf(std::string_view package, std::string_view id) {
  auto entries = io::read_zip(package, "the 3MF toolpath", "a 3MF package", [](std::string_view p) { return p == kModelPath; });
  if (!entries) return entries.error();
  const std::string placeholder = fmt::format("<metadata name=\"pa:set\">{}</metadata>", kSetPlaceholder);
  std::string model = entries.value().empty() ? std::string() : std::move(entries.value().front().bytes);
  const std::size_t at = model.find(placeholder);
  if (at == std::string::npos) return make_error(ErrorCode::kInternal, "the 3MF toolpath's model has no set id to fill");
  model.replace(at, placeholder.size(), fmt::format("<metadata name=\"pa:set\">{}</metadata>", xml_text(id)));
  return io::replace_zip_entry(package, std::string(kModelPath), model);
}

}  // namespace polyaxis::post
