#include "polyaxis/lamination/waterjet.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "core/config_json.h"
#include "polyaxis/geom2d/clip.h"
#include "polyaxis/machine/kinematics.h"
#include "edges.h"
#include "polyaxis/post/gcode.h"

namespace polyaxis::lamination {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kHoleLeadShare = 0.45;  // a hole's lead-in: at most this share of its width along the normal
constexpr double kLeadMinMm = 1e-6;      // the start sample's own edges are no width

constexpr const char* kDefaultWaterjet = R"({
  "name": "awj_steel",
  "jet_on": "M64 P0",
  "jet_off": "M65 P0",
  "pierce_s": 1.5,
  "kerf_mm": 0.8,
  "margin_mm": 5,
  "lead_in_mm": 2,
  "lead_out_mm": 1,
  "clearance_mm": 10,
  "travel_feed_mm_s": 150,
  "min_feed_mm_s": 0.2,
  "max_feed_mm_s": 60,
  "feed": {"orifice_mm": 0.33, "insert_mm": 1.02, "abrasive_ratio": 0.2, "pressure_mpa": 380,
           "specific_energy_gj_m3": 130, "water_density_kg_m3": 1000}
}
)";

constexpr const char* kDefaultWaterjetMachine = R"({
  "name": "awj5_head_ac",
  "kinematics": "xyzac-head",
  "limits": {
    "x": {"min": 0, "max": 1500},
    "y": {"min": 0, "max": 1500},
    "z": {"min": -50, "max": 400},
    "a": {"min": -60, "max": 60},
    "c": {"continuous": true, "unwind": true}
  },
  "pivot": {"pivot_length_mm": 100},
  "feed": {"linear_max_mm_min": 10000, "rotary_max_deg_min": 7200},
  "nozzle": {"tip_half_angle_deg": 15, "cone_height_mm": 30, "cylinder_radius_mm": 12, "cylinder_height_mm": 120},
  "table": {"radius_mm": 1000}
}
)";

Vec2 rotate(Vec2 v, double deg) {
  double x = 0, y = 0;
  place(Placement{0, deg, 0.0, 0.0}, v.x, v.y, x, y);
  return {x, y};
}

}  // namespace

std::string_view default_waterjet_process_json() { return kDefaultWaterjet; }
std::string_view default_waterjet_machine_json() { return kDefaultWaterjetMachine; }

