// Reading a 3MF toolpath package (post 3mf-toolpath; post/toolpath_3mf.h) move by move for the
// simulator, the build verifier and the playback, as a consumer of the Toolpath Extension runs it:
// the layers in the toolpath resource's order, each layer's segments in document order, the tip
// straight and the tool axis (the frame's local z) along the great circle between points, the
// process on along a segment and off between segments, the profile's prewaittime after switching
// on. Between segments the route in the layer's <pa:jump> elements is taken where polyaxis wrote
// one; otherwise the machine moves straight at its rapid rates (the spec leaves jumps to the
// consumer). "Line" numbers are the package's poses, counted from 1 in reading order.
#include <fmt/format.h>
#include <libxml/parser.h>
#include <libxml/tree.h>

#include <algorithm>
#include <charconv>
#include <climits>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "gcode_walk.h"
#include "polyaxis/io/zip_archive.h"
#include "polyaxis/post/toolpath_3mf.h"
#include "post/toolpath_3mf_frame.h"

namespace polyaxis::verify::detail {
namespace {

using core::ErrorCode;
using core::make_error;
using core::Vec3;
using machine::MachinePose;

constexpr std::string_view kDeprecatedToolpathNamespace = "http://schemas.microsoft.com/3dmanufacturing/toolpath/2019/05";
constexpr std::string_view kDeprecatedLayerRelationship = "http://schemas.microsoft.com/3dmanufacturing/2019/05/toolpath";
constexpr std::string_view kModelRelationship = "http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel";
constexpr std::string_view kCoreNamespace = "http://schemas.microsoft.com/3dmanufacturing/core/2015/02";
// A quaternion whose squared norm is below this cannot be normalised (the spec: reject the point).
constexpr double kMinQuaternionNorm2 = 1e-12;

core::Error invalid(std::string message) { return make_error(ErrorCode::kInvalidInput, "3MF toolpath: " + std::move(message)); }

struct DocFree {
  void operator()(xmlDoc* d) const { xmlFreeDoc(d); }
};
using Doc = std::unique_ptr<xmlDoc, DocFree>;

// PART's XML, parsed without the network, entity substitution or DTD loading.
core::Result<Doc> parse(const std::string& part, std::string_view path) {
  static std::once_flag init;
  std::call_once(init, [] { xmlInitParser(); });
  if (part.size() > static_cast<std::size_t>(INT_MAX)) return invalid(fmt::format("part '{}' is too large to parse", path));
  Doc doc(xmlReadMemory(part.data(), static_cast<int>(part.size()), nullptr, nullptr, XML_PARSE_NONET | XML_PARSE_NOERROR | XML_PARSE_NOWARNING));
  if (doc == nullptr || xmlDocGetRootElement(doc.get()) == nullptr) {
    const xmlError* e = xmlGetLastError();
    std::string why = e != nullptr && e->message != nullptr ? e->message : "not XML";
    while (!why.empty() && (why.back() == '\n' || why.back() == ' ')) why.pop_back();
    return invalid(fmt::format("part '{}' is not well-formed XML (line {}: {})", path, e != nullptr ? e->line : 0, why));
  }
  return doc;
}

std::string_view name_of(const xmlNode* n) { return reinterpret_cast<const char*>(n->name); }
std::string_view ns_of(const xmlNode* n) { return n->ns != nullptr && n->ns->href != nullptr ? reinterpret_cast<const char*>(n->ns->href) : ""; }
bool is(const xmlNode* n, std::string_view ns, std::string_view name) {
  return n->type == XML_ELEMENT_NODE && name_of(n) == name &&
         (ns_of(n) == ns || (ns == post::kToolpathNamespace && ns_of(n) == kDeprecatedToolpathNamespace));
}
bool is_toolpath(const xmlNode* n, std::string_view name) { return is(n, post::kToolpathNamespace, name); }

// The attribute NAME without a namespace (or in none), as written; nullopt when absent.
std::optional<std::string_view> attr(const xmlNode* n, std::string_view name) {
  for (const xmlAttr* a = n->properties; a != nullptr; a = a->next) {
    if (a->ns != nullptr || reinterpret_cast<const char*>(a->name) != name) continue;
    if (a->children == nullptr || a->children->content == nullptr) return std::string_view();
    return std::string_view(reinterpret_cast<const char*>(a->children->content));
  }
  return std::nullopt;
}

template <class T>
bool number(std::string_view s, T& out) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '+')) s.remove_prefix(1);
  while (!s.empty() && s.back() == ' ') s.remove_suffix(1);
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  if constexpr (std::is_floating_point_v<T>) {
    if (!std::isfinite(out)) return false;
  }
  return ec == std::errc() && ptr == s.data() + s.size() && !s.empty();
}

