#include "polyaxis/report/report_html.h"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <numbers>
#include <nlohmann/json.hpp>

#include "polyaxis/machine/robot.h"
#include "polyaxis/mesh/properties.h"

namespace polyaxis::report {
namespace {

static_assert(std::endian::native == std::endian::little, "the viewer reads little-endian typed arrays");

// Base64 of the bytes of a typed array (the viewer decodes it into the same typed array).
template <typename T>
std::string base64(const std::vector<T>& values) {
  static constexpr char kDigits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* bytes = reinterpret_cast<const unsigned char*>(values.data());
  const std::size_t n = values.size() * sizeof(T);
  std::string out;
  out.reserve((n + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < n; i += 3) {
    const std::uint32_t w = (std::uint32_t{bytes[i]} << 16) | (std::uint32_t{bytes[i + 1]} << 8) | bytes[i + 2];
    out += kDigits[w >> 18], out += kDigits[(w >> 12) & 63], out += kDigits[(w >> 6) & 63], out += kDigits[w & 63];
  }
  if (i < n) {
    const std::uint32_t w = (std::uint32_t{bytes[i]} << 16) | (i + 1 < n ? std::uint32_t{bytes[i + 1]} << 8 : 0u);
    out += kDigits[w >> 18], out += kDigits[(w >> 12) & 63];
    out += i + 1 < n ? kDigits[(w >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

void push(std::vector<float>& out, Vec3 v) {
  out.push_back(static_cast<float>(v.x)), out.push_back(static_cast<float>(v.y)), out.push_back(static_cast<float>(v.z));
}

std::string vec(Vec3 v) { return fmt::format("[{:.6g},{:.6g},{:.6g}]", v.x, v.y, v.z); }

// Rings as one flat float array and the index of each ring's first point.
std::string rings_fields(const std::vector<std::vector<Vec3>>& rings, const char* name, const char* starts_name) {
  std::vector<float> points;
  std::vector<std::size_t> starts;
  for (const auto& ring : rings) {
    starts.push_back(points.size() / 3);
    for (const Vec3& p : ring) push(points, p);
  }
  return fmt::format("\"{}\":\"{}\",\"{}\":[{}]", name, base64(points), starts_name, fmt::join(starts, ","));
}

// Indices of N items kept for the page: all up to MAX (0: no cap); beyond, every k-th and every
// item MUST_KEEP(i) names.
template <typename MustKeep>
std::vector<std::size_t> kept_indices(std::size_t n, std::size_t max, MustKeep must_keep) {
  std::vector<std::size_t> kept;
  const std::size_t stride = max == 0 || n <= max ? 1 : (n + max - 1) / max;
  std::size_t since = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (stride == 1 || must_keep(i) || ++since >= stride) kept.push_back(i), since = 0;
  }
  return kept;
}

// The program points kept: every k-th point of each run of deposit or travel moves, with the
// run's first and last point (every layer's first and last among them).
std::vector<std::size_t> kept_points(const std::vector<post::ProgramPoint>& program, std::size_t max_points) {
  auto differ = [&](std::size_t a, std::size_t b) { return program[a].process_on != program[b].process_on || program[a].layer != program[b].layer; };
  return kept_indices(program.size(), max_points, [&](std::size_t i) {
    return i == 0 || i + 1 == program.size() || differ(i - 1, i) || differ(i, i + 1);
  });
}

// The playback's frames kept: every k-th, every frame where the process, the layer or the motion
// mode changes, and the last.
std::vector<std::size_t> kept_frames(const std::vector<verify::PlaybackFrame>& frames, std::size_t max_frames) {
  return kept_indices(frames.size(), max_frames, [&](std::size_t i) {
    return i == 0 || i + 1 == frames.size() || frames[i - 1].process_on != frames[i].process_on || frames[i - 1].layer != frames[i].layer ||
           frames[i - 1].rapid != frames[i].rapid;
  });
}

// ,"robot":{...},"arm":"..." for a robot cell's playback, else "": the arm's geometry (robot.h),
// its base frame and TCP in the playback's frame (the positioner's fixed frame, where the joints X
// Y Z put the tip), its joints q1..q6 for each kept frame, and, for the viewer's test, the TCP our
// own forward kinematics gives at the first kept frame.
std::string robot_json(const ViewPlayback& p, const std::vector<std::size_t>& kept) {
  const machine::MachineConfig& m = p.machine;
  if (!m.robot || kept.empty() || !p.frames[kept.front()].has_arm) return {};
  const machine::RobotCell& r = *m.robot;
  std::vector<float> arm;
  for (const std::size_t i : kept) arm.insert(arm.end(), p.frames[i].arm.begin(), p.frames[i].arm.end());
  // The scene is the positioner's fixed frame: world = Rz(P.rz)·scene + P.origin.
  const double prz = r.positioner.rz_deg * std::numbers::pi / 180.0;
  auto to_scene = [&](core::Vec3 w) {
    const core::Vec3 d{w.x - r.positioner.origin_mm[0], w.y - r.positioner.origin_mm[1], w.z - r.positioner.origin_mm[2]};
    return core::Vec3{std::cos(prz) * d.x + std::sin(prz) * d.y, -std::sin(prz) * d.x + std::cos(prz) * d.y, d.z};
  };
  const core::Vec3 base = to_scene({r.base.origin_mm[0], r.base.origin_mm[1], r.base.origin_mm[2]});
  machine::RobotJoints q0{};
  for (std::size_t k = 0; k < 6; ++k) q0[k] = p.frames[kept.front()].arm[k];
  const core::Vec3 tcp = to_scene(machine::robot_tcp_world(r, q0).origin);
  auto six = [](const std::array<double, 6>& v) { return fmt::format("[{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g}]", v[0], v[1], v[2], v[3], v[4], v[5]); };
  return fmt::format(
      ",\"robot\":{{\"model\":{},\"geometry_mm\":[{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g}],\"sign\":{},\"zero_deg\":{},"
      "\"base\":[{:.9g},{:.9g},{:.9g},{:.9g}],\"tcp\":[{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g}],\"check_tcp\":[{:.9g},{:.9g},{:.9g}]}},"
      "\"arm\":\"{}\"",
      nlohmann::json(r.model).dump(), r.a1_mm, r.a2_mm, r.b_mm, r.c1_mm, r.c2_mm, r.c3_mm, r.c4_mm, six(r.sign), six(r.zero_deg), base.x, base.y, base.z,
      r.base.rz_deg - r.positioner.rz_deg, r.tcp_mm[0], r.tcp_mm[1], r.tcp_mm[2], r.tcp_quaternion[0], r.tcp_quaternion[1], r.tcp_quaternion[2],
      r.tcp_quaternion[3], tcp.x, tcp.y, tcp.z, base64(arm));
}

// "playback": the kinematics to pose the machine (machine/kinematics.h: trt-kins' rotation point,
// tilt offset and sense; the head's pivot length), the head, table and plate to draw, and the
// frames (joints X Y Z tilt C, the time each ends, its line, process and rapid flags, its layer).
std::string playback_json(const ViewPlayback& p, const machine::BuildModel& model, std::size_t max_frames) {
  const machine::MachineConfig& m = p.machine;
  const std::vector<std::size_t> kept = kept_frames(p.frames, max_frames);
  std::vector<float> joints, times;
  std::vector<std::uint32_t> lines;
  std::vector<std::int32_t> layers;
  std::vector<std::uint8_t> flags;
  for (const std::size_t i : kept) {
    const verify::PlaybackFrame& f = p.frames[i];
    for (const double v : {f.pose.x_mm, f.pose.y_mm, f.pose.z_mm, f.pose.a_or_b_deg, f.pose.c_deg}) joints.push_back(static_cast<float>(v));
    times.push_back(static_cast<float>(f.time_s));
    lines.push_back(static_cast<std::uint32_t>(std::min<std::uint64_t>(f.line, 0xffffffffu)));
    layers.push_back(static_cast<std::int32_t>(f.layer));
    flags.push_back(static_cast<std::uint8_t>((f.process_on ? 1 : 0) | (f.rapid ? 2 : 0)));
  }
  const machine::TrtPivot& pv = m.pivot;
  const bool a = machine::tilt_axis_letter(m.kind) == 'A';
  const std::string robot = robot_json(p, kept);
  const double dz = pv.z_offset_mm + pv.tool_offset_mm;
  const machine::SubstratePlate& s = model.substrate;
  const machine::NozzleModel& n = model.nozzle;
  return fmt::format(
      "{{\"kinematics\":{},\"sense\":{},\"rot_point\":[{:.6g},{:.6g},{:.6g}],\"offset\":[{:.6g},{:.6g},{:.6g}],\"pivot_length_mm\":{:.6g},"
      "\"nozzle\":{{\"tip_half_angle_deg\":{:.6g},\"cone_height_mm\":{:.6g},\"cylinder_radius_mm\":{:.6g},\"cylinder_height_mm\":{:.6g}}},"
      "\"table\":{{\"radius_mm\":{:.6g},\"centre\":[{:.6g},{:.6g}],\"top_z_mm\":{:.6g}}},"
      "\"plate\":{{\"x_mm\":[{:.6g},{:.6g}],\"y_mm\":[{:.6g},{:.6g}],\"top_z_mm\":{:.6g},\"thickness_mm\":{:.6g}}},"
      "\"total_frames\":{},\"duration_s\":{:.6g},\"joints\":\"{}\",\"time\":\"{}\",\"line\":\"{}\",\"layer\":\"{}\",\"flags\":\"{}\"{}}}",
      nlohmann::json(std::string(machine::kinematics_name(m.kind))).dump(), pv.conventional_directions ? 1 : -1, pv.x_rot_point_mm,
      pv.y_rot_point_mm, pv.z_rot_point_mm, a ? 0.0 : pv.x_offset_mm, a ? pv.y_offset_mm : 0.0, dz, pv.pivot_length_mm,
      n.tip_half_angle_deg, n.cone_height_mm, n.cylinder_radius_mm, n.cylinder_height_mm, model.table_radius_mm, model.table_centre_mm.x,
      model.table_centre_mm.y, model.table_top_z_mm(), s.x_min_mm, s.x_max_mm, s.y_min_mm, s.y_max_mm, s.top_z_mm, s.thickness_mm,
      p.frames.size(), p.frames.empty() ? 0.0 : p.frames.back().time_s, base64(joints), base64(times), base64(lines), base64(layers),
      base64(flags), robot);
}

}  // namespace

std::string view_data_json(const PlanView& view, const HtmlOptions& options) {
  std::string out = "{\"format\":\"polyaxis-view/1\",\"title\":";
  out += nlohmann::json(view.part).dump();
  out += ",\"metrics\":";
  out += metrics_object(view.metrics_json);
  fmt::format_to(std::back_inserter(out), ",\"machine\":{{\"name\":{},\"kinematics\":{},\"tilt_axis\":{}}},\"bead_width_mm\":{:.6g}",
                 nlohmann::json(view.machine).dump(), nlohmann::json(view.kinematics).dump(), nlohmann::json(view.tilt_axis).dump(),
                 view.bead_width_mm);
  out += ",\"regions\":[";
  for (std::size_t i = 0; i < view.regions.size(); ++i) {
    const planner::PlanRegion& r = view.regions[i];
    std::vector<float> positions;
    positions.reserve(3 * r.mesh.vertices.size());
    for (const Vec3& v : r.mesh.vertices) push(positions, v);
    std::vector<std::uint32_t> indices;
    indices.reserve(3 * r.mesh.triangles.size());
    for (const auto& t : r.mesh.triangles) indices.insert(indices.end(), t.begin(), t.end());
    fmt::format_to(std::back_inserter(out),
                   "{}{{\"id\":{},\"parent\":{},\"build_direction\":{},\"base_point\":{},\"volume_mm3\":{:.6g},\"support_free\":{},"
                   "\"layers\":{{\"strategy\":\"{}\",\"why\":{}}},\"prebuilt\":{},\"positions\":\"{}\",\"indices\":\"{}\"}}",
                   i ? "," : "", r.id, r.parent ? fmt::to_string(*r.parent) : std::string("null"), vec(core::normalized(r.direction)),
                   vec(r.base_point), mesh::signed_volume(r.mesh), r.support_free, slicing::layer_strategy_name(r.layers),
                   nlohmann::json(r.layers_why).dump(), r.prebuilt, base64(positions), base64(indices));
  }
  out += "],\"axis\":";
  if (!view.axis) {
    out += "null";
  } else {
    out += "{\"nodes\":[";
    for (std::size_t i = 0; i < view.axis->nodes.size(); ++i) out += (i ? "," : "") + vec(view.axis->nodes[i]);
    out += "],\"links\":[";
    for (std::size_t i = 0; i < view.axis->links.size(); ++i) {
      const auto& l = view.axis->links[i];
      fmt::format_to(std::back_inserter(out), "{}[{},{},{}]", i ? "," : "", l[0], l[1], l[2]);
    }
    out += "]}";
  }

  // The toolpath: kept points, in program order (layers are contiguous and in build order).
  const std::vector<std::size_t> kept = kept_points(view.program, options.max_points);
  std::vector<float> points, axes;
  std::vector<std::uint8_t> flags;
  std::vector<std::uint16_t> regions;
  points.reserve(3 * kept.size()), axes.reserve(3 * kept.size()), flags.reserve(kept.size()), regions.reserve(kept.size());
  std::vector<std::size_t> first(view.layers.size(), 0), count(view.layers.size(), 0);
  for (std::size_t k = 0; k < kept.size(); ++k) {
    const post::ProgramPoint& p = view.program[kept[k]];
    push(points, p.tip_part_mm);
    push(axes, core::normalized(p.tool_axis_part));
    flags.push_back(static_cast<std::uint8_t>((p.process_on ? 1 : 0) | (k == 0 ? 2 : 0)));
    regions.push_back(static_cast<std::uint16_t>(std::min<std::uint32_t>(p.region, 0xffff)));
    if (p.layer < view.layers.size()) {
      if (count[p.layer] == 0) first[p.layer] = k;
      ++count[p.layer];
    }
  }
  out += ",\"layers\":[";
  for (std::size_t k = 0; k < view.layers.size(); ++k) {
    const ViewLayer& l = view.layers[k];
    fmt::format_to(std::back_inserter(out),
                   "{}\n{{\"index\":{},\"region\":{},\"origin\":{},\"normal\":{},\"thickness_mm\":{:.6g},\"thickness_range_mm\":[{:.6g},{:.6g}],"
                   "\"area_mm2\":{:.6g},\"unsupported_area_mm2\":{:.6g},\"max_tilt_deg\":{:.6g},\"tilt_deg\":[{:.6g},{:.6g}],\"c_deg\":[{:.6g},{:.6g}],{},{},"
                   "\"path_first\":{},\"path_count\":{}}}",
                   k ? "," : "", l.index, l.region, vec(l.origin), vec(l.normal), l.thickness_mm, l.thickness_range_mm[0], l.thickness_range_mm[1],
                   l.area_mm2, l.unsupported_area_mm2,
                   l.max_tilt_deg, l.tilt_deg[0], l.tilt_deg[1], l.c_deg[0], l.c_deg[1], rings_fields(l.contours, "contours", "contour_starts"),
                   rings_fields(l.unsupported, "unsupported", "unsupported_starts"), first[k], count[k]);
  }
  fmt::format_to(std::back_inserter(out),
                 "],\n\"toolpath\":{{\"points\":\"{}\",\"axes\":\"{}\",\"flags\":\"{}\",\"region\":\"{}\",\"total_points\":{},"
                 "\"shown_points\":{}}},\"collisions\":[",
                 base64(points), base64(axes), base64(flags), base64(regions), view.program.size(), kept.size());
  for (std::size_t i = 0; i < view.collisions.size(); ++i) {
    const Vec3& p = view.collisions[i].position;
    fmt::format_to(std::back_inserter(out), "{}{{\"position\":[{:.4f},{:.4f},{:.4f}],\"what\":{},\"line\":{}}}", i ? "," : "", p.x, p.y,
                   p.z, nlohmann::json(view.collisions[i].what).dump(), view.collisions[i].line);
  }
  out += "]";
  if (view.playback) {
    const std::size_t frames = options.max_points == 0 ? 0 : std::min(options.max_points, kViewerMaxFrames);  // 0: all
    out += ",\n\"playback\":" + playback_json(*view.playback, view.build_model, frames);
  }
  out += "}";
  return out;
}

std::string report_html(const PlanView& view, std::string_view bundle, const HtmlOptions& options) {
  // Neither the data nor the script may end the <script> element it sits in. In the JSON every
  // "<" becomes "\\u003c" ('<' appears only inside JSON strings, where the escape reads as the
  // same character), so no "</script" or "<!--" can appear. The bundle is checked when it is built
  // (viewer/build.mjs refuses "</script" and "<!--"); here "</script" is escaped once more in case.
  auto escaped_data = [](std::string_view text) {
    std::string out;
    out.reserve(text.size());
    for (char c : text) {
      if (c == '<') {
        out += "\\u003c";
      } else {
        out += c;
      }
    }
    return out;
  };
  auto escaped_script = [](std::string_view text) {
    std::string out;
    out.reserve(text.size());
    for (std::size_t i = 0; i < text.size(); ++i) {
      out += text[i];
      if (text[i] != '<' || i + 1 >= text.size() || text[i + 1] != '/') continue;
      std::string next(text.substr(i + 2, 6));
      std::transform(next.begin(), next.end(), next.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
      if (next == "script") out += '\\';
    }
    return out;
  };
  std::string title = view.part.substr(view.part.find_last_of('/') == std::string::npos ? 0 : view.part.find_last_of('/') + 1);
  std::string safe_title;
  for (char c : title) safe_title += c == '<' ? std::string("&lt;") : c == '&' ? std::string("&amp;") : std::string(1, c);
  std::string out =
      "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><meta name=\"viewport\" "
      "content=\"width=device-width,initial-scale=1\">\n<title>polyaxis — " +
      safe_title + "</title></head>\n<body>\n<script type=\"application/json\" id=\"polyaxis-data\">";
  out += escaped_data(view_data_json(view, options));
  out += "</script>\n<script>";
  out += escaped_script(bundle);
  out += "</script>\n</body></html>\n";
  return out;
}

}  // namespace polyaxis::report