core::Result<WaterjetProcess> parse_waterjet_process(std::string_view text, const std::string& source) {
  auto doc = core::detail::parse_document(text, source);
  if (!doc) return doc.error();
  const nlohmann::json& root = doc.value();
  core::detail::ConfigReader r(source);
  if (!r.check_object(root, "", {"name", "jet_on", "jet_off", "pierce_s", "kerf_mm", "margin_mm", "lead_in_mm", "lead_out_mm", "clearance_mm",
                                 "travel_feed_mm_s", "min_feed_mm_s", "max_feed_mm_s", "feed"})) {
    return r.error();
  }
  WaterjetProcess p;
  p.name = r.string(root, "", "name", std::nullopt);
  p.jet_on = r.string(root, "", "jet_on", std::nullopt);
  p.jet_off = r.string(root, "", "jet_off", std::nullopt);
  p.pierce_s = r.number(root, "", "pierce_s", std::nullopt);
  p.kerf_mm = r.number(root, "", "kerf_mm", std::nullopt);
  p.margin_mm = r.number(root, "", "margin_mm", std::nullopt);
  p.lead_in_mm = r.number(root, "", "lead_in_mm", std::nullopt);
  p.lead_out_mm = r.number(root, "", "lead_out_mm", std::nullopt);
  p.clearance_mm = r.number(root, "", "clearance_mm", std::nullopt);
  p.travel_feed_mm_s = r.number(root, "", "travel_feed_mm_s", std::nullopt);
  p.min_feed_mm_s = r.number(root, "", "min_feed_mm_s", std::nullopt);
  p.max_feed_mm_s = r.number(root, "", "max_feed_mm_s", std::nullopt);
  if (r.has(root, "feed")) {
    const auto& f = root["feed"];
    if (!r.check_object(f, "feed", {"orifice_mm", "insert_mm", "abrasive_ratio", "pressure_mpa", "specific_energy_gj_m3", "water_density_kg_m3"})) return r.error();
    p.orifice_mm = r.number(f, "feed", "orifice_mm", std::nullopt);
    p.insert_mm = r.number(f, "feed", "insert_mm", std::nullopt);
    p.abrasive_ratio = r.number(f, "feed", "abrasive_ratio", std::nullopt);
    p.pressure_mpa = r.number(f, "feed", "pressure_mpa", std::nullopt);
    p.specific_energy_gj_m3 = r.number(f, "feed", "specific_energy_gj_m3", std::nullopt);
    p.water_density_kg_m3 = r.number(f, "feed", "water_density_kg_m3", std::nullopt);
  } else {
    r.fail("'feed' (Eq. 3's coefficients) is missing");
  }
  if (r.failed()) return r.error();
  for (const auto& [key, v] : {std::pair<std::string_view, const std::string&>{"jet_on", p.jet_on}, {"jet_off", p.jet_off}}) {
    if (const std::string why = process::switch_code_problem(v); !why.empty()) r.fail(fmt::format("'{}' (\"{}\"): {}", key, v, why));
  }
  if (p.jet_on == p.jet_off) r.fail("'jet_on' and 'jet_off' must differ");
  auto positive = [&](std::string_view key, double v) {
    if (!(v > 0.0)) r.fail(fmt::format("'{}' ({}) must be > 0", key, v));
  };
  positive("kerf_mm", p.kerf_mm), positive("margin_mm", p.margin_mm), positive("clearance_mm", p.clearance_mm);
  positive("feed.orifice_mm", p.orifice_mm), positive("feed.insert_mm", p.insert_mm), positive("feed.abrasive_ratio", p.abrasive_ratio);
  positive("feed.pressure_mpa", p.pressure_mpa), positive("feed.specific_energy_gj_m3", p.specific_energy_gj_m3);
  positive("feed.water_density_kg_m3", p.water_density_kg_m3);
  if (p.pierce_s < 0.0) r.fail(fmt::format("'pierce_s' ({}) must be ≥ 0", p.pierce_s));
  if (p.lead_in_mm < 0.0 || p.lead_in_mm > 0.5 * p.margin_mm) r.fail(fmt::format("'lead_in_mm' ({}) must be in [0, margin_mm/2 = {}]", p.lead_in_mm, 0.5 * p.margin_mm));
  if (p.lead_out_mm < 0.0 || p.lead_out_mm > 0.5 * p.margin_mm) r.fail(fmt::format("'lead_out_mm' ({}) must be in [0, margin_mm/2 = {}]", p.lead_out_mm, 0.5 * p.margin_mm));
  for (const auto& [key, v] : {std::pair<std::string_view, double>{"travel_feed_mm_s", p.travel_feed_mm_s}, {"min_feed_mm_s", p.min_feed_mm_s},
                               {"max_feed_mm_s", p.max_feed_mm_s}}) {
    if (!(v >= process::kMinFeedMmS && v <= process::kMaxFeedMmS)) {
      r.fail(fmt::format("'{}' ({}) must be between {} and {} mm/s", key, v, process::kMinFeedMmS, process::kMaxFeedMmS));
    }
  }
  r.require_le(p.min_feed_mm_s, "min_feed_mm_s", p.max_feed_mm_s, "max_feed_mm_s");
  if (r.failed()) return r.error();
  return p;
}

double waterjet_feed_mm_s(const WaterjetProcess& p, double thickness_mm, double tilt_rad) {
  const double d0 = p.orifice_mm * 1e-3, di = p.insert_mm * 1e-3, h = thickness_mm * 1e-3 / std::max(std::cos(tilt_rad), 1e-3);
  const double pressure = p.pressure_mpa * 1e6, mu = p.specific_energy_gj_m3 * 1e9, R = p.abrasive_ratio;
  const double v_m_s = kPi / 4.0 * d0 * d0 * R * std::pow(1.0 / (1.0 + R), 2.0) * std::pow(pressure, 1.5) / (mu * di * h) *
                       std::sqrt(2.0 / p.water_density_kg_m3);
  return std::clamp(v_m_s * 1e3, p.min_feed_mm_s, p.max_feed_mm_s);
}

process::ProcessConfig post_process(const WaterjetProcess& w) {
  process::ProcessConfig p;
  p.name = w.name;
  p.process_on = w.jet_on;
  p.process_off = w.jet_off;
  p.dwell_on_s = w.pierce_s;
  p.travel_feed_mm_s = w.travel_feed_mm_s;
  p.deposit_feed_mm_s = w.max_feed_mm_s;
  return p;
}