std::vector<const xmlNode*> children(const xmlNode* n) {
  std::vector<const xmlNode*> out;
  for (const xmlNode* c = n->children; c != nullptr; c = c->next) {
    if (c->type == XML_ELEMENT_NODE) out.push_back(c);
  }
  return out;
}

std::string part_name(std::string_view target) {
  while (!target.empty() && target.front() == '/') target.remove_prefix(1);
  return std::string(target);
}

struct Profile {
  double speed_mm_s = 0.0;  // depositionspeed; 0 when absent
  double prewait_s = 0.0;
  bool modulated = false;   // a constant depositionspeed modifier on factor f
  double fmin = 0.0, fmax = 0.0;
};

struct PoseIn {
  Vec3 tip, axis;
  std::optional<double> speed_mm_s;  // a jump pose's "speed"; a point's speed from its profile and f
};

class Reader {
 public:
  Reader(const machine::MachineConfig& m, const WalkCallbacks& cb) : m_(m), cb_(cb) {}

  core::Status run(std::string_view data) {
    auto entries = io::read_zip(data, "3MF toolpath", "a 3MF package", [](std::string_view p) {
      return p.ends_with(".model") || p.ends_with(".rels") || p.ends_with(".xml");
    });
    if (!entries) return make_error(entries.error().code, "3MF toolpath: " + entries.error().message);
    for (io::ZipEntry& e : entries.value()) parts_[e.path] = std::move(e.bytes);
    const std::string model = model_path();
    auto doc = parse_part(model);
    if (!doc) return doc.error();
    auto layers = resource(xmlDocGetRootElement(doc.value().get()), model);
    if (!layers) return layers.error();
    for (std::size_t k = 0; k < layers.value().size(); ++k) {
      if (auto st = layer(layers.value()[k], k); !st) return st;
    }
    return {};
  }

 private:
  core::Result<Doc> parse_part(const std::string& path) {
    const auto it = parts_.find(path);
    if (it == parts_.end()) return invalid(fmt::format("no part '/{}' in the package", path));
    return parse(it->second, path);
  }

  // The 3D model part the package's root relationship names (3D/3dmodel.model when there is none).
  std::string model_path() {
    auto rels = parse_part("_rels/.rels");
    if (!rels) return "3D/3dmodel.model";
    for (const xmlNode* r : children(xmlDocGetRootElement(rels.value().get()))) {
      if (attr(r, "Type") == kModelRelationship && attr(r, "Target")) return part_name(*attr(r, "Target"));
    }
    return "3D/3dmodel.model";
  }

  // The targets of the model part's toolpath layer relationships.
  std::vector<std::string> layer_targets(const std::string& model) {
    std::vector<std::string> out;
    const std::size_t slash = model.rfind('/');
    const std::string rels = (slash == std::string::npos ? std::string() : model.substr(0, slash + 1)) + "_rels/" +
                             model.substr(slash == std::string::npos ? 0 : slash + 1) + ".rels";
    auto doc = parse_part(rels);
    if (!doc) return out;
    for (const xmlNode* r : children(xmlDocGetRootElement(doc.value().get()))) {
      const auto type = attr(r, "Type");
      if ((type == post::kToolpathLayerRelationship || type == kDeprecatedLayerRelationship) && attr(r, "Target")) {
        out.push_back(part_name(*attr(r, "Target")));
      }
    }
    return out;
  }

  // The toolpath resource the build names (or the first): its profiles, unit and layer parts.
  core::Result<std::vector<std::string>> resource(const xmlNode* root, const std::string& model) {
    if (!is(root, kCoreNamespace, "model")) return invalid(fmt::format("'/{}' is not a 3MF model", model));
    std::optional<std::string_view> wanted;
    const xmlNode* chosen = nullptr;
    std::vector<const xmlNode*> resources;
    for (const xmlNode* c : children(root)) {
      if (is(c, kCoreNamespace, "build")) {
        for (const xmlAttr* a = c->properties; a != nullptr; a = a->next) {
          if (a->ns != nullptr && a->name != nullptr && std::string_view(reinterpret_cast<const char*>(a->name)) == "toolpathid" &&
              a->children != nullptr && a->children->content != nullptr) {
            wanted = reinterpret_cast<const char*>(a->children->content);
          }
        }
      }
      if (is(c, kCoreNamespace, "resources")) {
        for (const xmlNode* r : children(c)) {
          if (is_toolpath(r, "toolpathresource")) resources.push_back(r);
        }
      }
    }
    for (const xmlNode* r : resources) {
      if (!wanted || attr(r, "id") == wanted) {
        chosen = r;
        break;
      }
    }
    if (chosen == nullptr) {
      return invalid(wanted ? fmt::format("the build's toolpathid {} names no toolpath resource", *wanted)
                            : std::string("no toolpath resource in the model"));
    }
    const std::string type(attr(chosen, "toolpathtype").value_or("planar"));
    if (type != "6axis" && type != "3axis") {
      return invalid(fmt::format("toolpathtype '{}' is not read: polyaxis reads 3axis and 6axis toolpaths (deposition)", type));
    }
    six_axis_ = type == "6axis";
    if (!attr(chosen, "unitfactor") || !number(*attr(chosen, "unitfactor"), unit_) || !(unit_ > 0.0)) {
      return invalid("the toolpath resource's unitfactor is missing or not a positive number");
    }
    std::vector<std::string> paths;
    const std::vector<std::string> targets = layer_targets(model);
    for (const xmlNode* c : children(chosen)) {
      if (is_toolpath(c, "toolpathprofiles")) {
        for (const xmlNode* p : children(c)) {
          if (auto st = profile(p); !st) return st.error();
        }
      }
      if (is_toolpath(c, "toolpathlayers")) {
        for (const xmlNode* l : children(c)) {
          if (!is_toolpath(l, "toolpathlayer") || !attr(l, "path")) return invalid("a toolpathlayer without a path");
          const std::string path = part_name(*attr(l, "path"));
          if (std::find(targets.begin(), targets.end(), path) == targets.end()) {
            return invalid(fmt::format("layer '/{}' is not the target of a toolpath layer relationship of the model part", path));
          }
          paths.push_back(path);
        }
      }
    }
    return paths;
  }

  core::Status profile(const xmlNode* p) {
    if (!is_toolpath(p, "toolpathprofile")) return {};
    const auto uuid = attr(p, "uuid");
    if (!uuid) return invalid("a toolpath profile without a uuid");
    Profile out;
    if (const auto s = attr(p, "depositionspeed"); s && (!number(*s, out.speed_mm_s) || !(out.speed_mm_s > 0.0))) {
      return invalid(fmt::format("profile {}: depositionspeed '{}' is not a positive number", *uuid, *s));
    }
    if (const auto s = attr(p, "prewaittime"); s) {
      if (!number(*s, out.prewait_s) || !(out.prewait_s >= 0.0)) return invalid(fmt::format("profile {}: prewaittime '{}' is not a number", *uuid, *s));
      out.prewait_s *= 1e-6;
    }
    for (const xmlNode* mod : children(p)) {
      if (!is_toolpath(mod, "modifier")) continue;
      // A consumer rejects a document with a modifier it does not support (spec §4.2).
      if (attr(mod, "attribute") != "depositionspeed" || attr(mod, "type") != "constant" || attr(mod, "factor") != "f" || !attr(mod, "minvalue") ||
          !attr(mod, "maxvalue") || !number(*attr(mod, "minvalue"), out.fmin) || !number(*attr(mod, "maxvalue"), out.fmax) || !(out.fmin > 0.0) ||
          !(out.fmax > out.fmin)) {
        return invalid(fmt::format("profile {}: a modifier polyaxis does not support (it reads a constant depositionspeed modifier on factor f)", *uuid));
      }
      out.modulated = true;
    }
    profiles_[std::string(*uuid)] = out;
    return {};
  }