geom2d::Ring footprint(const Layer& layer, const Piece& piece, double kerf_mm) {
  std::vector<geom2d::Ring> rings;
  for (double h : {layer.z_bottom_mm, layer.z_top()}) {
    for (const auto& p : kept_section(layer, piece, h, 0.5 * kerf_mm)) rings.push_back(p.outer);
  }
  const auto u = geom2d::union_rings(rings, geom2d::FillRule::kNonZero);
  geom2d::Ring best;
  double best_area = -1.0;
  for (const auto& p : u) {
    const double a = geom2d::signed_area_mm2(p.outer);
    if (a > best_area) best_area = a, best = p.outer;
  }
  return best;
}

core::Result<std::vector<Sheet>> nest_sheets(const Lamination& lam, const WaterjetProcess& process, double sheet_w_mm, double sheet_h_mm,
                                             const machine::MachineConfig& machine) {
  std::map<double, std::vector<SheetPiece>> groups;  // by thickness, thinnest first
  std::map<double, std::vector<geom2d::Ring>> outlines;
  for (const auto& layer : lam.layers) {
    for (std::uint32_t i = 0; i < layer.pieces.size(); ++i) {
      groups[layer.thickness_mm].push_back(SheetPiece{layer.index, i, {}});
      outlines[layer.thickness_mm].push_back(footprint(layer, layer.pieces[i], process.kerf_mm));
    }
  }
  const core::Vec3 centre = machine::work_centre_mm(machine);
  std::vector<Sheet> sheets;
  for (auto& [t, pieces] : groups) {
    auto placed = nest(outlines[t], NestOptions{sheet_w_mm, sheet_h_mm, process.margin_mm});
    if (!placed) {
      return core::make_error(placed.error().code, fmt::format("{} mm sheets: {}", t, placed.error().message));
    }
    const std::size_t first = sheets.size();
    for (std::size_t i = 0; i < pieces.size(); ++i) {
      pieces[i].placement = placed.value()[i];
      const std::size_t k = first + pieces[i].placement.sheet;
      while (sheets.size() <= k) {
        Sheet s;
        s.index = static_cast<std::uint32_t>(sheets.size());
        s.thickness_mm = t;
        s.size_mm[0] = sheet_w_mm, s.size_mm[1] = sheet_h_mm;
        s.origin_mm[0] = centre.x - 0.5 * sheet_w_mm, s.origin_mm[1] = centre.y - 0.5 * sheet_h_mm;
        sheets.push_back(s);
      }
      sheets[k].pieces.push_back(pieces[i]);
      sheets[k].utilisation += lam.layers[pieces[i].layer].pieces[pieces[i].piece].area_mm2 / (sheet_w_mm * sheet_h_mm);
    }
  }
  return sheets;
}

namespace {

// The program of one sheet, point by point.
class SheetWriter {
 public:
  SheetWriter(const Lamination& lam, const Sheet& sheet, const WaterjetProcess& w) : lam_(lam), sheet_(sheet), w_(w) {}

  std::vector<post::ProgramPoint> write() {
    for (const auto& sp : sheet_.pieces) {
      const Layer& layer = lam_.layers[sp.layer];
      const Piece& piece = layer.pieces[sp.piece];
      for (std::size_t h = 0; h < piece.holes.size(); ++h) cut_loop(layer, sp, piece.holes[h], fmt::format("L{}.P{} hole {}", sp.layer, sp.piece, h));
      cut_loop(layer, sp, piece.outer, fmt::format("L{}.P{} outer", sp.layer, sp.piece));
    }
    return std::move(points_);
  }

 private:
  struct Jet {
    Vec3 tip, axis;
    double feed = 0.0;
  };

  // The jet's centre line of CUT at sample S, in machine coordinates: tip on the sheet's top face.
  Jet jet(const Layer& layer, const SheetPiece& sp, const EdgeSample& s, const Cut& cut, double out_mm) const {
    const double r = cut.r_mid_mm + cut.slope * (layer.z_top() - layer.z_ref_mm) + 0.5 * w_.kerf_mm * std::sqrt(1.0 + cut.slope * cut.slope) + out_mm;
    double x = 0, y = 0;
    place(sp.placement, s.p.x + s.n.x * r, s.p.y + s.n.y * r, x, y);
    const Vec2 n = rotate(s.n, sp.placement.rotation_deg);
    Jet j;
    j.tip = {sheet_.origin_mm[0] + x, sheet_.origin_mm[1] + y, layer.thickness_mm};
    j.axis = core::normalized(Vec3{n.x * cut.slope, n.y * cut.slope, 1.0});
    j.feed = waterjet_feed_mm_s(w_, layer.thickness_mm, std::atan(std::fabs(cut.slope)));
    return j;
  }