  // A <point6d>, <point3d> or <pa:pose>: the tip in mm and the unit tool axis.
  core::Result<PoseIn> pose(const xmlNode* n, bool six, const std::string& where) {
    std::int64_t c[3];
    for (int k = 0; k < 3; ++k) {
      const auto s = attr(n, std::string_view("xyz").substr(static_cast<std::size_t>(k), 1));
      if (!s || !number(*s, c[k]) || c[k] < INT32_MIN || c[k] > INT32_MAX) return invalid(fmt::format("{}: {} is missing or not a 32-bit integer", where, "xyz"[k]));
    }
    PoseIn out;
    out.tip = Vec3{static_cast<double>(c[0]) * unit_, static_cast<double>(c[1]) * unit_, static_cast<double>(c[2]) * unit_};
    out.axis = Vec3{0, 0, 1};
    if (six) {
      double q[4];
      for (int k = 0; k < 4; ++k) {
        const auto s = attr(n, std::string_view("ijkw").substr(static_cast<std::size_t>(k), 1));
        if (!s || !number(*s, q[k])) return invalid(fmt::format("{}: quaternion {} is missing or not a number", where, "ijkw"[k]));
      }
      if (!(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3] > kMinQuaternionNorm2)) {
        return invalid(fmt::format("{}: the quaternion cannot be normalised", where));
      }
      out.axis = core::normalized(post::detail::z_axis(post::detail::normalized({q[0], q[1], q[2], q[3]})));
    }
    return out;
  }

  core::Status layer(const std::string& path, std::size_t ordinal) {
    auto doc = parse_part(path);
    if (!doc) return doc.error();
    const xmlNode* root = xmlDocGetRootElement(doc.value().get());
    if (!is_toolpath(root, "layer")) return invalid(fmt::format("'/{}' is not a toolpath layer", path));
    std::map<std::string, std::string, std::less<>> profile_ids;  // local id -> profile uuid
    std::vector<std::string> part_ids;
    std::map<std::size_t, const xmlNode*> jumps;
    std::vector<const xmlNode*> segments;
    layer_ = static_cast<std::int64_t>(ordinal), region_ = 0;
    for (const xmlNode* c : children(root)) {
      if (is_toolpath(c, "parts")) {
        for (const xmlNode* p : children(c)) {
          if (attr(p, "id")) part_ids.emplace_back(*attr(p, "id"));
        }
      } else if (is_toolpath(c, "profiles")) {
        for (const xmlNode* p : children(c)) {
          if (attr(p, "id") && attr(p, "uuid")) profile_ids[std::string(*attr(p, "id"))] = std::string(*attr(p, "uuid"));
        }
      } else if (is_toolpath(c, "data")) {
        for (const xmlNode* d : children(c)) {
          if (is(d, post::kPolyaxisNamespace, "layer")) {
            if (!attr(d, "index") || !number(*attr(d, "index"), layer_) || !attr(d, "region") || !number(*attr(d, "region"), region_)) {
              return invalid(fmt::format("'/{}': pa:layer needs integer index and region", path));
            }
          } else if (is(d, post::kPolyaxisNamespace, "jump")) {
            std::size_t before = 0;
            if (!attr(d, "segment") || !number(*attr(d, "segment"), before)) return invalid(fmt::format("'/{}': pa:jump needs a segment index", path));
            jumps[before] = d;
          }
        }
      } else if (is_toolpath(c, "segments")) {
        for (const xmlNode* s : children(c)) {
          if (is_toolpath(s, "segment")) segments.push_back(s);
        }
      }
    }
    if (!jumps.empty() && jumps.rbegin()->first > segments.size()) {
      return invalid(fmt::format("'/{}': a pa:jump before segment {} of {}", path, jumps.rbegin()->first, segments.size()));
    }
    for (std::size_t s = 0; s <= segments.size(); ++s) {
      if (const auto j = jumps.find(s); j != jumps.end()) {
        for (const xmlNode* p : children(j->second)) {
          if (!is(p, post::kPolyaxisNamespace, "pose")) continue;
          const std::string where = fmt::format("'/{}' jump before segment {}, pose", path, s);
          auto in = pose(p, true, where);
          if (!in) return in.error();
          if (const auto sp = attr(p, "speed")) {
            double v = 0.0;
            if (!number(*sp, v) || !(v > 0.0)) return invalid(fmt::format("{}: speed '{}' is not a positive number", where, *sp));
            in.value().speed_mm_s = v;
          }
          if (auto st = move(in.value(), false, where); !st) return st;
        }
      }
      if (s == segments.size()) break;
      if (auto st = segment(segments[s], path, s, profile_ids, part_ids); !st) return st;
    }
    return {};
  }

  core::Status segment(const xmlNode* seg, const std::string& path, std::size_t s, const std::map<std::string, std::string, std::less<>>& profile_ids,
                       const std::vector<std::string>& part_ids) {
    const std::string where = fmt::format("'/{}' segment {}", path, s);
    const std::string type(attr(seg, "type").value_or(""));
    if (type != (six_axis_ ? "polyline6d" : "polyline3d")) {
      return invalid(fmt::format("{}: type '{}' in a {} toolpath (polyaxis reads {})", where, type, six_axis_ ? "6axis" : "3axis",
                                 six_axis_ ? "polyline6d" : "polyline3d"));
    }
    const auto pid = attr(seg, "profileid"), part = attr(seg, "partid");
    const auto local = pid ? profile_ids.find(*pid) : profile_ids.end();
    const auto prof = local == profile_ids.end() ? profiles_.end() : profiles_.find(local->second);
    if (prof == profiles_.end()) return invalid(fmt::format("{}: profileid '{}' names no profile of the layer and resource", where, pid.value_or("")));
    if (!part || std::find(part_ids.begin(), part_ids.end(), *part) == part_ids.end()) {
      return invalid(fmt::format("{}: partid '{}' names no part of the layer", where, part.value_or("")));
    }
    const Profile& pr = prof->second;
    if (!(pr.speed_mm_s > 0.0)) return invalid(fmt::format("{}: its profile has no depositionspeed", where));
    std::vector<const xmlNode*> points;
    for (const xmlNode* p : children(seg)) {
      if (is_toolpath(p, six_axis_ ? "point6d" : "point3d")) points.push_back(p);
    }
    if (points.size() < 2) return invalid(fmt::format("{}: a polyline needs two or more points, it has {}", where, points.size()));
    for (std::size_t k = 0; k < points.size(); ++k) {
      const std::string at = fmt::format("{} point {}", where, k);
      auto in = pose(points[k], six_axis_, at);
      if (!in) return in.error();
      if (k == 0) {
        if (auto st = move(in.value(), false, at); !st) return st;  // to the start, if not there yet
        if (cb_.dwell && pr.prewait_s > 0.0) cb_.dwell(line_, pr.prewait_s, true);
        continue;
      }
      double speed = pr.speed_mm_s;
      if (const auto f = attr(points[k], "f")) {
        double v = 0.0;
        if (!pr.modulated || !number(*f, v) || v < 0.0 || v > 1.0) return invalid(fmt::format("{}: factor f '{}' without its modifier or not in [0, 1]", at, *f));
        speed = pr.fmin + v * (pr.fmax - pr.fmin);
      }
      in.value().speed_mm_s = speed;
      if (auto st = move(in.value(), true, at); !st) return st;
    }
    return {};
  }

  // One move to IN (a rapid when it has no speed), with the process ON.
  core::Status move(const PoseIn& in, bool on, const std::string& where) {
    ++line_;
    auto target = machine::inverse(m_, in.tip, in.axis, have_ ? &pos_ : nullptr);
    if (!target) return make_error(target.error().code, fmt::format("3MF toolpath {} (pose {}): {}", where, line_, target.error().message));
    if (cb_.target) cb_.target(line_, target.value(), where);
    WalkMove mv;
    mv.line = line_, mv.from = pos_, mv.to = target.value(), mv.rapid = !in.speed_mm_s;
    mv.process_on = on, mv.layer = layer_, mv.region = region_;
    mv.tool_space = true;
    mv.tip_from = tip_, mv.tip_to = in.tip, mv.axis_from = axis_, mv.axis_to = in.axis;
    if (in.speed_mm_s) mv.feed = *in.speed_mm_s * 60.0, mv.f_word = mv.feed;
    if (!have_) {
      mv.from_known = false;
      if (cb_.move) cb_.move(mv);
    } else {
      const double tip_mm = core::norm(in.tip - tip_);
      const double turn_deg = std::atan2(core::norm(core::cross(axis_, in.axis)), core::dot(axis_, in.axis)) * 180.0 / M_PI;
      if (tip_mm == 0.0 && turn_deg == 0.0) return {};
      const MachinePose& to = target.value();
      mv.l_xyz_mm = core::norm(Vec3{to.x_mm - pos_.x_mm, to.y_mm - pos_.y_mm, to.z_mm - pos_.z_mm});
      mv.d_tilt_deg = std::abs(to.a_or_b_deg - pos_.a_or_b_deg);
      mv.d_c_deg = std::abs(to.c_deg - pos_.c_deg);
      if (!mv.rapid) mv.time_min = tip_mm > 0.0 ? tip_mm / mv.feed : turn_deg / mv.feed;
      if (cb_.move) cb_.move(mv);
    }
    pos_ = target.value(), tip_ = in.tip, axis_ = in.axis, have_ = true;
    return {};
  }

  const machine::MachineConfig& m_;
  const WalkCallbacks& cb_;
  std::map<std::string, std::string> parts_;
  std::map<std::string, Profile> profiles_;
  double unit_ = 0.0;
  bool six_axis_ = true;
  std::int64_t layer_ = -1, region_ = -1;
  std::uint64_t line_ = 0;
  MachinePose pos_{};
  Vec3 tip_{}, axis_{0, 0, 1};
  bool have_ = false;
};

}  // namespace

core::Status walk_toolpath_3mf(const machine::MachineConfig& machine, std::string_view package, const WalkCallbacks& callbacks, bool* program_end) {
  Reader reader(machine, callbacks);
  if (auto st = reader.run(package); !st) return st;
  if (program_end != nullptr) *program_end = true;  // a package holds the whole program
  return {};
}

}  // namespace polyaxis::verify::detail