  void add(const Jet& j, double feed, bool on, std::uint32_t layer, std::uint32_t piece, std::string comment = {}, bool unwind = false) {
    post::ProgramPoint p;
    p.tip_part_mm = j.tip;
    p.tool_axis_part = j.axis;
    p.feed_mm_s = feed;
    p.process_on = on;
    p.layer = layer;
    p.region = piece;
    p.comment_if_new_block = std::move(comment);
    p.c_unwind = unwind;
    points_.push_back(std::move(p));
  }

  // How far along +n from the start sample the lead may go: inside a hole, a share of the hole's
  // width there; outside a piece, the lead-in itself (the margin keeps neighbours away).
  double lead_room(const EdgeLoop& loop, const EdgeSample& s) const {
    if (!loop.hole) return w_.lead_in_mm;
    const double nearest = detail::distance_across(loop, s.p, s.n, kLeadMinMm);
    return std::min(w_.lead_in_mm, kHoleLeadShare * (std::isfinite(nearest) ? nearest : 0.0));
  }

  void cut_loop(const Layer& layer, const SheetPiece& sp, const EdgeLoop& loop, const std::string& name) {
    if (loop.samples.empty()) return;
    const EdgeSample& start = loop.samples.front();
    const double lead = lead_room(loop, start);
    const Jet first = jet(layer, sp, start, start.cuts.front(), 0.0);
    const Jet pierce = jet(layer, sp, start, start.cuts.front(), lead);
    // Over the pierce point with the tool vertical (C unwinds there), then down onto it tilted.
    Jet above = pierce;
    above.tip.z += w_.clearance_mm;
    above.axis = {0, 0, 1};
    add(above, w_.travel_feed_mm_s, false, layer.index, sp.piece, name, true);
    add(pierce, w_.travel_feed_mm_s, false, layer.index, sp.piece);
    add(first, first.feed, true, layer.index, sp.piece, "lead-in");
    const int passes = loop.passes();
    for (int k = 0; k < passes; ++k) {
      for (std::size_t i = 1; i <= loop.samples.size(); ++i) {
        const EdgeSample& s = loop.samples[i % loop.samples.size()];
        const Cut& cut = s.cuts[std::min<std::size_t>(static_cast<std::size_t>(k), s.cuts.size() - 1)];
        const Jet j = jet(layer, sp, s, cut, 0.0);
        add(j, j.feed, true, layer.index, sp.piece, i == 1 ? fmt::format("pass {}", k + 1) : std::string());
      }
    }
    const EdgeSample& last = loop.samples.front();
    const Cut& last_cut = last.cuts[std::min<std::size_t>(static_cast<std::size_t>(passes - 1), last.cuts.size() - 1)];
    const Jet out = jet(layer, sp, last, last_cut, loop.hole ? std::min(w_.lead_out_mm, lead) : w_.lead_out_mm);
    add(out, out.feed, true, layer.index, sp.piece, "lead-out");
    Jet up = out;
    up.tip.z += w_.clearance_mm;
    up.axis = {0, 0, 1};
    add(up, w_.travel_feed_mm_s, false, layer.index, sp.piece);
  }

  const Lamination& lam_;
  const Sheet& sheet_;
  const WaterjetProcess& w_;
  std::vector<post::ProgramPoint> points_;
};

}  // namespace

core::Result<std::vector<post::ProgramPoint>> sheet_program(const Lamination& lam, const Sheet& sheet, const WaterjetProcess& process,
                                                            const machine::MachineConfig& machine) {
  if (!machine::tilts_head(machine.kind)) {
    return core::make_error(core::ErrorCode::kUsage, fmt::format("machine '{}' ({}): a waterjet tilts its head over the sheet; give a head-head machine "
                                                                 "(xyzac-head or xyzbc-head)", machine.name, machine::kinematics_name(machine.kind)));
  }
  return SheetWriter(lam, sheet, process).write();
}

core::Result<std::string> sheet_gcode(const Lamination& lam, const Sheet& sheet, const WaterjetProcess& process, const machine::MachineConfig& machine) {
  auto points = sheet_program(lam, sheet, process, machine);
  if (!points) return points.error();
  post::GcodeOptions options;
  options.rapid_travel = true;
  options.split_stalls = false;
  return post::write_gcode(machine, post_process(process), points.value(), options);
}

}  // namespace polyaxis::lamination
